/* test_interp.c: the paper's 4-nearest-direction interpolation
 * (Hao–Varshney 2004 §3.2, Fig. 3), kept beside our spherical-triangle
 * barycentrics for the accuracy study (docs/accuracy.md): the lookup picks the four
 * nearest samples with inverse-angle weights summing to 1 and is exact at
 * the samples; the decoder's NEAREST4 form blends the stored rows with
 * those weights, and its TRIANGLE form is sss_decode_all to the bit. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/decode.h"
#include "sss/dirset.h"
#include "sss/random.h"
#include "sss/vec3.h"


/* Random directions: the four indices are the four largest cosines (brute
 * force), weights positive, decreasing with angle, summing to 1. */
static void nearest4PicksNearestWithInverseAngleWeights(void **state)
{
    (void)state;
    sss_dirset s = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_fibonacci(&s, 200, &err), SSS_OK);
    uint64_t rng = 7;
    for (int t = 0; t < 500; t++) {
        double d[3];
        sss_rng_direction(&rng, d);
        uint32_t idx[4];
        double w[4];
        assert_int_equal(sss_dirset_nearest4(&s, d, idx, w), 4);
        double sum = 0.0;
        for (int k = 0; k < 4; k++) {
            assert_true(w[k] > 0.0);
            sum += w[k];
            if (k) assert_true(w[k] <= w[k - 1] + 1e-15);
        }
        assert_true(fabs(sum - 1.0) < 1e-12);
        /* no other sample is nearer than the fourth */
        const double c4 = sss_dot3(d, s.dir + 3 * (size_t)idx[3]);
        for (uint32_t j = 0; j < s.n; j++) {
            if (j == idx[0] || j == idx[1] || j == idx[2] || j == idx[3]) continue;
            assert_true(sss_dot3(d, s.dir + 3 * (size_t)j) <= c4 + 1e-15);
        }
        /* the length of d does not matter */
        double d2[3] = {5 * d[0], 5 * d[1], 5 * d[2]}, w2[4];
        uint32_t i2[4];
        sss_dirset_nearest4(&s, d2, i2, w2);
        for (int k = 0; k < 4; k++) assert_true(i2[k] == idx[k] && fabs(w2[k] - w[k]) < 1e-12);
    }
    sss_dirset_free(&s);
}

/* On a sample: that sample alone, weight 1. Zero or NaN: 0 samples. Fewer
 * than four samples: all of them. */
static void nearest4ExactAtSamplesAndEdgeCases(void **state)
{
    (void)state;
    sss_dirset s = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_fibonacci(&s, 50, &err), SSS_OK);
    uint32_t idx[4];
    double w[4];
    for (uint32_t j = 0; j < s.n; j++) {
        assert_int_equal(sss_dirset_nearest4(&s, s.dir + 3 * (size_t)j, idx, w), 1);
        assert_int_equal(idx[0], j);
        assert_true(w[0] == 1.0 && w[1] == 0.0 && w[2] == 0.0 && w[3] == 0.0);
    }
    const double zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 1};
    assert_int_equal(sss_dirset_nearest4(&s, zero, idx, w), 0);
    assert_true(w[0] == 1.0 && idx[0] == 0);
    assert_int_equal(sss_dirset_nearest4(&s, nan3, idx, w), 0);
    sss_dirset_free(&s);
    assert_int_equal(sss_dirset_fibonacci(&s, 3, &err), SSS_OK);
    const double d[3] = {0.3, -0.2, 0.9};
    assert_int_equal(sss_dirset_nearest4(&s, d, idx, w), 3);
    assert_true(fabs(w[0] + w[1] + w[2] - 1.0) < 1e-12 && w[3] == 0.0);
    sss_dirset_free(&s);
}

static void bake_blob(sss_quant quant, sss_bake_file *out)
{
    sss_mesh m;
    sss_material mat;
    sss_error err = {{0}};
    if (sss_gen_blob(&m, 1.0, 2, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 40;
    opt.quant = quant;
    opt.threads = 2;
    if (sss_bake(&m, "blob", &mat, &opt, out, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    sss_mesh_free(&m);
}

/* Decoder: NEAREST4 gives the stored row at a sample and a convex blend of
 * the four rows elsewhere; TRIANGLE is sss_decode_all to the bit. */
static void decodeNearest4BlendsStoredRows(void **state)
{
    (void)state;
    const sss_quant forms[2] = {SSS_QUANT_FLOAT, SSS_QUANT_LLOYD8};
    for (int fi = 0; fi < 2; fi++) {
        sss_bake_file f;
        bake_blob(forms[fi], &f);
        const size_t n = (size_t)f.mesh.nv * f.channels;
        float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
        assert_non_null(a);
        assert_non_null(b);
        for (uint32_t j = 0; j < f.dirs.n; j += 7) {
            sss_decode_all_interp(&f, f.dirs.dir + 3 * (size_t)j, SSS_INTERP_NEAREST4, a);
            for (size_t i = 0; i < n; i++)
                assert_true(a[i] == sss_decode_sample(&f, j, (uint32_t)(i / f.channels), (uint32_t)(i % f.channels)));
        }
        uint64_t rng = 11;
        for (int t = 0; t < 20; t++) {
            double d[3];
            sss_rng_direction(&rng, d);
            sss_decode_all(&f, d, a);
            sss_decode_all_interp(&f, d, SSS_INTERP_TRIANGLE, b);
            assert_memory_equal(a, b, n * sizeof *a);
            sss_decode_all_interp(&f, d, SSS_INTERP_NEAREST4, b);
            uint32_t idx[4];
            double w[4];
            sss_dirset_nearest4(&f.dirs, d, idx, w);
            for (size_t i = 0; i < n; i++) {
                const uint32_t v = (uint32_t)(i / f.channels), c = (uint32_t)(i % f.channels);
                double lo = INFINITY, hi = -INFINITY;
                for (int k = 0; k < 4; k++) {
                    double x = sss_decode_sample(&f, idx[k], v, c);
                    lo = fmin(lo, x);
                    hi = fmax(hi, x);
                }
                assert_true(b[i] >= lo - 1e-6 * fabs(hi) && b[i] <= hi + 1e-6 * fabs(hi));
            }
        }
        free(a);
        free(b);
        sss_file_free(&f);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(nearest4PicksNearestWithInverseAngleWeights),
        cmocka_unit_test(nearest4ExactAtSamplesAndEdgeCases),
        cmocka_unit_test(decodeNearest4BlendsStoredRows),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
