/* shaders.h: GLSL sources of the renderer (GL 4.3 core). */
#ifndef SSS_SHADERS_H
#define SSS_SHADERS_H

/* Compute: q = w0·row_a + w1·row_b + w2·row_c for every vertex and channel
 * (Hao–Varshney 2004 §3.2 interpolation, barycentric in the spherical
 * Delaunay triangle). Prefixed at compile time with "#define LLOYD8 1" for
 * 8-bit storage (rows hold packed bytes; binding 4 holds the three level
 * tables with the weights folded in, levels[(r·C + c)·256 + index]), and
 * additionally "#define REFS 1" for the reference rows of the compressed
 * form (§4.2): the rows then have one entry per reference vertex, and the
 * values go both to the reference buffer (binding 5, read by the second
 * pass) and to q at the reference's vertex (binding 6 lists them). */
extern const char *sss_glsl_scatter_cs;

/* Compute, compressed forms (§4.1, §4.3): for every coded vertex and
 * channel, the blend of its three reference values (REFS) plus the SH sum
 * Σ_i table[c, i, code] · y_i(light), clamped at 0. See shaders.c for the
 * defines it needs. */
extern const char *sss_glsl_coded_cs;

/* Vertex + fragment: shading L = E·q·F_t(η, n·ω_o) + specular, exposure,
 * tone mapping, optional sRGB encoding. */
extern const char *sss_glsl_shade_vs;
extern const char *sss_glsl_shade_fs;

/* Depth-only program of the shadow map (shadow.c): positions through one
 * matrix, no colour. */
extern const char *sss_glsl_shadow_vs;
extern const char *sss_glsl_shadow_fs;

/* Compute, the near terms of files with OWNT (sss/ownterm.h), two passes:
 * own_vis: per vertex, V(x_i, ω) into lit[] (binding 4) and g_i V_i into
 * gv[] (binding 2), g = F_t(η, c)·max(0, c) as sss_own_transfer computes
 * it; with "#define RAYS 1" and "#define SSS_BVH_STACK n" V is the bake's
 * ray traced through the BVH (bvh.h; bindings 5 nodes, 6 triangles),
 * otherwise the bake's ray against the vertex's own triangles and the
 * shadow map (Hao–Varshney 2004 §3.1's depth comparison). 64 invocations
 * per group. own_near: per vertex o, q[o·C + c] += Σ_i w̃(o, i) g_i V_i over
 * o's row (sss_near_sum's order); needs "#define CHANNELS n". */
extern const char *sss_glsl_own_vis_cs;
extern const char *sss_glsl_own_near_cs;

#endif
