/* gather_internal.h: the hierarchy shared by gather_tree.c (build, moments,
 * interaction lists, far-field weights) and gather_blocks.c (dense-block
 * weights, the dense block product). Not a public header. */
#ifndef SSS_GATHER_INTERNAL_H
#define SSS_GATHER_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include "sss/gather.h"

/* One octree node: a contiguous range of the Morton order. */
typedef struct sss_gnode {
    double c[3];     /* area-weighted centroid of its sources, mm */
    double r;        /* largest distance of a source from c, mm (bounding sphere) */
    double rho_max;  /* largest area-disk radius sqrt(ΔA/π) of a source, mm */
    uint32_t lo, hi; /* sources perm[lo .. hi) */
    uint32_t child;  /* first child (children are consecutive); 0 for a leaf */
    uint32_t nchild;
    uint32_t depth;
} sss_gnode;

struct sss_gather_tree {
    uint32_t nv;
    uint32_t D;            /* directions loaded in Gm and mom (a chunk of the bake's, bake_tree.c) */
    uint32_t cap_dirs;     /* directions Gm and mom have room for */
    double s;              /* mm per mesh unit */
    sss_gather_params p;
    uint32_t *perm;        /* Morton position → vertex */
    double *pmm;           /* vertex positions in mm, 3 per vertex */
    double *group_area;    /* per vertex: Σ area (mesh units²) of the vertices at its exact position, in index order */
    sss_gnode *node;
    uint32_t nnodes, nleaves, maxdepth;
    float *mom;            /* SSS_GATHER_MOMENTS × D floats per node (mm² flux moments about c) */
    uint32_t *block;       /* node index of each receiver block, Morton order */
    uint32_t nblocks;
    float *Gm;             /* nv × D transfer table in Morton order (row m is vertex perm[m]) */
    const sss_field_kernel *field; /* κ of a heterogeneous object, or NULL (sss_gather_tree_set_field) */
    sss_field_point *fpt;  /* per node: its centroid's f, σtr and dipoles (gather_field.c) */
    uint32_t field_group;  /* most receivers per group whose near κ are kept (≤ SSS_GATHER_FIELD_GROUP; 0: none) */
};

/* A thread's near pairs' κ within a group of consecutive blocks
 * (gather_field.c, docs/heterogeneous.md §4.5): the pair of Morton
 * offsets x > y from the group's first receiver at entry x(x − 1)/2 + y,
 * SSS_MAX_CHANNELS doubles, valid where stamp holds gen. */
typedef struct sss_gather_fpairs {
    double *kap;
    uint32_t *stamp;
    uint32_t lo, n; /* the group's receivers: Morton positions [lo, lo + n) */
    uint32_t gen;
    uint64_t kept; /* κ read from the table */
} sss_gather_fpairs;

/* Receivers per group of blocks whose near pairs' κ are kept (at most),
 * and the entries of a thread's table: one per pair of them. */
#define SSS_GATHER_FIELD_GROUP 1024
#define SSS_GATHER_FIELD_PAIRS ((size_t)SSS_GATHER_FIELD_GROUP * (SSS_GATHER_FIELD_GROUP - 1) / 2)

/* Scales receiver o's weights in W (channel c at W + c·ldc: Sn near
 * columns for the sources src at Morton positions msrc, then
 * SSS_GATHER_MOMENTS × nfar far columns, moment-major) by the field's κ
 * (gather_field.c); mo is o's Morton position, fp the thread's pairs of
 * the group being run (or NULL). */
void sss_gather_field_scale(const sss_gather_tree *t, const sss_mesh *mesh, uint32_t C, uint32_t o, uint32_t mo,
                            const uint32_t *src, const uint32_t *msrc, uint32_t Sn, const uint32_t *far, uint32_t nfar,
                            float *W, uint64_t ldc, sss_gather_fpairs *fp);

/* Interaction list of one receiver block. */
typedef struct sss_glist {
    uint32_t *near;  /* leaf nodes whose sources are summed one by one */
    uint32_t nnear, cap_near;
    uint32_t *far;   /* nodes taken through their moments */
    uint32_t nfar, cap_far;
    uint32_t near_sources; /* Σ sources over near leaves */
} sss_glist;

/* Fills l for block node b: every node whose sources may lie within
 * radius_mm of a receiver of b is either far (θ criterion) or a near leaf.
 * Returns 0 on allocation failure. */
int sss_gather_lists(const sss_gather_tree *t, uint32_t b, double radius_mm, sss_glist *l);

/* The block product Q (M × N, row stride ldq) = W (M × K, row stride
 * ldw) · Ψ, Ψ's row k being the N floats at rows[k] (gather_gemm.c). Every
 * element is the chain acc ← fmaf(W[m][k], Ψ[k][n], acc) over k in order
 * from 0, so every path gives the same bits. scratch holds
 * sss_gather_gemm_scratch(N) floats. sss_gather_gemm takes the fastest
 * path this CPU has; sss_gather_gemm_isa forces one (for tests and
 * benchmarks) and returns 0, leaving Q alone, where the CPU lacks it. */
enum { SSS_GEMM_PORTABLE = 0, SSS_GEMM_AVX2 = 1, SSS_GEMM_AVX512 = 2 };
size_t sss_gather_gemm_scratch(uint32_t N);
void sss_gather_gemm(uint32_t M, uint32_t N, uint32_t K, const float *W, uint64_t ldw, const float *const *rows,
                     float *Q, uint64_t ldq, float *scratch);
int sss_gather_gemm_isa(int isa, uint32_t M, uint32_t N, uint32_t K, const float *W, uint64_t ldw,
                        const float *const *rows, float *Q, uint64_t ldq, float *scratch);
int sss_gather_gemm_best(void);

/* Per-channel constants of the float profile kernels. */
typedef struct sss_gkernel {
    float sigma, z_r, z_v, zr2, zv2, coef; /* coef = α′/(4π) · 1/π */
} sss_gkernel;
void sss_gkernel_init(sss_gkernel *k, const sss_dipole *d);

/* (1/π) R_d as piecewise polynomials in x = r² (gather_rdtab.c): octave
 * e0 + i of x holds Σ_j c[j][i] u^j, u = 2t − 1, x = 2^(e0+i) (1 + t). */
#define SSS_RDTAB_N 32
#define SSS_RDTAB_DEG 10
typedef struct sss_rdtab {
    int e0; /* the first octave: xmax's octave is the last */
    _Alignas(64) float c[SSS_RDTAB_DEG + 1][SSS_RDTAB_N];
} sss_rdtab;
void sss_rdtab_init(sss_rdtab *t, const sss_dipole *d, double xmax);
float sss_rdtab_eval(const sss_rdtab *t, float x);

/* (1/π) R_d(r) ΔA · in for S sources (squared distances r2v in mm², areas
 * dA in mm², inv 0 or 1 for beyond / within the cutoff), channel c into
 * w[c · ldc + a] (gather_blocks.c). isa SSS_GEMM_AVX512: the permutation
 * kernel for three channels; SSS_GEMM_PORTABLE: the loops over
 * sss_rdtab_at (vectorised by the compiler's clones). Both give the same
 * bits; returns 0, writing nothing, for a path that does not apply. */
int sss_gather_rd_rows_isa(int isa, const sss_rdtab *tab, uint32_t C, const float *r2v, const float *dA,
                           const float *inv, uint32_t S, float *w, uint64_t ldc);

/* The profile at x ≥ 0; inline so that the weight loops vectorise it.
 * Integer and fused operations only, so every vector width gives the
 * same bits (an x below the first octave is taken at its start, above the
 * last one on the last polynomial: such sources lie beyond the cutoff). */
static inline float sss_rdtab_at(const sss_rdtab *tab, float x)
{
    const int32_t lo = (127 + tab->e0) << 23, hi = (127 + tab->e0 + SSS_RDTAB_N) << 23; /* 2^e0, 2^(e0+N) */
    int32_t b;
    memcpy(&b, &x, sizeof b);
    b = b > lo ? b : lo;
    b = b < hi - 1 ? b : hi - 1;
    const int32_t i = (b >> 23) - (127 + tab->e0);
    const float u = (float)(b & 0x7fffff) * 0x1p-22f - 1.0f;
    float p = tab->c[SSS_RDTAB_DEG][i];
    for (int j = SSS_RDTAB_DEG - 1; j >= 0; j--) p = fmaf(p, u, tab->c[j][i]);
    return p;
}

/* Far-field weights of one receiver at x_o (mm) against nfar far nodes
 * whose centroids are c (x of every node, then y, then z:
 * sss_gather_far_centroids): for channel c, moment m of node f goes to
 * W[c * ldc + m * nfar + f] (Ψ's far rows in the same order: moment-major).
 * Zero where the centroid is beyond radius_mm. scratch: 9 · nfar floats. */
void sss_gather_far_centroids(const sss_gather_tree *t, const uint32_t *far, uint32_t nfar, double *c);
void sss_gather_far_weights(const double *c, uint32_t nfar, const double x_o[3], const sss_gkernel *k,
                            uint32_t channels, double radius_mm, float *scratch, float *W, uint64_t ldc);

/* e^x for x ≤ 0 in float, vectorisable (no libm call, no float
 * compare-select, which gcc does not vectorise here): Cody–Waite range
 * reduction and a degree-6 polynomial, relative error < 2e-7; 0 below
 * e^-87. The reduction and the polynomial are written as fmaf: fused
 * multiply-adds, correctly rounded by the C standard, so every vector
 * width gives the same bits (the AVX2 and AVX-512 clones use the
 * instruction; a machine without it gets the same values from libm, only
 * slower). Measured: a quarter less time per weight than separate
 * multiplies and adds (docs/benchmarks.md, "dense blocks"). */
static inline float sss_gexpf(float x)
{
    int32_t ki = (int32_t)(x * 1.44269504f - 0.5f); /* ≈ round(x / ln 2) for x ≤ 0 */
    const float keep = (float)(ki > -126);
    ki = ki < -126 ? -126 : ki;
    const float k = (float)ki;
    float f = fmaf(-k, 0.693145752f, x);
    f = fmaf(-k, 1.42860677e-6f, f);
    float p = 1.0f / 720.0f;
    p = fmaf(p, f, 1.0f / 120.0f);
    p = fmaf(p, f, 1.0f / 24.0f);
    p = fmaf(p, f, 1.0f / 6.0f);
    p = fmaf(p, f, 0.5f);
    p = fmaf(p, f, 1.0f);
    p = fmaf(p, f, 1.0f);
    int32_t bits = (ki + 127) << 23;
    float sc;
    memcpy(&sc, &bits, sizeof sc);
    return p * sc * keep;
}

/* Vector-width clones of the weight kernels (AVX-512 on the machines the
 * benchmarks ran on); x86-64-v3 is AVX2 with FMA (plain "avx2" would leave
 * sss_gexpf's fmaf to libm); the default clone is plain SSE2. */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SSS_GATHER_CLONES __attribute__((target_clones("avx512f", "arch=x86-64-v3", "default")))
#else
#define SSS_GATHER_CLONES
#endif

#endif
