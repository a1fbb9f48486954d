/* sss/import.h: mesh import (PLY ascii/binary, OBJ, OFF, STL) through
 * OpenMesh, with validation and reported repairs. C interface over the C++17
 * adapter in precompute/src/import_openmesh.cpp.
 *
 * Policy (docs/robustness.md will list it case by case):
 *  - rejected with an error naming file and element: unreadable or
 *    unrecognised file; declared counts that cannot fit in the file's size
 *    (checked before any allocation); NaN/Inf coordinates; a face index out of
 *    range; no triangles left after repair.
 *  - repaired and counted: polygons with more than 3 vertices (fan
 *    triangulated), faces with fewer than 3 vertices or a repeated vertex
 *    index (dropped), zero-area faces (dropped), vertices no face references
 *    (removed, the rest renumbered in order).
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
} sss_import_report;

/* Reads the mesh at path into *out (pos and tri set; nrm/area computed too).
 * The format is chosen from the extension (.ply .obj .off .stl, any case).
 * *rep (may be NULL) receives the counts above. On failure *out is zeroed
 * and err says "FILE: ELEMENT: problem". */
sss_result sss_import_mesh(const char *path, sss_mesh *out, sss_import_report *rep, sss_error *err);

/* Number of repairs in rep (sum of the repair counters). */
uint64_t sss_import_repairs(const sss_import_report *rep);

/* Writes one line per non-zero repair counter to stream (a FILE*), each
 * prefixed with prefix, e.g. "sss-bake: bunny.ply: repaired: 12 polygons
 * with more than 3 vertices fan-triangulated". */
void sss_import_print_repairs(const sss_import_report *rep, const char *prefix, void *stream);

/* Writes m as a binary little-endian PLY (float x y z; uchar-count int
 * vertex_indices). Used by the data tools and tests. */
sss_result sss_export_ply(const char *path, const sss_mesh *m, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
