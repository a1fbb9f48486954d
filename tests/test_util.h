/* test_util.h: the small helpers several test programs need, defined once
 * (header-only: each test program is one translation unit). */
#ifndef SSS_TEST_UTIL_H
#define SSS_TEST_UTIL_H

#include <math.h>
#include <stdint.h>

#include "sss/vec3.h"

/* xorshift64 in [0, 1) with 53 bits: the fixed-seed test data the tests
 * were written with (sss/random.h is the library's own generator). */
static inline double test_urand(uint64_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 7;
    *s ^= *s << 17;
    return (double)(*s >> 11) / 9007199254740992.0;
}

/* A uniform unit direction from two test_urand draws (z = 2u − 1, φ = 2πu'). */
static inline void test_random_dir(uint64_t *s, double d[3])
{
    const double z = 2 * test_urand(s) - 1, phi = 2 * SSS_PI * test_urand(s), r = sqrt(1 - z * z);
    d[0] = r * cos(phi);
    d[1] = r * sin(phi);
    d[2] = z;
}

/* Little-endian fields of a .sss file (docs/format.md §1), read back. */
static inline uint32_t test_rd32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static inline uint64_t test_rd64(const uint8_t *p) { return (uint64_t)test_rd32(p) | (uint64_t)test_rd32(p + 4) << 32; }

#endif
