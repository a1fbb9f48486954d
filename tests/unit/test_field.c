#define _POSIX_C_SOURCE 200809L
/* Material fields and the spatially varying kernel (docs/heterogeneous.md):
 * the field module, the scene keys, section FELD, the .vdb reader and
 * writer, and the acceptance checks of the baked path: constant fields
 * reduce to the homogeneous bakes, an absorbing inclusion never brightens,
 * a back-lit slab follows Beer–Lambert through an absorbing layer, and a
 * field moved rigidly with its object leaves q unchanged. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "genmesh.h"
#include "test_scene_util.h"
#include "sss/bake_scene.h"
#include "sss/exact.h"
#include "sss/field.h"
#include "sss/fieldio.h"
#include "sss/fieldweights.h"
#include "sss/import.h"
#include "sss/nbhd.h"
#include "sss/nearterms.h"
#include "sss/reference.h"
#include "sss/transfer.h"
#include "sss/vec3.h"
#include "gather/gather_internal.h"

static char tmpdir[256];

static int setup(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_field_XXXXXX");
    return mkdtemp(tmpdir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

/* ---- 1. the field module ---------------------------------------------------- */

static void blendIsExactAtBothEndsAndLinearBetween(void **state)
{
    (void)state;
    sss_material a, b, m;
    sss_error err = {{0}};
    assert_int_equal(sss_material_preset("marble", &a, &err), SSS_OK);
    assert_int_equal(sss_material_preset("ketchup", &b, &err), SSS_OK);
    sss_material_blend(&a, &b, 0.0, &m);
    assert_memory_equal(m.sigma_a, a.sigma_a, sizeof a.sigma_a);
    assert_memory_equal(m.sigmap_s, a.sigmap_s, sizeof a.sigmap_s);
    sss_material_blend(&a, &b, 1.0, &m);
    assert_memory_equal(m.sigma_a, b.sigma_a, sizeof b.sigma_a);
    assert_memory_equal(m.sigmap_s, b.sigmap_s, sizeof b.sigmap_s);
    assert_true(m.eta == a.eta);
    sss_material_blend(&a, &b, 0.25, &m);
    for (int c = 0; c < 3; c++) {
        assert_float_equal(m.sigma_a[c], 0.75 * a.sigma_a[c] + 0.25 * b.sigma_a[c], 1e-12);
        const double str = sss_material_sigma_tr(&a, &b, 0.25, (uint32_t)c);
        assert_float_equal(str, sqrt(3 * m.sigma_a[c] * (m.sigma_a[c] + m.sigmap_s[c])), 1e-12);
    }
}

static void transportColourIsReachedAfterTheTransportDistance(void **state)
{
    (void)state;
    const double colour[3] = {0.8, 0.4, 0.1}, sps[3] = {2.19, 2.62, 3.0};
    double sa[3];
    sss_error err = {{0}};
    assert_int_equal(sss_transport_sigma_a(colour, 5.0, sps, sa, &err), SSS_OK);
    for (int c = 0; c < 3; c++) {
        /* exp(−σtr T_d) = T_c with σtr = sqrt(3 σa (σa + σ′s)) */
        const double str = sqrt(3 * sa[c] * (sa[c] + sps[c]));
        assert_float_equal(exp(-str * 5.0), colour[c], 1e-12);
    }
    assert_true(sa[0] < sa[1] && sa[1] < sa[2]); /* a redder colour absorbs less red */
    const double bad[3] = {0.8, 1.0, 0.1};
    assert_int_not_equal(sss_transport_sigma_a(bad, 5.0, sps, sa, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "colour 1"));
}

static void proceduralFieldsAreDeterministicBoundedAndSeeded(void **state)
{
    (void)state;
    sss_field v = {.kind = SSS_FIELD_VEINS, .seed = 7, .scale_mm = 10.0};
    sss_field w = v;
    w.seed = 8;
    sss_field in = {.kind = SSS_FIELD_INCLUSIONS, .seed = 3, .scale_mm = 5.0, .thickness_mm = 1.5, .edge_mm = 0.2};
    sss_error err = {{0}};
    assert_int_equal(sss_field_check(&v, &err), SSS_OK);
    assert_int_equal(sss_field_check(&in, &err), SSS_OK);
    double vmin = 1, vmax = 0, imin = 1, imax = 0, differ = 0;
    for (int k = 0; k < 4000; k++) {
        const double x[3] = {0.37 * k - 700.0, 0.11 * k, 25.0 - 0.05 * k};
        const double a = sss_field_eval(&v, x), b = sss_field_eval(&in, x);
        assert_true(a >= 0 && a <= 1 && b >= 0 && b <= 1);
        assert_true(a == sss_field_eval(&v, x)); /* a pure function */
        differ = fmax(differ, fabs(a - sss_field_eval(&w, x)));
        vmin = fmin(vmin, a), vmax = fmax(vmax, a), imin = fmin(imin, b), imax = fmax(imax, b);
    }
    assert_true(vmin < 0.01 && vmax > 0.9); /* veins and the matrix between them */
    assert_true(imin == 0.0 && imax == 1.0); /* inside and outside the balls */
    assert_true(differ > 0.5);                /* the seed changes the pattern */
    /* a fixed value, so that a change of the noise shows here first */
    const double x0[3] = {1.25, -3.5, 7.0};
    print_message("veins(1.25, -3.5, 7) = %.9f\n", sss_field_eval(&v, x0));
}

static void shapesFollowTheirSignedDistanceWithASmoothEdge(void **state)
{
    (void)state;
    sss_field s = {.kind = SSS_FIELD_SPHERE, .centre_mm = {1, 2, 3}, .half_mm = {4}, .edge_mm = 1.0};
    const double c[3] = {1, 2, 3}, on[3] = {5, 2, 3}, in[3] = {4.5, 2, 3}, out[3] = {5.5, 2, 3};
    assert_true(sss_field_eval(&s, c) == 1.0);
    assert_float_equal(sss_field_eval(&s, on), 0.5, 1e-12);
    assert_true(sss_field_eval(&s, in) == 1.0 && sss_field_eval(&s, out) == 0.0);
    sss_field b = {.kind = SSS_FIELD_BOX, .centre_mm = {0, 0, 0}, .half_mm = {1, 2, 3}};
    const double bi[3] = {0.9, -1.9, 2.9}, bo[3] = {1.1, 0, 0};
    assert_true(sss_field_eval(&b, bi) == 1.0 && sss_field_eval(&b, bo) == 0.0);
    sss_field l = {.kind = SSS_FIELD_LAYERS, .normal = {0, 0, 1}, .thickness_mm = 1.0, .offset_mm = 2.0,
                   .scale_mm = 5.0};
    for (int k = -3; k <= 3; k++) {
        const double a[3] = {9, 9, 2.5 + 5.0 * k}, o[3] = {9, 9, 4.5 + 5.0 * k};
        assert_true(sss_field_eval(&l, a) == 1.0); /* every period's stratum */
        assert_true(sss_field_eval(&l, o) == 0.0);
    }
    sss_error err = {{0}};
    sss_field bad = l;
    bad.scale_mm = 0.5; /* a period thinner than the stratum */
    assert_int_not_equal(sss_field_check(&bad, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "period_mm"));
}

static void gridIsTrilinearAndSamplingReproducesALinearField(void **state)
{
    (void)state;
    /* f linear in x, y, z: trilinear interpolation of its samples is exact */
    float data[4 * 3 * 2];
    sss_field g = {.kind = SSS_FIELD_GRID, .n = {4, 3, 2}, .origin_mm = {-1, 0, 2}, .voxel_mm = 0.5, .data = data};
    for (int k = 0; k < 2; k++)
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 4; i++) data[(k * 3 + j) * 4 + i] = (float)(0.1 * i + 0.2 * j + 0.15 * k);
    sss_error err = {{0}};
    assert_int_equal(sss_field_check(&g, &err), SSS_OK);
    const double x[3] = {-1 + 0.5 * 1.3, 0.5 * 0.7, 2 + 0.5 * 0.4};
    assert_float_equal(sss_field_eval(&g, x), 0.1 * 1.3 + 0.2 * 0.7 + 0.15 * 0.4, 1e-7);
    const double lo[3] = {-1, 0, 2}, hi[3] = {0.5, 1, 2.5}, far[3] = {0.5, 1, 9};
    char why[300];
    assert_true(sss_field_covers(&g, lo, hi, why, sizeof why));
    assert_false(sss_field_covers(&g, lo, far, why, sizeof why));
    assert_non_null(strstr(why, "does not cover"));
    data[5] = 1.5f; /* outside [0, 1] */
    assert_int_not_equal(sss_field_check(&g, &err), SSS_OK);
}

/* ---- 2. scene keys ------------------------------------------------------------- */

static void expect_error(const char *json, const char *want)
{
    sss_scene s;
    sss_error err = {{0}};
    assert_int_not_equal(sss_scene_parse(json, "scene.json", &s, &err), SSS_OK);
    if (!strstr(err.msg, want)) fail_msg("message '%s' lacks '%s'", err.msg, want);
    assert_null(strchr(err.msg, '\n'));
}

static void sceneReadsFieldInsideAndTransportAndNamesErrors(void **state)
{
    (void)state;
    sss_scene s;
    sss_error err = {{0}};
    const char *ok = "{\"objects\":[{\"mesh\":\"a.ply\",\"mm_per_unit\":2,\"transform\":{\"translate\":[1,2,3],"
                     "\"rotate_deg\":[0,0,90],\"scale\":2},\"material\":{\"preset\":\"marble\",\"field\":{"
                     "\"procedural\":\"sphere\",\"centre_mm\":[0,0,0],\"radius_mm\":3,\"edge_mm\":0.5},"
                     "\"inside\":{\"preset\":\"marble\",\"transport\":{\"colour\":[0.9,0.5,0.2],\"distance_mm\":4}}}}]}";
    if (sss_scene_parse(ok, "scene.json", &s, &err) != SSS_OK) fail_msg("%s", err.msg);
    const sss_scene_object *o = &s.objects[0];
    assert_int_equal(o->hetero.field.kind, SSS_FIELD_SPHERE);
    assert_true(o->hetero.field.half_mm[0] == 3.0);
    assert_true(o->hetero.inside.sigma_a[0] < o->hetero.inside.sigma_a[2]);
    assert_true(o->hetero.inside.eta == o->material.eta);
    /* the world point of object point (1, 0, 0): 2·Rz(90)·(1,0,0) + t = (1, 4, 3); rest frame 2 mm */
    const double pw[3] = {1, 4, 3};
    double x[3];
    sss_hetero_to_rest(&o->hetero, pw, x);
    assert_float_equal(x[0], 2.0, 1e-12);
    assert_float_equal(x[1], 0.0, 1e-12);
    assert_float_equal(x[2], 0.0, 1e-12);
    sss_scene_free(&s);
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"field\":{\"constant\":0.5}}}]}",
                 "scene.json: /objects/0/material/inside: missing");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":\"ketchup\","
                 "\"field\":{\"constant\":1.5}}}]}",
                 "scene.json: /objects/0/material/field/constant: 1.5 is out of range [0, 1]");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":\"ketchup\","
                 "\"field\":{\"procedural\":\"clouds\"}}}]}",
                 "scene.json: /objects/0/material/field/procedural: 'clouds' is not");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":\"ketchup\","
                 "\"field\":{\"procedural\":\"box\",\"centre_mm\":[0,0,0]}}}]}",
                 "scene.json: /objects/0/material/field/half_mm: missing");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":{\"sigma_a\":[1,1,1],"
                 "\"sigmap_s\":[1,1,1],\"field\":{\"constant\":1}},\"field\":{\"constant\":1}}}]}",
                 "scene.json: /objects/0/material/inside/field: unknown key");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"sigma_a\":[1,1,1],"
                 "\"transport\":{\"colour\":[0.5,0.5,0.5],\"distance_mm\":1}}}]}",
                 "scene.json: /objects/0/material/transport: give sigma_a or transport, not both");
}

/* ---- 3. baking ---------------------------------------------------------------- */

typedef test_scene baked;

static sss_result load(baked *b, const char *json, sss_error *err) { return test_scene_load(b, tmpdir, json, err); }
static void unload(baked *b) { test_scene_unload(b); }

/* Bakes object 0 of the scene text; the file goes through encode/decode,
 * so what is checked is what a reader gets. */
static void bake_scene(const char *json, sss_bake_file *f)
{
    baked b;
    sss_error err = {{0}};
    if (load(&b, json, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    sss_bake_file g;
    if (sss_bake_object(&b.sc, &b.plan, b.world, 0, &o, &g, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&g, &buf, &len, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_file_decode(buf, len, "mem.sss", f, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(f->version_minor, g.hetero.field.kind ? 8 : g.weights == SSS_WEIGHTS_HAT ? 5 : 4);
    free(buf);
    sss_file_free(&g);
    unload(&b);
}

static void write_mesh(const char *name, const sss_mesh *m)
{
    char p[400];
    snprintf(p, sizeof p, "%s/%s", tmpdir, name);
    sss_error err = {{0}};
    assert_int_equal(sss_export_ply(p, m, &err), SSS_OK);
}

static void make_meshes(void)
{
    static int done;
    if (done) return;
    done = 1;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 10.0, 3, &err), SSS_OK);
    write_mesh("ball.ply", &m);
    sss_mesh_free(&m);
    assert_int_equal(sss_gen_box(&m, 30.0, 30.0, 6.0, 20, 0, &err), SSS_OK);
    write_mesh("slab.ply", &m);
    sss_mesh_free(&m);
}

#define BASE "\"sigma_a\":[0.01,0.01,0.01],\"sigmap_s\":[1,1,1]"
#define INSIDE "{\"sigma_a\":[0.2,0.2,0.2],\"sigmap_s\":[1,1,1]}"

static char *scene_text(const char *mesh, const char *field, const char *light, const char *transform)
{
    static char buf[2000];
    if (field)
        snprintf(buf, sizeof buf, "{\"objects\":[{\"mesh\":\"%s\",\"material\":{" BASE ",\"inside\":" INSIDE
                 ",\"field\":%s}%s}],\"lights\":[{\"type\":\"directional\",\"direction\":[%s]}]}",
                 mesh, field, transform ? transform : "", light);
    else
        snprintf(buf, sizeof buf, "{\"objects\":[{\"mesh\":\"%s\",\"material\":{" BASE "}%s}],"
                 "\"lights\":[{\"type\":\"directional\",\"direction\":[%s]}]}", mesh, transform ? transform : "",
                 light);
    return buf;
}

static void same_q(const sss_bake_file *a, const sss_bake_file *b)
{
    assert_int_equal(a->fx.nexact, 1);
    assert_int_equal(b->fx.nexact, 1);
    assert_int_equal(a->mesh.nv, b->mesh.nv);
    assert_int_equal(a->channels, b->channels);
    assert_memory_equal(a->fx.exact_q, b->fx.exact_q, (size_t)a->mesh.nv * a->channels * sizeof(float));
}

/* Constant fields c = 0 and c = 1 give the base's and the inside's q bit
 * for bit: as constants (folded by the planner, no section FELD) and
 * through the kernel (a box holding the whole ball is f = 1 everywhere, a
 * stratum far away f = 0; sqrt(P·P)/P = 1). surface: the same as surface
 * textures (docs/heterogeneous.md §4.4). */
static void constants_reduce_to_the_homogeneous_bakes(int surface)
{
    make_meshes();
    const char *tail = surface ? ",\"surface\":true}" : "}";
    char field[256];
    sss_bake_file hom, in_hom, f;
    bake_scene(scene_text("ball.ply", NULL, "0.3,0.2,0.9", NULL), &hom);
    bake_scene("{\"objects\":[{\"mesh\":\"ball.ply\",\"material\":" INSIDE "}],"
               "\"lights\":[{\"type\":\"directional\",\"direction\":[0.3,0.2,0.9]}]}", &in_hom);
    snprintf(field, sizeof field, "{\"constant\":0%s", tail);
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &f);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_NONE);
    same_q(&f, &hom);
    sss_file_free(&f);
    snprintf(field, sizeof field, "{\"constant\":1%s", tail);
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &f);
    same_q(&f, &in_hom);
    sss_file_free(&f);
    snprintf(field, sizeof field, "{\"procedural\":\"box\",\"centre_mm\":[0,0,0],\"half_mm\":[50,50,50]%s", tail);
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &f);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_BOX);
    assert_int_equal(f.hetero.surface, surface);
    same_q(&f, &in_hom);
    sss_file_free(&f);
    snprintf(field, sizeof field,
             "{\"procedural\":\"layers\",\"normal\":[0,0,1],\"thickness_mm\":1,\"offset_mm\":500%s", tail);
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &f);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_LAYERS);
    assert_int_equal(f.hetero.surface, surface);
    same_q(&f, &hom);
    sss_file_free(&f);
    sss_file_free(&hom);
    sss_file_free(&in_hom);
}

static void constantFieldsReduceToTheHomogeneousBakes(void **state)
{
    (void)state;
    constants_reduce_to_the_homogeneous_bakes(0);
}

/* q of the file recomputed by the exact evaluator from the file alone */
static float *exact_q(const sss_bake_file *f, const double light[3])
{
    sss_error err = {{0}};
    sss_exact *ex;
    if (sss_exact_create(f, &ex, &err) != SSS_OK) fail_msg("%s", err.msg);
    float *q = malloc((size_t)f->mesh.nv * f->channels * sizeof *q);
    sss_exact_eval(ex, light, q);
    sss_exact_destroy(ex);
    return q;
}

static void absorbingInclusionNeverBrightensAndDarkensWhatIsBehindIt(void **state)
{
    (void)state;
    make_meshes();
    const double L[3] = {0, 0, 1};
    sss_bake_file hom, f;
    bake_scene(scene_text("ball.ply", NULL, "0,0,1", NULL), &hom);
    /* σ′s equal, σa 20x: a ball of radius 5 mm inside the 10 mm ball */
    bake_scene(scene_text("ball.ply", "{\"procedural\":\"sphere\",\"centre_mm\":[0,0,0],\"radius_mm\":5,"
                          "\"edge_mm\":1}", "0,0,1", NULL), &f);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_SPHERE);
    /* the file alone gives the bake's q back (section FELD): the exact
     * evaluator marches every pair, the bake its far pairs through the
     * cells' cache (docs/heterogeneous.md §4.3), whose error this is */
    float *q = exact_q(&f, L);
    double qmax = 0.0, dmax = 0.0;
    for (size_t k = 0; k < f.mesh.nv; k++) qmax = fmax(qmax, q[k]);
    for (size_t k = 0; k < f.mesh.nv; k++) dmax = fmax(dmax, fabs((double)q[k] - f.fx.exact_q[k]));
    print_message("inclusion: bake vs exact evaluator: max |dq| %.3g of max q %.3g (%.3g %%)\n", dmax, qmax,
                  100 * dmax / qmax);
    assert_true(dmax <= 0.01 * qmax);
    free(q);
    uint32_t behind = 0;
    double worst_ratio = 0.0, max_behind = 0.0;
    for (uint32_t v = 0; v < f.mesh.nv; v++) {
        const float a = f.fx.exact_q[v], h = hom.fx.exact_q[v];
        assert_true(a <= h);
        worst_ratio = fmax(worst_ratio, h > 0 ? a / h : 0.0);
        if (f.mesh.pos[3 * (size_t)v + 2] < -8.0f) { /* the far side: its light crossed the inclusion */
            behind++;
            assert_true(a < 0.9f * h);
            max_behind = fmax(max_behind, a / h);
        }
    }
    print_message("inclusion: q / q_homogeneous at most %.6f; behind it at most %.4f (%u vertices)\n", worst_ratio,
                  max_behind, behind);
    assert_true(behind > 10);
    sss_file_free(&f);
    /* a stone that breaks the surface: the vertices inside it take the
     * stone's own profile (σa = 0.2 σ′s here, where the dipole's R_d(r)
     * still falls with σa at every r: docs/heterogeneous.md §4.1) */
    bake_scene(scene_text("ball.ply", "{\"procedural\":\"sphere\",\"centre_mm\":[0,0,10],\"radius_mm\":3,"
                          "\"edge_mm\":0.5}", "0,0,1", NULL), &f);
    uint32_t inside = 0;
    for (uint32_t v = 0; v < f.mesh.nv; v++) {
        assert_true(f.fx.exact_q[v] <= hom.fx.exact_q[v]);
        inside += f.mesh.pos[3 * (size_t)v + 2] > 9.6f;
    }
    assert_true(inside > 3);
    sss_file_free(&f);
    sss_file_free(&hom);
}

/* Mean q over the top face's centre (|x|, |y| < 5 mm) of the back-lit slab. */
static double top_centre(const sss_bake_file *f)
{
    double s = 0.0;
    int n = 0;
    for (uint32_t v = 0; v < f->mesh.nv; v++) {
        const float *p = &f->mesh.pos[3 * (size_t)v];
        if (p[2] > 2.9f && fabsf(p[0]) < 5.0f && fabsf(p[1]) < 5.0f) s += f->fx.exact_q[v], n++;
    }
    assert_true(n >= 9);
    return s / n;
}

/* Beer–Lambert's prediction for the slab's top centre: each pair (o, i)
 * crosses the stratum of thickness t (1 mm smooth edges) along a segment
 * of length r with a height |Δz| = 6 mm, so the light pays
 * exp(−r/|Δz| ∫ Δσtr dz); the homogeneous weights and transfer average
 * that over the pairs. */
static double beer_lambert_ratio(double t)
{
    /* ∫ (σtr(f(z)) − σtr(0)) dz across the stratum with its smooth edges
     * (σtr is not linear in f), by the midpoint rule on 60000 cells */
    const sss_field layer = {.kind = SSS_FIELD_LAYERS, .normal = {0, 0, 1}, .thickness_mm = t, .offset_mm = -t / 2,
                             .edge_mm = 0.5};
    const sss_material base = {.sigma_a = {0.01, 0.01, 0.01}, .sigmap_s = {1, 1, 1}, .eta = 1.3},
                       in = {.sigma_a = {0.2, 0.2, 0.2}, .sigmap_s = {1, 1, 1}, .eta = 1.3};
    double dstr_t = 0.0;
    for (int k = 0; k < 60000; k++) {
        const double x[3] = {0, 0, -3.0 + 6.0 * (k + 0.5) / 60000};
        dstr_t += (sss_material_sigma_tr(&base, &in, sss_field_eval(&layer, x), 0) - sss_material_sigma_tr(&base, &in, 0.0, 0)) * 1e-4;
    }
    baked b;
    sss_error err = {{0}};
    if (load(&b, scene_text("slab.ply", NULL, "0,0,-1", NULL), &err) != SSS_OK) fail_msg("%s", err.msg);
    const sss_mesh *m = &b.world[0];
    sss_dipole d;
    assert_int_equal(sss_dipole_init(&d, 0.01, 1.0, 1.3), SSS_OK);
    const double R = sss_nbhd_radii(m, 1.0, &d, 1, 1e-3, NULL);
    uint32_t top[64], nt = 0;
    for (uint32_t v = 0; v < m->nv && nt < 64; v++) {
        const float *p = &m->pos[3 * (size_t)v];
        if (p[2] > 2.9f && fabsf(p[0]) < 5.0f && fabsf(p[1]) < 5.0f) top[nt++] = v;
    }
    sss_weights w;
    assert_int_equal(sss_nbhd_build(m, 1.0, &d, 1, R, top, nt, 0, NULL, &w, &err), SSS_OK);
    const double down[3] = {0, 0, -1};
    float *G = malloc(m->nv * sizeof *G);
    assert_int_equal(sss_transfer_compute(m, NULL, down, 1, 1.3, NULL, G, NULL, NULL, &err), SSS_OK);
    double with = 0.0, without = 0.0;
    for (uint32_t k = 0; k < nt; k++)
        for (uint64_t e = w.start[k]; e < w.start[k + 1]; e++) {
            const uint32_t i = w.idx[e];
            if (G[i] == 0.0f) continue;
            double r2 = 0.0;
            for (int a = 0; a < 3; a++) {
                const double dx = (double)m->pos[3 * (size_t)i + a] - m->pos[3 * (size_t)top[k] + a];
                r2 += dx * dx;
            }
            const double dz = fabs((double)m->pos[3 * (size_t)i + 2] - m->pos[3 * (size_t)top[k] + 2]);
            const double c = (double)w.w[e] * G[i];
            without += c;
            with += c * exp(-dstr_t * sqrt(r2) / dz); /* every bottom-to-top pair crosses the stratum */
        }
    free(G);
    sss_weights_free(&w);
    unload(&b);
    return with / without;
}

/* The scene text with the paper's point weights, as beer_lambert_ratio sums. */
static const char *point_weights(const char *json)
{
    static char buf[2100];
    snprintf(buf, sizeof buf, "%.*s,\"bake\":{\"weights\":\"point\"}}", (int)strlen(json) - 1, json);
    return buf;
}

static void backLitSlabFollowsBeerLambertThroughAnAbsorbingLayer(void **state)
{
    (void)state;
    make_meshes();
    sss_bake_file hom, l1, l2;
    bake_scene(point_weights(scene_text("slab.ply", NULL, "0,0,-1", NULL)), &hom);
    /* strata of 1 and 2 mm across the middle of the 6 mm slab, lit from below */
    bake_scene(point_weights(scene_text("slab.ply", "{\"procedural\":\"layers\",\"normal\":[0,0,1],"
                                        "\"thickness_mm\":1,\"offset_mm\":-0.5,\"edge_mm\":0.5}", "0,0,-1", NULL)), &l1);
    bake_scene(point_weights(scene_text("slab.ply", "{\"procedural\":\"layers\",\"normal\":[0,0,1],"
                                        "\"thickness_mm\":2,\"offset_mm\":-1,\"edge_mm\":0.5}", "0,0,-1", NULL)), &l2);
    const double dstr = sqrt(3 * 0.2 * 1.2) - sqrt(3 * 0.01 * 1.01); /* σtr inside − σtr base, 1/mm */
    const double q0 = top_centre(&hom), r1 = top_centre(&l1) / q0, r2 = top_centre(&l2) / q0;
    const double p1 = beer_lambert_ratio(1.0), p2 = beer_lambert_ratio(2.0);
    print_message("Beer-Lambert: 1 mm: q/q0 = %.4f, predicted %.4f (straight through %.4f); 2 mm: %.4f, predicted "
                  "%.4f (%.4f)\n", r1, p1, exp(-dstr), r2, p2, exp(-2 * dstr));
    /* no pair crosses the stratum on less than its thickness */
    assert_true(r1 < exp(-dstr) && r2 < exp(-2 * dstr));
    /* the march against the closed form, pair by pair, averaged over the
     * same point weights: within 2 % (the midpoint rule over steps of a
     * quarter of the edge) */
    assert_float_equal(r1 / p1, 1.0, 0.02);
    assert_float_equal(r2 / p2, 1.0, 0.02);
    sss_file_free(&hom);
    sss_file_free(&l1);
    sss_file_free(&l2);
}

static void fieldMovedRigidlyWithItsObjectLeavesQUnchanged(void **state)
{
    (void)state;
    make_meshes();
    const char *field = "{\"procedural\":\"sphere\",\"centre_mm\":[4,1,0],\"radius_mm\":4,\"edge_mm\":1}";
    sss_bake_file a, b;
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &a);
    /* rotated 40° about z and moved: the light turns with it */
    const double t = 40.0 * SSS_PI / 180.0;
    char light[200];
    snprintf(light, sizeof light, "%.17g,%.17g,0.9", 0.3 * cos(t) - 0.2 * sin(t), 0.3 * sin(t) + 0.2 * cos(t));
    bake_scene(scene_text("ball.ply", field, light, ",\"transform\":{\"rotate_deg\":[0,0,40],\"translate\":[5,-3,2]}"),
               &b);
    double worst = 0.0, top = 0.0;
    for (uint32_t v = 0; v < a.mesh.nv; v++) top = fmax(top, a.fx.exact_q[v]);
    for (uint32_t v = 0; v < a.mesh.nv; v++) worst = fmax(worst, fabs((double)a.fx.exact_q[v] - b.fx.exact_q[v]));
    print_message("rigid motion: max |dq| %.3g of max q %.3g\n", worst, top);
    assert_true(worst <= 1e-4 * top);
    /* and the field mattered: without it q differs by far more */
    sss_bake_file h;
    bake_scene(scene_text("ball.ply", NULL, "0.3,0.2,0.9", NULL), &h);
    double d = 0.0;
    for (uint32_t v = 0; v < a.mesh.nv; v++) d = fmax(d, fabs((double)a.fx.exact_q[v] - h.fx.exact_q[v]));
    assert_true(d > 100 * worst);
    sss_file_free(&a);
    sss_file_free(&b);
    sss_file_free(&h);
}

/* The veined ball of the kernel's own checks: a base of little absorption
 * (σa 0.01–0.03 per mm) with veins (S = 6 mm) of an inside whose σa is
 * inside_sa in every channel, the field in millimetres. */
static void veined_ball(double inside_sa, sss_hetero *h, sss_material *base)
{
    memset(h, 0, sizeof *h);
    h->field = (sss_field){.kind = SSS_FIELD_VEINS, .seed = 1, .scale_mm = 6.0};
    h->xf[0] = h->xf[5] = h->xf[10] = 1.0;
    *base = (sss_material){.name = "b", .sigma_a = {0.01, 0.02, 0.03}, .sigmap_s = {1, 1.2, 1.4}, .eta = 1.3};
    h->inside = *base;
    for (int c = 0; c < 3; c++) h->inside.sigma_a[c] = inside_sa;
}

/* A veined ball of radius 10 (subdivision level sub) and its kernel (3
 * channels, inside σa 0.3/mm); h is borrowed by k, so the caller holds it. */
static void veined_ball_kernel(uint32_t sub, sss_mesh *m, sss_hetero *h, sss_field_kernel *k)
{
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(m, 10.0, sub, &err), SSS_OK);
    sss_material base;
    veined_ball(0.3, h, &base);
    if (sss_field_kernel_create(m, 1.0, &base, h, 3, 1e-3, "ball", k, &err) != SSS_OK) fail_msg("%s", err.msg);
}

static void kernelIsSymmetricInItsEndpoints(void **state)
{
    (void)state;
    sss_mesh m;
    sss_hetero h;
    sss_field_kernel k;
    veined_ball_kernel(2, &m, &h, &k);
    assert_true(k.f_min < k.f_max);
    double worst = 0.0;
    uint32_t sym = 0, asym = 0;
    for (uint32_t o = 0; o < m.nv; o += 7)
        for (uint32_t i = 0; i < m.nv; i += 5) {
            double a[3], b[3];
            sss_field_kappa(&k, &m, o, i, a);
            sss_field_kappa(&k, &m, i, o, b);
            /* where sss_field_kappa_sym says so, κ(i, o) has κ(o, i)'s bits
             * (the tree gather keeps one for both, gather_field.c) */
            double s0[3], s1[3];
            const int so = sss_field_kappa_sym(&k, &m, o, i, s0), si = sss_field_kappa_sym(&k, &m, i, o, s1);
            assert_int_equal(so, si);
            assert_memory_equal(s0, a, sizeof a);
            if (so) {
                assert_memory_equal(a, b, sizeof a);
                sym++;
            } else {
                asym++;
            }
            for (int c = 0; c < 3; c++) {
                /* the profile ratio and τ are symmetric; the weights then
                 * differ only by ΔA_i vs ΔA_o, as the homogeneous ones do */
                if (fabs(m.area[o] - m.area[i]) == 0.0) assert_true(a[c] == b[c]);
                worst = fmax(worst, fabs(a[c] - b[c]) / fmax(a[c], 1e-300));
                assert_true(a[c] >= 0.0 && isfinite(a[c]));
            }
        }
    print_message("kappa(o,i) vs kappa(i,o): max relative difference %.3g; %u pairs symmetric bit for bit, %u not "
                  "(own term, near disks)\n", worst, sym, asym);
    assert_true(sym > 0 && asym > 0);
    sss_field_kernel_free(&k);
    sss_mesh_free(&m);
}

/* The tree gather keeps a near pair's κ for the pair's second receiver
 * when both lie in one group of blocks (docs/heterogeneous.md §4.5,
 * gather_field.c): q with the groups' tables has the bits of q with every
 * κ computed (field_group 0), and the table was read from. */
static void treeKeptKappaHasTheBitsItWouldCompute(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    sss_hetero h;
    sss_field_kernel k;
    veined_ball_kernel(4, &m, &h, &k);
    float *G = malloc((size_t)m.nv * sizeof *G);
    float *qa = malloc((size_t)m.nv * 3 * sizeof *qa), *qb = malloc((size_t)m.nv * 3 * sizeof *qb);
    assert_non_null(G);
    assert_non_null(qa);
    assert_non_null(qb);
    for (uint32_t v = 0; v < m.nv; v++) G[v] = 0.5f + 0.5f * m.pos[3 * (size_t)v + 2] / 10.0f; /* lit from +z */
    sss_gather_tree *t = NULL;
    sss_gather_params p = {0};
    assert_int_equal(sss_gather_tree_build(&m, 1.0, G, 1, &p, &t, &err), SSS_OK);
    assert_int_equal(sss_gather_tree_set_field(t, &m, &k, &err), SSS_OK);
    assert_true(t->field_group > 0 && m.nv > t->field_group); /* more than one group */
    sss_gather_stats sa, sb;
    const uint32_t nb = sss_gather_tree_blocks(t);
    assert_int_equal(sss_gather_run(t, &m, k.dip_ref, 3, k.radius_mm, 0, nb, qa, 1, &sa, &err), SSS_OK);
    t->field_group = 0;
    assert_int_equal(sss_gather_run(t, &m, k.dip_ref, 3, k.radius_mm, 0, nb, qb, 1, &sb, &err), SSS_OK);
    print_message("tree: %llu near pairs, %llu near kappa read from the groups' tables\n",
                  (unsigned long long)sa.near_pairs, (unsigned long long)sa.field_kept);
    assert_true(sa.field_kept > 0);
    assert_true(sb.field_kept == 0);
    assert_memory_equal(qa, qb, (size_t)m.nv * 3 * sizeof *qa);
    sss_gather_tree_destroy(t);
    free(G), free(qa), free(qb);
    sss_field_kernel_free(&k);
    sss_mesh_free(&m);
}

/* The profiles' table (docs/heterogeneous.md §4.1, fieldweights.c
 * build_profiles): κ read from it against κ from the exact dipole profiles
 * (the same kernel without its table), over every pair whose profiles are
 * point values within the radius, on a veined ball whose inside absorbs
 * little more than its base and one where σa rises 100-fold (σtr from
 * 0.17 to 1.8 per mm): within the kernel's prof_tol, itself within
 * 2·10⁻³ (measured 3.2·10⁻⁴ and 1.4·10⁻³), and not exact (the table is
 * read). An endpoint at f_min reads g = 0
 * exactly: where both ends are there, κ is τ alone, bit for bit. */
static void profileTableIsWithinItsBoundOfTheExactProfiles(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 10.0, 2, &err), SSS_OK);
    const double inside_sa[2] = {0.3, 1.0};
    for (int t = 0; t < 2; t++) {
        sss_hetero h;
        sss_material base;
        veined_ball(inside_sa[t], &h, &base);
        sss_field_kernel k;
        if (sss_field_kernel_create(&m, 1.0, &base, &h, 3, 1e-3, "ball", &k, &err) != SSS_OK) fail_msg("%s", err.msg);
        assert_non_null(k.prof);
        assert_true(k.prof_tol > 0.0 && k.prof_tol <= 2e-3);
        double worst = 0.0;
        uint64_t pairs = 0, both_ref = 0;
        for (uint32_t o = 0; o < m.nv; o++)
            for (uint32_t i = 0; i < m.nv; i++) {
                const float *a = &m.pos[3 * (size_t)o], *b = &m.pos[3 * (size_t)i];
                const double r = sqrt(((double)a[0] - b[0]) * ((double)a[0] - b[0]) +
                                      ((double)a[1] - b[1]) * ((double)a[1] - b[1]) +
                                      ((double)a[2] - b[2]) * ((double)a[2] - b[2]));
                if (!(r > 0.0 && r <= k.radius_mm && r >= sqrt(m.area[i] / SSS_PI))) continue;
                double kt[3], ke[3];
                sss_field_kappa(&k, &m, o, i, kt);
                float *tab = k.prof;
                k.prof = NULL;
                sss_field_kappa(&k, &m, o, i, ke);
                k.prof = tab;
                const int ref = k.f[o] == k.f_min && k.f[i] == k.f_min;
                for (int c = 0; c < 3; c++) {
                    assert_true(kt[c] > 0.0 && isfinite(kt[c]));
                    if (ref) assert_true(kt[c] == ke[c]);
                    worst = fmax(worst, fabs(log(kt[c] / ke[c])));
                }
                pairs++;
                both_ref += (uint64_t)ref;
            }
        print_message("inside sigma_a %.1f: %llu pairs, largest |ln kappa_table - ln kappa_exact| %.3g, "
                      "prof_tol %.3g\n", inside_sa[t], (unsigned long long)pairs, worst, k.prof_tol);
        assert_true(pairs > 10000);
        assert_true(worst > 0.0);
        assert_true(worst <= k.prof_tol);
        sss_field_kernel_free(&k);
    }
    sss_mesh_free(&m);
}

/* ---- 4. the file and .vdb ---------------------------------------------------- */

/* Section FELD of the encoded file buf: its bytes, and its entry in the
 * section table (docs/format.md §2.2). */
static uint8_t *feld_section(uint8_t *buf, uint8_t **entry, uint64_t *size)
{
    const uint32_t nsec = (uint32_t)(buf[12] | buf[13] << 8 | buf[14] << 16 | (uint32_t)buf[15] << 24);
    for (uint32_t k = 0; k < nsec; k++) {
        uint8_t *e = buf + 24 + 40 * (size_t)k;
        if (memcmp(e, "FELD", 4)) continue;
        uint64_t off = 0;
        *size = 0;
        for (int b = 7; b >= 0; b--) off = off << 8 | e[8 + b], *size = *size << 8 | e[16 + b];
        *entry = e;
        return buf + off;
    }
    fail_msg("no section FELD");
    return NULL;
}

/* Writes v at byte `at` of section FELD of the encoded file buf and
 * recomputes the section's and the header's CRCs (docs/format.md §2.2,
 * §3), so that only the reader's own checks can refuse the result. */
static void feld_put_u32(uint8_t *buf, size_t at, uint32_t v)
{
    uint8_t *e;
    uint64_t size;
    uint8_t *sec = feld_section(buf, &e, &size);
    for (int b = 0; b < 4; b++) sec[at + b] = (uint8_t)(v >> 8 * b);
    const uint32_t crc = sss_crc32(0, sec, (size_t)size);
    for (int b = 0; b < 4; b++) e[32 + b] = (uint8_t)(crc >> 8 * b);
    const uint32_t nsec = (uint32_t)(buf[12] | buf[13] << 8 | buf[14] << 16 | (uint32_t)buf[15] << 24);
    const uint32_t hcrc = sss_crc32(0, buf, 24 + 40 * (size_t)nsec);
    for (int b = 0; b < 4; b++) buf[24 + 40 * (size_t)nsec + b] = (uint8_t)(hcrc >> 8 * b);
}

static void fieldSectionRoundTripsAndRefusesABadGrid(void **state)
{
    (void)state;
    make_meshes();
    sss_bake_file f;
    bake_scene(scene_text("ball.ply", "{\"procedural\":\"inclusions\",\"seed\":4,\"scale_mm\":6,\"radius_mm\":2}",
                          "0,0,1", NULL), &f);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_INCLUSIONS);
    assert_int_equal(f.hetero.field.seed, 4);
    assert_true(f.hetero.inside.sigma_a[0] == 0.2);
    /* a grid field: samples survive bit for bit */
    sss_error err = {{0}};
    sss_field g;
    const double lo[3] = {-11, -11, -11}, hi[3] = {11, 11, 11};
    assert_int_equal(sss_field_sample(&f.hetero.field, lo, hi, 17, &g, &err), SSS_OK);
    sss_field_free(&f.hetero.field);
    f.hetero.field = g;
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    sss_bake_file r;
    if (sss_file_decode(buf, len, "mem.sss", &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(r.hetero.field.kind, SSS_FIELD_GRID);
    assert_memory_equal(r.hetero.field.n, g.n, sizeof g.n);
    assert_memory_equal(r.hetero.field.data, g.data, (size_t)g.n[0] * g.n[1] * g.n[2] * sizeof(float));
    assert_memory_equal(r.hetero.xf, f.hetero.xf, sizeof f.hetero.xf);
    sss_file_free(&r);
    /* a hostile node count behind valid checksums: refused before any
     * allocation, naming the section (docs/format.md §2.2, §5.22) */
    feld_put_u32(buf, 264, UINT32_MAX); /* n[0] = 2³² − 1 */
    assert_int_not_equal(sss_file_decode(buf, len, "hostile.sss", &r, &err), SSS_OK);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "hostile.sss: section FELD: a grid of 4294967295 x"));
    free(buf);
    /* a value out of range is refused by the writer, naming the section */
    g.data[3] = 2.0f;
    assert_int_not_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "section FELD"));
    sss_file_free(&f);
}

static void vdbWrittenAndReadBackGivesTheSameField(void **state)
{
    (void)state;
    sss_field veins = {.kind = SSS_FIELD_VEINS, .seed = 2, .scale_mm = 8.0}, g, back;
    const double lo[3] = {-12, -10, -9}, hi[3] = {12, 10, 9};
    sss_error err = {{0}};
    assert_int_equal(sss_field_sample(&veins, lo, hi, 25, &g, &err), SSS_OK);
    char path[400];
    snprintf(path, sizeof path, "%s/veins.vdb", tmpdir);
    if (sss_field_write_vdb(path, "density", &g, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_field_load(path, "density", &back, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_memory_equal(back.n, g.n, sizeof g.n);
    for (int a = 0; a < 3; a++) assert_float_equal(back.origin_mm[a], g.origin_mm[a], 1e-9);
    assert_float_equal(back.voxel_mm, g.voxel_mm, 1e-12);
    assert_memory_equal(back.data, g.data, (size_t)g.n[0] * g.n[1] * g.n[2] * sizeof(float));
    /* and evaluates as the field it sampled at the nodes */
    const double x[3] = {g.origin_mm[0] + 3 * g.voxel_mm, g.origin_mm[1] + 5 * g.voxel_mm, g.origin_mm[2]};
    assert_float_equal(sss_field_eval(&back, x), sss_field_eval(&veins, x), 1e-6);
    sss_field_free(&back);
    /* a grid name that is not there, and a file that is not a .vdb */
    assert_int_not_equal(sss_field_load(path, "temperature", &back, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "veins.vdb: grid 'temperature' not found (the file holds: density)"));
    char bad[400];
    snprintf(bad, sizeof bad, "%s/bad.vdb", tmpdir);
    FILE *fp = fopen(bad, "wb");
    fputs("this is not a volume", fp);
    fclose(fp);
    assert_int_not_equal(sss_field_load(bad, "density", &back, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "bad.vdb: not a readable OpenVDB file"));
    assert_null(strchr(err.msg, '\n'));
    /* truncated ones, cut in the header, the metadata, the tree and the
     * last bytes: each refused in one line (a cut at 300 bytes used to
     * read on from a failed stream for 100 s, docs/heterogeneous.md §6) */
    snprintf(bad, sizeof bad, "%s/cut.vdb", tmpdir);
    struct stat st;
    assert_int_equal(stat(path, &st), 0);
    const long cuts[] = {8, 40, 120, 300, 600, (long)st.st_size / 2, (long)st.st_size - 1};
    for (size_t i = 0; i < sizeof cuts / sizeof *cuts; i++) {
        char cmd[1000];
        snprintf(cmd, sizeof cmd, "head -c %ld '%s' > '%s'", cuts[i], path, bad);
        assert_int_equal(system(cmd), 0);
        if (sss_field_load(bad, "density", &back, &err) == SSS_OK) fail_msg("a cut at %ld bytes was read", cuts[i]);
        assert_non_null(strstr(err.msg, "cut.vdb: "));
        assert_null(strchr(err.msg, '\n'));
    }
    sss_field_free(&g);
}

static void fieldOutsideTheMeshOrABadVdbFailsTheBakeNamingTheFile(void **state)
{
    (void)state;
    make_meshes();
    baked b;
    sss_error err = {{0}};
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    sss_bake_file f;
    /* a sphere field far from the ball */
    if (load(&b, scene_text("ball.ply", "{\"procedural\":\"sphere\",\"centre_mm\":[100,0,0],\"radius_mm\":5}",
                            "0,0,1", NULL), &err) != SSS_OK)
        fail_msg("%s", err.msg);
    assert_int_not_equal(sss_bake_object(&b.sc, &b.plan, b.world, 0, &o, &f, NULL, &err), SSS_OK);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "scene.json: /objects/0/material/field: field: the sphere"));
    assert_non_null(strstr(err.msg, "lies outside the object"));
    unload(&b);
    /* a .vdb whose grid does not cover the ball */
    sss_field small = {.kind = SSS_FIELD_CONSTANT, .value = 0.5}, g;
    const double lo[3] = {-2, -2, -2}, hi[3] = {2, 2, 2};
    assert_int_equal(sss_field_sample(&small, lo, hi, 5, &g, &err), SSS_OK);
    char path[400];
    snprintf(path, sizeof path, "%s/small.vdb", tmpdir);
    assert_int_equal(sss_field_write_vdb(path, "density", &g, &err), SSS_OK);
    sss_field_free(&g);
    if (load(&b, scene_text("ball.ply", "{\"vdb\":\"small.vdb\",\"grid\":\"density\"}", "0,0,1", NULL), &err) !=
        SSS_OK)
        fail_msg("%s", err.msg);
    assert_int_not_equal(sss_bake_object(&b.sc, &b.plan, b.world, 0, &o, &f, NULL, &err), SSS_OK);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "small.vdb: field: the grid spans"));
    unload(&b);
    /* a .vdb that is not one */
    snprintf(path, sizeof path, "%s/junk.vdb", tmpdir);
    FILE *fp = fopen(path, "wb");
    fputs("junk", fp);
    fclose(fp);
    if (load(&b, scene_text("ball.ply", "{\"vdb\":\"junk.vdb\",\"grid\":\"density\"}", "0,0,1", NULL), &err) !=
        SSS_OK)
        fail_msg("%s", err.msg);
    assert_int_not_equal(sss_bake_object(&b.sc, &b.plan, b.world, 0, &o, &f, NULL, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "junk.vdb: not a readable OpenVDB file"));
    unload(&b);
}

/* ---- 4. the surface texture (Hao–Varshney 2004 §5, docs/heterogeneous.md §4.4) -- */

static void surfaceTextureOfAConstantIsTheHomogeneousBake(void **state)
{
    (void)state;
    constants_reduce_to_the_homogeneous_bakes(1);
}

static void surfaceTextureIgnoresAnInclusionThatHoldsNoVertex(void **state)
{
    (void)state;
    make_meshes();
    sss_bake_file hom, vol, tex;
    const char *ball = "{\"procedural\":\"sphere\",\"centre_mm\":[0,0,0],\"radius_mm\":5,\"edge_mm\":1%s}";
    char field[200];
    bake_scene(scene_text("ball.ply", NULL, "0,0,1", NULL), &hom);
    snprintf(field, sizeof field, ball, "");
    bake_scene(scene_text("ball.ply", field, "0,0,1", NULL), &vol);
    snprintf(field, sizeof field, ball, ",\"surface\":true");
    bake_scene(scene_text("ball.ply", field, "0,0,1", NULL), &tex);
    assert_true(tex.hetero.surface && !vol.hetero.surface);
    /* every vertex lies 10 mm from the centre, outside the 5.5 mm ball and
     * its edge: a texture reads f = 0 at every endpoint, the base's q */
    same_q(&tex, &hom);
    /* the volume field charges the segments that cross the ball */
    uint32_t behind = 0;
    double worst = 0.0;
    for (uint32_t v = 0; v < vol.mesh.nv; v++)
        if (vol.mesh.pos[3 * (size_t)v + 2] < -8.0f) {
            behind++;
            worst = fmax(worst, vol.fx.exact_q[v] / hom.fx.exact_q[v]);
        }
    print_message("texture: q bit for bit the homogeneous; volume behind the ball at most %.4f of it (%u vertices)\n",
                  worst, behind);
    assert_true(behind > 10 && worst < 0.9);
    sss_file_free(&hom);
    sss_file_free(&vol);
    sss_file_free(&tex);
}

static void surfaceTextureBakeIsWhatTheExactEvaluatorRecomputesFromTheFile(void **state)
{
    (void)state;
    make_meshes();
    const double L[3] = {0.3, 0.2, 0.9};
    sss_bake_file tex, vol;
    const char *veins = "{\"procedural\":\"veins\",\"seed\":5,\"scale_mm\":6%s}";
    char field[200];
    snprintf(field, sizeof field, veins, ",\"surface\":true");
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &tex);
    snprintf(field, sizeof field, veins, "");
    bake_scene(scene_text("ball.ply", field, "0.3,0.2,0.9", NULL), &vol);
    const size_t n = (size_t)tex.mesh.nv * tex.channels;
    float *q = exact_q(&tex, L);
    double qmax = 0.0, d = 0.0, dvol = 0.0;
    for (size_t k = 0; k < n; k++) qmax = fmax(qmax, tex.fx.exact_q[k]);
    for (size_t k = 0; k < n; k++) d = fmax(d, fabs((double)q[k] - tex.fx.exact_q[k]));
    for (size_t k = 0; k < n; k++) dvol = fmax(dvol, fabs((double)vol.fx.exact_q[k] - tex.fx.exact_q[k]));
    free(q);
    /* the flag is what the evaluator reads: cleared, it marches the volume */
    tex.hetero.surface = 0;
    q = exact_q(&tex, L);
    double dflag = 0.0;
    for (size_t k = 0; k < n; k++) dflag = fmax(dflag, fabs((double)q[k] - tex.fx.exact_q[k]));
    free(q);
    print_message("texture: bake vs exact %.3g, vs the volume bake %.3g, vs exact without the flag %.3g (max q %.3g)\n",
                  d, dvol, dflag, qmax);
    assert_true(d <= 1e-6 * qmax);
    assert_true(dvol > 1e-3 * qmax);
    assert_true(dflag > 1e-3 * qmax);
    sss_file_free(&tex);
    sss_file_free(&vol);
}

static void surfaceFlagRoundTripsAndBadValuesAreRefused(void **state)
{
    (void)state;
    make_meshes();
    sss_bake_file f, r;
    sss_error err = {{0}};
    bake_scene(scene_text("ball.ply", "{\"procedural\":\"sphere\",\"centre_mm\":[0,0,9],\"radius_mm\":3,"
                          "\"surface\":true}", "0,0,1", NULL), &f);
    assert_true(f.hetero.surface);
    uint8_t *buf;
    size_t len;
    assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
    /* a volume field writes the flag word 0: its bytes as before the flag */
    f.hetero.surface = 0;
    uint8_t *buf0;
    size_t len0;
    assert_int_equal(sss_file_encode(&f, &buf0, &len0, &err), SSS_OK);
    assert_int_equal(len0, len);
    size_t ndiff = 0;
    for (size_t k = 0; k < len; k++) ndiff += buf[k] != buf0[k];
    /* the flag's byte and the two CRCs it is under (section, header) */
    assert_true(ndiff >= 2 && ndiff <= 9);
    uint8_t *e;
    uint64_t size;
    assert_int_equal(feld_section(buf, &e, &size)[276], 1);
    assert_int_equal(feld_section(buf0, &e, &size)[276], 0);
    free(buf0);
    /* a flag bit this reader does not know: refused by number */
    feld_put_u32(buf, 276, 5u);
    assert_int_equal(sss_file_decode(buf, len, "later.sss", &r, &err), SSS_ERR_UNSUPPORTED);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "later.sss: section FELD: flag bit 2 is unknown to this reader"));
    feld_put_u32(buf, 276, 1u);
    if (sss_file_decode(buf, len, "mem.sss", &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_true(r.hetero.surface);
    sss_file_free(&r);
    free(buf);
    /* the path-traced reference cannot track a texture: refused in one line */
    f.hetero.surface = 1;
    sss_ref_medium med;
    assert_int_equal(sss_ref_medium_from_material(&f.material, 0.0, &med, &err), SSS_OK);
    med.hetero = &f.hetero;
    assert_int_equal(sss_ref_medium_validate(&med, &err), SSS_ERR_UNSUPPORTED);
    assert_non_null(strstr(err.msg, "a surface texture (section FELD) has no volume"));
    assert_null(strchr(err.msg, '\n'));
    f.hetero.surface = 0;
    assert_int_equal(sss_ref_medium_validate(&med, &err), SSS_OK);
    sss_file_free(&f);
    /* scene values: a non-boolean, and a texture on an editable object */
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":\"ketchup\","
                 "\"field\":{\"procedural\":\"veins\",\"scale_mm\":5,\"surface\":\"yes\"}}}]}",
                 "scene.json: /objects/0/material/field/surface: expected true or false");
    expect_error("{\"objects\":[{\"mesh\":\"a.ply\",\"material\":{\"preset\":\"marble\",\"inside\":\"ketchup\","
                 "\"field\":{\"constant\":0.5,\"surface\":1}}}]}",
                 "scene.json: /objects/0/material/field/surface: expected true or false");
    baked b;
    assert_int_not_equal(load(&b, scene_text("ball.ply", "{\"procedural\":\"veins\",\"scale_mm\":5,\"surface\":true}",
                                             "0,0,1", ",\"editable\":true"), &err), SSS_OK);
    print_message("%s\n", err.msg);
    assert_non_null(strstr(err.msg, "scene.json: /objects/0/material/field/surface: a surface texture on an editable"));
    unload(&b);
}

/* ---- 5. readers' near terms with the field's kernel (docs/heterogeneous.md §4, §5) */

/* q of row j of f's direction set plus the near terms nr for that
 * direction (a convex ball: V = 1 wherever n·ω > 0, the bake's rule) */
static void q_plus_near(const sss_bake_file *f, const sss_weights *nr, uint32_t j, float *out)
{
    const size_t n = (size_t)f->mesh.nv * f->channels;
    memcpy(out, f->q + (size_t)j * n, n * sizeof *out);
    float *gv = malloc(f->mesh.nv * sizeof *gv);
    sss_near_transfer(f->mesh.nrm, f->mesh.nv, (float)f->material.eta, f->dirs.dir + 3 * (size_t)j, NULL, gv);
    sss_near_add(nr, gv, out);
    free(gv);
}

static void runTimeNearTermsOfAFieldFileAreTheBakedOnes(void **state)
{
    (void)state;
    make_meshes();
    /* a volume inclusion breaking the surface and a surface texture */
    const char *fields[] = {"{\"procedural\":\"sphere\",\"centre_mm\":[0,0,8],\"radius_mm\":4,\"edge_mm\":1}",
                            "{\"procedural\":\"veins\",\"seed\":5,\"scale_mm\":6,\"surface\":true}"};
    for (int k = 0; k < 2; k++) {
        char json[2400], base[2100];
        snprintf(base, sizeof base, "%s", scene_text("ball.ply", fields[k], "0,0,1", NULL));
        char *light = strstr(base, "\"direction\":[0,0,1]}");
        assert_non_null(light);
        /* a moving light (a direction set), float rows; near terms baked, then at run time */
        snprintf(json, sizeof json, "%.*s\"direction\":[0,0,1],\"moving\":true}],\"bake\":{\"dirs\":24,"
                 "\"compress\":\"none\",\"near_terms\":\"baked\"}}", (int)(light - base), base);
        sss_bake_file baked_f, run;
        bake_scene(json, &baked_f);
        snprintf(json, sizeof json, "%.*s\"direction\":[0,0,1],\"moving\":true}],\"bake\":{\"dirs\":24,"
                 "\"compress\":\"none\"}}", (int)(light - base), base);
        bake_scene(json, &run);
        assert_int_equal(baked_f.near_terms, 0);
        assert_int_equal(run.near_terms, SSS_NEAR_TERMS_RUNTIME);
        assert_non_null(baked_f.q);
        assert_non_null(run.q);
        assert_int_equal(run.dirs.n, baked_f.dirs.n);
        sss_weights nr, hom;
        sss_error err = {{0}};
        if (sss_near_build_file(&run, &nr, &err) != SSS_OK) fail_msg("%s", err.msg);
        /* what a reader that ignored FELD would add: the base's weights */
        const sss_near_spec spec = {.radius_mm = run.near_radius_mm, .weights = run.weights, .eps = run.eps};
        if (sss_near_build_spec(&run.mesh, &run.material, run.mm_per_unit, run.channels, &spec, NULL, &hom, &err) !=
            SSS_OK)
            fail_msg("%s", err.msg);
        const size_t n = (size_t)run.mesh.nv * run.channels;
        float *a = malloc(n * sizeof *a), *b = malloc(n * sizeof *b);
        double qmax = 0.0, d = 0.0, dhom = 0.0;
        for (uint32_t j = 0; j < run.dirs.n; j++) {
            q_plus_near(&run, &nr, j, a);
            q_plus_near(&run, &hom, j, b);
            const float *want = baked_f.q + (size_t)j * n;
            for (size_t e = 0; e < n; e++) {
                qmax = fmax(qmax, want[e]);
                d = fmax(d, fabs((double)a[e] - want[e]));
                dhom = fmax(dhom, fabs((double)b[e] - want[e]));
            }
        }
        print_message("%s: run-time near terms + rows vs rows with every term, %u directions: max |dq| %.3g of max q "
                      "%.3g; with the base material's weights %.3g\n", k ? "texture" : "inclusion", run.dirs.n, d, qmax,
                      dhom);
        assert_true(d <= 1e-5 * qmax);    /* float rounding */
        assert_true(dhom > 1e-3 * qmax);  /* the check can fail */
        free(a);
        free(b);
        sss_weights_free(&nr);
        sss_weights_free(&hom);
        sss_file_free(&baked_f);
        sss_file_free(&run);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(blendIsExactAtBothEndsAndLinearBetween),
        cmocka_unit_test(transportColourIsReachedAfterTheTransportDistance),
        cmocka_unit_test(proceduralFieldsAreDeterministicBoundedAndSeeded),
        cmocka_unit_test(shapesFollowTheirSignedDistanceWithASmoothEdge),
        cmocka_unit_test(gridIsTrilinearAndSamplingReproducesALinearField),
        cmocka_unit_test(sceneReadsFieldInsideAndTransportAndNamesErrors),
        cmocka_unit_test(constantFieldsReduceToTheHomogeneousBakes),
        cmocka_unit_test(absorbingInclusionNeverBrightensAndDarkensWhatIsBehindIt),
        cmocka_unit_test(backLitSlabFollowsBeerLambertThroughAnAbsorbingLayer),
        cmocka_unit_test(fieldMovedRigidlyWithItsObjectLeavesQUnchanged),
        cmocka_unit_test(kernelIsSymmetricInItsEndpoints),
        cmocka_unit_test(treeKeptKappaHasTheBitsItWouldCompute),
        cmocka_unit_test(profileTableIsWithinItsBoundOfTheExactProfiles),
        cmocka_unit_test(fieldSectionRoundTripsAndRefusesABadGrid),
        cmocka_unit_test(vdbWrittenAndReadBackGivesTheSameField),
        cmocka_unit_test(fieldOutsideTheMeshOrABadVdbFailsTheBakeNamingTheFile),
        cmocka_unit_test(surfaceTextureOfAConstantIsTheHomogeneousBake),
        cmocka_unit_test(surfaceTextureIgnoresAnInclusionThatHoldsNoVertex),
        cmocka_unit_test(surfaceTextureBakeIsWhatTheExactEvaluatorRecomputesFromTheFile),
        cmocka_unit_test(surfaceFlagRoundTripsAndBadValuesAreRefused),
        cmocka_unit_test(runTimeNearTermsOfAFieldFileAreTheBakedOnes),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
