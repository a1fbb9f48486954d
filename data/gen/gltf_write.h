/* gltf_write.h: a mesh as glTF 2.0, the test assets of the glTF importer
 * (docs/robustness.md, "glTF"): .gltf (JSON with the buffer embedded as a
 * base64 data: URI) or .glb (a JSON chunk and a binary chunk), chosen by
 * the path's extension. */
#ifndef SSS_GLTF_WRITE_H
#define SSS_GLTF_WRITE_H

#include "sss/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

enum {
    /* Two instances of the mesh under one parent node: the parent moves by
     * (0, 0, 1); child A by (-2, 0, 0); child B is scaled by 0.5, turned
     * 90 degrees about +z (x -> y) and moved by (2, 0, 0). World positions:
     *   A: p + (-2, 0, 1)        B: (-0.5 p_y + 2, 0.5 p_x, 0.5 p_z + 1) */
    SSS_GLTF_TWO_NODES = 1u << 0,
    /* TEXCOORD_0 (u, v) = the position's x and y mapped from the bounding
     * box to [0, 1] (glTF's v, downward), and COLOR_0 (u, v, 0.5, 1) */
    SSS_GLTF_ATTRIBUTES = 1u << 1,
    /* A two-bone rig along z (docs/deformable.md §5): JOINTS_0 (unsigned
     * byte) and WEIGHTS_0 (float) per vertex, joint 1's weight rising
     * smoothly from 0 to 1 over the middle quarter of the mesh's z extent;
     * skin 0 with joints bone0 (at the lowest z) and its child bone1 (at
     * the middle), their inverse bind matrices, and one clip "bend" that
     * turns bone1 about +x by 0, 45, 0, −45, 0 degrees at 0, 1, 2, 3, 4 s. */
    SSS_GLTF_SKIN = 1u << 2,
    /* With SSS_GLTF_SKIN, broken on purpose for the importer's tests:
     * vertex 5 names joint 7 of the two; vertex 3's weights sum to 0.5 */
    SSS_GLTF_BAD_JOINT = 1u << 3,
    SSS_GLTF_BAD_WEIGHTS = 1u << 4
};

/* Whether path ends in .gltf or .glb (any case). */
int sss_gltf_path(const char *path);

/* Writes m's positions and triangles (one primitive, uint32 indices)
 * atomically to path (sss/fileio.h). */
sss_result sss_gltf_write(const char *path, const sss_mesh *m, unsigned flags, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
