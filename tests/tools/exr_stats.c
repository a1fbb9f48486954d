/* exr_stats: numbers from the linear float images sss-view writes as .exr,
 * for the tests of summed lights (tests/integration/view_lights.sh). The
 * EXR is read with the probe reader (sss/probe.h), which takes an image of
 * any size as long as its pixels are finite and >= 0.
 *
 *   sss-exrstats A.exr B.exr
 *     prints "DIFF MEAN_A MEAN_B": the largest absolute difference of a
 *     sample, relative to the largest sample of either image, and the mean
 *     sample of each.
 *   sss-exrstats A.exr B.exr SUM.exr
 *     prints "DIFF": the largest |A + B - SUM| of a sample, relative to the
 *     largest sample of SUM: how far SUM is from the sum of A and B.
 *
 * Exit status 1 (one line on stderr) when an image cannot be read or the
 * sizes differ. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sss/probe.h"

static int load(const char *path, sss_probe *p)
{
    sss_error err = {{0}};
    if (sss_probe_read(path, p, &err) != SSS_OK) {
        fprintf(stderr, "sss-exrstats: %s\n", err.msg);
        return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 4) {
        fprintf(stderr, "usage: sss-exrstats A.exr B.exr [SUM.exr]\n");
        return 2;
    }
    sss_probe im[3];
    memset(im, 0, sizeof im);
    const int n = argc - 1;
    int ok = 1;
    for (int k = 0; k < n && ok; k++) ok = load(argv[k + 1], &im[k]);
    for (int k = 1; k < n && ok; k++)
        if (im[k].w != im[0].w || im[k].h != im[0].h) {
            fprintf(stderr, "sss-exrstats: %s: %ux%u, not the %ux%u of %s\n", argv[k + 1], im[k].w, im[k].h, im[0].w,
                    im[0].h, argv[1]);
            ok = 0;
        }
    if (ok) {
        const size_t ns = 3 * (size_t)im[0].w * im[0].h;
        double diff = 0, peak = 0, mean[2] = {0, 0};
        for (size_t i = 0; i < ns; i++) {
            const double a = im[0].rgb[i], b = im[1].rgb[i];
            if (n == 3) {
                const double s = im[2].rgb[i];
                diff = fmax(diff, fabs(a + b - s));
                peak = fmax(peak, s);
            } else {
                diff = fmax(diff, fabs(a - b));
                peak = fmax(peak, fmax(a, b));
                mean[0] += a;
                mean[1] += b;
            }
        }
        const double rel = peak > 0 ? diff / peak : diff;
        if (n == 3) printf("%.3e\n", rel);
        else printf("%.3e %.6g %.6g\n", rel, mean[0] / (double)ns, mean[1] / (double)ns);
    }
    for (int k = 0; k < n; k++) sss_probe_free(&im[k]);
    return ok ? 0 : 1;
}
