/* single.c: single scattering in homogeneous and flat layered media.
 *
 * Jensen, Marschner, Levoy and Hanrahan, "A practical model for subsurface
 * light transport" (SIGGRAPH 2001), §2.3 eq. 4–5: the first-order term S⁽¹⁾
 * with refracted directions and Fresnel at both crossings
 * (docs/layers.md §1). François, Pattanaik, Bouatouch and Breton,
 * "Subsurface Texture Mapping" (IRISA PI 1806, 2006; seed 002): layers of
 * given depth, the reduced intensity through the layers above (Eqs. 6, 11,
 * 12) and the ray march of Algorithms 1 and 2 (Eqs. 4, 5, 13).
 *
 * Every choice where the paper's pseudo-code and equations differ is listed
 * in docs/layers.md §3. Lengths in mm, coefficients in 1/mm.
 */
#include "sss/single.h"
#include "sss/dipole.h"
#include "sss/vec3.h"

#include <math.h>
#include <string.h>

double sss_phase_hg(double g, double cos_theta)
{
    const double den = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * SSS_PI * den * sqrt(den));
}

double sss_phase_schlick(double k, double cos_theta)
{
    const double den = 1.0 - k * cos_theta;
    return (1.0 - k * k) / (4.0 * SSS_PI * den * den);
}

double sss_phase_eval(sss_phase_kind kind, double g, double cos_theta)
{
    return kind == SSS_PHASE_SCHLICK ? sss_phase_schlick(g, cos_theta) : sss_phase_hg(g, cos_theta);
}

double sss_ss_refract(const double n[3], const double w[3], double eta, double t[3])
{
    const double c = sss_dot3(n, w);
    const double s2 = (1.0 - c * c) / (eta * eta);
    const double ct = sqrt(fmax(0.0, 1.0 - s2));
    for (int k = 0; k < 3; k++) t[k] = -w[k] / eta + (c / eta - ct) * n[k];
    return ct;
}

int sss_ss_geometry(const double n[3], const double wi[3], const double wo[3], double eta, int refract,
                    sss_ss_geom *g)
{
    memset(g, 0, sizeof *g);
    const double ci = sss_dot3(n, wi), co = sss_dot3(n, wo);
    if (!(ci > 0.0) || !(co > 0.0)) return 0;
    double ti[3], to[3];
    if (refract) {
        g->mu_i = sss_ss_refract(n, wi, eta, ti);
        g->mu_o = sss_ss_refract(n, wo, eta, to);
        /* in: F_t of the irradiance over the refracted beam's cross-section;
         * out: F_t of the radiance, over η² (docs/reference.md §5.4) */
        g->boundary = sss_ft(eta, ci) * ci / g->mu_i * sss_ft(eta, co) / (eta * eta);
    } else {
        for (int k = 0; k < 3; k++) ti[k] = -wi[k], to[k] = -wo[k];
        g->mu_i = ci;
        g->mu_o = co;
        g->boundary = 1.0;
    }
    /* the scattered light propagates against the view ray's way in (−to) */
    g->cos_phase = -sss_dot3(ti, to);
    memcpy(g->dir_i, ti, sizeof ti);
    memcpy(g->dir_o, to, sizeof to);
    return 1;
}

double sss_ss_halfspace(double sigma_s, double sigma_t, double hg_g, const sss_ss_geom *g)
{
    if (!(sigma_t > 0.0)) return 0.0;
    /* ∫₀^∞ e^{−σt s μ_o/μ_i} e^{−σt s} ds = μ_i / (σt (μ_i + μ_o)) */
    return g->boundary * sigma_s * sss_phase_hg(hg_g, g->cos_phase) * g->mu_i / (sigma_t * (g->mu_i + g->mu_o));
}

double sss_ss_albedo(double sigma_s, double sigma_t, double hg_g, double eta)
{
    const int cells = 1024;
    const double n[3] = {0.0, 0.0, 1.0};
    double sum = 0.0;
    for (int k = 0; k < cells; k++) {
        const double mu = (k + 0.5) / cells;
        const double wo[3] = {sqrt(1.0 - mu * mu), 0.0, mu};
        sss_ss_geom g;
        if (sss_ss_geometry(n, n, wo, eta, 1, &g)) sum += sss_ss_halfspace(sigma_s, sigma_t, hg_g, &g) * mu;
    }
    /* ∫ L cos θ_o dω_o = 2π ∫₀¹ L(μ) μ dμ; E = L_i at normal incidence */
    return 2.0 * SSS_PI * sum / cells;
}

uint32_t sss_layers_find(const sss_layer_stack *st, double z)
{
    uint32_t k = 0;
    while (k < st->n && !(z < st->layer[k].depth)) k++;
    return k;
}

double sss_layers_tau(const sss_layer_stack *st, uint32_t c, double z, double mu)
{
    return sss_layers_tau_path(st, c, z / mu, mu);
}

double sss_layers_tau_path(const sss_layer_stack *st, uint32_t c, double km, double mu)
{
    /* Eq. 12: the path's length in layer j is what is left of |KM| after
     * the layers above, at most the layer's own slant thickness, and never
     * negative (the clamp the equation lacks) */
    double left = km, tau = 0.0, top = 0.0;
    for (uint32_t j = 0; j < st->n && left > 0.0; j++) {
        const double Dj = (st->layer[j].depth - top) / mu;
        const double d = fmax(0.0, fmin(left, Dj));
        tau += st->layer[j].sigma_t[c] * d;
        left -= Dj;
        top = st->layer[j].depth;
    }
    return tau;
}

double sss_layers_closed(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g)
{
    const double m = 1.0 / g->mu_i + 1.0 / g->mu_o;
    double sum = 0.0, tau = 0.0, top = 0.0;
    for (uint32_t k = 0; k < st->n; k++) {
        const sss_layer *L = &st->layer[k];
        const double h = L->depth - top, st_k = L->sigma_t[c];
        top = L->depth;
        if (!(h > 0.0) || !(st_k > 0.0)) continue; /* no thickness, or nothing scatters nor attenuates */
        const double p = sss_phase_eval(st->phase, L->g, g->cos_phase);
        /* ∫ over layer k's depths z of σs p e^{−τ(z) m} dz / μ_o, τ linear in z */
        const double open = isinf(h) ? 1.0 : -expm1(-st_k * h * m);
        sum += L->sigma_s[c] * p * g->mu_i / (st_k * (g->mu_i + g->mu_o)) * exp(-tau * m) * open;
        tau += st_k * h;
    }
    return g->boundary * sum;
}

double sss_ss_march(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g, double s_max, uint32_t n,
                    sss_ss_locate_fn locate, void *user)
{
    if (n == 0) return 0.0;
    const double delta = s_max / n;
    double L = 0.0, T = 1.0; /* Algorithm 1's L(P, ω_out) and AttenuationPM */
    for (uint32_t j = 0; j < n; j++) {
        sss_ss_point pt;
        locate(user, c, j * delta, &pt);
        if (pt.layer >= st->n) continue; /* below every layer: nothing there */
        const sss_layer *ly = &st->layer[pt.layer];
        L += ly->sigma_s[c] * sss_phase_eval(st->phase, ly->g, g->cos_phase) * exp(-pt.tau_light) * T * delta;
        T *= exp(-ly->sigma_t[c] * delta); /* Eq. 13 */
    }
    return g->boundary * L;
}

/* (1 − e^{−x}) / x, 1 at x = 0: the mean of e^{−t} over t ∈ [0, x]. */
static double mean_exp(double x) { return fabs(x) < 1e-12 ? 1.0 - 0.5 * x : -expm1(-x) / x; }

/* One stretch [a, b] of layer k: adds its exact integral to *L, with both
 * optical depths linear in s, and advances the view's optical depth. */
static void segment(const sss_layer_stack *st, uint32_t c, double cos_phase, uint32_t k, double a, double b,
                    double tau_a, double tau_b, double *tau_view, double *L)
{
    if (k >= st->n) return;
    const sss_layer *ly = &st->layer[k];
    const double len = b - a, dv = ly->sigma_t[c] * len;
    const double Ea = tau_a + *tau_view, Eb = tau_b + *tau_view + dv;
    /* ∫ e^{−E} over a linear E is symmetric in its ends: taken from the
     * smaller, so that a large optical depth at either end (a shaded entry
     * point) gives a finite answer */
    *L += ly->sigma_s[c] * sss_phase_eval(st->phase, ly->g, cos_phase) * len * exp(-fmin(Ea, Eb)) *
          mean_exp(fabs(Eb - Ea));
    *tau_view += dv;
}

double sss_ss_march_segments(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g, double s_max,
                             uint32_t n, sss_ss_locate_fn locate, void *user)
{
    if (n == 0) return 0.0;
    const double delta = s_max / n, tol = ldexp(s_max, -40);
    double L = 0.0, tau_view = 0.0;
    sss_ss_point pa;
    locate(user, c, 0.0, &pa);
    double a = 0.0;
    for (uint32_t j = 0; j < n; j++) {
        const double b = (j + 1 == n) ? s_max : (j + 1) * delta;
        sss_ss_point pb;
        locate(user, c, b, &pb);
        while (pa.layer != pb.layer) {
            /* a crossing inside [a, b]: bisect for the first point out of pa's layer */
            double lo = a, hi = b;
            sss_ss_point ph = pb;
            while (hi - lo > tol) {
                const double mid = 0.5 * (lo + hi);
                sss_ss_point pm;
                locate(user, c, mid, &pm);
                if (pm.layer == pa.layer)
                    lo = mid;
                else
                    hi = mid, ph = pm;
            }
            segment(st, c, g->cos_phase, pa.layer, a, hi, pa.tau_light, ph.tau_light, &tau_view, &L);
            a = hi;
            pa = ph;
        }
        segment(st, c, g->cos_phase, pa.layer, a, b, pa.tau_light, pb.tau_light, &tau_view, &L);
        a = b;
        pa = pb;
    }
    return g->boundary * L;
}

void sss_ss_locate_flat(void *user, uint32_t c, double s, sss_ss_point *out)
{
    const sss_ss_flat *f = user;
    const double z = s * f->mu_o;
    out->layer = sss_layers_find(f->stack, z);
    out->tau_light = sss_layers_tau(f->stack, c, z, f->mu_i);
}
