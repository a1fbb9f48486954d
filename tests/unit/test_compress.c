/* test_compress.c: the compressed storage forms of format 1.1 after
 * Hao–Varshney 2004 §4: SH-only coding (§4.1), reference points + weights
 * (§4.2) and SH-coded deltas (§4.3); their decoder (sss_decode_all /
 * sss_decode_vertex), byte accounting, file round trip, input checks, and a
 * reader that survives damaged REFS / SHC sections. */
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
#include "sss/random.h"
#include "sss/sh.h"
#include "test_util.h"

/* One small float bake shared by every test: blob (subdiv 3), skin1,
 * 20 mm per unit, 50 directions, RGB. */
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

static void compress_or_fail(uint32_t order, double fraction, uint32_t kind, int ls, sss_bake_file *out)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = order;
    o.fraction = fraction;
    o.sh_kind = kind;
    o.ls_weights = ls;
    sss_error err = {{0}};
    if (sss_compress(&g_file, &o, out, &err) != SSS_OK) fail_msg("compress(order %u, fraction %g): %s", order,
                                                                 fraction, err.msg);
}

static double rel_error(const sss_bake_file *cf)
{
    double rel[SSS_MAX_CHANNELS + 1], mx = 0;
    sss_error err = {{0}};
    if (sss_decode_error(cf, &g_file, 200, 7, rel, NULL, &mx, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (!isfinite(rel[cf->channels]) || !isfinite(mx)) fail_msg("error not finite: %g, max %g", rel[cf->channels], mx);
    return rel[cf->channels];
}

/* Encodes and decodes f; the decoded copy must reconstruct exactly the same
 * floats at a few light directions. */
static void expect_file_round_trip(const sss_bake_file *f)
{
    uint8_t *buf;
    size_t len;
    sss_error err = {{0}};
    if (sss_file_encode(f, &buf, &len, &err) != SSS_OK) fail_msg("encode: %s", err.msg);
    sss_bake_file g;
    if (sss_file_decode(buf, len, "rt.sss", &g, &err) != SSS_OK) fail_msg("decode: %s", err.msg);
    assert_int_equal(g.quant, f->quant);
    /* compressed forms are 1.1; a bake that records its ε (NBHD) is 1.4;
     * 16-bit SH codes are 1.7 (docs/format.md §5.8) */
    assert_int_equal(g.version_minor, f->sh.kind == SSS_SHQ_LINEAR16 ? 7 : f->eps > 0 ? 4 : 1);
    sss_storage s;
    sss_file_storage(&g, &s);
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    uint64_t seed = 3;
    for (int t = 0; t < 5; t++) {
        double l[3];
        sss_rng_direction(&seed, l);
        sss_decode_all(f, l, a);
        sss_decode_all(&g, l, b);
        assert_memory_equal(a, b, n * sizeof *a);
    }
    /* the accounted bytes are exactly the sizes of the scattering sections */
    uint64_t sect = 0;
    for (uint32_t i = 0; i < g.nsections; i++)
        if (!strcmp(g.sections[i].tag, "REFS") || !strcmp(g.sections[i].tag, "SHC ")) sect += g.sections[i].size;
    assert_int_equal(sect, s.scattering);
    free(a);
    free(b);
    free(buf);
    sss_file_free(&g);
}

/* ---- tests --------------------------------------------------------------- */

/* Fraction 1: every vertex is a reference, so at a direction sample the
 * reconstruction is the Lloyd-quantised stored value: within half the widest
 * gap between levels, or the distance from the top level to the maximum. */
static void fractionOneMatchesSamplesWithinLloydBound(void **state)
{
    (void)state;
    sss_bake_file cf;
    compress_or_fail(0, 1.0, SSS_SHQ_LINEAR8, 0, &cf);
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n;
    assert_int_equal(cf.quant, SSS_QUANT_REFS);
    assert_int_equal(cf.ref.nref, nv);
    assert_int_equal(cf.sh.ncoded, 0);
    double bound[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) {
        const float *L = cf.ref.levels + 256 * (size_t)c;
        double gap = 0.0, qmax = -INFINITY;
        for (int x = 1; x < 256; x++) gap = fmax(gap, (double)L[x] - L[x - 1]);
        for (size_t i = c; i < (size_t)nd * nv * C; i += C) qmax = fmax(qmax, g_file.q[i]);
        bound[c] = fmax(0.5 * gap, qmax - L[255]) * (1.0 + 1e-5) + 1e-6 * fabs(qmax);
        assert_true(bound[c] > 0.0 && bound[c] < 0.05 * qmax);
    }
    float *out = malloc((size_t)nv * C * sizeof *out);
    assert_non_null(out);
    for (uint32_t j = 0; j < nd; j++) {
        sss_decode_all(&cf, g_file.dirs.dir + 3 * (size_t)j, out);
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t c = 0; c < C; c++) {
                double want = g_file.q[((size_t)j * nv + v) * C + c], got = out[(size_t)v * C + c];
                if (!(fabs(got - want) <= bound[c]))
                    fail_msg("dir %u vertex %u channel %u: %.9g, stored %.9g (bound %g)", j, v, c, got, want, bound[c]);
            }
    }
    free(out);
    expect_file_round_trip(&cf);
    sss_file_free(&cf);
}

/* SH-only, linear 8-bit codes: at every direction sample the decoded value
 * is the unquantised least-squares fit, clamped at 0, within the code bound
 * Σ_i |y_i(ω_j)| · scale_i / 254 (half a code step per coefficient). */
static void shOnlyMatchesFitAtSamplesWithinCodeBound(void **state)
{
    (void)state;
    const uint32_t order = 4;
    sss_bake_file cf;
    compress_or_fail(order, 0.0, SSS_SHQ_LINEAR8, 0, &cf);
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n, ncoef = order * order;
    sss_sh_projector *p;
    sss_error err = {{0}};
    if (sss_sh_projector_create(&g_file.dirs, order, SSS_SH_LEAST_SQUARES, &p, &err) != SSS_OK) fail_msg("%s", err.msg);
    double *x = malloc((size_t)nd * sizeof *x);
    float *out = malloc((size_t)nv * C * sizeof *out);
    assert_non_null(x);
    assert_non_null(out);
    double worst = 0.0;
    for (uint32_t j = 0; j < nd; j++) {
        const double *dj = g_file.dirs.dir + 3 * (size_t)j;
        double y[SSS_SH_MAX_COUNT];
        sss_sh_eval(order, dj, y);
        sss_decode_all(&cf, dj, out);
        for (uint32_t v = 0; v < nv; v += 7)
            for (uint32_t c = 0; c < C; c++) {
                double coef[SSS_SH_MAX_COUNT], fit = 0.0, bound = 0.0;
                for (uint32_t i = 0; i < nd; i++) x[i] = g_file.q[((size_t)i * nv + v) * C + c];
                sss_sh_project(p, x, coef);
                for (uint32_t i = 0; i < ncoef; i++) {
                    fit += coef[i] * y[i];
                    bound += fabs(y[i]) * cf.sh.scale[c * ncoef + i] / 254.0;
                }
                double got = out[(size_t)v * C + c], want = fmax(fit, 0.0);
                bound = bound * (1.0 + 1e-4) + 1e-6 * fabs(want);
                if (!(fabs(got - want) <= bound))
                    fail_msg("dir %u vertex %u channel %u: %.9g, fit %.9g (bound %g)", j, v, c, got, want, bound);
                worst = fmax(worst, fabs(got - want) / bound);
            }
    }
    assert_true(worst > 0.05); /* the bound is not vacuous: codes do round */
    free(x);
    free(out);
    sss_sh_projector_destroy(p);
    expect_file_round_trip(&cf);
    sss_file_free(&cf);
}

/* Largest |decoded − fit| at the direction samples of an SH-only file, over
 * every 3rd vertex and every channel (the fit as in the test above). */
static double sh_only_max_error(const sss_bake_file *cf)
{
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n, order = cf->sh.order;
    sss_sh_projector *p;
    sss_error err = {{0}};
    if (sss_sh_projector_create(&g_file.dirs, order, SSS_SH_LEAST_SQUARES, &p, &err) != SSS_OK) fail_msg("%s", err.msg);
    double *x = malloc((size_t)nd * sizeof *x), worst = 0.0;
    float *out = malloc((size_t)nv * C * sizeof *out);
    assert_non_null(x);
    assert_non_null(out);
    for (uint32_t j = 0; j < nd; j++) {
        const double *dj = g_file.dirs.dir + 3 * (size_t)j;
        double y[SSS_SH_MAX_COUNT];
        sss_sh_eval(order, dj, y);
        sss_decode_all(cf, dj, out);
        for (uint32_t v = 0; v < nv; v += 3)
            for (uint32_t c = 0; c < C; c++) {
                double coef[SSS_SH_MAX_COUNT], fit = 0.0;
                for (uint32_t i = 0; i < nd; i++) x[i] = g_file.q[((size_t)i * nv + v) * C + c];
                sss_sh_project(p, x, coef);
                for (uint32_t i = 0; i < order * order; i++) fit += coef[i] * y[i];
                worst = fmax(worst, fabs(out[(size_t)v * C + c] - fmax(fit, 0.0)));
            }
    }
    free(x);
    free(out);
    sss_sh_projector_destroy(p);
    return worst;
}

/* SH-only, the paper's 16-bit codes (§4.1, order 7 as its 98 bytes): every
 * stored coefficient (int16)code · scale / 32767 is the least-squares fit's
 * within half a code step, scale / 65534 (plus the fit's rounding to float
 * before quantisation, ≤ 2^-23 |c|); the bound is not vacuous (some codes
 * round by more than 0.3 of it); and the decoded q is at least 50 times
 * closer to the fit than with the 8-bit codes. The file says 1.7 and reads
 * back to the same decode. */
static void shOnlyLinear16WithinHalfCodeStep(void **state)
{
    (void)state;
    const uint32_t order = 7, ncoef = order * order;
    sss_bake_file cf, c8;
    compress_or_fail(order, 0.0, SSS_SHQ_LINEAR16, 0, &cf);
    assert_int_equal(cf.sh.kind, SSS_SHQ_LINEAR16);
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n;
    sss_storage st;
    sss_file_storage(&cf, &st);
    assert_int_equal(st.sh_codes, (uint64_t)nv * C * ncoef * 2); /* 98 bytes per vertex and channel */
    assert_int_equal(st.sh_tables, (uint64_t)C * ncoef * 4);     /* one scale per (channel, coefficient) */
    sss_sh_projector *p;
    sss_error err = {{0}};
    if (sss_sh_projector_create(&g_file.dirs, order, SSS_SH_LEAST_SQUARES, &p, &err) != SSS_OK) fail_msg("%s", err.msg);
    double *x = malloc((size_t)nd * sizeof *x), worst = 0.0;
    assert_non_null(x);
    for (uint32_t v = 0; v < nv; v++)
        for (uint32_t c = 0; c < C; c++) {
            double coef[SSS_SH_MAX_COUNT];
            for (uint32_t j = 0; j < nd; j++) x[j] = g_file.q[((size_t)j * nv + v) * C + c];
            sss_sh_project(p, x, coef);
            for (uint32_t i = 0; i < ncoef; i++) {
                const uint64_t e = ((uint64_t)v * C + c) * ncoef + i;
                const double sc = cf.sh.scale[c * ncoef + i];
                const int code = (int16_t)sss_shq_code(cf.sh.code, SSS_SHQ_LINEAR16, e);
                assert_true(code >= -32767 && code <= 32767);
                const double got = code * sc / 32767.0, half = 0.5 * sc / 32767.0;
                const double bound = half * (1.0 + 1e-6) + fabs(coef[i]) * 0x1p-23;
                if (!(fabs(got - coef[i]) <= bound))
                    fail_msg("vertex %u channel %u coefficient %u: %.9g, fit %.9g (half a step %g)", v, c, i, got,
                             coef[i], half);
                if (half > 0.0) worst = fmax(worst, fabs(got - coef[i]) / half);
            }
        }
    assert_true(worst > 0.3);
    free(x);
    sss_sh_projector_destroy(p);
    compress_or_fail(order, 0.0, SSS_SHQ_LINEAR8, 0, &c8);
    const double e16 = sh_only_max_error(&cf), e8 = sh_only_max_error(&c8);
    if (!(e16 * 50.0 < e8)) fail_msg("16-bit codes' error %g is not 50 times below the 8-bit codes' %g", e16, e8);
    expect_file_round_trip(&cf);
    sss_file_free(&c8);
    sss_file_free(&cf);
}

/* order 8 has 64 coefficients: more than 50 samples, rejected (§4.1 needs
 * n² ≤ number of samples for least squares); order 7 (49) is accepted. */
static void orderWithMoreCoefficientsThanSamplesRejected(void **state)
{
    (void)state;
    sss_bake_file cf;
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = 8;
    o.fraction = 0.0;
    sss_error err = {{0}};
    assert_int_equal(sss_compress(&g_file, &o, &cf, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "50"));
    assert_null(cf.sh.code);
    compress_or_fail(7, 0.0, SSS_SHQ_LINEAR8, 0, &cf);
    assert_int_equal(cf.sh.ncoef, 49);
    sss_file_free(&cf);
}

/* Least squares at nested orders can only lower the residual at the
 * samples; between them (random test directions, where the reference is the
 * interpolated bake) a step of one band may not help (here order 4 is a
 * little worse than 3: band 3 is odd and the data nearly even), but every
 * two bands must, and no band may make things much worse. */
static void shOnlyErrorDecreasesWithOrder(void **state)
{
    (void)state;
    double e[7];
    for (uint32_t n = 1; n <= 6; n++) {
        sss_bake_file cf;
        compress_or_fail(n, 0.0, SSS_SHQ_LLOYD8, 0, &cf);
        assert_int_equal(cf.quant, SSS_QUANT_SH);
        assert_int_equal(cf.sh.ncoded, g_file.mesh.nv);
        e[n] = rel_error(&cf);
        sss_file_free(&cf);
    }
    for (uint32_t n = 3; n <= 6; n++)
        if (!(e[n] < e[n - 2])) fail_msg("SH order %u: relative RMS %g, not below order %u's %g", n, e[n], n - 2, e[n - 2]);
    for (uint32_t n = 2; n <= 6; n++)
        if (!(e[n] < 1.1 * e[n - 1])) fail_msg("SH order %u: relative RMS %g, far above order %u's %g", n, e[n], n - 1, e[n - 1]);
    if (!(e[6] < 0.5 * e[1])) fail_msg("order 6 (%g) not half of order 1 (%g)", e[6], e[1]);
}

static void referenceDeltaOrder3BeatsOrder0(void **state)
{
    (void)state;
    sss_bake_file c0, c3;
    compress_or_fail(0, 0.05, SSS_SHQ_LINEAR8, 0, &c0);
    compress_or_fail(3, 0.05, SSS_SHQ_LINEAR8, 0, &c3);
    const uint32_t nv = g_file.mesh.nv;
    assert_true(c3.ref.nref > 0 && c3.ref.nref < nv);
    assert_int_equal(c3.ref.nref + c3.sh.ncoded, nv);
    /* every stored barycentric pair leaves a non-negative third */
    for (uint32_t k = 0; k < c3.sh.ncoded; k++) assert_true((uint32_t)c3.ref.w[2 * k] + c3.ref.w[2 * k + 1] <= 65535u);
    double e0 = rel_error(&c0), e3 = rel_error(&c3);
    if (!(e3 < e0)) fail_msg("order 3 delta: relative RMS %g, not below order 0's %g", e3, e0);
    expect_file_round_trip(&c0);
    expect_file_round_trip(&c3);
    sss_file_free(&c0);
    sss_file_free(&c3);
}

/* Beyond the paper: least-squares weights minimise what the SH delta cannot
 * represent, so with the same references they cannot do worse than the
 * barycentrics they start from (up to quantisation noise). */
static void leastSquaresWeightsBeatBarycentrics(void **state)
{
    (void)state;
    sss_bake_file b, l;
    compress_or_fail(2, 0.05, SSS_SHQ_LLOYD8, 0, &b);
    compress_or_fail(2, 0.05, SSS_SHQ_LLOYD8, 1, &l);
    assert_int_equal(b.ref.nref, l.ref.nref);
    assert_true(l.ref.w_lo < 0.0f && l.ref.w_hi > 1.0f);
    double eb = rel_error(&b), el = rel_error(&l);
    if (!(el < eb)) fail_msg("least-squares weights: relative RMS %g, not below barycentric %g", el, eb);
    expect_file_round_trip(&l);
    sss_file_free(&b);
    sss_file_free(&l);
}

/* Where every reference row is the same (constant q: a degenerate least-
 * squares system, all corners alike), the least-squares weights fall back
 * to the closest-point barycentrics: finite, in [0, 1], summing to 1; and
 * the reconstruction is the constant. */
static void leastSquaresWeightsOnIdenticalRowsStayBounded(void **state)
{
    (void)state;
    sss_bake_file flat = g_file;
    const size_t nq = (size_t)g_file.dirs.n * g_file.mesh.nv * g_file.channels;
    flat.q = malloc(nq * sizeof *flat.q);
    assert_non_null(flat.q);
    for (size_t i = 0; i < nq; i++) flat.q[i] = 0.25f;
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = 2;
    o.fraction = 0.05;
    o.ls_weights = 1;
    sss_bake_file cf;
    sss_error err = {{0}};
    if (sss_compress(&flat, &o, &cf, &err) != SSS_OK) fail_msg("%s", err.msg);
    const double span = (double)cf.ref.w_hi - cf.ref.w_lo;
    for (uint32_t k = 0; k < cf.sh.ncoded; k++) {
        double w0 = cf.ref.w_lo + span * cf.ref.w[2 * k] / 65535.0, w1 = cf.ref.w_lo + span * cf.ref.w[2 * k + 1] / 65535.0;
        if (!(w0 >= -1e-4 && w1 >= -1e-4 && w0 + w1 <= 1.0 + 1e-4))
            fail_msg("coded vertex %u: weights %g %g outside the triangle", k, w0, w1);
    }
    float *out = malloc((size_t)g_file.mesh.nv * g_file.channels * sizeof *out);
    assert_non_null(out);
    const double l[3] = {0.6, 0.0, 0.8};
    sss_decode_all(&cf, l, out);
    for (size_t i = 0; i < (size_t)g_file.mesh.nv * g_file.channels; i++)
        if (!(fabs(out[i] - 0.25) < 1e-3)) fail_msg("value %zu = %g, not 0.25", i, out[i]);
    free(out);
    free(flat.q);
    sss_file_free(&cf);
}

/* Lloyd-Max tables are MSE-optimal per coefficient: at 8 bits no worse than
 * the paper's linear codes; 4 bits is coarser than 8. */
static void lloydCodesAtLeastAsGoodAsLinear(void **state)
{
    (void)state;
    sss_bake_file a, b, c;
    compress_or_fail(4, 0.0, SSS_SHQ_LINEAR8, 0, &a);
    compress_or_fail(4, 0.0, SSS_SHQ_LLOYD8, 0, &b);
    compress_or_fail(4, 0.0, SSS_SHQ_LLOYD4, 0, &c);
    double ea = rel_error(&a), eb = rel_error(&b), ec = rel_error(&c);
    if (!(eb <= ea * 1.001)) fail_msg("lloyd8 %g worse than linear8 %g", eb, ea);
    if (!(ec > eb)) fail_msg("lloyd4 %g not above lloyd8 %g", ec, eb);
    sss_storage sa, sc;
    sss_file_storage(&a, &sa);
    sss_file_storage(&c, &sc);
    assert_int_equal(sa.sh_codes, (uint64_t)g_file.mesh.nv * g_file.channels * 16);
    assert_int_equal(sc.sh_codes, ((uint64_t)g_file.mesh.nv * g_file.channels * 16 + 1) / 2);
    expect_file_round_trip(&b);
    expect_file_round_trip(&c);
    sss_file_free(&a);
    sss_file_free(&b);
    sss_file_free(&c);
}

/* sss_decode_vertex gives the very floats sss_decode_all writes, for every
 * storage form, including at a direction sample and a pole. */
static void decodeVertexMatchesDecodeAll(void **state)
{
    (void)state;
    sss_bake_file forms[4];
    forms[0] = g_file;
    compress_or_fail(3, 0.0, SSS_SHQ_LLOYD4, 0, &forms[1]);
    compress_or_fail(3, 0.05, SSS_SHQ_LINEAR8, 1, &forms[2]);
    compress_or_fail(2, 0.05, SSS_SHQ_LLOYD8, 0, &forms[3]);
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels;
    float *all = malloc((size_t)nv * C * sizeof *all);
    assert_non_null(all);
    const double lights[3][3] = {{0.2, 0.9, -0.3}, {0, 0, 1}, {0, 0, 0}};
    for (int f = 0; f < 4; f++)
        for (int t = 0; t < 4; t++) {
            const double *l = t < 3 ? lights[t] : g_file.dirs.dir + 3 * 7;
            sss_decode_all(&forms[f], l, all);
            for (uint32_t v = 0; v < nv; v++) {
                float one[SSS_MAX_CHANNELS];
                sss_decode_vertex(&forms[f], v, l, one);
                for (uint32_t c = 0; c < C; c++)
                    if (one[c] != all[(size_t)v * C + c] || !isfinite(one[c]) || one[c] < 0.0f)
                        fail_msg("form %d light %d vertex %u channel %u: %.9g vs %.9g", f, t, v, c, one[c],
                                 all[(size_t)v * C + c]);
            }
        }
    float one[SSS_MAX_CHANNELS] = {1, 1, 1};
    sss_decode_vertex(&forms[2], nv, lights[0], one); /* out of range: zeros, no crash */
    assert_true(one[0] == 0.0f);
    free(all);
    for (int f = 1; f < 4; f++) sss_file_free(&forms[f]);
}

static void accountingSumsToTotal(void **state)
{
    (void)state;
    const double fr[2] = {0.0, 0.05};
    for (int t = 0; t < 2; t++) {
        sss_bake_file cf;
        compress_or_fail(3, fr[t], SSS_SHQ_LINEAR8, 0, &cf);
        sss_storage b;
        sss_file_storage(&cf, &b);
        uint64_t s = b.values + b.lloyd_tables + b.section_headers + b.ref_vertex + b.ref_tri + b.vertex_tri +
                     b.weights + b.ref_values + b.sh_tables + b.sh_codes;
        assert_int_equal(s, b.scattering);
        assert_int_equal(b.total, b.scattering + b.dirs);
        const uint64_t C = g_file.channels, nd = g_file.dirs.n, nref = cf.ref.nref, ncoded = cf.sh.ncoded;
        assert_int_equal(b.sh_codes, ncoded * C * 9);
        assert_int_equal(b.sh_tables, C * 9 * 4);
        assert_int_equal(b.ref_values, nd * nref * C);
        assert_int_equal(b.weights, nref ? ncoded * 4 : 0);
        assert_int_equal(b.vertex_tri, nref ? ncoded * 2 : 0); /* fewer than 65537 triangles: 2 bytes */
        assert_int_equal(b.ref_tri, (uint64_t)cf.ref.nrt * 12);
        assert_int_equal(b.ref_vertex, nref * 4);
        assert_int_equal(b.lloyd_tables, nref ? C * 1024 : 0);
        assert_true(fabs(sss_file_integral_bytes_per_vertex(&cf) - (double)b.scattering / g_file.mesh.nv) < 1e-9);
        sss_file_free(&cf);
    }
}

static void garbageInputsRejected(void **state)
{
    (void)state;
    sss_bake_file cf;
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    sss_error err = {{0}};
    assert_int_equal(sss_compress(NULL, &o, &cf, &err), SSS_ERR_ARG);
    assert_true(err.msg[0] != 0);
    assert_int_equal(sss_compress(&g_file, &o, NULL, &err), SSS_ERR_ARG);
    assert_int_equal(sss_compress(&g_file, NULL, &cf, &err), SSS_ERR_ARG);
    struct {
        uint32_t order, kind, wbits;
        double fraction, illum;
        const char *needle;
    } bad[] = {
        {9, 0, 16, 0.0, 0.0, "order 9"},      {3, 0, 16, 1.5, 0.0, "fraction"}, {3, 0, 16, -0.1, 0.0, "fraction"},
        {3, 0, 16, NAN, 0.0, "fraction"},      {0, 0, 16, 0.0, 0.0, "order"},     {3, 7, 16, 0.0, 0.0, "quantisation"},
        {3, 0, 12, 0.03, 0.0, "bits"},         {3, 0, 16, 0.03, -1.0, "illumination"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        o.order = bad[i].order;
        o.sh_kind = bad[i].kind;
        o.wbits = bad[i].wbits;
        o.fraction = bad[i].fraction;
        o.illum_weight = bad[i].illum;
        memset(&err, 0, sizeof err);
        assert_int_equal(sss_compress(&g_file, &o, &cf, &err), SSS_ERR_ARG);
        if (!strstr(err.msg, bad[i].needle)) fail_msg("case %zu: \"%s\" lacks \"%s\"", i, err.msg, bad[i].needle);
        assert_null(cf.mesh.pos);
    }
    sss_compress_opts_default(&o);
    sss_bake_file q8 = g_file;
    q8.quant = SSS_QUANT_LLOYD8;
    memset(&err, 0, sizeof err);
    assert_int_equal(sss_compress(&q8, &o, &cf, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "float"));
    double rel[4];
    assert_int_equal(sss_decode_error(NULL, &g_file, 10, 1, rel, NULL, NULL, &err), SSS_ERR_ARG);
}

/* ---- damaged compressed files --------------------------------------------- */

static void wr32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (uint8_t)(v >> (8 * i));
}

/* Offset and size of the section with this tag; recomputes checksums. */
static uint8_t *section(uint8_t *b, const char *tag, uint64_t *size)
{
    uint32_t n = test_rd32(b + 12);
    for (uint32_t i = 0; i < n; i++) {
        uint8_t *e = b + 24 + 40 * (size_t)i;
        if (!memcmp(e, tag, 4)) {
            *size = test_rd32(e + 16);
            return b + test_rd32(e + 8);
        }
    }
    fail_msg("no section %s", tag);
    return NULL;
}

static void fix_crcs(uint8_t *b)
{
    uint32_t n = test_rd32(b + 12);
    for (uint32_t i = 0; i < n; i++) {
        uint8_t *e = b + 24 + 40 * (size_t)i;
        wr32(e + 32, sss_crc32(0, b + test_rd32(e + 8), test_rd32(e + 16)));
    }
    wr32(b + 24 + 40 * (size_t)n, sss_crc32(0, b, 24 + 40 * (size_t)n));
}

/* Each field of REFS and SHC set to an invalid value (checksums repaired,
 * so only the value checks stand between it and the decoder) is refused
 * with a message naming the section. */
static void damagedCompressedSectionsRejected(void **state)
{
    (void)state;
    sss_bake_file cf;
    compress_or_fail(2, 0.05, SSS_SHQ_LLOYD4, 0, &cf);
    uint8_t *buf;
    size_t len;
    sss_error err = {{0}};
    if (sss_file_encode(&cf, &buf, &len, &err) != SSS_OK) fail_msg("%s", err.msg);
    const uint32_t C = cf.channels, nref = cf.ref.nref, nrt = cf.ref.nrt;
    struct {
        const char *tag;
        size_t off;
        uint32_t value;
        int width;
        const char *needle;
    } bad[] = {
        {"REFS", 0, 2, 4, "channels"},
        {"REFS", 4, 0, 4, "reference vertices"},
        {"REFS", 4, 0xFFFFFFFFu, 4, "reference vertices"},
        {"REFS", 8, 0x7FFFFFFFu, 4, "bytes per triangle"},
        {"REFS", 12, 4, 4, "bytes per triangle"},
        {"REFS", 16, 12, 4, "bits per weight"},
        {"REFS", 20, 0x7FC00000u, 4, "weight range"}, /* NaN */
        {"REFS", 24, 0x42000000u, 4, "weight range"}, /* 32 */
        {"REFS", 28, 0xBF800000u, 4, "level"},        /* level 0 = −1 */
        {"REFS", 28 + 4 * 256 * (size_t)C, 0xFFFFFFFFu, 4, "out of range"},            /* reference vertex */
        {"REFS", 28 + 4 * 256 * (size_t)C + 4 * (size_t)nref, nref, 4, "out of range"}, /* ref triangle index */
        {"REFS", 28 + 4 * 256 * (size_t)C + 4 * (size_t)nref + 12 * (size_t)nrt, 0xFFFF, 2, "triangle"},
        {"SHC ", 0, 1, 4, "channels"},
        {"SHC ", 4, 9, 4, "order"},
        {"SHC ", 4, 3, 4, "size"},
        {"SHC ", 8, 5, 4, "coded vertices"},
        {"SHC ", 12, 4, 4, "kind"},
        {"SHC ", 16, 0x7F800000u, 4, "not finite"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        uint8_t *c = malloc(len);
        assert_non_null(c);
        memcpy(c, buf, len);
        uint64_t sz;
        uint8_t *s = section(c, bad[i].tag, &sz);
        assert_true(bad[i].off + (size_t)bad[i].width <= sz);
        if (bad[i].width == 4) wr32(s + bad[i].off, bad[i].value);
        else s[bad[i].off] = (uint8_t)bad[i].value, s[bad[i].off + 1] = (uint8_t)(bad[i].value >> 8);
        fix_crcs(c);
        sss_bake_file g;
        memset(&err, 0, sizeof err);
        sss_result r = sss_file_decode(c, len, "t.sss", &g, &err);
        if (r == SSS_OK) fail_msg("case %zu (%s +%zu): accepted", i, bad[i].tag, bad[i].off);
        if (!strstr(err.msg, bad[i].tag) || !strstr(err.msg, bad[i].needle))
            fail_msg("case %zu: \"%s\" lacks \"%s\" / \"%s\"", i, err.msg, bad[i].tag, bad[i].needle);
        assert_null(g.ref.idx);
        free(c);
    }
    free(buf);
    sss_file_free(&cf);
}

/* A 16-bit SH file whose scale table or codes are damaged (checksums
 * repaired, so only the value checks can catch it) is refused naming the
 * section and the fault: a NaN, a negative and an infinite scale, the
 * meaningless code −32768, an unknown kind. */
static void damagedLinear16Rejected(void **state)
{
    (void)state;
    sss_bake_file cf;
    compress_or_fail(3, 0.0, SSS_SHQ_LINEAR16, 0, &cf);
    uint8_t *buf;
    size_t len;
    sss_error err = {{0}};
    if (sss_file_encode(&cf, &buf, &len, &err) != SSS_OK) fail_msg("%s", err.msg);
    const size_t codes = 16 + 4 * (size_t)cf.channels * cf.sh.ncoef; /* the first code's offset */
    const struct {
        size_t off;
        uint32_t value;
        int width;
        const char *needle;
    } bad[] = {
        {16, 0x7FC00000u, 4, "scale 0"},                                /* NaN */
        {16 + 4 * 5, 0xBF800000u, 4, "scale 5"},                        /* −1 */
        {16 + 4 * 8, 0x7F800000u, 4, "scale 8"},                        /* +inf */
        {codes, 0x8000u, 2, "code 0 is -32768"},
        {codes + 2 * 11, 0x8000u, 2, "code 11 is -32768"},
        {12, 4, 4, "unknown quantisation kind 4"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        uint8_t *c = malloc(len);
        assert_non_null(c);
        memcpy(c, buf, len);
        uint64_t sz;
        uint8_t *s = section(c, "SHC ", &sz);
        assert_true(bad[i].off + (size_t)bad[i].width <= sz);
        if (bad[i].width == 4) wr32(s + bad[i].off, bad[i].value);
        else s[bad[i].off] = (uint8_t)bad[i].value, s[bad[i].off + 1] = (uint8_t)(bad[i].value >> 8);
        fix_crcs(c);
        sss_bake_file g;
        memset(&err, 0, sizeof err);
        sss_result r = sss_file_decode(c, len, "t.sss", &g, &err);
        if (r == SSS_OK) fail_msg("case %zu (+%zu): accepted", i, bad[i].off);
        assert_int_equal(r, SSS_ERR_CORRUPT);
        if (!strstr(err.msg, "t.sss: section SHC") || !strstr(err.msg, bad[i].needle))
            fail_msg("case %zu: \"%s\" lacks \"%s\"", i, err.msg, bad[i].needle);
        assert_null(g.sh.code);
        free(c);
    }
    free(buf);
    sss_file_free(&cf);
}

/* Random bytes written into REFS and SHC (checksums repaired): every file is
 * either refused with a message or decodes to finite, non-negative q. */
static void randomDamageNeverCrashes(void **state)
{
    (void)state;
    sss_bake_file cf;
    compress_or_fail(2, 0.05, SSS_SHQ_LINEAR8, 1, &cf);
    uint8_t *buf;
    size_t len;
    sss_error err = {{0}};
    if (sss_file_encode(&cf, &buf, &len, &err) != SSS_OK) fail_msg("%s", err.msg);
    const size_t n = (size_t)cf.mesh.nv * cf.channels;
    float *out = malloc(n * sizeof *out);
    assert_non_null(out);
    uint64_t seed = 99;
    int accepted = 0, refused = 0;
    for (int t = 0; t < 400; t++) {
        uint8_t *c = malloc(len);
        assert_non_null(c);
        memcpy(c, buf, len);
        uint64_t sz;
        uint8_t *s = section(c, t % 2 ? "REFS" : "SHC ", &sz);
        int nb = 1 + (int)(sss_rng_next(&seed) % 4);
        for (int k = 0; k < nb; k++) {
            /* half the hits land in the first 64 bytes, where the counts are */
            uint64_t at = sss_rng_next(&seed) % (k % 2 ? sz : (sz < 64 ? sz : 64));
            s[at] = (uint8_t)sss_rng_next(&seed);
        }
        fix_crcs(c);
        sss_bake_file g;
        memset(&err, 0, sizeof err);
        if (sss_file_decode(c, len, "t.sss", &g, &err) == SSS_OK) {
            accepted++;
            const double l[3] = {0.1, 0.2, 0.97};
            sss_decode_all(&g, l, out);
            for (size_t i = 0; i < n; i++)
                if (!isfinite(out[i]) || out[i] < 0.0f) fail_msg("trial %d: value %zu = %g", t, i, out[i]);
            sss_file_free(&g);
        } else {
            refused++;
            assert_true(err.msg[0] != 0);
        }
        free(c);
    }
    assert_true(accepted > 0 && refused > 0); /* both paths were exercised */
    free(out);
    free(buf);
    sss_file_free(&cf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fractionOneMatchesSamplesWithinLloydBound),
        cmocka_unit_test(shOnlyMatchesFitAtSamplesWithinCodeBound),
        cmocka_unit_test(shOnlyLinear16WithinHalfCodeStep),
        cmocka_unit_test(orderWithMoreCoefficientsThanSamplesRejected),
        cmocka_unit_test(shOnlyErrorDecreasesWithOrder),
        cmocka_unit_test(referenceDeltaOrder3BeatsOrder0),
        cmocka_unit_test(leastSquaresWeightsBeatBarycentrics),
        cmocka_unit_test(leastSquaresWeightsOnIdenticalRowsStayBounded),
        cmocka_unit_test(lloydCodesAtLeastAsGoodAsLinear),
        cmocka_unit_test(decodeVertexMatchesDecodeAll),
        cmocka_unit_test(accountingSumsToTotal),
        cmocka_unit_test(garbageInputsRejected),
        cmocka_unit_test(damagedCompressedSectionsRejected),
        cmocka_unit_test(damagedLinear16Rejected),
        cmocka_unit_test(randomDamageNeverCrashes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
