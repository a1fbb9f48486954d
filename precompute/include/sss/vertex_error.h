/* sss/vertex_error.h: how far a .sss file's reconstruction of q is from the
 * exact evaluator (sss/exact.h), per vertex, at random light directions
 * (docs/accuracy.md; the paper's error protocol is Hao–Varshney 2004 §3.3). */
#ifndef SSS_VERTEX_ERROR_H
#define SSS_VERTEX_ERROR_H
#include <stdint.h>
#include "sss/decode.h"
#include "sss/dirset.h"
#include "sss/exact.h"
#include "sss/format.h"
#ifdef __cplusplus
extern "C" {
#endif

/* Index `channels` of every array holds the figure over all channels. */
typedef struct sss_vertex_error {
    uint32_t channels;  /* of the file */
    uint32_t ndirs;     /* light directions used */
    double rms[SSS_MAX_CHANNELS + 1];       /* sqrt(Σ_d Σ_v A_v (r − x)² / (ndirs Σ_v A_v)) */
    double rel_rms[SSS_MAX_CHANNELS + 1];   /* sqrt(Σ A (r − x)² / Σ A x²) */
    double max_abs[SSS_MAX_CHANNELS + 1];   /* max |r − x| */
    double rms_exact[SSS_MAX_CHANNELS + 1]; /* area-weighted RMS of x itself, for scale */
} sss_vertex_error;

/* Per-vertex error of f's reconstruction r = sss_decode_all(f, ω) against
 * the exact x = sss_exact_eval(e, ω) (e built from f) at ndirs random unit
 * directions from `seed` (sss_rng_direction), each at least 1e-6 rad from
 * every direction sample (closer ones are redrawn), area-weighted with
 * A_v = 1/3 of the incident triangle areas. Deterministic. Errors:
 * SSS_ERR_ARG (NULL, ndirs 0, e not from a file like f), SSS_ERR_NOMEM. */
sss_result sss_vertex_error_vs_exact(const sss_bake_file *f, const sss_exact *e, uint32_t ndirs, uint64_t seed,
                                     sss_vertex_error *out, sss_error *err);

/* The same with a choice of direction interpolation (sss_decode_all_interp). */
sss_result sss_vertex_error_vs_exact_interp(const sss_bake_file *f, const sss_exact *e, uint32_t ndirs, uint64_t seed,
                                            sss_interp interp, sss_vertex_error *out, sss_error *err);

/* The random light directions of both error measures: sss_rng_direction
 * from *state, redrawn while within 1e-6 rad of a sample of s. */
void sss_vertex_error_draw_direction(const sss_dirset *s, uint64_t *state, double d[3]);

#ifdef __cplusplus
}
#endif
#endif
