/* sgemm_peak: OpenBLAS sgemm's rate on this machine (docs/benchmarks.md, "Bake at scale"), the
 * reference for the hierarchical gather's dense blocks. Each OpenMP thread
 * runs its own single-threaded sgemm, as the gather does.
 *   sgemm_peak [M N K [REPEAT]]   (default 1000 1000 1000 10; the gather's
 *                                  blocks are about 60-200 x 200 x 2000-4000)
 * Prints GFLOP/s per thread and in total, by the wall clock and by each
 * thread's CPU time (the gather's near_gflops counts CPU time: on a machine
 * shared with other jobs the two differ by the share of time taken away,
 * and the CPU-time rates of the two programs are what compare). */
#define _POSIX_C_SOURCE 200809L
#include <cblas.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

void openblas_set_num_threads(int);

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double cpu(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    const int M = argc > 3 ? atoi(argv[1]) : 1000, N = argc > 3 ? atoi(argv[2]) : 1000,
              K = argc > 3 ? atoi(argv[3]) : 1000, reps = argc > 4 ? atoi(argv[4]) : 10;
    openblas_set_num_threads(1);
    double total = 0, total_cpu = 0;
#pragma omp parallel reduction(+ : total, total_cpu)
    {
        float *A = malloc(sizeof(float) * (size_t)M * K), *B = malloc(sizeof(float) * (size_t)K * N),
              *C = malloc(sizeof(float) * (size_t)M * N);
        for (size_t i = 0; i < (size_t)M * K; i++) A[i] = (float)(i % 7) * 0.1f;
        for (size_t i = 0; i < (size_t)K * N; i++) B[i] = (float)(i % 5) * 0.1f;
        cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, M, N, K, 1.f, A, K, B, N, 0.f, C, N); /* warm-up */
        double t = now(), c = cpu();
        for (int r = 0; r < reps; r++)
            cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, M, N, K, 1.f, A, K, B, N, 0.f, C, N);
        t = now() - t;
        c = cpu() - c;
        total += 2.0 * M * N * (double)K * reps / t * 1e-9;
        total_cpu += 2.0 * M * N * (double)K * reps / c * 1e-9;
        free(A);
        free(B);
        free(C);
    }
    printf("{\"M\":%d,\"N\":%d,\"K\":%d,\"threads\":%d,\"gflops_total\":%.1f,\"gflops_per_thread\":%.1f,"
           "\"gflops_per_thread_cpu\":%.1f}\n", M, N, K, omp_get_max_threads(), total, total / omp_get_max_threads(),
           total_cpu / omp_get_max_threads());
    return 0;
}
