/* gather_blocks.c: the dense blocks of the hierarchical gather and the dense
 * block product (sss/gather.h).
 *
 * Receivers are taken a Morton block at a time. The block's interaction
 * list (gather_tree.c) names near leaves, whose sources are summed one by
 * one with the direct sum's weights (Hao–Varshney 2004 §3.1:
 * (1/π) R_d(r) ΔA, the self term and the near disks of nbhd.c), and far
 * nodes, whose 10 flux-moment rows carry the Taylor weights. Both become
 * the columns of one dense matrix W (channels × receivers by rows), and the
 * block's integrals are one product
 *   Q (C·B × D) = W (C·B × S) · Ψ (S × D),
 * Ψ's rows being the transfer rows G[i, ·] of the near sources and the
 * moment rows of the far nodes, taken through pointers and packed a panel
 * at a time by gather_gemm.c (a register-tiled kernel near the machine's
 * FMA peak, where the direct sum's sparse row loop is bound by memory;
 * docs/benchmarks.md). One thread computes a
 * whole block in a fixed order, so the bytes do not depend on the thread
 * count.
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

/* The same near-disk rule as nbhd.c: a neighbour closer than its own
 * area-disk radius is integrated over the disk. */
#define NEAR_DISKS 1.0

typedef struct work {
    float *W, *Q;
    size_t capW, capQ;
    const float **rows; /* Ψ: a pointer to each row */
    size_t caprows;
    float *pack; /* the block product's scratch */
    size_t cappack;
    uint32_t *src, *msrc; /* the near sources and their Morton positions */
    size_t capsrc, capmsrc;
    float *fs; /* per source: dA, r², inside; then the far scratch */
    size_t capfs;
    double *sxyz; /* source positions (mesh units), x then y then z */
    size_t capxyz;
    unsigned char *flag;
    size_t capflag;
    sss_glist l;
    sss_gather_fpairs fp; /* a field's near pairs within the group (gather_field.c) */
} work;

static int grow(void **p, size_t *cap, size_t need, size_t elem)
{
    if (need <= *cap) return 1;
    size_t c = need + need / 2 + 64;
    void *n = realloc(*p, c * elem);
    if (!n) return 0;
    *p = n;
    *cap = c;
    return 1;
}

/* (1/π) R_d(r) ΔA for S sources at squared distances r2v (mm²), zero
 * where inv[a] = 0 (beyond the cutoff), from the channel's polynomials
 * (gather_rdtab.c), into w[a]. Three channels (RGB) share the octave and u
 * of each source: one pass writes the three rows. */
SSS_GATHER_CLONES
static void rd_row(const sss_rdtab *tab, const float *restrict r2v, const float *restrict dA,
                   const float *restrict inv, uint32_t S, float *restrict w)
{
    for (uint32_t a = 0; a < S; a++) w[a] = sss_rdtab_at(tab, r2v[a]) * (dA[a] * inv[a]);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
/* The three rows with AVX-512 written out, each coefficient of the 32
 * octaves one two-register permutation (vpermt2ps) rather than a gather:
 * the same operations in the same order as sss_rdtab_at, the same bits. */
__attribute__((target("avx512f"))) static void rd_rows3_512(const sss_rdtab *tab, const float *restrict r2v,
                                                             const float *restrict dA, const float *restrict inv,
                                                             uint32_t S, float *restrict w, uint64_t ldc)
{
    const int32_t e0 = tab[0].e0; /* the channels share the cutoff's octave */
    const __m512i lo = _mm512_set1_epi32((127 + e0) << 23), hi = _mm512_set1_epi32(((127 + e0 + SSS_RDTAB_N) << 23) - 1);
    const __m512i mant = _mm512_set1_epi32(0x7fffff), base = _mm512_set1_epi32(127 + e0);
    const __m512 scale = _mm512_set1_ps(0x1p-22f), one = _mm512_set1_ps(1.0f);
    for (uint32_t a0 = 0; a0 < S; a0 += 16) {
        const __mmask16 m = S - a0 >= 16 ? (__mmask16)0xffff : (__mmask16)((1u << (S - a0)) - 1u);
        __m512i b = _mm512_castps_si512(_mm512_maskz_loadu_ps(m, r2v + a0));
        b = _mm512_min_epi32(_mm512_max_epi32(b, lo), hi);
        const __m512i i = _mm512_sub_epi32(_mm512_srli_epi32(b, 23), base);
        const __m512 u = _mm512_sub_ps(_mm512_mul_ps(_mm512_cvtepi32_ps(_mm512_and_si512(b, mant)), scale), one);
        const __m512 s = _mm512_mul_ps(_mm512_maskz_loadu_ps(m, dA + a0), _mm512_maskz_loadu_ps(m, inv + a0));
        for (int c = 0; c < 3; c++) {
            const sss_rdtab *t = &tab[c];
            __m512 p = _mm512_permutex2var_ps(_mm512_load_ps(t->c[SSS_RDTAB_DEG]), i,
                                              _mm512_load_ps(t->c[SSS_RDTAB_DEG] + 16));
            for (int j = SSS_RDTAB_DEG - 1; j >= 0; j--)
                p = _mm512_fmadd_ps(p, u, _mm512_permutex2var_ps(_mm512_load_ps(t->c[j]), i, _mm512_load_ps(t->c[j] + 16)));
            _mm512_mask_storeu_ps(w + c * ldc + a0, m, _mm512_mul_ps(p, s));
        }
    }
}
#define SSS_HAVE_RD512 1
#endif

SSS_GATHER_CLONES
static void rd_rows3_any(const sss_rdtab *tab, const float *restrict r2v, const float *restrict dA,
                         const float *restrict inv, uint32_t S, float *restrict w, uint64_t ldc)
{
    float *restrict w0 = w, *restrict w1 = w + ldc, *restrict w2 = w + 2 * ldc;
    for (uint32_t a = 0; a < S; a++) {
        const float rr = r2v[a], s = dA[a] * inv[a];
        w0[a] = sss_rdtab_at(&tab[0], rr) * s;
        w1[a] = sss_rdtab_at(&tab[1], rr) * s;
        w2[a] = sss_rdtab_at(&tab[2], rr) * s;
    }
}

int sss_gather_rd_rows_isa(int isa, const sss_rdtab *tab, uint32_t C, const float *r2v, const float *dA,
                           const float *inv, uint32_t S, float *w, uint64_t ldc)
{
    if (C == 3 && isa == SSS_GEMM_AVX512) {
#ifdef SSS_HAVE_RD512
        if (tab[0].e0 == tab[1].e0 && tab[1].e0 == tab[2].e0 && __builtin_cpu_supports("avx512f")) {
            rd_rows3_512(tab, r2v, dA, inv, S, w, ldc);
            return 1;
        }
#endif
        return 0;
    }
    if (isa != SSS_GEMM_PORTABLE) return 0;
    if (C == 3)
        rd_rows3_any(tab, r2v, dA, inv, S, w, ldc);
    else
        for (uint32_t c = 0; c < C; c++) rd_row(&tab[c], r2v, dA, inv, S, w + c * ldc);
    return 1;
}

/* The rows by the fastest path: the AVX-512 kernel where it applies, else
 * the compiler's clones (also vector code, chosen by the CPU at load). */
static void rd_rows(const sss_rdtab *tab, uint32_t C, const float *r2v, const float *dA, const float *inv, uint32_t S,
                    float *w, uint64_t ldc)
{
    if (!sss_gather_rd_rows_isa(SSS_GEMM_AVX512, tab, C, r2v, dA, inv, S, w, ldc))
        sss_gather_rd_rows_isa(SSS_GEMM_PORTABLE, tab, C, r2v, dA, inv, S, w, ldc);
}

/* Squared distances in mm from x_o to the S sources at (mesh units, as
 * double) sx, sy, sz, with the arithmetic of nbhd.c in the same order, so
 * that membership d² ≤ R² is decided bit for bit as there; inv gets the
 * membership as 0/1, r2f the distance in float, and flag marks the pairs
 * that need nbhd.c's special terms (same position, or inside the source's
 * own area disk: d² < 1.01 ΔA/π). */
SSS_GATHER_CLONES
static void near_d2(const double *restrict sx, const double *restrict sy, const double *restrict sz,
                    const float *restrict dA, uint32_t S, double ox, double oy, double oz, double s, double r2,
                    float *restrict r2f, float *restrict inv, unsigned char *restrict flag)
{
    for (uint32_t a = 0; a < S; a++) {
        const double dx = (sx[a] - ox) * s, dy = (sy[a] - oy) * s, dz = (sz[a] - oz) * s;
        double d2 = 0;
        d2 += dx * dx;
        d2 += dy * dy;
        d2 += dz * dz;
        r2f[a] = (float)d2;
        const int in = d2 <= r2;
        inv[a] = (float)in;
        flag[a] = (unsigned char)(in & ((float)d2 < dA[a] * (float)(1.01 / SSS_PI) + 1e-30f));
    }
}

/* Weights of receiver o against the near sources of the block (arrays of
 * the work space) into W[c * ldc + a]: the tabulated profile for ordinary pairs,
 * then the self / coincident / near-disk pairs redone in double exactly as
 * nbhd.c does them. */
static void near_weights(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, const sss_rdtab *tab,
                         uint32_t C, double radius_mm, uint32_t o, const uint32_t *src, const double *sxyz,
                         const float *dA, uint32_t S, float *r2f, float *inv, unsigned char *flag, float *W,
                         uint64_t ldc)
{
    const double s = t->s, r2 = radius_mm * radius_mm, s2 = s * s;
    const float *po = mesh->pos + 3 * (size_t)o;
    near_d2(sxyz, sxyz + S, sxyz + 2 * (size_t)S, dA, S, po[0], po[1], po[2], s, r2, r2f, inv, flag);
    rd_rows(tab, C, r2f, dA, inv, S, W, ldc);
    for (uint32_t a = 0; a < S; a++) {
        /* flagged pairs are a handful per receiver: skip the others
         * eight flags at a time (flag has room for S rounded up to 8) */
        if ((a & 7) == 0) {
            uint64_t f8;
            memcpy(&f8, flag + a, sizeof f8);
            if (!f8) {
                a += 7;
                continue;
            }
        }
        if (!flag[a]) continue;
        const uint32_t i = src[a];
        const float *pi = mesh->pos + 3 * (size_t)i;
        double d2 = 0;
        for (int c = 0; c < 3; c++) {
            const double dx = ((double)pi[c] - po[c]) * s;
            d2 += dx * dx;
        }
        const double dAi = mesh->area[i] * s2;
        if (i == o || d2 == 0.0) {
            /* self term: R_d over a disk of the coincident group's area,
             * this vertex's share of it (docs/physics.md §2 (a), robustness B4) */
            const double ga = t->group_area[o];
            const double share = ga > 0.0 ? mesh->area[i] / ga : 0.0;
            for (uint32_t c = 0; c < C; c++) {
                const double gd = ga > 0.0 ? sss_rd_disk(&dip[c], sqrt(ga * s * s / SSS_PI)) / SSS_PI : 0.0;
                W[c * ldc + a] = (float)(gd * share);
            }
            continue;
        }
        const double r = sqrt(d2), rho = sqrt(dAi / SSS_PI);
        if (r < NEAR_DISKS * rho)
            for (uint32_t c = 0; c < C; c++) W[c * ldc + a] = (float)(sss_rd_disk_offset(&dip[c], r, rho) / SSS_PI);
    }
}

/* Cost per element, in sgemm flops, of the parts of a block that are not
 * the product: a weight (receiver × row × channel), a row element of Ψ
 * copied and packed (row × column), a value of q written (receiver ×
 * channel × direction). Fitted to per-block CPU times of the 100K dragon
 * (200 directions) and of `sss-genmesh pair 6` (100 directions): 212 / 197,
 * 81 / 70, 752 / 551 (docs/benchmarks.md, "Progress"), with OpenBLAS and the
 * R_d formula; with gather_gemm.c and the polynomials a weight costs about
 * half as much (not re-fitted: only the progress bar's weighting of sparse
 * blocks shifts, and cli_progress still holds its ETA bound). */
#define WORK_WEIGHT 200.0
#define WORK_ROWCOPY 75.0
#define WORK_WRITE 650.0

uint64_t sss_gather_block_work(const sss_gather_tree *t, uint32_t b, uint32_t rows, uint32_t C, uint32_t Dc)
{
    const sss_gnode *n = &t->node[t->block[b]];
    const double M = (double)C * (n->hi - n->lo);
    return (uint64_t)(2.0 * M * rows * Dc + WORK_WEIGHT * M * rows + WORK_ROWCOPY * rows * Dc + WORK_WRITE * M * Dc) + 1;
}

sss_result sss_gather_block_rows(const sss_gather_tree *t, double radius_mm, uint32_t b0, uint32_t b1, uint32_t *rows,
                                 sss_error *err)
{
    if (b1 > t->nblocks || b0 > b1) return sss_fail(err, SSS_ERR_ARG, "gather: invalid block range");
    int failed = 0;
#pragma omp parallel
    {
        sss_glist l;
        memset(&l, 0, sizeof l);
#pragma omp for schedule(dynamic, 16)
        for (int64_t b = b0; b < (int64_t)b1; b++) {
            if (failed) continue;
            if (!sss_gather_lists(t, t->block[b], radius_mm, &l)) {
#pragma omp atomic write
                failed = 1;
                continue;
            }
            rows[b - b0] = l.near_sources + SSS_GATHER_MOMENTS * l.nfar;
        }
        free(l.near);
        free(l.far);
    }
    if (failed) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory for the interaction lists");
    return SSS_OK;
}

uint64_t sss_gather_workspace_rows_bytes(uint32_t max_rows, uint32_t D, uint32_t C, const sss_gather_params *pin,
                                         int threads)
{
    sss_gather_params p = pin ? *pin : (sss_gather_params){0};
    const uint64_t B = p.block_size ? p.block_size : 128, S = max_rows;
    /* W, Q, the product's packed panel, and per row: a row pointer,
     * source index, 3 floats, 3 doubles, a flag; grow() leaves up to half
     * again as much */
    const uint64_t per =
        (C * B * S * 4 + C * B * D * 4 + sss_gather_gemm_scratch(D) * 4 + S * (8 + 4 + 12 + 24 + 1)) * 3 / 2 +
        64 * 1024;
    return per * (uint64_t)(threads > 0 ? threads : 1);
}

uint64_t sss_gather_workspace_bytes(uint32_t nv, uint32_t D, uint32_t C, const sss_gather_params *pin, int threads)
{
    /* rows per block: measured below 4000 on the dragons at θ = 0.5; allow 16000 */
    const uint64_t S = nv < 16000 ? nv + 10 * 64 : 16000;
    return sss_gather_workspace_rows_bytes((uint32_t)S, D, C, pin, threads);
}

sss_result sss_gather_run(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, uint32_t C,
                          double radius_mm, uint32_t b0, uint32_t b1, float *out, int full, sss_gather_stats *st,
                          sss_error *err)
{
    return sss_gather_run_chunk(t, mesh, dip, C, radius_mm, b0, b1, 0, t->D, out, full, st, err);
}

sss_result sss_gather_run_chunk(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, uint32_t C,
                                double radius_mm, uint32_t b0, uint32_t b1, uint32_t j0, uint32_t n_total, float *out,
                                int full, sss_gather_stats *st, sss_error *err)
{
    if (C < 1 || C > SSS_MAX_CHANNELS || b1 > t->nblocks || b0 > b1 || mesh->nv != t->nv || !t->Gm || t->D == 0 ||
        (uint64_t)j0 + t->D > n_total)
        return sss_fail(err, SSS_ERR_ARG, "gather: invalid arguments");
    sss_gather_stats s0;
    memset(&s0, 0, sizeof s0);
    s0.nodes = t->nnodes;
    s0.leaves = t->nleaves;
    s0.blocks = b1 - b0;
    const uint32_t D = t->D, nv = t->nv;
    sss_gkernel k[SSS_MAX_CHANNELS];
    sss_rdtab tab[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) {
        sss_gkernel_init(&k[c], &dip[c]);
        sss_rdtab_init(&tab[c], &dip[c], radius_mm * radius_mm);
    }
    /* Offsets of each block's receivers in the output (block order). */
    uint64_t *off = malloc(((size_t)(b1 - b0) + 1) * sizeof *off);
    if (!off) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory");
    off[0] = 0;
    for (uint32_t b = b0; b < b1; b++) {
        const sss_gnode *n = &t->node[t->block[b]];
        off[b - b0 + 1] = off[b - b0] + (n->hi - n->lo);
    }
    /* Groups of consecutive blocks, each run by one thread in Morton
     * order: with a field, of at most SSS_GATHER_FIELD_GROUP receivers, so
     * that the near pairs within a group are computed once (gather_field.c);
     * without, one block each. */
    uint32_t *gstart = malloc(((size_t)(b1 - b0) + 1) * sizeof *gstart);
    if (!gstart) {
        free(off);
        return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory");
    }
    uint32_t ng = 0;
    for (uint32_t b = b0; b < b1; b++)
        if (b == b0 || !t->field || off[b - b0 + 1] - off[gstart[ng - 1] - b0] > t->field_group) gstart[ng++] = b;
    gstart[ng] = b1;
    int failed = 0;
    double rows_total = 0;
#pragma omp parallel reduction(+ : rows_total)
    {
        work wk;
        memset(&wk, 0, sizeof wk);
        double tl = 0, tw = 0, tg = 0, ts = 0, fl = 0;
        uint64_t np = 0, fp = 0;
        if (t->field && t->field_group) {
            wk.fp.kap = malloc(SSS_GATHER_FIELD_PAIRS * SSS_MAX_CHANNELS * sizeof *wk.fp.kap);
            wk.fp.stamp = calloc(SSS_GATHER_FIELD_PAIRS, sizeof *wk.fp.stamp);
            if (!wk.fp.kap || !wk.fp.stamp) {
#pragma omp atomic write
                failed = 1;
            }
        }
#pragma omp for schedule(dynamic, 1)
        for (int64_t g = 0; g < (int64_t)ng; g++) {
            if (wk.fp.kap && !failed) { /* the group's receivers; its pairs kept from now on */
                wk.fp.lo = t->node[t->block[gstart[g]]].lo;
                wk.fp.n = (uint32_t)(off[gstart[g + 1] - b0] - off[gstart[g] - b0]);
                if (wk.fp.n > SSS_GATHER_FIELD_GROUP) wk.fp.n = 0; /* one block larger than the table: none kept */
                wk.fp.gen++;
            }
            for (int64_t bi = (int64_t)gstart[g]; bi < (int64_t)gstart[g + 1]; bi++) {
                if (failed || sss_cancelled(t->p.cancel)) continue;
                const uint32_t bn = t->block[bi];
                const sss_gnode *blk = &t->node[bn];
                const uint32_t B = blk->hi - blk->lo;
                double t0 = sss_thread_cpu();
                if (!sss_gather_lists(t, bn, radius_mm, &wk.l)) {
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
                const uint32_t Sn = wk.l.near_sources, Sf = wk.l.nfar;
                const size_t S = (size_t)Sn + (size_t)SSS_GATHER_MOMENTS * Sf;
                if (!grow((void **)&wk.W, &wk.capW, (size_t)C * B * S + 1, sizeof(float)) ||
                    !grow((void **)&wk.rows, &wk.caprows, S + 1, sizeof(float *)) ||
                    !grow((void **)&wk.pack, &wk.cappack, sss_gather_gemm_scratch(D), sizeof(float)) ||
                    !grow((void **)&wk.Q, &wk.capQ, (size_t)C * B * D + 1, sizeof(float)) ||
                    !grow((void **)&wk.src, &wk.capsrc, (size_t)Sn + 1, sizeof(uint32_t)) ||
                    !grow((void **)&wk.msrc, &wk.capmsrc, (size_t)Sn + 1, sizeof(uint32_t)) ||
                    !grow((void **)&wk.fs, &wk.capfs, 3 * (size_t)Sn + 10 * (size_t)Sf + 1, sizeof(float)) ||
                    !grow((void **)&wk.sxyz, &wk.capxyz, 3 * ((size_t)Sn + Sf) + 1, sizeof(double)) ||
                    !grow((void **)&wk.flag, &wk.capflag, (size_t)Sn + 8, 1)) {
#pragma omp atomic write
                    failed = 1;
                    continue;
                }
                memset(wk.flag + Sn, 0, 8); /* near_weights reads the flags eight at a time */
                /* Ψ: the near sources' transfer rows (a leaf is a contiguous
                 * run of the Morton-ordered G), then the far nodes' moment rows */
                uint32_t a = 0;
                for (uint32_t e = 0; e < wk.l.nnear; e++) {
                    const sss_gnode *n = &t->node[wk.l.near[e]];
                    for (uint32_t m = n->lo; m < n->hi; m++, a++) {
                        const uint32_t i = t->perm[m];
                        wk.rows[a] = t->Gm + (size_t)m * D;
                        wk.src[a] = i;
                        wk.msrc[a] = m;
                        wk.fs[a] = (float)(mesh->area[i] * t->s * t->s);
                        for (int x = 0; x < 3; x++) wk.sxyz[(size_t)x * Sn + a] = mesh->pos[3 * (size_t)i + x];
                    }
                }
                double *const fc = wk.sxyz + 3 * (size_t)Sn; /* far centroids, x then y then z */
                sss_gather_far_centroids(t, wk.l.far, Sf, fc);
                for (uint32_t f = 0; f < Sf; f++) { /* moment-major, as sss_gather_far_weights writes W */
                    const float *mf = t->mom + (size_t)wk.l.far[f] * SSS_GATHER_MOMENTS * D;
                    for (int x = 0; x < SSS_GATHER_MOMENTS; x++) wk.rows[(size_t)Sn + (size_t)x * Sf + f] = mf + (size_t)x * D;
                }
                double t1 = sss_thread_cpu();
                /* W: row c·B + k is receiver k's weights for channel c */
                for (uint32_t kr = 0; kr < B; kr++) {
                    const uint32_t o = t->perm[blk->lo + kr];
                    float *wrow = wk.W + (size_t)kr * S;
                    near_weights(t, mesh, dip, tab, C, radius_mm, o, wk.src, wk.sxyz, wk.fs, Sn, wk.fs + Sn,
                                 wk.fs + 2 * (size_t)Sn, wk.flag, wrow, (uint64_t)B * S);
                    sss_gather_far_weights(fc, Sf, t->pmm + 3 * (size_t)o, k, C, radius_mm, wk.fs + 3 * (size_t)Sn,
                                           wrow + Sn, (uint64_t)B * S);
                    if (t->field) /* docs/heterogeneous.md §4.5 */
                        sss_gather_field_scale(t, mesh, C, o, blk->lo + kr, wk.src, wk.msrc, Sn, wk.l.far, Sf, wrow,
                                               (uint64_t)B * S, wk.fp.kap ? &wk.fp : NULL);
                }
                double t2 = sss_thread_cpu();
                sss_gather_gemm(C * B, D, (uint32_t)S, wk.W, S, wk.rows, wk.Q, D, wk.pack);
                double t3 = sss_thread_cpu();
                /* q is a sum of non-negative terms; the far field's Taylor
                 * terms and float cancellation can leave tiny negative values
                 * where it is ~0 (fully shadowed): clamp, as the file requires
                 * (not Q's components, which take either sign).
                 * The channels of one (vertex, direction) share a cache line
                 * of q: write them together, a direction at a time (q is
                 * vertex-major within a direction, so a receiver's directions
                 * are nv·C floats apart). */
                const uint64_t base = off[bi - b0];
                for (uint32_t kr = 0; kr < B; kr++) {
                    const uint32_t v = t->perm[blk->lo + kr];
                    const float *qr = wk.Q + (size_t)kr * D; /* channel c at qr + c·B·D */
                    const size_t cs = (size_t)B * D;
                    for (uint32_t j = 0; j < D; j++) {
                        float *o = full ? out + ((size_t)(j0 + j) * nv + v) * C : out + ((base + kr) * D + j) * C;
                        for (uint32_t c = 0; c < C; c++) {
                            const float x = qr[c * cs + j];
                            o[c] = x > 0.0f || t->p.signed_sources ? x : 0.0f;
                        }
                    }
                }
                double t4 = sss_thread_cpu();
                tl += t1 - t0;
                tw += t2 - t1;
                tg += t3 - t2;
                ts += t4 - t3;
                fl += 2.0 * C * B * (double)S * D;
                np += (uint64_t)B * Sn;
                fp += (uint64_t)B * Sf;
                rows_total += (double)S;
                sss_progress_tick(sss_gather_block_work(t, (uint32_t)bi, (uint32_t)S, C, D));
            }
        }
#pragma omp critical
        {
            s0.t_lists += tl;
            s0.t_weights += tw;
            s0.t_sgemm += tg;
            s0.t_scatter += ts;
            s0.flops += fl;
            s0.near_pairs += np;
            s0.field_kept += wk.fp.kept;
            s0.far_pairs += fp;
        }
        free(wk.W);
        free(wk.rows);
        free(wk.pack);
        free(wk.Q);
        free(wk.src);
        free(wk.msrc);
        free(wk.fp.kap);
        free(wk.fp.stamp);
        free(wk.fs);
        free(wk.sxyz);
        free(wk.flag);
        free(wk.l.near);
        free(wk.l.far);
    }
    free(off);
    free(gstart);
    s0.rows_mean = b1 > b0 ? rows_total / (b1 - b0) : 0;
    if (st) *st = s0;
    if (failed) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory for a block's matrices");
    if (sss_cancelled(t->p.cancel)) return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during integrals");
    return SSS_OK;
}
