/* shaders_fx.h: GLSL of the scene-effect evaluation on the GPU (fx_gpu.c,
 * format 1.2 effects, docs/scenes.md). One compute shader source, compiled
 * per effect with one of these defines in front (plus CHANNELS, and NCOEF
 * for the environment):
 *   FX_ROWS  q += float(w_c · src[e]): a static light's stored QDIR row
 *            (directional-exact), or the direction-set value the renderer's
 *            own compute pass has just interpolated (Hao–Varshney 2004 §3.2);
 *   FX_SHELL q += float(w_c · float((Σ_k w_k row_k[e]) / r²)): the point
 *            light's six shell rows (§3.3, directions × distance shells);
 *   FX_ENV   q += max(0, Σ_i T_i L_i) per vertex and RGB channel (the
 *            environment's SH transfer dotted with the probe's SH).
 * Every sum is `precise` and in double, in the order of the C evaluator
 * (common/src/fx_eval.c, runtime/src/scene_view.c), so on an IEEE GPU the
 * two agree to the bit. Target buffer at binding 6; u_first = 1 starts the
 * sum at 0 (the first light of a frame). */
#ifndef SSS_SHADERS_FX_H
#define SSS_SHADERS_FX_H

extern const char *sss_glsl_fx_cs;

#endif
