/* refs_decimate.h: private C interface to the C++17 OpenMesh adapter
 * (refs_decimate.cpp) that chooses the reference points of Hao–Varshney 2004
 * §4.2 by quadric-error half-edge-collapse decimation. refs.c validates the
 * mesh and drops repeated-index faces first; everything here is topology and
 * collapse order, and the result is the simplified triangle list in the
 * original vertex numbering.
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
    SSS_OM_DECIMATE_FAILED      /* OpenMesh refused (decimater did not initialise) or any
                                   other C++ exception; msg says which */
} sss_om_decimate_status;

/* Builds an OpenMesh TriMesh (double points) with all nv vertices of pos
 * (3*nv floats) in order, then tri's nf triangles in order (indices < nv, no
 * repeated index within a triangle; the caller checks), leaving out each one
 * TriMesh::add_face would refuse as non-manifold (tested beforehand with the
 * same checks, so OpenMesh prints nothing); *rejected counts them.
 * Decimates with ModQuadricT (priority) and ModNormalFlippingT (veto) until
 * `target` of the vertices that have a face remain, or no legal collapse is
 * left. Half-edge collapses keep the surviving vertices where they were, so
 * the result is a subset of the original vertices.
 *
 * On success *out_tri (malloc'd; free with free()) holds 3*(*out_nf) original
 * vertex indices, counter-clockwise as in the input, in OpenMesh face order;
 * *out_nf may be 0 when every face was rejected. On failure the outputs are
 * zeroed/NULL and msg (msglen bytes, may be 0) holds one line. Never throws;
 * deterministic. */
sss_om_decimate_status sss_om_decimate(const float *pos, uint32_t nv, const uint32_t *tri, uint32_t nf,
                                       uint32_t target, uint32_t **out_tri, uint32_t *out_nf,
                                       uint32_t *rejected, char *msg, size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
