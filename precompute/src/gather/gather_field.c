/* gather_field.c: the hierarchical gather of a heterogeneous object
 * (docs/heterogeneous.md §4.5). The tree's weights are built for the
 * field kernel's reference material, as the direct rows are (§4), and
 * then scaled by κ: a near column (a source summed one by one) by
 * κ(o, i) of the pair, exactly the factor the direct rows' entry gets
 * (sss_field_kappa, the far pairs' cache of §4.3 included); a far node's
 * SSS_GATHER_MOMENTS columns by one κ between the receiver and the node's
 * area centroid, with the field's f read at the centroid — the Taylor
 * expansion of R_d about the centroid (gather_tree.c) then carries the
 * blend's profile there, which is exact when f is constant over the node
 * and off by the profile ratio's spread over the node's f range
 * otherwise (measured in §4.5).
 */
#include <stdlib.h>
#include <string.h>

#include "gather/gather_internal.h"

sss_result sss_gather_tree_set_field(sss_gather_tree *t, const sss_mesh *mesh, const sss_field_kernel *k,
                                     sss_error *err)
{
    free(t->fpt);
    t->fpt = NULL;
    t->field = NULL;
    if (!k) return SSS_OK;
    if (k->nv != t->nv || mesh->nv != t->nv || k->s != t->s || k->C < 1 || k->C > SSS_MAX_CHANNELS)
        return sss_fail(err, SSS_ERR_ARG, "gather: the field kernel is for another mesh (%u vertices at %g mm per "
                        "unit, the tree %u at %g)", k->nv, k->s, t->nv, t->s);
    t->fpt = malloc((size_t)t->nnodes * sizeof *t->fpt + 1);
    if (!t->fpt) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory for the field at %u nodes", t->nnodes);
    int64_t bad = -1;
#pragma omp parallel for schedule(static)
    for (int64_t n = 0; n < (int64_t)t->nnodes; n++) {
        const double x[3] = {t->node[n].c[0] / t->s, t->node[n].c[1] / t->s, t->node[n].c[2] / t->s};
        if (sss_field_point_at(k, x, &t->fpt[n]) != SSS_OK) {
#pragma omp critical
            bad = bad < 0 || n < bad ? n : bad;
        }
    }
    if (bad >= 0) {
        const double f = t->fpt[bad].f;
        free(t->fpt);
        t->fpt = NULL;
        return sss_fail(err, SSS_ERR_ARG, "gather: node %lld: the blend at its centroid's f = %g makes no dipole",
                        (long long)bad, f);
    }
    t->field = k;
    t->field_group = SSS_GATHER_FIELD_GROUP;
    return SSS_OK;
}

void sss_gather_field_scale(const sss_gather_tree *t, const sss_mesh *mesh, uint32_t C, uint32_t o, uint32_t mo,
                            const uint32_t *src, const uint32_t *msrc, uint32_t Sn, const uint32_t *far, uint32_t nfar,
                            float *W, uint64_t ldc, sss_gather_fpairs *fp)
{
    double kap[SSS_MAX_CHANNELS];
    /* Each near pair is asked for twice, once from each endpoint's block
     * (the direct rows compute it once for both entries, §4.3). Where both
     * endpoints lie in the group of blocks this thread runs, the first
     * (the receiver earlier in Morton order) keeps κ and the second reads
     * it: the blocks of a group run in Morton order on one thread, and κ
     * is a pure function of the pair with the same bits in both orders
     * (sss_field_kappa_sym), so the q have the same bytes whether or not
     * a pair was kept, whatever the thread count. */
    const uint32_t x = fp && mo - fp->lo < fp->n ? mo - fp->lo : UINT32_MAX;
    const double *row = x != UINT32_MAX ? fp->kap + (size_t)x * (x - 1) / 2 * SSS_MAX_CHANNELS : NULL;
    const uint32_t *rstamp = x != UINT32_MAX ? fp->stamp + (size_t)x * (x - 1) / 2 : NULL;
    for (uint32_t a = 0; a < Sn; a++) {
        /* beyond the cutoff every channel's weight is 0, and so is its
         * product with κ: no march */
        int any = 0;
        for (uint32_t c = 0; c < C; c++) any |= W[c * ldc + a] != 0.0f;
        if (!any) continue;
        const uint32_t y = msrc[a] - (fp ? fp->lo : 0);
        if (row && y < x && rstamp[y] == fp->gen) {
            /* kept by receiver y; the channels copied by a loop, not a call
             * to memcpy of a size the compiler does not know */
            for (uint32_t c = 0; c < C; c++) kap[c] = row[(size_t)y * SSS_MAX_CHANNELS + c];
            fp->kept++;
        } else if (sss_field_kappa_sym(t->field, mesh, o, src[a], kap) && x != UINT32_MAX && y > x && y < fp->n) {
            const size_t e = (size_t)y * (y - 1) / 2 + x; /* for receiver y, which comes later */
            for (uint32_t c = 0; c < C; c++) fp->kap[e * SSS_MAX_CHANNELS + c] = kap[c];
            fp->stamp[e] = fp->gen;
        }
        for (uint32_t c = 0; c < C; c++) W[c * ldc + a] = (float)((double)W[c * ldc + a] * kap[c]);
    }
    float *wf = W + Sn; /* moment x of far node f at wf[x · nfar + f] */
    for (uint32_t f = 0; f < nfar; f++) {
        int any = 0;
        for (uint32_t c = 0; c < C; c++)
            for (int x = 0; x < SSS_GATHER_MOMENTS; x++) any |= wf[c * ldc + (size_t)x * nfar + f] != 0.0f;
        if (!any) continue;
        sss_field_kappa_point(t->field, mesh, o, &t->fpt[far[f]], kap);
        for (uint32_t c = 0; c < C; c++)
            for (int x = 0; x < SSS_GATHER_MOMENTS; x++) {
                float *w = &wf[c * ldc + (size_t)x * nfar + f];
                *w = (float)((double)*w * kap[c]);
            }
    }
}

uint64_t sss_gather_field_workspace_bytes(int threads)
{
    return SSS_GATHER_FIELD_PAIRS * (SSS_MAX_CHANNELS * sizeof(double) + sizeof(uint32_t)) *
           (uint64_t)(threads > 0 ? threads : 1);
}
