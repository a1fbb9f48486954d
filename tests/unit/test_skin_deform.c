/* test_skin_deform.c: the scene's "skin" deformer (sss/skin.h, sss/deform.h,
 * docs/deformable.md §2): a bone chain given in the rest frame, weights
 * from the rest distances to the bones, linear blend skinning shared with
 * the glTF importer. Checked here: the rest pose bit for bit where every
 * angle is 0; one bone turns the mesh rigidly (distances and normals);
 * along a two-bone chain the vertices near the first bone's head follow
 * bone 0 and those near the second's tail follow bone 0 then bone 1, each
 * against rotations computed here; the weights' properties; the glTF
 * tube's clip agrees outside both blend zones; the per-frame path's exact
 * mode equals the exact evaluator on a skinned pose; determinism; and the
 * one-line refusals with the JSON path. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "genmesh.h"
#include "gltf_write.h"
#include "sss/deform.h"
#include "sss/exact.h"
#include "sss/format.h"
#include "sss/import.h"
#include "sss/perframe.h"
#include "sss/scene.h"
#include "sss/skin.h"
#include "sss/vec3.h"

/* The tube of docs/deformable.md §5 (radius 0.125, length 1 along z from
 * −0.5 to 0.5, 16 × 16 segments). */
static sss_mesh tube_or_fail(void)
{
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_tube(&m, 0.125, 1.0, 16, 16, &err) != SSS_OK) fail_msg("%s", err.msg);
    return m;
}

static sss_skin_bone bone(double hz, double tz, int parent, double ax, double ay, double az, double deg)
{
    sss_skin_bone b = {{0, 0, hz}, {0, 0, tz}, parent, {ax, ay, az}, deg, 4.0};
    return b;
}

/* The two-bone chain along the tube: bone 0 from the bottom to the middle
 * turning about +y by a0, bone 1 from the middle to the top, its child,
 * turning about +x by a1. */
static sss_deform chain(double a0, double a1)
{
    sss_deform d;
    memset(&d, 0, sizeof d);
    d.kind = SSS_DEFORM_SKIN;
    d.skin.nbones = 2;
    d.skin.bone[0] = bone(-0.5, 0.0, -1, 0, 1, 0, a0);
    d.skin.bone[1] = bone(0.0, 0.5, 0, 1, 0, 0, a1);
    return d;
}

static sss_mesh pose_or_fail(const sss_deform *d, double t, const sss_mesh *rest)
{
    sss_mesh out;
    sss_error err = {{0}};
    if (sss_deform_pose(d, t, rest, "tube", &out, &err) != SSS_OK) fail_msg("%s", err.msg);
    return out;
}

/* y = R(a, θ)(x − c) + c by Rodrigues' formula, written out here apart
 * from skin.c's matrices. */
static void turn(const double a[3], double theta, const double c[3], const double x[3], double y[3])
{
    double v[3], axv[3];
    sss_sub3(v, x, c);
    sss_cross3(a, v, axv);
    const double cs = cos(theta), sn = sin(theta), av = sss_dot3(a, v);
    for (int k = 0; k < 3; k++) y[k] = c[k] + v[k] * cs + axv[k] * sn + a[k] * av * (1 - cs);
}

static void restPoseWhereEveryAngleIsZero(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d = chain(20, 45);
    sss_mesh p0 = pose_or_fail(&d, 0.0, &rest); /* θ_b(0) = 0 for every bone */
    assert_memory_equal(p0.pos, rest.pos, 3 * (size_t)rest.nv * sizeof(float));
    assert_memory_equal(p0.nrm, rest.nrm, 3 * (size_t)rest.nv * sizeof(float));
    d.skin.bone[0].angle_deg = d.skin.bone[1].angle_deg = 0;
    sss_mesh pa = pose_or_fail(&d, 1.0, &rest);
    assert_memory_equal(pa.pos, rest.pos, 3 * (size_t)rest.nv * sizeof(float));
    /* the angle-0 matrices are exactly I (what the copy stands for) */
    double M[32], th[2] = {0, 0};
    sss_skin_matrices(&d.skin, th, M);
    for (int k = 0; k < 32; k++) assert_true(M[k] == (k % 16 % 5 == 0 ? 1.0 : 0.0));
    /* and a quarter period moves it (the check could fail) */
    d = chain(20, 45);
    sss_mesh pq = pose_or_fail(&d, 1.0, &rest);
    double moved = 0;
    for (size_t i = 0; i < 3 * (size_t)rest.nv; i++) moved = fmax(moved, fabs(pq.pos[i] - rest.pos[i]));
    assert_true(moved > 0.1);
    sss_mesh_free(&p0), sss_mesh_free(&pa), sss_mesh_free(&pq), sss_mesh_free(&rest);
}

/* One bone (off the mesh's axis, turning about a slanted axis): every
 * vertex turns rigidly about the bone's head, so every distance is kept
 * and every normal turns with it. */
static void singleBoneTurnsTheMeshRigidly(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d;
    memset(&d, 0, sizeof d);
    d.kind = SSS_DEFORM_SKIN;
    d.skin.nbones = 1;
    const double a[3] = {0.6, 0, 0.8}, h[3] = {0.1, -0.2, -0.3};
    d.skin.bone[0] = (sss_skin_bone){{h[0], h[1], h[2]}, {0.1, -0.2, 0.4}, -1, {a[0], a[1], a[2]}, 70.0, 4.0};
    sss_mesh p = pose_or_fail(&d, 1.0, &rest);
    const double theta = 70.0 * SSS_PI / 180.0;
    double worst = 0, dist = 0, nrm = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *r = &rest.pos[3 * (size_t)v], *q = &p.pos[3 * (size_t)v];
        const double x[3] = {r[0], r[1], r[2]}, zero[3] = {0, 0, 0};
        double y[3];
        turn(a, theta, h, x, y);
        for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(q[k] - y[k]));
        /* the distance to a vertex across the mesh */
        const uint32_t u = (v * 7919u + 13u) % rest.nv;
        const float *ru = &rest.pos[3 * (size_t)u], *qu = &p.pos[3 * (size_t)u];
        double d0 = 0, d1 = 0;
        for (int k = 0; k < 3; k++) {
            d0 += ((double)ru[k] - r[k]) * ((double)ru[k] - r[k]);
            d1 += ((double)qu[k] - q[k]) * ((double)qu[k] - q[k]);
        }
        dist = fmax(dist, fabs(sqrt(d1) - sqrt(d0)));
        const double n0[3] = {rest.nrm[3 * v], rest.nrm[3 * v + 1], rest.nrm[3 * v + 2]};
        double n1[3];
        turn(a, theta, zero, n0, n1);
        for (int k = 0; k < 3; k++) nrm = fmax(nrm, fabs(p.nrm[3 * (size_t)v + k] - n1[k]));
    }
    printf("one bone, 70 deg: max |x' - R x| %.2g, max distance change %.2g, max normal change %.2g\n", worst, dist, nrm);
    assert_true(worst < 1e-6);  /* float rounding of coordinates below 1 */
    assert_true(dist < 2e-6);
    assert_true(nrm < 1e-5);    /* normals recomputed from the turned triangles */
    sss_mesh_free(&p), sss_mesh_free(&rest);
}

/* Two bones at t = 1 (a quarter period: the full angles): bone 0 turns by
 * 20° about +y through (0, 0, −0.5), bone 1 by 45° about +x through
 * (0, 0, 0) and then with bone 0. The blend radius is 1/8 (a quarter of
 * 0.5); a surface vertex at height z from the joint is √(R² + z²) − R
 * farther from the other bone, more than 1/8 once |z| > 0.217: those with
 * |z| ≥ 0.25 follow one bone exactly, and so do the caps' centres. */
static void twoBoneChainEndsFollowTheirBones(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d = chain(20, 45);
    sss_mesh p = pose_or_fail(&d, 1.0, &rest);
    const double ay[3] = {0, 1, 0}, ax[3] = {1, 0, 0}, h0[3] = {0, 0, -0.5}, h1[3] = {0, 0, 0};
    const double t0 = 20 * SSS_PI / 180, t1 = 45 * SSS_PI / 180;
    int low = 0, high = 0, mid = 0;
    double dev = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *r = &rest.pos[3 * (size_t)v], *q = &p.pos[3 * (size_t)v];
        const double x[3] = {r[0], r[1], r[2]};
        double y0[3], y1[3], y01[3];
        turn(ay, t0, h0, x, y0);   /* bone 0 alone */
        turn(ax, t1, h1, x, y1);   /* bone 1's own turn, */
        turn(ay, t0, h0, y1, y01); /* then its parent's */
        if (x[2] <= -0.25) {
            for (int k = 0; k < 3; k++) assert_true(fabs(q[k] - y0[k]) < 1e-6), dev = fmax(dev, fabs(q[k] - y0[k]));
            low++;
        } else if (x[2] >= 0.25) {
            for (int k = 0; k < 3; k++) assert_true(fabs(q[k] - y01[k]) < 1e-6), dev = fmax(dev, fabs(q[k] - y01[k]));
            high++;
        } else if (x[2] == 0.0 && fabs(hypot(x[0], x[1]) - 0.125) < 1e-6) {
            /* the ring at the joint is equally far from both: the mean */
            for (int k = 0; k < 3; k++) assert_true(fabs(q[k] - 0.5 * (y0[k] + y01[k])) < 1e-6);
            mid++;
        }
    }
    printf("two bones: %d vertices follow bone 0, %d bone 1, max deviation %.2g\n", low, high, dev);
    assert_true(low >= 16 * 4 + 1 && high >= 16 * 4 + 1 && mid == 16);
    sss_mesh_free(&p), sss_mesh_free(&rest);
}

/* The weights: in [0, 1], summing to 1, exactly one-hot beyond the blend
 * zone, 1/2 on the joint's ring, and continuous along the tube (no step
 * between neighbouring rings larger than the smoothstep's slope allows). */
static void weightsAreNormalisedAndOneHotAwayFromTheJoint(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d = chain(20, 45);
    double *w = malloc((size_t)rest.nv * 2 * sizeof *w);
    sss_skin_weights(&d.skin, &rest, w);
    assert_true(sss_skin_radius(&d.skin) == 0.125);
    int blended = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const double *wv = &w[2 * (size_t)v], z = rest.pos[3 * (size_t)v + 2];
        assert_true(wv[0] >= 0 && wv[0] <= 1 && wv[1] >= 0 && wv[1] <= 1);
        assert_true(fabs(wv[0] + wv[1] - 1) < 1e-15);
        if (z <= -0.25) assert_true(wv[0] == 1.0 && wv[1] == 0.0);
        if (z >= 0.25) assert_true(wv[0] == 0.0 && wv[1] == 1.0);
        if (z == 0.0 && v < 17 * 16) assert_true(wv[0] == 0.5);
        blended += wv[1] > 0 && wv[1] < 1;
        if (v >= 16 && v < 17 * 16) /* the ring below, same angle: rings 1/16 apart */
            assert_true(fabs(wv[1] - w[2 * (size_t)(v - 16) + 1]) < 0.35);
    }
    assert_true(blended >= 3 * 16); /* the joint's ring and one on each side */
    free(w);
    sss_mesh_free(&rest);
}

/* The glTF tube of sss-genmesh (`tube … skin`) has the same two joints
 * (bone0 from the bottom to the middle, bone1 above it) and at t = 1 s its
 * clip turns bone1 by +45° about +x, as this chain does at a quarter of
 * its period. The rigs' weights differ (the glTF's smoothstep over
 * |z| < 1/8 against distances to the bones here), so the poses agree where
 * both are one-hot: |z| ≥ 1/4, within 10⁻⁵ (float rounding of the two
 * matrix products). */
static void matchesTheSkinnedGltfOutsideBothBlendZones(void **state)
{
    (void)state;
    char dir[] = "/tmp/sss_test_skin_deform_XXXXXX", path[96];
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/tube.gltf", dir);
    sss_mesh gen = tube_or_fail(), rest, clip;
    sss_error err = {{0}};
    if (sss_gltf_write(path, &gen, SSS_GLTF_SKIN, &err) != SSS_OK || sss_import_mesh(path, &rest, NULL, &err) != SSS_OK ||
        sss_import_mesh_at(path, 1.0, &clip, NULL, &err) != SSS_OK)
        fail_msg("%s", err.msg);
    unlink(path);
    rmdir(dir);
    sss_deform d = chain(0, 45);
    sss_mesh p = pose_or_fail(&d, 1.0, &rest);
    assert_int_equal(p.nv, clip.nv);
    int n = 0;
    double worst = 0, moved = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float z = rest.pos[3 * (size_t)v + 2];
        if (fabsf(z) < 0.25f) continue;
        for (int k = 0; k < 3; k++) {
            worst = fmax(worst, fabs(p.pos[3 * (size_t)v + k] - clip.pos[3 * (size_t)v + k]));
            moved = fmax(moved, fabs(p.pos[3 * (size_t)v + k] - rest.pos[3 * (size_t)v + k]));
        }
        n++;
    }
    printf("skin against the glTF's clip at t = 1, |z| >= 1/4: %d vertices, max |diff| %.2g\n", n, worst);
    assert_true(n > 100);
    assert_true(moved > 0.1);
    assert_true(worst < 1e-5);
    sss_mesh_free(&gen), sss_mesh_free(&rest), sss_mesh_free(&clip), sss_mesh_free(&p);
}

/* The per-frame path on a skinned pose (docs/deformable.md §3): its exact
 * mode computes what the exact evaluator computes on a file holding the
 * pose, to one float rounding, as test_perframe checks for the bend. */
static void perFrameExactModeEqualsExactEvaluatorOnSkinnedPose(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d = chain(20, 45);
    sss_mesh pose = pose_or_fail(&d, 1.0, &rest);
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    const double mpu = 100.0, light[3] = {-0.3, 0.9, 0.3};
    sss_bake_file f;
    memset(&f, 0, sizeof f);
    f.mesh = pose;
    f.mesh.area = NULL;
    f.material = mat;
    f.mm_per_unit = mpu;
    f.channels = 3;
    f.eps = 1e-3;
    sss_exact *e;
    if (sss_exact_create(&f, &e, &err) != SSS_OK) fail_msg("%s", err.msg);
    const size_t n = (size_t)pose.nv * 3;
    float *q = malloc(n * sizeof *q), *want = malloc(n * sizeof *want);
    sss_perframe_options o = {.mode = SSS_PERFRAME_EXACT};
    if (sss_perframe_q(&pose, &mat, 3, mpu, light, &o, q, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_exact_eval(e, light, want);
    float lo = INFINITY, hi = 0;
    double rel = 0;
    for (size_t i = 0; i < n; i++) {
        assert_true(fabsf(q[i] - want[i]) <= 1.2e-7f * fabsf(want[i]));
        lo = fminf(lo, want[i]), hi = fmaxf(hi, want[i]);
        if (want[i] > 0) rel = fmax(rel, fabs((double)q[i] - want[i]) / want[i]);
    }
    printf("per-frame exact against the exact evaluator on the skinned pose: max relative difference %.2g\n", rel);
    /* the light reaches every vertex through the 25 mm tube (R = 21 mm in
     * red) but the far side gets far less: a q that varies */
    assert_true(hi > 0 && lo < 0.1f * hi);
    sss_exact_destroy(e);
    free(q), free(want);
    sss_mesh_free(&pose), sss_mesh_free(&rest);
}

static void posesAreDeterministic(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail();
    sss_deform d = chain(-30, 80);
    sss_mesh a = pose_or_fail(&d, 0.7, &rest), b = pose_or_fail(&d, 0.7, &rest);
    assert_memory_equal(a.pos, b.pos, 3 * (size_t)rest.nv * sizeof(float));
    assert_memory_equal(a.nrm, b.nrm, 3 * (size_t)rest.nv * sizeof(float));
    sss_mesh_free(&a), sss_mesh_free(&b), sss_mesh_free(&rest);
}

/* sss_deform_pose refuses a bad chain given through the API with the
 * bone and member at fault, and leaves *out zeroed. */
static void poseRefusesABadChain(void **state)
{
    (void)state;
    sss_mesh rest = tube_or_fail(), out;
    sss_error err = {{0}};
    sss_deform d = chain(20, 45);
    d.skin.bone[0].parent = 1; /* 0 → 1 → 0 */
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: bones/0/parent: 1: the parents of bone 0 never reach a root"));
    assert_null(out.pos);
    d = chain(20, 45);
    d.skin.bone[1].tail[2] = 0.0;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: bones/1/tail: equals the head"));
    d = chain(20, 45);
    d.skin.nbones = 0;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: bones: 0 bones, expected 1 to 16"));
    d = chain(20, 45);
    d.skin.blend_radius = -1;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: blend_radius: -1 must be > 0"));
    d = chain(20, 45);
    d.skin.bone[1].axis[0] = 2; /* the API takes unit axes (the scene normalises) */
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: bones/1/axis: (2, 0, 0) is not a unit vector"));
    d = chain(20, 45);
    d.skin.bone[0].head[2] = NAN;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "tube", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "tube: deform: bones/0/head: not a point of finite coordinates"));
    d = chain(20, 45);
    assert_int_equal(sss_deform_pose(&d, INFINITY, &rest, "tube", &out, &err), SSS_ERR_ARG);
    sss_mesh_free(&rest);
}

static void sceneParsesSkin(void **state)
{
    (void)state;
    sss_scene s;
    sss_error err = {{0}};
    if (sss_scene_parse("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":\"skin1\",\"deform\":{\"type\":\"skin\","
                        "\"blend_radius\":0.1,\"bones\":["
                        "{\"head\":[0,0,-0.5],\"tail\":[0,0,0],\"axis\":[0,2,0],\"angle_deg\":20},"
                        "{\"head\":[0,0,0],\"tail\":[0,0,0.5],\"parent\":0,\"axis\":[1,0,0],\"angle_deg\":-45,"
                        "\"period_s\":2}]}}]}",
                        "scene.json", &s, &err) != SSS_OK)
        fail_msg("%s", err.msg);
    const sss_deform *d = &s.objects[0].deform;
    assert_int_equal(d->kind, SSS_DEFORM_SKIN);
    assert_int_equal(d->skin.nbones, 2);
    assert_true(d->skin.blend_radius == 0.1);
    const sss_skin_bone *b0 = &d->skin.bone[0], *b1 = &d->skin.bone[1];
    assert_true(b0->parent == -1 && b0->axis[1] == 1 && b0->period_s == SSS_DEFORM_PERIOD_DEFAULT);
    assert_true(b1->parent == 0 && b1->angle_deg == -45 && b1->period_s == 2 && b1->tail[2] == 0.5);
    assert_string_equal(sss_deform_kind_name(d->kind), "skin");
    /* the angle for messages: the bone of the largest amplitude, bone 1 */
    assert_true(fabs(sss_deform_angle(d, 0.5) + 45 * SSS_PI / 180) < 1e-12);
    sss_scene_free(&s);
}

static void expect_error(const char *deform, const char *want)
{
    char json[2048];
    snprintf(json, sizeof json, "{\"objects\":[{\"mesh\":\"a.ply\",\"material\":\"marble\",\"deform\":%s}]}", deform);
    sss_scene s;
    sss_error err = {{0}};
    assert_int_not_equal(sss_scene_parse(json, "scene.json", &s, &err), SSS_OK);
    if (!strstr(err.msg, want)) fail_msg("got '%s', want '%s'", err.msg, want);
    assert_null(strchr(err.msg, '\n'));
}

#define B0 "{\"head\":[0,0,-0.5],\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":20}"
#define B1 "{\"head\":[0,0,0],\"tail\":[0,0,0.5],\"parent\":0,\"axis\":[1,0,0],\"angle_deg\":45}"

static void sceneRefusesBadSkinWithItsPath(void **state)
{
    (void)state;
    expect_error("{\"type\":\"skin\"}", "scene.json: /objects/0/deform/bones: missing");
    expect_error("{\"type\":\"skin\",\"bones\":[]}", "scene.json: /objects/0/deform/bones: expected an array of 1 to 16");
    expect_error("{\"type\":\"skin\",\"bones\":{}}", "/objects/0/deform/bones: expected an array of 1 to 16");
    char many[2048] = "{\"type\":\"skin\",\"bones\":[" B0;
    for (int i = 0; i < 16; i++) strcat(many, "," B0);
    strcat(many, "]}");
    expect_error(many, "/objects/0/deform/bones: expected an array of 1 to 16");
    expect_error("{\"type\":\"skin\",\"bones\":[3]}", "/objects/0/deform/bones/0: expected an object");
    expect_error("{\"type\":\"skin\",\"bones\":[" B0 ",{\"head\":[0,0,0],\"tail\":[0,0,0.5],\"parent\":2,\"axis\":[1,0,0],"
                 "\"angle_deg\":45}]}",
                 "/objects/0/deform/bones/1/parent: 2 is not a bone index in [0, 2)");
    expect_error("{\"type\":\"skin\",\"bones\":[" B0 ",{\"head\":[0,0,0],\"tail\":[0,0,0.5],\"parent\":0.5,\"axis\":[1,0,0],"
                 "\"angle_deg\":45}]}",
                 "/objects/0/deform/bones/1/parent: expected an integer");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,-0.5],\"tail\":[0,0,0],\"parent\":1,\"axis\":[0,1,0],"
                 "\"angle_deg\":20}," B1 "]}",
                 "/objects/0/deform/bones/0/parent: 1: the parents of bone 0 never reach a root (a cycle)");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,0],\"tail\":[0,0,1],\"parent\":0,\"axis\":[1,0,0],"
                 "\"angle_deg\":20}]}",
                 "/objects/0/deform/bones/0/parent: 0: the parents of bone 0 never reach a root");
    expect_error("{\"type\":\"skin\",\"bones\":[" B0 ",{\"head\":[0,0,0],\"tail\":[0,0,0],\"axis\":[1,0,0],\"angle_deg\":4}]}",
                 "/objects/0/deform/bones/1/tail: equals the head");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1e999],\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":2}]}",
                 "/objects/0/deform/bones/0/head: expected 3 numbers");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":2}]}",
                 "/objects/0/deform/bones/0/head: missing");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"angle_deg\":2}]}",
                 "/objects/0/deform/bones/0/axis: missing");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"axis\":[0,0,0],\"angle_deg\":2}]}",
                 "/objects/0/deform/bones/0/axis: must be a non-zero vector");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"axis\":[0,1,0]}]}",
                 "/objects/0/deform/bones/0/angle_deg: missing");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":400}]}",
                 "/objects/0/deform/bones/0/angle_deg: 400 is out of range");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":4,"
                 "\"period_s\":0}]}",
                 "/objects/0/deform/bones/0/period_s: 0 is out of range");
    expect_error("{\"type\":\"skin\",\"bones\":[{\"head\":[0,0,1],\"tail\":[0,0,0],\"axis\":[0,1,0],\"angle_deg\":4,"
                 "\"length\":1}]}",
                 "/objects/0/deform/bones/0/length: unknown key");
    expect_error("{\"type\":\"skin\",\"angle_deg\":4,\"bones\":[" B0 "]}", "/objects/0/deform/angle_deg: unknown key");
    expect_error("{\"type\":\"skin\",\"blend_radius\":0,\"bones\":[" B0 "]}",
                 "/objects/0/deform/blend_radius: must be > 0");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(restPoseWhereEveryAngleIsZero),
        cmocka_unit_test(singleBoneTurnsTheMeshRigidly),
        cmocka_unit_test(twoBoneChainEndsFollowTheirBones),
        cmocka_unit_test(weightsAreNormalisedAndOneHotAwayFromTheJoint),
        cmocka_unit_test(matchesTheSkinnedGltfOutsideBothBlendZones),
        cmocka_unit_test(perFrameExactModeEqualsExactEvaluatorOnSkinnedPose),
        cmocka_unit_test(posesAreDeterministic),
        cmocka_unit_test(poseRefusesABadChain),
        cmocka_unit_test(sceneParsesSkin),
        cmocka_unit_test(sceneRefusesBadSkinWithItsPath),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
