/* refs_decimate.h: private C interface to the C++17 OpenMesh adapter
 * (refs_decimate.cpp) that chooses the reference points of Hao–Varshney 2004
 * §4.2 by quadric-error half-edge-collapse decimation, optionally steered by
 * a per-vertex illumination feature (the paper's §6 future work). refs.c
 * validates the mesh and the feature and drops repeated-index faces first;
 * everything here is topology and collapse order, and the result is the
 * simplified triangle list in the original vertex numbering.
 */
#ifndef SSS_REFS_DECIMATE_H
#define SSS_REFS_DECIMATE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Result of sss_om_decimate. */
typedef enum sss_om_decimate_status {
    SSS_OM_DECIMATE_OK = 0,
    SSS_OM_DECIMATE_NO_MEMORY,  /* std::bad_alloc or malloc failed */
    SSS_OM_DECIMATE_FAILED      /* bad argument, OpenMesh refused (decimater did not
                                   initialise) or any other C++ exception; msg says which */
} sss_om_decimate_status;

/* Decimates the triangles tri (nf of them, indices < nv, no repeated index
 * within a triangle; the caller checks) over the positions pos (3*nv floats,
 * finite) until `target` distinct original vertices that have a triangle
 * remain, or no legal collapse is left (a vertex may have several copies,
 * below: each pass collapses as many copies as originals are in excess,
 * then recounts).
 *
 * Before anything else, vertices at exactly the same position are welded
 * (the lowest index stands for the group) and triangles this makes
 * degenerate are left out (unless that is all of them). Non-manifold input:
 * then a triangle and its reverse on the same three vertices (a
 * zero-thickness flap) cancel and are both left out (unless that would leave
 * nothing); then fins are left out, one at a time: triangles with a free
 * edge and an edge that two or more other triangles share (a flap of which
 * the importer kept one triangle; never all triangles). *left_out counts the
 * triangles left out in these three steps. The
 * rest is split, never dropped: every edge is resolved into manifold pairs
 * of oppositely oriented triangles (an edge with more than two triangles is
 * paired by the angular order of the triangles around it), every vertex gets
 * one copy per fan of triangles joined through those pairs, and the few
 * configurations that would still be non-manifold are cut further, so that
 * OpenMesh's TriMesh accepts every triangle. *copies receives the number of
 * vertex copies made beyond the nv originals. A manifold, consistently
 * oriented input without coincident vertices goes through unchanged and
 * decimates as it did before these steps existed.
 *
 * Priority: ModQuadricT (Garland–Heckbert quadric error) when feature is
 * NULL or feature_scale is 0; else a module adding feature_scale times the
 * feature error of keeping the surviving vertex: Σ over the merged triangles
 * of area · |the triangle's linear feature interpolant at its position − its
 * feature|² (see refs_decimate.cpp). feature holds feature_dim floats per
 * original vertex (nv·feature_dim, finite). ModNormalFlippingT vetoes
 * fold-overs.
 *
 * On success *out_tri (malloc'd; free with free()) holds 3*(*out_nf)
 * ORIGINAL vertex indices, counter-clockwise as in the input, in OpenMesh
 * face order, with the triangles that the mapping copy → original makes
 * degenerate (a repeated index) left out; *out_nf may be 0. On failure the
 * outputs are zeroed/NULL and msg (msglen bytes, may be 0) holds one line.
 * Never throws; deterministic (single-threaded). */
sss_om_decimate_status sss_om_decimate(const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nf,
                                       const float *feature, uint32_t feature_dim, double feature_scale,
                                       uint32_t target, uint32_t **out_tri, uint32_t *out_nf, uint32_t *left_out,
                                       uint32_t *copies, char *msg, size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
