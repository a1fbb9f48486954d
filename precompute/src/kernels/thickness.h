/* thickness.h: detection of parts thinner than the scattering range
 * (docs/robustness.md B8). Private to libsss_bake. */
#ifndef SSS_THICKNESS_H
#define SSS_THICKNESS_H

#include <stdint.h>
#include "sss/mesh.h"
#include "sss/result.h"

/* Counts the vertices whose local thickness, the distance from the vertex
 * into the object along -n to the next surface, is below limit (mesh
 * units). mesh needs normals. *thinnest receives the smallest thickness
 * found (INFINITY if no ray hits anything). Deterministic, independent of
 * the thread count. Stops early (returning SSS_ERR_INTERRUPTED) when
 * cancel is set (sss/result.h). */
sss_result sss_thin_count(const sss_mesh *mesh, double limit, const sss_cancel_flag *cancel, uint32_t *count,
                          double *thinnest, sss_error *err);

#endif
