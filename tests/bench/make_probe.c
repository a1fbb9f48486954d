/* make_probe: writes a small analytic OpenEXR lat-long sky probe for the
 * scene benchmarks (docs/scenes.md): a blue sky dome, a bright sun lobe
 * and a dark ground. usage: make_probe OUT.exr [W H] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "sss/probe.h"

int main(int argc, char **argv)
{
    if (argc != 2 && argc != 4) {
        fprintf(stderr, "usage: make_probe OUT.exr [W H]\n");
        return 2;
    }
    sss_probe p = {argc == 4 ? (uint32_t)atoi(argv[2]) : 128, argc == 4 ? (uint32_t)atoi(argv[3]) : 64, NULL};
    if (p.w < 2 || p.h < 1 || p.w > 8192 || p.h > 8192) return 2;
    p.rgb = malloc(3 * (size_t)p.w * p.h * sizeof(float));
    if (!p.rgb) return 1;
    const double sun[3] = {0.48, 0.36, 0.8};
    for (uint32_t y = 0; y < p.h; y++)
        for (uint32_t x = 0; x < p.w; x++) {
            double d[3], dw;
            sss_probe_pixel_dir(p.w, p.h, x, y, d, &dw);
            const double up = d[2] > 0 ? d[2] : 0, c = d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2];
            const double lobe = c > 0 ? 8.0 * pow(c, 32) : 0;
            const double rgb[3] = {0.3 * up + 0.05 + lobe, 0.45 * up + 0.05 + lobe, 0.8 * up + 0.05 + 0.9 * lobe};
            for (int k = 0; k < 3; k++) p.rgb[3 * ((size_t)y * p.w + x) + k] = (float)rgb[k];
        }
    sss_error err = {{0}};
    int rc = sss_probe_write(argv[1], &p, &err) == SSS_OK ? 0 : 1;
    if (rc) fprintf(stderr, "make_probe: %s\n", err.msg);
    free(p.rgb);
    return rc;
}
