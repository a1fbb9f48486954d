/* scene_cli.h: the --scene mode of sss-bake (scene_cli.c). */
#ifndef SSS_SCENE_CLI_H
#define SSS_SCENE_CLI_H
#include "sss/bake.h"
/* Returns the process exit status: 0, 1 (bake or I/O failure), 2 (bad scene or options). */
int scene_main(const char *tool, const char *scene_path, const char *outdir, int plan_only, int json, int quiet,
               const sss_bake_options *opt);
#endif
