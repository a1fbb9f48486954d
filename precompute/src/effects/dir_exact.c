/* dir_exact.c: the directional-exact effect (docs/scenes.md). A static
 * directional light, or a static point light far enough that its direction
 * and falloff hardly vary across the object, gets q(x_o, ω_l) of
 * Hao–Varshney 2004 §3.1 for exactly its direction ω_l: one value per
 * vertex and channel, without the §3.2 direction set and its interpolation
 * error (section QDIR, docs/format.md §5.11).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effect.h"

static int claim(const sss_scene *s, const sss_object_plan *p, const sss_scene_light *L, char *reason, size_t n)
{
    if (L->kind == SSS_LIGHT_DIRECTIONAL && !L->moving) {
        snprintf(reason, n, "static directional light: q baked exactly for direction (%.4g, %.4g, %.4g), one value "
                 "per vertex and channel, no interpolation", L->direction[0], L->direction[1], L->direction[2]);
        return 1;
    }
    if (L->kind != SSS_LIGHT_POINT) return 0;
    const double near = sss_near_factor(s), ratio = sss_point_ratio(p, L);
    if (ratio < near || L->moving) return 0; /* the point-shells effect's */
    snprintf(reason, n, "static point light %.3g object sizes away (>= %g): treated as a directional light from the "
             "object's centre, baked exactly", ratio, near);
    return 1;
}

/* Static directional lights (and far static point lights, taken from the
 * object's centre): q(x_o, ω_l) of §3.1 for exactly ω_l. */
static sss_result bake(const sss_pass_ctx *c, sss_error *err)
{
    const sss_scene *s = c->scene;
    const uint32_t nv = c->mesh->nv, nl = c->plan->exact_rows;
    sss_effects *fx = &c->out->fx;
    fx->exact_dir = malloc(3 * (size_t)nl * sizeof(double));
    fx->exact_q = malloc((size_t)nl * nv * c->C * sizeof(float) + 1);
    float *G = malloc((size_t)nv * sizeof(float) + 1);
    if (!fx->exact_dir || !fx->exact_q || !G) {
        free(G);
        return sss_fail(err, SSS_ERR_NOMEM, "directional-exact pass: out of memory");
    }
    uint32_t k = 0;
    for (uint32_t l = 0; l < s->nlights; l++) {
        if (c->plan->light_pass[l] != SSS_PASS_DIR_EXACT) continue;
        double d[3];
        sss_plan_exact_direction(c->plan, &s->lights[l], d);
        /* one row per direction: lights sharing one are summed by the
         * viewer from that row (the planner counted the rows) */
        uint32_t j = 0;
        while (j < k && !sss_plan_same_direction(&fx->exact_dir[3 * (size_t)j], d)) j++;
        if (j < k) continue;
        memcpy(&fx->exact_dir[3 * (size_t)k], d, sizeof d);
        sss_pass_transfer(c, d, 1, G, &c->st->rays);
        const sss_result r = sss_pass_integrate(c, G, 1, 0, &fx->exact_q[(size_t)k * nv * c->C], err);
        if (r != SSS_OK) {
            free(G);
            return r;
        }
        k++;
    }
    fx->nexact = k;
    free(G);
    return SSS_OK;
}

static void memory(const sss_pass_ctx *c, uint64_t *kept, uint64_t *transient)
{
    const uint64_t nv = c->mesh->nv, nl = c->plan->exact_rows;
    *kept = nl * (24u + nv * c->C * 4u);
    *transient = nv * 4u;
}

const sss_effect_unit sss_effect_dir_exact = {SSS_PASS_DIR_EXACT, "directional-exact", SSS_FX_DIR_EXACT, claim, bake,
                                              NULL, memory};
