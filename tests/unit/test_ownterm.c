/* test_ownterm.c: the own term split off at bake time and added back by the
 * reader (sss/ownterm.h, format 1.3 section OWNT; docs/accuracy.md "Where
 * the error comes from"). On a torus, whose inner side is shadowed by the
 * opposite side (cast shadows, not only the terminator):
 *  - at every direction sample the reader's rows + own term give back the
 *    q of the same bake without the split (1e-5 of the largest q);
 *  - the stored rest is never negative and never above q;
 *  - at random directions the per-vertex error against the exact
 *    evaluator is well below the unsplit file's (measured 0.055 vs 0.103:
 *    the torus is coarse, so its neighbours' shadows keep a large share);
 *  - the bytes do not depend on the thread count;
 *  - the reader refuses an OWNT section it does not understand, the writer
 *    an OWNT in a scene bake; compression keeps the mark. */
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
#include "sss/accuracy.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/exact.h"
#include "sss/ownterm.h"
#include "sss/recon.h"

static sss_mesh g_mesh;
static sss_bake_file g_plain, g_own; /* the same bake without and with the split, through encode/decode */

static void bake_or_fail(uint32_t own, int threads, sss_bake_file *out, uint8_t **bytes, size_t *nbytes)
{
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 100;
    opt.threads = threads;
    opt.own_term = own;
    sss_bake_file baked;
    if (sss_bake(&g_mesh, "torus", &mat, &opt, &baked, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&baked, &buf, &len, &err) != SSS_OK) fail_msg("encode: %s", err.msg);
    sss_file_free(&baked);
    if (out && sss_file_decode(buf, len, "torus.sss", out, &err) != SSS_OK) fail_msg("decode: %s", err.msg);
    if (bytes) {
        *bytes = buf;
        *nbytes = len;
    } else {
        free(buf);
    }
}

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    /* R = 1, r = 0.45: the hole is narrow enough for the inner side to
     * shadow itself over a wide range of light directions */
    if (sss_gen_torus(&g_mesh, 1.0, 0.45, 48, 24, &err) != SSS_OK) return -1;
    bake_or_fail(0, 2, &g_plain, NULL, NULL);
    bake_or_fail(SSS_OWN_TERM_RUNTIME, 2, &g_own, NULL, NULL);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sss_file_free(&g_plain);
    sss_file_free(&g_own);
    sss_mesh_free(&g_mesh);
    return 0;
}

static void fileIsMarked(void **state)
{
    (void)state;
    assert_int_equal(g_plain.own_term, 0);
    assert_int_equal(g_plain.version_minor, 0);
    assert_int_equal(g_own.own_term, SSS_OWN_TERM_RUNTIME);
    assert_int_equal(g_own.version_minor, 3);
    assert_non_null(strstr(g_own.params_json, "\"own_term\":\"runtime"));
}

/* Rows + own term at ω_j = the unsplit q_j; 0 ≤ rest ≤ q; and the split
 * takes something off (the own term is not empty). */
static void samplesRestoreQ(void **state)
{
    (void)state;
    const uint32_t nv = g_own.mesh.nv, C = g_own.channels, nd = g_own.dirs.n;
    const size_t row = (size_t)nv * C;
    sss_error err = {{0}};
    sss_recon *rc;
    assert_int_equal(sss_recon_create(&g_own, &rc, &err), SSS_OK);
    assert_true(sss_recon_has_own_term(rc));
    float *r = malloc(row * sizeof *r);
    assert_non_null(r);
    double qmax = 0.0, worst = 0.0, taken = 0.0, total = 0.0;
    for (size_t k = 0; k < (size_t)nd * row; k++) {
        qmax = fmax(qmax, g_plain.q[k]);
        assert_true(g_own.q[k] >= 0.0f);
        assert_true(g_own.q[k] <= g_plain.q[k] * (1.0f + 1e-6f) + 1e-30f);
        taken += g_plain.q[k] - g_own.q[k];
        total += g_plain.q[k];
    }
    for (uint32_t j = 0; j < nd; j++) {
        sss_recon_eval(rc, g_own.dirs.dir + 3 * (size_t)j, SSS_INTERP_TRIANGLE, r);
        for (size_t k = 0; k < row; k++) worst = fmax(worst, fabs((double)r[k] - g_plain.q[(size_t)j * row + k]));
    }
    print_message("own term: %.1f %% of all q; rows + own term vs unsplit q at the samples: max |diff| %.3g of max q\n",
                  100.0 * taken / total, worst / qmax);
    assert_true(taken > 0.1 * total);
    assert_true(worst <= 1e-5 * qmax);
    free(r);
    sss_recon_destroy(rc);
}

/* Between the samples the split file is much closer to the exact q. */
static void errorShrinksBetweenSamples(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_exact *e;
    assert_int_equal(sss_exact_create(&g_plain, &e, &err), SSS_OK);
    sss_vertex_error a, b;
    assert_int_equal(sss_vertex_error_vs_exact(&g_plain, e, 40, 7, &a, &err), SSS_OK);
    sss_exact_destroy(e);
    assert_int_equal(sss_exact_create(&g_own, &e, &err), SSS_OK);
    assert_int_equal(sss_vertex_error_vs_exact(&g_own, e, 40, 7, &b, &err), SSS_OK);
    sss_exact_destroy(e);
    const uint32_t C = g_plain.channels;
    print_message("per-vertex rel. RMS at 40 random directions: %.4f without the split, %.4f with it\n", a.rel_rms[C],
                  b.rel_rms[C]);
    assert_true(b.rel_rms[C] > 0.0);
    assert_true(b.rel_rms[C] < 0.6 * a.rel_rms[C]);
}

static void threadsGiveSameBytes(void **state)
{
    (void)state;
    uint8_t *b1, *b2;
    size_t n1, n2;
    bake_or_fail(SSS_OWN_TERM_RUNTIME, 1, NULL, &b1, &n1);
    bake_or_fail(SSS_OWN_TERM_RUNTIME, 2, NULL, &b2, &n2);
    assert_int_equal(n1, n2);
    assert_memory_equal(b1, b2, n1);
    free(b1);
    free(b2);
}

static uint32_t rd32(const uint8_t *p) { return p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24; }
static void wr32(uint8_t *p, uint32_t v)
{
    for (int k = 0; k < 4; k++) p[k] = (uint8_t)(v >> (8 * k));
}

/* An OWNT whose mode this reader does not know is refused by name; so is
 * OWNT in a file whose q rows are not a direction set of a plain bake. */
static void readerAndWriterRefuse(void **state)
{
    (void)state;
    sss_error err = {{0}};
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&g_own, &buf, &len, &err), SSS_OK);
    const uint32_t nsec = rd32(buf + 12);
    int found = 0;
    for (uint32_t i = 0; i < nsec; i++) {
        uint8_t *e = buf + 24 + 40 * (size_t)i;
        if (memcmp(e, "OWNT", 4) != 0) continue;
        found = 1;
        assert_true(rd32(e + 4) & 1u); /* required: an older reader must refuse */
        const uint64_t off = rd32(e + 8) | (uint64_t)rd32(e + 12) << 32;
        wr32(buf + off, 2);
        wr32(e + 32, sss_crc32(0, buf + off, 4));
    }
    assert_true(found);
    wr32(buf + 24 + 40 * (size_t)nsec, sss_crc32(0, buf, 24 + 40 * (size_t)nsec));
    sss_bake_file f;
    assert_int_equal(sss_file_decode(buf, len, "bad.sss", &f, &err), SSS_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "OWNT"));
    free(buf);

    sss_bake_file s = g_own;
    s.fx.mask = SSS_FX_DIR_SET | (g_own.channels == 3 ? SSS_FX_RGB : 0);
    assert_int_not_equal(sss_file_encode(&s, &buf, &len, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "OWNT"));
}

/* Compressing a split file keeps the mark (the rows compressed are the
 * rest, and the reader must still add the own term). */
static void compressionKeepsTheMark(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_compress_opts co;
    sss_compress_opts_default(&co);
    sss_bake_file c;
    assert_int_equal(sss_compress(&g_own, &co, &c, &err), SSS_OK);
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&c, &buf, &len, &err), SSS_OK);
    sss_file_free(&c);
    assert_int_equal(sss_file_decode(buf, len, "c.sss", &c, &err), SSS_OK);
    assert_int_equal(c.own_term, SSS_OWN_TERM_RUNTIME);
    assert_int_equal(c.version_minor, 3);
    sss_file_free(&c);
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fileIsMarked),
        cmocka_unit_test(samplesRestoreQ),
        cmocka_unit_test(errorShrinksBetweenSamples),
        cmocka_unit_test(threadsGiveSameBytes),
        cmocka_unit_test(readerAndWriterRefuse),
        cmocka_unit_test(compressionKeepsTheMark),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
