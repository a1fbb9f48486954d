/* A program outside the source tree that uses the installed libsss
 * (docs/install.md): reads a .sss file, decodes q(x_v, ω) for one light with
 * sss_decode_all and prints one vertex's values and a checksum of all.
 * Usage: consumer FILE.sss X,Y,Z VERTEX */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "sss/decode.h"
#include "sss/format.h"

int main(int argc, char **argv)
{
    double light[3];
    if (argc != 4 || sscanf(argv[2], "%lf,%lf,%lf", &light[0], &light[1], &light[2]) != 3) {
        fprintf(stderr, "usage: consumer FILE.sss X,Y,Z VERTEX\n");
        return 2;
    }
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) {
        fprintf(stderr, "consumer: %s\n", err.msg);
        return 1;
    }
    const uint32_t nv = f.mesh.nv, C = f.channels, v = (uint32_t)strtoul(argv[3], NULL, 10);
    float *q = malloc(sizeof(float) * (size_t)nv * C);
    if (!q || v >= nv) {
        fprintf(stderr, "consumer: %s: no memory, or vertex %u not below %u\n", argv[1], v, nv);
        free(q);
        sss_file_free(&f);
        return 1;
    }
    sss_decode_all(&f, light, q);
    /* FNV-1a over the bits of every value: equal output, equal bits */
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < (size_t)nv * C; i++) {
        uint32_t b;
        memcpy(&b, &q[i], sizeof b);
        for (int k = 0; k < 4; k++) h = (h ^ ((b >> (8 * k)) & 0xffu)) * 16777619u;
    }
    printf("vertices %" PRIu32 " channels %" PRIu32 " checksum %08" PRIx32 "\nq", nv, C, h);
    for (uint32_t c = 0; c < C; c++) printf(" %.17g", (double)q[(size_t)v * C + c]);
    printf("\n");
    free(q);
    sss_file_free(&f);
    return 0;
}
