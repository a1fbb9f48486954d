/* sss/transfer.h: the transfer table G(x_i, ω_j) of the bake and the direct
 * sum of the integrals over the neighbourhoods (Hao–Varshney 2004 §3.1):
 *
 *   q(x_o, ω_j) = Σ_{x_i ∈ N(x_o)} w(o, i) · G(x_i, ω_j),
 *   G(x_i, ω)   = F_t(η, n_i·ω) · max(0, n_i·ω) · V(x_i, ω).
 *
 * Part of libsss_bake (kernels/transfer.c).
 */
#ifndef SSS_TRANSFER_H
#define SSS_TRANSFER_H

#include <stdint.h>
#include "sss/mesh.h"
#include "sss/nbhd.h"
#include "sss/result.h"
#include "sss/visibility.h"

#ifdef __cplusplus
extern "C" {
#endif

/* G[i * n + j] for all vertices i and the n unit directions dirs (towards
 * the lights); vis NULL means no occlusion test. rays/occluded (may be
 * NULL) count the rays traced and blocked. Polls cancel (sss/result.h). */
sss_result sss_transfer_compute(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n, double eta,
                                const sss_cancel_flag *cancel, float *G, uint64_t *rays, uint64_t *occluded,
                                sss_error *err);

/* q for every neighbourhood row and direction: q[(j * nrows + r) * channels + c]
 * = Σ_i w_c(r, i) G[i * n + j], accumulated in double. */
void sss_integrate(const sss_weights *nb, const float *G, uint32_t n, float *q);

/* The same with the hat-function corrections of sss_hat_corrections (rows
 * for the same receivers; NULL: none) added to each row's sum after its
 * neighbours, in double, and the result clamped at 0 (docs/physics.md §9). */
void sss_integrate_hat(const sss_weights *nb, const sss_weights *hat, const float *G, uint32_t n, float *q);

/* The same sums without the clamp, for G of either sign (the SH
 * projections of the environment transfer, effects/env_sh.c). */
void sss_integrate_hat_signed(const sss_weights *nb, const sss_weights *hat, const float *G, uint32_t n, float *q);

#ifdef __cplusplus
}
#endif
#endif
