/* random.c: splitmix64 (Steele, Lea & Flood 2014 constants) and the uniform
 * direction built from it (see sss/random.h). */
#include "sss/random.h"

#include <math.h>

uint64_t sss_rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

double sss_rng_unit(uint64_t *s) { return (double)(sss_rng_next(s) >> 11) * (1.0 / 9007199254740992.0); }

void sss_rng_direction(uint64_t *s, double d[3])
{
    double z = 2.0 * sss_rng_unit(s) - 1.0, phi = 2.0 * 3.14159265358979323846 * sss_rng_unit(s);
    double r = sqrt(fmax(0.0, 1.0 - z * z));
    d[0] = r * cos(phi);
    d[1] = r * sin(phi);
    d[2] = z;
}
