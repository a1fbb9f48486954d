/* splat.c: the tables and tests of Chen et al. 2012's multiresolution
 * splatting that need no GL (sss/splat.h; Chen et al. 2012 §4, Eqs. 10–16). */
#include "sss/splat.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/vec3.h"

double sss_splat_required_rate(double alpha, double R_w, double R_P, double n_dot_L)
{
    const double c = fabs(n_dot_L);
    if (!(c > 0) || !(R_P > 0)) return INFINITY;
    return alpha * R_w / (R_P * c);
}

int sss_splat_sample_valid(double z_max, double z_min, double z0, double T, double M)
{
    return z_max - z_min < z0 && T > M;
}

/* The largest radius R_P may take (mm): the radius rule's bisection bound
 * (sss_rd_radius; a tail of r⁻³ as α′ → 1 would otherwise reach it). */
#define SPLAT_R_MAX 1e6

sss_result sss_splat_profile_dipole(const sss_dipole *dip, uint32_t channels, uint32_t n, sss_splat_profile *out,
                                    sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (n < 2) return sss_fail(err, SSS_ERR_ARG, "splat profile: %u samples (at least 2)", n);
    if (channels != 1 && channels != 3) return sss_fail(err, SSS_ERR_ARG, "splat profile: %u channels (1 or 3)", channels);
    double C[3];
    for (uint32_t c = 0; c < channels; c++) {
        /* R_P: the disk holding SSS_SPLAT_ENERGY of R_d,total (Eq. 11) */
        out->R_P[c] = sss_rd_radius(&dip[c], 1.0 - SSS_SPLAT_ENERGY, SPLAT_R_MAX);
        /* Eq. 16: ∫_0^{R_P} R_d(r) r dr = (the disk's integral) / 2π */
        const double m = sss_rd_disk(&dip[c], out->R_P[c]) / (2.0 * SSS_PI);
        if (!(out->R_P[c] > 0) || !(m > 0))
            return sss_fail(err, SSS_ERR_ARG, "splat profile: channel %u scatters nothing (R_d,total 0)", c);
        C[c] = out->R_P[c] * out->R_P[c] / m;
    }
    out->p = malloc((size_t)n * sizeof *out->p);
    if (!out->p) return sss_fail(err, SSS_ERR_NOMEM, "splat profile: out of memory for %u samples", n);
    out->n = n;
    out->channels = channels;
    for (uint32_t i = 0; i < n; i++) { /* Eq. 15, averaged over the profiles */
        const double r = (double)i / (n - 1);
        double s = 0;
        for (uint32_t c = 0; c < channels; c++) s += C[c] * sss_rd(&dip[c], r * out->R_P[c]);
        out->p[i] = s / channels;
    }
    return SSS_OK;
}

void sss_splat_profile_free(sss_splat_profile *p)
{
    if (!p) return;
    free(p->p);
    memset(p, 0, sizeof *p);
}

/* P̄ at r ∈ [0, 1], linear between the samples (0 beyond 1). */
static double pbar(const sss_splat_profile *p, double r)
{
    if (r < 0 || r > 1) return 0.0;
    const double x = r * (p->n - 1);
    uint32_t i = (uint32_t)x;
    if (i >= p->n - 1) return p->p[p->n - 1];
    const double w = x - i;
    return (1 - w) * p->p[i] + w * p->p[i + 1];
}

/* ∫_r^1 P̄(s) s ds on the samples' grid: the exact integral of the linear
 * interpolant times s, summed from the top so that it is 0 at r = 1. */
static double tail_integral(const sss_splat_profile *p, double r)
{
    const uint32_t n = p->n;
    const double h = 1.0 / (n - 1);
    double sum = 0;
    for (uint32_t i = n - 1; i > 0; i--) {
        const double a = (i - 1) * h, b = i * h;
        if (b <= r) break;
        const double lo = a > r ? a : r;
        /* ∫_lo^b f(s) s ds, f linear between (a, f_a) and (b, f_b): Simpson
         * is exact for this cubic */
        const double mid = 0.5 * (lo + b);
        sum += (b - lo) / 6.0 * (pbar(p, lo) * lo + 4.0 * pbar(p, mid) * mid + pbar(p, b) * b);
    }
    return sum;
}

/* Eq. 14's difference at r for resolution T. */
static double splat_error(const sss_splat_profile *p, double T, double r)
{
    const uint32_t M = (uint32_t)floor((1.0 - r) * T);
    double s = 0;
    for (uint32_t m = 0; m <= M; m++) {
        const double rh = r + m / T;
        s += pbar(p, rh) * rh;
    }
    return fabs(s / T - tail_integral(p, r));
}

double sss_splat_min_radius(const sss_splat_profile *p, double T, double eps)
{
    if (!p || !p->p || !(T > 0) || !(eps > 0)) return 1.0;
    /* from r = 1 down on a grid of the table's spacing: the smallest r from
     * which on every r' ≥ r meets ε (the error is not monotone: a sum can
     * cross the integral by chance close to the peak) */
    const uint32_t steps = p->n - 1;
    double rbar = 1.0;
    for (uint32_t i = steps; i-- > 0;) {
        const double r = (double)i / steps;
        if (!(splat_error(p, T, r) < eps)) break;
        rbar = r;
    }
    return rbar;
}

void sss_splat_level_ranges(const sss_splat_profile *p, double R_P, double T0, uint32_t n_levels, double eps,
                            double *rmin, double *rmax)
{
    if (n_levels == 0) return;
    rmin[0] = 0.0;
    for (uint32_t k = 1; k < n_levels; k++) {
        const double Tk = T0 / (double)(1u << (k < 31 ? k : 31));
        double r = R_P * sss_splat_min_radius(p, Tk, eps);
        if (r < rmin[k - 1]) r = rmin[k - 1];
        if (r > R_P) r = R_P;
        rmin[k] = r;
    }
    for (uint32_t k = 0; k + 1 < n_levels; k++) rmax[k] = rmin[k + 1];
    rmax[n_levels - 1] = R_P;
}
