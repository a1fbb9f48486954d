/* gather_gemm.c: the dense block product of the hierarchical gather,
 *   Q (M × N) = W (M × K) · Ψ (K × N),
 * with Ψ given as K row pointers (gather_blocks.c).
 *
 * Why not sgemm (OpenBLAS): the block's W is computed here and its Ψ rows
 * already lie in memory (the Morton-ordered transfer rows of the near
 * sources, the moment rows of the far nodes), but a BLAS call needs Ψ as
 * one strided matrix and then packs both operands again into its own
 * panel layout: on the 100K dragon these copies took a quarter of the
 * product's time (a copy of every Ψ row, then OpenBLAS's itcopy / oncopy),
 * and for the short blocks of the gather (M = C·B ≈ 140 rows) they are not
 * amortised (docs/benchmarks.md, "Dense blocks: the block product"). This
 * kernel reads W in place (row-major, 8 rows broadcast at a time) and
 * copies Ψ's rows once, a panel of KC rows at a time, into one aligned
 * block that stays in the L2 cache while every register tile of the block
 * (8 × 48 accumulators with AVX-512, 4 × 24 with AVX2) streams through it.
 *
 * Every element of Q is the chain acc ← fma(W[m][k], Ψ[k][n], acc) over
 * k = 0, 1, …, K − 1 in order, from acc = 0, whatever the vector width, the
 * tile, the panel or the number of columns: the AVX-512, AVX2+FMA and
 * portable (C11 fmaf, correctly rounded) paths give the same bits
 * (tests/unit/test_gather_kernels.c), and a column's bits do not depend on
 * which other columns are computed with it, so a bake in direction chunks
 * gives the bytes of the bake in one piece without further care. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "gather/gather_internal.h"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define SSS_GEMM_X86 1
#endif

/* Rows of Ψ per panel: the packed panel (KC × N floats, 205 KB for 200
 * directions) and W's columns for it (M × KC) stay in the L2 cache while
 * every tile of the block reads them (measured on the 100K dragon: 128,
 * 256 and 512 within noise of each other; no panels at all, 40 % slower). */
#define KC 256

static uint32_t padded(uint32_t N)
{
    return (N + 15u) & ~15u;
}

size_t sss_gather_gemm_scratch(uint32_t N)
{
    return (size_t)KC * padded(N) + 16; /* + 16: room to align to 64 bytes */
}

/* Ψ's rows k0 .. k1 − 1 copied into P, rows of ld = padded(N) floats, the
 * columns past N zero: Ψ's own rows lie scattered over the transfer table
 * and straddle cache lines, and read in place the kernel's loads waited on
 * memory (40 % of its samples); copied a whole row at a time (a leaf's
 * rows are contiguous in the table), the copy streams. */
static void pack(const float *const *rows, uint32_t k0, uint32_t k1, uint32_t N, float *P)
{
    const uint32_t ld = padded(N);
    for (uint32_t k = k0; k < k1; k++, P += ld) {
        memcpy(P, rows[k], N * sizeof(float));
        for (uint32_t j = N; j < ld; j++) P[j] = 0.0f;
    }
}

/* ---- portable path: C11 fmaf, 4 × 16 tiles ---- */
static void tile_c(uint32_t mr, uint32_t nr, uint32_t kn, const float *W, uint64_t ldw, const float *P, uint32_t ldp,
                   float *Q, uint64_t ldq)
{
    float acc[4][16];
    for (uint32_t i = 0; i < mr; i++)
        for (uint32_t j = 0; j < nr; j++) acc[i][j] = Q[i * ldq + j];
    for (uint32_t k = 0; k < kn; k++) {
        const float *p = P + (size_t)k * ldp;
        for (uint32_t i = 0; i < mr; i++) {
            const float a = W[i * ldw + k];
            for (uint32_t j = 0; j < nr; j++) acc[i][j] = fmaf(a, p[j], acc[i][j]);
        }
    }
    for (uint32_t i = 0; i < mr; i++)
        for (uint32_t j = 0; j < nr; j++) Q[i * ldq + j] = acc[i][j];
}

static void panel_c(uint32_t M, uint32_t N, uint32_t kn, const float *W, uint64_t ldw, const float *P, uint32_t ldp,
                    float *Q, uint64_t ldq)
{
    for (uint32_t n0 = 0; n0 < N; n0 += 16)
        for (uint32_t m0 = 0; m0 < M; m0 += 4)
            tile_c(M - m0 < 4 ? M - m0 : 4, N - n0 < 16 ? N - n0 : 16, kn, W + m0 * ldw, ldw, P + n0, ldp,
                   Q + m0 * ldq + n0, ldq);
}

#ifdef SSS_GEMM_X86
/* ---- AVX-512: MR × NV·16 tiles, MR ≤ 8, NV ≤ 3: 24 accumulators, 3
 * loads of Ψ and 8 broadcasts of W per k, compute-bound on two FMA ports.
 * The panel is padded, so its loads need no mask; Q's last vector is masked
 * to the columns left. MR and NV are constants in each instance (the table
 * below), and the accumulators are named variables, not an array: gcc
 * keeps an array of vectors in memory and stores it back every k
 * (measured: half the rate). */
#define M512(v) ((v) == NV - 1 ? last : (__mmask16)0xffff)
#define LD512(i, v) (MR > (i) && NV > (v) ? _mm512_maskz_loadu_ps(M512(v), Q + (i) * ldq + 16 * (v)) : z)
#define ST512(i, v)                                                                                                   \
    if (MR > (i) && NV > (v)) _mm512_mask_storeu_ps(Q + (i) * ldq + 16 * (v), M512(v), c##i##v)
#define ROW512_DECL(i) __m512 c##i##0 = LD512(i, 0), c##i##1 = LD512(i, 1), c##i##2 = LD512(i, 2)
#define ROW512_FMA(i)                                                                                                 \
    if (MR > (i)) {                                                                                                   \
        const __m512 a = _mm512_set1_ps(w[(i) * ldw]);                                                                \
        c##i##0 = _mm512_fmadd_ps(a, b0, c##i##0);                                                                    \
        if (NV > 1) c##i##1 = _mm512_fmadd_ps(a, b1, c##i##1);                                                        \
        if (NV > 2) c##i##2 = _mm512_fmadd_ps(a, b2, c##i##2);                                                        \
    }
#define ROW512_ST(i)                                                                                                  \
    ST512(i, 0);                                                                                                      \
    ST512(i, 1);                                                                                                      \
    ST512(i, 2)
#define T512(R, V)                                                                                                    \
    __attribute__((target("avx512f"))) static void t512_##R##_##V(uint32_t kn, const float *W, uint64_t ldw,       \
                                                                    const float *P, uint32_t ldp, __mmask16 last,    \
                                                                    float *Q, uint64_t ldq)                          \
    {                                                                                                                 \
        enum { MR = R, NV = V };                                                                                      \
        const __m512 z = _mm512_setzero_ps();                                                                         \
        ROW512_DECL(0);                                                                                               \
        ROW512_DECL(1);                                                                                               \
        ROW512_DECL(2);                                                                                               \
        ROW512_DECL(3);                                                                                               \
        ROW512_DECL(4);                                                                                               \
        ROW512_DECL(5);                                                                                               \
        ROW512_DECL(6);                                                                                               \
        ROW512_DECL(7);                                                                                               \
        for (uint32_t k = 0; k < kn; k++) {                                                                           \
            const float *p = P + (size_t)k * ldp, *w = W + k;                                                         \
            const __m512 b0 = _mm512_load_ps(p);                                                                      \
            const __m512 b1 = NV > 1 ? _mm512_load_ps(p + 16) : z;                                                    \
            const __m512 b2 = NV > 2 ? _mm512_load_ps(p + 32) : z;                                                    \
            ROW512_FMA(0)                                                                                             \
            ROW512_FMA(1)                                                                                             \
            ROW512_FMA(2)                                                                                             \
            ROW512_FMA(3)                                                                                             \
            ROW512_FMA(4)                                                                                             \
            ROW512_FMA(5)                                                                                             \
            ROW512_FMA(6)                                                                                             \
            ROW512_FMA(7)                                                                                             \
        }                                                                                                             \
        ROW512_ST(0);                                                                                                 \
        ROW512_ST(1);                                                                                                 \
        ROW512_ST(2);                                                                                                 \
        ROW512_ST(3);                                                                                                 \
        ROW512_ST(4);                                                                                                 \
        ROW512_ST(5);                                                                                                 \
        ROW512_ST(6);                                                                                                 \
        ROW512_ST(7);                                                                                                 \
    }
#define T512_ROW(MR) T512(MR, 1) T512(MR, 2) T512(MR, 3)
T512_ROW(1)
T512_ROW(2)
T512_ROW(3)
T512_ROW(4)
T512_ROW(5)
T512_ROW(6)
T512_ROW(7)
T512_ROW(8)

typedef void (*t512_fn)(uint32_t, const float *, uint64_t, const float *, uint32_t, __mmask16, float *, uint64_t);
#define T512_ENTRY(MR) {t512_##MR##_1, t512_##MR##_2, t512_##MR##_3}
static const t512_fn t512_table[8][3] = {T512_ENTRY(1), T512_ENTRY(2), T512_ENTRY(3), T512_ENTRY(4),
                                         T512_ENTRY(5), T512_ENTRY(6), T512_ENTRY(7), T512_ENTRY(8)};

static void panel_512(uint32_t M, uint32_t N, uint32_t kn, const float *W, uint64_t ldw, const float *P, uint32_t ldp,
                      float *Q, uint64_t ldq)
{
    /* tiles of three vectors, the last ones of two where the vector count
     * is not a multiple of three (200 columns: 3, 3, 3, 2, 2 vectors rather
     * than 3, 3, 3, 3, 1, whose one-vector tile would be bound by loads) */
    const uint32_t nvec = (N + 15) / 16, n3 = nvec % 3 == 1 && nvec > 3 ? nvec / 3 - 1 : nvec / 3;
    for (uint32_t n0 = 0, t = 0; n0 < N; t++) {
        const uint32_t want = t < n3 ? 48 : 32, nr = N - n0 < want ? N - n0 : want, nv = (nr + 15) / 16,
                       tail = nr - 16 * (nv - 1);
        const __mmask16 last = (__mmask16)(tail == 16 ? 0xffffu : (1u << tail) - 1u);
        for (uint32_t m0 = 0; m0 < M; m0 += 8) {
            const uint32_t mr = M - m0 < 8 ? M - m0 : 8;
            t512_table[mr - 1][nv - 1](kn, W + m0 * ldw, ldw, P + n0, ldp, last, Q + m0 * ldq + n0, ldq);
        }
        n0 += nr;
    }
}

/* ---- AVX2 + FMA: MR × NV·8 tiles, MR ≤ 4, NV ≤ 3 (12 accumulators of
 * the 16 ymm registers) ---- */
#define M256(v) ((v) == NV - 1 ? last : all)
#define LD256(i, v) (MR > (i) && NV > (v) ? _mm256_maskload_ps(Q + (i) * ldq + 8 * (v), M256(v)) : z)
#define ST256(i, v)                                                                                                   \
    if (MR > (i) && NV > (v)) _mm256_maskstore_ps(Q + (i) * ldq + 8 * (v), M256(v), c##i##v)
#define ROW256_DECL(i) __m256 c##i##0 = LD256(i, 0), c##i##1 = LD256(i, 1), c##i##2 = LD256(i, 2)
#define ROW256_FMA(i)                                                                                                 \
    if (MR > (i)) {                                                                                                   \
        const __m256 a = _mm256_broadcast_ss(w + (i) * ldw);                                                          \
        c##i##0 = _mm256_fmadd_ps(a, b0, c##i##0);                                                                    \
        if (NV > 1) c##i##1 = _mm256_fmadd_ps(a, b1, c##i##1);                                                        \
        if (NV > 2) c##i##2 = _mm256_fmadd_ps(a, b2, c##i##2);                                                        \
    }
#define ROW256_ST(i)                                                                                                  \
    ST256(i, 0);                                                                                                      \
    ST256(i, 1);                                                                                                      \
    ST256(i, 2)
#define T256(R, V)                                                                                                    \
    __attribute__((target("avx2,fma"))) static void t256_##R##_##V(uint32_t kn, const float *W, uint64_t ldw,      \
                                                                     const float *P, uint32_t ldp, __m256i last,     \
                                                                     float *Q, uint64_t ldq)                         \
    {                                                                                                                 \
        enum { MR = R, NV = V };                                                                                      \
        const __m256i all = _mm256_set1_epi32(-1);                                                                    \
        const __m256 z = _mm256_setzero_ps();                                                                         \
        ROW256_DECL(0);                                                                                               \
        ROW256_DECL(1);                                                                                               \
        ROW256_DECL(2);                                                                                               \
        ROW256_DECL(3);                                                                                               \
        for (uint32_t k = 0; k < kn; k++) {                                                                           \
            const float *p = P + (size_t)k * ldp, *w = W + k;                                                         \
            const __m256 b0 = _mm256_loadu_ps(p);                                                                     \
            const __m256 b1 = NV > 1 ? _mm256_loadu_ps(p + 8) : z;                                                    \
            const __m256 b2 = NV > 2 ? _mm256_loadu_ps(p + 16) : z;                                                   \
            ROW256_FMA(0)                                                                                             \
            ROW256_FMA(1)                                                                                             \
            ROW256_FMA(2)                                                                                             \
            ROW256_FMA(3)                                                                                             \
        }                                                                                                             \
        ROW256_ST(0);                                                                                                 \
        ROW256_ST(1);                                                                                                 \
        ROW256_ST(2);                                                                                                 \
        ROW256_ST(3);                                                                                                 \
    }
#define T256_ROW(MR) T256(MR, 1) T256(MR, 2) T256(MR, 3)
T256_ROW(1)
T256_ROW(2)
T256_ROW(3)
T256_ROW(4)

typedef void (*t256_fn)(uint32_t, const float *, uint64_t, const float *, uint32_t, __m256i, float *, uint64_t);
#define T256_ENTRY(MR) {t256_##MR##_1, t256_##MR##_2, t256_##MR##_3}
static const t256_fn t256_table[4][3] = {T256_ENTRY(1), T256_ENTRY(2), T256_ENTRY(3), T256_ENTRY(4)};

__attribute__((target("avx2"))) static __m256i mask256(uint32_t n)
{
    const __m256i idx = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    return _mm256_cmpgt_epi32(_mm256_set1_epi32((int)n), idx);
}

__attribute__((target("avx2,fma"))) static void panel_256(uint32_t M, uint32_t N, uint32_t kn, const float *W,
                                                           uint64_t ldw, const float *P, uint32_t ldp, float *Q,
                                                           uint64_t ldq)
{
    for (uint32_t n0 = 0; n0 < N; n0 += 24) {
        const uint32_t nr = N - n0 < 24 ? N - n0 : 24, nv = (nr + 7) / 8, tail = nr - 8 * (nv - 1);
        const __m256i last = mask256(tail);
        for (uint32_t m0 = 0; m0 < M; m0 += 4) {
            const uint32_t mr = M - m0 < 4 ? M - m0 : 4;
            t256_table[mr - 1][nv - 1](kn, W + m0 * ldw, ldw, P + n0, ldp, last, Q + m0 * ldq + n0, ldq);
        }
    }
}
#endif

typedef void (*panel_fn)(uint32_t, uint32_t, uint32_t, const float *, uint64_t, const float *, uint32_t, float *,
                         uint64_t);

static int have(int isa)
{
#ifdef SSS_GEMM_X86
    __builtin_cpu_init();
    if (isa == SSS_GEMM_AVX512) return __builtin_cpu_supports("avx512f");
    if (isa == SSS_GEMM_AVX2) return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#endif
    return isa == SSS_GEMM_PORTABLE;
}

int sss_gather_gemm_best(void)
{
    return have(SSS_GEMM_AVX512) ? SSS_GEMM_AVX512 : have(SSS_GEMM_AVX2) ? SSS_GEMM_AVX2 : SSS_GEMM_PORTABLE;
}

int sss_gather_gemm_isa(int isa, uint32_t M, uint32_t N, uint32_t K, const float *W, uint64_t ldw,
                        const float *const *rows, float *Q, uint64_t ldq, float *scratch)
{
    if (!have(isa)) return 0;
    panel_fn panel = panel_c;
#ifdef SSS_GEMM_X86
    if (isa == SSS_GEMM_AVX512) panel = panel_512;
    if (isa == SSS_GEMM_AVX2) panel = panel_256;
#endif
    float *P = (float *)(((uintptr_t)scratch + 63) & ~(uintptr_t)63);
    for (uint32_t m = 0; m < M; m++) memset(Q + m * ldq, 0, (size_t)N * sizeof(float));
    for (uint32_t k0 = 0; k0 < K; k0 += KC) {
        const uint32_t k1 = K - k0 < KC ? K : k0 + KC;
        pack(rows, k0, k1, N, P);
        panel(M, N, k1 - k0, W + k0, ldw, P, padded(N), Q, ldq);
    }
    return 1;
}

void sss_gather_gemm(uint32_t M, uint32_t N, uint32_t K, const float *W, uint64_t ldw, const float *const *rows,
                     float *Q, uint64_t ldq, float *scratch)
{
    static int best = -1; /* the same answer from every thread: a benign race */
    int isa = __atomic_load_n(&best, __ATOMIC_RELAXED);
    if (isa < 0) {
        isa = sss_gather_gemm_best();
        __atomic_store_n(&best, isa, __ATOMIC_RELAXED);
    }
    sss_gather_gemm_isa(isa, M, N, K, W, ldw, rows, Q, ldq, scratch);
}
