/* sss/vec3.h: π and the few double-precision 3-vector operations the
 * modules share, defined once. Each is the plain formula, so a sum is taken
 * in the same order wherever it is used (the bytes of a bake do not depend
 * on which module computed a value).
 */
#ifndef SSS_VEC3_H
#define SSS_VEC3_H

#include <math.h>

/* π to double precision (C11's <math.h> has no M_PI). */
#define SSS_PI 3.14159265358979323846

static inline double sss_dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static inline void sss_sub3(double r[3], const double a[3], const double b[3])
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static inline void sss_cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* Scales v to unit length in place (each component divided by the length)
 * and returns the length; a zero vector is left as it is. */
static inline double sss_normalize3(double v[3])
{
    const double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (n > 0)
        for (int k = 0; k < 3; k++) v[k] /= n;
    return n;
}

/* Unit direction towards a light, or 0 for a zero or non-finite one. A
 * light that is already unit up to rounding (every stored ω_j) is used as
 * given, so at a direction sample the rays and cosines are bit for bit the
 * bake's; others are scaled by their largest component first, so huge or
 * tiny finite vectors normalise without overflow. Shared by the exact
 * evaluator and the per-frame path (docs/deformable.md §3), which must
 * take the same ω to agree to rounding. */
static inline int sss_light_unit(const double l[3], double d[3])
{
    if (!isfinite(l[0]) || !isfinite(l[1]) || !isfinite(l[2])) return 0;
    double n2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    if (fabs(n2 - 1.0) <= 1e-12) {
        d[0] = l[0], d[1] = l[1], d[2] = l[2];
        return 1;
    }
    double m = fmax(fabs(l[0]), fmax(fabs(l[1]), fabs(l[2])));
    if (!(m > 0.0)) return 0;
    double s[3] = {l[0] / m, l[1] / m, l[2] / m};
    double len = sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    for (int k = 0; k < 3; k++) d[k] = s[k] / len;
    return 1;
}

#endif
