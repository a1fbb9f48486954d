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
#include "sss/vec3.h"

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
    if ((flags & SSS_GLTF_SKIN) && (flags & (SSS_GLTF_ATTRIBUTES | SSS_GLTF_TWO_NODES)))
        return sss_fail(err, SSS_ERR_ARG, "glTF: a skinned mesh is written alone, without attributes or instances");
    const int glb = ends_with_ci(path, ".glb"), attrs = (flags & SSS_GLTF_ATTRIBUTES) != 0;
    const int skin = (flags & SSS_GLTF_SKIN) != 0;
    double lo[3], hi[3];
    sss_mesh_bounds(m, lo, hi);
    /* the binary data: positions, [uv, colours,] indices, [joints, weights,
     * inverse bind matrices, clip times, clip rotations] */
    const size_t nv = m->nv, nf = m->nf;
    const size_t off_uv = 12 * nv, off_col = off_uv + (attrs ? 8 * nv : 0), off_idx = off_col + (attrs ? 16 * nv : 0);
    const size_t off_jnt = off_idx + 12 * nf, off_wgt = off_jnt + (skin ? 4 * nv : 0),
                 off_ibm = off_wgt + (skin ? 16 * nv : 0), off_time = off_ibm + (skin ? 128 : 0),
                 off_rot = off_time + (skin ? 20 : 0);
    const size_t nbin = off_rot + (skin ? 80 : 0);
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
    const double zmid = 0.5 * (lo[2] + hi[2]), h = (hi[2] - lo[2]) / 8.0;
    for (size_t v = 0; skin && v < nv; v++) {
        /* joint 1's weight: a smoothstep over [zmid − h, zmid + h] */
        const double x = h > 0 ? ((double)m->pos[3 * v + 2] - (zmid - h)) / (2.0 * h) : 0.5;
        const double c = x < 0 ? 0 : x > 1 ? 1 : x, w1 = c * c * (3.0 - 2.0 * c);
        unsigned char *j = bin + off_jnt + 4 * v;
        j[0] = 0, j[1] = 1, j[2] = j[3] = 0;
        float w[4] = {(float)(1.0 - w1), (float)w1, 0.0f, 0.0f};
        if ((flags & SSS_GLTF_BAD_JOINT) && v == 5) j[1] = 7;
        if ((flags & SSS_GLTF_BAD_WEIGHTS) && v == 3) w[0] = 0.25f, w[1] = 0.25f;
        for (int k = 0; k < 4; k++) put_f32(bin + off_wgt + 16 * v + 4 * (size_t)k, w[k]);
    }
    if (skin) {
        /* inverse bind matrices (column-major): bone0's world bind pose is
         * a translation to (0, 0, lo_z), bone1's to (0, 0, zmid) */
        const double tz[2] = {lo[2], zmid};
        for (int b = 0; b < 2; b++)
            for (int k = 0; k < 16; k++)
                put_f32(bin + off_ibm + 64 * (size_t)b + 4 * (size_t)k,
                        k == 0 || k == 5 || k == 10 || k == 15 ? 1.0f : k == 14 ? (float)-tz[b] : 0.0f);
        static const double deg[5] = {0, 45, 0, -45, 0};
        for (int k = 0; k < 5; k++) {
            put_f32(bin + off_time + 4 * (size_t)k, (float)k);
            const double a = deg[k] * SSS_PI / 360.0; /* half angle */
            const float q[4] = {(float)sin(a), 0.0f, 0.0f, (float)cos(a)};
            for (int c = 0; c < 4; c++) put_f32(bin + off_rot + 16 * (size_t)k + 4 * (size_t)c, q[c]);
        }
    }
    const size_t nbin4 = (nbin + 3) & ~(size_t)3;
    memset(bin + nbin, 0, nbin4 - nbin);

    int ok = tx(&t, "{\"asset\":{\"version\":\"2.0\",\"generator\":\"sss-genmesh\"},\"scene\":0,");
    if (flags & SSS_GLTF_TWO_NODES)
        ok = ok && tx(&t, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"translation\":[0,0,1],\"children\":[1,2]},"
                          "{\"mesh\":0,\"translation\":[-2,0,0]},{\"mesh\":0,\"translation\":[2,0,0],"
                          "\"rotation\":[0,0,0.70710678118654752,0.70710678118654752],\"scale\":[0.5,0.5,0.5]}],");
    else if (skin)
        /* accessors after the mesh's: 2 JOINTS_0, 3 WEIGHTS_0, 4 inverse
         * bind matrices, 5 clip times, 6 clip rotations */
        ok = ok && tx(&t, "\"scenes\":[{\"nodes\":[0,1]}],\"nodes\":[{\"mesh\":0,\"skin\":0},"
                          "{\"name\":\"bone0\",\"translation\":[0,0,%.9g],\"children\":[2]},"
                          "{\"name\":\"bone1\",\"translation\":[0,0,%.9g]}],"
                          "\"skins\":[{\"joints\":[1,2],\"inverseBindMatrices\":4,\"skeleton\":1}],"
                          "\"animations\":[{\"name\":\"bend\",\"channels\":[{\"sampler\":0,\"target\":{\"node\":2,"
                          "\"path\":\"rotation\"}}],\"samplers\":[{\"input\":5,\"output\":6,\"interpolation\":\"LINEAR\"}]}],",
                      lo[2], zmid - lo[2]);
    else
        ok = ok && tx(&t, "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],");
    ok = ok && tx(&t, "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0%s%s},\"indices\":%d,\"mode\":4}]}],",
                  attrs ? ",\"TEXCOORD_0\":2,\"COLOR_0\":3" : "", skin ? ",\"JOINTS_0\":2,\"WEIGHTS_0\":3" : "", 1);
    ok = ok && tx(&t, "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC3\","
                      "\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]},"
                      "{\"bufferView\":%d,\"componentType\":5125,\"count\":%zu,\"type\":\"SCALAR\"}",
                  nv, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], attrs ? 3 : 1, 3 * nf);
    if (attrs)
        ok = ok && tx(&t, ",{\"bufferView\":1,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC2\"},"
                          "{\"bufferView\":2,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC4\"}", nv, nv);
    if (skin) /* views and accessors 2 … 6, after POSITION's and the indices' (no attributes with a skin) */
        ok = ok && tx(&t, ",{\"bufferView\":2,\"componentType\":5121,\"count\":%zu,\"type\":\"VEC4\"},"
                          "{\"bufferView\":3,\"componentType\":5126,\"count\":%zu,\"type\":\"VEC4\"},"
                          "{\"bufferView\":4,\"componentType\":5126,\"count\":2,\"type\":\"MAT4\"},"
                          "{\"bufferView\":5,\"componentType\":5126,\"count\":5,\"type\":\"SCALAR\",\"min\":[0],"
                          "\"max\":[4]},{\"bufferView\":6,\"componentType\":5126,\"count\":5,\"type\":\"VEC4\"}",
                      nv, nv);
    ok = ok && tx(&t, "],\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu}", 12 * nv);
    if (attrs)
        ok = ok && tx(&t, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,"
                          "\"byteLength\":%zu}", off_uv, 8 * nv, off_col, 16 * nv);
    ok = ok && tx(&t, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}", off_idx, 12 * nf);
    if (skin)
        ok = ok && tx(&t, ",{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,"
                          "\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":128},{\"buffer\":0,"
                          "\"byteOffset\":%zu,\"byteLength\":20},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":80}",
                      off_jnt, 4 * nv, off_wgt, 16 * nv, off_ibm, off_time, off_rot);
    ok = ok && tx(&t, "],");
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
