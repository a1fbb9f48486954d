/* test_deform.c: the procedural deformers of sss/deform.h (docs/deformable.md
 * §2) and their "deform" key in scene files (docs/scenes.md): the rest pose
 * at t = 0 and for a zero angle, the bend's kept lengths along its axis,
 * the twist's kept distances to it, the wave's amplitude, the normals
 * recomputed on the pose, determinism, and the one-line errors with the
 * JSON path of the element at fault. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/deform.h"
#include "sss/planner.h"
#include "sss/scene.h"
#include "sss/vec3.h"

static sss_mesh box_or_fail(void)
{
    sss_mesh m;
    sss_error err = {{0}};
    /* a bar along +x: 4 × 1 × 1, each face a 4 × 4 grid, so every face has
     * a centre vertex */
    if (sss_gen_box(&m, 4.0, 1.0, 1.0, 4, 0, &err) != SSS_OK) fail_msg("%s", err.msg);
    return m;
}

static sss_mesh pose_or_fail(const sss_deform *d, double t, const sss_mesh *rest)
{
    sss_mesh out;
    sss_error err = {{0}};
    if (sss_deform_pose(d, t, rest, "bar", &out, &err) != SSS_OK) fail_msg("%s", err.msg);
    return out;
}

static void restPoseAtTimeZeroAndForZeroAngle(void **state)
{
    (void)state;
    sss_mesh rest = box_or_fail();
    const sss_deform_kind kinds[] = {SSS_DEFORM_BEND, SSS_DEFORM_TWIST, SSS_DEFORM_WAVE};
    for (int k = 0; k < 3; k++) {
        sss_deform d = {.kind = kinds[k], .axis = {1, 0, 0}, .angle_deg = 40.0, .period_s = 4.0};
        sss_mesh p0 = pose_or_fail(&d, 0.0, &rest);
        assert_memory_equal(p0.pos, rest.pos, 3 * (size_t)rest.nv * sizeof(float));
        assert_memory_equal(p0.nrm, rest.nrm, 3 * (size_t)rest.nv * sizeof(float));
        sss_mesh_free(&p0);
        /* a whole period later, the pose is back at rest up to sin(2π)'s rounding */
        sss_mesh p4 = pose_or_fail(&d, 4.0, &rest);
        for (size_t i = 0; i < 3 * (size_t)rest.nv; i++) assert_true(fabsf(p4.pos[i] - rest.pos[i]) < 1e-5f);
        sss_mesh_free(&p4);
        d.angle_deg = 0.0;
        sss_mesh pa = pose_or_fail(&d, 1.0, &rest);
        assert_memory_equal(pa.pos, rest.pos, 3 * (size_t)rest.nv * sizeof(float));
        sss_mesh_free(&pa);
        /* and the pose at a quarter period moves the mesh (the check could fail) */
        d.angle_deg = 40.0;
        sss_mesh pq = pose_or_fail(&d, 1.0, &rest);
        double moved = 0;
        for (size_t i = 0; i < 3 * (size_t)rest.nv; i++) moved = fmax(moved, fabs(pq.pos[i] - rest.pos[i]));
        assert_true(moved > 0.1);
        sss_mesh_free(&pq);
    }
    sss_mesh_free(&rest);
}

/* A line of vertices on the bend's axis line (the centre row of a plane
 * along x; u is +y, the plane's own plane) keeps its arc length: each
 * chord between neighbours is the chord of an arc of the rest spacing on a
 * circle of radius 1/κ, and the arcs add up to the rest length. */
static void bendKeepsLengthsAlongTheAxis(void **state)
{
    (void)state;
    sss_mesh rest;
    sss_error err = {{0}};
    if (sss_gen_plane(&rest, 4.0, 1.0, 64, 2, &err) != SSS_OK) fail_msg("%s", err.msg);
    const double angles[] = {30.0, 90.0, 200.0, -120.0};
    for (int a = 0; a < 4; a++) {
        sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {1, 0, 0}, .angle_deg = angles[a], .period_s = 4.0};
        sss_mesh p = pose_or_fail(&d, 1.0, &rest); /* t = T/4: θ = angle */
        const double theta = sss_deform_angle(&d, 1.0), kappa = theta / 4.0;
        assert_true(fabs(theta - angles[a] * SSS_PI / 180.0) < 1e-12);
        /* the rest centre row (y = 0), in order of x */
        uint32_t row[65];
        uint32_t n = 0;
        for (uint32_t v = 0; v < rest.nv; v++)
            if (rest.pos[3 * (size_t)v + 1] == 0.0f) {
                assert_true(n < 65);
                row[n++] = v;
            }
        assert_int_equal(n, 65);
        for (uint32_t i = 1; i < n; i++)
            for (uint32_t j = i; j > 0 && rest.pos[3 * (size_t)row[j]] < rest.pos[3 * (size_t)row[j - 1]]; j--) {
                uint32_t t = row[j];
                row[j] = row[j - 1];
                row[j - 1] = t;
            }
        double arcs = 0;
        for (uint32_t i = 1; i < n; i++) {
            const float *p0 = &p.pos[3 * (size_t)row[i - 1]], *p1 = &p.pos[3 * (size_t)row[i]];
            const double dx = p1[0] - p0[0], dy = p1[1] - p0[1], dz = p1[2] - p0[2];
            const double chord = sqrt(dx * dx + dy * dy + dz * dz);
            const double ds = rest.pos[3 * (size_t)row[i]] - rest.pos[3 * (size_t)row[i - 1]];
            assert_true(fabs(dz) < 1e-6);
            assert_true(fabs(chord - 2.0 * sin(0.5 * fabs(kappa) * ds) / fabs(kappa)) < 1e-5 * ds);
            arcs += 2.0 * asin(0.5 * fabs(kappa) * chord) / fabs(kappa);
        }
        assert_true(fabs(arcs - 4.0) < 1e-5);
        /* the fixed end stays, the far end turns by θ about the bend centre */
        assert_true(fabs(p.pos[3 * (size_t)row[0]] - rest.pos[3 * (size_t)row[0]]) < 1e-6);
        const float *e = &p.pos[3 * (size_t)row[n - 1]];
        assert_true(fabs((e[0] + 2.0) - sin(theta) / kappa) < 1e-5);
        assert_true(fabs(e[1] - (1.0 - cos(theta)) / kappa) < 1e-5);
        sss_mesh_free(&p);
    }
    sss_mesh_free(&rest);
}

static void twistKeepsDistancesToTheAxisAndWaveHasItsAmplitude(void **state)
{
    (void)state;
    sss_mesh rest = box_or_fail();
    sss_deform tw = {.kind = SSS_DEFORM_TWIST, .axis = {1, 0, 0}, .angle_deg = 90.0, .period_s = 4.0};
    sss_mesh p = pose_or_fail(&tw, 1.0, &rest);
    double turned = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *a = &rest.pos[3 * (size_t)v], *b = &p.pos[3 * (size_t)v];
        assert_true(fabs(a[0] - b[0]) < 1e-6); /* σ' = σ */
        assert_true(fabs(hypot(a[1], a[2]) - hypot(b[1], b[2])) < 1e-6);
        /* the far end (x = 2) turns by the whole 90°: (y, z) → (−z, y) */
        if (a[0] == 2.0f) {
            assert_true(fabs(b[1] + a[2]) < 1e-6 && fabs(b[2] - a[1]) < 1e-6);
            turned += 1;
        }
    }
    assert_true(turned > 0);
    sss_mesh_free(&p);
    sss_deform wv = {.kind = SSS_DEFORM_WAVE, .axis = {1, 0, 0}, .angle_deg = 30.0, .period_s = 4.0};
    p = pose_or_fail(&wv, 1.0, &rest);
    const double amp = 4.0 * tan(30.0 * SSS_PI / 180.0) / (2.0 * SSS_PI);
    double top = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *a = &rest.pos[3 * (size_t)v], *b = &p.pos[3 * (size_t)v];
        const double want = amp * sin(2.0 * SSS_PI * (a[0] + 2.0) / 4.0);
        assert_true(fabs(a[0] - b[0]) < 1e-6 && fabs(a[2] - b[2]) < 1e-6);
        assert_true(fabs((b[1] - a[1]) - want) < 1e-5);
        top = fmax(top, fabs(b[1] - a[1]));
    }
    assert_true(fabs(top - amp) < 1e-5); /* x = −1 and x = 1 are vertices of the 4 × 4 grid */
    sss_mesh_free(&p);
    sss_mesh_free(&rest);
}

/* Normals and areas are those of the pose: the far cap of the bar bent by
 * 90° towards u = +y faces +y, and its area is the rest cap's (the cap is
 * moved rigidly). */
static void poseRecomputesNormalsAndAreas(void **state)
{
    (void)state;
    sss_mesh rest = box_or_fail();
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {1, 0, 0}, .angle_deg = 90.0, .period_s = 4.0};
    sss_mesh p = pose_or_fail(&d, 1.0, &rest);
    int found = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *a = &rest.pos[3 * (size_t)v];
        if (a[0] != 2.0f || a[1] != 0.0f || a[2] != 0.0f) continue; /* the far cap's centre */
        const float *n = &p.nrm[3 * (size_t)v];
        assert_true(fabs(n[0]) < 1e-5 && fabs(n[1] - 1.0) < 1e-5 && fabs(n[2]) < 1e-5);
        assert_true(fabs(p.area[v] - rest.area[v]) < 1e-6 * rest.area[v]);
        found = 1;
    }
    assert_true(found);
    sss_mesh_free(&p);
    sss_mesh_free(&rest);
}

static void poseIsDeterministic(void **state)
{
    (void)state;
    sss_mesh rest = box_or_fail();
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {0.6, 0.8, 0}, .angle_deg = 70.0, .period_s = 3.0};
    sss_mesh a = pose_or_fail(&d, 0.37, &rest), b = pose_or_fail(&d, 0.37, &rest);
    assert_memory_equal(a.pos, b.pos, 3 * (size_t)rest.nv * sizeof(float));
    assert_memory_equal(a.nrm, b.nrm, 3 * (size_t)rest.nv * sizeof(float));
    assert_memory_equal(a.area, b.area, (size_t)rest.nv * sizeof(double));
    sss_mesh_free(&a);
    sss_mesh_free(&b);
    sss_mesh_free(&rest);
}

static void poseRefusesBadParameters(void **state)
{
    (void)state;
    sss_mesh rest = box_or_fail(), out;
    sss_error err = {{0}};
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {1, 1, 0}, .angle_deg = 40.0, .period_s = 4.0};
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "bar", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "bar: deform: axis"));
    d.axis[1] = 0;
    d.period_s = 0;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "bar", &out, &err), SSS_ERR_ARG);
    d.period_s = 4;
    assert_int_equal(sss_deform_pose(&d, NAN, &rest, "bar", &out, &err), SSS_ERR_ARG);
    d.kind = SSS_DEFORM_WAVE;
    d.angle_deg = 89;
    assert_int_equal(sss_deform_pose(&d, 1.0, &rest, "bar", &out, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "wave angle 89"));
    assert_null(out.pos);
    sss_mesh_free(&rest);
}

static void sceneParsesDeform(void **state)
{
    (void)state;
    sss_scene s;
    sss_error err = {{0}};
    assert_int_equal(sss_scene_parse("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":\"marble\",\"deform\":"
                                     "{\"type\":\"twist\",\"axis\":[0,2,0],\"angle_deg\":-30,\"period_s\":2}},"
                                     "{\"mesh\":\"b.ply\",\"material\":\"marble\",\"deform\":"
                                     "{\"type\":\"bend\",\"angle_deg\":40}},"
                                     "{\"mesh\":\"c.ply\",\"material\":\"marble\"}]}",
                                     "scene.json", &s, &err),
                     SSS_OK);
    const sss_deform *a = &s.objects[0].deform, *b = &s.objects[1].deform, *c = &s.objects[2].deform;
    assert_int_equal(a->kind, SSS_DEFORM_TWIST);
    assert_true(a->axis[0] == 0 && a->axis[1] == 1 && a->axis[2] == 0); /* normalised */
    assert_true(a->angle_deg == -30 && a->period_s == 2);
    assert_int_equal(b->kind, SSS_DEFORM_BEND);
    assert_true(b->axis[2] == 1 && b->period_s == SSS_DEFORM_PERIOD_DEFAULT);
    assert_int_equal(c->kind, SSS_DEFORM_NONE);
    sss_scene_free(&s);
}

static void expect_error(const char *deform, const char *want)
{
    char json[512];
    snprintf(json, sizeof json, "{\"objects\":[{\"mesh\":\"a.ply\",\"material\":\"marble\",\"deform\":%s}]}", deform);
    sss_scene s;
    sss_error err = {{0}};
    assert_int_not_equal(sss_scene_parse(json, "scene.json", &s, &err), SSS_OK);
    if (!strstr(err.msg, want)) fail_msg("got '%s', want '%s'", err.msg, want);
    assert_null(strchr(err.msg, '\n'));
}

static void sceneRefusesBadDeformWithItsPath(void **state)
{
    (void)state;
    expect_error("3", "scene.json: /objects/0/deform: expected an object");
    expect_error("{\"angle_deg\":3}", "scene.json: /objects/0/deform/type: missing");
    expect_error("{\"type\":\"bent\",\"angle_deg\":3}", "/objects/0/deform/type: 'bent' is not");
    expect_error("{\"type\":\"bend\"}", "/objects/0/deform/angle_deg: missing");
    expect_error("{\"type\":\"bend\",\"angle_deg\":3,\"axes\":[0,0,1]}", "/objects/0/deform/axes: unknown key");
    expect_error("{\"type\":\"bend\",\"angle_deg\":3,\"axis\":[0,0,0]}", "/objects/0/deform/axis: must be a non-zero");
    expect_error("{\"type\":\"bend\",\"angle_deg\":3,\"axis\":[0,1]}", "/objects/0/deform/axis: expected 3 numbers");
    expect_error("{\"type\":\"wave\",\"angle_deg\":85}", "/objects/0/deform/angle_deg: 85 is out of range");
    expect_error("{\"type\":\"bend\",\"angle_deg\":3,\"period_s\":0}", "/objects/0/deform/period_s: 0 is out of range");
    expect_error("{\"type\":\"bend\",\"angle_deg\":3,\"angle_deg\":4}", "/objects/0/deform/angle_deg: given twice");
    /* a skin takes bones, not the procedural keys (test_skin_deform.c) */
    expect_error("{\"type\":\"skin\",\"bones\":[]}", "/objects/0/deform/bones: expected an array of 1 to 16 bones");
}

/* The planner sends a deforming object to the per-frame path (nothing
 * baked, the reason given) and keeps a static object's bake; a deforming
 * object with no directional light is refused with its JSON path. */
static void plannerSendsDeformingObjectToPerFramePath(void **state)
{
    (void)state;
    sss_scene s;
    sss_error err = {{0}};
    assert_int_equal(sss_scene_parse("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":\"marble\",\"deform\":"
                                     "{\"type\":\"wave\",\"angle_deg\":20}},"
                                     "{\"mesh\":\"b.ply\",\"material\":\"marble\"}],"
                                     "\"lights\":[{\"type\":\"directional\",\"direction\":[0,0,1]}]}",
                                     "scene.json", &s, &err),
                     SSS_OK);
    sss_mesh world[2];
    world[0] = box_or_fail();
    world[1] = box_or_fail();
    sss_plan plan;
    if (sss_plan_scene(&s, world, &plan, &err) != SSS_OK) fail_msg("%s", err.msg);
    const sss_object_plan *a = &plan.obj[0], *b = &plan.obj[1];
    assert_int_equal(a->per_frame, 1);
    assert_int_equal(a->effects & ~(uint32_t)SSS_FX_RGB, 0);
    assert_int_equal(a->light_pass[0], UINT32_MAX);
    int said = 0;
    for (uint32_t d = 0; d < a->ndecisions; d++)
        said |= !strcmp(a->decisions[d].effect, "deform") && !strcmp(a->decisions[d].choice, "per-frame") &&
                strstr(a->decisions[d].reason, "nothing is baked") != NULL;
    assert_true(said);
    assert_int_equal(b->per_frame, 0);
    assert_int_equal(b->light_pass[0], SSS_PASS_DIR_EXACT);
    assert_int_equal(b->scene_shadow, 0); /* the deforming object casts no baked shadow */
    sss_plan_free(&plan);
    s.lights[0].kind = SSS_LIGHT_POINT;
    assert_int_equal(sss_plan_scene(&s, world, &plan, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "scene.json: /objects/0/deform: no directional light"));
    sss_mesh_free(&world[0]);
    sss_mesh_free(&world[1]);
    sss_scene_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(restPoseAtTimeZeroAndForZeroAngle),
        cmocka_unit_test(bendKeepsLengthsAlongTheAxis),
        cmocka_unit_test(twistKeepsDistancesToTheAxisAndWaveHasItsAmplitude),
        cmocka_unit_test(poseRecomputesNormalsAndAreas),
        cmocka_unit_test(poseIsDeterministic),
        cmocka_unit_test(poseRefusesBadParameters),
        cmocka_unit_test(sceneParsesDeform),
        cmocka_unit_test(sceneRefusesBadDeformWithItsPath),
        cmocka_unit_test(plannerSendsDeformingObjectToPerFramePath),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
