/* export_ply.c: a mesh as binary little-endian PLY (sss/import.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <errno.h>

#include "sss/fileio.h"

static void put_u32le(unsigned char *b, uint32_t v)
{
    b[0] = (unsigned char)(v & 0xffu);
    b[1] = (unsigned char)((v >> 8) & 0xffu);
    b[2] = (unsigned char)((v >> 16) & 0xffu);
    b[3] = (unsigned char)((v >> 24) & 0xffu);
}

sss_result sss_export_ply(const char *path, const sss_mesh *m, sss_error *err)
{
    if (!path || !m || (m->nv && !m->pos) || (m->nf && !m->tri))
        return sss_fail(err, SSS_ERR_ARG, "export: no path or no mesh");
    if (m->nv > (uint32_t)INT32_MAX)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %u vertices do not fit PLY int indices", path, m->nv);
    for (size_t i = 0; i < 3 * (size_t)m->nf; i++)
        if (m->tri[i] >= m->nv)
            return sss_fail(err, SSS_ERR_ARG, "%s: face %zu: vertex index %u out of range [0, %u)", path, i / 3, m->tri[i],
                            m->nv);
    /* written atomically, to a path the output policy allows (sss/fileio.h) */
    sss_atomic a;
    sss_result r = sss_atomic_begin(&a, path, NULL, err);
    if (r != SSS_OK) return r;
    /* texture coordinates, where the mesh has them, as the properties u
     * and v (the names the importer reads first, import_ply.c) */
    const int tex = m->uv != NULL;
    char hdr[320];
    const int hn = snprintf(hdr, sizeof hdr,
                            "ply\nformat binary_little_endian 1.0\nelement vertex %u\nproperty float x\nproperty float y\n"
                            "property float z\n%selement face %u\nproperty list uchar int vertex_indices\nend_header\n",
                            m->nv, tex ? "property float u\nproperty float v\n" : "", m->nf);
    r = sss_atomic_write(&a, hdr, (size_t)hn, err);
    unsigned char buf[65536];
    size_t used = 0;
    for (uint32_t v = 0; r == SSS_OK && v < m->nv; v++) {
        if (used + 20 > sizeof buf) { r = sss_atomic_write(&a, buf, used, err); used = 0; }
        for (int k = 0; k < 3 + 2 * tex; k++) {
            uint32_t u;
            memcpy(&u, k < 3 ? &m->pos[3 * (size_t)v + k] : &m->uv[2 * (size_t)v + (k - 3)], 4);
            put_u32le(buf + used, u);
            used += 4;
        }
    }
    for (uint32_t t = 0; r == SSS_OK && t < m->nf; t++) {
        if (used + 13 > sizeof buf) { r = sss_atomic_write(&a, buf, used, err); used = 0; }
        buf[used++] = 3;
        for (int k = 0; k < 3; k++) {
            put_u32le(buf + used, m->tri[3 * (size_t)t + k]);
            used += 4;
        }
    }
    if (r == SSS_OK && used) r = sss_atomic_write(&a, buf, used, err);
    if (r != SSS_OK) {
        sss_atomic_abort(&a);
        return r;
    }
    return sss_atomic_commit(&a, err);
}
