/* bvh.h: a bounding volume hierarchy over a mesh's triangles, built once on
 * the CPU and traced on the GPU (effects/near.c, GLSL near_vis.comp.glsl) so
 * that the viewer's near terms get every vertex's own visibility V(x_i, ω)
 * from the very ray the bake traces (precompute/src/kernels/visibility.c) instead of
 * a shadow map's approximation of it.
 *
 * Layout, as the shader reads it (std430):
 *  - nodes: 32 bytes each, children of an inner node adjacent (a, a + 1);
 *    root at 0. `b` packs the leaf's triangle count (b >> 2, 0 for an inner
 *    node) and the split axis of an inner node (b & 3), which orders the
 *    traversal (the child nearer the light's origin side first);
 *  - triangles in leaf order, 12 floats each: v0, e1 = v0 − v1, e2 = v2 − v0
 *    and Ng = cross(e2, e1), the values Embree's Möller–Trumbore test forms
 *    (its TriangleM stores v0, e1, e2; Ng with fused multiply-subtracts), so
 *    that the shader repeats the bake's arithmetic rather than an
 *    equivalent one (bvh.c says why that matters).
 * Boxes are padded outwards (SSS_BVH_PAD of the mesh's box diagonal) so that
 * a triangle the float test reports as hit is never in a box the float slab
 * test rejects.
 */
#ifndef SSS_BVH_H
#define SSS_BVH_H

#include "sss/render.h" /* sss_bvh, sss_bvh_node, SSS_BVH_STACK, sss_bvh_build, sss_bvh_occluded */

#define SSS_BVH_MAX_LEAF 4   /* triangles per leaf, at most */
#define SSS_BVH_PAD 1e-6     /* box padding, of the box diagonal */

#endif
