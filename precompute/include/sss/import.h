/* sss/import.h: mesh import (PLY ascii/binary, OBJ, OFF, STL through
 * OpenMesh; glTF 2.0 .gltf/.glb through Assimp), with validation and
 * reported repairs. C interface over the C++17 adapters in
 * precompute/src/input/import_openmesh.cpp and import_assimp.cpp.
 *
 * Policy (docs/robustness.md will list it case by case):
 *  - rejected with an error naming file and element: unreadable or
 *    unrecognised file; declared counts that cannot fit in the file's size
 *    (checked before any allocation); NaN/Inf coordinates; a face index out of
 *    range; no triangles left after repair.
 *  - repaired and counted: polygons with more than 3 vertices (convex ones
 *    fan triangulated, non-convex ones ear-clipped in their plane), faces
 *    with fewer than 3 vertices or a repeated vertex index (dropped),
 *    zero-area faces (dropped), triangles repeating an earlier one's three
 *    vertices (dropped), vertices no face references (removed, the rest
 *    renumbered in order), triangles whose winding disagrees with their
 *    surface or turns a closed surface inside out (flipped), a mesh whose
 *    centre lies far from the origin compared with its size (recentred in
 *    double before the positions become float32).
 *  - warned: polygons that could not be ear-clipped, manifold edges left with
 *    inconsistent orientation (non-orientable surfaces).
 * docs/robustness.md lists each case with its test.
 */
#ifndef SSS_IMPORT_H
#define SSS_IMPORT_H

#include <stdint.h>
#include "sss/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_import_report {
    uint64_t vertices_read;          /* vertices in the file */
    uint64_t faces_read;             /* faces (polygons) in the file */
    uint64_t polygons_triangulated;  /* faces with > 3 vertices, fan triangulated */
    uint64_t faces_too_small;        /* faces with < 3 vertices, dropped */
    uint64_t faces_repeated_index;   /* faces using one vertex twice, dropped */
    uint64_t faces_zero_area;        /* triangles of zero area, dropped */
    uint64_t vertices_unreferenced;  /* vertices used by no face, removed */
    /* docs/robustness.md B5-B7: */
    uint64_t polygons_ear_clipped;   /* of polygons_triangulated: non-convex, ear-clipped instead of fanned */
    uint64_t polygons_unclipped;     /* warning: non-convex polygons left fanned (self-intersecting,
                                      * more than SSS_IMPORT_EAR_MAX vertices, or past 2^28 steps of
                                      * ear clipping in the whole mesh) */
    uint64_t faces_duplicate;        /* triangles with the same three vertices as an earlier one, dropped */
    uint64_t faces_flipped;          /* triangles of closed surfaces flipped: consistent and outward */
    uint64_t surfaces_inside_out;    /* of those: closed surfaces that were inside out as a whole */
    uint64_t open_faces_flipped;     /* triangles of open surfaces flipped to agree with the majority */
    uint64_t orientation_conflicts;  /* warning: manifold edges whose triangles still disagree
                                      * (non-orientable surface, e.g. a Moebius strip) */
    uint64_t recentred;              /* 1 when offset[] was subtracted from every position */
    double offset[3];                /* what was subtracted (file units), else 0 */
    /* warning (OBJ): lines whose statement is not one of the OBJ
     * specification's (v, f, vt, vn, g, o, s, usemtl, ...): ignored, but a
     * misspelt or damaged "v" there would shift every later face index */
    uint64_t unknown_statements;
    char first_unknown[36];          /* the first one's keyword (at most 32 bytes, shown as sss_fail shows text) */
    uint64_t first_unknown_line;     /* and its line */
    /* glTF (docs/robustness.md, "glTF"): */
    uint64_t primitives_skipped;     /* warning: primitives of points or lines, which have no surface */
    int texcoords;                   /* the mesh carries texture coordinates (sss_mesh.uv) */
    int colours;                     /* the mesh carries vertex colours (sss_mesh.rgba) */
    /* glTF skinning (sss_import_mesh_at, docs/deformable.md §5): 1 when a
     * skinned mesh was posed by the file's first clip, whose keyframes
     * span [clip_start, clip_end] seconds */
    int animated;
    double clip_start, clip_end;
} sss_import_report;

/* Polygons with more vertices than this are fanned even when non-convex
 * (ear clipping is cubic in the polygon's size at worst). */
#define SSS_IMPORT_EAR_MAX 4096

/* Reads the mesh at path into *out (pos and tri set; nrm/area computed too;
 * uv/rgba where a glTF file has them). The format is chosen from the
 * extension (.ply .obj .off .stl .gltf .glb, any case).
 * *rep (may be NULL) receives the counts above. On failure *out is zeroed
 * and err says "FILE: ELEMENT: problem". */
sss_result sss_import_mesh(const char *path, sss_mesh *out, sss_import_report *rep, sss_error *err);

/* The same with a glTF's skinned meshes posed at time t (seconds): each
 * node's translation, rotation and scale from the file's first animation
 * at t (clamped to its keyframes; LINEAR and STEP, rotations slerped), the
 * joints' matrices G(joint) · inverse bind matrix, and every vertex moved
 * by linear blend skinning, Σ_i w_i J_{j_i} p (glTF 2.0 §3.7.3; the
 * skinned mesh node's own transform does not apply). The rest of the
 * import is sss_import_mesh's. Other formats, and glTF without skins, read
 * as sss_import_mesh reads them. Errors beyond its: a non-finite t, a clip
 * the scanner cannot sample (CUBICSPLINE, bad accessors), a skinned mesh
 * used by several nodes. */
sss_result sss_import_mesh_at(const char *path, double t, sss_mesh *out, sss_import_report *rep, sss_error *err);

/* Number of repairs in rep (sum of the repair counters; the subsets
 * polygons_ear_clipped and surfaces_inside_out and the warnings are not
 * added). */
uint64_t sss_import_repairs(const sss_import_report *rep);

/* Writes one line per non-zero repair counter to stream (a FILE*), each
 * prefixed with prefix, e.g. "sss-bake: bunny.ply: repaired: 12 polygons
 * with more than 3 vertices fan-triangulated". */
void sss_import_print_repairs(const sss_import_report *rep, const char *prefix, void *stream);

/* Writes one line per non-zero warning counter (polygons_unclipped,
 * orientation_conflicts, unknown_statements, primitives_skipped): "PREFIX: warning: ...". Meant to be printed even
 * when the repairs are not (sss-bake -q). */
void sss_import_print_warnings(const sss_import_report *rep, const char *prefix, void *stream);

/* Writes m as a binary little-endian PLY (float x y z, and float u v when
 * m->uv is not NULL; uchar-count int vertex_indices). Used by the data
 * tools and tests. */
sss_result sss_export_ply(const char *path, const sss_mesh *m, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
