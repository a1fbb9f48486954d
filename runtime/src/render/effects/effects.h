/* effects.h: the run-time passes of the effects a file can carry, one file
 * each in this folder (internal to sss_render).
 *
 * near.c: the near terms of section OWNT (sss/ownterm.h, docs/viewer.md),
 * two compute passes over q after it is evaluated or uploaded.
 */
#ifndef SSS_EFFECTS_INTERNAL_H
#define SSS_EFFECTS_INTERNAL_H

#include "renderer.h"

typedef struct sss_near_pass sss_near_pass;

/* Builds the near terms of m's file (which has OWNT): their rows and
 * weights, the mesh's BVH, the triangle fans and the programs. */
sss_result sss_near_pass_create(const sss_gpu_mesh *m, sss_near_pass **out, sss_error *err);
void sss_near_pass_destroy(sss_near_pass *n);

/* Adds the near terms for the unit light l to m->qbuf with the visibility p
 * asks for, under the GL_TIME_ELAPSED query `query`; returns 1 when they
 * ran (0: no light, or no visibility test could be had). */
int sss_near_pass_run(sss_near_pass *n, const sss_gpu_mesh *m, const double l[3], const sss_view_params *p,
                      GLuint query);

/* V of the last pass per vertex into lit[nv] (sss_renderer_read_own_visibility). */
void sss_near_pass_read_visibility(const sss_near_pass *n, uint32_t nv, uint8_t *lit);

#endif
