/* test_sh.c: real spherical harmonics, spherical Voronoi areas and the two
 * projections of baked samples onto SH (Hao–Varshney 2004 §4.1; constants
 * and conventions from docs/physics.md §7; no Condon–Shortley phase). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/random.h"
#include "sss/dirset.h"
#include "sss/sh.h"

#define PI 3.14159265358979323846

/* ---- helpers ------------------------------------------------------------ */

/* |a − b| ≤ eps (cmocka 1.1.5 has no assert_close). */
#define assert_close(a, b, eps)                                                                                    \
    do {                                                                                                           \
        double a_ = (a), b_ = (b);                                                                                 \
        if (!(fabs(a_ - b_) <= (eps))) fail_msg("%s = %.17g, expected %.17g (within %g)", #a, a_, b_, (double)(eps)); \
    } while (0)

static uint64_t rng_state;
static double rng_unit(void) { return sss_rng_unit(&rng_state); }

static int idx(int l, int m) { return l * (l + 1) + m; }

static void make_dirs(sss_dirset *s, uint32_t n, const double *d)
{
    memset(s, 0, sizeof *s);
    s->n = n;
    s->dir = malloc(3 * (size_t)n * sizeof *s->dir);
    assert_non_null(s->dir);
    memcpy(s->dir, d, 3 * (size_t)n * sizeof *d);
}

/* Textbook y_l^m from θ = acos z, φ = atan2(y, x), independent of sh.c:
 * P_l^m by the standard recurrence without the (−1)^m phase, K_l^m from
 * factorials in long double (Hao–Varshney 2004 §4.1). */
static double ref_ylm(int l, int m, const double d[3])
{
    int am = m < 0 ? -m : m;
    double th = acos(fmax(-1.0, fmin(1.0, d[2]))), ph = atan2(d[1], d[0]);
    double x = cos(th), st = sin(th);
    double pmm = 1.0;
    for (int k = 1; k <= am; k++) pmm *= (2.0 * k - 1.0) * st;
    double p;
    if (l == am) {
        p = pmm;
    } else {
        double p1 = x * (2.0 * am + 1.0) * pmm, p0 = pmm;
        p = p1;
        for (int ll = am + 2; ll <= l; ll++) {
            p = ((2.0 * ll - 1.0) * x * p1 - (ll + am - 1.0) * p0) / (ll - am);
            p0 = p1;
            p1 = p;
        }
    }
    long double f = 1.0L;
    for (int k = l - am + 1; k <= l + am; k++) f *= (long double)k; /* (l+|m|)!/(l−|m|)! */
    double K = (double)sqrtl((long double)(2 * l + 1) / (4.0L * 3.141592653589793238462643383279502884L) / f);
    if (m == 0) return K * p;
    if (m > 0) return sqrt(2.0) * K * cos(m * ph) * p;
    return sqrt(2.0) * K * sin(am * ph) * p;
}

/* Legendre polynomial P_l(x) (Bonnet). */
static double legendre(int l, double x)
{
    double p0 = 1.0, p1 = x;
    if (l == 0) return 1.0;
    for (int k = 2; k <= l; k++) {
        double p = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
        p0 = p1;
        p1 = p;
    }
    return p1;
}

/* n-point Gauss–Legendre nodes and weights on [−1, 1] (Newton on P_n). */
static void gauss_legendre(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double t = cos(PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p = legendre(n, t), pm = legendre(n - 1, t);
            dp = n * (t * p - pm) / (t * t - 1.0);
            double dt = p / dp;
            t -= dt;
            if (fabs(dt) < 1e-16) break;
        }
        double p = legendre(n, t), pm = legendre(n - 1, t);
        dp = n * (t * p - pm) / (t * t - 1.0);
        x[i] = t;
        w[i] = 2.0 / ((1.0 - t * t) * dp * dp);
    }
}

/* max |Σ_q w_q y_i(q) y_k(q) − δ_ik| over i, k < 64 for a quadrature rule. */
static double orthonormality_error(size_t nq, const double *dirs, const double *wts)
{
    double G[SSS_SH_MAX_COUNT][SSS_SH_MAX_COUNT];
    memset(G, 0, sizeof G);
    for (size_t q = 0; q < nq; q++) {
        double y[SSS_SH_MAX_COUNT];
        sss_sh_eval(8, dirs + 3 * q, y);
        for (int i = 0; i < 64; i++)
            for (int k = 0; k < 64; k++) G[i][k] += wts[q] * y[i] * y[k];
    }
    double e = 0.0;
    for (int i = 0; i < 64; i++)
        for (int k = 0; k < 64; k++) e = fmax(e, fabs(G[i][k] - (i == k ? 1.0 : 0.0)));
    return e;
}

/* ---- evaluation ------------------------------------------------------------ */

static void countIsOrderSquaredUpToEightAndZeroBeyond(void **state)
{
    (void)state;
    for (uint32_t n = 0; n <= 8; n++) assert_int_equal(sss_sh_count(n), n * n);
    assert_int_equal(sss_sh_count(7), 49); /* the paper's n = 7 */
    assert_int_equal(sss_sh_count(9), 0);
    assert_int_equal(sss_sh_count(UINT32_MAX), 0);
}

static void bandZeroAndOneMatchPhysicsSheetConstants(void **state)
{
    (void)state;
    const double c1 = 0.48860251190292;
    rng_state = 11;
    for (int t = 0; t < 100; t++) {
        double d[3], y[4];
        sss_rng_direction(&rng_state, d);
        sss_sh_eval(2, d, y);
        assert_close(y[0], 0.2820947917738781, 1e-16);
        assert_close(y[idx(1, -1)], c1 * d[1], 1e-14);
        assert_close(y[idx(1, 0)], c1 * d[2], 1e-14);
        assert_close(y[idx(1, 1)], c1 * d[0], 1e-14);
    }
}

static void bandTwoMatchesPhysicsSheetY20AndKnownPolynomials(void **state)
{
    (void)state;
    rng_state = 12;
    for (int t = 0; t < 100; t++) {
        double d[3], y[9];
        sss_rng_direction(&rng_state, d);
        const double x = d[0], yy = d[1], z = d[2];
        sss_sh_eval(3, d, y);
        assert_close(y[idx(2, 0)], 0.9461746957575601 * z * z - 0.3153915652525201, 1e-14);
        assert_close(y[idx(2, -2)], 1.0925484305920792 * x * yy, 1e-14);
        assert_close(y[idx(2, -1)], 1.0925484305920792 * yy * z, 1e-14);
        assert_close(y[idx(2, 1)], 1.0925484305920792 * x * z, 1e-14);
        assert_close(y[idx(2, 2)], 0.5462742152960396 * (x * x - yy * yy), 1e-14);
    }
}

static void noCondonShortleyPhaseGivesPositiveY11AtPlusX(void **state)
{
    (void)state;
    double y[64];
    const double px[3] = {1, 0, 0}, py[3] = {0, 1, 0};
    sss_sh_eval(8, px, y);
    assert_close(y[idx(1, 1)], +0.48860251190292, 1e-14);
    assert_true(y[idx(1, 1)] > 0.0);
    /* y_l^l ∝ Re (x + iy)^l with a positive factor: positive at +x for every
     * l (with the Condon–Shortley phase odd l would be negative). */
    for (int l = 1; l < 8; l++) assert_true(y[idx(l, l)] > 0.0);
    sss_sh_eval(8, py, y);
    assert_close(y[idx(1, -1)], +0.48860251190292, 1e-14);
    /* y_l^−l ∝ Im (x + iy)^l: positive at φ = π/(2l). */
    for (int l = 1; l < 8; l++) {
        double d[3] = {cos(PI / (2 * l)), sin(PI / (2 * l)), 0};
        sss_sh_eval(8, d, y);
        assert_true(y[idx(l, -l)] > 0.0);
    }
}

static void evalMatchesSphericalCoordinateDefinitionAtRandomDirections(void **state)
{
    (void)state;
    rng_state = 13;
    for (int t = 0; t < 500; t++) {
        double d[3], y[64];
        sss_rng_direction(&rng_state, d);
        sss_sh_eval(8, d, y);
        for (int l = 0; l < 8; l++)
            for (int m = -l; m <= l; m++) assert_close(y[idx(l, m)], ref_ylm(l, m, d), 1e-12);
    }
}

static void lowerOrdersArePrefixesOfOrderEight(void **state)
{
    (void)state;
    const double d[3] = {0.3, -0.7, 0.2};
    double y8[64];
    sss_sh_eval(8, d, y8);
    for (uint32_t n = 1; n < 8; n++) {
        double y[64];
        for (int i = 0; i < 64; i++) y[i] = 12345.0;
        sss_sh_eval(n, d, y);
        for (uint32_t i = 0; i < n * n; i++) assert_true(y[i] == y8[i]);
        for (uint32_t i = n * n; i < 64; i++) assert_true(y[i] == 12345.0); /* nothing written past n² */
    }
}

static void orthonormalToRoundoffUnderGaussLegendreProductRule(void **state)
{
    (void)state;
    /* 16 Gauss–Legendre nodes in z × 32 uniform φ integrate every product
     * of two order-8 harmonics (degree ≤ 14 in z, frequency ≤ 14 in φ)
     * exactly. */
    enum { NZ = 16, NP = 32 };
    double gx[NZ], gw[NZ];
    gauss_legendre(NZ, gx, gw);
    double *dirs = malloc(3 * NZ * NP * sizeof *dirs), *w = malloc(NZ * NP * sizeof *w);
    assert_non_null(dirs);
    assert_non_null(w);
    double wsum = 0.0;
    for (int a = 0; a < NZ; a++)
        for (int b = 0; b < NP; b++) {
            size_t q = (size_t)a * NP + b;
            double ph = 2.0 * PI * (b + 0.5) / NP, r = sqrt(1.0 - gx[a] * gx[a]);
            dirs[3 * q] = r * cos(ph);
            dirs[3 * q + 1] = r * sin(ph);
            dirs[3 * q + 2] = gx[a];
            w[q] = gw[a] * 2.0 * PI / NP;
            wsum += w[q];
        }
    assert_close(wsum, 4.0 * PI, 1e-12);
    double e = orthonormality_error(NZ * NP, dirs, w);
    if (!(e <= 1e-12)) fail_msg("Gauss–Legendre orthonormality error %.3g > 1e-12", e);
    free(dirs);
    free(w);
}

static void voronoiQuadratureOrthonormalityConvergesWithDirectionCount(void **state)
{
    (void)state;
    /* The Voronoi-area rule is only second order (a midpoint rule on the
     * cells): max |G − I| for order 8 is 1.7e-2 at N = 200, 2.0e-4 at 5000,
     * 3.7e-5 at 20000, so it cannot show 1e-6 at any practical N; the
     * Gauss–Legendre test above does that. This checks the rule converges. */
    static const uint32_t ns[] = {5000, 20000};
    static const double tol[] = {5e-4, 1e-4};
    for (int k = 0; k < 2; k++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, ns[k], NULL), SSS_OK);
        double *area = malloc(s.n * sizeof *area);
        assert_non_null(area);
        sss_sh_voronoi_areas(&s, area);
        double e = orthonormality_error(s.n, s.dir, area);
        if (!(e <= tol[k])) fail_msg("N = %u: Voronoi-quadrature orthonormality error %.3g > %g", ns[k], e, tol[k]);
        free(area);
        sss_dirset_free(&s);
    }
}

static void polesAreExactWithEveryNonzeroMTermZero(void **state)
{
    (void)state;
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double d[3] = {0.0, 0.0, (double)sgn};
        double y[64];
        sss_sh_eval(8, d, y);
        for (int l = 0; l < 8; l++)
            for (int m = -l; m <= l; m++) {
                double v = y[idx(l, m)];
                assert_true(isfinite(v));
                if (m != 0) {
                    assert_true(v == 0.0);
                } else {
                    /* y_l^0(±z) = sqrt((2l+1)/(4π)) (±1)^l */
                    assert_close(v, sqrt((2.0 * l + 1.0) / (4.0 * PI)) * ((l % 2 && sgn < 0) ? -1.0 : 1.0), 1e-14);
                }
            }
        /* −0 components and non-unit length are the same pole. */
        const double d2[3] = {-0.0, 0.0, 5.0 * sgn};
        double y2[64];
        sss_sh_eval(8, d2, y2);
        for (int i = 0; i < 64; i++) assert_close(y2[i], y[i], 1e-15);
    }
}

static void polesAreContinuousFromDirectionsOneTenMillionthAway(void **state)
{
    (void)state;
    for (int sgn = -1; sgn <= 1; sgn += 2) {
        const double pole[3] = {0.0, 0.0, (double)sgn};
        double y0[64];
        sss_sh_eval(8, pole, y0);
        for (int k = 0; k < 16; k++) {
            double ph = 2.0 * PI * k / 16 + 0.1, e = 1e-7;
            double d[3] = {sin(e) * cos(ph), sin(e) * sin(ph), sgn * cos(e)}, y[64];
            sss_sh_eval(8, d, y);
            for (int i = 0; i < 64; i++) {
                assert_true(isfinite(y[i]));
                assert_close(y[i], y0[i], 1e-6);
            }
        }
    }
}

static void bandEnergyIsRotationInvariant(void **state)
{
    (void)state;
    /* Addition theorem: Σ_m y_l^m(a) y_l^m(b) = (2l+1)/(4π) P_l(a·b). */
    rng_state = 14;
    for (int t = 0; t < 200; t++) {
        double a[3], b[3], ya[64], yb[64];
        sss_rng_direction(&rng_state, a);
        sss_rng_direction(&rng_state, b);
        if (t == 0) memcpy(b, a, sizeof b);
        sss_sh_eval(8, a, ya);
        sss_sh_eval(8, b, yb);
        double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        for (int l = 0; l < 8; l++) {
            double sum = 0.0;
            for (int m = -l; m <= l; m++) sum += ya[idx(l, m)] * yb[idx(l, m)];
            assert_close(sum, (2.0 * l + 1.0) / (4.0 * PI) * legendre(l, c), 1e-13);
        }
    }
}

static void evalNormalisesDirectionsOfAnyLength(void **state)
{
    (void)state;
    const double u[3] = {0.48, -0.6, 0.64};
    static const double scales[] = {1e-300, 4.9e-324 * 8, 1e-3, 7.0, 1e300, 1.7e308};
    double y0[64];
    sss_sh_eval(8, u, y0);
    for (size_t k = 0; k < sizeof scales / sizeof scales[0]; k++) {
        double d[3] = {u[0] * scales[k], u[1] * scales[k], u[2] * scales[k]}, y[64];
        sss_sh_eval(8, d, y);
        /* the 8·denormal case is only accurate to its 3 mantissa bits */
        double tol = scales[k] < 1e-310 ? 0.3 : 1e-13;
        for (int i = 0; i < 64; i++) {
            assert_true(isfinite(y[i]));
            assert_close(y[i], y0[i], tol);
        }
    }
}

static void zeroNaNAndInfiniteDirectionsGiveZerosNeverNaN(void **state)
{
    (void)state;
    const double bad[][3] = {{0, 0, 0}, {-0.0, 0, -0.0}, {NAN, 0, 1}, {0, NAN, 0}, {1, 0, NAN},
                             {INFINITY, 0, 0}, {0, -INFINITY, 1}, {NAN, NAN, NAN}};
    const double coeffs[64] = {1, 2, 3, 4};
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        double y[64];
        float yf[64];
        for (int i = 0; i < 64; i++) {
            y[i] = NAN;
            yf[i] = NAN;
        }
        sss_sh_eval(8, bad[k], y);
        for (int i = 0; i < 64; i++) assert_true(y[i] == 0.0);
        const float bf[3] = {(float)bad[k][0], (float)bad[k][1], (float)bad[k][2]};
        sss_sh_evalf(8, bf, yf);
        for (int i = 0; i < 64; i++) assert_true(yf[i] == 0.0f);
        assert_true(sss_sh_reconstruct(8, coeffs, bad[k]) == 0.0);
    }
}

static void orderZeroAndOrderAboveEightWriteNothing(void **state)
{
    (void)state;
    const double d[3] = {0, 0, 1};
    double y[100];
    for (int i = 0; i < 100; i++) y[i] = 7.0;
    sss_sh_eval(0, d, y);
    sss_sh_eval(9, d, y);
    sss_sh_eval(UINT32_MAX, d, y);
    for (int i = 0; i < 100; i++) assert_true(y[i] == 7.0);
}

static void evalfMatchesEvalToFloatPrecision(void **state)
{
    (void)state;
    rng_state = 15;
    for (int t = 0; t < 200; t++) {
        double d[3], y[64];
        sss_rng_direction(&rng_state, d);
        /* volatile: gcc -O3 (SLP) may otherwise feed the unrounded doubles to
         * sss_sh_eval, and order-8 harmonics amplify that difference past 1e-7 */
        volatile float vf[3] = {(float)d[0], (float)d[1], (float)d[2]};
        const float df[3] = {vf[0], vf[1], vf[2]};
        const double dd[3] = {vf[0], vf[1], vf[2]};
        float yf[64];
        sss_sh_eval(8, dd, y);
        sss_sh_evalf(8, df, yf);
        for (int i = 0; i < 64; i++) assert_close((double)yf[i], y[i], 1e-7 * fmax(1.0, fabs(y[i])));
    }
}

static void reconstructSumsCoefficientsTimesHarmonics(void **state)
{
    (void)state;
    rng_state = 16;
    double c[64], d[3], y[64];
    for (int i = 0; i < 64; i++) c[i] = rng_unit() - 0.5;
    sss_rng_direction(&rng_state, d);
    sss_sh_eval(8, d, y);
    for (uint32_t n = 1; n <= 8; n++) {
        double s = 0.0;
        for (uint32_t i = 0; i < n * n; i++) s += c[i] * y[i];
        assert_close(sss_sh_reconstruct(n, c, d), s, 1e-14);
    }
    assert_true(sss_sh_reconstruct(0, c, d) == 0.0);
    assert_true(sss_sh_reconstruct(9, c, d) == 0.0);
}

/* ---- Voronoi areas --------------------------------------------------------- */

static void voronoiAreasArePositiveAndSumTo4Pi(void **state)
{
    (void)state;
    static const uint32_t ns[] = {4, 5, 6, 12, 25, 200, 801, 5000};
    for (size_t k = 0; k < sizeof ns / sizeof ns[0]; k++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, ns[k], NULL), SSS_OK);
        double *a = malloc(s.n * sizeof *a), sum = 0.0, amin = INFINITY, amax = 0.0;
        assert_non_null(a);
        sss_sh_voronoi_areas(&s, a);
        for (uint32_t j = 0; j < s.n; j++) {
            assert_true(a[j] > 0.0);
            sum += a[j];
            amin = fmin(amin, a[j]);
            amax = fmax(amax, a[j]);
        }
        assert_close(sum, 4.0 * PI, 1e-9);
        /* Fibonacci cells are near-equal: within a factor 2 of each other. */
        if (ns[k] >= 25) assert_true(amax < 2.0 * amin);
        free(a);
        sss_dirset_free(&s);
    }
}

static void voronoiAreasOfOctahedronAndCubeAreEqualShares(void **state)
{
    (void)state;
    /* Octahedron: each cell is a spherical square, 4π/6. */
    static const double oct[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    /* Cube corners: each face is split into two triangles sharing one
     * circumcentre, so the fan has zero-area pieces; cells are 4π/8. */
    double cube[24];
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) cube[3 * i + k] = ((i >> k) & 1 ? 1.0 : -1.0) / sqrt(3.0);
    const double *sets[2] = {oct, cube};
    const uint32_t ns[2] = {6, 8};
    for (int c = 0; c < 2; c++) {
        sss_dirset s;
        make_dirs(&s, ns[c], sets[c]);
        assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
        double a[8];
        sss_sh_voronoi_areas(&s, a);
        for (uint32_t j = 0; j < ns[c]; j++) assert_close(a[j], 4.0 * PI / ns[c], 1e-12);
        sss_dirset_free(&s);
    }
}

static void voronoiAreasAreNaNWithoutTriangulationOrWithOpenFan(void **state)
{
    (void)state;
    static const double d3[] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    sss_dirset s;
    make_dirs(&s, 3, d3);
    assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
    assert_int_equal(s.ntri, 0);
    double a[8];
    sss_sh_voronoi_areas(&s, a);
    for (int j = 0; j < 3; j++) assert_true(isnan(a[j]));
    sss_dirset_free(&s);

    /* Octahedron with one triangle's orientation flipped: not a closed
     * counter-clockwise fan. */
    static const double oct[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    make_dirs(&s, 6, oct);
    assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
    uint32_t tmp = s.tri[1];
    s.tri[1] = s.tri[2];
    s.tri[2] = tmp;
    sss_sh_voronoi_areas(&s, a);
    for (int j = 0; j < 6; j++) assert_true(isnan(a[j]));
    sss_sh_projector *p = (sss_sh_projector *)&s; /* poison: must be reset to NULL */
    sss_error err = {{0}};
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_QUADRATURE, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    assert_non_null(strstr(err.msg, "fan"));
    sss_dirset_free(&s);
}

/* ---- projection ------------------------------------------------------------ */

/* f_j = Σ_i c_i y_i(ω_j) for random c (order n). */
static void band_limited_samples(const sss_dirset *s, uint32_t n, double *c, double *f)
{
    for (uint32_t i = 0; i < n * n; i++) c[i] = 2.0 * rng_unit() - 1.0;
    for (uint32_t j = 0; j < s->n; j++) f[j] = sss_sh_reconstruct(n, c, s->dir + 3 * (size_t)j);
}

static void leastSquaresReproducesBandLimitedFunctionAtOrdersOneToEight(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    rng_state = 17;
    double f[200];
    for (uint32_t n = 1; n <= 8; n++) {
        sss_sh_projector *p = NULL;
        sss_error err = {{0}};
        assert_int_equal(sss_sh_projector_create(&s, n, SSS_SH_LEAST_SQUARES, &p, &err), SSS_OK);
        for (int trial = 0; trial < 5; trial++) {
            double c[64], got[64];
            band_limited_samples(&s, n, c, f);
            sss_sh_project(p, f, got);
            for (uint32_t i = 0; i < n * n; i++) assert_close(got[i], c[i], 1e-10);
            /* and hence the function everywhere, not only at the samples */
            for (int t = 0; t < 50; t++) {
                double d[3];
                sss_rng_direction(&rng_state, d);
                assert_close(sss_sh_reconstruct(n, got, d), sss_sh_reconstruct(n, c, d), 1e-10);
            }
        }
        sss_sh_projector_destroy(p);
    }
    sss_dirset_free(&s);
}

static void leastSquaresResidualIsOrthogonalToEveryHarmonic(void **state)
{
    (void)state;
    /* For data that is not band-limited the minimiser is characterised by
     * Yᵀ(Y c − f) = 0 (normal equations). */
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    double f[200], c[64];
    for (uint32_t j = 0; j < 200; j++) {
        const double *w = s.dir + 3 * (size_t)j;
        f[j] = (w[0] + 0.3 * w[2] > 0.2 ? 1.0 : 0.0) + exp(w[1]);
    }
    for (uint32_t n = 1; n <= 8; n++) {
        sss_sh_projector *p = NULL;
        assert_int_equal(sss_sh_projector_create(&s, n, SSS_SH_LEAST_SQUARES, &p, NULL), SSS_OK);
        sss_sh_project(p, f, c);
        double g[64] = {0};
        for (uint32_t j = 0; j < 200; j++) {
            double y[64];
            sss_sh_eval(n, s.dir + 3 * (size_t)j, y);
            double r = -f[j];
            for (uint32_t i = 0; i < n * n; i++) r += c[i] * y[i];
            for (uint32_t i = 0; i < n * n; i++) g[i] += y[i] * r;
        }
        for (uint32_t i = 0; i < n * n; i++) assert_close(g[i], 0.0, 1e-11);
        sss_sh_projector_destroy(p);
    }
    sss_dirset_free(&s);
}

static void leastSquaresMatrixIsLeftInverseOfSampleMatrix(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 64, NULL), SSS_OK); /* square: n² = N */
    for (int pass = 0; pass < 2; pass++) {
        if (pass == 1) {
            sss_dirset_free(&s);
            assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
        }
        sss_sh_projector *p = NULL;
        assert_int_equal(sss_sh_projector_create(&s, 8, SSS_SH_LEAST_SQUARES, &p, NULL), SSS_OK);
        const double *P = sss_sh_projector_matrix(p);
        assert_non_null(P);
        assert_int_equal(sss_sh_projector_order(p), 8);
        assert_int_equal(sss_sh_projector_ndirs(p), s.n);
        double *Y = malloc((size_t)s.n * 64 * sizeof *Y);
        assert_non_null(Y);
        for (uint32_t j = 0; j < s.n; j++) sss_sh_eval(8, s.dir + 3 * (size_t)j, Y + 64 * (size_t)j);
        for (int i = 0; i < 64; i++)
            for (int k = 0; k < 64; k++) {
                double v = 0.0;
                for (uint32_t j = 0; j < s.n; j++) v += P[(size_t)i * s.n + j] * Y[64 * (size_t)j + k];
                assert_close(v, i == k ? 1.0 : 0.0, 1e-11);
            }
        free(Y);
        sss_sh_projector_destroy(p);
    }
    sss_dirset_free(&s);
}

static void quadratureOfConstantGivesSqrt4PiInC00(void **state)
{
    (void)state;
    static const uint32_t ns[] = {50, 200, 801};
    for (size_t k = 0; k < sizeof ns / sizeof ns[0]; k++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, ns[k], NULL), SSS_OK);
        sss_sh_projector *p = NULL;
        assert_int_equal(sss_sh_projector_create(&s, 7, SSS_SH_QUADRATURE, &p, NULL), SSS_OK);
        double *f = malloc(s.n * sizeof *f), c[64];
        assert_non_null(f);
        for (uint32_t j = 0; j < s.n; j++) f[j] = 1.0;
        sss_sh_project(p, f, c);
        assert_close(c[0], sqrt(4.0 * PI), 1e-9);
        free(f);
        sss_sh_projector_destroy(p);
        sss_dirset_free(&s);
    }
}

static void quadratureMatrixIsVoronoiAreaTimesHarmonic(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    sss_sh_projector *p = NULL;
    assert_int_equal(sss_sh_projector_create(&s, 8, SSS_SH_QUADRATURE, &p, NULL), SSS_OK);
    const double *P = sss_sh_projector_matrix(p);
    double area[200];
    sss_sh_voronoi_areas(&s, area);
    for (uint32_t j = 0; j < 200; j++) {
        double y[64];
        sss_sh_eval(8, s.dir + 3 * (size_t)j, y);
        for (int i = 0; i < 64; i++) assert_close(P[(size_t)i * 200 + j], area[j] * y[i], 1e-15);
    }
    /* The quadrature is close to (not exactly) a projection: a band-1
     * function comes back within a few percent. */
    double f[200], c[64];
    for (uint32_t j = 0; j < 200; j++) f[j] = s.dir[3 * j + 2];
    sss_sh_project(p, f, c);
    assert_close(c[idx(1, 0)], 1.0 / 0.48860251190292, 0.02);
    sss_sh_projector_destroy(p);
    sss_dirset_free(&s);
}

static void stridedProjectionMatchesPerChannelProjection(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    rng_state = 18;
    double rgb[3 * 200], ch[200];
    for (int k = 0; k < 3 * 200; k++) rgb[k] = rng_unit();
    for (int m = 0; m < 2; m++) {
        sss_sh_projector *p = NULL;
        assert_int_equal(sss_sh_projector_create(&s, 6, (sss_sh_method)m, &p, NULL), SSS_OK);
        for (int c = 0; c < 3; c++) {
            double a[64], b[64];
            for (int j = 0; j < 200; j++) ch[j] = rgb[3 * j + c];
            sss_sh_project(p, ch, a);
            sss_sh_project_strided(p, rgb + c, 3, b);
            for (int i = 0; i < 36; i++) assert_true(a[i] == b[i]);
        }
        sss_sh_projector_destroy(p);
    }
    sss_dirset_free(&s);
}

static void orderZeroProjectorHasNoCoefficients(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 20, NULL), SSS_OK);
    for (int m = 0; m < 2; m++) {
        sss_sh_projector *p = NULL;
        assert_int_equal(sss_sh_projector_create(&s, 0, (sss_sh_method)m, &p, NULL), SSS_OK);
        assert_non_null(p);
        assert_null(sss_sh_projector_matrix(p));
        assert_int_equal(sss_sh_projector_order(p), 0);
        double f[20] = {0}, c[1] = {5.0};
        sss_sh_project(p, f, c);
        assert_true(c[0] == 5.0);
        sss_sh_projector_destroy(p);
    }
    sss_sh_projector_destroy(NULL);
    sss_dirset_free(&s);
}

/* ---- invalid input --------------------------------------------------------- */

static void projectorRejectsOrderNineNamingIt(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    for (int m = 0; m < 2; m++) {
        sss_sh_projector *p = (sss_sh_projector *)&s;
        sss_error err = {{0}};
        assert_int_equal(sss_sh_projector_create(&s, 9, (sss_sh_method)m, &p, &err), SSS_ERR_ARG);
        assert_null(p);
        assert_non_null(strstr(err.msg, "order 9"));
        assert_non_null(strstr(err.msg, "[0, 8]"));
        assert_non_null(strstr(err.msg, "200 directions"));
    }
    sss_dirset_free(&s);
}

static void projectorRejectsMoreCoefficientsThanDirections(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 50, NULL), SSS_OK);
    for (int m = 0; m < 2; m++) {
        sss_sh_projector *p = NULL;
        sss_error err = {{0}};
        assert_int_equal(sss_sh_projector_create(&s, 8, (sss_sh_method)m, &p, &err), SSS_ERR_ARG);
        assert_null(p);
        assert_non_null(strstr(err.msg, "order 8"));
        assert_non_null(strstr(err.msg, "64 coefficients"));
        assert_non_null(strstr(err.msg, "50 directions"));
        /* order 7 (49 ≤ 50) is fine */
        assert_int_equal(sss_sh_projector_create(&s, 7, (sss_sh_method)m, &p, &err), SSS_OK);
        sss_sh_projector_destroy(p);
    }
    sss_dirset_free(&s);
}

static void leastSquaresRejectsRankDeficientDirections(void **state)
{
    (void)state;
    /* 100 directions on the equator: y_1^0 = 0.4886 z vanishes at all of
     * them, so order 2 is rank deficient although 4 ≤ 100. */
    double d[300];
    for (int j = 0; j < 100; j++) {
        d[3 * j] = cos(2.0 * PI * j / 100);
        d[3 * j + 1] = sin(2.0 * PI * j / 100);
        d[3 * j + 2] = 0.0;
    }
    sss_dirset s;
    make_dirs(&s, 100, d);
    sss_sh_projector *p = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_sh_projector_create(&s, 1, SSS_SH_LEAST_SQUARES, &p, &err), SSS_OK);
    sss_sh_projector_destroy(p);
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    assert_non_null(strstr(err.msg, "rank deficient"));
    assert_non_null(strstr(err.msg, "order 2"));
    assert_non_null(strstr(err.msg, "100 directions"));

    /* Nearly on the equator (|z| = 1e-11): full rank in floating point but
     * the z coefficient would amplify noise by ~1e11. */
    for (int j = 0; j < 100; j++) s.dir[3 * j + 2] = (j % 2 ? 1e-11 : -1e-11);
    err.msg[0] = 0;
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    assert_non_null(strstr(err.msg, "order 2"));
    assert_non_null(strstr(err.msg, "100 directions"));
    assert_true(strstr(err.msg, "ill-conditioned") || strstr(err.msg, "rank deficient"));
    sss_dirset_free(&s);
}

static void quadratureRejectsUntriangulatedSet(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    free(s.tri);
    s.tri = NULL;
    s.ntri = 0;
    sss_sh_projector *p = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_sh_projector_create(&s, 3, SSS_SH_QUADRATURE, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    assert_non_null(strstr(err.msg, "triangulated"));
    assert_non_null(strstr(err.msg, "order 3"));
    /* least squares needs no triangles */
    assert_int_equal(sss_sh_projector_create(&s, 3, SSS_SH_LEAST_SQUARES, &p, &err), SSS_OK);
    sss_sh_projector_destroy(p);
    sss_dirset_free(&s);
}

static void projectorRejectsNaNOrZeroDirectionNamingIt(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 30, NULL), SSS_OK);
    sss_error err = {{0}};
    sss_sh_projector *p = NULL;
    s.dir[3 * 7 + 1] = NAN;
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    assert_non_null(strstr(err.msg, "direction 7"));
    s.dir[3 * 7] = s.dir[3 * 7 + 1] = s.dir[3 * 7 + 2] = 0.0;
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "direction 7"));
    sss_dirset_free(&s);
}

static void projectorRejectsNullAndEmptyAndUnknownMethod(void **state)
{
    (void)state;
    sss_dirset s;
    sss_sh_projector *p = NULL;
    sss_error err = {{0}};
    assert_int_equal(sss_sh_projector_create(NULL, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_null(p);
    memset(&s, 0, sizeof s);
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, &p, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "empty"));
    assert_int_equal(sss_dirset_fibonacci(&s, 30, NULL), SSS_OK);
    assert_int_equal(sss_sh_projector_create(&s, 2, SSS_SH_LEAST_SQUARES, NULL, &err), SSS_ERR_ARG);
    assert_int_equal(sss_sh_projector_create(&s, 2, (sss_sh_method)7, &p, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "method 7"));
    assert_null(p);
    sss_dirset_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(countIsOrderSquaredUpToEightAndZeroBeyond),
        cmocka_unit_test(bandZeroAndOneMatchPhysicsSheetConstants),
        cmocka_unit_test(bandTwoMatchesPhysicsSheetY20AndKnownPolynomials),
        cmocka_unit_test(noCondonShortleyPhaseGivesPositiveY11AtPlusX),
        cmocka_unit_test(evalMatchesSphericalCoordinateDefinitionAtRandomDirections),
        cmocka_unit_test(lowerOrdersArePrefixesOfOrderEight),
        cmocka_unit_test(orthonormalToRoundoffUnderGaussLegendreProductRule),
        cmocka_unit_test(voronoiQuadratureOrthonormalityConvergesWithDirectionCount),
        cmocka_unit_test(polesAreExactWithEveryNonzeroMTermZero),
        cmocka_unit_test(polesAreContinuousFromDirectionsOneTenMillionthAway),
        cmocka_unit_test(bandEnergyIsRotationInvariant),
        cmocka_unit_test(evalNormalisesDirectionsOfAnyLength),
        cmocka_unit_test(zeroNaNAndInfiniteDirectionsGiveZerosNeverNaN),
        cmocka_unit_test(orderZeroAndOrderAboveEightWriteNothing),
        cmocka_unit_test(evalfMatchesEvalToFloatPrecision),
        cmocka_unit_test(reconstructSumsCoefficientsTimesHarmonics),
        cmocka_unit_test(voronoiAreasArePositiveAndSumTo4Pi),
        cmocka_unit_test(voronoiAreasOfOctahedronAndCubeAreEqualShares),
        cmocka_unit_test(voronoiAreasAreNaNWithoutTriangulationOrWithOpenFan),
        cmocka_unit_test(leastSquaresReproducesBandLimitedFunctionAtOrdersOneToEight),
        cmocka_unit_test(leastSquaresResidualIsOrthogonalToEveryHarmonic),
        cmocka_unit_test(leastSquaresMatrixIsLeftInverseOfSampleMatrix),
        cmocka_unit_test(quadratureOfConstantGivesSqrt4PiInC00),
        cmocka_unit_test(quadratureMatrixIsVoronoiAreaTimesHarmonic),
        cmocka_unit_test(stridedProjectionMatchesPerChannelProjection),
        cmocka_unit_test(orderZeroProjectorHasNoCoefficients),
        cmocka_unit_test(projectorRejectsOrderNineNamingIt),
        cmocka_unit_test(projectorRejectsMoreCoefficientsThanDirections),
        cmocka_unit_test(leastSquaresRejectsRankDeficientDirections),
        cmocka_unit_test(quadratureRejectsUntriangulatedSet),
        cmocka_unit_test(projectorRejectsNaNOrZeroDirectionNamingIt),
        cmocka_unit_test(projectorRejectsNullAndEmptyAndUnknownMethod),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
