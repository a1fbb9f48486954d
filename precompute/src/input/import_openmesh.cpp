// import_openmesh.cpp: the only C++ in libsss_bake. A thin adapter that lets
// OpenMesh's file readers (PLY, OBJ, OFF, STL) parse a file that import.c
// has already validated and canonicalised in memory, and hands the raw
// polygon soup back to C.
//
// Why a custom importer instead of reading into an OpenMesh::TriMesh: the
// TriMesh importer silently drops faces that would make the mesh
// non-manifold (and triangulates on its own); here every face the reader
// produces is recorded as it is, and import.c decides what to repair and
// reports it.
//
// OpenMesh's readers keep per-reader state in global singletons, and the
// capture of their messages redirects std::cerr, so reads are serialised with
// a mutex.

#include "input/import_openmesh.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/Options.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/IO/reader/OBJReader.hh>
#include <OpenMesh/Core/IO/reader/OFFReader.hh>
#include <OpenMesh/Core/IO/reader/PLYReader.hh>
#include <OpenMesh/Core/IO/reader/STLReader.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <istream>
#include <limits>
#include <mutex>
#include <new>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>

namespace {

using OpenMesh::EdgeHandle;
using OpenMesh::FaceHandle;
using OpenMesh::HalfedgeHandle;
using OpenMesh::VertexHandle;
using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
namespace Attr = OpenMesh::Attributes;

// Growable malloc'd array, so the result can be handed to C without a copy.
template <typename T>
struct CArray {
    T *data = nullptr;
    std::uint64_t size = 0, cap = 0;

    CArray() = default;
    CArray(const CArray &) = delete;
    CArray &operator=(const CArray &) = delete;
    ~CArray() { std::free(data); }

    void reserve(std::uint64_t n)
    {
        if (n <= cap) return;
        if (n > std::numeric_limits<std::size_t>::max() / sizeof(T)) throw std::bad_alloc();
        void *p = std::realloc(data, static_cast<std::size_t>(n) * sizeof(T));
        if (!p) throw std::bad_alloc();
        data = static_cast<T *>(p);
        cap = n;
    }
    void push(T v)
    {
        if (size == cap) reserve(cap < 16 ? 16 : cap + cap / 2);
        data[size++] = v;
    }
    T *release()
    {
        T *p = data;
        data = nullptr;
        size = cap = 0;
        return p;
    }
};

// Records vertices and faces exactly as the reader delivers them; every other
// attribute (normals, colours, texture coordinates, status) is ignored.
class SoupImporter final : public OpenMesh::IO::BaseImporter {
public:
    explicit SoupImporter(std::uint64_t size_hint) : hint_(size_hint) {}

    CArray<float> pos;
    CArray<std::int32_t> idx;
    CArray<std::uint32_t> fsize;

    VertexHandle add_vertex(const Vec3f &p) override
    {
        if (n_vertices() >= static_cast<std::size_t>(std::numeric_limits<int>::max()))
            throw std::length_error("more vertices than an OpenMesh handle can address");
        pos.push(p[0]);
        pos.push(p[1]);
        pos.push(p[2]);
        return VertexHandle(static_cast<int>(n_vertices() - 1));
    }
    VertexHandle add_vertex(const Vec3d &p) override
    {
        return add_vertex(Vec3f(static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])));
    }
    VertexHandle add_vertex() override { return add_vertex(Vec3f(0.0f, 0.0f, 0.0f)); }

    FaceHandle add_face(const VHandles &v) override
    {
        if (v.size() > std::numeric_limits<std::uint32_t>::max())
            throw std::length_error("face with more than 2^32 vertices");
        if (n_faces() >= static_cast<std::size_t>(std::numeric_limits<int>::max()))
            throw std::length_error("more faces than an OpenMesh handle can address");
        for (const VertexHandle &h : v) idx.push(h.idx());
        fsize.push(static_cast<std::uint32_t>(v.size()));
        return FaceHandle(static_cast<int>(n_faces() - 1));
    }

    void set_point(VertexHandle vh, const Vec3f &p) override
    {
        if (!vh.is_valid() || static_cast<std::size_t>(vh.idx()) >= n_vertices()) return;
        std::size_t i = 3 * static_cast<std::size_t>(vh.idx());
        pos.data[i] = p[0];
        pos.data[i + 1] = p[1];
        pos.data[i + 2] = p[2];
    }

    void reserve(unsigned int nV, unsigned int /*nE*/, unsigned int nF) override
    {
        // Counts come from the file's header; import.c checked them against
        // the file's size, and the hint caps them once more.
        std::uint64_t v = nV < hint_ ? nV : hint_, f = nF < hint_ ? nF : hint_;
        pos.reserve(3 * v);
        fsize.reserve(f);
        idx.reserve(3 * f);
    }

    std::size_t n_vertices() const override { return static_cast<std::size_t>(pos.size / 3); }
    std::size_t n_faces() const override { return static_cast<std::size_t>(fsize.size); }
    std::size_t n_edges() const override { return 0; }

    // Unused by a soup: accepted and ignored.
    HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
    FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f> &) override {}
    void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f> &) override {}
    void set_face_texindex(FaceHandle, int) override {}
    void set_halfedge(VertexHandle, HalfedgeHandle) override {}
    void set_normal(VertexHandle, const Vec3f &) override {}
    void set_normal(VertexHandle, const Vec3d &) override {}
    void set_color(VertexHandle, const Vec3uc &) override {}
    void set_color(VertexHandle, const Vec4uc &) override {}
    void set_color(VertexHandle, const Vec3f &) override {}
    void set_color(VertexHandle, const Vec4f &) override {}
    void set_texcoord(VertexHandle, const Vec2f &) override {}
    void set_status(VertexHandle, const Attr::StatusInfo &) override {}
    void set_next(HalfedgeHandle, HalfedgeHandle) override {}
    void set_face(HalfedgeHandle, FaceHandle) override {}
    void request_face_texcoords2D() override {}
    void set_texcoord(HalfedgeHandle, const Vec2f &) override {}
    void set_texcoord(VertexHandle, const Vec3f &) override {}
    void set_texcoord(HalfedgeHandle, const Vec3f &) override {}
    void set_status(HalfedgeHandle, const Attr::StatusInfo &) override {}
    void set_color(EdgeHandle, const Vec3uc &) override {}
    void set_color(EdgeHandle, const Vec4uc &) override {}
    void set_color(EdgeHandle, const Vec3f &) override {}
    void set_color(EdgeHandle, const Vec4f &) override {}
    void set_status(EdgeHandle, const Attr::StatusInfo &) override {}
    void set_normal(FaceHandle, const Vec3f &) override {}
    void set_normal(FaceHandle, const Vec3d &) override {}
    void set_color(FaceHandle, const Vec3uc &) override {}
    void set_color(FaceHandle, const Vec4uc &) override {}
    void set_color(FaceHandle, const Vec3f &) override {}
    void set_color(FaceHandle, const Vec4f &) override {}
    void set_status(FaceHandle, const Attr::StatusInfo &) override {}
    void add_texture_information(int, std::string) override {}

private:
    std::uint64_t hint_;
};

// Read-only, seekable stream buffer over memory (the readers seek: the PLY
// reader back to the start of binary data, the OBJ reader to the beginning
// for its second pass).
class MemBuf final : public std::streambuf {
public:
    MemBuf(const char *data, std::size_t len)
    {
        char *p = const_cast<char *>(data);
        setg(p, p, p + len);
    }

protected:
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode which) override
    {
        if (!(which & std::ios_base::in)) return pos_type(off_type(-1));
        off_type base;
        if (dir == std::ios_base::beg) base = 0;
        else if (dir == std::ios_base::cur) base = gptr() - eback();
        else base = egptr() - eback();
        off_type target = base + off;
        if (target < 0 || target > egptr() - eback()) return pos_type(off_type(-1));
        setg(eback(), eback() + target, egptr());
        return pos_type(target);
    }
    pos_type seekpos(pos_type p, std::ios_base::openmode which) override
    {
        return seekoff(off_type(p), std::ios_base::beg, which);
    }
};

// Restores std::cerr's buffer however the read ends.
class CerrCapture {
public:
    explicit CerrCapture(std::streambuf *to) : old_(std::cerr.rdbuf(to)) {}
    ~CerrCapture() { std::cerr.rdbuf(old_); }
    CerrCapture(const CerrCapture &) = delete;
    CerrCapture &operator=(const CerrCapture &) = delete;

private:
    std::streambuf *old_;
};

std::mutex g_read_mutex;

// Once per process: make sure the reader singletons exist (they register
// themselves with the IOManager in their constructors; referencing them also
// keeps them in a static link) and silence OpenMesh's informational streams.
// omerr stays enabled: it writes to std::cerr, which is redirected into a
// string for the duration of each read, so its messages end up in our error
// line instead of on the terminal. (mostream::disconnect would leak its
// target object, so omerr is not re-targeted.)
void init_openmesh_io()
{
    (void)OpenMesh::IO::PLYReader();
    (void)OpenMesh::IO::OBJReader();
    (void)OpenMesh::IO::OFFReader();
    (void)OpenMesh::IO::STLReader();
    omlog().disable();
    omout().disable();
}

void set_msg(char *msg, std::size_t msglen, const std::string &s)
{
    if (!msg || msglen == 0) return;
    std::size_t n = s.size() < msglen - 1 ? s.size() : msglen - 1;
    std::memcpy(msg, s.data(), n);
    msg[n] = '\0';
}

// First non-empty line of captured reader output, trimmed.
std::string first_line(const std::string &s)
{
    std::istringstream in(s);
    std::string line;
    while (std::getline(in, line)) {
        std::size_t a = line.find_first_not_of(" \t\r");
        if (a == std::string::npos) continue;
        std::size_t b = line.find_last_not_of(" \t\r");
        return line.substr(a, b - a + 1);
    }
    return std::string();
}

const char *format_ext(sss_om_format fmt)
{
    switch (fmt) {
    case SSS_OM_PLY: return "ply";
    case SSS_OM_OBJ: return "obj";
    case SSS_OM_OFF: return "off";
    case SSS_OM_STL_ASCII:
    case SSS_OM_STL_BINARY: return "stl";
    }
    return "";
}

}  // namespace

extern "C" sss_om_status sss_om_read(const char *data, std::size_t len, sss_om_format fmt,
                                     sss_om_soup *out, char *msg, std::size_t msglen)
{
    if (out) std::memset(out, 0, sizeof *out);
    set_msg(msg, msglen, std::string());
    try {
        static std::once_flag once;
        std::call_once(once, init_openmesh_io);
        std::lock_guard<std::mutex> lock(g_read_mutex);

        std::ostringstream cerr_text;

        // Hint for reserve(): no element can take less than 2 bytes of file.
        SoupImporter imp(len / 2 + 16);
        OpenMesh::IO::Options opt;  // positions and faces only
        if (fmt == SSS_OM_STL_BINARY) opt += OpenMesh::IO::Options::Binary;

        MemBuf buf(data, len);
        std::istream in(&buf);
        bool ok;
        {
            CerrCapture cap(cerr_text.rdbuf());
            ok = OpenMesh::IO::IOManager().read(in, format_ext(fmt), imp, opt);
            omerr().flush();
        }
        if (!ok) {
            std::string why = first_line(cerr_text.str());
            set_msg(msg, msglen, "the OpenMesh " + std::string(format_ext(fmt)) + " reader failed" +
                                     (why.empty() ? std::string() : ": " + why));
            return SSS_OM_READ_FAILED;
        }
        if (out) {
            out->nv = imp.pos.size / 3;
            out->nidx = imp.idx.size;
            out->nf = imp.fsize.size;
            out->pos = imp.pos.release();
            out->idx = imp.idx.release();
            out->fsize = imp.fsize.release();
        }
        return SSS_OM_OK;
    } catch (const std::bad_alloc &) {
        set_msg(msg, msglen, "out of memory while reading");
        return SSS_OM_NO_MEMORY;
    } catch (const std::exception &e) {
        set_msg(msg, msglen, std::string("reader error: ") + e.what());
        return SSS_OM_EXCEPTION;
    } catch (...) {
        set_msg(msg, msglen, "reader error: unknown C++ exception");
        return SSS_OM_EXCEPTION;
    }
}

extern "C" void sss_om_soup_free(sss_om_soup *s)
{
    if (!s) return;
    std::free(s->pos);
    std::free(s->idx);
    std::free(s->fsize);
    std::free(s->uv);
    std::free(s->rgba);
    std::memset(s, 0, sizeof *s);
}
