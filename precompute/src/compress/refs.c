/* refs.c: reference points and per-vertex barycentric weights
 * (Hao–Varshney 2004 §4.2).
 *
 * §4.2 stores the full integrals only at reference points, "a subset of the
 * original vertices" found by mesh simplification, and for every other vertex
 * V the three references of the simplified triangle V projects onto with the
 * barycentric coordinates w_1..w_3 of the projection V', so that
 * q(V) ≈ Σ w_k q(V_k) plus an SH-coded low-frequency difference.
 *
 * Steps: validate; choose the simplified triangles (identity, or OpenMesh
 * quadric decimation in refs_decimate.cpp, which also splits non-manifold
 * input and, beyond the paper, can weigh an illumination feature: §6 asks
 * for reference points chosen from "both geometry and illumination");
 * references are the (original) vertices those triangles use; each
 * reference maps onto itself with weight exactly 1; every other vertex gets
 * the triangle holding its closest point (CGAL AABB tree in
 * refs_closest.cpp) and the barycentric weights of that point, computed here
 * in double. Every step runs in a fixed order: same input, same bytes.
 */
#include "sss/refs.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "compress/refs_closest.h"
#include "compress/refs_decimate.h"
#include "sss/vec3.h"

#define NONE UINT32_MAX

void sss_refs_free(sss_refs *r)
{
    if (!r) return;
    free(r->ref_vertex);
    free(r->ref_tri);
    free(r->vtri);
    free(r->w);
    memset(r, 0, sizeof *r);
}

/* ---- weights of the closest point --------------------------------------- */


/* Closest point of segment s0 s1 to p as s0 + t (s1 − s0), t clamped to
 * [0, 1]; a zero-length segment gives t = 0. */
static double segment_t(const double *p, const double *s0, const double *s1)
{
    double d[3], sp[3];
    sss_sub3(d, s1, s0);
    sss_sub3(sp, p, s0);
    double dd = sss_dot3(d, d);
    if (!(dd > 0.0)) return 0.0;
    double t = sss_dot3(sp, d) / dd;
    return t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
}

/* Weight 1 on the corner nearest to p (ties: the lower corner). */
static void nearest_corner(const double *p, const double *const c[3], double w[3])
{
    int best = 0;
    double bd = INFINITY;
    for (int k = 0; k < 3; k++) {
        double d[3];
        sss_sub3(d, p, c[k]);
        double dd = sss_dot3(d, d);
        if (dd < bd) {
            bd = dd;
            best = k;
        }
    }
    w[0] = w[1] = w[2] = 0.0;
    w[best] = 1.0;
}

void sss_refs_closest_weights(const double p[3], const double a[3], const double b[3], const double c[3],
                              double w[3])
{
    const double *const corner[3] = {a, b, c};
    for (int k = 0; k < 3; k++)
        if (!isfinite(p[k]) || !isfinite(a[k]) || !isfinite(b[k]) || !isfinite(c[k])) {
            w[0] = 1.0;
            w[1] = w[2] = 0.0;
            return;
        }

    double ab[3], ac[3], bc[3], n[3];
    sss_sub3(ab, b, a);
    sss_sub3(ac, c, a);
    sss_sub3(bc, c, b);
    n[0] = ab[1] * ac[2] - ab[2] * ac[1];
    n[1] = ab[2] * ac[0] - ab[0] * ac[2];
    n[2] = ab[0] * ac[1] - ab[1] * ac[0];
    double lab = sss_dot3(ab, ab), lac = sss_dot3(ac, ac), lbc = sss_dot3(bc, bc);
    double lmax = fmax(lab, fmax(lac, lbc));

    if (!(lmax > 0.0)) { /* all three corners coincide */
        w[0] = 1.0;
        w[1] = w[2] = 0.0;
        return;
    }
    if (!(sqrt(sss_dot3(n, n)) > 1e-12 * lmax)) {
        /* Collinear (or nearly): the triangle is its longest edge, which
         * covers the other two; its closest point is the triangle's. */
        int i, j;
        if (lab >= lac && lab >= lbc) i = 0, j = 1;
        else if (lac >= lbc) i = 0, j = 2;
        else i = 1, j = 2;
        double t = segment_t(p, corner[i], corner[j]);
        w[0] = w[1] = w[2] = 0.0;
        w[i] = 1.0 - t;
        w[j] = t;
        return;
    }

    /* Ericson, Real-Time Collision Detection §5.1.5: find the Voronoi region
     * of p (corner, edge or face) and the barycentrics of its projection.
     * Edge parameters come from segment_t, the clamped projection (equal to
     * Ericson's d1 / (d1 − d3) and kin, but never 0/0). */
    double ap[3], bp[3], cp[3];
    sss_sub3(ap, p, a);
    double d1 = sss_dot3(ab, ap), d2 = sss_dot3(ac, ap);
    sss_sub3(bp, p, b);
    double d3 = sss_dot3(ab, bp), d4 = sss_dot3(ac, bp);
    sss_sub3(cp, p, c);
    double d5 = sss_dot3(ab, cp), d6 = sss_dot3(ac, cp);
    double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;

    if (d1 <= 0.0 && d2 <= 0.0) {
        w[0] = 1.0, w[1] = 0.0, w[2] = 0.0;
    } else if (d3 >= 0.0 && d4 <= d3) {
        w[0] = 0.0, w[1] = 1.0, w[2] = 0.0;
    } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        double t = segment_t(p, a, b);
        w[0] = 1.0 - t, w[1] = t, w[2] = 0.0;
    } else if (d6 >= 0.0 && d5 <= d6) {
        w[0] = 0.0, w[1] = 0.0, w[2] = 1.0;
    } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        double t = segment_t(p, a, c);
        w[0] = 1.0 - t, w[1] = 0.0, w[2] = t;
    } else if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
        double t = segment_t(p, b, c);
        w[0] = 0.0, w[1] = 1.0 - t, w[2] = t;
    } else {
        double s = va + vb + vc;
        w[0] = va / s, w[1] = vb / s, w[2] = vc / s;
    }

    /* Rounding (p far from a thin triangle) can leave a weight slightly
     * negative or the sum off 1: clamp and renormalise; if nothing usable
     * is left, the nearest corner. */
    double sum = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(w[k])) {
            nearest_corner(p, corner, w);
            return;
        }
        if (w[k] < 0.0) w[k] = 0.0;
        sum += w[k];
    }
    if (!(sum > 0.0) || !isfinite(sum)) {
        nearest_corner(p, corner, w);
        return;
    }
    for (int k = 0; k < 3; k++) w[k] /= sum;
}

/* ---- building the references -------------------------------------------- */

static void load3(double *d, const float *pos, uint32_t v)
{
    const float *p = pos + 3 * (size_t)v;
    d[0] = p[0];
    d[1] = p[1];
    d[2] = p[2];
}

sss_result sss_refs_build(const sss_mesh *m, double fraction, uint32_t min_refs, sss_refs *out,
                          sss_error *err)
{
    return sss_refs_build_ex(m, fraction, min_refs, NULL, 0, 0.0, out, err);
}

/* Scale of the feature term (see refs.h): feature_weight · diag² / var,
 * over the vertices the triangles use, with diag their bounding-box diagonal
 * and var the mean of |f − f̄|². Centring makes the term blind to a constant
 * offset of the feature (an ambient term added to every q); dividing by the
 * variance makes it blind to the feature's units. 0 (geometry alone) when
 * the feature or the mesh has no spread. */
static double feature_scale(const sss_mesh *m, const uint32_t *used, const float *feature, uint32_t dim,
                            double weight, double *mean)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    uint32_t n = 0;
    for (uint32_t d = 0; d < dim; d++) mean[d] = 0.0;
    for (uint32_t v = 0; v < m->nv; v++) {
        if (used[v] == NONE) continue;
        n++;
        for (int k = 0; k < 3; k++) {
            double x = m->pos[3 * (size_t)v + k];
            lo[k] = fmin(lo[k], x);
            hi[k] = fmax(hi[k], x);
        }
        for (uint32_t d = 0; d < dim; d++) mean[d] += feature[(size_t)dim * v + d];
    }
    if (n == 0 || !(weight > 0.0)) return 0.0;
    for (uint32_t d = 0; d < dim; d++) mean[d] /= n;
    double var = 0.0;
    for (uint32_t v = 0; v < m->nv; v++) {
        if (used[v] == NONE) continue;
        for (uint32_t d = 0; d < dim; d++) {
            double x = feature[(size_t)dim * v + d] - mean[d];
            var += x * x;
        }
    }
    var /= n;
    double diag2 = 0.0;
    for (int k = 0; k < 3; k++) diag2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    if (!(var > 0.0) || !(diag2 > 0.0)) return 0.0;
    double s = weight * diag2 / var;
    return isfinite(s) ? s : 0.0;
}

sss_result sss_refs_build_ex(const sss_mesh *m, double fraction, uint32_t min_refs, const float *feature,
                             uint32_t feature_dim, double feature_weight, sss_refs *out, sss_error *err)
{
    if (!out) return sss_fail(err, SSS_ERR_ARG, "refs: NULL output");
    memset(out, 0, sizeof *out);
    if (!m) return sss_fail(err, SSS_ERR_ARG, "refs: NULL mesh");
    if (!(fraction > 0.0 && fraction <= 1.0))
        return sss_fail(err, SSS_ERR_ARG, "refs: fraction %g not in (0, 1]", fraction);
    if (feature) {
        if (feature_dim == 0) return sss_fail(err, SSS_ERR_ARG, "refs: feature given with feature_dim 0");
        if (!(feature_weight >= 0.0) || !isfinite(feature_weight))
            return sss_fail(err, SSS_ERR_ARG, "refs: feature_weight %g not finite and >= 0", feature_weight);
        if (feature_dim > SIZE_MAX / sizeof(float) / (m->nv ? m->nv : 1))
            return sss_fail(err, SSS_ERR_ARG, "refs: %u x %u feature values do not fit in memory", m->nv,
                            feature_dim);
    }
    if (m->nv == 0 || m->nf == 0 || !m->pos || !m->tri)
        return sss_fail(err, SSS_ERR_MESH, "refs: mesh has no vertices or no triangles");
    const uint32_t nv = m->nv, nf = m->nf;
    for (uint32_t v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(m->pos[3 * (size_t)v + k]))
                return sss_fail(err, SSS_ERR_MESH, "refs: vertex %u: non-finite position", v);
    for (uint32_t f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++)
            if (m->tri[3 * (size_t)f + k] >= nv)
                return sss_fail(err, SSS_ERR_MESH, "refs: triangle %u: vertex index %u out of range [0, %u)", f,
                                m->tri[3 * (size_t)f + k], nv);
    if (feature)
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t d = 0; d < feature_dim; d++)
                if (!isfinite(feature[(size_t)feature_dim * v + d]))
                    return sss_fail(err, SSS_ERR_ARG, "refs: vertex %u: feature %u is not finite", v, d);

    sss_result r = SSS_OK;
    uint32_t *vt = NULL, *st = NULL, *ref_of = NULL, *qv = NULL, *qt = NULL;
    double *fmean = NULL;
    uint32_t nvt = 0, nst = 0, skipped = 0, split = 0;

    /* Triangles with a repeated index are no triangles to OpenMesh (nor to
     * the projection); everything else goes in, zero-area ones included. */
    vt = malloc(3 * (size_t)nf * sizeof *vt);
    ref_of = malloc((size_t)nv * sizeof *ref_of);
    if (!vt || !ref_of) {
        r = sss_fail(err, SSS_ERR_NOMEM, "refs: out of memory for %u vertices", nv);
        goto done;
    }
    for (uint32_t v = 0; v < nv; v++) ref_of[v] = NONE;
    uint32_t n_used = 0;
    for (uint32_t f = 0; f < nf; f++) {
        const uint32_t *t = m->tri + 3 * (size_t)f;
        if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
            skipped++;
            continue;
        }
        for (int k = 0; k < 3; k++) {
            vt[3 * (size_t)nvt + k] = t[k];
            if (ref_of[t[k]] == NONE) ref_of[t[k]] = 0, n_used++;
        }
        nvt++;
    }
    if (nvt == 0) {
        r = sss_fail(err, SSS_ERR_MESH, "refs: all %u triangles repeat a vertex index", nf);
        goto done;
    }

    /* Target count: the fraction of the paper's "about 3% of the total"
     * (§4.2, teapot) is the caller's; min_refs keeps small meshes usable. */
    double want = floor(fraction * (double)nv + 0.5);
    uint32_t target = want >= (double)nv ? nv : (uint32_t)want;
    if (target < min_refs) target = min_refs;

    if (target >= n_used) {
        /* Nothing to remove: every vertex a triangle uses is a reference and
         * the reference mesh is the input itself (fraction = 1). */
        st = vt, nst = nvt, vt = NULL;
    } else {
        /* Illumination-aware selection (refs.h, §6 future work): the
         * feature only steers the collapse order, so it is scaled here and
         * not needed afterwards. */
        double scale = 0.0;
        if (feature) {
            fmean = malloc((size_t)feature_dim * sizeof *fmean);
            if (!fmean) {
                r = sss_fail(err, SSS_ERR_NOMEM, "refs: out of memory for %u feature values", feature_dim);
                goto done;
            }
            scale = feature_scale(m, ref_of, feature, feature_dim, feature_weight, fmean);
        }
        char msg[400];
        uint32_t left_out = 0;
        sss_om_decimate_status s = sss_om_decimate(m->pos, nv, vt, nvt, scale > 0.0 ? feature : NULL, feature_dim,
                                                   scale, target, &st, &nst, &left_out, &split, msg, sizeof msg);
        free(vt);
        vt = NULL;
        if (s == SSS_OM_DECIMATE_NO_MEMORY) {
            r = sss_fail(err, SSS_ERR_NOMEM, "refs: %s", msg);
            goto done;
        }
        if (s != SSS_OM_DECIMATE_OK) {
            r = sss_fail(err, SSS_ERR_UNSUPPORTED, "refs: %s", msg);
            goto done;
        }
        skipped += left_out;
        if (nst == 0) {
            r = sss_fail(err, SSS_ERR_MESH, "refs: no non-degenerate triangle left after simplifying %u triangles",
                         nvt);
            goto done;
        }
    }

    /* References: the vertices the simplified triangles use, in increasing
     * original index (so the file can store them as a sorted list). */
    for (uint32_t v = 0; v < nv; v++) ref_of[v] = NONE;
    for (size_t k = 0; k < 3 * (size_t)nst; k++) ref_of[st[k]] = 0;
    uint32_t nref = 0;
    for (uint32_t v = 0; v < nv; v++)
        if (ref_of[v] != NONE) ref_of[v] = nref++;

    out->nv = nv;
    out->nref = nref;
    out->nrt = nst;
    out->faces_skipped = skipped;
    out->vertices_split = split;
    out->ref_vertex = malloc((size_t)nref * sizeof *out->ref_vertex);
    out->ref_tri = malloc(3 * (size_t)nst * sizeof *out->ref_tri);
    out->vtri = malloc((size_t)nv * sizeof *out->vtri);
    out->w = calloc(3 * (size_t)nv, sizeof *out->w);
    if (!out->ref_vertex || !out->ref_tri || !out->vtri || !out->w) {
        r = sss_fail(err, SSS_ERR_NOMEM, "refs: out of memory for %u vertices", nv);
        goto done;
    }
    for (uint32_t v = 0; v < nv; v++)
        if (ref_of[v] != NONE) out->ref_vertex[ref_of[v]] = v;
    for (size_t k = 0; k < 3 * (size_t)nst; k++) out->ref_tri[k] = ref_of[st[k]];

    /* A reference is its own interpolant: weight exactly 1 on its corner of
     * the first triangle that uses it, so q(ref) is reproduced bit for bit. */
    for (uint32_t v = 0; v < nv; v++) out->vtri[v] = NONE;
    for (uint32_t t = 0; t < nst; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t v = st[3 * (size_t)t + k];
            if (out->vtri[v] == NONE) {
                out->vtri[v] = t;
                out->w[3 * (size_t)v + k] = 1.0f;
            }
        }

    /* Every other vertex: the triangle of its closest point (§4.2 "project
     * the vertex onto planes defined by those triangles"), then the
     * barycentrics of that point. */
    uint32_t nq = nv - nref;
    if (nq > 0) {
        qv = malloc((size_t)nq * sizeof *qv);
        qt = malloc((size_t)nq * sizeof *qt);
        if (!qv || !qt) {
            r = sss_fail(err, SSS_ERR_NOMEM, "refs: out of memory for %u projections", nq);
            goto done;
        }
        uint32_t i = 0;
        for (uint32_t v = 0; v < nv; v++)
            if (out->vtri[v] == NONE) qv[i++] = v;
        char msg[400];
        sss_cgal_closest_status s = sss_cgal_closest_triangles(m->pos, st, nst, qv, nq, qt, msg, sizeof msg);
        if (s != SSS_CGAL_CLOSEST_OK) {
            r = sss_fail(err, s == SSS_CGAL_CLOSEST_NO_MEMORY ? SSS_ERR_NOMEM : SSS_ERR_UNSUPPORTED, "refs: %s",
                         msg);
            goto done;
        }
        for (i = 0; i < nq; i++) {
            uint32_t v = qv[i], t = qt[i];
            const uint32_t *c = st + 3 * (size_t)t;
            double p[3], a[3], b[3], cc[3], w[3];
            load3(p, m->pos, v);
            load3(a, m->pos, c[0]);
            load3(b, m->pos, c[1]);
            load3(cc, m->pos, c[2]);
            sss_refs_closest_weights(p, a, b, cc, w);
            out->vtri[v] = t;
            for (int k = 0; k < 3; k++) out->w[3 * (size_t)v + k] = (float)w[k];
        }
    }

done:
    free(vt);
    free(st);
    free(ref_of);
    free(fmean);
    free(qv);
    free(qt);
    if (r != SSS_OK) sss_refs_free(out);
    return r;
}
