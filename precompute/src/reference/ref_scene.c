/* ref_scene.c: the reference's mesh in mm behind Embree 3 closest-hit and
 * occlusion rays (the device and geometry set up as in
 * kernels/visibility.c), and the surface frames the walks need: the
 * geometric normal of a triangle, the shading normal interpolated from the
 * vertex normals with the hit's barycentrics (docs/reference.md §2). */
#include "reference/ref_internal.h"

#include <embree3/rtcore.h>
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/vec3.h"

void sss_ref_scene_destroy(sss_ref_scene *s)
{
    if (!s) return;
    if (s->scene) rtcReleaseScene((RTCScene)s->scene);
    if (s->device) rtcReleaseDevice((RTCDevice)s->device);
    free(s->pos);
    free(s->nrm);
    free(s->tri);
    free(s->ng);
    free(s);
}

sss_result sss_ref_scene_create(const sss_mesh *m, double mm_per_unit, sss_ref_scene **out, sss_error *err)
{
    *out = NULL;
    if (!m || !m->nrm || m->nf == 0 || m->nv == 0) return sss_fail(err, SSS_ERR_ARG, "reference: mesh without normals or triangles");
    if (mm_per_unit == 0.0) mm_per_unit = 1.0;
    if (!(mm_per_unit > 0.0) || !isfinite(mm_per_unit))
        return sss_fail(err, SSS_ERR_ARG, "reference: mm per unit %g must be a positive number", mm_per_unit);
    sss_ref_scene *s = calloc(1, sizeof *s);
    if (!s) return sss_fail(err, SSS_ERR_NOMEM, "reference: out of memory");
    s->nv = m->nv;
    s->nf = m->nf;
    s->mm_per_unit = mm_per_unit;
    s->pos = malloc(3 * sizeof(double) * m->nv);
    s->nrm = malloc(3 * sizeof(double) * m->nv);
    s->tri = malloc(3 * sizeof(uint32_t) * m->nf);
    s->ng = malloc(3 * sizeof(double) * m->nf);
    if (!s->pos || !s->nrm || !s->tri || !s->ng) {
        sss_ref_scene_destroy(s);
        return sss_fail(err, SSS_ERR_NOMEM, "reference: out of memory for %u vertices", m->nv);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, amax = 0.0;
    for (size_t i = 0; i < 3 * (size_t)m->nv; i++) {
        s->pos[i] = (double)m->pos[i] * mm_per_unit;
        s->nrm[i] = m->nrm[i];
        lo[i % 3] = fmin(lo[i % 3], s->pos[i]);
        hi[i % 3] = fmax(hi[i % 3], s->pos[i]);
        amax = fmax(amax, fabs(s->pos[i]));
    }
    memcpy(s->tri, m->tri, 3 * sizeof(uint32_t) * m->nf);
    for (uint32_t f = 0; f < m->nf; f++) {
        const uint32_t *t = &m->tri[3 * (size_t)f];
        if (t[0] >= m->nv || t[1] >= m->nv || t[2] >= m->nv) {
            sss_ref_scene_destroy(s);
            return sss_fail(err, SSS_ERR_MESH, "reference: triangle %u: vertex index out of range", f);
        }
        double e1[3], e2[3];
        sss_sub3(e1, &s->pos[3 * (size_t)t[1]], &s->pos[3 * (size_t)t[0]]);
        sss_sub3(e2, &s->pos[3 * (size_t)t[2]], &s->pos[3 * (size_t)t[0]]);
        sss_cross3(e1, e2, &s->ng[3 * (size_t)f]);
        sss_normalize3(&s->ng[3 * (size_t)f]);
    }
    double diag = 0.0;
    for (int k = 0; k < 3; k++) {
        s->centre[k] = 0.5 * (lo[k] + hi[k]);
        diag += (hi[k] - lo[k]) * (hi[k] - lo[k]);
    }
    diag = sqrt(diag);
    s->radius = 0.5 * diag;
    /* Embree intersects in float: a hit lies within a few ulps of the largest
     * coordinate of the surface, so rays leaving a surface skip that much */
    s->eps = fmax(1e-7 * diag, 16.0 * FLT_EPSILON * amax);

    RTCDevice dev = rtcNewDevice("verbose=0");
    if (!dev) {
        sss_ref_scene_destroy(s);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "reference: Embree device creation failed");
    }
    s->device = dev;
    RTCScene sc = rtcNewScene(dev);
    s->scene = sc;
    /* watertight rays: a ray through an edge or a vertex hits one of its
     * triangles, so no walk slips out of a closed mesh */
    rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m->nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m->nf);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        sss_ref_scene_destroy(s);
        return sss_fail(err, SSS_ERR_NOMEM, "reference: Embree buffers for %u triangles", m->nf);
    }
    for (size_t i = 0; i < 3 * (size_t)m->nv; i++) vb[i] = (float)s->pos[i];
    memcpy(ib, m->tri, 3 * sizeof(unsigned) * m->nf);
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sc);
    if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) {
        sss_ref_scene_destroy(s);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "reference: Embree scene build failed");
    }
    *out = s;
    return SSS_OK;
}

/* Barycentrics (b1, b2) of p in the plane of triangle f, by the
 * least-squares projection onto its edges (exact for p in the plane). */
static int barycentrics(const sss_ref_scene *s, uint32_t f, const double p[3], double *b1, double *b2)
{
    const uint32_t *t = &s->tri[3 * (size_t)f];
    double e1[3], e2[3], w[3];
    sss_sub3(e1, &s->pos[3 * (size_t)t[1]], &s->pos[3 * (size_t)t[0]]);
    sss_sub3(e2, &s->pos[3 * (size_t)t[2]], &s->pos[3 * (size_t)t[0]]);
    sss_sub3(w, p, &s->pos[3 * (size_t)t[0]]);
    const double a = sss_dot3(e1, e1), b = sss_dot3(e1, e2), c = sss_dot3(e2, e2);
    const double d = sss_dot3(w, e1), e = sss_dot3(w, e2), den = a * c - b * b;
    if (!(den > 0.0)) return 0;
    *b1 = (c * d - b * e) / den;
    *b2 = (a * e - b * d) / den;
    return 1;
}

int ref_shading_normal_at(const sss_ref_scene *s, uint32_t f, const double p[3], double n[3])
{
    double b1, b2;
    if (!barycentrics(s, f, p, &b1, &b2)) return 0;
    const double b0 = 1.0 - b1 - b2;
    const uint32_t *t = &s->tri[3 * (size_t)f];
    for (int k = 0; k < 3; k++)
        n[k] = b0 * s->nrm[3 * (size_t)t[0] + k] + b1 * s->nrm[3 * (size_t)t[1] + k] + b2 * s->nrm[3 * (size_t)t[2] + k];
    return sss_normalize3(n) > 0.0;
}

double ref_plane_t(const sss_ref_scene *s, uint32_t f, const double o[3], const double d[3])
{
    const double *ng = &s->ng[3 * (size_t)f];
    const double den = sss_dot3(d, ng);
    if (den == 0.0) return -1.0;
    double w[3];
    sss_sub3(w, &s->pos[3 * (size_t)s->tri[3 * (size_t)f]], o);
    return sss_dot3(w, ng) / den;
}

static void make_ray(struct RTCRay *r, const double o[3], const double d[3], double tnear)
{
    r->org_x = (float)o[0];
    r->org_y = (float)o[1];
    r->org_z = (float)o[2];
    r->dir_x = (float)d[0];
    r->dir_y = (float)d[1];
    r->dir_z = (float)d[2];
    r->tnear = (float)tnear;
    r->tfar = INFINITY;
    r->time = 0.0f;
    r->mask = 0xFFFFFFFFu;
    r->id = 0;
    r->flags = 0;
}

int ref_intersect(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, ref_hit *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    make_ray(&rh.ray, o, d, tnear);
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1((RTCScene)s->scene, &ctx, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
    const uint32_t f = rh.hit.primID;
    /* the distance along the float ray, the point on the double ray */
    h->t = rh.ray.tfar;
    for (int k = 0; k < 3; k++) {
        h->p[k] = o[k] + h->t * d[k];
        h->ng[k] = s->ng[3 * (size_t)f + k];
    }
    h->tri = f;
    const double u = rh.hit.u, v = rh.hit.v, w = 1.0 - u - v;
    const uint32_t *t = &s->tri[3 * (size_t)f];
    for (int k = 0; k < 3; k++)
        h->ns[k] = w * s->nrm[3 * (size_t)t[0] + k] + u * s->nrm[3 * (size_t)t[1] + k] + v * s->nrm[3 * (size_t)t[2] + k];
    if (!(sss_normalize3(h->ns) > 0.0))
        for (int k = 0; k < 3; k++) h->ns[k] = h->ng[k];
    return 1;
}

int ref_occluded(const sss_ref_scene *s, const double o[3], const double d[3], double tnear)
{
    return ref_occluded_upto(s, o, d, tnear, INFINITY);
}

int ref_occluded_upto(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, double tfar)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRay r;
    make_ray(&r, o, d, tnear);
    r.tfar = (float)tfar;
    rtcOccluded1((RTCScene)s->scene, &ctx, &r);
    return r.tfar < 0.0f;
}
