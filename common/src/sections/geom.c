/* geom.c: section GEOM, the mesh (docs/format.md §5.1): vertex and triangle
 * counts, float positions and the bake's own unit normals, and the
 * triangles. Vertex areas are not stored: a reader recomputes them exactly
 * from the float positions (sss_mesh_compute_normals_areas). */
#include <stdlib.h>

#include "sections.h"

uint64_t sss_sec_geom_size(const sss_bake_file *f)
{
    return 8u + 24u * (uint64_t)f->mesh.nv + 12u * (uint64_t)f->mesh.nf;
}

uint64_t sss_sec_geom_count(const sss_bake_file *f) { return f->mesh.nv; }

sss_result sss_sec_geom_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_mesh *m = &f->mesh;
    if (m->nv == 0 || m->nf == 0)
        return sss_fail(err, code, "%s: section GEOM: mesh has %u vertices and %u triangles (need at least 1 each)",
                        name, m->nv, m->nf);
    if (!m->pos || !m->nrm || !m->tri)
        return sss_fail(err, code, "%s: section GEOM: positions, normals or triangles missing", name);
    for (uint32_t v = 0; v < m->nv; v++) {
        for (int k = 0; k < 3; k++) {
            if (!isfinite(m->pos[3 * (size_t)v + k]))
                return sss_fail(err, code, "%s: section GEOM: vertex %u: position coordinate %d is not finite",
                                name, v, k);
            /* the range every stage computes in (sss/mesh.h) */
            if (!(fabs((double)m->pos[3 * (size_t)v + k]) <= SSS_COORD_MAX))
                return sss_fail(err, code, "%s: section GEOM: vertex %u: position coordinate %d is %g, beyond %g",
                                name, v, k, (double)m->pos[3 * (size_t)v + k], SSS_COORD_MAX);
            if (!isfinite(m->nrm[3 * (size_t)v + k]))
                return sss_fail(err, code, "%s: section GEOM: vertex %u: normal coordinate %d is not finite",
                                name, v, k);
        }
        /* the bake's normals are unit, or (0,0,0) where the incident
         * normals cancel (sss_mesh_compute_normals_areas): rays start at
         * x + δn, so a long normal throws them out of range */
        const float *n = &m->nrm[3 * (size_t)v];
        const double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (len != 0.0 && !(fabs(len - 1.0) <= 1e-4))
            return sss_fail(err, code, "%s: section GEOM: vertex %u: normal has length %.9g, not 1 (or 0)", name, v,
                            len);
    }
    for (uint32_t t = 0; t < m->nf; t++)
        for (int k = 0; k < 3; k++)
            if (m->tri[3 * (size_t)t + k] >= m->nv)
                return sss_fail(err, code, "%s: section GEOM: triangle %u: vertex index %u out of range (%u vertices)",
                                name, t, m->tri[3 * (size_t)t + k], m->nv);
    return SSS_OK;
}

void sss_sec_geom_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_mesh *m = &f->mesh;
    put_u32(p, m->nv);
    put_u32(p + 4, m->nf);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)m->nv; k++, p += 4) put_f32(p, m->pos[k]);
    for (size_t k = 0; k < 3 * (size_t)m->nv; k++, p += 4) put_f32(p, m->nrm[k]);
    for (size_t k = 0; k < 3 * (size_t)m->nf; k++, p += 4) put_u32(p, m->tri[k]);
}

sss_result sss_sec_geom_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size < 8)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section GEOM: size %llu is too small for the vertex and triangle "
                        "counts", name, (unsigned long long)size);
    uint32_t nv = get_u32(p), nf = get_u32(p + 4);
    if (nv == 0) return sss_fail(err, SSS_ERR_CORRUPT, "%s: section GEOM: mesh has no vertices", name);
    if (nf == 0) return sss_fail(err, SSS_ERR_CORRUPT, "%s: section GEOM: mesh has no triangles", name);
    const uint64_t want = 8u + 24u * (uint64_t)nv + 12u * (uint64_t)nf;
    if (size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section GEOM: size %llu does not match %u vertices and %u "
                        "triangles (%llu bytes)", name, (unsigned long long)size, nv, nf, (unsigned long long)want);
    if (count != nv) return sss_sec_count_mismatch(err, name, "GEOM", count, nv, "vertices");
    /* Sizes now agree with bytes that exist, so these allocations are
     * bounded by the file size. */
    sss_mesh *m = &f->mesh;
    if (sss_mesh_alloc(m, nv, nf, NULL) != SSS_OK) return sss_sec_nomem(err, name, "GEOM", size);
    m->nrm = malloc(3 * (size_t)nv * sizeof(float));
    if (!m->nrm) return sss_sec_nomem(err, name, "GEOM", size);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)nv; k++, p += 4) m->pos[k] = get_f32(p);
    for (size_t k = 0; k < 3 * (size_t)nv; k++, p += 4) m->nrm[k] = get_f32(p);
    for (size_t k = 0; k < 3 * (size_t)nf; k++, p += 4) m->tri[k] = get_u32(p);
    return sss_sec_geom_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_geom_free(sss_bake_file *f) { sss_mesh_free(&f->mesh); }

int sss_sec_geom_wants(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_sec_need sss_sec_geom_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_PRESENT;
}
