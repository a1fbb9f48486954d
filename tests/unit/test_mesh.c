/* test_mesh.c: the mesh helpers of libsss that the bake and the viewer must
 * agree on: bounds and the ray-offset rule (sss/mesh.h). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "sss/mesh.h"

/* An axis-aligned box with corners lo and hi as a two-triangle-per-face
 * mesh (only the positions matter here). */
static void box(sss_mesh *m, const double lo[3], const double hi[3])
{
    assert_int_equal(sss_mesh_alloc(m, 8, 12, NULL), SSS_OK);
    for (uint32_t v = 0; v < 8; v++)
        for (int k = 0; k < 3; k++) m->pos[3 * v + k] = (float)((v >> k & 1u) ? hi[k] : lo[k]);
    static const uint32_t t[36] = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                   2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
    memcpy(m->tri, t, sizeof t);
}

static void rayOffsetIsTenMicroDiagonalsRoundedOnce(void **state)
{
    (void)state;
    sss_mesh m;
    const double lo[3] = {-1, -2, 0}, hi[3] = {3, 2, 2}; /* extents 4, 4, 2: diagonal 6 */
    box(&m, lo, hi);
    double blo[3], bhi[3];
    assert_true(fabs(sss_mesh_bounds(&m, blo, bhi) - 6.0) < 1e-12);
    assert_true(sss_mesh_ray_offset(&m) == (float)(1e-5 * 6.0));
    sss_mesh_free(&m);
}

static void rayOffsetFollowsScaleNotPosition(void **state)
{
    (void)state;
    sss_mesh a, b, c;
    const double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 1};
    const double lo2[3] = {100, -50, 7}, hi2[3] = {101, -49, 8};  /* the same box moved */
    const double lo3[3] = {0, 0, 0}, hi3[3] = {1000, 1000, 1000}; /* scaled by 1000 */
    box(&a, lo, hi);
    box(&b, lo2, hi2);
    box(&c, lo3, hi3);
    assert_true(fabsf(sss_mesh_ray_offset(&a) - sss_mesh_ray_offset(&b)) <= 1e-6f * sss_mesh_ray_offset(&a));
    assert_true(fabsf(sss_mesh_ray_offset(&c) / sss_mesh_ray_offset(&a) - 1000.0f) < 1e-3f);
    sss_mesh_free(&a);
    sss_mesh_free(&b);
    sss_mesh_free(&c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(rayOffsetIsTenMicroDiagonalsRoundedOnce),
        cmocka_unit_test(rayOffsetFollowsScaleNotPosition),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
