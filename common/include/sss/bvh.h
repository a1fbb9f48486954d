/* sss/bvh.h: a bounding volume hierarchy over a mesh's triangles, built once
 * on the CPU and traced on the CPU (sss_bvh_occluded, sss_bvh_lit) or on the
 * GPU (runtime/shaders/near_vis.comp.glsl), so that the near terms
 * (sss/nearterms.h) get every vertex's own visibility V(x_i, ω) from the
 * very ray the bake traces (precompute/src/kernels/visibility.c) instead of
 * a shadow map's approximation of it. Part of libsss (no GL): the viewer,
 * the runtime API (sss/api.h) and an engine share it.
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

#include <stdint.h>
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_BVH_MAX_LEAF 4   /* triangles per leaf, at most */
#define SSS_BVH_PAD 1e-6     /* box padding, of the box diagonal */
#define SSS_BVH_STACK 64     /* the shader's traversal stack; the build keeps the depth below it */

/* An inner node's children are node[a] and node[a + 1], split axis b & 3;
 * a leaf holds the b >> 2 triangles from a. 32 bytes, as the shader reads
 * it (std430). */
typedef struct sss_bvh_node {
    float lo[3];
    uint32_t a;  /* inner: first child; leaf: first triangle */
    float hi[3];
    uint32_t b;  /* (triangle count << 2) | split axis */
} sss_bvh_node;

typedef struct sss_bvh {
    sss_bvh_node *node; /* nnode nodes, root at 0; owned */
    uint32_t nnode;
    float *tri;       /* 12 floats per triangle, leaf order (v0, e1, e2, Ng as Embree forms them); owned */
    uint32_t *prim;   /* the mesh triangle of each, leaf order; owned */
    uint32_t ntri;    /* triangles kept: those with finite vertices */
    uint32_t depth;   /* root = 1; at most SSS_BVH_STACK */
} sss_bvh;

/* Builds the hierarchy over the nf triangles (tri: 3 indices each into the
 * nv float3 positions pos, mesh units). Deterministic: binned SAH on
 * centroids (16 bins), object median where the tree grows deep. O(n log n).
 * Triangles with a non-finite vertex or an index ≥ nv are left out, as
 * Embree leaves them out. Re-entrant: builds on several threads at once do
 * not interfere. SSS_ERR_NOMEM on allocation failure, SSS_ERR_UNSUPPORTED
 * when the tree would be deeper than SSS_BVH_STACK. Free with sss_bvh_free
 * (NULL-safe). */
sss_result sss_bvh_build(const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nf, sss_bvh *out,
                         sss_error *err);
void sss_bvh_free(sss_bvh *b);

/* The shader's occlusion query on the CPU, operation for operation (fused
 * where Embree fuses): 1 when the ray o + t d hits a triangle at t > tnear
 * (d in float as given, not normalised here; tnear in mesh units). Reads b
 * only: any number of threads may trace one hierarchy at once. */
int sss_bvh_occluded(const sss_bvh *b, const float o[3], const float d[3], float tnear);

/* The nearest hit of the ray o + t d beyond t = tnear (the same triangle
 * test as sss_bvh_occluded): its t in units of d (INFINITY when the ray
 * leaves the mesh without a hit) and, when prim is not NULL, its mesh
 * triangle. Where single scattering's light enters and its view ray leaves
 * (sss/single_mesh.h). Reads b only. */
float sss_bvh_nearest(const sss_bvh *b, const float o[3], const float d[3], float tnear, uint32_t *prim);

/* V(x_v, ω) of vertex v of `mesh` (the mesh b was built from) by the bake's
 * ray (visibility.c): 0 where n_v·ω ≤ 0 (in double, float n and double ω,
 * left to right); else the ray from x_v + δ n_v (float, product and sum
 * rounded apart) towards ω, blocked by a hit beyond t = δ, δ =
 * sss_mesh_ray_offset(mesh). d is the unit light direction in double; the
 * ray runs along its float rounding. What near_vis.comp.glsl (RAYS)
 * computes per vertex, operation for operation. Reads only. */
uint8_t sss_bvh_lit(const sss_bvh *b, const sss_mesh *mesh, float delta, uint32_t v, const double d[3]);

#ifdef __cplusplus
}
#endif
#endif
