/* scatter.c: q(x_v, ω) for every vertex and channel, per frame, from the
 * direction set's rows in any storage form (renderer.h; Hao–Varshney 2004
 * §3.2, moved to the GPU as its §6 suggests).
 *
 * GPU storage of the scattering data: one buffer holding every direction's
 * row (nv·channels values, float32 or packed bytes), each row padded to the
 * SSBO offset alignment so that the three rows a frame needs can be bound
 * with glBindBufferRange. A bound range is one row (a few MB), far below
 * GL_MAX_SHADER_STORAGE_BLOCK_SIZE (128 MiB on llvmpipe), while the whole
 * table (1 GB for the 437K dragon in RGB float) only needs to fit in memory.
 *
 * Compressed forms (format 1.1, Hao–Varshney 2004 §4) stay compressed on
 * the GPU: the SH codes (§4.1, each vertex's codes word-aligned), and for
 * the reference form the reference rows (laid out like a lloyd8 file's, one
 * entry per reference) plus each coded vertex's triangle and weight codes
 * (§4.2–4.3). Two passes: the references' values, then every coded vertex
 * (blend of three of them plus its SH-coded delta).
 * Per frame the CPU does only the light-dependent, vertex-independent work:
 * it folds the direction weights into the 256-level tables and the SH basis
 * values y_i(light) into the SH tables (a few thousand products), exactly as
 * the C decoder (common/src/decode.c) does, so the GPU's per-vertex sums use
 * the very same float terms and give the C decoder's result to the bit.
 *
 * The CPU path (SSS_EVAL_CPU) decodes with sss_decode_all and uploads.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gl_util.h"
#include "renderer.h"
#include "shaders.h"
#include "sss/clock.h"
#include "sss/decode.h"

static double now_ms(void) { return 1e3 * sss_now(); }

sss_result sss_scatter_create(sss_scatter *s, const sss_gpu_mesh *m, sss_error *err)
{
    const sss_bake_file *f = m->f;
    const uint32_t nv = m->nv, C = m->C;
    s->cpu_q = malloc((size_t)nv * C * sizeof(float));
    if (!s->cpu_q) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");

    const sss_quant qt = f->quant;
    const int l8 = qt == SSS_QUANT_LLOYD8, refs = qt == SSS_QUANT_REFS, sh = qt == SSS_QUANT_SH;
    if (qt != SSS_QUANT_FLOAT && !l8 && !refs && !sh)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: storage form %d is not supported", (int)qt);
    const sss_shcode *shc = &f->sh;
    s->sh_levels = shc->ncoef ? sss_shq_levels(shc->kind) : 0;
    if ((sh || refs) && shc->ncoef && !s->sh_levels)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: SH code kind %u is not supported", shc->kind);
    /* SH-only codes every vertex, in vertex order; the reference form codes
     * the others (the reader has checked both). */
    s->ncoded = sh || refs ? shc->ncoded : 0;
    if ((sh && s->ncoded != nv) || (refs && (uint64_t)s->ncoded + f->ref.nref != nv))
        return sss_fail(err, SSS_ERR_CORRUPT, "renderer: %u coded vertices do not match %u vertices", s->ncoded, nv);

    /* Programs: the row interpolation (float, lloyd8, and pass 1 of the
     * reference form) and the coded-vertex pass (compressed forms). */
    int ok = 1;
    /* A scene bake without the direction-set effect (format 1.2,
     * docs/scenes.md) has no rows to interpolate: no program is built, and
     * the per-vertex values come from the effect evaluation
     * (sss_renderer_upload_q, runtime/src/render/scene_view.c). */
    const int no_set = f->fx.mask && !(f->fx.mask & SSS_FX_DIR_SET);
    if (!sh && !no_set) {
        GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, refs ? "#define LLOYD8 1\n#define REFS 1\n" : l8 ? "#define LLOYD8 1\n" : "",
                                   sss_glsl_scatter_comp, err);
        ok = cs && (s->prog_cs = sss_gl_link(cs, 0, err)) != 0;
    }
    if (ok && (sh || refs)) {
        char pre[192];
        snprintf(pre, sizeof pre, "#define CHANNELS %u\n#define NCOEF %u\n#define SH_LEVELS %u\n%s%s", C, shc->ncoef,
                 s->sh_levels ? s->sh_levels : 256u, shc->kind == SSS_SHQ_LLOYD4 ? "#define SH_NIBBLE 1\n" : "",
                 refs ? "#define REFS 1\n" : "");
        GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_scatter_coded_comp, err);
        ok = cs && (s->prog_coded = sss_gl_link(cs, 0, err)) != 0;
    }
    if (!ok) return SSS_ERR_UNSUPPORTED;

    /* Buffers bound whole must fit one storage block. */
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    const uint32_t per_word = shc->kind == SSS_SHQ_LLOYD4 ? 8 : 4, ncv = C * shc->ncoef;
    const uint32_t vwords = shc->ncoef ? (ncv + per_word - 1) / per_word : 0;
    const uint64_t code_bytes = (uint64_t)s->ncoded * vwords * 4;
    const uint64_t whole[3] = {(uint64_t)nv * C * sizeof(float), code_bytes,
                               (uint64_t)s->ncoded * 3 * sizeof(uint32_t)};
    for (int k = 0; k < 3; k++)
        if (max_block > 0 && whole[k] > (uint64_t)max_block)
            return sss_fail(err, SSS_ERR_UNSUPPORTED,
                            "renderer: a %.1f MiB storage buffer is needed, above this GL's limit of %.1f MiB",
                            (double)whole[k] / 1048576.0, (double)max_block / 1048576.0);

    /* Direction rows, each padded to the SSBO offset alignment: the
     * vertices' rows (float, lloyd8) or the references' (§4.2). */
    if (!sh && !no_set) {
        s->row_n = refs ? f->ref.nref : nv;
        s->row_bytes = (GLsizeiptr)s->row_n * C * (l8 || refs ? 1 : 4);
        s->row_stride = sss_gl_row_stride(s->row_bytes);
        const void *src = refs ? (const void *)f->ref.idx : l8 ? (const void *)f->qidx : (const void *)f->q;
        s->rows = sss_gl_rows(src, f->dirs.n, s->row_bytes, s->row_stride);
    }
    if (l8 || refs) {
        s->lvl = refs ? f->ref.levels : f->levels;
        s->fold_l = malloc((size_t)3 * C * 256 * sizeof(float));
        s->levels = sss_gl_ssbo((GLsizeiptr)3 * C * 256 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    }
    if (shc->ncoef && (sh || refs)) {
        /* The codes as stored, but each vertex's C·ncoef codes starting on
         * a word of their own (at most 3 bytes of padding per vertex): an
         * invocation then loads its vertex's few words once, at fixed
         * offsets, instead of one word per code. */
        uint32_t *words = calloc((size_t)s->ncoded * vwords + 1, sizeof *words);
        if (words) {
            const uint32_t bits = 32 / per_word;
            for (size_t k = 0; k < s->ncoded; k++)
                for (uint32_t b = 0; b < ncv; b++)
                    words[k * vwords + b / per_word] |= sss_shq_code(shc->code, shc->kind, (uint64_t)k * ncv + b)
                                                        << (b % per_word * bits);
            s->sh_codes = sss_gl_ssbo((GLsizeiptr)code_bytes, words, GL_STATIC_DRAW);
            free(words);
        }
        size_t ntab = (size_t)C * shc->ncoef * s->sh_levels;
        s->fold_sh = malloc(ntab * sizeof(float));
        s->sh_tab = sss_gl_ssbo((GLsizeiptr)(ntab * sizeof(float)), NULL, GL_DYNAMIC_DRAW);
    }
    if (refs) {
        const sss_refcode *rf = &f->ref;
        s->ref_q = sss_gl_ssbo((GLsizeiptr)rf->nref * C * sizeof(float), NULL, GL_DYNAMIC_COPY);
        s->ref_vertex = sss_gl_ssbo((GLsizeiptr)rf->nref * sizeof(uint32_t), rf->ref_vertex, GL_STATIC_DRAW);
        s->ref_tri = sss_gl_ssbo((GLsizeiptr)rf->nrt * 3 * sizeof(uint32_t), rf->ref_tri, GL_STATIC_DRAW);
        /* one record per coded vertex: its vertex, its reference triangle,
         * its two weight codes packed in one word (≤ 16 bits each) */
        uint32_t *rec = malloc(((size_t)s->ncoded * 3 + 1) * sizeof *rec);
        /* every weight a code can stand for, as coded_weights in the C
         * decoder computes it (in double): at most 65536 values, and the
         * GPU then needs no double division */
        const uint32_t nw = rf->wbits == 16 ? 65536u : 256u;
        double *wt = malloc(nw * sizeof *wt);
        if (rec && wt) {
            for (size_t k = 0; k < s->ncoded; k++) {
                rec[3 * k] = rf->coded_vertex[k];
                rec[3 * k + 1] = rf->vtri[k];
                rec[3 * k + 2] = (uint32_t)rf->w[2 * k] | (uint32_t)rf->w[2 * k + 1] << 16;
            }
            const double span = (double)rf->w_hi - rf->w_lo, wmax = rf->wbits == 16 ? 65535.0 : 255.0;
            for (uint32_t x = 0; x < nw; x++) wt[x] = rf->w_lo + span * ((double)x / wmax);
            s->coded_rec = sss_gl_ssbo((GLsizeiptr)s->ncoded * 3 * sizeof(uint32_t), rec, GL_STATIC_DRAW);
            s->wtab = sss_gl_ssbo((GLsizeiptr)nw * sizeof(double), wt, GL_STATIC_DRAW);
        }
        free(rec);
        free(wt);
    }
    if ((s->lvl && !s->fold_l) || (s->sh_tab && (!s->fold_sh || !s->sh_codes)) || (refs && !s->wtab))
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    return SSS_OK;
}

void sss_scatter_destroy(sss_scatter *s)
{
    GLuint bufs[9] = {s->rows, s->levels, s->sh_codes, s->sh_tab, s->ref_q,
                      s->ref_vertex, s->ref_tri, s->coded_rec, s->wtab};
    glDeleteBuffers(9, bufs);
    if (s->prog_cs) glDeleteProgram(s->prog_cs);
    if (s->prog_coded) glDeleteProgram(s->prog_coded);
    free(s->cpu_q);
    free(s->fold_l);
    free(s->fold_sh);
}

void sss_scatter_cpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3])
{
    double t0 = now_ms();
    sss_decode_all(m->f, l, s->cpu_q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, m->qbuf);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)m->nv * m->C * sizeof(float), s->cpu_q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    s->cpu_ms = now_ms() - t0;
}

void sss_scatter_gpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3], GLuint query)
{
    const sss_bake_file *f = m->f;
    const uint32_t C = m->C;
    uint32_t idx[3] = {0, 0, 0};
    double w[3] = {0.0, 0.0, 0.0};
    if (s->rows && sss_dirset_lookup(&f->dirs, l, idx, w) < 0 && f->dirs.ntri > 0) {
        idx[0] = idx[1] = idx[2] = 0;
        w[0] = w[1] = w[2] = 0.0; /* zero or NaN light: no scattering */
    }
    /* Light-dependent tables, folded on the CPU in double and rounded once,
     * term for term what the C decoder forms (see the top of this file). */
    if (s->fold_l) {
        /* T_t[c][x] = w_t · level_c[x]: the §3.2 interpolation of 8-bit rows
         * becomes three table loads per value */
        const size_t n = (size_t)C * 256;
        for (size_t t = 0; t < 3; t++)
            for (size_t x = 0; x < n; x++) s->fold_l[t * n + x] = (float)(w[t] * s->lvl[x]);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->levels);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(3 * n * sizeof(float)), s->fold_l);
    }
    if (s->fold_sh) {
        /* T_c,i[x] = table_c,i[x] · y_i(ω): q̃ = Σ_i c_i y_i(ω) (§4.1) becomes
         * one table load per coefficient */
        const size_t n = (size_t)C * f->sh.ncoef * s->sh_levels;
        sss_decode_fold_sh(f, l, s->fold_sh);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->sh_tab);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(n * sizeof(float)), s->fold_sh);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glBeginQuery(GL_TIME_ELAPSED, query);
    GLuint count = s->row_n * C;
    if (s->prog_cs && count > 0) {
        /* rows of the vertices (float, lloyd8), or pass 1 of the reference
         * form: the references' values, also scattered to their vertices */
        glUseProgram(s->prog_cs);
        for (int k = 0; k < 3; k++)
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, (GLuint)k, s->rows, s->row_stride * (GLintptr)idx[k],
                              (s->row_bytes + 3) / 4 * 4);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m->qbuf);
        if (s->levels) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s->levels);
        if (s->ref_q) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, s->ref_q);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s->ref_vertex);
        }
        glUniform3f(glGetUniformLocation(s->prog_cs, "u_w"), (float)w[0], (float)w[1], (float)w[2]);
        glUniform1ui(glGetUniformLocation(s->prog_cs, "u_count"), count);
        glUniform1ui(glGetUniformLocation(s->prog_cs, "u_channels"), C);
        glDispatchCompute((count + 255) / 256, 1, 1);
    }
    count = s->ncoded;
    if (s->prog_coded && count > 0) {
        /* pass 2 reads the reference values pass 1 has just written */
        if (s->prog_cs) glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(s->prog_coded);
        if (s->sh_codes) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s->sh_codes);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s->sh_tab);
        }
        if (s->coded_rec) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, s->coded_rec);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, s->ref_tri);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, s->ref_q);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s->wtab);
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m->qbuf);
        glUniform1ui(glGetUniformLocation(s->prog_coded, "u_count"), count);
        glDispatchCompute((count + 255) / 256, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glEndQuery(GL_TIME_ELAPSED);
}
