/* import_gltf.c: the glTF 2.0 scanner (.gltf JSON and .glb binary;
 * docs/robustness.md, "glTF"). Like the other scanners (import_internal.h)
 * it checks everything the reader would take on trust, then hands the
 * reader canonical bytes and the exact counts it must deliver.
 *
 * Assimp's glTF reader (import_assimp.cpp) is third-party code reading
 * hostile input, and it clamps an index out of range instead of refusing
 * it. So the whole file is checked here first, with cJSON: the GLB header
 * and chunks, every buffer (a data: URI, a file beside the asset, or the
 * GLB's binary chunk) against its byteLength, every bufferView and accessor
 * used against its buffer, component types, counts, every index against
 * its primitive's vertex count, the node hierarchy (no node with two
 * parents, no cycle) and the transforms (finite numbers). What passes is
 * rewritten as a canonical GLB holding only what the bake uses: the scene's
 * nodes and transforms, and per triangle primitive float32 POSITION,
 * TEXCOORD_0 and COLOR_0 (RGBA) and uint32 indices, tightly packed. Assimp
 * reads only that, and applies the node transforms.
 *
 * Primitives of points or lines (modes 0-3) have no surface: they are
 * skipped and counted (a warning). Triangle strips and fans (modes 5 and 6)
 * are refused: exporters write plain triangles, and a strip read wrongly
 * would turn faces inside out unnoticed.
 */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <unistd.h>

#include "sss/base64.h"
#include "sss/fileio.h"
#include "sss/skin.h"

#define GLB_MAGIC 0x46546C67u /* "glTF" */
#define GLB_JSON 0x4E4F534Au  /* "JSON" */
#define GLB_BIN 0x004E4942u   /* "BIN\0" */

/* A file of N bytes may place at most ELEMENTS_BASE + ELEMENTS_PER_BYTE * N
 * vertices and triangles in the world, and hold as many in its primitives:
 * node instancing multiplies a mesh legitimately, and so does a primitive
 * reading an accessor another one reads, but a small hostile file must not
 * make the import allocate gigabytes (a 1 MiB file: 20 million). */
#define ELEMENTS_BASE ((ull)1 << 22)
#define ELEMENTS_PER_BYTE 16ull

/* Node hierarchies deeper than this are refused: Assimp reads and walks
 * them by recursion (so does import_assimp.cpp), and a chain of nodes a
 * hostile file lists by the thousand would exhaust the stack. Scenes from
 * modelling tools nest a few levels. */
#define DEPTH_MAX 256

enum { C_BYTE = 5120, C_UBYTE = 5121, C_SHORT = 5122, C_USHORT = 5123, C_UINT = 5125, C_FLOAT = 5126 };

typedef struct gbuf {
    const unsigned char *data; /* NULL until loaded */
    unsigned char *own;        /* malloc'd (data: URI or external file) */
    ull len;                   /* byteLength */
} gbuf;

typedef struct gltf {
    src *s;
    sss_error *err;
    cJSON *root;
    const unsigned char *bin; /* GLB binary chunk */
    ull bin_len;
    int nbuf, nview, nacc, nnode, nmesh;
    gbuf *buf;
    /* the arrays' items by index (cJSON arrays are lists: walking one per
     * look-up would be quadratic in a hostile file) */
    cJSON **views, **accs, **nodes, **meshes, **buffers;
    /* per mesh: the fewest joints of the skins nodes give it (-1: none),
     * and one such skin (docs/deformable.md §5) */
    int *mesh_joints, *mesh_skin;
    /* posing (ex->pose): every node's global matrix at the pose time
     * (16 doubles each, column-major as glTF), NULL when not posing */
    double *G;
    expect *ex;
} gltf;

/* An accessor, checked: element e component c is at
 * base + e * stride + c * csize. */
typedef struct acc {
    const unsigned char *base;
    ull count, stride;
    int ctype, ncomp, csize, normalized;
} acc;

static sss_result bad(gltf *g, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static sss_result bad(gltf *g, const char *fmt, ...)
{
    char msg[300];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return sss_fail(g->err, SSS_ERR_FORMAT, "%s: %s", g->s->name, msg);
}

/* A non-negative integer member (def when absent and def >= 0); -1 after an
 * error naming what. */
static long long get_uint(gltf *g, const cJSON *o, const char *key, long long def, const char *what)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!v) {
        if (def < 0) bad(g, "%s: no '%s'", what, key);
        return def;
    }
    double d = cJSON_IsNumber(v) ? v->valuedouble : -1.0;
    if (!(d >= 0.0 && d <= 4294967295.0 && d == floor(d))) {
        bad(g, "%s: '%s' is not an integer in [0, 2^32)", what, key);
        return -1;
    }
    return (long long)d;
}

/* Index member `key` of o into an array of n items; -1 after an error, -2
 * when absent and optional. */
static long long get_index(gltf *g, const cJSON *o, const char *key, int n, int optional, const char *what,
                           const char *of)
{
    if (optional && !cJSON_GetObjectItemCaseSensitive(o, key)) return -2;
    long long i = get_uint(g, o, key, -1, what);
    if (i < 0) return -1;
    if (i >= n) {
        bad(g, "%s: %s %lld out of range [0, %d)", what, of, i, n);
        return -1;
    }
    return i;
}

/* An optional array member: NULL when absent, *bad_ set when not an array. */
static cJSON *get_array(gltf *g, const cJSON *o, const char *key, int *n, int *failed)
{
    cJSON *a = cJSON_GetObjectItemCaseSensitive(o, key);
    *n = 0;
    if (!a) return NULL;
    if (!cJSON_IsArray(a)) {
        bad(g, "'%s' is not an array", key);
        *failed = 1;
        return NULL;
    }
    *n = cJSON_GetArraySize(a);
    return a;
}

/* The items of array a (n of them) by index; NULL when out of memory. */
static cJSON **items(cJSON *a, int n)
{
    cJSON **v = malloc(((size_t)n + 1) * sizeof *v);
    if (!v) return NULL;
    int i = 0;
    cJSON *x;
    cJSON_ArrayForEach(x, a) v[i++] = x;
    v[i] = NULL;
    return v;
}

/* Percent-decodes a relative URI into out (n bytes); 0 when it is not a
 * plain relative path (a scheme, an absolute path, a bad escape). */
static int uri_path(const char *uri, char *out, size_t n)
{
    if (uri[0] == '/' || strchr(uri, ':')) return 0;
    size_t k = 0;
    for (const char *p = uri; *p; p++) {
        int c = (unsigned char)*p;
        if (c == '%') {
            int h = 0;
            for (int j = 1; j <= 2; j++) {
                char x = p[j];
                int d = is_digit(x) ? x - '0' : (lower(x) >= 'a' && lower(x) <= 'f') ? lower(x) - 'a' + 10 : -1;
                if (d < 0) return 0;
                h = h * 16 + d;
            }
            if (h == 0) return 0;
            c = h;
            p += 2;
        }
        if (k + 1 >= n) return 0;
        out[k++] = (char)c;
    }
    out[k] = 0;
    return k > 0;
}

/* Buffer i: its bytes, from the GLB chunk, a data: URI or a file beside the
 * asset, at least byteLength of them. */
static sss_result load_buffer(gltf *g, const cJSON *b, int i)
{
    gbuf *gb = &g->buf[i];
    char what[48];
    snprintf(what, sizeof what, "buffer %d", i);
    long long len = get_uint(g, b, "byteLength", -1, what);
    if (len < 0) return SSS_ERR_FORMAT;
    if (len == 0) return bad(g, "%s: byteLength is 0", what);
    gb->len = (ull)len;
    const cJSON *u = cJSON_GetObjectItemCaseSensitive(b, "uri");
    if (!u) {
        if (i != 0 || !g->bin) return bad(g, "%s: no 'uri' and no GLB binary chunk", what);
        if (g->bin_len < gb->len)
            return bad(g, "%s: byteLength %llu but the binary chunk holds %llu bytes", what, gb->len, g->bin_len);
        gb->data = g->bin;
        return SSS_OK;
    }
    if (!cJSON_IsString(u)) return bad(g, "%s: 'uri' is not a string", what);
    const char *uri = u->valuestring;
    ull got;
    if (strncmp(uri, "data:", 5) == 0) {
        const char *comma = strchr(uri, ',');
        const char *b64 = strstr(uri, ";base64,");
        if (!comma || !b64 || b64 + 7 != comma) return bad(g, "%s: data: URI is not base64", what);
        size_t n = strlen(comma + 1), at = 0;
        gb->own = malloc(n / 4 * 3 + 1);
        if (!gb->own) return sss_fail(g->err, SSS_ERR_NOMEM, "%s: %s: out of memory", g->s->name, what);
        long long d = sss_base64_decode(comma + 1, n, gb->own, &at);
        if (d < 0) return bad(g, "%s: data: URI: invalid base64 at character %zu", what, at);
        got = (ull)d;
    } else {
        char rel[1024], path[2048];
        if (!uri_path(uri, rel, sizeof rel))
            return bad(g, "%s: uri '%.64s' is not a relative file name or a data: URI", what, uri);
        const char *slash = strrchr(g->s->name, '/');
        int dir = slash ? (int)(slash - g->s->name + 1) : 0;
        if ((size_t)snprintf(path, sizeof path, "%.*s%s", dir, g->s->name, rel) >= sizeof path)
            return bad(g, "%s: uri too long", what);
        int fd;
        uint64_t size;
        sss_error e2 = {{0}};
        if (sss_input_open(path, &fd, &size, &e2) != SSS_OK) return bad(g, "%s: %s", what, e2.msg);
        if (size < gb->len) {
            close(fd);
            return bad(g, "%s: byteLength %llu but '%s' has %llu bytes", what, gb->len, rel, (ull)size);
        }
        gb->own = malloc((size_t)gb->len + 1);
        if (!gb->own) {
            close(fd);
            return sss_fail(g->err, SSS_ERR_NOMEM, "%s: %s: out of memory", g->s->name, what);
        }
        size_t have = 0;
        while (have < gb->len) {
            ssize_t r = read(fd, gb->own + have, (size_t)(gb->len - have));
            if (r <= 0) {
                close(fd);
                return bad(g, "%s: reading '%s' failed: %s", what, rel, r < 0 ? strerror(errno) : "file shrank");
            }
            have += (size_t)r;
        }
        close(fd);
        got = gb->len;
    }
    if (got < gb->len) return bad(g, "%s: byteLength %llu but its data holds %llu bytes", what, gb->len, got);
    gb->data = gb->own;
    return SSS_OK;
}

static int type_ncomp(const char *t)
{
    static const struct { const char *name; int n; } types[] = {
        {"SCALAR", 1}, {"VEC2", 2}, {"VEC3", 3}, {"VEC4", 4}, {"MAT2", 4}, {"MAT3", 9}, {"MAT4", 16}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0) return types[i].n;
    return 0;
}

static int ctype_size(int c)
{
    switch (c) {
    case C_BYTE: case C_UBYTE: return 1;
    case C_SHORT: case C_USHORT: return 2;
    case C_UINT: case C_FLOAT: return 4;
    default: return 0;
    }
}

/* Accessor i, checked against its bufferView and buffer (glTF 2.0 §3.6). */
static sss_result get_acc(gltf *g, int i, acc *a)
{
    char what[48];
    snprintf(what, sizeof what, "accessor %d", i);
    const cJSON *o = g->accs[i];
    if (!cJSON_IsObject(o)) return bad(g, "%s: not an object", what);
    if (cJSON_GetObjectItemCaseSensitive(o, "sparse")) return bad(g, "%s: sparse accessors are not supported", what);
    if (!cJSON_GetObjectItemCaseSensitive(o, "bufferView"))
        return bad(g, "%s: no bufferView (an all-zero accessor has no geometry)", what);
    long long v = get_index(g, o, "bufferView", g->nview, 0, what, "bufferView");
    long long ct = get_uint(g, o, "componentType", -1, what);
    long long count = get_uint(g, o, "count", -1, what);
    long long off = get_uint(g, o, "byteOffset", 0, what);
    if (v < 0 || ct < 0 || count < 0 || off < 0) return SSS_ERR_FORMAT;
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(o, "type");
    const cJSON *nz = cJSON_GetObjectItemCaseSensitive(o, "normalized");
    a->ctype = (int)ct;
    a->csize = ctype_size(a->ctype);
    a->ncomp = cJSON_IsString(t) ? type_ncomp(t->valuestring) : 0;
    a->normalized = cJSON_IsTrue(nz);
    if (!a->csize) return bad(g, "%s: componentType %lld is not one of glTF's", what, ct);
    if (!a->ncomp) return bad(g, "%s: 'type' is not SCALAR, VEC2-4 or MAT2-4", what);
    if (count == 0) return bad(g, "%s: count is 0", what);
    if (off % a->csize) return bad(g, "%s: byteOffset %lld is not a multiple of the component size %d", what, off, a->csize);
    const cJSON *bv = g->views[v];
    char vwhat[48];
    snprintf(vwhat, sizeof vwhat, "bufferView %lld", v);
    if (!cJSON_IsObject(bv)) return bad(g, "%s: not an object", vwhat);
    long long b = get_index(g, bv, "buffer", g->nbuf, 0, vwhat, "buffer");
    long long voff = get_uint(g, bv, "byteOffset", 0, vwhat);
    long long vlen = get_uint(g, bv, "byteLength", -1, vwhat);
    long long stride = get_uint(g, bv, "byteStride", 0, vwhat);
    if (b < 0 || voff < 0 || vlen < 0 || stride < 0) return SSS_ERR_FORMAT;
    if (!g->buf[b].data) {
        sss_result r = load_buffer(g, g->buffers[b], (int)b);
        if (r != SSS_OK) return r;
    }
    if ((ull)voff + (ull)vlen > g->buf[b].len)
        return bad(g, "%s: bytes [%lld, %llu) lie outside buffer %lld of %llu bytes", vwhat, voff, (ull)voff + (ull)vlen,
                   b, g->buf[b].len);
    ull esize = (ull)a->csize * (ull)a->ncomp;
    if (stride && (stride < 4 || stride > 252 || stride % 4 || (ull)stride < esize))
        return bad(g, "%s: byteStride %lld is not a multiple of 4 in [max(4, %llu), 252]", vwhat, stride, esize);
    a->stride = stride ? (ull)stride : esize;
    ull end = (ull)off + a->stride * ((ull)count - 1) + esize;
    if (end > (ull)vlen)
        return bad(g, "%s: %lld elements from byte %lld need %llu bytes; %s has %lld", what, count, off, end, vwhat, vlen);
    a->base = g->buf[b].data + voff + off;
    a->count = (ull)count;
    return SSS_OK;
}

static ull acc_uint(const acc *a, ull e)
{
    const unsigned char *p = a->base + e * a->stride;
    return rd_uint(p, (size_t)a->csize, 0);
}

/* Component c of element e as a float, normalised integers mapped as glTF
 * 2.0 §3.11 says. */
static float acc_float(const acc *a, ull e, int c)
{
    const unsigned char *p = a->base + e * a->stride + (ull)c * (ull)a->csize;
    ull u = rd_uint(p, (size_t)a->csize, 0);
    switch (a->ctype) {
    case C_FLOAT: { float f; uint32_t w = (uint32_t)u; memcpy(&f, &w, 4); return f; }
    case C_UBYTE: return (float)u / 255.0f;
    case C_USHORT: return (float)u / 65535.0f;
    case C_BYTE: { float f = (float)(int8_t)u / 127.0f; return f < -1.0f ? -1.0f : f; }
    case C_SHORT: { float f = (float)(int16_t)u / 32767.0f; return f < -1.0f ? -1.0f : f; }
    default: return (float)u;
    }
}

/* One checked triangle primitive, and where the canonical file holds it. */
typedef struct prim {
    acc pos, uv, col, idx;
    int has_uv, has_col, has_idx;
    ull nv, ni; /* vertices; indices (a multiple of 3) */
} prim;

/* Checks attribute `key` of a primitive: the types glTF 2.0 §3.7.2.1
 * allows, and as many elements as POSITION. */
static sss_result get_attr(gltf *g, const cJSON *attrs, const char *key, const char *what, ull nv, acc *a, int *has)
{
    *has = 0;
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(attrs, key);
    if (!x) return SSS_OK;
    char w2[96];
    snprintf(w2, sizeof w2, "%s: %s", what, key);
    long long i = get_index(g, attrs, key, g->nacc, 0, w2, "accessor");
    if (i < 0) return SSS_ERR_FORMAT;
    sss_result r = get_acc(g, (int)i, a);
    if (r != SSS_OK) return r;
    int is_col = key[0] == 'C';
    int ok = a->ctype == C_FLOAT || ((a->ctype == C_UBYTE || a->ctype == C_USHORT) && a->normalized);
    if (!ok || (is_col ? a->ncomp != 3 && a->ncomp != 4 : a->ncomp != 2))
        return bad(g, "accessor %lld: %s must be %s of float or normalised unsigned byte/short", i, key,
                   is_col ? "VEC3 or VEC4" : "VEC2");
    if (a->count != nv)
        return bad(g, "accessor %lld: %s has %llu elements, POSITION has %llu", i, key, a->count, nv);
    for (ull e = 0; e < a->count && a->ctype == C_FLOAT; e++)
        for (int c = 0; c < a->ncomp; c++)
            if (!isfinite(acc_float(a, e, c))) return bad(g, "accessor %lld: element %llu: %s is not finite", i, e, key);
    *has = 1;
    return SSS_OK;
}

/* A skinned primitive's JOINTS_0 and WEIGHTS_0 (glTF 2.0 §3.7.3.3;
 * docs/deformable.md §5): both or neither; as many elements as POSITION;
 * joints VEC4 of unsigned byte or short naming joints the mesh's skin has;
 * weights VEC4 of float or normalised unsigned byte or short, each finite
 * and ≥ 0, summing to 1 within 10⁻³ (the linear blend of the joints'
 * transforms is a weighted mean). The rig is checked, not yet applied: the
 * canonical file holds the rest pose (docs/deformable.md §6). */
static sss_result check_skin(gltf *g, int m, const cJSON *attrs, const char *what, ull nv)
{
    const int hj = cJSON_GetObjectItemCaseSensitive(attrs, "JOINTS_0") != NULL,
              hw = cJSON_GetObjectItemCaseSensitive(attrs, "WEIGHTS_0") != NULL;
    if (!hj && !hw) return SSS_OK;
    if (!hj || !hw) return bad(g, "%s: %s without %s", what, hj ? "JOINTS_0" : "WEIGHTS_0", hj ? "WEIGHTS_0" : "JOINTS_0");
    char w2[96];
    snprintf(w2, sizeof w2, "%s: JOINTS_0", what);
    long long ij = get_index(g, attrs, "JOINTS_0", g->nacc, 0, w2, "accessor");
    snprintf(w2, sizeof w2, "%s: WEIGHTS_0", what);
    long long iw = get_index(g, attrs, "WEIGHTS_0", g->nacc, 0, w2, "accessor");
    if (ij < 0 || iw < 0) return SSS_ERR_FORMAT;
    acc j, w;
    sss_result r = get_acc(g, (int)ij, &j);
    if (r == SSS_OK) r = get_acc(g, (int)iw, &w);
    if (r != SSS_OK) return r;
    if (j.ncomp != 4 || j.normalized || (j.ctype != C_UBYTE && j.ctype != C_USHORT))
        return bad(g, "accessor %lld: JOINTS_0 must be VEC4 of unsigned byte or short", ij);
    if (w.ncomp != 4 || !(w.ctype == C_FLOAT || ((w.ctype == C_UBYTE || w.ctype == C_USHORT) && w.normalized)))
        return bad(g, "accessor %lld: WEIGHTS_0 must be VEC4 of float or normalised unsigned byte/short", iw);
    if (j.count != nv) return bad(g, "accessor %lld: JOINTS_0 has %llu elements, POSITION has %llu", ij, j.count, nv);
    if (w.count != nv) return bad(g, "accessor %lld: WEIGHTS_0 has %llu elements, POSITION has %llu", iw, w.count, nv);
    const int nj = g->mesh_joints[m];
    if (nj < 0) return bad(g, "%s: JOINTS_0 but no node gives mesh %d a skin", what, m);
    for (ull e = 0; e < nv; e++) {
        double sum = 0;
        for (int c = 0; c < 4; c++) {
            const float x = acc_float(&w, e, c);
            if (!isfinite(x) || x < 0)
                return bad(g, "accessor %lld: WEIGHTS_0 of vertex %llu: weight %d is %g (finite and >= 0 expected)", iw,
                           e, c, x);
            sum += x;
            const unsigned char *p = j.base + e * j.stride + (ull)c * (ull)j.csize;
            const ull k = rd_uint(p, (size_t)j.csize, 0);
            if (k >= (ull)nj)
                return bad(g, "accessor %lld: JOINTS_0 of vertex %llu names joint %llu, but skin %d has %d joints", ij,
                           e, k, g->mesh_skin[m], nj);
        }
        if (!(fabs(sum - 1.0) <= 1e-3))
            return bad(g, "accessor %lld: WEIGHTS_0 of vertex %llu sum to %.6g, not 1", iw, e, sum);
    }
    return SSS_OK;
}

static sss_result skin_rows(gltf *g, cJSON **skins, int nskin);

/* The joint counts of the skins nodes give each mesh (gltf.mesh_joints):
 * skins' joints must be nodes of the file. */
static sss_result skin_joints(gltf *g)
{
    int failed = 0, nskin = 0;
    cJSON *skins = get_array(g, g->root, "skins", &nskin, &failed);
    if (failed) return SSS_ERR_FORMAT;
    cJSON **sk_items = items(skins, nskin); /* by index: no list walk per node */
    if (!sk_items) return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", g->s->name);
    sss_result r = skin_rows(g, sk_items, nskin);
    free(sk_items);
    return r;
}

static sss_result skin_rows(gltf *g, cJSON **skins, int nskin)
{
    int failed = 0;
    for (int m = 0; m < g->nmesh; m++) g->mesh_joints[m] = -1, g->mesh_skin[m] = -1;
    for (int n = 0; n < g->nnode; n++) {
        const cJSON *o = g->nodes[n];
        if (!cJSON_IsObject(o) || !cJSON_GetObjectItemCaseSensitive(o, "skin")) continue;
        char what[32];
        snprintf(what, sizeof what, "node %d", n);
        long long sk = get_index(g, o, "skin", nskin, 0, what, "skin");
        long long m = cJSON_GetObjectItemCaseSensitive(o, "mesh") ? get_index(g, o, "mesh", g->nmesh, 0, what, "mesh")
                                                                 : -2;
        if (sk < 0 || m == -1) return SSS_ERR_FORMAT;
        const cJSON *so = skins[sk];
        char swhat[32];
        snprintf(swhat, sizeof swhat, "skin %lld", sk);
        int nj = 0;
        cJSON *joints = cJSON_IsObject(so) ? get_array(g, so, "joints", &nj, &failed) : NULL;
        if (failed) return SSS_ERR_FORMAT;
        if (!joints || nj == 0) return bad(g, "%s: no 'joints'", swhat);
        int k = 0;
        const cJSON *jn;
        cJSON_ArrayForEach(jn, joints) {
            if (!cJSON_IsNumber(jn) || jn->valuedouble != floor(jn->valuedouble) || jn->valuedouble < 0 ||
                jn->valuedouble >= g->nnode)
                return bad(g, "%s: joint %d is not a node of the file's %d", swhat, k, g->nnode);
            k++;
        }
        if (m >= 0 && (g->mesh_joints[m] < 0 || nj < g->mesh_joints[m])) g->mesh_joints[m] = nj, g->mesh_skin[m] = (int)sk;
    }
    return SSS_OK;
}

/* ---- posing skinned meshes (docs/deformable.md §5; glTF 2.0 §3.7.3) ---- */

/* A node's local transform: its matrix, or T · R · S. */
typedef struct local_xf {
    double t[3], r[4], s[3], m[16];
    int has_m;
} local_xf;

/* Up to n numbers of member key of o into v (left as they are when absent
 * or not numbers: canon_nodes refuses such a node later). */
static void read_numbers(const cJSON *o, const char *key, int n, double *v)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, key);
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != n) return;
    int i = 0;
    const cJSON *x;
    cJSON_ArrayForEach(x, a) {
        if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble)) return;
        v[i++] = x->valuedouble;
    }
}

static void node_local(const cJSON *o, local_xf *x)
{
    memset(x, 0, sizeof *x);
    x->r[3] = 1.0;
    x->s[0] = x->s[1] = x->s[2] = 1.0;
    if (!cJSON_IsObject(o)) return;
    x->has_m = cJSON_GetObjectItemCaseSensitive(o, "matrix") != NULL;
    if (x->has_m) {
        for (int k = 0; k < 16; k++) x->m[k] = k % 5 == 0;
        read_numbers(o, "matrix", 16, x->m);
    }
    read_numbers(o, "translation", 3, x->t);
    read_numbers(o, "rotation", 4, x->r);
    read_numbers(o, "scale", 3, x->s);
}

/* T · R · S as a column-major matrix, the quaternion (x, y, z, w)
 * normalised first. */
static void local_matrix(const local_xf *x, double m[16])
{
    if (x->has_m) {
        memcpy(m, x->m, sizeof x->m);
        return;
    }
    double q[4] = {x->r[0], x->r[1], x->r[2], x->r[3]};
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (n > 0)
        for (int k = 0; k < 4; k++) q[k] /= n;
    const double X = q[0], Y = q[1], Z = q[2], W = q[3];
    const double R[9] = {1 - 2 * (Y * Y + Z * Z), 2 * (X * Y + Z * W), 2 * (X * Z - Y * W),  /* column 0 */
                         2 * (X * Y - Z * W), 1 - 2 * (X * X + Z * Z), 2 * (Y * Z + X * W),  /* column 1 */
                         2 * (X * Z + Y * W), 2 * (Y * Z - X * W), 1 - 2 * (X * X + Y * Y)}; /* column 2 */
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++) m[4 * c + r] = R[3 * c + r] * x->s[c];
        m[4 * c + 3] = 0;
    }
    m[12] = x->t[0], m[13] = x->t[1], m[14] = x->t[2], m[15] = 1;
}

/* The inverse of an affine column-major matrix; 0 when singular. */
static int affine_inverse(const double *m, double *inv)
{
    const double a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g2 = m[2], h = m[6], i = m[10];
    const double A = e * i - f * h, B = -(d * i - f * g2), C = d * h - e * g2;
    const double det = a * A + b * B + c * C;
    if (!(fabs(det) > 0) || !isfinite(det)) return 0;
    const double r[9] = {A / det, B / det, C / det,                                   /* column 0 of the inverse */
                         -(b * i - c * h) / det, (a * i - c * g2) / det, -(a * h - b * g2) / det, /* column 1 */
                         (b * f - c * e) / det, -(a * f - c * d) / det, (a * e - b * d) / det};  /* column 2 */
    for (int col = 0; col < 3; col++) {
        for (int row = 0; row < 3; row++) inv[4 * col + row] = r[3 * col + row];
        inv[4 * col + 3] = 0;
    }
    for (int row = 0; row < 3; row++)
        inv[12 + row] = -(inv[row] * m[12] + inv[4 + row] * m[13] + inv[8 + row] * m[14]);
    inv[15] = 1;
    return 1;
}

/* Channel values of a sampler at t (clamped to its keyframes): STEP takes
 * the keyframe at or before t, LINEAR interpolates (a rotation by slerp,
 * glTF 2.0 Appendix C). */
static sss_result sample_channel(gltf *g, int ch, const cJSON *smp, int ncomp, double t, double *out)
{
    char what[48];
    snprintf(what, sizeof what, "animation 0 channel %d", ch);
    long long ii = get_index(g, smp, "input", g->nacc, 0, what, "accessor");
    long long io = get_index(g, smp, "output", g->nacc, 0, what, "accessor");
    if (ii < 0 || io < 0) return SSS_ERR_FORMAT;
    const cJSON *ip = cJSON_GetObjectItemCaseSensitive(smp, "interpolation");
    const char *mode = cJSON_IsString(ip) ? ip->valuestring : "LINEAR";
    if (strcmp(mode, "LINEAR") != 0 && strcmp(mode, "STEP") != 0)
        return bad(g, "%s: interpolation '%.20s' is not supported (LINEAR or STEP)", what, mode);
    acc in, o;
    sss_result r = get_acc(g, (int)ii, &in);
    if (r == SSS_OK) r = get_acc(g, (int)io, &o);
    if (r != SSS_OK) return r;
    if (in.ctype != C_FLOAT || in.ncomp != 1) return bad(g, "accessor %lld: a clip's times must be SCALAR float", ii);
    if (o.ctype != C_FLOAT || o.ncomp != ncomp || o.count != in.count)
        return bad(g, "accessor %lld: %s needs %llu float VEC%d values", io, what, in.count, ncomp);
    const ull n = in.count;
    double prev = -INFINITY;
    for (ull k = 0; k < n; k++) {
        const double tk = acc_float(&in, k, 0);
        if (!isfinite(tk) || tk < prev)
            return bad(g, "accessor %lld: keyframe %llu: times must be finite and increasing", ii, k);
        prev = tk;
        for (int c = 0; c < ncomp; c++)
            if (!isfinite(acc_float(&o, k, c))) return bad(g, "accessor %lld: value %llu is not finite", io, k);
    }
    const double t0 = acc_float(&in, 0, 0), t1 = acc_float(&in, n - 1, 0);
    if (!g->ex->animated || t0 < g->ex->clip_t0) g->ex->clip_t0 = t0;
    if (!g->ex->animated || t1 > g->ex->clip_t1) g->ex->clip_t1 = t1;
    g->ex->animated = 1;
    const double tc = t < t0 ? t0 : t > t1 ? t1 : t;
    ull k = 0;
    while (k + 1 < n && acc_float(&in, k + 1, 0) <= tc) k++;
    double a[4], b[4];
    for (int c = 0; c < ncomp; c++) a[c] = acc_float(&o, k, c), b[c] = acc_float(&o, k + 1 < n ? k + 1 : k, c);
    const double span = k + 1 < n ? acc_float(&in, k + 1, 0) - acc_float(&in, k, 0) : 0.0;
    const double u = !strcmp(mode, "STEP") || !(span > 0) ? 0.0 : (tc - acc_float(&in, k, 0)) / span;
    if (ncomp == 4) { /* slerp along the shorter arc */
        double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
        if (d < 0) {
            d = -d;
            for (int c = 0; c < 4; c++) b[c] = -b[c];
        }
        double wa = 1 - u, wb = u;
        if (d < 0.9995) {
            const double th = acos(d), st = sin(th);
            wa = sin((1 - u) * th) / st, wb = sin(u * th) / st;
        }
        for (int c = 0; c < 4; c++) out[c] = wa * a[c] + wb * b[c];
    } else {
        for (int c = 0; c < ncomp; c++) out[c] = (1 - u) * a[c] + u * b[c];
    }
    return SSS_OK;
}

/* Every node's global matrix at ex->pose_t into g->G: the local
 * transforms, the first animation's channels over them, then parent ·
 * child down each tree (a cycle or a second parent is refused here as
 * canon_nodes refuses it). */
static sss_result pose_nodes(gltf *g)
{
    const int nn = g->nnode;
    local_xf *L = calloc((size_t)nn + 1, sizeof *L);
    int *parent = malloc(((size_t)nn + 1) * sizeof *parent), *state = calloc((size_t)nn + 1, sizeof *state);
    g->G = malloc(((size_t)nn + 1) * 16 * sizeof *g->G);
    sss_result r = SSS_OK;
    if (!L || !parent || !state || !g->G) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory for %d nodes", g->s->name, nn);
    for (int n = 0; r == SSS_OK && n < nn; n++) parent[n] = -1, node_local(g->nodes[n], &L[n]);
    for (int n = 0; r == SSS_OK && n < nn; n++) {
        const cJSON *ch = cJSON_IsObject(g->nodes[n]) ? cJSON_GetObjectItemCaseSensitive(g->nodes[n], "children") : NULL;
        const cJSON *c;
        cJSON_ArrayForEach(c, ch) {
            const double d = cJSON_IsNumber(c) ? c->valuedouble : -1.0;
            if (!(d >= 0.0 && d < nn && d == floor(d)) || d == n || parent[(int)d] >= 0) {
                r = bad(g, "node %d: child is not a node index in [0, %d) of its own (nodes must form trees)", n, nn);
                break;
            }
            parent[(int)d] = n;
        }
    }
    int na = 0, failed = 0;
    cJSON *anims = r == SSS_OK ? get_array(g, g->root, "animations", &na, &failed) : NULL;
    if (failed) r = SSS_ERR_FORMAT;
    if (r == SSS_OK && na > 0) {
        const cJSON *a0 = cJSON_GetArrayItem(anims, 0);
        int nch = 0, nsm = 0;
        cJSON *chs = cJSON_IsObject(a0) ? get_array(g, a0, "channels", &nch, &failed) : NULL;
        cJSON *sms = cJSON_IsObject(a0) ? get_array(g, a0, "samplers", &nsm, &failed) : NULL;
        if (failed) r = SSS_ERR_FORMAT;
        cJSON **smv = r == SSS_OK ? items(sms, nsm) : NULL;
        if (r == SSS_OK && !smv) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", g->s->name);
        int ci = 0;
        const cJSON *c;
        cJSON_ArrayForEach(c, chs) {
            if (r != SSS_OK) break;
            char what[48];
            snprintf(what, sizeof what, "animation 0 channel %d", ci);
            const cJSON *tg = cJSON_IsObject(c) ? cJSON_GetObjectItemCaseSensitive(c, "target") : NULL;
            const cJSON *path = cJSON_IsObject(tg) ? cJSON_GetObjectItemCaseSensitive(tg, "path") : NULL;
            long long si = cJSON_IsObject(c) ? get_index(g, c, "sampler", nsm, 0, what, "sampler") : -1;
            long long ni = cJSON_IsObject(tg) && cJSON_GetObjectItemCaseSensitive(tg, "node")
                               ? get_index(g, tg, "node", nn, 0, what, "node")
                               : -1;
            /* get_index has named the fault when it returned -1 for a
             * member that is there; a missing object or node is named here */
            if (!cJSON_IsObject(c)) { r = bad(g, "%s: not an object", what); break; }
            if (!cJSON_IsObject(tg) || !cJSON_GetObjectItemCaseSensitive(tg, "node")) {
                r = bad(g, "%s: no target node", what);
                break;
            }
            if (si < 0 || ni < 0 || !cJSON_IsString(path)) {
                r = si < 0 || ni < 0 ? SSS_ERR_FORMAT : bad(g, "%s: no target path", what);
                break;
            }
            const char *pth = path->valuestring;
            double *dst = !strcmp(pth, "translation") ? L[ni].t : !strcmp(pth, "rotation") ? L[ni].r
                                                                : !strcmp(pth, "scale")      ? L[ni].s
                                                                                             : NULL;
            if (dst && L[ni].has_m) r = bad(g, "%s: node %lld has a matrix and may not be animated", what, ni);
            else if (dst) r = sample_channel(g, ci, smv[si], !strcmp(pth, "rotation") ? 4 : 3, g->ex->pose_t, dst);
            ci++; /* "weights" (morph targets) are not applied */
        }
        free(smv);
    }
    /* global matrices, each node once, down from its root */
    for (int n = 0; r == SSS_OK && n < nn; n++) {
        int k = n, steps = 0;
        while (state[k] == 0 && parent[k] >= 0 && steps++ <= nn) k = parent[k];
        if (steps > nn) { r = bad(g, "node %d: the hierarchy has a cycle through it", n); break; }
        /* k is a root or done: walk back down, each step from its parent */
        int chain[DEPTH_MAX + 2], len = 0;
        for (int j = n; j != k && len <= DEPTH_MAX; j = parent[j]) chain[len++] = j;
        if (len > DEPTH_MAX) { r = bad(g, "node %d: more than %d levels deep in the hierarchy", n, DEPTH_MAX); break; }
        if (state[k] == 0) { local_matrix(&L[k], &g->G[16 * (size_t)k]); state[k] = 1; }
        for (int i = len - 1; i >= 0; i--) {
            double l[16];
            local_matrix(&L[chain[i]], l);
            sss_mat4_mul(&g->G[16 * (size_t)parent[chain[i]]], l, &g->G[16 * (size_t)chain[i]]);
            state[chain[i]] = 1;
        }
    }
    free(L);
    free(parent);
    free(state);
    return r;
}

/* Primitive pr of skinned mesh m posed: *posed (3 floats a vertex,
 * caller frees) and pr->pos made to read it. */
static sss_result pose_prim(gltf *g, int m, const cJSON *attrs, prim *pr, float **posed)
{
    *posed = NULL;
    const int sk = g->mesh_skin[m];
    /* the one node that instances the mesh: its transform is undone, the
     * joints place the mesh (glTF 2.0 §3.7.3.3) */
    int mn = -1, uses = 0;
    for (int n = 0; n < g->nnode; n++) {
        const cJSON *o = g->nodes[n], *mi = cJSON_IsObject(o) ? cJSON_GetObjectItemCaseSensitive(o, "mesh") : NULL;
        if (cJSON_IsNumber(mi) && mi->valuedouble == m) mn = n, uses++;
    }
    if (uses != 1) return bad(g, "mesh %d: skinned and used by %d nodes; posing needs exactly one", m, uses);
    double Ginv[16];
    if (!affine_inverse(&g->G[16 * (size_t)mn], Ginv)) return bad(g, "node %d: its transform is singular", mn);
    const cJSON *so = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(g->root, "skins"), sk);
    const cJSON *jl = cJSON_GetObjectItemCaseSensitive(so, "joints");
    const int nj = cJSON_GetArraySize(jl);
    double *J = malloc((size_t)nj * 16 * sizeof *J);
    if (!J) return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", g->s->name);
    acc ibm = {0};
    int has_ibm = cJSON_GetObjectItemCaseSensitive(so, "inverseBindMatrices") != NULL;
    char what[32];
    snprintf(what, sizeof what, "skin %d", sk);
    if (has_ibm) {
        long long ia = get_index(g, so, "inverseBindMatrices", g->nacc, 0, what, "accessor");
        sss_result r = ia < 0 ? SSS_ERR_FORMAT : get_acc(g, (int)ia, &ibm);
        if (r == SSS_OK && (ibm.ctype != C_FLOAT || ibm.ncomp != 16 || ibm.count < (ull)nj))
            r = bad(g, "accessor %lld: inverseBindMatrices must be %d MAT4 of float", ia, nj);
        if (r != SSS_OK) { free(J); return r; }
    }
    int k = 0;
    const cJSON *jn;
    cJSON_ArrayForEach(jn, jl) { /* J_k = G(joint k) · IBM_k, then the mesh node's transform undone */
        double ib[16], t1[16];
        for (int e = 0; e < 16; e++) ib[e] = has_ibm ? acc_float(&ibm, (ull)k, e) : e % 5 == 0;
        sss_mat4_mul(&g->G[16 * (size_t)(int)jn->valuedouble], ib, t1);
        sss_mat4_mul(Ginv, t1, &J[16 * (size_t)k]);
        k++;
    }
    long long ij = get_index(g, attrs, "JOINTS_0", g->nacc, 0, "JOINTS_0", "accessor");
    long long iw = get_index(g, attrs, "WEIGHTS_0", g->nacc, 0, "WEIGHTS_0", "accessor");
    acc ja, wa;
    sss_result r = get_acc(g, (int)ij, &ja);
    if (r == SSS_OK) r = get_acc(g, (int)iw, &wa);
    float *out = r == SSS_OK ? malloc((size_t)pr->nv * 3 * sizeof *out + 1) : NULL;
    if (r == SSS_OK && !out) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", g->s->name);
    for (ull e = 0; r == SSS_OK && e < pr->nv; e++) {
        const double p[3] = {acc_float(&pr->pos, e, 0), acc_float(&pr->pos, e, 1), acc_float(&pr->pos, e, 2)};
        double q[3], w[4];
        uint32_t j[4];
        for (int c = 0; c < 4; c++) { /* check_skin: j_i < joints, Σ w_i = 1 */
            w[c] = acc_float(&wa, e, c);
            j[c] = (uint32_t)rd_uint(ja.base + e * ja.stride + (ull)c * (ull)ja.csize, (size_t)ja.csize, 0);
        }
        sss_skin_blend(J, j, w, 4, p, q); /* Σ_i w_i J_{j_i} p */
        for (int a = 0; a < 3; a++) {
            if (!(fabs(q[a]) <= SSS_COORD_MAX)) r = bad(g, "mesh %d: posed vertex %llu leaves the coordinate range", m, e);
            out[3 * e + (ull)a] = (float)q[a];
        }
    }
    free(J);
    if (r != SSS_OK) { free(out); return r; }
    pr->pos.base = (const unsigned char *)out;
    pr->pos.stride = 12;
    pr->pos.ctype = C_FLOAT;
    pr->pos.csize = 4;
    pr->pos.ncomp = 3;
    pr->pos.normalized = 0;
    *posed = out;
    return SSS_OK;
}

/* Checks primitive p of mesh m; *skip when it has no surface (points or
 * lines). */
static sss_result get_prim(gltf *g, int m, int p, const cJSON *o, prim *pr, int *skip)
{
    char what[64];
    snprintf(what, sizeof what, "mesh %d primitive %d", m, p);
    memset(pr, 0, sizeof *pr);
    *skip = 0;
    if (!cJSON_IsObject(o)) return bad(g, "%s: not an object", what);
    long long mode = get_uint(g, o, "mode", 4, what);
    if (mode < 0) return SSS_ERR_FORMAT;
    if (mode <= 3) { *skip = 1; return SSS_OK; }
    if (mode == 5 || mode == 6)
        return bad(g, "%s: mode %lld (triangle %s) is not supported; export plain triangles", what, mode,
                   mode == 5 ? "strip" : "fan");
    if (mode != 4) return bad(g, "%s: mode %lld is not one of glTF's", what, mode);
    const cJSON *attrs = cJSON_GetObjectItemCaseSensitive(o, "attributes");
    if (!cJSON_IsObject(attrs)) return bad(g, "%s: no 'attributes'", what);
    char w2[96];
    snprintf(w2, sizeof w2, "%s: POSITION", what);
    long long pi = get_index(g, attrs, "POSITION", g->nacc, 0, w2, "accessor");
    if (pi < 0) return SSS_ERR_FORMAT;
    sss_result r = get_acc(g, (int)pi, &pr->pos);
    if (r != SSS_OK) return r;
    if (pr->pos.ctype != C_FLOAT || pr->pos.ncomp != 3) return bad(g, "accessor %lld: POSITION must be VEC3 of float", pi);
    pr->nv = pr->pos.count;
    if (pr->nv > (ull)INT32_MAX) return bad(g, "accessor %lld: %llu vertices; at most 2^31-1 are supported", pi, pr->nv);
    for (ull e = 0; e < pr->nv; e++)
        for (int c = 0; c < 3; c++)
            if (!isfinite(acc_float(&pr->pos, e, c)))
                return bad(g, "accessor %lld: element %llu: coordinate is not finite", pi, e);
    if ((r = get_attr(g, attrs, "TEXCOORD_0", what, pr->nv, &pr->uv, &pr->has_uv)) != SSS_OK) return r;
    if ((r = get_attr(g, attrs, "COLOR_0", what, pr->nv, &pr->col, &pr->has_col)) != SSS_OK) return r;
    if ((r = check_skin(g, m, attrs, what, pr->nv)) != SSS_OK) return r;
    if (cJSON_GetObjectItemCaseSensitive(o, "indices")) {
        long long ii = get_index(g, o, "indices", g->nacc, 0, what, "accessor");
        if (ii < 0) return SSS_ERR_FORMAT;
        if ((r = get_acc(g, (int)ii, &pr->idx)) != SSS_OK) return r;
        if (pr->idx.ncomp != 1 || pr->idx.normalized ||
            (pr->idx.ctype != C_UBYTE && pr->idx.ctype != C_USHORT && pr->idx.ctype != C_UINT))
            return bad(g, "accessor %lld: indices must be SCALAR unsigned byte, short or int", ii);
        if (pr->idx.count % 3)
            return bad(g, "accessor %lld: %llu indices is not a whole number of triangles", ii, pr->idx.count);
        for (ull e = 0; e < pr->idx.count; e++) {
            ull v = acc_uint(&pr->idx, e);
            if (v >= pr->nv) return bad(g, "accessor %lld: index %llu out of range [0, %llu)", ii, v, pr->nv);
        }
        pr->has_idx = 1;
        pr->ni = pr->idx.count;
    } else {
        if (pr->nv % 3) return bad(g, "%s: %llu vertices without indices is not a whole number of triangles", what, pr->nv);
        pr->ni = pr->nv;
    }
    return SSS_OK;
}

/* A node's transform: "matrix" (16 finite numbers) or translation (3),
 * rotation (4, a quaternion of non-zero length) and scale (3), copied into
 * the canonical node. */
static sss_result copy_transform(gltf *g, int n, const cJSON *o, cJSON *out)
{
    static const struct { const char *key; int len; } t[] = {{"matrix", 16}, {"translation", 3}, {"rotation", 4}, {"scale", 3}};
    for (size_t k = 0; k < 4; k++) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, t[k].key);
        if (!a) continue;
        double v[16], q = 0.0;
        if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != t[k].len)
            return bad(g, "node %d: '%s' is not an array of %d numbers", n, t[k].key, t[k].len);
        for (int i = 0; i < t[k].len; i++) {
            const cJSON *x = cJSON_GetArrayItem(a, i);
            if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble) || fabs(x->valuedouble) > SSS_COORD_MAX)
                return bad(g, "node %d: %s[%d] is not a finite number", n, t[k].key, i);
            v[i] = x->valuedouble;
            q += v[i] * v[i];
        }
        if (t[k].len == 4 && !(q > 0.0)) return bad(g, "node %d: rotation is a zero quaternion", n);
        cJSON_AddItemToObject(out, t[k].key, cJSON_CreateDoubleArray(v, t[k].len));
    }
    return SSS_OK;
}

/* The canonical GLB's binary chunk, grown as primitives are appended. */
typedef struct blob {
    unsigned char *p;
    size_t n, cap;
} blob;

static unsigned char *blob_add(blob *b, size_t n)
{
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + n) cap *= 2;
        unsigned char *q = realloc(b->p, cap);
        if (!q) return NULL;
        b->p = q;
        b->cap = cap;
    }
    unsigned char *at = b->p + b->n;
    b->n += n;
    return at;
}

/* Appends count elements of ncomp floats (or uint32 indices) as one
 * bufferView and accessor of the canonical file; returns the accessor's
 * index, or -1 when out of memory. */
static int put_acc(blob *b, cJSON *views, cJSON *accs, const acc *a, ull count, int ncomp, int as_index)
{
    size_t bytes = (size_t)count * (size_t)ncomp * 4;
    size_t off = b->n;
    unsigned char *p = blob_add(b, bytes);
    if (!p) return -1;
    for (ull e = 0; e < count; e++)
        for (int c = 0; c < ncomp; c++) {
            uint32_t w;
            if (as_index) w = a ? (uint32_t)acc_uint(a, e) : (uint32_t)e;
            else {
                /* COLOR_0 of three components gets alpha 1 (glTF 2.0 §3.7.2.1) */
                float f = c < a->ncomp ? acc_float(a, e, c) : 1.0f;
                memcpy(&w, &f, 4);
            }
            for (int k = 0; k < 4; k++) p[((size_t)e * (size_t)ncomp + (size_t)c) * 4 + (size_t)k] = (unsigned char)(w >> (8 * k));
        }
    cJSON *v = cJSON_CreateObject();
    cJSON_AddNumberToObject(v, "buffer", 0);
    cJSON_AddNumberToObject(v, "byteOffset", (double)off);
    cJSON_AddNumberToObject(v, "byteLength", (double)bytes);
    cJSON_AddItemToArray(views, v);
    cJSON *x = cJSON_CreateObject();
    cJSON_AddNumberToObject(x, "bufferView", cJSON_GetArraySize(views) - 1);
    cJSON_AddNumberToObject(x, "componentType", as_index ? C_UINT : C_FLOAT);
    cJSON_AddNumberToObject(x, "count", (double)count);
    cJSON_AddStringToObject(x, "type", ncomp == 1 ? "SCALAR" : ncomp == 2 ? "VEC2" : ncomp == 3 ? "VEC3" : "VEC4");
    if (ncomp == 3 && !as_index) {
        /* glTF requires min and max on POSITION; Assimp does not read them */
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (ull e = 0; e < count; e++)
            for (int c = 0; c < 3; c++) {
                double f = acc_float(a, e, c);
                if (f < lo[c]) lo[c] = f;
                if (f > hi[c]) hi[c] = f;
            }
        cJSON_AddItemToObject(x, "min", cJSON_CreateDoubleArray(lo, 3));
        cJSON_AddItemToObject(x, "max", cJSON_CreateDoubleArray(hi, 3));
    }
    cJSON_AddItemToArray(accs, x);
    return cJSON_GetArraySize(accs) - 1;
}

/* Meshes: checks every primitive and writes the triangle ones into the
 * canonical file. Per mesh m: vert[m] and tri[m], what one instance of it
 * adds, and canon[m], its canonical index (-1: no triangles). */
static sss_result canon_meshes(gltf *g, blob *b, cJSON *out, ull *vert, ull *tri, int *canon, expect *ex)
{
    cJSON *views = cJSON_AddArrayToObject(out, "bufferViews");
    cJSON *accs = cJSON_AddArrayToObject(out, "accessors");
    cJSON *meshes = cJSON_AddArrayToObject(out, "meshes");
    int ncanon = 0;
    ull held = 0, cap = sat_add(ELEMENTS_BASE, sat_mul(ELEMENTS_PER_BYTE, g->s->size));
    for (int m = 0; m < g->nmesh; m++) {
        const cJSON *mo = g->meshes[m];
        const cJSON *ps = cJSON_IsObject(mo) ? cJSON_GetObjectItemCaseSensitive(mo, "primitives") : NULL;
        if (!cJSON_IsArray(ps) || cJSON_GetArraySize(ps) == 0) return bad(g, "mesh %d: no 'primitives'", m);
        vert[m] = tri[m] = 0;
        canon[m] = -1;
        cJSON *cprims = NULL;
        int p = -1;
        const cJSON *po;
        cJSON_ArrayForEach(po, ps) {
            p++;
            prim pr;
            int skip;
            sss_result r = get_prim(g, m, p, po, &pr, &skip);
            if (r != SSS_OK) return r;
            if (skip) {
                ex->skipped++;
                continue;
            }

            held = sat_add(held, sat_add(pr.nv, pr.ni / 3));
            if (held > cap)
                return bad(g, "mesh %d primitive %d: the primitives hold more than %llu vertices and triangles, the most a file of %llu bytes may", m, p, cap, g->s->size);
            if (!cprims) {
                cJSON *cm = cJSON_CreateObject();
                cJSON_AddItemToArray(meshes, cm);
                cprims = cJSON_AddArrayToObject(cm, "primitives");
                canon[m] = ncanon++;
            }
            cJSON *cp = cJSON_CreateObject();
            cJSON_AddItemToArray(cprims, cp);
            cJSON *at = cJSON_AddObjectToObject(cp, "attributes");
            /* a skinned primitive posed (sss_import_mesh_at): pr.pos reads
             * the posed copy while it is packed */
            float *posed = NULL;
            const cJSON *pat = cJSON_GetObjectItemCaseSensitive(po, "attributes");
            if (g->G && g->mesh_skin[m] >= 0 && cJSON_GetObjectItemCaseSensitive(pat, "JOINTS_0") &&
                (r = pose_prim(g, m, pat, &pr, &posed)) != SSS_OK)
                return r;
            int ip = put_acc(b, views, accs, &pr.pos, pr.nv, 3, 0);
            free(posed);
            int iu = pr.has_uv ? put_acc(b, views, accs, &pr.uv, pr.nv, 2, 0) : 0;
            int ic = pr.has_col ? put_acc(b, views, accs, &pr.col, pr.nv, 4, 0) : 0;
            int ii = put_acc(b, views, accs, pr.has_idx ? &pr.idx : NULL, pr.ni, 1, 1);
            if (ip < 0 || iu < 0 || ic < 0 || ii < 0)
                return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory for mesh %d", g->s->name, m);
            cJSON_AddNumberToObject(at, "POSITION", ip);
            if (pr.has_uv) cJSON_AddNumberToObject(at, "TEXCOORD_0", iu);
            if (pr.has_col) cJSON_AddNumberToObject(at, "COLOR_0", ic);
            cJSON_AddNumberToObject(cp, "indices", ii);
            cJSON_AddNumberToObject(cp, "mode", 4);
            vert[m] += pr.nv;
            tri[m] += pr.ni / 3;
            ex->texcoords |= pr.has_uv;
            ex->colours |= pr.has_col;
        }
    }
    return SSS_OK;
}

/* Nodes: indices in range, no node the child of two parents or of itself
 * (glTF 2.0 §3.5.2: the hierarchy is a set of disjoint trees), finite
 * transforms; copied into the canonical file with their mesh renumbered. */
static sss_result canon_nodes(gltf *g, cJSON *out, const int *canon, int *parent)
{
    cJSON *nodes = cJSON_AddArrayToObject(out, "nodes");
    for (int n = 0; n < g->nnode; n++) parent[n] = -1;
    for (int n = 0; n < g->nnode; n++) {
        char what[32];
        snprintf(what, sizeof what, "node %d", n);
        const cJSON *o = g->nodes[n];
        if (!cJSON_IsObject(o)) return bad(g, "%s: not an object", what);
        cJSON *cn = cJSON_CreateObject();
        cJSON_AddItemToArray(nodes, cn);
        long long mi = get_index(g, o, "mesh", g->nmesh, 1, what, "mesh");
        if (mi == -1) return SSS_ERR_FORMAT;
        if (mi >= 0 && canon[mi] >= 0) cJSON_AddNumberToObject(cn, "mesh", canon[mi]);
        sss_result r = copy_transform(g, n, o, cn);
        if (r != SSS_OK) return r;
        const cJSON *ch = cJSON_GetObjectItemCaseSensitive(o, "children");
        if (!ch) continue;
        if (!cJSON_IsArray(ch)) return bad(g, "%s: 'children' is not an array", what);
        cJSON *cc = cJSON_AddArrayToObject(cn, "children");
        const cJSON *c;
        cJSON_ArrayForEach(c, ch) {
            double d = cJSON_IsNumber(c) ? c->valuedouble : -1.0;
            if (!(d >= 0.0 && d < g->nnode && d == floor(d))) return bad(g, "%s: child is not a node index in [0, %d)", what, g->nnode);
            int k = (int)d;
            if (k == n || parent[k] >= 0)
                return bad(g, "%s: child %d already has a parent (node %d); nodes must form trees", what, k, k == n ? n : parent[k]);
            parent[k] = n;
            cJSON_AddItemToArray(cc, cJSON_CreateNumber(k));
        }
    }
    /* One parent each, but a loop of nodes (a parent of b, b of a) has no
     * root. Each node's depth is its parent's plus one, found once by
     * walking up to a node already known (linear time on a long chain);
     * depth[] reuses the walk's marks: 0 unknown, -1 on the current walk. */
    int *depth = calloc((size_t)g->nnode + 1, sizeof *depth);
    if (!depth) return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory for %d nodes", g->s->name, g->nnode);
    sss_result r = SSS_OK;
    for (int n = 0; n < g->nnode && r == SSS_OK; n++) {
        int k = n;
        while (depth[k] == 0 && parent[k] >= 0) {
            depth[k] = -1;
            k = parent[k];
        }
        if (depth[k] == -1) {
            r = bad(g, "node %d: the hierarchy has a cycle through it", k);
            break;
        }
        int d = depth[k] > 0 ? depth[k] : 1; /* a root is at depth 1 */
        depth[k] = d;
        /* down again from n, numbering the nodes just walked */
        int len = 0;
        for (int j = n; j != k; j = parent[j]) len++;
        for (int j = n, i = 0; j != k; j = parent[j], i++) depth[j] = d + len - i;
        if (depth[n] > DEPTH_MAX) r = bad(g, "node %d: more than %d levels deep in the hierarchy", n, DEPTH_MAX);
    }
    free(depth);
    return r;
}

/* The scene: its root nodes (parentless, each once) into the canonical
 * file, and the vertices and triangles of every mesh instance under them
 * into ex (each node is reached once: the nodes form trees). */
static sss_result canon_scene(gltf *g, cJSON *out, const ull *vert, const ull *tri, const int *parent, expect *ex)
{
    int nscene = 0, failed = 0;
    cJSON *scenes = get_array(g, g->root, "scenes", &nscene, &failed);
    if (failed) return SSS_ERR_FORMAT;
    if (nscene == 0) return bad(g, "no scene: nothing places a mesh in the world");
    long long si = get_index(g, g->root, "scene", nscene, 1, "scene", "scene");
    if (si == -1) return SSS_ERR_FORMAT;
    if (si == -2) si = 0;
    char what[32];
    snprintf(what, sizeof what, "scene %lld", si);
    const cJSON *so = cJSON_GetArrayItem(scenes, (int)si);
    if (!cJSON_IsObject(so)) return bad(g, "%s: not an object", what);
    const cJSON *roots = cJSON_GetObjectItemCaseSensitive(so, "nodes");
    if (roots && !cJSON_IsArray(roots)) return bad(g, "%s: 'nodes' is not an array", what);
    cJSON_AddNumberToObject(out, "scene", 0);
    cJSON *cs = cJSON_CreateObject();
    cJSON_AddItemToArray(cJSON_AddArrayToObject(out, "scenes"), cs);
    cJSON *croots = cJSON_AddArrayToObject(cs, "nodes");
    int *stack = malloc(((size_t)g->nnode + 1) * sizeof *stack);
    unsigned char *seen = calloc((size_t)g->nnode + 1, 1);
    if (!stack || !seen) {
        free(stack); free(seen);
        return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory for %d nodes", g->s->name, g->nnode);
    }
    ull cap = sat_add(ELEMENTS_BASE, sat_mul(ELEMENTS_PER_BYTE, g->s->size));
    sss_result r = SSS_OK;
    const cJSON *c;
    cJSON_ArrayForEach(c, roots) {
        double d = cJSON_IsNumber(c) ? c->valuedouble : -1.0;
        if (!(d >= 0.0 && d < g->nnode && d == floor(d))) { r = bad(g, "%s: root is not a node index in [0, %d)", what, g->nnode); break; }
        int n0 = (int)d;
        if (parent[n0] >= 0 || seen[n0]) { r = bad(g, "%s: node %d is not a root (it has a parent or is listed twice)", what, n0); break; }
        cJSON_AddItemToArray(croots, cJSON_CreateNumber(n0));
        int top = 0;
        stack[top++] = n0;
        while (top > 0 && r == SSS_OK) {
            int n = stack[--top];
            seen[n] = 1;
            const cJSON *o = g->nodes[n];
            const cJSON *mi = cJSON_GetObjectItemCaseSensitive(o, "mesh");
            if (mi) {
                int m = (int)mi->valuedouble; /* checked by canon_nodes */
                ex->nv = sat_add(ex->nv, vert[m]);
                ex->nf = sat_add(ex->nf, tri[m]);
                if (sat_add(ex->nv, ex->nf) > cap)
                    r = bad(g, "node %d: the scene places more than %llu vertices and triangles, the most a file of %llu bytes may", n, cap, g->s->size);
            }
            /* the order of the visit does not change the counts */
            const cJSON *k;
            cJSON_ArrayForEach(k, cJSON_GetObjectItemCaseSensitive(o, "children")) stack[top++] = (int)k->valuedouble;
        }
        if (r != SSS_OK) break;
    }
    free(stack);
    free(seen);
    return r;
}

/* GLB (glTF 2.0 §4.4): 12-byte header, then a JSON chunk and an optional
 * binary chunk, each 4-byte aligned; the header's length is the file's. */
static sss_result parse_glb(gltf *g, const unsigned char *d, ull size, const unsigned char **json, ull *jlen)
{
    if (size < 20) return bad(g, "GLB header: %llu bytes, too short for a header and a chunk", size);
    ull ver = rd_uint(d + 4, 4, 0), len = rd_uint(d + 8, 4, 0);
    if (ver != 2) return bad(g, "GLB header: version %llu, expected 2", ver);
    if (len != size) return bad(g, "GLB header: length %llu but the file has %llu bytes (truncated?)", len, size);
    ull at = 12;
    for (int chunk = 0; at < size; chunk++) {
        if (size - at < 8) return bad(g, "GLB chunk %d: header cut off at byte %llu", chunk, at);
        ull clen = rd_uint(d + at, 4, 0), type = rd_uint(d + at + 4, 4, 0);
        at += 8;
        if (clen > size - at) return bad(g, "GLB chunk %d: length %llu runs past the end of the file", chunk, clen);
        if (clen % 4) return bad(g, "GLB chunk %d: length %llu is not a multiple of 4", chunk, clen);
        if (chunk == 0) {
            if (type != GLB_JSON) return bad(g, "GLB chunk 0: type 0x%08llx, expected JSON", type);
            *json = d + at;
            *jlen = clen;
        } else if (chunk == 1 && type == GLB_BIN) {
            g->bin = d + at;
            g->bin_len = clen;
        }
        at += clen;
    }
    return SSS_OK;
}

static void gltf_free(gltf *g)
{
    for (int i = 0; g->buf && i < g->nbuf; i++) free(g->buf[i].own);
    free(g->buf);
    free(g->buffers); free(g->views); free(g->accs); free(g->nodes); free(g->meshes);
    free(g->mesh_joints); free(g->mesh_skin); free(g->G);
    cJSON_Delete(g->root);
}

/* Checks and canonicalises; the canonical GLB goes to ex->own. */
static sss_result scan(gltf *g, expect *ex)
{
    src *s = g->s;
    sss_result r = sss_src_read_all(s, g->err);
    if (r != SSS_OK) return r;
    const unsigned char *d = (const unsigned char *)s->data, *json = d;
    ull jlen = s->size;
    if (s->size >= 4 && rd_uint(d, 4, 0) == GLB_MAGIC) {
        if ((r = parse_glb(g, d, s->size, &json, &jlen)) != SSS_OK) return r;
    } else {
        const char *dot = strrchr(s->name, '.');
        if (dot && tok_is_ci((tok){(char *)dot, strlen(dot)}, ".glb"))
            return bad(g, "GLB header: no 'glTF' magic at the start");
    }
    g->root = cJSON_ParseWithLength((const char *)json, (size_t)jlen);
    if (!g->root) {
        const char *at = cJSON_GetErrorPtr();
        ull off = at && at >= (const char *)json && at <= (const char *)json + jlen ? (ull)(at - (const char *)json) : 0;
        return bad(g, "JSON: syntax error near byte %llu", off);
    }
    if (!cJSON_IsObject(g->root)) return bad(g, "JSON: the top level is not an object");
    const cJSON *asset = cJSON_GetObjectItemCaseSensitive(g->root, "asset");
    const cJSON *ver = cJSON_IsObject(asset) ? cJSON_GetObjectItemCaseSensitive(asset, "version") : NULL;
    if (!cJSON_IsString(ver) || strncmp(ver->valuestring, "2.", 2) != 0)
        return bad(g, "asset: 'version' is not \"2.x\" (only glTF 2.0 is read)");
    int failed = 0, nreq = 0;
    cJSON *req = get_array(g, g->root, "extensionsRequired", &nreq, &failed);
    if (failed) return SSS_ERR_FORMAT;
    if (nreq > 0) {
        const cJSON *e = cJSON_GetArrayItem(req, 0);
        return bad(g, "extensionsRequired: '%.40s' is not supported", cJSON_IsString(e) ? e->valuestring : "?");
    }
    cJSON *bufs = get_array(g, g->root, "buffers", &g->nbuf, &failed);
    cJSON *views = get_array(g, g->root, "bufferViews", &g->nview, &failed);
    cJSON *accs = get_array(g, g->root, "accessors", &g->nacc, &failed);
    cJSON *nodes = get_array(g, g->root, "nodes", &g->nnode, &failed);
    cJSON *meshes = get_array(g, g->root, "meshes", &g->nmesh, &failed);
    if (failed) return SSS_ERR_FORMAT;
    g->buffers = items(bufs, g->nbuf);
    g->views = items(views, g->nview);
    g->accs = items(accs, g->nacc);
    g->nodes = items(nodes, g->nnode);
    g->meshes = items(meshes, g->nmesh);
    if (!g->buffers || !g->views || !g->accs || !g->nodes || !g->meshes)
        return sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    g->buf = calloc((size_t)g->nbuf + 1, sizeof *g->buf);
    ull *vert = malloc(((size_t)g->nmesh + 1) * sizeof *vert);
    ull *tri = malloc(((size_t)g->nmesh + 1) * sizeof *tri);
    int *canon = malloc(((size_t)g->nmesh + 1) * sizeof *canon);
    int *parent = malloc(((size_t)g->nnode + 1) * sizeof *parent);
    cJSON *out = cJSON_CreateObject();
    blob b = {0};
    if (!g->buf || !vert || !tri || !canon || !parent || !out)
        r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    g->mesh_joints = malloc(((size_t)g->nmesh + 1) * sizeof *g->mesh_joints);
    g->mesh_skin = malloc(((size_t)g->nmesh + 1) * sizeof *g->mesh_skin);
    if (r == SSS_OK && (!g->mesh_joints || !g->mesh_skin)) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    if (r == SSS_OK) r = skin_joints(g);
    g->ex = ex;
    if (r == SSS_OK && ex->pose) r = pose_nodes(g);
    if (r == SSS_OK) {
        cJSON *a = cJSON_AddObjectToObject(out, "asset");
        cJSON_AddStringToObject(a, "version", "2.0");
        r = canon_meshes(g, &b, out, vert, tri, canon, ex);
    }
    if (r == SSS_OK) r = canon_nodes(g, out, canon, parent);
    if (r == SSS_OK) r = canon_scene(g, out, vert, tri, parent, ex);
    if (r == SSS_OK && ex->nf == 0)
        r = sss_fail(g->err, SSS_ERR_MESH, "%s: no triangles in the scene (%llu primitives of points or lines skipped)",
                     s->name, ex->skipped);
    char *text = NULL;
    if (r == SSS_OK) {
        cJSON *buffers = cJSON_AddArrayToObject(out, "buffers");
        cJSON *b0 = cJSON_CreateObject();
        cJSON_AddNumberToObject(b0, "byteLength", (double)b.n);
        cJSON_AddItemToArray(buffers, b0);
        text = cJSON_PrintUnformatted(out);
        if (!text) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    }
    if (r == SSS_OK) {
        size_t tl = strlen(text), tp = (tl + 3) & ~(size_t)3, bp = (b.n + 3) & ~(size_t)3;
        size_t total = 12 + 8 + tp + 8 + bp;
        unsigned char *glb = total <= UINT32_MAX ? malloc(total) : NULL;
        if (!glb) r = sss_fail(g->err, SSS_ERR_NOMEM, "%s: out of memory for %zu bytes", s->name, total);
        else {
            const uint32_t head[5] = {GLB_MAGIC, 2, (uint32_t)total, (uint32_t)tp, GLB_JSON};
            for (int k = 0; k < 5; k++)
                for (int j = 0; j < 4; j++) glb[4 * k + j] = (unsigned char)(head[k] >> (8 * j));
            memcpy(glb + 20, text, tl);
            memset(glb + 20 + tl, ' ', tp - tl);
            const uint32_t bhead[2] = {(uint32_t)bp, GLB_BIN};
            for (int k = 0; k < 2; k++)
                for (int j = 0; j < 4; j++) glb[20 + tp + 4 * (size_t)k + (size_t)j] = (unsigned char)(bhead[k] >> (8 * j));
            if (b.n) memcpy(glb + 28 + tp, b.p, b.n);
            memset(glb + 28 + tp + b.n, 0, bp - b.n);
            ex->own = (char *)glb;
            ex->om_data = (char *)glb;
            ex->om_len = total;
            ex->faces_in_file = ex->nf;
            ex->nv_max = ex->nv;
            ex->nf_max = ex->nf;
        }
    }
    cJSON_free(text);
    cJSON_Delete(out);
    free(b.p);
    free(vert);
    free(tri);
    free(canon);
    free(parent);
    return r;
}

sss_result sss_scan_gltf(src *s, expect *ex, sss_error *err)
{
    gltf g;
    memset(&g, 0, sizeof g);
    g.s = s;
    g.err = err;
    sss_result r = scan(&g, ex);
    gltf_free(&g);
    return r;
}
