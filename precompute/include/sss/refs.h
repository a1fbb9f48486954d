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
 * C interface over two C++17 adapters: precompute/src/refs_decimate.cpp
 * (OpenMesh) and precompute/src/refs_closest.cpp (CGAL).
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
                               a repeated vertex index, or (when decimating) rejected by
                               OpenMesh's TriMesh as non-manifold (complex edge/vertex) */
} sss_refs;

/* Chooses the reference points of m and maps every vertex onto them.
 *
 * Target count: n = max(min_refs, round(fraction · m->nv)). If n is at least
 * the number of vertices used by a triangle (fraction = 1 always is), there is
 * no simplification: every vertex used by a triangle is a reference, the
 * reference triangles are m's triangles (repeated-index ones dropped). Else
 * m's triangles are decimated by half-edge collapses with quadric error and
 * normal-flip prevention until n vertices remain, or until no legal collapse
 * is left (then nref > n). Faces OpenMesh's TriMesh refuses (non-manifold) are
 * absent from that input and counted in faces_skipped.
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
 * message says why). On failure *out is zeroed. */
sss_result sss_refs_build(const sss_mesh *m, double fraction, uint32_t min_refs, sss_refs *out,
                          sss_error *err);

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
