/* table.c: the run-time pass table (effects.h): which pass serves which
 * effect of the file (docs/format.md §5.10, docs/scenes.md), in the order
 * the passes are created and run. Adding an effect is its file in this
 * folder plus its row here (and its hooks' declarations just below).
 */
#include <stddef.h>

#include "effects.h"

/* dir_set.c: direction-set lights, the renderer's §3.2 evaluation (scatter.c) weighted into a scene's sum */
GLuint sss_pass_dir_set_frame(void *state, const sss_effect_frame *fr);
const char *sss_pass_dir_set_describe(const void *state);
void sss_pass_dir_set_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                          float *q);
/* dir_exact.c: static directional lights, one exact row each */
sss_result sss_pass_dir_exact_create(const sss_effect_ctx *c, void **state, sss_error *err);
GLuint sss_pass_dir_exact_frame(void *state, const sss_effect_frame *fr);
void sss_pass_dir_exact_destroy(void *state);
const char *sss_pass_dir_exact_describe(const void *state);
void sss_pass_dir_exact_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                            float *q);
/* point_shells.c: near point lights, Hao–Varshney 2004 §3.3 */
sss_result sss_pass_point_shells_create(const sss_effect_ctx *c, void **state, sss_error *err);
GLuint sss_pass_point_shells_frame(void *state, const sss_effect_frame *fr);
void sss_pass_point_shells_destroy(void *state);
const char *sss_pass_point_shells_describe(const void *state);
void sss_pass_point_shells_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                               float *q);
/* env_sh.c: the environment's SH transfer */
sss_result sss_pass_env_sh_create(const sss_effect_ctx *c, void **state, sss_error *err);
GLuint sss_pass_env_sh_frame(void *state, const sss_effect_frame *fr);
void sss_pass_env_sh_destroy(void *state);
const char *sss_pass_env_sh_describe(const void *state);
void sss_pass_env_sh_cpu(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s,
                         float *q);
/* near.c: the near terms, added to every q */
int sss_pass_near_present(const sss_bake_file *f);
sss_result sss_pass_near_create(const sss_effect_ctx *c, void **state, sss_error *err);
GLuint sss_pass_near_frame(void *state, const sss_effect_frame *fr);
void sss_pass_near_destroy(void *state);
const char *sss_pass_near_describe(const void *state);

const sss_effect sss_pass_table[] = {
    /* name               fx bit               section light kind  program bit
     *   present                 create                        frame                        destroy
     *   describe                cpu */
    {"direction-set",     SSS_FX_DIR_SET,      "DIRS", 1, SSS_FXGPU_ROWS,
     NULL,                   NULL,                         sss_pass_dir_set_frame,      NULL,
     sss_pass_dir_set_describe,      sss_pass_dir_set_cpu},
    {"directional-exact", SSS_FX_DIR_EXACT,    "QDIR", 0, SSS_FXGPU_ROWS,
     NULL,                   sss_pass_dir_exact_create,    sss_pass_dir_exact_frame,    sss_pass_dir_exact_destroy,
     sss_pass_dir_exact_describe,    sss_pass_dir_exact_cpu},
    {"point-shells",      SSS_FX_POINT_SHELLS, "PSHL", 2, SSS_FXGPU_SHELL,
     NULL,                   sss_pass_point_shells_create, sss_pass_point_shells_frame, sss_pass_point_shells_destroy,
     sss_pass_point_shells_describe, sss_pass_point_shells_cpu},
    {"environment-sh",    SSS_FX_ENV_SH,       "ENVT", 3, SSS_FXGPU_ENV,
     NULL,                   sss_pass_env_sh_create,       sss_pass_env_sh_frame,       sss_pass_env_sh_destroy,
     sss_pass_env_sh_describe,       sss_pass_env_sh_cpu},
    {"near terms",        0,                   "OWNT", -1, 0,
     sss_pass_near_present,  sss_pass_near_create,         sss_pass_near_frame,         sss_pass_near_destroy,
     sss_pass_near_describe,         NULL},
};

const unsigned sss_pass_table_n = sizeof sss_pass_table / sizeof sss_pass_table[0];

int sss_effect_present(const sss_effect *e, const sss_bake_file *f)
{
    if (e->present) return e->present(f);
    const uint32_t m = f->fx.mask ? f->fx.mask : SSS_FX_DIR_SET; /* a plain bake is a direction set */
    return (m & e->fx_bit) != 0;
}

const sss_effect *sss_effect_for_light(int kind)
{
    for (unsigned i = 0; i < sss_pass_table_n; i++)
        if (sss_pass_table[i].light_kind == kind) return &sss_pass_table[i];
    return NULL;
}

_Static_assert(sizeof sss_pass_table / sizeof sss_pass_table[0] <= SSS_EFFECTS_MAX, "raise SSS_EFFECTS_MAX (renderer.h)");
