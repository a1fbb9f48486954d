/* gpu.c: a file's direction set laid out for a GPU (sss/gpu.h,
 * docs/gpu_layout.md). The layout is what the shaders of runtime/shaders/
 * read; the per-frame tables are the C decoder's own terms
 * (common/src/decode.c), so the GPU sums give sss_decode_all's floats.
 *
 * Storage on the GPU:
 *   rows    every direction's row (nv·C values, float32 or bytes; the
 *           references' rows in the reference form), each padded to the
 *           offset alignment of a bound range, so that the three rows a
 *           frame needs are bound as ranges: a bound range is one row, far
 *           below any storage-block limit, while the whole table (1 GB for
 *           the 437K dragon in RGB float) only needs to fit in memory;
 *   compressed forms (Hao–Varshney 2004 §4) stay compressed: the SH codes
 *           (§4.1, each vertex's codes on groups of four words; 4, 8 or 16 bits), and for the
 *           reference form each coded vertex's three references and two weights (§4.2–4.3).
 *           Two passes: the references' values, then every coded vertex
 *           (blend of three references plus its SH-coded delta).
 * Per frame the CPU does only the light-dependent, vertex-independent work:
 * it folds the direction weights into the 256-level tables and the SH basis
 * values y_i(ω) into the SH tables (a few thousand products).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common_glsl.h"
#include "sss/decode.h"
#include "sss/gpu.h"

const char *sss_gpu_glsl(const char *name)
{
    if (!name) return NULL;
    if (!strcmp(name, "scatter")) return sss_glsl_scatter_comp;
    if (!strcmp(name, "scatter_coded")) return sss_glsl_scatter_coded_comp;
    return NULL;
}

static void set_buffer(sss_gpu_buffer *b, const char *name, uint32_t binding, uint32_t passes, uint32_t access,
                       const void *data, uint64_t nrows, uint64_t row_bytes, uint64_t stride)
{
    b->name = name;
    b->binding = binding;
    b->passes = passes;
    b->access = access;
    b->data = data;
    b->nrows = nrows;
    b->row_bytes = row_bytes;
    b->stride = stride;
    b->bytes = nrows * stride;
}

static void one_block(sss_gpu_buffer *b, const char *name, uint32_t binding, uint32_t passes, uint32_t access,
                      const void *data, uint64_t bytes)
{
    set_buffer(b, name, binding, passes, access, data, 1, bytes, bytes);
}

static void set_program(sss_gpu_program *p, const char *name, uint32_t count)
{
    p->name = name;
    p->source = sss_gpu_glsl(name);
    p->count = count;
    p->groups = (uint32_t)(((uint64_t)count + SSS_GPU_GROUP_SIZE - 1) / SSS_GPU_GROUP_SIZE);
}

static sss_result layout_create(const sss_bake_file *f, uint32_t row_alignment, int vector, sss_gpu_layout *L,
                                sss_error *err)
{
    memset(L, 0, sizeof *L);
    const uint32_t nv = f->mesh.nv, C = f->channels;
    const sss_quant qt = f->quant;
    const int l8 = qt == SSS_QUANT_LLOYD8, refs = qt == SSS_QUANT_REFS, sh = qt == SSS_QUANT_SH;
    if (qt != SSS_QUANT_FLOAT && !l8 && !refs && !sh)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "gpu layout: storage form %d is not supported", (int)qt);
    if (row_alignment & (row_alignment - 1))
        return sss_fail(err, SSS_ERR_ARG, "gpu layout: row alignment %u is not a power of two", row_alignment);
    const uint64_t align = row_alignment < 4 ? 4 : row_alignment;
    L->f = f;
    L->nv = nv;
    L->channels = C;
    L->quant = qt;
    for (int k = 0; k < SSS_GPU_BUFFERS; k++) L->buffer[k].name = "";
    const uint32_t both = 1u << SSS_GPU_PASS_ROWS | 1u << SSS_GPU_PASS_CODED;
    const uint64_t q_bytes = (uint64_t)nv * C * sizeof(float);
    if ((uint64_t)nv * C > UINT32_MAX)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "gpu layout: %u vertices x %u channels exceed 2^32 entries", nv, C);

    /* A scene bake without the direction-set effect (format 1.2,
     * docs/scenes.md) has no rows to interpolate: only q, which the effect
     * evaluation fills (sss/effects.h). */
    if (f->fx.mask && !(f->fx.mask & SSS_FX_DIR_SET)) {
        one_block(&L->buffer[SSS_GPU_BUF_Q], "q", 3, 0, SSS_GPU_WRITTEN, NULL, q_bytes);
        return SSS_OK;
    }
    const sss_shcode *shc = &f->sh;
    L->sh_levels = (sh || refs) && shc->ncoef ? sss_decode_fold_levels(shc->kind) : 0;
    if ((sh || refs) && shc->ncoef && !L->sh_levels) {
        memset(L, 0, sizeof *L);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "gpu layout: SH code kind %u is not supported", shc->kind);
    }
    /* SH-only codes every vertex, in vertex order; the reference form codes
     * the others (the reader has checked both). */
    L->ncoded = sh || refs ? shc->ncoded : 0;
    if ((sh && L->ncoded != nv) || (refs && (uint64_t)L->ncoded + f->ref.nref != nv)) {
        uint32_t n = L->ncoded;
        memset(L, 0, sizeof *L);
        return sss_fail(err, SSS_ERR_CORRUPT, "gpu layout: %u coded vertices do not match %u vertices", n, nv);
    }
    one_block(&L->buffer[SSS_GPU_BUF_Q], "q", 3, sh ? 1u << SSS_GPU_PASS_CODED : refs ? both : 1u << SSS_GPU_PASS_ROWS,
              SSS_GPU_WRITTEN, NULL, q_bytes);

    /* rows pass: the vertices' rows (float, lloyd8) or the references'
     * (§4.2), interpolated between the light's three directions (§3.2) */
    if (!sh) {
        L->ndirs = f->dirs.n;
        L->row_n = refs ? f->ref.nref : nv;
        /* Q's rows instead (format 1.7: never next to the compressed forms) */
        L->vector = vector && f->qvec && !refs;
        const uint64_t row_bytes = L->vector ? (uint64_t)nv * C * 12u : (uint64_t)L->row_n * C * (l8 || refs ? 1 : 4);
        const uint64_t stride = (row_bytes + align - 1) / align * align;
        L->row_range = (row_bytes + 3) / 4 * 4;
        const void *src = L->vector ? (const void *)f->qvec
                          : refs  ? (const void *)f->ref.idx
                          : l8    ? (const void *)f->qidx
                                  : (const void *)f->q;
        set_buffer(&L->buffer[SSS_GPU_BUF_ROWS], "rows", 0, 1u << SSS_GPU_PASS_ROWS, SSS_GPU_UPLOAD, src, L->ndirs,
                   row_bytes, stride);
        set_program(&L->pass[SSS_GPU_PASS_ROWS], "scatter", L->row_n * C);
        snprintf(L->pass[SSS_GPU_PASS_ROWS].defines, sizeof L->pass[0].defines, "%s",
                 L->vector ? "#define VECTOR 1\n" : refs ? "#define LLOYD8 1\n#define REFS 1\n" : l8 ? "#define LLOYD8 1\n" : "");
        /* four tables: the 4-nearest blend's (§3.2, Fig. 3); a triangle frame leaves the fourth 0 */
        if ((l8 || refs) && !L->vector) L->levels_bytes = (uint64_t)4 * C * 256 * sizeof(float);
    }
    if (sh || refs) {
        set_program(&L->pass[SSS_GPU_PASS_CODED], "scatter_coded", L->ncoded);
        snprintf(L->pass[SSS_GPU_PASS_CODED].defines, sizeof L->pass[0].defines,
                 "#define CHANNELS %u\n#define NCOEF %u\n#define SH_LEVELS %u\n%s%s", C, shc->ncoef,
                 L->sh_levels ? L->sh_levels : 256u,
                 shc->kind == SSS_SHQ_LLOYD4    ? "#define SH_NIBBLE 1\n"
                 : shc->kind == SSS_SHQ_LINEAR16 ? "#define SH_LINEAR16 1\n"
                 : shc->kind == SSS_SHQ_LINEAR8  ? "#define SH_LINEAR8 1\n"
                                                 : "",
                 refs ? "#define REFS 1\n" : "");
        if (shc->ncoef) {
            /* The codes as stored, but each vertex's C·ncoef codes starting
             * on a word of their own and padded to a group of four words
             * (one uvec4 load), and quad-major: word n of coded vertex k at
             * ((n / 4)·ncoded + k)·4 + n mod 4, so that neighbouring
             * invocations (vertices) read neighbouring groups. Vertex-major
             * (k·W + n), a group's loads were W words apart, a cache line
             * each: 74 words per vertex at order 7 in 16 bits, and the
             * SH-only frame was 50× lloyd8's on llvmpipe; one word per load,
             * each load was a loop over the lanes there (docs/benchmarks.md,
             * "Compressed forms' per-frame cost"). */
            const uint32_t per_word = shc->kind == SSS_SHQ_LLOYD4 ? 8 : shc->kind == SSS_SHQ_LINEAR16 ? 2 : 4;
            const uint32_t ncv = C * shc->ncoef;
            const uint32_t vwords = (ncv + per_word - 1) / per_word, bits = 32 / per_word;
            const uint32_t quads = (vwords + 3) / 4;
            uint32_t *words = calloc((size_t)L->ncoded * quads * 4 + 1, sizeof *words);
            if (!words) goto oom;
            L->owned_[0] = words;
            for (size_t k = 0; k < L->ncoded; k++)
                for (uint32_t b = 0; b < ncv; b++) {
                    const uint32_t n = b / per_word;
                    words[((size_t)(n / 4) * L->ncoded + k) * 4 + n % 4] |=
                        sss_shq_code(shc->code, shc->kind, (uint64_t)k * ncv + b) << (b % per_word * bits);
                }
            one_block(&L->buffer[SSS_GPU_BUF_SH_CODES], "sh_codes", 0, 1u << SSS_GPU_PASS_CODED, SSS_GPU_UPLOAD, words,
                      (uint64_t)L->ncoded * quads * 16);
            /* The frame's tables as a uniform block when they fit the 16 KiB
             * minimum of GL_MAX_UNIFORM_BLOCK_SIZE (and Vulkan's
             * maxUniformBufferRange): the linear kinds' C·ncoef steps and
             * order 3's 4-bit pair tables (12.2 KiB in RGB). On llvmpipe a
             * uniform load at a constant index is one scalar load, and at a
             * code-dependent one a gather, where a storage-buffer load is a
             * loop over the lanes (docs/benchmarks.md). std140 gives a
             * float[] a 16-byte stride, so the block is a vec4[]. */
            const uint64_t fl = sss_decode_fold_floats(shc->kind, C, shc->ncoef);
            L->sh_uniform = fl * sizeof(float) <= 16384;
            L->sh_bytes = L->sh_uniform ? (fl + 3) / 4 * 16 : fl * sizeof(float);
            if (L->sh_uniform) {
                const size_t d = strlen(L->pass[SSS_GPU_PASS_CODED].defines);
                snprintf(L->pass[SSS_GPU_PASS_CODED].defines + d, sizeof L->pass[0].defines - d, "#define SH_UBO %u\n",
                         (unsigned)((fl + 3) / 4));
            }
        }
    }
    if (refs) {
        const sss_refcode *rf = &f->ref;
        /* four floats a reference, whatever C (1 or 3): the coded pass
         * loads a reference's values as one vec4 */
        one_block(&L->buffer[SSS_GPU_BUF_REF_Q], "ref_q", 5, both, SSS_GPU_WRITTEN, NULL,
                  (uint64_t)rf->nref * 4 * sizeof(float));
        one_block(&L->buffer[SSS_GPU_BUF_REF_VERTEX], "ref_vertex", 6, 1u << SSS_GPU_PASS_ROWS, SSS_GPU_UPLOAD,
                  rf->ref_vertex, (uint64_t)rf->nref * sizeof(uint32_t));
        /* One record per coded vertex, resolved here once: its vertex and
         * its reference triangle's three references (one uvec4 load), and
         * its two weights as the floats the C decoder blends with
         * (sss_decode_ref_weight, in double rounded to float: the GPU needs
         * no division; one vec2 load). Each table a vertex followed before
         * (triangle, then references, then two weight codes, then their
         * weights) was a load of its own, and on llvmpipe every load a loop
         * over the lanes (docs/benchmarks.md). 24 bytes a coded vertex. */
        uint32_t *rec = malloc(((size_t)L->ncoded * 4 + 1) * sizeof *rec);
        float *wt = malloc(((size_t)L->ncoded * 2 + 1) * sizeof *wt);
        L->owned_[1] = rec;
        L->owned_[2] = wt;
        if (!rec || !wt) goto oom;
        const uint32_t nw = rf->wbits == 16 ? 65536u : 256u;
        float *wtab = malloc(nw * sizeof *wtab);
        if (!wtab) goto oom;
        for (uint32_t x = 0; x < nw; x++) wtab[x] = sss_decode_ref_weight(rf, x);
        for (size_t k = 0; k < L->ncoded; k++) {
            const uint32_t *t = rf->ref_tri + 3 * (size_t)rf->vtri[k];
            rec[4 * k] = rf->coded_vertex[k];
            for (int j = 0; j < 3; j++) rec[4 * k + 1 + j] = t[j];
            wt[2 * k] = wtab[rf->w[2 * k]];
            wt[2 * k + 1] = wtab[rf->w[2 * k + 1]];
        }
        free(wtab);
        one_block(&L->buffer[SSS_GPU_BUF_CODED], "coded", 1, 1u << SSS_GPU_PASS_CODED, SSS_GPU_UPLOAD, rec,
                  (uint64_t)L->ncoded * 4 * sizeof(uint32_t));
        one_block(&L->buffer[SSS_GPU_BUF_WEIGHTS], "weights", 6, 1u << SSS_GPU_PASS_CODED, SSS_GPU_UPLOAD, wt,
                  (uint64_t)L->ncoded * 2 * sizeof(float));
    }
    return SSS_OK;
oom:
    sss_gpu_layout_free(L);
    return sss_fail(err, SSS_ERR_NOMEM, "gpu layout: out of memory");
}

sss_result sss_gpu_layout_create(const sss_bake_file *f, uint32_t row_alignment, sss_gpu_layout *L, sss_error *err)
{
    return layout_create(f, row_alignment, 1, L, err);
}

sss_result sss_gpu_layout_create_scalar(const sss_bake_file *f, uint32_t row_alignment, sss_gpu_layout *L,
                                        sss_error *err)
{
    return layout_create(f, row_alignment, 0, L, err);
}

void sss_gpu_layout_free(sss_gpu_layout *L)
{
    if (!L) return;
    for (int k = 0; k < 3; k++) free(L->owned_[k]);
    memset(L, 0, sizeof *L);
}

void sss_gpu_buffer_pack(const sss_gpu_buffer *b, void *dst)
{
    char *d = dst;
    const char *s = b->data;
    for (uint64_t j = 0; j < b->nrows; j++) {
        if (s) memcpy(d + j * b->stride, s + j * b->row_bytes, b->row_bytes);
        else memset(d + j * b->stride, 0, b->row_bytes);
        memset(d + j * b->stride + b->row_bytes, 0, b->stride - b->row_bytes);
    }
}

sss_result sss_gpu_frame_init(const sss_gpu_layout *L, sss_gpu_frame *fr, sss_error *err)
{
    memset(fr, 0, sizeof *fr);
    if (L->levels_bytes && !(fr->levels = malloc(L->levels_bytes))) goto oom;
    if (L->sh_bytes && !(fr->sh = calloc(1, L->sh_bytes))) goto oom; /* a uniform block's padding stays 0 */
    fr->levels_bytes = L->levels_bytes;
    fr->sh_bytes = L->sh_bytes;
    return SSS_OK;
oom:
    sss_gpu_frame_free(fr);
    return sss_fail(err, SSS_ERR_NOMEM, "gpu layout: out of memory");
}

void sss_gpu_frame_free(sss_gpu_frame *fr)
{
    if (!fr) return;
    free(fr->levels);
    free(fr->sh);
    memset(fr, 0, sizeof *fr);
}

void sss_gpu_frame_eval(const sss_gpu_layout *L, const double light[3], sss_gpu_frame *fr)
{
    sss_gpu_frame_eval_interp(L, light, SSS_INTERP_TRIANGLE, fr);
}

void sss_gpu_frame_eval_interp(const sss_gpu_layout *L, const double light[3], sss_interp interp,
                               sss_gpu_frame *fr)
{
    const sss_bake_file *f = L->f;
    const uint32_t C = L->channels;
    uint32_t idx[4] = {0, 0, 0, 0};
    double w[4] = {0.0, 0.0, 0.0, 0.0};
    for (int p = 0; p < SSS_GPU_PASSES; p++) fr->u_count[p] = L->pass[p].count;
    fr->u_channels = C;
    /* the light as sss_decode_all takes it: normalised once here; a zero
     * or non-finite one (or a file without directions) is no light */
    const double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    const int lit = f->dirs.n > 0 && len > 0.0 && isfinite(len);
    const double d[3] = {lit ? light[0] / len : 0.0, lit ? light[1] / len : 0.0, lit ? light[2] / len : 0.0};
    const int n4 = interp == SSS_INTERP_NEAREST4;
    fr->nrows = n4 ? 4 : 3;
    if (lit && L->ndirs) {
        if (n4) sss_dirset_nearest4(&f->dirs, d, idx, w);
        else sss_dirset_lookup(&f->dirs, d, idx, w);
    }
    for (int k = 0; k < 4; k++) {
        fr->row[k] = idx[k];
        fr->row_offset[k] = (uint64_t)idx[k] * L->buffer[SSS_GPU_BUF_ROWS].stride;
        fr->u_w[k] = (float)w[k];
    }
    for (int k = 0; k < 3; k++) fr->u_light[k] = (float)d[k]; /* as sss_decode_vector_range rounds it */
    /* Light-dependent tables, folded in double and rounded once, term for
     * term what the C decoder forms (common/src/decode.c). */
    if (fr->levels) {
        /* T_t[c][x] = w_t · level_c[x]: the §3.2 interpolation of 8-bit rows
         * becomes three (4-nearest: four) table loads per value */
        const float *lvl = L->quant == SSS_QUANT_REFS ? f->ref.levels : f->levels;
        const size_t n = (size_t)C * 256;
        for (size_t t = 0; t < 4; t++)
            for (size_t x = 0; x < n; x++) fr->levels[t * n + x] = (float)(w[t] * lvl[x]);
    }
    if (fr->sh) {
        /* T_c,i[x] = table_c,i[x] · y_i(ω): q̃ = Σ_i c_i y_i(ω) (§4.1)
         * becomes one table load per coefficient */
        if (lit) sss_decode_fold_sh(f, d, fr->sh);
        else memset(fr->sh, 0, L->sh_bytes);
    }
}
