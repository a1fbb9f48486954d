/* deform_error.h: sss-stat --scene S.json --time T --error (docs/deformable.md
 * §4): the per-vertex error of what sss-view draws for a deforming object
 * (the per-frame path as it runs there) against the exact evaluator on the
 * same pose. */
#ifndef SSS_DEFORM_ERROR_H
#define SSS_DEFORM_ERROR_H

#include <stdint.h>

/* Measures every deforming object of the scene at time t over `views`
 * random light directions from `seed`; prints one line per object (or one
 * JSON object with an array). Returns the exit status (0; 1 after a
 * failure; 2 for a scene with nothing to measure), messages one line each. */
int sss_deform_error_report(const char *tool, const char *scene, double t, uint32_t views, uint64_t seed, int json);

#endif
