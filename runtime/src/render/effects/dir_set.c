/* dir_set.c: a scene's direction-set lights (moving directional lights;
 * format §5.10's DIR_SET: DIRS + QFLT / QL8 / SHC). The effect is the base
 * of the renderer: its per-frame interpolation (Hao–Varshney 2004 §3.2, any
 * storage form) is scatter.c. In a scene's sum each such light runs that
 * evaluation into the renderer's q buffer and adds it, times the light's
 * colour, with the row kernel (light_row.comp.glsl) that directional-exact
 * lights use too. The pass keeps no state of its own.
 */
#include <string.h>

#include "effects.h"
#include "sss/decode.h"

GLuint sss_pass_dir_set_frame(void *state, const sss_effect_frame *fr)
{
    (void)state;
    if (!fr->row_program) return 0;
    const sss_scene_light_frame *lf = fr->lf;
    const sss_gpu_mesh *m = &fr->r->mesh;
    const GLuint nvc = m->nv * m->C;
    /* the renderer's §3.2 interpolation (any storage form) into its q
     * buffer, then weighted into the sum */
    sss_view_params p;
    sss_view_params_default(&p);
    memcpy(p.light, lf->dir, sizeof p.light);
    p.path = SSS_EVAL_GPU;
    /* a file with OWNT: the evaluation adds this light's near terms as the
     * view asks (on, off, rays or map), so the sum holds each light's full
     * q and the draw adds nothing more */
    if (fr->p) {
        p.near_terms = fr->p->near_terms;
        p.near_visibility = fr->p->near_visibility;
        p.shadow_size = fr->p->shadow_size;
    }
    sss_renderer_evaluate(fr->r, &p);
    sss_pass_light_begin(fr->row_program, nvc, fr->first, lf->w);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, 0, m->qbuf, 0, fr->whole);
    return nvc;
}

const char *sss_pass_dir_set_describe(const void *state)
{
    (void)state;
    return "rows";
}

void sss_pass_dir_set_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                          float *q)
{
    sss_decode_all(f, lf->dir, s->tmp);
    if (s->add_near) s->add_near(s->near_ctx, lf->dir, s->tmp); /* OWNT: this light's near terms (scene_view.c) */
    sss_pass_cpu_add_row(f, lf->w, s->tmp, q);
}
