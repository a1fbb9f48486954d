/* test_skin.c: skinned glTF input (docs/deformable.md §5): the two-bone
 * tube sss-genmesh writes (gltf_write.c, SSS_GLTF_SKIN) passes the
 * importer's checks of JOINTS_0, WEIGHTS_0 and the skin, and reads as its
 * rest pose; posed at a time (sss_import_mesh_at) its clip bends the upper
 * half by linear blend skinning; a joint index beyond the skin's joints or
 * weights that do not sum to 1 give one line naming the file, the accessor
 * and the vertex. */
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
#include "sss/import.h"
#include "sss/vec3.h"

static char g_dir[64], g_files[8][160];
static int g_nfiles;

static int setup(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_skin_XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    for (int i = 0; i < g_nfiles; i++) unlink(g_files[i]);
    return rmdir(g_dir);
}

/* The tube (radius 0.125, length 1, 16 × 16 segments) written with flags. */
static const char *write_tube(const char *name, unsigned flags, sss_mesh *tube)
{
    sss_error err = {{0}};
    if (sss_gen_tube(tube, 0.125, 1.0, 16, 16, &err) != SSS_OK) fail_msg("%s", err.msg);
    char *p = g_files[g_nfiles++];
    snprintf(p, sizeof g_files[0], "%s/%s", g_dir, name);
    if (sss_gltf_write(p, tube, flags, &err) != SSS_OK) fail_msg("%s", err.msg);
    return p;
}

static void skinnedTubeReadsAsItsRestPose(void **state)
{
    (void)state;
    sss_mesh tube, in;
    const char *p = write_tube("tube.gltf", SSS_GLTF_SKIN, &tube);
    sss_error err = {{0}};
    if (sss_import_mesh(p, &in, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(in.nf, tube.nf);
    double lo[3], hi[3], lo2[3], hi2[3];
    sss_mesh_bounds(&tube, lo, hi);
    sss_mesh_bounds(&in, lo2, hi2);
    for (int k = 0; k < 3; k++) assert_true(lo[k] == lo2[k] && hi[k] == hi2[k]);
    sss_mesh_free(&in);
    sss_mesh_free(&tube);
}

static void expect_refused(const char *name, unsigned flags, const char *want)
{
    sss_mesh tube, in;
    const char *p = write_tube(name, SSS_GLTF_SKIN | flags, &tube);
    sss_mesh_free(&tube);
    sss_error err = {{0}};
    assert_int_not_equal(sss_import_mesh(p, &in, NULL, &err), SSS_OK);
    char full[400];
    snprintf(full, sizeof full, "%s: %s", p, want);
    if (!strstr(err.msg, full)) fail_msg("got '%s', want '%s'", err.msg, full);
    assert_null(strchr(err.msg, '\n'));
}

static void badJointIndexIsRefusedByAccessorAndVertex(void **state)
{
    (void)state;
    expect_refused("joint.gltf", SSS_GLTF_BAD_JOINT,
                   "accessor 2: JOINTS_0 of vertex 5 names joint 7, but skin 0 has 2 joints");
}

static void weightsNotSummingToOneAreRefusedByAccessorAndVertex(void **state)
{
    (void)state;
    expect_refused("weights.glb", SSS_GLTF_BAD_WEIGHTS, "accessor 3: WEIGHTS_0 of vertex 3 sum to 0.5, not 1");
}

/* The clip turns bone1 (at z = 0, the tube's middle) about +x by 45° at
 * t = 1 and −45° at t = 3: a vertex beyond the blend zone (z ≥ 1/8, joint
 * 1's weight 1) turns rigidly about (0, 0, 0), one below it (z ≤ −1/8)
 * stays; t = 0 and t beyond the last keyframe are the rest pose. */
static void posedTubeBendsItsUpperHalfByTheClip(void **state)
{
    (void)state;
    sss_mesh tube, rest, p1, p3, p9;
    const char *p = write_tube("posed.glb", SSS_GLTF_SKIN, &tube);
    sss_error err = {{0}};
    sss_import_report rep;
    if (sss_import_mesh(p, &rest, NULL, &err) != SSS_OK || sss_import_mesh_at(p, 1.0, &p1, &rep, &err) != SSS_OK ||
        sss_import_mesh_at(p, 3.0, &p3, NULL, &err) != SSS_OK || sss_import_mesh_at(p, 9.0, &p9, NULL, &err) != SSS_OK)
        fail_msg("%s", err.msg);
    assert_int_equal(rep.animated, 1);
    assert_true(rep.clip_start == 0.0 && rep.clip_end == 4.0);
    assert_int_equal(p1.nv, rest.nv);
    const double c = cos(SSS_PI / 4), sn = sin(SSS_PI / 4);
    int moved = 0, kept = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        const float *r0 = &rest.pos[3 * (size_t)v], *a = &p1.pos[3 * (size_t)v], *b = &p3.pos[3 * (size_t)v],
                    *z9 = &p9.pos[3 * (size_t)v];
        for (int k = 0; k < 3; k++) assert_true(fabsf(z9[k] - r0[k]) < 1e-6f); /* clamped to t = 4: 0° */
        if (r0[2] >= 0.125f + 1e-6f) { /* rotation about +x by ±45°: y' = c y − s z, z' = s y + c z */
            assert_true(fabs(a[0] - r0[0]) < 1e-6);
            assert_true(fabs(a[1] - (c * r0[1] - sn * r0[2])) < 1e-5 && fabs(a[2] - (sn * r0[1] + c * r0[2])) < 1e-5);
            assert_true(fabs(b[1] - (c * r0[1] + sn * r0[2])) < 1e-5 && fabs(b[2] - (-sn * r0[1] + c * r0[2])) < 1e-5);
            moved++;
        } else if (r0[2] <= -0.125f - 1e-6f) {
            for (int k = 0; k < 3; k++) assert_true(fabsf(a[k] - r0[k]) < 1e-6f && fabsf(b[k] - r0[k]) < 1e-6f);
            kept++;
        }
    }
    assert_true(moved > 50 && kept > 50);
    sss_mesh p0;
    if (sss_import_mesh_at(p, 0.0, &p0, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    for (size_t i = 0; i < 3 * (size_t)rest.nv; i++) assert_true(fabsf(p0.pos[i] - rest.pos[i]) < 1e-6f);
    sss_mesh_free(&p0);
    assert_int_equal(sss_import_mesh_at(p, NAN, &p0, NULL, &err), SSS_ERR_ARG);
    assert_null(p0.pos); /* zeroed on failure */
    sss_mesh_free(&tube), sss_mesh_free(&rest), sss_mesh_free(&p1), sss_mesh_free(&p3), sss_mesh_free(&p9);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(skinnedTubeReadsAsItsRestPose),
        cmocka_unit_test(posedTubeBendsItsUpperHalfByTheClip),
        cmocka_unit_test(badJointIndexIsRefusedByAccessorAndVertex),
        cmocka_unit_test(weightsNotSummingToOneAreRefusedByAccessorAndVertex),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
