/* cli_util.h: shared option parsing and reporting for sss-bake and sss-stat. */
#ifndef SSS_CLI_UTIL_H
#define SSS_CLI_UTIL_H

#include <stdint.h>

/* Each parser returns 1 on success, 0 (after printing
 * "TOOL: OPTION: 'TEXT' ..." on stderr) on failure. */
int cli_parse_double(const char *tool, const char *opt, const char *s, double lo, double hi, double *out);
int cli_parse_u32(const char *tool, const char *opt, const char *s, uint32_t lo, uint32_t hi, uint32_t *out);
int cli_parse_triple(const char *tool, const char *opt, const char *s, double out[3]);

/* Peak resident memory of this process in MiB (getrusage). */
double cli_peak_rss_mib(void);

/* Basename of a path (pointer into it). */
const char *cli_basename(const char *path);

#endif
