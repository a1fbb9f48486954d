/* near_terms.c: the near-terms effect of plain bakes and of a scene's
 * direction set (bake_scene.c, docs/scenes.md "Near terms"), its bake side
 * (`--own-term runtime [--rings K]`, section OWNT, docs/format.md §5.14):
 * the rows store q minus the terms of the vertex itself and its K mesh
 * rings, which every reader adds back for the actual light with every
 * vertex's own visibility (sss/nearterms.h; docs/accuracy_4000.md, "Where the
 * error comes from"). It has no planner rule: a plain bake asks for it.
 */
#include <math.h>
#include <stdlib.h>

#include "effects/effect.h"
#include "sss/nearterms.h"

/* Splits the near terms off q in place (sss/nearterms.h): for every
 * direction sample ω_j and vertex o, q_j −= Σ_{i in o's rings} w̃(o, i)
 * g(n_i, ω_j) V(x_i, ω_j), with the bake's own visibility rule (one
 * occlusion ray per vertex facing ω_j, as sss_transfer_rows traces) and
 * the readers' float sum (sss_near_sum), so that a reader adding the terms
 * back at ω_j restores q_j up to rounding (and the clamp at 0 below).
 * Independent elements: the result does not depend on the thread count. */
static sss_result split(const sss_mesh *mesh, const sss_material *mat, const sss_field_kernel *field,
                        const sss_bake_options *o, uint32_t C, const sss_dirset *ds, const sss_weights *hat,
                        int self_shadow, float *q, float *qvec, uint64_t *rays, uint64_t *entries, sss_error *err)
{
    const uint32_t nv = mesh->nv, D = ds->n;
    sss_weights nr;
    const sss_near_spec spec = {.rings = o->near_radius_mm > 0.0 ? 0 : o->near_rings, .radius_mm = o->near_radius_mm,
                                .weights = o->weights, .eps = o->eps, .field = field};
    sss_result r = sss_near_build_spec(mesh, mat, o->mm_per_unit, C, &spec, hat, &nr, err);
    if (r != SSS_OK) return r;
    if (entries) *entries = nr.start[nv];
    sss_vis *vis = NULL;
    uint8_t *lit = malloc((size_t)nv + 1);
    float *gv = malloc((size_t)nv * sizeof *gv + 1);
    float *hv = qvec ? malloc((size_t)nv * sizeof *hv + 1) : NULL;
    if (!lit || !gv || (qvec && !hv)) r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for the near terms of %u vertices", nv);
    if (r == SSS_OK && self_shadow) r = sss_vis_create(mesh, &vis, err);
    uint64_t traced = 0;
    for (uint32_t j = 0; j < D && r == SSS_OK; j++) {
        const double *d = ds->dir + 3 * (size_t)j;
        if (self_shadow)
            traced += sss_vis_lit_all(vis, mesh, d, lit);
        else /* a convex object (the planner's self-shadow rule): V = 1 wherever n_i.w > 0 */
            for (uint32_t v = 0; v < nv; v++) {
                const float *n = mesh->nrm + 3 * (size_t)v;
                lit[v] = n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0;
            }
        sss_near_transfer(mesh->nrm, nv, (float)mat->eta, d, lit, gv);
        float *qj = q + (size_t)j * nv * C;
#pragma omp parallel for schedule(static)
        for (int64_t v = 0; v < (int64_t)nv; v++) {
            float s[3];
            sss_near_sum(&nr, (uint32_t)v, gv, s);
            /* ≥ 0, as every stored q: the rest is a sum of non-negative
             * terms, and only rounding (or weights that differ from
             * nbhd.c's, e.g. coincident copies sharing a disk) takes it
             * below */
            for (uint32_t c = 0; c < C; c++) qj[(size_t)v * C + c] = fmaxf(qj[(size_t)v * C + c] - s[c], 0.0f);
        }
        /* Q's rows (section QVEC): the same terms with G's cosine replaced
         * by the normal's component a (Hao–Varshney 2004 §3.1), so that a
         * reader's Q·ω_j plus the near terms it adds at ω_j gives back
         * q_j; components take either sign, so no clamp */
        for (int a = 0; a < 3 && qvec; a++) {
            for (uint32_t v = 0; v < nv; v++) {
                const float *n = mesh->nrm + 3 * (size_t)v;
                const double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
                hv[v] = gv[v] != 0.0f && c > 0.0 ? (float)((double)gv[v] / c * n[a]) : 0.0f;
            }
            float *Qj = qvec + 3 * (size_t)j * nv * C;
#pragma omp parallel for schedule(static)
            for (int64_t v = 0; v < (int64_t)nv; v++) {
                float s[3];
                sss_near_sum(&nr, (uint32_t)v, hv, s);
                for (uint32_t c = 0; c < C; c++) Qj[3 * ((size_t)v * C + c) + (size_t)a] -= s[c];
            }
        }
        if (sss_cancelled(o->cancel))
            r = sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted while splitting the near terms");
    }
    if (rays) *rays += traced;
    sss_vis_destroy(vis);
    free(lit);
    free(gv);
    free(hv);
    sss_weights_free(&nr);
    return r;
}

sss_result sss_near_terms_split(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o, uint32_t C,
                                const sss_dirset *ds, const sss_weights *hat, int self_shadow, float *q,
                                uint64_t *rays, uint64_t *entries, sss_error *err)
{
    return split(mesh, mat, NULL, o, C, ds, hat, self_shadow, q, NULL, rays, entries, err);
}

sss_result sss_near_terms_split_field(const sss_mesh *mesh, const sss_field_kernel *field, const sss_bake_options *o,
                                      uint32_t C, const sss_dirset *ds, int self_shadow, float *q, uint64_t *rays,
                                      uint64_t *entries, sss_error *err)
{
    return split(mesh, &field->ref, field, o, C, ds, NULL, self_shadow, q, NULL, rays, entries, err);
}

sss_result sss_near_terms_split_vector(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                                       uint32_t C, const sss_dirset *ds, const sss_weights *hat, float *q, float *qvec,
                                       uint64_t *rays, uint64_t *entries, sss_error *err)
{
    return split(mesh, mat, NULL, o, C, ds, hat, 1, q, qvec, rays, entries, err);
}
