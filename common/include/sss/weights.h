/* sss/weights.h: the weights w(x_o, x_i) of the sum of Hao–Varshney 2004
 * §3.1 (docs/physics.md §4), per receiver x_o, in compressed-row form:
 *
 *   q(x_o, ω) = Σ_i w(x_o, x_i) · G(x_i, ω)   over the entries of row o.
 *
 * The bake's neighbourhoods (sss_nbhd_build, precompute) and the near terms
 * every reader adds at run time (sss_near_build, sss/nearterms.h) are both
 * such rows; this is their one type.
 */
#ifndef SSS_WEIGHTS_H
#define SSS_WEIGHTS_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_weights {
    uint32_t nrows;    /* receivers */
    uint32_t channels; /* 1 or 3 */
    uint64_t *start;   /* nrows + 1 offsets: row r is entries [start[r], start[r + 1]) */
    uint32_t *idx;     /* start[nrows] source vertex indices */
    float *w;          /* start[nrows] × channels weights, interleaved (entry a, channel c at a·channels + c) */
} sss_weights;

/* Frees the arrays and zeroes w. NULL-safe. */
void sss_weights_free(sss_weights *w);

#ifdef __cplusplus
}
#endif
#endif
