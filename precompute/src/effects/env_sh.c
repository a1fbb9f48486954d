/* env_sh.c: the environment-sh effect (docs/scenes.md). Under distant
 * radiance L(ω) the scattered term is ∫ L(ω) q(x_o, ω) dω, q the §3.1
 * integral per unit irradiance from ω. Projecting both onto the real SH
 * basis y_i (sss/sh.h, orthonormal) turns it into a dot product,
 *     ∫ L q dω = Σ_i L_i T_i(x_o),   T_i(x_o) = ∫ q(x_o, ω) y_i(ω) dω,
 * exact when L is band-limited to the order used (Sloan et al. 2002's
 * precomputed transfer; Hao–Varshney 2004 §2 cite it for this lighting).
 * q is linear in G (§3.1), so T_i = Σ_j w(o, j) g_i(x_j) with
 * g_i(x) = ∫ G(x, ω) y_i(ω) dω: one SH projection per vertex, then the
 * same sparse sum as every other pass. The probe's L_i are stored with the
 * file for convenience; a renderer may replace or rotate them.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effect.h"
#include "kernels/transfer.h"
#include "sss/bake_scene.h" /* sss_env_sh_dirs */
#include "sss/probe.h"
#include "sss/effects.h"
#include "sss/sh.h"
#include "sss/vec3.h"

uint32_t sss_env_sh_dirs(uint32_t order)
{
    const uint32_t K = order * order;
    return K * 128 > 2048 ? K * 128 : 2048;
}

static int claim(const sss_scene *s, const sss_object_plan *p, const sss_scene_light *L, char *reason, size_t n)
{
    (void)s;
    (void)p;
    if (L->kind != SSS_LIGHT_ENVIRONMENT) return 0;
    snprintf(reason, n, "environment probe: q projected onto SH per vertex and dotted with the probe's SH at run "
             "time%s", L->moving ? " (rotating the probe rotates its coefficients)" : "");
    return 1;
}

static sss_result bake(const sss_pass_ctx *c, sss_error *err)
{
    const uint32_t order = c->sh_order, K = order * order, nv = c->mesh->nv;
    sss_effects *fx = &c->out->fx;
    /* the probes: Σ over environment lights of intensity · colour · L_i */
    double Lsum[3 * SSS_SH_MAX_COUNT] = {0};
    for (uint32_t l = 0; l < c->scene->nlights; l++) {
        if (c->plan->light_pass[l] != SSS_PASS_ENV_SH) continue;
        const sss_scene_light *L = &c->scene->lights[l];
        sss_probe pr;
        sss_result r = sss_probe_read_limited(L->probe, c->memory_left, &pr, err);
        if (r != SSS_OK) return r;
        double Ll[3 * SSS_SH_MAX_COUNT];
        sss_probe_sh(&pr, order, Ll);
        sss_probe_free(&pr);
        for (int ch = 0; ch < 3; ch++) {
            sss_sh_rotate_z(order, L->rotation_deg * (SSS_PI / 180.0), &Ll[ch * K]);
            for (uint32_t i = 0; i < K; i++) Lsum[ch * K + i] += L->intensity * L->colour[ch] * Ll[ch * K + i];
        }
    }
    for (uint32_t i = 0; i < 3 * K; i++) fx->env_probe[i] = (float)Lsum[i];

    /* g_i(x) by quadrature over a spherical Fibonacci set of M nearly
     * equal-area directions (weight 4π/M each): enough samples that the
     * horizon kink of max(0, n·ω) and the shadow edges average out for the
     * low orders used here */
    const uint32_t M = sss_env_sh_dirs(order);
    sss_dirset q = {0};
    sss_result r = sss_dirset_fibonacci(&q, M, err);
    if (r != SSS_OK) return r;
    double *gsh = calloc((size_t)nv * K, sizeof(double));
    double *Y = malloc((size_t)M * K * sizeof(double));
    float *g32 = malloc((size_t)nv * K * sizeof(float) + 1);
    float *tmp = malloc((size_t)nv * K * c->C * sizeof(float) + 1);
    fx->env_t = malloc((size_t)nv * K * c->C * sizeof(float) + 1);
    if (!gsh || !Y || !g32 || !tmp || !fx->env_t) {
        r = sss_fail(err, SSS_ERR_NOMEM, "environment-sh pass: out of memory for %u vertices", nv);
        goto done;
    }
    const double wq = 4.0 * SSS_PI / M;
    for (uint32_t m = 0; m < M; m++) sss_sh_eval(order, &q.dir[3 * (size_t)m], &Y[(size_t)m * K]);
    uint64_t rays = 0;
    /* vertex-outer, directions in order: deterministic sums, one parallel
     * region */
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : rays)
    for (int64_t i = 0; i < (int64_t)nv; i++) {
        double *g = &gsh[(size_t)i * K];
        for (uint32_t m = 0; m < M; m++) {
            int traced = 0;
            const float G = sss_transfer_one(c->mesh, c->vis, (uint32_t)i, &q.dir[3 * (size_t)m], c->eta, &traced, NULL);
            rays += (uint64_t)(traced && c->vis);
            if (G == 0.0f) continue;
            const double gw = G * wq;
            for (uint32_t k = 0; k < K; k++) g[k] += gw * Y[(size_t)m * K + k];
        }
    }
    c->st->rays += rays;
    for (size_t k = 0; k < (size_t)nv * K; k++) g32[k] = (float)gsh[k];
    /* T = Σ_j w(o, j) g(x_j): the SH coefficients play the directions */
    if ((r = sss_pass_integrate(c, g32, K, 1, tmp, err)) != SSS_OK) goto done; /* SH coefficients take either sign */
    for (uint32_t v = 0; v < nv; v++)
        for (uint32_t ch = 0; ch < c->C; ch++)
            for (uint32_t k = 0; k < K; k++)
                fx->env_t[((size_t)v * c->C + ch) * K + k] = tmp[((size_t)k * nv + v) * c->C + ch];
    fx->env_order = order;
done:
    free(gsh);
    free(Y);
    free(g32);
    free(tmp);
    sss_dirset_free(&q);
    return r;
}

static void provenance(const sss_pass_ctx *c, cJSON *params) { cJSON_AddNumberToObject(params, "sh_order", c->sh_order); }

/* The probes' pixels are planned where they are read
 * (sss_probe_read_limited, with what is left after this). */
static void memory(const sss_pass_ctx *c, uint64_t *kept, uint64_t *transient)
{
    const uint64_t nv = c->mesh->nv, K = (uint64_t)c->sh_order * c->sh_order;
    const uint64_t M = sss_env_sh_dirs(c->sh_order);
    *kept = nv * K * c->C * 4u;
    *transient = nv * K * 8u + M * K * 8u + M * 36u + nv * K * 4u + nv * K * c->C * 4u; /* gsh, Y, directions, g32, tmp */
}

const sss_effect_unit sss_effect_env_sh = {SSS_PASS_ENV_SH, "environment-sh", SSS_FX_ENV_SH, claim, bake, provenance,
                                           memory};
