/* sgemm_columns: does the gather's rule for chunked products
 * (sss_gather_call_width, gather_near.c) give every column the bits of the
 * whole product? A bake in direction chunks (issue 8, memory) computes a
 * block's q for directions [j0, j0 + Dc) in its own sgemm call; the bytes
 * must be those of the one call over all directions. OpenBLAS does not
 * promise that in general (small products take other kernels, and a
 * one-column call sums in another order), so the rule picks the calls; this
 * program checks the rule against this machine's OpenBLAS on random
 * matrices shaped like the gather's blocks (M = channels x receivers
 * rows, K product rows, D directions), for several chunk counts.
 *   sgemm_columns [quick]     quick: the ctest subset (a second or two)
 * Exit status 1 and the failing shapes when a column differs. */
#include <cblas.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gather_internal.h"

void openblas_set_num_threads(int);

static float rnd(uint32_t *s)
{
    *s = *s * 1664525u + 1013904223u;
    return (float)((*s >> 8) & 0xffff) / 65536.0f;
}

/* Q (M x n) = A (M x K) B (K x n), as gather_near.c calls it */
static void product(int M, int n, int K, const float *A, const float *B, float *Q)
{
    cblas_sgemm(CblasRowMajor, CblasNoTrans, CblasNoTrans, M, n, K, 1.0f, A, K, B, n, 0.0f, Q, n);
}

int main(int argc, char **argv)
{
    const int quick = argc > 1 && !strcmp(argv[1], "quick");
    openblas_set_num_threads(1);
    static const int Mq[] = {3, 48, 192}, Kq[] = {40, 1000, 5000}, Dq[] = {37, 200}, Cq[] = {2, 3, 7, 25};
    static const int Mf[] = {1, 3, 15, 48, 63, 96, 150, 192}, Kf[] = {2, 40, 333, 1000, 2900, 6000, 12000},
                     Df[] = {16, 37, 48, 200, 333}, Cf[] = {2, 3, 4, 5, 7, 9, 13, 25, 50};
    const int *Ms = quick ? Mq : Mf, *Ks = quick ? Kq : Kf, *Ds = quick ? Dq : Df, *Cs = quick ? Cq : Cf;
    const int nM = quick ? 3 : 8, nK = quick ? 3 : 7, nD = 2 + (quick ? 0 : 3), nC = quick ? 4 : 9;
    long calls = 0, narrow = 0, bad = 0;
    for (int di = 0; di < nD; di++)
        for (int mi = 0; mi < nM; mi++)
            for (int ki = 0; ki < nK; ki++) {
                const int M = Ms[mi], K = Ks[ki], D = Ds[di];
                uint32_t seed = (uint32_t)(M * 7919 + K * 31 + D);
                float *A = malloc(sizeof(float) * (size_t)M * K), *B = malloc(sizeof(float) * (size_t)K * D);
                float *Q = malloc(sizeof(float) * (size_t)M * D), *Qc = malloc(sizeof(float) * (size_t)M * D);
                float *Bc = malloc(sizeof(float) * (size_t)K * D);
                if (!A || !B || !Q || !Qc || !Bc) return 2;
                /* weights with zeros (beyond the cutoff), fluxes of either sign (moments) */
                for (size_t i = 0; i < (size_t)M * K; i++) A[i] = rnd(&seed) < 0.3f ? 0.0f : rnd(&seed);
                for (size_t i = 0; i < (size_t)K * D; i++) B[i] = rnd(&seed) - 0.3f;
                product(M, D, K, A, B, Q);
                for (int ci = 0; ci < nC; ci++) {
                    const int nch = Cs[ci] < D ? Cs[ci] : D;
                    for (int c = 0; c < nch; c++) {
                        const uint32_t j0 = (uint32_t)((long)D * c / nch), j1 = (uint32_t)((long)D * (c + 1) / nch);
                        uint32_t c0;
                        const uint32_t n = sss_gather_call_width((uint64_t)M, (uint64_t)K, j1 - j0, (uint32_t)D, j0, &c0);
                        memset(Bc, 0, sizeof(float) * (size_t)K * n);
                        for (int k = 0; k < K; k++)
                            memcpy(Bc + (size_t)k * n + c0, B + (size_t)k * D + j0, (j1 - j0) * sizeof(float));
                        product(M, (int)n, K, A, Bc, Qc);
                        calls++;
                        narrow += n < (uint32_t)D;
                        for (int i = 0; i < M; i++)
                            if (memcmp(Qc + (size_t)i * n + c0, Q + (size_t)i * D + j0, (j1 - j0) * sizeof(float))) {
                                if (bad < 20)
                                    printf("differs: M %d K %d D %d, chunk %d of %d (directions %u..%u, call of %u "
                                           "columns)\n", M, K, D, c, nch, j0, j1 - 1, n);
                                bad++;
                                break;
                            }
                    }
                }
                free(A);
                free(B);
                free(Q);
                free(Qc);
                free(Bc);
            }
    printf("{\"calls\":%ld,\"narrower_than_whole\":%ld,\"differing\":%ld}\n", calls, narrow, bad);
    return bad ? 1 : 0;
}
