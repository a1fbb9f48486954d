/* gather_tree.c: the far field of the hierarchical gather (sss/gather.h).
 *
 * Hao–Varshney 2004 §3.1 sums over every vertex within the cutoff radius
 * and notes that an octree as in Jensen & Buhler 2002 would make the bake
 * O(N log N). Jensen & Buhler (§4, "hierarchical evaluation") store in
 * each octree node the total irradiance, the area and an
 * irradiance-weighted position, and use a node whose solid angle seen from
 * the receiver is below a threshold instead of its points. Here the points
 * are mesh vertices in Morton order (a node is a contiguous range, children
 * split it by the next three Morton bits) and each node stores, per light
 * direction, the flux Φ_j = Σ ΔA_i G[i, j] with its first and second
 * moments about the node's area centroid c. Since R_d depends on the
 * distance only, the Taylor expansion of R_d(‖x_o − x_i‖) about c,
 *   R_d(d) − R_d′(d) u·δ + ½ δᵀ[R_d″ uuᵀ + (R_d′/d)(I − uuᵀ)]δ,
 * (y = x_o − c, d = ‖y‖, u = y/d, δ = x_i − c) summed against the flux gives
 * a far node's contribution from 10 numbers per direction; the first-order
 * term is what Jensen–Buhler's irradiance-weighted centre removes, the
 * second-order term keeps the relative error of a far node near θ³/100
 * instead of θ²/4 (measured: docs/benchmarks.md, "Hierarchical gather").
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "gather/gather_internal.h"
#include "kernels/progress.h"
#include "sss/vec3.h"

#define MORTON_BITS 21
/* Fewest sources in a far node. A far node costs 10 moment rows of the
 * block product, a near one a row per source. 48 before; 32 lets full
 * leaves be far and cut the rows per block from 3,400 to 2,900 on the 437K
 * dragon. 10 (where far rows start to cost less than near columns) cut them
 * to 2,400 but moved test_exact's blob 1e-3 of its largest q away from the
 * direct sum (that test holds the bake to 1e-5); 32 keeps it at 7e-7
 * (docs/benchmarks.md "Bake at scale"). */
#define SSS_GATHER_FAR_MIN 32

static uint64_t spread3(uint64_t x)
{
    x &= 0x1fffff;
    x = (x | x << 32) & 0x1f00000000ffffULL;
    x = (x | x << 16) & 0x1f0000ff0000ffULL;
    x = (x | x << 8) & 0x100f00f00f00f00fULL;
    x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
    x = (x | x << 2) & 0x1249249249249249ULL;
    return x;
}

typedef struct { uint64_t code; uint32_t v; } keyed;

static int cmp_keyed(const void *a, const void *b)
{
    const keyed *x = a, *y = b;
    if (x->code != y->code) return x->code < y->code ? -1 : 1;
    return (x->v > y->v) - (x->v < y->v);
}

typedef struct builder {
    sss_gather_tree *t;
    uint64_t *code; /* Morton code by Morton position */
    uint32_t cap;
    int failed;
} builder;

static uint32_t new_nodes(builder *b, uint32_t n)
{
    sss_gather_tree *t = b->t;
    if (t->nnodes + n > b->cap) {
        uint32_t cap = b->cap * 2 + n;
        sss_gnode *nn = realloc(t->node, (size_t)cap * sizeof *nn);
        if (!nn) { b->failed = 1; return 0; }
        t->node = nn;
        b->cap = cap;
    }
    uint32_t first = t->nnodes;
    memset(t->node + first, 0, (size_t)n * sizeof *t->node);
    t->nnodes += n;
    return first;
}

/* Splits node `id` by the next Morton digit that separates its sources;
 * children are allocated consecutively, so a child's index is always larger
 * than its parent's (the moments are accumulated in reverse index order). */
static void build_node(builder *b, uint32_t id, uint32_t level)
{
    sss_gather_tree *t = b->t;
    const uint32_t lo = t->node[id].lo, hi = t->node[id].hi;
    if (hi - lo <= t->p.leaf_size) return;
    for (; level < MORTON_BITS; level++) {
        const int shift = 3 * (MORTON_BITS - 1 - (int)level);
        if (((b->code[lo] >> shift) & 7) != ((b->code[hi - 1] >> shift) & 7)) break;
    }
    if (level >= MORTON_BITS) return; /* more than leaf_size sources at one Morton cell: a leaf */
    const int shift = 3 * (MORTON_BITS - 1 - (int)level);
    uint32_t bounds[9], nb = 0;
    bounds[nb++] = lo;
    for (uint32_t k = lo + 1; k < hi; k++)
        if (((b->code[k] >> shift) & 7) != ((b->code[k - 1] >> shift) & 7)) bounds[nb++] = k;
    bounds[nb] = hi;
    const uint32_t first = new_nodes(b, nb);
    if (b->failed) return;
    t->node[id].child = first;
    t->node[id].nchild = nb;
    for (uint32_t c = 0; c < nb; c++) {
        t->node[first + c].lo = bounds[c];
        t->node[first + c].hi = bounds[c + 1];
        t->node[first + c].depth = t->node[id].depth + 1;
    }
    for (uint32_t c = 0; c < nb && !b->failed; c++) build_node(b, first + c, level + 1);
}

static void collect_blocks(sss_gather_tree *t, uint32_t id, uint32_t *count, int store)
{
    const sss_gnode *n = &t->node[id];
    if (n->hi - n->lo <= t->p.block_size || !n->nchild) {
        if (store) t->block[*count] = id;
        (*count)++;
        return;
    }
    for (uint32_t c = 0; c < n->nchild; c++) collect_blocks(t, n->child + c, count, store);
}

void sss_gather_tree_destroy(sss_gather_tree *t)
{
    if (!t) return;
    free(t->perm);
    free(t->pmm);
    free(t->group_area);
    free(t->node);
    free(t->mom);
    free(t->block);
    free(t->Gm);
    free(t->fpt);
    free(t);
}

static void params_defaults(sss_gather_params *p)
{
    if (!(p->theta > 0)) p->theta = SSS_GATHER_THETA_DEFAULT;
    if (p->leaf_size == 0) p->leaf_size = 32;
    if (p->block_size == 0) p->block_size = 128; /* sss/gather.h */
}

uint64_t sss_gather_tree_bytes(uint32_t nv, uint32_t n_dirs, const sss_gather_params *pin)
{
    sss_gather_params p = pin ? *pin : (sss_gather_params){0};
    params_defaults(&p);
    /* An octree leaf holds at least one source; measured on the dragons
     * about leaf_size / 4 on average, so nodes ≤ 2 nv / (leaf_size / 4) with
     * the internal nodes; bound it by 8 nv / leaf_size + 64. */
    const uint64_t nodes = 8ull * nv / p.leaf_size + 64;
    return nodes * (sizeof(sss_gnode) + (uint64_t)SSS_GATHER_MOMENTS * n_dirs * sizeof(float)) +
           (uint64_t)nv * (4 + 24 + 8 + 16 + 4) + (uint64_t)nv * n_dirs * sizeof(float);
}

uint64_t sss_gather_tree_size(const sss_gather_tree *t, uint32_t n_dirs)
{
    return (uint64_t)t->nv * (sizeof *t->perm + 3 * sizeof *t->pmm + sizeof *t->group_area) +
           (uint64_t)t->nnodes * sizeof *t->node + (uint64_t)t->nblocks * sizeof *t->block +
           (uint64_t)n_dirs * ((uint64_t)t->nv + (uint64_t)t->nnodes * SSS_GATHER_MOMENTS) * sizeof(float);
}

uint32_t sss_gather_tree_blocks(const sss_gather_tree *t) { return t->nblocks; }

uint32_t sss_gather_tree_block_vertices(const sss_gather_tree *t, uint32_t b0, uint32_t b1, uint32_t *vertices)
{
    uint32_t k = 0;
    for (uint32_t b = b0; b < b1 && b < t->nblocks; b++) {
        const sss_gnode *n = &t->node[t->block[b]];
        for (uint32_t m = n->lo; m < n->hi; m++) {
            if (vertices) vertices[k] = t->perm[m];
            k++;
        }
    }
    return k;
}

/* Moments of a leaf straight from its sources, in double. */
static void leaf_moments(const sss_gather_tree *t, const sss_mesh *mesh, const sss_gnode *n, double *acc, float *out)
{
    const uint32_t D = t->D;
    memset(acc, 0, (size_t)SSS_GATHER_MOMENTS * D * sizeof(double));
    const double s2 = t->s * t->s;
    for (uint32_t m = n->lo; m < n->hi; m++) {
        const uint32_t i = t->perm[m];
        const double dA = mesh->area[i] * s2;
        const double dx = t->pmm[3 * (size_t)i] - n->c[0], dy = t->pmm[3 * (size_t)i + 1] - n->c[1],
                     dz = t->pmm[3 * (size_t)i + 2] - n->c[2];
        const double mul[SSS_GATHER_MOMENTS] = {1, dx, dy, dz, dx * dx, dy * dy, dz * dz, dx * dy, dx * dz, dy * dz};
        const float *g = t->Gm + (size_t)m * D;
        for (int k = 0; k < SSS_GATHER_MOMENTS; k++) {
            double *a = acc + (size_t)k * D;
            const double f = dA * mul[k];
            for (uint32_t j = 0; j < D; j++) a[j] += f * g[j];
        }
    }
    for (size_t k = 0; k < (size_t)SSS_GATHER_MOMENTS * D; k++) out[k] = (float)acc[k];
}

/* Moments of an internal node from its children's, moved to its centroid
 * by the parallel-axis rule: with t = c_child − c,
 *   M1 += M1_child + Φ_child t,  M2 += M2_child + t M1_childᵀ + M1_child tᵀ + Φ_child t tᵀ. */
static void internal_moments(const sss_gather_tree *t, const sss_gnode *n, double *acc, float *out)
{
    const uint32_t D = t->D;
    memset(acc, 0, (size_t)SSS_GATHER_MOMENTS * D * sizeof(double));
    static const int AX[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (uint32_t c = 0; c < n->nchild; c++) {
        const sss_gnode *ch = &t->node[n->child + c];
        const float *m = t->mom + (size_t)(n->child + c) * SSS_GATHER_MOMENTS * D;
        const double tv[3] = {ch->c[0] - n->c[0], ch->c[1] - n->c[1], ch->c[2] - n->c[2]};
        for (uint32_t j = 0; j < D; j++) {
            const double phi = m[j], m1[3] = {m[D + j], m[2 * D + j], m[3 * D + j]};
            acc[j] += phi;
            for (int a = 0; a < 3; a++) acc[(size_t)(1 + a) * D + j] += m1[a] + phi * tv[a];
            for (int e = 0; e < 6; e++) {
                const int a = AX[e][0], b = AX[e][1];
                acc[(size_t)(4 + e) * D + j] += m[(size_t)(4 + e) * D + j] + tv[a] * m1[b] + m1[a] * tv[b] + phi * tv[a] * tv[b];
            }
        }
    }
    for (size_t k = 0; k < (size_t)SSS_GATHER_MOMENTS * D; k++) out[k] = (float)acc[k];
}

sss_result sss_gather_tree_create(const sss_mesh *mesh, double s, const sss_gather_params *pin, sss_gather_tree **out,
                                  sss_error *err)
{
    *out = NULL;
    if (!mesh->area || mesh->nv == 0 || !(s > 0)) return sss_fail(err, SSS_ERR_ARG, "gather tree: invalid arguments");
    sss_gather_params p = pin ? *pin : (sss_gather_params){0};
    params_defaults(&p);
    if (!(p.theta < 1.0)) return sss_fail(err, SSS_ERR_ARG, "--theta %g must be in (0, 1)", p.theta);
    const uint32_t nv = mesh->nv;
    sss_gather_tree *t = calloc(1, sizeof *t);
    keyed *kv = malloc((size_t)nv * sizeof *kv);
    builder b = {t, NULL, 0, 0};
    b.code = malloc((size_t)nv * sizeof(uint64_t));
    if (t) {
        t->nv = nv;
        t->s = s;
        t->p = p;
        t->perm = malloc((size_t)nv * sizeof(uint32_t));
        t->pmm = malloc((size_t)nv * 3 * sizeof(double));
        t->group_area = malloc((size_t)nv * sizeof(double));
    }
    if (!t || !kv || !b.code || !t->perm || !t->pmm || !t->group_area) goto nomem;

    /* Morton order of the vertices in their bounding box (ties by index);
     * scaling by s > 0 keeps the extremes, so the box in mm is the mesh's
     * box times s. */
    for (size_t e = 0; e < (size_t)nv * 3; e++) t->pmm[e] = (double)mesh->pos[e] * s;
    double lo[3], hi[3];
    sss_mesh_bounds(mesh, lo, hi);
    for (int a = 0; a < 3; a++) {
        lo[a] *= s;
        hi[a] *= s;
    }
    double ext = fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    if (!(ext > 0)) ext = 1.0;
    const double scale = ((1u << MORTON_BITS) - 1) / ext;
    for (uint32_t v = 0; v < nv; v++) {
        uint64_t c = 0;
        for (int a = 0; a < 3; a++) {
            double q = (t->pmm[3 * (size_t)v + a] - lo[a]) * scale;
            uint64_t qi = q <= 0 ? 0 : q >= (1u << MORTON_BITS) - 1 ? (1u << MORTON_BITS) - 1 : (uint64_t)q;
            c |= spread3(qi) << (2 - a);
        }
        kv[v].code = c;
        kv[v].v = v;
    }
    qsort(kv, nv, sizeof *kv, cmp_keyed);
    for (uint32_t m = 0; m < nv; m++) {
        t->perm[m] = kv[m].v;
        b.code[m] = kv[m].code;
    }
    /* Coincident vertices share a Morton code and sit together, by index:
     * their area sum in index order is what nbhd.c sums for the shared disk
     * (docs/robustness.md B4). */
    for (uint32_t m = 0; m < nv;) {
        uint32_t e = m + 1;
        while (e < nv && b.code[e] == b.code[m]) e++;
        for (uint32_t a = m; a < e; a++) {
            const uint32_t va = t->perm[a];
            const float *pa = mesh->pos + 3 * (size_t)va;
            double g = 0.0;
            for (uint32_t c = m; c < e; c++) {
                const float *pc = mesh->pos + 3 * (size_t)t->perm[c];
                if (pa[0] == pc[0] && pa[1] == pc[1] && pa[2] == pc[2]) g += mesh->area[t->perm[c]];
            }
            t->group_area[va] = g;
        }
        m = e;
    }
    free(kv);
    kv = NULL;

    /* Octree on the Morton digits. */
    b.cap = 64;
    t->node = malloc((size_t)b.cap * sizeof *t->node);
    if (!t->node) goto nomem;
    new_nodes(&b, 1);
    t->node[0].lo = 0;
    t->node[0].hi = nv;
    build_node(&b, 0, 0);
    free(b.code);
    b.code = NULL;
    if (b.failed) goto nomem;
    for (uint32_t n = 0; n < t->nnodes; n++) t->nleaves += t->node[n].nchild == 0;

    /* Centroid, bounding radius and largest area disk of each node. */
    const double s2 = s * s;
#pragma omp parallel for schedule(dynamic, 64)
    for (int64_t n = 0; n < (int64_t)t->nnodes; n++) {
        sss_gnode *nd = &t->node[n];
        double A = 0, c[3] = {0, 0, 0}, rho2 = 0;
        for (uint32_t m = nd->lo; m < nd->hi; m++) {
            const uint32_t i = t->perm[m];
            const double a = mesh->area[i] * s2;
            A += a;
            for (int k = 0; k < 3; k++) c[k] += a * t->pmm[3 * (size_t)i + k];
            rho2 = fmax(rho2, a / SSS_PI);
        }
        if (A > 0) {
            for (int k = 0; k < 3; k++) c[k] /= A;
        } else { /* zero-area sources only: the plain mean */
            for (int k = 0; k < 3; k++) c[k] = 0;
            for (uint32_t m = nd->lo; m < nd->hi; m++)
                for (int k = 0; k < 3; k++) c[k] += t->pmm[3 * (size_t)t->perm[m] + k];
            for (int k = 0; k < 3; k++) c[k] /= (double)(nd->hi - nd->lo);
        }
        double r2 = 0;
        for (uint32_t m = nd->lo; m < nd->hi; m++) {
            const double *x = t->pmm + 3 * (size_t)t->perm[m];
            const double d2 = (x[0] - c[0]) * (x[0] - c[0]) + (x[1] - c[1]) * (x[1] - c[1]) + (x[2] - c[2]) * (x[2] - c[2]);
            r2 = fmax(r2, d2);
        }
        for (int k = 0; k < 3; k++) nd->c[k] = c[k];
        /* a hair larger, so that distance bounds built on it are safe
         * against the rounding of the distances themselves */
        nd->r = sqrt(r2) * (1.0 + 1e-12) + 1e-12;
        nd->rho_max = sqrt(rho2);
    }
    t->maxdepth = 0;
    for (uint32_t n = 0; n < t->nnodes; n++) t->maxdepth = t->node[n].depth > t->maxdepth ? t->node[n].depth : t->maxdepth;

    uint32_t nb = 0;
    collect_blocks(t, 0, &nb, 0);
    t->block = malloc((size_t)nb * sizeof(uint32_t));
    if (!t->block) goto nomem;
    t->nblocks = 0;
    collect_blocks(t, 0, &t->nblocks, 1);
    *out = t;
    return SSS_OK;

nomem:
    free(kv);
    free(b.code);
    sss_gather_tree_destroy(t);
    return sss_fail(err, SSS_ERR_NOMEM, "gather tree: out of memory for %u vertices", mesh->nv);
}

const uint32_t *sss_gather_tree_order(const sss_gather_tree *t) { return t->perm; }

void sss_gather_tree_set_signed(sss_gather_tree *t, int signed_sources) { t->p.signed_sources = signed_sources; }

float *sss_gather_tree_rows(sss_gather_tree *t, uint32_t n_dirs)
{
    if (n_dirs == 0) return NULL;
    /* The buffers keep the largest width asked for: a bake in direction
     * chunks (bake_tree.c) loads chunk after chunk into the same memory. */
    if (n_dirs > t->cap_dirs) {
        free(t->Gm);
        free(t->mom);
        t->Gm = malloc((size_t)t->nv * n_dirs * sizeof(float) + 1);
        t->mom = malloc((size_t)t->nnodes * SSS_GATHER_MOMENTS * n_dirs * sizeof(float) + 1);
        if (!t->Gm || !t->mom) {
            free(t->Gm);
            free(t->mom);
            t->Gm = t->mom = NULL;
            t->cap_dirs = t->D = 0;
            return NULL;
        }
        t->cap_dirs = n_dirs;
    }
    t->D = n_dirs;
    return t->Gm;
}

sss_result sss_gather_tree_moments(sss_gather_tree *t, const sss_mesh *mesh, sss_error *err)
{
    const uint32_t D = t->D;
    if (!t->Gm || D == 0 || mesh->nv != t->nv) return sss_fail(err, SSS_ERR_ARG, "gather tree: no transfer rows loaded");
    /* Flux moments, deepest nodes first (a level at a time, in parallel).
     * Every direction j is summed on its own, in the same order whatever
     * the other directions loaded with it: a node's moments for ω_j have
     * the same bits in a bake in direction chunks as in one piece. */
    int failed = 0;
    for (int64_t dep = t->maxdepth; dep >= 0; dep--) {
#pragma omp parallel
        {
            double *acc = malloc((size_t)SSS_GATHER_MOMENTS * D * sizeof(double));
            if (!acc) {
#pragma omp atomic write
                failed = 1;
            }
#pragma omp for schedule(dynamic, 16)
            for (int64_t n = 0; n < (int64_t)t->nnodes; n++) {
                const sss_gnode *nd = &t->node[n];
                if (!acc || nd->depth != (uint32_t)dep) continue;
                float *o = t->mom + (size_t)n * SSS_GATHER_MOMENTS * D;
                if (nd->nchild) internal_moments(t, nd, acc, o);
                else leaf_moments(t, mesh, nd, acc, o);
            }
            free(acc);
        }
        if (failed)
            return sss_fail(err, SSS_ERR_NOMEM, "gather tree: out of memory for the moments of %u directions", D);
    }
    return SSS_OK;
}

sss_result sss_gather_tree_build(const sss_mesh *mesh, double s, const float *G, uint32_t D,
                                 const sss_gather_params *pin, sss_gather_tree **out, sss_error *err)
{
    *out = NULL;
    if (D == 0 || !G) return sss_fail(err, SSS_ERR_ARG, "gather tree: invalid arguments");
    sss_gather_tree *t = NULL;
    sss_result r = sss_gather_tree_create(mesh, s, pin, &t, err);
    if (r != SSS_OK) return r;
    /* G in Morton order: a near leaf's rows are then one contiguous run */
    float *Gm = sss_gather_tree_rows(t, D);
    if (!Gm) {
        sss_gather_tree_destroy(t);
        return sss_fail(err, SSS_ERR_NOMEM, "gather tree: out of memory for %u vertices x %u directions", mesh->nv, D);
    }
#pragma omp parallel for schedule(static)
    for (int64_t m = 0; m < (int64_t)t->nv; m++)
        memcpy(Gm + (size_t)m * D, G + (size_t)t->perm[m] * D, D * sizeof(float));
    r = sss_gather_tree_moments(t, mesh, err);
    if (r != SSS_OK) {
        sss_gather_tree_destroy(t);
        return r;
    }
    *out = t;
    return SSS_OK;
}

static int push(uint32_t **a, uint32_t *n, uint32_t *cap, uint32_t v)
{
    if (*n == *cap) {
        uint32_t c = *cap ? *cap * 2 : 64;
        uint32_t *na = realloc(*a, (size_t)c * sizeof **a);
        if (!na) return 0;
        *a = na;
        *cap = c;
    }
    (*a)[(*n)++] = v;
    return 1;
}

int sss_gather_lists(const sss_gather_tree *t, uint32_t b, double radius_mm, sss_glist *l)
{
    l->nnear = l->nfar = l->near_sources = 0;
    const sss_gnode *rb = &t->node[b];
    const double theta = t->p.theta;
    const double R = radius_mm * (1.0 + 1e-9) + 1e-12;
    uint32_t stack[64 * 8 + 8];
    uint32_t sp = 0;
    stack[sp++] = 0;
    while (sp) {
        const uint32_t id = stack[--sp];
        const sss_gnode *n = &t->node[id];
        const double dx = n->c[0] - rb->c[0], dy = n->c[1] - rb->c[1], dz = n->c[2] - rb->c[2];
        const double dist = sqrt(dx * dx + dy * dy + dz * dz);
        /* every (receiver, source) pair is at least this far apart */
        const double gap = dist - rb->r - n->r;
        if (gap > R) continue;
        /* Far: the node subtends less than θ from every receiver of the
         * block (Jensen–Buhler's solid-angle test, with the block's radius
         * taken off the distance), and no source's area disk reaches a
         * receiver (those are integrated over the disk in the direct sum,
         * sss_rd_disk_offset, and coincident vertices are never far). A
         * node of few sources is cheaper as near columns (one per source)
         * than as 10 moment rows, and summing it exactly keeps the far
         * field out of the range where R_d is largest. */
        if (gap > n->rho_max && n->r < theta * (dist - rb->r) && n->hi - n->lo >= SSS_GATHER_FAR_MIN) {
            /* a far node counts only where its centroid is within the
             * cutoff (sss_gather_far_weights): beyond it for every
             * receiver of the block, its 10 rows would be zero columns */
            if (dist - rb->r > R) continue;
            if (!push(&l->far, &l->nfar, &l->cap_far, id)) return 0;
        } else if (!n->nchild) {
            if (!push(&l->near, &l->nnear, &l->cap_near, id)) return 0;
            l->near_sources += n->hi - n->lo;
        } else {
            /* children in reverse so they are visited in Morton order */
            for (uint32_t c = n->nchild; c-- > 0;) stack[sp++] = n->child + c;
        }
    }
    return 1;
}

void sss_gkernel_init(sss_gkernel *k, const sss_dipole *d)
{
    k->sigma = (float)d->sigma_tr;
    k->z_r = (float)d->z_r;
    k->z_v = (float)d->z_v;
    k->zr2 = (float)(d->z_r * d->z_r);
    k->zv2 = (float)(d->z_v * d->z_v);
    k->coef = (float)(d->alpha_p / (4.0 * SSS_PI) / SSS_PI);
}

/* R_d and its first two radial derivatives at distances r (r2 = r²),
 * times coef, for n nodes at once. For one dipole source at depth z, with
 * e = e^{−σ d_z}, d_z = sqrt(r² + z²):
 *   g   = (1 + σd) e / d³                         (docs/physics.md §2)
 *   g′  = −e (σ²d² + 3σd + 3) / d⁴
 *   g″  =  e (σ³d³ + 5σ²d² + 12σd + 12) / d⁵
 *   ∂r g(d_z) = g′ r/d_z,  ∂²r g(d_z) = g″ r²/d_z² + g′ z²/d_z³. */
SSS_GATHER_CLONES
static void rd_derivs(const sss_gkernel *kp, const float *restrict r2v, const float *restrict rv, uint32_t n,
                      float *restrict f0, float *restrict f1, float *restrict f2)
{
    const float sigma = kp->sigma, coef = kp->coef;
    const float zs[2] = {kp->z_r, kp->z_v}, zs2[2] = {kp->zr2, kp->zv2};
    for (uint32_t a = 0; a < n; a++) {
        const float r2 = r2v[a], r = rv[a];
        float a0 = 0, a1 = 0, a2 = 0;
        for (int s = 0; s < 2; s++) {
            const float z = zs[s], z2 = zs2[s];
            const float d = sqrtf(r2 + z2), id = 1.0f / d;
            const float sd = sigma * d;
            const float e = sss_gexpf(-sd);
            const float id2 = id * id, id3 = id2 * id;
            const float g1 = -e * (sd * sd + 3.0f * sd + 3.0f) * id3 * id;
            const float g2 = e * (((sd + 5.0f) * sd + 12.0f) * sd + 12.0f) * id3 * id2;
            a0 += z * (1.0f + sd) * e * id3;
            a1 += z * g1 * r * id;
            a2 += z * (g2 * r2 * id2 + g1 * z2 * id3);
        }
        f0[a] = coef * a0;
        f1[a] = coef * a1;
        f2[a] = coef * a2;
    }
}

/* The ten moment weights of nfar nodes for one channel from R_d and its
 * radial derivatives (f0, f1, f2 at distances r, unit vectors u): the
 * second-order Taylor expansion of R_d about each node's centroid
 * (docs/benchmarks.md, "Far field"). Moment m of node f goes to wm[f]:
 * ten separate runs (restrict parameters; as offsets into one array gcc
 * could not rule out their overlap and left the loop scalar). */
SSS_GATHER_CLONES
static void taylor_weights(const float *restrict f0, const float *restrict f1, const float *restrict f2,
                           const float *restrict r, const float *restrict in, const float *restrict ux,
                           const float *restrict uy, const float *restrict uz, uint32_t nfar, float *restrict w0,
                           float *restrict w1, float *restrict w2, float *restrict w3, float *restrict w4,
                           float *restrict w5, float *restrict w6, float *restrict w7, float *restrict w8,
                           float *restrict w9)
{
    for (uint32_t f = 0; f < nfar; f++) {
        const float m = in[f], id = 1.0f / r[f];
        const float x = ux[f], y = uy[f], z = uz[f];
        const float A = (f2[f] - f1[f] * id) * m, B = f1[f] * id * m, F1 = f1[f] * m;
        w0[f] = f0[f] * m;
        w1[f] = -F1 * x;
        w2[f] = -F1 * y;
        w3[f] = -F1 * z;
        w4[f] = 0.5f * (A * x * x + B);
        w5[f] = 0.5f * (A * y * y + B);
        w6[f] = 0.5f * (A * z * z + B);
        w7[f] = A * x * y;
        w8[f] = A * x * z;
        w9[f] = A * y * z;
    }
}

/* Distance, cutoff mark and unit vector from each far node's centroid to
 * the receiver, in double as the lists decide (vectorised: the centroids
 * come as three arrays, gathered once per block by the caller). */
SSS_GATHER_CLONES
static void far_geometry(const double *restrict cx, const double *restrict cy, const double *restrict cz,
                         uint32_t nfar, double ox, double oy, double oz, double R2, float *restrict r2,
                         float *restrict r, float *restrict in, float *restrict ux, float *restrict uy,
                         float *restrict uz)
{
    for (uint32_t f = 0; f < nfar; f++) {
        const double y0 = ox - cx[f], y1 = oy - cy[f], y2 = oz - cz[f];
        const double d2 = y0 * y0 + y1 * y1 + y2 * y2, d = sqrt(d2), id = 1.0 / d;
        /* a node whose centroid is beyond the cutoff counts as outside */
        in[f] = (float)(d2 <= R2);
        r2[f] = (float)d2;
        r[f] = (float)d;
        ux[f] = (float)(y0 * id);
        uy[f] = (float)(y1 * id);
        uz[f] = (float)(y2 * id);
    }
}

void sss_gather_far_centroids(const sss_gather_tree *t, const uint32_t *far, uint32_t nfar, double *c)
{
    for (uint32_t f = 0; f < nfar; f++)
        for (int x = 0; x < 3; x++) c[(size_t)x * nfar + f] = t->node[far[f]].c[x];
}

void sss_gather_far_weights(const double *c, uint32_t nfar, const double x_o[3], const sss_gkernel *k,
                            uint32_t channels, double radius_mm, float *scratch, float *W, uint64_t ldc)
{
    float *r2 = scratch, *r = r2 + nfar, *in = r + nfar, *ux = in + nfar, *uy = ux + nfar, *uz = uy + nfar;
    float *f0 = uz + nfar, *f1 = f0 + nfar, *f2 = f1 + nfar;
    far_geometry(c, c + nfar, c + 2 * (size_t)nfar, nfar, x_o[0], x_o[1], x_o[2], radius_mm * radius_mm, r2, r, in,
                 ux, uy, uz);
    for (uint32_t c = 0; c < channels; c++) {
        rd_derivs(&k[c], r2, r, nfar, f0, f1, f2);
        float *w = W + c * ldc;
        const size_t n = nfar;
        taylor_weights(f0, f1, f2, r, in, ux, uy, uz, nfar, w, w + n, w + 2 * n, w + 3 * n, w + 4 * n, w + 5 * n,
                       w + 6 * n, w + 7 * n, w + 8 * n, w + 9 * n);
    }
}
