/* gltf_write.c: a mesh as glTF 2.0 (gltf_write.h). */
#define _POSIX_C_SOURCE 200809L
#include "gltf_write.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "sss/base64.h"
#include "sss/fileio.h"

static int ends_with_ci(const char *s, const char *tail)
{
    size_t n = strlen(s), k = strlen(tail);
    return n > k && strcasecmp(s + n - k, tail) == 0;
}

int sss_gltf_path(const char *path) { return ends_with_ci(path, ".gltf") || ends_with_ci(path, ".glb"); }

static void put_u32(unsigned char *b, uint32_t v)
{
    for (int k = 0; k < 4; k++) b[k] = (unsigned char)(v >> (8 * k));
}

static void put_f32(unsigned char *b, float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32(b, u);
}

/* Appends printf output to a growing string; 0 when out of memory. */
typedef struct text {
    char *p;
    size_t n, cap;
} text;

static int tx(text *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static int tx(text *t, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (k < 0) return 0;
    if (t->n + (size_t)k + 1 > t->cap) {
        size_t cap = t->cap ? t->cap : 4096;
        while (cap < t->n + (size_t)k + 1) cap *= 2;
        char *q = realloc(t->p, cap);
        if (!q) return 0;
        t->p = q;
        t->cap = cap;
    }
    va_start(ap, fmt);
    vsnprintf(t->p + t->n, (size_t)k + 1, fmt, ap);
    va_end(ap);
    t->n += (size_t)k;
    return 1;
}

sss_result sss_gltf_write(const char *path, const sss_mesh *m, unsigned flags, sss_error *err)
{
    if (!path || !m || !m->nv || !m->nf || !m->pos || !m->tri) return sss_fail(err, SSS_ERR_ARG, "glTF: no path or no mesh");
    const int glb = ends_with_ci(path, ".glb"), attrs = (flags & SSS_GLTF_ATTRIBUTES) != 0;
    double lo[3], hi[3];
    sss_mesh_bounds(m, lo, hi);
    /* the binary data: positions, [uv, colours,] indices */
    const size_t nv = m->nv, nf = m->nf;
    const size_t off_uv = 12 * nv, off_col = off_uv + (attrs ? 8 * nv : 0), off_idx = off_col + (attrs ? 16 * nv : 0);
    const size_t nbin = off_idx + 12 * nf;
    unsigned char *bin = malloc(nbin + 3);
    text t = {0};
    char *b64 = NULL;
    sss_result r = SSS_OK;
    if (!bin) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    for (size_t v = 0; v < nv; v++) {
        const float *p = m->pos + 3 * v;
        for (int k = 0; k < 3; k++) put_f32(bin + 12 * v + 4 * (size_t)k, p[k]);
        if (!attrs) continue;
        float uv[2];
        for (int k = 0; k < 2; k++) uv[k] = hi[k] > lo[k] ? (float)(((double)p[k] - lo[k]) / (hi[k] - lo[k])) : 0.0f;
        const float col[4] = {uv[0], uv[1], 0.5f, 1.0f};
        for (int k = 0; k < 2; k++) put_f32(bin + off_uv + 8 * v + 4 * (size_t)k, uv[k]);
        for (int k = 0; k < 4; k++) put_f32(bin + off_col + 16 * v + 4 * (size_t)k, col[k]);
    }
    for (size_t i = 0; i < 3 * nf; i++) put_u32(bin + off_idx + 4 * i, m->tri[i]);
    const size_t nbin4 = (nbin + 3) & ~(size_t)3;
    memset(bin + nbin, 0, nbin4 - nbin);

    int ok = tx(&t, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"sss-genmesh\"},\"scene\":0,");
    if (flags & SSS_GLTF_TWO_NODES)
        ok = ok && tx(&t, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"translation\":[0,0,1],\"children\":[1,2]},"
                          "{\"mesh\":0,\"translation\":[-2,0,0]},{\"mesh\":0,\"translation\":[2,0,0],"
                          "\"rotation\":[0,0,0.70710678118654752,0.70710678118654752],\"scale\":[0.5,0.5,0.5]}],");
    else
        ok = ok && tx(&t, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],");
    ok = ok && tx(&t, "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0%s},\"indices\":%d,\"mode\":4}]}],",
                  attrs ? ",\"TEXCOORD_0\":2,\"COLOR_0\":3" : "", 1);
    ok = ok && tx(&t, "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
                      "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
                      "{\"bufferView\":%d,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}",
                  nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], attrs ? 3 : 1, 3 * nf);
    if (attrs)
        ok = ok && tx(&t, ",{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
                          "{\"bufferView\":2,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC4\"}", nv, nv);
    ok = ok && tx(&t, "],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu}", 12 * nv);
    if (attrs)
        ok = ok && tx(&t, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,"
                          "\"byteLength\":%zu}", off_uv, 8 * nv, off_col, 16 * nv);
    ok = ok && tx(&t, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],", off_idx, 12 * nf);
    if (glb) ok = ok && tx(&t, "\"buffers\":[{\"byteLength\":%zu}]}", nbin);
    else {
        b64 = malloc(sss_base64_encoded_len(nbin) + 1);
        if (b64) sss_base64_encode(bin, nbin, b64);
        ok = ok && b64 && tx(&t, "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}]}\n",
                             nbin, b64);
    }
    if (!ok) r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);

    sss_atomic a;
    if (r == SSS_OK) r = sss_atomic_begin(&a, path, NULL, err);
    if (r == SSS_OK) {
        if (glb) {
            /* glTF 2.0 §4.4: header, JSON chunk padded with spaces, binary
             * chunk padded with zeros, every chunk 4-byte aligned */
            while (r == SSS_OK && t.n % 4) ok = tx(&t, " ");
            unsigned char h[20], bh[8];
            put_u32(h, 0x46546C67u);
            put_u32(h + 4, 2);
            put_u32(h + 8, (uint32_t)(12 + 8 + t.n + 8 + nbin4));
            put_u32(h + 12, (uint32_t)t.n);
            put_u32(h + 16, 0x4E4F534Au);
            put_u32(bh, (uint32_t)nbin4);
            put_u32(bh + 4, 0x004E4942u);
            r = ok ? sss_atomic_write(&a, h, sizeof h, err) : sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
            if (r == SSS_OK) r = sss_atomic_write(&a, t.p, t.n, err);
            if (r == SSS_OK) r = sss_atomic_write(&a, bh, sizeof bh, err);
            if (r == SSS_OK) r = sss_atomic_write(&a, bin, nbin4, err);
        } else {
            r = sss_atomic_write(&a, t.p, t.n, err);
        }
        if (r == SSS_OK) r = sss_atomic_commit(&a, err);
        else sss_atomic_abort(&a);
    }
    free(bin);
    free(b64);
    free(t.p);
    return r;
}
