/* test_vector.c: the vector integral Q (Hao–Varshney 2004 §3.1–3.2,
 * section QVEC, docs/format.md §5.19): at every direction sample
 * Q_j·ω_j gives back the stored q_j whichever gather, weight rule and near
 * terms made them; the decoder reproduces the stored values at the
 * samples; where every source has the same normal (a plane) Q_j is that
 * normal scaled by q_j / (n·ω_j), and lit head-on Q and q agree; the file
 * round-trips Q and refuses a corrupted QVEC with a message naming the
 * file and the section; files without Q keep their version. */
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
#include "sss/format.h"
#include "sss/nearterms.h"
#include "test_util.h"

#define HDR 24u /* docs/format.md §2: header bytes, section table entry bytes */
#define ENT 40u

static void bake_blob(int gather, uint32_t weights, int near, sss_quant quant, sss_bake_file *f)
{
    sss_mesh mesh = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&mesh, 1.0, 2, &err), SSS_OK);
    sss_material m;
    assert_int_equal(sss_material_preset("skin1", &m, &err), SSS_OK);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = 10.0;
    o.n_dirs = 40;
    o.quant = quant;
    o.gather = gather;
    o.weights = weights;
    o.vector = 1;
    if (near) {
        o.near_terms = SSS_NEAR_TERMS_RUNTIME;
        o.near_fraction = SSS_NEAR_FRACTION_DEFAULT;
    }
    sss_bake_stats st;
    sss_result r = sss_bake(&mesh, "blob", &m, &o, f, &st, &err);
    if (r != SSS_OK) fail_msg("%s", err.msg);
    assert_non_null(f->qvec);
    sss_mesh_free(&mesh);
}

/* max_j,v,c |Q_j·ω_j − q_j| over max q (the q rows as stored, float) */
static double dot_error(const sss_bake_file *f)
{
    double num = 0.0, den = 0.0;
    for (uint32_t j = 0; j < f->dirs.n; j++) {
        const double *w = f->dirs.dir + 3 * (size_t)j;
        for (uint32_t v = 0; v < f->mesh.nv; v++)
            for (uint32_t c = 0; c < f->channels; c++) {
                float Q[3];
                sss_decode_vector_sample(f, j, v, c, Q);
                const double q = f->q[((size_t)j * f->mesh.nv + v) * f->channels + c];
                const double dq = Q[0] * w[0] + Q[1] * w[1] + Q[2] * w[2];
                /* q rows with the near terms split off are clamped at 0
                 * (near_terms.c); Q's components are not */
                const double e = fabs((f->near_terms ? fmax(dq, 0.0) : dq) - q);
                num = e > num ? e : num;
                den = q > den ? q : den;
            }
    }
    assert_true(den > 0.0);
    return num / den;
}

static void vectorDotsToScalarAtSamplesForEveryGather(void **state)
{
    (void)state;
    const struct { int gather; uint32_t weights; int near; } cases[] = {
        {SSS_GATHER_DIRECT, SSS_WEIGHTS_POINT, 0}, {SSS_GATHER_DIRECT, SSS_WEIGHTS_HAT, 1},
        {SSS_GATHER_TREE, SSS_WEIGHTS_POINT, 0},   {SSS_GATHER_TREE, SSS_WEIGHTS_HAT, 0},
        {SSS_GATHER_TREE, SSS_WEIGHTS_HAT, 1}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        sss_bake_file f;
        bake_blob(cases[k].gather, cases[k].weights, cases[k].near, SSS_QUANT_FLOAT, &f);
        const double e = dot_error(&f);
        /* sums of float terms in double, each rounded once to float; the tree's
         * far field is linear in the sources, so its error is the same in q and Q */
        /* with the near terms split off, q_j and Q_j·ω_j are each what
         * remains after subtracting float sums (sss_near_sum) of terms that
         * together are several times the rest */
        if (!(e < (cases[k].near ? 1e-4 : 2e-5))) fail_msg("case %zu: max |Q_j.w_j - q_j| / max q = %g", k, e);
        sss_file_free(&f);
    }
}

/* At a direction sample the decoder's weights are (1, 0, 0) up to
 * rounding: q̃ = Q_j·ω_j = q_j, for both interpolations. */
static void vectorDecodeReproducesStoredSamples(void **state)
{
    (void)state;
    sss_bake_file f;
    bake_blob(SSS_GATHER_TREE, SSS_WEIGHTS_HAT, 0, SSS_QUANT_FLOAT, &f);
    assert_true(sss_decode_has_vector(&f));
    const uint32_t nv = f.mesh.nv, C = f.channels;
    float *out = malloc((size_t)nv * C * sizeof *out), *ref = malloc((size_t)nv * C * sizeof *ref);
    assert_non_null(out);
    assert_non_null(ref);
    double qmax = 0.0;
    for (size_t i = 0; i < (size_t)f.dirs.n * nv * C; i++) qmax = fmax(qmax, f.q[i]);
    for (int interp = 0; interp < 2; interp++)
        for (uint32_t j = 0; j < f.dirs.n; j++) {
            const double *w = f.dirs.dir + 3 * (size_t)j;
            sss_decode_vector_range(&f, w, (sss_interp)interp, 0, nv, out);
            for (uint32_t v = 0; v < nv; v++)
                for (uint32_t c = 0; c < C; c++) {
                    const double q = f.q[((size_t)j * nv + v) * C + c];
                    if (!(fabs(out[v * C + c] - q) <= 2e-5 * qmax))
                        fail_msg("interp %d sample %u vertex %u: decoded %g, stored %g", interp, j, v,
                                 (double)out[v * C + c], q);
                }
        }
    /* a range is the slice of the whole, to the bit */
    const double l[3] = {0.3, -0.5, 0.8};
    sss_decode_vector_range(&f, l, SSS_INTERP_TRIANGLE, 0, nv, out);
    sss_decode_vector_range(&f, l, SSS_INTERP_TRIANGLE, 7, nv - 20, ref);
    assert_memory_equal(out + 7 * C, ref, (size_t)(nv - 20) * C * sizeof *out);
    free(out);
    free(ref);
    sss_file_free(&f);
}

/* A plane: every source has the normal n = +z, so Q_j = (q_j / n·ω_j) n
 * (the irradiance direction does not vary); lit head-on, Q̃·n and q̃
 * differ only by the cosines of the samples around n, which q̃ carries
 * and Q̃ does not (Hao–Varshney 2004 §3.2). */
static void vectorParallelToNormalOnPlaneAndAgreesHeadOn(void **state)
{
    (void)state;
    sss_mesh mesh = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_gen_plane(&mesh, 1.0, 1.0, 24, 24, &err), SSS_OK);
    sss_material m;
    assert_int_equal(sss_material_preset("marble", &m, &err), SSS_OK);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = 20.0;
    o.n_dirs = 60;
    o.quant = SSS_QUANT_FLOAT;
    o.vector = 1;
    sss_bake_file f;
    sss_bake_stats st;
    assert_int_equal(sss_bake(&mesh, "plane", &m, &o, &f, &st, &err), SSS_OK);
    const uint32_t nv = f.mesh.nv, C = f.channels;
    for (uint32_t v = 0; v < nv; v++) assert_true(f.mesh.nrm[3 * v + 2] == 1.0f);
    for (uint32_t j = 0; j < f.dirs.n; j++) {
        const double *w = f.dirs.dir + 3 * (size_t)j;
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t c = 0; c < C; c++) {
                float Q[3];
                sss_decode_vector_sample(&f, j, v, c, Q);
                const double q = f.q[((size_t)j * nv + v) * C + c];
                assert_true(Q[0] == 0.0f && Q[1] == 0.0f);
                if (w[2] <= 0.0) assert_true(Q[2] == 0.0f && q == 0.0);
                else assert_true(fabs(Q[2] - q / w[2]) <= 1e-5 * fmax(q / w[2], 1e-30));
            }
    }
    /* head-on */
    const double n[3] = {0.0, 0.0, 1.0};
    uint32_t idx[3];
    double wt[3];
    sss_dirset_lookup(&f.dirs, n, idx, wt);
    double cmin = 1.0;
    for (int t = 0; t < 3; t++) cmin = fmin(cmin, f.dirs.dir[3 * (size_t)idx[t] + 2]);
    assert_true(cmin > 0.8);
    float *qv = malloc((size_t)nv * C * sizeof *qv), *qs = malloc((size_t)nv * C * sizeof *qs);
    assert_non_null(qv);
    assert_non_null(qs);
    sss_decode_vector_range(&f, n, SSS_INTERP_TRIANGLE, 0, nv, qv);
    sss_decode_all(&f, n, qs);
    double lo = 1e30, hi = 0.0;
    for (size_t i = 0; i < (size_t)nv * C; i++) {
        if (!(qs[i] > 0.0f)) continue;
        const double ratio = qs[i] / (double)qv[i];
        lo = fmin(lo, ratio);
        hi = fmax(hi, ratio);
    }
    /* q̃ = Σ w_t (n·ω_t) q_t/(n·ω_t) against Q̃·n = Σ w_t q_t/(n·ω_t) */
    assert_true(lo >= cmin - 1e-5 && hi <= 1.0 + 1e-5);
    assert_true(hi > lo - 1e-12);
    free(qv);
    free(qs);
    sss_file_free(&f);
    sss_mesh_free(&mesh);
}

/* The table entry of section tag in an encoded file, or NULL. */
static uint8_t *entry(uint8_t *b, const char *tag)
{
    const uint32_t n = test_rd32(b + 12);
    for (uint32_t i = 0; i < n; i++)
        if (!memcmp(b + HDR + ENT * i, tag, 4)) return b + HDR + ENT * i;
    return NULL;
}

static void put64(uint8_t *p, uint64_t x)
{
    for (int k = 0; k < 8; k++) p[k] = (uint8_t)(x >> (8 * k));
}

/* The section's CRC over its (possibly edited) data, then the header's. */
static void fix_crcs(uint8_t *b, uint8_t *e)
{
    const uint32_t n = test_rd32(b + 12);
    const uint32_t c = sss_crc32(0, b + test_rd64(e + 8), (size_t)test_rd64(e + 16));
    for (int k = 0; k < 4; k++) e[32 + k] = (uint8_t)(c >> (8 * k));
    const uint32_t h = sss_crc32(0, b, HDR + ENT * (size_t)n);
    for (int k = 0; k < 4; k++) b[HDR + ENT * n + k] = (uint8_t)(h >> (8 * k));
}

static void expect_refused(const uint8_t *b, size_t len, const char *what)
{
    sss_bake_file g;
    sss_error err = {{0}};
    const sss_result r = sss_file_decode(b, len, "bad.sss", &g, &err);
    if (r == SSS_OK) fail_msg("%s: accepted", what);
    if (!strstr(err.msg, "bad.sss") || !strstr(err.msg, "QVEC") || strchr(err.msg, '\n'))
        fail_msg("%s: message '%s' does not name the file and section QVEC on one line", what, err.msg);
}

static void vectorFileRoundTripsAndCorruptionIsRefused(void **state)
{
    (void)state;
    sss_bake_file f;
    bake_blob(SSS_GATHER_TREE, SSS_WEIGHTS_HAT, 1, SSS_QUANT_LLOYD8, &f);
    uint8_t *buf = NULL;
    size_t len = 0;
    sss_error err = {{0}};
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    assert_int_equal(buf[10] | buf[11] << 8, 7); /* written with QVEC's minor version (§4) */
    sss_bake_file g;
    assert_int_equal(sss_file_decode(buf, len, "ok.sss", &g, &err), SSS_OK);
    assert_int_equal(g.quant, SSS_QUANT_LLOYD8);
    const size_t nQ = 3 * (size_t)f.dirs.n * f.mesh.nv * f.channels;
    assert_non_null(g.qvec);
    assert_memory_equal(g.qvec, f.qvec, nQ * sizeof *f.qvec);
    sss_file_free(&g);

    uint8_t *b = malloc(len);
    assert_non_null(b);
    /* a NaN, and a value beyond SSS_VALUE_MAX, with fresh CRCs */
    const float bad[2] = {NAN, 1e30f};
    for (int k = 0; k < 2; k++) {
        memcpy(b, buf, len);
        uint8_t *e = entry(b, "QVEC");
        assert_non_null(e);
        memcpy(b + test_rd64(e + 8) + 4 * 123, &bad[k], 4);
        fix_crcs(b, e);
        expect_refused(b, len, k ? "huge value" : "NaN");
    }
    /* a count that does not match the counts of GEOM, DIRS and MATL */
    memcpy(b, buf, len);
    uint8_t *e = entry(b, "QVEC");
    e[24] ^= 3;
    fix_crcs(b, e);
    expect_refused(b, len, "count");
    /* a section four bytes short: its last value cut, the sections after
     * it moved up, every offset and the file size put right */
    memcpy(b, buf, len);
    e = entry(b, "QVEC");
    const uint64_t end = test_rd64(e + 8) + test_rd64(e + 16);
    memmove(b + end - 4, b + end, len - end);
    put64(e + 16, test_rd64(e + 16) - 4);
    put64(b + 16, len - 4);
    for (uint32_t i = 0; i < test_rd32(b + 12); i++) {
        uint8_t *ei = b + HDR + ENT * i;
        if (test_rd64(ei + 8) >= end) put64(ei + 8, test_rd64(ei + 8) - 4);
    }
    fix_crcs(b, e);
    expect_refused(b, len - 4, "size");
    free(b);
    free(buf);

    /* without Q the file is what it was: no QVEC, the version of its other sections */
    free(f.qvec);
    f.qvec = NULL;
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    assert_null(entry(buf, "QVEC"));
    assert_true((buf[10] | buf[11] << 8) < 7);
    free(buf);
    sss_file_free(&f);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(vectorDotsToScalarAtSamplesForEveryGather),
        cmocka_unit_test(vectorDecodeReproducesStoredSamples),
        cmocka_unit_test(vectorParallelToNormalOnPlaneAndAgreesHeadOn),
        cmocka_unit_test(vectorFileRoundTripsAndCorruptionIsRefused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
