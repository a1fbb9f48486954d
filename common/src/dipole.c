/* dipole.c: the dipole diffusion profile of Jensen, Marschner, Levoy and
 * Hanrahan (SIGGRAPH 2001) as used by Hao–Varshney 2004 §3.1, with its
 * closed-form disk integral, total diffuse reflectance, Fresnel terms and the
 * measured materials of Jensen 2001 (Figure 5 there; docs/physics.md §5).
 *
 * All quantities per colour channel, lengths in mm, coefficients in 1/mm.
 */
#include "sss/dipole.h"
#include "sss/vec3.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* Jensen 2001 measured parameters, σ′s and σa in 1/mm, η = 1.3. */
static const struct {
    const char *name;
    double sigmap_s[3], sigma_a[3];
} presets[] = {
    {"apple", {2.29, 2.39, 1.97}, {0.0030, 0.0034, 0.046}},
    {"chicken1", {0.15, 0.21, 0.38}, {0.015, 0.077, 0.19}},
    {"chicken2", {0.19, 0.25, 0.32}, {0.018, 0.088, 0.20}},
    {"cream", {7.38, 5.47, 3.15}, {0.0002, 0.0028, 0.0163}},
    {"ketchup", {0.18, 0.07, 0.03}, {0.061, 0.97, 1.45}},
    {"marble", {2.19, 2.62, 3.00}, {0.0021, 0.0041, 0.0071}},
    {"potato", {0.68, 0.70, 0.55}, {0.0024, 0.0090, 0.12}},
    {"skimmilk", {0.70, 1.22, 1.90}, {0.0014, 0.0025, 0.0142}},
    {"skin1", {0.74, 0.88, 1.01}, {0.032, 0.17, 0.48}},
    {"skin2", {1.09, 1.59, 1.79}, {0.013, 0.070, 0.145}},
    {"wholemilk", {2.55, 3.21, 3.77}, {0.0011, 0.0024, 0.014}},
};
#define NPRESETS ((int)(sizeof presets / sizeof presets[0]))

int sss_material_preset_count(void) { return NPRESETS; }

const char *sss_material_preset_name(int i)
{
    return (i >= 0 && i < NPRESETS) ? presets[i].name : NULL;
}

static int name_eq(const char *a, const char *b)
{
    for (; *a && *b; a++, b++)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b)) return 0;
    return *a == *b;
}

sss_result sss_material_preset(const char *name, sss_material *out, sss_error *err)
{
    for (int i = 0; i < NPRESETS; i++) {
        if (!name_eq(name, presets[i].name)) continue;
        memset(out, 0, sizeof *out);
        snprintf(out->name, sizeof out->name, "%s", presets[i].name);
        for (int c = 0; c < 3; c++) {
            out->sigma_a[c] = presets[i].sigma_a[c];
            out->sigmap_s[c] = presets[i].sigmap_s[c];
        }
        out->eta = 1.3;
        return SSS_OK;
    }
    char list[256] = "";
    for (int i = 0; i < NPRESETS; i++) {
        strncat(list, presets[i].name, sizeof list - strlen(list) - 1);
        if (i + 1 < NPRESETS) strncat(list, ", ", sizeof list - strlen(list) - 1);
    }
    return sss_fail(err, SSS_ERR_ARG, "material '%s': unknown preset (known: %s)", name, list);
}

uint32_t sss_material_channels(const sss_material *m)
{
    const int grey = m->sigma_a[0] == m->sigma_a[1] && m->sigma_a[1] == m->sigma_a[2] &&
                     m->sigmap_s[0] == m->sigmap_s[1] && m->sigmap_s[1] == m->sigmap_s[2];
    return grey ? 1 : 3;
}

sss_result sss_material_validate(const sss_material *m, sss_error *err)
{
    return sss_material_check(m, 3, SSS_ERR_ARG, err);
}

sss_result sss_material_check(const sss_material *m, uint32_t channels, sss_result code, sss_error *err)
{
    const char *n = memchr(m->name, 0, sizeof m->name) && m->name[0] ? m->name : "custom";
    if (!isfinite(m->eta) || m->eta <= 0.0)
        return sss_fail(err, code, "material '%s': eta %g must be a finite number > 0", n, m->eta);
    /* The diffuse Fresnel fits (sss_fdr) reach 1 near η = 0.26 and 3.85,
     * where A = (1 + F_dr)/(1 − F_dr) and the virtual source blow up
     * (docs/robustness.md B1); every real material lies well inside. */
    if (m->eta < SSS_ETA_MIN || m->eta > SSS_ETA_MAX)
        return sss_fail(err, code, "material '%s': eta %g is outside [%g, %g], where the diffuse Fresnel "
                        "fit F_dr stays below 1", n, m->eta, SSS_ETA_MIN, SSS_ETA_MAX);
    if (!(fabs(m->g) <= SSS_G_MAX))
        return sss_fail(err, code, "material '%s': g %g is outside [%g, %g]", n, m->g, -SSS_G_MAX, SSS_G_MAX);
    static const char rgb[] = "RGB";
    for (uint32_t c = 0; c < channels && c < 3; c++) {
        if (!isfinite(m->sigma_a[c]) || m->sigma_a[c] < 0.0)
            return sss_fail(err, code, "material '%s': sigma_a %c = %g must be finite and >= 0", n, rgb[c], m->sigma_a[c]);
        if (!isfinite(m->sigmap_s[c]) || m->sigmap_s[c] < 0.0)
            return sss_fail(err, code, "material '%s': sigma'_s %c = %g must be finite and >= 0", n, rgb[c], m->sigmap_s[c]);
        /* above 1e6 /mm (a mean free path under a nanometre) σ′t and σtr
         * overflow or lose all digits (docs/robustness.md B2) */
        if (m->sigma_a[c] > SSS_SIGMA_MAX || m->sigmap_s[c] > SSS_SIGMA_MAX)
            return sss_fail(err, code, "material '%s': channel %c: coefficients above %g /mm are not a "
                            "scattering medium", n, rgb[c], SSS_SIGMA_MAX);
        if (!(m->sigma_a[c] + m->sigmap_s[c] > 0.0))
            return sss_fail(err, code, "material '%s': channel %c has sigma'_t = 0 (no extinction: the dipole is undefined)", n, rgb[c]);
        if (!(m->sigma_a[c] + m->sigmap_s[c] >= SSS_SIGMA_T_MIN))
            return sss_fail(err, code, "material '%s': channel %c has sigma'_t = sigma_a + sigma'_s = %g /mm, below %g "
                            "(a mean free path beyond 1e12 mm: the dipole's depths leave float range)", n, rgb[c],
                            m->sigma_a[c] + m->sigmap_s[c], SSS_SIGMA_T_MIN);
    }
    return SSS_OK;
}

/* F_dr: Jensen 2001 eq. (docs/physics.md §1); for η < 1 Egan & Hilgeman's fit. */
double sss_fdr(double eta)
{
    if (eta == 1.0) return 0.0; /* index-matched boundary reflects nothing; the fit says 0.0016 */
    if (eta >= 1.0) return -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta;
    return -0.4399 + 0.7099 / eta - 0.3319 / (eta * eta) + 0.0636 / (eta * eta * eta);
}

/* Unpolarised Fresnel reflectance for light entering a medium of relative
 * index η at incidence cosine c (docs/physics.md §3); F_t = 1 − F_r. */
double sss_material_sigma_s(const sss_material *m, int c) { return m->sigmap_s[c] / (1.0 - m->g); }

double sss_ft(double eta, double c)
{
    if (!(c > 0.0)) return 0.0; /* grazing or from behind: nothing enters */
    if (c > 1.0) c = 1.0;
    double g2 = eta * eta - 1.0 + c * c;
    if (g2 < 0.0) return 0.0; /* total internal reflection (only possible for η < 1) */
    double g = sqrt(g2);
    double a = (g - c) / (g + c);
    double b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0);
    double Fr = 0.5 * a * a * (1.0 + b * b);
    if (Fr > 1.0) Fr = 1.0;
    return 1.0 - Fr;
}

double sss_exit_norm(double eta)
{
    const int n = 4096;
    double s = 0.0;
    for (int k = 0; k < n; k++) {
        const double mu = (k + 0.5) / n;
        s += sss_ft(eta, mu) * mu;
    }
    return 2.0 * s / n;
}

sss_result sss_dipole_init(sss_dipole *d, double sigma_a, double sigmap_s, double eta)
{
    memset(d, 0, sizeof *d);
    if (!isfinite(sigma_a) || !isfinite(sigmap_s) || !isfinite(eta) || sigma_a < 0.0 || sigmap_s < 0.0 ||
        !(sigma_a + sigmap_s > 0.0) || !(eta > 0.0))
        return SSS_ERR_ARG;
    d->sigma_a = sigma_a;
    d->sigmap_s = sigmap_s;
    d->sigmap_t = sigma_a + sigmap_s;              /* σ′t, 1/mm */
    d->alpha_p = sigmap_s / d->sigmap_t;          /* α′ */
    d->sigma_tr = sqrt(3.0 * sigma_a * d->sigmap_t); /* σtr uses the *reduced* σ′t (physics §1) */
    d->D = 1.0 / (3.0 * d->sigmap_t);              /* mm */
    d->F_dr = sss_fdr(eta);
    d->A = (1.0 + d->F_dr) / (1.0 - d->F_dr);
    d->z_r = 1.0 / d->sigmap_t;                    /* mm */
    d->z_v = d->z_r + 4.0 * d->A * d->D;           /* mm */
    /* outside the fits' range (F_dr ≥ 1) or at overflowing coefficients the
     * dipole has no meaning: refuse rather than hand out NaN */
    if (!(d->F_dr < 1.0) || !isfinite(d->sigmap_t) || !isfinite(d->sigma_tr) || !isfinite(d->A) ||
        !isfinite(d->z_v) || !(d->z_v > 0.0)) {
        memset(d, 0, sizeof *d);
        return SSS_ERR_ARG;
    }
    return SSS_OK;
}

/* One source's term z (1 + σtr d) e^{−σtr d} / d³ with d = sqrt(r² + z²). */
static double rd_term(double sigma_tr, double z, double r)
{
    double d = sqrt(r * r + z * z);
    return z * (1.0 + sigma_tr * d) * exp(-sigma_tr * d) / (d * d * d);
}

double sss_rd(const sss_dipole *d, double r)
{
    return d->alpha_p / (4.0 * SSS_PI) * (rd_term(d->sigma_tr, d->z_r, r) + rd_term(d->sigma_tr, d->z_v, r));
}

/* e^{−σz} − z e^{−σd}/d for one source, written without cancellation for
 * small R: with δ = d − z = R²/(d + z), it is −e^{−σz} expm1(−σδ − log1p(δ/z)). */
static double disk_term(double sigma_tr, double z, double R)
{
    double d = sqrt(R * R + z * z);
    double delta = R * R / (d + z);
    return -exp(-sigma_tr * z) * expm1(-sigma_tr * delta - log1p(delta / z));
}

double sss_rd_disk(const sss_dipole *d, double R)
{
    if (!(R > 0.0)) return 0.0;
    if (isinf(R)) return sss_rd_total(d);
    return 0.5 * d->alpha_p * (disk_term(d->sigma_tr, d->z_r, R) + disk_term(d->sigma_tr, d->z_v, R));
}

/* A disk at height h on the axis: with D = sqrt(s² + h² + z²) and
 * s ds = D dD, ∫_0^R z (1 + σD) e^{−σD}/D³ 2πs ds = 2π z [e^{−σD}/D] from
 * D₁ = sqrt(R² + D₀²) to D₀ = sqrt(h² + z²); disk_term's form with z → D₀
 * and the factor z/D₀ (δ = D₁ − D₀ = R²/(D₁ + D₀)). */
double sss_rd_disk_axis(const sss_dipole *d, double h, double R)
{
    if (!(R > 0.0)) return 0.0;
    double s = 0.0;
    const double z[2] = {d->z_r, d->z_v};
    for (int k = 0; k < 2; k++) {
        const double D0 = sqrt(h * h + z[k] * z[k]), D1 = sqrt(R * R + D0 * D0);
        const double delta = R * R / (D1 + D0);
        s += z[k] / D0 * -exp(-d->sigma_tr * D0) * expm1(-d->sigma_tr * delta - log1p(delta / D0));
    }
    return 0.5 * d->alpha_p * s;
}

/* 16-point Gauss–Legendre nodes and weights on [−1, 1] (positive half). */
static const double GL_X[8] = {0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                               0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499};
static const double GL_W[8] = {0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                               0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541};

double sss_rd_disk_offset(const sss_dipole *d, double r, double rho)
{
    if (!(rho > 0.0) || !(r >= 0.0) || !isfinite(r) || !isfinite(rho)) return 0.0;
    /* In polar coordinates about the receiving point, the circle of radius s
     * lies inside the disk (centre at distance r, radius ρ) along an arc of
     * angle 2θ(s): θ = π for s ≤ ρ − r, 0 for s ≥ r + ρ, and in between
     * cos θ = (s² + r² − ρ²) / (2 s r). So
     *   ∫_disk R_d dA = ∫_0^{ρ−r} R_d 2πs ds + ∫_{|ρ−r|}^{ρ+r} R_d(s) 2 s θ(s) ds,
     * the first part in closed form, the second by 16-point Gauss–Legendre
     * on pieces, each after s = lo + (hi − lo)(1 − cos t)/2, which smooths
     * the square-root ends of θ. */
    double full = rho > r ? sss_rd_disk(d, rho - r) : 0.0;
    const double a = fabs(rho - r), b = rho + r;
    if (!(b > a)) return full;
    /* R_d peaks at s = 0 on the scale z_r and decays on the scale 1/σtr:
     * pieces of geometrically growing length ℓ, 2ℓ, 4ℓ, … from a (ℓ the
     * smaller scale) resolve both; 16 nodes each */
    const double ell = fmax(fmin(d->z_r, d->sigma_tr > 0.0 ? 1.0 / d->sigma_tr : d->z_r), 1e-9 * (b - a));
    double part = 0.0, lo = a, len = ell;
    for (int p = 0; p < 24 && lo < b; p++) {
        const double hi = (p == 23 || lo + 2.0 * len >= b) ? b : lo + len;
        const double L = hi - lo;
        for (int k = 0; k < 16; k++) {
            const double x = k < 8 ? -GL_X[7 - k] : GL_X[k - 8], w = k < 8 ? GL_W[7 - k] : GL_W[k - 8];
            const double t = 0.5 * SSS_PI * (x + 1.0);
            const double sv = lo + 0.5 * L * (1.0 - cos(t)), ds = 0.5 * L * sin(t) * 0.5 * SSS_PI;
            if (!(sv > 0.0)) continue;
            double c = (sv * sv + r * r - rho * rho) / (2.0 * sv * r);
            c = c > 1.0 ? 1.0 : c < -1.0 ? -1.0 : c;
            part += w * ds * 2.0 * sv * acos(c) * sss_rd(d, sv);
        }
        lo = hi;
        len *= 2.0;
    }
    return full + part;
}

double sss_rd_total(const sss_dipole *d)
{
    double s = sqrt(3.0 * (1.0 - d->alpha_p));
    return 0.5 * d->alpha_p * (1.0 + exp(-(4.0 / 3.0) * d->A * s)) * exp(-s);
}

/* The energy outside radius R: (α′/2) Σ z e^{−σtr d(R)} / d(R); computed
 * directly, not as total − disk, so tiny tails keep their digits. */
static double rd_tail(const sss_dipole *d, double R)
{
    double dr = sqrt(R * R + d->z_r * d->z_r), dv = sqrt(R * R + d->z_v * d->z_v);
    return 0.5 * d->alpha_p * (d->z_r * exp(-d->sigma_tr * dr) / dr + d->z_v * exp(-d->sigma_tr * dv) / dv);
}

double sss_rd_radius(const sss_dipole *d, double eps, double r_max)
{
    double total = sss_rd_total(d);
    if (!(total > 0.0) || !(r_max > 0.0)) return 0.0;
    double target = eps * total;
    if (rd_tail(d, r_max) > target) return r_max; /* α′ → 1: r⁻¹-like tail, clamp */
    double lo = 0.0, hi = r_max;
    for (int it = 0; it < 200 && hi - lo > 1e-12 * hi; it++) {
        double mid = 0.5 * (lo + hi);
        if (rd_tail(d, mid) > target) lo = mid;
        else hi = mid;
    }
    return hi;
}

double sss_material_slab_q(const sss_material *m, uint32_t channels)
{
    double q = 0.0;
    for (uint32_t c = 0; c < channels && c < SSS_MAX_CHANNELS; c++) {
        sss_dipole d;
        if (sss_dipole_init(&d, m->sigma_a[c], m->sigmap_s[c], m->eta) != SSS_OK) return 0.0;
        q = fmax(q, sss_ft(m->eta, 1.0) * sss_rd_total(&d) / SSS_PI);
    }
    return q;
}
