#define _POSIX_C_SOURCE 200809L
/* The environment probe reader (precompute/src/input/probe.c;
 * docs/robustness.md items 1, 6, 7): every channel layout and pixel type
 * HDR tools write, half-float RGBA first (it crashed: the alpha channel had
 * no destination); a FIFO refused at once; a probe whose pixels would not
 * fit the memory limit refused before anything of its size is allocated. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <unistd.h>

#include "sss/probe.h"
#include "test_exr.h"

static char dir[128];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/sss_test_probe_XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Writes w x h of chans (half or float), reads it back, and checks every
 * pixel's R, G, B against what was written (a missing G or B is R; Y alone
 * is grey; any other channel is dropped). */
static void roundtrip(int half, const char *chans, int zip)
{
    char path[256];
    snprintf(path, sizeof path, "%s/p_%s_%s%s.exr", dir, half ? "half" : "float", chans, zip ? "_zip" : "");
    const int w = 37, h = 19;
    assert_int_equal(test_exr_write(path, w, h, half, chans, 0.75f, zip), 0);
    sss_probe p;
    sss_error err = {{0}};
    if (sss_probe_read(path, &p, &err) != SSS_OK) fail_msg("%s %s: %s", half ? "half" : "float", chans, err.msg);
    assert_int_equal(p.w, w);
    assert_int_equal(p.h, h);
    const char *r = strchr(chans, 'R') ? strchr(chans, 'R') : strchr(chans, 'Y');
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            for (int k = 0; k < 3; k++) {
                const char *c = strchr(chans, "RGB"[k]);
                if (!c) c = r; /* copied from R (or Y) */
                const float want = test_exr_value(0.75f, x, y, (int)(c - chans));
                const float got = p.rgb[3 * ((size_t)y * w + x) + k];
                if (fabsf(got - want) > (half ? 1e-3f * want : 0.0f))
                    fail_msg("%s %s: pixel (%d, %d) channel %d is %g, wrote %g", half ? "half" : "float", chans, x, y,
                             k, (double)got, (double)want);
            }
    sss_probe_free(&p);
}

static void probeReadsHalfRgbaAndEveryOtherLayout(void **state)
{
    (void)state;
    /* what most HDR tools write: half RGBA (a segfault before) */
    roundtrip(1, "RGBA", 0);
    roundtrip(1, "RGBA", 1);
    roundtrip(0, "RGBA", 0);
    roundtrip(1, "RGB", 0);
    roundtrip(0, "RGB", 1);
    roundtrip(1, "Y", 0);
    roundtrip(0, "YA", 0);
    roundtrip(1, "ABGRZ", 0); /* two channels beside R, G, B */
    roundtrip(1, "R", 0);
}

static void probeRefusesFifoWithoutBlocking(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "%s/fifo.exr", dir);
    assert_int_equal(mkfifo(path, 0600), 0);
    /* a blocking open would wait for a writer forever: alarm as the
     * failure, 10 s (the refusal takes microseconds) */
    alarm(10);
    sss_probe p;
    sss_error err = {{0}};
    assert_int_not_equal(sss_probe_read(path, &p, &err), SSS_OK);
    alarm(0);
    assert_non_null(strstr(err.msg, "fifo.exr: not a regular file (a FIFO)"));
}

static void probeBeyondMemoryLimitRefusedBeforeAllocating(void **state)
{
    (void)state;
    char path[256];
    snprintf(path, sizeof path, "%s/big.exr", dir);
    /* 8192 x 4096 half Y, ZIP: a small file whose pixels need 384 MiB as floats */
    assert_int_equal(test_exr_write(path, 8192, 4096, 1, "Y", 1.0f, 1), 0);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    assert_true(st.st_size < (32 << 20));
    sss_probe p;
    sss_error err = {{0}};
    assert_int_equal(sss_probe_read_limited(path, (uint64_t)64 << 20, &p, &err), SSS_ERR_NOMEM);
    assert_non_null(strstr(err.msg, "big.exr: the probe needs at least 0.38 GiB for 8192 x 4096 pixels but 0.06 GiB is "
                                    "available (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the limit)"));
    assert_null(p.rgb);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(probeReadsHalfRgbaAndEveryOtherLayout),
        cmocka_unit_test(probeRefusesFifoWithoutBlocking),
        cmocka_unit_test(probeBeyondMemoryLimitRefusedBeforeAllocating),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
