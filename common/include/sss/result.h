/* sss/result.h: result codes and error messages for every libsss call.
 *
 * Errors are values: a function returns sss_result and, when given a non-NULL
 * sss_error, writes one line (no trailing newline) naming the file and the
 * element at fault, e.g. "bunny.sss: section GEOM: size 12 too small for 40
 * vertices". Command-line tools print "TOOL: " followed by that line.
 */
#ifndef SSS_RESULT_H
#define SSS_RESULT_H

#include <signal.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sss_result {
    SSS_OK = 0,
    SSS_ERR_ARG,         /* invalid argument or option value */
    SSS_ERR_IO,          /* open/read/write/rename failed */
    SSS_ERR_NOMEM,       /* allocation failed or size would overflow */
    SSS_ERR_FORMAT,      /* not a file of the expected kind */
    SSS_ERR_VERSION,     /* a major version this build cannot read */
    SSS_ERR_CORRUPT,     /* checksum, size, offset or value check failed */
    SSS_ERR_MESH,        /* mesh content unusable (empty, NaN, bad index) */
    SSS_ERR_UNSUPPORTED, /* valid but not handled by this build */
    SSS_ERR_INTERRUPTED  /* stopped by its caller (a cancel flag) before completion */
} sss_result;

/* One line describing the failure; msg[0] == 0 when nothing was set. */
typedef struct sss_error {
    char msg[512];
} sss_error;

/* Static English name of a result code ("ok", "corrupt file", ...). */
const char *sss_result_string(sss_result r);

/* printf-style: writes the message into err (if err is non-NULL) and
 * returns r, so callers can write `return sss_fail(err, SSS_ERR_IO, ...)`. */
sss_result sss_fail(sss_error *err, sss_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Cancellation of long calls (the bake and its kernels; Embree's progress
 * monitor is the model): the caller owns a flag, may set it from a signal
 * handler or another thread, and passes a pointer to it; the call polls it
 * and returns SSS_ERR_INTERRUPTED soon after it becomes non-zero, having
 * written nothing it was asked to produce. NULL: never cancelled. */
typedef volatile sig_atomic_t sss_cancel_flag;
static inline int sss_cancelled(const sss_cancel_flag *cancel) { return cancel && *cancel; }

#ifdef __cplusplus
}
#endif
#endif
