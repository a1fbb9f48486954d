/* scatter.c: q(x_v, ω) for every vertex and channel, per frame, from the
 * direction set's rows in any storage form (renderer.h; Hao–Varshney 2004
 * §3.2, moved to the GPU as its §6 suggests).
 *
 * What the GPU holds and what changes per frame is libsss's GPU layout
 * (sss/gpu.h, common/src/gpu.c; docs/gpu_layout.md): the rows padded to the
 * SSBO offset alignment and bound as three ranges, the compressed forms'
 * codes and records, and per frame the folded tables, which are the C
 * decoder's own terms, so the GPU's sums give its result to the bit. This
 * file is that layout's GL consumer: it makes the buffers and programs,
 * uploads the frame's tables and dispatches the passes. The SH tables
 * are bound as a uniform block or a storage buffer, whichever is faster
 * on the GL at hand (sss_scatter_storage; docs/viewer.md, "SH tables on
 * the GPU").
 *
 * The CPU path (SSS_EVAL_CPU) decodes with sss_decode_all_interp (or, for
 * a file with the vector integrals Q, sss_decode_vector_range) and
 * uploads. Both paths offer the paper's 4-nearest blend beside the
 * triangle's (sss_view_params.interp; Hao–Varshney 2004 §3.2, Fig. 3): on
 * the GPU the rows pass's NEAREST4 variant, compiled with the other
 * programs, reads a fourth row (docs/gpu_layout.md).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gl_util.h"
#include "renderer.h"
#include "sss/clock.h"
#include "sss/decode.h"

static double now_ms(void) { return 1e3 * sss_now(); }

/* vector 0: q's rows even when the file holds Q (sss_gpu_layout_create_scalar) */
static sss_result scatter_create(sss_scatter *s, const sss_gpu_mesh *m, int vector, sss_error *err)
{
    s->cpu_q = malloc((size_t)m->nv * m->C * sizeof(float));
    if (!s->cpu_q) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    GLint align = 16;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    const uint32_t al = align > 0 ? (uint32_t)align : 4u;
    sss_result res = vector ? sss_gpu_layout_create(m->f, al, &s->layout, err)
                            : sss_gpu_layout_create_scalar(m->f, al, &s->layout, err);
    if (res == SSS_OK) res = sss_gpu_frame_init(&s->layout, &s->frame, err);
    if (res != SSS_OK) return res;
    const sss_gpu_layout *L = &s->layout;

    /* Programs: the row interpolation (float, lloyd8, and pass 1 of the
     * reference form) and the coded-vertex pass (compressed forms); a scene
     * bake without the direction-set effect gets neither, its q comes from
     * the effect evaluation (sss_renderer_upload_q, scene_view.c). */
    for (int p = 0; p < SSS_GPU_PASSES; p++) {
        if (!L->pass[p].name) continue;
        GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, L->pass[p].defines, L->pass[p].source, err);
        if (!cs || !(s->prog[p] = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
        if (p != SSS_GPU_PASS_ROWS) continue;
        char pre[sizeof L->pass[p].defines + sizeof SSS_GPU_NEAREST4_DEFINE];
        snprintf(pre, sizeof pre, "%s%s", L->pass[p].defines, SSS_GPU_NEAREST4_DEFINE);
        cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, L->pass[p].source, err);
        if (!cs || !(s->prog_n4 = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
    }

    /* the coded pass as the layout declares it; its other variants when a frame asks */
    if (s->prog[SSS_GPU_PASS_CODED]) {
        const int st = L->sh_bytes && !L->sh_uniform;
        s->coded[st] = s->prog[SSS_GPU_PASS_CODED];
        s->coded_count[st] = glGetUniformLocation(s->coded[st], "u_count");
    }
    const char *gl = sss_gl_renderer_name();
    s->software = strstr(gl, "llvmpipe") || strstr(gl, "softpipe") || strstr(gl, "SwiftShader");

    /* Each frame sets these uniforms: their locations once, here. */
    for (int p = 0; p <= SSS_GPU_PASSES; p++) {
        const GLuint prog = p < SSS_GPU_PASSES ? s->prog[p] : s->prog_n4;
        struct sss_scatter_uniforms *u = &s->uni[p];
        u->w = prog ? glGetUniformLocation(prog, "u_w") : -1;
        u->light = prog ? glGetUniformLocation(prog, "u_light") : -1;
        u->channels = prog ? glGetUniformLocation(prog, "u_channels") : -1;
        u->count = prog ? glGetUniformLocation(prog, "u_count") : -1;
    }

    /* Buffers bound whole must fit one storage block; so must a row range. */
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    for (int k = 0; k < SSS_GPU_BUFFERS; k++) {
        const uint64_t whole = k == SSS_GPU_BUF_ROWS ? L->row_range : L->buffer[k].bytes;
        if (L->buffer[k].passes && max_block > 0 && whole > (uint64_t)max_block)
            return sss_fail(err, SSS_ERR_UNSUPPORTED,
                            "renderer: a %.1f MiB storage buffer (%s) is needed, above this GL's limit of %.1f MiB",
                            (double)whole / 1048576.0, L->buffer[k].name, (double)max_block / 1048576.0);
    }
    for (int k = 0; k < SSS_GPU_BUFFERS; k++) {
        const sss_gpu_buffer *b = &L->buffer[k];
        if (!b->passes || k == SSS_GPU_BUF_Q) continue; /* q is the mesh's buffer */
        if (k == SSS_GPU_BUF_ROWS)
            s->buf[k] = sss_gl_rows(b->data, b->nrows, (GLsizeiptr)b->row_bytes, (GLsizeiptr)b->stride);
        else
            s->buf[k] = sss_gl_ssbo((GLsizeiptr)b->bytes, b->data,
                                    b->access == SSS_GPU_WRITTEN ? GL_DYNAMIC_COPY : GL_STATIC_DRAW);
    }
    if (L->levels_bytes) s->levels = sss_gl_ssbo((GLsizeiptr)L->levels_bytes, NULL, GL_DYNAMIC_DRAW);
    if (L->sh_bytes) s->sh_tab = sss_gl_ssbo((GLsizeiptr)L->sh_bytes, NULL, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    return SSS_OK;
}

sss_result sss_scatter_create(sss_scatter *s, const sss_gpu_mesh *m, sss_error *err)
{
    return scatter_create(s, m, 1, err);
}

sss_result sss_scatter_create_scalar(sss_scatter *s, const sss_gpu_mesh *m, sss_error *err)
{
    return scatter_create(s, m, 0, err);
}

/* The coded pass with its SH tables as a storage buffer or as the
 * layout's uniform block (sss_view_params.sh_tables), compiled the first
 * time a frame asks; 0 if it does not compile. */
static GLuint coded_program(sss_scatter *s, int storage)
{
    if (s->coded[storage] || s->coded_failed[storage]) return s->coded[storage];
    const sss_gpu_program *pg = &s->layout.pass[SSS_GPU_PASS_CODED];
    char def[sizeof pg->defines];
    snprintf(def, sizeof def, "%s", pg->defines);
    /* the same floats as a storage buffer: the block's line out */
    char *u = strstr(def, "#define SH_UBO ");
    if (storage && u) memmove(u, strchr(u, '\n') + 1, strlen(strchr(u, '\n') + 1) + 1);
    sss_error err = {{0}};
    GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, def, pg->source, &err);
    GLuint prog = cs ? sss_gl_link(cs, 0, &err) : 0;
    if (!prog) {
        fprintf(stderr, "sss-view: the coded pass with its SH tables as a %s: %s\n",
                storage ? "storage buffer" : "uniform block", err.msg);
        s->coded_failed[storage] = 1;
        return 0;
    }
    s->coded_count[storage] = glGetUniformLocation(prog, "u_count");
    return s->coded[storage] = prog;
}

void sss_scatter_destroy(sss_scatter *s)
{
    for (int k = 0; k < 2; k++)
        if (s->coded[k] && s->coded[k] != s->prog[SSS_GPU_PASS_CODED]) glDeleteProgram(s->coded[k]);
    glDeleteBuffers(SSS_GPU_BUFFERS, s->buf);
    glDeleteBuffers(1, &s->levels);
    glDeleteBuffers(1, &s->sh_tab);
    for (int p = 0; p < SSS_GPU_PASSES; p++)
        if (s->prog[p]) glDeleteProgram(s->prog[p]);
    if (s->prog_n4) glDeleteProgram(s->prog_n4);
    free(s->cpu_q);
    sss_gpu_frame_free(&s->frame);
    sss_gpu_layout_free(&s->layout);
}

void sss_scatter_cpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3], int interp)
{
    double t0 = now_ms();
    const sss_interp how = interp == SSS_INTERP_NEAREST4 ? SSS_INTERP_NEAREST4 : SSS_INTERP_TRIANGLE;
    /* the layout's choice of q or Q (Hao–Varshney 2004 §3.2), on both paths */
    if (s->layout.vector) sss_decode_vector_range(m->f, l, how, 0, m->nv, s->cpu_q);
    else sss_decode_all_interp(m->f, l, how, s->cpu_q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, m->qbuf);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)m->nv * m->C * sizeof(float), s->cpu_q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    s->cpu_ms = now_ms() - t0;
}

int sss_scatter_storage(const sss_scatter *s, const sss_view_params *p)
{
    const sss_gpu_layout *L = &s->layout;
    return L->sh_bytes && (!L->sh_uniform || p->sh_tables == SSS_SH_TABLES_STORAGE ||
                           (p->sh_tables == 0 && !s->software));
}

void sss_scatter_gpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3], const sss_view_params *vp,
                     GLuint query)
{
    const sss_gpu_layout *L = &s->layout;
    sss_gpu_frame *fr = &s->frame;
    const int interp = vp->interp;
    const int n4 = interp == SSS_INTERP_NEAREST4;
    /* the coded pass with the tables where they are read fastest here, or
     * the layout's own where this GL cannot compile that variant */
    int storage = sss_scatter_storage(s, vp);
    GLuint coded = s->prog[SSS_GPU_PASS_CODED] ? coded_program(s, storage) : 0;
    if (s->prog[SSS_GPU_PASS_CODED] && !coded) {
        storage = L->sh_bytes && !L->sh_uniform;
        coded = s->prog[SSS_GPU_PASS_CODED];
    }
    /* the light's rows, weights and folded tables (sss/gpu.h) */
    sss_gpu_frame_eval_interp(L, l, n4 ? SSS_INTERP_NEAREST4 : SSS_INTERP_TRIANGLE, fr);
    if (fr->levels) {
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->levels);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)fr->levels_bytes, fr->levels);
    }
    if (fr->sh) {
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->sh_tab);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)fr->sh_bytes, fr->sh);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glBeginQuery(GL_TIME_ELAPSED, query);
    for (int p = 0; p < SSS_GPU_PASSES; p++) {
        const int variant = p == SSS_GPU_PASS_ROWS && n4 ? SSS_GPU_PASSES : p;
        const GLuint prog = variant == SSS_GPU_PASSES ? s->prog_n4 : p == SSS_GPU_PASS_CODED ? coded : s->prog[p];
        const struct sss_scatter_uniforms *u = &s->uni[variant];
        if (!prog || fr->u_count[p] == 0) continue;
        /* the coded pass reads the reference values the rows pass has just written */
        if (p == SSS_GPU_PASS_CODED && s->prog[SSS_GPU_PASS_ROWS]) glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(prog);
        for (int k = 0; k < SSS_GPU_BUFFERS; k++) {
            const sss_gpu_buffer *b = &L->buffer[k];
            if (!(b->passes >> p & 1)) continue;
            if (k == SSS_GPU_BUF_ROWS) {
                for (int t = 0; t < (int)fr->nrows; t++)
                    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, t < 3 ? b->binding + (GLuint)t : SSS_GPU_ROW4_BINDING,
                                      s->buf[k], (GLintptr)fr->row_offset[t], (GLsizeiptr)L->row_range);
            } else {
                glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b->binding, k == SSS_GPU_BUF_Q ? m->qbuf : s->buf[k]);
            }
        }
        if (p == SSS_GPU_PASS_ROWS) {
            if (fr->levels) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s->levels);
            if (n4) glUniform4f(u->w, fr->u_w[0], fr->u_w[1], fr->u_w[2], fr->u_w[3]);
            else glUniform3f(u->w, fr->u_w[0], fr->u_w[1], fr->u_w[2]);
            if (L->vector) glUniform3f(u->light, fr->u_light[0], fr->u_light[1], fr->u_light[2]);
            glUniform1ui(u->channels, fr->u_channels);
        } else if (fr->sh) {
            /* a uniform block where the tables fit one and that is faster here (sss_scatter_storage) */
            glBindBufferBase(storage ? GL_SHADER_STORAGE_BUFFER : GL_UNIFORM_BUFFER, 4, s->sh_tab);
        }
        glUniform1ui(p == SSS_GPU_PASS_CODED ? s->coded_count[storage] : u->count, fr->u_count[p]);
        glDispatchCompute(L->pass[p].groups, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glEndQuery(GL_TIME_ELAPSED);
}
