/* sss/depthmap.h: the layer depths of a scene object evaluated at bake
 * time (docs/layers.md §3): depth maps read from PNG files and procedural
 * depths, per vertex, into section LDEP's array. Part of libsss_bake
 * (input/depthmap.c reads the PNG, bake/layer_depths.c evaluates). */
#ifndef SSS_DEPTHMAP_H
#define SSS_DEPTHMAP_H

#include "sss/layer_depth.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest depth map read: 2²⁶ samples (a 8192 × 8192 map). */
#define SSS_DEPTH_MAP_MAX_SAMPLES ((uint64_t)1 << 26)

/* Reads an 8- or 16-bit grey PNG (colour type 0, any interlace) into *im,
 * each sample over its largest value (255 or 65535). One line naming the
 * file otherwise: missing or unreadable, not a PNG, another colour type
 * or bit depth (named), more than SSS_DEPTH_MAP_MAX_SAMPLES samples, or
 * libpng's own complaint about damaged data. */
sss_result sss_depth_map_read(const char *path, sss_depth_image *im, sss_error *err);

/* Writes im as a grey PNG of 8 or 16 bits per sample, each value in
 * [0, 1] (clamped) times 255 or 65535, rounded; atomically, to a path the
 * output policy allows (sss/fileio.h). The tests' and sss-genmesh's maps. */
sss_result sss_depth_map_write(const char *path, const sss_depth_image *im, int bits, sss_error *err);

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
