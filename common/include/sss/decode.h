/* sss/decode.h: reconstructs q(x_v, ω) for an arbitrary light direction from
 * a decoded .sss file (CPU path; the viewer and error measurement use it).
 */
#ifndef SSS_DECODE_H
#define SSS_DECODE_H

#include <stdint.h>
#include "sss/format.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Stored value of q for direction sample j, vertex v, channel c. */
float sss_decode_sample(const sss_bake_file *f, uint32_t j, uint32_t v, uint32_t c);

/* Writes q(x_v, ω) for all vertices into out[v * channels + c], interpolating
 * between the three direction samples of the spherical triangle containing
 * `light` (unit vector towards the light; normalised here). For the
 * compressed forms (SSS_QUANT_SH, SSS_QUANT_REFS) the reference rows are
 * interpolated the same way, blended, and the SH part evaluated at `light`;
 * the result is clamped at 0. */
void sss_decode_all(const sss_bake_file *f, const double light[3], float *out);

/* sss_decode_all for vertices [first, first + count) only, into
 * out[(v − first) · channels + c] (count · channels floats): the slice of
 * what sss_decode_all writes, to the bit (the same loops over the same
 * values). Nothing is written when the range does not lie within the
 * mesh. Per call it costs the light's lookup (and for SH codes the folded
 * tables, for references every reference's value) plus the range. */
void sss_decode_range(const sss_bake_file *f, const double light[3], uint32_t first, uint32_t count, float *out);

/* How q at a light direction is formed from the direction samples. */
typedef enum sss_interp {
    SSS_INTERP_TRIANGLE = 0, /* barycentric in the spherical Delaunay triangle (the default; sss/dirset.h) */
    SSS_INTERP_NEAREST4 = 1  /* the paper's 4 nearest samples, inverse-angle weights (sss_dirset_nearest4) */
} sss_interp;

/* sss_decode_all with a choice of direction interpolation (docs/accuracy.md: the
 * accuracy study compares the two). SSS_INTERP_TRIANGLE is sss_decode_all
 * to the bit. With SSS_INTERP_NEAREST4 the rows of float and lloyd8 files
 * and the reference rows of SSS_QUANT_REFS files are blended over the four
 * nearest samples instead (the SH part, which has no direction samples, is
 * unchanged). The file format stays barycentric; the GPU layout has the
 * NEAREST4 form too (sss_gpu_frame_eval_interp), and the viewer draws
 * either (sss_view_params.interp). */
void sss_decode_all_interp(const sss_bake_file *f, const double light[3], sss_interp interp, float *out);

/* The SH tables of f's compressed form (f->sh) folded with the basis at
 * unit direction d: T[(c·ncoef + i)·L + x] = table[(c·ncoef + i)·L + x] ·
 * y_i(d), L = sss_decode_fold_levels(f->sh.kind); T holds channels·ncoef·L
 * floats (LLOYD4: sss_decode_fold_floats, paired). Per frame, these make
 * q̃ = Σ_i c_i y_i(d) (§4.1) one table load per coefficient (per pair of
 * 4-bit codes): the C decoder's and the GPU path's terms, to the bit.
 * The linear kinds (L = 1): T[c·ncoef + i] = scale · y_i(d) / M (M = 127
 * for LINEAR8, 32767 for LINEAR16, sss_shq_linear_max), and a coefficient
 * costs the float product (int8_t or int16_t)code · T. */
void sss_decode_fold_sh(const sss_bake_file *f, const double d[3], float *T);

/* Levels per coefficient of sss_decode_fold_sh's tables: 1 for the linear
 * kinds (the folded step), else sss_shq_levels (256 or 16). */
uint32_t sss_decode_fold_levels(uint32_t kind);

/* Floats of sss_decode_fold_sh's tables: channels·ncoef·levels, except
 * LLOYD4, whose codes are summed two at a time: per channel ⌊ncoef / 2⌋
 * tables of 256 (pair m: T[(c·P + m)·256 + (x0 | x1 << 4)] = term_2m(x0) +
 * term_2m+1(x1), P = ⌊ncoef / 2⌋), then, for an odd ncoef, the last
 * coefficient's 16 levels of every channel at T[C·P·256 + c·16 + x]. */
uint64_t sss_decode_fold_floats(uint32_t kind, uint32_t channels, uint32_t ncoef);

/* Builds the decoder's load-time layout of f's SH codes (f->sh.planes,
 * coefficient-major; sss_file_decode and sss_file_read call it). The file's
 * codes stay as they are; the layout only lets the per-frame sums run over
 * many vertices at once, each vertex's terms added in the same order, so
 * every decode gives the same floats with or without it. Call it again
 * after changing f->sh.code in place. Returns 0, or −1 when out of memory
 * (the decoder then keeps its per-vertex loop). */
int sss_decode_prepare(sss_bake_file *f);

/* The weight a reference-form weight code stands for (Hao–Varshney 2004
 * §4.2; sss_refcode): w_lo + (w_hi − w_lo) · code / (2^wbits − 1) in
 * double, rounded once to float. The decoder blends in float with these
 * weights, the third 1 − w0 − w1; the GPU layout's weight table holds the
 * same floats. */
float sss_decode_ref_weight(const sss_refcode *r, uint32_t code);

/* Instruction sets of the compressed forms' block loops (the load-time
 * layout's per-frame sums and the references' blend), chosen at run time
 * from what the CPU has: the same C loop compiled for each, the same float
 * operations in the same order, so every decoded value is the same on
 * every choice (docs/benchmarks.md, "Run-time instruction sets, 4-bit
 * codes by permutes, the references' blend in float"). */
enum { SSS_DECODE_ISA_BASELINE = 0, SSS_DECODE_ISA_AVX2 = 1, SSS_DECODE_ISA_AVX512 = 2 };

/* The set the block loops use now: the one forced by sss_decode_force_isa,
 * else the one named by the environment variable SSS_DECODE_ISA
 * ("baseline", "avx2", "avx512") when the CPU has it, else the widest the
 * CPU has. */
int sss_decode_isa(void);

/* Forces the block loops onto isa (for tests and benchmarks; call it
 * before decoding, not while another thread decodes), or back to the
 * automatic choice with −1. Returns 0, or −1 when the CPU lacks isa
 * (nothing changed). */
int sss_decode_force_isa(int isa);

/* q(x_v, ω) for one vertex into out[0 … channels−1], the same value
 * sss_decode_all writes for it (same arithmetic, same rounding). Any
 * storage form. v out of range, or a zero or non-finite light, gives 0. */
void sss_decode_vertex(const sss_bake_file *f, uint32_t v, const double light[3], float *out);

/* ---- the vector integral Q (format 1.7, section QVEC) --------------------
 * Hao–Varshney 2004 §3.2: Q is interpolated between the direction samples
 * and dotted with the actual light direction ω, q̃ = Q̃(ω)·ω; at a sample
 * Q_j·ω_j = q_j (docs/physics.md §10). The interpolation weights are q's
 * (the spherical triangle, or the four nearest samples), each component
 * formed as the float path forms q (float weights and products). */

/* Whether f holds Q. */
int sss_decode_has_vector(const sss_bake_file *f);

/* Stored Q_j of vertex v, channel c into out[0..2] (zeros without Q). */
void sss_decode_vector_sample(const sss_bake_file *f, uint32_t j, uint32_t v, uint32_t c, float out[3]);

/* q̃(x_v, ω) = max(0, Q̃(x_v, ω)·ω) for vertices [first, first + count)
 * into out[(v − first) · channels + c], ω the normalised light; like the
 * rows of q, without the near terms and clamped at 0. Without Q (or with a
 * range outside the mesh) it is sss_decode_range / sss_decode_all_interp's
 * result for the same arguments (NEAREST4 over the whole mesh only). */
void sss_decode_vector_range(const sss_bake_file *f, const double light[3], sss_interp interp, uint32_t first,
                             uint32_t count, float *out);

/* Area-weighted error statistics of an approximation a against a reference
 * r over one mesh, accumulated one light direction at a time (every error
 * figure of the toolkit is formed here). Index `channels` of the results is
 * over all channels. */
typedef struct sss_err_accum {
    uint32_t channels, ndirs;
    double area_sum;                            /* Σ_v A_v */
    /* 1 when Σ_v A_v is 0 (every triangle degenerate): each vertex then
     * weighs 1, so the RMS does not read 0 next to a non-zero maximum */
    int unweighted;
    double num[SSS_MAX_CHANNELS], den[SSS_MAX_CHANNELS]; /* Σ A (a − r)², Σ A r² */
    double max_abs[SSS_MAX_CHANNELS];           /* max |a − r| (NaN once any difference was NaN) */
} sss_err_accum;

void sss_err_accum_init(sss_err_accum *acc, uint32_t channels, const double *area, uint32_t nv);
/* Adds one direction: a and r hold nv × channels values. */
void sss_err_accum_add(sss_err_accum *acc, const double *area, const float *a, const float *r, uint32_t nv);
/* rms, rel_rms, max_abs, rms_ref: channels + 1 entries each, any may be NULL.
 *   rms = sqrt(Σ A (a − r)² / (ndirs Σ A)), rel_rms = sqrt(Σ A (a − r)² / Σ A r²),
 *   rms_ref = sqrt(Σ A r² / (ndirs Σ A)); rel_rms is NaN when any difference was. */
void sss_err_accum_result(const sss_err_accum *acc, double *rms, double *rel_rms, double *max_abs, double *rms_ref);

/* Per-vertex error of `approx` against `ref` (same mesh, channels) over
 * ndirs random unit light directions (sss_rng_direction from `seed`), both
 * reconstructed by sss_decode_all. Area-weighted (A_v = 1/3 of the incident
 * triangle areas, sss_mesh_vertex_areas of ref's mesh):
 *   rel_rms[c] = sqrt(Σ_d Σ_v A_v (a − r)²) / sqrt(Σ_d Σ_v A_v r²),
 *   rms[c]     = sqrt(Σ_d Σ_v A_v (a − r)² / (ndirs Σ_v A_v)),
 * index `channels` holding the same over all channels (arrays need
 * channels + 1 entries; rms may be NULL). *max_abs (may be NULL) is the
 * largest |a − r|. Errors: SSS_ERR_ARG (mismatch, NULL, ndirs 0),
 * SSS_ERR_NOMEM. */
sss_result sss_decode_error(const sss_bake_file *approx, const sss_bake_file *ref, uint32_t ndirs, uint64_t seed,
                            double *rel_rms, double *rms, double *max_abs, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
