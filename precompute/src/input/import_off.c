/* import_off.c: the OFF scanner (ascii; the header becomes plain
 * "OFF\nNV NF 0"; input/import_internal.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

/* Like next_tok, but a token starting with '#' begins a comment: the rest of
 * its line is blanked (the reader does not know comments) and skipped. */
static int off_tok(char **pp, char *end, tok *t)
{
    for (;;) {
        if (!sss_scan_token(pp, end, t)) return 0;
        if (t->s[0] != '#') return 1;
        char *q = t->s;
        while (q < end && *q != '\n') *q++ = ' ';
        *pp = q;
    }
}

sss_result sss_scan_off(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = sss_src_read(s, n, err);
    if (r != SSS_OK) return r;
    if (sss_src_drop_bom(s)) n -= 3;
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
        if (!sss_scan_count(t, &cnt[k]))
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

    r = sss_src_read_all(s, err);
    if (r != SSS_OK) return r;
    if (!(ex->dpos = sss_src_alloc_dpos(s, nv, err))) return SSS_ERR_NOMEM;
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
                            sss_scan_line_of(base, q));
        }
    }
    for (ull v = 0; v < nv; v++) {
        for (int k = 0; k < 3; k++) {
            if (!off_tok(&p, end, &t))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: element vertex: file ends inside vertex %llu of %llu (truncated)",
                                s->name, v, nv);
            num_check c = sss_scan_float(t);
            if (c == NUM_NONFINITE)
                return sss_fail(err, SSS_ERR_MESH, "%s: vertex %llu: coordinate is not finite ('" TOKF "', line %llu)",
                                s->name, v, TOKA(t), sss_scan_line_of(base, t.s));
            if (c == NUM_BAD)
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: vertex %llu: '" TOKF "' is not a number (line %llu)", s->name, v,
                                TOKA(t), sss_scan_line_of(base, t.s));
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
        if (!sss_scan_int(t, &k) || k < 0)
            return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: bad vertex count '" TOKF "' (line %llu)", s->name, f,
                            TOKA(t), sss_scan_line_of(base, t.s));
        for (sll j = 0; j < k; j++) {
            sll v;
            if (!off_tok(&p, end, &t))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: element face: file ends inside face %llu of %llu (truncated)",
                                s->name, f, nf);
            if (!sss_scan_int(t, &v))
                return sss_fail(err, SSS_ERR_CORRUPT, "%s: face %llu: '" TOKF "' is not a vertex index (line %llu)", s->name,
                                f, TOKA(t), sss_scan_line_of(base, t.s));
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
    char *start = sss_src_put_header(s, body, hdr, (size_t)hl);
    if (!start) return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: header too large to rewrite", s->name);
    ex->fmt = SSS_OM_OFF;
    ex->om_data = start;
    ex->om_len = (size_t)(p - start);
    ex->nv = nv;
    ex->nf = nf;
    ex->faces_in_file = nf;
    return SSS_OK;
}
