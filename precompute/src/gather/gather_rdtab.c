/* gather_rdtab.c: the dipole profile of the dense blocks as piecewise
 * polynomials (docs/benchmarks.md, "Bake at scale"; dense blocks at the machine's peak).
 *
 * The near weights of the hierarchical gather are (1/π) R_d(r) ΔA for
 * every (receiver, source) pair of a block (Hao–Varshney 2004 §3.1; R_d of
 * Jensen et al. 2001, docs/physics.md §2). Evaluated directly, R_d costs two
 * square roots, two divisions and two exponentials per channel and pair: a
 * quarter of the dense blocks's time, the part that kept it from the
 * machine's peak (docs/benchmarks.md). Here f = R_d / π is a function of
 * x = r² in float, on SSS_RDTAB_N = 32 octaves of x ending with the one
 * that holds the cutoff radius R²: the octave is read off the float's
 * exponent (no square root, no logarithm), and on it f is one polynomial
 * of degree SSS_RDTAB_DEG in u = 2t − 1 ∈ [−1, 1), x = 2^e (1 + t), t the
 * mantissa. 32 intervals make each coefficient one 32-entry register
 * lookup on AVX-512 (vpermt2ps: gathers from a table measured slower than
 * the direct formula on this machine).
 *
 * Accuracy: on an octave [a, 2a], f's nearest singularity lies at
 * x = −z² ≤ 0 (d = √(x + z²), z > 0), at least 3 half-widths from the
 * octave's centre, so Chebyshev interpolation converges like
 * (3 + √8)^−n: n = 10 gives ~2·10⁻⁸ relative, under the float Horner
 * step's own rounding. The polynomial interpolates f at the 11 Chebyshev
 * nodes of each octave; tests/unit/test_gather_kernels.c bounds the float
 * evaluation at 10⁻⁶ relative from 10⁻³ mm to R. Below the first octave
 * (r < 2^(e₀/2) mm, 7·10⁻⁴ mm for marble's R = 32 mm) f is taken at its
 * start: R_d is flat there to ~10⁻⁵, and such pairs are the self / disk
 * pairs that nbhd.c's rules redo in double anyway. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gather/gather_internal.h"
#include "sss/vec3.h"

void sss_rdtab_init(sss_rdtab *t, const sss_dipole *d, double xmax)
{
    int E = 0;
    (void)frexp(xmax > 0.0 && isfinite(xmax) ? xmax : 1.0, &E); /* xmax < 2^E */
    /* keep 2^e0 and 2^(e0 + N) normal floats, so that the evaluator's
     * exponent arithmetic stays in range (cutoffs of 10⁻¹⁴ mm or 10¹⁹ mm) */
    E = E < SSS_RDTAB_N - 126 ? SSS_RDTAB_N - 126 : E > 127 ? 127 : E;
    t->e0 = E - SSS_RDTAB_N;
    enum { NP = SSS_RDTAB_DEG + 1 };
    for (int i = 0; i < SSS_RDTAB_N; i++) {
        const double a = ldexp(1.0, t->e0 + i); /* octave [a, 2a): x = a (1 + (u + 1) / 2) */
        /* f at the Chebyshev nodes u_m = cos(π (m + ½) / NP), then the
         * Chebyshev coefficients c_k = (2 / NP) Σ_m f(u_m) T_k(u_m) */
        double fu[NP], ch[NP];
        for (int m = 0; m < NP; m++) {
            const double u = cos(SSS_PI * (m + 0.5) / NP);
            fu[m] = sss_rd(d, sqrt(a * (1.0 + (u + 1.0) / 2.0))) / SSS_PI;
        }
        for (int k = 0; k < NP; k++) {
            double s = 0;
            for (int m = 0; m < NP; m++) s += fu[m] * cos(SSS_PI * k * (m + 0.5) / NP);
            ch[k] = 2.0 * s / NP;
        }
        ch[0] *= 0.5;
        /* Σ c_k T_k(u) as powers of u: T_{k+1} = 2u T_k − T_{k−1} */
        double mono[NP], Tkm1[NP], Tk[NP], Tn[NP];
        memset(mono, 0, sizeof mono);
        memset(Tkm1, 0, sizeof Tkm1);
        memset(Tk, 0, sizeof Tk);
        Tkm1[0] = 1.0; /* T_0 */
        Tk[1] = 1.0;   /* T_1 */
        mono[0] += ch[0];
        for (int j = 0; j < NP; j++) mono[j] += ch[1] * Tk[j];
        for (int k = 2; k < NP; k++) {
            for (int j = 0; j < NP; j++) Tn[j] = (j > 0 ? 2.0 * Tk[j - 1] : 0.0) - Tkm1[j];
            for (int j = 0; j < NP; j++) mono[j] += ch[k] * Tn[j];
            memcpy(Tkm1, Tk, sizeof Tk);
            memcpy(Tk, Tn, sizeof Tn);
        }
        for (int j = 0; j < NP; j++) t->c[j][i] = (float)mono[j];
    }
}

float sss_rdtab_eval(const sss_rdtab *t, float x)
{
    return sss_rdtab_at(t, x);
}
