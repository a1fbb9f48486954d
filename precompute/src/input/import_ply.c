/* import_ply.c: the PLY scanner (ascii, binary little and big endian):
 * header, declared sizes, data, and the canonical header the reader gets
 * (input/import_internal.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

#define MAX_PROPS 1024               /* properties per PLY element */
#define MAX_ELEMS 256                /* PLY elements */

typedef enum { PT_NONE = 0, PT_I8, PT_U8, PT_I16, PT_U16, PT_I32, PT_U32, PT_F32, PT_F64 } ptype;

static ptype ply_type(tok t)
{
    static const struct { const char *n; ptype t; } map[] = {
        {"char", PT_I8},    {"int8", PT_I8},     {"uchar", PT_U8},   {"uint8", PT_U8},
        {"short", PT_I16},  {"int16", PT_I16},   {"ushort", PT_U16}, {"uint16", PT_U16},
        {"int", PT_I32},    {"int32", PT_I32},   {"uint", PT_U32},   {"uint32", PT_U32},
        {"float", PT_F32},  {"float32", PT_F32}, {"double", PT_F64}, {"float64", PT_F64},
    };
    for (size_t i = 0; i < sizeof map / sizeof map[0]; i++)
        if (tok_is(t, map[i].n)) return map[i].t;
    return PT_NONE;
}

static size_t ptype_size(ptype t)
{
    switch (t) {
    case PT_I8: case PT_U8: return 1;
    case PT_I16: case PT_U16: return 2;
    case PT_I32: case PT_U32: case PT_F32: return 4;
    case PT_F64: return 8;
    default: return 0;
    }
}

/* Names OpenMesh's PLY reader understands. */
static const char *ptype_name(ptype t)
{
    switch (t) {
    case PT_I8: return "char";
    case PT_U8: return "uchar";
    case PT_I16: return "short";
    case PT_U16: return "ushort";
    case PT_I32: return "int";
    case PT_U32: return "uint";
    case PT_F32: return "float";
    case PT_F64: return "double";
    default: return "?";
    }
}

/* List length types OpenMesh accepts (uchar, uint16, int), by width; the scan
 * rejects negative lengths, so signedness does not matter. */
static const char *ply_count_name(ptype t)
{
    switch (ptype_size(t)) {
    case 1: return "uchar";
    case 2: return "uint16";
    default: return "int";
    }
}

static int ptype_is_int(ptype t) { return t != PT_NONE && t != PT_F32 && t != PT_F64; }

enum { ROLE_OTHER = 0, ROLE_X, ROLE_Y, ROLE_Z, ROLE_INDICES };
enum { PLY_ASCII = 0, PLY_LE, PLY_BE };

typedef struct ply_prop {
    ptype type;        /* scalar type, or list entry type */
    ptype count_type;  /* PT_NONE for scalars */
    int role;
    int tex;           /* vertex texture coordinate: 1 u, 2 v, 0 neither (role stays ROLE_OTHER) */
    char name[48];
} ply_prop;

typedef struct ply_elem {
    char name[48];
    ull count;
    ply_prop *props;
    int nprops;
} ply_elem;

typedef struct ply_header {
    int format;
    ply_elem elems[MAX_ELEMS];
    int nelems;
    int iv, ifc;       /* index of element vertex / face */
    size_t data_off;   /* first byte after the end_header line */
    int tex_prop[2];   /* the vertex properties read as u and v (float or double), or -1 (ply_tex_props) */
} ply_header;

/* Which vertex properties hold texture coordinates: the first float or
 * double one named as u and the first named as v; both or neither. */
static void ply_tex_props(ply_header *h)
{
    h->tex_prop[0] = h->tex_prop[1] = -1;
    const ply_elem *ev = &h->elems[h->iv];
    for (int i = 0; i < ev->nprops; i++) {
        const ply_prop *pr = &ev->props[i];
        if (pr->tex && !pr->count_type && (pr->type == PT_F32 || pr->type == PT_F64) && h->tex_prop[pr->tex - 1] < 0)
            h->tex_prop[pr->tex - 1] = i;
    }
    if (h->tex_prop[0] < 0 || h->tex_prop[1] < 0) h->tex_prop[0] = h->tex_prop[1] = -1;
}

/* Which of u (0) and v (1) property i of the vertex element is, or -1. */
static int ply_tex_slot(const ply_header *h, int i) { return i == h->tex_prop[0] ? 0 : i == h->tex_prop[1] ? 1 : -1; }

static void ply_free(ply_header *h)
{
    for (int i = 0; i < h->nelems; i++) free(h->elems[i].props);
    h->nelems = 0;
}

static void copy_name(char *dst, size_t cap, tok t)
{
    size_t n = t.n < cap - 1 ? t.n : cap - 1;
    memcpy(dst, t.s, n);
    dst[n] = '\0';
}

static const char *elem_noun(const ply_header *h, int e)
{
    return e == h->iv ? "vertices" : e == h->ifc ? "faces" : "records";
}

/* Parses the header in data[0..n); n is what was read (at most HEADER_MAX). */
static sss_result ply_parse_header(src *s, size_t n, ply_header *h, sss_error *err)
{
    const char *name = s->name;
    char *p = s->data, *end = s->data + n;
    memset(h, 0, sizeof *h);
    h->iv = h->ifc = -1;
    h->format = -1;
    ull lineno = 0;
    int done = 0;
    while (p < end && !done) {
        char *eol = memchr(p, '\n', (size_t)(end - p));
        char *lend = eol ? eol : end;
        if (!eol && (ull)n < s->size) break; /* line cut at the read limit */
        lineno++;
        char *q = p;
        tok w[6];
        int nw = 0;
        tok t;
        while (nw < 6 && sss_scan_token(&q, lend, &t)) w[nw++] = t;
        tok extra;
        int more = sss_scan_token(&q, lend, &extra);
        p = eol ? eol + 1 : end;
        if (lineno == 1) {
            if (nw != 1 || !(tok_is(w[0], "ply") || tok_is(w[0], "PLY")))
                return sss_fail(err, SSS_ERR_FORMAT, "%s: not a PLY file (the first line is not 'ply')", name);
            continue;
        }
        if (nw == 0) continue;
        if (tok_is(w[0], "comment") || tok_is(w[0], "obj_info")) continue;
        if (tok_is(w[0], "format")) {
            if (nw < 2 || h->format != -1)
                return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: bad format line", name, lineno);
            if (tok_is(w[1], "ascii")) h->format = PLY_ASCII;
            else if (tok_is(w[1], "binary_little_endian")) h->format = PLY_LE;
            else if (tok_is(w[1], "binary_big_endian")) h->format = PLY_BE;
            else
                return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: unknown format '" TOKF "'", name, lineno,
                                TOKA(w[1]));
            continue;
        }
        if (tok_is(w[0], "element")) {
            if (nw != 3 || more)
                return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: expected 'element NAME COUNT'", name, lineno);
            if (h->nelems == MAX_ELEMS)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header: more than %d elements", name, MAX_ELEMS);
            ply_elem *e = &h->elems[h->nelems];
            memset(e, 0, sizeof *e);
            copy_name(e->name, sizeof e->name, w[1]);
            if (!sss_scan_count(w[2], &e->count))
                return sss_fail(err, SSS_ERR_FORMAT, "%s: element %s: count '" TOKF "' is not a number", name, e->name,
                                TOKA(w[2]));
            if (e->count > UINT32_MAX)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: element %s: count %llu is more than 4294967295", name,
                                e->name, e->count);
            if (tok_is(w[1], "vertex")) {
                if (h->iv >= 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: header: two 'element vertex' lines", name);
                h->iv = h->nelems;
            } else if (tok_is(w[1], "face")) {
                if (h->ifc >= 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: header: two 'element face' lines", name);
                h->ifc = h->nelems;
            }
            h->nelems++;
            continue;
        }
        if (tok_is(w[0], "property")) {
            if (h->nelems == 0)
                return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: property before any element", name, lineno);
            ply_elem *e = &h->elems[h->nelems - 1];
            ply_prop pr;
            memset(&pr, 0, sizeof pr);
            tok pname;
            if (nw >= 2 && tok_is(w[1], "list")) {
                if (nw != 5 || more)
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: expected 'property list COUNT_TYPE TYPE NAME'",
                                    name, lineno);
                pr.count_type = ply_type(w[2]);
                pr.type = ply_type(w[3]);
                pname = w[4];
                if (!ptype_is_int(pr.count_type))
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: element %s: list '" TOKF "': length type '" TOKF "' is not an integer type",
                                    name, e->name, TOKA(pname), TOKA(w[2]));
                if (pr.type == PT_NONE)
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: element %s: list '" TOKF "': unknown type '" TOKF "'", name,
                                    e->name, TOKA(pname), TOKA(w[3]));
            } else {
                if (nw != 3 || more)
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: expected 'property TYPE NAME'", name, lineno);
                pr.type = ply_type(w[1]);
                pname = w[2];
                if (pr.type == PT_NONE && ply_type(w[2]) != PT_NONE) { /* "property NAME TYPE" */
                    pr.type = ply_type(w[2]);
                    pname = w[1];
                }
                if (pr.type == PT_NONE)
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: element %s: property '" TOKF "': unknown type '" TOKF "'", name,
                                    e->name, TOKA(pname), TOKA(w[1]));
            }
            copy_name(pr.name, sizeof pr.name, pname);
            int ev = h->nelems - 1 == h->iv, ef = h->nelems - 1 == h->ifc;
            if (ev && !pr.count_type) {
                if (tok_is(pname, "x")) pr.role = ROLE_X;
                else if (tok_is(pname, "y")) pr.role = ROLE_Y;
                else if (tok_is(pname, "z")) pr.role = ROLE_Z;
                /* the names the common writers use for texture coordinates;
                 * the float and double ones are read (ply_tex_props) */
                else if (tok_is(pname, "u") || tok_is(pname, "s") || tok_is(pname, "texture_u")) pr.tex = 1;
                else if (tok_is(pname, "v") || tok_is(pname, "t") || tok_is(pname, "texture_v")) pr.tex = 2;
            }
            if (ef && pr.count_type && (tok_is(pname, "vertex_indices") || tok_is(pname, "vertex_index"))) {
                int have = 0;
                for (int i = 0; i < e->nprops; i++) have |= e->props[i].role == ROLE_INDICES;
                if (!have) pr.role = ROLE_INDICES;
            }
            for (int i = 0; i < e->nprops; i++)
                if (pr.role != ROLE_OTHER && e->props[i].role == pr.role)
                    return sss_fail(err, SSS_ERR_FORMAT, "%s: element %s: property %s appears twice", name, e->name, pr.name);
            if (e->nprops == MAX_PROPS)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: element %s: more than %d properties", name, e->name, MAX_PROPS);
            ply_prop *np = realloc(e->props, (size_t)(e->nprops + 1) * sizeof *np);
            if (!np) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", name);
            e->props = np;
            e->props[e->nprops++] = pr;
            continue;
        }
        if (tok_is(w[0], "end_header")) {
            h->data_off = (size_t)(p - s->data);
            done = 1;
            continue;
        }
        return sss_fail(err, SSS_ERR_FORMAT, "%s: header line %llu: unknown keyword '" TOKF "'", name, lineno, TOKA(w[0]));
    }
    if (!done) {
        if ((ull)n < s->size)
            return sss_fail(err, SSS_ERR_FORMAT, "%s: header: no end_header within the first %zu bytes", name, n);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: header: no end_header line", name);
    }
    if (h->format < 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: header: no format line", name);
    return SSS_OK;
}

/* What this importer (and OpenMesh's reader) can use. */
static sss_result ply_check_usable(const src *s, ply_header *h, sss_error *err)
{
    const char *name = s->name;
    if (h->iv < 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: header: no element vertex", name);
    if (h->ifc < 0) return sss_fail(err, SSS_ERR_MESH, "%s: header: no element face (a point cloud has nothing to bake)", name);
    if (h->ifc < h->iv)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header: element face comes before element vertex", name);
    ply_elem *ev = &h->elems[h->iv], *ef = &h->elems[h->ifc];
    int have[4] = {0, 0, 0, 0};
    for (int i = 0; i < ev->nprops; i++) {
        ply_prop *pr = &ev->props[i];
        have[pr->role] = 1;
        if (pr->role != ROLE_OTHER && h->format != PLY_ASCII && pr->type != PT_F32 && pr->type != PT_F64)
            return sss_fail(err, SSS_ERR_UNSUPPORTED,
                            "%s: element vertex: property %s has type %s; binary coordinates must be float or double", name,
                            pr->name, ptype_name(pr->type));
    }
    static const char *axis[4] = {"", "x", "y", "z"};
    for (int r = ROLE_X; r <= ROLE_Z; r++)
        if (!have[r]) return sss_fail(err, SSS_ERR_FORMAT, "%s: element vertex: no property %s", name, axis[r]);
    for (int e = 0; e < h->ifc; e++)
        for (int i = 0; i < h->elems[e].nprops; i++)
            if (h->elems[e].props[i].count_type)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: element %s: list property %s is not supported", name,
                                h->elems[e].name, h->elems[e].props[i].name);
    int iidx = -1;
    for (int i = 0; i < ef->nprops; i++)
        if (ef->props[i].role == ROLE_INDICES) iidx = i;
    if (iidx < 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: element face: no vertex_indices list property", name);
    if (!ptype_is_int(ef->props[iidx].type))
        return sss_fail(err, SSS_ERR_FORMAT, "%s: element face: vertex_indices has type %s, not an integer type", name,
                        ptype_name(ef->props[iidx].type));
    return SSS_OK;
}

/* Declared counts against the file's size, before the file is read. */
static sss_result ply_check_sizes(const src *s, const ply_header *h, sss_error *err)
{
    ull remaining = s->size - h->data_off, need = 0;
    int last = h->ifc >= 0 ? h->ifc : h->nelems - 1; /* the reader stops after the faces */
    for (int e = 0; e <= last; e++) {
        const ply_elem *el = &h->elems[e];
        ull rec = 0;
        for (int i = 0; i < el->nprops; i++) {
            const ply_prop *pr = &el->props[i];
            if (h->format == PLY_ASCII) rec += 2; /* a digit and a separator */
            else rec += ptype_size(pr->count_type ? pr->count_type : pr->type);
        }
        need = sat_add(need, sat_mul(el->count, rec));
        if (need > remaining)
            return sss_fail(err, SSS_ERR_CORRUPT,
                            "%s: element %s: declares %llu %s but the file has only %llu bytes "
                            "(at least %s%llu bytes of %s data needed after the header)",
                            s->name, el->name, el->count, elem_noun(h, e), s->size, need == ULLONG_MAX ? "> " : "",
                            need, h->format == PLY_ASCII ? "ascii" : "binary");
    }
    if (h->iv >= 0 && h->elems[h->iv].count > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: element vertex: %llu vertices; at most 4294967294 are supported",
                        s->name, h->elems[h->iv].count);
    return SSS_OK;
}

/* Integer property value (for list lengths). */
static sll rd_int(const char *p, ptype t, int be)
{
    size_t n = ptype_size(t);
    ull u = rd_uint((const unsigned char *)p, n, be);
    switch (t) {
    case PT_I8: return (sll)(signed char)(unsigned char)u;
    case PT_I16: return (u & 0x8000u) ? (sll)u - 0x10000 : (sll)u;
    case PT_I32: return (u & 0x80000000u) ? (sll)u - 0x100000000LL : (sll)u;
    default: return (sll)u;
    }
}

static int face_has_extras(const ply_header *h)
{
    return h->elems[h->ifc].nprops > 1;
}

/* Binary body: checks every record fits (list lengths included), and when the
 * face element has properties besides vertex_indices, compacts each face
 * record to just that list in place. *end receives the end of the face data. */
static sss_result ply_scan_binary(src *s, const ply_header *h, char **endp, double *dpos, float *uv, sss_error *err)
{
    int be = h->format == PLY_BE;
    char *p = s->data + h->data_off, *end = s->data + s->size;
    for (int e = 0; e <= h->ifc; e++) {
        const ply_elem *el = &h->elems[e];
        if (e != h->ifc) {
            ull rec = 0;
            for (int i = 0; i < el->nprops; i++) rec += ptype_size(el->props[i].type);
            ull avail = (ull)(end - p);
            if (sat_mul(el->count, rec) > avail)
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: element %s: file ends inside record %llu of %llu (truncated)",
                                s->name, el->name, rec ? avail / rec : 0, el->count);
            if (e == h->iv && (dpos || uv)) {
                /* coordinates in double (float ones widen exactly) */
                for (ull r = 0; r < el->count; r++) {
                    size_t off = 0;
                    for (int i = 0; i < el->nprops; i++) {
                        const ply_prop *pr = &el->props[i];
                        const unsigned char *b = (const unsigned char *)p + r * rec + off;
                        off += ptype_size(pr->type);
                        const int slot = uv ? ply_tex_slot(h, i) : -1;
                        if (slot < 0 && (!dpos || pr->role < ROLE_X || pr->role > ROLE_Z)) continue;
                        double v;
                        if (pr->type == PT_F64) {
                            uint64_t u = rd_uint(b, 8, be);
                            memcpy(&v, &u, 8);
                        } else {
                            uint32_t u = (uint32_t)rd_uint(b, 4, be);
                            float f;
                            memcpy(&f, &u, 4);
                            v = f;
                        }
                        if (slot >= 0) {
                            if (!isfinite(v))
                                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: texture coordinate %s is not finite",
                                                s->name, r, pr->name);
                            uv[2 * r + (ull)slot] = (float)v;
                            continue;
                        }
                        dpos[3 * r + (ull)(pr->role - ROLE_X)] = v;
                    }
                }
            }
            p += el->count * rec;
            continue;
        }
        int compact = face_has_extras(h);
        char *w = p;
        for (ull r = 0; r < el->count; r++) {
            for (int i = 0; i < el->nprops; i++) {
                const ply_prop *pr = &el->props[i];
                char *start = p;
                if (!pr->count_type) {
                    size_t sz = ptype_size(pr->type);
                    if ((size_t)(end - p) < sz) goto truncated;
                    p += sz;
                    continue;
                }
                size_t csz = ptype_size(pr->count_type), esz = ptype_size(pr->type);
                if ((size_t)(end - p) < csz) goto truncated;
                sll cnt = rd_int(p, pr->count_type, be);
                if (cnt < 0)
                    return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: list %s has negative length %lld", s->name, r,
                                    pr->name, cnt);
                p += csz;
                if ((ull)cnt > (ull)(end - p) / esz) goto truncated;
                p += (size_t)cnt * esz;
                if (compact && pr->role == ROLE_INDICES) {
                    memmove(w, start, (size_t)(p - start));
                    w += p - start;
                }
            }
            continue;
        truncated:
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: element face: file ends inside face %llu of %llu (truncated)",
                            s->name, r, el->count);
        }
        *endp = compact ? w : p;
    }
    return SSS_OK;
}

/* Ascii body: every token of every record up to the faces, numbers where the
 * reader parses numbers, list lengths that fit, finite coordinates, face
 * indices in range. Compacts face records to "n i1 .. in" like the binary
 * scan. */
static sss_result ply_scan_ascii(src *s, const ply_header *h, char **endp, double *dpos, float *uv, sss_error *err)
{
    char *base = s->data, *p = s->data + h->data_off, *end = s->data + s->size;
    ull nv = h->elems[h->iv].count;
    tok t;
    for (int e = 0; e <= h->ifc; e++) {
        const ply_elem *el = &h->elems[e];
        int is_v = e == h->iv, is_f = e == h->ifc;
        int compact = is_f && face_has_extras(h);
        if (compact) /* keep the separator after the previous element's last token */
            while (p < end && is_space(*p)) p++;
        char *w = p;
        for (ull r = 0; r < el->count; r++) {
            for (int i = 0; i < el->nprops; i++) {
                const ply_prop *pr = &el->props[i];
                if (!sss_scan_token(&p, end, &t)) goto truncated;
                if (!pr->count_type) {
                    const int slot = is_v && uv ? ply_tex_slot(h, i) : -1;
                    if (slot >= 0) {
                        num_check c = sss_scan_float(t);
                        if (c != NUM_OK)
                            return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: texture coordinate %s '" TOKF "' is not "
                                            "a finite number (line %llu)", s->name, r, pr->name, TOKA(t),
                                            sss_scan_line_of(base, t.s));
                        uv[2 * r + (ull)slot] = (float)tok_double(t);
                    }
                    if (is_v && pr->role != ROLE_OTHER) {
                        num_check c = sss_scan_float(t);
                        if (c == NUM_NONFINITE)
                            return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite ('" TOKF "', line %llu)",
                                            s->name, r, TOKA(t), sss_scan_line_of(base, t.s));
                        if (c == NUM_BAD)
                            return sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu: %s '" TOKF "' is not a number (line %llu)",
                                            s->name, r, pr->name, TOKA(t), sss_scan_line_of(base, t.s));
                        if (dpos) dpos[3 * r + (ull)(pr->role - ROLE_X)] = tok_double(t);
                    }
                    continue;
                }
                sll cnt;
                if (!sss_scan_int(t, &cnt) || cnt < 0)
                    return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: list %s: bad length '" TOKF "' (line %llu)",
                                    s->name, r, pr->name, TOKA(t), sss_scan_line_of(base, t.s));
                int idx = pr->role == ROLE_INDICES;
                if (compact && idx) {
                    memmove(w, t.s, t.n);
                    w += t.n;
                }
                for (sll k = 0; k < cnt; k++) {
                    if (!sss_scan_token(&p, end, &t)) goto truncated;
                    if (!idx) continue;
                    sll v;
                    if (!sss_scan_int(t, &v))
                        return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)",
                                        s->name, r, TOKA(t), sss_scan_line_of(base, t.s));
                    if (v < 0 || (ull)v >= nv)
                        return sss_fail(err, SSS_ERR_MESH, "%s: face %llu: vertex index %lld out of range [0, %llu)",
                                        s->name, r, v, nv);
                    if (compact) {
                        *w++ = ' ';
                        memmove(w, t.s, t.n);
                        w += t.n;
                    }
                }
                if (compact && idx) *w++ = '\n';
            }
            continue;
        truncated:
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: element %s: file ends inside %s %llu of %llu (truncated)", s->name,
                            el->name, is_v ? "vertex" : is_f ? "face" : "record", r, el->count);
        }
        if (is_f) *endp = compact ? w : p;
    }
    return SSS_OK;
}

/* Header OpenMesh reads reliably: no comments, single spaces, one element
 * per line, x y z and vertex_indices under their names and every other
 * property renamed so that the reader skips it; nothing after the faces. */
static sss_result ply_canonical(src *s, const ply_header *h, char **start, sss_error *err)
{
    size_t cap = 256, len = 0;
    for (int e = 0; e <= h->ifc; e++) cap += 96 + (size_t)h->elems[e].nprops * 64;
    char *buf = malloc(cap);
    if (!buf) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    static const char *fmt[3] = {"ascii", "binary_little_endian", "binary_big_endian"};
    len += (size_t)snprintf(buf + len, cap - len, "ply\nformat %s 1.0\n", fmt[h->format]);
    for (int e = 0; e <= h->ifc; e++) {
        const ply_elem *el = &h->elems[e];
        if (e == h->iv || e == h->ifc)
            len += (size_t)snprintf(buf + len, cap - len, "element %s %llu\n", e == h->iv ? "vertex" : "face", el->count);
        else /* other elements (before the faces) are skipped by the reader */
            len += (size_t)snprintf(buf + len, cap - len, "element _e%d %llu\n", e, el->count);
        for (int i = 0; i < el->nprops; i++) {
            const ply_prop *pr = &el->props[i];
            if (e == h->ifc) {
                if (pr->role != ROLE_INDICES) continue;
                len += (size_t)snprintf(buf + len, cap - len, "property list %s %s vertex_indices\n",
                                        ply_count_name(pr->count_type), ptype_name(pr->type));
                continue;
            }
            static const char *axis[4] = {"", "x", "y", "z"};
            if (e == h->iv && pr->role != ROLE_OTHER)
                len += (size_t)snprintf(buf + len, cap - len, "property %s %s\n", ptype_name(pr->type), axis[pr->role]);
            else
                len += (size_t)snprintf(buf + len, cap - len, "property %s _p%d\n", ptype_name(pr->type), i);
        }
    }
    len += (size_t)snprintf(buf + len, cap - len, "end_header\n");
    *start = sss_src_put_header(s, h->data_off, buf, len);
    free(buf);
    if (!*start) return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header too large to rewrite", s->name);
    return SSS_OK;
}

sss_result sss_scan_ply(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = sss_src_read(s, n, err);
    if (r != SSS_OK) return r;
    if (sss_src_drop_bom(s)) n -= 3; /* the header is text */
    ply_header *h = malloc(sizeof *h);
    if (!h) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    r = ply_parse_header(s, n, h, err);
    if (r == SSS_OK) r = ply_check_sizes(s, h, err);
    if (r == SSS_OK) r = ply_check_usable(s, h, err);
    if (r == SSS_OK) r = sss_src_read_all(s, err);
    if (r == SSS_OK) {
        /* Double positions where the file holds more than float32. */
        int wide = h->format == PLY_ASCII;
        for (int i = 0; i < h->elems[h->iv].nprops; i++)
            wide |= h->elems[h->iv].props[i].role != ROLE_OTHER && h->elems[h->iv].props[i].type == PT_F64;
        if (wide && !(ex->dpos = sss_src_alloc_dpos(s, h->elems[h->iv].count, err))) r = SSS_ERR_NOMEM;
        ply_tex_props(h);
        /* the file's size bounds the count (ply_check_sizes) */
        if (r == SSS_OK && h->tex_prop[0] >= 0 &&
            !(ex->uv = malloc((size_t)h->elems[h->iv].count * 2 * sizeof(float) + 1)))
            r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for texture coordinates", s->name);
    }
    char *end = NULL, *start = NULL;
    if (r == SSS_OK)
        r = h->format == PLY_ASCII ? ply_scan_ascii(s, h, &end, ex->dpos, ex->uv, err)
                                   : ply_scan_binary(s, h, &end, ex->dpos, ex->uv, err);
    if (r == SSS_OK) r = ply_canonical(s, h, &start, err);
    if (r == SSS_OK) {
        ex->fmt = SSS_OM_PLY;
        ex->om_data = start;
        ex->om_len = (size_t)(end - start);
        ex->nv = h->elems[h->iv].count;
        ex->nf = h->elems[h->ifc].count;
        ex->faces_in_file = ex->nf;
    }
    ply_free(h);
    free(h);
    return r;
}
