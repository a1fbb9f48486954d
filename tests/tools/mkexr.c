/* sss-mkexr: OpenEXR probes of any channel layout for the shell tests
 * (tests/test_exr.h writes them; docs/robustness.md items 1, 7, 8).
 *
 *   sss-mkexr OUT.exr W H half|float CHANNELS VALUE [zip]
 *
 * CHANNELS: one letter per channel ("RGBA", "Y", ...); pixel (x, y),
 * channel k holds test_exr_value(VALUE, x, y, k). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test_exr.h"

int main(int argc, char **argv)
{
    if (argc != 7 && argc != 8) {
        fprintf(stderr, "usage: sss-mkexr OUT.exr W H half|float CHANNELS VALUE [zip]\n");
        return 2;
    }
    const int w = atoi(argv[2]), h = atoi(argv[3]);
    if (w < 1 || h < 1 || w > 65536 || h > 65536) return 2;
    const int zip = argc == 8 && !strcmp(argv[7], "zip");
    if (test_exr_write(argv[1], w, h, !strcmp(argv[4], "half"), argv[5], (float)atof(argv[6]), zip) != 0) {
        fprintf(stderr, "sss-mkexr: %s: cannot write\n", argv[1]);
        return 1;
    }
    return 0;
}
