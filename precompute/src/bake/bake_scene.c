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
 * Every pass sums with the weight rule the plan chose (the hat-function
 * corrections of docs/physics.md §9 by default, as plain bakes); the
 * direction set's rows then lose their near terms when the plan moves them
 * to run time (near_terms.c, docs/format.md §5.14, §5.17) and are
 * compressed when it says so (sss_compress, docs/compression.md).
 */
#include "sss/bake_scene.h"
#include "sss/layer_depths.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bake/bake_tree.h"
#include "effects/effect.h"
#include "kernels/progress.h"
#include "kernels/transfer.h"
#include "sss/compress.h"
#include "sss/fieldweights.h"
#include "sss/fieldio.h"
#include "sss/gather.h"
#include "sss/hatweights.h"
#include "sss/memory.h"
#include "sss/nearterms.h"

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

sss_result sss_pass_integrate(const sss_pass_ctx *c, const float *G, uint32_t n, int signed_sources, float *q,
                              sss_error *err)
{
    if (!c->tree) {
        if (signed_sources) sss_integrate_hat_signed(c->nb, c->hat, G, n, q);
        else sss_integrate_hat(c->nb, c->hat, G, n, q);
        return SSS_OK;
    }
    const uint32_t nv = c->mesh->nv;
    /* the pass's sources in the tree's Morton rows, then its moments: the
     * hierarchy itself does not depend on the sources (sss/gather.h) */
    float *Gm = sss_gather_tree_rows(c->tree, n);
    if (!Gm) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory for %u x %u source values", nv, n);
    const uint32_t *order = sss_gather_tree_order(c->tree);
#pragma omp parallel for schedule(static)
    for (int64_t m = 0; m < (int64_t)nv; m++) memcpy(Gm + (size_t)m * n, G + (size_t)order[m] * n, n * sizeof *G);
    sss_gather_tree_set_signed(c->tree, signed_sources);
    sss_result r = sss_gather_tree_moments(c->tree, c->mesh, err);
    sss_gather_stats gs;
    memset(&gs, 0, sizeof gs);
    if (r == SSS_OK)
        r = sss_gather_run_chunk(c->tree, c->mesh, c->dip, c->C, c->radius_mm, 0, sss_gather_tree_blocks(c->tree), 0, n,
                                 q, 1, &gs, err);
    if (r != SSS_OK) return r;
    /* the hat-function corrections on the point weights the tree used
     * (docs/physics.md §9), as the plain bake's tree path adds them */
    if (c->hat && !sss_bake_add_hat(c->hat, c->tree_inv, Gm, nv, c->C, 0, n, !signed_sources, q))
        return sss_fail(err, SSS_ERR_NOMEM, "out of memory for the hat-function corrections");
    c->st->tree_nodes = gs.nodes;
    c->st->near_pairs = gs.near_pairs;
    c->st->far_pairs = gs.far_pairs;
    c->st->rows_mean = gs.rows_mean;
    c->st->neighbours_total = gs.near_pairs;
    c->st->neighbours_mean = nv ? (double)gs.near_pairs / nv : 0.0;
    return SSS_OK;
}

static char *params(const sss_scene *s, const sss_object_plan *p, const sss_pass_ctx *c, double eps,
                    const double *radius, const sss_compress_opts *co)
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
    if (p->field) /* docs/heterogeneous.md §5 */
        cJSON_AddStringToObject(o, "field", p->field == SSS_PLAN_FIELD_BAKED ? sss_field_kind_name(ob->hetero.field.kind)
                                                                             : "constant (folded)");
    cJSON_AddNumberToObject(o, "eps", eps);
    cJSON_AddNumberToObject(o, "mm_per_unit", c->out->mm_per_unit);
    cJSON_AddItemToObject(o, "radius_mm", cJSON_CreateDoubleArray(radius, (int)c->C));
    /* what the rows hold, in the plain bake's words (bake.c params_json) */
    if (p->weights == SSS_WEIGHTS_HAT)
        cJSON_AddStringToObject(o, "weights", "hat: (1/pi) integral of phi_i R_d over the one-ring of x_i");
    if (c->out->near_terms) {
        cJSON_AddStringToObject(o, "own_term", "runtime (direction set only): rows hold q minus the sum over the "
                                "vertices within near_radius_mm of w F_t(eta,n_i.w) max(0,n_i.w) V(x_i,w)");
        cJSON_AddNumberToObject(o, "near_radius_mm", c->out->near_radius_mm);
        cJSON_AddNumberToObject(o, "near_fraction", sss_near_fraction_default(c->C));
        cJSON_AddNumberToObject(o, "near_fraction_held", c->st->near_fraction_held);
        if (c->st->near_capped) cJSON_AddBoolToObject(o, "near_capped", 1);
    }
    if (p->gather == SSS_GATHER_TREE) { /* which gather made q, in the plain bake's words (bake.c) */
        cJSON_AddStringToObject(o, "gather", "tree");
        cJSON_AddNumberToObject(o, "theta", c->st->theta);
    }
    if (co) sss_compress_opts_to_json(co, o);
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
    out->layers = ob->layers;
    /* depth maps and procedural depths, per vertex (section LDEP,
     * docs/layers.md §3); LAYR then holds each layer's largest */
    if ((r = sss_layer_depths_eval(scene, obj, &world[obj], &out->layer_depth, &out->layers, err)) != SSS_OK) {
        sss_file_free(out);
        return r;
    }
    out->material = p->material; /* a constant field folded into its blend (planner.c rule_field) */
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
    for (uint32_t k = 0; k < c.C; k++) sss_dipole_init(&dip[k], p->material.sigma_a[k], p->material.sigmap_s[k], c.eta);
    /* the radius rule of bake.c, so the exact evaluator (which recomputes
     * it from the file) finds the same neighbourhoods */
    st.search_radius_mm = sss_nbhd_radii(c.mesh, out->mm_per_unit, dip, c.C, eps, st.radius_mm);
    /* A baked field (docs/heterogeneous.md §4): the rows are built for the
     * kernel's reference material and radius, then scaled pair by pair;
     * the field goes into the file (section FELD) for the exact evaluator. */
    sss_field_kernel fk;
    memset(&fk, 0, sizeof fk);
    if (p->field == SSS_PLAN_FIELD_BAKED) {
        char name[SSS_SCENE_PATH_MAX + 80];
        snprintf(name, sizeof name, "%s: /objects/%u/material/field", scene->path, obj);
        out->hetero = ob->hetero;
        memset(&out->hetero.field, 0, sizeof out->hetero.field);
        r = ob->field_path[0] ? sss_field_load(ob->field_path, ob->field_grid, &out->hetero.field, err)
                              : sss_field_copy(&ob->hetero.field, &out->hetero.field, err);
        if (r == SSS_OK)
            r = sss_field_kernel_create(c.mesh, out->mm_per_unit, &p->material, &out->hetero, c.C, eps,
                                        ob->field_path[0] ? ob->field_path : name, &fk, err);
        /* far pairs through the cells' cache (docs/heterogeneous.md §4.3) */
        if (r == SSS_OK) r = sss_field_kernel_far(&fk, c.mesh, SSS_FIELD_FAR_CELLS, err);
        if (r != SSS_OK) {
            sss_file_free(out);
            return r;
        }
        memcpy(dip, fk.dip_ref, sizeof dip);
        st.search_radius_mm = fk.radius_mm;
    }
    sss_weights nb = {0}, hat = {0};
    sss_vis *vis = NULL;
    sss_gather_tree *tree = NULL;
    uint32_t *tree_inv = NULL;
    const sss_mesh **occ = NULL;
    sss_compress_opts co;
    double t = sss_now();
    /* the hat-function corrections (docs/physics.md §9), before the
     * neighbourhoods as in bake.c: their entries come off what those get */
    uint64_t hat_bytes = 0;
    if (p->weights == SSS_WEIGHTS_HAT) {
        r = sss_hat_corrections(c.mesh, out->mm_per_unit, dip, c.C, st.search_radius_mm, NULL, 0, opt->cancel, &hat,
                                err);
        if (r != SSS_OK) goto done;
        st.t_hat = sss_now() - t;
        st.hat_entries = hat.start[hat.nrows];
        hat_bytes = st.hat_entries * (4u + 4u * c.C);
        if (avail && hat_bytes >= avail - need) {
            r = sss_fail(err, SSS_ERR_NOMEM, "the bake needs more than %.2f GiB for %u vertices (the hat weights' %llu "
                         "entries) (SSS_MEMORY_LIMIT_MB lowers the limit)", avail / 1073741824.0, world[obj].nv,
                         (unsigned long long)st.hat_entries);
            goto done;
        }
        c.hat = &hat;
    }
    out->weights = p->weights;
    t = sss_now();
    st.gather = p->gather;
    if (p->gather == SSS_GATHER_TREE) {
        /* The hierarchical gather (sss/gather.h): no neighbour rows, one
         * hierarchy for every pass, each pass's sources loaded into it
         * (sss_pass_integrate); a field's κ scales its weights
         * (docs/heterogeneous.md §4.5). */
        sss_gather_params gp = {.theta = opt->theta, .cancel = opt->cancel};
        st.theta = gp.theta > 0 ? gp.theta : SSS_GATHER_THETA_DEFAULT;
        r = sss_gather_tree_create(c.mesh, out->mm_per_unit, &gp, &tree, err);
        if (r == SSS_OK && avail) {
            /* the widest table of sources a pass loads (sss_pass_integrate):
             * the tree's copy of it, the nodes' moments and the threads'
             * block matrices, planned as the rows would be (bake_tree.c) */
            uint32_t widest = 1;
            if (p->pass_lights[SSS_PASS_DIR_SET] && c.n_dirs > widest) widest = c.n_dirs;
            if (p->pass_lights[SSS_PASS_POINT_SHELLS] && c.shells * c.n_dirs > widest) widest = c.shells * c.n_dirs;
            if (p->pass_lights[SSS_PASS_ENV_SH] && c.sh_order * c.sh_order > widest) widest = c.sh_order * c.sh_order;
#ifdef _OPENMP
            const int threads = omp_get_max_threads();
#else
            const int threads = 1;
#endif
            const uint64_t tb = sss_gather_tree_size(tree, widest) +
                                sss_gather_workspace_bytes(c.mesh->nv, widest, c.C, &gp, threads) +
                                (fk.f ? sss_gather_field_workspace_bytes(threads) : 0);
            if (tb + hat_bytes >= avail - need)
                r = sss_fail(err, SSS_ERR_NOMEM, "the bake needs more than %.2f GiB for %u vertices (the gather tree "
                             "with %u source column%s) but %.2f GiB is available (estimate before starting; "
                             "SSS_MEMORY_LIMIT_MB lowers the limit): use fewer directions or shells, or a lower SH "
                             "order", (need + hat_bytes + tb) / 1073741824.0, c.mesh->nv, widest, widest == 1 ? "" : "s",
                             avail / 1073741824.0);
        }
        if (r == SSS_OK && fk.f) r = sss_gather_tree_set_field(tree, c.mesh, &fk, err);
        if (r == SSS_OK && !(tree_inv = malloc((size_t)c.mesh->nv * sizeof *tree_inv + 1)))
            r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u vertices", c.mesh->nv);
        if (r != SSS_OK) goto done;
        const uint32_t *order = sss_gather_tree_order(tree);
        for (uint32_t m = 0; m < c.mesh->nv; m++) tree_inv[order[m]] = m;
        c.tree = tree;
        c.tree_inv = tree_inv;
        c.dip = dip;
        c.radius_mm = st.search_radius_mm;
        st.tree_blocks = sss_gather_tree_blocks(tree);
        st.t_tree = sss_now() - t;
        if (avail) {
            const uint64_t tb = sss_gather_tree_size(tree, 0) + hat_bytes;
            c.memory_left = avail - need > tb ? avail - need - tb : 1;
        }
    } else {
        r = sss_nbhd_build(c.mesh, out->mm_per_unit, dip, c.C, st.search_radius_mm, NULL, 0,
                           avail ? (avail - need - hat_bytes) / 10 * 9 : nb_max, opt->cancel, &nb, err);
        if (r != SSS_OK) goto done;
        st.t_neighbourhoods = sss_now() - t;
        st.neighbours_total = nb.start[nb.nrows];
        st.neighbours_mean = (double)st.neighbours_total / nb.nrows;
        for (uint32_t v = 0; v < nb.nrows; v++) {
            const uint32_t k = (uint32_t)(nb.start[v + 1] - nb.start[v]);
            if (k > st.neighbours_max) st.neighbours_max = k;
        }
        if (avail) { /* what is left for the probes (env_sh.c reads them) */
            const uint64_t nbb = st.neighbours_total * (4u + 4u * c.C) + hat_bytes;
            c.memory_left = avail - need > nbb ? avail - need - nbb : 1;
        }
        c.nb = &nb;
    }
    if (fk.f) {
        t = sss_now();
        if (nb.nrows) r = sss_field_weights_apply(&fk, c.mesh, &nb, opt->cancel, err);
        if (r == SSS_OK && hat.nrows) r = sss_field_weights_apply(&fk, c.mesh, &hat, opt->cancel, err);
        if (r != SSS_OK) goto done;
        st.t_neighbourhoods += sss_now() - t;
    }
    t = sss_now();
    if (p->self_shadow || p->noccluders) {
        occ = malloc((p->noccluders + 1) * sizeof *occ);
        if (!occ) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto done; }
        for (uint32_t k = 0; k < p->noccluders; k++) occ[k] = &world[p->occluders[k]];
        r = sss_vis_create_scene(c.mesh, p->self_shadow, occ, p->noccluders, &vis, err);
        if (r != SSS_OK) goto done;
    }
    c.vis = vis;
    /* compact rows store their directions in float32 (DIRC, docs/format.md
     * §5.18): the passes bake at those directions, as bake.c does */
    if (p->compress && p->pass_lights[SSS_PASS_DIR_SET] && !out->dirs.n) {
        r = sss_dirset_fibonacci(&out->dirs, c.n_dirs, err);
        if (r != SSS_OK) goto done;
        sss_dirset_round_f32(&out->dirs);
    }
    for (int k = 0; k < SSS_PASS_KINDS; k++) {
        if (!p->pass_lights[k]) continue;
        r = sss_effect_units[k]->bake(&c, err);
        if (r != SSS_OK) goto done;
    }
    st.t_integrals = sss_now() - t;
    sss_vis_destroy(vis); /* built over out->mesh, which the compression below replaces */
    vis = NULL;
    c.vis = NULL;
    sss_gather_tree_destroy(tree); /* the same */
    tree = NULL;
    c.tree = NULL;
    out->eps = eps;
    /* The direction set's near terms to run time (the plan's storage rule):
     * the plain bake's split (bake.c), the radius holding
     * sss_near_fraction_default of R_d,total, within the neighbourhood and
     * capped at SSS_NEAR_ENTRIES_MAX entries per vertex. Only the q rows
     * lose them: QDIR, PSHL and ENVT keep every term. */
    if (p->near_runtime && out->q) {
        t = sss_now();
        sss_bake_options no;
        memset(&no, 0, sizeof no);
        no.mm_per_unit = out->mm_per_unit;
        no.eps = eps;
        no.weights = p->weights;
        no.cancel = opt->cancel;
        no.near_terms = SSS_NEAR_TERMS_RUNTIME;
        no.near_fraction = sss_near_fraction_default(c.C);
        no.near_radius_mm = sss_near_radius_bake(c.mesh, out->mm_per_unit, &p->material, c.C, no.near_fraction,
                                                 st.search_radius_mm, &st.near_capped, &st.near_fraction_held);
        /* a field's rows hold κ-scaled terms: the same taken off
         * (docs/heterogeneous.md §4, sss_near_build_file adds them back) */
        r = fk.f ? sss_near_terms_split_field(c.mesh, &fk, &no, c.C, &out->dirs, p->self_shadow, out->q, &st.rays,
                                              &st.near_entries, err)
                 : sss_near_terms_split(c.mesh, &p->material, &no, c.C, &out->dirs, c.hat, p->self_shadow, out->q,
                                        &st.rays, &st.near_entries, err);
        if (r != SSS_OK) goto done;
        out->near_terms = SSS_NEAR_TERMS_RUNTIME;
        out->near_rings = 0;
        out->near_radius_mm = no.near_radius_mm;
        st.t_visibility += sss_now() - t;
    }
    /* The direction set's rows compressed with the plain bake's default
     * (the compact preset for the object's channels, its SH order fitting
     * the direction count: sss-bake's options()); the other effects' data
     * move over unchanged. */
    const sss_compress_opts *cop = NULL;
    if (p->compress && out->q) {
        if (sss_cancelled(opt->cancel)) { r = sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted before compression"); goto done; }
        t = sss_now();
        sss_compress_opts_default(&co);
        sss_compress_preset_apply(&co, SSS_COMPRESS_COMPACT, c.C, out->dirs.n, 0);
        sss_bake_file cf;
        r = sss_compress(out, &co, &cf, err);
        if (r != SSS_OK) goto done;
        cf.fx = out->fx;
        memset(&out->fx, 0, sizeof out->fx);
        cf.hetero = out->hetero; /* the field moves over with the effects' data */
        memset(&out->hetero, 0, sizeof out->hetero);
        sss_file_free(out);
        *out = cf;
        c.mesh = &out->mesh;
        cop = &co;
        st.t_compress = sss_now() - t;
    }
    free(out->params_json); /* the compression's copy of none */
    out->params_json = params(scene, p, &c, eps, st.radius_mm, cop);
    if (!out->params_json) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto done; }
    if (st_out) *st_out = st;
done:
    sss_gather_tree_destroy(tree);
    free(tree_inv);
    sss_field_kernel_free(&fk);
    sss_vis_destroy(vis);
    free(occ);
    sss_weights_free(&nb);
    sss_weights_free(&hat);
    if (r != SSS_OK) sss_file_free(out);
    return r;
}
