/* bake_scene.c: one object of a planned scene (docs/scenes.md). The
 * neighbourhoods and weights of §3.1 are built once and shared by every
 * pass; the passes differ only in how the light enters G(x_i, ·), one
 * effect unit each (effects/effect.h):
 *   directional-exact  one direction per static light, q stored as is (dir_exact.c);
 *   direction-set      the §3.2 set, interpolated at run time (dir_set.c);
 *   point-shells       §3.3 (point_shells.c);
 *   environment-sh     SH transfer (env_sh.c).
 * Visibility is traced against what the plan names (the object itself
 * unless it is convex, and the static occluders), and not at all when that
 * is nothing: a convex object alone pays no ray.
 */
#include "sss/bake_scene.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "effects/effect.h"
#include "kernels/progress.h"
#include "kernels/transfer.h"
#include "sss/memory.h"

void sss_pass_transfer(const sss_pass_ctx *c, const double *dirs, uint32_t n, float *G, uint64_t *rays_out)
{
    uint64_t rays = 0;
    /* vertex-outer: one parallel region for all directions */
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : rays)
    for (int64_t i = 0; i < (int64_t)c->mesh->nv; i++)
        for (uint32_t j = 0; j < n; j++) {
            int traced = 0;
            G[(size_t)i * n + j] = sss_transfer_one(c->mesh, c->vis, (uint32_t)i, &dirs[3 * (size_t)j], c->eta, &traced, NULL);
            rays += (uint64_t)(traced && c->vis);
        }
    if (rays_out) *rays_out += rays;
}

static char *params(const sss_scene *s, const sss_object_plan *p, const sss_pass_ctx *c, double eps,
                    const double *radius)
{
    cJSON *o = cJSON_CreateObject();
    if (!o) return NULL;
    const sss_scene_object *ob = &s->objects[p->object];
    cJSON_AddStringToObject(o, "generator", "sss-bake 0.1.0 --scene");
    cJSON_AddStringToObject(o, "format", "1.2");
    cJSON_AddStringToObject(o, "scene", s->path);
    cJSON_AddStringToObject(o, "object", ob->name);
    cJSON_AddStringToObject(o, "mesh", ob->mesh);
    cJSON_AddStringToObject(o, "material", ob->material.name);
    cJSON_AddNumberToObject(o, "eps", eps);
    cJSON_AddNumberToObject(o, "mm_per_unit", c->out->mm_per_unit);
    cJSON_AddItemToObject(o, "radius_mm", cJSON_CreateDoubleArray(radius, (int)c->C));
    cJSON *fx = cJSON_AddArrayToObject(o, "effects");
    for (uint32_t b = 0; b < SSS_FX_COUNT; b++)
        if (p->effects >> b & 1u) cJSON_AddItemToArray(fx, cJSON_CreateString(sss_effect_name(b)));
    sss_plan_add_decisions_json(p, o);
    for (int k = 0; k < SSS_PASS_KINDS; k++)
        if (p->effects & sss_effect_units[k]->fx && sss_effect_units[k]->provenance)
            sss_effect_units[k]->provenance(c, o);
    char *txt = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return txt;
}

sss_result sss_bake_object(const sss_scene *scene, const sss_plan *plan, const sss_mesh *world, uint32_t obj,
                           const sss_bake_options *opt, sss_bake_file *out, sss_bake_stats *st_out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    sss_bake_stats st;
    memset(&st, 0, sizeof st);
    if (obj >= scene->nobjects || obj >= plan->nobjects) return sss_fail(err, SSS_ERR_ARG, "no object %u", obj);
    const sss_object_plan *p = &plan->obj[obj];
    const sss_scene_object *ob = &scene->objects[obj];
    const double eps = scene->bake.eps > 0 ? scene->bake.eps : opt->eps > 0 ? opt->eps : 1e-3;
#ifdef _OPENMP
    if (opt->threads > 0) omp_set_num_threads(opt->threads);
#endif
    sss_pass_ctx c;
    memset(&c, 0, sizeof c);
    c.scene = scene;
    c.plan = p;
    c.eta = ob->material.eta;
    c.C = p->channels;
    c.n_dirs = scene->bake.dirs ? scene->bake.dirs : opt->n_dirs ? opt->n_dirs : 200;
    c.sh_order = scene->bake.sh_order ? scene->bake.sh_order : 4;
    c.shells = scene->bake.shells ? scene->bake.shells : 4;
    c.near_factor = scene->bake.near_factor > 0 ? scene->bake.near_factor : 5.0;
    c.out = out;
    c.st = &st;

    sss_result r = sss_mesh_copy(&world[obj], &out->mesh, err);
    if (r != SSS_OK) return r;
    c.mesh = &out->mesh;
    out->material = ob->material;
    out->mm_per_unit = sss_scene_object_mm_per_world_unit(ob);
    out->channels = c.C;
    out->quant = SSS_QUANT_FLOAT;
    out->fx.mask = p->effects;

    /* Memory planned before anything of the object's size is allocated, as
     * the plain bake plans it (bake.c; docs/robustness.md, "Memory"): every
     * pass's output and its largest work array, then the neighbourhoods get
     * 90 % of the rest, counted before they are allocated. */
    uint64_t need = (uint64_t)world[obj].nv * (12u + 12u + 8u) + (uint64_t)world[obj].nf * 12u, kept = 0, peak = 0;
    for (int k = 0; k < SSS_PASS_KINDS; k++) {
        if (!p->pass_lights[k] || !sss_effect_units[k]->memory) continue;
        uint64_t kk = 0, tt = 0;
        sss_effect_units[k]->memory(&c, &kk, &tt);
        kept += kk;
        if (kept + tt > peak) peak = kept + tt;
    }
    need += peak > kept ? peak : kept;
    const uint64_t avail = sss_memory_available(opt->memory_limit);
    if (avail && need > avail) {
        r = sss_fail(err, SSS_ERR_NOMEM, "the bake needs at least %.2f GiB for %u vertices (the passes' data and "
                     "work arrays) but %.2f GiB is available (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the "
                     "limit): use fewer directions or shells, or a lower SH order", need / 1073741824.0,
                     world[obj].nv, avail / 1073741824.0);
        sss_file_free(out);
        return r;
    }
    const uint64_t nb_max = avail ? (avail - need) / 10 * 9 : 0;

    sss_dipole dip[SSS_MAX_CHANNELS];
    for (uint32_t k = 0; k < c.C; k++) sss_dipole_init(&dip[k], ob->material.sigma_a[k], ob->material.sigmap_s[k], c.eta);
    /* the radius rule of bake.c, so the exact evaluator (which recomputes
     * it from the file) finds the same neighbourhoods */
    st.search_radius_mm = sss_nbhd_radii(c.mesh, out->mm_per_unit, dip, c.C, eps, st.radius_mm);
    sss_weights nb = {0};
    sss_vis *vis = NULL;
    const sss_mesh **occ = NULL;
    double t = sss_now();
    r = sss_nbhd_build(c.mesh, out->mm_per_unit, dip, c.C, st.search_radius_mm, NULL, 0, nb_max, opt->cancel, &nb, err);
    if (r != SSS_OK) goto done;
    st.t_neighbourhoods = sss_now() - t;
    st.neighbours_total = nb.start[nb.nrows];
    st.neighbours_mean = (double)st.neighbours_total / nb.nrows;
    for (uint32_t v = 0; v < nb.nrows; v++) {
        const uint32_t k = (uint32_t)(nb.start[v + 1] - nb.start[v]);
        if (k > st.neighbours_max) st.neighbours_max = k;
    }
    if (avail) { /* what is left for the probes (env_sh.c reads them) */
        const uint64_t nbb = st.neighbours_total * (4u + 4u * c.C);
        c.memory_left = avail - need > nbb ? avail - need - nbb : 1;
    }
    c.nb = &nb;
    t = sss_now();
    if (p->self_shadow || p->noccluders) {
        occ = malloc((p->noccluders + 1) * sizeof *occ);
        if (!occ) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto done; }
        for (uint32_t k = 0; k < p->noccluders; k++) occ[k] = &world[p->occluders[k]];
        r = sss_vis_create_scene(c.mesh, p->self_shadow, occ, p->noccluders, &vis, err);
        if (r != SSS_OK) goto done;
    }
    c.vis = vis;
    for (int k = 0; k < SSS_PASS_KINDS; k++) {
        if (!p->pass_lights[k]) continue;
        r = sss_effect_units[k]->bake(&c, err);
        if (r != SSS_OK) goto done;
    }
    st.t_integrals = sss_now() - t;
    out->eps = eps;
    out->params_json = params(scene, p, &c, eps, st.radius_mm);
    if (!out->params_json) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto done; }
    if (st_out) *st_out = st;
done:
    sss_vis_destroy(vis);
    free(occ);
    sss_weights_free(&nb);
    if (r != SSS_OK) sss_file_free(out);
    return r;
}
