// refs_decimate.cpp: OpenMesh adapter that picks the reference points of
// Hao–Varshney 2004 §4.2 by mesh simplification.
//
// The paper builds reference points "using a mesh simplification algorithm
// similar to [...] Garland and Heckbert [1997]" and prefers them to be "a
// subset of the original vertices to reduce the storage overhead" (§4.2,
// Fig. 8). OpenMesh's DecimaterT does exactly that with ModQuadricT: every
// step is a half-edge collapse v0 → v1 that deletes v0 and leaves v1 where it
// was, ranked by the Garland–Heckbert quadric error at v1, so the survivors
// are original vertices at their original positions. ModNormalFlippingT
// vetoes collapses that would turn a face over (fold-overs would make the
// later closest-point projection pick triangles on the wrong side).
//
// Non-manifold input: TriMesh::add_face refuses a face that would create a
// complex edge or vertex, printing a line to omerr. Each face is tested first
// with the same checks (see can_add_face), so refused faces are counted and
// simply left out of the simplification input, and nothing is printed; the
// closest-point step in refs.c still maps every original vertex.

#include "refs_decimate.h"

// OpenMesh's PropertyT<Vec3d>::push_back appends a default-constructed,
// deliberately uninitialised VectorT that add_vertex then overwrites; GCC 12
// at -O2 reports that copy as -Wmaybe-uninitialized inside libstdc++. The
// pragma covers the headers first included here (libstdc++'s allocator among
// them), where those instantiations are located.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>

namespace {

// Double points and normals: the quadrics are accumulated in double anyway,
// and the normal-flip test compares normals of thin faces.
struct DTraits : public OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3d Point;
    typedef OpenMesh::Vec3d Normal;
};
typedef OpenMesh::TriMesh_ArrayKernelT<DTraits> Mesh;
typedef OpenMesh::Decimater::DecimaterT<Mesh> Decimater;
typedef OpenMesh::Decimater::ModQuadricT<Mesh>::Handle HQuadric;
typedef OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle HNormalFlip;

using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;

void set_msg(char *msg, std::size_t msglen, const std::string &s)
{
    if (!msg || msglen == 0) return;
    std::size_t n = s.size() < msglen - 1 ? s.size() : msglen - 1;
    std::memcpy(msg, s.data(), n);
    msg[n] = '\0';
}

// True when PolyConnectivity::add_face would accept the triangle v[0..2]:
// the same three tests in the same order as OpenMesh 9's add_face, without
// modifying the mesh: every vertex on a boundary (or isolated) ("complex
// vertex"), every existing edge with a free side in this orientation
// ("complex edge"), and where two consecutive edges exist but are not
// consecutive around their shared vertex, another boundary gap at that vertex
// to move the patch in between into ("patch re-linking failed"). The
// re-linking add_face does for one corner only touches the halfedges entering
// that corner, so testing the corners independently is exact.
bool can_add_face(const Mesh &mesh, const VertexHandle v[3])
{
    HalfedgeHandle he[3];
    bool is_new[3];
    for (int i = 0; i < 3; i++) {
        if (!mesh.is_boundary(v[i])) return false;  // complex vertex
        he[i] = mesh.find_halfedge(v[i], v[(i + 1) % 3]);
        is_new[i] = !he[i].is_valid();
        if (!is_new[i] && !mesh.is_boundary(he[i])) return false;  // complex edge
    }
    for (int i = 0; i < 3; i++) {
        int ii = (i + 1) % 3;
        if (is_new[i] || is_new[ii]) continue;
        HalfedgeHandle inner_prev = he[i], inner_next = he[ii];
        if (mesh.next_halfedge_handle(inner_prev) == inner_next) continue;
        HalfedgeHandle boundary_prev = mesh.opposite_halfedge_handle(inner_next);
        do
            boundary_prev = mesh.opposite_halfedge_handle(mesh.next_halfedge_handle(boundary_prev));
        while (!mesh.is_boundary(boundary_prev));
        if (boundary_prev == inner_prev) return false;  // patch re-linking would fail
    }
    return true;
}

}  // namespace

extern "C" sss_om_decimate_status sss_om_decimate(const float *pos, uint32_t nv, const uint32_t *tri,
                                                  uint32_t nf, uint32_t target, uint32_t **out_tri,
                                                  uint32_t *out_nf, uint32_t *rejected, char *msg,
                                                  size_t msglen)
{
    if (out_tri) *out_tri = nullptr;
    if (out_nf) *out_nf = 0;
    if (rejected) *rejected = 0;
    set_msg(msg, msglen, std::string());
    if (!pos || !tri || !out_tri || !out_nf || !rejected) {
        set_msg(msg, msglen, "sss_om_decimate: NULL argument");
        return SSS_OM_DECIMATE_FAILED;
    }
    if (nv >= static_cast<uint32_t>(std::numeric_limits<int>::max()) ||
        nf >= static_cast<uint32_t>(std::numeric_limits<int>::max() / 3)) {
        set_msg(msg, msglen, "mesh too large for OpenMesh handles");
        return SSS_OM_DECIMATE_FAILED;
    }
    try {
        Mesh mesh;
        // Status flags (deleted) outlive the decimater: it requests them too
        // and releases its reference when destroyed; ours keeps them.
        mesh.request_vertex_status();
        mesh.request_edge_status();
        mesh.request_face_status();
        // Edges ≈ 1.5 faces on a closed manifold; a hint only.
        mesh.reserve(nv, nf + nf / 2 + 3, nf);
        // Vertices in order, all of them (also those no face uses: they stay
        // isolated and are never collapsed), so handle index = original
        // index. Collapses only mark elements deleted and garbage_collection()
        // is never called, so that identity holds to the end and no index
        // property is needed.
        for (uint32_t i = 0; i < nv; i++) {
            const float *p = pos + 3 * static_cast<std::size_t>(i);
            mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
        }
        uint32_t nrej = 0;
        for (uint32_t f = 0; f < nf; f++) {
            const uint32_t *t = tri + 3 * static_cast<std::size_t>(f);
            VertexHandle v[3] = {VertexHandle(static_cast<int>(t[0])), VertexHandle(static_cast<int>(t[1])),
                                 VertexHandle(static_cast<int>(t[2]))};
            if (!can_add_face(mesh, v) || !mesh.add_face(v[0], v[1], v[2]).is_valid()) nrej++;
        }
        *rejected = nrej;

        uint32_t nconn = 0;
        for (auto vh : mesh.vertices())
            if (!mesh.is_isolated(vh)) nconn++;

        if (mesh.n_faces() > 0 && nconn > target) {
            mesh.request_face_normals();
            mesh.update_face_normals();
            Decimater dec(mesh);
            HQuadric hq;
            HNormalFlip hn;
            dec.add(hq);
            dec.add(hn);
            // No error bound: the quadric only ranks; the count stops it.
            dec.module(hq).unset_max_err();
            if (!dec.initialize()) {
                set_msg(msg, msglen, "OpenMesh decimater did not initialise");
                return SSS_OM_DECIMATE_FAILED;
            }
            dec.decimate(static_cast<std::size_t>(nconn - target));
        }

        std::size_t nout = 0;
        for (auto fh : mesh.faces())
            if (!mesh.status(fh).deleted()) nout++;
        uint32_t *t = nullptr;
        if (nout > 0) {
            t = static_cast<uint32_t *>(std::malloc(3 * nout * sizeof *t));
            if (!t) throw std::bad_alloc();
            std::size_t k = 0;
            for (auto fh : mesh.faces()) {
                if (mesh.status(fh).deleted()) continue;
                for (auto vh : mesh.fv_range(fh)) t[k++] = static_cast<uint32_t>(vh.idx());
            }
        }
        *out_tri = t;
        *out_nf = static_cast<uint32_t>(nout);
        return SSS_OM_DECIMATE_OK;
    } catch (const std::bad_alloc &) {
        set_msg(msg, msglen, "out of memory while decimating");
        return SSS_OM_DECIMATE_NO_MEMORY;
    } catch (const std::exception &e) {
        set_msg(msg, msglen, std::string("OpenMesh decimation error: ") + e.what());
        return SSS_OM_DECIMATE_FAILED;
    } catch (...) {
        set_msg(msg, msglen, "OpenMesh decimation error: unknown C++ exception");
        return SSS_OM_DECIMATE_FAILED;
    }
}
