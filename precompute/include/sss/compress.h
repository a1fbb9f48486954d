/* sss/compress.h: compression of baked integrals q(x_v, ω_j), after
 * Hao–Varshney 2004 §4 (in memory only; no file-format change yet).
 *
 * Two modes:
 *   - SH-only (fraction 0, §4.1): every vertex and channel stores the
 *     least-squares coefficients of q over the direction samples in the
 *     first order² real spherical harmonics.
 *   - Reference points (fraction > 0, §4.2–4.3): a subset of vertices
 *     (sss_refs_build) keeps its full per-direction integrals, quantised with
 *     one 256-level Lloyd table per channel (sss_lloyd8); every other vertex
 *     stores its reference triangle, two 16-bit barycentric weights and an
 *     SH-coded delta Δq_j = q_j − Σ_k w_k q̂(ref_k, ω_j), formed in double
 *     from the *dequantised* reference values and weights, so the delta
 *     also corrects the quantisation of both.
 * In both modes SH coefficients are stored as 8-bit codes with one scale per
 * (channel, coefficient index): code = round(127 c / scale), scale = max |c|
 * over the coded vertices.
 */
#ifndef SSS_COMPRESS_H
#define SSS_COMPRESS_H
#include <stdint.h>
#include "sss/dirset.h"
#include "sss/format.h"
#include "sss/result.h"
#ifdef __cplusplus
extern "C" {
#endif

/* A compressed bake. All arrays owned; free with sss_compressed_free.
 * "Stored" arrays are what a file would hold and are counted by
 * sss_compressed_bytes; "derived" ones are rebuilt from stored ones. */
typedef struct sss_compressed {
    uint32_t nv;          /* vertices */
    uint32_t channels;    /* 1 or 3 */
    uint32_t order;       /* SH order n (bands 0 … n−1), 0 … 8 */
    uint32_t ncoef;       /* order² */
    double fraction;      /* reference fraction asked for (0: SH-only mode) */
    sss_dirset dirs;      /* copy of the file's direction set (stored: directions; triangulation derived) */

    /* reference mode (all NULL / 0 in SH-only mode) */
    uint32_t nref;        /* reference vertices */
    uint32_t *ref_vertex; /* stored: nref vertex indices, increasing */
    uint32_t nrt;         /* reference triangles */
    uint32_t *ref_tri;    /* stored: 3*nrt indices into ref_vertex */
    float *levels;        /* stored: channels * 256 Lloyd levels */
    uint8_t *ref_idx;     /* stored: ndirs * nref * channels codes, direction-major
                             ((j * nref + r) * channels + c) */

    /* coded vertices: the non-references (reference mode) or every vertex
     * (SH-only); their order is increasing vertex index */
    uint32_t ncoded;
    uint32_t *coded_vertex; /* derived: ncoded vertex indices (complement of ref_vertex) */
    uint32_t *vtri;         /* stored (reference mode): ncoded reference-triangle indices */
    uint16_t *w16;          /* stored (reference mode): 2*ncoded weights w0, w1 × 65535; w2 = 1 − w0 − w1 ≥ 0 */
    int8_t *sh_code;        /* stored: ncoded * channels * ncoef codes, ((k * channels + c) * ncoef + i) */
    float *sh_scale;        /* stored: channels * ncoef scales, (c * ncoef + i) */
} sss_compressed;

/* Exact storage of every part, in bytes. */
typedef struct sss_compressed_bytes {
    uint64_t header;          /* 7 × uint32: nv, channels, ndirs, order, nref, nrt, ncoded */
    uint64_t directions;      /* ndirs × 3 float32 (triangulation is recomputed) */
    uint64_t ref_integrals;   /* ndirs × nref × channels uint8 */
    uint64_t lloyd_tables;    /* channels × 256 float32 */
    uint64_t ref_vertex_list; /* nref × uint32 */
    uint64_t vertex_tri;      /* ncoded × uint32 (reference mode) */
    uint64_t ref_tri_table;   /* nrt × 3 uint32 */
    uint64_t weights;         /* ncoded × 2 uint16 (reference mode) */
    uint64_t sh_codes;        /* ncoded × channels × ncoef int8 */
    uint64_t sh_scales;       /* channels × ncoef float32 */
    uint64_t total;           /* sum of the above */
    double per_vertex;        /* total / nv */
} sss_compressed_bytes;

/* Compresses the float bake f (quant SSS_QUANT_FLOAT) with SH order `order`
 * (0 … 8; order² ≤ number of directions) and reference fraction `fraction`
 * in [0, 1] (0: SH-only mode, which needs order ≥ 1). Errors: SSS_ERR_ARG
 * (NULL, quantised input, bad order or fraction, too few directions),
 * SSS_ERR_NOMEM, and whatever sss_refs_build / sss_lloyd8 return. On
 * failure *out is zeroed. */
sss_result sss_compress(const sss_bake_file *f, uint32_t order, double fraction, sss_compressed *out,
                        sss_error *err);

/* Frees every array and zeroes the struct. NULL-safe. */
void sss_compressed_free(sss_compressed *cq);

/* The byte count of every stored part (mesh geometry excluded: it is the
 * same with or without compression). */
void sss_compressed_bytes_of(const sss_compressed *cq, sss_compressed_bytes *b);

/* Reconstructs q(x_v, light) for all vertices into out[v * channels + c]:
 * reference rows interpolated over the direction triangle (as
 * sss_decode_all), blended with the weights, plus the SH delta evaluated at
 * the light (one sss_sh_eval per call, then a dot product per vertex and
 * channel). SH-only mode: the SH dot product alone. A zero or non-finite
 * light writes zeros. */
void sss_compressed_eval(const sss_compressed *cq, const double light[3], float *out);

/* Error against the uncompressed interpolation (sss_decode_all of f) over
 * ndirs_test random unit light directions (fixed seed): for each channel c,
 * rel_rms[c] = sqrt(Σ_d Σ_v A_v (r − u)²) / sqrt(Σ_d Σ_v A_v u²) with A_v
 * the vertex area (1/3 of incident triangle areas); rel_rms[channels] is
 * the same over all channels. *max_abs (may be NULL) gets max |r − u| and
 * *max_rel (may be NULL) that divided by the overall area-weighted RMS of u.
 * rel_rms needs channels + 1 entries. Errors: SSS_ERR_ARG (mismatched f,
 * NULL, ndirs_test 0), SSS_ERR_NOMEM. */
sss_result sss_compressed_error(const sss_compressed *cq, const sss_bake_file *f, uint32_t ndirs_test, uint64_t seed,
                                double *rel_rms, double *max_abs, double *max_rel, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
