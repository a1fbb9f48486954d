/* effects.c: run-time side of the scene-bake effects (sss/effects.h). The
 * renderer sums one term per light (design.md "Effects": several lights →
 * the sum), each from the parameterisation the planner chose. */
#include "sss/effects.h"

#include <math.h>
#include <string.h>

const float *sss_fx_exact(const sss_bake_file *f, uint32_t l)
{
    if (!(f->fx.mask & SSS_FX_DIR_EXACT) || l >= f->fx.nexact) return NULL;
    return f->fx.exact_q + (size_t)l * f->mesh.nv * f->channels;
}

void sss_fx_env(const sss_bake_file *f, const float *L, float *out)
{
    sss_fx_env_range(f, L, 0, f->mesh.nv, out);
}

void sss_fx_env_range(const sss_bake_file *f, const float *L, uint32_t first, uint32_t count, float *out)
{
    const uint32_t C = f->channels, K = f->fx.env_order * f->fx.env_order;
    if (first > f->mesh.nv || count > f->mesh.nv - first) return;
    if (!(f->fx.mask & SSS_FX_ENV_SH) || !K) {
        memset(out, 0, (size_t)count * 3 * sizeof *out);
        return;
    }
    if (!L) L = f->fx.env_probe;
    for (uint32_t v = first; v < first + count; v++)
        for (uint32_t k = 0; k < 3; k++) {
            const float *T = &f->fx.env_t[((size_t)v * C + (C == 3 ? k : 0)) * K];
            double acc = 0.0;
            for (uint32_t i = 0; i < K; i++) acc += (double)T[i] * L[k * K + i];
            /* the SH truncation can ring below zero; radiance cannot */
            out[(size_t)(v - first) * 3 + k] = acc > 0.0 ? (float)acc : 0.0f;
        }
}

int sss_fx_point_weights(const sss_bake_file *f, const double P[3], uint32_t row[6], double w[6], double *r2)
{
    const sss_effects *x = &f->fx;
    const uint32_t n = f->dirs.n, S = x->nshells;
    double d[3], rr = 0;
    for (int k = 0; k < 3; k++) d[k] = P[k] - x->shell_centre[k], rr += d[k] * d[k];
    const double r = sqrt(rr);
    for (int k = 0; k < 6; k++) row[k] = 0, w[k] = 0.0;
    *r2 = 1.0;
    if (!(f->fx.mask & SSS_FX_POINT_SHELLS) || !(r > 0) || !isfinite(r) || S < 2) return 0;
    /* §3.3: barycentric over the spherical triangle of directions around
     * P − c, linear in r between the two shells around |P − c| */
    uint32_t idx[3];
    double wb[3];
    sss_dirset_lookup(&f->dirs, d, idx, wb);
    uint32_t s = 0;
    while (s + 2 < S && r > x->shell_radius[s + 1]) s++;
    double t = (r - x->shell_radius[s]) / (x->shell_radius[s + 1] - x->shell_radius[s]);
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    const double ws[2] = {1.0 - t, t};
    for (int a = 0; a < 2; a++)
        for (int b = 0; b < 3; b++) {
            row[a * 3 + b] = (s + (uint32_t)a) * n + idx[b];
            w[a * 3 + b] = ws[a] * wb[b];
        }
    /* q_pt = stored / r²: a light inside the first shell is taken at its
     * radius (at least SSS_SHELL_RADIUS_MIN, docs/format.md §5.13), so a
     * light at the centre gives finite values, not 1/0 */
    const double r0 = x->shell_radius[0];
    *r2 = rr > r0 * r0 ? rr : r0 * r0;
    return 1;
}

void sss_fx_point(const sss_bake_file *f, const double P[3], float *out)
{
    sss_fx_point_range(f, P, 0, f->mesh.nv, out);
}

void sss_fx_point_range(const sss_bake_file *f, const double P[3], uint32_t first, uint32_t count, float *out)
{
    if (first > f->mesh.nv || count > f->mesh.nv - first) return;
    const size_t C = f->channels, NVC = (size_t)f->mesh.nv * C, e0 = (size_t)first * C, ne = (size_t)count * C;
    uint32_t row[6];
    double w[6], r2;
    if (!sss_fx_point_weights(f, P, row, w, &r2)) {
        memset(out, 0, ne * sizeof *out);
        return;
    }
    const float *q = f->fx.shell_q;
    /* the GPU path (runtime/shaders/point_shells.comp.glsl) forms the same double sum in
     * the same order, so the two agree to the bit */
    for (size_t e = 0; e < ne; e++) {
        double acc = 0.0;
        for (int k = 0; k < 6; k++) acc += w[k] * q[(size_t)row[k] * NVC + e0 + e];
        out[e] = (float)(acc / r2);
    }
}

void sss_sh_rotate_z(uint32_t order, double alpha, double *c)
{
    for (uint32_t l = 0; l < order; l++)
        for (uint32_t m = 1; m <= l; m++) {
            const size_t ip = l * (l + 1) + m, in = l * (l + 1) - m;
            const double cm = cos(m * alpha), sm = sin(m * alpha);
            const double a = c[ip], b = c[in];
            c[ip] = a * cm - b * sm;
            c[in] = a * sm + b * cm;
        }
}
