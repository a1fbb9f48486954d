/* sss/reconstruct.h: a file's reconstruction of q for any light direction, as a
 * reader shows it — the interpolated rows (sss_decode_all_interp, Hao–
 * Varshney 2004 §3.2; for a file with the vector integrals Q, section
 * QVEC, Q interpolated and dotted with the light, sss_decode_vector_range) plus, for a file whose rows hold q minus the own
 * term (section OWNT, sss/nearterms.h), that term added back with the
 * vertex's own visibility traced by a ray under the bake's rule. The
 * measuring tools (vertex_error.h, sss-stat --query, the image error) use this
 * so that they measure what the file stores, not a different split. */
#ifndef SSS_RECONSTRUCT_H
#define SSS_RECONSTRUCT_H
#include <stdint.h>
#include "sss/decode.h"
#include "sss/format.h"
#ifdef __cplusplus
extern "C" {
#endif
typedef struct sss_reconstruct sss_reconstruct;
/* f must outlive the result. For a file without OWNT nothing is built.
 * Errors: SSS_ERR_ARG, SSS_ERR_NOMEM, SSS_ERR_UNSUPPORTED (Embree). */
sss_result sss_reconstruct_create(const sss_bake_file *f, sss_reconstruct **out, sss_error *err);
/* out[v * channels + c] for light direction light (need not be unit). */
void sss_reconstruct_eval(const sss_reconstruct *r, const double light[3], sss_interp interp, float *out);
/* One vertex (sss_decode_vertex, plus its own term) into out[0 … C−1]. */
void sss_reconstruct_eval_vertex(const sss_reconstruct *r, uint32_t v, const double light[3], float *out);
/* The same without the own term (the stored rows alone, interpolated). */
void sss_reconstruct_eval_rows(const sss_reconstruct *r, const double light[3], sss_interp interp, float *out);
/* Own visibility the reconstruction used for light direction light: 1 =
 * lit, per vertex (all 1 for a file without OWNT). */
void sss_reconstruct_near_lit(const sss_reconstruct *r, const double light[3], uint8_t *lit);
/* Does f split off the own term? */
int sss_reconstruct_has_near_terms(const sss_reconstruct *r);
/* NULL-safe. */
void sss_reconstruct_destroy(sss_reconstruct *r);
#ifdef __cplusplus
}
#endif
#endif
