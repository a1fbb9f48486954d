/* sss/random.h: a small deterministic generator (splitmix64) for fixed-seed
 * shuffles and random test directions, so results repeat bit for bit on
 * every platform. Not for anything security-related. */
#ifndef SSS_RANDOM_H
#define SSS_RANDOM_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Next 64 random bits; *state is the whole generator state (any seed). */
uint64_t sss_rng_next(uint64_t *state);

/* Uniform double in [0, 1) with 53 random bits. */
double sss_rng_unit(uint64_t *state);

/* Uniform direction on the unit sphere: z = 2u − 1, φ = 2πu' (two draws). */
void sss_rng_direction(uint64_t *state, double d[3]);

#ifdef __cplusplus
}
#endif
#endif
