/* sss/mesh.h: indexed triangle mesh with per-vertex normals and areas.
 *
 * Positions are float32 in the mesh's own units (the bake scales them by
 * mm_per_unit); everything derived from them (normals, areas) is computed in
 * double from those float positions, so a reader of a .sss file can recompute
 * exactly what the bake used.
 */
#ifndef SSS_MESH_H
#define SSS_MESH_H

#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The range of geometry every stage computes in (docs/robustness.md,
 * "Ranges"). Coordinates (mesh units) and the mesh's extent in mm bound
 * what reaches Embree (which asserts beyond about 1.8e18), FLANN and the
 * tree gather (float positions in mm and their squares), the renderer
 * (float) and the ray offset; mm per unit is the bake's own option range.
 * The importer, the bake and the .sss reader refuse anything outside. */
#define SSS_COORD_MAX 1e15        /* |coordinate|, mesh units */
#define SSS_EXTENT_MM_MAX 1e15    /* bounding-box diagonal × mm per unit */
#define SSS_MM_PER_UNIT_MIN 1e-12
#define SSS_MM_PER_UNIT_MAX 1e12

typedef struct sss_mesh {
    uint32_t nv;     /* vertex count */
    uint32_t nf;     /* triangle count */
    float *pos;      /* 3*nv, mesh units, owned */
    float *nrm;      /* 3*nv, unit area-weighted vertex normals, owned (may be NULL) */
    uint32_t *tri;   /* 3*nf vertex indices, counter-clockwise seen from outside, owned */
    double *area;    /* nv, ΔA(x_i) = 1/3 of the incident triangle areas, mesh units², owned (may be NULL) */
    /* What an asset carries besides its shape (glTF's TEXCOORD_0 and
     * COLOR_0, docs/robustness.md "glTF"), kept in memory for the bake and
     * reported; no stage computes with them and the .sss file does not
     * store them. Each is NULL when the input has none. */
    float *uv;       /* 2*nv texture coordinates (u, v), v upward (OpenGL's origin at the bottom left), owned */
    float *rgba;     /* 4*nv linear vertex colours in [0, 1], owned */
} sss_mesh;

/* Allocates pos and tri for nv vertices and nf triangles (nrm, area, uv,
 * rgba NULL).
 * Zero-initialises the arrays. Fails with SSS_ERR_NOMEM on overflow. */
sss_result sss_mesh_alloc(sss_mesh *m, uint32_t nv, uint32_t nf, sss_error *err);

/* Frees every owned array and zeroes the struct. NULL-safe. */
void sss_mesh_free(sss_mesh *m);

/* Deep copy of src into *dst: pos and tri, and nrm / area / uv / rgba
 * where src has them (NULL otherwise). On failure (SSS_ERR_NOMEM) *dst is zeroed. */
sss_result sss_mesh_copy(const sss_mesh *src, sss_mesh *dst, sss_error *err);

/* Checks indices < nv and finite positions; then computes nrm (area-weighted
 * face normals, normalised; a vertex whose incident normals cancel gets
 * (0,0,0)) and area (ΔA, Hao–Varshney 2004 §3.1), both accumulated in double
 * in triangle order so the result is deterministic. `name` prefixes errors. */
sss_result sss_mesh_compute_normals_areas(sss_mesh *m, const char *name, sss_error *err);

/* ΔA for every vertex into area[nv], the same sums in the same order as
 * sss_mesh_compute_normals_areas, for a mesh that cannot be modified (e.g.
 * one read from a file). Indices must already be valid. */
void sss_mesh_vertex_areas(const sss_mesh *m, double *area);

/* The interpolated unit normal of triangle t of m (nrm required) at the
 * point p (mesh units), by the barycentrics of p's projection: the normal a
 * rasteriser interpolates, and the one the path tracer's boundary and the
 * single-scattering oracle use (docs/reference.md, docs/layers.md §5). */
void sss_mesh_normal_at(const sss_mesh *m, uint32_t t, const double p[3], double n[3]);

/* Per-vertex tangent frames from the texture coordinates (the frame
 * seed 002 §2.3 marches texture coordinates in): tangent[4 v .. 4 v + 3]
 * = (T, w), T the unit direction of ∂p/∂u at vertex v made orthogonal to
 * its normal (Gram–Schmidt), w = ±1 the handedness, so that the bitangent
 * is B = w (N × T) and points along ∂p/∂v. ∂p/∂u of each triangle comes
 * from its edges and their (u, v) differences, weighted by the triangle's
 * area (unnormalised cross products) and summed in triangle order, so the
 * result is deterministic. A triangle whose (u, v) are collinear, or
 * whose u or v differences exceed 1/2 (the periodic seam of a welded mesh,
 * as sss-genmesh's sphere, torus and tube have), adds nothing; a vertex left with no usable direction (or no normal) gets the
 * unit vector least aligned with its normal, made orthogonal, and w = 1.
 * Needs m->uv and m->nrm; SSS_ERR_ARG (naming `name`) otherwise. */
sss_result sss_mesh_tangents(const sss_mesh *m, float *tangent, const char *name, sss_error *err);

/* Whether m lies in the range above: every coordinate finite and at most
 * SSS_COORD_MAX in magnitude and, when mm_per_unit is not 0, mm_per_unit in
 * [SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX] and the bounding-box diagonal
 * times it at most SSS_EXTENT_MM_MAX. One line naming `name` and the vertex
 * (SSS_ERR_MESH) otherwise. */
sss_result sss_mesh_check_range(const sss_mesh *m, double mm_per_unit, const char *name, sss_error *err);

/* Axis-aligned bounds of the positions; returns the diagonal length. */
double sss_mesh_bounds(const sss_mesh *m, double lo[3], double hi[3]);

/* The sphere about the centre of those bounds through the farthest vertex:
 * its radius (1 for a mesh of no extent), the centre in centre[3]. The
 * viewer frames it (sss_view_frame) and fits light-space maps to it. */
double sss_mesh_bounding_sphere(const sss_mesh *m, double centre[3]);

/* δ, the offset of the visibility rays cast from m's vertices, in mesh
 * units: 1e-5 of the bounding-box diagonal (sss_mesh_bounds), rounded once
 * to float. Every test that must give V(x, ω) (Hao–Varshney 2004 §3.1's
 * shadowing, decided by rays) as the bake decides it applies one rule with
 * this value: the ray from vertex x with unit normal n starts at
 *     o = x + δ·n    (float; the product and the sum rounded separately),
 * runs towards ω (float) and is blocked by any hit at t > δ (tnear = δ).
 * The offset keeps the ray off the triangles that share x; a smaller δ lets
 * grazing rays clip them. δ depends on m alone, so occluders added around
 * it do not move the origins. 0 for an empty mesh. */
float sss_mesh_ray_offset(const sss_mesh *m);

#ifdef __cplusplus
}
#endif
#endif
