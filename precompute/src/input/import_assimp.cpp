// import_assimp.cpp: a thin adapter that lets Assimp's glTF 2.0 reader parse
// the canonical GLB import_gltf.c has written after checking the file, and
// hands back one polygon soup of the whole scene in world space
// (import_assimp.h). Assimp composes each node's transform from its matrix
// or translation, rotation and scale; the products down the hierarchy and
// the positions are computed here, in double.

#include "input/import_assimp.h"

#include <assimp/Importer.hpp>
#include <assimp/scene.h>

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>

namespace {

struct Mat {
    double m[4][4];
};

Mat from_ai(const aiMatrix4x4 &a)
{
    const float *p = &a.a1; // row-major, 16 floats
    Mat r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) r.m[i][j] = p[4 * i + j];
    return r;
}

Mat mul(const Mat &a, const Mat &b)
{
    Mat r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) s += a.m[i][k] * b.m[k][j];
            r.m[i][j] = s;
        }
    return r;
}

struct Walk {
    const aiScene *scene;
    sss_om_soup *out;
    bool count_only;
    std::uint64_t nv = 0, nf = 0;
    bool uv = false, rgba = false;
    const char *error = nullptr;
};

void set_msg(char *msg, size_t msglen, const char *text)
{
    if (msglen) std::snprintf(msg, msglen, "%s", text);
}

// Depth-first, children in order; the scanner bounds the depth.
void walk(Walk &w, const aiNode *n, const Mat &parent)
{
    const Mat world = mul(parent, from_ai(n->mTransformation));
    for (unsigned i = 0; i < n->mNumMeshes && !w.error; i++) {
        if (n->mMeshes[i] >= w.scene->mNumMeshes) { w.error = "a node names a mesh that does not exist"; return; }
        const aiMesh *m = w.scene->mMeshes[n->mMeshes[i]];
        if (w.count_only) {
            w.nv += m->mNumVertices;
            w.nf += m->mNumFaces;
            w.uv = w.uv || m->HasTextureCoords(0);
            w.rgba = w.rgba || m->HasVertexColors(0);
            continue;
        }
        sss_om_soup *s = w.out;
        const std::uint64_t base = w.nv;
        for (unsigned v = 0; v < m->mNumVertices; v++) {
            const aiVector3D &p = m->mVertices[v];
            const double x[4] = {p.x, p.y, p.z, 1.0};
            for (int k = 0; k < 3; k++) {
                double t = 0.0;
                for (int j = 0; j < 4; j++) t += world.m[k][j] * x[j];
                // beyond float's range is infinite (then refused by the
                // repair's finite check), not an undefined conversion
                s->pos[3 * (base + v) + (unsigned)k] =
                    std::fabs(t) <= FLT_MAX ? (float)t : t > 0 ? HUGE_VALF : t < 0 ? -HUGE_VALF : NAN;
            }
            if (s->uv) {
                const bool has = m->HasTextureCoords(0);
                s->uv[2 * (base + v)] = has ? m->mTextureCoords[0][v].x : 0.0f;
                s->uv[2 * (base + v) + 1] = has ? m->mTextureCoords[0][v].y : 0.0f;
            }
            if (s->rgba) {
                const bool has = m->HasVertexColors(0);
                const aiColor4D c = has ? m->mColors[0][v] : aiColor4D(1.0f, 1.0f, 1.0f, 1.0f);
                float *q = s->rgba + 4 * (base + v);
                q[0] = c.r; q[1] = c.g; q[2] = c.b; q[3] = c.a;
            }
        }
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            const aiFace &fa = m->mFaces[f];
            if (fa.mNumIndices != 3) { w.error = "Assimp delivered a face that is not a triangle"; return; }
            for (int k = 0; k < 3; k++) {
                if (fa.mIndices[k] >= m->mNumVertices) { w.error = "Assimp delivered an index out of range"; return; }
                s->idx[3 * (w.nf + f) + (unsigned)k] = (std::int32_t)(base + fa.mIndices[k]);
            }
            s->fsize[w.nf + f] = 3;
        }
        w.nv += m->mNumVertices;
        w.nf += m->mNumFaces;
    }
    for (unsigned c = 0; c < n->mNumChildren && !w.error; c++) walk(w, n->mChildren[c], world);
}

} // namespace

extern "C" sss_om_status sss_ai_read(const char *data, size_t len, sss_om_format, sss_om_soup *out, char *msg,
                                     size_t msglen)
{
    std::memset(out, 0, sizeof *out);
    if (msglen) msg[0] = 0;
    try {
        Assimp::Importer imp;
        // no post-processing: the scanner has made every primitive indexed
        // triangles, and the toolkit recomputes normals itself
        const aiScene *sc = imp.ReadFileFromMemory(data, len, 0, "glb");
        if (!sc || !sc->mRootNode) {
            if (msglen) std::snprintf(msg, msglen, "Assimp: %s", imp.GetErrorString());
            return SSS_OM_READ_FAILED;
        }
        Mat id{};
        for (int i = 0; i < 4; i++) id.m[i][i] = 1.0;
        Walk w;
        w.scene = sc;
        w.out = out;
        w.count_only = true;
        walk(w, sc->mRootNode, id);
        if (!w.error && w.nv > (std::uint64_t)INT32_MAX) w.error = "more than 2^31-1 vertices";
        if (w.error) {
            set_msg(msg, msglen, w.error);
            return SSS_OM_READ_FAILED;
        }
        out->pos = static_cast<float *>(std::malloc(3 * w.nv * sizeof(float) + 1));
        out->idx = static_cast<std::int32_t *>(std::malloc(3 * w.nf * sizeof(std::int32_t) + 1));
        out->fsize = static_cast<std::uint32_t *>(std::malloc(w.nf * sizeof(std::uint32_t) + 1));
        if (w.uv) out->uv = static_cast<float *>(std::malloc(2 * w.nv * sizeof(float) + 1));
        if (w.rgba) out->rgba = static_cast<float *>(std::malloc(4 * w.nv * sizeof(float) + 1));
        if (!out->pos || !out->idx || !out->fsize || (w.uv && !out->uv) || (w.rgba && !out->rgba)) throw std::bad_alloc();
        Walk fill;
        fill.scene = sc;
        fill.out = out;
        fill.count_only = false;
        walk(fill, sc->mRootNode, id);
        if (fill.error) {
            set_msg(msg, msglen, fill.error);
            sss_om_soup_free(out);
            return SSS_OM_READ_FAILED;
        }
        out->nv = fill.nv;
        out->nf = fill.nf;
        out->nidx = 3 * fill.nf;
        return SSS_OM_OK;
    } catch (const std::bad_alloc &) {
        sss_om_soup_free(out);
        set_msg(msg, msglen, "out of memory");
        return SSS_OM_NO_MEMORY;
    } catch (const std::exception &e) {
        sss_om_soup_free(out);
        if (msglen) std::snprintf(msg, msglen, "Assimp: %s", e.what());
        return SSS_OM_EXCEPTION;
    } catch (...) {
        sss_om_soup_free(out);
        set_msg(msg, msglen, "Assimp: unknown exception");
        return SSS_OM_EXCEPTION;
    }
}
