/* import_internal.h (internal): what the format scanners of the importer
 * share (sss/import.h has the policy, import.c the pipeline): tokens and
 * numbers as the readers take them, the file in memory, what the reader
 * must deliver, and the steps after the reader (repair.c, orient.c).
 *
 * A format is one scanner file plus one row of the table in import.c: its
 * scanner reads the header, checks the declared counts against the file's
 * size before anything large is allocated, then scans the whole file,
 * rejecting with the element named what OpenMesh's reader would misread
 * and rewriting into canonical bytes what it would misread although valid,
 * and fills `expect` with the exact counts the reader must deliver.
 */
#ifndef SSS_IMPORT_INTERNAL_H
#define SSS_IMPORT_INTERNAL_H

#include <limits.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input/import_assimp.h"
#include "input/import_openmesh.h"
#include "sss/import.h"

#define HEADER_MAX ((size_t)1 << 20) /* a PLY/OFF header must end within this */
#define SLACK ((size_t)16384)        /* room before the data for a rewritten header */

typedef unsigned long long ull;
typedef long long sll;

/* ---- tokens and numbers (import_scan.c) ------------------------------ */

static inline int is_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

static inline int is_digit(char c) { return c >= '0' && c <= '9'; }

static inline char lower(char c) { return (c >= 'A' && c <= 'Z') ? (char)(c - 'A' + 'a') : c; }

typedef struct tok {
    char *s;
    size_t n;
} tok;

/* Case-sensitive / case-insensitive comparison of a token with a C string. */
static inline int tok_is(tok t, const char *w)
{
    size_t n = strlen(w);
    return t.n == n && memcmp(t.s, w, n) == 0;
}

static inline int tok_is_ci(tok t, const char *w)
{
    size_t n = strlen(w);
    if (t.n != n) return 0;
    for (size_t i = 0; i < n; i++)
        if (lower(t.s[i]) != lower(w[i])) return 0;
    return 1;
}

/* Saturating a*b+c for size checks. */
static inline ull sat_mul(ull a, ull b)
{
    if (a != 0 && b > ULLONG_MAX / a) return ULLONG_MAX;
    return a * b;
}

static inline ull sat_add(ull a, ull b) { return a > ULLONG_MAX - b ? ULLONG_MAX : a + b; }

/* Token shown in a message: at most 32 characters. */
#define TOKF "%.*s%s"
#define TOKA(t) (int)((t).n > 32 ? 32 : (t).n), (t).s, ((t).n > 32 ? "..." : "")

typedef enum { NUM_OK, NUM_NONFINITE, NUM_BAD } num_check;

/* Unsigned integer of n bytes, little- or big-endian (be). */
static inline ull rd_uint(const unsigned char *b, size_t n, int be)
{
    ull v = 0;
    for (size_t i = 0; i < n; i++) v |= (ull)b[be ? n - 1 - i : i] << (8 * i);
    return v;
}


/* Next whitespace-delimited token in [*pp, end); 0 at the end. */
int sss_scan_token(char **pp, char *end, tok *t);
/* 1-based line number of position p in [base, ...). Only used for errors. */
ull sss_scan_line_of(const char *base, const char *p);
/* A float token as C++'s `stream >> float` reads it (import_scan.c). */
num_check sss_scan_float(tok t);
/* An integer token [+-]digits. The value saturates at +-2^62. */
int sss_scan_int(tok t, sll *out);
/* Unsigned decimal count (digits only). */
int sss_scan_count(tok t, ull *out);
/* Number of distinct values in v[0..n); sorts v when n is large. */
size_t sss_count_distinct(sll *v, size_t n);

/* ---- the file in memory (import_scan.c) ------------------------------ */

typedef struct src {
    const char *name; /* path as given, for messages */
    FILE *f;
    ull size;
    char *mem;        /* SLACK bytes, then the file, then one spare byte */
    char *data;       /* mem + SLACK + skip */
    size_t have;      /* bytes of the file read so far (after the skipped ones) */
    size_t skip;      /* bytes dropped at the start: a UTF-8 byte-order mark (sss_src_drop_bom) */
} src;

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
    /* PLY (properties u v, s t or texture_u texture_v) and OBJ (vt, the
     * first corner's of each vertex): 2 per vertex in the reader's vertex
     * order, or NULL; handed to the soup (sss_om_soup.uv) after the read */
    float *uv;
    /* OBJ: statements the specification does not know (sss_import_report) */
    ull unknown;
    char first_unknown[36];
    ull first_unknown_line;
    /* glTF (import_gltf.c): om_data is this malloc'd canonical GLB, freed
     * with the rest; primitives of points or lines skipped; whether some
     * triangle primitive has TEXCOORD_0 / COLOR_0 */
    char *own;
    ull skipped;
    int texcoords, colours;
    /* glTF skinning (docs/deformable.md §5): in, pose = 1 asks for the
     * skinned meshes posed at pose_t by the file's first clip; out,
     * animated = 1 when a skinned mesh was posed, and the clip's times */
    int pose;
    double pose_t;
    int animated;
    double clip_t0, clip_t1;
} expect;

sss_result sss_src_open(src *s, const char *path, sss_error *err);
/* Makes the first n bytes of the file available at s->data (n <= size). */
sss_result sss_src_read(src *s, size_t n, sss_error *err);
sss_result sss_src_read_all(src *s, sss_error *err);
/* Text formats: a UTF-8 byte-order mark (EF BB BF) at the start of the file
 * is not part of the first token (an OBJ's first "v" would become an unknown
 * statement and every face index would shift by one), so it is dropped:
 * s->data then starts after it and s->size counts the bytes after it. Needs
 * the first 3 bytes read (or the whole file when it is shorter); returns 1
 * when a mark was dropped. */
int sss_src_drop_bom(src *s);
void sss_src_close(src *s);
/* Writes hdr so that it ends at data + at; returns where it starts, or NULL
 * if there is not enough room in front. */
char *sss_src_put_header(src *s, size_t at, const char *hdr, size_t len);
/* Room for the double positions of nv vertices (NULL with an error set). */
double *sss_src_alloc_dpos(const src *s, ull nv, sss_error *err);

/* A token sss_scan_float accepted, as a double. The file's bytes are followed by
 * whitespace or the terminating NUL (sss_src_read), so strtod stops at the
 * token's end. */
static inline double tok_double(tok t) { return strtod(t.s, NULL); }

/* Lines for OBJ and ascii STL: split at '\n', trimmed of " \t\r" like the
 * readers do. */
typedef struct line_it {
    char *p, *end;
    ull no;
} line_it;
/* Next line as [*b, *e) trimmed; 0 at the end. */
int sss_scan_line(line_it *it, char **b, char **e);

/* ---- the scanners, one file per format ------------------------------- */

sss_result sss_scan_ply(src *s, expect *ex, sss_error *err); /* import_ply.c */
sss_result sss_scan_off(src *s, expect *ex, sss_error *err); /* import_off.c */
sss_result sss_scan_obj(src *s, expect *ex, sss_error *err); /* import_obj.c */
sss_result sss_scan_stl(src *s, expect *ex, sss_error *err); /* import_stl.c */
sss_result sss_scan_gltf(src *s, expect *ex, sss_error *err); /* import_gltf.c, .gltf and .glb */

/* ---- after the reader ------------------------------------------------ */

/* The reader's polygon soup checked and repaired into out (repair.c). */
sss_result sss_soup_to_mesh(const char *name, sss_om_soup *s, const expect *ex, sss_mesh *out,
                            sss_import_report *rep, sss_error *err);
/* Consistent, outward winding (orient.c, docs/robustness.md B5). */
sss_result sss_orient(const char *name, sss_mesh *m, sss_import_report *rep, sss_error *err);

#endif
