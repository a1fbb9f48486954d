/* sss/compress.h: compression of baked integrals q(x_v, ω_j) into the
 * storage forms of format 1.1 (sss/format.h), after Hao–Varshney 2004 §4.
 *
 *   - SH-only (fraction 0, §4.1): every vertex and channel stores the
 *     least-squares coefficients of q over the direction samples in the
 *     first order² real spherical harmonics (sss/sh.h).
 *   - References (fraction > 0, §4.2–4.3): a subset of vertices
 *     (sss_refs_build) keeps its full per-direction rows, quantised with one
 *     256-level Lloyd table per channel; every other vertex stores its
 *     reference triangle, two quantised weights and an SH-coded delta
 *     Δq_j = q_j − Σ_k w_k q̂(ref_k, ω_j), formed in double from the
 *     *dequantised* reference values and weights, so the delta also
 *     corrects the quantisation of both. RGB shares triangles and weights.
 *
 * SH coefficients are quantised per (channel, coefficient index): the
 * paper's linear 8-bit codes with one scale (SSS_SHQ_LINEAR8, §4.3), its
 * linear 16-bit codes (SSS_SHQ_LINEAR16, §4.1), or Lloyd-Max
 * tables of 256 or 16 levels (SSS_SHQ_LLOYD8, SSS_SHQ_LLOYD4).
 *
 * Beyond the paper (its §6 lists both as future work):
 *   - ls_weights: the two free weights of each vertex minimise the energy of
 *     the part of the delta that the SH order cannot represent (least
 *     squares over all directions and channels) instead of being the
 *     closest-point barycentrics; they may leave [0, 1] (stored in [−1, 2]).
 *   - illum_weight > 0: reference selection sees the integrals as well as the
 *     geometry (sss_refs_build_ex), so references gather at shadow
 *     boundaries.
 */
#ifndef SSS_COMPRESS_H
#define SSS_COMPRESS_H
#include <stdint.h>
#include "sss/format.h"
#include "sss/refs.h"
#include "sss/result.h"
#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_compress_opts {
    uint32_t order;      /* SH order n, 0 … 8 (n² coefficients); 0 only with references */
    double fraction;     /* reference fraction in [0, 1]; 0: SH-only */
    uint32_t sh_kind;    /* sss_shq */
    uint32_t wbits;      /* 8 or 16 bits per stored weight */
    int ls_weights;      /* 0: closest-point barycentrics (paper); 1: least squares */
    double illum_weight; /* 0: geometric references (paper); > 0: illumination-aware */
    /* 1: the directions are stored in float32 (section DIRC, docs/format.md
     * §5.18): sss_compress rounds them in its copy, and a bake that
     * compresses rounds them before it computes the rows. 0: as given. */
    int dirs_f32;
    /* Optional: references chosen beforehand by sss_compress_choose_refs for
     * this bake, fraction and illum_weight (then ignored), so that a sweep
     * over SH orders and codes decimates once. NULL: chosen here. */
    const sss_refs *refs;
} sss_compress_opts;

/* The references sss_compress would choose for f: sss_refs_build on its
 * mesh, or with illum_weight > 0 sss_refs_build_ex with q at every 4th
 * direction sample (channels averaged) as the feature. */
sss_result sss_compress_choose_refs(const sss_bake_file *f, double fraction, double illum_weight, sss_refs *out,
                                   sss_error *err);

/* Paper defaults: order 3 (9 coefficients), 3 % references, linear 8-bit
 * SH codes, 16-bit barycentric weights, geometric references. */
void sss_compress_opts_default(sss_compress_opts *o);

/* Presets (docs/compression.md): the paper's configuration, "compact":
 * at most 16 (grey) / 30 (RGB) bytes per vertex at no more error than the
 * paper's, measured on the dragons, and the paper's SH-only configuration of
 * §4.1 (order 7, 16-bit codes, no references: 98 code bytes per vertex and
 * channel). */
typedef enum sss_compress_preset {
    SSS_COMPRESS_PAPER = 0,
    SSS_COMPRESS_COMPACT = 1,
    SSS_COMPRESS_PAPER_SH = 2
} sss_compress_preset;

/* Fields of sss_compress_opts a caller set itself (bits of `given`). */
enum {
    SSS_CO_ORDER = 1u << 0,
    SSS_CO_FRACTION = 1u << 1,
    SSS_CO_SH_KIND = 1u << 2,
    SSS_CO_WBITS = 1u << 3,
    SSS_CO_LS_WEIGHTS = 1u << 4,
    SSS_CO_ILLUM = 1u << 5
};

/* Sets every field of o that `given` does not name to preset p's value for
 * a file of `channels` channels (sss_material_channels) and n_dirs
 * directions: the user's own choices stay, the preset fills the rest. The
 * preset's SH order fits no more coefficients than there are direction
 * samples (order² ≤ n_dirs; a few directions get the lower orders). */
void sss_compress_preset_apply(sss_compress_opts *o, sss_compress_preset p, uint32_t channels, uint32_t n_dirs,
                               uint32_t given);

/* Adds the options' provenance to a bake's PARM object (docs/format.md
 * §5.6): an object "compression" with the SH order, reference fraction,
 * SH code kind, weight bits, least-squares weights and illumination
 * weight. */
struct cJSON;
void sss_compress_opts_to_json(const sss_compress_opts *co, struct cJSON *params);

/* Compresses the float bake src into *dst: a deep copy of src's mesh,
 * material, directions and parameters with quant SSS_QUANT_SH or
 * SSS_QUANT_REFS and the matching sh / ref parts, ready for sss_file_write.
 * Deterministic (the same bytes whatever the thread count). Errors:
 * SSS_ERR_ARG (NULL, quantised input, bad options, order² above the number
 * of directions), SSS_ERR_NOMEM, and whatever sss_refs_build returns. On
 * failure *dst is zeroed. */
sss_result sss_compress(const sss_bake_file *src, const sss_compress_opts *o, sss_bake_file *dst, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
