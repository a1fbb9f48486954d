/* sss/htsm_gpu.h: seed 000's heterogeneous translucent shadow maps on the
 * GPU (Shopf 2007 §4.3; library sss_render; docs/heterogeneous.md §9), the
 * run-time path of an object whose material is edited live. Each frame:
 *   1. the light-space map: the mesh drawn from the light (orthographic
 *      along a directional light, the shadow map's frame; perspective from
 *      a point light), per texel the position, normal and transmitted flux
 *      E_t of the surface nearest the light, with mips;
 *   2. per visible pixel, q(x_o) by the estimator of sss/htsm.h (its CPU
 *      oracle, sss_htsm_q): the hierarchical pattern of n = 1, 5, 9 or 13
 *      samples, each marched through the field's mipmapped 3D texture with
 *      a fixed number of steps;
 *   3. in the same pass, the light's surface terms at each pixel's x_o
 *      (specular and diffuse reflection, as p asks), shadowed by testing
 *      x_o against that light's own map, summed over the lights;
 * then the renderer's own draw shades that q per pixel as it shades any q
 * and adds the surface terms as they are.
 * The materials, the field's strength, n and the steps are uniforms: an
 * edit shows in the next frame. Needs the renderer's context.
 */
#ifndef SSS_HTSM_GPU_H
#define SSS_HTSM_GPU_H

#include "sss/htsm.h"
#include "sss/render.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_htsm_view {
    uint32_t n;            /* samples: 1, 5, 9, 13 */
    uint32_t steps;        /* march steps per sample, 1 … SSS_HTSM_MAX_STEPS */
    double r0_mm;          /* the pattern's inner radius (sss_htsm_pattern_make); 0: the bounding radius / 4 */
    sss_htsm_material mat; /* base, inside, strength, mm per unit: edited live */
    /* lights added to p's (a scene's second and later ones); each takes
     * its own map and pass, and q is their sum (docs/heterogeneous.md
     * §9.1). more_point[k] 0: a directional light, more_light[k] towards
     * it and more_rgb[k] its irradiance E per channel; 1: a point light,
     * more_light[k] its position (world = mesh units) and more_rgb[k] its
     * intensity per steradian per channel (E = I / r², r in world units, as
     * a baked point light's, docs/scenes.md) */
    uint32_t nmore;
    double more_light[SSS_HTSM_MAX_LIGHTS][3], more_rgb[SSS_HTSM_MAX_LIGHTS][3];
    int more_point[SSS_HTSM_MAX_LIGHTS];
    int no_p_light; /* 1: p's light is not drawn (a scene without a directional light) */
} sss_htsm_view;

/* n = 13, 4 steps, r0 from the radius, the file's material as the base and
 * as the inside (h's inside when given), strength 1, the file's mm per
 * unit. */
void sss_htsm_view_default(sss_htsm_view *v, const sss_bake_file *f, const sss_hetero *h);

/* A scene's lights into p and v (docs/heterogeneous.md §9.1), in the
 * scene's order, those of non-zero intensity: the first directional one
 * into p (the one the window's keys turn; none: v->no_p_light), every
 * other directional or point light into v's more lights, up to
 * SSS_HTSM_MAX_LIGHTS in all. Not drawn, and counted in *skipped:
 * environment lights, point lights within the bounding sphere of the mesh
 * m (sss_htsm_point_drawn: no view from
 * there sees the object whole), and lights beyond the limit. Returns how
 * many are drawn. */
uint32_t sss_htsm_view_lights(sss_htsm_view *v, sss_view_params *p, const sss_scene *sc, const sss_mesh *m,
                              uint32_t *skipped);

typedef struct sss_htsm_gpu sss_htsm_gpu;

/* Builds the programs, a map_size² light-space map (power of two, 16 …
 * 4096; 0: 256) and the field h (NULL: none) sampled on 2^vol_log2 voxels
 * per side over the mesh's bounds (0: 64³) into a mipmapped 3D texture. */
sss_result sss_htsm_gpu_create(sss_renderer *r, const sss_hetero *h, uint32_t map_size, uint32_t vol_log2,
                               sss_htsm_gpu **out, sss_error *err);
void sss_htsm_gpu_destroy(sss_htsm_gpu *g);

/* The frame's image as sss_renderer_render_q_image returns it, q per pixel
 * from the pass for p's light (direction and light_rgb), v's more lights
 * and p's camera. */
sss_result sss_htsm_gpu_render_image(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, int width,
                                     int height, float **rgb, float **hdr, sss_error *err);

/* The pass alone for p at width × height (its q texture filled), and the
 * wall time it took between glFinish calls, ms: p's light (unless
 * v->no_p_light), then each of v's more lights added into the same q (x_o
 * is the same in each); 1 to SSS_HTSM_MAX_LIGHTS lights. A point light
 * within the bounding sphere is refused. */
sss_result sss_htsm_gpu_frame(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, int width,
                              int height, double *ms, sss_error *err);

/* on: the renderer's draws shade the q of g's last frame (per pixel, at
 * that frame's size) until called with 0 (the window's frames). */
sss_result sss_htsm_gpu_attach(sss_htsm_gpu *g, int on);

/* What the last frame computed, for the oracle: the map's level 0 read
 * back (its mips rebuilt on the CPU, its lookup), and per pixel q and the
 * exit point x_o (RGBA, w = 1 where the object was drawn), width × height
 * floats × 4 each (caller frees). */
sss_result sss_htsm_gpu_read(const sss_htsm_gpu *g, sss_htsm_map *map, float **q, float **x, sss_error *err);

/* The last frame's surface terms per pixel (RGBA, rgb the radiance of
 * every light's specular and diffuse reflection summed, before the
 * exposure), width × height floats × 4 (caller frees). */
sss_result sss_htsm_gpu_read_surface(const sss_htsm_gpu *g, float **s, sss_error *err);

/* The field's volume as uploaded (owned by g). */
const sss_htsm_volume *sss_htsm_gpu_volume(const sss_htsm_gpu *g);

#ifdef __cplusplus
}
#endif
#endif
