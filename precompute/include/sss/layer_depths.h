/* sss/layer_depths.h: the layer depths of a scene object evaluated at
 * bake time (docs/layers.md §3): depth maps (sss/depthmap.h) and
 * procedural depths (sss/layer_depth.h), per vertex, into section LDEP's
 * array. Part of libsss_bake (bake/layer_depths.c). */
#ifndef SSS_LAYER_DEPTHS_H
#define SSS_LAYER_DEPTHS_H

#include "sss/layer_depth.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The depths of object `obj`'s layers at every vertex of its placed mesh
 * `world` (the scene's rest pose; texture coordinates for maps): when
 * some layer's depth is a map or procedural, *layer_depth = nv · n float
 * mm, vertex-major (section LDEP), each vertex's made non-decreasing
 * (sss_layer_depths_monotone), and stack's depths set to each layer's
 * largest; else *layer_depth = NULL and stack is left as it is. Errors
 * name the layer ("material/layers/K/depth_mm", the key under the
 * object, which the caller names with the scene file) and the files: a
 * map on a mesh without texture coordinates, a map that cannot be read
 * (sss_depth_map_read). */
sss_result sss_layer_depths_eval(const sss_scene *scene, uint32_t obj, const sss_mesh *world, float **layer_depth,
                                 sss_layer_stack *stack, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
