/* refs_closest.h: private C interface to the C++17 CGAL adapter
 * (refs_closest.cpp): for each query vertex, the triangle of the simplified
 * mesh that holds its closest point (Hao–Varshney 2004 §4.2 projects every
 * vertex onto the simplified triangles). Only that file includes CGAL.
 */
#ifndef SSS_REFS_CLOSEST_H
#define SSS_REFS_CLOSEST_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Result of sss_cgal_closest_triangles. */
typedef enum sss_cgal_closest_status {
    SSS_CGAL_CLOSEST_OK = 0,
    SSS_CGAL_CLOSEST_NO_MEMORY,  /* std::bad_alloc */
    SSS_CGAL_CLOSEST_FAILED      /* bad argument or any other C++ exception; msg says which */
} sss_cgal_closest_status;

/* Triangles: ntri >= 1, corners tri[3t..3t+2] index pos (3 floats per
 * vertex, finite; the caller checks). Queries: nq vertex indices qv into pos.
 * Writes to out_tri[i] the index t of a triangle at the smallest Euclidean
 * distance from pos[qv[i]] (CGAL AABB tree over Simple_cartesian<double>
 * Triangle_3, closest_point_and_primitive; degenerate triangles act as their
 * longest edge). Queries run in parallel (OpenMP), each independently, so
 * the answer does not depend on the thread count. On failure msg (msglen
 * bytes, may be 0) holds one line. Never throws. */
sss_cgal_closest_status sss_cgal_closest_triangles(const float *pos, const uint32_t *tri, uint32_t ntri,
                                                   const uint32_t *qv, uint32_t nq, uint32_t *out_tri,
                                                   char *msg, size_t msglen);

#ifdef __cplusplus
}
#endif
#endif
