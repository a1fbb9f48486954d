/* result.c: result code names and the one-line error formatter. */
#include "sss/result.h"

#include <stdarg.h>
#include <stdio.h>

const char *sss_result_string(sss_result r)
{
    switch (r) {
    case SSS_OK: return "ok";
    case SSS_ERR_ARG: return "invalid argument";
    case SSS_ERR_IO: return "input/output error";
    case SSS_ERR_NOMEM: return "out of memory";
    case SSS_ERR_FORMAT: return "unrecognised format";
    case SSS_ERR_VERSION: return "unsupported version";
    case SSS_ERR_CORRUPT: return "corrupt file";
    case SSS_ERR_MESH: return "unusable mesh";
    case SSS_ERR_UNSUPPORTED: return "unsupported";
    case SSS_ERR_INTERRUPTED: return "interrupted";
    }
    return "unknown error";
}

sss_result sss_fail(sss_error *err, sss_result r, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->msg, sizeof err->msg, fmt, ap);
        va_end(ap);
        /* one line, by construction (README.md, "Errors"): a file name or a
         * key from a file holding a newline, an escape sequence or any
         * other control character is shown with '?' there */
        for (char *q = err->msg; *q; q++)
            if ((unsigned char)*q < 0x20 || *q == 0x7f) *q = '?';
    }
    return r;
}
