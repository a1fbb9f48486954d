// refs_closest.cpp: CGAL adapter for the projection step of the reference
// points (Hao–Varshney 2004 §4.2): every vertex that is not a reference is
// mapped to the simplified triangle holding its closest point.
//
// The paper finds the triangle by walking the simplified triangles around
// the vertex's parent in the simplification hierarchy and testing the
// projection against their edges. OpenMesh's decimater does not hand out that
// hierarchy, and a walk can miss when the projection falls outside every
// incident triangle; a global closest-point query cannot miss. CGAL's AABB
// tree answers it in O(log n) per vertex, with the internal KD-tree hint
// (accelerate_distance_queries) starting each search near the answer.
//
// Only the triangle index leaves this file: refs.c recomputes the closest
// point's barycentric weights itself (sss_refs_closest_weights), in double
// and with explicit handling of degenerate triangles, so CGAL's own rounding
// never reaches the stored weights.
//
// This is the only file in libsss_bake that includes CGAL headers (CMake
// builds it in its own object library, see precompute/CMakeLists.txt).

#include "compress/refs_closest.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <atomic>
#include <cstdint>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace {

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 Point;
typedef K::Triangle_3 Triangle;
typedef std::vector<Triangle>::const_iterator TriIt;
typedef CGAL::AABB_triangle_primitive<K, TriIt> Primitive;
typedef CGAL::AABB_traits<K, Primitive> Traits;
typedef CGAL::AABB_tree<Traits> Tree;

void set_msg(char *msg, std::size_t msglen, const std::string &s)
{
    if (!msg || msglen == 0) return;
    std::size_t n = s.size() < msglen - 1 ? s.size() : msglen - 1;
    std::memcpy(msg, s.data(), n);
    msg[n] = '\0';
}

Point point_of(const float *pos, uint32_t v)
{
    const float *p = pos + 3 * static_cast<std::size_t>(v);
    return Point(p[0], p[1], p[2]);
}

}  // namespace

extern "C" sss_cgal_closest_status sss_cgal_closest_triangles(const float *pos, const uint32_t *tri,
                                                              uint32_t ntri, const uint32_t *qv, uint32_t nq,
                                                              uint32_t *out_tri, char *msg, size_t msglen)
{
    set_msg(msg, msglen, std::string());
    if (nq == 0) return SSS_CGAL_CLOSEST_OK;
    if (!pos || !tri || ntri == 0 || !qv || !out_tri) {
        set_msg(msg, msglen, "sss_cgal_closest_triangles: no triangles or NULL argument");
        return SSS_CGAL_CLOSEST_FAILED;
    }
    try {
        std::vector<Triangle> tris;
        tris.reserve(ntri);
        for (uint32_t t = 0; t < ntri; t++) {
            const uint32_t *c = tri + 3 * static_cast<std::size_t>(t);
            tris.emplace_back(point_of(pos, c[0]), point_of(pos, c[1]), point_of(pos, c[2]));
        }
        Tree tree(tris.begin(), tris.end());
        // Build the tree and its KD-tree now: later const queries from
        // several threads then only read.
        tree.build();
        tree.accelerate_distance_queries();

        std::atomic<int> failed(0);
        const long n = static_cast<long>(nq);
#pragma omp parallel for schedule(static)
        for (long i = 0; i < n; i++) {
            try {
                auto cp = tree.closest_point_and_primitive(point_of(pos, qv[i]));
                out_tri[i] = static_cast<uint32_t>(cp.second - tris.begin());
            } catch (...) {
                // Exceptions cannot leave an OpenMP region; report after it.
                failed.store(1, std::memory_order_relaxed);
                out_tri[i] = 0;
            }
        }
        if (failed.load()) {
            set_msg(msg, msglen, "CGAL closest-point query failed");
            return SSS_CGAL_CLOSEST_FAILED;
        }
        return SSS_CGAL_CLOSEST_OK;
    } catch (const std::bad_alloc &) {
        set_msg(msg, msglen, "out of memory while building the AABB tree");
        return SSS_CGAL_CLOSEST_NO_MEMORY;
    } catch (const std::exception &e) {
        set_msg(msg, msglen, std::string("CGAL error: ") + e.what());
        return SSS_CGAL_CLOSEST_FAILED;
    } catch (...) {
        set_msg(msg, msglen, "CGAL error: unknown C++ exception");
        return SSS_CGAL_CLOSEST_FAILED;
    }
}
