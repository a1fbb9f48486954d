/* sss/nbhd.h: scattering neighbourhoods N(x_o) and their weights
 * (Hao–Varshney 2004 §3.1), the rows every integral of the bake sums over.
 * Part of libsss_bake (kernels/nbhd.c); sss/precompute.h includes every
 * header of the library.
 */
#ifndef SSS_NBHD_H
#define SSS_NBHD_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/weights.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Scattering neighbourhoods N(x_o) as weight rows (sss/weights.h): for
 * every receiver the vertices within the search radius and their
 * per-channel weights w_c(o, i) = (1/π) R_d,c(‖x_i − x_o‖) ΔA(x_i) (mm² ·
 * 1/mm² = sr⁻¹ units of q), and for i = o the self term (1/π) ∫_disk R_d dA
 * over a disk of x_o's own area (docs/physics.md §4). Rows list neighbours
 * in increasing index order, so sums are taken in the same order whatever
 * the thread count. */

/* Builds neighbourhoods for `targets` (ntargets vertex indices; NULL means all
 * vertices in order). mesh must have area computed. radius_mm is the search
 * radius; dip[c] the channel models. Counts first: if the rows would take
 * more than max_bytes (0: no limit), fails with SSS_ERR_NOMEM and a message
 * giving the size before allocating them. Polls cancel (sss/result.h). */
sss_result sss_nbhd_build(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t channels,
                          double radius_mm, const uint32_t *targets, uint32_t ntargets, uint64_t max_bytes,
                          const sss_cancel_flag *cancel, sss_weights *out, sss_error *err);

/* The neighbourhood radius rule, shared by the bake, the exact evaluator and
 * the scene passes so that all of them find the same neighbourhoods: per
 * channel the disk holding 1−ε of R_d,total (docs/physics.md §2), clamped
 * to the object's diagonal (α′ → 1). Fills radius_mm[c] (may be NULL) and
 * returns the largest, the radius searched. */
double sss_nbhd_radii(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t channels, double eps,
                      double *radius_mm);

#ifdef __cplusplus
}
#endif
#endif
