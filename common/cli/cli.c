/* cli.c: the tools' table-driven option parser (sss/cli.h). Every reading
 * and every message here is the one the tools printed before they shared
 * it, so a tool that moves onto a table keeps its output byte for byte. */
#include "sss/cli.h"

#include <errno.h>
#include <stdarg.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

static FILE *err_of(const sss_cli *cli) { return cli->err ? cli->err : stderr; }

/* Control characters (C0 and DEL) as '?', except a last '\n'. */
static void one_line(char *s, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        const unsigned char c = (unsigned char)s[i];
        if ((c < 0x20 || c == 0x7f) && !(c == '\n' && i + 1 == n)) s[i] = '?';
    }
}

static int vprint_line(FILE *f, const char *fmt, va_list ap)
{
    va_list aq;
    va_copy(aq, ap);
    char small[1024];
    const int n = vsnprintf(small, sizeof small, fmt, aq);
    va_end(aq);
    if (n < 0) return n;
    char *buf = (size_t)n < sizeof small ? small : malloc((size_t)n + 1);
    if (!buf) return -1;
    if (buf != small) vsnprintf(buf, (size_t)n + 1, fmt, ap);
    one_line(buf, (size_t)n);
    fputs(buf, f);
    if (buf != small) free(buf);
    return n;
}

int sss_cli_printf(FILE *f, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    const int n = vprint_line(f, fmt, ap);
    va_end(ap);
    return n;
}

char *sss_cli_shown(const char *s, char *buf, size_t n)
{
    if (!n) return buf;
    snprintf(buf, n, "%s", s ? s : "");
    for (char *q = buf; *q; q++) /* a last newline of s too: it is inside a line */
        if ((unsigned char)*q < 0x20 || *q == 0x7f) *q = '?';
    return buf;
}
static FILE *out_of(const sss_cli *cli) { return cli->out ? cli->out : stdout; }

static const char *default_msg(sss_cli_kind kind)
{
    switch (kind) {
    case SSS_CLI_DOUBLE: return "%s: %s: '%s' must be a number in [%g, %g]\n";
    case SSS_CLI_U32: return "%s: %s: '%s' must be an integer in [%u, %u]\n";
    case SSS_CLI_INT: return "%s: %s: '%s' must be an integer in [%d, %d]\n";
    case SSS_CLI_TRIPLE: return "%s: %s: '%s' must be three numbers X,Y,Z\n";
    case SSS_CLI_SIZE: return "%s: %s: '%s' must be WxH with each in [%d, %d]\n";
    case SSS_CLI_POINT: return "%s: %s: '%s' must be X,Y,Z or X,Y,Z,I with I > 0\n";
    default: return "%s: %s: '%s' is not a valid value\n";
    }
}

/* "%s: %s: '%s' must be A, B or C\n": the wording of every enumeration
 * sss-bake and sss-view print. */
static void print_choices(FILE *e, const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    sss_cli_printf(e, "%s: %s: '%s' must be ", cli->tool, opt, text);
    size_t n = 0;
    while (o->choices && o->choices[n]) n++;
    for (size_t k = 0; k < n; k++)
        fprintf(e, "%s%s", k == 0 ? "" : k + 1 == n ? " or " : ", ", o->choices[k]);
    fputc('\n', e);
}

int sss_cli_fail(const sss_cli *cli, const sss_cli_opt *o, const char *fmt, const char *opt, const char *text)
{
    FILE *e = err_of(cli);
    if (!fmt && o->kind == SSS_CLI_CHOICE) {
        print_choices(e, cli, o, opt, text);
        return SSS_CLI_PRINTED;
    }
    if (!fmt) fmt = default_msg(o->kind);
    /* the range in the type its conversions name (sss/cli.h) */
    switch (o->kind) {
    case SSS_CLI_U32: sss_cli_printf(e, fmt, cli->tool, opt, text, (unsigned)o->lo, (unsigned)o->hi); break;
    case SSS_CLI_INT:
    case SSS_CLI_SIZE: sss_cli_printf(e, fmt, cli->tool, opt, text, (int)o->lo, (int)o->hi); break;
    default: sss_cli_printf(e, fmt, cli->tool, opt, text, o->lo, o->hi); break;
    }
    return SSS_CLI_PRINTED;
}

/* A bad value: its message, and sss_cli_value's 0. */
static int bad(const sss_cli *cli, const sss_cli_opt *o, const char *fmt, const char *opt, const char *text)
{
    sss_cli_fail(cli, o, fmt, opt, text);
    return 0;
}

/* A number as strtod reads it; strict: the whole text, errno clear, finite
 * (how sss-bake, sss-stat and sss-view have read their numbers); lax: see
 * SSS_CLI_LAX. */
static int read_double(const char *s, unsigned flags, double lo, double hi, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    const int in_range = (flags & SSS_CLI_ABOVE_LO ? v > lo : v >= lo) && v <= hi; /* false for NaN */
    if (flags & SSS_CLI_LAX) {
        if (*end || !in_range) return 0;
    } else if (end == s || *end || errno || !isfinite(v) || !in_range) {
        return 0;
    }
    *out = v;
    return 1;
}

/* An integer; strict: strtoull's digits without a leading '-' (which
 * strtoull would negate), errno clear; lax: strtoll alone. */
static int read_integer(const char *s, unsigned flags, double lo, double hi, long long *out)
{
    char *end;
    if (flags & SSS_CLI_LAX) {
        long long v = strtoll(s, &end, 10);
        if (*end || (double)v < lo || (double)v > hi) return 0;
        *out = v;
        return 1;
    }
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (end == s || *end || errno || s[0] == '-' || v < (unsigned long long)lo || v > (unsigned long long)hi)
        return 0;
    *out = (long long)v;
    return 1;
}

/* "X,Y,Z": each number strict, exactly one comma between them. With
 * maxn 4 a fourth number may follow a third comma. Returns how many
 * numbers were read (3 or 4), 0 on a bad text. */
static int read_numbers(const char *s, int maxn, double out[4])
{
    double t[4];
    const char *p = s;
    for (int k = 0; k < maxn; k++) {
        char *end;
        errno = 0;
        t[k] = strtod(p, &end);
        if (end == p || errno || !isfinite(t[k])) return 0;
        if (*end == 0 && k >= 2) {
            memcpy(out, t, (size_t)(k + 1) * sizeof *t);
            return k + 1;
        }
        if (*end != ',') return 0;
        p = end + 1;
    }
    return 0;
}

static int read_triple(const char *s, double out[3])
{
    double t[4];
    if (read_numbers(s, 3, t) != 3) return 0;
    memcpy(out, t, 3 * sizeof *t);
    return 1;
}

/* "WxH" as sss-view's --size has read it (sscanf's "%dx%d": blanks before W
 * and before H pass, and nothing may follow H), read with strtol so that a
 * number beyond int is refused instead of wrapping modulo 2^32 (sscanf's
 * %d overflow is undefined; glibc wraps 4294967396 to 100). */
static int read_size(const char *s, double lo, double hi, int out[2])
{
    long v[2];
    const char *p = s;
    for (int k = 0; k < 2; k++) {
        char *end;
        errno = 0;
        v[k] = strtol(p, &end, 10);
        if (end == p || errno || (k == 0 ? *end != 'x' : *end != 0) || v[k] < lo || v[k] > hi) return 0;
        p = end + 1;
    }
    out[0] = (int)v[0];
    out[1] = (int)v[1];
    return 1;
}

int sss_cli_value(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    switch (o->kind) {
    case SSS_CLI_FLAG:
        if (o->dest) *(int *)o->dest = o->values ? o->values[0] : 1;
        break;
    case SSS_CLI_STRING:
        if (o->dest) *(const char **)o->dest = text;
        break;
    case SSS_CLI_DOUBLE: {
        double v;
        if (!read_double(text, o->flags, o->lo, o->hi, &v)) return bad(cli, o, o->msg, opt, text);
        *(double *)o->dest = v;
        break;
    }
    case SSS_CLI_U32:
    case SSS_CLI_INT: {
        long long v;
        if (!read_integer(text, o->flags, o->lo, o->hi, &v)) return bad(cli, o, o->msg, opt, text);
        if (o->kind == SSS_CLI_U32) *(uint32_t *)o->dest = (uint32_t)v;
        else *(int *)o->dest = (int)v;
        break;
    }
    case SSS_CLI_TRIPLE: {
        double t[3];
        if (!read_triple(text, t)) return bad(cli, o, o->msg, opt, text);
        /* a direction: its length, squared, a positive normal number, so
         * that normalising it neither divides by 0 nor overflows (a huge
         * --light gave NaN pictures) */
        const double l2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
        if ((o->flags & SSS_CLI_NONZERO) && !(l2 >= DBL_MIN && l2 <= DBL_MAX))
            return bad(cli, o, o->msg2 ? o->msg2 : "%s: %s: '%s' is not a direction\n", opt, text);
        memcpy(o->dest, t, sizeof t);
        break;
    }
    case SSS_CLI_POINT: {
        double t[4] = {0, 0, 0, 0};
        const int n = read_numbers(text, 4, t);
        if (n == 0 || (n == 4 && !(t[3] > 0))) return bad(cli, o, o->msg, opt, text);
        memcpy(o->dest, t, sizeof t);
        break;
    }
    case SSS_CLI_SIZE:
        if (!read_size(text, o->lo, o->hi, (int *)o->dest)) return bad(cli, o, o->msg, opt, text);
        break;
    case SSS_CLI_CHOICE: {
        int k = 0;
        while (o->choices && o->choices[k] && strcmp(o->choices[k], text)) k++;
        if (!o->choices || !o->choices[k]) return bad(cli, o, o->msg, opt, text);
        *(int *)o->dest = o->values ? o->values[k] : k;
        break;
    }
    case SSS_CLI_CUSTOM: {
        const int r = o->parse(cli, o, opt, text);
        if (r == SSS_CLI_PRINTED) return 0;
        if (r != 1) return bad(cli, o, o->msg, opt, text);
        break;
    }
    }
    if (o->given) *o->given = 1;
    return 1;
}

static const sss_cli_opt *find_opt(const sss_cli *cli, const char *a)
{
    for (size_t k = 0; k < cli->nopts; k++) {
        const sss_cli_opt *o = &cli->opts[k];
        if ((o->name && !strcmp(a, o->name)) || (o->alias && !strcmp(a, o->alias))) return o;
    }
    return NULL;
}

static size_t elem_size(sss_cli_kind kind)
{
    switch (kind) {
    case SSS_CLI_STRING: return sizeof(const char *);
    case SSS_CLI_DOUBLE: return sizeof(double);
    case SSS_CLI_U32: return sizeof(uint32_t);
    case SSS_CLI_INT:
    case SSS_CLI_FLAG:
    case SSS_CLI_CHOICE: return sizeof(int);
    case SSS_CLI_TRIPLE: return 3 * sizeof(double);
    case SSS_CLI_SIZE: return 2 * sizeof(int);
    case SSS_CLI_POINT: return 4 * sizeof(double);
    case SSS_CLI_CUSTOM: return 0;
    }
    return 0;
}

/* Positional number k (from 0) into its row. */
static int read_positional(const sss_cli *cli, int k, const char *text)
{
    const size_t last = cli->npos - 1;
    const sss_cli_opt *p = &cli->pos[(size_t)k < last ? (size_t)k : last];
    sss_cli_opt r = *p;
    if ((size_t)k > last && r.dest) r.dest = (char *)r.dest + ((size_t)k - last) * elem_size(r.kind);
    return sss_cli_value(cli, &r, r.name, text);
}

/* One more value of a repeated option (SSS_CLI_REPEAT) into the next
 * element of its array, or its refusal beyond the row's max. */
static int read_repeated(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    if (!o->count || *o->count >= o->max) {
        sss_cli_printf(err_of(cli), "%s: %s: '%s': at most %d may be given\n", cli->tool, opt, text, o->max);
        return 0;
    }
    sss_cli_opt r = *o;
    r.dest = (char *)o->dest + (size_t)*o->count * elem_size(o->kind);
    if (!sss_cli_value(cli, &r, opt, text)) return 0;
    (*o->count)++;
    return 1;
}

/* Prints a count message, or the usage text on err when there is none. */
static void count_error(const sss_cli *cli, const char *fmt, const char *fallback, const char *arg)
{
    FILE *e = err_of(cli);
    if (fmt) sss_cli_printf(e, fmt, cli->tool, arg);
    else if (cli->usage) cli->usage(e);
    else sss_cli_printf(e, fallback, cli->tool, arg);
}

int sss_cli_parse(const sss_cli *cli, int argc, char *const argv[])
{
    const int options = !(cli->flags & SSS_CLI_NO_OPTIONS);
    const int repeats = cli->npos && (cli->pos[cli->npos - 1].flags & SSS_CLI_REPEAT);
    int max_pos = cli->max_pos ? cli->max_pos : (int)cli->npos;
    if (!repeats && max_pos > (int)cli->npos) max_pos = (int)cli->npos; /* more needs a row that repeats */
    int npos = 0;
    for (size_t k = 0; k < cli->nopts; k++)
        if ((cli->opts[k].flags & SSS_CLI_REPEAT) && cli->opts[k].count) *cli->opts[k].count = 0;
    /* the walk: options as they come, positionals counted */
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (options) {
            if (cli->usage && (!strcmp(a, "-h") || !strcmp(a, "--help"))) {
                cli->usage(out_of(cli));
                return 0;
            }
            const sss_cli_opt *o = find_opt(cli, a);
            if (o && o->kind == SSS_CLI_FLAG) {
                sss_cli_value(cli, o, a, NULL);
                continue;
            }
            if (o) {
                if (i + 1 >= argc || ((o->flags & SSS_CLI_NONEMPTY) && !argv[i + 1][0])) {
                    const char *fmt = o->need_msg ? o->need_msg : cli->need_msg ? cli->need_msg : "%s: %s needs a value\n";
                    sss_cli_printf(err_of(cli), fmt, cli->tool, a);
                    return 2;
                }
                if (!((o->flags & SSS_CLI_REPEAT) ? read_repeated(cli, o, a, argv[i + 1])
                                                  : sss_cli_value(cli, o, a, argv[i + 1])))
                    return 2;
                i++;
                continue;
            }
            if (a[0] == '-' && a[1]) {
                sss_cli_printf(err_of(cli), cli->unknown_msg ? cli->unknown_msg : "%s: unknown option '%s' (see --help)\n",
                        cli->tool, a);
                return 2;
            }
        }
        if (npos >= max_pos) {
            count_error(cli, cli->extra_msg, "%s: unexpected argument '%s'\n", a);
            return 2;
        }
        npos++;
    }
    if (npos < cli->min_pos) {
        count_error(cli, cli->missing_msg, "%s: missing argument (see --help)\n", NULL);
        return 2;
    }
    /* the positionals, now that their number is right; the walk skips the
     * options and their values exactly as above (it met no error there) */
    int k = 0;
    for (int i = 1; i < argc; i++) {
        if (options) {
            const sss_cli_opt *o = find_opt(cli, argv[i]);
            if (o) {
                if (o->kind != SSS_CLI_FLAG) i++;
                continue;
            }
        }
        if (!read_positional(cli, k++, argv[i])) return 2;
    }
    if (cli->npos_given) *cli->npos_given = npos;
    return SSS_CLI_RUN;
}

int sss_cli_parse_double(const char *tool, const char *opt, const char *s, double lo, double hi, double *out)
{
    const sss_cli cli = {.tool = tool};
    const sss_cli_opt o = {.kind = SSS_CLI_DOUBLE, .dest = out, .lo = lo, .hi = hi};
    return sss_cli_value(&cli, &o, opt, s);
}

int sss_cli_parse_u32(const char *tool, const char *opt, const char *s, uint32_t lo, uint32_t hi, uint32_t *out)
{
    const sss_cli cli = {.tool = tool};
    const sss_cli_opt o = {.kind = SSS_CLI_U32, .dest = out, .lo = lo, .hi = hi};
    return sss_cli_value(&cli, &o, opt, s);
}

int sss_cli_parse_triple(const char *tool, const char *opt, const char *s, double out[3])
{
    const sss_cli cli = {.tool = tool};
    const sss_cli_opt o = {.kind = SSS_CLI_TRIPLE, .dest = out};
    return sss_cli_value(&cli, &o, opt, s);
}

uint64_t sss_cli_memory_limit(void)
{
    const char *lim = getenv("SSS_MEMORY_LIMIT_MB");
    if (!lim || !*lim) return 0;
    char *end;
    errno = 0;
    unsigned long long mb = strtoull(lim, &end, 10);
    if (*end || errno || mb == 0 || mb > (UINT64_MAX >> 20)) return 0;
    return (uint64_t)mb << 20;
}

double sss_cli_peak_rss_mib(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

const char *sss_cli_basename(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}
