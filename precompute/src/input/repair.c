/* repair.c: the reader's polygon soup into a mesh: finite coordinates,
 * indices in range, recentring far meshes (docs/robustness.md B6),
 * polygons triangulated (fan or ear clipping, B7), degenerate and
 * duplicate faces dropped (B5), unreferenced vertices removed; then the
 * orientation (orient.c) and the normals and areas. */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"
#include "sss/vec3.h"

#include <math.h>

static int zero_area(const float *pos, uint32_t a, uint32_t b, uint32_t c)
{
    const float *p0 = pos + 3 * (size_t)a, *p1 = pos + 3 * (size_t)b, *p2 = pos + 3 * (size_t)c;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p1[k] - (double)p0[k];
        e2[k] = (double)p2[k] - (double)p0[k];
    }
    double x = e1[1] * e2[2] - e1[2] * e2[1];
    double y = e1[2] * e2[0] - e1[0] * e2[2];
    double z = e1[0] * e2[1] - e1[1] * e2[0];
    return x == 0.0 && y == 0.0 && z == 0.0;
}

static int has_repeat(const int32_t *v, uint32_t n, sll *scratch)
{
    if (n <= 32) {
        for (uint32_t i = 1; i < n; i++)
            for (uint32_t j = 0; j < i; j++)
                if (v[i] == v[j]) return 1;
        return 0;
    }
    for (uint32_t i = 0; i < n; i++) scratch[i] = v[i];
    return sss_count_distinct(scratch, n) != n;
}

/* ---------------------------------------------------------------------------
 * Recentring (docs/robustness.md B6)
 * ------------------------------------------------------------------------- */

/* A mesh whose bounding-box centre c lies farther from the origin than
 * RECENTRE_RATIO times its half-size h (largest half-extent) is moved by -c,
 * in double, before its positions become float32. float32 spacing at |x| is
 * |x|·2^-23; the bake starts shadow rays 1e-5 of the bounding-box diagonal
 * (>= 2e-5·h) off the surface (visibility.c), which at |c| = 16h is still
 * about 10 float steps. Nearer meshes keep their coordinates, so their bakes
 * stay byte-identical; farther ones lost triangles to rounding and shadowed
 * themselves (a unit sphere at 10^6: spacing 1/16, 9,152 of 16,128 triangles
 * collapsed, 15 % of rays blocked). */
#define RECENTRE_RATIO 16.0

/* used[v] != UINT32_MAX marks the vertices that faces of 3 or more corners
 * use; only those decide the box and move: they lie within h of c, so the
 * result is finite; the others are removed later anyway. */
static void recentre(sss_om_soup *s, const expect *ex, const uint32_t *used, sss_import_report *rep)
{
    ull nv = s->nv;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (ull v = 0; v < nv; v++) {
        if (used[v] == UINT32_MAX) continue;
        for (int k = 0; k < 3; k++) {
            double x = ex->dpos ? ex->dpos[3 * v + (ull)k] : (double)s->pos[3 * v + (ull)k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    }
    double c[3], h = 0.0, cmax = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!(lo[k] <= hi[k])) return; /* no face uses a vertex */
        double half = 0.5 * (hi[k] - lo[k]);
        c[k] = lo[k] + half;
        if (half > h) h = half;
        if (fabs(c[k]) > cmax) cmax = fabs(c[k]);
    }
    if (!(h > 0.0) || cmax <= RECENTRE_RATIO * h) return;
    for (ull v = 0; v < nv; v++) {
        if (used[v] == UINT32_MAX) continue;
        for (int k = 0; k < 3; k++) {
            double x = ex->dpos ? ex->dpos[3 * v + (ull)k] : (double)s->pos[3 * v + (ull)k];
            s->pos[3 * v + (ull)k] = (float)(x - c[k]);
        }
    }
    rep->recentred = 1;
    for (int k = 0; k < 3; k++) rep->offset[k] = c[k];
}

/* ---------------------------------------------------------------------------
 * Polygon triangulation (docs/robustness.md B7)
 * ------------------------------------------------------------------------- */

typedef struct poly_scratch {
    double *xy;       /* 2 per corner: coordinates in the polygon's plane */
    uint32_t *prev, *next, *reflex;
    unsigned char *is_reflex;
    /* Ear clipping is cubic at worst (a full pass per ear, every reflex
     * corner tested): the steps a mesh may spend on it in all are capped so
     * that a hostile file (thousands of jagged polygons) still imports in
     * bounded time; past the cap, polygons are fanned and warned. Reset
     * before each pass so both passes decide alike. */
    uint64_t budget;
} poly_scratch;

#define EAR_BUDGET ((uint64_t)1 << 28)

static void poly_scratch_free(poly_scratch *sc)
{
    free(sc->xy); free(sc->prev); free(sc->next); free(sc->reflex); free(sc->is_reflex);
    memset(sc, 0, sizeof *sc);
}

static int poly_scratch_alloc(poly_scratch *sc, uint32_t n)
{
    memset(sc, 0, sizeof *sc);
    if (n <= 3) return 1;
    size_t m = n < SSS_IMPORT_EAR_MAX ? n : SSS_IMPORT_EAR_MAX;
    sc->xy = malloc(2 * (size_t)n * sizeof(double));
    sc->prev = malloc(m * sizeof(uint32_t));
    sc->next = malloc(m * sizeof(uint32_t));
    sc->reflex = malloc(m * sizeof(uint32_t));
    sc->is_reflex = malloc(m);
    if (sc->xy && sc->prev && sc->next && sc->reflex && sc->is_reflex) return 1;
    poly_scratch_free(sc);
    return 0;
}

enum { POLY_FAN = 0, POLY_EAR, POLY_UNCLIPPED };

static double cross2(const double *xy, uint32_t a, uint32_t b, uint32_t c)
{
    return (xy[2 * b] - xy[2 * a]) * (xy[2 * c + 1] - xy[2 * a + 1]) -
           (xy[2 * b + 1] - xy[2 * a + 1]) * (xy[2 * c] - xy[2 * a]);
}

/* Corner b of the remaining polygon (a, b, c consecutive) is an ear: a left
 * turn, and no reflex corner lies inside or on the triangle (a convex
 * corner cannot lie in it unless a reflex one does). Corners at the same
 * position as a, b or c are not in the way. */
static int is_ear(const poly_scratch *sc, uint32_t nreflex, uint32_t a, uint32_t b, uint32_t c)
{
    const double *xy = sc->xy;
    if (!(cross2(xy, a, b, c) > 0.0)) return 0;
    for (uint32_t r = 0; r < nreflex; r++) {
        uint32_t p = sc->reflex[r];
        if (!sc->is_reflex[p] || p == a || p == b || p == c) continue;
        int same = 0;
        for (int k = 0; k < 3 && !same; k++) {
            uint32_t q = k == 0 ? a : k == 1 ? b : c;
            same = xy[2 * p] == xy[2 * q] && xy[2 * p + 1] == xy[2 * q + 1];
        }
        if (same) continue;
        if (cross2(xy, a, b, p) >= 0.0 && cross2(xy, b, c, p) >= 0.0 && cross2(xy, c, a, p) >= 0.0) return 0;
    }
    return 1;
}

/* Triangulates polygon v[0..n), n > 3, into n - 2 triangles whose corners
 * (positions 0..n-1 in v) go to tri, 3 each, in the polygon's winding.
 *
 * A convex polygon (every turn to the left of its best-fit plane's normal,
 * once around) is fanned from corner 0, as every polygon was before, so
 * existing meshes import unchanged. The fan of a non-convex polygon folds
 * over: a triangle comes out flipped and overlapping the others (B7: an
 * L-shaped hexagon of area 3 gave areas -0.5, 0.5, 2, 1). Those are
 * ear-clipped instead, in the plane of the Newell normal (the polygon's
 * plane if it is planar, a best fit if it is warped). Returns POLY_FAN,
 * POLY_EAR, or POLY_UNCLIPPED when no ear is left (a self-intersecting
 * polygon), the polygon has more than SSS_IMPORT_EAR_MAX corners, or the
 * mesh's ear-clipping budget is spent: what remains is fanned. */
static int triangulate(const float *pos, const int32_t *v, uint32_t n, poly_scratch *sc, uint32_t *tri)
{
#define P(i, k) ((double)pos[3 * (size_t)v[i] + (k)] - (double)pos[3 * (size_t)v[0] + (k)])
    double N[3] = {0.0, 0.0, 0.0};
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = i + 1 == n ? 0 : i + 1;
        N[0] += (P(i, 1) - P(j, 1)) * (P(i, 2) + P(j, 2));
        N[1] += (P(i, 2) - P(j, 2)) * (P(i, 0) + P(j, 0));
        N[2] += (P(i, 0) - P(j, 0)) * (P(i, 1) + P(j, 1));
    }
    double len = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
    int status = POLY_FAN;
    if (len > 0.0 && isfinite(len)) {
        for (int k = 0; k < 3; k++) N[k] /= len;
        /* u, w, N right-handed: u x w = N, so the polygon's winding is
         * counter-clockwise (positive area) in (u, w). */
        int ax = fabs(N[0]) <= fabs(N[1]) && fabs(N[0]) <= fabs(N[2]) ? 0 : fabs(N[1]) <= fabs(N[2]) ? 1 : 2;
        double e[3] = {0.0, 0.0, 0.0}, u[3], w[3];
        e[ax] = 1.0;
        u[0] = e[1] * N[2] - e[2] * N[1];
        u[1] = e[2] * N[0] - e[0] * N[2];
        u[2] = e[0] * N[1] - e[1] * N[0];
        double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int k = 0; k < 3; k++) u[k] /= ul;
        w[0] = N[1] * u[2] - N[2] * u[1];
        w[1] = N[2] * u[0] - N[0] * u[2];
        w[2] = N[0] * u[1] - N[1] * u[0];
        double *xy = sc->xy;
        for (uint32_t i = 0; i < n; i++) {
            xy[2 * i] = P(i, 0) * u[0] + P(i, 1) * u[1] + P(i, 2) * u[2];
            xy[2 * i + 1] = P(i, 0) * w[0] + P(i, 1) * w[1] + P(i, 2) * w[2];
        }
        /* Convex: no right turn between successive edges of non-zero length
         * (a tolerance of 1e-12 relative keeps nearly straight corners
         * convex), and the turns add up to one full turn (a star polygon
         * turns left everywhere but twice around). */
        int convex = 1, nedges = 0;
        double turning = 0.0, first[2] = {0.0, 0.0}, last[2] = {0.0, 0.0};
        for (uint32_t i = 0; i < n && convex; i++) {
            uint32_t j = i + 1 == n ? 0 : i + 1;
            double d[2] = {xy[2 * j] - xy[2 * i], xy[2 * j + 1] - xy[2 * i + 1]};
            if (d[0] == 0.0 && d[1] == 0.0) continue;
            if (nedges++ == 0) {
                first[0] = d[0]; first[1] = d[1];
            } else {
                double cr = last[0] * d[1] - last[1] * d[0], dt = last[0] * d[0] + last[1] * d[1];
                if (cr < -1e-12 * hypot(last[0], last[1]) * hypot(d[0], d[1])) convex = 0;
                turning += atan2(cr, dt);
            }
            last[0] = d[0]; last[1] = d[1];
        }
        if (convex && nedges >= 3) {
            double cr = last[0] * first[1] - last[1] * first[0], dt = last[0] * first[0] + last[1] * first[1];
            if (cr < -1e-12 * hypot(last[0], last[1]) * hypot(first[0], first[1])) convex = 0;
            turning += atan2(cr, dt);
            if (fabs(turning - 2.0 * SSS_PI) > 1e-3) convex = 0;
        }
        if (!convex) status = n > SSS_IMPORT_EAR_MAX ? POLY_UNCLIPPED : POLY_EAR;
    }
#undef P
    uint32_t t = 0;
    if (status == POLY_EAR) {
        uint32_t *prev = sc->prev, *next = sc->next, nreflex = 0;
        for (uint32_t i = 0; i < n; i++) {
            prev[i] = i == 0 ? n - 1 : i - 1;
            next[i] = i + 1 == n ? 0 : i + 1;
        }
        for (uint32_t i = 0; i < n; i++) {
            sc->is_reflex[i] = !(cross2(sc->xy, prev[i], i, next[i]) > 0.0);
            if (sc->is_reflex[i]) sc->reflex[nreflex++] = i;
        }
        uint32_t m = n, cur = 0, stall = 0;
        while (m > 3) {
            uint32_t a = prev[cur], c = next[cur];
            if (sc->budget <= (uint64_t)nreflex + 1) { sc->budget = 0; status = POLY_UNCLIPPED; break; }
            sc->budget -= (uint64_t)nreflex + 1;
            if (is_ear(sc, nreflex, a, cur, c)) {
                tri[3 * t] = a; tri[3 * t + 1] = cur; tri[3 * t + 2] = c;
                t++;
                next[a] = c;
                prev[c] = a;
                sc->is_reflex[cur] = 0;
                m--;
                /* Clipping an ear can only make its neighbours convex. */
                if (sc->is_reflex[a] && cross2(sc->xy, prev[a], a, c) > 0.0) sc->is_reflex[a] = 0;
                if (sc->is_reflex[c] && cross2(sc->xy, a, c, next[c]) > 0.0) sc->is_reflex[c] = 0;
                cur = c;
                stall = 0;
            } else {
                cur = c;
                if (++stall >= m) { status = POLY_UNCLIPPED; break; }
            }
        }
        if (status == POLY_EAR) {
            tri[3 * t] = prev[cur]; tri[3 * t + 1] = cur; tri[3 * t + 2] = next[cur];
            return POLY_EAR;
        }
        /* No ear: fan what is left from cur. */
        for (uint32_t b = next[cur]; next[b] != cur; b = next[b]) {
            tri[3 * t] = cur; tri[3 * t + 1] = b; tri[3 * t + 2] = next[b];
            t++;
        }
        return POLY_UNCLIPPED;
    }
    for (uint32_t k = 1; k + 1 < n; k++) {
        tri[3 * t] = 0; tri[3 * t + 1] = k; tri[3 * t + 2] = k + 1;
        t++;
    }
    return status;
}

/* ---------------------------------------------------------------------------
 * Duplicate triangles and orientation (docs/robustness.md B5)
 * ------------------------------------------------------------------------- */

typedef struct tri_key {
    uint32_t v[3]; /* sorted */
    uint32_t f;
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    return (a->f > b->f) - (a->f < b->f);
}

/* Drops every triangle on the same three vertices as an earlier one (in
 * either winding). Copies add their area to the vertices twice (B5: mean q
 * +40 %), and an opposite-winding copy cancels the vertex normals (q = 0
 * everywhere). The first one stays; the orientation pass then decides its
 * winding. */
static sss_result drop_duplicates(const char *name, sss_mesh *m, sss_import_report *rep, sss_error *err)
{
    tri_key *key = malloc((size_t)m->nf * sizeof *key + 1);
    unsigned char *dup = calloc((size_t)m->nf + 1, 1);
    if (!key || !dup) {
        free(key); free(dup);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %u triangles", name, m->nf);
    }
    for (uint32_t f = 0; f < m->nf; f++) {
        uint32_t a = m->tri[3 * (size_t)f], b = m->tri[3 * (size_t)f + 1], c = m->tri[3 * (size_t)f + 2], x;
        if (a > b) { x = a; a = b; b = x; }
        if (b > c) { x = b; b = c; c = x; }
        if (a > b) { x = a; a = b; b = x; }
        key[f] = (tri_key){{a, b, c}, f};
    }
    qsort(key, m->nf, sizeof *key, cmp_tri_key);
    uint64_t ndup = 0;
    for (uint32_t i = 1; i < m->nf; i++)
        if (memcmp(key[i].v, key[i - 1].v, sizeof key[i].v) == 0) {
            dup[key[i].f] = 1;
            ndup++;
        }
    free(key);
    if (ndup) {
        uint32_t t = 0;
        for (uint32_t f = 0; f < m->nf; f++)
            if (!dup[f]) {
                memmove(m->tri + 3 * (size_t)t, m->tri + 3 * (size_t)f, 3 * sizeof(uint32_t));
                t++;
            }
        m->nf = t;
    }
    free(dup);
    rep->faces_duplicate = ndup;
    return SSS_OK;
}

sss_result sss_soup_to_mesh(const char *name, sss_om_soup *s, const expect *ex, sss_mesh *out, sss_import_report *rep,
                             sss_error *err)
{
    ull nv = s->nv;
    rep->vertices_read = nv;
    rep->faces_read = ex->faces_in_file;
    rep->faces_too_small = ex->too_small;
    rep->faces_repeated_index = ex->repeated;
    rep->unknown_statements = ex->unknown;
    memcpy(rep->first_unknown, ex->first_unknown, sizeof rep->first_unknown);
    rep->first_unknown_line = ex->first_unknown_line;
    rep->primitives_skipped = ex->skipped;
    rep->texcoords = s->uv != NULL;
    rep->colours = s->rgba != NULL;
    if (nv > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu vertices; at most 4294967294 are supported", name, nv);
    for (ull v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(s->pos[3 * v + (ull)k]))
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite", name, v);
    /* remap first marks (0) the vertices faces of 3 or more corners use,
     * for recentre; pass 1 below marks the ones kept. */
    uint32_t *remap = malloc(((size_t)nv + 1) * sizeof *remap);
    if (!remap) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", name, nv);
    for (ull v = 0; v < nv; v++) remap[v] = UINT32_MAX;
    uint32_t maxn = 0;
    {
        ull off = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            if (n > maxn) maxn = n;
            for (uint32_t i = 0; i < n; i++) {
                int32_t v = s->idx[off + i];
                if (v < 0 || (ull)v >= nv) {
                    free(remap);
                    return sss_fail(err, SSS_ERR_MESH, "%s: face %llu: vertex index %d out of range [0, %llu)", name, f, v, nv);
                }
                if (n >= 3) remap[v] = 0;
            }
            off += n;
        }
    }
    recentre(s, ex, remap, rep);
    sll *scratch = maxn > 32 ? malloc((size_t)maxn * sizeof *scratch) : NULL;
    uint32_t *ptri = maxn > 3 ? malloc(3 * ((size_t)maxn - 2) * sizeof *ptri) : NULL;
    poly_scratch ps;
    int ps_ok = poly_scratch_alloc(&ps, maxn);
    if ((maxn > 32 && !scratch) || (maxn > 3 && !ptri) || !ps_ok) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", name, nv);
    }
    for (ull v = 0; v < nv; v++) remap[v] = UINT32_MAX;

    /* Pass 1: classify faces, count triangles, mark the vertices kept. */
    ull ntri = 0;
    ps.budget = EAR_BUDGET;
    {
        ull off = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            const int32_t *v = s->idx + off;
            off += n;
            if (ex->drop && ex->drop[f]) continue; /* counted by the scan */
            if (n < 3) { rep->faces_too_small++; continue; }
            if (has_repeat(v, n, scratch)) { rep->faces_repeated_index++; continue; }
            static const uint32_t one[3] = {0, 1, 2};
            const uint32_t *pt = one;
            if (n > 3) {
                rep->polygons_triangulated++;
                int how = triangulate(s->pos, v, n, &ps, ptri);
                rep->polygons_ear_clipped += how == POLY_EAR;
                rep->polygons_unclipped += how == POLY_UNCLIPPED;
                pt = ptri;
            }
            for (uint32_t k = 0; k + 2 < n; k++) {
                uint32_t a = (uint32_t)v[pt[3 * k]], b = (uint32_t)v[pt[3 * k + 1]], c = (uint32_t)v[pt[3 * k + 2]];
                if (zero_area(s->pos, a, b, c)) {
                    rep->faces_zero_area++;
                    continue;
                }
                ntri++;
                remap[a] = remap[b] = remap[c] = 0;
            }
        }
    }
    if (ntri == 0) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_MESH, "%s: no triangles left after repair (%llu faces read)", name, ex->faces_in_file);
    }
    if (ntri > UINT32_MAX) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu triangles; at most 4294967295 are supported", name, ntri);
    }
    uint32_t nv2 = 0;
    for (ull v = 0; v < nv; v++)
        if (remap[v] == 0) remap[v] = nv2++;
    rep->vertices_unreferenced = nv - nv2;

    sss_result r = sss_mesh_alloc(out, nv2, (uint32_t)ntri, err);
    if (r != SSS_OK) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return r;
    }
    /* what an asset carries besides positions follows its vertex through
     * the renumbering (sss/mesh.h) */
    if (s->uv && !(out->uv = malloc(2 * (size_t)nv2 * sizeof(float) + 1))) r = SSS_ERR_NOMEM;
    if (s->rgba && !(out->rgba = malloc(4 * (size_t)nv2 * sizeof(float) + 1))) r = SSS_ERR_NOMEM;
    if (r != SSS_OK) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps); sss_mesh_free(out);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %u vertices", name, nv2);
    }
    for (ull v = 0; v < nv; v++)
        if (remap[v] != UINT32_MAX) {
            memcpy(out->pos + 3 * (size_t)remap[v], s->pos + 3 * v, 3 * sizeof(float));
            if (out->uv) memcpy(out->uv + 2 * (size_t)remap[v], s->uv + 2 * v, 2 * sizeof(float));
            if (out->rgba) memcpy(out->rgba + 4 * (size_t)remap[v], s->rgba + 4 * v, 4 * sizeof(float));
        }

    /* Pass 2: the same decisions, writing the triangles. */
    ps.budget = EAR_BUDGET;
    {
        ull off = 0, t = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            const int32_t *v = s->idx + off;
            off += n;
            if ((ex->drop && ex->drop[f]) || n < 3 || has_repeat(v, n, scratch)) continue;
            static const uint32_t one[3] = {0, 1, 2};
            const uint32_t *pt = one;
            if (n > 3) {
                triangulate(s->pos, v, n, &ps, ptri);
                pt = ptri;
            }
            for (uint32_t k = 0; k + 2 < n; k++) {
                uint32_t a = (uint32_t)v[pt[3 * k]], b = (uint32_t)v[pt[3 * k + 1]], c = (uint32_t)v[pt[3 * k + 2]];
                if (zero_area(s->pos, a, b, c)) continue;
                out->tri[3 * t + 0] = remap[a];
                out->tri[3 * t + 1] = remap[b];
                out->tri[3 * t + 2] = remap[c];
                t++;
            }
        }
    }
    free(scratch);
    free(remap);
    free(ptri);
    poly_scratch_free(&ps);
    r = drop_duplicates(name, out, rep, err);
    if (r == SSS_OK) r = sss_orient(name, out, rep, err);
    if (r == SSS_OK) r = sss_mesh_compute_normals_areas(out, name, err);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}
