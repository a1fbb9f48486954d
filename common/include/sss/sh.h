/* sss/sh.h: real spherical harmonics and projection of baked per-direction
 * integrals q(x, ω_j) onto them (Hao–Varshney 2004 §4.1 compresses the
 * ~200 baked values per vertex into the first n² SH coefficients; physics
 * sheet §7 fixes the conventions below).
 *
 * Conventions
 *   - "Order n" is the number of bands: bands l = 0 … n−1, n² coefficients
 *     (the paper's n = 7 gives 49). n is in [0, SSS_SH_MAX_ORDER]; order 0
 *     has no coefficients.
 *   - Coefficient index i = l(l+1) + m, −l ≤ m ≤ l.
 *   - y_l^m = √2 K_l^m cos(mφ) P_l^m(cos θ)     m > 0
 *             √2 K_l^m sin(|m|φ) P_l^|m|(cos θ)  m < 0
 *             K_l^0 P_l^0(cos θ)                 m = 0
 *     with K_l^m = sqrt((2l+1)/(4π) · (l−|m|)!/(l+|m|)!) (Hao–Varshney 2004
 *     §4.1), orthonormal over the unit sphere, θ measured from +z.
 *   - NO Condon–Shortley phase: P_l^m here excludes the (−1)^m factor, so
 *     every y_l^m with m ≠ 0 is a positive multiple of Re or Im of
 *     (x + iy)^|m| times a polynomial in z. Band 1 is
 *     (y_1^−1, y_1^0, y_1^1) = 0.48860251190292 · (y, z, x); in particular
 *     y_1^1(+x) = +0.4886. This is the graphics convention of Ramamoorthi and
 *     Hanrahan 2001 (and of most irradiance/PRT code); physics texts that
 *     include the phase have y_1^1 = −0.4886 x and flip the sign of every
 *     odd-m function.
 *
 * Evaluation is Cartesian (docs/physics.md §7): the z part by the associated
 * Legendre recurrence, the φ part by C_m = x C_{m−1} − y S_{m−1},
 * S_m = x S_{m−1} + y C_{m−1} (C_m + i S_m = (x + iy)^m). No atan2, no
 * division by sin θ: exact at the poles, where every m ≠ 0 term is exactly 0.
 */
#ifndef SSS_SH_H
#define SSS_SH_H

#include <stddef.h>
#include <stdint.h>
#include "sss/dirset.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_SH_MAX_ORDER 8u                                      /* bands 0 … 7 */
#define SSS_SH_MAX_COUNT (SSS_SH_MAX_ORDER * SSS_SH_MAX_ORDER) /* 64 */

/* order² for order in [0, SSS_SH_MAX_ORDER]; 0 for larger (invalid) orders. */
uint32_t sss_sh_count(uint32_t order);

/* Writes the sss_sh_count(order) values y_i(d) to y. d need not be
 * normalised (it is, internally, with overflow-safe scaling). A zero or
 * non-finite d (any component NaN or ±inf) writes all zeros, never NaN.
 * An order above SSS_SH_MAX_ORDER writes nothing. Pure and thread-safe. */
void sss_sh_eval(uint32_t order, const double d[3], double *y);

/* Float variant for the renderer: same values, computed in double and
 * rounded once (relative error ≤ 2^−24 per value). */
void sss_sh_evalf(uint32_t order, const float d[3], float *y);

/* Σ_i coeffs[i] y_i(d): the reconstruction q̃(d) of Hao–Varshney 2004 §4.1.
 * Returns 0 for a zero or non-finite d or an invalid order. */
double sss_sh_reconstruct(uint32_t order, const double *coeffs, const double d[3]);

/* Area of the spherical Voronoi cell of every direction of s (n values,
 * summing to 4π). The Voronoi vertices are the circumcentres of the Delaunay
 * triangles s->tri around each direction, taken in counter-clockwise order;
 * the cell is the fan of spherical triangles (ω_j, cc_t, cc_t+1), each area
 * from tan(E/2) = a·(b×c) / (1 + a·b + b·c + c·a). s must be triangulated as
 * sss_dirset_triangulate leaves it (closed, counter-clockwise from outside,
 * unit directions). Writes NaN for every direction when s has no triangles
 * (n < 4) or the triangles around some direction do not form one closed
 * fan (never the case for sss_dirset_triangulate output). */
void sss_sh_voronoi_areas(const sss_dirset *s, double *area);

typedef enum sss_sh_method {
    /* c = argmin Σ_j (f_j − Σ_i c_i y_i(ω_j))², solved by Householder QR of
     * the N × n² matrix Y_ji = y_i(ω_j) in double: P = R⁻¹ Qᵀ. Exact for
     * band-limited f (up to rounding). Needs n² ≤ N and Y of full rank. */
    SSS_SH_LEAST_SQUARES = 0,
    /* c_i = Σ_j A_j y_i(ω_j) f_j with A_j the spherical Voronoi area of
     * ω_j (sss_sh_voronoi_areas): a direct discretisation of the paper's
     * projection integral q_l^m = ∫ q y_l^m dω (Hao–Varshney 2004 §4.1).
     * Needs a triangulated s. */
    SSS_SH_QUADRATURE = 1
} sss_sh_method;

/* Opaque projector: the n² × N matrix P for one (direction set, order,
 * method), built once, then applied to every vertex's N samples. */
typedef struct sss_sh_projector sss_sh_projector;

/* Builds the projector for s (s is not referenced afterwards). Fails with
 * SSS_ERR_ARG when s or out is NULL, s has no directions, a direction is
 * zero or not finite, order > SSS_SH_MAX_ORDER, order² > s->n (fewer
 * samples than coefficients), the method is unknown, least squares is rank
 * deficient on these directions (or so ill-conditioned that the estimate
 * ‖Y‖_F ‖P‖_F exceeds 1e10), or quadrature is asked of an untriangulated
 * set; with SSS_ERR_NOMEM when allocation fails. The message names the
 * order and the number of directions. Order 0 is valid (no coefficients).
 * On failure *out is NULL. */
sss_result sss_sh_projector_create(const sss_dirset *s, uint32_t order, sss_sh_method method,
                                   sss_sh_projector **out, sss_error *err);

/* coeffs[i] = Σ_j P_ij f[j], i < n², j < N. Pure and thread-safe. */
void sss_sh_project(const sss_sh_projector *p, const double *f, double *coeffs);

/* Same with sample j read from f[j * stride] (interleaved channels: pass
 * f + channel and the channel count). stride ≥ 1. */
void sss_sh_project_strided(const sss_sh_projector *p, const double *f, size_t stride, double *coeffs);

/* The n² × N row-major matrix P (row i = coefficient i); NULL for order 0. */
const double *sss_sh_projector_matrix(const sss_sh_projector *p);

uint32_t sss_sh_projector_order(const sss_sh_projector *p);
uint32_t sss_sh_projector_ndirs(const sss_sh_projector *p);

/* NULL-safe. */
void sss_sh_projector_destroy(sss_sh_projector *p);

#ifdef __cplusplus
}
#endif
#endif
