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
 * `light` (unit vector towards the light; normalised here). */
void sss_decode_all(const sss_bake_file *f, const double light[3], float *out);

#ifdef __cplusplus
}
#endif
#endif
