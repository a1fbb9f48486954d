/* visibility.c: V(x_i, ω_j), whether vertex x_i sees the light from ω_j.
 * Hao–Varshney 2004 §3.1 uses shadow maps; we trace exact occlusion rays
 * with Embree 3 against the mesh itself.
 *
 * Ray origin: x_i pushed off the surface along n_i by δ, and tnear = δ,
 * with δ = sss_mesh_ray_offset (1e-5 of the bounding-box diagonal, mesh
 * units: the one rule the viewer's near-term rays share), so a ray does not
 * hit the triangles that share x_i; a smaller δ lets grazing rays clip them.
 */
#include "sss/visibility.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sss_vis {
    RTCDevice device;
    RTCScene scene;
    const sss_mesh *mesh;
    float delta; /* origin offset, mesh units */
};

/* Adds one mesh to the Embree scene (Embree copies into its own buffers; it
 * may read 16 bytes past the last vertex, which its own allocation pads for). */
static int add_mesh(sss_vis *vis, const sss_mesh *mesh)
{
    RTCGeometry g = rtcNewGeometry(vis->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh->nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh->nf);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        return 0;
    }
    memcpy(vb, mesh->pos, (size_t)mesh->nv * 3 * sizeof(float));
    memcpy(ib, mesh->tri, (size_t)mesh->nf * 3 * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(vis->scene, g);
    rtcReleaseGeometry(g);
    return 1;
}

sss_result sss_vis_create_scene(const sss_mesh *mesh, int self, const sss_mesh *const *occ, uint32_t nocc,
                                sss_vis **out, sss_error *err)
{
    *out = NULL;
    if (!mesh->nrm || mesh->nf == 0) return sss_fail(err, SSS_ERR_ARG, "visibility: mesh without normals or triangles");
    sss_vis *vis = calloc(1, sizeof *vis);
    if (!vis) return sss_fail(err, SSS_ERR_NOMEM, "visibility: out of memory");
    vis->device = rtcNewDevice("verbose=0");
    if (!vis->device) {
        free(vis);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "visibility: Embree device creation failed");
    }
    vis->scene = rtcNewScene(vis->device);
    rtcSetSceneBuildQuality(vis->scene, RTC_BUILD_QUALITY_HIGH);
    int ok = !self || add_mesh(vis, mesh);
    for (uint32_t k = 0; k < nocc && ok; k++) ok = occ[k]->nf == 0 || add_mesh(vis, occ[k]);
    if (!ok) {
        sss_vis_destroy(vis);
        return sss_fail(err, SSS_ERR_NOMEM, "visibility: Embree buffers for %u triangles", mesh->nf);
    }
    rtcCommitScene(vis->scene);
    if (rtcGetDeviceError(vis->device) != RTC_ERROR_NONE) {
        sss_vis_destroy(vis);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "visibility: Embree scene build failed");
    }
    /* the offset depends on the object whose vertices cast the rays only,
     * so adding occluders does not move the origins */
    vis->delta = sss_mesh_ray_offset(mesh);
    vis->mesh = mesh;
    *out = vis;
    return SSS_OK;
}

sss_result sss_vis_create(const sss_mesh *mesh, sss_vis **out, sss_error *err)
{
    return sss_vis_create_scene(mesh, 1, NULL, 0, out, err);
}

void sss_vis_destroy(sss_vis *vis)
{
    if (!vis) return;
    if (vis->scene) rtcReleaseScene(vis->scene);
    if (vis->device) rtcReleaseDevice(vis->device);
    free(vis);
}

int sss_vis_occluded(const sss_vis *vis, uint32_t v, const double d[3])
{
    return sss_vis_occluded_upto(vis, v, d, INFINITY);
}

int sss_vis_occluded_upto(const sss_vis *vis, uint32_t v, const double d[3], double tfar)
{
    const float *p = &vis->mesh->pos[3 * (size_t)v], *n = &vis->mesh->nrm[3 * (size_t)v];
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay ray;
    ray.org_x = p[0] + vis->delta * n[0];
    ray.org_y = p[1] + vis->delta * n[1];
    ray.org_z = p[2] + vis->delta * n[2];
    ray.dir_x = (float)d[0];
    ray.dir_y = (float)d[1];
    ray.dir_z = (float)d[2];
    ray.tnear = vis->delta;
    ray.tfar = (float)tfar;
    ray.time = 0.0f;
    ray.mask = 0xFFFFFFFFu;
    ray.id = 0;
    ray.flags = 0;
    rtcOccluded1(vis->scene, &ctx, &ray);
    return ray.tfar < 0.0f; /* Embree sets tfar = −inf when blocked */
}

uint64_t sss_vis_lit_all(const sss_vis *vis, const sss_mesh *mesh, const double d[3], uint8_t *lit)
{
    uint64_t traced = 0;
#pragma omp parallel for schedule(dynamic, 1024) reduction(+ : traced)
    for (int64_t v = 0; v < (int64_t)mesh->nv; v++) {
        const float *n = mesh->nrm + 3 * (size_t)v;
        const int facing = n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0;
        traced += (uint64_t)facing;
        lit[v] = facing && !sss_vis_occluded(vis, (uint32_t)v, d);
    }
    return traced;
}
