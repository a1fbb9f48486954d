/* test_decode_planes.c: the decoder's load-time layout of the SH codes
 * (sss_decode_prepare, common/src/decode.c; docs/benchmarks.md "Compressed
 * forms' per-frame cost"). The layout only reorders the work of a frame
 * (code e of every coded vertex contiguous, blocks of vertices per loop
 * step); every value must come out as the per-vertex loop forms it. Oracles:
 * for SH-only files the sum of Hao–Varshney 2004 §4.1 written out here, each
 * vertex's terms in coefficient order from the folded tables; for the
 * reference form (§4.2–4.3) the per-vertex loop the decoder keeps for files
 * without the layout, and sss_decode_vertex. Every code kind, one and three
 * channels, SH orders 3 and 7, with and without references, and the block
 * loops on every instruction set the CPU has (sss_decode_isa: the baseline
 * and its AVX2 and AVX-512 copies must give the same floats), with the
 * references' load-time blend and without it (a stale one). */
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

/* Float bakes of one blob (subdivision 3: 2,562 vertices, ten blocks of the
 * layout and a partial one), 64 directions (order 7 fits 49
 * coefficients): RGB skin and a grey material (skin's first channel). */
static sss_bake_file g_rgb, g_grey;

static int bake(const sss_material *mat, sss_bake_file *out)
{
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_blob(&m, 1.0, 3, &err) != SSS_OK) return -1;
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 64;
    opt.quant = SSS_QUANT_FLOAT;
    opt.threads = 2;
    sss_bake_stats st;
    sss_result r = sss_bake(&m, "blob", mat, &opt, out, &st, &err);
    sss_mesh_free(&m);
    if (r != SSS_OK) fprintf(stderr, "bake failed: %s\n", err.msg);
    return r == SSS_OK ? 0 : -1;
}

static int setup(void **state)
{
    (void)state;
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK || bake(&mat, &g_rgb)) return -1;
    for (int c = 1; c < 3; c++) {
        mat.sigma_a[c] = mat.sigma_a[0];
        mat.sigmap_s[c] = mat.sigmap_s[0];
    }
    if (sss_material_channels(&mat) != 1 || bake(&mat, &g_grey)) return -1;
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sss_file_free(&g_rgb);
    sss_file_free(&g_grey);
    return 0;
}

/* §4.1 for an SH-only file, vertex by vertex: channel c of vertex v is
 * Σ_i T_c,i(code) in coefficient order, in float, clamped at 0; T the
 * folded tables (sss_decode_fold_sh), a linear code's term the float
 * product code · T, 4-bit codes two at a time from the pairs' tables. */
static void oracle_sh(const sss_bake_file *f, const double light[3], float *out)
{
    const sss_shcode *s = &f->sh;
    const size_t C = f->channels, N = s->ncoef, L = sss_decode_fold_levels(s->kind);
    const double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};
    float *T = malloc(sss_decode_fold_floats(s->kind, (uint32_t)C, (uint32_t)N) * sizeof *T);
    assert_non_null(T);
    sss_decode_fold_sh(f, d, T);
    for (size_t v = 0; v < f->mesh.nv; v++)
        for (size_t c = 0; c < C; c++) {
            float a = 0.0f;
            const uint8_t *code = s->code;
            const uint64_t e0 = (uint64_t)v * C * N + c * N;
            if (s->kind == SSS_SHQ_LLOYD4) { /* two codes a table, then an odd last one */
                const size_t P = N / 2;
                for (size_t m = 0; m < P; m++)
                    a += T[(c * P + m) * 256 + (sss_shq_code(code, s->kind, e0 + 2 * m) |
                                                sss_shq_code(code, s->kind, e0 + 2 * m + 1) << 4)];
                if (N & 1) a += T[C * P * 256 + c * 16 + sss_shq_code(code, s->kind, e0 + N - 1)];
                out[v * C + c] = a > 0.0f ? a : 0.0f;
                continue;
            }
            for (size_t i = 0; i < N; i++) {
                const size_t e = c * N + i;
                const uint32_t x = sss_shq_code(code, s->kind, (uint64_t)v * C * N + e);
                if (s->kind == SSS_SHQ_LINEAR16 || s->kind == SSS_SHQ_LINEAR8) {
                    const int code = s->kind == SSS_SHQ_LINEAR16 ? (int16_t)(uint16_t)x : (int8_t)(uint8_t)x;
                    const float prod = (float)code * T[e];
                    a += prod;
                } else {
                    a += T[e * L + x];
                }
            }
            out[v * C + c] = a > 0.0f ? a : 0.0f;
        }
    free(T);
}

/* Instruction sets check_form ran the block loops on (bit i: set i). */
static unsigned g_isas_run;

/* Compresses src (order, reference fraction, code kind), then decodes a
 * fixed set of lights without and with the layout, and through a range
 * and single vertices: every float equal. */
static void check_form(const sss_bake_file *src, uint32_t order, double fraction, uint32_t kind)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = order;
    o.fraction = fraction;
    o.sh_kind = kind;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_compress(src, &o, &f, &err) != SSS_OK)
        fail_msg("compress(order %u, fraction %g, %s): %s", order, fraction, sss_shq_name(kind), err.msg);
    const char *what = sss_shq_name(kind);
    assert_int_equal(f.quant, fraction > 0 ? SSS_QUANT_REFS : SSS_QUANT_SH);
    assert_null(f.sh.planes); /* the compressor's file has no layout: the per-vertex loop */
    const size_t C = f.channels, nv = f.mesh.nv, n = nv * C;
    float *want = malloc(n * sizeof *want), *got = malloc(n * sizeof *got), *sh = malloc(n * sizeof *sh);
    assert_non_null(want);
    assert_non_null(got);
    assert_non_null(sh);
    /* random lights, one at a direction sample, one between two */
    double lights[8][3];
    uint64_t seed = 11;
    for (int t = 0; t < 6; t++) sss_rng_direction(&seed, lights[t]);
    memcpy(lights[6], src->dirs.dir, sizeof lights[6]);
    for (int a = 0; a < 3; a++) lights[7][a] = src->dirs.dir[a] + src->dirs.dir[3 + a];
    size_t positive = 0;
    for (int t = 0; t < 8; t++) {
        /* the per-vertex loop: the file as the compressor made it */
        free(f.sh.planes);
        f.sh.planes = NULL;
        f.sh.planes_of = NULL;
        sss_decode_all(&f, lights[t], want);
        if (f.quant == SSS_QUANT_SH) {
            oracle_sh(&f, lights[t], sh);
            for (size_t i = 0; i < n; i++)
                if (memcmp(&sh[i], &want[i], sizeof *sh))
                    fail_msg("%s order %u, %zu channels, light %d, value %zu: per-vertex loop %.9g, §4.1 sum %.9g",
                             what, order, C, t, i, want[i], sh[i]);
        }
        assert_int_equal(sss_decode_prepare(&f), 0);
        assert_non_null(f.sh.planes);
        /* the layout's block loops on every instruction set this CPU has
         * (the baseline always): each the per-vertex loop's floats */
        for (int isa = SSS_DECODE_ISA_BASELINE; isa <= SSS_DECODE_ISA_AVX512; isa++) {
            if (sss_decode_force_isa(isa)) continue;
            g_isas_run |= 1u << isa;
            assert_int_equal(sss_decode_isa(), isa);
            memset(got, 0xff, n * sizeof *got);
            sss_decode_all(&f, lights[t], got);
            for (size_t i = 0; i < n; i++)
                if (memcmp(&got[i], &want[i], sizeof *got))
                    fail_msg("%s order %u, fraction %g, %zu channels, light %d, vertex %zu channel %zu: layout on "
                             "instruction set %d %.9g, per-vertex loop %.9g",
                             what, order, fraction, C, t, i / C, i % C, isa, got[i], want[i]);
        }
        assert_int_equal(sss_decode_force_isa(-1), 0);
        for (size_t i = 0; i < n; i++) positive += want[i] > 0.0f;
        /* ranges that start and end inside blocks: the slice; with
         * references, also ranges that start or end at one or hold only
         * references (each block stores the references after its coded
         * vertices, the caller those before the range's first) */
        uint32_t ranges[6][2] = {{(uint32_t)nv / 3 + 1, (uint32_t)nv / 2 + 3}};
        size_t nr = 1;
        if (f.quant == SSS_QUANT_REFS && f.ref.nref > 2) {
            const uint32_t *rv = f.ref.ref_vertex, a = rv[f.ref.nref / 3], b = rv[2 * f.ref.nref / 3];
            ranges[nr][0] = a, ranges[nr++][1] = b - a + 1;  /* a reference at each end */
            ranges[nr][0] = a + 1, ranges[nr++][1] = b - a;  /* ends on one */
            ranges[nr][0] = a, ranges[nr++][1] = 1;          /* one reference alone */
            ranges[nr][0] = 0, ranges[nr++][1] = rv[0] + 1;  /* up to the first */
            ranges[nr][0] = rv[f.ref.nref - 1], ranges[nr++][1] = (uint32_t)nv - rv[f.ref.nref - 1]; /* from the last */
        }
        for (size_t q = 0; q < nr; q++) {
            const uint32_t first = ranges[q][0], count = ranges[q][1];
            memset(got, 0xff, n * sizeof *got);
            sss_decode_range(&f, lights[t], first, count, got);
            assert_memory_equal(got, want + (size_t)first * C, (size_t)count * C * sizeof *got);
        }
        for (uint32_t v = 0; v < nv; v += 97) {
            float one[3];
            sss_decode_vertex(&f, v, lights[t], one);
            assert_memory_equal(one, want + (size_t)v * C, C * sizeof *one);
        }
    }
    assert_true(positive > n); /* the comparisons are not of zeros */
    free(want);
    free(got);
    free(sh);
    sss_file_free(&f);
}

static const uint32_t kinds[] = {SSS_SHQ_LINEAR8, SSS_SHQ_LLOYD8, SSS_SHQ_LLOYD4, SSS_SHQ_LINEAR16};

/* check_form for every code kind, orders 3 and 7, RGB and grey; fraction:
 * the share of reference points (0: SH only) */
static void check_every_form(double fraction)
{
    for (size_t k = 0; k < sizeof kinds / sizeof *kinds; k++)
        for (uint32_t order = 3; order <= 7; order += 4) {
            check_form(&g_rgb, order, fraction, kinds[k]);
            check_form(&g_grey, order, fraction, kinds[k]);
        }
}

static void shOnlyLayoutIsThePerVertexSum(void **state)
{
    (void)state;
    check_every_form(0.0);
}

static void referencesLayoutIsThePerVertexSum(void **state)
{
    (void)state;
    check_every_form(0.05);
}

/* The run-time choice of instruction set (sss_decode_isa): the baseline can
 * always be forced, a set that does not exist cannot, −1 goes back to the
 * widest the CPU has; check_form compares every set the CPU has (for every
 * form in the tests above), the automatic choice among them. */
static void everyInstructionSetGivesTheBaselineFloats(void **state)
{
    (void)state;
    assert_int_equal(sss_decode_force_isa(SSS_DECODE_ISA_BASELINE), 0);
    assert_int_equal(sss_decode_isa(), SSS_DECODE_ISA_BASELINE);
    assert_int_equal(sss_decode_force_isa(SSS_DECODE_ISA_AVX512 + 1), -1);
    assert_int_equal(sss_decode_isa(), SSS_DECODE_ISA_BASELINE); /* unchanged by the refusal */
    assert_int_equal(sss_decode_force_isa(-1), 0);
    const int best = sss_decode_isa();
    assert_true(best >= SSS_DECODE_ISA_BASELINE && best <= SSS_DECODE_ISA_AVX512);
    g_isas_run = 0;
    check_form(&g_rgb, 3, 0.03, SSS_SHQ_LLOYD4);
    assert_true(g_isas_run & 1u); /* the baseline */
    assert_true(g_isas_run & (1u << best)); /* and the automatic choice */
    printf("instruction sets compared: baseline%s%s\n", g_isas_run & 2u ? ", avx2" : "",
           g_isas_run & 4u ? ", avx512" : "");
}

/* A layout built from other codes is not used: after the codes are
 * replaced (a new array), the decoder gives the new codes' values, and
 * sss_decode_prepare on a file without SH codes builds nothing. */
static void staleLayoutIsNotUsed(void **state)
{
    (void)state;
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = 3;
    o.fraction = 0.0;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_compress(&g_rgb, &o, &f, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
    const size_t n = (size_t)f.mesh.nv * f.channels, nb = n * f.sh.ncoef;
    assert_int_equal(sss_decode_prepare(&f), 0);
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    uint8_t *code = malloc(nb);
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(code);
    for (size_t e = 0; e < nb; e++) code[e] = (uint8_t)(f.sh.code[e] ^ 0x15u); /* other codes, same kind */
    const double l[3] = {0.3, -0.5, 0.8};
    sss_decode_all(&f, l, a);
    uint8_t *old = f.sh.code;
    f.sh.code = code;
    sss_decode_all(&f, l, b); /* planes_of still names the old array: the per-vertex loop */
    assert_memory_not_equal(a, b, n * sizeof *a);
    oracle_sh(&f, l, a);
    assert_memory_equal(a, b, n * sizeof *a);
    f.sh.code = old;
    free(code);
    sss_file_free(&f);
    /* nothing to lay out in a float file */
    sss_bake_file g;
    memset(&g, 0, sizeof g);
    g.quant = SSS_QUANT_FLOAT;
    assert_int_equal(sss_decode_prepare(&g), 0);
    assert_null(g.sh.planes);
    free(a);
    free(b);
}

/* The references' load-time blend (sss_refcode.blend; built by
 * sss_decode_prepare beside the planes): it holds each coded vertex's first
 * two weights as sss_decode_ref_weight's floats and its triangle's three
 * references, one record a vertex in order (format.h). After the
 * weight codes are replaced (a new array) it is not used: the blend reads
 * the new codes through the planes and gives, on every instruction set, the
 * per-vertex loop's floats for them. 16-bit weights in RGB, 8-bit in grey. */
static void check_stale_blend(const sss_bake_file *src, uint32_t wbits)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.fraction = 0.05;
    o.wbits = wbits;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_compress(src, &o, &f, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
    sss_refcode *r = &f.ref;
    assert_int_equal(sss_decode_prepare(&f), 0);
    assert_non_null(r->blend);
    assert_ptr_equal(r->blend_of, r->w);
    const size_t nc = f.sh.ncoded, C = f.channels, n = (size_t)f.mesh.nv * C;
    for (size_t k = 0; k < nc; k += 37) {
        for (uint32_t j = 0; j < 2; j++) {
            const float w = sss_decode_ref_weight(r, r->w[2 * k + j]);
            assert_memory_equal(j ? &r->blend[k].w1 : &r->blend[k].w0, &w, sizeof w);
        }
        for (size_t j = 0; j < 3; j++) assert_int_equal(r->blend[k].t[j], r->ref_tri[3 * (size_t)r->vtri[k] + j]);
    }
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b), *want = malloc(n * sizeof *want);
    uint16_t *w = malloc(2 * nc * sizeof *w);
    assert_non_null(a);
    assert_non_null(b);
    assert_non_null(want);
    assert_non_null(w);
    const double l[3] = {0.4, 0.7, -0.3};
    sss_decode_all(&f, l, a);
    /* other weight codes (in range), in a new array: the layout is stale */
    const uint32_t top = wbits == 16 ? 65535u : 255u;
    for (size_t e = 0; e < 2 * nc; e++) w[e] = (uint16_t)(top - r->w[e]);
    uint16_t *old = r->w;
    r->w = w;
    for (int isa = SSS_DECODE_ISA_BASELINE; isa <= SSS_DECODE_ISA_AVX512; isa++) {
        if (sss_decode_force_isa(isa)) continue;
        sss_decode_all(&f, l, b);
        assert_memory_not_equal(a, b, n * sizeof *a); /* the new codes' values, not the layout's */
        void *planes = f.sh.planes;
        f.sh.planes = NULL; /* the per-vertex loop, for the oracle */
        sss_decode_all(&f, l, want);
        f.sh.planes = planes;
        for (size_t i = 0; i < n; i++)
            if (memcmp(&b[i], &want[i], sizeof *b))
                fail_msg("%u-bit weights, %zu channels, instruction set %d, value %zu: blocks %.9g, per-vertex %.9g",
                         wbits, C, isa, i, b[i], want[i]);
    }
    assert_int_equal(sss_decode_force_isa(-1), 0);
    r->w = old;
    free(w);
    free(a);
    free(b);
    free(want);
    sss_file_free(&f);
}

static void staleBlendLayoutIsNotUsed(void **state)
{
    (void)state;
    check_stale_blend(&g_rgb, 16); /* RGB: the lanes' blend */
    check_stale_blend(&g_grey, 8);  /* grey: the planes' loop */
}

/* The reader builds the layout: a compressed file read back decodes
 * through it, to the compressor's floats. */
static void readerBuildsTheLayout(void **state)
{
    (void)state;
    sss_compress_opts o;
    sss_compress_opts_default(&o); /* the paper's: 3 % references, SH 3 linear8 */
    sss_bake_file f, g;
    sss_error err = {{0}};
    if (sss_compress(&g_rgb, &o, &f, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&f, &buf, &len, &err) != SSS_OK) fail_msg("encode: %s", err.msg);
    if (sss_file_decode(buf, len, "planes.sss", &g, &err) != SSS_OK) fail_msg("decode: %s", err.msg);
    assert_non_null(g.sh.planes);
    assert_ptr_equal(g.sh.planes_of, g.sh.code);
    assert_non_null(g.ref.blend); /* and the references' blend */
    assert_ptr_equal(g.ref.blend_of, g.ref.w);
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    const double l[3] = {-0.2, 0.9, 0.1};
    sss_decode_all(&f, l, a);
    sss_decode_all(&g, l, b);
    assert_memory_equal(a, b, n * sizeof *a);
    free(a);
    free(b);
    free(buf);
    sss_file_free(&f);
    sss_file_free(&g);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(shOnlyLayoutIsThePerVertexSum),
        cmocka_unit_test(referencesLayoutIsThePerVertexSum),
        cmocka_unit_test(everyInstructionSetGivesTheBaselineFloats),
        cmocka_unit_test(staleLayoutIsNotUsed),
        cmocka_unit_test(staleBlendLayoutIsNotUsed),
        cmocka_unit_test(readerBuildsTheLayout),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
