/* sss/visibility.h: V(x_i, ω), whether a vertex sees a light, by occlusion
 * rays (Embree). Hao–Varshney 2004 §3.1 used shadow maps; rays are exact up
 * to the origin offset (kernels/visibility.c). Part of libsss_bake.
 */
#ifndef SSS_VISIBILITY_H
#define SSS_VISIBILITY_H

#include <stdint.h>
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_vis sss_vis;
sss_result sss_vis_create(const sss_mesh *mesh, sss_vis **out, sss_error *err);
void sss_vis_destroy(sss_vis *vis);
/* Is vertex v's light from direction d (unit, towards the light) blocked? */
int sss_vis_occluded(const sss_vis *vis, uint32_t v, const double d[3]);
/* Every vertex's own visibility towards unit d, lit[v] = 1 when it faces d
 * (n_v·d > 0, in double) and its ray is not blocked — the rule of the
 * bake's transfer rows, where back-facing vertices trace no ray. mesh is
 * the one vis was built on (its normals). Returns the rays traced. */
uint64_t sss_vis_lit_all(const sss_vis *vis, const sss_mesh *mesh, const double d[3], uint8_t *lit);
/* Visibility for a scene (docs/scenes.md): rays start at mesh's vertices
 * (offset as above, from mesh's own diagonal) and are tested against mesh
 * itself when self != 0 and against the nocc occluder meshes (same world
 * units). sss_vis_create(m) is sss_vis_create_scene(m, 1, NULL, 0). */
sss_result sss_vis_create_scene(const sss_mesh *mesh, int self, const sss_mesh *const *occ, uint32_t nocc,
                                sss_vis **out, sss_error *err);
/* The same test with the ray ending at distance tfar (mesh units): a point
 * light's shadow ends at the light. */
int sss_vis_occluded_upto(const sss_vis *vis, uint32_t v, const double d[3], double tfar);

#ifdef __cplusplus
}
#endif
#endif
