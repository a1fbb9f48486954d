/* sss/splat_gpu.h: the image-space multiresolution splatting of Chen et
 * al. 2012 §4 on the GPU (GL 4.3 compute; library sss_render), for an
 * object whose shape changes every frame (docs/deformable.md §9). For each
 * directional light:
 *   1. buffers: the irradiance buffer (the mesh rendered orthographically
 *      from the light, light_size² texels: world position and the flux
 *      F_t(η, n·ω) a_t of each texel, visibility implicit in the depth
 *      test) with its mips and min/max depth mips; the splatting buffer
 *      (position, normal of the visible surface, the frame's size) with its
 *      median-depth mips;
 *   2. the adaptive selection (Eq. 10 with M of Eq. 11, sss/splat.h);
 *   3. the splat of R_d (the toolkit's dipole, sss/dipole.h) at `levels`
 *      camera levels, level k taking the distances [R_min^k, R_max^k) of
 *      Eq. 13 with R̄ of Eq. 14 (sss_splat_min_radius) at the sample's
 *      projected resolution T(x_i);
 *   4. bilateral upsampling and accumulation (Eq. 17);
 * then the renderer's own draw shades the per-pixel q exactly as it shades
 * a per-vertex q (exit Fresnel, surface terms, tone map).
 * For a homogeneous material the result estimates the object-space
 * per-frame path's q (sss/perframe.h) on the pose: its test oracle.
 * Needs the renderer's context (sss/render.h's conventions).
 */
#ifndef SSS_SPLAT_GPU_H
#define SSS_SPLAT_GPU_H

#include "sss/render.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_splat_options {
    int light_size;  /* irradiance buffer texels per side, power of two 64 … 4096 (0: the paper's 512) */
    int levels;      /* splatting levels 1 … 3 (0: the paper's 3); 1 splats everything at full resolution */
    int adaptive;    /* 1: the adaptive selection over 3 irradiance levels; 0: every texel of level 0 a sample */
    double alpha;    /* Eq. 11's α (0: 15) */
    double z0;       /* Eq. 10's z0 as a share of the bounding radius (0: the paper's 0.03) */
    double eps;      /* Eq. 14's ε (0: 0.001) */
    double cut_eps;  /* the last level reaches the bake's radius, 1 − cut_eps of R_d's total (0: 1e-3) */
} sss_splat_options;

/* The defaults above: 512², three levels, adaptive on. */
void sss_splat_options_default(sss_splat_options *o);

typedef struct sss_splat_gpu sss_splat_gpu;

/* Builds the programs and tables for the material of r's file (its
 * material, channels and mm per unit). Errors: SSS_ERR_ARG (an option out
 * of range), SSS_ERR_UNSUPPORTED (a shader), SSS_ERR_NOMEM. */
sss_result sss_splat_gpu_create(sss_renderer *r, const sss_splat_options *o, sss_splat_gpu **out, sss_error *err);
void sss_splat_gpu_destroy(sss_splat_gpu *s);

/* A spatially varying material (docs/deformable.md §10): f[v] ∈ [0, 1]
 * per vertex of the mesh r holds (read at the rest pose, so that the
 * material moves with the surface), the material at f the blend of the
 * file's (f = 0) and `inside` (f = 1), σa and σ′s linear in f, η the
 * file's. f is interpolated into both buffers; each pair splats
 * sqrt(R_d(r; m_o) R_d(r; m_i)) (seed 003 Eq. 8, the dipole evaluated per
 * pair), over the level ranges of the larger endpoint R_P; Eq. 17 weighs by
 * the materials' R_P. f = NULL returns to the homogeneous material.
 * Errors: SSS_ERR_ARG (f outside [0, 1], a blend without a dipole). */
sss_result sss_splat_gpu_set_field(sss_splat_gpu *s, const sss_material *inside, const float *f, sss_error *err);

/* Stage times of the last frame, milliseconds, summed over its lights:
 * the wall clock between glFinish calls (splat_gpu.c says why not
 * GL_TIME_ELAPSED). */
typedef struct sss_splat_times {
    double buffers_ms;  /* both rasters, their mips and the selection */
    double level_ms[3]; /* the splat of each camera level */
    double accum_ms;    /* upsampling and accumulation */
} sss_splat_times;
sss_splat_times sss_splat_gpu_times(const sss_splat_gpu *s);

/* The frame's image as sss_renderer_render_q_image returns it, with q per
 * pixel from the splatting of nl directional lights: dirs[l] towards light
 * l, w[l] its weight per channel (intensity × colour; a grey file takes
 * channel 0), p's light and light_rgb for the shading as ever. The mesh is
 * the one r holds now (after sss_renderer_update_geometry for a new pose). */
sss_result sss_splat_gpu_render_image(sss_splat_gpu *s, const sss_view_params *p, const double (*dirs)[3],
                                      const double (*w)[3], uint32_t nl, int width, int height, float **rgb,
                                      float **hdr, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
