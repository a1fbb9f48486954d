/* shadow.h: a depth-only shadow map of the mesh seen from a directional
 * light, for every vertex's own visibility V(x_i, ω) in the run-time near
 * terms (the own term and its rings, sss/nearterms.h) when a view asks for it
 * (sss_view_params.near_visibility = SSS_NEAR_MAP). By default the renderer
 * traces the bake's rays instead (sss/bvh.h), which agree with the bake on every
 * vertex where the map misses a few per thousand near shadow outlines.
 *
 * Hao–Varshney 2004 §3.1 determines shadowing this way: "We first generate
 * a depth image of the scene as seen by the light source. Then, for each
 * vertex, we transform it into light space and compare its depth value
 * against the value on the depth image." The bake traces rays instead
 * (precompute/src/kernels/visibility.c); the lookup parameters below are chosen so
 * that the map reproduces the rays' answer (README.md, "Viewing").
 *
 * Projection: orthographic along ω, fitted to the mesh's bounding sphere
 * (centre c, radius R, enlarged by SSS_SHADOW_MARGIN so that no triangle is
 * clipped), so one map serves every light direction with the same texel
 * size t = 2 R' / size. The matrix maps a world point p to
 *   s = ½ + ½ u·(p − c)/R',  t = ½ + ½ v·(p − c)/R',  z = ½ − ½ ω·(p − c)/R'
 * with (u, v, ω) orthonormal: z is the window depth the rasteriser stores,
 * smaller towards the light.
 *
 * Needs a current GL ≥ 4.3 core context.
 */
#ifndef SSS_SHADOW_H
#define SSS_SHADOW_H

#include <epoxy/gl.h>
#include <stdint.h>
#include "sss/render.h" /* SSS_SHADOW_SIZE: the default map resolution */
/* R' = R · (1 + margin): the bounding sphere plus the normal offset. */
#define SSS_SHADOW_MARGIN 0.02
/* Lookup (shadow.c says why): the point tested is x_o + k_n · t · n_o, t the
 * texel's world size; it is lit when its depth − bias ≤ the map's depth at
 * its texel, bias = (k_c + k_s · min(tan θ, tan_max)) / size in depth units
 * (a texel's worth of world length is 1/size of the depth range), cos θ =
 * n_o·ω. Chosen by measurement against the bake's rays on the 23K dragon and
 * the blob (docs in README.md, "Viewing"). */
#define SSS_SHADOW_NORMAL_OFFSET 0.5 /* k_n, texels */
#define SSS_SHADOW_BIAS_CONST 0.05   /* k_c, texels */
#define SSS_SHADOW_BIAS_SLOPE 0.5    /* k_s, texels per unit of tan θ */
#define SSS_SHADOW_TAN_MAX 10.0      /* tan θ clamp (θ ≈ 84°) */

typedef struct sss_shadow sss_shadow;

/* The map of `size` texels per side (clamped to 256 … 8192; 0: SSS_SHADOW_SIZE)
 * in *s, created or replaced when its size differs; 0 when none can be had
 * (an old map is kept when a new size fails). */
int sss_shadow_ensure(sss_shadow **s, GLuint vao, uint32_t nf, const double centre[3], double radius, int size);

/* Creates the depth texture (size × size, GL_DEPTH_COMPONENT32F), its FBO
 * and the depth-only program. vao draws the mesh (attribute 0: float3
 * positions; GL_TRIANGLES of nf triangles from its element buffer). */
sss_result sss_shadow_create(GLuint vao, uint32_t nf, const double centre[3], double radius, int size,
                             sss_shadow **out, sss_error *err);
void sss_shadow_destroy(sss_shadow *s);

/* Renders the map for the unit direction l (towards the light) unless it
 * already holds that direction. Saves and restores the framebuffer
 * bindings, viewport and depth-test state it changes. Begins the
 * GL_TIME_ELAPSED query `query` (0: none) before the draw, after the
 * framebuffer switch and clear; the caller ends it. Returns 1 when it
 * rendered. */
int sss_shadow_update(sss_shadow *s, const float l[3], GLuint query);

/* The projection above for the light direction l (need not be unit) about
 * centre c and radius R' (the margin included): the world → clip matrix
 * the rasteriser draws with and the world → (s, t, z) lookup, both
 * column-major; 0 when l has no direction. The shadow map uses it, and
 * single scattering's light-space map (effects/single.c). */
int sss_shadow_frame(const double c[3], double R, const float l[3], float clip[16], float lookup[16]);

/* The perspective projection from a point light at P (world units) onto
 * the sphere about c of radius R' (the margin included; the run-time path
 * of an editable object, docs/heterogeneous.md §9.1): the cone from P
 * tangent to the sphere, square, depth from D − R' to D + R' (D = |c − P|);
 * clip and the world → (s, t, depth) lookup as above, each to be divided by
 * its w, the depth along the axis (row 3), and *ref_w = D. 0 when P lies
 * within the sphere, which no such view can see whole. */
int sss_shadow_frame_point(const double c[3], double R, const double P[3], float clip[16], float lookup[16],
                           double *ref_w);

/* Forgets the direction held, so that the next update renders. */
void sss_shadow_invalidate(sss_shadow *s);

/* The depth texture, the world → (s, t, z) matrix of the direction held
 * (column-major, for glUniformMatrix4fv), the size, and the texel's world
 * size t. */
GLuint sss_shadow_texture(const sss_shadow *s);
/* Binds the map to texture unit `unit` and sets the uniforms of
 * shadow_map.glsl in program prog (current): the map, its matrix and size,
 * the normal offset and the depth bias above. The caller unbinds the
 * texture when done. */
void sss_shadow_bind(const sss_shadow *s, GLuint prog, int unit);
const float *sss_shadow_matrix(const sss_shadow *s);
int sss_shadow_size(const sss_shadow *s);
double sss_shadow_texel(const sss_shadow *s);

#endif
