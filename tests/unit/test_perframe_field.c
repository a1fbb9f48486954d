/* test_perframe_field.c: the object-space per-frame path with a material
 * field on a deforming object (sss/perframe.h, docs/deformable.md §10):
 * each vertex takes the blend at f of its rest-pose position, and each
 * pair the endpoints' product sqrt(R_d(r; m_o) R_d(r; m_i)) (seed 003
 * Eq. 8) without the transmittance τ. Checked: a constant field is the
 * homogeneous blend bit for bit; on a bent pose q is the direct sum of the
 * endpoint products over every pair within the radius, computed here
 * from the dipoles of the per-vertex materials; a rigid motion of the rest
 * pose carries the material with it (q unchanged) while a field left in
 * place changes q; the refusals. */
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
#include "sss/field.h"
#include "sss/hatweights.h"
#include "sss/perframe.h"
#include "sss/planner.h"
#include "sss/scene.h"
#include "sss/transfer.h"
#include "sss/vec3.h"
#include "sss/visibility.h"

#define MM_PER_UNIT 20.0

/* The lumpy blob (642 vertices, about 40 mm across) at rest and bent by
 * 60° about z. */
static sss_mesh g_rest, g_pose;
static sss_material g_base, g_inside;
static const double g_light[3] = {0.3, 0.2, 0.93};

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    if (sss_gen_blob(&g_rest, 1.0, 3, &err) != SSS_OK) return -1;
    sss_deform bend = {.kind = SSS_DEFORM_BEND, .axis = {0, 0, 1}, .angle_deg = 60.0, .period_s = 4.0};
    if (sss_deform_pose(&bend, 1.0, &g_rest, "blob", &g_pose, &err) != SSS_OK) return -1;
    if (sss_material_preset("skin1", &g_base, &err) != SSS_OK) return -1;
    return sss_material_preset("ketchup", &g_inside, &err) == SSS_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    sss_mesh_free(&g_rest);
    sss_mesh_free(&g_pose);
    return 0;
}

/* Strata of ketchup in skin1 across x (8 mm thick every 16 mm, 2 mm
 * edges), the rest frame in mm: x_mm = MM_PER_UNIT · x. */
static void strata(sss_hetero *h)
{
    memset(h, 0, sizeof *h);
    h->field.kind = SSS_FIELD_LAYERS;
    h->field.normal[0] = 1.0;
    h->field.thickness_mm = 8.0;
    h->field.scale_mm = 16.0;
    h->field.offset_mm = -4.0;
    h->field.edge_mm = 2.0;
    h->inside = g_inside;
    h->xf[0] = h->xf[5] = h->xf[10] = MM_PER_UNIT;
}

static float *q_or_fail(const sss_mesh *m, const sss_material *mat, const double L[3], uint32_t weights,
                        const sss_hetero *h, const float *rest)
{
    float *q = malloc((size_t)m->nv * 3 * sizeof *q);
    assert_non_null(q);
    sss_perframe_options o = {.weights = weights, .hetero = h, .rest = rest};
    sss_error err = {{0}};
    if (sss_perframe_q(m, mat, 3, MM_PER_UNIT, L, &o, q, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    return q;
}

/* max |a − b| over max |b| */
static double max_rel(const float *a, const float *b, size_t n)
{
    double d = 0, m = 0;
    for (size_t i = 0; i < n; i++) {
        d = fmax(d, fabs((double)a[i] - b[i]));
        m = fmax(m, fabs((double)b[i]));
    }
    return m > 0 ? d / m : d;
}

static void constantFieldGivesTheHomogeneousBlendBitForBit(void **state)
{
    (void)state;
    const double cs[3] = {0.0, 0.35, 1.0};
    const size_t n = (size_t)g_pose.nv * 3;
    for (int i = 0; i < 3; i++)
        for (uint32_t w = 0; w < 2; w++) {
            sss_hetero h;
            strata(&h);
            memset(&h.field, 0, sizeof h.field);
            h.field.kind = SSS_FIELD_CONSTANT;
            h.field.value = cs[i];
            sss_material blend;
            sss_material_blend(&g_base, &g_inside, cs[i], &blend);
            float *qf = q_or_fail(&g_pose, &g_base, g_light, w, &h, g_rest.pos);
            float *qh = q_or_fail(&g_pose, &blend, g_light, w, NULL, NULL);
            print_message("constant c = %.2f, %s weights: max difference %.3g of max q\n", cs[i], w ? "hat" : "point",
                          max_rel(qf, qh, n));
            assert_memory_equal(qf, qh, n * sizeof *qf);
            free(qf);
            free(qh);
        }
}

/* The profile the rows use for a pair (nbhd.c with NEAR_DISKS 1): the
 * disk of x_o's own area for the own term, the disk of x_i's area where
 * it covers x_o (weight without ΔA), the point value R_d(r) ΔA otherwise. */
static double pair_weight(const sss_dipole *d, double r, double rho_o, double rho_i, double dA)
{
    if (r == 0.0) return sss_rd_disk(d, rho_o) / SSS_PI;
    if (r < rho_i) return sss_rd_disk_offset(d, r, rho_i) / SSS_PI;
    return sss_rd(d, r) * dA / SSS_PI;
}

/* q on the bent pose, the field read at the rest pose, against the direct
 * sum Σ_i sqrt(w(o, i; m_o) w(o, i; m_i)) G(x_i) over every pair within
 * the radius, with m_v the blend at f(rest position of v). */
static void bentPoseEqualsDirectSumOfEndpointProducts(void **state)
{
    (void)state;
    sss_hetero h;
    strata(&h);
    const uint32_t nv = g_pose.nv;
    float *q = q_or_fail(&g_pose, &g_base, g_light, SSS_WEIGHTS_POINT, &h, g_rest.pos);
    float *qb = q_or_fail(&g_pose, &g_base, g_light, SSS_WEIGHTS_POINT, NULL, NULL);
    /* per-vertex dipoles from the rest positions */
    sss_dipole *dip = malloc((size_t)nv * 3 * sizeof *dip);
    assert_non_null(dip);
    double fmin_ = 1, fmax_ = 0;
    uint32_t n_in = 0;
    for (uint32_t v = 0; v < nv; v++) {
        const double x[3] = {MM_PER_UNIT * g_rest.pos[3 * v], MM_PER_UNIT * g_rest.pos[3 * v + 1],
                             MM_PER_UNIT * g_rest.pos[3 * v + 2]};
        const double f = sss_field_eval(&h.field, x);
        fmin_ = fmin(fmin_, f), fmax_ = fmax(fmax_, f);
        n_in += f > 0.5;
        sss_material m;
        sss_material_blend(&g_base, &g_inside, f, &m);
        for (int c = 0; c < 3; c++)
            assert_int_equal(sss_dipole_init(&dip[3 * v + c], m.sigma_a[c], m.sigmap_s[c], g_base.eta), SSS_OK);
    }
    assert_true(fmin_ < 0.01 && fmax_ > 0.99 && n_in > nv / 5 && n_in < nv * 4 / 5);
    /* the radius: the larger of the rule at f_min and at f_max */
    sss_dipole dlo[3], dhi[3];
    sss_material mlo, mhi;
    sss_material_blend(&g_base, &g_inside, fmin_, &mlo);
    sss_material_blend(&g_base, &g_inside, fmax_, &mhi);
    for (int c = 0; c < 3; c++) {
        sss_dipole_init(&dlo[c], mlo.sigma_a[c], mlo.sigmap_s[c], g_base.eta);
        sss_dipole_init(&dhi[c], mhi.sigma_a[c], mhi.sigmap_s[c], g_base.eta);
    }
    const double R = fmax(sss_cutoff_radius_mm(&g_pose, MM_PER_UNIT, dlo, 3, 1e-3, NULL),
                          sss_cutoff_radius_mm(&g_pose, MM_PER_UNIT, dhi, 3, 1e-3, NULL));
    /* G with the pose's rays */
    float *G = malloc((size_t)nv * sizeof *G);
    sss_vis *vis = NULL;
    sss_error err = {{0}};
    uint64_t rays = 0;
    double L[3];
    sss_light_unit(g_light, L);
    assert_int_equal(sss_vis_create(&g_pose, &vis, &err), SSS_OK);
    assert_int_equal(sss_transfer_compute(&g_pose, vis, L, 1, g_base.eta, NULL, G, &rays, NULL, &err), SSS_OK);
    sss_vis_destroy(vis);
    double worst = 0, qmax = 0, change = 0;
    for (uint32_t o = 0; o < nv; o++) {
        double sum[3] = {0, 0, 0};
        const double rho_o = sqrt(g_pose.area[o] / SSS_PI) * MM_PER_UNIT;
        for (uint32_t i = 0; i < nv; i++) {
            double d2 = 0;
            for (int k = 0; k < 3; k++) {
                const double dx = ((double)g_pose.pos[3 * i + k] - g_pose.pos[3 * o + k]) * MM_PER_UNIT;
                d2 += dx * dx;
            }
            const double r = sqrt(d2);
            if (r > R || G[i] == 0.0f) continue;
            const double dA = g_pose.area[i] * MM_PER_UNIT * MM_PER_UNIT, rho_i = sqrt(dA / SSS_PI);
            for (int c = 0; c < 3; c++) {
                const double wo = pair_weight(&dip[3 * o + c], r, rho_o, rho_i, dA);
                const double wi = pair_weight(&dip[3 * i + c], r, rho_o, rho_i, dA);
                sum[c] += sqrt(wo * wi) * G[i];
            }
        }
        for (int c = 0; c < 3; c++) {
            worst = fmax(worst, fabs(sum[c] - q[3 * o + c]));
            qmax = fmax(qmax, sum[c]);
            change = fmax(change, fabs((double)qb[3 * o + c] - q[3 * o + c]));
        }
    }
    print_message("bent blob, strata read at rest: max |q - direct sum| %.3g of max q; the field changes q by %.3g of "
                  "max q\n", worst / qmax, change / qmax);
    assert_true(worst < 1e-5 * qmax);
    assert_true(change > 0.05 * qmax); /* the field is not a no-op */
    free(G), free(dip), free(q), free(qb);
}

/* The rest pose turned by 40° about z and moved, its light turned with it:
 * the material read at the rest positions moves with the surface and q is
 * unchanged; the field read where the moved vertices are (left in place)
 * changes q. */
static void materialMovesWithTheSurface(void **state)
{
    (void)state;
    sss_hetero h;
    strata(&h);
    const uint32_t nv = g_rest.nv;
    const double a = 40.0 * SSS_PI / 180.0, c = cos(a), s = sin(a), t[3] = {0.4, -0.3, 0.2};
    sss_mesh moved = {0};
    sss_error err = {{0}};
    /* angle 0: the rest pose bit for bit, as a copy */
    sss_deform none = {.kind = SSS_DEFORM_BEND, .axis = {0, 0, 1}, .angle_deg = 0.0, .period_s = 4.0};
    assert_int_equal(sss_deform_pose(&none, 0.0, &g_rest, "blob", &moved, &err), SSS_OK);
    for (uint32_t v = 0; v < nv; v++) {
        const double x = moved.pos[3 * v], y = moved.pos[3 * v + 1];
        moved.pos[3 * v] = (float)(c * x - s * y + t[0]);
        moved.pos[3 * v + 1] = (float)(s * x + c * y + t[1]);
        moved.pos[3 * v + 2] = (float)(moved.pos[3 * v + 2] + t[2]);
    }
    assert_int_equal(sss_mesh_compute_normals_areas(&moved, "moved", &err), SSS_OK);
    const double L1[3] = {c * g_light[0] - s * g_light[1], s * g_light[0] + c * g_light[1], g_light[2]};
    float *q0 = q_or_fail(&g_rest, &g_base, g_light, SSS_WEIGHTS_HAT, &h, g_rest.pos);
    float *q1 = q_or_fail(&moved, &g_base, L1, SSS_WEIGHTS_HAT, &h, g_rest.pos);
    float *q2 = q_or_fail(&moved, &g_base, L1, SSS_WEIGHTS_HAT, &h, moved.pos);
    const double with = max_rel(q1, q0, (size_t)nv * 3), left = max_rel(q2, q0, (size_t)nv * 3);
    print_message("rigid motion: q changes by %.3g of max q with the material carried, %.3g with the field left in "
                  "place\n", with, left);
    assert_true(with < 1e-5);
    assert_true(left > 1e-2);
    free(q0), free(q1), free(q2);
    sss_mesh_free(&moved);
}

static void refusalsAreOneLine(void **state)
{
    (void)state;
    sss_hetero h;
    strata(&h);
    float *q = malloc((size_t)g_pose.nv * 3 * sizeof *q);
    sss_error err = {{0}};
    sss_perframe_options o = {.mode = SSS_PERFRAME_TREE, .hetero = &h, .rest = g_rest.pos};
    assert_int_equal(sss_perframe_q(&g_pose, &g_base, 3, MM_PER_UNIT, g_light, &o, q, NULL, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "exact mode"));
    assert_null(strchr(err.msg, '\n'));
    o.mode = SSS_PERFRAME_EXACT;
    o.rest = NULL;
    assert_int_equal(sss_perframe_q(&g_pose, &g_base, 3, MM_PER_UNIT, g_light, &o, q, NULL, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "rest-pose"));
    /* a field that misses the object: a sphere far away */
    memset(&h.field, 0, sizeof h.field);
    h.field.kind = SSS_FIELD_SPHERE;
    h.field.centre_mm[0] = 1000.0;
    h.field.half_mm[0] = 5.0;
    o.rest = g_rest.pos;
    assert_int_equal(sss_perframe_q(&g_pose, &g_base, 3, MM_PER_UNIT, g_light, &o, q, NULL, &err), SSS_ERR_ARG);
    print_message("%s\n", err.msg);
    assert_null(strchr(err.msg, '\n'));
    free(q);
}

/* The planner sends a deforming object with a field to the per-frame path
 * and says which model; a constant still folds. */
static void plannerTakesAFieldOnADeformingObject(void **state)
{
    (void)state;
    const char *json[2] = {
        "{\"objects\":[{\"mesh\":\"a.ply\",\"mm_per_unit\":20,\"deform\":{\"type\":\"bend\",\"angle_deg\":60},"
        "\"material\":{\"preset\":\"skin1\",\"inside\":\"ketchup\",\"field\":{\"procedural\":\"layers\","
        "\"normal\":[1,0,0],\"thickness_mm\":8,\"period_mm\":16,\"edge_mm\":2}}}],"
        "\"lights\":[{\"type\":\"directional\",\"direction\":[0,0,1]}]}",
        "{\"objects\":[{\"mesh\":\"a.ply\",\"mm_per_unit\":20,\"deform\":{\"type\":\"bend\",\"angle_deg\":60},"
        "\"material\":{\"preset\":\"skin1\",\"inside\":\"ketchup\",\"field\":{\"constant\":0.5}}}],"
        "\"lights\":[{\"type\":\"directional\",\"direction\":[0,0,1]}]}"};
    for (int k = 0; k < 2; k++) {
        sss_scene s;
        sss_error err = {{0}};
        if (sss_scene_parse(json[k], "scene.json", &s, &err) != SSS_OK) fail_msg("%s", err.msg);
        sss_plan plan;
        if (sss_plan_scene(&s, &g_rest, &plan, &err) != SSS_OK) fail_msg("%s", err.msg);
        const sss_object_plan *a = &plan.obj[0];
        assert_int_equal(a->per_frame, 1);
        assert_int_equal(a->field, k == 0 ? SSS_PLAN_FIELD_PER_FRAME : SSS_PLAN_FIELD_FOLDED);
        assert_int_equal(a->channels, 3);
        int said = 0;
        for (uint32_t d = 0; d < a->ndecisions; d++)
            said |= !strcmp(a->decisions[d].effect, "field") &&
                    (k == 0 ? strstr(a->decisions[d].reason, "rest-pose position") != NULL &&
                                  strstr(a->decisions[d].reason, "Eq. 8") != NULL
                            : !strcmp(a->decisions[d].choice, "folded"));
        assert_true(said);
        if (k == 1) assert_true(a->material.sigma_a[0] != s.objects[0].material.sigma_a[0]); /* the blend at 0.5 */
        sss_plan_free(&plan);
        sss_scene_free(&s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(constantFieldGivesTheHomogeneousBlendBitForBit),
        cmocka_unit_test(bentPoseEqualsDirectSumOfEndpointProducts),
        cmocka_unit_test(materialMovesWithTheSurface),
        cmocka_unit_test(refusalsAreOneLine),
        cmocka_unit_test(plannerTakesAFieldOnADeformingObject),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
