/* bvh.c: the triangle hierarchy the viewer and the runtime API (sss/api.h)
 * trace the bake's visibility rays through (sss/bvh.h).
 *
 * Why the triangle test repeats Embree's arithmetic: the near terms need
 * V(x_o, ω) exactly as the bake decided it, and a vertex that gets the other
 * answer is off by about half of its q (docs/viewer.md). The ray starts only
 * δ = 1e-5 of the diagonal off the surface, so at grazing light it passes
 * the vertex's own triangles and their neighbours within a few ulps of
 * their edges, where two correct float tests can disagree. Forming the
 * same floats as Embree does (v0, e1 = v0 − v1, e2 = v2 − v0, Ng =
 * cross(e2, e1), the edge tests U, V against |den| and the depth test
 * |den|·tnear < T, with the fused multiply-adds its AVX2/AVX-512 kernels
 * use in cross and dot) removes the test itself as a source of
 * disagreement. test_render_near_terms measures none at all on the blob, the torus
 * and the 23K dragon; an unfused variant of the same formulas measured none
 * either, so the fusing is a margin for other meshes rather than a need on
 * these.
 *
 * Why the boxes are padded: the float triangle test may accept a ray that
 * passes a few ulps outside the triangle, and the float slab test may
 * reject a box the ray touches within a few ulps; a pad of 1e-6 of the
 * diagonal (tens of ulps at the mesh's scale) keeps every box conservative
 * at a negligible cost in traversal.
 *
 * The build: binned SAH (16 bins per axis, fewer for fewer triangles, all
 * three axes, traversal and triangle cost 1), leaves of at most SSS_BVH_MAX_LEAF triangles; below
 * depth 32 the object median instead, which bounds the depth by
 * 32 + log2(n) and so the shader's fixed stack. Every choice depends only on
 * the input, so the tree is the same on every run.
 */
#include "sss/bvh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NBINS 16
#define MEDIAN_DEPTH 32

typedef struct prim {
    float lo[3], hi[3], c[3]; /* bounds and their centre */
    uint32_t t;               /* mesh triangle */
} prim;

typedef struct builder {
    prim *p;
    sss_bvh_node *node;
    uint32_t nnode, depth;
} builder;

static double half_area(const float lo[3], const float hi[3])
{
    const double dx = (double)hi[0] - lo[0], dy = (double)hi[1] - lo[1], dz = (double)hi[2] - lo[2];
    if (!(dx >= 0 && dy >= 0 && dz >= 0)) return 0.0; /* empty */
    return dx * dy + dy * dz + dz * dx;
}

static void box_empty(float lo[3], float hi[3])
{
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
}

/* Selects rather than branches (minss / maxss): the build's inner loop,
 * where a branch per coordinate mispredicts half of the time. */
static void box_grow(float *restrict lo, float *restrict hi, const float *restrict plo, const float *restrict phi)
{
    for (int k = 0; k < 3; k++) {
        lo[k] = plo[k] < lo[k] ? plo[k] : lo[k];
        hi[k] = phi[k] > hi[k] ? phi[k] : hi[k];
    }
}

/* The bin of centroid coordinate c on an axis starting at cmin: the same
 * function for binning and partitioning, so the two always agree. */
static int bin_of(float c, float cmin, double scale, int nb)
{
    int b = (int)(((double)c - cmin) * scale);
    return b < 0 ? 0 : b >= nb ? nb - 1 : b;
}

/* qsort's comparisons, one per axis: qsort passes no context, and a
 * global axis would make two builds on two threads (two assets opened at
 * once, sss/api.h) interfere. */
static int cmp_centroid(const prim *a, const prim *b, int axis)
{
    if (a->c[axis] != b->c[axis]) return a->c[axis] < b->c[axis] ? -1 : 1;
    return a->t < b->t ? -1 : a->t > b->t; /* a total order: the same tree every run */
}
static int cmp_x(const void *x, const void *y) { return cmp_centroid(x, y, 0); }
static int cmp_y(const void *x, const void *y) { return cmp_centroid(x, y, 1); }
static int cmp_z(const void *x, const void *y) { return cmp_centroid(x, y, 2); }

static void make_leaf(builder *B, uint32_t ni, uint32_t begin, uint32_t n)
{
    B->node[ni].a = begin;
    B->node[ni].b = n << 2;
}

/* Bounds of the triangles and of their centroids over [begin, end). */
static void range_bounds(const prim *p, uint32_t begin, uint32_t end, float lo[3], float hi[3], float clo[3],
                         float chi[3])
{
    box_empty(lo, hi);
    box_empty(clo, chi);
    for (uint32_t i = begin; i < end; i++) {
        box_grow(lo, hi, p[i].lo, p[i].hi);
        box_grow(clo, chi, p[i].c, p[i].c);
    }
}

/* A bin of the SAH: its triangles' count, bounds and centroid bounds. */
typedef struct bin {
    uint32_t n;
    float lo[3], hi[3], clo[3], chi[3];
} bin;

/* Node ni over p[begin, end), whose bounds (lo, hi) and centroid bounds
 * (clo, chi) the caller knows: the parent's bins give them for free. */
static void build(builder *B, uint32_t ni, uint32_t begin, uint32_t end, uint32_t depth, const float clo[3],
                  const float chi[3])
{
    sss_bvh_node *nd = &B->node[ni];
    const uint32_t n = end - begin;
    prim *p = B->p;
    if (depth > B->depth) B->depth = depth;
    if (n <= 1) {
        make_leaf(B, ni, begin, n);
        return;
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        if ((double)chi[k] - clo[k] > (double)chi[axis] - clo[axis]) axis = k;
    uint32_t mid = begin + n / 2;
    int binned = 0;
    bin L = {0}, R = {0}; /* the children's bounds, from the bins when the SAH split */
    if (!((double)chi[axis] - clo[axis] > 0.0)) {
        /* all centroids coincide: no plane separates them */
        if (n <= SSS_BVH_MAX_LEAF) {
            make_leaf(B, ni, begin, n);
            return;
        }
    } else if (depth >= MEDIAN_DEPTH) {
        if (n <= SSS_BVH_MAX_LEAF) {
            make_leaf(B, ni, begin, n);
            return;
        }
        qsort(p + begin, n, sizeof *p, axis == 0 ? cmp_x : axis == 1 ? cmp_y : cmp_z);
    } else {
        /* binned SAH over the three axes, in one pass over the triangles;
         * as many bins as triangles below NBINS, since most nodes are small
         * and the bins' sweeps would cost more than the binning */
        const int nb = n < NBINS ? (int)n : NBINS;
        bin bins[3][NBINS];
        double scale[3];
        for (int k = 0; k < 3; k++) {
            const double ext = (double)chi[k] - clo[k];
            scale[k] = ext > 0.0 ? nb / ext : 0.0;
            for (int b = 0; b < nb; b++) {
                bins[k][b].n = 0;
                box_empty(bins[k][b].lo, bins[k][b].hi);
                box_empty(bins[k][b].clo, bins[k][b].chi);
            }
        }
        for (uint32_t i = begin; i < end; i++)
            for (int k = 0; k < 3; k++) {
                bin *bn = &bins[k][bin_of(p[i].c[k], clo[k], scale[k], nb)];
                bn->n++;
                box_grow(bn->lo, bn->hi, p[i].lo, p[i].hi);
                box_grow(bn->clo, bn->chi, p[i].c, p[i].c);
            }
        double best = INFINITY;
        int best_axis = -1, best_split = 0;
        for (int k = 0; k < 3; k++) {
            if (!(scale[k] > 0.0)) continue;
            /* right-hand sweep: area and count of bins s … nb − 1 */
            double ra[NBINS];
            uint32_t rn[NBINS];
            float lo[3], hi[3];
            box_empty(lo, hi);
            uint32_t m = 0;
            for (int b = nb - 1; b > 0; b--) {
                if (bins[k][b].n) box_grow(lo, hi, bins[k][b].lo, bins[k][b].hi), m += bins[k][b].n;
                ra[b] = half_area(lo, hi);
                rn[b] = m;
            }
            box_empty(lo, hi);
            m = 0;
            for (int sp = 1; sp < nb; sp++) {
                if (bins[k][sp - 1].n) box_grow(lo, hi, bins[k][sp - 1].lo, bins[k][sp - 1].hi), m += bins[k][sp - 1].n;
                if (m == 0 || rn[sp] == 0) continue;
                const double c = half_area(lo, hi) * m + ra[sp] * rn[sp];
                if (c < best) best = c, best_axis = k, best_split = sp;
            }
        }
        const double area = half_area(nd->lo, nd->hi);
        /* costs relative to the node's area: leaf n, split 1 + best / area */
        if (n <= SSS_BVH_MAX_LEAF && (best_axis < 0 || (double)n * area <= area + best)) {
            make_leaf(B, ni, begin, n);
            return;
        }
        if (best_axis >= 0) {
            axis = best_axis;
            uint32_t i = begin, j = end;
            while (i < j) {
                if (bin_of(p[i].c[axis], clo[axis], scale[axis], nb) < best_split) i++;
                else {
                    j--;
                    prim tmp = p[i];
                    p[i] = p[j];
                    p[j] = tmp;
                }
            }
            mid = i;
            box_empty(L.lo, L.hi), box_empty(L.clo, L.chi), box_empty(R.lo, R.hi), box_empty(R.clo, R.chi);
            for (int b = 0; b < nb; b++) {
                bin *side = b < best_split ? &L : &R;
                if (!bins[axis][b].n) continue;
                box_grow(side->lo, side->hi, bins[axis][b].lo, bins[axis][b].hi);
                box_grow(side->clo, side->chi, bins[axis][b].clo, bins[axis][b].chi);
            }
            binned = 1;
        }
    }
    if (!binned) {
        range_bounds(p, begin, mid, L.lo, L.hi, L.clo, L.chi);
        range_bounds(p, mid, end, R.lo, R.hi, R.clo, R.chi);
    }
    /* children adjacent, so the node stores one index */
    const uint32_t c0 = B->nnode;
    B->nnode += 2;
    nd->a = c0;
    nd->b = (uint32_t)axis;
    memcpy(B->node[c0].lo, L.lo, sizeof L.lo);
    memcpy(B->node[c0].hi, L.hi, sizeof L.hi);
    memcpy(B->node[c0 + 1].lo, R.lo, sizeof R.lo);
    memcpy(B->node[c0 + 1].hi, R.hi, sizeof R.hi);
    build(B, c0, begin, mid, depth + 1, L.clo, L.chi);
    build(B, c0 + 1, mid, end, depth + 1, R.clo, R.chi);
}

void sss_bvh_free(sss_bvh *b)
{
    if (!b) return;
    free(b->node);
    free(b->tri);
    free(b->prim);
    memset(b, 0, sizeof *b);
}

sss_result sss_bvh_build(const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nf, sss_bvh *out,
                         sss_error *err)
{
    memset(out, 0, sizeof *out);
    prim *p = malloc(((size_t)nf + 1) * sizeof *p);
    if (!p) return sss_fail(err, SSS_ERR_NOMEM, "bvh: out of memory for %u triangles", nf);
    uint32_t n = 0;
    for (uint32_t t = 0; t < nf; t++) {
        const uint32_t *v = &tri[3 * (size_t)t];
        if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;
        prim *q = &p[n];
        box_empty(q->lo, q->hi);
        int finite = 1;
        for (int i = 0; i < 3; i++) {
            const float *x = &pos[3 * (size_t)v[i]];
            for (int k = 0; k < 3; k++) finite &= isfinite(x[k]) != 0;
            box_grow(q->lo, q->hi, x, x);
        }
        if (!finite) continue;
        for (int k = 0; k < 3; k++) q->c[k] = 0.5f * q->lo[k] + 0.5f * q->hi[k];
        q->t = t;
        n++;
    }
    builder B = {p, NULL, 1, 0};
    /* a binary tree with leaves of ≥ 1 triangle: at most 2n − 1 nodes */
    B.node = calloc(n > 0 ? 2 * (size_t)n : 1, sizeof *B.node);
    out->tri = malloc(((size_t)n * 12 + 1) * sizeof *out->tri);
    out->prim = malloc(((size_t)n + 1) * sizeof *out->prim);
    if (!B.node || !out->tri || !out->prim) {
        free(p);
        free(B.node);
        sss_bvh_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "bvh: out of memory for %u triangles", nf);
    }
    if (n > 0) {
        float clo[3], chi[3];
        range_bounds(p, 0, n, B.node[0].lo, B.node[0].hi, clo, chi);
        build(&B, 0, 0, n, 1, clo, chi);
    } else {
        /* nothing to hit: an empty leaf whose box no ray enters */
        box_empty(B.node[0].lo, B.node[0].hi);
        B.depth = 1;
    }
    if (B.depth > SSS_BVH_STACK) {
        free(p);
        free(B.node);
        sss_bvh_free(out);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "bvh: depth %u above the traversal stack of %d", B.depth,
                        SSS_BVH_STACK);
    }
    /* pad every box (sss/bvh.h) */
    if (n > 0) {
        const sss_bvh_node *r = &B.node[0];
        double d2 = 0;
        for (int k = 0; k < 3; k++) d2 += ((double)r->hi[k] - r->lo[k]) * ((double)r->hi[k] - r->lo[k]);
        const double pad = SSS_BVH_PAD * sqrt(d2) + 1e-30;
        for (uint32_t i = 0; i < B.nnode; i++)
            for (int k = 0; k < 3; k++) {
                B.node[i].lo[k] = (float)((double)B.node[i].lo[k] - pad);
                B.node[i].hi[k] = (float)((double)B.node[i].hi[k] + pad);
            }
    }
    /* the triangles in leaf order, as Embree's TriangleM holds them */
    for (uint32_t i = 0; i < n; i++) {
        const uint32_t *v = &tri[3 * (size_t)p[i].t];
        const float *a = &pos[3 * (size_t)v[0]], *b = &pos[3 * (size_t)v[1]], *c = &pos[3 * (size_t)v[2]];
        float *o = &out->tri[12 * (size_t)i];
        float e1[3], e2[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = a[k] - b[k];
            e2[k] = c[k] - a[k];
            o[k] = a[k];
            o[3 + k] = e1[k];
            o[6 + k] = e2[k];
        }
        /* Ng = cross(e2, e1), each component msub(x, y, z·w) = fma(x, y, −z·w) */
        o[9] = fmaf(e2[1], e1[2], -(e2[2] * e1[1]));
        o[10] = fmaf(e2[2], e1[0], -(e2[0] * e1[2]));
        o[11] = fmaf(e2[0], e1[1], -(e2[1] * e1[0]));
        out->prim[i] = p[i].t;
    }
    free(p);
    out->node = B.node;
    out->nnode = B.nnode;
    out->ntri = n;
    out->depth = B.depth;
    return SSS_OK;
}

/* Embree's vector products with its fused operations (sss/bvh.h). */
static void cross_f(const float a[3], const float b[3], float c[3])
{
    c[0] = fmaf(a[1], b[2], -(a[2] * b[1]));
    c[1] = fmaf(a[2], b[0], -(a[0] * b[2]));
    c[2] = fmaf(a[0], b[1], -(a[1] * b[0]));
}

static float dot_f(const float a[3], const float b[3]) { return fmaf(a[0], b[0], fmaf(a[1], b[1], a[2] * b[2])); }

/* Embree's Möller–Trumbore test up to the distance: 1 when the line
 * o + t d crosses the triangle, with t = *T / *abs_den. */
static int tri_cross(const float *t, const float o[3], const float d[3], float *T, float *abs_den)
{
    const float *v0 = t, *e1 = t + 3, *e2 = t + 6, *ng = t + 9;
    float C[3], R[3];
    for (int k = 0; k < 3; k++) C[k] = v0[k] - o[k];
    cross_f(C, d, R);
    const float den = dot_f(ng, d);
    *abs_den = fabsf(den);
    const float sg = signbit(den) ? -1.0f : 1.0f; /* Embree flips the sign bit: exact */
    const float U = sg * dot_f(R, e2), V = sg * dot_f(R, e1);
    if (!(den != 0.0f && U >= 0.0f && V >= 0.0f && U + V <= *abs_den)) return 0;
    *T = sg * dot_f(ng, C);
    return 1;
}

static int tri_hit(const float *t, const float o[3], const float d[3], float tnear)
{
    float T, abs_den;
    return tri_cross(t, o, d, &T, &abs_den) && abs_den * tnear < T;
}

/* 1/d per axis, a huge finite value for an axis the ray does not move
 * along (the slab test then keeps or rejects that axis whole). */
static void ray_inverse(const float d[3], float inv[3])
{
    for (int k = 0; k < 3; k++) inv[k] = fabsf(d[k]) > 1e-30f ? 1.0f / d[k] : 1e30f;
}

/* The slab test: the ray o + t d meets node nd's box for some t in
 * [0, tmax]. Both traversals use it, and near_vis.comp.glsl replays it
 * operation for operation. */
static int node_hit(const sss_bvh_node *nd, const float o[3], const float inv[3], float tmax)
{
    float tmin = 0.0f;
    for (int k = 0; k < 3; k++) {
        const float t0 = (nd->lo[k] - o[k]) * inv[k], t1 = (nd->hi[k] - o[k]) * inv[k];
        tmin = fmaxf(tmin, fminf(t0, t1));
        tmax = fminf(tmax, fmaxf(t0, t1));
    }
    return tmin <= tmax;
}

int sss_bvh_occluded(const sss_bvh *b, const float o[3], const float d[3], float tnear)
{
    if (!b->ntri) return 0;
    float inv[3];
    ray_inverse(d, inv);
    uint32_t stack[SSS_BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const sss_bvh_node *nd = &b->node[ni];
        if (node_hit(nd, o, inv, INFINITY)) {
            const uint32_t cnt = nd->b >> 2;
            if (cnt == 0) {
                const int far = d[nd->b & 3] < 0.0f; /* right child first when the ray runs downwards */
                stack[sp++] = nd->a + (uint32_t)!far;
                ni = nd->a + (uint32_t)far;
                continue;
            }
            for (uint32_t i = 0; i < cnt; i++)
                if (tri_hit(&b->tri[12 * (size_t)(nd->a + i)], o, d, tnear)) return 1;
        }
        if (sp == 0) return 0;
        ni = stack[--sp];
    }
}

float sss_bvh_nearest(const sss_bvh *b, const float o[3], const float d[3], float tnear, uint32_t *prim)
{
    float best = INFINITY;
    if (!b->ntri) return best;
    float inv[3];
    ray_inverse(d, inv);
    uint32_t stack[SSS_BVH_STACK];
    int sp = 0;
    uint32_t ni = 0;
    for (;;) {
        const sss_bvh_node *nd = &b->node[ni];
        if (node_hit(nd, o, inv, best)) {
            const uint32_t cnt = nd->b >> 2;
            if (cnt == 0) {
                const int far = d[nd->b & 3] < 0.0f;
                stack[sp++] = nd->a + (uint32_t)!far;
                ni = nd->a + (uint32_t)far;
                continue;
            }
            for (uint32_t i = 0; i < cnt; i++) {
                float T, abs_den;
                if (!tri_cross(&b->tri[12 * (size_t)(nd->a + i)], o, d, &T, &abs_den) || !(abs_den * tnear < T))
                    continue;
                const float t = T / abs_den;
                if (t < best) {
                    best = t;
                    if (prim) *prim = b->prim[nd->a + i];
                }
            }
        }
        if (sp == 0) return best;
        ni = stack[--sp];
    }
}

uint8_t sss_bvh_lit(const sss_bvh *b, const sss_mesh *mesh, float delta, uint32_t v, const double d[3])
{
    const float *x = &mesh->pos[3 * (size_t)v], *n = &mesh->nrm[3 * (size_t)v];
    /* the bake's facing test in double (float n, double ω), left to right */
    const double c = (double)n[0] * d[0] + (double)n[1] * d[1] + (double)n[2] * d[2];
    if (!(c > 0.0)) return 0;
    const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
    const float o[3] = {x[0] + delta * n[0], x[1] + delta * n[1], x[2] + delta * n[2]};
    return b->ntri == 0 || !sss_bvh_occluded(b, o, df, delta);
}
