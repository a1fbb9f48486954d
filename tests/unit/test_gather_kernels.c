/* The hierarchical gather's kernels (docs/benchmarks.md, "Bake at scale").
 * The profile polynomials (precompute/src/gather/gather_rdtab.c): within 10⁻⁶
 * relative of R_d / π in double over their 32 octaves (to the cutoff) for
 * several materials and radii, finite and bounded outside that range; the
 * weight rows give the same bits by every path (gather_blocks.c).
 * The block product (precompute/src/gather/gather_gemm.c):
 * every path this CPU has (AVX-512, AVX2+FMA, portable fmaf) gives the same
 * bits, equal to one fmaf chain per element computed here; a column's bits
 * do not depend on the other columns (what keeps a bake in direction chunks
 * byte-identical); the values agree with a double-precision sum; edge
 * shapes (one row, one column, no rows of Ψ, panels of K) work. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gather/gather_internal.h"
#include "sss/dipole.h"
#include "sss/random.h"
#include "sss/vec3.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static float urand(void)
{
    return (float)sss_rng_unit(&rng);
}

typedef struct prob {
    uint32_t M, N, K;
    float *W, *G, *Q, *scratch;
    const float **rows;
} prob;

/* W random with some zero weights (sources beyond the cutoff), Ψ's rows
 * scattered over a larger table with a row length that is not a multiple
 * of the vector width, as Gm's rows are. */
static prob make(uint32_t M, uint32_t N, uint32_t K)
{
    prob p = {M, N, K, NULL, NULL, NULL, NULL, NULL};
    const uint32_t ld = N + 3, table = 2 * K + 5;
    p.W = malloc(sizeof(float) * ((size_t)M * K + 1));
    p.G = malloc(sizeof(float) * (size_t)table * ld);
    p.Q = malloc(sizeof(float) * ((size_t)M * N + 1));
    p.rows = malloc(sizeof *p.rows * (K + 1));
    p.scratch = malloc(sizeof(float) * sss_gather_gemm_scratch(N));
    assert_non_null(p.scratch);
    assert_non_null(p.W);
    assert_non_null(p.G);
    assert_non_null(p.Q);
    assert_non_null(p.rows);
    for (size_t i = 0; i < (size_t)M * K; i++) p.W[i] = urand() < 0.2f ? 0.0f : urand() * 1e-3f;
    for (size_t i = 0; i < (size_t)table * ld; i++) p.G[i] = urand() * 2.0f - 0.5f;
    for (uint32_t k = 0; k < K; k++) p.rows[k] = p.G + (size_t)((k * 7u) % table) * ld;
    return p;
}

static void drop(prob *p)
{
    free(p->W);
    free(p->G);
    free(p->Q);
    free(p->rows);
    free(p->scratch);
}

/* The reference chain: acc ← fmaf(W[m][k], Ψ[k][n], acc), k in order. */
static float chain(const prob *p, uint32_t m, uint32_t n)
{
    float acc = 0.0f;
    for (uint32_t k = 0; k < p->K; k++) acc = fmaf(p->W[(size_t)m * p->K + k], p->rows[k][n], acc);
    return acc;
}

static void check_shape(uint32_t M, uint32_t N, uint32_t K)
{
    prob p = make(M, N, K);
    int ran = 0;
    for (int isa = SSS_GEMM_PORTABLE; isa <= SSS_GEMM_AVX512; isa++) {
        for (size_t i = 0; i < (size_t)M * N; i++) p.Q[i] = NAN; /* every element must be written */
        if (!sss_gather_gemm_isa(isa, M, N, K, p.W, K, p.rows, p.Q, N, p.scratch)) continue;
        ran++;
        for (uint32_t m = 0; m < M; m++)
            for (uint32_t n = 0; n < N; n++) {
                const float want = chain(&p, m, n), got = p.Q[(size_t)m * N + n];
                if (memcmp(&want, &got, sizeof want))
                    fail_msg("path %d, %u x %u x %u: Q[%u][%u] = %.9g, the fmaf chain gives %.9g", isa, M, N, K, m, n,
                             (double)got, (double)want);
                double ref = 0, mag = 0;
                for (uint32_t k = 0; k < K; k++) {
                    ref += (double)p.W[(size_t)m * K + k] * p.rows[k][n];
                    mag += fabs((double)p.W[(size_t)m * K + k] * p.rows[k][n]);
                }
                assert_true(fabs(got - ref) <= 1e-6 * K * mag + 1e-30);
            }
    }
    assert_true(ran >= 1); /* the portable path always runs */
    drop(&p);
}

static void paths_agree_bit_for_bit(void **state)
{
    (void)state;
    /* the gather's shapes (M = 3·B, N = 200 directions), tails of every
     * tile size, K across panels of 256 */
    check_shape(141, 200, 700);
    check_shape(3, 200, 40);
    static const uint32_t Ms[] = {1, 2, 5, 7, 8, 9, 13, 17};
    static const uint32_t Ns[] = {1, 7, 8, 15, 16, 17, 24, 33, 47, 48, 49, 64, 96, 113};
    for (size_t a = 0; a < sizeof Ms / sizeof *Ms; a++)
        for (size_t b = 0; b < sizeof Ns / sizeof *Ns; b++) check_shape(Ms[a], Ns[b], 1 + (uint32_t)(a * 37 + b * 11) % 300);
    check_shape(9, 33, 257);
    check_shape(9, 33, 512);
    /* no rows of Q, no columns */
    check_shape(0, 20, 30);
    check_shape(6, 0, 30);
}

static void empty_product_is_zero(void **state)
{
    (void)state;
    prob p = make(5, 20, 0);
    for (int isa = SSS_GEMM_PORTABLE; isa <= SSS_GEMM_AVX512; isa++) {
        for (size_t i = 0; i < 100; i++) p.Q[i] = NAN;
        if (!sss_gather_gemm_isa(isa, 5, 20, 0, p.W, 0, p.rows, p.Q, 20, p.scratch)) continue;
        for (size_t i = 0; i < 100; i++) assert_true(p.Q[i] == 0.0f);
    }
    drop(&p);
}

/* A chunk of directions is a product over fewer columns of Ψ (rows moved
 * to the chunk's first column): its columns must have the bits of the
 * whole product's. */
static void columns_do_not_depend_on_the_others(void **state)
{
    (void)state;
    const uint32_t M = 21, N = 200, K = 600;
    prob p = make(M, N, K);
    static const uint32_t j0s[] = {0, 1, 17, 64, 150, 199}, ws[] = {1, 3, 16, 37, 50, 1};
    float *Qc = malloc(sizeof(float) * M * N);
    const float **rc = malloc(sizeof *rc * K);
    assert_non_null(Qc);
    assert_non_null(rc);
    for (int isa = SSS_GEMM_PORTABLE; isa <= SSS_GEMM_AVX512; isa++) {
        if (!sss_gather_gemm_isa(isa, M, N, K, p.W, K, p.rows, p.Q, N, p.scratch)) continue;
        for (size_t c = 0; c < sizeof j0s / sizeof *j0s; c++) {
            const uint32_t j0 = j0s[c], w = ws[c];
            for (uint32_t k = 0; k < K; k++) rc[k] = p.rows[k] + j0;
            assert_int_equal(sss_gather_gemm_isa(isa, M, w, K, p.W, K, rc, Qc, w, p.scratch), 1);
            for (uint32_t m = 0; m < M; m++)
                assert_memory_equal(Qc + (size_t)m * w, p.Q + (size_t)m * N + j0, w * sizeof(float));
        }
    }
    free(Qc);
    free(rc);
    drop(&p);
}

static void an_unknown_path_is_refused(void **state)
{
    (void)state;
    float Q[4] = {1, 2, 3, 4}, W[4] = {0}, scratch[4096 + 16];
    const float *rows[2] = {W, W};
    assert_true(sss_gather_gemm_scratch(2) <= 4096 + 16);
    assert_int_equal(sss_gather_gemm_isa(7, 2, 2, 2, W, 2, rows, Q, 2, scratch), 0);
    assert_true(Q[0] == 1.0f && Q[3] == 4.0f);
}

/* The dispatching entry takes a path this CPU has, with that path's bits. */
static void the_dispatch_takes_an_available_path(void **state)
{
    (void)state;
    const uint32_t M = 13, N = 57, K = 300;
    prob p = make(M, N, K);
    float *Qd = malloc(sizeof(float) * M * N);
    assert_non_null(Qd);
    sss_gather_gemm(M, N, K, p.W, K, p.rows, Qd, N, p.scratch);
    assert_int_equal(sss_gather_gemm_isa(sss_gather_gemm_best(), M, N, K, p.W, K, p.rows, p.Q, N, p.scratch), 1);
    assert_memory_equal(Qd, p.Q, sizeof(float) * M * N);
    free(Qd);
    drop(&p);
}

/* R_d / π from the polynomials against the double formula, at float x:
 * relative to f, or to 10⁻³ f(0) where f is smaller (the tail of a cutoff
 * at ε < 10⁻³, where a weight's error is below 10⁻⁹ of the nearest ones). */
static double profile_error(const sss_dipole *d, double R)
{
    sss_rdtab t;
    sss_rdtab_init(&t, d, R * R);
    const double rmin = sqrt(ldexp(1.0, t.e0)); /* the first octave's start */
    double worst = 0;
    const double floor = 1e-3 * sss_rd(d, 0.0) / SSS_PI;
    for (int k = 0; k <= 20000; k++) {
        const double r = rmin * pow(R / rmin, k / 20000.0);
        const float x = (float)(r * r);
        const double want = sss_rd(d, sqrt((double)x)) / SSS_PI, got = sss_rdtab_eval(&t, x);
        const double e = fabs(got - want) / (want > floor ? want : floor);
        if (e > worst) worst = e;
    }
    return worst;
}

static void profile_polynomials_match_rd(void **state)
{
    (void)state;
    static const char *names[] = {"marble", "skin1", "ketchup", "wholemilk"};
    for (size_t n = 0; n < sizeof names / sizeof *names; n++) {
        sss_material mat;
        sss_error err = {{0}};
        assert_int_equal(sss_material_preset(names[n], &mat, &err), SSS_OK);
        for (int c = 0; c < 3; c++) {
            sss_dipole d;
            assert_int_equal(sss_dipole_init(&d, mat.sigma_a[c], mat.sigmap_s[c], mat.eta), SSS_OK);
            /* the cutoff radius of the default ε = 10⁻³, and of ε = 10⁻⁶ */
            const double R = sss_rd_radius(&d, 1e-3, 1e6), R6 = sss_rd_radius(&d, 1e-6, 1e6);
            const double e1 = profile_error(&d, R), e2 = profile_error(&d, R6);
            if (e1 > 1e-6 || e2 > 1e-6)
                fail_msg("%s channel %d: R = %.3g / %.3g mm, worst relative error %.3g / %.3g", names[n], c, R, R6, e1,
                         e2);
            print_message("%s %d: R %.3g mm %.2e, R(1e-6) %.3g mm %.2e\n", names[n], c, R, e1, R6, e2);
        }
    }
}

static void profile_outside_its_range_is_finite(void **state)
{
    (void)state;
    sss_dipole d;
    assert_int_equal(sss_dipole_init(&d, 0.0021, 2.19, 1.5), SSS_OK);
    sss_rdtab t;
    sss_rdtab_init(&t, &d, 30.0 * 30.0);
    const double f0 = sss_rd(&d, 0.0) / SSS_PI;
    /* below the first octave: R_d's value at r = 0 to 10⁻⁴ */
    assert_true(fabs(sss_rdtab_eval(&t, 0.0f) - f0) <= 1e-4 * f0);
    assert_true(fabs(sss_rdtab_eval(&t, 1e-30f) - f0) <= 1e-4 * f0);
    /* beyond the last octave (sources past the cutoff, weight 0 anyway):
     * finite, never above the value at r = 0 */
    static const float far[] = {2048.0f, 1e6f, 3e38f};
    for (size_t k = 0; k < 3; k++) {
        const float v = sss_rdtab_eval(&t, far[k]);
        assert_true(isfinite(v) && fabs(v) <= f0);
    }
}

/* The weight rows by every path (the AVX-512 permutation kernel, the
 * compiler-vectorised loops) against sss_rdtab_eval times ΔA·in computed
 * here, bit for bit: three channels and one, lengths around the vector
 * width, and x at 0, subnormal, octave edges, the cutoff, beyond the table,
 * infinite and NaN. */
static void profile_paths_agree_bit_for_bit(void **state)
{
    (void)state;
    sss_material mat;
    sss_error err = {{0}};
    assert_int_equal(sss_material_preset("marble", &mat, &err), SSS_OK);
    sss_rdtab tab[3];
    const double R = 32.2;
    for (int c = 0; c < 3; c++) {
        sss_dipole d;
        assert_int_equal(sss_dipole_init(&d, mat.sigma_a[c], mat.sigmap_s[c], mat.eta), SSS_OK);
        sss_rdtab_init(&tab[c], &d, R * R);
    }
    enum { SMAX = 100 };
    float x[SMAX], dA[SMAX], in[SMAX], w[3 * SMAX + 8], ref[3 * SMAX];
    const float edge = ldexpf(1.0f, tab[0].e0 + 7);
    const float special[] = {0.0f, -0.0f, 1e-45f, 1e-40f, ldexpf(1.0f, tab[0].e0), nextafterf(edge, 0.0f), edge,
                             nextafterf(edge, 1e30f), (float)(R * R), (float)(1.5 * R * R), 3e38f, INFINITY, NAN};
    for (int k = 0; k < SMAX; k++) {
        x[k] = k < (int)(sizeof special / sizeof *special) ? special[k] : urand() * (float)(R * R);
        dA[k] = 0.01f + urand() * 0.1f;
        in[k] = (k % 5 == 3) ? 0.0f : 1.0f;
    }
    static const uint32_t Ss[] = {1, 15, 16, 17, 33, SMAX};
    static const uint32_t Cs[] = {3, 1};
    for (size_t ci = 0; ci < 2; ci++) {
        const uint32_t C = Cs[ci];
        for (size_t si = 0; si < sizeof Ss / sizeof *Ss; si++) {
            const uint32_t S = Ss[si];
            for (uint32_t c = 0; c < C; c++)
                for (uint32_t a = 0; a < S; a++) ref[c * S + a] = sss_rdtab_eval(&tab[c], x[a]) * (dA[a] * in[a]);
            int ran = 0;
            for (int isa = SSS_GEMM_PORTABLE; isa <= SSS_GEMM_AVX512; isa++) {
                for (size_t k = 0; k < sizeof w / sizeof *w; k++) w[k] = -1.0f; /* nothing past C·S is written */
                if (!sss_gather_rd_rows_isa(isa, tab, C, x, dA, in, S, w, S)) continue;
                ran++;
                for (uint32_t k = 0; k < C * S; k++)
                    if (memcmp(&w[k], &ref[k], sizeof(float)))
                        fail_msg("path %d, C %u, S %u: weight %u = %.9g, want %.9g (x = %.9g)", isa, C, S, k,
                                 (double)w[k], (double)ref[k], (double)x[k % S]);
                for (size_t k = C * S; k < sizeof w / sizeof *w; k++) assert_true(w[k] == -1.0f);
            }
            assert_true(ran >= 1);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(profile_polynomials_match_rd),
        cmocka_unit_test(profile_outside_its_range_is_finite),
        cmocka_unit_test(profile_paths_agree_bit_for_bit),
        cmocka_unit_test(paths_agree_bit_for_bit),
        cmocka_unit_test(empty_product_is_zero),
        cmocka_unit_test(columns_do_not_depend_on_the_others),
        cmocka_unit_test(an_unknown_path_is_refused),
        cmocka_unit_test(the_dispatch_takes_an_available_path),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
