/* cli_util.c: option parsing and reporting shared by the command-line tools. */
#include "cli_util.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

int cli_parse_double(const char *tool, const char *opt, const char *s, double lo, double hi, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v) || v < lo || v > hi) {
        fprintf(stderr, "%s: %s: '%s' must be a number in [%g, %g]\n", tool, opt, s, lo, hi);
        return 0;
    }
    *out = v;
    return 1;
}

int cli_parse_u32(const char *tool, const char *opt, const char *s, uint32_t lo, uint32_t hi, uint32_t *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (end == s || *end || errno || s[0] == '-' || v < lo || v > hi) {
        fprintf(stderr, "%s: %s: '%s' must be an integer in [%u, %u]\n", tool, opt, s, lo, hi);
        return 0;
    }
    *out = (uint32_t)v;
    return 1;
}

int cli_parse_triple(const char *tool, const char *opt, const char *s, double out[3])
{
    const char *p = s;
    for (int k = 0; k < 3; k++) {
        char *end;
        errno = 0;
        out[k] = strtod(p, &end);
        if (end == p || errno || !isfinite(out[k]) || (k < 2 ? *end != ',' : *end != 0)) {
            fprintf(stderr, "%s: %s: '%s' must be three numbers X,Y,Z\n", tool, opt, s);
            return 0;
        }
        p = end + 1;
    }
    return 1;
}

double cli_peak_rss_mib(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0) return 0.0;
    return (double)ru.ru_maxrss / 1024.0; /* Linux reports KiB */
}

const char *cli_basename(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? s + 1 : path;
}
