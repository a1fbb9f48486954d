/* effects.h: the run-time passes of the effects a file can carry (internal
 * to sss_render), one file each in this folder, tied together by one table
 * (table.c).
 *
 * An effect is what the planner bakes for a scene (docs/scenes.md): the
 * direction set (§3.2 of Hao–Varshney 2004: the base, whose per-frame
 * interpolation is scatter.c), static directional lights (QDIR), point-light
 * shells (PSHL, §3.3), environment SH transfer (ENVT), the near terms
 * (OWNT). At run time each is one pass of one of two kinds:
 *  - a scene light's term (light_kind ≥ 0): the GPU sum of a scene's lights
 *    (fx_gpu.c) runs, for each light in the scene's order, the pass of its
 *    kind, which adds the light's term to the sum, and the CPU sum
 *    (scene_view.c, the reference) runs its `cpu` hook;
 *  - a pass over q (light_kind < 0): the renderer (renderer.c) runs it after
 *    every evaluation or upload of q, for the frame's light.
 * Only the passes whose data the file carries are created, so a scene that
 * does not call for an effect pays nothing for it.
 *
 * Adding an effect: its file here (the hooks of sss_effect below, named
 * sss_pass_NAME_HOOK), its shader in runtime/shaders/ (embedded and validated
 * in runtime/CMakeLists.txt), and its row in the table of table.c.
 */
#ifndef SSS_EFFECTS_INTERNAL_H
#define SSS_EFFECTS_INTERNAL_H

#include "renderer.h"

/* What a pass is created from. */
typedef struct sss_effect_ctx {
    const sss_gpu_mesh *mesh;         /* the renderer's mesh and q buffer; mesh->f is the file */
    GLint64 max_block;                /* GL_MAX_SHADER_STORAGE_BLOCK_SIZE (≤ 0: unknown) */
    GLsizeiptr row_bytes, row_stride; /* scene lights: one per-vertex row (nv·C floats), padded to the
                                       * SSBO offset alignment so that rows bind with glBindBufferRange */
} sss_effect_ctx;

/* One frame's work for a pass. */
typedef struct sss_effect_frame {
    /* passes over q */
    const double *light;              /* unit, towards the light */
    const sss_view_params *p;
    GLuint query;                     /* GL_TIME_ELAPSED query the pass runs under (begun and ended by it) */
    /* scene lights */
    const sss_scene_light_frame *lf;  /* the light, this frame (sss_scene_eval_light) */
    sss_renderer *r;                  /* the renderer whose q buffer the sum goes to */
    int first;                        /* the frame's first light: the sum starts at 0 */
    GLuint row_program;               /* the row kernel (light_row.comp.glsl), when a pass needs it */
    /* (p above: for scene lights, the view's near-term settings, sss_scene_eval_view) */
    GLsizeiptr whole;                 /* one row's bytes rounded up to 4: the range a row binds */
} sss_effect_frame;

/* Scratch of the CPU sum (scene_view.c): nv·3 floats each; and, for a
 * file with OWNT and the near terms asked for, what adds a light's near
 * terms to a row of q (the direction set's pass calls it; NULL: none). */
typedef struct sss_effect_scratch {
    float *tmp, *env;
    void (*add_near)(void *ctx, const double light[3], float *row);
    void *near_ctx;
} sss_effect_scratch;

typedef struct sss_effect {
    const char *name;        /* as docs/scenes.md and the planner name the effect */
    uint32_t fx_bit;         /* SSS_FX_* of the file's effect set it serves (format §5.10), 0: none */
    char section[5];         /* the file section its data comes from (docs/format.md) */
    int light_kind;          /* the sss_scene_light_frame.kind it sums; -1: a pass over q */
    unsigned gpu_bit;        /* SSS_FXGPU_* of its program (sss_fx_gpu_programs), 0: none */
    /* Whether file f carries the effect; NULL: f's effect set has fx_bit (a
     * plain bake, mask 0, is a direction set). */
    int (*present)(const sss_bake_file *f);
    /* Uploads the effect's data and builds its program; *state is the
     * pass's (NULL allowed). On failure *state is NULL and nothing is kept. */
    sss_result (*create)(const sss_effect_ctx *c, void **state, sss_error *err);
    /* One frame. A scene light's pass selects its program (sss_pass_light_begin),
     * binds its inputs and returns the invocations the caller dispatches (0:
     * nothing to add); a pass over q does all of its work and returns 1 when
     * it ran under fr->query. */
    GLuint (*frame)(void *state, const sss_effect_frame *fr);
    void (*destroy)(void *state);
    /* What the pass runs on the GPU in a word or two, for logs. */
    const char *(*describe)(const void *state);
    /* A scene light's term on the CPU, added to q (nv·C floats) exactly as
     * the GPU pass adds it: the reference of the GPU sum. */
    void (*cpu)(const sss_bake_file *f, const sss_scene_light_frame *lf, const sss_effect_scratch *s, float *q);
} sss_effect;

/* The pass table (table.c), in the order the passes are created and run. */
extern const sss_effect sss_pass_table[];
extern const unsigned sss_pass_table_n;

/* Whether f carries effect e. */
int sss_effect_present(const sss_effect *e, const sss_bake_file *f);
/* The scene-light pass for light kind `kind`, NULL if none. */
const sss_effect *sss_effect_for_light(int kind);

/* Shared by the scene-light passes (fx_gpu.c): selects program p and sets
 * the sum's uniforms of light_sum.glsl (u_count, u_first, u_w). */
void sss_pass_light_begin(GLuint p, GLuint count, int first, const double w[3]);
/* Builds a scene-light program: "#define CHANNELS C" (and "#define NCOEF
 * n" when ncoef > 0), light_sum.glsl, then body. 0 and err on failure. */
GLuint sss_pass_light_program(const char *body, uint32_t C, uint32_t ncoef, sss_error *err);
/* q += float(w_c · src) over nv·C values, in the CPU sum's order (scene_view.c). */
void sss_pass_cpu_add_row(const sss_bake_file *f, const double w[3], const float *src, float *q);

/* The near terms' own interface beyond the table (sss_renderer_read_near_visibility). */
void sss_near_read_visibility(const void *state, uint32_t nv, uint8_t *lit);

#endif
