/* dirset.c: the baked light directions ω_j, their spherical Delaunay
 * triangulation and barycentric interpolation weights.
 *
 * Direction set: Hao–Varshney 2004 §3.2 bakes the scattering integrals for a
 * fixed set of ~200 light directions and, at run time, blends the 4 samples
 * nearest to the actual light direction. That blend is discontinuous: the
 * weights jump whenever the set of 4 nearest samples changes, which shows as
 * popping while a light moves. We instead interpolate barycentrically inside
 * the spherical Delaunay triangle that contains the direction (docs/physics.md
 * §7): the weights are continuous on the whole sphere (neighbouring triangles
 * agree on their shared edge, where the opposite weight is 0) and exact at
 * the samples (d = ω_i gives weight 1 on i).
 *
 * Triangulation: for points on the unit sphere the convex hull is the
 * spherical Delaunay triangulation (a hull facet's plane cuts the sphere in
 * the facet's circumcircle, and "no point above the facet's plane" is "no
 * point inside its circumcircle"). We build the hull incrementally with a
 * conflict list per facet, inserting the points in a fixed pseudo-random
 * order (expected O(n log n)). Visibility uses an exact orientation predicate
 * (floating-point filter, exact expansion arithmetic when the filter cannot
 * decide), so the combinatorics are consistent for cocircular input such as
 * the octahedron's 6 axis directions; a point exactly on a facet's plane
 * counts as not seeing it, which triangulates cocircular groups consistently.
 */
#include "sss/dirset.h"
#include "sss/random.h"
#include "sss/vec3.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define DIRSET_MAX_N (1u << 20)
#define DIRSET_PI 3.14159265358979323846

/* ------------------------------------------------------------------------ */
/* Exact orientation predicate                                              */
/* ------------------------------------------------------------------------ */

/* x + y = a * b exactly (fma is correctly rounded by C11). */
static void two_prod(double a, double b, double *x, double *y)
{
    *x = a * b;
    *y = fma(a, b, -*x);
}

/* x + y = a + b exactly (Knuth's TwoSum; no multiplications, so no
 * contraction can change it). */
static void two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    double bv = s - a;
    double av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* Shewchuk's Grow-Expansion with zero elimination, in place: h is a
 * nonoverlapping expansion in increasing magnitude order; adds b. */
static void grow(double *h, int *hlen, double b)
{
    double q = b;
    int k = 0;
    for (int i = 0; i < *hlen; i++) {
        double s, e;
        two_sum(q, h[i], &s, &e);
        q = s;
        if (e != 0.0) h[k++] = e;
    }
    if (q != 0.0 || k == 0) h[k++] = q;
    *hlen = k;
}

/* h += sign * x * y * z exactly (4 components). */
static void add_triple(double *h, int *hlen, double sign, double x, double y, double z)
{
    double p, e, p1, e1, p2, e2;
    two_prod(x, y, &p, &e);
    two_prod(p, z, &p1, &e1);
    two_prod(e, z, &p2, &e2);
    grow(h, hlen, sign * e2);
    grow(h, hlen, sign * p2);
    grow(h, hlen, sign * e1);
    grow(h, hlen, sign * p1);
}

/* h += sign * x · (y × z) exactly. */
static void add_det(double *h, int *hlen, double sign, const double *x, const double *y, const double *z)
{
    add_triple(h, hlen, sign, x[0], y[1], z[2]);
    add_triple(h, hlen, -sign, x[0], y[2], z[1]);
    add_triple(h, hlen, sign, x[1], y[2], z[0]);
    add_triple(h, hlen, -sign, x[1], y[0], z[2]);
    add_triple(h, hlen, sign, x[2], y[0], z[1]);
    add_triple(h, hlen, -sign, x[2], y[1], z[0]);
}

/* Sign (−1, 0, +1) of (b−a)×(c−a)·(p−a), computed exactly:
 * = det(b,c,p) + det(a,b,p) + det(c,a,p) − det(a,b,c). */
static double orient_exact(const double *a, const double *b, const double *c, const double *p)
{
    double h[4 * 24 + 8];
    int n = 0;
    add_det(h, &n, 1.0, b, c, p);
    add_det(h, &n, 1.0, a, b, p);
    add_det(h, &n, 1.0, c, a, p);
    add_det(h, &n, -1.0, a, b, c);
    double top = h[n - 1]; /* largest component carries the sign */
    return top > 0.0 ? 1.0 : (top < 0.0 ? -1.0 : 0.0);
}

/* (b−a)×(c−a)·(p−a) with the correct sign: positive when p lies on the side
 * from which a, b, c appear counter-clockwise ("above" the oriented facet).
 * Filter after Shewchuk's orient3d (error bound 4·DBL_EPSILON·permanent,
 * slightly above his (7+56ε)ε with ε = 2⁻⁵³); exact otherwise. */
static double orient(const double *a, const double *b, const double *c, const double *p)
{
    double adx = a[0] - p[0], ady = a[1] - p[1], adz = a[2] - p[2];
    double bdx = b[0] - p[0], bdy = b[1] - p[1], bdz = b[2] - p[2];
    double cdx = c[0] - p[0], cdy = c[1] - p[1], cdz = c[2] - p[2];
    double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
    double cdxady = cdx * ady, adxcdy = adx * cdy;
    double adxbdy = adx * bdy, bdxady = bdx * ady;
    double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
    double perm = (fabs(bdxcdy) + fabs(cdxbdy)) * fabs(adz) + (fabs(cdxady) + fabs(adxcdy)) * fabs(bdz) +
                  (fabs(adxbdy) + fabs(bdxady)) * fabs(cdz);
    /* det here is det[a−p; b−p; c−p] = −(b−a)×(c−a)·(p−a). */
    if (fabs(det) > 4.0 * DBL_EPSILON * perm) return -det;
    return orient_exact(a, b, c, p);
}

/* ------------------------------------------------------------------------ */
/* Incremental convex hull with conflict lists                             */
/* ------------------------------------------------------------------------ */

typedef struct hull {
    const double *p; /* 3n normalised directions */
    uint32_t n;
    uint32_t cap;     /* face slots */
    uint32_t nslot;   /* slots ever used */
    int32_t freelist; /* dead slots, chained through head[] */
    uint32_t *fv;     /* 3 per face: vertices, counter-clockwise from outside */
    int32_t *adj;     /* 3 per face: adj[3f+k] is across edge fv[3f+k] → fv[3f+(k+1)%3] */
    int32_t *head;    /* per face: first conflict point, −1 if none */
    uint32_t *stamp;  /* per face: insertion step at which visibility was tested */
    unsigned char *alive, *vis;
    int32_t *conf;   /* per point: a face it sees, −1 if none */
    int32_t *next;   /* per point: next point in the same conflict list */
    uint32_t *vstamp;   /* per point: step at which it started a horizon edge */
    int32_t *startface; /* per point: new face whose horizon edge starts there */
    int32_t *stack, *visible, *newf; /* work lists, ≤ cap each */
} hull;

static void hull_free(hull *h)
{
    free(h->fv);
    free(h->adj);
    free(h->head);
    free(h->stamp);
    free(h->alive);
    free(h->vis);
    free(h->conf);
    free(h->next);
    free(h->vstamp);
    free(h->startface);
    free(h->stack);
    free(h->visible);
    free(h->newf);
}

static int32_t face_new(hull *h, uint32_t a, uint32_t b, uint32_t c)
{
    int32_t f;
    if (h->freelist >= 0) {
        f = h->freelist;
        h->freelist = h->head[f];
    } else {
        if (h->nslot >= h->cap) return -1;
        f = (int32_t)h->nslot++;
    }
    h->fv[3 * (size_t)f] = a;
    h->fv[3 * (size_t)f + 1] = b;
    h->fv[3 * (size_t)f + 2] = c;
    h->adj[3 * (size_t)f] = h->adj[3 * (size_t)f + 1] = h->adj[3 * (size_t)f + 2] = -1;
    h->head[f] = -1;
    h->stamp[f] = 0;
    h->alive[f] = 1;
    h->vis[f] = 0;
    return f;
}

static double face_orient(const hull *h, int32_t f, uint32_t q)
{
    const uint32_t *v = h->fv + 3 * (size_t)f;
    return orient(h->p + 3 * (size_t)v[0], h->p + 3 * (size_t)v[1], h->p + 3 * (size_t)v[2], h->p + 3 * (size_t)q);
}

static void conflict_push(hull *h, int32_t f, uint32_t q)
{
    h->conf[q] = f;
    h->next[q] = h->head[f];
    h->head[f] = (int32_t)q;
}


static int cmp_tri(const void *x, const void *y)
{
    const uint32_t *a = x, *b = y;
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

static sss_result hull_build(hull *h, uint32_t **tri_out, sss_error *err)
{
    const uint32_t n = h->n;
    const double *P = h->p;
    size_t cap = 3 * (size_t)n + 16; /* live faces + one insertion's new faces ≤ 3n */
    h->cap = (uint32_t)cap;
    h->freelist = -1;
    h->fv = malloc(3 * cap * sizeof *h->fv);
    h->adj = malloc(3 * cap * sizeof *h->adj);
    h->head = malloc(cap * sizeof *h->head);
    h->stamp = malloc(cap * sizeof *h->stamp);
    h->alive = malloc(cap);
    h->vis = malloc(cap);
    h->conf = malloc(n * sizeof *h->conf);
    h->next = malloc(n * sizeof *h->next);
    h->vstamp = calloc(n, sizeof *h->vstamp);
    h->startface = malloc(n * sizeof *h->startface);
    h->stack = malloc(cap * sizeof *h->stack);
    h->visible = malloc(cap * sizeof *h->visible);
    h->newf = malloc(cap * sizeof *h->newf);
    uint32_t *order = malloc(n * sizeof *order);
    if (!h->fv || !h->adj || !h->head || !h->stamp || !h->alive || !h->vis || !h->conf || !h->next || !h->vstamp ||
        !h->startface || !h->stack || !h->visible || !h->newf || !order) {
        free(order);
        return sss_fail(err, SSS_ERR_NOMEM, "out of memory triangulating %u directions", n);
    }

    /* Initial tetrahedron: 0, the direction farthest from it, the one
     * farthest from their line, the one farthest from their plane. */
    uint32_t i0 = 0, i1 = 0, i2 = 0, i3 = 0;
    double best = INFINITY;
    for (uint32_t i = 1; i < n; i++) {
        double d = P[0] * P[3 * (size_t)i] + P[1] * P[3 * (size_t)i + 1] + P[2] * P[3 * (size_t)i + 2];
        if (d < best) best = d, i1 = i;
    }
    best = 0.0;
    const double *a = P, *b = P + 3 * (size_t)i1;
    for (uint32_t i = 1; i < n; i++) {
        const double *c = P + 3 * (size_t)i;
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
        double q = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
        if (q > best) best = q, i2 = i;
    }
    if (best == 0.0) {
        free(order);
        return sss_fail(err, SSS_ERR_ARG, "%u directions are collinear (degenerate direction set)", n);
    }
    best = 0.0;
    for (uint32_t i = 1; i < n; i++) {
        double o = fabs(orient(P, P + 3 * (size_t)i1, P + 3 * (size_t)i2, P + 3 * (size_t)i));
        if (o > best) best = o, i3 = i;
    }
    if (best == 0.0) {
        free(order);
        return sss_fail(err, SSS_ERR_ARG, "%u directions are coplanar (degenerate direction set)", n);
    }
    if (orient(P, P + 3 * (size_t)i1, P + 3 * (size_t)i2, P + 3 * (size_t)i3) > 0.0) {
        uint32_t t = i1;
        i1 = i2;
        i2 = t;
    }
    /* Now i3 is below (i0,i1,i2): faces (i0,i1,i2), (i0,i3,i1), (i1,i3,i2), (i2,i3,i0). */
    int32_t f4[4];
    f4[0] = face_new(h, i0, i1, i2);
    f4[1] = face_new(h, i0, i3, i1);
    f4[2] = face_new(h, i1, i3, i2);
    f4[3] = face_new(h, i2, i3, i0);
    for (int f = 0; f < 4; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t u = h->fv[3 * f + k], v = h->fv[3 * f + (k + 1) % 3];
            for (int g = 0; g < 4; g++)
                for (int j = 0; j < 3; j++)
                    if (h->fv[3 * g + j] == v && h->fv[3 * g + (j + 1) % 3] == u) h->adj[3 * f + k] = f4[g];
        }

    /* Insertion order: all other points, shuffled with a fixed seed. */
    uint32_t m = 0;
    for (uint32_t i = 0; i < n; i++)
        if (i != i0 && i != i1 && i != i2 && i != i3) order[m++] = i;
    uint64_t seed = 0x5353535F44495253ull; /* "SSS_DIRS" */
    for (uint32_t i = m; i > 1; i--) {
        uint32_t j = (uint32_t)(sss_rng_next(&seed) % i);
        uint32_t t = order[i - 1];
        order[i - 1] = order[j];
        order[j] = t;
    }
    for (uint32_t i = 0; i < n; i++) h->conf[i] = -1, h->next[i] = -1;
    /* Conflict lists are pushed in reverse so that they end up in order. */
    for (uint32_t r = m; r-- > 0;) {
        uint32_t q = order[r];
        for (int f = 0; f < 4; f++)
            if (face_orient(h, f4[f], q) > 0.0) {
                conflict_push(h, f4[f], q);
                break;
            }
    }

    sss_result rc = SSS_OK;
    for (uint32_t r = 0; r < m; r++) {
        uint32_t p = order[r];
        uint32_t step = r + 1;
        int32_t f0 = h->conf[p];
        if (f0 < 0) {
            rc = sss_fail(err, SSS_ERR_ARG,
                          "direction %u is not outside the convex hull of the others "
                          "(duplicate or nearly duplicate direction)",
                          p);
            break;
        }
        /* Visible faces: flood fill from f0 (the visible region is a disk). */
        uint32_t nvis = 0, nst = 0;
        h->stamp[f0] = step;
        h->vis[f0] = 1;
        h->visible[nvis++] = f0;
        h->stack[nst++] = f0;
        while (nst > 0) {
            int32_t f = h->stack[--nst];
            for (int k = 0; k < 3; k++) {
                int32_t g = h->adj[3 * (size_t)f + k];
                if (h->stamp[g] == step) continue;
                h->stamp[g] = step;
                h->vis[g] = face_orient(h, g, p) > 0.0;
                if (h->vis[g]) h->visible[nvis++] = g, h->stack[nst++] = g;
            }
        }
        /* One new face (u, v, p) per horizon edge u → v. */
        uint32_t nnew = 0;
        for (uint32_t i = 0; i < nvis && rc == SSS_OK; i++) {
            int32_t f = h->visible[i];
            for (int k = 0; k < 3; k++) {
                int32_t g = h->adj[3 * (size_t)f + k];
                if (h->vis[g]) continue;
                uint32_t u = h->fv[3 * (size_t)f + k], v = h->fv[3 * (size_t)f + (k + 1) % 3];
                int32_t nf = face_new(h, u, v, p);
                if (nf < 0 || h->vstamp[u] == step) {
                    rc = sss_fail(err, SSS_ERR_ARG, "direction %u: inconsistent hull horizon (degenerate direction set)",
                                  p);
                    break;
                }
                h->vstamp[u] = step;
                h->startface[u] = nf;
                h->adj[3 * (size_t)nf] = g;
                for (int j = 0; j < 3; j++)
                    if (h->adj[3 * (size_t)g + j] == f && h->fv[3 * (size_t)g + j] == v) h->adj[3 * (size_t)g + j] = nf;
                h->newf[nnew++] = nf;
            }
        }
        if (rc != SSS_OK) break;
        for (uint32_t i = 0; i < nnew; i++) {
            int32_t nf = h->newf[i];
            uint32_t v = h->fv[3 * (size_t)nf + 1];
            if (h->vstamp[v] != step) {
                rc = sss_fail(err, SSS_ERR_ARG, "direction %u: open hull horizon (degenerate direction set)", p);
                break;
            }
            int32_t mf = h->startface[v];
            h->adj[3 * (size_t)nf + 1] = mf;
            h->adj[3 * (size_t)mf + 2] = nf;
        }
        if (rc != SSS_OK) break;
        /* Hand the conflict points of the deleted faces to the new faces. A
         * point that saw a deleted face and is still outside sees a new one. */
        for (uint32_t i = 0; i < nvis; i++) {
            int32_t f = h->visible[i];
            int32_t q = h->head[f];
            while (q >= 0) {
                int32_t qn = h->next[q];
                h->conf[q] = -1;
                if ((uint32_t)q != p)
                    for (uint32_t j = 0; j < nnew; j++)
                        if (face_orient(h, h->newf[j], (uint32_t)q) > 0.0) {
                            conflict_push(h, h->newf[j], (uint32_t)q);
                            break;
                        }
                q = qn;
            }
            h->alive[f] = 0;
            h->head[f] = h->freelist;
            h->freelist = f;
        }
    }
    free(order);
    if (rc != SSS_OK) return rc;

    uint32_t ntri = 2 * n - 4, cnt = 0;
    uint32_t *tri = malloc(3 * (size_t)ntri * sizeof *tri);
    if (!tri) return sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u triangles", ntri);
    for (uint32_t f = 0; f < h->nslot; f++) {
        if (!h->alive[f]) continue;
        if (cnt == ntri) {
            cnt++;
            break;
        }
        const uint32_t *v = h->fv + 3 * (size_t)f;
        /* Rotate so the smallest index comes first (orientation kept). */
        int s = (v[1] < v[0] && v[1] < v[2]) ? 1 : (v[2] < v[0] && v[2] < v[1]) ? 2 : 0;
        for (int k = 0; k < 3; k++) tri[3 * (size_t)cnt + k] = v[(s + k) % 3];
        cnt++;
    }
    if (cnt != ntri) {
        free(tri);
        return sss_fail(err, SSS_ERR_ARG, "hull of %u directions has %u triangles, expected %u (degenerate direction set)",
                        n, cnt, ntri);
    }
    qsort(tri, ntri, 3 * sizeof *tri, cmp_tri);
    static const double origin[3] = {0.0, 0.0, 0.0};
    for (uint32_t t = 0; t < ntri; t++) {
        const uint32_t *v = tri + 3 * (size_t)t;
        /* det(a,b,c) > 0 ⇔ the origin is strictly below the facet. */
        if (!(orient(P + 3 * (size_t)v[0], P + 3 * (size_t)v[1], P + 3 * (size_t)v[2], origin) < 0.0)) {
            uint32_t a0 = v[0], a1 = v[1], a2 = v[2];
            free(tri);
            return sss_fail(err, SSS_ERR_ARG,
                            "directions do not surround the origin: triangle (%u, %u, %u) has det <= 0 "
                            "(all directions within one closed hemisphere?)",
                            a0, a1, a2);
        }
    }
    *tri_out = tri;
    return SSS_OK;
}

sss_result sss_dirset_triangulate(sss_dirset *s, sss_error *err)
{
    if (!s) return sss_fail(err, SSS_ERR_ARG, "dirset is NULL");
    free(s->tri);
    s->tri = NULL;
    s->ntri = 0;
    const uint32_t n = s->n;
    if (n > 0 && !s->dir) return sss_fail(err, SSS_ERR_ARG, "dirset has %u directions but no direction array", n);
    for (uint32_t i = 0; i < n; i++) {
        const double *d = s->dir + 3 * (size_t)i;
        if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
            return sss_fail(err, SSS_ERR_ARG, "direction %u (%g, %g, %g) is not finite", i, d[0], d[1], d[2]);
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(fabs(len - 1.0) <= 1e-6))
            return sss_fail(err, SSS_ERR_ARG, "direction %u (%g, %g, %g) has length %.9g, not within 1e-6 of 1", i,
                            d[0], d[1], d[2], len);
    }
    if (n < 4) return SSS_OK;

    /* Hull of the normalised directions, so every point is on the sphere to
     * rounding (an input off by 1e-6 could otherwise fall inside the hull of
     * its neighbours at large n). */
    double *p = malloc(3 * (size_t)n * sizeof *p);
    if (!p) return sss_fail(err, SSS_ERR_NOMEM, "out of memory triangulating %u directions", n);
    for (uint32_t i = 0; i < n; i++) {
        const double *d = s->dir + 3 * (size_t)i;
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        for (int k = 0; k < 3; k++) p[3 * (size_t)i + k] = d[k] / len;
    }
    hull h;
    memset(&h, 0, sizeof h);
    h.p = p;
    h.n = n;
    uint32_t *tri = NULL;
    sss_result rc = hull_build(&h, &tri, err);
    hull_free(&h);
    free(p);
    if (rc != SSS_OK) return rc;
    s->tri = tri;
    s->ntri = 2 * n - 4;
    return SSS_OK;
}

sss_result sss_dirset_fibonacci(sss_dirset *s, uint32_t n, sss_error *err)
{
    if (!s) return sss_fail(err, SSS_ERR_ARG, "dirset is NULL");
    memset(s, 0, sizeof *s);
    if (n < 1 || n > DIRSET_MAX_N)
        return sss_fail(err, SSS_ERR_ARG, "direction count %u outside [1, %u]", n, DIRSET_MAX_N);
    s->dir = malloc(3 * (size_t)n * sizeof *s->dir);
    if (!s->dir) return sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u directions", n);
    s->n = n;
    /* Hao–Varshney 2004 §3.2 only needs the directions to cover the sphere
     * evenly; the spherical Fibonacci set does that with equal-area bands. */
    const double golden = (1.0 + sqrt(5.0)) / 2.0;
    for (uint32_t i = 0; i < n; i++) {
        double z = 1.0 - 2.0 * (i + 0.5) / n;
        double phi = 2.0 * DIRSET_PI * i / golden;
        double r = sqrt(1.0 - z * z);
        s->dir[3 * (size_t)i] = r * cos(phi);
        s->dir[3 * (size_t)i + 1] = r * sin(phi);
        s->dir[3 * (size_t)i + 2] = z;
    }
    sss_result rc = sss_dirset_triangulate(s, err);
    if (rc != SSS_OK) sss_dirset_free(s);
    return rc;
}

/* ------------------------------------------------------------------------ */
/* Lookup                                                                   */
/* ------------------------------------------------------------------------ */


/* det(x, y, z) = x · (y × z). */
static double det3(const double *x, const double *y, const double *z)
{
    return x[0] * (y[1] * z[2] - y[2] * z[1]) + x[1] * (y[2] * z[0] - y[0] * z[2]) + x[2] * (y[0] * z[1] - y[1] * z[0]);
}

/* Barycentrics of d in triangle t, normalised to sum 1 (docs/physics.md §7):
 * λ_a = det(d, v_b, v_c) / det(v_a, v_b, v_c) cyclically. The common
 * denominator cancels in the normalisation (as does the length of d), so mu
 * = (det(d,b,c), det(d,c,a), det(d,a,b)) / their sum. Returns min(mu), or
 * −∞ when d points away from the triangle (sum ≤ 0). */
static double bary(const sss_dirset *s, uint32_t t, const double *d, double mu[3])
{
    const uint32_t *v = s->tri + 3 * (size_t)t;
    const double *a = s->dir + 3 * (size_t)v[0], *b = s->dir + 3 * (size_t)v[1], *c = s->dir + 3 * (size_t)v[2];
    double la = det3(d, b, c), lb = det3(d, c, a), lc = det3(d, a, b);
    double sum = la + lb + lc;
    if (!(sum > 0.0)) return -INFINITY;
    double inv = 1.0 / sum;
    mu[0] = la * inv;
    mu[1] = lb * inv;
    mu[2] = lc * inv;
    return fmin(mu[0], fmin(mu[1], mu[2]));
}

/* Barycentrics this far below 0 are rounding of a point on an edge or at a
 * vertex (exactness at the samples: d = ω_i gives mu ≈ (1, ±1e−17, ±1e−17)).
 * Clamping them moves the weights by no more than this. */
#define LOOKUP_TOL (64.0 * DBL_EPSILON)

/* Triangle across the edge v[k] → v[k+1] of triangle t (−1 if none). */
static int32_t across(const sss_dirset *s, uint32_t t, int k)
{
    uint32_t u = s->tri[3 * (size_t)t + k], v = s->tri[3 * (size_t)t + (k + 1) % 3];
    for (uint32_t g = 0; g < s->ntri; g++) {
        const uint32_t *w = s->tri + 3 * (size_t)g;
        if ((w[0] == v && w[1] == u) || (w[1] == v && w[2] == u) || (w[2] == v && w[0] == u)) return (int32_t)g;
    }
    return -1;
}

int32_t sss_dirset_lookup(const sss_dirset *s, const double d[3], uint32_t idx[3], double w[3])
{
    idx[0] = idx[1] = idx[2] = 0;
    w[0] = w[1] = w[2] = 0.0;
    if (!s || s->n == 0 || !s->dir) return -1;
    w[0] = 1.0;
    if (!d) return -1;
    /* Normalised, which keeps the determinants away from overflow and
     * underflow; the weights themselves do not depend on the length of d. */
    double mx = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2])));
    if (!(mx > 0.0) || !isfinite(mx) || isnan(d[0]) || isnan(d[1]) || isnan(d[2])) return -1;
    double dn[3] = {d[0] / mx, d[1] / mx, d[2] / mx};
    double len = sqrt(sss_dot3(dn, dn));
    for (int k = 0; k < 3; k++) dn[k] /= len;
    d = dn;

    /* Nearest sample (two interleaved scans for instruction-level
     * parallelism; ties go to the lower index). */
    uint32_t near = 0, near1 = 1;
    double bestdot = -INFINITY, bestdot1 = -INFINITY;
    const double *dir = s->dir;
    uint32_t i = 0;
    for (; i + 1 < s->n; i += 2) {
        double t0 = sss_dot3(d, dir + 3 * (size_t)i), t1 = sss_dot3(d, dir + 3 * (size_t)i + 3);
        if (t0 > bestdot) bestdot = t0, near = i;
        if (t1 > bestdot1) bestdot1 = t1, near1 = i + 1;
    }
    if (i < s->n) {
        double t0 = sss_dot3(d, dir + 3 * (size_t)i);
        if (t0 > bestdot) bestdot = t0, near = i;
    }
    if (bestdot1 > bestdot || (bestdot1 == bestdot && near1 < near)) near = near1;
    idx[0] = idx[1] = idx[2] = near;
    if (s->ntri == 0 || !s->tri) return -1;

    /* 1. Triangles around the nearest sample: usually one contains d (for
     * 200 Fibonacci directions, all but ~1.5e−4 of random directions).
     * sss_dirset_triangulate stores the smallest index first and sorts the
     * triangles, so those incident to `near` all lie before the first
     * triangle whose first index exceeds it; scanning that prefix backwards
     * finds them first when nearby directions have nearby indices (as in
     * the Fibonacci set). (If tri was ordered otherwise this scan may miss;
     * the walk and full scan below still find a triangle.) */
    uint32_t lo = 0, hi = s->ntri;
    while (lo < hi) {
        uint32_t mid = lo + (hi - lo) / 2;
        if (s->tri[3 * (size_t)mid] <= near) lo = mid + 1;
        else hi = mid;
    }
    int32_t bt = -1;
    double bmin = -INFINITY, bmu[3] = {1.0, 0.0, 0.0}, mu[3] = {1.0, 0.0, 0.0};
    for (uint32_t t = lo; t-- > 0;) {
        const uint32_t *v = s->tri + 3 * (size_t)t;
        if (v[0] != near && v[1] != near && v[2] != near) continue;
        double mn = bary(s, t, d, mu);
        if (mn > bmin || bt < 0) {
            bt = (int32_t)t, bmin = mn;
            memcpy(bmu, mu, sizeof mu);
            if (mn >= 0.0) break;
        }
    }
    /* 2. Otherwise walk across the edge d lies beyond (visibility walk; it
     * terminates on a Delaunay triangulation; bounded here regardless). */
    int32_t cur = bt;
    double cmu[3];
    memcpy(cmu, bmu, sizeof cmu);
    double cmin = bmin;
    for (int steps = 0; steps < 64 && bmin < -LOOKUP_TOL && cur >= 0 && cmin > -INFINITY; steps++) {
        int k = cmu[0] <= cmu[1] && cmu[0] <= cmu[2] ? 0 : (cmu[1] <= cmu[2] ? 1 : 2);
        /* mu_k < 0: d is beyond the edge opposite vertex k, v[k+1] → v[k+2]. */
        cur = across(s, (uint32_t)cur, (k + 1) % 3);
        if (cur < 0) break;
        cmin = bary(s, (uint32_t)cur, d, cmu);
        if (cmin > bmin) {
            bt = cur, bmin = cmin;
            memcpy(bmu, cmu, sizeof cmu);
        }
    }
    /* 3. Fallback: every triangle; keep the one whose smallest barycentric
     * is largest, so a direction on an edge or vertex always gets one. */
    if (bmin < -LOOKUP_TOL) {
        for (uint32_t t = 0; t < s->ntri; t++) {
            double mn = bary(s, t, d, mu);
            if (mn > bmin) {
                bt = (int32_t)t, bmin = mn;
                memcpy(bmu, mu, sizeof mu);
                if (mn >= 0.0) break;
            }
        }
    }
    if (bt < 0 || bmin == -INFINITY) return -1; /* no usable triangle */

    double sum = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!(bmu[k] > 0.0)) bmu[k] = 0.0;
        sum += bmu[k];
    }
    for (int k = 0; k < 3; k++) {
        idx[k] = s->tri[3 * (size_t)bt + k];
        w[k] = bmu[k] / sum;
    }
    /* Snap rounding dust: a weight below 1e-12 is a direction on the
     * opposite edge or at a sample; zeroing it makes the interpolation
     * reproduce stored values bit for bit at the samples. */
    sum = 0.0;
    for (int k = 0; k < 3; k++) {
        if (w[k] < 1e-12) w[k] = 0.0;
        sum += w[k];
    }
    for (int k = 0; k < 3; k++) w[k] /= sum;
    return bt;
}

void sss_dirset_round_f32(sss_dirset *s)
{
    if (!s || !s->dir) return;
    for (size_t k = 0; k < 3 * (size_t)s->n; k++) s->dir[k] = (double)(float)s->dir[k];
}

void sss_dirset_free(sss_dirset *s)
{
    if (!s) return;
    free(s->dir);
    free(s->tri);
    memset(s, 0, sizeof *s);
}

int sss_dirset_nearest4(const sss_dirset *s, const double d[3], uint32_t idx[4], double w[4])
{
    for (int k = 0; k < 4; k++) idx[k] = 0, w[k] = 0.0;
    w[0] = 1.0;
    if (!s || s->n == 0 || !s->dir || !d) return 0;
    double mx = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2])));
    if (!(mx > 0.0) || !isfinite(mx) || isnan(d[0]) || isnan(d[1]) || isnan(d[2])) return 0;
    double dn[3] = {d[0] / mx, d[1] / mx, d[2] / mx};
    double len = sqrt(sss_dot3(dn, dn));
    for (int k = 0; k < 3; k++) dn[k] /= len;
    /* the four largest cosines, kept sorted (ties to the lower index) */
    double best[4] = {-INFINITY, -INFINITY, -INFINITY, -INFINITY};
    const int m = s->n < 4 ? (int)s->n : 4;
    for (uint32_t j = 0; j < s->n; j++) {
        double c = sss_dot3(dn, s->dir + 3 * (size_t)j);
        if (!(c > best[m - 1])) continue;
        int k = m - 1;
        while (k > 0 && c > best[k - 1]) {
            best[k] = best[k - 1];
            idx[k] = idx[k - 1];
            k--;
        }
        best[k] = c;
        idx[k] = j;
    }
    /* θ from the chord length (accurate near 0, where acos is not) */
    double inv[4], sum = 0.0;
    for (int k = 0; k < m; k++) {
        const double *v = s->dir + 3 * (size_t)idx[k];
        double e[3] = {dn[0] - v[0], dn[1] - v[1], dn[2] - v[2]};
        double theta = 2.0 * asin(fmin(1.0, 0.5 * sqrt(sss_dot3(e, e))));
        if (theta < 1e-9) {
            for (int t = 0; t < 4; t++) w[t] = 0.0;
            w[0] = 1.0;
            idx[0] = idx[k];
            for (int t = 1; t < 4; t++) idx[t] = idx[0];
            return 1;
        }
        inv[k] = 1.0 / theta;
        sum += inv[k];
    }
    for (int k = 0; k < 4; k++) w[k] = k < m ? inv[k] / sum : 0.0;
    for (int k = m; k < 4; k++) idx[k] = idx[0];
    return m;
}
