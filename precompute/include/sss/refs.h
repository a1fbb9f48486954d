/* sss/refs.h: reference points (Hao–Varshney 2004 §4.2).
 *
 * A subset of the original vertices, chosen by mesh simplification, stores
 * the full per-direction integrals; every other vertex x stores the reference
 * triangle it projects onto and barycentric weights w, so that
 *     q(x) ≈ Σ_k w_k q(ref_k) + (a small SH-coded delta).
 * The paper prefers references that are a subset of the original vertices
 * (§4.2, Fig. 8): here they are the vertices that survive quadric-error
 * half-edge-collapse decimation (Garland–Heckbert 1997 quadrics, OpenMesh),
 * and the triangle of a vertex is the one holding its closest point on the
 * simplified mesh (CGAL AABB tree), the paper's "project the vertex onto the
 * simplified triangles" step.
 *
 * Beyond the paper (its §6 future work: reference points chosen from "both
 * geometry and illumination"): sss_refs_build_ex takes an optional
 * per-vertex feature, e.g. the integrals q over a few light directions, and
 * makes collapses across a discontinuity of it (a shadow boundary) costly,
 * so references gather along such boundaries instead of geometry alone
 * deciding.
 *
 * C interface over two C++17 adapters: precompute/src/compress/refs_decimate.cpp
 * (OpenMesh) and precompute/src/compress/refs_closest.cpp (CGAL).
 */
#ifndef SSS_REFS_H
#define SSS_REFS_H

#include <stdint.h>
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Reference points of a mesh. All arrays are malloc'd and owned; free with
 * sss_refs_free. */
typedef struct sss_refs {
    uint32_t nv;            /* vertices of the full mesh */
    uint32_t nref;          /* number of reference vertices */
    uint32_t *ref_vertex;   /* nref original vertex indices, strictly increasing */
    uint32_t nrt;           /* triangles of the simplified mesh over the references */
    uint32_t *ref_tri;      /* 3*nrt indices into ref_vertex (0..nref-1) */
    uint32_t *vtri;         /* nv: for each vertex, the reference triangle (0..nrt-1) it projects onto */
    float *w;               /* 3*nv: weights of the corners of ref_tri[vtri[v]]; finite, >= 0, sum 1 */
    uint32_t faces_skipped; /* triangles of the input left out of the simplification input:
                               a repeated vertex index, or (when decimating) two corners at
                               exactly the same position, or a triangle and its reverse on the
                               same three vertices, which cancel, or a fin (a free edge and an
                               edge shared by two or more other triangles); non-manifold
                               triangles are otherwise split, not skipped */
    uint32_t vertices_split; /* vertex copies made, beyond nv, to hand a non-manifold input to
                                the decimation as a manifold one (0: manifold and consistently
                                oriented, or no decimation) */
} sss_refs;

/* Chooses the reference points of m and maps every vertex onto them.
 *
 * Target count: n = max(min_refs, round(fraction · m->nv)). If n is at least
 * the number of vertices used by a triangle (fraction = 1 always is), there is
 * no simplification: every vertex used by a triangle is a reference, the
 * reference triangles are m's triangles (repeated-index ones dropped). Else
 * m's triangles are decimated by half-edge collapses with quadric error and
 * normal-flip prevention until n vertices remain, or until no legal collapse
 * is left (then nref > n: a closed piece cannot go below a tetrahedron, an
 * open one keeps its rim's corners; the teapot stops at 21 when 8 are asked
 * for, and reaches 3 % and 5 % exactly, the dragons reach 1 %).
 *
 * Vertices at exactly the same position (unwelded patches: the teapot's 32
 * Bézier patches repeat 263 of its 792 vertices) are one vertex to the
 * decimation: the lowest index of such a group can become a reference, the
 * others map onto it with weight 1 (their closest point). Triangles this
 * makes degenerate are left out of the decimation and counted in
 * faces_skipped. (Left apart, the patches' rims and corners pinned the
 * teapot at 17.5 % whatever was asked.)
 *
 * Non-manifold input (edges with more than two triangles, vertices where
 * separate fans meet, orientation flips, triangles present twice; the
 * Stanford dragons have thousands) is decimated in full. A triangle and its
 * reverse on the same vertices enclose nothing and cancel (both counted in
 * faces_skipped; their vertices are mapped like any non-reference). So does
 * a fin, a triangle with a free edge on an edge that two or more other
 * triangles share: that is what such a flap becomes once sss_import_mesh has
 * dropped one triangle of the pair, and split off, each fin pinned its
 * vertices (the imported 23K dragon stopped at 10.4 % whatever was asked).
 * Fins go one at a time, so an edge keeps at least two triangles. OpenMesh's
 * TriMesh takes manifold input only, so the rest is split into a manifold
 * mesh (triangles around an edge glued in oppositely oriented pairs by their
 * angular order, one copy of a vertex per fan; vertices_split counts the
 * copies). A reference is still an original vertex: copies of one vertex
 * that survive are one reference, and a simplified triangle that this makes
 * degenerate is dropped. (Leaving the refused triangles out instead punched
 * holes whose rims cannot be collapsed, and reversed pairs came off as
 * pillows that cannot be: the 23K dragon stopped at 8.3 % whatever was
 * asked; it now reaches the requested count.) Tiny detached pieces that no
 * collapse can shrink (a lone fin triangle split off its edge, a
 * tetrahedron) keep their vertices, which count towards n.
 *
 * Mapping: a reference vertex gets the first reference triangle (in ref_tri
 * order) that uses it, with weight exactly 1.0 on its own corner and 0 on the
 * others. Any other vertex (including vertices no triangle uses) gets the
 * triangle holding its closest point on the simplified mesh and the weights
 * of sss_refs_closest_weights.
 *
 * m needs pos and tri only (nrm/area are not read). fraction in (0, 1].
 * Deterministic: the same input gives the same bytes, whatever the thread
 * count. Errors: SSS_ERR_ARG (bad fraction, NULL), SSS_ERR_MESH (no vertices
 * or triangles, index out of range, non-finite position, nothing left to
 * simplify), SSS_ERR_NOMEM, SSS_ERR_UNSUPPORTED (an adapter failed; the
 * message says why). On failure *out is zeroed.
 *
 * Same as sss_refs_build_ex(m, fraction, min_refs, NULL, 0, 0, out, err). */
sss_result sss_refs_build(const sss_mesh *m, double fraction, uint32_t min_refs, sss_refs *out,
                          sss_error *err);

/* sss_refs_build with illumination-aware selection (beyond the paper: its §6
 * proposes choosing reference points from illumination as well as geometry,
 * e.g. not to smear shadow boundaries).
 *
 * feature: NULL (geometry alone, exactly sss_refs_build), or
 * m->nv · feature_dim finite floats, feature_dim >= 1 per vertex, vertex v's
 * at feature[v·feature_dim]. Typically the integrals q of v for a few light
 * directions, each direction normalised by its mean, or any other signal
 * whose jumps the references should follow.
 *
 * Collapse cost: quadric error + s · E. E is the feature analogue of the
 * quadric (Hoppe 1999's attribute quadric, kept to half-edge collapses):
 * every triangle t interpolates the feature linearly over its plane, L_t,
 * and keeping vertex v1 for the triangles merged into it costs
 *     E = Σ_t area_t · |L_t(p_v1) − f_v1|²,
 * accumulated over collapses like the quadrics. Over triangles of constant
 * feature it is the area-weighted squared feature distance between the two
 * vertices of the collapse; across a step it grows with the square of v1's
 * distance from the step, so the vertices flanking a shadow boundary become
 * references and the reference triangles, which interpolate linearly (§4.2),
 * reproduce the step instead of smearing it. The quadric error is also area
 * × squared distance, and
 *     s = feature_weight · diag² / var,
 * diag = bounding-box diagonal and var = mean |f − mean f|², both over the
 * vertices that triangles use: feature_weight = w prices a feature error of
 * one standard deviation like a geometric deviation of √w · diag, whatever
 * the units of mesh and feature, and a constant offset of the feature is
 * ignored. 0 (or a constant feature) gives exactly the geometric result.
 * Measured on a unit sphere (subdivision 4, 5 % references) with a step
 * across a plane: w = 1e-3 puts 58 instead of 13 references within an edge
 * of the step and cuts the RMS error of the interpolated feature from 0.151
 * to 0.031, while the positions' RMS error grows from 0.023 to 0.030;
 * w = 1e-2 gives 0.020 and 0.039. Sensible: 1e-4 to 1e-2. The feature only
 * steers which vertices survive: the mapping and weights stay geometric.
 * Costs 8 · (11 + 4 · feature_dim) bytes per vertex while decimating.
 *
 * Errors as sss_refs_build, plus SSS_ERR_ARG for feature_dim 0 with a
 * feature, a non-finite feature value, or feature_weight < 0 or non-finite.
 * feature_dim and feature_weight are not read when feature is NULL. */
sss_result sss_refs_build_ex(const sss_mesh *m, double fraction, uint32_t min_refs, const float *feature,
                             uint32_t feature_dim, double feature_weight, sss_refs *out, sss_error *err);

/* Frees every array and zeroes the struct. NULL-safe. */
void sss_refs_free(sss_refs *r);

/* Barycentric weights (w[0] on a, w[1] on b, w[2] on c) of the point of the
 * closed triangle abc closest to p, in double: Voronoi-region test of
 * Ericson, Real-Time Collision Detection §5.1.5, so points outside the
 * triangle are clamped onto its boundary. A degenerate triangle (collinear or
 * coincident corners: twice its area below 1e-12 of its longest edge squared)
 * falls back to the closest point on its longest edge, or to a (weight 1) when
 * all corners coincide. Always finite, >= 0 and summing to 1 (renormalised);
 * a non-finite input gives (1, 0, 0).
 *
 * This is the geometric weighting sss_refs_build uses for non-reference
 * vertices; it is public so that another weighting (e.g. least squares on the
 * integrals themselves) can be compared against it and replace it. */
void sss_refs_closest_weights(const double p[3], const double a[3], const double b[3], const double c[3],
                              double w[3]);

#ifdef __cplusplus
}
#endif
#endif
