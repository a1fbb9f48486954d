/* fx_gpu.h: the scene's lights summed on the GPU (docs/scenes.md "Viewer"),
 * for `sss-view FILE.sss --scene S.json`: the same terms as the CPU sum of
 * scene_view.c (which stays the fallback, `--cpu`, and the reference), one
 * compute dispatch per light in the scene's order, written straight into
 * the renderer's per-vertex q buffer:
 *   directional-exact  the light's QDIR row times its colour (format §5.11);
 *   direction-set      the renderer's own §3.2 compute pass, then times its colour;
 *   point-shells       Hao–Varshney 2004 §3.3: six shell rows weighted
 *                      (directions × distance shells, trilinear), over r²;
 *   environment-sh     Σ_i T_i L_i per vertex and channel (format §5.12),
 *                      L rotated about +z on the CPU when the environment moves.
 * The CPU does only the vertex-independent work per frame (the shell rows
 * and weights, the rotated probe coefficients), with the very functions
 * the CPU path uses (sss_fx_point_weights, sss_scene_eval_light).
 *
 * Only the programs and buffers the file needs are built, from its effect
 * set (format §5.10): the row program for QDIR or a direction set, the
 * shell program and rows for PSHL, the environment program and transfer
 * for ENVT. A file without PSHL has no shell program and no shell buffer;
 * without ENVT, no environment program.
 *
 * Needs the renderer's GL context current (GL 4.3 with double precision in
 * shaders, core since 4.0).
 */
#ifndef SSS_FX_GPU_H
#define SSS_FX_GPU_H

#include "sss/render.h"
#include "scene_view.h"

typedef struct sss_fx_gpu sss_fx_gpu;

/* Programs sss_fx_gpu_programs reports as built. */
enum {
    SSS_FXGPU_ROWS = 1u,  /* directional-exact and direction-set */
    SSS_FXGPU_SHELL = 2u, /* point-shells */
    SSS_FXGPU_ENV = 4u    /* environment-sh */
};

/* Builds what f needs for the lights of ev, drawing through r (f, ev and r
 * must outlive it). Fails (the caller then sums on the CPU) when a program
 * does not compile or a buffer exceeds this GL's limits. */
sss_result sss_fx_gpu_create(const sss_bake_file *f, const sss_scene_eval *ev, sss_renderer *r, sss_fx_gpu **out,
                             sss_error *err);
void sss_fx_gpu_destroy(sss_fx_gpu *g);

/* Sums the lights at angle (radians: the moving lights turn about +z, as in
 * sss_scene_eval_frame) into the renderer's q buffer, ready to draw. */
void sss_fx_gpu_frame(sss_fx_gpu *g, double angle);

/* SSS_FXGPU_* bits of the programs built. */
unsigned sss_fx_gpu_programs(const sss_fx_gpu *g);

/* The programs built, e.g. "rows + env" ("none" when no light needs one). */
const char *sss_fx_gpu_describe(const sss_fx_gpu *g);

#endif
