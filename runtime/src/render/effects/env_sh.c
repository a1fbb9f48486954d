/* env_sh.c: a scene's environment light, section ENVT (format §5.12): the
 * per-vertex SH transfer T_i(x_v) = ∫ q(x_v, ω) y_i(ω) dω, dotted per frame
 * with the probe's SH coefficients L (rotated about +z on the CPU when the
 * environment moves: sss_scene_eval_light), clamped at 0 because the SH
 * truncation can ring below zero (env_sh.comp.glsl). The transfer is bound
 * whole, each (vertex, channel)'s K coefficients padded with zeros to a
 * multiple of 4 so that the kernel reads them as vec4s (on llvmpipe, where
 * every storage-buffer load is a per-lane access, this made the term 2–3×
 * faster; a padded term adds exactly 0, so the sum is unchanged).
 */
#include <stdlib.h>
#include <string.h>

#include "effects.h"
#include "gl_util.h"
#include "shaders.h"
#include "sss/effects.h"

typedef struct env_sh {
    GLuint prog;
    GLuint t;       /* ENVT transfer, padded */
    uint32_t K, k4; /* SH coefficients per (vertex, channel): stored, and on the GPU (K padded to a multiple of 4) */
} env_sh;

void sss_pass_env_sh_destroy(void *state)
{
    env_sh *e = state;
    if (!e) return;
    glDeleteBuffers(1, &e->t);
    if (e->prog) glDeleteProgram(e->prog);
    free(e);
}

sss_result sss_pass_env_sh_create(const sss_effect_ctx *c, void **state, sss_error *err)
{
    *state = NULL;
    const sss_gpu_mesh *m = c->mesh;
    const sss_bake_file *f = m->f;
    const uint32_t K = f->fx.env_order * f->fx.env_order, k4 = (K + 3) / 4 * 4;
    const uint64_t env_bytes = (uint64_t)m->nv * m->C * k4 * sizeof(float);
    if (c->max_block > 0 && env_bytes > (uint64_t)c->max_block)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "scene effects: a storage buffer above this GL's limit of %.1f MiB is needed",
                        (double)c->max_block / 1048576.0);
    env_sh *e = calloc(1, sizeof *e);
    if (!e) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    e->K = K;
    e->k4 = k4;
    e->prog = sss_pass_light_program(sss_glsl_env_sh_comp, m->C, K, err);
    if (!e->prog) {
        sss_pass_env_sh_destroy(e);
        return SSS_ERR_UNSUPPORTED;
    }
    /* each (vertex, channel)'s K coefficients padded with zeros to a
     * multiple of 4: the kernel loads them as vec4 */
    const size_t nvc = (size_t)m->nv * m->C;
    float *pad = calloc(nvc * k4 + 1, sizeof *pad);
    if (pad) {
        for (size_t i = 0; i < nvc; i++) memcpy(pad + i * k4, f->fx.env_t + i * K, K * sizeof *pad);
        e->t = sss_gl_ssbo((GLsizeiptr)env_bytes, pad, GL_STATIC_DRAW);
        free(pad);
    }
    if (!e->t) {
        sss_pass_env_sh_destroy(e);
        return sss_fail(err, SSS_ERR_NOMEM, "scene effects: the GPU is out of memory for the effect data");
    }
    *state = e;
    return SSS_OK;
}

GLuint sss_pass_env_sh_frame(void *state, const sss_effect_frame *fr)
{
    const env_sh *e = state;
    const GLuint nv = fr->r->mesh.nv;
    /* environment-sh: Σ_i T_i L_i, L rotated on the CPU */
    float L[3 * 64];
    memset(L, 0, sizeof L);
    for (uint32_t k = 0; k < 3; k++) memcpy(L + k * e->k4, fr->lf->env_L + k * e->K, e->K * sizeof *L);
    sss_pass_light_begin(e->prog, nv, fr->first, fr->lf->w);
    glUniform4fv(glGetUniformLocation(e->prog, "u_L"), (GLsizei)(3 * e->k4 / 4), L);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, e->t);
    return nv; /* one invocation per vertex, all channels */
}

const char *sss_pass_env_sh_describe(const void *state)
{
    (void)state;
    return "env";
}

void sss_pass_env_sh_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                         float *q)
{
    const uint32_t nv = f->mesh.nv, C = f->channels;
    sss_fx_env(f, lf->env_L, s->env);
    for (uint32_t v = 0; v < nv; v++)
        for (uint32_t c = 0; c < C; c++)
            q[(size_t)v * C + c] += C == 3 ? s->env[3 * (size_t)v + c]
                                           : (s->env[3 * (size_t)v] + s->env[3 * (size_t)v + 1] + s->env[3 * (size_t)v + 2]) / 3.0f;
}
