/* fuzz_probe.c: libFuzzer harness for the environment probe reader
 * (precompute/src/input/probe.c; docs/robustness.md items 1, 7). The input
 * is an OpenEXR file. sss_probe_read_limited must refuse it with one line
 * naming the file, or return a probe of the size it declares whose every
 * pixel is finite and >= 0; its SH projection (what the environment pass
 * stores) must then be finite. The reader reads a path (through the
 * shared input opener), so each input goes through a private file. A
 * memory limit of 256 MiB keeps a small file declaring a huge probe from
 * being allocated: the reader must refuse it, within -rss_limit_mb. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sss/probe.h"
#include "sss/sh.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char path[64];
    snprintf(path, sizeof path, "/tmp/sss-fuzz-probe-%ld.exr", (long)getpid());
    FILE *fp = fopen(path, "wb");
    if (!fp) return 0;
    if (size && fwrite(data, 1, size, fp) != size) {
        fclose(fp);
        unlink(path);
        return 0;
    }
    fclose(fp);
    sss_probe p;
    sss_error err = {{0}};
    sss_result r = sss_probe_read_limited(path, (uint64_t)256 << 20, &p, &err);
    unlink(path);
    if (r != SSS_OK) {
        if (!strstr(err.msg, path) || strchr(err.msg, '\n')) abort(); /* one line naming the file */
        if (p.rgb) abort();
        return 0;
    }
    if (p.w < 2 || p.h < 1 || !p.rgb) abort();
    for (size_t i = 0; i < 3 * (size_t)p.w * p.h; i++)
        if (!isfinite(p.rgb[i]) || p.rgb[i] < 0.0f) abort();
    /* order 2 keeps the work per input small; the sums are the pass's */
    double L[3 * SSS_SH_MAX_COUNT];
    sss_probe_sh(&p, 2, L);
    for (int i = 0; i < 3 * 4; i++)
        if (!isfinite(L[i])) abort();
    sss_probe_free(&p);
    return 0;
}
