/* import_obj.c: the OBJ scanner (input/import_internal.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

/* The statements of the OBJ specification (Wavefront, Appendix B1 of the
 * Advanced Visualizer manual) other than v and f. */
static int known_statement(tok kw)
{
    static const char *const known[] = {"vt", "vn", "vp", "g", "o", "s", "mg", "usemtl", "mtllib", "l", "p",
                                        "curv", "curv2", "surf", "cstype", "deg", "bmat", "step", "parm", "trim",
                                        "hole", "scrv", "sp", "end", "con", "bevel", "c_interp", "d_interp", "lod",
                                        "usemap", "maplib", "shadow_obj", "trace_obj", "ctech", "stech", "call",
                                        "csh", NULL};
    for (const char *const *k = known; *k; k++)
        if (tok_is(kw, *k)) return 1;
    return 0;
}

/* The texture coordinates of an OBJ file: each vertex takes the vt of the
 * first face corner that names one ("f v/vt ..."; a vertex on a seam,
 * whose corners name different vt, keeps its first). They are kept only
 * when every vertex that a face uses has one, every vt named is a pair
 * of finite numbers (a missing v is 0, as the specification says) and no
 * face comes before the first vt: otherwise the mesh has none, as before. */
typedef struct obj_uv {
    float *vt;        /* 2 per vt statement */
    ull nvt, cap;
    sll *first;       /* per vertex: the 1-based vt of its first corner, 0 no corner, -1 none or a bad one */
    int bad;          /* a vt statement that is not numbers, or a face before the first vt */
    int faces;        /* a face was seen before any vt */
} obj_uv;

static sss_result obj_vt(obj_uv *tx, char **q, char *e)
{
    if (tx->faces) tx->bad = 1;
    if (tx->nvt == tx->cap) {
        ull cap = tx->cap ? 2 * tx->cap : 1024;
        float *n = realloc(tx->vt, (size_t)cap * 2 * sizeof(float));
        if (!n) return SSS_ERR_NOMEM;
        tx->vt = n;
        tx->cap = cap;
    }
    float *w = &tx->vt[2 * tx->nvt++];
    w[0] = w[1] = 0.0f;
    tok t;
    for (int k = 0; k < 2; k++) {
        if (!sss_scan_token(q, e, &t)) {
            if (k == 0) tx->bad = 1; /* a vt needs its u */
            break;
        }
        if (sss_scan_float(t) != NUM_OK) {
            tx->bad = 1;
            break;
        }
        w[k] = (float)tok_double(t);
    }
    return SSS_OK;
}

/* A face corner of vertex v (1-based, resolved): [p, end) after its first
 * slash ("v/vt[/vn]"), or p NULL for a corner without one. Only the first
 * corner of each vertex counts. */
static sss_result obj_corner_uv(obj_uv *tx, sll v, ull nv, char *p, char *end)
{
    if (v < 1 || (ull)v > nv) return SSS_OK; /* the face's own check refuses it */
    /* no vt yet: nothing to keep (a file without texture coordinates costs
     * no per-vertex array); faces before the first vt leave the mesh
     * without (obj_vt) */
    if (!tx->nvt) {
        tx->faces = 1;
        return SSS_OK;
    }
    if (!tx->first && !(tx->first = calloc((size_t)nv + 1, sizeof *tx->first))) return SSS_ERR_NOMEM;
    if (tx->first[v - 1]) return SSS_OK;
    char *q = p;
    while (q && q < end && *q != '/') q++;
    sll vt;
    tok t = {p, p ? (size_t)(q - p) : 0};
    if (t.n == 0) { /* "v" or "v//vn": a corner without a texture coordinate */
        tx->first[v - 1] = -1;
        return SSS_OK;
    }
    if (!sss_scan_int(t, &vt) || vt == 0) vt = -1;
    else if (vt < 0) vt = (sll)tx->nvt + vt + 1 >= 1 ? (sll)tx->nvt + vt + 1 : -1;
    tx->first[v - 1] = vt;
    return SSS_OK;
}

static sss_result obj_vertex_uv(const obj_uv *tx, ull nv, float **out, const char *name, sss_error *err)
{
    *out = NULL;
    if (!tx->nvt || !tx->first || tx->bad) return SSS_OK;
    for (ull v = 0; v < nv; v++)
        if (tx->first[v] < 0 || (ull)tx->first[v] > tx->nvt) return SSS_OK;
    float *uv = malloc((size_t)nv * 2 * sizeof(float) + 1);
    if (!uv) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for texture coordinates", name);
    for (ull v = 0; v < nv; v++) {
        /* a vertex no face uses: (0, 0), and the repair drops it */
        if (!tx->first[v]) {
            uv[2 * v] = uv[2 * v + 1] = 0.0f;
            continue;
        }
        memcpy(&uv[2 * v], &tx->vt[2 * (ull)(tx->first[v] - 1)], 2 * sizeof(float));
    }
    *out = uv;
    return SSS_OK;
}

sss_result sss_scan_obj(src *s, expect *ex, sss_error *err)
{
    sss_result r = sss_src_read_all(s, err);
    if (r != SSS_OK) return r;
    sss_src_drop_bom(s);
    char *base = s->data, *end = s->data + s->size, *b, *e;
    tok t;

    /* Pass 1: how many vertices (indices may refer forward). */
    ull nv_total = 0;
    line_it it = {base, end, 0};
    while (sss_scan_line(&it, &b, &e)) {
        if (b == e || *b == '#' || is_space(*b)) continue;
        char *q = b;
        if (sss_scan_token(&q, e, &t) && tok_is(t, "v")) nv_total++;
    }
    if (nv_total > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu vertices; at most 4294967294 are supported", s->name, nv_total);

    if (!(ex->dpos = sss_src_alloc_dpos(s, nv_total, err))) return SSS_ERR_NOMEM;

    /* Pass 2: validate, predict what the reader adds, neutralise the rest. */
    size_t cap_idx = 64, cap_drop = 1024;
    sll *ids = malloc(cap_idx * sizeof *ids);
    unsigned char *drop = malloc(cap_drop);
    if (!ids || !drop) {
        free(ids); free(drop);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    }
    ull nv_seen = 0, nfaces = 0, added = 0;
    /* texture coordinates: the vt statements in order, and per vertex the
     * vt of the first face corner that names one (obj_vertex_uv) */
    obj_uv tx = {0};
    it = (line_it){base, end, 0};
    r = SSS_OK;
    while (r == SSS_OK && sss_scan_line(&it, &b, &e)) {
        if (b == e || *b == '#' || is_space(*b)) continue;
        char *q = b;
        tok kw;
        sss_scan_token(&q, e, &kw);
        if (tok_is(kw, "v")) {
            for (int k = 0; k < 3; k++) {
                if (!sss_scan_token(&q, e, &t)) {
                    r = sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu (line %llu): fewer than 3 coordinates", s->name,
                                 nv_seen, it.no);
                    break;
                }
                num_check c = sss_scan_float(t);
                if (c == NUM_NONFINITE)
                    r = sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite ('" TOKF "', line %llu)",
                                 s->name, nv_seen, TOKA(t), it.no);
                else if (c == NUM_BAD)
                    r = sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu: '" TOKF "' is not a number (line %llu)", s->name,
                                 nv_seen, TOKA(t), it.no);
                if (r != SSS_OK) break;
                ex->dpos[3 * nv_seen + (ull)k] = tok_double(t);
            }
            nv_seen++;
        } else if (tok_is(kw, "f")) {
            size_t n = 0;
            while (r == SSS_OK && sss_scan_token(&q, e, &t)) {
                tok c0 = t;
                char *slash = memchr(t.s, '/', t.n);
                if (slash) c0.n = (size_t)(slash - t.s);
                sll v;
                if (!sss_scan_int(c0, &v)) {
                    r = sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)", s->name,
                                 nfaces, TOKA(t), it.no);
                    break;
                }
                if (obj_corner_uv(&tx, v < 0 ? (sll)nv_seen + v + 1 : v, nv_total, slash ? slash + 1 : NULL, t.s + t.n) !=
                    SSS_OK) {
                    r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
                    break;
                }
                sll resolved = v < 0 ? (sll)nv_seen + v + 1 : v;
                if (v == 0 || resolved < 1 || (ull)resolved > nv_total) {
                    r = sss_fail(err, SSS_ERR_MESH, "%s: face %llu: vertex index " TOKF " out of range (line %llu; %llu vertices, "
                                 "OBJ indices start at 1)", s->name, nfaces, TOKA(c0), it.no, nv_total);
                    break;
                }
                if (n == cap_idx) {
                    sll *ni = realloc(ids, 2 * cap_idx * sizeof *ids);
                    if (!ni) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name); break; }
                    ids = ni;
                    cap_idx *= 2;
                }
                ids[n++] = resolved;
            }
            if (r != SSS_OK) break;
            nfaces++;
            if (n < 3) {
                ex->too_small++; /* the reader drops it */
                continue;
            }
            size_t d = sss_count_distinct(ids, n);
            if (d != n) ex->repeated++;
            if (d < 3) continue; /* the reader drops it */
            if (added == cap_drop) {
                unsigned char *nd = realloc(drop, 2 * cap_drop);
                if (!nd) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name); break; }
                drop = nd;
                cap_drop *= 2;
            }
            /* The reader keeps a face with a repeated index after removing the
             * repeats; the policy drops it, after the read. */
            drop[added++] = d != n;
        } else {
            if (tok_is(kw, "vt") && obj_vt(&tx, &q, e) != SSS_OK) {
                r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
                break;
            }
            /* vt (read above), vn, mtllib, usemtl, g, o, s, l, ...: nothing the bake needs,
             * and the reader fails on a one-number vt or opens material files.
             * A keyword the format does not have is counted and warned about:
             * a damaged "v" among them shifts every later index. */
            if (!known_statement(kw)) {
                if (!ex->unknown) {
                    size_t k = kw.n < 32 ? kw.n : 32;
                    for (size_t i = 0; i < k; i++) {
                        const unsigned char c = (unsigned char)kw.s[i];
                        ex->first_unknown[i] = c < 0x20 || c == 0x7f ? '?' : (char)c;
                    }
                    ex->first_unknown[k] = 0;
                    ex->first_unknown_line = it.no;
                }
                ex->unknown++;
            }
            *b = '#';
        }
    }
    free(ids);
    if (r == SSS_OK) r = obj_vertex_uv(&tx, nv_total, &ex->uv, s->name, err);
    free(tx.vt);
    free(tx.first);
    if (r != SSS_OK) {
        free(drop);
        return r;
    }
    ex->fmt = SSS_OM_OBJ;
    ex->om_data = s->data;
    ex->om_len = (size_t)s->size;
    ex->nv = nv_total;
    ex->nf = added;
    ex->faces_in_file = nfaces;
    ex->drop = drop;
    return SSS_OK;
}
