/* bake_pass.h (internal): what every pass of a scene bake gets
 * (bake_scene.c dispatches; one file per parameterisation). */
#ifndef SSS_BAKE_PASS_H
#define SSS_BAKE_PASS_H

#include "sss/bake_scene.h"
#include "sss/transfer.h"

typedef struct sss_pass_ctx {
    const sss_scene *scene;
    const sss_object_plan *plan;
    const sss_mesh *mesh;      /* the object, world units, normals and areas */
    const sss_nbhd *nb;        /* N(x_o) for every vertex */
    const sss_vis *vis;        /* NULL: no visibility rays */
    double eta;
    uint32_t C;
    uint32_t n_dirs, sh_order, shells;
    double near_factor;
    sss_bake_file *out;
    sss_bake_stats *st;
} sss_pass_ctx;

/* G(x_i, ω_j) for all vertices and the n directions dirs into G[i * n + j],
 * counting rays only when a visibility structure is present. */
void sss_pass_transfer(const sss_pass_ctx *c, const double *dirs, uint32_t n, float *G, uint64_t *rays);

sss_result sss_pass_env_sh(const sss_pass_ctx *c, sss_error *err);      /* bake_env.c */
sss_result sss_pass_point_shells(const sss_pass_ctx *c, sss_error *err); /* bake_point.c */

#endif
