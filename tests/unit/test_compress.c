/* test_compress.c: compression of baked integrals after Hao–Varshney 2004
 * §4: SH-only coding (§4.1), reference points + barycentric weights (§4.2)
 * and SH-coded deltas (§4.3), their byte accounting and input checks. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/decode.h"

/* One small float bake shared by every test: blob (subdiv 3), skin1,
 * 20 mm per unit, 50 directions. */
static sss_bake_file g_file;

static int setup(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_blob(&m, 1.0, 3, &err) != SSS_OK) return -1;
    sss_material mat;
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) return -1;
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 50;
    opt.quant = SSS_QUANT_FLOAT;
    opt.threads = 2;
    sss_bake_stats st;
    sss_result r = sss_bake(&m, "blob", &mat, &opt, &g_file, &st, &err);
    sss_mesh_free(&m);
    if (r != SSS_OK) {
        fprintf(stderr, "bake failed: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sss_file_free(&g_file);
    return 0;
}

static double rel_error(const sss_compressed *cq)
{
    double rel[SSS_MAX_CHANNELS + 1], mx = 0;
    sss_error err = {{0}};
    if (sss_compressed_error(cq, &g_file, 200, 7, rel, &mx, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (!isfinite(rel[cq->channels]) || !isfinite(mx)) fail_msg("error not finite: %g, max %g", rel[cq->channels], mx);
    return rel[cq->channels];
}

/* ---- tests --------------------------------------------------------------- */

/* Fraction 1: every vertex is a reference, so at a direction sample the
 * reconstruction is the Lloyd-quantised stored value: within half the widest
 * gap between levels, or the distance from the top level to the maximum. */
static void fractionOneMatchesSamplesWithinLloydBound(void **state)
{
    (void)state;
    sss_compressed cq;
    sss_error err = {{0}};
    if (sss_compress(&g_file, 0, 1.0, &cq, &err) != SSS_OK) fail_msg("%s", err.msg);
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n;
    assert_int_equal(cq.nref, nv);
    assert_int_equal(cq.ncoded, 0);
    double bound[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) {
        const float *L = cq.levels + 256 * (size_t)c;
        double gap = 0.0, qmax = -INFINITY;
        for (int x = 1; x < 256; x++) gap = fmax(gap, (double)L[x] - L[x - 1]);
        for (size_t i = c; i < (size_t)nd * nv * C; i += C) qmax = fmax(qmax, g_file.q[i]);
        bound[c] = fmax(0.5 * gap, qmax - L[255]) * (1.0 + 1e-5) + 1e-6 * fabs(qmax);
        assert_true(bound[c] > 0.0 && bound[c] < 0.05 * qmax);
    }
    float *out = malloc((size_t)nv * C * sizeof *out);
    assert_non_null(out);
    for (uint32_t j = 0; j < nd; j++) {
        sss_compressed_eval(&cq, g_file.dirs.dir + 3 * (size_t)j, out);
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t c = 0; c < C; c++) {
                double want = g_file.q[((size_t)j * nv + v) * C + c], got = out[(size_t)v * C + c];
                if (!(fabs(got - want) <= bound[c]))
                    fail_msg("dir %u vertex %u channel %u: %.9g, stored %.9g (bound %g)", j, v, c, got, want, bound[c]);
            }
    }
    free(out);
    sss_compressed_free(&cq);
    assert_null(cq.levels);
}

/* order 8 has 64 coefficients: more than 50 samples, rejected (§4.1 needs
 * n² ≤ number of samples for least squares); order 7 (49) is accepted. */
static void orderWithMoreCoefficientsThanSamplesRejected(void **state)
{
    (void)state;
    sss_compressed cq;
    sss_error err = {{0}};
    assert_int_equal(sss_compress(&g_file, 8, 0.0, &cq, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "50"));
    assert_null(cq.sh_code);
    memset(&err, 0, sizeof err);
    if (sss_compress(&g_file, 7, 0.0, &cq, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(cq.ncoef, 49);
    sss_compressed_free(&cq);
}

static void shOnlyErrorDecreasesWithOrder(void **state)
{
    (void)state;
    double prev = INFINITY;
    for (uint32_t n = 1; n <= 4; n++) {
        sss_compressed cq;
        sss_error err = {{0}};
        if (sss_compress(&g_file, n, 0.0, &cq, &err) != SSS_OK) fail_msg("%s", err.msg);
        assert_int_equal(cq.nref, 0);
        assert_int_equal(cq.ncoded, g_file.mesh.nv);
        double e = rel_error(&cq);
        if (!(e < prev)) fail_msg("SH order %u: relative RMS %g, not below order %u's %g", n, e, n - 1, prev);
        prev = e;
        sss_compressed_free(&cq);
    }
    assert_true(prev < 0.5);
}

static void referenceDeltaOrder3BeatsOrder0(void **state)
{
    (void)state;
    sss_compressed c0, c3;
    sss_error err = {{0}};
    if (sss_compress(&g_file, 0, 0.05, &c0, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_compress(&g_file, 3, 0.05, &c3, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_true(c3.nref > 0 && c3.nref < g_file.mesh.nv);
    assert_int_equal(c3.nref + c3.ncoded, g_file.mesh.nv);
    /* every stored weight pair leaves a non-negative third */
    for (uint32_t k = 0; k < c3.ncoded; k++) assert_true((uint32_t)c3.w16[2 * k] + c3.w16[2 * k + 1] <= 65535u);
    float *out = malloc((size_t)g_file.mesh.nv * g_file.channels * sizeof *out);
    assert_non_null(out);
    const double light[3] = {0.3, -0.5, 0.8};
    sss_compressed_eval(&c3, light, out);
    for (size_t i = 0; i < (size_t)g_file.mesh.nv * g_file.channels; i++)
        if (!isfinite(out[i])) fail_msg("output %zu not finite", i);
    free(out);
    double e0 = rel_error(&c0), e3 = rel_error(&c3);
    if (!(e3 < e0)) fail_msg("order 3 delta: relative RMS %g, not below order 0's %g", e3, e0);
    sss_compressed_free(&c0);
    sss_compressed_free(&c3);
}

static void accountingSumsToTotal(void **state)
{
    (void)state;
    const double fr[2] = {0.0, 0.05};
    for (int t = 0; t < 2; t++) {
        sss_compressed cq;
        sss_error err = {{0}};
        if (sss_compress(&g_file, 3, fr[t], &cq, &err) != SSS_OK) fail_msg("%s", err.msg);
        sss_compressed_bytes b;
        sss_compressed_bytes_of(&cq, &b);
        uint64_t s = b.header + b.directions + b.ref_integrals + b.lloyd_tables + b.ref_vertex_list + b.vertex_tri +
                     b.ref_tri_table + b.weights + b.sh_codes + b.sh_scales;
        assert_int_equal(s, b.total);
        const uint64_t C = g_file.channels, nd = g_file.dirs.n;
        assert_int_equal(b.sh_codes, (uint64_t)cq.ncoded * C * 9);
        assert_int_equal(b.sh_scales, C * 9 * 4);
        assert_int_equal(b.ref_integrals, nd * cq.nref * C);
        assert_int_equal(b.weights, cq.nref ? (uint64_t)cq.ncoded * 4 : 0);
        assert_int_equal(b.vertex_tri, cq.nref ? (uint64_t)cq.ncoded * 4 : 0);
        assert_int_equal(b.ref_tri_table, (uint64_t)cq.nrt * 12);
        assert_int_equal(b.lloyd_tables, cq.nref ? C * 1024 : 0);
        assert_true(fabs(b.per_vertex - (double)b.total / g_file.mesh.nv) < 1e-9);
        sss_compressed_free(&cq);
    }
}

static void garbageInputsRejected(void **state)
{
    (void)state;
    sss_compressed cq;
    sss_error err = {{0}};
    assert_int_equal(sss_compress(NULL, 3, 0.0, &cq, &err), SSS_ERR_ARG);
    assert_true(err.msg[0] != 0);
    assert_int_equal(sss_compress(&g_file, 3, 0.0, NULL, &err), SSS_ERR_ARG);
    memset(&err, 0, sizeof err);
    assert_int_equal(sss_compress(&g_file, 9, 0.0, &cq, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "order 9"));
    memset(&err, 0, sizeof err);
    assert_int_equal(sss_compress(&g_file, 3, 1.5, &cq, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "fraction"));
    assert_int_equal(sss_compress(&g_file, 3, -0.1, &cq, &err), SSS_ERR_ARG);
    assert_int_equal(sss_compress(&g_file, 3, NAN, &cq, &err), SSS_ERR_ARG);
    memset(&err, 0, sizeof err);
    assert_int_equal(sss_compress(&g_file, 0, 0.0, &cq, &err), SSS_ERR_ARG);
    assert_true(err.msg[0] != 0);
    sss_bake_file q8 = g_file;
    q8.quant = SSS_QUANT_LLOYD8;
    memset(&err, 0, sizeof err);
    assert_int_equal(sss_compress(&q8, 3, 0.0, &cq, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "float"));
    double rel[4];
    assert_int_equal(sss_compressed_error(NULL, &g_file, 10, 1, rel, NULL, NULL, &err), SSS_ERR_ARG);
    sss_compressed_free(NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fractionOneMatchesSamplesWithinLloydBound),
        cmocka_unit_test(orderWithMoreCoefficientsThanSamplesRejected),
        cmocka_unit_test(shOnlyErrorDecreasesWithOrder),
        cmocka_unit_test(referenceDeltaOrder3BeatsOrder0),
        cmocka_unit_test(accountingSumsToTotal),
        cmocka_unit_test(garbageInputsRejected),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
