/* sss/dirset.h: the set of light directions ω_j at which integrals are
 * baked (Hao–Varshney 2004 §3.2 uses ~200), its spherical Delaunay
 * triangulation, and interpolation weights for any direction.
 *
 * The paper interpolates from the 4 nearest samples, which is discontinuous
 * where the nearest set changes; we interpolate barycentrically inside the
 * spherical Delaunay triangle (= convex hull facet) containing the direction:
 * exact at the samples and continuous everywhere (docs/physics.md §7).
 */
#ifndef SSS_DIRSET_H
#define SSS_DIRSET_H

#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_dirset {
    uint32_t n;      /* number of directions */
    uint32_t ntri;   /* number of triangles: 2n − 4 for n ≥ 4, else 0 */
    double *dir;     /* 3*n unit vectors, owned */
    uint32_t *tri;   /* 3*ntri indices into dir, counter-clockwise seen from outside the sphere, owned */
} sss_dirset;

/* Spherical Fibonacci set: z_i = 1 − 2(i+½)/n, φ_i = 2π i / φ_golden
 * (φ_golden = (1+√5)/2), i = 0 … n−1. n in [1, 1<<20]. Also triangulates. */
sss_result sss_dirset_fibonacci(sss_dirset *s, uint32_t n, sss_error *err);

/* (Re)computes tri/ntri from dir: the convex hull of the unit vectors, which
 * is their spherical Delaunay triangulation. Deterministic. n < 4 gives
 * ntri = 0. Fails if directions are not unit length or are degenerate
 * (e.g. all coplanar with n ≥ 4). Also fails (SSS_ERR_ARG) on duplicate
 * directions and when the origin is not strictly inside the hull (all
 * directions within one closed hemisphere), since then some triangle would
 * have det(a,b,c) ≤ 0. On failure tri is NULL and ntri 0; dir is untouched
 * (the hull is built from normalised copies). */
sss_result sss_dirset_triangulate(sss_dirset *s, sss_error *err);

/* Interpolation for direction d (need not be normalised, must be non-zero):
 * writes the three sample indices and barycentric weights (each ≥ 0, sum 1)
 * of the containing triangle and returns its index. For n < 4 (no
 * triangulation) returns −1 and weight 1 on the nearest sample (the other two
 * weights 0, indices repeated). λ_a = det(d, v_b, v_c) / det(v_a, v_b, v_c)
 * cyclically, normalised to sum 1 (docs/physics.md §7). A zero or non-finite d
 * also returns −1 (index 0, weights 1, 0, 0). tri must be as triangulate
 * leaves it (any valid closed triangulation works, only slower). Pure and
 * thread-safe. */
int32_t sss_dirset_lookup(const sss_dirset *s, const double d[3], uint32_t idx[3], double w[3]);

/* The paper's interpolation (Hao–Varshney 2004 §3.2, Fig. 3 and the
 * Find-Outgoing-Radiance pseudo-code: "find 4 nearest matches q_j ...
 * interpolate the 4 matched values"), kept for comparison (docs/accuracy.md): the
 * four samples nearest to d by angle θ_k and inverse-angle weights
 * w_k = (1/θ_k) / Σ 1/θ_m (the paper does not give its weights; this is
 * the plain Shepard choice). d on a sample (θ < 1e−9 rad) gives weight 1
 * there. Discontinuous where the set of four nearest changes. n < 4 uses
 * the n samples (the other weights 0, indices repeated). Returns the number
 * of samples used (0 for a zero or non-finite d: index 0, weight 1). Pure
 * and thread-safe, O(n). */
int sss_dirset_nearest4(const sss_dirset *s, const double d[3], uint32_t idx[4], double w[4]);

/* Rounds every component to the nearest float32 (kept in double), so that
 * the file stores the set exactly in half the bytes (section DIRC,
 * docs/format.md §5.18). The directions move by under 1e-7 rad and stay
 * unit within 1e-7; the triangulation is kept. A bake rounds before it
 * computes its rows, so that the rows belong to the stored directions. */
void sss_dirset_round_f32(sss_dirset *s);

/* Frees owned arrays and zeroes the struct. NULL-safe. */
void sss_dirset_free(sss_dirset *s);

#ifdef __cplusplus
}
#endif
#endif
