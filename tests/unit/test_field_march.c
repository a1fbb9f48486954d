#define _POSIX_C_SOURCE 200809L
/* The bake's fast paths through the field kernel's march (docs/heterogeneous.md
 * §4.2, §8): the bricks' early-out must give τ's sum with the plain march's
 * bits on random segments through veins, strata, an inclusion and a grid,
 * and the rows scaled pair by pair (each pair's κ computed once for both
 * its entries) must hold exactly what κ gives entry by entry. */
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
#include "sss/field.h"
#include "sss/fieldweights.h"

/* A small deterministic generator (xorshift64*), so that a failure
 * reproduces. */
static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(void)
{
    rng ^= rng >> 12, rng ^= rng << 25, rng ^= rng >> 27;
    return (double)((rng * 0x2545f4914f6cdd1dull) >> 11) / 9007199254740992.0;
}

static void ball(sss_mesh *m)
{
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(m, 10.0, 2, &err), SSS_OK);
}

/* The hetero of one field around the ball (mm = world units), marble-like
 * base, a more absorbing inside. */
static void hetero_of(const sss_field *f, sss_hetero *h, sss_material *base)
{
    memset(h, 0, sizeof *h);
    h->field = *f;
    h->xf[0] = h->xf[5] = h->xf[10] = 1.0;
    *base = (sss_material){.name = "b", .sigma_a = {0.01, 0.02, 0.03}, .sigmap_s = {1, 1.2, 1.4}, .eta = 1.3};
    h->inside = *base;
    for (int c = 0; c < 3; c++) h->inside.sigma_a[c] = 0.3;
}

/* Random segments inside the ball's box, random step counts, and means
 * from the σtr of random f (a quarter of them both endpoints at f = 0, the
 * commonest pair where the field is mostly base): the sum with the bricks
 * (used whether or not the kernel chose to, use_bricks) has the plain
 * march's bits. Returns the share of midpoints that fall in a brick at
 * most the mean in every channel (what the early-out skips); *chose the
 * kernel's own choice. */
static double march_matches_plain(const char *what, const sss_field *f, int *chose)
{
    sss_mesh m;
    ball(&m);
    sss_hetero h;
    sss_material base;
    hetero_of(f, &h, &base);
    sss_field_kernel k;
    sss_error err = {{0}};
    if (sss_field_kernel_create(&m, 1.0, &base, &h, 3, 1e-3, what, &k, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_non_null(k.brick_hi);
    double *bricks = k.brick_hi;
    *chose = k.use_bricks;
    k.use_bricks = 1;
    long below = 0, total = 0, differ = 0, run = 0;
    const double face = k.t_voxel * SSS_FIELD_BRICK; /* a brick's side, mm */
    for (int s = 0; s < 4000; s++) {
        double a[3], b[3], mean[3];
        for (int x = 0; x < 3; x++) {
            a[x] = -10.0 + 20.0 * uniform();
            b[x] = s % 5 == 0 ? a[x] + 2.0 * (uniform() - 0.5) : -10.0 + 20.0 * uniform();
        }
        /* the cases where a brick-to-brick step could go wrong: segments
         * along an axis or in a plane (no face crossed along the others),
         * endpoints on brick faces, and ends beyond the grid, where the
         * cells clamp to its edge */
        if (s % 7 == 1)
            for (int x = 1 + s % 3; x < 3; x++) b[x] = a[x];
        if (s % 6 == 2)
            for (int x = 0; x < 3; x++) {
                a[x] = k.t_origin[x] + face * floor((a[x] - k.t_origin[x]) / face);
                b[x] = k.t_origin[x] + face * floor((b[x] - k.t_origin[x]) / face);
            }
        if (s % 9 == 4)
            for (int x = 0; x < 3; x++) a[x] *= 1.3, b[x] *= 1.3;
        const double fa = s % 4 == 0 ? 0.0 : uniform(), fb = s % 4 == 0 ? 0.0 : uniform();
        for (uint32_t c = 0; c < 3; c++)
            mean[c] = 0.5 * (sss_material_sigma_tr(&base, &h.inside, fa, c) + sss_material_sigma_tr(&base, &h.inside, fb, c));
        const int n = 1 + (int)(64.0 * uniform()) % SSS_FIELD_MARCH_MAX;
        double fast[3], plain[3];
        k.brick_hi = bricks;
        sss_field_march_sum(&k, a, b, n, mean, fast);
        k.brick_hi = NULL;
        sss_field_march_sum(&k, a, b, n, mean, plain);
        if (memcmp(fast, plain, sizeof fast) != 0) differ++;
        /* the midpoints the bricks skip, counted from the kernel's grid,
         * and those skipped as the continuation of a run in one brick
         * (the brick-to-brick step) */
        size_t prev[3] = {SIZE_MAX, SIZE_MAX, SIZE_MAX};
        for (int j = 0; j < n; j++) {
            const double t = (j + 0.5) / n;
            size_t bi[3];
            for (int x = 0; x < 3; x++) {
                const double top = (double)(k.tn[x] - 1);
                double u = (a[x] + t * (b[x] - a[x]) - k.t_origin[x]) / k.t_voxel;
                u = u < 0.0 ? 0.0 : u > top ? top : u;
                size_t cl = (size_t)u;
                if (k.tn[x] > 1 && cl >= k.tn[x] - 1) cl = k.tn[x] - 2;
                bi[x] = cl / SSS_FIELD_BRICK;
            }
            const double *hb = bricks + ((bi[2] * k.bn[1] + bi[1]) * k.bn[0] + bi[0]) * 3;
            const int skip = hb[0] <= mean[0] && hb[1] <= mean[1] && hb[2] <= mean[2];
            below += skip;
            run += skip && bi[0] == prev[0] && bi[1] == prev[1] && bi[2] == prev[2];
            memcpy(prev, bi, sizeof prev);
            total++;
        }
    }
    k.brick_hi = bricks;
    print_message("%s: %ld of 4000 segments differ; %.1f %% of the midpoints in bricks below the mean, %.1f %% "
                  "inside a run in one; the kernel %s the bricks\n", what, differ, 100.0 * below / total,
                  100.0 * run / total, *chose ? "uses" : "leaves out");
    assert_int_equal(differ, 0);
    assert_true(run > total / 20);
    sss_field_kernel_free(&k);
    sss_mesh_free(&m);
    return (double)below / total;
}

static void bricksEarlyOutHasThePlainMarchsBits(void **state)
{
    (void)state;
    const sss_field veins = {.kind = SSS_FIELD_VEINS, .seed = 3, .scale_mm = 8.0};
    const sss_field strata = {.kind = SSS_FIELD_LAYERS, .normal = {0.36, 0.48, 0.8}, .thickness_mm = 2.0,
                              .scale_mm = 6.0, .offset_mm = 0.3, .edge_mm = 0.5};
    const sss_field stone = {.kind = SSS_FIELD_SPHERE, .centre_mm = {2, -1, 3}, .half_mm = {4}, .edge_mm = 1.0};
    /* a grid: a slanted slab of f = 1 in a 24³ block, 1 mm voxels, with
     * one node of 0.5 beside it */
    static float data[24 * 24 * 24];
    for (int z = 0; z < 24; z++)
        for (int y = 0; y < 24; y++)
            for (int x = 0; x < 24; x++) data[(z * 24 + y) * 24 + x] = fabs((double)x + 0.5 * y - 17.0) < 2.5 ? 1.0f : 0.0f;
    data[(5 * 24 + 5) * 24 + 5] = 0.5f;
    const sss_field grid = {.kind = SSS_FIELD_GRID, .n = {24, 24, 24}, .origin_mm = {-11.5, -11.5, -11.5},
                            .voxel_mm = 1.0, .data = data};
    /* each early-out skips a real share of the midpoints, so the bits
     * checked above come from the fast path and not from a fallback; the
     * kernel keeps the bricks for the fields with plateaus and leaves them
     * out through veins, which vary everywhere (§4.2) */
    int chose[4];
    assert_true(march_matches_plain("veins", &veins, &chose[0]) > 0.05);
    assert_true(march_matches_plain("strata", &strata, &chose[1]) > 0.2);
    assert_true(march_matches_plain("inclusion", &stone, &chose[2]) > 0.3);
    assert_true(march_matches_plain("grid", &grid, &chose[3]) > 0.3);
    assert_false(chose[0]);
    assert_true(chose[1] && chose[2] && chose[3]);
}

/* Rows of every pair within 6 mm, sorted, all weights 1: scaled by the
 * kernel (each pair's march once, κ(i, o) reused where no disk covers an
 * endpoint), every entry must hold the float of κ(o, i) computed alone,
 * with and without the bricks. */
static void rowsScaledPairByPairHoldEachEntrysKappa(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 10.0, 3, &err), SSS_OK);
    /* every 7th vertex's area × 16: its disk (radius sqrt(A/π)) then
     * covers its neighbours, whose κ takes the disk profiles (not reused) */
    for (uint32_t v = 0; v < m.nv; v += 7) m.area[v] *= 16.0;
    const sss_field veins = {.kind = SSS_FIELD_VEINS, .seed = 5, .scale_mm = 6.0};
    sss_hetero h;
    sss_material base;
    hetero_of(&veins, &h, &base);
    sss_field_kernel k;
    if (sss_field_kernel_create(&m, 1.0, &base, &h, 3, 1e-3, "ball", &k, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_weights rows = {.nrows = m.nv, .channels = 3};
    rows.start = calloc((size_t)m.nv + 1, sizeof *rows.start);
    assert_non_null(rows.start);
    for (int pass = 0; pass < 2; pass++) {
        uint64_t e = 0;
        for (uint32_t o = 0; o < m.nv; o++) {
            rows.start[o] = e;
            for (uint32_t i = 0; i < m.nv; i++) {
                double d2 = 0.0;
                for (int x = 0; x < 3; x++) d2 += pow(m.pos[3 * i + x] - m.pos[3 * o + x], 2);
                if (d2 > 36.0) continue;
                if (pass) rows.idx[e] = i;
                e++;
            }
        }
        rows.start[m.nv] = e;
        if (!pass) {
            rows.idx = malloc(e * sizeof *rows.idx);
            rows.w = malloc(e * 3 * sizeof *rows.w);
            assert_true(rows.idx && rows.w);
        }
    }
    double *bricks = k.brick_hi;
    k.use_bricks = 1; /* the early-out's path as well, whatever the kernel chose for these veins */
    long near = 0;
    for (int use = 0; use < 2; use++) {
        k.brick_hi = use ? bricks : NULL;
        for (uint64_t e = 0; e < rows.start[m.nv] * 3; e++) rows.w[e] = 1.0f;
        assert_int_equal(sss_field_weights_apply(&k, &m, &rows, NULL, &err), SSS_OK);
        for (uint32_t o = 0; o < m.nv; o++)
            for (uint64_t e = rows.start[o]; e < rows.start[o + 1]; e++) {
                double kap[3];
                sss_field_kappa(&k, &m, o, rows.idx[e], kap);
                for (int c = 0; c < 3; c++) assert_true(rows.w[e * 3 + c] == (float)kap[c]);
                if (!use && rows.idx[e] != o) {
                    /* pairs whose disks cover the other endpoint take their own profiles */
                    double d2 = 0.0;
                    for (int x = 0; x < 3; x++) d2 += pow(m.pos[3 * rows.idx[e] + x] - m.pos[3 * o + x], 2);
                    near += d2 < m.area[o] / 3.14159 || d2 < m.area[rows.idx[e]] / 3.14159;
                }
            }
    }
    k.brick_hi = bricks;
    print_message("%llu entries, %ld with a disk over the other endpoint\n", (unsigned long long)rows.start[m.nv], near);
    assert_true(rows.start[m.nv] > 20 * (uint64_t)m.nv);
    assert_true(near > 100);
    assert_true(k.f_min < k.f_max);
    sss_weights_free(&rows);
    sss_field_kernel_free(&k);
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bricksEarlyOutHasThePlainMarchsBits),
        cmocka_unit_test(rowsScaledPairByPairHoldEachEntrysKappa),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
