/* thickness.c: parts thinner than the scattering range (docs/robustness.md
 * B8).
 *
 * Hao & Varshney 2004 gather light from every vertex within range measured
 * in 3-D (§2.2, §3.1), and weigh it with the dipole of a semi-infinite
 * medium (Jensen et al. 2001). Where the object is thinner than the range,
 * light entering the far face is gathered through the part (translucency,
 * wanted), but each face still counts the full half-space profile, so
 * energy is counted twice: a 4 mm slab with sigma_a = 0 reflects and
 * transmits 1.7x what enters it. The model stays as the paper has it; the
 * bake measures how much of the mesh is affected and the tool warns.
 *
 * Thickness at a vertex: one ray from just inside the surface (the vertex
 * moved by delta against its normal, delta as in visibility.c) along -n to
 * the first triangle hit. Open surfaces where the ray leaves the mesh have
 * no thickness (infinite). The scene is built here, before the
 * neighbourhoods, and freed at once, so it does not add to the bake's peak
 * memory (visibility builds its own later).
 */
#include "kernels/thickness.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>


sss_result sss_thin_count(const sss_mesh *mesh, double limit, const sss_cancel_flag *cancel, uint32_t *count,
                          double *thinnest, sss_error *err)
{
    *count = 0;
    *thinnest = INFINITY;
    if (!mesh->nrm || mesh->nf == 0 || !(limit > 0.0)) return SSS_OK;
    RTCDevice dev = rtcNewDevice("verbose=0");
    if (!dev) return sss_fail(err, SSS_ERR_UNSUPPORTED, "thickness: Embree device creation failed");
    RTCScene scene = rtcNewScene(dev);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh->nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh->nf);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
        return sss_fail(err, SSS_ERR_NOMEM, "thickness: Embree buffers for %u triangles", mesh->nf);
    }
    memcpy(vb, mesh->pos, (size_t)mesh->nv * 3 * sizeof(float));
    memcpy(ib, mesh->tri, (size_t)mesh->nf * 3 * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        rtcReleaseScene(scene);
        rtcReleaseDevice(dev);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "thickness: Embree scene build failed");
    }
    const float delta = sss_mesh_ray_offset(mesh);
    uint64_t n = 0;
    double best = INFINITY;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : n) reduction(min : best)
    for (int64_t vi = 0; vi < (int64_t)mesh->nv; vi++) {
        if (sss_cancelled(cancel)) continue; /* the rest is skipped quickly */
        const float *p = &mesh->pos[3 * (size_t)vi], *nr = &mesh->nrm[3 * (size_t)vi];
        if (nr[0] == 0.0f && nr[1] == 0.0f && nr[2] == 0.0f) continue; /* normals cancel: no inside */
        struct RTCIntersectContext ctx;
        rtcInitIntersectContext(&ctx);
        struct RTCRayHit rh;
        memset(&rh, 0, sizeof rh);
        rh.ray.org_x = p[0] - delta * nr[0];
        rh.ray.org_y = p[1] - delta * nr[1];
        rh.ray.org_z = p[2] - delta * nr[2];
        rh.ray.dir_x = -nr[0];
        rh.ray.dir_y = -nr[1];
        rh.ray.dir_z = -nr[2];
        rh.ray.tnear = delta;
        rh.ray.tfar = INFINITY;
        rh.ray.mask = 0xFFFFFFFFu;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        /* from the vertex: the origin is delta inside */
        const double t = (double)rh.ray.tfar + delta;
        if (t < best) best = t;
        if (t < limit) n++;
    }
    rtcReleaseScene(scene);
    rtcReleaseDevice(dev);
    if (sss_cancelled(cancel)) return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted while measuring thickness");
    *count = (uint32_t)n;
    *thinnest = best;
    return SSS_OK;
}
