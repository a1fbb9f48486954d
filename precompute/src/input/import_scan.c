/* import_scan.c: tokens and numbers as the mesh readers take them, and the
 * file in memory (input/import_internal.h). */
#define _POSIX_C_SOURCE 200809L

#include "input/import_internal.h"

#include <errno.h>
#include <math.h>
#include <unistd.h>

#include "sss/fileio.h"

/* Next whitespace-delimited token in [*pp, end); 0 at the end. */
int sss_scan_token(char **pp, char *end, tok *t)
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
ull sss_scan_line_of(const char *base, const char *p)
{
    ull line = 1;
    for (const char *q = base; q < p; q++)
        if (*q == '\n') line++;
    return line;
}


/* A float token as C++'s `stream >> float` reads it, whole token:
 * [+-] (digits [. digits] | . digits) [e [+-] digits]. NaN/Inf spellings and
 * values that overflow a float are NUM_NONFINITE (the stream would fail on
 * them); anything else is NUM_BAD. */
num_check sss_scan_float(tok t)
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
int sss_scan_int(tok t, sll *out)
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
int sss_scan_count(tok t, ull *out)
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


sss_result sss_src_open(src *s, const char *path, sss_error *err)
{
    memset(s, 0, sizeof *s);
    s->name = path;
    /* a regular file only, opened without blocking (sss/fileio.h) */
    int fd;
    uint64_t size;
    sss_result r = sss_input_open(path, &fd, &size, err);
    if (r != SSS_OK) return r;
    s->f = fdopen(fd, "rb");
    if (!s->f) {
        close(fd);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    if (size == 0) return sss_fail(err, SSS_ERR_FORMAT, "%s: file is empty", path);
    s->size = (ull)size;
    if (s->size > (ull)SIZE_MAX - SLACK - 2)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: file too large (%llu bytes)", path, s->size);
    return SSS_OK;
}

/* Makes the first n bytes of the file available at s->data (n <= size). */
sss_result sss_src_read(src *s, size_t n, sss_error *err)
{
    if (n <= s->have) return SSS_OK;
    char *m = realloc(s->mem, SLACK + s->skip + n + 1);
    if (!m) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %zu bytes", s->name, n);
    s->mem = m;
    s->data = m + SLACK + s->skip;
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

sss_result sss_src_read_all(src *s, sss_error *err) { return sss_src_read(s, (size_t)s->size, err); }

int sss_src_drop_bom(src *s)
{
    if (s->skip || s->have < 3 || memcmp(s->data, "\xEF\xBB\xBF", 3) != 0) return 0;
    s->skip = 3;
    s->data += 3;
    s->have -= 3;
    s->size -= 3;
    return 1;
}

void sss_src_close(src *s)
{
    if (s->f) fclose(s->f);
    free(s->mem);
    memset(s, 0, sizeof *s);
}

/* Writes hdr so that it ends at data + at; returns where it starts, or NULL
 * if there is not enough room in front. */
char *sss_src_put_header(src *s, size_t at, const char *hdr, size_t len)
{
    if (len > SLACK + at) return NULL;
    char *start = s->data + at - len;
    memcpy(start, hdr, len);
    return start;
}


/* Room for the double positions of nv vertices (NULL with an error set). */
double *sss_src_alloc_dpos(const src *s, ull nv, sss_error *err)
{
    if (nv > (ull)SIZE_MAX / 24 - 1) {
        sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", s->name, nv);
        return NULL;
    }
    double *d = malloc((size_t)nv * 3 * sizeof(double) + 1);
    if (!d) sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu vertices", s->name, nv);
    return d;
}


/* ---------------------------------------------------------------------------
 * Line iteration for OBJ and ascii STL: lines split at '\n', trimmed of
 * " \t\r" like the readers do.
 * ------------------------------------------------------------------------- */


/* Next line as [*b, *e) trimmed; 0 at the end. */
int sss_scan_line(line_it *it, char **b, char **e)
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

static int cmp_sll(const void *a, const void *b)
{
    sll x = *(const sll *)a, y = *(const sll *)b;
    return (x > y) - (x < y);
}

/* Number of distinct values in v[0..n); sorts v when n is large. */
size_t sss_count_distinct(sll *v, size_t n)
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
