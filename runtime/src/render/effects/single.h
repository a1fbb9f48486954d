/* single.h: single scattering per pixel in the shading draw (internal to
 * sss_render; docs/layers.md §8). Not a row of the pass table
 * (effects.h): its term is per pixel, added by the shading fragment
 * shader (single.glsl), not a pass over q nor a scene light's row. This
 * module owns what the shader reads: the per-vertex layer depths, the
 * light-space map of the surface nearest the light (position and
 * triangle per texel: the entry points K) and the camera's nearest back faces (where
 * the view ray leaves the object). */
#ifndef SSS_EFFECT_SINGLE_H
#define SSS_EFFECT_SINGLE_H

#include "renderer.h"

/* The light map's texels per side, and the default N (segments of the
 * per-segment closed form; docs/layers.md §8 measures the choice). */
#define SSS_SINGLE_MAP_SIZE 2048
#define SSS_SINGLE_SAMPLES_DEFAULT 32

typedef struct sss_single sss_single;

/* Whether the draw of f under p adds single scattering: p->single on, or
 * auto (0) and f's effect set has SSS_FX_SINGLE. */
int sss_single_wanted(const sss_bake_file *f, const sss_view_params *p);

/* Creates *s for m (its layer depths uploaded, the maps' programs built)
 * unless it exists; 0 when it cannot be had (GL refuses the maps, or the
 * mesh has 2^24 − 1 triangles or more, which the maps cannot name). */
int sss_single_ensure(sss_single **s, const sss_gpu_mesh *m);
void sss_single_destroy(sss_single *s);

/* Before the draw: the light map for the unit direction l (redrawn when it
 * changes) and the camera's back faces with mvp at width × height. Saves
 * and restores the framebuffer, viewport and the depth and cull state. */
void sss_single_prepare(sss_single *s, const sss_gpu_mesh *m, const float mvp[16], const float l[3], int width,
                        int height);

/* Sets single.glsl's uniforms in program pr (current) and binds its
 * textures to units unit and unit + 1 and the layer depths to SSBO binding 6.
 * The caller unbinds the textures (sss_single_unbind). */
void sss_single_bind(const sss_single *s, GLuint pr, const sss_gpu_mesh *m, const sss_view_params *p,
                     const float mvp[16], int unit);
void sss_single_unbind(int unit);

#endif
