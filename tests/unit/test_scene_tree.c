#define _POSIX_C_SOURCE 200809L
/* test_scene_tree.c: scene bakes through the hierarchical gather
 * (planner.c rule_gather, bake_scene.c sss_pass_integrate, gather_field.c;
 * docs/heterogeneous.md §4.5): the same q as the plain bake's tree path,
 * the direct rows' q within the tree's tolerance, with and without a
 * material field, constants through the kernel bit for bit, and the
 * scene key's refusal and reasons. Small generated meshes only. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "genmesh.h"
#include "test_scene_util.h"
#include "sss/bake.h"
#include "sss/bake_scene.h"
#include "sss/import.h"

static char tmpdir[256];

static int setup(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_scene_tree_XXXXXX");
    if (!mkdtemp(tmpdir)) return -1;
    sss_mesh m;
    sss_error err = {{0}};
    char p[400];
    /* concave (self-shadowing on, as a plain bake traces), 2562 vertices:
     * at 10 mm per unit the tree takes 15 far nodes per vertex */
    if (sss_gen_blob(&m, 1.0, 4, &err) != SSS_OK) return -1;
    snprintf(p, sizeof p, "%s/blob.ply", tmpdir);
    if (sss_export_ply(p, &m, &err) != SSS_OK) return -1;
    sss_mesh_free(&m);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd);
}

typedef test_scene baked;

static sss_result load(baked *b, const char *json, sss_error *err) { return test_scene_load(b, tmpdir, json, err); }
static void unload(baked *b) { test_scene_unload(b); }

static const sss_decision *decision(const sss_object_plan *p, const char *effect)
{
    for (uint32_t d = 0; d < p->ndecisions; d++)
        if (!strcmp(p->decisions[d].effect, effect)) return &p->decisions[d];
    fail_msg("no decision for %s", effect);
    return NULL;
}

/* Bakes object 0 of the scene text with the gather the scene asks for. */
static void bake(const char *json, int want_gather, sss_bake_file *f, sss_bake_stats *st)
{
    baked b;
    sss_error err = {{0}};
    if (load(&b, json, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(b.plan.obj[0].gather, want_gather);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    if (sss_bake_object(&b.sc, &b.plan, b.world, 0, &o, f, st, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(st->gather, want_gather);
    unload(&b);
}

/* The blob, 20 mm across, in a grey material whose neighbourhoods reach
 * across it: the tree has far nodes. Grey (one channel), so that a field's
 * kappa per pair costs a third of an RGB one's and the test stays short. */
#define MAT "\"sigma_a\":[0.05,0.05,0.05],\"sigmap_s\":[0.9,0.9,0.9]"
#define VEINS "{\"procedural\":\"veins\",\"scale_mm\":40,\"seed\":3}"
#define INSIDE "{\"sigma_a\":[0.4,0.4,0.4],\"sigmap_s\":[0.9,0.9,0.9]}"

static char *scene(const char *field, const char *light, const char *bake_opts)
{
    static char buf[1500];
    snprintf(buf, sizeof buf, "{\"objects\":[{\"mesh\":\"blob.ply\",\"mm_per_unit\":10,\"material\":{" MAT
             "%s%s%s}}],\"lights\":[%s],\"bake\":{%s}}", field ? ",\"inside\":" INSIDE ",\"field\":" : "",
             field ? field : "", "", light, bake_opts);
    return buf;
}

#define STATIC_LIGHT "{\"type\":\"directional\",\"direction\":[0.3,0.2,0.9]}"
#define MOVING_LIGHT "{\"type\":\"directional\",\"direction\":[0,0,1],\"moving\":true}"

/* RMS of a − b over RMS of b, and the largest |a − b| over the largest b. */
static void compare(const float *a, const float *b, size_t n, double *rms_rel, double *max_rel)
{
    double d2 = 0, b2 = 0, dm = 0, bm = 0;
    for (size_t k = 0; k < n; k++) {
        const double d = (double)a[k] - b[k];
        d2 += d * d;
        b2 += (double)b[k] * b[k];
        dm = fmax(dm, fabs(d));
        bm = fmax(bm, fabs((double)b[k]));
    }
    *rms_rel = b2 > 0 ? sqrt(d2 / b2) : 0;
    *max_rel = bm > 0 ? dm / bm : 0;
}

/* A homogeneous scene's direction set through the tree is the plain bake's
 * tree path (`sss-bake --gather tree`): the same hierarchy, transfer rows,
 * weights and hat corrections, so the same q to float rounding. */
static void sceneTreeIsThePlainTreeBake(void **state)
{
    (void)state;
    sss_bake_file f, plain;
    sss_bake_stats st, pst;
    bake(scene(NULL, MOVING_LIGHT, "\"dirs\":24,\"compress\":\"none\",\"near_terms\":\"baked\",\"gather\":\"tree\""),
         SSS_GATHER_TREE, &f, &st);
    assert_true(st.far_pairs > 0);
    sss_mesh m;
    sss_error err = {{0}};
    char p[400];
    snprintf(p, sizeof p, "%s/blob.ply", tmpdir);
    assert_int_equal(sss_import_mesh(p, &m, NULL, &err), SSS_OK);
    sss_material mat = f.material;
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.n_dirs = 24;
    o.mm_per_unit = 10;
    o.weights = SSS_WEIGHTS_HAT;
    o.gather = SSS_GATHER_TREE;
    assert_int_equal(sss_bake(&m, "blob", &mat, &o, &plain, &pst, &err), SSS_OK);
    assert_int_equal(pst.gather, SSS_GATHER_TREE);
    assert_int_equal(plain.mesh.nv, f.mesh.nv);
    assert_int_equal(plain.dirs.n, f.dirs.n);
    assert_int_equal(pst.far_pairs, st.far_pairs);
    const size_t n = (size_t)f.dirs.n * f.mesh.nv * f.channels;
    double rms, mx;
    compare(f.q, plain.q, n, &rms, &mx);
    const int same = !memcmp(f.q, plain.q, n * sizeof *f.q);
    print_message("scene tree vs plain tree: %s; RMS %.3g, max %.3g of max q (far pairs %llu)\n",
                  same ? "the same bytes" : "different bytes", rms, mx, (unsigned long long)st.far_pairs);
    assert_true(mx <= 1e-6);
    sss_file_free(&plain);
    sss_file_free(&f);
    sss_mesh_free(&m);
}

/* The tree against the direct rows on the same scene: within the tree's
 * documented tolerance (docs/benchmarks.md "Bake at scale": 1e-3 RMS),
 * with veins too (docs/heterogeneous.md §4.5: the far nodes' κ at the
 * centroid; measured 1.7e-4 and 1.6e-4 RMS, 3.2e-4 of the largest q at
 * most, where the veins move q by 6 % RMS). */
static void sceneTreeAgreesWithTheDirectRows(void **state)
{
    (void)state;
    const char *fields[] = {NULL, VEINS};
    const double bound_rms = 1e-3, bound_max = 5e-3;
    float *hom = NULL;
    for (int k = 0; k < 2; k++) {
        sss_bake_file t, d;
        sss_bake_stats st, sd;
        char js[1500];
        snprintf(js, sizeof js, "%s", scene(fields[k], STATIC_LIGHT, "\"gather\":\"tree\""));
        bake(js, SSS_GATHER_TREE, &t, &st);
        snprintf(js, sizeof js, "%s", scene(fields[k], STATIC_LIGHT, "\"gather\":\"direct\""));
        bake(js, SSS_GATHER_DIRECT, &d, &sd);
        assert_true(st.far_pairs > 0);
        assert_int_equal(t.fx.nexact, 1);
        assert_int_equal(d.fx.nexact, 1);
        assert_int_equal(t.hetero.field.kind, k ? SSS_FIELD_VEINS : SSS_FIELD_NONE);
        const size_t n = (size_t)t.mesh.nv * t.channels;
        double rms, mx;
        compare(t.fx.exact_q, d.fx.exact_q, n, &rms, &mx);
        print_message("%s: tree vs direct rows: RMS %.3g, max %.3g of max q (far pairs per vertex %.1f)\n",
                      k ? "veins" : "homogeneous", rms, mx, (double)st.far_pairs / t.mesh.nv);
        assert_true(rms > 0.0); /* the far field is used */
        assert_true(rms <= bound_rms);
        assert_true(mx <= bound_max);
        if (k == 0) {
            hom = malloc(n * sizeof *hom);
            memcpy(hom, t.fx.exact_q, n * sizeof *hom);
        } else { /* the veins change q far beyond the bound: the field is there */
            compare(t.fx.exact_q, hom, n, &rms, &mx);
            print_message("veins against homogeneous (tree): RMS %.3g, max %.3g of max q\n", rms, mx);
            assert_true(rms > 10 * bound_rms);
        }
        sss_file_free(&t);
        sss_file_free(&d);
    }
    free(hom);
}

/* A field through the tree keeps a near pair's κ for its second block
 * when both lie in one group of blocks (docs/heterogeneous.md §4.5,
 * gather_field.c): which thread runs which group must not reach the
 * bytes. One thread and three give the same q. (Which pairs are kept
 * depends on the groups alone; test_field's
 * treeKeptKappaHasTheBitsItWouldCompute compares kept with computed.) */
static void fieldThroughTheTreeHasTheSameBytesWhateverTheThreadCount(void **state)
{
    (void)state;
    const int saved = omp_get_max_threads();
    sss_bake_file a, b;
    sss_bake_stats sa, sb;
    char js[1500];
    snprintf(js, sizeof js, "%s", scene(VEINS, STATIC_LIGHT, "\"gather\":\"tree\""));
    omp_set_num_threads(1);
    bake(js, SSS_GATHER_TREE, &a, &sa);
    omp_set_num_threads(3);
    bake(js, SSS_GATHER_TREE, &b, &sb);
    omp_set_num_threads(saved);
    assert_int_equal(a.hetero.field.kind, SSS_FIELD_VEINS);
    assert_int_equal(a.fx.nexact, 1);
    assert_int_equal(b.fx.nexact, 1);
    assert_true(a.mesh.nv > 1024); /* more than one group (SSS_GATHER_FIELD_GROUP, 1,024 receivers) */
    const size_t n = (size_t)a.mesh.nv * a.channels;
    assert_memory_equal(a.fx.exact_q, b.fx.exact_q, n * sizeof *a.fx.exact_q);
    sss_file_free(&a);
    sss_file_free(&b);
}

/* Constant fields through the tree: c = 0 folds (planner) into the
 * homogeneous tree bake; a box holding the whole blob (f = 1 everywhere)
 * and a stratum far away (f = 0) go through the kernel, whose κ is then 1
 * at every near pair and every far node's centroid: the homogeneous tree
 * bakes of the inside and of the base, bit for bit. */
static void constantFieldsThroughTheTreeAreTheHomogeneousTreeBakes(void **state)
{
    (void)state;
    const char *tree = "\"gather\":\"tree\"";
    sss_bake_file hom, in_hom, f;
    sss_bake_stats st;
    bake(scene(NULL, STATIC_LIGHT, tree), SSS_GATHER_TREE, &hom, &st);
    assert_true(st.far_pairs > 0);
    char js[1500];
    snprintf(js, sizeof js, "{\"objects\":[{\"mesh\":\"blob.ply\",\"mm_per_unit\":10,\"material\":" INSIDE
             "}],\"lights\":[" STATIC_LIGHT "],\"bake\":{%s}}", tree);
    bake(js, SSS_GATHER_TREE, &in_hom, &st);
    const size_t n = (size_t)hom.mesh.nv * hom.channels * sizeof(float);
    bake(scene("{\"constant\":0}", STATIC_LIGHT, tree), SSS_GATHER_TREE, &f, &st);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_NONE);
    assert_memory_equal(f.fx.exact_q, hom.fx.exact_q, n);
    sss_file_free(&f);
    bake(scene("{\"procedural\":\"box\",\"centre_mm\":[0,0,0],\"half_mm\":[50,50,50]}", STATIC_LIGHT, tree),
         SSS_GATHER_TREE, &f, &st);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_BOX);
    assert_true(st.far_pairs > 0);
    assert_memory_equal(f.fx.exact_q, in_hom.fx.exact_q, n);
    sss_file_free(&f);
    bake(scene("{\"procedural\":\"layers\",\"normal\":[0,0,1],\"thickness_mm\":10,\"offset_mm\":500}", STATIC_LIGHT,
               tree), SSS_GATHER_TREE, &f, &st);
    assert_int_equal(f.hetero.field.kind, SSS_FIELD_LAYERS);
    assert_memory_equal(f.fx.exact_q, hom.fx.exact_q, n);
    sss_file_free(&f);
    sss_file_free(&hom);
    sss_file_free(&in_hom);
}

/* "gather" in the scene's bake options: the plain bake's default (the
 * tree) with its reason, "direct" on request, a field's reason naming §4.5,
 * any other value refused with its JSON path. */
static void gatherKeyIsPlannedWithItsReasonAndBadValuesAreRefused(void **state)
{
    (void)state;
    baked b;
    sss_error err = {{0}};
    assert_int_equal(load(&b, scene(NULL, STATIC_LIGHT, ""), &err), SSS_OK);
    assert_int_equal(b.plan.obj[0].gather, SSS_GATHER_TREE);
    assert_string_equal(decision(&b.plan.obj[0], "gather")->choice, "tree");
    assert_non_null(strstr(decision(&b.plan.obj[0], "gather")->reason, "the plain bake's default"));
    assert_null(strstr(decision(&b.plan.obj[0], "gather")->reason, "kappa"));
    unload(&b);
    assert_int_equal(load(&b, scene(VEINS, STATIC_LIGHT, "\"gather\":\"tree\""), &err), SSS_OK);
    assert_non_null(strstr(decision(&b.plan.obj[0], "gather")->reason, "(bake.gather)"));
    assert_non_null(strstr(decision(&b.plan.obj[0], "gather")->reason, "heterogeneous.md sec. 4.5"));
    unload(&b);
    assert_int_equal(load(&b, scene(VEINS, STATIC_LIGHT, "\"gather\":\"direct\""), &err), SSS_OK);
    assert_int_equal(b.plan.obj[0].gather, SSS_GATHER_DIRECT);
    assert_string_equal(decision(&b.plan.obj[0], "gather")->choice, "direct");
    assert_non_null(strstr(decision(&b.plan.obj[0], "gather")->reason, "kappa"));
    unload(&b);
    assert_int_not_equal(load(&b, scene(NULL, STATIC_LIGHT, "\"gather\":\"octree\""), &err), SSS_OK);
    assert_non_null(strstr(err.msg, "scene.json: /bake/gather: 'octree' is not \"direct\" or \"tree\""));
    assert_null(strchr(err.msg, '\n'));
    unload(&b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sceneTreeIsThePlainTreeBake),
        cmocka_unit_test(sceneTreeAgreesWithTheDirectRows),
        cmocka_unit_test(fieldThroughTheTreeHasTheSameBytesWhateverTheThreadCount),
        cmocka_unit_test(constantFieldsThroughTheTreeAreTheHomogeneousTreeBakes),
        cmocka_unit_test(gatherKeyIsPlannedWithItsReasonAndBadValuesAreRefused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
