/* sss/dipole.h: the dipole diffusion model (Jensen et al. 2001) per colour
 * channel, as used by Hao–Varshney 2004 §3.1. Units: lengths in mm,
 * coefficients in 1/mm, R_d in 1/mm². Formulas: docs/physics.md §1–§3.
 */
#ifndef SSS_DIPOLE_H
#define SSS_DIPOLE_H

#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_MAX_CHANNELS 3

/* A homogeneous material: per channel σa and reduced scattering σ′s (1/mm),
 * one relative index of refraction η = n_inside / n_outside, and the
 * Henyey–Greenstein mean cosine g of its phase function (0: isotropic, the
 * presets' and every older file's). The dipole sees σ′s only; single
 * scattering (sss/single.h) needs σs = σ′s / (1 − g) and g itself. */
typedef struct sss_material {
    char name[32];                      /* preset name or "custom" */
    double sigma_a[SSS_MAX_CHANNELS];   /* absorption, 1/mm */
    double sigmap_s[SSS_MAX_CHANNELS];  /* reduced scattering σ′s = σs(1−g), 1/mm */
    double eta;                         /* relative index of refraction */
    double g;                           /* HG mean cosine, |g| ≤ SSS_G_MAX; > 0 scatters forwards */
} sss_material;

/* Derived dipole quantities for one channel (docs/physics.md §1). */
typedef struct sss_dipole {
    double sigma_a, sigmap_s;  /* inputs, 1/mm */
    double sigmap_t;           /* σ′t = σa + σ′s, 1/mm */
    double alpha_p;            /* α′ = σ′s / σ′t */
    double sigma_tr;           /* σtr = sqrt(3 σa σ′t), 1/mm */
    double D;                  /* 1 / (3 σ′t), mm */
    double F_dr;               /* diffuse Fresnel reflectance */
    double A;                  /* (1 + F_dr) / (1 − F_dr) */
    double z_r, z_v;           /* real source depth, virtual source height, mm */
} sss_dipole;

/* Number of presets and their names, in table order (apple … wholemilk). */
int sss_material_preset_count(void);
const char *sss_material_preset_name(int i);

/* Looks a Jensen 2001 preset up by name (case-insensitive); η = 1.3. */
sss_result sss_material_preset(const char *name, sss_material *out, sss_error *err);

/* Accepted ranges: η where the F_dr fits stay below 1; coefficients up to a
 * sub-nanometre mean free path. */
#define SSS_ETA_MIN 0.3
#define SSS_ETA_MAX 3.5
#define SSS_SIGMA_MAX 1e6
/* σ′t = σa + σ′s at least this (a mean free path of at most 1e12 mm): below
 * it the dipole's depths z_r, z_v and their squares leave the range of the
 * float gather and of double (σa = 0 with σ′s < 1e-154 made NaN;
 * docs/robustness.md, "Materials"). */
#define SSS_SIGMA_T_MIN 1e-12

/* The largest |g| accepted: at 0.99 σs = 100 σ′s and HG's forward peak is
 * 4·10⁴ times its mean; beyond, σs leaves the coefficients' range for
 * ordinary σ′s and the peak needs more than float precision. */
#define SSS_G_MAX 0.99

/* Checks a material: finite, 0 ≤ σa, σ′s ≤ SSS_SIGMA_MAX, σ′t ≥
 * SSS_SIGMA_T_MIN per channel, SSS_ETA_MIN ≤ η ≤ SSS_ETA_MAX, |g| ≤
 * SSS_G_MAX. */
sss_result sss_material_validate(const sss_material *m, sss_error *err);

/* The same checks for the first `channels` channels only (a file's MATL
 * keeps the unused ones as given); `code` is the result returned. */
sss_result sss_material_check(const sss_material *m, uint32_t channels, sss_result code, sss_error *err);

/* Colour channels a bake of m stores: 1 when σa and σ′s are equal in R, G
 * and B (one dipole profile serves all three, and a grey material pays for
 * one channel only), else 3. */
uint32_t sss_material_channels(const sss_material *m);

/* The scattering coefficient σs = σ′s / (1 − g) of channel c (1/mm),
 * docs/physics.md §1: what single scattering sees. */
double sss_material_sigma_s(const sss_material *m, int c);

/* Diffuse Fresnel reflectance F_dr(η), Jensen's fit (Egan–Hilgeman for η<1);
 * exactly 0 at η = 1, where the fit's 0.0016 is an artefact. */
double sss_fdr(double eta);

/* Fresnel transmittance F_t(η, cos θ) = 1 − F_r for unpolarised light
 * entering from outside; 0 under total internal reflection; cos θ is
 * clamped to [0, 1]. */
double sss_ft(double eta, double cos_theta);

/* The exit's hemispherical transmittance c(η) = 2 ∫₀¹ F_t(η, μ) μ dμ
 * (= 1 − 2 C1, C1 the first Fresnel moment; 0.93887 at η = 1.3): the share
 * of a Lambertian exitance that the exit term F_t(η, n·ω_o)/π lets out.
 * Dividing that term by it makes the radiance integrate to the dipole's
 * exitance: the "normalised" exit of docs/physics.md §4, measured against
 * the path-traced reference in docs/accuracy.md ("What the truth shows").
 * By the midpoint rule on 4096 cells (error below 10⁻⁷). */
double sss_exit_norm(double eta);

/* Fills d for one channel. Fails (SSS_ERR_ARG) when σ′t ≤ 0 or inputs are not
 * finite. */
sss_result sss_dipole_init(sss_dipole *d, double sigma_a, double sigmap_s, double eta);

/* R_d(r), 1/mm² (docs/physics.md §2). Finite at r = 0. */
double sss_rd(const sss_dipole *d, double r);

/* ∫_0^R R_d(r) 2πr dr, exact closed form (dimensionless). */
double sss_rd_disk(const sss_dipole *d, double R);

/* ∫ R_d(|y|) dA over a disk of radius R on the axis through the origin, at
 * distance h from it (its plane perpendicular to the axis; dimensionless):
 * closed form, sss_rd_disk(R) at h = 0. Seed 000's run-time samples stand
 * for such disks (docs/heterogeneous.md §9.2). */
double sss_rd_disk_axis(const sss_dipole *d, double h, double R);

/* ∫ R_d(|y|) dA over a disk of radius rho whose centre lies at distance r
 * from the origin (dimensionless): the contribution of a neighbour's area
 * ΔA = π rho² at distance r without point-sampling R_d, whose peak at 0 a
 * point sample over- or undershoots when r is comparable to rho (and
 * overshoots badly for coincident vertices, r = 0). Equals sss_rd_disk(rho)
 * at r = 0 and tends to R_d(r) π rho² for r ≫ rho. */
double sss_rd_disk_offset(const sss_dipole *d, double r, double rho);

/* Total diffuse reflectance ∫_0^∞ R_d 2πr dr = (α′/2)(1 + e^{−(4/3)A s}) e^{−s}. */
double sss_rd_total(const sss_dipole *d);

/* The largest q of a flat surface of m lit head-on by unit irradiance,
 * over its first `channels` channels (1 or 3; a grey file's other channels
 * are not material): F_t(η, 1) · R_d,total / π (docs/physics.md §4).
 * The exposure 1 / this maps it to 1, so that a first render of a file is
 * neither black nor clipped (sss-view without --exposure). 0 for an invalid
 * material. */
double sss_material_slab_q(const sss_material *m, uint32_t channels);

/* Smallest radius R (mm) with sss_rd_disk(R) ≥ (1 − eps) · sss_rd_total,
 * found by bisection on the closed form; clamped to r_max (α′ → 1 makes the
 * tail decay like r⁻³). Returns 0 when the total is 0. */
double sss_rd_radius(const sss_dipole *d, double eps, double r_max);

#ifdef __cplusplus
}
#endif
#endif
