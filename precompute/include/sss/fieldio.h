/* sss/fieldio.h: material fields on disk (docs/heterogeneous.md §6):
 * OpenVDB float grids read into and written from a sampled field
 * (sss/field.h). Part of libsss_bake (input/fieldio.c, over the C++17
 * adapter input/vdb_io.cpp). The .vdb's world units are the object's
 * rest-frame millimetres; only axis-aligned uniform voxels are read.
 */
#ifndef SSS_FIELDIO_H
#define SSS_FIELDIO_H

#include "sss/field.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest .vdb file read (bytes). */
#define SSS_VDB_MAX_BYTES ((uint64_t)1 << 30)

/* Reads the float grid named `grid` of the .vdb file at path into *out (kind
 * grid): the dense block of its active voxels' bounding box, node (i, j, k)
 * at the voxel's centre in the grid's world space. Fails with one line
 * naming the file and the grid: not a .vdb, no such grid, not a float grid,
 * a rotated or non-uniform transform, no active voxel, a value outside
 * [0, 1], more than SSS_FIELD_GRID_MAX_NODES nodes. */
sss_result sss_field_load(const char *path, const char *grid, sss_field *out, sss_error *err);

/* Writes the grid field f (kind grid) as the float grid `grid` of a .vdb
 * file at path, atomically (sss/fileio.h). */
sss_result sss_field_write_vdb(const char *path, const char *grid, const sss_field *f, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
