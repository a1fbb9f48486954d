/* gemm_bench: the gather's block product (gather_gemm.c) against
 * OpenBLAS's sgemm on the same block shape, one thread, side by side.
 *   gemm_bench [M N K [REPEAT]]   (default 141 200 2742 200: the 100K
 *                                  dragon's mean RGB block, docs/benchmarks.md, "Bake at scale")
 * Ψ's K rows are runs of 32 rows taken from a larger table, as a block's
 * near leaves are, so the sgemm column includes the copy of Ψ into one
 * matrix that a BLAS call needs (the old gather did the same). Prints
 * GFLOP/s by CPU time for: sgemm alone on a ready Ψ, copy + sgemm, and this
 * kernel on every path this CPU has, and whether the paths agree bit for
 * bit. */
#include <cblas.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gather/gather_internal.h"
#include "kernels/progress.h"
#include "sss/random.h"

void openblas_set_num_threads(int);

int main(int argc, char **argv)
{
    const long lM = argc > 3 ? strtol(argv[1], NULL, 10) : 141, lN = argc > 3 ? strtol(argv[2], NULL, 10) : 200,
               lK = argc > 3 ? strtol(argv[3], NULL, 10) : 2742, lr = argc > 4 ? strtol(argv[4], NULL, 10) : 200;
    if (lM < 1 || lN < 1 || lK < 1 || lr < 1 || lM > 100000 || lN > 100000 || lK > 1000000 || lr > 1000000) {
        fprintf(stderr, "gemm_bench: M N K (REPEAT) must be positive integers (at most 1e5, 1e5, 1e6, 1e6)\n");
        return 2;
    }
    const uint32_t M = (uint32_t)lM, N = (uint32_t)lN, K = (uint32_t)lK;
    const int reps = (int)lr;
    openblas_set_num_threads(1);
    const uint32_t table_rows = 4 * K + 64;
    float *G = malloc(sizeof(float) * (size_t)table_rows * N), *W = malloc(sizeof(float) * (size_t)M * K),
          *Psi = malloc(sizeof(float) * (size_t)K * N), *Q = malloc(sizeof(float) * (size_t)M * N),
          *Q2 = malloc(sizeof(float) * (size_t)M * N), *Qref = malloc(sizeof(float) * (size_t)M * N);
    const float **rows = malloc(sizeof *rows * K);
    float *scratch = malloc(sizeof(float) * sss_gather_gemm_scratch(N));
    if (!G || !W || !Psi || !Q || !Q2 || !Qref || !rows || !scratch) return 1;
    uint64_t x = 88172645463325252ull;
    for (size_t i = 0; i < (size_t)table_rows * N; i++) G[i] = (float)sss_rng_unit(&x);
    for (size_t i = 0; i < (size_t)M * K; i++) W[i] = (float)sss_rng_unit(&x);
    /* runs of 32 rows from every other 32-row stretch of the table */
    for (uint32_t k = 0; k < K; k++) rows[k] = G + (size_t)((k / 32) * 64 + k % 32) * N;
    const double flops = 2.0 * M * N * (double)K * reps;
    double t;

    for (uint32_t k = 0; k < K; k++) memcpy(Psi + (size_t)k * N, rows[k], N * sizeof(float));
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, (int)M, (int)N, (int)K, 1.f, W, (int)K, Psi, (int)N, 0.f, Q,
                (int)N);
    t = sss_thread_cpu();
    for (int r = 0; r < reps; r++)
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, (int)M, (int)N, (int)K, 1.f, W, (int)K, Psi, (int)N,
                    0.f, Q, (int)N);
    const double g_sgemm = flops / (sss_thread_cpu() - t) * 1e-9;
    t = sss_thread_cpu();
    for (int r = 0; r < reps; r++) {
        for (uint32_t k = 0; k < K; k++) memcpy(Psi + (size_t)k * N, rows[k], N * sizeof(float));
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, (int)M, (int)N, (int)K, 1.f, W, (int)K, Psi, (int)N,
                    0.f, Q, (int)N);
    }
    const double g_copy = flops / (sss_thread_cpu() - t) * 1e-9;
    printf("{\"M\":%u,\"N\":%u,\"K\":%u,\"sgemm_gflops\":%.1f,\"copy_sgemm_gflops\":%.1f", M, N, K, g_sgemm, g_copy);

    static const char *name[] = {"portable", "avx2", "avx512"};
    int have_ref = 0, same = 1;
    double maxrel = 0;
    for (int isa = SSS_GEMM_AVX512; isa >= SSS_GEMM_PORTABLE; isa--) {
        if (!sss_gather_gemm_isa(isa, M, N, K, W, K, rows, Q2, N, scratch)) continue;
        const int r_isa = isa == SSS_GEMM_PORTABLE ? (reps + 49) / 50 : reps; /* fmaf may be a libm call */
        t = sss_thread_cpu();
        for (int r = 0; r < r_isa; r++) sss_gather_gemm_isa(isa, M, N, K, W, K, rows, Q2, N, scratch);
        printf(",\"%s_gflops\":%.1f", name[isa], flops / reps * r_isa / (sss_thread_cpu() - t) * 1e-9);
        if (!have_ref) {
            memcpy(Qref, Q2, sizeof(float) * M * N); /* keep the first path's result */
            have_ref = 1;
        } else if (memcmp(Qref, Q2, sizeof(float) * M * N))
            same = 0;
        for (size_t i = 0; i < (size_t)M * N; i++) {
            const double d = Q2[i] - Q[i], rel = d < 0 ? -d / Q[i] : d / Q[i];
            if (rel > maxrel) maxrel = rel;
        }
    }
    printf(",\"paths_identical\":%s,\"max_rel_diff_to_sgemm\":%.2e}\n", same ? "true" : "false", maxrel);
    free(G);
    free(W);
    free(Psi);
    free(Q);
    free(Q2);
    free(Qref);
    free(rows);
    free(scratch);
    return same ? 0 : 1;
}
