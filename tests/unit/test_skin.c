/* test_skin.c: skinned glTF input (docs/deformable.md §5): the two-bone
 * tube sss-genmesh writes (gltf_write.c, SSS_GLTF_SKIN) passes the
 * importer's checks of JOINTS_0, WEIGHTS_0 and the skin, and reads as its
 * rest pose; a joint index beyond the skin's joints or weights that do not
 * sum to 1 give one line naming the file, the accessor and the vertex. */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "genmesh.h"
#include "gltf_write.h"
#include "sss/import.h"

static char g_dir[64], g_files[4][160];
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(skinnedTubeReadsAsItsRestPose),
        cmocka_unit_test(badJointIndexIsRefusedByAccessorAndVertex),
        cmocka_unit_test(weightsNotSummingToOneAreRefusedByAccessorAndVertex),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
