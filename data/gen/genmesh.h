/* genmesh.h: procedural test meshes at any resolution, outward-facing,
 * counter-clockwise, with shared (welded) vertices. Normals and areas are
 * computed (sss_mesh_compute_normals_areas). Sizes are in mesh units.
 *
 * Texture coordinates (sss_mesh.uv, what a layer's depth map is read at,
 * docs/layers.md §3): the plane (i/nx, j/ny), the sphere and the blob
 * made from it (u = 1/2 + atan2(y, x)/2π, v = 1/2 + asin(z/|p|)/π), the
 * torus (i/nu, j/nv: around z, around the tube) and the tube's side
 * (around, along z; each cap's centre at u = 1/2 and its ring's v). The
 * vertices stay welded, so the triangles that close a periodic direction
 * span u (or v) from about 1 back to 0 (sss_mesh_tangents skips them).
 * The box, slab, pair and subdivided meshes have none.
 */
#ifndef SSS_GENMESH_H
#define SSS_GENMESH_H

#include "sss/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Geodesic sphere: icosahedron subdivided `subdiv` times (10·4^s + 2 vertices). */
sss_result sss_gen_sphere(sss_mesh *m, double radius, unsigned subdiv, sss_error *err);

/* Plane z = 0 centred at the origin, sx × sy, nx × ny quads (two triangles
 * each), normal +z. */
sss_result sss_gen_plane(sss_mesh *m, double sx, double sy, unsigned nx, unsigned ny, sss_error *err);

/* Closed box centred at the origin, sx × sy × sz, each face an n × n grid.
 * With sz small it is the thin slab. `inward` != 0 flips orientation (a
 * room seen from inside). */
sss_result sss_gen_box(sss_mesh *m, double sx, double sy, double sz, unsigned n, int inward, sss_error *err);

/* Torus around z: major radius R, minor radius r, nu × nv segments. */
sss_result sss_gen_torus(sss_mesh *m, double R, double r, unsigned nu, unsigned nv, sss_error *err);

/* Closed tube along z, centred at the origin: radius, length, nring
 * vertices around and nseg segments along, capped by fans about the axis
 * (the bending tube of docs/deformable.md). */
sss_result sss_gen_tube(sss_mesh *m, double radius, double length, unsigned nring, unsigned nseg, sss_error *err);

/* A lumpy sphere (radius modulated by low-frequency bumps) with concave
 * regions that shadow themselves: the bundled sample's shape. */
sss_result sss_gen_blob(sss_mesh *m, double radius, unsigned subdiv, sss_error *err);

/* Appends b's vertices and triangles to a (indices shifted). */
sss_result sss_mesh_append(sss_mesh *a, const sss_mesh *b, sss_error *err);

/* Every triangle of `in` cut into n² (each edge into n equal segments,
 * the points in the triangle's plane): the midpoint subdivision for n = 2,
 * for any n, so that a mesh of T triangles, E edges and V vertices gets
 * T n² triangles and V + E (n − 1) + T (n − 1)(n − 2)/2 vertices. The
 * surface stays as it was (no smoothing); for meshes of a given size
 * (tests/bench/table1.sh). */
sss_result sss_gen_subdivide(const sss_mesh *in, unsigned n, sss_mesh *m, sss_error *err);

/* Generates by name: "sphere", "plane", "cube", "box", "slab", "torus",
 * "blob" with a resolution knob `res` (subdivisions or segments). */
sss_result sss_gen_by_name(const char *kind, unsigned res, double size, sss_mesh *m, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
