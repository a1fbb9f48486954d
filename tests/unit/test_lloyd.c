/* Lloyd-Max 8-bit quantiser tests. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>

#include "sss/lloyd.h"
#include "test_util.h"

static uint64_t rng = 0x9E3779B97F4A7C15ull;
static double urand(void) { return test_urand(&rng); }

static void quantiserIsOptimalEnoughOnSkewedData(void **state)
{
    (void)state;
    const size_t n = 200000;
    float *x = malloc(n * sizeof *x);
    uint8_t *idx = malloc(n);
    /* like baked integrals: ~40% exact zeros (shadowed / facing away), the
     * rest spread over two decades */
    for (size_t k = 0; k < n; k++) x[k] = urand() < 0.4 ? 0.0f : (float)(0.3 * pow(urand(), 3.0));
    float lv[256];
    double S, N;
    assert_int_equal(sss_lloyd8(x, n, 1, lv, idx, &S, &N, NULL), SSS_OK);
    for (int k = 1; k < 256; k++) assert_true(lv[k] >= lv[k - 1]);
    assert_true(lv[0] == 0.0f); /* pinned to the minimum: zeros decode to zeros */
    double S2 = 0, N2 = 0;
    for (size_t k = 0; k < n; k++) {
        if (x[k] == 0.0f) assert_int_equal(idx[k], 0);
        /* every value maps to its nearest level */
        double e = fabs((double)x[k] - lv[idx[k]]);
        if (idx[k] > 0) assert_true(e <= fabs((double)x[k] - lv[idx[k] - 1]));
        if (idx[k] < 255) assert_true(e <= fabs((double)x[k] - lv[idx[k] + 1]));
        S2 += (double)x[k] * x[k];
        N2 += e * e;
    }
    assert_true(fabs(S - S2) <= 1e-9 * S2 && fabs(N - N2) <= 1e-6 * N2);
    double snr = 10 * log10(S / N);
    /* a uniform 256-level quantiser over [0, max] gives ~45 dB here; Lloyd must beat it */
    double Su = 0, Nu = 0, step = 0.3 / 255;
    for (size_t k = 0; k < n; k++) {
        double r = round(x[k] / step) * step, e = x[k] - r;
        Su += (double)x[k] * x[k];
        Nu += e * e;
    }
    print_message("lloyd %.2f dB, uniform %.2f dB\n", snr, 10 * log10(Su / Nu));
    assert_true(snr > 10 * log10(Su / Nu) + 0.5);
    /* Lloyd's optimality condition: every level is the centroid of its cell */
    double sum[256] = {0}, cnt[256] = {0};
    for (size_t k = 0; k < n; k++) { sum[idx[k]] += x[k]; cnt[idx[k]] += 1; }
    for (int k = 1; k < 256; k++)
        if (cnt[k] > 0) assert_true(fabs(sum[k] / cnt[k] - lv[k]) <= 1e-5 * lv[255]);
    free(x);
    free(idx);
}

static void quantiserIsExactOnFewDistinctValues(void **state)
{
    (void)state;
    float x[1000];
    uint8_t idx[1000];
    float lv[256];
    double S, N;
    for (int k = 0; k < 1000; k++) x[k] = 0.25f;
    assert_int_equal(sss_lloyd8(x, 1000, 1, lv, idx, &S, &N, NULL), SSS_OK);
    assert_true(N == 0.0);
    for (int k = 0; k < 1000; k++) assert_true(lv[idx[k]] == 0.25f);
    for (int k = 0; k < 1000; k++) x[k] = (k % 3) ? 1.5f : 0.0f;
    assert_int_equal(sss_lloyd8(x, 1000, 1, lv, idx, &S, &N, NULL), SSS_OK);
    assert_true(N == 0.0);
    for (int k = 0; k < 1000; k++) assert_true(lv[idx[k]] == x[k]);
}

static void quantiserHonoursStride(void **state)
{
    (void)state;
    float x[3000];
    uint8_t idx[3000];
    for (int k = 0; k < 3000; k++) x[k] = (k % 3 == 1) ? (float)(k % 17) : -1.0f;
    for (int k = 0; k < 3000; k++) idx[k] = 77;
    float lv[256];
    double S, N;
    assert_int_equal(sss_lloyd8(x + 1, 1000, 3, lv, idx + 1, &S, &N, NULL), SSS_OK);
    assert_true(N == 0.0); /* 17 distinct values fit in 256 levels */
    for (int k = 0; k < 3000; k++) {
        if (k % 3 == 1) assert_true(lv[idx[k]] == x[k]);
        else assert_int_equal(idx[k], 77); /* other channels untouched */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(quantiserIsOptimalEnoughOnSkewedData),
        cmocka_unit_test(quantiserIsExactOnFewDistinctValues),
        cmocka_unit_test(quantiserHonoursStride),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
