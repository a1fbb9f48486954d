/* sss/splat.h: the CPU side of Chen et al. 2012's multiresolution
 * splatting (Chen et al. 2012 §4; docs/deformable.md §8): the required sampling
 * rate M (Eq. 11), the sample selection test (Eq. 10), the mean normalised
 * scattering profile P̄ (Eqs. 15–16), the minimal effective rendering
 * radius R̄ (Eq. 14) and the levels' rendering ranges [R_min^k, R_max^k]
 * (Eq. 13). These are the tables and tests the GPU passes use (sss_render's
 * splat_gpu.c, sss/splat_gpu.h; docs/deformable.md §9). No GL: part of libsss.
 *
 * Symbols follow the paper: R_P the effective scattering range (the radius
 * holding 95 % of the profile's energy), R_w the diameter of the object's
 * bounding sphere, T the sampling resolution (texels across a length), ε
 * the error tolerance (0.001 in the paper).
 */
#ifndef SSS_SPLAT_H
#define SSS_SPLAT_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The share of a profile's energy inside R_P (Eq. 11's "95 % percent"). */
#define SSS_SPLAT_ENERGY 0.95
/* The paper's ε of Eq. 14 and α of Eq. 11. */
#define SSS_SPLAT_EPS 1e-3
#define SSS_SPLAT_ALPHA 15.0

/* Eq. 11: M(x) = α R_w / (R_P |n(x)·L(x)|), the texture resolution a
 * sample needs; INFINITY where n·L = 0 (a grazing sample is never coarse
 * enough to stand for its neighbours). */
double sss_splat_required_rate(double alpha, double R_w, double R_P, double n_dot_L);

/* Eq. 10: a sample of the hierarchical irradiance buffer is valid when it
 * spans no depth discontinuity and its level samples finely enough:
 *     z_max − z_min < z0  and  T > M.
 * (The paper's Algorithm 1 prints the test inverted: it discards a sample
 * when z_max − z_min < z0 or T^k > M, i.e. exactly the valid ones; this is
 * the equation, which the text around it describes.) */
int sss_splat_sample_valid(double z_max, double z_min, double z0, double T, double M);

/* P̄(r) on the normalised range r ∈ [0, 1] (Eqs. 15–16), sampled at
 * r_i = i / (n − 1): the mean over the profiles P_x of
 *     P'_x(r) = C_x P_x(r R_P,x),   C_x = R_P,x² / ∫_0^{R_P,x} P_x(r) r dr.
 * Here the profiles are the dipole's R_d of each channel (a homogeneous
 * material's profiles differ by channel only). */
typedef struct sss_splat_profile {
    uint32_t n;       /* samples, ≥ 2 */
    double *p;        /* P̄(r_i), owned */
    double R_P[3];    /* mm, per channel */
    uint32_t channels;
} sss_splat_profile;

/* Errors: SSS_ERR_ARG (n < 2, channels not 1 or 3, a channel whose total
 * reflectance is 0), SSS_ERR_NOMEM. */
sss_result sss_splat_profile_dipole(const sss_dipole *dip, uint32_t channels, uint32_t n, sss_splat_profile *out,
                                    sss_error *err);
void sss_splat_profile_free(sss_splat_profile *p);

/* Eq. 14: the smallest r ∈ [0, 1] at which splatting P̄ at resolution T
 * (samples r̂ = r + m/T, m = 0 … ⌊(1 − r)T⌋) reproduces its energy beyond r
 * within ε:
 *     | (1/T) Σ_r̂ P̄(r̂) r̂ − ∫_r^1 P̄(s) s ds | < ε.
 * (The paper writes the difference without the bars; a sum that falls
 * short is as wrong as one that overshoots.) 1 when no r < 1 qualifies. */
double sss_splat_min_radius(const sss_splat_profile *p, double T, double eps);

/* Eq. 13 for n_levels levels whose resolution halves from level to level:
 * T^k = T0 / 2^k texels across R_P (T(x_i) of the paper for level 0), 
 *     R_min^0 = 0,  R_min^k = R_P R̄(T^k),  R_max^k = R_min^{k+1},
 *     R_max^{n−1} = R_P,
 * each R_min^k also at least R_min^{k−1} (R̄ grows as T shrinks; the
 * maximum makes rounding in the table unable to break the order), so the
 * ranges tile [0, R_P] without gap or overlap. rmin and rmax take
 * n_levels values each. */
void sss_splat_level_ranges(const sss_splat_profile *p, double R_P, double T0, uint32_t n_levels, double eps,
                            double *rmin, double *rmax);

#ifdef __cplusplus
}
#endif
#endif
