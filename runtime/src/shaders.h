/* shaders.h: GLSL sources of the renderer (GL 4.3 core). */
#ifndef SSS_SHADERS_H
#define SSS_SHADERS_H

/* Compute: q = w0·row_a + w1·row_b + w2·row_c for every vertex and channel
 * (Hao–Varshney 2004 §3.2 interpolation, barycentric in the spherical
 * Delaunay triangle). Prefixed at compile time with "#define LLOYD8 1" for
 * 8-bit storage (rows hold packed bytes, levels[c·256 + index]). */
extern const char *sss_glsl_scatter_cs;

/* Vertex + fragment: shading L = E·q·F_t(η, n·ω_o) + specular, exposure,
 * tone mapping, optional sRGB encoding. */
extern const char *sss_glsl_shade_vs;
extern const char *sss_glsl_shade_fs;

#endif
