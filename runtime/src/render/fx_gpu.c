/* fx_gpu.c: the scene's lights summed on the GPU (sss_fx_gpu_*, sss/render.h;
 * docs/scenes.md "Viewer"), for `sss-view FILE.sss --scene S.json`.
 *
 * The CPU does only the vertex-independent work per frame (the shell rows
 * and weights, the rotated probe coefficients), with the very functions
 * the CPU path uses (sss_fx_point_weights, sss_scene_eval_light). Only the
 * programs and buffers the file needs are built, from its effect set
 * (format §5.10): the row program for QDIR or a direction set, the shell
 * program and rows for PSHL, the environment program and transfer for ENVT.
 * A file without PSHL has no shell program and no shell buffer; without
 * ENVT, no environment program.
 *
 * Storage: the per-light data the file carries, uploaded once. QDIR's rows
 * and PSHL's S·n rows (one per shell and direction, nv·channels floats each)
 * are padded to the SSBO offset alignment, as the renderer's direction rows
 * are, so that the rows a light needs are bound with glBindBufferRange: a
 * bound row is far below GL_MAX_SHADER_STORAGE_BLOCK_SIZE even where the
 * whole table (220 MB for 23 k vertices × 200 directions × 4 shells in
 * RGB) is not. ENVT's transfer is bound whole, each (vertex, channel)'s K
 * coefficients padded with zeros to a multiple of 4 so that the kernel
 * reads them as vec4s (on llvmpipe, where every storage-buffer load is a
 * per-lane access, this made the environment term 2–3× faster; a padded
 * term adds exactly 0, so the sum is unchanged).
 *
 * Per frame, for each light in the scene's order, one dispatch adds the
 * light's term to the sum (shaders.h). A direction-set light first runs
 * the renderer's own §3.2 pass into its q buffer; the sum then goes to a
 * buffer of this module and is copied into q at the end.
 */
#include <epoxy/gl.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "shaders.h"
#include "sss/effects.h"
#include "sss/render.h"

struct sss_fx_gpu {
    const sss_bake_file *f;
    const sss_scene_eval *ev;
    sss_renderer *r;
    uint32_t nv, C;
    GLsizeiptr row_bytes, row_stride; /* one row: nv·C floats; padded */
    GLuint prog_rows, prog_shell, prog_env;
    GLuint exact_rows;  /* QDIR, nexact rows */
    GLuint shell_rows;  /* PSHL, S·n rows, row s·n + j */
    GLuint env_t;       /* ENVT transfer */
    GLuint acc;         /* the sum when a direction-set light uses the renderer's q buffer */
    uint32_t nset;      /* direction-set lights of the scene */
    uint32_t k4;        /* SH coefficients per (vertex, channel) on the GPU: K padded to a multiple of 4 */
    unsigned built;
    char desc[64];
};

static GLuint build(const char *defines, uint32_t C, uint32_t ncoef, sss_error *err)
{
    char pre[160];
    snprintf(pre, sizeof pre, "%s#define CHANNELS %u\n#define NCOEF %u\n", defines, C, ncoef ? ncoef : 1u);
    GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_scene_lights_comp, err);
    return cs ? sss_gl_link(cs, 0, err) : 0;
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
    g->f = f;
    g->ev = ev;
    g->r = r;
    g->nv = f->mesh.nv;
    g->C = f->channels;
    const uint32_t m = f->fx.mask ? f->fx.mask : SSS_FX_DIR_SET; /* a plain bake is a direction set */
    for (uint32_t i = 0; i < sss_scene_eval_count(ev); i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(ev, i, 0.0, &lf);
        g->nset += lf.kind == 1;
    }

    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    g->row_bytes = (GLsizeiptr)g->nv * g->C * (GLsizeiptr)sizeof(float);
    g->row_stride = sss_gl_row_stride(g->row_bytes);
    const uint32_t K = f->fx.env_order * f->fx.env_order;
    g->k4 = (K + 3) / 4 * 4;
    const uint64_t env_bytes = (uint64_t)g->nv * g->C * g->k4 * sizeof(float);
    if (max_block > 0 && ((uint64_t)g->row_bytes > (uint64_t)max_block ||
                          ((m & SSS_FX_ENV_SH) && env_bytes > (uint64_t)max_block))) {
        sss_fx_gpu_destroy(g);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "scene effects: a storage buffer above this GL's limit of %.1f MiB is needed",
                        (double)max_block / 1048576.0);
    }

    /* Each program only for the sections the file carries (§5.10–5.13). */
    int ok = 1;
    if (m & (SSS_FX_DIR_EXACT | SSS_FX_DIR_SET)) ok = (g->prog_rows = build("#define FX_ROWS 1\n", g->C, 0, err)) != 0;
    if (ok && (m & SSS_FX_POINT_SHELLS)) ok = (g->prog_shell = build("#define FX_SHELL 1\n", g->C, 0, err)) != 0;
    if (ok && (m & SSS_FX_ENV_SH)) ok = (g->prog_env = build("#define FX_ENV 1\n", g->C, K, err)) != 0;
    if (!ok) {
        sss_fx_gpu_destroy(g);
        return SSS_ERR_UNSUPPORTED;
    }
    if (m & SSS_FX_DIR_EXACT) g->exact_rows = sss_gl_rows(f->fx.exact_q, f->fx.nexact, g->row_bytes, g->row_stride);
    if (m & SSS_FX_POINT_SHELLS)
        g->shell_rows = sss_gl_rows(f->fx.shell_q, (size_t)f->fx.nshells * f->dirs.n, g->row_bytes, g->row_stride);
    if (m & SSS_FX_ENV_SH) {
        /* each (vertex, channel)'s K coefficients padded with zeros to a
         * multiple of 4: the kernel loads them as vec4 */
        const size_t nvc = (size_t)g->nv * g->C;
        float *pad = calloc(nvc * g->k4 + 1, sizeof *pad);
        if (pad) {
            for (size_t e = 0; e < nvc; e++) memcpy(pad + e * g->k4, f->fx.env_t + e * K, K * sizeof *pad);
            g->env_t = sss_gl_ssbo((GLsizeiptr)env_bytes, pad, GL_STATIC_DRAW);
            free(pad);
        }
    }
    if (g->nset) g->acc = sss_gl_ssbo(g->row_bytes, NULL, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    if (glGetError() == GL_OUT_OF_MEMORY || ((m & SSS_FX_ENV_SH) && !g->env_t)) {
        sss_fx_gpu_destroy(g);
        return sss_fail(err, SSS_ERR_NOMEM, "scene effects: the GPU is out of memory for the effect data");
    }
    g->built = (g->prog_rows ? SSS_FXGPU_ROWS : 0u) | (g->prog_shell ? SSS_FXGPU_SHELL : 0u) |
               (g->prog_env ? SSS_FXGPU_ENV : 0u);
    static const char *const nm[3] = {"rows", "shells", "env"};
    size_t k = 0;
    g->desc[0] = 0;
    for (int i = 0; i < 3; i++)
        if (g->built & (1u << i)) k += (size_t)snprintf(g->desc + k, sizeof g->desc - k, "%s%s", k ? " + " : "", nm[i]);
    if (!k) snprintf(g->desc, sizeof g->desc, "none");
    *out = g;
    return SSS_OK;
}

void sss_fx_gpu_destroy(sss_fx_gpu *g)
{
    if (!g) return;
    GLuint bufs[4] = {g->exact_rows, g->shell_rows, g->env_t, g->acc};
    glDeleteBuffers(4, bufs);
    if (g->prog_rows) glDeleteProgram(g->prog_rows);
    if (g->prog_shell) glDeleteProgram(g->prog_shell);
    if (g->prog_env) glDeleteProgram(g->prog_env);
    free(g);
}

unsigned sss_fx_gpu_programs(const sss_fx_gpu *g) { return g->built; }

const char *sss_fx_gpu_describe(const sss_fx_gpu *g) { return g->desc; }

static void common_uniforms(GLuint p, GLuint count, int first, const double w[3])
{
    glUseProgram(p);
    glUniform1ui(glGetUniformLocation(p, "u_count"), count);
    glUniform1i(glGetUniformLocation(p, "u_first"), first);
    glUniform1dv(glGetUniformLocation(p, "u_w"), 3, w);
}

void sss_fx_gpu_frame(sss_fx_gpu *g, double angle)
{
    const sss_bake_file *f = g->f;
    const GLuint qb = sss_renderer_q_buffer(g->r);
    const GLuint nvc = g->nv * g->C;
    /* with a direction-set light the renderer's q buffer is the input of
     * that light's term: sum elsewhere, copy at the end */
    const GLuint target = g->nset ? g->acc : qb;
    const GLsizeiptr whole = (g->row_bytes + 3) / 4 * 4;
    int first = 1;
    for (uint32_t i = 0; i < sss_scene_eval_count(g->ev); i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(g->ev, i, angle, &lf);
        GLuint count = nvc; /* invocations: one per value */
        if (lf.kind == 0 && g->prog_rows && g->exact_rows && lf.exact < f->fx.nexact) {
            /* directional-exact: the stored row (no interpolation) */
            common_uniforms(g->prog_rows, nvc, first, lf.w);
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, g->exact_rows, g->row_stride * (GLintptr)lf.exact, whole);
        } else if (lf.kind == 1 && g->prog_rows) {
            /* direction-set: the renderer's §3.2 interpolation (any storage
             * form) into its q buffer, then weighted into the sum */
            sss_view_params p;
            sss_view_params_default(&p);
            memcpy(p.light, lf.dir, sizeof p.light);
            p.path = SSS_EVAL_GPU;
            sss_renderer_evaluate(g->r, &p);
            common_uniforms(g->prog_rows, nvc, first, lf.w);
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, qb, 0, whole);
        } else if (lf.kind == 2 && g->prog_shell) {
            /* point-shells (§3.3): the six rows and weights of sss_fx_point */
            uint32_t row[6];
            double w[6], r2;
            sss_fx_point_weights(f, lf.pos, row, w, &r2);
            common_uniforms(g->prog_shell, nvc, first, lf.w);
            glUniform1dv(glGetUniformLocation(g->prog_shell, "u_pw"), 6, w);
            glUniform1d(glGetUniformLocation(g->prog_shell, "u_r2"), r2);
            for (GLuint k = 0; k < 6; k++)
                glBindBufferRange(GL_SHADER_STORAGE_BUFFER, k, g->shell_rows, g->row_stride * (GLintptr)row[k], whole);
        } else if (lf.kind == 3 && g->prog_env) {
            /* environment-sh: Σ_i T_i L_i, L rotated on the CPU */
            const uint32_t K = f->fx.env_order * f->fx.env_order;
            float L[3 * 64];
            memset(L, 0, sizeof L);
            for (uint32_t k = 0; k < 3; k++) memcpy(L + k * g->k4, lf.env_L + k * K, K * sizeof *L);
            common_uniforms(g->prog_env, g->nv, first, lf.w);
            glUniform4fv(glGetUniformLocation(g->prog_env, "u_L"), (GLsizei)(3 * g->k4 / 4), L);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g->env_t);
            count = g->nv; /* one invocation per vertex, all channels */
        } else {
            continue; /* no data: sss_scene_eval_create has refused such a light */
        }
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
