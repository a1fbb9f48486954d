// vdb_io.cpp: the C++17 adapter between OpenVDB and the C field reader
// (fieldio.c, docs/heterogeneous.md §6). Everything OpenVDB throws is
// caught here and becomes one line of text; no C++ type crosses vdb_io.h.

#include "input/vdb_io.h"

#include <openvdb/openvdb.h>
#include <openvdb/io/Stream.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>
#include <string>

namespace {

void init_once()
{
    static std::once_flag once;
    std::call_once(once, [] { openvdb::initialize(); });
}

void say(char *msg, size_t n, const std::string &s)
{
    if (!msg || !n) return;
    std::snprintf(msg, n, "%s", s.c_str());
    for (char *p = msg; *p; p++)
        if (static_cast<unsigned char>(*p) < 0x20) *p = ' '; // one line, whatever the library said
}

} // namespace

extern "C" int sss_vdb_read(const char *data, size_t len, const char *grid, uint64_t max_nodes, float **values,
                            uint32_t n[3], double origin[3], double *voxel, char *msg, size_t msglen)
{
    *values = nullptr;
    try {
        init_once();
        std::istringstream in(std::string(data, len), std::ios::binary);
        // Read from this stream, not a delayed-load temporary file, and
        // throw at the first read past its end: OpenVDB's readers do not
        // check the stream, so a truncated file went on with lengths read
        // from a failed stream and built strings of gigabytes for 100 s
        // (docs/heterogeneous.md §6).
        in.exceptions(std::ios::failbit | std::ios::badbit);
        openvdb::io::Stream stream(in, false);
        openvdb::GridPtrVecPtr grids = stream.getGrids();
        openvdb::GridBase::Ptr base;
        for (const auto &g : *grids)
            if (g && g->getName() == grid) base = g;
        if (!base) {
            std::string names;
            for (const auto &g : *grids) names += (names.empty() ? "" : ", ") + (g ? g->getName() : std::string("?"));
            say(msg, msglen, std::string("grid '") + grid + "' not found (the file holds: " +
                                 (names.empty() ? "no grid" : names) + ")");
            return -1;
        }
        openvdb::FloatGrid::Ptr fg = openvdb::gridPtrCast<openvdb::FloatGrid>(base);
        if (!fg) {
            say(msg, msglen, std::string("grid '") + grid + "' holds " + base->valueType() + " values, not float");
            return -1;
        }
        const openvdb::math::Transform &xf = fg->transform();
        // only axis-aligned cubic voxels: node (i, j, k) = origin + voxel (i, j, k)
        const openvdb::Vec3d o = xf.indexToWorld(openvdb::Coord(0, 0, 0));
        const openvdb::Vec3d ex = xf.indexToWorld(openvdb::Coord(1, 0, 0)) - o,
                             ey = xf.indexToWorld(openvdb::Coord(0, 1, 0)) - o,
                             ez = xf.indexToWorld(openvdb::Coord(0, 0, 1)) - o;
        const double h = ex[0];
        const double tol = 1e-9 * std::fabs(h);
        if (!xf.isLinear() || !(h > 0.0) || std::fabs(ex[1]) > tol || std::fabs(ex[2]) > tol ||
            std::fabs(ey[0]) > tol || std::fabs(ey[1] - h) > tol || std::fabs(ey[2]) > tol || std::fabs(ez[0]) > tol ||
            std::fabs(ez[1]) > tol || std::fabs(ez[2] - h) > tol) {
            say(msg, msglen, std::string("grid '") + grid +
                                 "': its transform is not an axis-aligned uniform voxel size (only those are read)");
            return -1;
        }
        const openvdb::CoordBBox bb = fg->evalActiveVoxelBoundingBox();
        if (bb.empty()) {
            say(msg, msglen, std::string("grid '") + grid + "' has no active voxel");
            return -1;
        }
        const openvdb::Coord d = bb.dim();
        const uint64_t nn = static_cast<uint64_t>(d[0]) * static_cast<uint64_t>(d[1]) * static_cast<uint64_t>(d[2]);
        if (nn > max_nodes) {
            say(msg, msglen, std::string("grid '") + grid + "': " + std::to_string(d[0]) + " x " +
                                 std::to_string(d[1]) + " x " + std::to_string(d[2]) + " voxels, more than " +
                                 std::to_string(max_nodes));
            return -1;
        }
        float *v = static_cast<float *>(std::malloc(nn * sizeof(float)));
        if (!v) {
            say(msg, msglen, "out of memory for the grid's voxels");
            return -1;
        }
        auto acc = fg->getConstAccessor();
        size_t k = 0;
        for (int z = bb.min()[2]; z <= bb.max()[2]; z++)
            for (int y = bb.min()[1]; y <= bb.max()[1]; y++)
                for (int x = bb.min()[0]; x <= bb.max()[0]; x++) v[k++] = acc.getValue(openvdb::Coord(x, y, z));
        const openvdb::Vec3d w0 = xf.indexToWorld(bb.min());
        for (int a = 0; a < 3; a++) {
            n[a] = static_cast<uint32_t>(d[a]);
            origin[a] = w0[a];
        }
        *voxel = h;
        *values = v;
        return 0;
    } catch (const std::exception &e) {
        say(msg, msglen, std::string("not a readable OpenVDB file: ") + e.what());
    } catch (...) {
        say(msg, msglen, "not a readable OpenVDB file");
    }
    std::free(*values);
    *values = nullptr;
    return -1;
}

extern "C" int sss_vdb_write(const float *values, const uint32_t n[3], const double origin[3], double voxel,
                             const char *grid, char **out, size_t *outlen, char *msg, size_t msglen)
{
    *out = nullptr;
    *outlen = 0;
    try {
        init_once();
        openvdb::FloatGrid::Ptr g = openvdb::FloatGrid::create(0.0f);
        g->setName(grid);
        g->setGridClass(openvdb::GRID_FOG_VOLUME);
        openvdb::math::Transform::Ptr xf = openvdb::math::Transform::createLinearTransform(voxel);
        xf->postTranslate(openvdb::Vec3d(origin[0], origin[1], origin[2]));
        g->setTransform(xf);
        auto acc = g->getAccessor();
        size_t k = 0;
        for (uint32_t z = 0; z < n[2]; z++)
            for (uint32_t y = 0; y < n[1]; y++)
                for (uint32_t x = 0; x < n[0]; x++, k++)
                    acc.setValueOn(openvdb::Coord(static_cast<int>(x), static_cast<int>(y), static_cast<int>(z)),
                                   values[k]); // every node active, zeros too: the dense block is the field's box
        std::ostringstream os(std::ios::binary);
        openvdb::GridPtrVec grids{g};
        openvdb::io::Stream(os).write(grids);
        const std::string s = os.str();
        char *b = static_cast<char *>(std::malloc(s.size() ? s.size() : 1));
        if (!b) {
            say(msg, msglen, "out of memory for the .vdb image");
            return -1;
        }
        std::memcpy(b, s.data(), s.size());
        *out = b;
        *outlen = s.size();
        return 0;
    } catch (const std::exception &e) {
        say(msg, msglen, std::string("OpenVDB: ") + e.what());
    } catch (...) {
        say(msg, msglen, "OpenVDB: unknown failure");
    }
    return -1;
}
