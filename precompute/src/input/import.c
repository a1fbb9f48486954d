/* import.c: mesh import (PLY, OBJ, OFF, STL) with validation and counted
 * repairs; see sss/import.h for the policy.
 *
 * The work is split in three:
 *
 *  1. Before anything large is allocated, the header is parsed from the first
 *     bytes of the file and the counts it declares are checked against the
 *     file's size (PLY, OFF, binary STL).
 *
 *  2. The file is read into memory and scanned in C. The scan rejects what
 *     OpenMesh's readers would silently misread (they turn a "nan" token into
 *     zeros, skip an unparsable OBJ vertex and so shift every later index,
 *     take a list length of 4e9 at face value, lose a binary PLY's data
 *     offset after a comment line, ...) with an error that names the element,
 *     and it canonicalises what they would misread although it is valid: the
 *     PLY header is rewritten (comments dropped, properties other than x y z
 *     renamed so the reader skips them by size, extra face properties
 *     compacted away), the OFF header is rewritten to plain "OFF" with the
 *     counts on their own line and trailing data on face lines blanked, and
 *     OBJ/STL lines the reader has no use for are turned into comments.
 *     The scan also predicts exactly what the reader must deliver, so a
 *     disagreement is caught instead of producing a wrong mesh.
 *
 *  3. OpenMesh parses the canonical bytes into a raw polygon soup
 *     (import_openmesh.cpp); the soup is checked (finite coordinates, indices
 *     in range), repaired (fan triangulation, degenerate faces dropped,
 *     unreferenced vertices removed) and turned into an sss_mesh.
 */
#define _POSIX_C_SOURCE 200809L

#include "sss/import.h"

#include <errno.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "input/import_openmesh.h"

#define HEADER_MAX ((size_t)1 << 20) /* a PLY/OFF header must end within this */
#define SLACK ((size_t)16384)        /* room before the data for a rewritten header */
#define MAX_PROPS 1024               /* properties per PLY element */
#define MAX_ELEMS 256                /* PLY elements */

typedef unsigned long long ull;
typedef long long sll;

/* ---------------------------------------------------------------------------
 * Small helpers
 * ------------------------------------------------------------------------- */

static int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

static char lower(char c) { return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c; }

typedef struct tok {
    char *s;
    size_t n;
} tok;

/* Case-sensitive / case-insensitive comparison of a token with a C string. */
static int tok_is(tok t, const char *w)
{
    size_t n = strlen(w);
    return t.n == n && memcmp(t.s, w, n) == 0;
}

static int tok_is_ci(tok t, const char *w)
{
    size_t n = strlen(w);
    if (t.n != n) return 0;
    for (size_t i = 0; i < n; i++)
        if (lower(t.s[i]) != lower(w[i])) return 0;
    return 1;
}

/* Next whitespace-delimited token in [*pp, end); 0 at the end. */
static int next_tok(char **pp, char *end, tok *t)
{
    char *p = *pp;
    while (p < end && is_space(*p)) p++;
    if (p == end) { *pp = p; return 0; }
    t->s = p;
    while (p < end && !is_space(*p)) p++;
    t->n = (size_t)(p - t->s);
    *pp = p;
    return 1;
}

/* 1-based line number of position p in [base, ...). Only used for errors. */
static ull line_of(const char *base, const char *p)
{
    ull line = 1;
    for (const char *q = base; q < p; q++)
        if (*q == '\n') line++;
    return line;
}

/* Saturating a*b+c for size checks. */
static ull sat_mul(ull a, ull b)
{
    if (a != 0 && b > ULLONG_MAX / a) return ULLONG_MAX;
    return a * b;
}

static ull sat_add(ull a, ull b) { return a > ULLONG_MAX - b ? ULLONG_MAX : a + b; }

/* Token shown in a message: at most 32 characters. */
#define TOKF "%.*s%s"
#define TOKA(t) (int)((t).n > 32 ? 32 : (t).n), (t).s, ((t).n > 32 ? "..." : "")

typedef enum { NUM_OK, NUM_NONFINITE, NUM_BAD } num_check;

/* A float token as C++'s `stream >> float` reads it, whole token:
 * [+-] (digits [. digits] | . digits) [e [+-] digits]. NaN/Inf spellings and
 * values that overflow a float are NUM_NONFINITE (the stream would fail on
 * them); anything else is NUM_BAD. */
static num_check check_float(tok t)
{
    size_t i = 0, n = t.n;
    const char *s = t.s;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    size_t mant = 0, int_digits = 0; /* significant digits before the point */
    while (i < n && is_digit(s[i])) {
        if (int_digits || s[i] != '0') int_digits++;
        i++;
        mant++;
    }
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && is_digit(s[i])) { i++; mant++; }
    }
    int ok = mant > 0;
    long ex = 0;
    if (ok && i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        int neg = 0;
        if (i < n && (s[i] == '+' || s[i] == '-')) neg = s[i++] == '-';
        size_t nd = 0;
        while (i < n && is_digit(s[i])) {
            if (ex < 100000) ex = ex * 10 + (s[i] - '0');
            i++;
            nd++;
        }
        if (nd == 0) ok = 0;
        if (neg) ex = -ex;
    }
    if (!ok || i != n) {
        /* nan, inf, infinity, nan(...) in any case, with an optional sign. */
        size_t j = (n > 0 && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
        char w[4] = {0};
        for (size_t k = 0; k < 3 && j + k < n; k++) w[k] = lower(s[j + k]);
        if (n - j >= 3 && (strcmp(w, "nan") == 0 || strcmp(w, "inf") == 0)) return NUM_NONFINITE;
        return NUM_BAD;
    }
    /* |value| < 10^(int_digits + ex) <= 1e38 < FLT_MAX: certainly finite.
     * Only larger magnitudes need the exact conversion. */
    if ((long)int_digits + ex <= 38) return NUM_OK;
    char buf[400];
    if (n >= sizeof buf) return NUM_BAD;
    memcpy(buf, s, n);
    buf[n] = '\0';
    return isfinite(strtof(buf, NULL)) ? NUM_OK : NUM_NONFINITE;
}

/* An integer token [+-]digits. The value saturates at +-2^62. */
static int parse_int(tok t, sll *out)
{
    size_t i = 0;
    int neg = 0;
    if (t.n > 0 && (t.s[0] == '+' || t.s[0] == '-')) { neg = t.s[0] == '-'; i++; }
    if (i == t.n) return 0;
    const sll cap = (sll)1 << 62;
    sll v = 0;
    for (; i < t.n; i++) {
        if (!is_digit(t.s[i])) return 0;
        v = v <= cap / 10 ? v * 10 + (t.s[i] - '0') : cap;
    }
    if (v > cap) v = cap;
    *out = neg ? -v : v;
    return 1;
}

/* Unsigned decimal count (digits only). */
static int parse_count(tok t, ull *out)
{
    if (t.n == 0) return 0;
    ull v = 0;
    for (size_t i = 0; i < t.n; i++) {
        if (!is_digit(t.s[i])) return 0;
        v = v > ULLONG_MAX / 10 - 10 ? ULLONG_MAX : v * 10 + (ull)(t.s[i] - '0');
    }
    *out = v;
    return 1;
}

/* ---------------------------------------------------------------------------
 * The file in memory
 * ------------------------------------------------------------------------- */

typedef struct src {
    const char *name; /* path as given, for messages */
    FILE *f;
    ull size;
    char *mem;        /* SLACK bytes, then the file, then one spare byte */
    char *data;       /* mem + SLACK */
    size_t have;      /* bytes of the file read so far */
} src;

static sss_result src_open(src *s, const char *path, sss_error *err)
{
    memset(s, 0, sizeof *s);
    s->name = path;
    s->f = fopen(path, "rb");
    if (!s->f) return sss_fail(err, SSS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fileno(s->f), &st) != 0)
        return sss_fail(err, SSS_ERR_IO, "%s: cannot stat: %s", path, strerror(errno));
    if (!S_ISREG(st.st_mode)) return sss_fail(err, SSS_ERR_IO, "%s: not a regular file", path);
    if (st.st_size <= 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: file is empty", path);
    s->size = (ull)st.st_size;
    if (s->size > (ull)SIZE_MAX - SLACK - 2)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: file too large (%llu bytes)", path, s->size);
    return SSS_OK;
}

/* Makes the first n bytes of the file available at s->data (n <= size). */
static sss_result src_read(src *s, size_t n, sss_error *err)
{
    if (n <= s->have) return SSS_OK;
    char *m = realloc(s->mem, SLACK + n + 1);
    if (!m) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %zu bytes", s->name, n);
    s->mem = m;
    s->data = m + SLACK;
    while (s->have < n) {
        size_t got = fread(s->data + s->have, 1, n - s->have, s->f);
        if (got == 0) {
            if (ferror(s->f)) return sss_fail(err, SSS_ERR_IO, "%s: read failed: %s", s->name, strerror(errno));
            return sss_fail(err, SSS_ERR_IO, "%s: file shrank while reading (%zu of %zu bytes)", s->name, s->have, n);
        }
        s->have += got;
    }
    s->data[n] = '\0';
    return SSS_OK;
}

static sss_result src_read_all(src *s, sss_error *err) { return src_read(s, (size_t)s->size, err); }

static void src_close(src *s)
{
    if (s->f) fclose(s->f);
    free(s->mem);
    memset(s, 0, sizeof *s);
}

/* Writes hdr so that it ends at data + at; returns where it starts, or NULL
 * if there is not enough room in front. */
static char *put_header(src *s, size_t at, const char *hdr, size_t len)
{
    if (len > SLACK + at) return NULL;
    char *start = s->data + at - len;
    memcpy(start, hdr, len);
    return start;
}

/* What the reader must deliver, and the repairs counted before it ran. */
typedef struct expect {
    sss_om_format fmt;
    char *om_data;       /* canonical bytes for OpenMesh */
    size_t om_len;
    ull nv;              /* exact vertex count, or ULLONG_MAX: at most nv_max */
    ull nv_max;
    ull nf;              /* exact face count, or ULLONG_MAX: at most nf_max */
    ull nf_max;
    ull faces_in_file;
    ull too_small;       /* faces the reader drops itself (OBJ) */
    ull repeated;
    unsigned char *drop; /* OBJ: per delivered face, 1 = uses a vertex twice in the file */
    /* Positions as the file states them, in double (3 per vertex, in the
     * reader's vertex order), where the file holds more than float32: ascii
     * PLY, OFF and OBJ, binary PLY with double coordinates; NULL otherwise
     * (STL, float PLY). OpenMesh's readers deliver float32 only; these let a
     * far-off mesh be recentred before the float conversion
     * (docs/robustness.md B6). */
    double *dpos;
} expect;

/* Room for the double positions of nv vertices (NULL with an error set). */
static double *alloc_dpos(const src *s, ull nv, sss_error *err)
{
    if (nv > (ull)SIZE_MAX / 24 - 1) {
        sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", s->name, nv);
        return NULL;
    }
    double *d = malloc((size_t)nv * 3 * sizeof(double) + 1);
    if (!d) sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", s->name, nv);
    return d;
}

/* A token check_float accepted, as a double. The file's bytes are followed by
 * whitespace or the terminating NUL (src_read), so strtod stops at the
 * token's end. */
static double tok_double(tok t) { return strtod(t.s, NULL); }

/* ---------------------------------------------------------------------------
 * PLY
 * ------------------------------------------------------------------------- */

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
} ply_header;

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
        while (nw < 6 && next_tok(&q, lend, &t)) w[nw++] = t;
        tok extra;
        int more = next_tok(&q, lend, &extra);
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
            if (!parse_count(w[2], &e->count))
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

static ull rd_uint(const unsigned char *b, size_t n, int be)
{
    ull v = 0;
    for (size_t i = 0; i < n; i++) v |= (ull)b[be ? n - 1 - i : i] << (8 * i);
    return v;
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
static sss_result ply_scan_binary(src *s, const ply_header *h, char **endp, double *dpos, sss_error *err)
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
            if (e == h->iv && dpos) {
                /* coordinates in double (float ones widen exactly) */
                for (ull r = 0; r < el->count; r++) {
                    size_t off = 0;
                    for (int i = 0; i < el->nprops; i++) {
                        const ply_prop *pr = &el->props[i];
                        const unsigned char *b = (const unsigned char *)p + r * rec + off;
                        off += ptype_size(pr->type);
                        if (pr->role < ROLE_X || pr->role > ROLE_Z) continue;
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
static sss_result ply_scan_ascii(src *s, const ply_header *h, char **endp, double *dpos, sss_error *err)
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
                if (!next_tok(&p, end, &t)) goto truncated;
                if (!pr->count_type) {
                    if (is_v && pr->role != ROLE_OTHER) {
                        num_check c = check_float(t);
                        if (c == NUM_NONFINITE)
                            return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite ('" TOKF "', line %llu)",
                                            s->name, r, TOKA(t), line_of(base, t.s));
                        if (c == NUM_BAD)
                            return sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu: %s '" TOKF "' is not a number (line %llu)",
                                            s->name, r, pr->name, TOKA(t), line_of(base, t.s));
                        if (dpos) dpos[3 * r + (ull)(pr->role - ROLE_X)] = tok_double(t);
                    }
                    continue;
                }
                sll cnt;
                if (!parse_int(t, &cnt) || cnt < 0)
                    return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: list %s: bad length '" TOKF "' (line %llu)",
                                    s->name, r, pr->name, TOKA(t), line_of(base, t.s));
                int idx = pr->role == ROLE_INDICES;
                if (compact && idx) {
                    memmove(w, t.s, t.n);
                    w += t.n;
                }
                for (sll k = 0; k < cnt; k++) {
                    if (!next_tok(&p, end, &t)) goto truncated;
                    if (!idx) continue;
                    sll v;
                    if (!parse_int(t, &v))
                        return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)",
                                        s->name, r, TOKA(t), line_of(base, t.s));
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
    *start = put_header(s, h->data_off, buf, len);
    free(buf);
    if (!*start) return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header too large to rewrite", s->name);
    return SSS_OK;
}

static sss_result prepare_ply(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = src_read(s, n, err);
    if (r != SSS_OK) return r;
    ply_header *h = malloc(sizeof *h);
    if (!h) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    r = ply_parse_header(s, n, h, err);
    if (r == SSS_OK) r = ply_check_sizes(s, h, err);
    if (r == SSS_OK) r = ply_check_usable(s, h, err);
    if (r == SSS_OK) r = src_read_all(s, err);
    if (r == SSS_OK) {
        /* Double positions where the file holds more than float32. */
        int wide = h->format == PLY_ASCII;
        for (int i = 0; i < h->elems[h->iv].nprops; i++)
            wide |= h->elems[h->iv].props[i].role != ROLE_OTHER && h->elems[h->iv].props[i].type == PT_F64;
        if (wide && !(ex->dpos = alloc_dpos(s, h->elems[h->iv].count, err))) r = SSS_ERR_NOMEM;
    }
    char *end = NULL, *start = NULL;
    if (r == SSS_OK)
        r = h->format == PLY_ASCII ? ply_scan_ascii(s, h, &end, ex->dpos, err) : ply_scan_binary(s, h, &end, ex->dpos, err);
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

/* ---------------------------------------------------------------------------
 * OFF (ascii; the header becomes plain "OFF\nNV NF 0")
 * ------------------------------------------------------------------------- */

/* Like next_tok, but a token starting with '#' begins a comment: the rest of
 * its line is blanked (the reader does not know comments) and skipped. */
static int off_tok(char **pp, char *end, tok *t)
{
    for (;;) {
        if (!next_tok(pp, end, t)) return 0;
        if (t->s[0] != '#') return 1;
        char *q = t->s;
        while (q < end && *q != '\n') *q++ = ' ';
        *pp = q;
    }
}

static sss_result prepare_off(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = src_read(s, n, err);
    if (r != SSS_OK) return r;
    char *p = s->data, *end = s->data + n, *base = s->data;
    tok t;
    if (!off_tok(&p, end, &t)) return sss_fail(err, SSS_ERR_FORMAT, "%s: not an OFF file (no OFF keyword)", s->name);
    /* [ST][C][N][4][n]OFF */
    size_t i = 0;
    if (t.n >= 2 && t.s[0] == 'S' && t.s[1] == 'T') i += 2;
    if (i < t.n && t.s[i] == 'C') i++;
    if (i < t.n && t.s[i] == 'N') i++;
    int highdim = 0;
    if (i < t.n && t.s[i] == '4') { i++; highdim = 1; }
    if (i < t.n && t.s[i] == 'n') { i++; highdim = 1; }
    if (t.n - i != 3 || memcmp(t.s + i, "OFF", 3) != 0)
        return sss_fail(err, SSS_ERR_FORMAT, "%s: not an OFF file (first word '" TOKF "')", s->name, TOKA(t));
    if (highdim)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header: '" TOKF "' (4D or n-dimensional vertices) is not supported",
                        s->name, TOKA(t));
    ull cnt[3];
    static const char *what[3] = {"vertex count", "face count", "edge count"};
    for (int k = 0; k < 3; k++) {
        if (!off_tok(&p, end, &t))
            return sss_fail(err, SSS_ERR_FORMAT, "%s: header: missing %s", s->name, what[k]);
        if (k == 0 && tok_is(t, "BINARY"))
            return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header: binary OFF is not supported", s->name);
        if (!parse_count(t, &cnt[k]))
            return sss_fail(err, SSS_ERR_FORMAT, "%s: header: %s '" TOKF "' is not a number", s->name, what[k], TOKA(t));
    }
    ull nv = cnt[0], nf = cnt[1];
    size_t body = (size_t)(p - s->data);
    ull remaining = s->size - body;
    /* Each vertex needs "0 0 0\n", each face at least "0\n"; the last line
     * may lack its newline. */
    if (sat_mul(nv, 6) > remaining + 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: element vertex: declares %llu vertices but the file has only %llu bytes",
                        s->name, nv, s->size);
    if (sat_add(sat_mul(nv, 6), sat_mul(nf, 2)) > remaining + 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: element face: declares %llu faces but the file has only %llu bytes",
                        s->name, nf, s->size);
    if (nv > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu vertices; at most 4294967294 are supported", s->name, nv);
    if (nf > UINT32_MAX)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu faces; at most 4294967295 are supported", s->name, nf);

    r = src_read_all(s, err);
    if (r != SSS_OK) return r;
    if (!(ex->dpos = alloc_dpos(s, nv, err))) return SSS_ERR_NOMEM;
    base = s->data;
    p = s->data + body;
    end = s->data + s->size;
    /* Rest of the counts line: only a comment may follow. */
    {
        char *q = p;
        while (q < end && *q != '\n' && is_space(*q)) q++;
        if (q < end && *q == '#') {
            while (q < end && *q != '\n') *q++ = ' ';
        } else if (q < end && *q != '\n') {
            return sss_fail(err, SSS_ERR_FORMAT, "%s: header: unexpected data after the counts (line %llu)", s->name,
                            line_of(base, q));
        }
    }
    for (ull v = 0; v < nv; v++) {
        for (int k = 0; k < 3; k++) {
            if (!off_tok(&p, end, &t))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: element vertex: file ends inside vertex %llu of %llu (truncated)",
                                s->name, v, nv);
            num_check c = check_float(t);
            if (c == NUM_NONFINITE)
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite ('" TOKF "', line %llu)",
                                s->name, v, TOKA(t), line_of(base, t.s));
            if (c == NUM_BAD)
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu: '" TOKF "' is not a number (line %llu)", s->name, v,
                                TOKA(t), line_of(base, t.s));
            ex->dpos[3 * v + (ull)k] = tok_double(t);
        }
        /* The reader discards the rest of a vertex line (normals, colours). */
        while (p < end && *p != '\n') p++;
        if (p < end) p++;
    }
    for (ull f = 0; f < nf; f++) {
        sll k;
        if (!off_tok(&p, end, &t))
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: element face: file ends inside face %llu of %llu (truncated)",
                            s->name, f, nf);
        if (!parse_int(t, &k) || k < 0)
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: bad vertex count '" TOKF "' (line %llu)", s->name, f,
                            TOKA(t), line_of(base, t.s));
        for (sll j = 0; j < k; j++) {
            sll v;
            if (!off_tok(&p, end, &t))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: element face: file ends inside face %llu of %llu (truncated)",
                                s->name, f, nf);
            if (!parse_int(t, &v))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)", s->name,
                                f, TOKA(t), line_of(base, t.s));
            if (v < 0 || (ull)v >= nv)
                return sss_fail(err, SSS_ERR_MESH, "%s: face %llu: vertex index %lld out of range [0, %llu)", s->name, f, v,
                                nv);
        }
        /* Face colours (or anything else) after the indices: blanked, as the
         * plain-OFF reader would take them for the next face. */
        while (p < end && *p != '\n') *p++ = ' ';
    }
    char hdr[96];
    int hl = snprintf(hdr, sizeof hdr, "OFF\n%llu %llu 0", nv, nf);
    char *start = put_header(s, body, hdr, (size_t)hl);
    if (!start) return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header too large to rewrite", s->name);
    ex->fmt = SSS_OM_OFF;
    ex->om_data = start;
    ex->om_len = (size_t)(p - start);
    ex->nv = nv;
    ex->nf = nf;
    ex->faces_in_file = nf;
    return SSS_OK;
}

/* ---------------------------------------------------------------------------
 * Line iteration for OBJ and ascii STL: lines split at '\n', trimmed of
 * " \t\r" like the readers do.
 * ------------------------------------------------------------------------- */

typedef struct line_it {
    char *p, *end;
    ull no;
} line_it;

/* Next line as [*b, *e) trimmed; 0 at the end. */
static int next_line(line_it *it, char **b, char **e)
{
    if (it->p >= it->end) return 0;
    char *s = it->p;
    char *nl = memchr(s, '\n', (size_t)(it->end - s));
    char *le = nl ? nl : it->end;
    it->p = nl ? nl + 1 : it->end;
    it->no++;
    while (s < le && (*s == ' ' || *s == '\t' || *s == '\r')) s++;
    while (le > s && (le[-1] == ' ' || le[-1] == '\t' || le[-1] == '\r')) le--;
    *b = s;
    *e = le;
    return 1;
}

/* ---------------------------------------------------------------------------
 * OBJ
 * ------------------------------------------------------------------------- */

static int cmp_sll(const void *a, const void *b)
{
    sll x = *(const sll *)a, y = *(const sll *)b;
    return (x > y) - (x < y);
}

/* Number of distinct values in v[0..n); sorts v when n is large. */
static size_t count_distinct(sll *v, size_t n)
{
    if (n <= 32) {
        size_t d = 0;
        for (size_t i = 0; i < n; i++) {
            size_t j = 0;
            while (j < i && v[j] != v[i]) j++;
            d += j == i;
        }
        return d;
    }
    qsort(v, n, sizeof *v, cmp_sll);
    size_t d = n ? 1 : 0;
    for (size_t i = 1; i < n; i++) d += v[i] != v[i - 1];
    return d;
}

static sss_result prepare_obj(src *s, expect *ex, sss_error *err)
{
    sss_result r = src_read_all(s, err);
    if (r != SSS_OK) return r;
    char *base = s->data, *end = s->data + s->size, *b, *e;
    tok t;

    /* Pass 1: how many vertices (indices may refer forward). */
    ull nv_total = 0;
    line_it it = {base, end, 0};
    while (next_line(&it, &b, &e)) {
        if (b == e || *b == '#' || is_space(*b)) continue;
        char *q = b;
        if (next_tok(&q, e, &t) && tok_is(t, "v")) nv_total++;
    }
    if (nv_total > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu vertices; at most 4294967294 are supported", s->name, nv_total);

    if (!(ex->dpos = alloc_dpos(s, nv_total, err))) return SSS_ERR_NOMEM;

    /* Pass 2: validate, predict what the reader adds, neutralise the rest. */
    size_t cap_idx = 64, cap_drop = 1024;
    sll *ids = malloc(cap_idx * sizeof *ids);
    unsigned char *drop = malloc(cap_drop);
    if (!ids || !drop) {
        free(ids); free(drop);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", s->name);
    }
    ull nv_seen = 0, nfaces = 0, added = 0;
    it = (line_it){base, end, 0};
    r = SSS_OK;
    while (r == SSS_OK && next_line(&it, &b, &e)) {
        if (b == e || *b == '#' || is_space(*b)) continue;
        char *q = b;
        tok kw;
        next_tok(&q, e, &kw);
        if (tok_is(kw, "v")) {
            for (int k = 0; k < 3; k++) {
                if (!next_tok(&q, e, &t)) {
                    r = sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu (line %llu): fewer than 3 coordinates", s->name,
                                 nv_seen, it.no);
                    break;
                }
                num_check c = check_float(t);
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
            while (r == SSS_OK && next_tok(&q, e, &t)) {
                tok c0 = t;
                char *slash = memchr(t.s, '/', t.n);
                if (slash) c0.n = (size_t)(slash - t.s);
                sll v;
                if (!parse_int(c0, &v)) {
                    r = sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)", s->name,
                                 nfaces, TOKA(t), it.no);
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
            size_t d = count_distinct(ids, n);
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
            /* vt, vn, mtllib, usemtl, g, o, s, l, ...: nothing the bake needs,
             * and the reader fails on a one-number vt or opens material files. */
            *b = '#';
        }
    }
    free(ids);
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

/* ---------------------------------------------------------------------------
 * STL
 * ------------------------------------------------------------------------- */

static float le_float(const unsigned char *b)
{
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static int has_word_ci(const char *p, size_t n, const char *w)
{
    size_t k = strlen(w);
    for (size_t i = 0; i + k <= n; i++) {
        size_t j = 0;
        while (j < k && lower(p[i + j]) == w[j]) j++;
        if (j == k) return 1;
    }
    return 0;
}

static sss_result prepare_stl(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = src_read(s, n, err);
    if (r != SSS_OK) return r;
    const unsigned char *u = (const unsigned char *)s->data;
    ull count = s->size >= 84 ? rd_uint(u + 80, 4, 0) : 0;
    int binary = s->size >= 84 && 84 + 50 * count == s->size;
    int ascii = 0;
    if (!binary) {
        /* "solid", then "facet" or "endsolid" after the first line. */
        size_t i = 0;
        while (i < n && is_space(s->data[i])) i++;
        if (n - i >= 5 && has_word_ci(s->data + i, 5, "solid")) {
            char *nl = memchr(s->data + i, '\n', n - i);
            if (nl) {
                size_t rest = n - (size_t)(nl - s->data);
                size_t look = rest < 4096 ? rest : 4096;
                ascii = has_word_ci(nl, look, "facet") || has_word_ci(nl, look, "endsolid");
            }
        }
    }
    if (!binary && !ascii) {
        if (s->size < 84)
            return sss_fail(err, SSS_ERR_FORMAT,
                            "%s: not an STL file (%llu bytes: too short for binary STL, and not ascii 'solid ... facet')",
                            s->name, s->size);
        return sss_fail(err, SSS_ERR_CORRUPT,
                        "%s: binary STL: declares %llu triangles (%llu bytes) but the file has %llu bytes", s->name, count,
                        84 + 50 * count, s->size);
    }
    r = src_read_all(s, err);
    if (r != SSS_OK) return r;
    if (binary) {
        u = (const unsigned char *)s->data;
        for (ull f = 0; f < count; f++)
            for (int k = 0; k < 9; k++)
                if (!isfinite(le_float(u + 84 + 50 * f + 12 + 4 * k)))
                    return sss_fail(err, SSS_ERR_MESH, "%s: triangle %llu: vertex %d: coordinate is not finite", s->name, f,
                                    k / 3);
        ex->fmt = SSS_OM_STL_BINARY;
        ex->om_data = s->data;
        ex->om_len = (size_t)s->size;
        ex->nf_max = count;
        ex->faces_in_file = count;
    } else {
        char *b, *e;
        line_it it = {s->data, s->data + s->size, 0};
        ull ntri = 0;
        while (next_line(&it, &b, &e)) {
            tok w;
            char *q = b;
            if (!next_tok(&q, e, &w)) continue;
            if (tok_is_ci(w, "solid") || tok_is_ci(w, "endsolid")) {
                /* The solid's name could contain "outer" or "facet normal". */
                while (q < e) *q++ = ' ';
                continue;
            }
            size_t ln = (size_t)(e - b);
            int outer = 0;
            for (size_t i = 0; i + 5 <= ln && !outer; i++)
                outer = memcmp(b + i, "outer", 5) == 0 || memcmp(b + i, "OUTER", 5) == 0;
            if (!outer) continue;
            for (int k = 0; k < 3; k++) {
                if (!next_line(&it, &b, &e) || (q = b, !next_tok(&q, e, &w)) || !tok_is_ci(w, "vertex"))
                    return sss_fail(err, SSS_ERR_CORRUPT, "%s: triangle %llu: expected 'vertex x y z' on line %llu", s->name,
                                    ntri, it.no);
                for (int c = 0; c < 3; c++) {
                    tok t;
                    if (!next_tok(&q, e, &t))
                        return sss_fail(err, SSS_ERR_CORRUPT, "%s: triangle %llu: vertex %d: fewer than 3 coordinates (line %llu)",
                                        s->name, ntri, k, it.no);
                    num_check ck = check_float(t);
                    if (ck == NUM_NONFINITE)
                        return sss_fail(err, SSS_ERR_MESH, "%s: triangle %llu: vertex %d: coordinate is not finite ('" TOKF "', line %llu)",
                                        s->name, ntri, k, TOKA(t), it.no);
                    if (ck == NUM_BAD)
                        return sss_fail(err, SSS_ERR_CORRUPT, "%s: triangle %llu: vertex %d: '" TOKF "' is not a number (line %llu)",
                                        s->name, ntri, k, TOKA(t), it.no);
                }
            }
            ntri++;
        }
        ex->fmt = SSS_OM_STL_ASCII;
        ex->om_data = s->data;
        ex->om_len = (size_t)s->size;
        ex->nf_max = ntri;
        ex->faces_in_file = ntri;
    }
    ex->nv = ULLONG_MAX;
    ex->nv_max = 3 * ex->nf_max;
    ex->nf = ULLONG_MAX;
    return SSS_OK;
}

/* ---------------------------------------------------------------------------
 * Soup -> mesh
 * ------------------------------------------------------------------------- */

static int zero_area(const float *pos, uint32_t a, uint32_t b, uint32_t c)
{
    const float *p0 = pos + 3 * (size_t)a, *p1 = pos + 3 * (size_t)b, *p2 = pos + 3 * (size_t)c;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)p1[k] - (double)p0[k];
        e2[k] = (double)p2[k] - (double)p0[k];
    }
    double x = e1[1] * e2[2] - e1[2] * e2[1];
    double y = e1[2] * e2[0] - e1[0] * e2[2];
    double z = e1[0] * e2[1] - e1[1] * e2[0];
    return x == 0.0 && y == 0.0 && z == 0.0;
}

static int has_repeat(const int32_t *v, uint32_t n, sll *scratch)
{
    if (n <= 32) {
        for (uint32_t i = 1; i < n; i++)
            for (uint32_t j = 0; j < i; j++)
                if (v[i] == v[j]) return 1;
        return 0;
    }
    for (uint32_t i = 0; i < n; i++) scratch[i] = v[i];
    return count_distinct(scratch, n) != n;
}

/* ---------------------------------------------------------------------------
 * Recentring (docs/robustness.md B6)
 * ------------------------------------------------------------------------- */

/* A mesh whose bounding-box centre c lies farther from the origin than
 * RECENTRE_RATIO times its half-size h (largest half-extent) is moved by -c,
 * in double, before its positions become float32. float32 spacing at |x| is
 * |x|·2^-23; the bake starts shadow rays 1e-5 of the bounding-box diagonal
 * (>= 2e-5·h) off the surface (visibility.c), which at |c| = 16h is still
 * about 10 float steps. Nearer meshes keep their coordinates, so their bakes
 * stay byte-identical; farther ones lost triangles to rounding and shadowed
 * themselves (a unit sphere at 10^6: spacing 1/16, 9,152 of 16,128 triangles
 * collapsed, 15 % of rays blocked). */
#define RECENTRE_RATIO 16.0

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* used[v] != UINT32_MAX marks the vertices that faces of 3 or more corners
 * use; only those decide the box and move: they lie within h of c, so the
 * result is finite; the others are removed later anyway. */
static void recentre(sss_om_soup *s, const expect *ex, const uint32_t *used, sss_import_report *rep)
{
    ull nv = s->nv;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (ull v = 0; v < nv; v++) {
        if (used[v] == UINT32_MAX) continue;
        for (int k = 0; k < 3; k++) {
            double x = ex->dpos ? ex->dpos[3 * v + (ull)k] : (double)s->pos[3 * v + (ull)k];
            if (x < lo[k]) lo[k] = x;
            if (x > hi[k]) hi[k] = x;
        }
    }
    double c[3], h = 0.0, cmax = 0.0;
    for (int k = 0; k < 3; k++) {
        if (!(lo[k] <= hi[k])) return; /* no face uses a vertex */
        double half = 0.5 * (hi[k] - lo[k]);
        c[k] = lo[k] + half;
        if (half > h) h = half;
        if (fabs(c[k]) > cmax) cmax = fabs(c[k]);
    }
    if (!(h > 0.0) || cmax <= RECENTRE_RATIO * h) return;
    for (ull v = 0; v < nv; v++) {
        if (used[v] == UINT32_MAX) continue;
        for (int k = 0; k < 3; k++) {
            double x = ex->dpos ? ex->dpos[3 * v + (ull)k] : (double)s->pos[3 * v + (ull)k];
            s->pos[3 * v + (ull)k] = (float)(x - c[k]);
        }
    }
    rep->recentred = 1;
    for (int k = 0; k < 3; k++) rep->offset[k] = c[k];
}

/* ---------------------------------------------------------------------------
 * Polygon triangulation (docs/robustness.md B7)
 * ------------------------------------------------------------------------- */

typedef struct poly_scratch {
    double *xy;       /* 2 per corner: coordinates in the polygon's plane */
    uint32_t *prev, *next, *reflex;
    unsigned char *is_reflex;
    /* Ear clipping is cubic at worst (a full pass per ear, every reflex
     * corner tested): the steps a mesh may spend on it in all are capped so
     * that a hostile file (thousands of jagged polygons) still imports in
     * bounded time; past the cap, polygons are fanned and warned. Reset
     * before each pass so both passes decide alike. */
    uint64_t budget;
} poly_scratch;

#define EAR_BUDGET ((uint64_t)1 << 28)

static void poly_scratch_free(poly_scratch *sc)
{
    free(sc->xy); free(sc->prev); free(sc->next); free(sc->reflex); free(sc->is_reflex);
    memset(sc, 0, sizeof *sc);
}

static int poly_scratch_alloc(poly_scratch *sc, uint32_t n)
{
    memset(sc, 0, sizeof *sc);
    if (n <= 3) return 1;
    size_t m = n < SSS_IMPORT_EAR_MAX ? n : SSS_IMPORT_EAR_MAX;
    sc->xy = malloc(2 * (size_t)n * sizeof(double));
    sc->prev = malloc(m * sizeof(uint32_t));
    sc->next = malloc(m * sizeof(uint32_t));
    sc->reflex = malloc(m * sizeof(uint32_t));
    sc->is_reflex = malloc(m);
    if (sc->xy && sc->prev && sc->next && sc->reflex && sc->is_reflex) return 1;
    poly_scratch_free(sc);
    return 0;
}

enum { POLY_FAN = 0, POLY_EAR, POLY_UNCLIPPED };

static double cross2(const double *xy, uint32_t a, uint32_t b, uint32_t c)
{
    return (xy[2 * b] - xy[2 * a]) * (xy[2 * c + 1] - xy[2 * a + 1]) -
           (xy[2 * b + 1] - xy[2 * a + 1]) * (xy[2 * c] - xy[2 * a]);
}

/* Corner b of the remaining polygon (a, b, c consecutive) is an ear: a left
 * turn, and no reflex corner lies inside or on the triangle (a convex
 * corner cannot lie in it unless a reflex one does). Corners at the same
 * position as a, b or c are not in the way. */
static int is_ear(const poly_scratch *sc, uint32_t nreflex, uint32_t a, uint32_t b, uint32_t c)
{
    const double *xy = sc->xy;
    if (!(cross2(xy, a, b, c) > 0.0)) return 0;
    for (uint32_t r = 0; r < nreflex; r++) {
        uint32_t p = sc->reflex[r];
        if (!sc->is_reflex[p] || p == a || p == b || p == c) continue;
        int same = 0;
        for (int k = 0; k < 3 && !same; k++) {
            uint32_t q = k == 0 ? a : k == 1 ? b : c;
            same = xy[2 * p] == xy[2 * q] && xy[2 * p + 1] == xy[2 * q + 1];
        }
        if (same) continue;
        if (cross2(xy, a, b, p) >= 0.0 && cross2(xy, b, c, p) >= 0.0 && cross2(xy, c, a, p) >= 0.0) return 0;
    }
    return 1;
}

/* Triangulates polygon v[0..n), n > 3, into n - 2 triangles whose corners
 * (positions 0..n-1 in v) go to tri, 3 each, in the polygon's winding.
 *
 * A convex polygon (every turn to the left of its best-fit plane's normal,
 * once around) is fanned from corner 0, as every polygon was before, so
 * existing meshes import unchanged. The fan of a non-convex polygon folds
 * over: a triangle comes out flipped and overlapping the others (B7: an
 * L-shaped hexagon of area 3 gave areas -0.5, 0.5, 2, 1). Those are
 * ear-clipped instead, in the plane of the Newell normal (the polygon's
 * plane if it is planar, a best fit if it is warped). Returns POLY_FAN,
 * POLY_EAR, or POLY_UNCLIPPED when no ear is left (a self-intersecting
 * polygon), the polygon has more than SSS_IMPORT_EAR_MAX corners, or the
 * mesh's ear-clipping budget is spent: what remains is fanned. */
static int triangulate(const float *pos, const int32_t *v, uint32_t n, poly_scratch *sc, uint32_t *tri)
{
#define P(i, k) ((double)pos[3 * (size_t)v[i] + (k)] - (double)pos[3 * (size_t)v[0] + (k)])
    double N[3] = {0.0, 0.0, 0.0};
    for (uint32_t i = 0; i < n; i++) {
        uint32_t j = i + 1 == n ? 0 : i + 1;
        N[0] += (P(i, 1) - P(j, 1)) * (P(i, 2) + P(j, 2));
        N[1] += (P(i, 2) - P(j, 2)) * (P(i, 0) + P(j, 0));
        N[2] += (P(i, 0) - P(j, 0)) * (P(i, 1) + P(j, 1));
    }
    double len = sqrt(N[0] * N[0] + N[1] * N[1] + N[2] * N[2]);
    int status = POLY_FAN;
    if (len > 0.0 && isfinite(len)) {
        for (int k = 0; k < 3; k++) N[k] /= len;
        /* u, w, N right-handed: u x w = N, so the polygon's winding is
         * counter-clockwise (positive area) in (u, w). */
        int ax = fabs(N[0]) <= fabs(N[1]) && fabs(N[0]) <= fabs(N[2]) ? 0 : fabs(N[1]) <= fabs(N[2]) ? 1 : 2;
        double e[3] = {0.0, 0.0, 0.0}, u[3], w[3];
        e[ax] = 1.0;
        u[0] = e[1] * N[2] - e[2] * N[1];
        u[1] = e[2] * N[0] - e[0] * N[2];
        u[2] = e[0] * N[1] - e[1] * N[0];
        double ul = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
        for (int k = 0; k < 3; k++) u[k] /= ul;
        w[0] = N[1] * u[2] - N[2] * u[1];
        w[1] = N[2] * u[0] - N[0] * u[2];
        w[2] = N[0] * u[1] - N[1] * u[0];
        double *xy = sc->xy;
        for (uint32_t i = 0; i < n; i++) {
            xy[2 * i] = P(i, 0) * u[0] + P(i, 1) * u[1] + P(i, 2) * u[2];
            xy[2 * i + 1] = P(i, 0) * w[0] + P(i, 1) * w[1] + P(i, 2) * w[2];
        }
        /* Convex: no right turn between successive edges of non-zero length
         * (a tolerance of 1e-12 relative keeps nearly straight corners
         * convex), and the turns add up to one full turn (a star polygon
         * turns left everywhere but twice around). */
        int convex = 1, nedges = 0;
        double turning = 0.0, first[2] = {0.0, 0.0}, last[2] = {0.0, 0.0};
        for (uint32_t i = 0; i < n && convex; i++) {
            uint32_t j = i + 1 == n ? 0 : i + 1;
            double d[2] = {xy[2 * j] - xy[2 * i], xy[2 * j + 1] - xy[2 * i + 1]};
            if (d[0] == 0.0 && d[1] == 0.0) continue;
            if (nedges++ == 0) {
                first[0] = d[0]; first[1] = d[1];
            } else {
                double cr = last[0] * d[1] - last[1] * d[0], dt = last[0] * d[0] + last[1] * d[1];
                if (cr < -1e-12 * hypot(last[0], last[1]) * hypot(d[0], d[1])) convex = 0;
                turning += atan2(cr, dt);
            }
            last[0] = d[0]; last[1] = d[1];
        }
        if (convex && nedges >= 3) {
            double cr = last[0] * first[1] - last[1] * first[0], dt = last[0] * first[0] + last[1] * first[1];
            if (cr < -1e-12 * hypot(last[0], last[1]) * hypot(first[0], first[1])) convex = 0;
            turning += atan2(cr, dt);
            if (fabs(turning - 2.0 * M_PI) > 1e-3) convex = 0;
        }
        if (!convex) status = n > SSS_IMPORT_EAR_MAX ? POLY_UNCLIPPED : POLY_EAR;
    }
#undef P
    uint32_t t = 0;
    if (status == POLY_EAR) {
        uint32_t *prev = sc->prev, *next = sc->next, nreflex = 0;
        for (uint32_t i = 0; i < n; i++) {
            prev[i] = i == 0 ? n - 1 : i - 1;
            next[i] = i + 1 == n ? 0 : i + 1;
        }
        for (uint32_t i = 0; i < n; i++) {
            sc->is_reflex[i] = !(cross2(sc->xy, prev[i], i, next[i]) > 0.0);
            if (sc->is_reflex[i]) sc->reflex[nreflex++] = i;
        }
        uint32_t m = n, cur = 0, stall = 0;
        while (m > 3) {
            uint32_t a = prev[cur], c = next[cur];
            if (sc->budget <= (uint64_t)nreflex + 1) { sc->budget = 0; status = POLY_UNCLIPPED; break; }
            sc->budget -= (uint64_t)nreflex + 1;
            if (is_ear(sc, nreflex, a, cur, c)) {
                tri[3 * t] = a; tri[3 * t + 1] = cur; tri[3 * t + 2] = c;
                t++;
                next[a] = c;
                prev[c] = a;
                sc->is_reflex[cur] = 0;
                m--;
                /* Clipping an ear can only make its neighbours convex. */
                if (sc->is_reflex[a] && cross2(sc->xy, prev[a], a, c) > 0.0) sc->is_reflex[a] = 0;
                if (sc->is_reflex[c] && cross2(sc->xy, a, c, next[c]) > 0.0) sc->is_reflex[c] = 0;
                cur = c;
                stall = 0;
            } else {
                cur = c;
                if (++stall >= m) { status = POLY_UNCLIPPED; break; }
            }
        }
        if (status == POLY_EAR) {
            tri[3 * t] = prev[cur]; tri[3 * t + 1] = cur; tri[3 * t + 2] = next[cur];
            return POLY_EAR;
        }
        /* No ear: fan what is left from cur. */
        for (uint32_t b = next[cur]; next[b] != cur; b = next[b]) {
            tri[3 * t] = cur; tri[3 * t + 1] = b; tri[3 * t + 2] = next[b];
            t++;
        }
        return POLY_UNCLIPPED;
    }
    for (uint32_t k = 1; k + 1 < n; k++) {
        tri[3 * t] = 0; tri[3 * t + 1] = k; tri[3 * t + 2] = k + 1;
        t++;
    }
    return status;
}

/* ---------------------------------------------------------------------------
 * Duplicate triangles and orientation (docs/robustness.md B5)
 * ------------------------------------------------------------------------- */

typedef struct tri_key {
    uint32_t v[3]; /* sorted */
    uint32_t f;
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    for (int k = 0; k < 3; k++)
        if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
    return (a->f > b->f) - (a->f < b->f);
}

/* Drops every triangle on the same three vertices as an earlier one (in
 * either winding). Copies add their area to the vertices twice (B5: mean q
 * +40 %), and an opposite-winding copy cancels the vertex normals (q = 0
 * everywhere). The first one stays; the orientation pass then decides its
 * winding. */
static sss_result drop_duplicates(const char *name, sss_mesh *m, sss_import_report *rep, sss_error *err)
{
    tri_key *key = malloc((size_t)m->nf * sizeof *key + 1);
    unsigned char *dup = calloc((size_t)m->nf + 1, 1);
    if (!key || !dup) {
        free(key); free(dup);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %u triangles", name, m->nf);
    }
    for (uint32_t f = 0; f < m->nf; f++) {
        uint32_t a = m->tri[3 * (size_t)f], b = m->tri[3 * (size_t)f + 1], c = m->tri[3 * (size_t)f + 2], x;
        if (a > b) { x = a; a = b; b = x; }
        if (b > c) { x = b; b = c; c = x; }
        if (a > b) { x = a; a = b; b = x; }
        key[f] = (tri_key){{a, b, c}, f};
    }
    qsort(key, m->nf, sizeof *key, cmp_tri_key);
    uint64_t ndup = 0;
    for (uint32_t i = 1; i < m->nf; i++)
        if (memcmp(key[i].v, key[i - 1].v, sizeof key[i].v) == 0) {
            dup[key[i].f] = 1;
            ndup++;
        }
    free(key);
    if (ndup) {
        uint32_t t = 0;
        for (uint32_t f = 0; f < m->nf; f++)
            if (!dup[f]) {
                memmove(m->tri + 3 * (size_t)t, m->tri + 3 * (size_t)f, 3 * sizeof(uint32_t));
                t++;
            }
        m->nf = t;
    }
    free(dup);
    rep->faces_duplicate = ndup;
    return SSS_OK;
}

static int cmp_u64(const void *pa, const void *pb)
{
    uint64_t a = *(const uint64_t *)pa, b = *(const uint64_t *)pb;
    return (a > b) - (a < b);
}

/* Edge k of triangle t runs tri[k] -> tri[(k+1)%3]. */
static int edge_of(const uint32_t *t, uint32_t lo, uint32_t hi, int *forward)
{
    for (int k = 0; k < 3; k++) {
        uint32_t a = t[k], b = t[(k + 1) % 3];
        if ((a == lo && b == hi) || (a == hi && b == lo)) {
            *forward = a == lo;
            return k;
        }
    }
    return -1;
}

#define NB_NONE UINT32_MAX

typedef struct comp_info {
    uint64_t nfaces, nflip;
    uint32_t seed;
    int closed;
    double volume;       /* 6 x signed volume, in the orientation relative to the seed */
    double lo[3], hi[3]; /* bounding box */
    int invert;          /* decision: reverse every flip of the component */
} comp_info;

/* Does the ray from o along d cross triangle (a, b, c)? Möller–Trumbore in
 * double, t > 0. */
static int ray_hits(const double o[3], const double d[3], const double a[3], const double b[3], const double c[3])
{
    double e1[3], e2[3], p[3], s[3], q[3];
    for (int k = 0; k < 3; k++) { e1[k] = b[k] - a[k]; e2[k] = c[k] - a[k]; s[k] = o[k] - a[k]; }
    p[0] = d[1] * e2[2] - d[2] * e2[1];
    p[1] = d[2] * e2[0] - d[0] * e2[2];
    p[2] = d[0] * e2[1] - d[1] * e2[0];
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0.0) return 0;
    double inv = 1.0 / det;
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inv;
    if (u < 0.0 || u > 1.0) return 0;
    q[0] = s[1] * e1[2] - s[2] * e1[1];
    q[1] = s[2] * e1[0] - s[0] * e1[2];
    q[2] = s[0] * e1[1] - s[1] * e1[0];
    double w = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inv;
    if (w < 0.0 || u + w > 1.0) return 0;
    return (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inv > 0.0;
}

static void vpos(const sss_mesh *m, uint32_t v, double p[3])
{
    for (int k = 0; k < 3; k++) p[k] = m->pos[3 * (size_t)v + k];
}

/* Makes the winding consistent and outward (B5: normals follow the winding
 * and shadow rays start along them, so an inside-out cube baked q = 0 and a
 * sphere with half its triangles flipped lost 60 % of its mean q).
 *
 * Triangles are grouped into surfaces (connected through manifold edges:
 * exactly two triangles); a breadth-first walk from each surface's first
 * triangle flips its neighbours to agree with it. A closed surface (every
 * edge manifold and consistent) is then turned outward by its signed
 * volume: a negative one is inverted, unless it lies inside another closed
 * surface (ray parity), where it may be a cavity (a hollow shell's inner
 * wall faces inward) or a solid inside a solid, which the file must decide.
 * An open surface keeps the winding of the majority of its triangles (ties:
 * its first triangle's). Edges still inconsistent afterwards (a
 * non-orientable surface) are counted for a warning. A consistently wound,
 * outward mesh is left as it is. */
static sss_result orient(const char *name, sss_mesh *m, sss_import_report *rep, sss_error *err)
{
    const uint32_t nv = m->nv, nf = m->nf;
    const uint32_t *tri = m->tri;
    uint64_t *bstart = calloc((size_t)nv + 2, sizeof *bstart);
    uint64_t *he = malloc(3 * (size_t)nf * sizeof *he + 1);
    uint32_t *nb = malloc(3 * (size_t)nf * sizeof *nb + 1);
    unsigned char *same = calloc(3 * (size_t)nf + 1, 1);
    if (!bstart || !he || !nb || !same) {
        free(bstart); free(he); free(nb); free(same);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the edges of %u triangles", name, nf);
    }
    /* Half-edges bucketed by their smaller vertex, sorted by (larger
     * vertex, triangle): equal edges end up adjacent, in triangle order. */
    for (size_t i = 0; i < 3 * (size_t)nf; i++) {
        uint32_t a = tri[i], b = tri[i % 3 == 2 ? i - 2 : i + 1];
        bstart[(a < b ? a : b) + 2]++;
    }
    for (size_t v = 2; v < (size_t)nv + 2; v++) bstart[v] += bstart[v - 1];
    for (size_t i = 0; i < 3 * (size_t)nf; i++) {
        uint32_t a = tri[i], b = tri[i % 3 == 2 ? i - 2 : i + 1];
        uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
        he[bstart[lo + 1]++] = (uint64_t)hi << 32 | (uint64_t)(i / 3);
    }
    for (size_t i = 0; i < 3 * (size_t)nf; i++) nb[i] = NB_NONE;
    for (uint32_t lo = 0; lo < nv; lo++) {
        uint64_t b0 = bstart[lo], b1 = bstart[lo + 1];
        if (b1 - b0 > 1) qsort(he + b0, (size_t)(b1 - b0), sizeof *he, cmp_u64);
        for (uint64_t i = b0; i < b1;) {
            uint64_t j = i + 1;
            while (j < b1 && he[j] >> 32 == he[i] >> 32) j++;
            if (j - i == 2) { /* manifold edge: exactly two triangles */
                uint32_t hi = (uint32_t)(he[i] >> 32), f = (uint32_t)he[i], g = (uint32_t)he[i + 1];
                int ff = 0, fg = 0;
                int kf = edge_of(tri + 3 * (size_t)f, lo, hi, &ff), kg = edge_of(tri + 3 * (size_t)g, lo, hi, &fg);
                nb[3 * (size_t)f + (size_t)kf] = g;
                nb[3 * (size_t)g + (size_t)kg] = f;
                /* same direction in both: they disagree as stored */
                same[3 * (size_t)f + (size_t)kf] = same[3 * (size_t)g + (size_t)kg] = ff == fg;
            }
            i = j;
        }
    }
    free(he);
    free(bstart);

    uint32_t *comp = malloc((size_t)nf * sizeof *comp + 1);
    uint32_t *queue = malloc((size_t)nf * sizeof *queue + 1);
    unsigned char *flip = calloc((size_t)nf + 1, 1);
    size_t ccap = 16, ncomp = 0;
    comp_info *ci = malloc(ccap * sizeof *ci);
    uint32_t *cstart = NULL, *cface = queue;
    sss_result r = SSS_OK;
    if (!comp || !queue || !flip || !ci) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces of %u triangles", name, nf);
        goto done;
    }
    for (uint32_t f = 0; f < nf; f++) comp[f] = NB_NONE;
    for (uint32_t seed = 0; seed < nf; seed++) {
        if (comp[seed] != NB_NONE) continue;
        if (ncomp == ccap) {
            comp_info *nc = realloc(ci, 2 * ccap * sizeof *ci);
            if (!nc) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces", name); goto done; }
            ci = nc;
            ccap *= 2;
        }
        comp_info *c = &ci[ncomp];
        memset(c, 0, sizeof *c);
        c->seed = seed;
        c->closed = 1;
        uint32_t qh = 0, qt = 0;
        queue[qt++] = seed;
        comp[seed] = (uint32_t)ncomp;
        while (qh < qt) {
            uint32_t f = queue[qh++];
            for (int k = 0; k < 3; k++) {
                uint32_t g = nb[3 * (size_t)f + (size_t)k];
                if (g == NB_NONE) { c->closed = 0; continue; }
                unsigned char want = flip[f] ^ same[3 * (size_t)f + (size_t)k];
                if (comp[g] == NB_NONE) {
                    comp[g] = (uint32_t)ncomp;
                    flip[g] = want;
                    queue[qt++] = g;
                } else if (flip[g] != want) {
                    c->closed = 0; /* non-orientable */
                }
            }
        }
        c->nfaces = qt;
        double ref[3];
        vpos(m, tri[3 * (size_t)seed], ref);
        for (int k = 0; k < 3; k++) { c->lo[k] = INFINITY; c->hi[k] = -INFINITY; }
        for (uint32_t i = 0; i < qt; i++) {
            uint32_t f = queue[i];
            c->nflip += flip[f];
            double p[3][3];
            for (int j = 0; j < 3; j++) {
                vpos(m, tri[3 * (size_t)f + (size_t)j], p[j]);
                for (int k = 0; k < 3; k++) {
                    if (p[j][k] < c->lo[k]) c->lo[k] = p[j][k];
                    if (p[j][k] > c->hi[k]) c->hi[k] = p[j][k];
                    p[j][k] -= ref[k];
                }
            }
            if (c->closed) {
                double det = p[0][0] * (p[1][1] * p[2][2] - p[1][2] * p[2][1]) -
                             p[0][1] * (p[1][0] * p[2][2] - p[1][2] * p[2][0]) +
                             p[0][2] * (p[1][0] * p[2][1] - p[1][1] * p[2][0]);
                c->volume += flip[f] ? -det : det;
            }
        }
        ncomp++;
    }

    /* Closed surfaces facing inward; the faces of each surface, for their
     * containment test. */
    uint64_t nneg = 0;
    for (size_t i = 0; i < ncomp; i++) nneg += ci[i].closed && ci[i].volume < 0.0;
    if (nneg) {
        cstart = calloc(ncomp + 2, sizeof *cstart);
        if (!cstart) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the surfaces", name); goto done; }
        for (uint32_t f = 0; f < nf; f++) cstart[comp[f] + 2]++;
        for (size_t i = 2; i < ncomp + 2; i++) cstart[i] += cstart[i - 1];
        for (uint32_t f = 0; f < nf; f++) cface[cstart[comp[f] + 1]++] = f;
    }
    /* The containment test costs a bounding-box check per pair of
     * surfaces and a ray test per triangle of each candidate container:
     * beyond 2^26 pairs or 2^28 triangle tests in all (thousands of
     * inside-out parts in a large closed one) the remaining negative
     * surfaces are taken as not nested, so the work stays bounded. */
    const int test_nesting = nneg * (uint64_t)ncomp <= ((uint64_t)1 << 26);
    uint64_t ray_budget = (uint64_t)1 << 28;
    /* A direction no axis-aligned mesh lines up with. */
    const double dir[3] = {0.5376, 0.6812, 0.4968};
    for (size_t i = 0; i < ncomp; i++) {
        comp_info *c = &ci[i];
        if (!c->closed || c->volume == 0.0) {
            c->invert = 2 * c->nflip > c->nfaces; /* open: the majority's winding */
            continue;
        }
        if (c->volume > 0.0) continue; /* outward */
        int nested = 0;
        if (test_nesting && ray_budget > 0) {
            /* the centroid of the seed triangle, in the final positions */
            double o[3] = {0.0, 0.0, 0.0}, p[3];
            for (int j = 0; j < 3; j++) {
                vpos(m, tri[3 * (size_t)c->seed + (size_t)j], p);
                for (int k = 0; k < 3; k++) o[k] += p[k] / 3.0;
            }
            for (size_t e = 0; e < ncomp && !nested; e++) {
                const comp_info *d = &ci[e];
                if (e == i || !d->closed) continue;
                int inside_box = 1;
                for (int k = 0; k < 3; k++) inside_box &= d->lo[k] <= c->lo[k] && c->hi[k] <= d->hi[k];
                if (!inside_box) continue;
                uint64_t len = cstart[e + 1] - cstart[e];
                if (len > ray_budget) { ray_budget = 0; break; }
                ray_budget -= len;
                uint64_t hits = 0;
                for (uint32_t q = cstart[e]; q < cstart[e + 1]; q++) {
                    const uint32_t *t = tri + 3 * (size_t)cface[q];
                    double a[3], b[3], cc[3];
                    vpos(m, t[0], a); vpos(m, t[1], b); vpos(m, t[2], cc);
                    hits += (uint64_t)ray_hits(o, dir, a, b, cc);
                }
                nested = hits % 2 == 1;
            }
        }
        c->invert = !nested;
    }
    /* Apply; count. */
    uint32_t *t = m->tri;
    for (uint32_t f = 0; f < nf; f++) {
        const comp_info *c = &ci[comp[f]];
        if (!(flip[f] ^ (unsigned char)c->invert)) continue;
        uint32_t x = t[3 * (size_t)f + 1];
        t[3 * (size_t)f + 1] = t[3 * (size_t)f + 2];
        t[3 * (size_t)f + 2] = x;
        if (c->closed) rep->faces_flipped++;
        else rep->open_faces_flipped++;
    }
    for (size_t i = 0; i < ncomp; i++) {
        const comp_info *c = &ci[i];
        uint64_t final_flips = c->invert ? c->nfaces - c->nflip : c->nflip;
        if (c->closed && 2 * final_flips > c->nfaces) rep->surfaces_inside_out++;
    }
    /* Manifold edges whose triangles disagree after all (each edge once). */
    for (uint32_t f = 0; f < nf; f++)
        for (int k = 0; k < 3; k++) {
            uint32_t g = nb[3 * (size_t)f + (size_t)k];
            if (g == NB_NONE || g < f) continue;
            unsigned char ef = flip[f] ^ (unsigned char)ci[comp[f]].invert;
            unsigned char eg = flip[g] ^ (unsigned char)ci[comp[g]].invert;
            if ((ef ^ eg) != same[3 * (size_t)f + (size_t)k]) rep->orientation_conflicts++;
        }
done:
    free(cstart);
    free(nb);
    free(same);
    free(comp);
    free(queue);
    free(flip);
    free(ci);
    return r;
}

static sss_result build_mesh(const char *name, sss_om_soup *s, const expect *ex, sss_mesh *out, sss_import_report *rep,
                             sss_error *err)
{
    ull nv = s->nv;
    rep->vertices_read = nv;
    rep->faces_read = ex->faces_in_file;
    rep->faces_too_small = ex->too_small;
    rep->faces_repeated_index = ex->repeated;
    if (nv > (ull)UINT32_MAX - 1)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu vertices; at most 4294967294 are supported", name, nv);
    for (ull v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++)
            if (!isfinite(s->pos[3 * v + (ull)k]))
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite", name, v);
    /* remap first marks (0) the vertices faces of 3 or more corners use,
     * for recentre; pass 1 below marks the ones kept. */
    uint32_t *remap = malloc(((size_t)nv + 1) * sizeof *remap);
    if (!remap) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", name, nv);
    for (ull v = 0; v < nv; v++) remap[v] = UINT32_MAX;
    uint32_t maxn = 0;
    {
        ull off = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            if (n > maxn) maxn = n;
            for (uint32_t i = 0; i < n; i++) {
                int32_t v = s->idx[off + i];
                if (v < 0 || (ull)v >= nv) {
                    free(remap);
                    return sss_fail(err, SSS_ERR_MESH, "%s: face %llu: vertex index %d out of range [0, %llu)", name, f, v, nv);
                }
                if (n >= 3) remap[v] = 0;
            }
            off += n;
        }
    }
    recentre(s, ex, remap, rep);
    sll *scratch = maxn > 32 ? malloc((size_t)maxn * sizeof *scratch) : NULL;
    uint32_t *ptri = maxn > 3 ? malloc(3 * ((size_t)maxn - 2) * sizeof *ptri) : NULL;
    poly_scratch ps;
    int ps_ok = poly_scratch_alloc(&ps, maxn);
    if ((maxn > 32 && !scratch) || (maxn > 3 && !ptri) || !ps_ok) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", name, nv);
    }
    for (ull v = 0; v < nv; v++) remap[v] = UINT32_MAX;

    /* Pass 1: classify faces, count triangles, mark the vertices kept. */
    ull ntri = 0;
    ps.budget = EAR_BUDGET;
    {
        ull off = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            const int32_t *v = s->idx + off;
            off += n;
            if (ex->drop && ex->drop[f]) continue; /* counted by the scan */
            if (n < 3) { rep->faces_too_small++; continue; }
            if (has_repeat(v, n, scratch)) { rep->faces_repeated_index++; continue; }
            static const uint32_t one[3] = {0, 1, 2};
            const uint32_t *pt = one;
            if (n > 3) {
                rep->polygons_triangulated++;
                int how = triangulate(s->pos, v, n, &ps, ptri);
                rep->polygons_ear_clipped += how == POLY_EAR;
                rep->polygons_unclipped += how == POLY_UNCLIPPED;
                pt = ptri;
            }
            for (uint32_t k = 0; k + 2 < n; k++) {
                uint32_t a = (uint32_t)v[pt[3 * k]], b = (uint32_t)v[pt[3 * k + 1]], c = (uint32_t)v[pt[3 * k + 2]];
                if (zero_area(s->pos, a, b, c)) {
                    rep->faces_zero_area++;
                    continue;
                }
                ntri++;
                remap[a] = remap[b] = remap[c] = 0;
            }
        }
    }
    if (ntri == 0) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_MESH, "%s: no triangles left after repair (%llu faces read)", name, ex->faces_in_file);
    }
    if (ntri > UINT32_MAX) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %llu triangles; at most 4294967295 are supported", name, ntri);
    }
    uint32_t nv2 = 0;
    for (ull v = 0; v < nv; v++)
        if (remap[v] == 0) remap[v] = nv2++;
    rep->vertices_unreferenced = nv - nv2;

    sss_result r = sss_mesh_alloc(out, nv2, (uint32_t)ntri, err);
    if (r != SSS_OK) {
        free(scratch); free(remap); free(ptri); poly_scratch_free(&ps);
        return r;
    }
    for (ull v = 0; v < nv; v++)
        if (remap[v] != UINT32_MAX) memcpy(out->pos + 3 * (size_t)remap[v], s->pos + 3 * v, 3 * sizeof(float));

    /* Pass 2: the same decisions, writing the triangles. */
    ps.budget = EAR_BUDGET;
    {
        ull off = 0, t = 0;
        for (ull f = 0; f < s->nf; f++) {
            uint32_t n = s->fsize[f];
            const int32_t *v = s->idx + off;
            off += n;
            if ((ex->drop && ex->drop[f]) || n < 3 || has_repeat(v, n, scratch)) continue;
            static const uint32_t one[3] = {0, 1, 2};
            const uint32_t *pt = one;
            if (n > 3) {
                triangulate(s->pos, v, n, &ps, ptri);
                pt = ptri;
            }
            for (uint32_t k = 0; k + 2 < n; k++) {
                uint32_t a = (uint32_t)v[pt[3 * k]], b = (uint32_t)v[pt[3 * k + 1]], c = (uint32_t)v[pt[3 * k + 2]];
                if (zero_area(s->pos, a, b, c)) continue;
                out->tri[3 * t + 0] = remap[a];
                out->tri[3 * t + 1] = remap[b];
                out->tri[3 * t + 2] = remap[c];
                t++;
            }
        }
    }
    free(scratch);
    free(remap);
    free(ptri);
    poly_scratch_free(&ps);
    r = drop_duplicates(name, out, rep, err);
    if (r == SSS_OK) r = orient(name, out, rep, err);
    if (r == SSS_OK) r = sss_mesh_compute_normals_areas(out, name, err);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}

/* ---------------------------------------------------------------------------
 * Public API
 * ------------------------------------------------------------------------- */

typedef enum { FMT_UNKNOWN, FMT_PLY, FMT_OBJ, FMT_OFF, FMT_STL } file_format;

static file_format format_of(const char *path, const char **ext)
{
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    *ext = dot ? dot : "";
    if (!dot) return FMT_UNKNOWN;
    tok t = {(char *)(dot + 1), strlen(dot + 1)};
    if (tok_is_ci(t, "ply")) return FMT_PLY;
    if (tok_is_ci(t, "obj")) return FMT_OBJ;
    if (tok_is_ci(t, "off")) return FMT_OFF;
    if (tok_is_ci(t, "stl")) return FMT_STL;
    return FMT_UNKNOWN;
}

sss_result sss_import_mesh(const char *path, sss_mesh *out, sss_import_report *rep, sss_error *err)
{
    sss_import_report local;
    if (!rep) rep = &local;
    memset(rep, 0, sizeof *rep);
    if (out) memset(out, 0, sizeof *out);
    if (!path || !out) return sss_fail(err, SSS_ERR_ARG, "import: no path or no output mesh");

    const char *ext;
    file_format ff = format_of(path, &ext);
    if (ff == FMT_UNKNOWN) {
        if (!*ext)
            return sss_fail(err, SSS_ERR_FORMAT, "%s: no file extension (expected .ply, .obj, .off or .stl)", path);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: unknown extension '%s' (expected .ply, .obj, .off or .stl)", path, ext);
    }

    src s;
    expect ex;
    memset(&ex, 0, sizeof ex);
    sss_result r = src_open(&s, path, err);
    if (r == SSS_OK) {
        switch (ff) {
        case FMT_PLY: r = prepare_ply(&s, &ex, err); break;
        case FMT_OBJ: r = prepare_obj(&s, &ex, err); break;
        case FMT_OFF: r = prepare_off(&s, &ex, err); break;
        default: r = prepare_stl(&s, &ex, err); break;
        }
    }
    if (s.f) { fclose(s.f); s.f = NULL; }

    sss_om_soup soup;
    memset(&soup, 0, sizeof soup);
    if (r == SSS_OK) {
        char msg[400];
        sss_om_status st = sss_om_read(ex.om_data, ex.om_len, ex.fmt, &soup, msg, sizeof msg);
        if (st == SSS_OM_NO_MEMORY) r = sss_fail(err, SSS_ERR_NOMEM, "%s: %s", path, msg);
        else if (st != SSS_OM_OK) r = sss_fail(err, SSS_ERR_FORMAT, "%s: %s", path, msg);
    }
    /* The memory copy of the file is not needed any more. */
    free(s.mem);
    s.mem = NULL;

    if (r == SSS_OK) {
        /* The reader must deliver what the scan predicted. */
        if (ex.nv != ULLONG_MAX ? soup.nv != ex.nv : soup.nv > ex.nv_max)
            r = sss_fail(err, SSS_ERR_FORMAT, "%s: the reader delivered %llu vertices, the file has %llu", path,
                         (ull)soup.nv, ex.nv != ULLONG_MAX ? ex.nv : ex.nv_max);
        else if (ex.nf != ULLONG_MAX ? soup.nf != ex.nf : soup.nf > ex.nf_max)
            r = sss_fail(err, SSS_ERR_FORMAT, "%s: the reader delivered %llu faces, expected %llu", path, (ull)soup.nf,
                         ex.nf != ULLONG_MAX ? ex.nf : ex.nf_max);
    }
    if (r == SSS_OK) {
        /* STL: the reader merges equal corners and drops the triangles that
         * then use a vertex twice. */
        if (ex.nf == ULLONG_MAX) ex.repeated += ex.nf_max - soup.nf;
        r = build_mesh(path, &soup, &ex, out, rep, err);
    }
    sss_om_soup_free(&soup);
    free(ex.drop);
    free(ex.dpos);
    src_close(&s);
    if (r != SSS_OK) sss_mesh_free(out);
    return r;
}

uint64_t sss_import_repairs(const sss_import_report *rep)
{
    if (!rep) return 0;
    return rep->polygons_triangulated + rep->faces_too_small + rep->faces_repeated_index + rep->faces_zero_area +
           rep->vertices_unreferenced + rep->faces_duplicate + rep->faces_flipped + rep->open_faces_flipped +
           rep->recentred;
}

void sss_import_print_repairs(const sss_import_report *rep, const char *prefix, void *stream)
{
    if (!rep) return;
    FILE *f = stream ? (FILE *)stream : stderr;
    const char *sep = (prefix && *prefix) ? ": " : "";
    if (!prefix) prefix = "";
    struct { uint64_t n; const char *one, *many; } lines[] = {
        {rep->polygons_triangulated, "polygon with more than 3 vertices fan-triangulated",
         "polygons with more than 3 vertices fan-triangulated"},
        {rep->faces_too_small, "face with fewer than 3 vertices dropped", "faces with fewer than 3 vertices dropped"},
        {rep->faces_repeated_index, "face using a vertex more than once dropped",
         "faces using a vertex more than once dropped"},
        {rep->faces_zero_area, "zero-area triangle dropped", "zero-area triangles dropped"},
        {rep->vertices_unreferenced, "unreferenced vertex removed", "unreferenced vertices removed"},
        {rep->polygons_ear_clipped, "non-convex polygon ear-clipped in its plane instead (a fan would fold over)",
         "non-convex polygons ear-clipped in their plane instead (a fan would fold over)"},
        {rep->faces_duplicate, "triangle repeating an earlier one's vertices dropped",
         "triangles repeating an earlier one's vertices dropped"},
        {rep->faces_flipped, "triangle of a closed surface flipped to face outward consistently",
         "triangles of closed surfaces flipped to face outward consistently"},
        {rep->surfaces_inside_out, "closed surface was inside out as a whole", "closed surfaces were inside out as a whole"},
        {rep->open_faces_flipped, "triangle of an open surface flipped to agree with the majority of its surface",
         "triangles of open surfaces flipped to agree with the majority of their surface"},
    };
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++)
        if (lines[i].n)
            fprintf(f, "%s%srepaired: %llu %s\n", prefix, sep, (ull)lines[i].n, lines[i].n == 1 ? lines[i].one : lines[i].many);
    if (rep->recentred)
        fprintf(f, "%s%srepaired: mesh recentred: (%.17g, %.17g, %.17g) subtracted from every position, as its centre lies "
                "far from the origin for its size (float32 positions)\n", prefix, sep, rep->offset[0], rep->offset[1],
                rep->offset[2]);
}

void sss_import_print_warnings(const sss_import_report *rep, const char *prefix, void *stream)
{
    if (!rep) return;
    FILE *f = stream ? (FILE *)stream : stderr;
    const char *sep = (prefix && *prefix) ? ": " : "";
    if (!prefix) prefix = "";
    if (rep->polygons_unclipped)
        fprintf(f, "%s%swarning: %llu non-convex polygon%s could not be ear-clipped (self-intersecting, more than %d "
                "vertices, or past the import's ear-clipping budget) and %s fan-triangulated: some of %s triangles may overlap or face the wrong way\n", prefix, sep,
                (ull)rep->polygons_unclipped, rep->polygons_unclipped == 1 ? "" : "s", SSS_IMPORT_EAR_MAX,
                rep->polygons_unclipped == 1 ? "was" : "were", rep->polygons_unclipped == 1 ? "its" : "their");
    if (rep->orientation_conflicts)
        fprintf(f, "%s%swarning: %llu edge%s between triangles of opposite orientation could not be made consistent "
                "(a non-orientable surface such as a Moebius strip): normals there are unreliable\n", prefix, sep,
                (ull)rep->orientation_conflicts, rep->orientation_conflicts == 1 ? "" : "s");
}

/* ---------------------------------------------------------------------------
 * PLY export
 * ------------------------------------------------------------------------- */

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
