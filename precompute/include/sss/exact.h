/* sss/exact.h: the exact evaluator of q(x_v, ω) (Hao–Varshney 2004 §3.1)
 * for ANY light direction ω, from a .sss file alone.
 *
 * A bake stores q only at its direction samples ω_j, possibly quantised or
 * compressed (§3.2, §4); a renderer interpolates between them. To measure
 * what that costs, this evaluator recomputes the integral itself, with the
 * physics, neighbourhoods, self term and visibility rule of the bake:
 *
 *   q(x_o, ω) = Σ_{x_i ∈ N(x_o)} w_c(o, i) · F_t(η, n_i·ω) · max(0, n_i·ω) · V(x_i, ω)
 *
 * (docs/format.md §5.4). Everything it needs is in the file: the mesh with
 * its normals (GEOM; the areas ΔA are recomputed exactly from the float
 * positions), the material and mm per unit (MATL), and the neighbourhood
 * energy cutoff ε (NBHD; PARM's "eps" in files before format 1.4). The
 * stored integrals and directions are not
 * used, so any storage form works, and at a direction sample ω_j of a float
 * bake the result is the stored value.
 */
#ifndef SSS_EXACT_H
#define SSS_EXACT_H

#include <stdint.h>
#include "sss/format.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Opaque: a copy of the mesh with areas, the neighbourhoods N(x_o) with
 * their per-channel weights, and the occlusion BVH, built once. */
typedef struct sss_exact sss_exact;

/* Builds the evaluator for f (which may be freed afterwards). ε is f->eps
 * (section NBHD) or, in files before format 1.4, read from f->params_json
 * ("eps"; 1e-3, the bake's default, when PARM is empty or has no "eps"); the
 * neighbourhood radius per channel is then recomputed as the
 * bake did (sss_rd_radius clamped to the bounding-box diagonal). Errors:
 * SSS_ERR_ARG (no mesh, bad channel count), SSS_ERR_CORRUPT (PARM is not a
 * JSON object, or "eps" is not a number in (0, 1)), SSS_ERR_NOMEM,
 * SSS_ERR_UNSUPPORTED (Embree). The message names the section at fault, not
 * the file (the caller knows its name). */
sss_result sss_exact_create(const sss_bake_file *f, sss_exact **out, sss_error *err);

/* The same with the memory planned as the bake plans it: the neighbourhood
 * rows are counted first and refused (SSS_ERR_NOMEM, the bake's one-line
 * message) when they would take more than 90 % of what sss_memory_available
 * (sss/memory.h) gives for memory_limit (0: what the system has available);
 * sss_exact_create plans nothing. */
sss_result sss_exact_create_limited(const sss_bake_file *f, uint64_t memory_limit, sss_exact **out, sss_error *err);

/* q(x_v, ω) for every vertex into out[v * channels + c] (channels of the
 * file). light points towards the light and need not be unit; a zero or
 * non-finite light gives zeros. Each vertex's sum runs over its neighbours
 * in increasing index order in double, so the result does not depend on the
 * thread count. */
void sss_exact_eval(const sss_exact *e, const double light[3], float *out);

/* The same for one vertex into out[0 … channels−1], bit for bit what
 * sss_exact_eval writes for it (it traces only that vertex's neighbours'
 * rays). v out of range gives zeros. */
void sss_exact_eval_vertex(const sss_exact *e, uint32_t v, const double light[3], float *out);

/* q at a few receivers over many light directions (the environment's
 * transfer, docs/scenes.md "Accuracy"): sss_exact_eval_vertex traces a
 * neighbour shared by several receivers once per receiver, sss_exact_eval
 * every vertex of the mesh. A subset traces G(x_i, ω) once per light for
 * the union of its receivers' neighbourhoods (the "sources"), then sums
 * each receiver's row as sss_exact_eval_vertex does, bit for bit. */
typedef struct sss_exact_subset sss_exact_subset;

/* The longest prefix of verts[0 … n−1] (at least one vertex) whose sources
 * number at most max_sources (0: no limit), so that the cost of a
 * measurement is bounded on big meshes whatever their neighbourhoods. e
 * must outlive the subset. Errors: SSS_ERR_ARG (n 0, a vertex out of
 * range), SSS_ERR_NOMEM. */
sss_result sss_exact_subset_create(const sss_exact *e, const uint32_t *verts, uint32_t n, uint64_t max_sources,
                                   sss_exact_subset **out, sss_error *err);
/* Receivers taken (the prefix) and their sources. */
uint32_t sss_exact_subset_vertices(const sss_exact_subset *s);
uint64_t sss_exact_subset_sources(const sss_exact_subset *s);
/* out[(l * n + k) * channels + c] = q at receiver k (n of them) for light
 * l of lights[3l … 3l+2], as sss_exact_eval_vertex writes it. The lights
 * are taken in batches, each one parallel region (a region per light costs
 * more than the light on a busy machine). Deterministic whatever the thread
 * count; not thread-safe against concurrent evaluations of the same subset
 * (it owns the tables of G). */
void sss_exact_subset_eval(sss_exact_subset *s, const double *lights, uint32_t nlights, float *out);
/* NULL-safe. */
void sss_exact_subset_destroy(sss_exact_subset *s);

/* Vertex and channel counts of the evaluator's mesh and material. */
uint32_t sss_exact_vertices(const sss_exact *e);
uint32_t sss_exact_channels(const sss_exact *e);

/* ε used (from NBHD, PARM or the default) and the neighbourhood search radius in
 * mm it gives: reported by sss-stat --query. */
double sss_exact_eps(const sss_exact *e);
double sss_exact_search_radius_mm(const sss_exact *e);

/* Visibility on (the default, the bake's rule) or off (V ≡ 1: every
 * front-facing source lit). Off is not the physics of any file; it lets a
 * diagnostic separate the error the interpolation makes at cast shadows
 * from the error at the terminator (tests/bench/error_sources.c). Not
 * thread-safe against concurrent evaluations. */
void sss_exact_set_shadows(sss_exact *e, int on);
/* NULL-safe. */
void sss_exact_destroy(sss_exact *e);

#ifdef __cplusplus
}
#endif
#endif
