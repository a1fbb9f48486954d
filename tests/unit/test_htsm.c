/* The run-time estimator of a heterogeneous object (sss/htsm.h,
 * docs/heterogeneous.md §9): a back-lit slab whose light-space map the test
 * fills itself (the lit face z = 0, E_t = 1), the exit point on the far face.
 * Its pattern tiles the disk it claims, a constant field is the homogeneous
 * answer, an absorbing inclusion only darkens, the march converges at the
 * midpoint rule's order as its steps grow, and bad arguments are refused. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sss/htsm.h"
#include "sss/vec3.h"

#define MAP 256
#define WIDTH 40.0 /* mm: the map spans [-20, 20]² */
#define T 10.0     /* the slab's thickness, mm */
#define R0 1.25    /* the pattern's inner radius: 13 samples reach 10 mm */

/* The slab's lit face as the light sees it: every texel covered, position
 * (x, y, 0), normal −z, E_t = 1 in every channel. */
static void slab_map(sss_htsm_map *m)
{
    sss_error err = {{0}};
    assert_int_equal(sss_htsm_map_init(m, MAP, &err), SSS_OK);
    memset(m->lookup, 0, sizeof m->lookup);
    m->lookup[0] = (float)(1.0 / WIDTH);
    m->lookup[5] = (float)(1.0 / WIDTH);
    m->lookup[12] = 0.5f;
    m->lookup[13] = 0.5f;
    m->lookup[15] = 1.0f;
    m->light[2] = -1.0; /* towards the light: −z, directional */
    for (uint32_t j = 0; j < MAP; j++)
        for (uint32_t i = 0; i < MAP; i++) {
            float *p = m->pos[0] + ((size_t)j * MAP + i) * 4, *n = m->nrm[0] + ((size_t)j * MAP + i) * 4,
                  *e = m->irr[0] + ((size_t)j * MAP + i) * 4;
            p[0] = (float)(((i + 0.5) / MAP - 0.5) * WIDTH);
            p[1] = (float)(((j + 0.5) / MAP - 0.5) * WIDTH);
            p[2] = 0.0f;
            p[3] = 1.0f;
            n[2] = -1.0f;
            n[3] = 1.0f;
            e[0] = e[1] = e[2] = e[3] = 1.0f;
        }
    sss_htsm_map_mips(m);
}

static void materials(sss_htsm_material *mat)
{
    memset(mat, 0, sizeof *mat);
    strcpy(mat->base.name, "base");
    mat->base.eta = 1.3;
    mat->inside = mat->base;
    for (int c = 0; c < 3; c++) {
        mat->base.sigma_a[c] = 0.01 * (c + 1);
        mat->base.sigmap_s[c] = 1.0;
        mat->inside.sigma_a[c] = 0.05 * (c + 1);
        mat->inside.sigmap_s[c] = 1.0;
    }
    mat->strength = 1.0;
    mat->mm_per_unit = 1.0;
}

static void hetero(sss_hetero *h, uint32_t kind, const sss_htsm_material *mat)
{
    memset(h, 0, sizeof *h);
    h->field.kind = kind;
    h->inside = mat->inside;
    h->xf[0] = h->xf[5] = h->xf[10] = 1.0; /* mesh units are rest-frame mm */
}

static void volume(const sss_hetero *h, sss_htsm_volume *v)
{
    const double lo[3] = {-WIDTH / 2, -WIDTH / 2, 0.0}, hi[3] = {WIDTH / 2, WIDTH / 2, T};
    sss_error err = {{0}};
    assert_int_equal(sss_htsm_volume_build(h, lo, hi, 6, v, &err), SSS_OK);
}

static void pattern(uint32_t n, const sss_htsm_map *m, sss_htsm_pattern *p)
{
    sss_error err = {{0}};
    assert_int_equal(sss_htsm_pattern_make(n, R0, sss_htsm_texel_mm(m, 1.0), m->levels, p, &err), SSS_OK);
}

/* The areas tile the disk of radius r0 2^k that n = 4k + 1 samples claim,
 * each sample lies inside its own quarter annulus, and the coarser rings
 * read coarser levels. */
static void patternTilesItsDiskAndCoarsensOutwards(void **state)
{
    (void)state;
    sss_htsm_map m;
    slab_map(&m);
    for (uint32_t k = 0; k <= 3; k++) {
        sss_htsm_pattern p;
        pattern(4 * k + 1, &m, &p);
        double sum = 0.0;
        for (uint32_t i = 0; i < p.n; i++) sum += p.area[i];
        const double R = R0 * ldexp(1.0, (int)k);
        assert_true(fabs(sum - SSS_PI * R * R) < 1e-12 * sum);
        for (uint32_t i = 1; i < p.n; i++) {
            const uint32_t ring = (i - 1) / 4 + 1;
            const double r = hypot(p.off[i][0], p.off[i][1]);
            assert_true(r > R0 * ldexp(1.0, (int)ring - 1) && r < R0 * ldexp(1.0, (int)ring));
            assert_int_equal(p.vol_level[i], ring);
            assert_true(p.map_level[i] >= p.map_level[i > 4 ? i - 4 : 0]);
        }
    }
    sss_htsm_map_free(&m);
}

/* f = c everywhere: every excess under τ is 0 and sqrt(P·P) = P, so the
 * estimate is the homogeneous one of the blend at c, to rounding. */
static void constantFieldEqualsTheHomogeneousAnswer(void **state)
{
    (void)state;
    sss_htsm_map m;
    slab_map(&m);
    sss_htsm_material mat;
    materials(&mat);
    sss_hetero h;
    hetero(&h, SSS_FIELD_CONSTANT, &mat);
    h.field.value = 0.37;
    sss_htsm_volume v;
    volume(&h, &v);
    sss_htsm_material hom = mat;
    sss_material_blend(&mat.base, &mat.inside, (double)(float)0.37, &hom.base);
    for (uint32_t n = 1; n <= 13; n += 4) {
        sss_htsm_pattern p;
        pattern(n, &m, &p);
        const double xo[3][3] = {{0, 0, T}, {3.1, -2.2, T}, {0.4, 0.3, 0}};
        for (int k = 0; k < 3; k++) {
            double q[3], q0[3];
            sss_htsm_q(&m, &v, &mat, &p, 16, xo[k], q);
            sss_htsm_q(&m, NULL, &hom, &p, 16, xo[k], q0);
            for (int c = 0; c < 3; c++) {
                assert_true(q0[c] > 0.0);
                assert_true(fabs(q[c] - q0[c]) <= 1e-12 * q0[c]);
            }
        }
    }
    sss_htsm_volume_free(&v);
    sss_htsm_map_free(&m);
}

static void inclusion(sss_hetero *h, const sss_htsm_material *mat)
{
    hetero(h, SSS_FIELD_SPHERE, mat);
    h->field.centre_mm[2] = T / 2;
    h->field.half_mm[0] = 2.5;
    h->field.edge_mm = 0.5;
}

/* A ball of 5× the absorption in the middle of the slab: no exit point on
 * the far face is brighter than without it for any pattern or step count,
 * and the one straight behind it is clearly darker. */
static void absorbingInclusionNeverBrightens(void **state)
{
    (void)state;
    sss_htsm_map m;
    slab_map(&m);
    sss_htsm_material mat;
    materials(&mat);
    sss_hetero h;
    inclusion(&h, &mat);
    sss_htsm_volume v;
    volume(&h, &v);
    double darkest = 1.0;
    for (uint32_t n = 1; n <= 13; n += 4) {
        sss_htsm_pattern p;
        pattern(n, &m, &p);
        for (uint32_t steps = 2; steps <= 64; steps *= 4)
            for (int y = -4; y <= 4; y++)
                for (int x = -4; x <= 4; x++) {
                    const double xo[3] = {1.5 * x, 1.5 * y, T};
                    double q[3], q0[3];
                    sss_htsm_q(&m, &v, &mat, &p, steps, xo, q);
                    sss_htsm_q(&m, NULL, &mat, &p, steps, xo, q0);
                    for (int c = 0; c < 3; c++) {
                        assert_true(q0[c] > 0.0);
                        assert_true(q[c] <= q0[c] * (1.0 + 1e-12));
                        if (x == 0 && y == 0) darkest = fmin(darkest, q[c] / q0[c]);
                    }
                }
    }
    printf("behind the inclusion: q / q_homogeneous down to %.4f\n", darkest);
    assert_true(darkest < 0.5);
    sss_htsm_volume_free(&v);
    sss_htsm_map_free(&m);
}

/* τ's march is the midpoint rule on a piecewise smooth integrand (the
 * trilinear field, kinked at cell faces and where the excess meets 0): its
 * error should fall like steps⁻². The order is the least-squares slope of
 * log error against log steps, 4 to 128 steps, against 1024. */
static void marchConvergesAsStepsGrow(void **state)
{
    (void)state;
    sss_htsm_map m;
    slab_map(&m);
    sss_htsm_material mat;
    materials(&mat);
    sss_hetero h;
    inclusion(&h, &mat);
    sss_htsm_volume v;
    volume(&h, &v);
    for (uint32_t n = 1; n <= 13; n += 12) {
        sss_htsm_pattern p;
        pattern(n, &m, &p);
        const double xo[3] = {0.7, -0.4, T};
        double ref[3];
        sss_htsm_q(&m, &v, &mat, &p, 1024, xo, ref);
        double sx = 0, sy = 0, sxx = 0, sxy = 0, e64 = 0;
        int k = 0;
        for (uint32_t steps = 4; steps <= 128; steps *= 2, k++) {
            double q[3];
            sss_htsm_q(&m, &v, &mat, &p, steps, xo, q);
            double e = 0.0;
            for (int c = 0; c < 3; c++) e = fmax(e, fabs(q[c] - ref[c]) / ref[c]);
            printf("n = %2u, %3u steps: relative error %.3e\n", n, steps, e);
            if (steps == 64) e64 = e;
            const double lx = log((double)steps), ly = log(e);
            sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
        }
        const double order = -(k * sxy - sx * sy) / (k * sxx - sx * sx);
        printf("n = %2u: observed order %.2f\n", n, order);
        assert_true(order > 1.6 && order < 2.6);
        assert_true(e64 < 2e-3);
    }
    sss_htsm_volume_free(&v);
    sss_htsm_map_free(&m);
}

/* The volume's levels keep a constant, and a map or pattern the estimator
 * cannot use is refused with a message. */
static void volumeLevelsAndBadArguments(void **state)
{
    (void)state;
    sss_htsm_material mat;
    materials(&mat);
    sss_hetero h;
    hetero(&h, SSS_FIELD_CONSTANT, &mat);
    h.field.value = 0.25;
    sss_htsm_volume v;
    volume(&h, &v);
    assert_int_equal(v.n[0], 64u);
    assert_int_equal(v.n[v.levels - 1], 2u);
    for (uint32_t l = 0; l < v.levels; l++) {
        const double x[3] = {3.3, -7.1, 2.2};
        assert_true(fabs(sss_htsm_volume_at(&v, l, x) - 0.25) < 1e-7);
    }
    sss_htsm_volume_free(&v);
    sss_error err = {{0}};
    sss_htsm_map m;
    assert_int_equal(sss_htsm_map_init(&m, 3, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "power of two"));
    sss_htsm_pattern p;
    assert_int_equal(sss_htsm_pattern_make(4, 1.0, 0.1, 4, &p, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "1, 5, 9 and 13"));
    assert_int_equal(sss_htsm_pattern_make(5, 0.0, 0.1, 4, &p, &err), SSS_ERR_ARG);
}

/* The slab's lit face as a point light at (0, 0, −D) sees it: a
 * perspective map whose texels meet the face where the orthographic map's
 * do (the cone through the map's edges at depth D), E_t = I / r² with I =
 * D² (1 at the foot of the light), the light and ref_w = D recorded. */
static void slab_point_map(sss_htsm_map *m, double D)
{
    slab_map(m);
    const double k = 0.5 * D / (0.5 * WIDTH); /* ½ / tan θ, tan θ = (W/2) / D */
    memset(m->lookup, 0, sizeof m->lookup);
    /* s w = (½ / tan θ) x + ½ w, t likewise, w = z + D */
    m->lookup[0] = (float)k;
    m->lookup[5] = (float)k;
    m->lookup[8] = m->lookup[9] = 0.5f;
    m->lookup[12] = m->lookup[13] = (float)(0.5 * D);
    m->lookup[11] = 1.0f;
    m->lookup[15] = (float)D;
    m->light[2] = -D;
    m->light[3] = 1.0;
    m->ref_w = D;
    for (uint32_t t = 0; t < MAP * MAP; t++) {
        const float *p = m->pos[0] + 4 * (size_t)t;
        const double r2 = (double)p[0] * p[0] + (double)p[1] * p[1] + D * D;
        for (int c = 0; c < 3; c++) m->irr[0][4 * (size_t)t + (size_t)c] = (float)(D * D / r2);
    }
    sss_htsm_map_mips(m);
}

/* A point light's perspective map (§9.2, "Point lights"): its texel at the
 * depth of reference is the orthographic map's; far away the estimate is
 * the directional one (within 10⁻⁶ at 10⁵ mm: 2·10⁻⁸ measured), and near
 * it is darker by percents (30 mm: 3.5–8.5 %), the light falling off as
 * 1/r² away from its foot and each sample standing for less area across
 * its slanted ray. */
static void farPointLightIsTheDirectionalLight(void **state)
{
    (void)state;
    sss_htsm_map md, mp;
    slab_map(&md);
    sss_htsm_material mat;
    materials(&mat);
    const double xo[3][3] = {{0, 0, T}, {3.1, -2.2, T}, {0.4, 0.3, 0}};
    const double D[2] = {1e5, 30.0};
    for (int k = 0; k < 2; k++) {
        slab_point_map(&mp, D[k]);
        assert_true(fabs(sss_htsm_texel_mm(&mp, 1.0) - WIDTH / MAP) < 1e-6 * WIDTH / MAP);
        for (uint32_t n = 1; n <= 13; n += 4) {
            sss_htsm_pattern p;
            pattern(n, &md, &p);
            double worst = 0.0;
            for (int x = 0; x < 3; x++) {
                double qd[3], qp[3];
                sss_htsm_q(&md, NULL, &mat, &p, 4, xo[x], qd);
                sss_htsm_q(&mp, NULL, &mat, &p, 4, xo[x], qp);
                for (int c = 0; c < 3; c++) {
                    assert_true(qd[c] > 0.0 && qp[c] > 0.0);
                    /* near, every texel but the one under the light gets less (E = I / r² < 1) and
                     * stands for less area across its slanted ray */
                    if (k == 1) assert_true(qp[c] < qd[c]);
                    worst = fmax(worst, fabs(qp[c] - qd[c]) / qd[c]);
                }
            }
            printf("point light at %g mm, n = %2u: largest relative difference from the directional %.2e\n", D[k],
                   n, worst);
            assert_true(k == 0 ? worst < 1e-6 : worst > 1e-2);
        }
        sss_htsm_map_free(&mp);
    }
    sss_htsm_map_free(&md);
}

/* A point light is drawn from outside the maps' sphere only (the mesh's
 * bounding sphere, 2 % larger): a box of half-diagonal 1.5 about (1, 0, 0),
 * lights along +x just inside and just outside 1.02 · 1.5; the message
 * names the light and the object. */
static void pointLightOutsideTheMapsSphereOnly(void **state)
{
    (void)state;
    sss_mesh m = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_mesh_alloc(&m, 2, 0, &err), SSS_OK);
    const float corner[6] = {0.0f, -1.0f, -0.5f, 2.0f, 1.0f, 0.5f};
    memcpy(m.pos, corner, sizeof corner);
    const double R = 1.5 * (1.0 + SSS_HTSM_MAP_MARGIN);
    double r = 0.0;
    const double in[3] = {1.0 + R * (1.0 - 1e-9), 0.0, 0.0}, out[3] = {1.0 + R * (1.0 + 1e-9), 0.0, 0.0},
                 centre[3] = {1.0, 0.0, 0.0};
    assert_int_equal(sss_htsm_point_drawn(&m, in, &r), 0);
    assert_true(fabs(r - R) < 1e-12);
    assert_int_equal(sss_htsm_point_drawn(&m, centre, NULL), 0);
    assert_int_equal(sss_htsm_point_drawn(&m, out, NULL), 1);
    char msg[320];
    sss_htsm_point_inside_msg(msg, sizeof msg, centre, "blob", r);
    assert_non_null(strstr(msg, "the point light at (1, 0, 0) lies within object 'blob''s bounding sphere (radius 1.53)"));
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(patternTilesItsDiskAndCoarsensOutwards),
        cmocka_unit_test(constantFieldEqualsTheHomogeneousAnswer),
        cmocka_unit_test(absorbingInclusionNeverBrightens),
        cmocka_unit_test(marchConvergesAsStepsGrow),
        cmocka_unit_test(volumeLevelsAndBadArguments),
        cmocka_unit_test(farPointLightIsTheDirectionalLight),
        cmocka_unit_test(pointLightOutsideTheMapsSphereOnly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
