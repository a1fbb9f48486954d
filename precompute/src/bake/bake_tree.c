/* bake_tree.c: the bake's visibility and integrals through the
 * hierarchical gather (sss/gather.h): memory estimate, transfer
 * table G, source tree, receiver blocks, and under MPI the split of both
 * the visibility rows and the receiver blocks across ranks. Every block's
 * result is computed the same way whichever rank or thread computes it, so
 * rank 0's file is byte-identical to a single process's.
 */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#if defined(__linux__)
#include <sys/mman.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

#include "bake/bake_tree.h"
#include "kernels/progress.h"
#include "sss/gather.h"
#include "kernels/transfer.h"

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
                               uint32_t v1, const sss_cancel_flag *cancel, float *G, sss_bake_stats *st, sss_error *err)
{
    sss_vis *vis = NULL;
    sss_result r = sss_vis_create(mesh, &vis, err);
    if (r != SSS_OK) return r;
    uint64_t occ = 0;
    sss_progress_begin("visibility", v1 - v0);
    r = sss_transfer_rows(mesh, vis, dirs, D, eta, v0, v1, cancel, G, &st->rays, &occ, err);
    sss_progress_end();
    sss_vis_destroy(vis);
    if (r != SSS_OK) return r;
    st->occluded_fraction = st->rays ? (double)occ / (double)st->rays : 0.0;
    return SSS_OK;
}

/* First of the n items that rank k of nranks owns (k = nranks: n). */
static uint32_t share_start(uint32_t n, int k, int nranks) { return (uint32_t)((uint64_t)n * k / nranks); }

/* Memory of Embree's scene for the occlusion rays, per triangle (BVH and
 * triangle copies; resident set grew by 72 B per triangle on the 100K
 * dragon, 92 on a 20K-triangle blob). */
#define VIS_BYTES_PER_TRIANGLE 112u
/* What the process holds besides the bake's own arrays: code, shared
 * libraries, threads' stacks, and freed memory
 * malloc keeps (peak RSS of a 2,562-vertex bake: 22 MiB, of which 8 MiB
 * its arrays). */
#define PROCESS_BYTES ((uint64_t)20 << 20)

/* Asks Linux for transparent huge pages under q (where the kernel leaves
 * them to madvise). A block writes its receivers' q for every direction,
 * and q is direction-major (the file's order), so a receiver's 200 values
 * lie nv·C floats apart, each on its own 4 KiB page: writing q was TLB
 * misses more than anything (docs/benchmarks.md, "Dense blocks: own block
 * product"). Only a hint: nothing changes where it is refused. */
static void huge_pages(void *p, size_t n)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    const uintptr_t page = 4096, a = ((uintptr_t)p + page - 1) & ~(page - 1), b = ((uintptr_t)p + n) & ~(page - 1);
    if (b > a) (void)madvise((void *)a, b - a, MADV_HUGEPAGE);
#else
    (void)p;
    (void)n;
#endif
}

/* Directions [c · D / n, (c + 1) · D / n) form chunk c of n: widths
 * differ by one at most. */
static uint32_t chunk_start(uint32_t D, uint32_t c, uint32_t n) { return (uint32_t)((uint64_t)D * c / n); }

/* q += Σ_i C(v, i) G[i, j] for the chunk's directions [j0, j0 + Dc), Gm
 * the tree's Morton-ordered rows (row inv[i] is vertex i), each element in
 * double from the gather's float and, with clamp, clamped at 0
 * (sss_integrate_hat's rule; not for Q's signed components): the
 * hat-function corrections of docs/physics.md §9 on top of the point
 * weights the gather used. Elements are independent: the bytes do not
 * depend on the thread count. */
int sss_bake_add_hat(const sss_weights *hat, const uint32_t *inv, const float *Gm, uint32_t nv, uint32_t C,
                     uint32_t j0, uint32_t Dc, int clamp, float *q)
{
    int failed = 0;
#pragma omp parallel
    {
        double *acc = malloc((size_t)Dc * C * sizeof *acc + 1);
        if (!acc) failed = 1;
#pragma omp for schedule(dynamic, 256)
        for (int64_t vv = 0; vv < (int64_t)nv; vv++) {
            const uint32_t v = (uint32_t)vv;
            if (!acc || hat->start[v] == hat->start[v + 1]) continue;
            for (uint32_t j = 0; j < Dc; j++)
                for (uint32_t c = 0; c < C; c++) acc[(size_t)c * Dc + j] = q[((size_t)(j0 + j) * nv + v) * C + c];
            for (uint64_t e = hat->start[v]; e < hat->start[v + 1]; e++) {
                const float *g = Gm + (size_t)inv[hat->idx[e]] * Dc;
                for (uint32_t c = 0; c < C; c++) {
                    const double w = hat->w[e * C + c];
                    double *a = acc + (size_t)c * Dc;
                    for (uint32_t j = 0; j < Dc; j++) a[j] += w * g[j];
                }
            }
            for (uint32_t j = 0; j < Dc; j++)
                for (uint32_t c = 0; c < C; c++) {
                    const float x = (float)acc[(size_t)c * Dc + j];
                    q[((size_t)(j0 + j) * nv + v) * C + c] = x > 0.0f || !clamp ? x : 0.0f;
                }
        }
        free(acc);
    }
    return !failed;
}

/* Component a of Q from one plane in q's layout, values [i0, i1) (the
 * file keeps the three components of a value together, sss/format.h). */
static void interleave(const float *P, size_t i0, size_t i1, int a, float *qvec)
{
#pragma omp parallel for schedule(static)
    for (int64_t i = (int64_t)i0; i < (int64_t)i1; i++) qvec[3 * (size_t)i + (size_t)a] = P[i];
}

sss_result sss_bake_vector_direct(const sss_mesh *mesh, const sss_dirset *ds, const sss_weights *nb,
                                  const sss_weights *hat, const float *G, float **qvec, sss_error *err)
{
    const uint32_t nv = mesh->nv, D = ds->n;
    const size_t nq = (size_t)D * nv * nb->channels;
    float *H = malloc((size_t)nv * D * sizeof *H + 1), *P = malloc(nq * sizeof *P + 1);
    *qvec = malloc(3 * nq * sizeof **qvec + 1);
    if (!H || !P || !*qvec) {
        free(H);
        free(P);
        free(*qvec);
        *qvec = NULL;
        return sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u vector integrals", nv, D);
    }
    sss_progress_begin("vector integrals", 3 * nb->start[nb->nrows]);
    for (int a = 0; a < 3; a++) {
        sss_transfer_axis(mesh, ds->dir, D, NULL, 0, nv, G, a, H);
        sss_integrate_hat_signed(nb, hat, H, D, P);
        interleave(P, 0, nq, a, *qvec);
    }
    sss_progress_end();
    free(H);
    free(P);
    return SSS_OK;
}

sss_result sss_bake_tree(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                         const sss_dipole *dip, uint32_t C, uint64_t avail, const sss_weights *hat,
                         sss_bake_file *out, sss_bake_stats *st, sss_error *err)
{
    const uint32_t nv = mesh->nv, D = o->n_dirs;
    const int mpi = o->nranks > 1 && o->comm;
    const int rank = mpi ? o->rank : 0, nranks = mpi ? o->nranks : 1;
    const int holds_q = rank == 0; /* under MPI rank 0 alone gets the integrals */
    const double R = st->search_radius_mm;
    sss_gather_params p = {.theta = o->theta, .cancel = o->cancel};
#ifdef _OPENMP
    const int threads = omp_get_max_threads();
#else
    const int threads = 1;
#endif
    sss_result r = SSS_OK;
    sss_gather_tree *tree = NULL;
    sss_vis *vis = NULL;
    float *part = NULL, *full = NULL, *Gq = NULL, *P = NULL; /* Gq: q's transfer rows while Q's are loaded; P: one component */
    uint32_t *verts = NULL, *rows = NULL, *bsplit = NULL, *inv = NULL;
    uint64_t *offs = NULL, *lens = NULL;

    /* The hierarchy first: it does not depend on the directions, takes
     * ~100 bytes per vertex, and its exact size (nodes, blocks, the rows of
     * each block's product) makes the memory plan below exact where it
     * counts. Its interaction lists give each block's work: the progress
     * weights and the MPI split. */
    double t = sss_now();
    r = sss_gather_tree_create(mesh, o->mm_per_unit, &p, &tree, err);
    if (r != SSS_OK) goto done;
    const uint32_t nb = sss_gather_tree_blocks(tree);
    rows = malloc((size_t)nb * sizeof *rows + 1);
    bsplit = malloc(((size_t)nranks + 1) * sizeof *bsplit);
    offs = calloc((size_t)nranks + 1, sizeof *offs);
    lens = calloc((size_t)nranks + 1, sizeof *lens);
    if (!rows || !bsplit || !offs || !lens) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u blocks", nb); goto done; }
    r = sss_gather_block_rows(tree, R, 0, nb, rows, err);
    if (r != SSS_OK) goto done;
    /* Receiver blocks per rank: contiguous Morton ranges of equal work (not
     * of equal block count: a block in a dense region costs 100× one in a
     * sparse region), so that the ranks finish together and rank 0's
     * progress, the only one shown, stands for all of them. Which rank
     * computes a block does not change its bytes. */
    {
        uint64_t total = 0;
        for (uint32_t b = 0; b < nb; b++) total += sss_gather_block_work(tree, b, rows[b], C, D);
        bsplit[0] = 0;
        uint64_t acc = 0;
        uint32_t b = 0;
        for (int k = 1; k < nranks; k++) {
            const double target = (double)total * k / nranks;
            while (b < nb && (double)acc < target) acc += sss_gather_block_work(tree, b, rows[b], C, D), b++;
            bsplit[k] = b;
        }
        bsplit[nranks] = nb;
    }
    const uint32_t b0 = bsplit[rank], b1 = bsplit[rank + 1];
    uint32_t rows_max = 0;
    for (uint32_t b = 0; b < nb; b++) rows_max = rows[b] > rows_max ? rows[b] : rows_max;
    const uint32_t mine = sss_gather_tree_block_vertices(tree, b0, b1, NULL); /* this rank's receivers */
    st->t_tree = sss_now() - t;

    /* Peak memory (this rank), and the widest chunk of directions that
     * fits. Whole during the gather: the process itself, the meshes, q
     * (rank 0), Embree's scene, the hierarchy, the threads' block matrices
     * (counted for all D directions, an upper bound when chunked). Per direction loaded: the Morton-ordered transfer rows
     * and the nodes' moments, and under MPI this rank's part of q and on
     * rank 0 the chunk it collects. After the gather (the hierarchy gone):
     * lloyd8 holds q, its 8-bit indices and the training sample (16 bytes
     * per sample: keys, radix buffer, prefix sums); writing a float file
     * holds q and the file's image, which sss_file_write builds in memory
     * to checksum it; the threads' freed work space stays with malloc
     * (measured: the 437K dragon's peak RSS 2,153 MiB against 2,091 without
     * it). Chunks do not shrink those phases. */
    /* with Q (options.vector, never under MPI): q and Q's three planes */
    const uint64_t qbytes = holds_q ? (uint64_t)nv * D * C * sizeof(float) * (o->vector ? 5u : 1u) : 0;
    /* the bake's copy of the mesh and the caller's (sss-bake's import) */
    const uint64_t mesh_bytes = 2 * ((uint64_t)nv * 32 + (uint64_t)mesh->nf * 12);
    const uint64_t ws = sss_gather_workspace_rows_bytes(rows_max, D, C, &p, threads);
    const uint64_t fixed = PROCESS_BYTES + qbytes + mesh_bytes + (uint64_t)mesh->nf * VIS_BYTES_PER_TRIANGLE +
                           sss_gather_tree_size(tree, 0) + (uint64_t)nb * sizeof *rows + ws +
                           (mpi && holds_q ? (uint64_t)nv * sizeof *verts : 0);
    const uint64_t per_dir = sss_gather_tree_size(tree, 1) - sss_gather_tree_size(tree, 0) +
                             (mpi ? (uint64_t)mine * C * sizeof(float) + (holds_q ? (uint64_t)nv * C * sizeof(float) : 0) : 0) +
                             (o->vector ? (uint64_t)nv * sizeof(float) : 0);
    const uint64_t train = (uint64_t)nv * D < (4u << 20) ? (uint64_t)nv * D : (4u << 20); /* lloyd.c MAX_TRAIN */
    const uint64_t after = !holds_q ? 0
                           : PROCESS_BYTES + mesh_bytes + qbytes + ws +
                                 (o->quant == SSS_QUANT_LLOYD8 ? qbytes / 4 + train * 16 + (1u << 19) /* lloyd.c */
                                                               : qbytes + mesh_bytes / 2);
    uint32_t width = D; /* widest chunk that fits; 0: not even one direction */
    if (avail) {
        if (after > avail || fixed + per_dir > avail) width = 0;
        else if (fixed + (uint64_t)D * per_dir > avail) width = (uint32_t)((avail - fixed) / per_dir);
    }
    if (mpi) { /* the ranks must cut the directions alike: the narrowest wins */
        uint32_t *w = calloc((size_t)nranks, sizeof *w);
        if (!w) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory"); goto done; }
        w[rank] = width;
        for (int k = 0; k < nranks; k++) {
            offs[k] = (uint64_t)k * sizeof *w;
            lens[k] = sizeof *w;
        }
        if (o->comm->allgather(w, offs, lens, o->comm->ctx) != 0) {
            free(w);
            r = sss_fail(err, SSS_ERR_IO, "MPI: exchanging the memory plan failed");
            goto done;
        }
        for (int k = 0; k < nranks; k++) width = w[k] < width ? w[k] : width;
        free(w);
    }
    if (width == 0) {
        const uint64_t need = after > fixed + per_dir ? after : fixed + per_dir;
        r = sss_fail(err, SSS_ERR_NOMEM,
                     "the bake needs at least %.2f GiB for %u vertices x %u directions x %u channels even one light "
                     "direction at a time (integrals %.2f GiB, kept whole; gather tree, work space%s) but %.2f GiB is "
                     "available%s (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the limit): use fewer --dirs",
                     need / 1073741824.0, nv, D, C, qbytes / 1073741824.0,
                     after > fixed + per_dir ? ", quantising and writing the file" : "", avail / 1073741824.0,
                     mpi ? " on one of the ranks" : "");
        goto done;
    }
    const uint32_t nch = (D + width - 1) / width, wmax = (D + nch - 1) / nch;
    st->direction_chunks = nch;
    st->direction_chunk_width = wmax;
    {
        const uint64_t peak = fixed + (uint64_t)wmax * per_dir;
        st->predicted_peak_bytes = peak > after ? peak : after;
    }
    if (nch > 1 && o->progress)
        fprintf(stderr,
                "gather: %.0f MiB may be used: light directions in %u chunks of at most %u (all %u at once would "
                "need %.0f MiB); the output is the same\n",
                avail / 1048576.0, nch, wmax, D, (fixed + (uint64_t)D * per_dir) / 1048576.0);

    /* Integrals (rank 0): whole, the output. */
    if (holds_q) {
        out->q = malloc((size_t)nv * D * C * sizeof(float) + 1);
        if (!out->q) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u x %u integrals", nv, D, C); goto done; }
        huge_pages(out->q, (size_t)nv * D * C * sizeof(float));
        if (o->vector) {
            out->qvec = malloc(3 * (size_t)nv * D * C * sizeof(float) + 1);
            Gq = malloc((size_t)nv * wmax * sizeof(float) + 1);
            P = malloc((size_t)nv * D * C * sizeof(float) + 1);
            if (!out->qvec || !Gq || !P) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u x %u vector integrals", nv, D, C); goto done; }
        }
    }
    if (mpi) {
        part = malloc((size_t)mine * wmax * C * sizeof(float) + 1);
        if (holds_q) {
            full = malloc((size_t)nv * wmax * C * sizeof(float) + 1);
            verts = malloc((size_t)nv * sizeof *verts + 1);
        }
        if (!part || (holds_q && (!full || !verts))) {
            r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for the integrals of %u vertices", nv);
            goto done;
        }
        if (holds_q) sss_gather_tree_block_vertices(tree, 0, nb, verts);
    }
    if (!sss_gather_tree_rows(tree, wmax)) { /* room for the widest chunk, reused by all */
        r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u transfer values", nv, wmax);
        goto done;
    }
    r = sss_vis_create(mesh, &vis, err);
    if (r != SSS_OK) goto done;

    const uint32_t *order = sss_gather_tree_order(tree);
    if (hat && holds_q) { /* vertex → its row of the Morton-ordered transfer table */
        inv = malloc((size_t)nv * sizeof *inv + 1);
        if (!inv) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u vertices", nv); goto done; }
        for (uint32_t m = 0; m < nv; m++) inv[order[m]] = m;
    }
    const uint32_t m0 = share_start(nv, rank, nranks), m1 = share_start(nv, rank + 1, nranks);
    uint64_t rays = 0, occ = 0;
    sss_gather_stats gs;
    memset(&gs, 0, sizeof gs);
    for (uint32_t c = 0; c < nch && r == SSS_OK; c++) {
        const uint32_t j0 = chunk_start(D, c, nch), Dc = chunk_start(D, c + 1, nch) - j0;
        char lab[48]; /* "visibility " and two 32-bit counts */
        /* Visibility of this rank's Morton range, straight into the tree's
         * rows; then every rank gets all rows (all are sources). */
        t = sss_now();
        float *Gm = sss_gather_tree_rows(tree, Dc);
        if (!Gm) { r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u x %u transfer values", nv, Dc); break; }
        if (nch > 1) snprintf(lab, sizeof lab, "visibility %u/%u", c + 1, nch);
        sss_progress_begin(nch > 1 ? lab : "visibility", m1 - m0);
        uint64_t ry = 0, oc = 0;
        r = sss_transfer_rows_ordered(mesh, vis, out->dirs.dir + 3 * (size_t)j0, Dc, mat->eta, order, m0, m1, o->cancel, Gm, &ry,
                                      &oc, err);
        sss_progress_end();
        if (r != SSS_OK) break;
        rays += ry;
        occ += oc;
        if (mpi) {
            for (int k = 0; k < nranks; k++) {
                offs[k] = (uint64_t)share_start(nv, k, nranks) * Dc * sizeof(float);
                lens[k] = (uint64_t)(share_start(nv, k + 1, nranks) - share_start(nv, k, nranks)) * Dc * sizeof(float);
            }
            if (o->comm->allgather(Gm, offs, lens, o->comm->ctx) != 0) {
                r = sss_fail(err, SSS_ERR_IO, "MPI: exchanging the transfer table failed");
                break;
            }
        }
        if (c + 1 == nch) { /* Embree's scene is not needed any more */
            sss_vis_destroy(vis);
            vis = NULL;
        }
        st->t_visibility += sss_now() - t;

        t = sss_now();
        r = sss_gather_tree_moments(tree, mesh, err);
        if (r != SSS_OK) break;
        st->t_tree += sss_now() - t;

        /* The gather of this rank's blocks, progress weighted by work. */
        t = sss_now();
        uint64_t total = 0;
        for (uint32_t b = b0; b < b1; b++) total += sss_gather_block_work(tree, b, rows[b], C, Dc);
        if (nch > 1) snprintf(lab, sizeof lab, "integrals %u/%u", c + 1, nch);
        sss_progress_begin(nch > 1 ? lab : "integrals", total);
        sss_gather_stats g;
        r = sss_gather_run_chunk(tree, mesh, dip, C, R, b0, b1, j0, D, mpi ? part : out->q, !mpi, &g, err);
        sss_progress_end();
        if (r != SSS_OK) break;
        if (c == 0) gs = g; /* the lists are the same for every chunk */
        else {
            gs.t_lists += g.t_lists;
            gs.t_weights += g.t_weights;
            gs.t_sgemm += g.t_sgemm;
            gs.t_scatter += g.t_scatter;
            gs.flops += g.flops;
        }
        if (mpi) {
            /* rank 0 collects the parts (rank order = block order) and
             * places them by vertex */
            for (int k = 0; k < nranks; k++) {
                const uint32_t before = sss_gather_tree_block_vertices(tree, 0, bsplit[k], NULL);
                const uint32_t n = sss_gather_tree_block_vertices(tree, bsplit[k], bsplit[k + 1], NULL);
                offs[k] = (uint64_t)before * Dc * C * sizeof(float);
                lens[k] = (uint64_t)n * Dc * C * sizeof(float);
            }
            if (o->comm->gather0(part, full, offs, lens, o->comm->ctx) != 0) {
                r = sss_fail(err, SSS_ERR_IO, "MPI: collecting the integrals failed");
                break;
            }
            if (holds_q) {
#pragma omp parallel for schedule(static)
                for (int64_t kk = 0; kk < (int64_t)nv; kk++) {
                    const uint32_t v = verts[kk];
                    for (uint32_t j = 0; j < Dc; j++)
                        for (uint32_t ch = 0; ch < C; ch++)
                            out->q[((size_t)(j0 + j) * nv + v) * C + ch] = full[((size_t)kk * Dc + j) * C + ch];
                }
            }
        }
        if (inv && !sss_bake_add_hat(hat, inv, Gm, nv, C, j0, Dc, 1, out->q)) {
            r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for the hat-function corrections");
            break;
        }
        if (Gq) { /* Q (Hao–Varshney 2004 §3.1): the same hierarchy and lists, H_a's rows and moments */
            const double tv = sss_now();
            memcpy(Gq, Gm, (size_t)nv * Dc * sizeof(float));
            sss_gather_tree_set_signed(tree, 1);
            if (nch > 1) snprintf(lab, sizeof lab, "vector integrals %u/%u", c + 1, nch);
            sss_progress_begin(nch > 1 ? lab : "vector integrals", 3 * total);
            for (int a = 0; a < 3 && r == SSS_OK; a++) {
                sss_transfer_axis(mesh, out->dirs.dir + 3 * (size_t)j0, Dc, order, 0, nv, Gq, a, Gm);
                r = sss_gather_tree_moments(tree, mesh, err);
                if (r == SSS_OK) r = sss_gather_run_chunk(tree, mesh, dip, C, R, b0, b1, j0, D, P, 1, &g, err);
                if (r == SSS_OK && inv && !sss_bake_add_hat(hat, inv, Gm, nv, C, j0, Dc, 0, P))
                    r = sss_fail(err, SSS_ERR_NOMEM, "out of memory for the hat-function corrections");
                if (r == SSS_OK) interleave(P, (size_t)j0 * nv * C, (size_t)(j0 + Dc) * nv * C, a, out->qvec);
            }
            sss_progress_end();
            sss_gather_tree_set_signed(tree, 0);
            st->t_vector += sss_now() - tv;
            if (r != SSS_OK) break;
        }
        st->t_integrals += sss_now() - t;
        if (sss_cancelled(o->cancel)) r = sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during integrals");
    }
    if (r != SSS_OK) goto done;
    st->rays = rays;
    st->occluded_fraction = rays ? (double)occ / (double)rays : 0.0;
    st->tree_nodes = gs.nodes;
    st->tree_blocks = nb;
    st->near_pairs = gs.near_pairs;
    st->far_pairs = gs.far_pairs;
    st->rows_mean = gs.rows_mean;
    st->gather_gflops = gs.t_sgemm > 0 ? gs.flops / gs.t_sgemm * 1e-9 : 0;
    {
        const double tt = gs.t_lists + gs.t_weights + gs.t_sgemm + gs.t_scatter;
        st->sgemm_fraction = tt > 0 ? gs.t_sgemm / tt : 0;
        st->near_gflops = tt > 0 ? gs.flops / tt * 1e-9 : 0;
    }
    /* the neighbourhood figures of the direct sum, for the summary: sources
     * per receiver taken one by one, and the rows per receiver */
    st->neighbours_total = gs.near_pairs;
    st->neighbours_mean = nv ? (double)gs.near_pairs / nv : 0;
    if (o->verbose)
        fprintf(stderr, "gather: %u nodes (%u leaves), %u blocks, rows/block %.0f, near pairs/receiver %.0f, far "
                "nodes/receiver %.1f; thread-s lists %.2f weights %.2f product %.2f scatter %.2f; product %.1f GFLOP/s, "
                "dense blocks %.1f GFLOP/s; tree %.2fs; %u direction chunks\n", gs.nodes, gs.leaves, nb, gs.rows_mean,
                (double)gs.near_pairs / nv, (double)gs.far_pairs / nv, gs.t_lists, gs.t_weights, gs.t_sgemm,
                gs.t_scatter, st->gather_gflops, st->near_gflops, st->t_tree, nch);

done:
    sss_vis_destroy(vis);
    sss_gather_tree_destroy(tree);
    free(part);
    free(full);
    free(Gq);
    free(P);
    free(verts);
    free(inv);
    free(rows);
    free(bsplit);
    free(offs);
    free(lens);
    return r;
}
