/* test_refs.c: reference points and barycentric weights (Hao–Varshney 2004
 * §4.2): selection by decimation, projection onto the simplified mesh,
 * degenerate and non-manifold input, and illumination-aware selection
 * (beyond the paper, its §6). */
#define _DEFAULT_SOURCE /* mkstemps, access, unlink */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>
#include <unistd.h>

#include "genmesh.h"
#include "sss/import.h"
#include "sss/refs.h"
#include "test_util.h"

/* ---- helpers ------------------------------------------------------------ */

/* |a − b| ≤ eps (cmocka 1.1.5 has no assert_close). */
#define assert_close(a, b, eps)                                                                                    \
    do {                                                                                                           \
        double a_ = (a), b_ = (b);                                                                                 \
        if (!(fabs(a_ - b_) <= (eps))) fail_msg("%s = %.17g, expected %.17g (within %g)", #a, a_, b_, (double)(eps)); \
    } while (0)

static void P(const sss_mesh *m, uint32_t v, double p[3])
{
    for (int k = 0; k < 3; k++) p[k] = m->pos[3 * (size_t)v + k];
}

static double dist3(const double *a, const double *b)
{
    return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
}

/* Σ_k w_k p(ref_k) for vertex v. */
static void reconstruct(const sss_mesh *m, const sss_refs *r, uint32_t v, double q[3])
{
    q[0] = q[1] = q[2] = 0.0;
    for (int k = 0; k < 3; k++) {
        double p[3];
        P(m, r->ref_vertex[r->ref_tri[3 * (size_t)r->vtri[v] + k]], p);
        for (int j = 0; j < 3; j++) q[j] += r->w[3 * (size_t)v + k] * p[j];
    }
}

static double mean_edge(const sss_mesh *m)
{
    double s = 0.0;
    for (uint32_t f = 0; f < m->nf; f++)
        for (int k = 0; k < 3; k++) {
            double a[3], b[3];
            P(m, m->tri[3 * (size_t)f + k], a);
            P(m, m->tri[3 * (size_t)f + (k + 1) % 3], b);
            s += dist3(a, b);
        }
    return s / (3.0 * m->nf);
}

/* Every structural promise of sss_refs: indices in range, references strictly
 * increasing, weights finite, ≥ 0 and summing to 1, references on themselves
 * with weight exactly 1. Returns the largest distance between a vertex and
 * its reconstruction Σ w_k p(ref_k), over vertices other than `skip`
 * (UINT32_MAX: none). */
static double check_refs(const sss_mesh *m, const sss_refs *r, uint32_t skip)
{
    assert_int_equal(r->nv, m->nv);
    assert_true(r->nref >= 1 && r->nref <= m->nv);
    assert_true(r->nrt >= 1);
    assert_non_null(r->ref_vertex);
    assert_non_null(r->ref_tri);
    assert_non_null(r->vtri);
    assert_non_null(r->w);
    uint32_t *ref_of = malloc(m->nv * sizeof *ref_of);
    assert_non_null(ref_of);
    for (uint32_t v = 0; v < m->nv; v++) ref_of[v] = UINT32_MAX;
    for (uint32_t i = 0; i < r->nref; i++) {
        assert_true(r->ref_vertex[i] < m->nv);
        if (i > 0 && !(r->ref_vertex[i] > r->ref_vertex[i - 1]))
            fail_msg("ref_vertex not increasing at %u: %u after %u", i, r->ref_vertex[i], r->ref_vertex[i - 1]);
        ref_of[r->ref_vertex[i]] = i;
    }
    for (size_t k = 0; k < 3 * (size_t)r->nrt; k++) assert_true(r->ref_tri[k] < r->nref);

    double worst = 0.0;
    for (uint32_t v = 0; v < m->nv; v++) {
        assert_true(r->vtri[v] < r->nrt);
        const float *w = r->w + 3 * (size_t)v;
        double s = 0.0;
        for (int k = 0; k < 3; k++) {
            if (!isfinite(w[k]) || w[k] < 0.0f) fail_msg("vertex %u: weight %d = %g", v, k, (double)w[k]);
            s += w[k];
        }
        if (!(fabs(s - 1.0) <= 1e-6)) fail_msg("vertex %u: weights sum to %.9g", v, s);
        if (ref_of[v] != UINT32_MAX) {
            /* a reference: weight exactly 1 on its own corner */
            const uint32_t *t = r->ref_tri + 3 * (size_t)r->vtri[v];
            int own = -1;
            for (int k = 0; k < 3; k++)
                if (t[k] == ref_of[v]) own = k;
            if (own < 0) fail_msg("reference vertex %u mapped to triangle %u, which does not use it", v, r->vtri[v]);
            for (int k = 0; k < 3; k++) assert_true(w[k] == (k == own ? 1.0f : 0.0f));
        }
        if (v == skip) continue;
        double p[3], q[3];
        P(m, v, p);
        reconstruct(m, r, v, q);
        if (ref_of[v] != UINT32_MAX) assert_true(dist3(p, q) == 0.0);
        worst = fmax(worst, dist3(p, q));
    }
    free(ref_of);
    return worst;
}

static int same_refs(const sss_refs *a, const sss_refs *b)
{
    return a->nv == b->nv && a->nref == b->nref && a->nrt == b->nrt && a->faces_skipped == b->faces_skipped &&
           a->vertices_split == b->vertices_split &&
           !memcmp(a->ref_vertex, b->ref_vertex, a->nref * sizeof *a->ref_vertex) &&
           !memcmp(a->ref_tri, b->ref_tri, 3 * (size_t)a->nrt * sizeof *a->ref_tri) &&
           !memcmp(a->vtri, b->vtri, a->nv * sizeof *a->vtri) && !memcmp(a->w, b->w, 3 * (size_t)a->nv * sizeof *a->w);
}

static void check_weights(const double w[3])
{
    double s = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(w[k]) || w[k] < 0.0) fail_msg("weight %d = %g", k, w[k]);
        s += w[k];
    }
    assert_close(s, 1.0, 1e-12);
}

/* ---- selection and mapping ---------------------------------------------- */

static void buildWithFractionOneIsIdentity(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 2, &err), SSS_OK);
    sss_refs r;
    assert_int_equal(sss_refs_build(&m, 1.0, 0, &r, &err), SSS_OK);
    assert_int_equal(r.nref, m.nv);
    assert_int_equal(r.nrt, m.nf);
    assert_int_equal(r.faces_skipped, 0);
    for (uint32_t i = 0; i < r.nref; i++) assert_int_equal(r.ref_vertex[i], i);
    assert_memory_equal(r.ref_tri, m.tri, 3 * (size_t)m.nf * sizeof *m.tri);
    assert_true(check_refs(&m, &r, UINT32_MAX) == 0.0);
    sss_refs_free(&r);
    assert_null(r.w);
    sss_mesh_free(&m);
}

static void buildKeepsFivePercentOfSphereAndReconstructsPositions(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 5, &err), SSS_OK);
    assert_int_equal(m.nv, 10242);
    sss_refs r;
    if (sss_refs_build(&m, 0.05, 4, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    long want = lround(0.05 * m.nv);
    if (labs((long)r.nref - want) > 1) fail_msg("%u references, expected %ld ± 1", r.nref, want);
    /* a closed genus-0 surface over the references: Euler V − E + F = 2 */
    assert_int_equal(r.nrt, 2 * r.nref - 4);
    double edge = mean_edge(&m), worst = check_refs(&m, &r, UINT32_MAX);
    /* Σ w_k p(ref_k) is the closest point on the simplified sphere: it lies
     * within the sagitta of a simplified triangle, a fraction of an edge of
     * the full mesh. */
    if (!(worst <= 2.0 * edge)) fail_msg("reconstruction off by %g (mean edge %g)", worst, edge);
    /* non-references really are interpolated, not all snapped to corners */
    uint32_t interior = 0;
    for (uint32_t v = 0; v < m.nv; v++) {
        const float *w = r.w + 3 * (size_t)v;
        if (w[0] > 0.0f && w[1] > 0.0f && w[2] > 0.0f) interior++;
    }
    assert_true(interior > m.nv / 2);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

static void buildMapsReferencesOntoThemselvesWithWeightOne(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    sss_refs r;
    if (sss_refs_build(&m, 0.1, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_true(r.nref < m.nv);
    uint32_t exact = 0;
    for (uint32_t i = 0; i < r.nref; i++) {
        uint32_t v = r.ref_vertex[i];
        const uint32_t *t = r.ref_tri + 3 * (size_t)r.vtri[v];
        for (int k = 0; k < 3; k++)
            if (t[k] == i && r.w[3 * (size_t)v + k] == 1.0f) exact++;
    }
    assert_int_equal(exact, r.nref);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* Same input, same bytes: twice, and with another thread count. */
static void buildIsDeterministic(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    sss_refs a, b, c;
    assert_int_equal(sss_refs_build(&m, 0.05, 0, &a, &err), SSS_OK);
    assert_int_equal(sss_refs_build(&m, 0.05, 0, &b, &err), SSS_OK);
    assert_true(same_refs(&a, &b));
    /* and whatever the thread count of the projection step */
    int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 3);
    assert_int_equal(sss_refs_build(&m, 0.05, 0, &c, &err), SSS_OK);
    omp_set_num_threads(threads);
    assert_true(same_refs(&a, &c));
    sss_refs_free(&a);
    sss_refs_free(&b);
    sss_refs_free(&c);
    sss_mesh_free(&m);
}

static void buildHonoursMinRefs(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 3, &err), SSS_OK);
    sss_refs r;
    assert_int_equal(sss_refs_build(&m, 0.01, 100, &r, &err), SSS_OK); /* 1% would be 6 */
    assert_int_equal(r.nref, 100);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* A vertex no triangle uses, next to a collinear (zero-area) triangle that is
 * the nearest reference triangle: it projects onto the triangle's longest
 * edge. fraction 1 keeps the input triangles as they are. */
static void buildHandlesDegenerateNearestTriangle(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_mesh_alloc(&m, 7, 2, &err), SSS_OK);
    const float pos[7][3] = {
        {0, 0, 0}, {1, 0, 0}, {2, 0, 0},       /* collinear triangle 0 */
        {10, 10, 10}, {11, 10, 10}, {10, 11, 10}, /* ordinary triangle 1, far away */
        {0.7f, 0.3f, 0.0f},                       /* used by no triangle */
    };
    memcpy(m.pos, pos, sizeof pos);
    const uint32_t tri[6] = {0, 1, 2, 3, 4, 5};
    memcpy(m.tri, tri, sizeof tri);
    sss_refs r;
    if (sss_refs_build(&m, 1.0, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(r.nref, 6);
    (void)check_refs(&m, &r, UINT32_MAX);
    assert_int_equal(r.vtri[6], 0);
    double q[3];
    reconstruct(&m, &r, 6, q);
    assert_close(q[0], 0.7, 1e-6);
    assert_close(q[1], 0.0, 1e-6);
    assert_close(q[2], 0.0, 1e-6);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* A plane with one vertex pulled far up into a spike, simplified hard: the
 * spike's neighbours lie far off whatever triangles remain. */
static void buildGivesFiniteWeightsForVertexFarOffSurface(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_plane(&m, 2.0, 2.0, 20, 20, &err), SSS_OK);
    uint32_t spike = UINT32_MAX;
    for (uint32_t v = 0; v < m.nv; v++)
        if (fabsf(m.pos[3 * (size_t)v]) < 1e-6f && fabsf(m.pos[3 * (size_t)v + 1]) < 1e-6f) spike = v;
    assert_true(spike != UINT32_MAX);
    m.pos[3 * (size_t)spike + 2] = 1000.0f;
    /* and a lone vertex far outside everything */
    sss_mesh lone;
    assert_int_equal(sss_mesh_alloc(&lone, 1, 0, &err), SSS_OK);
    lone.pos[0] = 1e30f, lone.pos[1] = -1e30f, lone.pos[2] = 3e30f;
    assert_int_equal(sss_mesh_append(&m, &lone, &err), SSS_OK);
    sss_mesh_free(&lone);

    sss_refs r;
    if (sss_refs_build(&m, 0.02, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_true(r.nref < m.nv / 10);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* Three triangles on one edge: OpenMesh's TriMesh would take two and refuse
 * the third. Each has two free edges, so each is a fin (a triangle with a
 * free edge on an edge that two others share, refs_decimate.cpp peel_fins):
 * the first is left out and the other two are a manifold pair, so nothing
 * is split, and the references are still original vertices. Then the same
 * fin on a sphere: left out, the sphere decimates as if it were not there.
 * (Before fins were left out, the split gave each its own vertex copies,
 * which a lone fin can afford but hundreds cannot: see
 * buildReachesTargetWithOneSidedFlaps.) */
static void buildSurvivesNonManifoldEdge(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh m;
    assert_int_equal(sss_mesh_alloc(&m, 5, 3, &err), SSS_OK);
    const float pos[5][3] = {{0, 0, 0}, {1, 0, 0}, {0.5f, 1, 0}, {0.5f, -1, 0}, {0.5f, 0, 1}};
    memcpy(m.pos, pos, sizeof pos);
    const uint32_t tri[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
    memcpy(m.tri, tri, sizeof tri);
    sss_refs r;
    if (sss_refs_build(&m, 0.6, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(r.faces_skipped, 1); /* the first fin, 0 1 2 */
    assert_int_equal(r.vertices_split, 0);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    /* identity keeps all three */
    assert_int_equal(sss_refs_build(&m, 1.0, 0, &r, &err), SSS_OK);
    assert_int_equal(r.nrt, 3);
    assert_int_equal(r.faces_skipped, 0);
    assert_int_equal(r.vertices_split, 0);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);

    /* a fin on an edge of a closed sphere */
    assert_int_equal(sss_gen_sphere(&m, 1.0, 3, &err), SSS_OK);
    sss_mesh fin;
    assert_int_equal(sss_mesh_alloc(&fin, 1, 0, &err), SSS_OK);
    uint32_t a = m.tri[0], b = m.tri[1];
    for (int k = 0; k < 3; k++) fin.pos[k] = 1.5f * 0.5f * (m.pos[3 * (size_t)a + k] + m.pos[3 * (size_t)b + k]);
    assert_int_equal(sss_mesh_append(&m, &fin, &err), SSS_OK);
    sss_mesh_free(&fin);
    uint32_t *t2 = realloc(m.tri, 3 * ((size_t)m.nf + 1) * sizeof *t2);
    assert_non_null(t2);
    m.tri = t2;
    m.tri[3 * (size_t)m.nf] = a, m.tri[3 * (size_t)m.nf + 1] = b, m.tri[3 * (size_t)m.nf + 2] = m.nv - 1;
    m.nf++;
    if (sss_refs_build(&m, 0.1, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(r.faces_skipped, 1);
    assert_int_equal(r.vertices_split, 0);
    long want = lround(0.1 * m.nv);
    if (labs((long)r.nref - want) > 1) fail_msg("%u references, expected %ld", r.nref, want);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* No reference triangle repeats a reference (copies of one vertex merged
 * back must not leave degenerate triangles behind). */
static void check_no_degenerate_ref_tri(const sss_refs *r)
{
    for (uint32_t t = 0; t < r->nrt; t++) {
        const uint32_t *c = r->ref_tri + 3 * (size_t)t;
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2])
            fail_msg("reference triangle %u repeats a corner: %u %u %u", t, c[0], c[1], c[2]);
    }
}

/* A small stand-in for the Stanford dragons' defects: sphere A; sphere B
 * sharing one vertex with A (two fans at one vertex); sphere C, A mirrored
 * across the plane through one of A's edges, sharing that edge (four
 * triangles on it); a fin (a third triangle on another edge of A); and 40
 * zero-thickness flaps (a triangle and its reverse) on edges of A, listed
 * before everything else. Before the split, OpenMesh took the flaps first,
 * refused A's triangles around them and stalled far above the target with
 * the hole rims and pillows pinned (188 references for a target of 20). */
static void make_nonmanifold(sss_mesh *out)
{
    sss_error err = {{0}};
    sss_mesh a, b, c, one;
    assert_int_equal(sss_gen_sphere(&a, 1.0, 3, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&b, 1.0, 3, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&c, 1.0, 3, &err), SSS_OK);
    const uint32_t n = a.nv, nf = a.nf;
    /* B touches A at A's rightmost vertex */
    uint32_t va = 0, vb = 0;
    for (uint32_t v = 0; v < n; v++) {
        if (a.pos[3 * (size_t)v] > a.pos[3 * (size_t)va]) va = v;
        if (b.pos[3 * (size_t)v] < b.pos[3 * (size_t)vb]) vb = v;
    }
    float shift[3];
    for (int k = 0; k < 3; k++) shift[k] = a.pos[3 * (size_t)va + k] - b.pos[3 * (size_t)vb + k];
    for (uint32_t v = 0; v < n; v++)
        for (int k = 0; k < 3; k++) b.pos[3 * (size_t)v + k] += shift[k];
    /* C: A mirrored across the plane through edge ea–eb, normal along ea + eb
     * (both corners stay put); the winding is flipped to keep it outward */
    const uint32_t ea = a.tri[0], eb = a.tri[1];
    double nn[3], len = 0.0, d = 0.0;
    for (int k = 0; k < 3; k++) {
        nn[k] = a.pos[3 * (size_t)ea + k] + a.pos[3 * (size_t)eb + k];
        len += nn[k] * nn[k];
    }
    for (int k = 0; k < 3; k++) {
        nn[k] /= sqrt(len);
        d += a.pos[3 * (size_t)ea + k] * nn[k];
    }
    for (uint32_t v = 0; v < n; v++) {
        double s = 0.0;
        for (int k = 0; k < 3; k++) s += c.pos[3 * (size_t)v + k] * nn[k];
        for (int k = 0; k < 3; k++) c.pos[3 * (size_t)v + k] -= (float)(2.0 * (s - d) * nn[k]);
    }
    for (uint32_t f = 0; f < c.nf; f++) {
        uint32_t t = c.tri[3 * (size_t)f + 1];
        c.tri[3 * (size_t)f + 1] = c.tri[3 * (size_t)f + 2];
        c.tri[3 * (size_t)f + 2] = t;
    }
    const uint32_t fin_a = a.tri[300], fin_b = a.tri[301];
    assert_int_equal(sss_mesh_append(&a, &b, &err), SSS_OK);
    assert_int_equal(sss_mesh_append(&a, &c, &err), SSS_OK);
    sss_mesh_free(&b);
    sss_mesh_free(&c);
    /* weld: B's vertex vb is A's va; C's copies of ea, eb are A's */
    for (size_t k = 3 * (size_t)nf; k < 6 * (size_t)nf; k++)
        if (a.tri[k] == n + vb) a.tri[k] = va;
    for (size_t k = 6 * (size_t)nf; k < 9 * (size_t)nf; k++) {
        if (a.tri[k] == 2 * n + ea) a.tri[k] = ea;
        else if (a.tri[k] == 2 * n + eb) a.tri[k] = eb;
    }
    /* the fin's apex and the flaps' tips, outside A */
    enum { NFLAP = 40 };
    uint32_t flap[NFLAP][2];
    for (uint32_t i = 0; i < NFLAP; i++) {
        uint32_t f = 7 + 31 * i;
        flap[i][0] = a.tri[3 * (size_t)f], flap[i][1] = a.tri[3 * (size_t)f + 1];
    }
    assert_int_equal(sss_mesh_alloc(&one, 1 + NFLAP, 0, &err), SSS_OK);
    for (int k = 0; k < 3; k++) one.pos[k] = 0.7f * (a.pos[3 * (size_t)fin_a + k] + a.pos[3 * (size_t)fin_b + k]);
    for (uint32_t i = 0; i < NFLAP; i++)
        for (int k = 0; k < 3; k++)
            one.pos[3 * (size_t)(i + 1) + k] =
                0.65f * (a.pos[3 * (size_t)flap[i][0] + k] + a.pos[3 * (size_t)flap[i][1] + k]);
    const uint32_t apex = a.nv;
    assert_int_equal(sss_mesh_append(&a, &one, &err), SSS_OK);
    sss_mesh_free(&one);
    uint32_t *t = malloc(3 * ((size_t)a.nf + 1 + 2 * NFLAP) * sizeof *t);
    assert_non_null(t);
    for (uint32_t i = 0; i < NFLAP; i++) {
        uint32_t *q = t + 6 * (size_t)i;
        q[0] = flap[i][0], q[1] = flap[i][1], q[2] = apex + 1 + i;
        q[3] = flap[i][1], q[4] = flap[i][0], q[5] = apex + 1 + i;
    }
    memcpy(t + 6 * NFLAP, a.tri, 3 * (size_t)a.nf * sizeof *t);
    uint32_t *fin = t + 6 * NFLAP + 3 * (size_t)a.nf;
    fin[0] = fin_a, fin[1] = fin_b, fin[2] = apex;
    free(a.tri);
    a.tri = t;
    a.nf += 1 + 2 * NFLAP;
    *out = a;
}

static void buildReachesTargetOnNonManifoldMesh(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    make_nonmanifold(&m);
    assert_int_equal(m.nv, 3 * 642 + 41);
    const double fractions[3] = {0.01, 0.03, 0.05};
    for (int i = 0; i < 3; i++) {
        sss_refs r;
        if (sss_refs_build(&m, fractions[i], 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
        long want = lround(fractions[i] * m.nv);
        if (labs((long)r.nref - want) > 1)
            fail_msg("fraction %g: %u references, expected %ld +- 1", fractions[i], r.nref, want);
        assert_int_equal(r.faces_skipped, 81); /* the 40 flaps cancel, the fin is left out */
        assert_true(r.vertices_split > 0);     /* B's and C's shared vertices */
        (void)check_refs(&m, &r, UINT32_MAX);
        check_no_degenerate_ref_tri(&r);
        sss_refs_free(&r);
    }
    /* deterministic here too, whatever the thread count */
    sss_refs a, b;
    assert_int_equal(sss_refs_build(&m, 0.03, 0, &a, &err), SSS_OK);
    int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 3);
    assert_int_equal(sss_refs_build(&m, 0.03, 0, &b, &err), SSS_OK);
    omp_set_num_threads(threads);
    assert_true(same_refs(&a, &b));
    sss_refs_free(&a);
    sss_refs_free(&b);
    sss_mesh_free(&m);
}

/* The Stanford dragons' zero-thickness flaps as the importer hands them on
 * since the importer keeps (docs/robustness.md B5) one triangle of each reversed pair: a sphere
 * with NFIN one-sided flaps, half hanging from one surface edge (a new tip
 * vertex outside), half folded over a surface vertex (on two surface edges
 * at once, the third edge free), the two kinds the 23K dragon has (1,052
 * flap triangles). With `pairs`, each flap is a triangle and its reverse,
 * as in the files, listed before the sphere. Fins are kept apart: no two
 * touch the same surface triangle. */
enum { NFIN = 48 };
static void make_flapped_sphere(sss_mesh *out, int pairs)
{
    sss_error err = {{0}};
    sss_mesh s;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 3, &err), SSS_OK);
    char *used = calloc(s.nv, 1);
    uint32_t fin[NFIN][3], nfin = 0, ntip = 0;
    float tip[NFIN / 2][3];
    for (uint32_t i = 0; nfin < NFIN; i++) {
        assert_true(i < s.nf);
        const uint32_t *t = s.tri + 3 * (size_t)((5 + 23 * (size_t)i) % s.nf);
        const uint32_t a = t[0], b = t[1], c = t[2];
        if (used[a] || used[b] || used[c]) continue;
        if (nfin % 2 == 0) {
            /* hanging from edge a b: a new tip outside */
            for (int k = 0; k < 3; k++)
                tip[ntip][k] = 0.65f * (s.pos[3 * (size_t)a + k] + s.pos[3 * (size_t)b + k]);
            fin[nfin][0] = a, fin[nfin][1] = b, fin[nfin][2] = s.nv + ntip++;
            used[a] = used[b] = used[c] = 1;
        } else {
            /* folded over b: on edges a b and b d, where d is the far corner
             * of the triangle across b c (c b d); a d is no edge */
            uint32_t d = UINT32_MAX;
            for (uint32_t g = 0; g < s.nf && d == UINT32_MAX; g++)
                for (int k = 0; k < 3; k++) {
                    const uint32_t *u = s.tri + 3 * (size_t)g;
                    if (u[k] == c && u[(k + 1) % 3] == b) d = u[(k + 2) % 3];
                }
            assert_true(d != UINT32_MAX);
            if (used[d]) continue;
            fin[nfin][0] = a, fin[nfin][1] = b, fin[nfin][2] = d;
            used[a] = used[b] = used[c] = used[d] = 1;
        }
        /* alternate the winding, as the scans do */
        if (nfin % 4 >= 2) {
            uint32_t x = fin[nfin][0];
            fin[nfin][0] = fin[nfin][1], fin[nfin][1] = x;
        }
        nfin++;
    }
    const uint32_t nflap = pairs ? 2 * NFIN : NFIN;
    assert_int_equal(sss_mesh_alloc(out, s.nv + ntip, s.nf + nflap, &err), SSS_OK);
    memcpy(out->pos, s.pos, 3 * (size_t)s.nv * sizeof *s.pos);
    memcpy(out->pos + 3 * (size_t)s.nv, tip, 3 * (size_t)ntip * sizeof *out->pos);
    uint32_t *q = out->tri;
    for (uint32_t i = 0; i < NFIN; i++) {
        q[0] = fin[i][0], q[1] = fin[i][1], q[2] = fin[i][2], q += 3;
        if (pairs) q[0] = fin[i][1], q[1] = fin[i][0], q[2] = fin[i][2], q += 3;
    }
    memcpy(q, s.tri, 3 * (size_t)s.nf * sizeof *q);
    free(used);
    sss_mesh_free(&s);
}

/* |nref − want| ≤ 10 % of want (at least 1). */
static void check_count(const sss_refs *r, double fraction, uint32_t nv, const char *what)
{
    const long want = lround(fraction * nv);
    const long tol = want / 10 > 1 ? want / 10 : 1;
    if (labs((long)r->nref - want) > tol)
        fail_msg("%s, fraction %g: %u references, expected %ld +- %ld", what, fraction, r->nref, want, tol);
}

/* The importer (docs/robustness.md) keeps one triangle of each reversed pair, so the flaps
 * no longer cancel: split into manifold pieces, each fin pinned its vertices
 * (a lone triangle, or a rim of three where it cut a surface triangle
 * loose), and the decimation stalled far above the target, whatever was
 * asked (this mesh: 144 of 666 vertices for 7, 20 or 67; the 23K dragon:
 * 2,392, 10.4 %). Fins are left out now, and the sphere decimates as if
 * they were not there. The pairs, as before, cancel. */
static void buildReachesTargetWithOneSidedFlaps(void **state)
{
    (void)state;
    sss_error err = {{0}};
    for (int pairs = 0; pairs < 2; pairs++) {
        sss_mesh m;
        make_flapped_sphere(&m, pairs);
        const double fractions[3] = {0.01, 0.03, 0.1};
        for (int i = 0; i < 3; i++) {
            sss_refs r;
            if (sss_refs_build(&m, fractions[i], 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
            check_count(&r, fractions[i], m.nv, pairs ? "reversed pairs" : "one-sided flaps");
            assert_int_equal(r.faces_skipped, pairs ? 2 * NFIN : NFIN); /* every flap, nothing else */
            assert_int_equal(r.vertices_split, 0);                      /* the sphere is left whole */
            (void)check_refs(&m, &r, UINT32_MAX);
            check_no_degenerate_ref_tri(&r);
            sss_refs_free(&r);
        }
        sss_mesh_free(&m);
    }
}

/* The same flaps as pairs in an OFF file, through the importer: what the
 * bake's compression does with a scan. */
static void buildReachesTargetOnImportedFlaps(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh m;
    make_flapped_sphere(&m, 1);
    char path[] = "/tmp/sss_test_refs_XXXXXX.off";
    int fd = mkstemps(path, 4);
    assert_true(fd >= 0);
    FILE *f = fdopen(fd, "w");
    assert_non_null(f);
    fprintf(f, "OFF\n%u %u 0\n", m.nv, m.nf);
    for (uint32_t v = 0; v < m.nv; v++)
        fprintf(f, "%.9g %.9g %.9g\n", m.pos[3 * (size_t)v], m.pos[3 * (size_t)v + 1], m.pos[3 * (size_t)v + 2]);
    for (uint32_t t = 0; t < m.nf; t++)
        fprintf(f, "3 %u %u %u\n", m.tri[3 * (size_t)t], m.tri[3 * (size_t)t + 1], m.tri[3 * (size_t)t + 2]);
    assert_int_equal(fclose(f), 0);
    sss_mesh im;
    sss_import_report rep;
    sss_result res = sss_import_mesh(path, &im, &rep, &err);
    unlink(path);
    if (res != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(rep.faces_duplicate, NFIN); /* one of each pair is dropped */
    assert_int_equal(im.nv, m.nv);
    sss_refs r;
    if (sss_refs_build(&im, 0.03, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    check_count(&r, 0.03, im.nv, "imported flaps");
    (void)check_refs(&im, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&im);
    sss_mesh_free(&m);
}

/* The regression on the real scan: the 22,998-vertex Stanford dragon
 * (data/fetch.sh) at 2 %, the compact preset's RGB fraction, stalled at
 * 2,392 references (10.4 %) when 460 were asked for. About 3 s. */
static void buildReachesTargetOnImportedDragon(void **state)
{
    (void)state;
    const char *path = SSS_TEST_DATA "/../../data/stanford/dragon_22998.ply";
    if (access(path, R_OK) != 0) {
        printf("  %s not fetched (data/fetch.sh): skipped\n", path);
        skip();
    }
    sss_error err = {{0}};
    sss_mesh m;
    assert_int_equal(sss_import_mesh(path, &m, NULL, &err), SSS_OK);
    sss_refs r;
    if (sss_refs_build(&m, 0.02, 1, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    check_count(&r, 0.02, m.nv, "dragon_22998");
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* A manifold input is not split: no copies, nothing skipped. */
static void buildDoesNotSplitManifoldMesh(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_torus(&m, 1.0, 0.3, 48, 16, &err), SSS_OK);
    sss_refs r;
    if (sss_refs_build(&m, 0.05, 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(r.vertices_split, 0);
    assert_int_equal(r.faces_skipped, 0);
    if (labs((long)r.nref - lround(0.05 * m.nv)) > 1) fail_msg("%u references", r.nref);
    (void)check_refs(&m, &r, UINT32_MAX);
    sss_refs_free(&r);
    sss_mesh_free(&m);
}

/* A sphere cut into 56 unwelded patches (by the cell of each triangle's
 * centroid; every patch has its own copies of its rim vertices), like the
 * teapot's Bézier patches: the patches are one surface to the decimation.
 * Before, their rims and corners stopped it at 234 references for any
 * target below. A vertex at the same position as a reference maps onto it
 * exactly. */
static void buildWeldsCoincidentVertices(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
    const uint32_t nv0 = m.nv;
    int *cell = malloc(m.nf * sizeof *cell), *owner = malloc(nv0 * sizeof *owner);
    uint32_t *copy_of = malloc(4 * (size_t)nv0 * sizeof *copy_of);
    int *copy_cell = malloc(4 * (size_t)nv0 * sizeof *copy_cell);
    float *pos = malloc(3 * 4 * (size_t)nv0 * sizeof *pos);
    assert_true(cell && owner && copy_of && copy_cell && pos);
    for (uint32_t f = 0; f < m.nf; f++) {
        double c[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++) c[j] += m.pos[3 * (size_t)m.tri[3 * (size_t)f + k] + j] / 3.0;
        cell[f] = (int)floor(c[0] * 1.5 + 2) * 25 + (int)floor(c[1] * 1.5 + 2) * 5 + (int)floor(c[2] * 1.5 + 2);
    }
    memcpy(pos, m.pos, 3 * (size_t)nv0 * sizeof *pos);
    for (uint32_t v = 0; v < nv0; v++) owner[v] = -1;
    uint32_t nv = nv0, ncopy = 0;
    for (uint32_t f = 0; f < m.nf; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = m.tri[3 * (size_t)f + k], found = UINT32_MAX;
            if (owner[v] < 0) owner[v] = cell[f];
            if (owner[v] == cell[f]) continue;
            for (uint32_t i = 0; i < ncopy && found == UINT32_MAX; i++)
                if (copy_of[i] == v && copy_cell[i] == cell[f]) found = nv0 + i;
            if (found == UINT32_MAX) {
                assert_true(ncopy < 3 * nv0);
                copy_of[ncopy] = v, copy_cell[ncopy] = cell[f];
                memcpy(pos + 3 * (size_t)nv, pos + 3 * (size_t)v, 3 * sizeof *pos);
                found = nv++, ncopy++;
            }
            m.tri[3 * (size_t)f + k] = found;
        }
    free(m.pos);
    m.pos = pos;
    m.nv = nv;
    assert_int_equal(ncopy, 798);
    const double fractions[2] = {0.01, 0.05};
    for (int i = 0; i < 2; i++) {
        sss_refs r;
        if (sss_refs_build(&m, fractions[i], 0, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
        long want = lround(fractions[i] * m.nv);
        if (labs((long)r.nref - want) > 1)
            fail_msg("fraction %g: %u references, expected %ld +- 1", fractions[i], r.nref, want);
        assert_int_equal(r.faces_skipped, 0);
        (void)check_refs(&m, &r, UINT32_MAX);
        check_no_degenerate_ref_tri(&r);
        /* a copy whose original is a reference (or vice versa) lands on it */
        uint32_t exact = 0;
        for (uint32_t c = 0; c < ncopy; c++) {
            double p[3], q[3], o[3];
            P(&m, nv0 + c, p);
            reconstruct(&m, &r, nv0 + c, q);
            reconstruct(&m, &r, copy_of[c], o);
            if (dist3(p, q) == 0.0 && dist3(p, o) == 0.0) exact++;
        }
        assert_true(exact > 0);
        sss_refs_free(&r);
    }
    free(cell);
    free(owner);
    free(copy_of);
    free(copy_cell);
    sss_mesh_free(&m);
}

/* ---- illumination-aware selection (beyond the paper, its §6) ------------- */

/* A shadow-boundary-like feature on a sphere: two channels, the first a
 * step across the plane x = 0.3 (lit 1, shadowed 0.1), the second constant. */
static float *step_feature(const sss_mesh *m)
{
    float *f = malloc(2 * (size_t)m->nv * sizeof *f);
    assert_non_null(f);
    for (uint32_t v = 0; v < m->nv; v++) {
        f[2 * (size_t)v] = m->pos[3 * (size_t)v] > 0.3f ? 1.0f : 0.1f;
        f[2 * (size_t)v + 1] = 0.5f;
    }
    return f;
}

/* RMS over vertices of Σ w_k f(ref_k) − f(v), channel 0. */
static double feature_rms(const sss_mesh *m, const sss_refs *r, const float *f)
{
    double s = 0.0;
    for (uint32_t v = 0; v < m->nv; v++) {
        double q = 0.0;
        for (int k = 0; k < 3; k++)
            q += r->w[3 * (size_t)v + k] * f[2 * (size_t)r->ref_vertex[r->ref_tri[3 * (size_t)r->vtri[v] + k]]];
        double e = q - f[2 * (size_t)v];
        s += e * e;
    }
    return sqrt(s / m->nv);
}

/* References within `band` of the step. */
static uint32_t refs_near_step(const sss_mesh *m, const sss_refs *r, double band)
{
    uint32_t n = 0;
    for (uint32_t i = 0; i < r->nref; i++)
        if (fabs(m->pos[3 * (size_t)r->ref_vertex[i]] - 0.3) <= band) n++;
    return n;
}

static void buildExKeepsReferencesAlongFeatureStep(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
    float *f = step_feature(&m);
    sss_refs geo, ill;
    if (sss_refs_build(&m, 0.05, 0, &geo, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_refs_build_ex(&m, 0.05, 0, f, 2, 1e-3, &ill, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(ill.nref, geo.nref); /* same budget */
    (void)check_refs(&m, &ill, UINT32_MAX);
    check_no_degenerate_ref_tri(&ill);
    double edge = mean_edge(&m);
    uint32_t ng = refs_near_step(&m, &geo, edge), ni = refs_near_step(&m, &ill, edge);
    double eg = feature_rms(&m, &geo, f), ei = feature_rms(&m, &ill, f);
    print_message("near the step: %u geometric, %u illumination-aware references; feature RMS %.4f vs %.4f\n", ng,
                  ni, eg, ei);
    /* measured: 58 vs 13, 0.031 vs 0.151 (and cluster feature distances
     * without the interpolants' gradients gave 8 vs 13, 0.113 vs 0.151) */
    if (!(ni >= 3 * ng)) fail_msg("%u references near the step, geometric selection has %u", ni, ng);
    if (!(ei <= eg / 3.0)) fail_msg("feature RMS %.4f, geometric selection %.4f", ei, eg);
    sss_refs_free(&geo);
    sss_refs_free(&ill);
    free(f);
    sss_mesh_free(&m);
}

/* No feature, weight 0 or a constant feature: exactly sss_refs_build. */
static void buildExWithoutFeatureSignalIsGeometric(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    float *f = step_feature(&m);
    sss_refs geo, a;
    assert_int_equal(sss_refs_build(&m, 0.05, 0, &geo, &err), SSS_OK);
    assert_int_equal(sss_refs_build_ex(&m, 0.05, 0, NULL, 0, 0.0, &a, &err), SSS_OK);
    assert_true(same_refs(&geo, &a));
    sss_refs_free(&a);
    assert_int_equal(sss_refs_build_ex(&m, 0.05, 0, f, 2, 0.0, &a, &err), SSS_OK);
    assert_true(same_refs(&geo, &a));
    sss_refs_free(&a);
    /* the step removed: both channels constant, nothing to steer by */
    for (uint32_t v = 0; v < m.nv; v++) f[2 * (size_t)v] = 0.25f;
    assert_int_equal(sss_refs_build_ex(&m, 0.05, 0, f, 2, 1e-2, &a, &err), SSS_OK);
    assert_true(same_refs(&geo, &a));
    sss_refs_free(&a);
    sss_refs_free(&geo);
    free(f);
    sss_mesh_free(&m);
}

/* With a feature: deterministic, whatever the thread count, and different
 * from the geometric choice. */
static void buildExIsDeterministic(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    float *f = step_feature(&m);
    sss_refs a, b, geo;
    assert_int_equal(sss_refs_build_ex(&m, 0.05, 0, f, 2, 1e-3, &a, &err), SSS_OK);
    int threads = omp_get_max_threads();
    omp_set_num_threads(threads > 1 ? 1 : 3);
    assert_int_equal(sss_refs_build_ex(&m, 0.05, 0, f, 2, 1e-3, &b, &err), SSS_OK);
    omp_set_num_threads(threads);
    assert_true(same_refs(&a, &b));
    assert_int_equal(sss_refs_build(&m, 0.05, 0, &geo, &err), SSS_OK);
    assert_false(same_refs(&a, &geo));
    sss_refs_free(&a);
    sss_refs_free(&b);
    sss_refs_free(&geo);
    free(f);
    sss_mesh_free(&m);
}

static void buildExRejectsBadFeature(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 2, &err), SSS_OK);
    float *f = step_feature(&m);
    sss_refs r;
    assert_int_equal(sss_refs_build_ex(&m, 0.1, 0, f, 0, 1e-3, &r, &err), SSS_ERR_ARG);
    assert_int_equal(sss_refs_build_ex(&m, 0.1, 0, f, 2, -1.0, &r, &err), SSS_ERR_ARG);
    assert_int_equal(sss_refs_build_ex(&m, 0.1, 0, f, 2, NAN, &r, &err), SSS_ERR_ARG);
    assert_int_equal(sss_refs_build_ex(&m, 0.1, 0, f, 2, INFINITY, &r, &err), SSS_ERR_ARG);
    f[2 * 17 + 1] = NAN;
    assert_int_equal(sss_refs_build_ex(&m, 0.1, 0, f, 2, 1e-3, &r, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "vertex 17"));
    assert_null(r.ref_vertex);
    free(f);
    sss_mesh_free(&m);
}

static void buildRejectsBadInput(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh m;
    assert_int_equal(sss_gen_sphere(&m, 1.0, 1, &err), SSS_OK);
    sss_refs r;
    assert_int_equal(sss_refs_build(&m, 0.0, 0, &r, &err), SSS_ERR_ARG);
    assert_int_equal(sss_refs_build(&m, 1.5, 0, &r, &err), SSS_ERR_ARG);
    assert_int_equal(sss_refs_build(&m, NAN, 0, &r, &err), SSS_ERR_ARG);
    assert_null(r.w);
    m.tri[4] = m.nv;
    assert_int_equal(sss_refs_build(&m, 0.5, 0, &r, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "triangle 1"));
    m.tri[4] = 0;
    m.pos[7] = NAN;
    assert_int_equal(sss_refs_build(&m, 0.5, 0, &r, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "vertex 2"));
    assert_null(r.ref_vertex);
    sss_mesh_free(&m);
    /* every triangle repeats an index: nothing to build on */
    assert_int_equal(sss_mesh_alloc(&m, 3, 1, &err), SSS_OK);
    m.tri[0] = 0, m.tri[1] = 1, m.tri[2] = 1;
    assert_int_equal(sss_refs_build(&m, 1.0, 0, &r, &err), SSS_ERR_MESH);
    sss_mesh_free(&m);
}

/* ---- sss_refs_closest_weights -------------------------------------------- */

static void closestWeightsMatchBarycentricsAndClampOutside(void **state)
{
    (void)state;
    const double a[3] = {0, 0, 0}, b[3] = {2, 0, 0}, c[3] = {0, 2, 0};
    double w[3];
    /* above the interior: the projection's barycentrics */
    const double p0[3] = {0.5, 0.25, 3.0};
    sss_refs_closest_weights(p0, a, b, c, w);
    check_weights(w);
    assert_close(w[0], 0.625, 1e-12);
    assert_close(w[1], 0.25, 1e-12);
    assert_close(w[2], 0.125, 1e-12);
    /* beyond corner b */
    const double p1[3] = {5, -1, 0};
    sss_refs_closest_weights(p1, a, b, c, w);
    check_weights(w);
    assert_close(w[1], 1.0, 0);
    /* outside edge bc: clamped onto it */
    const double p2[3] = {2, 2, -1};
    sss_refs_closest_weights(p2, a, b, c, w);
    check_weights(w);
    assert_close(w[0], 0.0, 0);
    assert_close(w[1], 0.5, 1e-12);
    assert_close(w[2], 0.5, 1e-12);
    /* outside edge ab, below it */
    const double p3[3] = {1.5, -4, 2};
    sss_refs_closest_weights(p3, a, b, c, w);
    check_weights(w);
    assert_close(w[0], 0.25, 1e-12);
    assert_close(w[1], 0.75, 1e-12);
    assert_close(w[2], 0.0, 0);
    /* far away: still a point of the triangle */
    const double p4[3] = {1e30, 3e29, -1e30};
    sss_refs_closest_weights(p4, a, b, c, w);
    check_weights(w);
    /* non-finite input: corner a */
    const double p5[3] = {NAN, 0, 0};
    sss_refs_closest_weights(p5, a, b, c, w);
    assert_true(w[0] == 1.0 && w[1] == 0.0 && w[2] == 0.0);
}

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double urand(void) { return test_urand(&rng_state); }

/* Random triangles (every third one a thin sliver) and points: the weighted
 * point is never farther from p than any point of a dense barycentric grid
 * over the triangle. */
static void closestWeightsBeatDenseSamplingOnRandomTriangles(void **state)
{
    (void)state;
    const int G = 60;
    for (int it = 0; it < 1500; it++) {
        double a[3], b[3], c[3], p[3], w[3];
        for (int k = 0; k < 3; k++) {
            a[k] = 2.0 * urand() - 1.0;
            b[k] = 2.0 * urand() - 1.0;
            c[k] = 2.0 * urand() - 1.0;
            p[k] = 4.0 * urand() - 2.0;
        }
        if (it % 3 == 0) /* c within 1e-9 of segment ab */
            for (int k = 0; k < 3; k++) c[k] = a[k] + 0.3 * (b[k] - a[k]) + 1e-9 * (urand() - 0.5);
        sss_refs_closest_weights(p, a, b, c, w);
        check_weights(w);
        double q[3];
        for (int k = 0; k < 3; k++) q[k] = w[0] * a[k] + w[1] * b[k] + w[2] * c[k];
        double d = dist3(p, q), best = INFINITY;
        for (int i = 0; i <= G; i++)
            for (int j = 0; i + j <= G; j++) {
                double u = (double)i / G, v = (double)j / G, s[3];
                for (int k = 0; k < 3; k++) s[k] = (1.0 - u - v) * a[k] + u * b[k] + v * c[k];
                best = fmin(best, dist3(p, s));
            }
        if (!(d <= best + 1e-8)) fail_msg("case %d: weighted point at %.12g, a grid point at %.12g", it, d, best);
    }
}

static void closestWeightsHandleDegenerateTriangles(void **state)
{
    (void)state;
    double w[3];
    /* collinear, middle corner listed last: longest edge is a–b */
    const double a[3] = {0, 0, 0}, b[3] = {4, 0, 0}, c[3] = {1, 0, 0};
    const double p[3] = {3, 2, 0};
    sss_refs_closest_weights(p, a, b, c, w);
    check_weights(w);
    assert_close(w[0], 0.25, 1e-12);
    assert_close(w[1], 0.75, 1e-12);
    assert_close(w[2], 0.0, 0);
    const double q[3] = {-3, 1, 1};
    sss_refs_closest_weights(q, a, b, c, w);
    check_weights(w);
    assert_close(w[0], 1.0, 0);
    /* nearly collinear sliver */
    const double s[3] = {2, 1e-14, 0};
    const double r0[3] = {2, 1, 0};
    sss_refs_closest_weights(r0, a, b, s, w);
    check_weights(w);
    double x = w[1] * 4 + w[2] * 2;
    assert_close(x, 2.0, 1e-9);
    /* two corners coincide */
    const double d[3] = {4, 0, 0};
    sss_refs_closest_weights(p, a, b, d, w);
    check_weights(w);
    assert_close(w[0], 0.25, 1e-12);
    /* all coincide */
    sss_refs_closest_weights(p, a, a, a, w);
    check_weights(w);
    assert_true(w[0] == 1.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(buildWithFractionOneIsIdentity),
        cmocka_unit_test(buildKeepsFivePercentOfSphereAndReconstructsPositions),
        cmocka_unit_test(buildMapsReferencesOntoThemselvesWithWeightOne),
        cmocka_unit_test(buildIsDeterministic),
        cmocka_unit_test(buildHonoursMinRefs),
        cmocka_unit_test(buildHandlesDegenerateNearestTriangle),
        cmocka_unit_test(buildGivesFiniteWeightsForVertexFarOffSurface),
        cmocka_unit_test(buildSurvivesNonManifoldEdge),
        cmocka_unit_test(buildReachesTargetOnNonManifoldMesh),
        cmocka_unit_test(buildReachesTargetWithOneSidedFlaps),
        cmocka_unit_test(buildReachesTargetOnImportedFlaps),
        cmocka_unit_test(buildReachesTargetOnImportedDragon),
        cmocka_unit_test(buildDoesNotSplitManifoldMesh),
        cmocka_unit_test(buildWeldsCoincidentVertices),
        cmocka_unit_test(buildExKeepsReferencesAlongFeatureStep),
        cmocka_unit_test(buildExWithoutFeatureSignalIsGeometric),
        cmocka_unit_test(buildExIsDeterministic),
        cmocka_unit_test(buildExRejectsBadFeature),
        cmocka_unit_test(buildRejectsBadInput),
        cmocka_unit_test(closestWeightsMatchBarycentricsAndClampOutside),
        cmocka_unit_test(closestWeightsBeatDenseSamplingOnRandomTriangles),
        cmocka_unit_test(closestWeightsHandleDegenerateTriangles),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
