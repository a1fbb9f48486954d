/* export_ply.c: a mesh as binary little-endian PLY (sss/import.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <errno.h>

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
    FILE *f = fopen(path, "wb");
    if (!f) return sss_fail(err, SSS_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    int ok = fprintf(f,
                     "ply\nformat binary_little_endian 1.0\nelement vertex %u\nproperty float x\nproperty float y\n"
                     "property float z\nelement face %u\nproperty list uchar int vertex_indices\nend_header\n",
                     m->nv, m->nf) > 0;
    unsigned char buf[65536];
    size_t used = 0;
    for (uint32_t v = 0; ok && v < m->nv; v++) {
        if (used + 12 > sizeof buf) { ok = fwrite(buf, 1, used, f) == used; used = 0; }
        for (int k = 0; k < 3; k++) {
            uint32_t u;
            memcpy(&u, &m->pos[3 * (size_t)v + k], 4);
            put_u32le(buf + used, u);
            used += 4;
        }
    }
    for (uint32_t t = 0; ok && t < m->nf; t++) {
        if (used + 13 > sizeof buf) { ok = fwrite(buf, 1, used, f) == used; used = 0; }
        buf[used++] = 3;
        for (int k = 0; k < 3; k++) {
            put_u32le(buf + used, m->tri[3 * (size_t)t + k]);
            used += 4;
        }
    }
    if (ok && used) ok = fwrite(buf, 1, used, f) == used;
    int e = errno;
    if (fclose(f) != 0 && ok) { ok = 0; e = errno; }
    if (!ok) {
        remove(path);
        return sss_fail(err, SSS_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return SSS_OK;
}
