/* sss/lloyd.h: Lloyd–Max scalar quantisers, for the 8-bit integrals of
 * `--quant lloyd8` (Hao–Varshney 2004 §4: the paper's quantised storage)
 * and the SH codes of the compressed forms. Part of libsss_bake
 * (kernels/lloyd.c).
 */
#ifndef SSS_LLOYD_H
#define SSS_LLOYD_H

#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Lloyd–Max scalar quantiser with 256 levels for one channel: trains on
 * (a deterministic subsample of) x[k * stride], k < count, writes levels in
 * increasing order (level 0 pinned to the minimum, so shadowed zeros decode
 * as zeros) and idx[k * stride]. Returns Σx² and Σ(x − x̂)² via the pointers. */
sss_result sss_lloyd8(const float *x, uint64_t count, uint32_t stride, float levels[256], uint8_t *idx,
                      double *signal, double *noise, sss_error *err);

/* The same quantiser with nlevels (2 … 256) levels; pin_min pins level 0 to
 * the minimum (what sss_lloyd8 does), else every level is a free centroid
 * (signed data such as SH coefficients). */
sss_result sss_lloyd(const float *x, uint64_t count, uint32_t stride, uint32_t nlevels, int pin_min, float *levels,
                     uint8_t *idx, double *signal, double *noise, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
