/* sh_projection_bench: which SH projection (least squares or Voronoi
 * quadrature, sss/sh.h) reconstructs baked directional data more accurately
 * (Hao–Varshney 2004 §4.1 compresses the per-vertex integrals q(x, ω_j)
 * into n² SH coefficients).
 *   sh_projection_bench [N [ORIENTATIONS [SEED]]]     defaults 200 16 1
 *
 * Two test functions, neither band-limited:
 *   lobe:    f(ω) = max(0, n·ω)                       (cosine-weighted, F = 1)
 *   shadow:  f(ω) = max(0, n·ω) if ω·t > 0.2 else 0   (hard shadow boundary)
 * for ORIENTATIONS random (n, t) pairs. For each, f is sampled at the N
 * Fibonacci directions, projected at orders 1 … 8 by both methods, and the
 * reconstruction is compared with f at 10,000 uniformly random directions
 * (not the samples). The table gives the RMS error pooled over all
 * orientations and evaluation directions, the range over orientations of
 * the per-orientation ratio RMS(quadrature)/RMS(least squares), and, as the
 * floor no projection from samples can beat, the error of the true L2
 * projection (coefficients by an equal-weight 2^20-point Fibonacci rule;
 * for the lobe also in closed form). Since the truncation error dominates,
 * it also gives each method's distance from that optimum: the RMS of
 * (its reconstruction − the optimal reconstruction), i.e. the error the
 * discrete projection adds (aliasing of the bands ≥ n into the kept ones).
 * For reference it also prints the error of barycentric interpolation of
 * the raw N samples (what the renderer does with uncompressed data).
 * Output is Markdown on stdout; deterministic for given arguments.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/random.h"
#include "sss/dirset.h"
#include "sss/sh.h"
#include "sss/vec3.h"

#define PI 3.14159265358979323846
#define NEVAL 10000
#define NREF (1u << 20)
#define MAXO 8

static uint64_t rng_state;


typedef struct orient {
    double n[3], t[3];
} orient;

/* kind 0: lobe, 1: shadow */
static double f_eval(int kind, const orient *o, const double w[3])
{
    double c = fmax(0.0, sss_dot3(o->n, w));
    if (kind == 1 && !(sss_dot3(o->t, w) > 0.2)) return 0.0;
    return c;
}

int main(int argc, char **argv)
{
    uint32_t N = argc > 1 ? (uint32_t)strtoul(argv[1], NULL, 10) : 200;
    int K = argc > 2 ? atoi(argv[2]) : 16;
    uint64_t seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 1;
    if (N < 64 || K < 1) {
        fprintf(stderr, "sh_projection_bench: need N >= 64 and ORIENTATIONS >= 1\n");
        return 2;
    }
    rng_state = seed;
    sss_error err = {{0}};
    sss_dirset s;
    if (sss_dirset_fibonacci(&s, N, &err) != SSS_OK) {
        fprintf(stderr, "sh_projection_bench: %s\n", err.msg);
        return 1;
    }
    sss_sh_projector *proj[2][MAXO + 1];
    for (int m = 0; m < 2; m++)
        for (uint32_t o = 1; o <= MAXO; o++)
            if (sss_sh_projector_create(&s, o, (sss_sh_method)m, &proj[m][o], &err) != SSS_OK) {
                fprintf(stderr, "sh_projection_bench: %s\n", err.msg);
                return 1;
            }

    orient *ori = malloc((size_t)K * sizeof *ori);
    double *ev = malloc(3 * (size_t)NEVAL * sizeof *ev);
    double *yev = malloc((size_t)NEVAL * 64 * sizeof *yev);
    double *ref = calloc((size_t)2 * K * 64, sizeof *ref); /* L2 coefficients */
    double *fs = malloc((size_t)N * sizeof *fs);
    if (!ori || !ev || !yev || !ref || !fs) {
        fprintf(stderr, "sh_projection_bench: out of memory\n");
        return 1;
    }
    for (int k = 0; k < K; k++) {
        sss_rng_direction(&rng_state, ori[k].n);
        sss_rng_direction(&rng_state, ori[k].t);
    }
    for (int e = 0; e < NEVAL; e++) {
        sss_rng_direction(&rng_state, ev + 3 * e);
        sss_sh_eval(MAXO, ev + 3 * e, yev + 64 * (size_t)e);
    }

    /* True L2 projection: equal-weight spherical Fibonacci rule. */
    {
        const double golden = (1.0 + sqrt(5.0)) / 2.0, wq = 4.0 * PI / NREF;
        for (uint32_t i = 0; i < NREF; i++) {
            double z = 1.0 - 2.0 * (i + 0.5) / NREF, ph = 2.0 * PI * fmod(i / golden, 1.0);
            double r = sqrt(fmax(0.0, 1.0 - z * z)), w[3] = {r * cos(ph), r * sin(ph), z}, y[64];
            sss_sh_eval(MAXO, w, y);
            for (int kind = 0; kind < 2; kind++)
                for (int k = 0; k < K; k++) {
                    double f = f_eval(kind, &ori[k], w);
                    if (f == 0.0) continue;
                    double *c = ref + ((size_t)kind * K + k) * 64;
                    for (int q = 0; q < 64; q++) c[q] += wq * f * y[q];
                }
        }
    }

    static const char *names[2] = {"lobe: max(0, n·ω)", "shadow: max(0, n·ω) if ω·t > 0.2 else 0"};
    printf("N = %u Fibonacci directions, %d random orientations (seed %llu), %d random evaluation directions\n\n", N,
           K, (unsigned long long)seed, NEVAL);
    for (int kind = 0; kind < 2; kind++) {
        /* sums of squared errors over orientations × evaluation directions */
        double se[3][MAXO + 1], sx[2][MAXO + 1], ratio_lo[MAXO + 1], ratio_hi[MAXO + 1], sf = 0.0, si = 0.0;
        memset(se, 0, sizeof se);
        memset(sx, 0, sizeof sx);
        for (uint32_t o = 1; o <= MAXO; o++) {
            ratio_lo[o] = INFINITY;
            ratio_hi[o] = 0.0;
        }
        for (int k = 0; k < K; k++) {
            for (uint32_t j = 0; j < N; j++) fs[j] = f_eval(kind, &ori[k], s.dir + 3 * (size_t)j);
            double c[2][MAXO + 1][64];
            for (int m = 0; m < 2; m++)
                for (uint32_t o = 1; o <= MAXO; o++) sss_sh_project(proj[m][o], fs, c[m][o]);
            const double *cr = ref + ((size_t)kind * K + k) * 64;
            double sek[2][MAXO + 1];
            memset(sek, 0, sizeof sek);
            for (int e = 0; e < NEVAL; e++) {
                const double *w = ev + 3 * e, *y = yev + 64 * (size_t)e;
                double f = f_eval(kind, &ori[k], w);
                sf += f * f;
                uint32_t id[3];
                double bw[3];
                sss_dirset_lookup(&s, w, id, bw);
                double fi = bw[0] * fs[id[0]] + bw[1] * fs[id[1]] + bw[2] * fs[id[2]];
                si += (fi - f) * (fi - f);
                for (uint32_t o = 1; o <= MAXO; o++) {
                    double r[3] = {0, 0, 0};
                    for (uint32_t q = 0; q < o * o; q++) {
                        r[0] += c[0][o][q] * y[q];
                        r[1] += c[1][o][q] * y[q];
                        r[2] += cr[q] * y[q];
                    }
                    for (int m = 0; m < 3; m++) se[m][o] += (r[m] - f) * (r[m] - f);
                    for (int m = 0; m < 2; m++) sx[m][o] += (r[m] - r[2]) * (r[m] - r[2]);
                    sek[0][o] += (r[0] - f) * (r[0] - f);
                    sek[1][o] += (r[1] - f) * (r[1] - f);
                }
            }
            for (uint32_t o = 1; o <= MAXO; o++) {
                double q = sqrt(sek[1][o] / sek[0][o]);
                ratio_lo[o] = fmin(ratio_lo[o], q);
                ratio_hi[o] = fmax(ratio_hi[o], q);
            }
        }
        const double cnt = (double)K * NEVAL;
        printf("### %s\n\nRMS of f: %.4f; barycentric interpolation of the %u raw samples: RMS error %.2e\n\n",
               names[kind], sqrt(sf / cnt), N, sqrt(si / cnt));
        printf("| order | coeffs | least squares | quadrature | quadrature / LS (range over orientations) | "
               "L2 optimum | LS − optimum | quadrature − optimum |\n");
        printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
        for (uint32_t o = 1; o <= MAXO; o++) {
            double ls = sqrt(se[0][o] / cnt), qd = sqrt(se[1][o] / cnt), op = sqrt(se[2][o] / cnt);
            printf("| %u | %u | %.4e | %.4e | %.4f (%.4f – %.4f) | %.4e | %.2e | %.2e |\n", o, o * o, ls, qd, qd / ls,
                   ratio_lo[o], ratio_hi[o], op, sqrt(sx[0][o] / cnt), sqrt(sx[1][o] / cnt));
        }
        if (kind == 0) {
            /* Closed form: the clamped cosine is zonal about n with
             * A_l = 2π sqrt((2l+1)/(4π)) ∫_0^1 z P_l(z) dz, ‖f‖² = 2π/3, so the
             * optimal mean squared error is 1/6 − Σ_{l<n} A_l² / (4π). The
             * integral is exact with 8 Gauss–Legendre nodes (degree ≤ 8). */
            static const double gx[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                         0.9602898564975363};
            static const double gw[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                         0.1012285362903763};
            double mse = 1.0 / 6.0;
            printf("\nClosed-form L2 optimum for the lobe:");
            for (int l = 0; l < MAXO; l++) {
                double I = 0.0;
                for (int g = 0; g < 8; g++) {
                    double x = g < 4 ? -gx[g] : gx[g - 4], wgt = gw[g % 4], z = 0.5 * (x + 1.0);
                    double p0 = 1.0, p1 = z, p = l == 0 ? 1.0 : z;
                    for (int ll = 2; ll <= l; ll++) {
                        p = ((2.0 * ll - 1.0) * z * p1 - (ll - 1.0) * p0) / ll;
                        p0 = p1;
                        p1 = p;
                    }
                    I += 0.5 * wgt * z * p;
                }
                double A = 2.0 * PI * sqrt((2.0 * l + 1.0) / (4.0 * PI)) * I;
                mse -= A * A / (4.0 * PI);
                printf(" %.4e", sqrt(fmax(0.0, mse)));
            }
            printf(" (orders 1 … 8; over the whole sphere, not the %d directions)\n", NEVAL);
        }
        printf("\n");
    }

    for (int m = 0; m < 2; m++)
        for (uint32_t o = 1; o <= MAXO; o++) sss_sh_projector_destroy(proj[m][o]);
    free(ori);
    free(ev);
    free(yev);
    free(ref);
    free(fs);
    sss_dirset_free(&s);
    return 0;
}
