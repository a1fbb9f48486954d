/* nearterms.c: the vertex's own term of q, split off at bake time and added
 * back at run time (sss/nearterms.h; Hao–Varshney 2004 §3.1). */
#include "sss/nearterms.h"
#include "sss/fieldweights.h"
#include "sss/hatweights.h"
#include "sss/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

float sss_near_g(float eta, const float n[3], const float d[3])
{
    /* F_t(η, c) max(0, c): the Fresnel transmittance of dipole.c's
     * sss_ft, in float, term for term as the vertex shader writes it */
    float c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    if (!(c > 0.0f)) return 0.0f;
    if (c > 1.0f) c = 1.0f;
    float g2 = eta * eta - 1.0f + c * c;
    if (g2 < 0.0f) return 0.0f;
    float g = sqrtf(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    float fr = fminf(0.5f * a * a * (1.0f + b * b), 1.0f);
    return (1.0f - fr) * c;
}

/* ---- near terms: own term and mesh rings --------------------------------- */

/* ‖x_i − x_o‖ in mm, with nbhd.c's arithmetic */
static double dist_mm(const sss_mesh *m, uint32_t o, uint32_t i, double s)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        const double dx = ((double)m->pos[3 * (size_t)i + k] - m->pos[3 * (size_t)o + k]) * s;
        d2 += dx * dx;
    }
    return sqrt(d2);
}

/* The radius's grid: cells as wide as the radius, 21 bits per axis (a
 * radius below 2^-21 of the object's size gets the outermost cells merged,
 * which only widens the search). */
#define VGRID_MAX ((int64_t)(1 << 21) - 1)

typedef struct vkey_entry {
    uint64_t key;
    uint32_t v;
} vkey_entry;

static uint64_t vkey(int64_t x, int64_t y, int64_t z) { return (uint64_t)x << 42 | (uint64_t)y << 21 | (uint64_t)z; }

static void cell3(const sss_mesh *m, uint32_t v, double s, const double lo[3], double cell, int64_t c[3])
{
    for (int k = 0; k < 3; k++) {
        const double f = floor(((double)m->pos[3 * (size_t)v + k] * s - lo[k]) / cell);
        c[k] = f < 0.0 ? 0 : f > (double)VGRID_MAX ? VGRID_MAX : (int64_t)f;
    }
}

static int cmp_vkey(const void *x, const void *y)
{
    const vkey_entry *a = x, *b = y;
    if (a->key != b->key) return a->key < b->key ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* The vertices sorted by (cell, index) in a grid of cells `cell` mm wide
 * whose corner is the mesh's lowest point. */
typedef struct vgrid {
    vkey_entry *e; /* nv entries */
    double lo[3], cell;
} vgrid;

/* 0 when out of memory. */
static int vgrid_build(vgrid *g, const sss_mesh *m, double s, double cell)
{
    const uint32_t nv = m->nv;
    g->cell = cell;
    g->e = malloc((size_t)nv * sizeof *g->e + 1);
    if (!g->e) return 0;
    for (int k = 0; k < 3; k++) g->lo[k] = INFINITY;
    for (uint32_t v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++) g->lo[k] = fmin(g->lo[k], (double)m->pos[3 * (size_t)v + k] * s);
    for (uint32_t v = 0; v < nv; v++) {
        int64_t c[3];
        cell3(m, v, s, g->lo, cell, c);
        g->e[v].key = vkey(c[0], c[1], c[2]);
        g->e[v].v = v;
    }
    qsort(g->e, nv, sizeof *g->e, cmp_vkey);
    return 1;
}

/* Every vertex within r ≤ g->cell mm of x_o (o itself included) into hits,
 * in the grid's order, from the 27 cells around x_o; returns their count. */
static uint32_t vgrid_within(const vgrid *g, const sss_mesh *m, double s, uint32_t o, double r, uint32_t *hits)
{
    const uint32_t nv = m->nv;
    uint32_t n = 0;
    int64_t c0[3];
    cell3(m, o, s, g->lo, g->cell, c0);
    for (int64_t dx = -1; dx <= 1; dx++)
        for (int64_t dy = -1; dy <= 1; dy++)
            for (int64_t dz = -1; dz <= 1; dz++) {
                const int64_t cx = c0[0] + dx, cy = c0[1] + dy, cz = c0[2] + dz;
                if (cx < 0 || cy < 0 || cz < 0 || cx > VGRID_MAX || cy > VGRID_MAX || cz > VGRID_MAX) continue;
                const uint64_t key = vkey(cx, cy, cz);
                uint32_t a = 0, b = nv; /* first cell entry with this key */
                while (a < b) {
                    const uint32_t mid = a + (b - a) / 2;
                    if (g->e[mid].key < key) a = mid + 1;
                    else b = mid;
                }
                for (; a < nv && g->e[a].key == key; a++)
                    if (dist_mm(m, o, g->e[a].v, s) <= r) hits[n++] = g->e[a].v;
            }
    return n;
}

/* Σ_o |{i : ‖x_i − x_o‖ ≤ r}| over the vertices (each counts itself),
 * through the grid of sss_near_build_spec; stops counting past `stop`.
 * 0 when out of memory. */
static uint64_t pairs_within(const sss_mesh *mesh, double s, double r, uint64_t stop)
{
    vgrid g;
    uint32_t *hits = malloc((size_t)mesh->nv * sizeof *hits + 1);
    if (!hits || !vgrid_build(&g, mesh, s, r)) {
        free(hits);
        return 0;
    }
    uint64_t total = 0;
    for (uint32_t o = 0; o < mesh->nv && total <= stop; o++) total += vgrid_within(&g, mesh, s, o, r, hits);
    free(g.e);
    free(hits);
    return total;
}

double sss_near_radius_bake(const sss_mesh *mesh, double mm_per_unit, const sss_material *m, uint32_t channels,
                            double fraction, double search_mm, int *capped, double *held)
{
    const double r = fmin(sss_near_radius_material(m, channels, fraction), search_mm);
    const double rc = sss_near_radius_capped(mesh, mm_per_unit, r);
    *capped = rc < r;
    *held = sss_near_fraction_held(m, channels, rc);
    return rc;
}

double sss_near_radius_capped(const sss_mesh *mesh, double mm_per_unit, double radius_mm)
{
    const uint32_t nv = mesh->nv;
    const uint64_t cap = (uint64_t)SSS_NEAR_ENTRIES_MAX * nv;
    if (!(radius_mm > 0.0) || nv <= SSS_NEAR_ENTRIES_MAX) return radius_mm;
    /* count, and shrink by the square root of the excess (entries grow as
     * r² on a surface) until the mean fits; a count stopped at 16x the cap
     * shrinks by 4 */
    double r = radius_mm;
    for (int it = 0; it < 40; it++) {
        const uint64_t n = pairs_within(mesh, mm_per_unit, r, 16 * cap);
        if (n == 0) return radius_mm; /* out of memory: the radius as it is */
        if (n <= cap) return r;
        r *= n > 16 * cap ? 0.25 : 0.97 * sqrt((double)cap / (double)n);
    }
    return r;
}

double sss_near_radius_material(const sss_material *m, uint32_t channels, double fraction)
{
    if (!(fraction > 0.0 && fraction < 1.0)) return 0.0;
    double R = 0.0;
    for (uint32_t c = 0; c < channels && c < SSS_MAX_CHANNELS; c++) {
        sss_dipole d;
        if (sss_dipole_init(&d, m->sigma_a[c], m->sigmap_s[c], m->eta) != SSS_OK) return 0.0;
        /* 10 m: beyond any object; the bake's own search radius clamps it
         * further (α′ → 1 tails, docs/physics.md §6) */
        R = fmax(R, sss_rd_radius(&d, 1.0 - fraction, 1e4));
    }
    return R;
}

double sss_near_fraction_held(const sss_material *m, uint32_t channels, double radius_mm)
{
    double f = 1.0;
    for (uint32_t c = 0; c < channels && c < SSS_MAX_CHANNELS; c++) {
        sss_dipole d;
        if (sss_dipole_init(&d, m->sigma_a[c], m->sigmap_s[c], m->eta) != SSS_OK) return 0.0;
        const double total = sss_rd_total(&d);
        if (total > 0.0) f = fmin(f, sss_rd_disk(&d, radius_mm) / total);
    }
    return f;
}

static int cmp_u32(const void *a, const void *b)
{
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

/* Position order for finding coincident copies (qsort has no context
 * argument in C11: the positions are passed through this file-scope pointer,
 * set and used only inside sss_near_build; not thread-safe, like qsort's
 * callers here). */
static const float *g_sort_pos;

static int same_pos(const float *p, uint32_t a, uint32_t b)
{
    return p[3 * (size_t)a] == p[3 * (size_t)b] && p[3 * (size_t)a + 1] == p[3 * (size_t)b + 1] &&
           p[3 * (size_t)a + 2] == p[3 * (size_t)b + 2];
}

static int cmp_pos(const void *x, const void *y)
{
    const uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    for (int k = 0; k < 3; k++) {
        const float u = g_sort_pos[3 * (size_t)a + k], v = g_sort_pos[3 * (size_t)b + k];
        if (u < v) return -1;
        if (u > v) return 1;
    }
    return (a > b) - (a < b);
}

sss_result sss_near_build(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                          uint32_t rings, sss_weights *out, sss_error *err)
{
    const sss_near_spec spec = {.rings = rings};
    return sss_near_build_spec(mesh, mat, mm_per_unit, channels, &spec, NULL, out, err);
}

sss_result sss_near_build_file(const sss_bake_file *f, sss_weights *out, sss_error *err)
{
    sss_near_spec spec = {.rings = f->near_rings, .radius_mm = f->near_radius_mm, .weights = f->weights,
                          .eps = f->eps};
    if (f->hetero.field.kind == SSS_FIELD_NONE)
        return sss_near_build_spec(&f->mesh, &f->material, f->mm_per_unit, f->channels, &spec, NULL, out, err);
    /* A field (section FELD): the kernel as bake_scene.c built it, over the
     * file's mesh with its vertex areas (what the bake's mesh carries), the
     * far pairs' cache included, so that κ is the rows' own to the bit */
    if (out) memset(out, 0, sizeof *out);
    sss_mesh ma = f->mesh;
    double *area = malloc((size_t)f->mesh.nv * sizeof *area + 1);
    if (!area) return sss_fail(err, SSS_ERR_NOMEM, "near terms: out of memory for %u vertices", f->mesh.nv);
    sss_mesh_vertex_areas(&f->mesh, area);
    ma.area = area;
    sss_field_kernel k;
    sss_result r = sss_field_kernel_create(&ma, f->mm_per_unit, &f->material, &f->hetero, f->channels, f->eps,
                                           "section FELD", &k, err);
    if (r == SSS_OK) r = sss_field_kernel_far(&k, &ma, SSS_FIELD_FAR_CELLS, err);
    spec.field = &k;
    if (r == SSS_OK) r = sss_near_build_spec(&ma, &k.ref, f->mm_per_unit, f->channels, &spec, NULL, out, err);
    sss_field_kernel_free(&k);
    free(area);
    return r;
}

/* Entry of source i in row o of sorted rows h (0 when absent). */
static const float *row_find(const sss_weights *h, uint32_t o, uint32_t i)
{
    uint64_t lo = h->start[o], hi = h->start[o + 1];
    while (lo < hi) {
        const uint64_t mid = lo + (hi - lo) / 2;
        if (h->idx[mid] < i) lo = mid + 1;
        else hi = mid;
    }
    return lo < h->start[o + 1] && h->idx[lo] == i ? &h->w[lo * h->channels] : NULL;
}

sss_result sss_near_build_spec(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                               const sss_near_spec *spec, const sss_weights *hat_in, sss_weights *out, sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (spec && spec->field) mat = &spec->field->ref; /* the rows' material (sss_near_spec) */
    const uint32_t rings = spec ? spec->rings : 0;
    const double radius = spec ? spec->radius_mm : 0.0;
    const int hat = spec && spec->weights == SSS_WEIGHTS_HAT;
    if (!mesh || !mat || !out || !spec || (channels != 1 && channels != 3) || rings > 8 || !(mm_per_unit > 0.0) ||
        !isfinite(mm_per_unit) || !(radius >= 0.0) || !isfinite(radius) ||
        (spec->weights != SSS_WEIGHTS_POINT && !hat) || (hat && !(spec->eps > 0.0 && spec->eps < 1.0)) ||
        (hat_in && (hat_in->nrows != mesh->nv || hat_in->channels != channels)))
        return sss_fail(err, SSS_ERR_ARG, "near terms: bad argument");
    const uint32_t nv = mesh->nv, nf = mesh->nf;
    const uint32_t C = channels;
    const double s = mm_per_unit;
    sss_result r = SSS_OK;
    sss_weights hat_own = {0};
    vgrid grid = {0};
    uint32_t *hits = NULL;
    double *area = malloc((size_t)nv * sizeof *area + 1);
    uint32_t *astart = calloc((size_t)nv + 1, sizeof *astart), *adj = NULL;
    uint32_t *mark = NULL, *list = NULL, *order = NULL, *grp = NULL, *gend = NULL;
    out->start = calloc((size_t)nv + 1, sizeof *out->start);
    if (!area || !astart || !out->start) goto nomem;
    sss_mesh_vertex_areas(mesh, area);

    /* vertex–vertex adjacency over the triangles' edges (with repeats,
     * which the ring walk below skips) */
    for (uint32_t t = 0; t < nf; t++)
        for (int k = 0; k < 3; k++) astart[mesh->tri[3 * (size_t)t + k] + 1] += 2;
    for (uint32_t v = 0; v < nv; v++) astart[v + 1] += astart[v];
    adj = malloc((size_t)astart[nv] * sizeof *adj + 1);
    uint32_t *fill = malloc((size_t)nv * sizeof *fill + 1);
    if (!adj || !fill) {
        free(fill);
        goto nomem;
    }
    memcpy(fill, astart, (size_t)nv * sizeof *fill);
    for (uint32_t t = 0; t < nf; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t a = mesh->tri[3 * (size_t)t + k];
            adj[fill[a]++] = mesh->tri[3 * (size_t)t + (k + 1) % 3];
            adj[fill[a]++] = mesh->tri[3 * (size_t)t + (k + 2) % 3];
        }
    free(fill);

    /* Coincident copies (the same position under several indices, e.g. a
     * seam with split normals) share one disk in nbhd.c's self term, and a
     * copy's light flips with the vertex's own: they join ring 0. grp[v]
     * = first index of v's position group in `order` (sorted by position,
     * then index); gend marks the end of each group. */
    order = malloc((size_t)nv * sizeof *order + 1);
    grp = malloc((size_t)nv * sizeof *grp + 1);
    gend = malloc((size_t)nv * sizeof *gend + 1);
    if (!order || !grp || !gend) goto nomem;
    for (uint32_t v = 0; v < nv; v++) order[v] = v;
    g_sort_pos = mesh->pos;
    qsort(order, nv, sizeof *order, cmp_pos);
    for (uint32_t k = 0; k < nv;) {
        uint32_t e = k + 1;
        while (e < nv && same_pos(mesh->pos, order[e], order[k])) e++;
        for (uint32_t m = k; m < e; m++) grp[order[m]] = k, gend[order[m]] = e;
        k = e;
    }

    /* A radius: the vertices in a grid of cells as wide as the radius. */
    if (radius > 0.0) {
        hits = malloc((size_t)nv * sizeof *hits + 1);
        if (!hits || !vgrid_build(&grid, mesh, s, radius)) goto nomem;
    }

    /* rings by breadth-first walk per vertex (a vertex brings its copies),
     * or the radius's cells; two passes (count, fill) so the rows are
     * allocated once. mark[v] = o + 1 when v is in o's row. */
    mark = calloc((size_t)nv, sizeof *mark);
    list = malloc((size_t)nv * sizeof *list + 1);
    if (!mark || !list) goto nomem;
    for (int pass = 0; pass < 2; pass++) {
        for (uint32_t o = 0; o < nv; o++) {
            const uint32_t tag = (uint32_t)pass * nv + o + 1;
            uint32_t m = 0, begin = 0;
            list[m++] = o;
            mark[o] = tag;
            for (uint32_t g = grp[o]; g < gend[o]; g++)
                if (mark[order[g]] != tag) mark[order[g]] = tag, list[m++] = order[g];
            if (radius > 0.0) { /* every vertex within the radius */
                const uint32_t nh = vgrid_within(&grid, mesh, s, o, radius, hits);
                for (uint32_t a = 0; a < nh; a++)
                    if (mark[hits[a]] != tag) mark[hits[a]] = tag, list[m++] = hits[a];
            }
            for (uint32_t k = 0; radius == 0.0 && k < rings; k++) { /* rings: breadth first */
                const uint32_t end = m;
                for (uint32_t a = begin; a < end; a++)
                    for (uint32_t e = astart[list[a]]; e < astart[list[a] + 1]; e++) {
                        const uint32_t i = adj[e];
                        if (mark[i] == tag) continue;
                        for (uint32_t g = grp[i]; g < gend[i]; g++)
                            if (mark[order[g]] != tag) mark[order[g]] = tag, list[m++] = order[g];
                    }
                begin = end;
            }
            if (pass == 0) {
                out->start[o + 1] = out->start[o] + m;
                continue;
            }
            qsort(list + 1, m - 1, sizeof *list, cmp_u32);
            memcpy(out->idx + out->start[o], list, (size_t)m * sizeof *list);
        }
        if (pass == 0) {
            const size_t total = out->start[nv];
            out->idx = malloc(total * sizeof *out->idx + 1);
            out->w = malloc(total * C * sizeof *out->w + 1);
            if (!out->idx || !out->w) goto nomem;
        }
    }

    /* With the hat-function weights every entry is the bake's W(o, i) =
     * w(o, i) + C(o, i) (sss/hatweights.h): nbhd.c's point weight inside
     * the neighbourhood cutoff (0 beyond it) plus the correction. */
    const sss_weights *hc = hat_in;
    double cutoff2 = INFINITY;
    if (hat) {
        sss_dipole dd[SSS_MAX_CHANNELS];
        for (uint32_t c = 0; c < C; c++)
            if (sss_dipole_init(&dd[c], mat->sigma_a[c], mat->sigmap_s[c], mat->eta) != SSS_OK) {
                r = sss_fail(err, SSS_ERR_ARG, "near terms: invalid material in channel %u", c);
                goto done;
            }
        /* a field's rows were searched with the kernel's radius, the larger
         * of the radius rule at f_min and f_max (docs/heterogeneous.md §4) */
        const double cut = spec->field ? spec->field->radius_mm : sss_cutoff_radius_mm(mesh, s, dd, C, spec->eps, NULL);
        cutoff2 = cut * cut;
        if (!hc) { /* the corrections of the rows' entries alone */
            sss_mesh ma = *mesh;
            ma.area = area;
            const sss_weights sel = {.nrows = nv, .channels = C, .start = out->start, .idx = out->idx};
            r = sss_hat_corrections_of(&ma, s, dd, C, cut, &sel, NULL, &hat_own, err);
            if (r != SSS_OK) goto done;
            hc = &hat_own;
        }
    }
    /* weights: the own disk first, then nbhd.c's rule per neighbour */
    for (uint32_t c = 0; c < C && r == SSS_OK; c++) {
        sss_dipole dip;
        if (sss_dipole_init(&dip, mat->sigma_a[c], mat->sigmap_s[c], mat->eta) != SSS_OK) {
            r = sss_fail(err, SSS_ERR_ARG, "near terms: invalid material in channel %u", c);
            break;
        }
        for (uint32_t o = 0; o < nv; o++) {
            /* the copies' common disk, shared by area (nbhd.c) */
            double garea = 0.0;
            for (uint32_t g = grp[o]; g < gend[o]; g++) garea += area[order[g]];
            const double gdisk = garea > 0.0 ? sss_rd_disk(&dip, sqrt(garea * s * s / SSS_PI)) / SSS_PI : 0.0;
            for (uint64_t a = out->start[o]; a < out->start[o + 1]; a++) {
                const uint32_t i = out->idx[a];
                const double dA = area[i] * s * s;
                double w;
                if (grp[i] == grp[o]) {
                    w = garea > 0.0 ? gdisk * (area[i] / garea) : 0.0;
                } else {
                    double d2 = 0.0;
                    for (int k = 0; k < 3; k++) {
                        const double dx = ((double)mesh->pos[3 * (size_t)i + k] - mesh->pos[3 * (size_t)o + k]) * s;
                        d2 += dx * dx;
                    }
                    const double dist = sqrt(d2);
                    w = hat && !(d2 <= cutoff2) ? 0.0 : sss_point_weight(&dip, dist, dA);
                }
                if (hc) {
                    const float *cw = row_find(hc, o, i);
                    if (cw) w += cw[c];
                }
                out->w[(size_t)a * C + c] = (float)w;
            }
        }
    }
    if (r == SSS_OK) {
        out->nrows = nv;
        out->channels = C;
        /* κ(o, i) on every entry, as the bake scales its rows (hat
         * corrections included) */
        if (spec->field) r = sss_field_weights_apply(spec->field, mesh, out, NULL, err);
    }
    goto done;
nomem:
    r = sss_fail(err, SSS_ERR_NOMEM, "near terms: out of memory for %u vertices", nv);
done:
    sss_weights_free(&hat_own);
    free(grid.e);
    free(hits);
    free(area);
    free(astart);
    free(adj);
    free(mark);
    free(list);
    free(order);
    free(grp);
    free(gend);
    if (r != SSS_OK) sss_weights_free(out);
    return r;
}

void sss_near_transfer(const float *nrm, uint32_t nv, float eta, const double d[3], const uint8_t *lit, float *gv)
{
    const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nv >= 16384)
#endif
    for (int64_t v = 0; v < (int64_t)nv; v++)
        gv[v] = lit && !lit[v] ? 0.0f : sss_near_g(eta, nrm + 3 * (size_t)v, df);
}

void sss_near_sum(const sss_weights *n, uint32_t o, const float *gv, float *s)
{
    const uint32_t C = n->channels;
    for (uint32_t c = 0; c < C; c++) s[c] = 0.0f;
    for (uint64_t a = n->start[o]; a < n->start[o + 1]; a++) {
        const float g = gv[n->idx[a]];
        for (uint32_t c = 0; c < C; c++) s[c] += n->w[(size_t)a * C + c] * g;
    }
}

void sss_near_add(const sss_weights *n, const float *gv, float *out)
{
    const uint32_t C = n->channels;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (n->nrows >= 16384)
#endif
    for (int64_t o = 0; o < (int64_t)n->nrows; o++) {
        float s[3];
        sss_near_sum(n, (uint32_t)o, gv, s);
        for (uint32_t c = 0; c < C; c++) out[(size_t)o * C + c] += s[c];
    }
}
