/* sss/ownterm.h: the vertex's own term of q, evaluated at run time.
 *
 * Hao–Varshney 2004 §3.1 sums over the whole neighbourhood, the vertex
 * itself included:
 *
 *   q(x_o, ω) = Σ_{x_i ∈ N(x_o)} w(o, i) F_t(η, n_i·ω) max(0, n_i·ω) V(x_i, ω).
 *
 * R_d peaks at r = 0, so the own entry i = o carries a large share of the
 * sum, and it is the entry that changes most abruptly with ω: it switches
 * off where x_o itself falls into a cast shadow and has a kink where x_o
 * turns away from the light. Interpolating between direction samples
 * (§3.2) smears both over the sample spacing (~14° at 200 directions), and
 * on the dragon 97 % of the squared per-vertex error sits at those steps
 * (docs/accuracy.md, "Where the error comes from").
 *
 * A file baked with `--own-term runtime` (section OWNT, docs/format.md
 * §5.14) therefore stores the rest, q − w̃_o g_o(ω_j) V(x_o, ω_j), and the
 * reader adds w̃_o g_o(ω) V(x_o, ω) back for the actual light, with the
 * vertex's own visibility from a shadow test of its own (rays in the tools,
 * a shadow map in the viewer: the paper's local-illumination pass already
 * shadows the surface, §3.2). w̃_o is not stored: both sides compute it
 * with sss_own_weights from the file's geometry and material, so it costs
 * no bytes.
 */
#ifndef SSS_OWNTERM_H
#define SSS_OWNTERM_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* w̃_o,c = (1/π) ∫_disk R_d dA over a disk of x_o's own area ΔA_o
 * (sss_mesh_vertex_areas, scaled by mm_per_unit²), i.e. the bake's self
 * weight (nbhd.c) without its sharing among coincident copies, for every
 * vertex and channel into w[v * channels + c]. mesh needs pos and tri
 * only. Deterministic (same sums in the same order wherever it runs).
 * Errors: SSS_ERR_ARG (NULL, channels not 1 or 3, mm_per_unit ≤ 0),
 * SSS_ERR_NOMEM. */
sss_result sss_own_weights(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                           float *w, sss_error *err);

/* g = F_t(η, c) · max(0, c), c = n·ω (n and ω unit; ω towards the light):
 * the transfer factor of the own term without visibility, in float as
 * every reader evaluates it (the GLSL version in runtime/src/shaders.c
 * computes the same expression). */
float sss_own_transfer(float eta, const float n[3], const float d[3]);

/* Adds the own term for unit light direction d to out[v * channels + c]:
 * out += w[v, c] · sss_own_transfer(η, n_v, d) · lit[v], with lit[v] the
 * vertex's own visibility (0 or 1; NULL: every vertex lit). */
void sss_own_add(const float *w, const float *nrm, uint32_t nv, uint32_t channels, float eta, const double d[3],
                 const uint8_t *lit, float *out);

#ifdef __cplusplus
}
#endif
#endif
