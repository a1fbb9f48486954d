/* gather_near.c: the near field of the hierarchical gather and the dense
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
 * Ψ stacking the transfer rows G[i, ·] of the near sources and the moment
 * rows of the far nodes. sgemm (OpenBLAS, single-threaded inside each
 * OpenMP thread) runs it near the machine's peak, where the direct sum's
 * sparse row loop is bound by memory (docs/benchmarks.md). One thread
 * computes a whole block in a fixed order, so the bytes do not depend on
 * the thread count.
 */
#include <cblas.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "gather_internal.h"
#include "progress.h"
#include "sss/bake.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* OpenBLAS's own threads would fight OpenMP's and make the sum's order
 * depend on the thread count. */
void openblas_set_num_threads(int);

/* The same near-disk rule as nbhd.c: a neighbour closer than its own
 * area-disk radius is integrated over the disk. */
#define NEAR_DISKS 1.0

typedef struct work {
    float *W, *Psi, *Q;
    size_t capW, capPsi, capQ;
    uint32_t *src;
    size_t capsrc;
    float *fs; /* per source: dA, r², inside; then the far scratch */
    size_t capfs;
    double *sxyz; /* source positions (mesh units), x then y then z */
    size_t capxyz;
    unsigned char *flag;
    size_t capflag;
    sss_glist l;
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

/* (1/π) R_d(r) ΔA for S sources at squared distances r2v, zero where
 * inv[a] = 0 (beyond the cutoff): the float form of sss_rd (physics sheet
 * §2), R_d = α′/(4π) Σ_z z (1 + σd) e^{−σd} / d³. */
SSS_GATHER_CLONES
static void rd_row(const sss_gkernel *kp, const float *restrict r2v, const float *restrict dA,
                   const float *restrict inv, uint32_t S, float *restrict w)
{
    const float sigma = kp->sigma, coef = kp->coef, z_r = kp->z_r, z_v = kp->z_v, zr2 = kp->zr2, zv2 = kp->zv2;
    for (uint32_t a = 0; a < S; a++) {
        const float rr = r2v[a];
        const float d1 = sqrtf(rr + zr2), d2 = sqrtf(rr + zv2);
        const float i1 = 1.0f / d1, i2 = 1.0f / d2;
        const float s1 = sigma * d1, s2 = sigma * d2;
        const float t1 = z_r * (1.0f + s1) * sss_gexpf(-s1) * i1 * i1 * i1;
        const float t2 = z_v * (1.0f + s2) * sss_gexpf(-s2) * i2 * i2 * i2;
        w[a] = coef * (t1 + t2) * dA[a] * inv[a];
    }
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
        flag[a] = (unsigned char)(in & ((float)d2 < dA[a] * (float)(1.01 / M_PI) + 1e-30f));
    }
}

/* Weights of receiver o against the near sources of the block (arrays of
 * the work space) into W[c * ldc + a]: the float kernel for ordinary pairs,
 * then the self / coincident / near-disk pairs redone in double exactly as
 * nbhd.c does them. */
static void near_weights(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, const sss_gkernel *k,
                         uint32_t C, double radius_mm, uint32_t o, const uint32_t *src, const double *sxyz,
                         const float *dA, uint32_t S, float *r2f, float *inv, unsigned char *flag, float *W,
                         uint64_t ldc)
{
    const double s = t->s, r2 = radius_mm * radius_mm, s2 = s * s;
    const float *po = mesh->pos + 3 * (size_t)o;
    near_d2(sxyz, sxyz + S, sxyz + 2 * (size_t)S, dA, S, po[0], po[1], po[2], s, r2, r2f, inv, flag);
    for (uint32_t c = 0; c < C; c++) rd_row(&k[c], r2f, dA, inv, S, W + c * ldc);
    for (uint32_t a = 0; a < S; a++) {
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
             * this vertex's share of it (physics sheet §2 (a), robustness B4) */
            const double ga = t->group_area[o];
            const double share = ga > 0.0 ? mesh->area[i] / ga : 0.0;
            for (uint32_t c = 0; c < C; c++) {
                const double gd = ga > 0.0 ? sss_rd_disk(&dip[c], sqrt(ga * s * s / M_PI)) / M_PI : 0.0;
                W[c * ldc + a] = (float)(gd * share);
            }
            continue;
        }
        const double r = sqrt(d2), rho = sqrt(dAi / M_PI);
        if (r < NEAR_DISKS * rho)
            for (uint32_t c = 0; c < C; c++) W[c * ldc + a] = (float)(sss_rd_disk_offset(&dip[c], r, rho) / M_PI);
    }
}

uint64_t sss_gather_workspace_bytes(uint32_t nv, uint32_t D, uint32_t C, const sss_gather_params *pin, int threads)
{
    sss_gather_params p = pin ? *pin : (sss_gather_params){0};
    const uint32_t B = p.block_size ? p.block_size : 64;
    /* rows per block: measured below 4000 on the dragons at θ = 0.5; allow 16000 */
    const uint64_t S = nv < 16000 ? nv + 10 * 64 : 16000;
    const uint64_t per = S * D * 4 + (uint64_t)C * B * S * 4 + (uint64_t)C * B * D * 4 + S * 12 + 64 * 1024;
    return per * (uint64_t)(threads > 0 ? threads : 1);
}

sss_result sss_gather_run(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, uint32_t C,
                          double radius_mm, uint32_t b0, uint32_t b1, float *out, int full, sss_gather_stats *st,
                          sss_error *err)
{
    if (C < 1 || C > SSS_MAX_CHANNELS || b1 > t->nblocks || b0 > b1 || mesh->nv != t->nv)
        return sss_fail(err, SSS_ERR_ARG, "gather: invalid arguments");
    sss_gather_stats s0;
    memset(&s0, 0, sizeof s0);
    s0.nodes = t->nnodes;
    s0.leaves = t->nleaves;
    s0.blocks = b1 - b0;
    const uint32_t D = t->D, nv = t->nv;
    sss_gkernel k[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) sss_gkernel_init(&k[c], &dip[c]);
    /* Offsets of each block's receivers in the output (block order). */
    uint64_t *off = malloc(((size_t)(b1 - b0) + 1) * sizeof *off);
    if (!off) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory");
    off[0] = 0;
    for (uint32_t b = b0; b < b1; b++) {
        const sss_gnode *n = &t->node[t->block[b]];
        off[b - b0 + 1] = off[b - b0] + (n->hi - n->lo);
    }
    openblas_set_num_threads(1);
    int failed = 0;
    double rows_total = 0;
#pragma omp parallel reduction(+ : rows_total)
    {
        work wk;
        memset(&wk, 0, sizeof wk);
        double tl = 0, tw = 0, tg = 0, ts = 0, fl = 0;
        uint64_t np = 0, fp = 0;
#pragma omp for schedule(dynamic, 1)
        for (int64_t bi = (int64_t)b0; bi < (int64_t)b1; bi++) {
            if (failed || sss_bake_interrupted) continue;
            const uint32_t bn = t->block[bi];
            const sss_gnode *blk = &t->node[bn];
            const uint32_t B = blk->hi - blk->lo;
            double t0 = sss_now();
            if (!sss_gather_lists(t, bn, radius_mm, &wk.l)) {
#pragma omp atomic write
                failed = 1;
                continue;
            }
            const uint32_t Sn = wk.l.near_sources, Sf = wk.l.nfar;
            const size_t S = (size_t)Sn + (size_t)SSS_GATHER_MOMENTS * Sf;
            if (!grow((void **)&wk.W, &wk.capW, (size_t)C * B * S + 1, sizeof(float)) ||
                !grow((void **)&wk.Psi, &wk.capPsi, S * D + 1, sizeof(float)) ||
                !grow((void **)&wk.Q, &wk.capQ, (size_t)C * B * D + 1, sizeof(float)) ||
                !grow((void **)&wk.src, &wk.capsrc, (size_t)Sn + 1, sizeof(uint32_t)) ||
                !grow((void **)&wk.fs, &wk.capfs, 3 * (size_t)Sn + 10 * (size_t)Sf + 1, sizeof(float)) ||
                !grow((void **)&wk.sxyz, &wk.capxyz, 3 * (size_t)Sn + 1, sizeof(double)) ||
                !grow((void **)&wk.flag, &wk.capflag, (size_t)Sn + 1, 1)) {
#pragma omp atomic write
                failed = 1;
                continue;
            }
            /* Ψ: near transfer rows (a leaf is a contiguous run of the
             * Morton-ordered G), then far moment rows */
            uint32_t a = 0;
            for (uint32_t e = 0; e < wk.l.nnear; e++) {
                const sss_gnode *n = &t->node[wk.l.near[e]];
                memcpy(wk.Psi + (size_t)a * D, t->Gm + (size_t)n->lo * D, (size_t)(n->hi - n->lo) * D * sizeof(float));
                for (uint32_t m = n->lo; m < n->hi; m++, a++) {
                    const uint32_t i = t->perm[m];
                    wk.src[a] = i;
                    wk.fs[a] = (float)(mesh->area[i] * t->s * t->s);
                    for (int x = 0; x < 3; x++) wk.sxyz[(size_t)x * Sn + a] = mesh->pos[3 * (size_t)i + x];
                }
            }
            for (uint32_t f = 0; f < Sf; f++)
                memcpy(wk.Psi + ((size_t)Sn + (size_t)SSS_GATHER_MOMENTS * f) * D,
                       t->mom + (size_t)wk.l.far[f] * SSS_GATHER_MOMENTS * D, (size_t)SSS_GATHER_MOMENTS * D * sizeof(float));
            double t1 = sss_now();
            /* W: row c·B + k is receiver k's weights for channel c */
            for (uint32_t kr = 0; kr < B; kr++) {
                const uint32_t o = t->perm[blk->lo + kr];
                float *wrow = wk.W + (size_t)kr * S;
                near_weights(t, mesh, dip, k, C, radius_mm, o, wk.src, wk.sxyz, wk.fs, Sn, wk.fs + Sn,
                             wk.fs + 2 * (size_t)Sn, wk.flag, wrow, (uint64_t)B * S);
                sss_gather_far_weights(t, t->pmm + 3 * (size_t)o, wk.l.far, Sf, k, C, radius_mm, wk.fs + 3 * (size_t)Sn,
                                       wrow + Sn, (uint64_t)B * S);
            }
            double t2 = sss_now();
            if (S > 0)
                cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, (int)(C * B), (int)D, (int)S, 1.0f, wk.W,
                            (int)S, wk.Psi, (int)D, 0.0f, wk.Q, (int)D);
            else
                memset(wk.Q, 0, (size_t)C * B * D * sizeof(float));
            double t3 = sss_now();
            /* q is a sum of non-negative terms; the far field's Taylor
             * terms and float cancellation can leave tiny negative values
             * where it is ~0 (fully shadowed): clamp, as the file requires */
            for (size_t e = 0; e < (size_t)C * B * D; e++) wk.Q[e] = wk.Q[e] > 0.0f ? wk.Q[e] : 0.0f;
            const uint64_t base = off[bi - b0];
            for (uint32_t kr = 0; kr < B; kr++) {
                const uint32_t v = t->perm[blk->lo + kr];
                for (uint32_t c = 0; c < C; c++) {
                    const float *qr = wk.Q + ((size_t)c * B + kr) * D;
                    if (full)
                        for (uint32_t j = 0; j < D; j++) out[((size_t)j * nv + v) * C + c] = qr[j];
                    else
                        for (uint32_t j = 0; j < D; j++) out[((base + kr) * D + j) * C + c] = qr[j];
                }
            }
            double t4 = sss_now();
            tl += t1 - t0;
            tw += t2 - t1;
            tg += t3 - t2;
            ts += t4 - t3;
            fl += 2.0 * C * B * (double)S * D;
            np += (uint64_t)B * Sn;
            fp += (uint64_t)B * Sf;
            rows_total += (double)S;
            sss_progress_tick(B);
        }
#pragma omp critical
        {
            s0.t_lists += tl;
            s0.t_weights += tw;
            s0.t_sgemm += tg;
            s0.t_scatter += ts;
            s0.flops += fl;
            s0.near_pairs += np;
            s0.far_pairs += fp;
        }
        free(wk.W);
        free(wk.Psi);
        free(wk.Q);
        free(wk.src);
        free(wk.fs);
        free(wk.sxyz);
        free(wk.flag);
        free(wk.l.near);
        free(wk.l.far);
    }
    free(off);
    s0.rows_mean = b1 > b0 ? rows_total / (b1 - b0) : 0;
    if (st) *st = s0;
    if (failed) return sss_fail(err, SSS_ERR_NOMEM, "gather: out of memory for a block's matrices");
    if (sss_bake_interrupted) return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during integrals");
    return SSS_OK;
}
