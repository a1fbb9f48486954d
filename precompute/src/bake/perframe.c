/* perframe.c: the object-space per-frame path (sss/perframe.h,
 * docs/deformable.md §3): Hao–Varshney 2004's run-time mode
 * (§2.3) on a posed mesh. Every piece is the bake's: the radius rule and
 * neighbourhoods of nbhd.c, the hat corrections of hatweights.c, the rays
 * of visibility.c, G of transfer.c, and either the direct sum of
 * transfer.c or the hierarchical gather of gather/ with the bake's
 * corrections on top (bake_tree.c). Nothing is kept between frames: the
 * pose changes N(x_o), ΔA and V.
 */
#include "sss/perframe.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_tree.h"
#include "sss/clock.h"
#include "sss/fieldweights.h"
#include "sss/format.h"
#include "sss/gather.h"
#include "sss/hatweights.h"
#include "sss/nbhd.h"
#include "sss/transfer.h"
#include "sss/vec3.h"
#include "sss/visibility.h"

/* The bake's default cutoff (sss_bake_options.eps = 0 means it). */
#define PERFRAME_DEFAULT_EPS 1e-3

sss_result sss_perframe_q(const sss_mesh *mesh, const sss_material *mat, uint32_t channels, double mm_per_unit,
                          const double light[3], const sss_perframe_options *o, float *q, sss_perframe_stats *stats,
                          sss_error *err)
{
    const sss_perframe_options zero = {0};
    if (!o) o = &zero;
    sss_perframe_stats st = {0};
    const double t0 = sss_now();
    if (!mesh || mesh->nv == 0 || !mesh->pos || !mesh->tri || !mesh->nrm || !mesh->area)
        return sss_fail(err, SSS_ERR_ARG, "per-frame path: the mesh has no vertices, normals or areas");
    if (channels != 1 && channels != 3)
        return sss_fail(err, SSS_ERR_ARG, "per-frame path: %u channels (1 or 3 expected)", channels);
    if (!(mm_per_unit >= SSS_MM_PER_UNIT_MIN && mm_per_unit <= SSS_MM_PER_UNIT_MAX))
        return sss_fail(err, SSS_ERR_ARG, "per-frame path: mm per unit %g is outside [%g, %g]", mm_per_unit,
                        SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX);
    if (o->mode != SSS_PERFRAME_EXACT && o->mode != SSS_PERFRAME_TREE)
        return sss_fail(err, SSS_ERR_ARG, "per-frame path: mode %d is neither exact (0) nor tree (1)", o->mode);
    if (o->weights != SSS_WEIGHTS_POINT && o->weights != SSS_WEIGHTS_HAT)
        return sss_fail(err, SSS_ERR_ARG, "per-frame path: weights %u are neither point (0) nor hat (1)", o->weights);
    const double eps = o->eps > 0 ? o->eps : PERFRAME_DEFAULT_EPS;
    if (!(eps < 1.0)) return sss_fail(err, SSS_ERR_ARG, "per-frame path: eps %g must lie in (0, 1)", eps);
    sss_dipole dip[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < channels; c++) {
        sss_result r = sss_dipole_init(&dip[c], mat->sigma_a[c], mat->sigmap_s[c], mat->eta);
        if (r != SSS_OK)
            return sss_fail(err, r, "per-frame path: channel %u: sigma_a %g, sigma'_s %g, eta %g do not make a dipole",
                            c, mat->sigma_a[c], mat->sigmap_s[c], mat->eta);
    }
    const uint32_t nv = mesh->nv;
    double d[3];
    if (!sss_light_unit(light, d)) {
        memset(q, 0, (size_t)nv * channels * sizeof *q);
        if (stats) *stats = st;
        return SSS_OK;
    }

    /* A field (docs/deformable.md §10): the rows are built for the
     * kernel's reference material and radius, then scaled pair by pair, as
     * the scene bake and the exact evaluator scale theirs. */
    sss_field_kernel fk;
    memset(&fk, 0, sizeof fk);
    if (o->hetero && o->hetero->field.kind != SSS_FIELD_NONE) {
        if (o->mode != SSS_PERFRAME_EXACT)
            return sss_fail(err, SSS_ERR_ARG, "per-frame path: a material field needs the exact mode (the per-frame "
                            "tree does not weigh its pairs by the field; the static bake's does, docs/heterogeneous.md "
                            "sec. 4.5)");
        sss_result fr = sss_field_kernel_create_ends(mesh, o->rest, mm_per_unit, mat, o->hetero, channels, eps,
                                                     "per-frame path", &fk, err);
        if (fr != SSS_OK) return fr;
        memcpy(dip, fk.dip_ref, sizeof dip);
    }
    sss_weights nb = {0}, hat = {0};
    sss_vis *vis = NULL;
    sss_gather_tree *tree = NULL;
    float *G = malloc((size_t)nv * sizeof *G);
    uint32_t *inv = NULL;
    sss_result r = G ? SSS_OK : sss_fail(err, SSS_ERR_NOMEM, "per-frame path: out of memory for %u vertices", nv);

    /* 1. the neighbourhood cutoff, rows and corrections of the bake (the
     *    radius rule of sss_nbhd_radii, so the exact evaluator's too) */
    double t = sss_now();
    st.radius_mm = fk.f ? fk.radius_mm : sss_nbhd_radii(mesh, mm_per_unit, dip, channels, eps, NULL);
    if (r == SSS_OK && o->mode == SSS_PERFRAME_EXACT)
        r = sss_nbhd_build(mesh, mm_per_unit, dip, channels, st.radius_mm, NULL, 0, 0, o->cancel, &nb, err);
    if (r == SSS_OK && o->weights == SSS_WEIGHTS_HAT)
        r = sss_hat_corrections(mesh, mm_per_unit, dip, channels, st.radius_mm, NULL, 0, o->cancel, &hat, err);
    if (r == SSS_OK && fk.f) r = sss_field_weights_apply(&fk, mesh, &nb, o->cancel, err);
    if (r == SSS_OK && fk.f && hat.nrows) r = sss_field_weights_apply(&fk, mesh, &hat, o->cancel, err);
    if (r == SSS_OK && o->mode == SSS_PERFRAME_EXACT) st.pairs = nb.start[nv];
    st.t_neighbourhoods = sss_now() - t;

    /* 2. irradiance per vertex with visibility: G(x_i, ω) with the pose's
     *    own rays */
    t = sss_now();
    if (r == SSS_OK && !o->no_shadows) r = sss_vis_create(mesh, &vis, err);
    if (r == SSS_OK) r = sss_transfer_compute(mesh, vis, d, 1, mat->eta, o->cancel, G, &st.rays, NULL, err);
    st.t_visibility = sss_now() - t;

    /* 3. the gather */
    t = sss_now();
    if (r == SSS_OK && o->mode == SSS_PERFRAME_EXACT) {
        if (o->weights == SSS_WEIGHTS_HAT) sss_integrate_hat(&nb, &hat, G, 1, q);
        else sss_integrate(&nb, G, 1, q);
    } else if (r == SSS_OK) {
        sss_gather_params p = {.theta = o->theta, .cancel = o->cancel};
        r = sss_gather_tree_build(mesh, mm_per_unit, G, 1, &p, &tree, err);
        if (r == SSS_OK)
            r = sss_gather_run(tree, mesh, dip, channels, st.radius_mm, 0, sss_gather_tree_blocks(tree), q, 1, NULL,
                               err);
        if (r == SSS_OK && o->weights == SSS_WEIGHTS_HAT) {
            /* the bake's tree path adds the corrections from G in the
             * tree's row order; here G is in vertex order (row i is vertex i) */
            if (!(inv = malloc((size_t)nv * sizeof *inv)))
                r = sss_fail(err, SSS_ERR_NOMEM, "per-frame path: out of memory for %u vertices", nv);
            for (uint32_t i = 0; inv && i < nv; i++) inv[i] = i;
            if (r == SSS_OK && !sss_bake_add_hat(&hat, inv, G, nv, channels, 0, 1, 1, q))
                r = sss_fail(err, SSS_ERR_NOMEM, "per-frame path: out of memory for the hat-function corrections");
        }
    }
    st.t_gather = sss_now() - t;
    st.t_total = sss_now() - t0;

    sss_field_kernel_free(&fk);
    sss_gather_tree_destroy(tree);
    sss_vis_destroy(vis);
    sss_weights_free(&nb);
    sss_weights_free(&hat);
    free(G);
    free(inv);
    if (stats) *stats = st;
    return r;
}
