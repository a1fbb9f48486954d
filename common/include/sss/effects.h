/* sss/effects.h: run-time evaluation of the effects of a scene bake
 * (format 1.2, docs/scenes.md): the light parameterisations other than the
 * direction set (which sss/decode.h handles). Each writes q-like values
 * out[v * channels + c] that a renderer multiplies by the light's
 * intensity and colour and by F_t(η, n·ω_o) (docs/format.md §5.4).
 */
#ifndef SSS_EFFECTS_H
#define SSS_EFFECTS_H

#include <stdint.h>
#include "sss/format.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Static directional light l of section QDIR: the stored exact values
 * (a pointer into f, nv * channels floats), or NULL when out of range. */
const float *sss_fx_exact(const sss_bake_file *f, uint32_t l);

/* Environment: out[v * 3 + k] = Σ_i T_i(x_v, c) L[k * order² + i] for RGB
 * k (channel c = k, or 0 for a grey file); L NULL uses the probe stored in
 * the file. */
void sss_fx_env(const sss_bake_file *f, const float *L, float *out);
/* The same for vertices [first, first + count) into out[(v − first) · 3 + k]
 * (the slice of sss_fx_env to the bit); nothing written for a range
 * outside the mesh. */
void sss_fx_env_range(const sss_bake_file *f, const float *L, uint32_t first, uint32_t count, float *out);

/* Near point light of unit intensity at P (world units): the shells of
 * section PSHL interpolated trilinearly — barycentric over the spherical
 * triangle of directions containing P − centre, linear in r between the two
 * shells around |P − centre| (clamped to the first and last) — divided by
 * r². Zeros when P is the centre or not finite. */
void sss_fx_point(const sss_bake_file *f, const double P[3], float *out);
/* The same for vertices [first, first + count) into out[(v − first) ·
 * channels + c] (the slice of sss_fx_point to the bit); nothing written
 * for a range outside the mesh. */
void sss_fx_point_range(const sss_bake_file *f, const double P[3], uint32_t first, uint32_t count, float *out);

/* The per-light, vertex-independent part of sss_fx_point: the six shell
 * rows (row s·n + j of PSHL, each nv·channels values) and their weights
 * (1−t, t) × barycentric, and r² = |P − centre|², so that
 * out = (Σ_k w[k] q[row[k]]) / r² summed in k order in double. Returns 0
 * (rows 0, weights 0, r² = 1) where sss_fx_point gives zeros. */
int sss_fx_point_weights(const sss_bake_file *f, const double P[3], uint32_t row[6], double w[6], double *r2);

/* Rotates real SH coefficients (sss/sh.h basis, order bands) of a function
 * on the sphere about +z by alpha radians: f'(φ) = f(φ − alpha). In place. */
void sss_sh_rotate_z(uint32_t order, double alpha, double *c);

#ifdef __cplusplus
}
#endif
#endif
