/* mesh.c: allocation, bounds, vertex normals and vertex areas ΔA(x_i)
 * (Hao–Varshney 2004 §3.1: the area a vertex represents in the scattering
 * sum is one third of the areas of its incident triangles). */
#include "sss/mesh.h"
#include "sss/vec3.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

sss_result sss_mesh_alloc(sss_mesh *m, uint32_t nv, uint32_t nf, sss_error *err)
{
    memset(m, 0, sizeof *m);
    /* 3 * UINT32_MAX fits easily in size_t on 64-bit hosts; calloc checks the product. */
    m->pos = calloc((size_t)nv * 3 + 1, sizeof(float));
    m->tri = calloc((size_t)nf * 3 + 1, sizeof(uint32_t));
    if (!m->pos || !m->tri) {
        sss_mesh_free(m);
        return sss_fail(err, SSS_ERR_NOMEM, "out of memory for %u vertices and %u triangles", nv, nf);
    }
    m->nv = nv;
    m->nf = nf;
    return SSS_OK;
}

void sss_mesh_free(sss_mesh *m)
{
    if (!m) return;
    free(m->pos);
    free(m->nrm);
    free(m->tri);
    free(m->area);
    free(m->uv);
    free(m->rgba);
    memset(m, 0, sizeof *m);
}

double sss_mesh_bounds(const sss_mesh *m, double lo[3], double hi[3])
{
    for (int k = 0; k < 3; k++) { lo[k] = INFINITY; hi[k] = -INFINITY; }
    for (uint32_t v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            double x = m->pos[3 * (size_t)v + k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    if (m->nv == 0) {
        for (int k = 0; k < 3; k++) lo[k] = hi[k] = 0.0;
        return 0.0;
    }
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    return sqrt(d2);
}

double sss_mesh_bounding_sphere(const sss_mesh *m, double centre[3])
{
    double lo[3], hi[3];
    sss_mesh_bounds(m, lo, hi);
    for (int k = 0; k < 3; k++) centre[k] = 0.5 * (lo[k] + hi[k]);
    double r2 = 0;
    for (uint32_t v = 0; v < m->nv; v++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = m->pos[3 * (size_t)v + k] - centre[k];
            d2 += d * d;
        }
        if (d2 > r2) r2 = d2;
    }
    return r2 > 0 ? sqrt(r2) : 1.0;
}

sss_result sss_mesh_check_range(const sss_mesh *m, double mm_per_unit, const char *name, sss_error *err)
{
    if (!name) name = "mesh";
    for (uint32_t v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            const double x = m->pos[3 * (size_t)v + k];
            if (!(fabs(x) <= SSS_COORD_MAX))
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %u: coordinate %d is %g, beyond %g (the range the bake "
                                "and the viewer compute in)", name, v, k, x, SSS_COORD_MAX);
        }
    if (mm_per_unit == 0.0) return SSS_OK;
    if (!(mm_per_unit >= SSS_MM_PER_UNIT_MIN && mm_per_unit <= SSS_MM_PER_UNIT_MAX))
        return sss_fail(err, SSS_ERR_MESH, "%s: %g mm per unit is outside [%g, %g]", name, mm_per_unit,
                        SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX);
    double lo[3], hi[3];
    const double ext = sss_mesh_bounds(m, lo, hi) * mm_per_unit;
    if (!(ext <= SSS_EXTENT_MM_MAX))
        return sss_fail(err, SSS_ERR_MESH, "%s: the mesh spans %g mm at %g mm per unit, beyond %g mm (the range the "
                        "bake's float geometry holds): lower the mm per unit", name, ext, mm_per_unit,
                        SSS_EXTENT_MM_MAX);
    return SSS_OK;
}

float sss_mesh_ray_offset(const sss_mesh *m)
{
    double lo[3], hi[3];
    return (float)(1e-5 * sss_mesh_bounds(m, lo, hi));
}

/* (p1 − p0) × (p2 − p0) of triangle f in double: its length is twice the
 * triangle's area and its direction the face normal. */
static void tri_cross(const sss_mesh *m, uint32_t f, double c[3])
{
    const uint32_t *t = &m->tri[3 * (size_t)f];
    double p[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) p[i][k] = m->pos[3 * (size_t)t[i] + k];
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) { e1[k] = p[1][k] - p[0][k]; e2[k] = p[2][k] - p[0][k]; }
    c[0] = e1[1] * e2[2] - e1[2] * e2[1];
    c[1] = e1[2] * e2[0] - e1[0] * e2[2];
    c[2] = e1[0] * e2[1] - e1[1] * e2[0];
}

void sss_mesh_vertex_areas(const sss_mesh *m, double *area)
{
    for (uint32_t v = 0; v < m->nv; v++) area[v] = 0.0;
    for (uint32_t f = 0; f < m->nf; f++) {
        double c[3];
        tri_cross(m, f, c);
        double a3 = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / 3.0;
        for (int i = 0; i < 3; i++) area[m->tri[3 * (size_t)f + i]] += a3;
    }
}

sss_result sss_mesh_copy(const sss_mesh *src, sss_mesh *dst, sss_error *err)
{
    sss_result r = sss_mesh_alloc(dst, src->nv, src->nf, err);
    if (r != SSS_OK) return r;
    memcpy(dst->pos, src->pos, (size_t)src->nv * 3 * sizeof(float));
    memcpy(dst->tri, src->tri, (size_t)src->nf * 3 * sizeof(uint32_t));
    if (src->nrm && !(dst->nrm = malloc((size_t)src->nv * 3 * sizeof(float) + 1))) goto nomem;
    if (src->area && !(dst->area = malloc((size_t)src->nv * sizeof(double) + 1))) goto nomem;
    if (src->nrm) memcpy(dst->nrm, src->nrm, (size_t)src->nv * 3 * sizeof(float));
    if (src->area) memcpy(dst->area, src->area, (size_t)src->nv * sizeof(double));
    if (src->uv && !(dst->uv = malloc((size_t)src->nv * 2 * sizeof(float) + 1))) goto nomem;
    if (src->rgba && !(dst->rgba = malloc((size_t)src->nv * 4 * sizeof(float) + 1))) goto nomem;
    if (src->uv) memcpy(dst->uv, src->uv, (size_t)src->nv * 2 * sizeof(float));
    if (src->rgba) memcpy(dst->rgba, src->rgba, (size_t)src->nv * 4 * sizeof(float));
    return SSS_OK;
nomem:
    sss_mesh_free(dst);
    return sss_fail(err, SSS_ERR_NOMEM, "out of memory copying a mesh of %u vertices", src->nv);
}

sss_result sss_mesh_compute_normals_areas(sss_mesh *m, const char *name, sss_error *err)
{
    if (!name) name = "mesh";
    for (uint32_t v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(m->pos[3 * (size_t)v + k]))
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %u: coordinate %d is not finite", name, v, k);
    for (uint32_t f = 0; f < m->nf; f++)
        for (int k = 0; k < 3; k++)
            if (m->tri[3 * (size_t)f + k] >= m->nv)
                return sss_fail(err, SSS_ERR_MESH, "%s: face %u: vertex index %u out of range [0, %u)",
                                name, f, m->tri[3 * (size_t)f + k], m->nv);

    double *acc = calloc((size_t)m->nv * 3 + 1, sizeof(double));
    double *area = calloc((size_t)m->nv + 1, sizeof(double));
    float *nrm = malloc(((size_t)m->nv * 3 + 1) * sizeof(float));
    if (!acc || !area || !nrm) {
        free(acc); free(area); free(nrm);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for normals of %u vertices", name, m->nv);
    }
    /* Sequential in triangle order: the sums, hence the bytes, do not depend
     * on thread count. The cross product's length is twice the triangle area,
     * so summing it weights face normals by area. */
    for (uint32_t f = 0; f < m->nf; f++) {
        const uint32_t *t = &m->tri[3 * (size_t)f];
        double c[3];
        tri_cross(m, f, c);
        double a3 = 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]) / 3.0;
        for (int i = 0; i < 3; i++) {
            area[t[i]] += a3;
            for (int k = 0; k < 3; k++) acc[3 * (size_t)t[i] + k] += c[k];
        }
    }
    for (uint32_t v = 0; v < m->nv; v++) {
        double *a = &acc[3 * (size_t)v];
        double len = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
        for (int k = 0; k < 3; k++) nrm[3 * (size_t)v + k] = len > 0.0 ? (float)(a[k] / len) : 0.0f;
    }
    free(acc);
    free(m->nrm);
    free(m->area);
    m->nrm = nrm;
    m->area = area;
    return SSS_OK;
}

/* Any unit vector orthogonal to n (n unit or zero): the axis least aligned
 * with n, made orthogonal to it. */
static void any_orthogonal(const double n[3], double t[3])
{
    const double ax = fabs(n[0]), ay = fabs(n[1]), az = fabs(n[2]);
    double e[3] = {0, 0, 0};
    e[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
    const double d = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
    for (int k = 0; k < 3; k++) t[k] = e[k] - d * n[k];
    const double l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
    for (int k = 0; k < 3; k++) t[k] /= l;
}

sss_result sss_mesh_tangents(const sss_mesh *m, float *tangent, const char *name, sss_error *err)
{
    if (!m || !tangent || !m->uv || !m->nrm)
        return sss_fail(err, SSS_ERR_ARG, "%s: tangent frames need texture coordinates and normals",
                        name ? name : "mesh");
    /* per vertex: Σ ∂p/∂u and Σ ∂p/∂v over its triangles, each the
     * solution of e1 = Δu1 T + Δv1 B, e2 = Δu2 T + Δv2 B times |det|, so a
     * triangle weighs by its size (Lengyel's construction) */
    double *acc = calloc((size_t)m->nv * 6 + 1, sizeof(double));
    if (!acc) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for tangent frames", name ? name : "mesh");
    for (uint32_t f = 0; f < m->nf; f++) {
        const uint32_t *t = &m->tri[3 * (size_t)f];
        const float *p0 = &m->pos[3 * (size_t)t[0]], *p1 = &m->pos[3 * (size_t)t[1]], *p2 = &m->pos[3 * (size_t)t[2]];
        const float *w0 = &m->uv[2 * (size_t)t[0]], *w1 = &m->uv[2 * (size_t)t[1]], *w2 = &m->uv[2 * (size_t)t[2]];
        const double du1 = (double)w1[0] - w0[0], dv1 = (double)w1[1] - w0[1];
        const double du2 = (double)w2[0] - w0[0], dv2 = (double)w2[1] - w0[1];
        const double det = du1 * dv2 - du2 * dv1;
        if (!(fabs(det) > 0.0) || !isfinite(det)) continue; /* (u, v) collinear: no direction */
        /* a span over 1/2 is the periodic seam of a welded mesh (u from
         * about 1 back to 0): its differences are not the surface's */
        if (fabs(du1) > 0.5 || fabs(du2) > 0.5 || fabs(dv1) > 0.5 || fabs(dv2) > 0.5) continue;
        const double s = det > 0 ? 1.0 : -1.0;
        double e1[3], e2[3], T[3], B[3];
        for (int k = 0; k < 3; k++) {
            e1[k] = (double)p1[k] - p0[k];
            e2[k] = (double)p2[k] - p0[k];
            T[k] = s * (dv2 * e1[k] - dv1 * e2[k]); /* ∂p/∂u · |det| */
            B[k] = s * (du1 * e2[k] - du2 * e1[k]); /* ∂p/∂v · |det| */
        }
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) {
                acc[6 * (size_t)t[c] + (size_t)k] += T[k];
                acc[6 * (size_t)t[c] + 3 + (size_t)k] += B[k];
            }
    }
    for (uint32_t v = 0; v < m->nv; v++) {
        const double n[3] = {m->nrm[3 * (size_t)v], m->nrm[3 * (size_t)v + 1], m->nrm[3 * (size_t)v + 2]};
        const double *T = &acc[6 * (size_t)v], *B = T + 3;
        const double tn = T[0] * n[0] + T[1] * n[1] + T[2] * n[2];
        double t[3] = {T[0] - tn * n[0], T[1] - tn * n[1], T[2] - tn * n[2]};
        const double l = sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
        const double nl = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
        double w = 1.0;
        if (l > 1e-12 * sqrt(T[0] * T[0] + T[1] * T[1] + T[2] * T[2]) && l > 0.0 && nl > 0.5) {
            for (int k = 0; k < 3; k++) t[k] /= l;
            const double c[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
            w = c[0] * B[0] + c[1] * B[1] + c[2] * B[2] < 0.0 ? -1.0 : 1.0;
        } else {
            any_orthogonal(n, t);
        }
        for (int k = 0; k < 3; k++) tangent[4 * (size_t)v + (size_t)k] = (float)t[k];
        tangent[4 * (size_t)v + 3] = (float)w;
    }
    free(acc);
    return SSS_OK;
}

/* Barycentrics of p's projection onto the triangle's plane (a degenerate
 * triangle: its centroid's weights). */
void sss_mesh_normal_at(const sss_mesh *m, uint32_t t, const double p[3], double n[3])
{
    const uint32_t *ix = &m->tri[3 * (size_t)t];
    double a[3], b[3], c[3], e1[3], e2[3], q[3], w[3];
    for (int k = 0; k < 3; k++) {
        a[k] = m->pos[3 * (size_t)ix[0] + k];
        b[k] = m->pos[3 * (size_t)ix[1] + k];
        c[k] = m->pos[3 * (size_t)ix[2] + k];
    }
    sss_sub3(e1, b, a);
    sss_sub3(e2, c, a);
    sss_sub3(q, p, a);
    const double d11 = sss_dot3(e1, e1), d12 = sss_dot3(e1, e2), d22 = sss_dot3(e2, e2);
    const double q1 = sss_dot3(q, e1), q2 = sss_dot3(q, e2), den = d11 * d22 - d12 * d12;
    w[1] = den != 0.0 ? (d22 * q1 - d12 * q2) / den : 1.0 / 3.0;
    w[2] = den != 0.0 ? (d11 * q2 - d12 * q1) / den : 1.0 / 3.0;
    w[0] = 1.0 - w[1] - w[2];
    for (int k = 0; k < 3; k++)
        n[k] = w[0] * m->nrm[3 * (size_t)ix[0] + k] + w[1] * m->nrm[3 * (size_t)ix[1] + k] +
               w[2] * m->nrm[3 * (size_t)ix[2] + k];
    sss_normalize3(n);
}
