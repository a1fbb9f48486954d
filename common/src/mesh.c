/* mesh.c: allocation, bounds, vertex normals and vertex areas ΔA(x_i)
 * (Hao–Varshney 2004 §3.1: the area a vertex represents in the scattering
 * sum is one third of the areas of its incident triangles). */
#include "sss/mesh.h"

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
