/* scene_view.h: `sss-view FILE.sss --scene S.json` (docs/scenes.md): the
 * scene's lights summed per vertex from the parameterisation the file
 * records for each (format 1.2 effects), and the scene's camera. */
#ifndef SSS_SCENE_VIEW_H
#define SSS_SCENE_VIEW_H

#include "sss/render.h"
#include "sss/format.h"
#include "sss/scene.h"

typedef struct sss_scene_eval sss_scene_eval;

/* Matches every light of sc to the effect data of f: a static directional
 * light (or far static point light) to its QDIR entry by direction, a
 * moving directional light to the direction set, a point light to PSHL, an
 * environment to ENVT. A light f has no data for is an error naming it
 * (the file was baked for another scene). */
sss_result sss_scene_eval_create(const sss_bake_file *f, const sss_scene *sc, sss_scene_eval **out, sss_error *err);
void sss_scene_eval_destroy(sss_scene_eval *e);

/* q for the frame into q[v * channels + c] (light colours and intensities
 * folded in; render with light_rgb = 1). angle (radians) turns the moving
 * lights about +z, so a benchmark's frames differ. */
void sss_scene_eval_frame(sss_scene_eval *e, double angle, float *q);

/* One light's parameters for the frame at angle (the vertex-independent
 * part of sss_scene_eval_frame), so that another evaluator (the GPU path,
 * fx_gpu.c) sums exactly the same terms in the same order. */
typedef struct sss_scene_light_frame {
    int kind;             /* 0 directional-exact, 1 direction-set, 2 point-shells, 3 environment-sh */
    double w[3];          /* weight of channel c < channels (colour × intensity; a grey file: the mean) */
    uint32_t exact;       /* kind 0: QDIR entry */
    double dir[3];        /* kind 1: direction towards the light this frame */
    double pos[3];        /* kind 2: position this frame (world units) */
    float env_L[3 * 64];  /* kind 3: the probe's SH this frame (rotated about +z when moving); w unused */
} sss_scene_light_frame;

/* Number of lights evaluated (lights of zero intensity and environments
 * after the first are dropped: the file's probe sums them). */
uint32_t sss_scene_eval_count(const sss_scene_eval *e);
void sss_scene_eval_light(const sss_scene_eval *e, uint32_t i, double angle, sss_scene_light_frame *out);

/* Which paths the file needs, e.g. "directional-exact + environment-sh". */
const char *sss_scene_eval_paths(const sss_scene_eval *e);

/* The scene's camera (if any) as view parameters: direction from the
 * object's centre, distance in bounding radii, field of view. */
void sss_scene_camera_params(const sss_scene *sc, const sss_bake_file *f, sss_view_params *p);

#endif
