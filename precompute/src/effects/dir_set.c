/* dir_set.c: the direction-set effect (docs/scenes.md): a moving
 * directional light gets q over the set of light directions of
 * Hao–Varshney 2004 §3.2, interpolated at run time — what a plain bake
 * stores (sections DIRS and QFLT, docs/format.md §5.3–5.4).
 */
#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>

#include "effects/effect.h"

static int claim(const sss_scene *s, const sss_object_plan *p, const sss_scene_light *L, char *reason, size_t n)
{
    (void)s;
    (void)p;
    if (L->kind != SSS_LIGHT_DIRECTIONAL || !L->moving) return 0;
    snprintf(reason, n, "moving directional light: q baked over a set of directions and interpolated at run time "
             "(Hao-Varshney 2004 sec. 3.2)");
    return 1;
}

/* Moving directional lights: the direction set of §3.2 (what sss_bake
 * stores), float values. */
static sss_result bake(const sss_pass_ctx *c, sss_error *err)
{
    sss_bake_file *o = c->out;
    if (!o->dirs.n) {
        sss_result r = sss_dirset_fibonacci(&o->dirs, c->n_dirs, err);
        if (r != SSS_OK) return r;
    }
    const uint32_t nv = c->mesh->nv, n = o->dirs.n;
    float *G = malloc((size_t)nv * n * sizeof(float) + 1);
    o->q = malloc((size_t)n * nv * c->C * sizeof(float) + 1);
    if (!G || !o->q) {
        free(G);
        return sss_fail(err, SSS_ERR_NOMEM, "direction-set pass: out of memory for %u x %u values", nv, n);
    }
    sss_pass_transfer(c, o->dirs.dir, n, G, &c->st->rays);
    const sss_result r = sss_pass_integrate(c, G, n, 0, o->q, err);
    free(G);
    o->quant = SSS_QUANT_FLOAT;
    return r;
}

static void provenance(const sss_pass_ctx *c, cJSON *params) { cJSON_AddNumberToObject(params, "dirs", c->n_dirs); }

static void memory(const sss_pass_ctx *c, uint64_t *kept, uint64_t *transient)
{
    const uint64_t nv = c->mesh->nv, n = c->n_dirs;
    *kept = n * nv * c->C * 4u + n * 36u; /* q, and the directions with their triangles */
    *transient = nv * n * 4u;             /* G */
}

const sss_effect_unit sss_effect_dir_set = {SSS_PASS_DIR_SET, "direction-set", SSS_FX_DIR_SET, claim, bake,
                                            provenance, memory};
