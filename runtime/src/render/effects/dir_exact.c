/* dir_exact.c: a scene's static directional lights (and far static point
 * lights), section QDIR (format §5.11): each baked exactly for its
 * direction, so a frame only weights the light's stored row by its colour,
 * with the row kernel (light_row.comp.glsl) the direction-set lights use
 * too. The rows are uploaded once, each padded to the SSBO offset
 * alignment so that a light's row binds with glBindBufferRange.
 */
#include <stdlib.h>

#include "effects.h"
#include "gl_util.h"
#include "sss/effects.h"

typedef struct dir_exact {
    GLuint rows;            /* QDIR, nexact rows */
    GLsizeiptr row_stride;
    uint32_t nexact;
} dir_exact;

sss_result sss_pass_dir_exact_create(const sss_effect_ctx *c, void **state, sss_error *err)
{
    *state = NULL;
    const sss_bake_file *f = c->mesh->f;
    dir_exact *d = calloc(1, sizeof *d);
    if (!d) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    d->row_stride = c->row_stride;
    d->nexact = f->fx.nexact;
    d->rows = sss_gl_rows(f->fx.exact_q, f->fx.nexact, c->row_bytes, c->row_stride);
    *state = d;
    return SSS_OK;
}

void sss_pass_dir_exact_destroy(void *state)
{
    dir_exact *d = state;
    if (!d) return;
    glDeleteBuffers(1, &d->rows);
    free(d);
}

GLuint sss_pass_dir_exact_frame(void *state, const sss_effect_frame *fr)
{
    const dir_exact *d = state;
    const sss_scene_light_frame *lf = fr->lf;
    if (!fr->row_program || !d->rows || lf->exact >= d->nexact) return 0;
    const sss_gpu_mesh *m = &fr->r->mesh;
    const GLuint nvc = m->nv * m->C;
    /* directional-exact: the stored row (no interpolation) */
    sss_pass_light_begin(fr->row_program, nvc, fr->first, lf->w);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, d->rows, d->row_stride * (GLintptr)lf->exact, fr->whole);
    return nvc;
}

const char *sss_pass_dir_exact_describe(const void *state)
{
    (void)state;
    return "rows";
}

void sss_pass_dir_exact_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                            float *q)
{
    (void)s;
    const float *src = sss_fx_exact(f, lf->exact);
    if (src) sss_pass_cpu_add_row(f, lf->w, src, q);
}
