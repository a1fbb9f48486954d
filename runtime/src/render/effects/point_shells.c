/* point_shells.c: a scene's near point lights, section PSHL (format §5.13;
 * Hao–Varshney 2004 §3.3): q baked for a point light at centre + r_s·ω_j
 * on distance shells s around the object, stored as r_s²·q_pt. A frame
 * interpolates trilinearly, barycentric over the spherical triangle of
 * directions around P − centre and linear in r between the two shells
 * around |P − centre|, then divides by r² (point_shells.comp.glsl). The
 * CPU forms the six rows and weights (sss_fx_point_weights, the very
 * function of the C evaluator) and the GPU the per-vertex sum, in double
 * and in the C evaluator's order. The S·n rows are uploaded once, each
 * padded to the SSBO offset alignment so that the six bind with
 * glBindBufferRange: a bound row is far below
 * GL_MAX_SHADER_STORAGE_BLOCK_SIZE even where the whole table (220 MB for
 * 23 k vertices × 200 directions × 4 shells in RGB) is not.
 */
#include <stdlib.h>

#include "effects.h"
#include "gl_util.h"
#include "shaders.h"
#include "sss/effects.h"

typedef struct point_shells {
    const sss_bake_file *f;
    GLuint prog;
    GLuint rows;            /* PSHL, S·n rows, row s·n + j */
    GLsizeiptr row_stride;
} point_shells;

void sss_pass_point_shells_destroy(void *state)
{
    point_shells *ps = state;
    if (!ps) return;
    glDeleteBuffers(1, &ps->rows);
    if (ps->prog) glDeleteProgram(ps->prog);
    free(ps);
}

sss_result sss_pass_point_shells_create(const sss_effect_ctx *c, void **state, sss_error *err)
{
    *state = NULL;
    const sss_bake_file *f = c->mesh->f;
    point_shells *ps = calloc(1, sizeof *ps);
    if (!ps) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    ps->f = f;
    ps->row_stride = c->row_stride;
    ps->prog = sss_pass_light_program(sss_glsl_point_shells_comp, c->mesh->C, 0, err);
    if (!ps->prog) {
        sss_pass_point_shells_destroy(ps);
        return SSS_ERR_UNSUPPORTED;
    }
    ps->rows = sss_gl_rows(f->fx.shell_q, (size_t)f->fx.nshells * f->dirs.n, c->row_bytes, c->row_stride);
    *state = ps;
    return SSS_OK;
}

GLuint sss_pass_point_shells_frame(void *state, const sss_effect_frame *fr)
{
    const point_shells *ps = state;
    const sss_gpu_mesh *m = &fr->r->mesh;
    const GLuint nvc = m->nv * m->C;
    /* point-shells (§3.3): the six rows and weights of sss_fx_point */
    uint32_t row[6];
    double w[6], r2;
    sss_fx_point_weights(ps->f, fr->lf->pos, row, w, &r2);
    sss_pass_light_begin(ps->prog, nvc, fr->first, fr->lf->w);
    glUniform1dv(glGetUniformLocation(ps->prog, "u_pw"), 6, w);
    glUniform1d(glGetUniformLocation(ps->prog, "u_r2"), r2);
    for (GLuint k = 0; k < 6; k++)
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, k, ps->rows, ps->row_stride * (GLintptr)row[k], fr->whole);
    return nvc;
}

const char *sss_pass_point_shells_describe(const void *state)
{
    (void)state;
    return "shells";
}

void sss_pass_point_shells_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                               float *q)
{
    sss_fx_point(f, lf->pos, s->tmp);
    sss_pass_cpu_add_row(f, lf->w, s->tmp, q);
}
