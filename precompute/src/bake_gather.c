/* bake_gather.c: the bake's visibility and integrals through the
 * hierarchical gather (sss/gather.h, issue 8): memory estimate, transfer
 * table G, source tree, receiver blocks, and under MPI the split of both
 * the visibility rows and the receiver blocks across ranks. Every block's
 * result is computed the same way whichever rank or thread computes it, so
 * rank 0's file is byte-identical to a single process's.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bake_gather.h"
#include "progress.h"
#include "sss/gather.h"
#include "transfer.h"

int sss_bake_choose_gather(const sss_bake_options *o)
{
    if (o->gather == SSS_GATHER_DIRECT || o->gather == SSS_GATHER_TREE) return o->gather;
    /* The tree by default: within 10⁻³ (per-vertex RMS) of the direct sum
     * on every mesh measured, and faster from 5K vertices up (2× at 5K,
     * 6× at 23K, ~130× at 437K: docs/benchmarks.md "Bake at scale"). On
     * meshes with a handful of neighbours per vertex the direct sum is
     * faster (docs/robustness.md, a million-vertex plane), but not by
     * enough to switch on a guess of the neighbour count. */
    return SSS_GATHER_TREE;
}

sss_result sss_bake_visibility(const sss_mesh *mesh, double eta, const double *dirs, uint32_t D, uint32_t v0,
                               uint32_t v1, float *G, sss_bake_stats *st, sss_error *err)
{
    sss_vis *vis = NULL;
    sss_result r = sss_vis_create(mesh, &vis, err);
    if (r != SSS_OK) return r;
    uint64_t occ = 0;
    sss_progress_begin("visibility", v1 - v0);
    r = sss_transfer_rows(mesh, vis, dirs, D, eta, v0, v1, G, &st->rays, &occ, err);
    sss_progress_end();
    sss_vis_destroy(vis);
    if (r != SSS_OK) return r;
    st->occluded_fraction = st->rays ? (double)occ / (double)st->rays : 0.0;
    return SSS_OK;
}

/* First of the n items that rank k of nranks owns (k = nranks: n). */
static uint32_t share_start(uint32_t n, int k, int nranks) { return (uint32_t)((uint64_t)n * k / nranks); }

sss_result sss_bake_tree(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                         const sss_dipole *dip, uint32_t C, uint64_t avail, uint64_t fixed, sss_bake_file *out,
                         sss_bake_stats *st, sss_error *err)
{
    const uint32_t nv = mesh->nv, D = o->n_dirs;
    const int mpi = o->nranks > 1 && o->comm;
    const int rank = mpi ? o->rank : 0, nranks = mpi ? o->nranks : 1;
    sss_gather_params p = {o->theta, 0, 0};
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    /* Peak memory, predicted: G, q and the quantiser's indices (fixed),
     * the tree with its moments, the threads' block matrices, the mesh copy
     * and under MPI the block-ordered integrals rank 0 gathers before
     * placing them. */
    const uint64_t qbytes = (uint64_t)nv * D * C * sizeof(float);
    const uint64_t mesh_bytes = (uint64_t)nv * 32 + (uint64_t)mesh->nf * 12;
    uint64_t need = fixed + sss_gather_tree_bytes(nv, D, &p) + sss_gather_workspace_bytes(nv, D, C, &p, threads) +
                    mesh_bytes + (mpi ? qbytes : 0);
    st->predicted_peak_bytes = need;
    if (avail && need > avail)
        return sss_fail(err, SSS_ERR_NOMEM,
                        "the bake needs at least %.2f GiB for %u vertices x %u directions x %u channels (transfer table, "
                        "integrals, gather tree) but %.2f GiB is available (estimate before starting; "
                        "SSS_MEMORY_LIMIT_MB lowers the limit): use fewer --dirs",
                        need / 1073741824.0, nv, D, C, avail / 1073741824.0);

    sss_result r = SSS_OK;
    sss_gather_tree *tree = NULL;
    float *G = NULL, *part = NULL, *full = NULL;
    uint32_t *verts = NULL;
    uint64_t *offs = NULL, *lens = NULL;

    double t = sss_now();
    G = malloc((size_t)nv * D * sizeof(float) + 1);
    offs = calloc((size_t)nranks + 1, sizeof *offs);
    lens = calloc((size_t)nranks + 1, sizeof *lens);
    if (!G || !offs || !lens) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u transfer values", nv, D); goto done; }
    {
        /* each rank traces the rays of its share of the vertices, then all
         * ranks exchange the rows: every rank needs all of G as sources */
        for (int k = 0; k < nranks; k++) {
            const uint32_t a = share_start(nv, k, nranks), b = share_start(nv, k + 1, nranks);
            offs[k] = (uint64_t)a * D * sizeof(float);
            lens[k] = (uint64_t)(b - a) * D * sizeof(float);
        }
        r = sss_bake_visibility(mesh, mat->eta, out->dirs.dir, D, share_start(nv, rank, nranks),
                                share_start(nv, rank + 1, nranks), G, st, err);
        if (r != SSS_OK) goto done;
        if (mpi && o->comm->allgather(G, offs, lens, o->comm->ctx) != 0) {
            r = sss_fail(err, SSS_ERR_IO, "MPI: exchanging the transfer table failed");
            goto done;
        }
    }
    st->t_visibility = sss_now() - t;

    t = sss_now();
    r = sss_gather_tree_build(mesh, o->mm_per_unit, G, D, &p, &tree, err);
    if (r != SSS_OK) goto done;
    st->t_tree = sss_now() - t;
    free(G); /* the tree holds its Morton-ordered copy */
    G = NULL;

    t = sss_now();
    const uint32_t nb = sss_gather_tree_blocks(tree);
    const uint32_t b0 = share_start(nb, rank, nranks), b1 = share_start(nb, rank + 1, nranks);
    sss_gather_stats gs;
    memset(&gs, 0, sizeof gs);
    const size_t nq = (size_t)D * nv * C;
    if (!mpi) {
        out->q = malloc(nq * sizeof(float) + 1);
        if (!out->q) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu integrals", nq); goto done; }
        sss_progress_begin("integrals", nv);
        r = sss_gather_run(tree, mesh, dip, C, st->search_radius_mm, 0, nb, out->q, 1, &gs, err);
        sss_progress_end();
        if (r != SSS_OK) goto done;
    } else {
        /* this rank's blocks in block order, then rank 0 collects all parts
         * (in rank order = block order) and places them by vertex */
        for (int k = 0; k < nranks; k++) {
            const uint32_t a = share_start(nb, k, nranks), b = share_start(nb, k + 1, nranks);
            const uint32_t before = sss_gather_tree_block_vertices(tree, 0, a, NULL);
            const uint32_t mine = sss_gather_tree_block_vertices(tree, a, b, NULL);
            offs[k] = (uint64_t)before * D * C * sizeof(float);
            lens[k] = (uint64_t)mine * D * C * sizeof(float);
        }
        part = malloc(lens[rank] + 1);
        if (!part) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu integrals", (size_t)(lens[rank] / 4)); goto done; }
        sss_progress_begin("integrals", lens[rank] / (sizeof(float) * D * C));
        r = sss_gather_run(tree, mesh, dip, C, st->search_radius_mm, b0, b1, part, 0, &gs, err);
        sss_progress_end();
        if (r != SSS_OK) goto done;
        if (rank == 0) {
            full = malloc(nq * sizeof(float) + 1);
            verts = malloc((size_t)nv * sizeof *verts);
            if (!full || !verts) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu integrals", nq); goto done; }
        }
        if (o->comm->gather0(part, full, offs, lens, o->comm->ctx) != 0) {
            r = sss_fail(err, SSS_ERR_IO, "MPI: collecting the integrals failed");
            goto done;
        }
        free(part);
        part = NULL;
        if (rank == 0) {
            sss_gather_tree_block_vertices(tree, 0, nb, verts);
            out->q = malloc(nq * sizeof(float) + 1);
            if (!out->q) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %zu integrals", nq); goto done; }
#pragma omp parallel for schedule(static)
            for (int64_t kk = 0; kk < (int64_t)nv; kk++) {
                const uint32_t v = verts[kk];
                for (uint32_t j = 0; j < D; j++)
                    for (uint32_t c = 0; c < C; c++)
                        out->q[((size_t)j * nv + v) * C + c] = full[((size_t)kk * D + j) * C + c];
            }
        }
    }
    st->t_integrals = sss_now() - t;
    st->tree_nodes = gs.nodes;
    st->tree_blocks = nb;
    st->near_pairs = gs.near_pairs;
    st->far_pairs = gs.far_pairs;
    st->rows_mean = gs.rows_mean;
    st->gather_gflops = gs.t_sgemm > 0 ? gs.flops / gs.t_sgemm * 1e-9 : 0;
    {
        const double tt = gs.t_lists + gs.t_weights + gs.t_sgemm + gs.t_scatter;
        st->sgemm_fraction = tt > 0 ? gs.t_sgemm / tt : 0;
    }
    /* the neighbourhood figures of the direct sum, for the summary: sources
     * per receiver taken one by one, and the rows per receiver */
    st->neighbours_total = gs.near_pairs;
    st->neighbours_mean = nv ? (double)gs.near_pairs / nv : 0;
    if (getenv("SSS_GATHER_VERBOSE"))
        fprintf(stderr, "gather: %u nodes (%u leaves), %u blocks, rows/block %.0f, near pairs/receiver %.0f, far "
                "nodes/receiver %.1f; thread-s lists %.2f weights %.2f sgemm %.2f scatter %.2f; sgemm %.1f GFLOP/s; "
                "tree %.2fs\n", gs.nodes, gs.leaves, nb, gs.rows_mean, (double)gs.near_pairs / nv,
                (double)gs.far_pairs / nv, gs.t_lists, gs.t_weights, gs.t_sgemm, gs.t_scatter, st->gather_gflops,
                st->t_tree);

done:
    sss_gather_tree_destroy(tree);
    free(G);
    free(part);
    free(full);
    free(verts);
    free(offs);
    free(lens);
    return r;
}
