/* env_error.c: a scene bake's environment transfer (ENVT) against the
 * exact evaluator (see sss/env_error.h). T_i(x_o) = ∫ q(x_o, ω) y_i(ω) dω
 * (docs/scenes.md; Sloan et al. 2002's transfer, cited by Hao–Varshney
 * 2004 §2) is recomputed from the exact q of §3.1 at a few vertices over a
 * denser, independent quadrature than the bake's, and compared both as
 * coefficients and as the radiance Σ_i T_i L_i the viewer shows.
 */
#include "sss/env_error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/bake_scene.h" /* sss_env_sh_dirs */
#include "sss/decode.h"     /* sss_err_accum */
#include "sss/dirset.h"
#include "sss/effects.h"    /* sss_fx_env */
#include "sss/mesh.h"
#include "sss/random.h"
#include "sss/sh.h"
#include "sss/vec3.h"

/* Reference directions evaluated per call of sss_exact_subset_eval. */
#define ENV_BATCH 256u

/* The receivers: n distinct vertices of nv in the order a partial
 * Fisher–Yates shuffle from *st draws them (0 … nv−1 when nv ≤ n). */
static uint32_t draw_receivers(uint32_t nv, uint32_t n, uint64_t *st, uint32_t *out, uint32_t *perm)
{
    if (nv <= n) {
        for (uint32_t v = 0; v < nv; v++) out[v] = v;
        return nv;
    }
    for (uint32_t v = 0; v < nv; v++) perm[v] = v;
    for (uint32_t k = 0; k < n; k++) {
        uint32_t j = k + (uint32_t)(sss_rng_unit(st) * (nv - k)); /* in [k, nv) */
        if (j >= nv) j = nv - 1;
        const uint32_t t = perm[k];
        perm[k] = perm[j];
        perm[j] = t;
        out[k] = perm[k];
    }
    return n;
}

/* A uniformly random rotation (rows r[0], r[1], r[2]): the first row a
 * random direction, the second a random direction made orthogonal to it. */
static void random_rotation(uint64_t *st, double r[3][3])
{
    double b[3];
    sss_rng_direction(st, r[0]);
    for (;;) {
        sss_rng_direction(st, b);
        const double p = b[0] * r[0][0] + b[1] * r[0][1] + b[2] * r[0][2];
        for (int k = 0; k < 3; k++) b[k] -= p * r[0][k];
        const double l = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
        if (l > 1e-3) {
            for (int k = 0; k < 3; k++) r[1][k] = b[k] / l;
            break;
        }
    }
    r[2][0] = r[0][1] * r[1][2] - r[0][2] * r[1][1];
    r[2][1] = r[0][2] * r[1][0] - r[0][0] * r[1][2];
    r[2][2] = r[0][0] * r[1][1] - r[0][1] * r[1][0];
}

/* A random environment band-limited to the file's order: a constant
 * radiance in [0.5, 1] per channel plus three directional lights of
 * intensity in [0, 1] per channel, each projected onto the K coefficients
 * (L_i = I y_i(d); sss/sh.h). */
static void random_environment(uint32_t order, uint64_t *st, float *L)
{
    const uint32_t K = order * order;
    double acc[3 * SSS_SH_MAX_COUNT] = {0}, y[SSS_SH_MAX_COUNT];
    for (int c = 0; c < 3; c++) acc[c * K] = (0.5 + 0.5 * sss_rng_unit(st)) * sqrt(4.0 * SSS_PI); /* y_0 = 1/√(4π) */
    for (int l = 0; l < 3; l++) {
        double d[3], I[3];
        sss_rng_direction(st, d);
        for (int c = 0; c < 3; c++) I[c] = sss_rng_unit(st);
        sss_sh_eval(order, d, y);
        for (int c = 0; c < 3; c++)
            for (uint32_t i = 0; i < K; i++) acc[c * K + i] += I[c] * y[i];
    }
    for (uint32_t i = 0; i < 3 * K; i++) L[i] = (float)acc[i];
}

/* The radiance of environment L at the receivers, from the file (sss_fx_env
 * over the mesh, read at the receivers) and from the reference transfer
 * tref[(k * C + c) * K + i], clamped at 0 as sss_fx_env clamps it; added to
 * acc (3 channels, weights area). */
static void radiance_error(const sss_bake_file *f, const float *L, const uint32_t *verts, uint32_t n,
                           const double *tref, const double *area, float *all, float *a, float *r, sss_err_accum *acc)
{
    const uint32_t C = f->channels, K = f->fx.env_order * f->fx.env_order;
    sss_fx_env(f, L, all);
    for (uint32_t k = 0; k < n; k++)
        for (uint32_t ch = 0; ch < 3; ch++) {
            const double *T = &tref[((size_t)k * C + (C == 3 ? ch : 0)) * K];
            double s = 0.0;
            for (uint32_t i = 0; i < K; i++) s += T[i] * L[ch * K + i];
            r[3 * k + ch] = s > 0.0 ? (float)s : 0.0f;
            a[3 * k + ch] = all[(size_t)verts[k] * 3 + ch];
        }
    sss_err_accum_add(acc, area, a, r, n);
}

sss_result sss_env_error_measure(const sss_bake_file *f, sss_exact *e, uint32_t nrandom, uint64_t seed,
                                 sss_env_error *out, sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!f || !e || !out) return sss_fail(err, SSS_ERR_ARG, "environment error: NULL argument");
    if (!(f->fx.mask & SSS_FX_ENV_SH) || !f->fx.env_t || f->fx.env_order < 1 || f->fx.env_order > SSS_SH_MAX_ORDER)
        return sss_fail(err, SSS_ERR_ARG, "environment error: the file has no environment transfer (ENVT)");
    if (sss_exact_vertices(e) != f->mesh.nv || sss_exact_channels(e) != f->channels)
        return sss_fail(err, SSS_ERR_ARG, "environment error: exact evaluator (%u vertices, %u channels) is not for "
                        "this file (%u, %u)", sss_exact_vertices(e), sss_exact_channels(e), f->mesh.nv, f->channels);
    const uint32_t nv = f->mesh.nv, C = f->channels, order = f->fx.env_order, K = order * order;
    const uint32_t M = sss_env_sh_dirs(order), Mr = SSS_ENV_ERROR_REF_FACTOR * M;
    if (nrandom > SSS_ENV_ERROR_RANDOM_MAX) nrandom = SSS_ENV_ERROR_RANDOM_MAX;
    uint64_t st = seed ^ 0x454e5654u; /* "ENVT": a stream of its own, the same for a seed */

    sss_result r = SSS_OK;
    sss_exact_subset *sub = NULL;
    sss_dirset q = {0};
    uint32_t *verts = malloc(SSS_ENV_ERROR_VERTICES * sizeof *verts);
    uint32_t *perm = nv > SSS_ENV_ERROR_VERTICES ? malloc((size_t)nv * sizeof *perm) : NULL;
    double *area_all = malloc((size_t)nv * sizeof *area_all);
    double *area = malloc(SSS_ENV_ERROR_VERTICES * sizeof *area);
    double *tref = calloc((size_t)SSS_ENV_ERROR_VERTICES * C * K, sizeof *tref);
    float *qk = malloc((size_t)ENV_BATCH * SSS_ENV_ERROR_VERTICES * C * sizeof *qk);
    double *dirs = malloc(3 * (size_t)ENV_BATCH * sizeof *dirs);
    float *ta = malloc((size_t)SSS_ENV_ERROR_VERTICES * C * sizeof *ta);
    float *tr = malloc((size_t)SSS_ENV_ERROR_VERTICES * C * sizeof *tr);
    float *all = malloc((size_t)nv * 3 * sizeof *all);
    float *ra = malloc((size_t)SSS_ENV_ERROR_VERTICES * 3 * sizeof *ra);
    float *rr = malloc((size_t)SSS_ENV_ERROR_VERTICES * 3 * sizeof *rr);
    if (!verts || (nv > SSS_ENV_ERROR_VERTICES && !perm) || !area_all || !area || !tref || !qk || !ta || !tr || !all ||
        !ra || !rr || !dirs) {
        r = sss_fail(err, SSS_ERR_NOMEM, "environment error: out of memory for %u vertices", nv);
        goto done;
    }
    const uint32_t drawn = draw_receivers(nv, SSS_ENV_ERROR_VERTICES, &st, verts, perm);
    r = sss_exact_subset_create(e, verts, drawn, SSS_ENV_ERROR_EVALS / Mr, &sub, err);
    if (r != SSS_OK) goto done;
    const uint32_t n = sss_exact_subset_vertices(sub);
    r = sss_dirset_fibonacci(&q, Mr, err);
    if (r != SSS_OK) goto done;
    double R[3][3];
    random_rotation(&st, R);

    /* the bake's visibility rule: rays only where it traced them */
    const int shadows = (f->fx.mask & SSS_FX_SELF_SHADOW) != 0;
    sss_exact_set_shadows(e, shadows);
    /* T_ref = (4π / Mr) Σ_m q(x_k, R ω_m) y_i(R ω_m), summed in direction
     * order in double */
    const double wq = 4.0 * SSS_PI / Mr;
    for (uint32_t m0 = 0; m0 < Mr; m0 += ENV_BATCH) {
        const uint32_t B = Mr - m0 < ENV_BATCH ? Mr - m0 : ENV_BATCH;
        for (uint32_t b = 0; b < B; b++) {
            const double *w = &q.dir[3 * ((size_t)m0 + b)];
            for (int k = 0; k < 3; k++) dirs[3 * b + k] = R[k][0] * w[0] + R[k][1] * w[1] + R[k][2] * w[2];
        }
        sss_exact_subset_eval(sub, dirs, B, qk);
        for (uint32_t b = 0; b < B; b++) {
            double y[SSS_SH_MAX_COUNT];
            sss_sh_eval(order, &dirs[3 * b], y);
            for (uint32_t k = 0; k < n; k++)
                for (uint32_t c = 0; c < C; c++) {
                    const double qw = (double)qk[((size_t)b * n + k) * C + c] * wq;
                    if (qw == 0.0) continue;
                    double *T = &tref[((size_t)k * C + c) * K];
                    for (uint32_t i = 0; i < K; i++) T[i] += qw * y[i];
                }
        }
    }
    sss_exact_set_shadows(e, 1);

    /* the coefficients: one "direction" of the accumulator per i */
    sss_mesh_vertex_areas(&f->mesh, area_all);
    for (uint32_t k = 0; k < n; k++) area[k] = area_all[verts[k]];
    sss_err_accum acc;
    sss_err_accum_init(&acc, C, area, n);
    for (uint32_t i = 0; i < K; i++) {
        for (uint32_t k = 0; k < n; k++)
            for (uint32_t c = 0; c < C; c++) {
                ta[(size_t)k * C + c] = f->fx.env_t[((size_t)verts[k] * C + c) * K + i];
                tr[(size_t)k * C + c] = (float)tref[((size_t)k * C + c) * K + i];
            }
        sss_err_accum_add(&acc, area, ta, tr, n);
    }
    sss_err_accum_result(&acc, out->t_rms, out->t_rel_rms, out->t_max_abs, out->t_rms_exact);

    /* the radiance under the file's probe, when it stores one */
    int probe = 0;
    for (uint32_t i = 0; i < 3 * K; i++) probe |= f->fx.env_probe[i] != 0.0f;
    if (probe) {
        sss_err_accum_init(&acc, 3, area, n);
        radiance_error(f, f->fx.env_probe, verts, n, tref, area, all, ra, rr, &acc);
        sss_err_accum_result(&acc, out->probe_rms, out->probe_rel_rms, out->probe_max_abs, NULL);
    }
    /* and under random band-limited environments */
    for (uint32_t l = 0; l < nrandom; l++) {
        float L[3 * SSS_SH_MAX_COUNT];
        random_environment(order, &st, L);
        sss_err_accum_init(&acc, 3, area, n);
        radiance_error(f, L, verts, n, tref, area, all, ra, rr, &acc);
        double rel[4];
        sss_err_accum_result(&acc, NULL, rel, NULL, NULL);
        out->random_rel_rms_max = fmax(out->random_rel_rms_max, rel[3]);
        out->random_rel_rms_mean += rel[3] / nrandom;
    }
    out->order = order;
    out->channels = C;
    out->bake_dirs = M;
    out->ref_dirs = Mr;
    out->vertices = n;
    out->sources = sss_exact_subset_sources(sub);
    out->shadows = shadows;
    out->have_probe = probe;
    out->nrandom = nrandom;
done:
    sss_exact_subset_destroy(sub);
    sss_dirset_free(&q);
    free(verts);
    free(perm);
    free(area_all);
    free(area);
    free(tref);
    free(qk);
    free(dirs);
    free(ta);
    free(tr);
    free(all);
    free(ra);
    free(rr);
    return r;
}
