/* import_stl.c: the STL scanner, ascii and binary (input/import_internal.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <math.h>

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

sss_result sss_scan_stl(src *s, expect *ex, sss_error *err)
{
    size_t n = s->size < HEADER_MAX ? (size_t)s->size : HEADER_MAX;
    sss_result r = sss_src_read(s, n, err);
    if (r != SSS_OK) return r;
    const unsigned char *u = (const unsigned char *)s->data;
    ull count = s->size >= 84 ? rd_uint(u + 80, 4, 0) : 0;
    int binary = s->size >= 84 && 84 + 50 * count == s->size;
    int ascii = 0;
    /* a binary STL's 80-byte header is any bytes; only ascii STL is text */
    if (!binary && sss_src_drop_bom(s)) n -= 3;
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
    r = sss_src_read_all(s, err);
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
        while (sss_scan_line(&it, &b, &e)) {
            tok w;
            char *q = b;
            if (!sss_scan_token(&q, e, &w)) continue;
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
                if (!sss_scan_line(&it, &b, &e) || (q = b, !sss_scan_token(&q, e, &w)) || !tok_is_ci(w, "vertex"))
                    return sss_fail(err, SSS_ERR_CORRUPT, "%s: triangle %llu: expected 'vertex x y z' on line %llu", s->name,
                                    ntri, it.no);
                for (int c = 0; c < 3; c++) {
                    tok t;
                    if (!sss_scan_token(&q, e, &t))
                        return sss_fail(err, SSS_ERR_CORRUPT, "%s: triangle %llu: vertex %d: fewer than 3 coordinates (line %llu)",
                                        s->name, ntri, k, it.no);
                    num_check ck = sss_scan_float(t);
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
