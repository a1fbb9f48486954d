/* scene_cli.h: the --scene mode of sss-bake (scene_cli.c). */
#ifndef SSS_SCENE_CLI_H
#define SSS_SCENE_CLI_H
#include "sss/bake.h"
/* Returns the process exit status: 0, 1 (bake or I/O failure), 2 (bad scene or options). */
int scene_main(const char *tool, const char *scene_path, const char *outdir, int plan_only, int json, int quiet,
               const sss_bake_options *opt);
/* `sss-bake MESH --point-light X,Y,Z[,I] ... -o OUT.sss` (docs/scenes.md,
 * "Point lights without a scene file"): the mesh as the one object of a
 * scene with a moving directional light and the point lights (points[k]:
 * X, Y, Z, I with I 0 for 1), planned and baked as --scene bakes it, into
 * OUT. Exit status as scene_main's. */
int points_main(const char *tool, const char *mesh, const char *out, const sss_material *mat, double mm_per_unit,
                const double (*points)[4], int npoints, int json, int quiet, const sss_bake_options *opt);
#endif
