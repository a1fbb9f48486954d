/* vdb_io.h: private C interface to the C++17 OpenVDB adapter (vdb_io.cpp).
 * Bytes in, bytes out: the files are opened and replaced by fieldio.c
 * through sss/fileio.h, as every other input and output.
 */
#ifndef SSS_VDB_IO_H
#define SSS_VDB_IO_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Parses a .vdb image and samples its float grid `grid` densely over the
 * active voxels' bounding box: *values (malloc'ed, x fastest), n, the first
 * node's world position and the voxel size. max_nodes bounds n0·n1·n2.
 * Returns 0, or -1 with one line in msg. Never throws. */
int sss_vdb_read(const char *data, size_t len, const char *grid, uint64_t max_nodes, float **values, uint32_t n[3],
                 double origin[3], double *voxel, char *msg, size_t msglen);

/* Builds a .vdb image holding one float grid `grid` (a fog volume) with the
 * dense values (x fastest), node (i, j, k) at origin + voxel · (i, j, k):
 * *out is malloc'ed. Returns 0, or -1 with one line in msg. Never throws. */
int sss_vdb_write(const float *values, const uint32_t n[3], const double origin[3], double voxel, const char *grid,
                  char **out, size_t *outlen, char *msg, size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
