/* sss-genmesh: writes a procedural test mesh as binary PLY.
 * Usage: sss-genmesh KIND RES OUT.ply [SIZE] */
#include <stdio.h>
#include <stdlib.h>

#include "genmesh.h"
#include "sss/import.h"

int main(int argc, char **argv)
{
    if (argc < 4 || argc > 5) {
        fprintf(stderr, "usage: sss-genmesh sphere|blob|plane|cube|slab|torus|pair RES OUT.ply [SIZE]\n"
                        "  RES: subdivisions (sphere, blob, pair) or segments per side (others); SIZE: radius or edge,\n"
                        "  default 1 (pair: a sphere of radius SIZE and one of 250 SIZE, far apart)\n");
        return 2;
    }
    char *end;
    long res = strtol(argv[2], &end, 10);
    if (*end || res < 0 || res > 100000) {
        fprintf(stderr, "sss-genmesh: RES '%s' must be an integer in [0, 100000]\n", argv[2]);
        return 2;
    }
    double size = argc == 5 ? strtod(argv[4], &end) : 1.0;
    if (argc == 5 && (*end || !(size > 0))) {
        fprintf(stderr, "sss-genmesh: SIZE '%s' must be a number > 0\n", argv[4]);
        return 2;
    }
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_by_name(argv[1], (unsigned)res, size, &m, &err) != SSS_OK ||
        sss_export_ply(argv[3], &m, &err) != SSS_OK) {
        fprintf(stderr, "sss-genmesh: %s\n", err.msg);
        return 1;
    }
    fprintf(stderr, "sss-genmesh: %s: %u vertices, %u triangles\n", argv[3], m.nv, m.nf);
    sss_mesh_free(&m);
    return 0;
}
