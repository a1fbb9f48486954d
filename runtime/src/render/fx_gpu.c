/* fx_gpu.c: the scene's lights summed on the GPU (sss_fx_gpu_*, sss/render.h;
 * docs/scenes.md "Viewer"), for `sss-view FILE.sss --scene S.json`: the
 * driver of the scene-light passes of the pass table (effects/effects.h).
 *
 * The CPU does only the vertex-independent work per frame (the shell rows
 * and weights, the rotated probe coefficients), with the very functions
 * the CPU path uses (sss_fx_point_weights, sss_scene_eval_light). Only the
 * passes and programs the file needs are built, from its effect set
 * (format §5.10): the row kernel (light_row.comp.glsl) for QDIR or a
 * direction set, each effect's own program and data for the others. A file
 * without PSHL has no shell program and no shell buffer; without ENVT, no
 * environment program.
 *
 * Storage: the per-light data the file carries, uploaded once by each pass
 * (effects/). Rows of nv·channels floats (QDIR's, PSHL's) are padded to the
 * SSBO offset alignment, as the renderer's direction rows are, so that the
 * rows a light needs are bound with glBindBufferRange.
 *
 * Per frame, for each light in the scene's order, the pass of its kind
 * binds its inputs and one dispatch adds the light's term to the sum
 * (light_sum.glsl). A direction-set light first runs the renderer's own
 * §3.2 pass into its q buffer; the sum then goes to a buffer of this module
 * and is copied into q at the end.
 */
#include <epoxy/gl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effects.h"
#include "gl_util.h"
#include "shaders.h"

struct sss_fx_gpu {
    const sss_scene_eval *ev;
    sss_renderer *r;
    uint32_t nv, C;
    GLsizeiptr row_bytes, row_stride; /* one row: nv·C floats; padded */
    GLuint prog_row;    /* the row kernel: directional-exact and direction-set lights */
    GLuint acc;         /* the sum when a direction-set light uses the renderer's q buffer */
    uint32_t nset;      /* direction-set lights of the scene */
    void *state[SSS_EFFECTS_MAX]; /* per row of the pass table: its pass, when created */
    unsigned on;        /* bit i: table row i was created */
    unsigned built;
    char desc[64];
};

GLuint sss_pass_light_program(const char *body, uint32_t C, uint32_t ncoef, sss_error *err)
{
    char pre[96];
    if (ncoef) snprintf(pre, sizeof pre, "#define CHANNELS %u\n#define NCOEF %u\n", C, ncoef);
    else snprintf(pre, sizeof pre, "#define CHANNELS %u\n", C);
    const char *parts[3] = {pre, sss_glsl_light_sum, body};
    GLuint cs = sss_gl_compile_parts(GL_COMPUTE_SHADER, parts, 3, err);
    return cs ? sss_gl_link(cs, 0, err) : 0;
}

void sss_pass_light_begin(GLuint p, GLuint count, int first, const double w[3])
{
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_count"), count);
    glUniform1i(glGetUniformLocation(p, "u_first"), first);
    glUniform1dv(glGetUniformLocation(p, "u_w"), 3, w);
}

sss_result sss_fx_gpu_create(const sss_bake_file *f, const sss_scene_eval *ev, sss_renderer *r, sss_fx_gpu **out,
                             sss_error *err)
{
    *out = NULL;
    if (epoxy_gl_version() < 43)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "scene effects on the GPU need OpenGL 4.3 (this context has %d.%d)",
                        epoxy_gl_version() / 10, epoxy_gl_version() % 10);
    sss_fx_gpu *g = calloc(1, sizeof *g);
    if (!g) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    g->ev = ev;
    g->r = r;
    g->nv = f->mesh.nv;
    g->C = f->channels;
    for (uint32_t i = 0; i < sss_scene_eval_count(ev); i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(ev, i, 0.0, &lf);
        g->nset += lf.kind == 1;
    }

    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    g->row_bytes = (GLsizeiptr)g->nv * g->C * (GLsizeiptr)sizeof(float);
    g->row_stride = sss_gl_row_stride(g->row_bytes);
    if (max_block > 0 && (uint64_t)g->row_bytes > (uint64_t)max_block) {
        sss_fx_gpu_destroy(g);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "scene effects: a storage buffer above this GL's limit of %.1f MiB is needed",
                        (double)max_block / 1048576.0);
    }

    /* The row kernel when a pass of the file uses it, then each pass the
     * file carries data for (§5.10–5.13), in table order. */
    const sss_effect_ctx c = {&r->mesh, max_block, g->row_bytes, g->row_stride};
    int rows = 0;
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        rows |= sss_pass_table[i].gpu_bit == SSS_FXGPU_ROWS && sss_effect_present(&sss_pass_table[i], f);
    if (rows && !(g->prog_row = sss_pass_light_program(sss_glsl_light_row_comp, g->C, 0, err))) {
        sss_fx_gpu_destroy(g);
        return SSS_ERR_UNSUPPORTED;
    }
    for (unsigned i = 0; i < sss_pass_table_n; i++) {
        const sss_effect *e = &sss_pass_table[i];
        if (e->light_kind < 0 || !sss_effect_present(e, f)) continue;
        sss_result res = e->create ? e->create(&c, &g->state[i], err) : SSS_OK;
        if (res != SSS_OK) {
            sss_fx_gpu_destroy(g);
            return res;
        }
        g->on |= 1u << i;
        g->built |= e->gpu_bit;
    }
    if (g->nset) g->acc = sss_gl_ssbo(g->row_bytes, NULL, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    if (glGetError() == GL_OUT_OF_MEMORY) {
        sss_fx_gpu_destroy(g);
        return sss_fail(err, SSS_ERR_NOMEM, "scene effects: the GPU is out of memory for the effect data");
    }
    /* "rows + shells + env": each program once, in the order of its bit */
    size_t k = 0;
    g->desc[0] = 0;
    for (unsigned bit = 1; bit <= SSS_FXGPU_ENV; bit <<= 1)
        for (unsigned i = 0; i < sss_pass_table_n; i++)
            if ((g->on >> i & 1) && sss_pass_table[i].gpu_bit == bit) {
                k += (size_t)snprintf(g->desc + k, sizeof g->desc - k, "%s%s", k ? " + " : "",
                                      sss_pass_table[i].describe(g->state[i]));
                break;
            }
    if (!k) snprintf(g->desc, sizeof g->desc, "none");
    *out = g;
    return SSS_OK;
}

void sss_fx_gpu_destroy(sss_fx_gpu *g)
{
    if (!g) return;
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if ((g->on >> i & 1) && sss_pass_table[i].destroy) sss_pass_table[i].destroy(g->state[i]);
    if (g->acc) glDeleteBuffers(1, &g->acc);
    if (g->prog_row) glDeleteProgram(g->prog_row);
    free(g);
}

unsigned sss_fx_gpu_programs(const sss_fx_gpu *g) { return g->built; }

const char *sss_fx_gpu_describe(const sss_fx_gpu *g) { return g->desc; }

void sss_fx_gpu_frame(sss_fx_gpu *g, double angle)
{
    const GLuint qb = sss_renderer_q_buffer(g->r);
    /* with a direction-set light the renderer's q buffer is the input of
     * that light's term: sum elsewhere, copy at the end */
    const GLuint target = g->nset ? g->acc : qb;
    sss_effect_frame fr;
    memset(&fr, 0, sizeof fr);
    fr.r = g->r;
    fr.p = sss_scene_eval_view(g->ev); /* the near terms of an OWNT file, per light */
    fr.row_program = g->prog_row;
    fr.whole = (g->row_bytes + 3) / 4 * 4;
    int first = 1;
    for (uint32_t i = 0; i < sss_scene_eval_count(g->ev); i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(g->ev, i, angle, &lf);
        if (!(sss_scene_eval_kinds(g->ev) >> lf.kind & 1)) continue; /* switched off (the panel) */
        /* the pass of the light's kind, if the file has its data
         * (sss_scene_eval_create has refused a light it has none for) */
        const sss_effect *e = sss_effect_for_light(lf.kind);
        const unsigned row = e ? (unsigned)(e - sss_pass_table) : 0;
        if (!e || !(g->on >> row & 1)) continue;
        fr.lf = &lf;
        fr.first = first;
        const GLuint count = e->frame(g->state[row], &fr); /* invocations */
        if (!count) continue;
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, target);
        glDispatchCompute((count + 255) / 256, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        first = 0;
    }
    if (first) {
        /* no light: q = 0, as the CPU path's memset */
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, qb);
        glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32F, GL_RED, GL_FLOAT, NULL);
    } else if (target != qb) {
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glBindBuffer(GL_COPY_READ_BUFFER, target);
        glBindBuffer(GL_COPY_WRITE_BUFFER, qb);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, g->row_bytes);
        glBindBuffer(GL_COPY_READ_BUFFER, 0);
        glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
}

sss_result sss_scene_render_image(sss_renderer *r, sss_scene_eval *ev, sss_fx_gpu *g, const sss_view_params *p,
                                  double angle, int width, int height, float **rgb, float **hdr, sss_error *err)
{
    *rgb = NULL;
    if (hdr) *hdr = NULL;
    const sss_bake_file *f = r->mesh.f;
    float *q = malloc((size_t)f->mesh.nv * f->channels * sizeof *q + 1);
    if (!q) return sss_fail(err, SSS_ERR_NOMEM, "scene: out of memory for %u vertices", f->mesh.nv);
    sss_scene_eval_set_view(ev, p);
    if (g) {
        /* the GPU sum, read back so that the one image path draws it */
        sss_fx_gpu_frame(g, angle);
        sss_renderer_read_q(r, q);
    } else {
        sss_scene_eval_frame(ev, angle, q);
    }
    /* the sum holds every light's near terms already (sss_scene_eval_frame) */
    sss_view_params d = *p;
    d.near_terms = 0;
    d.single = -1; /* drawn for one directional light only: a sum of lights has none (docs/layers.md §7) */
    sss_result res = sss_renderer_render_q_image(r, &d, q, width, height, rgb, hdr, err);
    free(q);
    return res;
}
