/* test_gpu_layout.c: libsss's GPU layout (sss/gpu.h, docs/gpu_layout.md)
 * without a GPU. The two shaders' arithmetic is replayed on the CPU from
 * nothing but the layout's buffer images (as sss_gpu_buffer_pack writes
 * them), its bindings and the frame's constants; the result must be
 * sss_decode_all's to the bit for every storage form. Also: row padding,
 * argument checks, a scene bake without a direction set, no light. The GL
 * side is tested by tests/render (example_render_gl, test_render). */
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
#include "sss/compress.h"
#include "sss/decode.h"
#include "sss/gpu.h"

static sss_bake_file g_float, g_l8;

static int bake(sss_quant q, sss_bake_file *f)
{
    sss_mesh m;
    sss_error err = {{0}};
    sss_material mat;
    if (sss_gen_blob(&m, 1.0, 2, &err) != SSS_OK || sss_material_preset("skin1", &mat, &err) != SSS_OK) return -1;
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 40;
    opt.quant = q;
    opt.threads = 2;
    sss_bake_stats st;
    sss_result r = sss_bake(&m, "blob", &mat, &opt, f, &st, &err);
    sss_mesh_free(&m);
    return r == SSS_OK ? 0 : -1;
}

static int setup(void **state)
{
    (void)state;
    return bake(SSS_QUANT_FLOAT, &g_float) || bake(SSS_QUANT_LLOYD8, &g_l8);
}

static int teardown(void **state)
{
    (void)state;
    sss_file_free(&g_float);
    sss_file_free(&g_l8);
    return 0;
}

/* The GPU image of buffer k (NULL when the file has none). */
static void *image(const sss_gpu_layout *L, int k)
{
    const sss_gpu_buffer *b = &L->buffer[k];
    if (!b->passes || b->access != SSS_GPU_UPLOAD) return NULL;
    void *p = malloc(b->bytes + 4);
    assert_non_null(p);
    sss_gpu_buffer_pack(b, p);
    return p;
}

/* A byte of a std430 uint[] array, as byte_at in scatter.comp.glsl reads it. */
static uint32_t byte_at(const uint8_t *row, uint32_t i) { return row[i]; }

/* scatter.comp.glsl, then scatter_coded.comp.glsl, invocation by
 * invocation, from the layout's images and the frame's constants. */
static void replay(const sss_gpu_layout *L, const sss_gpu_frame *fr, float *q, float *refq)
{
    const uint32_t C = L->channels;
    const sss_gpu_program *p0 = &L->pass[SSS_GPU_PASS_ROWS], *p1 = &L->pass[SSS_GPU_PASS_CODED];
    uint8_t *rows = image(L, SSS_GPU_BUF_ROWS);
    uint32_t *ref_vertex = image(L, SSS_GPU_BUF_REF_VERTEX);
    if (p0->name) {
        const int l8 = strstr(p0->defines, "LLOYD8") != NULL, refs = strstr(p0->defines, "REFS") != NULL;
        const uint8_t *ra = rows + fr->row_offset[0], *rb = rows + fr->row_offset[1], *rc = rows + fr->row_offset[2];
        /* the NEAREST4 variant's fourth row (SSS_GPU_ROW4_BINDING) */
        const uint8_t *rd = fr->nrows == 4 ? rows + fr->row_offset[3] : NULL;
        for (uint32_t i = 0; i < fr->u_count[0]; i++) {
            float x;
            if (l8) {
                const uint32_t ch = i % fr->u_channels, t = 256u * fr->u_channels, base = 256u * ch;
                x = fr->levels[base + byte_at(ra, i)] + fr->levels[t + base + byte_at(rb, i)];
                x += fr->levels[2u * t + base + byte_at(rc, i)];
                if (rd) x += fr->levels[3u * t + base + byte_at(rd, i)];
            } else {
                const float *a = (const float *)ra, *b = (const float *)rb, *c = (const float *)rc;
                if (rd) x = fr->u_w[0] * a[i] + fr->u_w[1] * b[i] + fr->u_w[2] * c[i] + fr->u_w[3] * ((const float *)rd)[i];
                else x = fr->u_w[0] * a[i] + fr->u_w[1] * b[i] + fr->u_w[2] * c[i];
            }
            if (refs) {
                refq[4 * (i / C) + i % C] = x; /* four floats a reference */
                q[ref_vertex[i / C] * C + i % C] = x;
            } else {
                q[i] = x;
            }
        }
    }
    if (p1->name) {
        uint32_t *codes = image(L, SSS_GPU_BUF_SH_CODES), *rec = image(L, SSS_GPU_BUF_CODED);
        float *wts = image(L, SSS_GPU_BUF_WEIGHTS);
        const uint32_t N = L->f->sh.ncoef, Lv = L->sh_levels ? L->sh_levels : 256u;
        const int lin16 = strstr(p1->defines, "SH_LINEAR16") != NULL, lin8 = strstr(p1->defines, "SH_LINEAR8") != NULL;
        const uint32_t BITS = strstr(p1->defines, "SH_NIBBLE") ? 4u : lin16 ? 16u : 8u, PER = 32u / BITS;
        const uint32_t W = (C * N + PER - 1u) / PER; /* words per coded vertex, in groups of four */
        if (N) assert_int_equal(L->buffer[SSS_GPU_BUF_SH_CODES].bytes, (uint64_t)fr->u_count[1] * ((W + 3) / 4) * 16);
        /* the frame's tables: a uniform block (vec4[], padded with zeros) exactly when they fit 16 KiB */
        const uint64_t fl = sss_decode_fold_floats(L->f->sh.kind, C, N);
        if (N) {
            assert_int_equal(L->sh_uniform, fl * 4 <= 16384);
            assert_int_equal(L->sh_bytes, L->sh_uniform ? (fl + 3) / 4 * 16 : fl * 4);
            assert_int_equal(strstr(p1->defines, "#define SH_UBO ") != NULL, L->sh_uniform);
            for (uint64_t x = fl; x < L->sh_bytes / 4; x++) assert_true(fr->sh[x] == 0.0f);
        }
        /* word n of coded vertex k: group n / 4, quad-major, element n mod 4 */
#define WORD(n) codes[(((n) / 4) * fr->u_count[1] + k) * 4 + (n) % 4]
        for (uint32_t k = 0; k < fr->u_count[1]; k++) {
            uint32_t v = k, r0 = 0, r1 = 0, r2 = 0;
            float w0 = 0, w1 = 0, w2 = 0;
            if (rec) {
                v = rec[4 * k];
                r0 = 4 * rec[4 * k + 1], r1 = 4 * rec[4 * k + 2], r2 = 4 * rec[4 * k + 3];
                w0 = wts[2 * k], w1 = wts[2 * k + 1];
                w2 = 1.0f - w0 - w1;
            }
            for (uint32_t ch = 0; ch < C; ch++) {
                float x = 0.0f;
                if (rec) x = w0 * refq[r0 + ch] + w1 * refq[r1 + ch] + w2 * refq[r2 + ch];
                if (N) {
                    float acc = 0.0f;
#define CODE_AT(e) ((WORD((e) / PER) >> (((e) % PER) * BITS)) & ((1u << BITS) - 1u))
                    if (BITS == 4) { /* the pairs' tables, then an odd last code (sss_decode_fold_sh) */
                        const uint32_t P = N / 2, e = ch * N;
                        for (uint32_t m = 0; m < P; m++)
                            acc += fr->sh[(ch * P + m) * 256 + (CODE_AT(e + 2 * m) | CODE_AT(e + 2 * m + 1) << 4)];
                        if (N & 1) acc += fr->sh[C * P * 256 + ch * 16 + CODE_AT(e + N - 1)];
                    }
#undef CODE_AT
                    for (uint32_t j = 0; j < N && BITS != 4; j++) {
                        const uint32_t e = ch * N + j;
                        const uint32_t code = (WORD(e / PER) >> ((e % PER) * BITS)) & ((1u << BITS) - 1u);
                        if (lin16 || lin8) {
                            /* int(w << (32 − BITS − shift)) >> (32 − BITS): the sign-extended code times the folded step */
                            const float prod = (float)(lin16 ? (int16_t)code : (int8_t)code) * fr->sh[ch * N + j];
                            acc += prod;
                        } else {
                            acc += fr->sh[(ch * N + j) * Lv + code];
                        }
                    }
                    x += acc;
                }
                q[v * C + ch] = x > 0.0f ? x : 0.0f;
            }
        }
#undef WORD
        free(codes), free(rec), free(wts);
    }
    free(rows), free(ref_vertex);
}

/* Every light of a fixed set, and no light, with either interpolation: the
 * replay equals sss_decode_all_interp (the 4-nearest frames with the rows
 * pass's NEAREST4 variant). */
static void check_form(const sss_bake_file *f, const char *what)
{
    sss_gpu_layout L;
    sss_gpu_frame fr;
    sss_error err = {{0}};
    assert_int_equal(sss_gpu_layout_create(f, 64, &L, &err), SSS_OK);
    assert_int_equal(sss_gpu_frame_init(&L, &fr, &err), SSS_OK);
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *gpu = malloc(n * sizeof *gpu), *cpu = malloc(n * sizeof *cpu);
    float *refq = malloc(((size_t)f->ref.nref * 4 + 1) * sizeof *refq);
    assert_true(gpu && cpu && refq);
    const double lights[][3] = {{0, 0, 1}, {0.3, 0.5, 0.8}, {-1, 0.2, 0.1}, {0, -2, 0}, {0.7, -0.1, -0.7}, {0, 0, 0}};
    for (int n4 = 0; n4 < 2; n4++)
        for (size_t i = 0; i < sizeof lights / sizeof lights[0]; i++) {
            const sss_interp in = n4 ? SSS_INTERP_NEAREST4 : SSS_INTERP_TRIANGLE;
            memset(gpu, 0xff, n * sizeof *gpu); /* NaN: a value the passes did not write shows */
            if (n4) sss_gpu_frame_eval_interp(&L, lights[i], in, &fr);
            else sss_gpu_frame_eval(&L, lights[i], &fr);
            assert_int_equal(fr.nrows, n4 ? 4u : 3u);
            replay(&L, &fr, gpu, refq);
            sss_decode_all_interp(f, lights[i], in, cpu);
            if (memcmp(gpu, cpu, n * sizeof *gpu) != 0)
                fail_msg("%s, %s, light %zu: the layout's q differs from sss_decode_all_interp", what,
                         n4 ? "4-nearest" : "triangle", i);
        }
    free(gpu), free(cpu), free(refq);
    sss_gpu_frame_free(&fr);
    sss_gpu_layout_free(&L);
}

static void compress_to(uint32_t order, double fraction, uint32_t kind, uint32_t wbits, sss_bake_file *out)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = order;
    o.fraction = fraction;
    o.sh_kind = kind;
    o.wbits = wbits;
    sss_error err = {{0}};
    if (sss_compress(&g_float, &o, out, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
}

static void everyFormReplaysToTheDecoder(void **state)
{
    (void)state;
    check_form(&g_float, "float");
    check_form(&g_l8, "lloyd8");
    static const struct { uint32_t order; double fraction; uint32_t kind, wbits; const char *what; } forms[] = {
        {4, 0.0, SSS_SHQ_LINEAR8, 16, "SH linear8"},  {3, 0.0, SSS_SHQ_LLOYD8, 16, "SH lloyd8"},
        {4, 0.0, SSS_SHQ_LLOYD4, 16, "SH lloyd4"},    {3, 0.05, SSS_SHQ_LLOYD4, 8, "refs + SH lloyd4, 8-bit weights"},
        {2, 0.1, SSS_SHQ_LINEAR8, 16, "refs + SH linear8"}, {0, 0.1, SSS_SHQ_LINEAR8, 16, "refs alone"},
        {6, 0.0, SSS_SHQ_LINEAR16, 16, "SH linear16"},      {5, 0.0, SSS_SHQ_LINEAR16, 16, "SH linear16, odd codes"},
        {3, 0.05, SSS_SHQ_LINEAR16, 8, "refs + SH linear16"}};
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; i++) {
        sss_bake_file cf;
        compress_to(forms[i].order, forms[i].fraction, forms[i].kind, forms[i].wbits, &cf);
        check_form(&cf, forms[i].what);
        sss_file_free(&cf);
    }
}

/* Rows padded to the alignment, padding zeroed, ranges and offsets agree. */
static void rowsArePaddedToTheAlignment(void **state)
{
    (void)state;
    sss_gpu_layout L;
    sss_error err = {{0}};
    assert_int_equal(sss_gpu_layout_create(&g_l8, 256, &L, &err), SSS_OK);
    const sss_gpu_buffer *b = &L.buffer[SSS_GPU_BUF_ROWS];
    const uint64_t row = (uint64_t)g_l8.mesh.nv * g_l8.channels;
    assert_int_equal(b->row_bytes, row);
    assert_int_equal(b->stride % 256, 0);
    assert_true(b->stride >= row && b->stride < row + 256);
    assert_int_equal(L.row_range, (row + 3) / 4 * 4);
    assert_int_equal(b->bytes, (uint64_t)g_l8.dirs.n * b->stride);
    assert_int_equal(L.pass[SSS_GPU_PASS_ROWS].groups, (row + 255) / 256);
    assert_null(L.pass[SSS_GPU_PASS_CODED].name);
    assert_non_null(strstr(L.pass[SSS_GPU_PASS_ROWS].defines, "#define LLOYD8 1\n"));
    assert_ptr_equal(L.pass[SSS_GPU_PASS_ROWS].source, sss_gpu_glsl("scatter"));
    uint8_t *img = image(&L, SSS_GPU_BUF_ROWS);
    for (uint32_t j = 0; j < g_l8.dirs.n; j++) {
        assert_memory_equal(img + j * b->stride, g_l8.qidx + j * row, row);
        for (uint64_t x = row; x < b->stride; x++) assert_int_equal(img[j * b->stride + x], 0);
    }
    free(img);
    sss_gpu_frame fr;
    assert_int_equal(sss_gpu_frame_init(&L, &fr, &err), SSS_OK);
    sss_gpu_frame_eval(&L, (const double[3]){0.2, -0.4, 0.9}, &fr);
    for (int t = 0; t < 3; t++) assert_int_equal(fr.row_offset[t], (uint64_t)fr.row[t] * b->stride);
    sss_gpu_frame_free(&fr);
    sss_gpu_layout_free(&L);
    /* 0 means 4; a value that is not a power of two is refused */
    assert_int_equal(sss_gpu_layout_create(&g_float, 0, &L, &err), SSS_OK);
    assert_int_equal(L.buffer[SSS_GPU_BUF_ROWS].stride % 4, 0);
    sss_gpu_layout_free(&L);
    assert_int_equal(sss_gpu_layout_create(&g_float, 48, &L, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "48"));
}

/* The GLSL is the files', and unknown names have none. */
static void glslIsEmbedded(void **state)
{
    (void)state;
    assert_non_null(strstr(sss_gpu_glsl("scatter"), "layout(local_size_x = 256) in;"));
    assert_non_null(strstr(sss_gpu_glsl("scatter_coded"), "SH_NIBBLE"));
    assert_null(sss_gpu_glsl("shade"));
    assert_null(sss_gpu_glsl(NULL));
}

/* A scene bake without the direction-set effect: q only, no pass; an
 * unknown storage form is refused with a message. */
static void sceneWithoutDirectionSetAndBadForms(void **state)
{
    (void)state;
    sss_bake_file f = g_float; /* shallow: only read */
    f.fx.mask = SSS_FX_RGB | SSS_FX_DIR_EXACT;
    sss_gpu_layout L;
    sss_error err = {{0}};
    assert_int_equal(sss_gpu_layout_create(&f, 16, &L, &err), SSS_OK);
    assert_null(L.pass[0].name);
    assert_null(L.pass[1].name);
    for (int k = 0; k < SSS_GPU_BUFFERS; k++) assert_int_equal(L.buffer[k].passes, 0);
    assert_int_equal(L.buffer[SSS_GPU_BUF_Q].bytes, (uint64_t)f.mesh.nv * f.channels * 4);
    sss_gpu_layout_free(&L);
    f.fx.mask = 0;
    f.quant = (sss_quant)7;
    assert_int_equal(sss_gpu_layout_create(&f, 16, &L, &err), SSS_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "storage form 7"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(everyFormReplaysToTheDecoder),
        cmocka_unit_test(rowsArePaddedToTheAlignment),
        cmocka_unit_test(glslIsEmbedded),
        cmocka_unit_test(sceneWithoutDirectionSetAndBadForms),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
