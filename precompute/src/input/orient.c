/* orient.c: consistent, outward winding (docs/robustness.md B5). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

static int cmp_u64(const void *pa, const void *pb)
{
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return (a > b) - (a < b);
}

/* Edge k of triangle t runs tri[k] -> tri[(k+1)%3]. */
static int edge_of(const uint32_t *t, uint32_t lo, uint32_t hi, int *forward)
{
    for (int k = 0; k < 3; k++) {
        uint32_t a = t[k], b = t[(k + 1) % 3];
        if ((a == lo && b == hi) || (a == hi && b == lo)) {
            *forward = a == lo;
            return k;
        }
    }
    return -1;
}

#define NB_NONE UINT32_MAX

typedef struct comp_info {
    uint64_t nfaces, nflip;
    uint32_t seed;
    int closed;
    double volume;       /* 6 x signed volume, in the orientation relative to the seed */
    double lo[3], hi[3]; /* bounding box */
    int invert;          /* decision: reverse every flip of the component */
} comp_info;

/* Does the ray from o along d cross triangle (a, b, c)? Möller–Trumbore in
 * double, t > 0. */
static int ray_hits(const double o[3], const double d[3], const double a[3], const double b[3], const double c[3])
{
    double e1[3], e2[3], p[3], s[3], q[3];
    for (int k = 0; k < 3; k++) { e1[k] = b[k] - a[k]; e2[k] = c[k] - a[k]; s[k] = o[k] - a[k]; }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) return 0;
    double inv = 1.0 / det;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0.0 || u > 1.0) return 0;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (w < 0.0 || u + w > 1.0) return 0;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv > 0.0;
}

static void vpos(const sss_mesh *m, uint32_t v, double p[3])
{
    for (int k = 0; k < 3; k++) p[k] = m->pos[3 * (size_t)v + k];
}

/* Makes the winding consistent and outward (B5: normals follow the winding
 * and shadow rays start along them, so an inside-out cube baked q = 0 and a
 * sphere with half its triangles flipped lost 60 % of its mean q).
 *
 * Triangles are grouped into surfaces (connected through manifold edges:
 * exactly two triangles); a breadth-first walk from each surface's first
 * triangle flips its neighbours to agree with it. A closed surface (every
 * edge manifold and consistent) is then turned outward by its signed
 * volume: a negative one is inverted, unless it lies inside another closed
 * surface (ray parity), where it may be a cavity (a hollow shell's inner
 * wall faces inward) or a solid inside a solid, which the file must decide.
 * An open surface keeps the winding of the majority of its triangles (ties:
 * its first triangle's). Edges still inconsistent afterwards (a
 * non-orientable surface) are counted for a warning. A consistently wound,
 * outward mesh is left as it is. */
sss_result sss_orient(const char *name, sss_mesh *m, sss_import_report *rep, sss_error *err)
{
    const uint32_t nv = m->nv, nf = m->nf;
    const uint32_t *tri = m->tri;
    uint64_t *bstart = calloc((size_t)nv + 2, sizeof *bstart);
    uint64_t *he = malloc(3 * (size_t)nf * sizeof *he + 1);
    uint32_t *nb = malloc(3 * (size_t)nf * sizeof *nb + 1);
    unsigned char *same = calloc(3 * (size_t)nf + 1, 1);
    if (!bstart || !he || !nb || !same) {
        free(bstart); free(he); free(nb); free(same);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the edges of %u triangles", name, nf);
    }
    /* Half-edges bucketed by their smaller vertex, sorted by (larger
     * vertex, triangle): equal edges end up adjacent, in triangle order. */
    for (size_t i = 0; i < 3 * (size_t)nf; i++) {
        uint32_t a = tri[i], b = tri[i % 3 == 2 ? i - 2 : i + 1];
        bstart[(a < b ? a : b) + 2]++;
    }
    for (size_t v = 2; v < (size_t)nv + 2; v++) bstart[v] += bstart[v - 1];
    for (size_t i = 0; i < 3 * (size_t)nf; i++) {
        uint32_t a = tri[i], b = tri[i % 3 == 2 ? i - 2 : i + 1];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        he[bstart[lo + 1]++] = (uint64_t)hi << 32 | (uint64_t)(i / 3);
    }
    for (size_t i = 0; i < 3 * (size_t)nf; i++) nb[i] = NB_NONE;
    for (uint32_t lo = 0; lo < nv; lo++) {
        uint64_t b0 = bstart[lo], b1 = bstart[lo + 1];
        if (b1 - b0 > 1) qsort(he + b0, (size_t)(b1 - b0), sizeof *he, cmp_u64);
        for (uint64_t i = b0; i < b1;) {
            uint64_t j = i + 1;
            while (j < b1 && he[j] >> 32 == he[i] >> 32) j++;
            if (j - i == 2) { /* manifold edge: exactly two triangles */
                uint32_t hi = (uint32_t)(he[i] >> 32), f = (uint32_t)he[i], g = (uint32_t)he[i + 1];
                int ff = 0, fg = 0;
                int kf = edge_of(tri + 3 * (size_t)f, lo, hi, &ff), kg = edge_of(tri + 3 * (size_t)g, lo, hi, &fg);
                nb[3 * (size_t)f + (size_t)kf] = g;
                nb[3 * (size_t)g + (size_t)kg] = f;
                /* same direction in both: they disagree as stored */
                same[3 * (size_t)f + (size_t)kf] = same[3 * (size_t)g + (size_t)kg] = ff == fg;
            }
            i = j;
        }
    }
    free(he);
    free(bstart);

    uint32_t *comp = malloc((size_t)nf * sizeof *comp + 1);
    uint32_t *queue = malloc((size_t)nf * sizeof *queue + 1);
    unsigned char *flip = calloc((size_t)nf + 1, 1);
    size_t ccap = 16, ncomp = 0;
    comp_info *ci = malloc(ccap * sizeof *ci);
    uint32_t *cstart = NULL, *cface = queue;
    sss_result r = SSS_OK;
    if (!comp || !queue || !flip || !ci) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces of %u triangles", name, nf);
        goto done;
    }
    for (uint32_t f = 0; f < nf; f++) comp[f] = NB_NONE;
    for (uint32_t seed = 0; seed < nf; seed++) {
        if (comp[seed] != NB_NONE) continue;
        if (ncomp == ccap) {
            comp_info *nc = realloc(ci, 2 * ccap * sizeof *ci);
            if (!nc) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces", name); goto done; }
            ci = nc;
            ccap *= 2;
        }
        comp_info *c = &ci[ncomp];
        memset(c, 0, sizeof *c);
        c->seed = seed;
        c->closed = 1;
        uint32_t qh = 0, qt = 0;
        queue[qt++] = seed;
        comp[seed] = (uint32_t)ncomp;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            for (int k = 0; k < 3; k++) {
                uint32_t g = nb[3 * (size_t)f + (size_t)k];
                if (g == NB_NONE) { c->closed = 0; continue; }
                unsigned char want = flip[f] ^ same[3 * (size_t)f + (size_t)k];
                if (comp[g] == NB_NONE) {
                    comp[g] = (uint32_t)ncomp;
                    flip[g] = want;
                    queue[qt++] = g;
                } else if (flip[g] != want) {
                    c->closed = 0; /* non-orientable */
                }
            }
        }
        c->nfaces = qt;
        double ref[3];
        vpos(m, tri[3 * (size_t)seed], ref);
        for (int k = 0; k < 3; k++) { c->lo[k] = INFINITY; c->hi[k] = -INFINITY; }
        for (uint32_t i = 0; i < qt; i++) {
            uint32_t f = queue[i];
            c->nflip += flip[f];
            double p[3][3];
            for (int j = 0; j < 3; j++) {
                vpos(m, tri[3 * (size_t)f + (size_t)j], p[j]);
                for (int k = 0; k < 3; k++) {
                    if (p[j][k] < c->lo[k]) c->lo[k] = p[j][k];
                    if (p[j][k] > c->hi[k]) c->hi[k] = p[j][k];
                    p[j][k] -= ref[k];
                }
            }
            if (c->closed) {
                double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                             p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                             p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
                c->volume += flip[f] ? -det : det;
            }
        }
        ncomp++;
    }

    /* Closed surfaces facing inward; the faces of each surface, for their
     * containment test. */
    uint64_t nneg = 0;
    for (size_t i = 0; i < ncomp; i++) nneg += ci[i].closed && ci[i].volume < 0.0;
    if (nneg) {
        cstart = calloc(ncomp + 2, sizeof *cstart);
        if (!cstart) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces", name); goto done; }
        for (uint32_t f = 0; f < nf; f++) cstart[comp[f] + 2]++;
        for (size_t i = 2; i < ncomp + 2; i++) cstart[i] += cstart[i - 1];
        for (uint32_t f = 0; f < nf; f++) cface[cstart[comp[f] + 1]++] = f;
    }
    /* The containment test costs a bounding-box check per pair of
     * surfaces and a ray test per triangle of each candidate container:
     * beyond 2^26 pairs or 2^28 triangle tests in all (thousands of
     * inside-out parts in a large closed one) the remaining negative
     * surfaces are taken as not nested, so the work stays bounded. */
    const int test_nesting = nneg * (uint64_t)ncomp <= ((uint64_t)1 << 26);
    uint64_t ray_budget = (uint64_t)1 << 28;
    /* A direction no axis-aligned mesh lines up with. */
    const double dir[3] = {0.5376, 0.6812, 0.4968};
    for (size_t i = 0; i < ncomp; i++) {
        comp_info *c = &ci[i];
        if (!c->closed || c->volume == 0.0) {
            c->invert = 2 * c->nflip > c->nfaces; /* open: the majority's winding */
            continue;
        }
        if (c->volume > 0.0) continue; /* outward */
        int nested = 0;
        if (test_nesting && ray_budget > 0) {
            /* the centroid of the seed triangle, in the final positions */
            double o[3] = {0.0, 0.0, 0.0}, p[3];
            for (int j = 0; j < 3; j++) {
                vpos(m, tri[3 * (size_t)c->seed + (size_t)j], p);
                for (int k = 0; k < 3; k++) o[k] += p[k] / 3.0;
            }
            for (size_t e = 0; e < ncomp && !nested; e++) {
                const comp_info *d = &ci[e];
                if (e == i || !d->closed) continue;
                int inside_box = 1;
                for (int k = 0; k < 3; k++) inside_box &= d->lo[k] <= c->lo[k] && c->hi[k] <= d->hi[k];
                if (!inside_box) continue;
                uint64_t len = cstart[e + 1] - cstart[e];
                if (len > ray_budget) { ray_budget = 0; break; }
                ray_budget -= len;
                uint64_t hits = 0;
                for (uint32_t q = cstart[e]; q < cstart[e + 1]; q++) {
                    const uint32_t *t = tri + 3 * (size_t)cface[q];
                    double a[3], b[3], cc[3];
                    vpos(m, t[0], a); vpos(m, t[1], b); vpos(m, t[2], cc);
                    hits += (uint64_t)ray_hits(o, dir, a, b, cc);
                }
                nested = hits % 2 == 1;
            }
        }
        c->invert = !nested;
    }
    /* Apply; count. */
    uint32_t *t = m->tri;
    for (uint32_t f = 0; f < nf; f++) {
        const comp_info *c = &ci[comp[f]];
        if (!(flip[f] ^ (unsigned char)c->invert)) continue;
        uint32_t x = t[3 * (size_t)f + 1];
        t[3 * (size_t)f + 1] = t[3 * (size_t)f + 2];
        t[3 * (size_t)f + 2] = x;
        if (c->closed) rep->faces_flipped++;
        else rep->open_faces_flipped++;
    }
    for (size_t i = 0; i < ncomp; i++) {
        const comp_info *c = &ci[i];
        uint64_t final_flips = c->invert ? c->nfaces - c->nflip : c->nflip;
        if (c->closed && 2 * final_flips > c->nfaces) rep->surfaces_inside_out++;
    }
    /* Manifold edges whose triangles disagree after all (each edge once). */
    for (uint32_t f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t g = nb[3 * (size_t)f + (size_t)k];
            if (g == NB_NONE || g < f) continue;
            unsigned char ef = flip[f] ^ (unsigned char)ci[comp[f]].invert;
            unsigned char eg = flip[g] ^ (unsigned char)ci[comp[g]].invert;
            if ((ef ^ eg) != same[3 * (size_t)f + (size_t)k]) rep->orientation_conflicts++;
        }
done:
    free(cstart);
    free(nb);
    free(same);
    free(comp);
    free(queue);
    free(flip);
    free(ci);
    return r;
}
