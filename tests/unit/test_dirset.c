/* test_dirset.c: the light-direction set (Hao–Varshney 2004 §3.2), its
 * spherical Delaunay triangulation and barycentric lookup (docs/physics.md §7). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/random.h"
#include "sss/dirset.h"

/* ---- helpers ------------------------------------------------------------ */

/* |a − b| ≤ eps (cmocka 1.1.5 has no assert_close). */
#define assert_close(a, b, eps)                                                                                    \
    do {                                                                                                           \
        double a_ = (a), b_ = (b);                                                                                 \
        if (!(fabs(a_ - b_) <= (eps))) fail_msg("%s = %.17g, expected %.17g (within %g)", #a, a_, b_, (double)(eps)); \
    } while (0)

static const double *V(const sss_dirset *s, uint32_t i) { return s->dir + 3 * (size_t)i; }

static double det3(const double *x, const double *y, const double *z)
{
    return x[0] * (y[1] * z[2] - y[2] * z[1]) + x[1] * (y[2] * z[0] - y[0] * z[2]) + x[2] * (y[0] * z[1] - y[1] * z[0]);
}

/* (b−a)×(c−a)·(p−a): > 0 when p is above the plane of the oriented facet,
 * i.e. strictly inside the facet's circumcircle on the sphere. */
static double above(const double *a, const double *b, const double *c, const double *p)
{
    double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double w[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
    return det3(w, u, v);
}

static uint64_t rng_state;

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

static int has_key(const uint64_t *keys, size_t n, uint64_t k)
{
    return bsearch(&k, keys, n, sizeof k, cmp_u64) != NULL;
}

/* Closed, consistently oriented triangulation of the sphere using every
 * direction, optionally Delaunay (no sample above any facet's plane). */
static void check_triangulation(const sss_dirset *s, int check_delaunay)
{
    const uint32_t n = s->n, F = s->ntri;
    assert_int_equal(F, 2 * n - 4);
    assert_non_null(s->tri);

    /* Positive orientation and every vertex used. */
    uint32_t *used = calloc(n, sizeof *used);
    assert_non_null(used);
    for (uint32_t t = 0; t < F; t++) {
        const uint32_t *v = s->tri + 3 * (size_t)t;
        for (int k = 0; k < 3; k++) {
            assert_true(v[k] < n);
            used[v[k]]++;
        }
        assert_true(v[0] != v[1] && v[1] != v[2] && v[2] != v[0]);
        double det = det3(V(s, v[0]), V(s, v[1]), V(s, v[2]));
        if (!(det > 0.0)) fail_msg("triangle %u (%u %u %u) has det %g", t, v[0], v[1], v[2], det);
    }
    for (uint32_t i = 0; i < n; i++)
        if (used[i] < 3) fail_msg("vertex %u used by %u triangles", i, used[i]);
    free(used);

    /* Each directed edge once, and its reverse present: every undirected
     * edge is shared by exactly two triangles with opposite orientation. */
    size_t ne = 3 * (size_t)F;
    uint64_t *keys = malloc(ne * sizeof *keys);
    assert_non_null(keys);
    for (uint32_t t = 0; t < F; t++)
        for (int k = 0; k < 3; k++)
            keys[3 * (size_t)t + k] = (uint64_t)s->tri[3 * (size_t)t + k] << 32 | s->tri[3 * (size_t)t + (k + 1) % 3];
    qsort(keys, ne, sizeof *keys, cmp_u64);
    for (size_t i = 1; i < ne; i++)
        if (keys[i] == keys[i - 1]) fail_msg("directed edge %u->%u twice", (unsigned)(keys[i] >> 32), (unsigned)keys[i]);
    for (size_t i = 0; i < ne; i++) {
        uint64_t rev = (keys[i] & 0xFFFFFFFFull) << 32 | keys[i] >> 32;
        if (!has_key(keys, ne, rev)) fail_msg("edge %u->%u has no twin", (unsigned)(keys[i] >> 32), (unsigned)keys[i]);
    }
    free(keys);
    /* Euler: V − E + F = 2 with E = 3F/2 undirected edges. */
    assert_int_equal(3 * (size_t)F % 2, 0);
    assert_int_equal((long)n - (long)(3 * (size_t)F / 2) + (long)F, 2);

    if (check_delaunay)
        for (uint32_t t = 0; t < F; t++) {
            const uint32_t *v = s->tri + 3 * (size_t)t;
            for (uint32_t q = 0; q < n; q++) {
                if (q == v[0] || q == v[1] || q == v[2]) continue;
                double o = above(V(s, v[0]), V(s, v[1]), V(s, v[2]), V(s, q));
                if (o > 1e-9) fail_msg("sample %u inside circumcircle of triangle %u (%g)", q, t, o);
            }
        }
}

/* Weights valid for d: indices in range, w ≥ 0, Σw = 1, Σ w_k v_k ∥ d and
 * d inside the returned triangle. */
static void check_lookup(const sss_dirset *s, const double d[3], int32_t t, const uint32_t idx[3], const double w[3])
{
    assert_true(t >= 0 && (uint32_t)t < s->ntri);
    for (int k = 0; k < 3; k++) {
        assert_int_equal(idx[k], s->tri[3 * (size_t)t + k]);
        assert_true(w[k] >= 0.0);
    }
    assert_true(fabs(w[0] + w[1] + w[2] - 1.0) <= 1e-12);
    double m[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++) m[j] += w[k] * V(s, idx[k])[j];
    double cx[3] = {m[1] * d[2] - m[2] * d[1], m[2] * d[0] - m[0] * d[2], m[0] * d[1] - m[1] * d[0]};
    double nm = sqrt(m[0] * m[0] + m[1] * m[1] + m[2] * m[2]), nd = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double rel = sqrt(cx[0] * cx[0] + cx[1] * cx[1] + cx[2] * cx[2]) / (nm * nd);
    if (!(rel <= 1e-9)) fail_msg("interpolated vector not parallel to d (%g)", rel);
    assert_true(m[0] * d[0] + m[1] * d[1] + m[2] * d[2] > 0.0);
    const double *a = V(s, idx[0]), *b = V(s, idx[1]), *c = V(s, idx[2]);
    double dn[3] = {d[0] / nd, d[1] / nd, d[2] / nd};
    assert_true(det3(dn, b, c) >= -1e-12);
    assert_true(det3(dn, c, a) >= -1e-12);
    assert_true(det3(dn, a, b) >= -1e-12);
}

static void make_dirs(sss_dirset *s, uint32_t n, const double *d)
{
    memset(s, 0, sizeof *s);
    s->n = n;
    s->dir = malloc(3 * (size_t)n * sizeof *s->dir);
    assert_non_null(s->dir);
    memcpy(s->dir, d, 3 * (size_t)n * sizeof *d);
}

/* ---- triangulation -------------------------------------------------------- */

static void fibonacciHas2NMinus4ValidDelaunayTriangles(void **state)
{
    (void)state;
    static const uint32_t ns[] = {4, 5, 6, 12, 25, 200, 801, 5000};
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        sss_dirset s;
        sss_error err = {{0}};
        assert_int_equal(sss_dirset_fibonacci(&s, ns[i], &err), SSS_OK);
        assert_int_equal(s.n, ns[i]);
        check_triangulation(&s, ns[i] <= 801);
        sss_dirset_free(&s);
    }
}

static void fibonacciLargeSetTriangulatesValidly(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 20000, NULL), SSS_OK);
    check_triangulation(&s, 0);
    sss_dirset_free(&s);
}

static void fibonacciDirectionsFollowFormula(void **state)
{
    (void)state;
    sss_dirset s;
    const uint32_t n = 200;
    assert_int_equal(sss_dirset_fibonacci(&s, n, NULL), SSS_OK);
    const double golden = (1.0 + sqrt(5.0)) / 2.0;
    for (uint32_t i = 0; i < n; i++) {
        double z = 1.0 - 2.0 * (i + 0.5) / n, phi = 2.0 * 3.14159265358979323846 * i / golden;
        double r = sqrt(1.0 - z * z);
        assert_close(V(&s, i)[0], r * cos(phi), 1e-12);
        assert_close(V(&s, i)[1], r * sin(phi), 1e-12);
        assert_close(V(&s, i)[2], z, 1e-15);
        double len = sqrt(V(&s, i)[0] * V(&s, i)[0] + V(&s, i)[1] * V(&s, i)[1] + V(&s, i)[2] * V(&s, i)[2]);
        assert_close(len, 1.0, 1e-14);
    }
    sss_dirset_free(&s);
}

static void triangulationIsDeterministicAcrossCalls(void **state)
{
    (void)state;
    sss_dirset a, b;
    assert_int_equal(sss_dirset_fibonacci(&a, 801, NULL), SSS_OK);
    assert_int_equal(sss_dirset_fibonacci(&b, 801, NULL), SSS_OK);
    assert_int_equal(a.ntri, b.ntri);
    assert_memory_equal(a.tri, b.tri, 3 * (size_t)a.ntri * sizeof *a.tri);
    /* Re-triangulating in place gives the same result again. */
    assert_int_equal(sss_dirset_triangulate(&a, NULL), SSS_OK);
    assert_memory_equal(a.tri, b.tri, 3 * (size_t)a.ntri * sizeof *a.tri);
    sss_dirset_free(&a);
    sss_dirset_free(&b);
}

static void octahedronCocircularDirectionsGive8Triangles(void **state)
{
    (void)state;
    static const double d[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    sss_dirset s;
    make_dirs(&s, 6, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_OK);
    assert_int_equal(s.ntri, 8);
    check_triangulation(&s, 1);
    /* Every octant face: each triangle has one axis of each kind. */
    for (uint32_t t = 0; t < 8; t++) {
        int axis[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) axis[s.tri[3 * t + k] / 2]++;
        assert_true(axis[0] == 1 && axis[1] == 1 && axis[2] == 1);
    }
    sss_dirset_free(&s);
}

static void cubeCornersWithCocircularFacesGive12Triangles(void **state)
{
    (void)state;
    double d[24];
    const double c = 1.0 / sqrt(3.0);
    for (int i = 0; i < 8; i++) {
        d[3 * i] = (i & 1) ? c : -c;
        d[3 * i + 1] = (i & 2) ? c : -c;
        d[3 * i + 2] = (i & 4) ? c : -c;
    }
    sss_dirset s;
    make_dirs(&s, 8, d);
    assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
    check_triangulation(&s, 1);
    sss_dirset_free(&s);
}

/* Rotates v about the unit axis ax by angle th (Rodrigues). */
static void rotate(double v[3], const double ax[3], double th)
{
    double c = cos(th), s = sin(th), d = ax[0] * v[0] + ax[1] * v[1] + ax[2] * v[2];
    double cr[3] = {ax[1] * v[2] - ax[2] * v[1], ax[2] * v[0] - ax[0] * v[2], ax[0] * v[1] - ax[1] * v[0]};
    for (int k = 0; k < 3; k++) v[k] = v[k] * c + cr[k] * s + ax[k] * d * (1.0 - c);
}

static void cocircularRingsTriangulateAsDelaunay(void **state)
{
    (void)state;
    /* Many exactly or nearly (after rotation) cocircular points: a ring of
     * 150 at z = 0.9 (one flat 150-gon on the hull), rings at z = 0 and
     * z = −0.6, and the poles; unrotated and rotated. */
    const uint32_t m0 = 150, m1 = 40, m2 = 33, n = 2 + m0 + m1 + m2;
    double *d = malloc(3 * n * sizeof *d);
    assert_non_null(d);
    const double axis[3] = {0.48, -0.6, 0.64};
    for (int variant = 0; variant < 3; variant++) {
        uint32_t k = 0;
        const double zs[3] = {0.9, 0.0, -0.6};
        const uint32_t ms[3] = {m0, m1, m2};
        d[3 * k] = 0, d[3 * k + 1] = 0, d[3 * k + 2] = 1, k++;
        d[3 * k] = 0, d[3 * k + 1] = 0, d[3 * k + 2] = -1, k++;
        for (int r = 0; r < 3; r++)
            for (uint32_t j = 0; j < ms[r]; j++) {
                double a = 2.0 * 3.14159265358979323846 * j / ms[r], rr = sqrt(1.0 - zs[r] * zs[r]);
                d[3 * k] = rr * cos(a), d[3 * k + 1] = rr * sin(a), d[3 * k + 2] = zs[r], k++;
            }
        for (uint32_t i = 0; i < n && variant > 0; i++) rotate(d + 3 * i, axis, variant == 1 ? 0.7 : 1e-9);
        sss_dirset s;
        make_dirs(&s, n, d);
        sss_error err = {{0}};
        if (sss_dirset_triangulate(&s, &err) != SSS_OK) fail_msg("variant %d: %s", variant, err.msg);
        check_triangulation(&s, 1);
        for (uint32_t i = 0; i < n; i++) {
            uint32_t idx[3];
            double w[3];
            check_lookup(&s, V(&s, i), sss_dirset_lookup(&s, V(&s, i), idx, w), idx, w);
        }
        sss_dirset_free(&s);
    }
    free(d);
}

static void randomDirectionsTriangulateAsDelaunay(void **state)
{
    (void)state;
    rng_state = 12345;
    const uint32_t n = 600;
    double *d = malloc(3 * n * sizeof *d);
    assert_non_null(d);
    for (uint32_t i = 0; i < n; i++) sss_rng_direction(&rng_state, d + 3 * i);
    sss_dirset s;
    make_dirs(&s, n, d);
    free(d);
    assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
    check_triangulation(&s, 1);
    /* Indices carry no spatial order here: lookup must still work. */
    for (int q = 0; q < 20000; q++) {
        double d[3];
        sss_rng_direction(&rng_state, d);
        uint32_t idx[3];
        double w[3];
        check_lookup(&s, d, sss_dirset_lookup(&s, d, idx, w), idx, w);
    }
    sss_dirset_free(&s);
}

static void lookupStaysCorrectWhenTrianglesAreReordered(void **state)
{
    (void)state;
    /* A caller may fill tri itself in any order and rotation; lookup then
     * cannot rely on the sorted order triangulate produces. */
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    for (uint32_t t = 0; t < s.ntri / 2; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t x = s.tri[3 * t + k];
            s.tri[3 * t + k] = s.tri[3 * (s.ntri - 1 - t) + k];
            s.tri[3 * (s.ntri - 1 - t) + k] = x;
        }
    for (uint32_t t = 0; t < s.ntri; t += 2) { /* rotate every other triangle */
        uint32_t x = s.tri[3 * t];
        s.tri[3 * t] = s.tri[3 * t + 1];
        s.tri[3 * t + 1] = s.tri[3 * t + 2];
        s.tri[3 * t + 2] = x;
    }
    check_triangulation(&s, 1);
    rng_state = 77;
    for (int q = 0; q < 20000; q++) {
        double d[3];
        sss_rng_direction(&rng_state, d);
        uint32_t idx[3];
        double w[3];
        check_lookup(&s, d, sss_dirset_lookup(&s, d, idx, w), idx, w);
    }
    for (uint32_t i = 0; i < s.n; i++) {
        uint32_t idx[3];
        double w[3];
        check_lookup(&s, V(&s, i), sss_dirset_lookup(&s, V(&s, i), idx, w), idx, w);
        for (int k = 0; k < 3; k++) assert_close(w[k], idx[k] == i ? 1.0 : 0.0, 1e-12);
    }
    sss_dirset_free(&s);
}

static void fewerThanFourDirectionsGiveNoTriangles(void **state)
{
    (void)state;
    for (uint32_t n = 1; n <= 3; n++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, n, NULL), SSS_OK);
        assert_int_equal(s.ntri, 0);
        assert_null(s.tri);
        for (uint32_t i = 0; i < n; i++) {
            /* Slightly off sample i: still nearest to it. */
            double d[3] = {V(&s, i)[0] + 0.01, V(&s, i)[1] - 0.01, V(&s, i)[2]};
            uint32_t idx[3];
            double w[3];
            assert_int_equal(sss_dirset_lookup(&s, d, idx, w), -1);
            assert_int_equal(idx[0], i);
            assert_int_equal(idx[1], i);
            assert_int_equal(idx[2], i);
            assert_true(w[0] == 1.0 && w[1] == 0.0 && w[2] == 0.0);
        }
        sss_dirset_free(&s);
    }
}

/* ---- invalid input --------------------------------------------------------- */

static void fibonacciRejectsZeroAndTooManyDirections(void **state)
{
    (void)state;
    sss_dirset s;
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_fibonacci(&s, 0, &err), SSS_ERR_ARG);
    assert_true(err.msg[0] != 0);
    assert_null(s.dir);
    assert_null(s.tri);
    assert_int_equal(sss_dirset_fibonacci(&s, (1u << 20) + 1, &err), SSS_ERR_ARG);
    assert_null(s.dir);
}

static void triangulateRejectsNaNDirectionNamingIt(void **state)
{
    (void)state;
    double d[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    d[3 * 4 + 1] = NAN;
    sss_dirset s;
    make_dirs(&s, 6, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "direction 4"));
    assert_non_null(strstr(err.msg, "finite"));
    assert_int_equal(s.ntri, 0);
    assert_null(s.tri);
    sss_dirset_free(&s);
}

static void triangulateRejectsNonUnitDirectionNamingIt(void **state)
{
    (void)state;
    double d[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    d[3 * 2 + 1] = 1.00001;
    sss_dirset s;
    make_dirs(&s, 6, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "direction 2"));
    /* Within 1e-6 of unit length is accepted. */
    s.dir[3 * 2 + 1] = 1.0 + 5e-7;
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_OK);
    check_triangulation(&s, 0);
    sss_dirset_free(&s);
}

static void triangulateRejectsCoplanarOrCollinearDirections(void **state)
{
    (void)state;
    /* Five directions on the equator. */
    double d[15];
    for (int i = 0; i < 5; i++) {
        double phi = 2.0 * 3.14159265358979323846 * i / 5.0;
        d[3 * i] = cos(phi);
        d[3 * i + 1] = sin(phi);
        d[3 * i + 2] = 0.0;
    }
    sss_dirset s;
    make_dirs(&s, 5, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "coplanar"));
    assert_int_equal(s.ntri, 0);
    sss_dirset_free(&s);
    /* Four directions on one line through the origin. */
    static const double l[] = {0, 1, 0, 0, -1, 0, 0, 1, 0, 0, -1, 0};
    make_dirs(&s, 4, l);
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "collinear"));
    sss_dirset_free(&s);
}

static void triangulateRejectsDuplicateDirection(void **state)
{
    (void)state;
    double d[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 1, 0};
    sss_dirset s;
    make_dirs(&s, 7, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_true(err.msg[0] != 0);
    sss_dirset_free(&s);
}

static void triangulateRejectsDirectionsInOneHemisphere(void **state)
{
    (void)state;
    /* Upper hemisphere only: the hull has a facet with the origin outside. */
    rng_state = 99;
    const uint32_t n = 50;
    double d[150];
    for (uint32_t i = 0; i < n; i++) {
        sss_rng_direction(&rng_state, d + 3 * i);
        d[3 * i + 2] = fabs(d[3 * i + 2]); /* reflect into z ≥ 0 */
    }
    sss_dirset s;
    make_dirs(&s, n, d);
    sss_error err = {{0}};
    assert_int_equal(sss_dirset_triangulate(&s, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "origin"));
    sss_dirset_free(&s);
}

static void freeIsNullSafeAndZeroes(void **state)
{
    (void)state;
    sss_dirset_free(NULL);
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 12, NULL), SSS_OK);
    sss_dirset_free(&s);
    assert_int_equal(s.n, 0);
    assert_int_equal(s.ntri, 0);
    assert_null(s.dir);
    assert_null(s.tri);
    sss_dirset_free(&s);
}

/* ---- lookup ---------------------------------------------------------------- */

static void lookupRandomDirectionsGiveValidBarycentrics(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    rng_state = 2024;
    for (int q = 0; q < 100000; q++) {
        double d[3];
        sss_rng_direction(&rng_state, d);
        if (q % 7 == 0) d[0] *= 3.0, d[1] *= 3.0, d[2] *= 3.0; /* need not be normalised */
        uint32_t idx[3];
        double w[3];
        int32_t t = sss_dirset_lookup(&s, d, idx, w);
        check_lookup(&s, d, t, idx, w);
    }
    sss_dirset_free(&s);
}

static void lookupAtSampleGivesWeightOneOnIt(void **state)
{
    (void)state;
    static const uint32_t ns[] = {4, 12, 200, 801};
    for (size_t j = 0; j < sizeof ns / sizeof ns[0]; j++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, ns[j], NULL), SSS_OK);
        for (uint32_t i = 0; i < s.n; i++) {
            uint32_t idx[3];
            double w[3];
            int32_t t = sss_dirset_lookup(&s, V(&s, i), idx, w);
            check_lookup(&s, V(&s, i), t, idx, w);
            double wi = 0.0, other = 0.0;
            for (int k = 0; k < 3; k++) *(idx[k] == i ? &wi : &other) += w[k];
            if (!(fabs(wi - 1.0) <= 1e-12 && other <= 1e-12))
                fail_msg("n=%u sample %u: weight %.17g on it, %.3g elsewhere", ns[j], i, wi, other);
        }
        sss_dirset_free(&s);
    }
}

static void lookupAtOctahedronVerticesIsExact(void **state)
{
    (void)state;
    static const double d[] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
    sss_dirset s;
    make_dirs(&s, 6, d);
    assert_int_equal(sss_dirset_triangulate(&s, NULL), SSS_OK);
    for (uint32_t i = 0; i < 6; i++) {
        uint32_t idx[3];
        double w[3];
        int32_t t = sss_dirset_lookup(&s, V(&s, i), idx, w);
        check_lookup(&s, V(&s, i), t, idx, w);
        for (int k = 0; k < 3; k++) assert_close(w[k], idx[k] == i ? 1.0 : 0.0, 1e-15);
    }
    /* Centre of an octant: equal weights. */
    double c[3] = {1, 1, 1};
    uint32_t idx[3];
    double w[3];
    check_lookup(&s, c, sss_dirset_lookup(&s, c, idx, w), idx, w);
    for (int k = 0; k < 3; k++) assert_close(w[k], 1.0 / 3.0, 1e-15);
    sss_dirset_free(&s);
}

static void lookupOnEdgeMidpointGivesZeroOppositeWeight(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    for (uint32_t t = 0; t < s.ntri; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = s.tri[3 * t + k], b = s.tri[3 * t + (k + 1) % 3];
            double d[3];
            for (int j = 0; j < 3; j++) d[j] = V(&s, a)[j] + V(&s, b)[j];
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int j = 0; j < 3; j++) d[j] /= len;
            uint32_t idx[3];
            double w[3];
            int32_t r = sss_dirset_lookup(&s, d, idx, w);
            check_lookup(&s, d, r, idx, w);
            double wa = 0.0, wb = 0.0, other = 0.0;
            for (int j = 0; j < 3; j++) {
                if (idx[j] == a) wa += w[j];
                else if (idx[j] == b) wb += w[j];
                else other += w[j];
            }
            if (!(other <= 1e-12)) fail_msg("edge %u-%u midpoint: weight %g off the edge", a, b, other);
            assert_close(wa, 0.5, 1e-12);
            assert_close(wb, 0.5, 1e-12);
        }
    sss_dirset_free(&s);
}

static void lookupAtPolesGivesValidWeights(void **state)
{
    (void)state;
    static const uint32_t ns[] = {4, 5, 6, 12, 25, 200, 801};
    for (size_t j = 0; j < sizeof ns / sizeof ns[0]; j++) {
        sss_dirset s;
        assert_int_equal(sss_dirset_fibonacci(&s, ns[j], NULL), SSS_OK);
        static const double poles[2][3] = {{0, 0, 1}, {0, 0, -1}};
        for (int p = 0; p < 2; p++) {
            uint32_t idx[3];
            double w[3];
            int32_t t = sss_dirset_lookup(&s, poles[p], idx, w);
            check_lookup(&s, poles[p], t, idx, w);
        }
        sss_dirset_free(&s);
    }
}

static void lookupIsContinuousAcrossEdges(void **state)
{
    (void)state;
    /* Weights as a function of d, summed per sample, change by O(step) along
     * a great circle: no jumps where the containing triangle changes. */
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 200, NULL), SSS_OK);
    double *prev = calloc(s.n, sizeof *prev), *cur = calloc(s.n, sizeof *cur);
    assert_non_null(prev);
    assert_non_null(cur);
    const int steps = 20000;
    const double h = 2.0 * 3.14159265358979323846 / steps;
    for (int i = 0; i <= steps; i++) {
        double a = i * h, d[3] = {cos(a) * 0.8, sin(a) * 0.8, 0.6 * sin(a + 0.3)};
        uint32_t idx[3];
        double w[3];
        memset(cur, 0, s.n * sizeof *cur);
        check_lookup(&s, d, sss_dirset_lookup(&s, d, idx, w), idx, w);
        for (int k = 0; k < 3; k++) cur[idx[k]] += w[k];
        if (i > 0) {
            double jump = 0.0;
            for (uint32_t v = 0; v < s.n; v++) jump = fmax(jump, fabs(cur[v] - prev[v]));
            if (!(jump < 0.05)) fail_msg("weights jump by %g at step %d", jump, i);
        }
        double *t = prev;
        prev = cur;
        cur = t;
    }
    free(prev);
    free(cur);
    sss_dirset_free(&s);
}

static void lookupOfZeroOrNaNDirectionReturnsMinusOne(void **state)
{
    (void)state;
    sss_dirset s;
    assert_int_equal(sss_dirset_fibonacci(&s, 25, NULL), SSS_OK);
    const double zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 1};
    uint32_t idx[3];
    double w[3];
    assert_int_equal(sss_dirset_lookup(&s, zero, idx, w), -1);
    assert_true(idx[0] < s.n && idx[1] < s.n && idx[2] < s.n);
    assert_close(w[0] + w[1] + w[2], 1.0, 0.0);
    assert_int_equal(sss_dirset_lookup(&s, nan3, idx, w), -1);
    assert_true(idx[0] < s.n && w[0] == 1.0);
    sss_dirset_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(fibonacciHas2NMinus4ValidDelaunayTriangles),
        cmocka_unit_test(fibonacciLargeSetTriangulatesValidly),
        cmocka_unit_test(fibonacciDirectionsFollowFormula),
        cmocka_unit_test(triangulationIsDeterministicAcrossCalls),
        cmocka_unit_test(octahedronCocircularDirectionsGive8Triangles),
        cmocka_unit_test(cubeCornersWithCocircularFacesGive12Triangles),
        cmocka_unit_test(cocircularRingsTriangulateAsDelaunay),
        cmocka_unit_test(randomDirectionsTriangulateAsDelaunay),
        cmocka_unit_test(lookupStaysCorrectWhenTrianglesAreReordered),
        cmocka_unit_test(fewerThanFourDirectionsGiveNoTriangles),
        cmocka_unit_test(fibonacciRejectsZeroAndTooManyDirections),
        cmocka_unit_test(triangulateRejectsNaNDirectionNamingIt),
        cmocka_unit_test(triangulateRejectsNonUnitDirectionNamingIt),
        cmocka_unit_test(triangulateRejectsCoplanarOrCollinearDirections),
        cmocka_unit_test(triangulateRejectsDuplicateDirection),
        cmocka_unit_test(triangulateRejectsDirectionsInOneHemisphere),
        cmocka_unit_test(freeIsNullSafeAndZeroes),
        cmocka_unit_test(lookupRandomDirectionsGiveValidBarycentrics),
        cmocka_unit_test(lookupAtSampleGivesWeightOneOnIt),
        cmocka_unit_test(lookupAtOctahedronVerticesIsExact),
        cmocka_unit_test(lookupOnEdgeMidpointGivesZeroOppositeWeight),
        cmocka_unit_test(lookupAtPolesGivesValidWeights),
        cmocka_unit_test(lookupIsContinuousAcrossEdges),
        cmocka_unit_test(lookupOfZeroOrNaNDirectionReturnsMinusOne),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
