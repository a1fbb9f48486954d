#define _POSIX_C_SOURCE 200809L
/* The scene's lights summed on the GPU (runtime/src/render/fx_gpu.c) against the
 * CPU sum (runtime/src/render/scene_view.c, the reference), per vertex and
 * channel, on scene bakes (format 1.2) with every light kind:
 * directional-exact, direction-set (Hao–Varshney 2004 §3.2), point-shells
 * (§3.3) and environment-sh, moving lights at several angles, RGB and grey;
 * and which GPU programs a file gets: only those its sections need.
 *
 * Stated tolerance: 1e-5 relative per value (float rounding of a few terms;
 * values below 1e-30 count as equal). The GPU kernels form the C
 * evaluator's double sums in its order (`precise`), so on llvmpipe the
 * terms other than the direction set's agree to the bit; the direction set
 * goes through the renderer's float compute pass (within 1e-4 of the C
 * decoder by test_render, measured far below). */
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
#include "sss/bake_scene.h"
#include "sss/import.h"
#include "sss/probe.h"
#include "sss/render.h"

static sss_offscreen *ctx;
static char tmpdir[256];

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_fx_gpu_XXXXXX");
    if (!mkdtemp(tmpdir)) return -1;
    if (sss_offscreen_create(&ctx, &err) != SSS_OK) {
        fprintf(stderr, "no offscreen GL context: %s\n", err.msg);
        return -1;
    }
    /* a blob (concave: self-shadowing) and a small probe with some
     * structure in azimuth, so that rotating it changes the light */
    sss_mesh m;
    char p[400];
    if (sss_gen_blob(&m, 1.0, 2, &err) != SSS_OK) return -1;
    snprintf(p, sizeof p, "%s/blob.ply", tmpdir);
    sss_result res = sss_export_ply(p, &m, &err);
    sss_mesh_free(&m);
    if (res != SSS_OK) return -1;
    sss_probe pr = {32, 16, NULL};
    pr.rgb = malloc(3 * (size_t)pr.w * pr.h * sizeof(float));
    if (!pr.rgb) return -1;
    for (uint32_t y = 0; y < pr.h; y++)
        for (uint32_t x = 0; x < pr.w; x++) {
            double d[3], dw;
            sss_probe_pixel_dir(pr.w, pr.h, x, y, d, &dw);
            const double L = 1 + 0.6 * d[2] + 0.5 * d[0] + 0.3 * d[0] * d[1];
            for (int c = 0; c < 3; c++) pr.rgb[3 * ((size_t)y * pr.w + x) + c] = (float)(L * (1.0 - 0.25 * c));
        }
    snprintf(p, sizeof p, "%s/sky.exr", tmpdir);
    res = sss_probe_write(p, &pr, &err);
    sss_probe_free(&pr);
    return res == SSS_OK ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    sss_offscreen_destroy(ctx);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Plans and bakes object 0 of the scene text (paths relative to tmpdir). */
static void bake_scene(const char *json, sss_scene *sc, sss_bake_file *f)
{
    sss_error err = {{0}};
    char path[400];
    snprintf(path, sizeof path, "%s/scene.json", tmpdir);
    if (sss_scene_parse(json, path, sc, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_mesh *world = calloc(sc->nobjects, sizeof *world);
    assert_non_null(world);
    for (uint32_t i = 0; i < sc->nobjects; i++) {
        sss_mesh m;
        if (sss_import_mesh(sc->objects[i].mesh, &m, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
        assert_int_equal(sss_scene_object_world(&sc->objects[i], &m, &world[i], &err), SSS_OK);
        sss_mesh_free(&m);
    }
    sss_plan plan;
    if (sss_plan_scene(sc, world, &plan, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.threads = 2;
    sss_bake_stats st;
    if (sss_bake_object(sc, &plan, world, 0, &o, f, &st, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_plan_free(&plan);
    for (uint32_t i = 0; i < sc->nobjects; i++) sss_mesh_free(&world[i]);
    free(world);
}

/* GPU vs CPU sum at several angles of the moving lights; returns the worst
 * relative difference. */
static double compare(const sss_bake_file *f, const sss_scene *sc, const char *label, unsigned want_programs)
{
    sss_error err = {{0}};
    sss_scene_eval *ev;
    if (sss_scene_eval_create(f, sc, &ev, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_renderer *r;
    if (sss_renderer_create(f, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_fx_gpu *g;
    if (sss_fx_gpu_create(f, ev, r, &g, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(sss_fx_gpu_programs(g), want_programs);
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *gq = malloc(n * sizeof *gq), *cq = malloc(n * sizeof *cq);
    assert_non_null(gq);
    assert_non_null(cq);
    double worst = 0, cmax = 0;
    size_t nexact = 0;
    for (int t = 0; t < 6; t++) {
        const double angle = 0.7 * t;
        sss_fx_gpu_frame(g, angle);
        sss_renderer_read_q(r, gq);
        sss_scene_eval_frame(ev, angle, cq);
        for (size_t i = 0; i < n; i++) {
            const double d = fabs((double)gq[i] - cq[i]);
            const double rel = d < 1e-30 ? 0.0 : d / fmax(fabs((double)cq[i]), 1e-30);
            if (rel > worst) worst = rel;
            if (cq[i] > cmax) cmax = cq[i];
            nexact += gq[i] == cq[i];
        }
    }
    print_message("GPU vs CPU scene sum, %s (%s; programs %s): %u vertices x %u channels x 6 frames: worst relative "
                  "difference %.3g, %.2f%% bit-identical, max q %.3g\n",
                  label, sss_scene_eval_paths(ev), sss_fx_gpu_describe(g), f->mesh.nv, f->channels, worst,
                  100.0 * (double)nexact / (6.0 * (double)n), cmax);
    assert_true(cmax > 0); /* the comparison saw light */
    free(gq);
    free(cq);
    sss_fx_gpu_destroy(g);
    sss_renderer_destroy(r);
    sss_scene_eval_destroy(ev);
    return worst;
}

#define OBJ(material) "{\"objects\":[{\"name\":\"blob\",\"mesh\":\"blob.ply\",\"material\":" material ",\"mm_per_unit\":10}],"
#define BAKE "\"bake\":{\"dirs\":40,\"shells\":3,\"sh_order\":3}}"

/* Every light kind at once, RGB: two static suns (two QDIR rows), a moving
 * coloured directional light (the direction set, through the renderer's
 * compute pass), a moving near point light and a turning environment. */
static void gpuSceneSumMatchesCpuAllEffects(void **state)
{
    (void)state;
    sss_scene sc;
    sss_bake_file f;
    bake_scene(OBJ("\"skin1\"") "\"lights\":["
               "{\"type\":\"directional\",\"direction\":[0,0,1],\"intensity\":2},"
               "{\"type\":\"directional\",\"direction\":[0,-1,0.2],\"colour\":[0.2,0.4,1]},"
               "{\"type\":\"directional\",\"direction\":[1,0,0.3],\"moving\":true,\"colour\":[1,0.5,0.2]},"
               "{\"type\":\"point\",\"position\":[0,0.5,2],\"moving\":true,\"intensity\":3},"
               "{\"type\":\"environment\",\"probe\":\"sky.exr\",\"intensity\":0.3,\"moving\":true}]," BAKE,
               &sc, &f);
    assert_int_equal(f.channels, 3);
    assert_true(f.fx.mask & SSS_FX_DIR_EXACT);
    assert_true(f.fx.mask & SSS_FX_DIR_SET);
    assert_true(f.fx.mask & SSS_FX_POINT_SHELLS);
    assert_true(f.fx.mask & SSS_FX_ENV_SH);
    double worst = compare(&f, &sc, "all effects, rgb", SSS_FXGPU_ROWS | SSS_FXGPU_SHELL | SSS_FXGPU_ENV);
    assert_true(worst <= 1e-5);
    sss_file_free(&f);
    sss_scene_free(&sc);
}

/* The panel's switches (sss_scene_eval_set_kinds): each light kind alone,
 * on the CPU and on the GPU, gives a non-zero term; the terms add up to the
 * sum of all kinds; none switched on gives q = 0 on both paths. */
static void sceneKindsSwitchEachEffect(void **state)
{
    (void)state;
    sss_scene sc;
    sss_bake_file f;
    sss_error err = {{0}};
    bake_scene(OBJ("\"skin1\"") "\"lights\":["
               "{\"type\":\"directional\",\"direction\":[0,0,1],\"intensity\":2},"
               "{\"type\":\"directional\",\"direction\":[1,0,0.3],\"moving\":true,\"colour\":[1,0.5,0.2]},"
               "{\"type\":\"point\",\"position\":[0,0.5,2],\"moving\":true,\"intensity\":3},"
               "{\"type\":\"environment\",\"probe\":\"sky.exr\",\"intensity\":0.3,\"moving\":true}]," BAKE,
               &sc, &f);
    sss_scene_eval *ev;
    if (sss_scene_eval_create(&f, &sc, &ev, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(sss_scene_eval_kinds(ev), SSS_SCENE_KINDS_ALL);
    assert_int_equal(sss_scene_eval_kinds_present(ev), 0xFu);
    sss_renderer *r;
    if (sss_renderer_create(&f, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_fx_gpu *g;
    if (sss_fx_gpu_create(&f, ev, r, &g, &err) != SSS_OK) fail_msg("%s", err.msg);
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *all = malloc(n * sizeof *all), *one = malloc(n * sizeof *one), *gq = malloc(n * sizeof *gq);
    double *sum = calloc(n, sizeof *sum);
    assert_true(all && one && gq && sum);
    const double angle = 0.9;
    sss_scene_eval_frame(ev, angle, all);
    for (unsigned k = 0; k < 4; k++) {
        sss_scene_eval_set_kinds(ev, 1u << k);
        sss_scene_eval_frame(ev, angle, one);
        sss_fx_gpu_frame(g, angle);
        sss_renderer_read_q(r, gq);
        double mx = 0, worst = 0;
        for (size_t i = 0; i < n; i++) {
            sum[i] += one[i];
            mx = fmax(mx, one[i]);
            worst = fmax(worst, fabs((double)gq[i] - one[i]) / fmax(fabs((double)one[i]), 1e-20));
        }
        print_message("light kind %u alone: max q %.3g, GPU vs CPU worst relative %.3g\n", k, mx, worst);
        assert_true(mx > 0);
        assert_true(worst <= 1e-5);
    }
    double worst = 0;
    for (size_t i = 0; i < n; i++) worst = fmax(worst, fabs(sum[i] - all[i]) / fmax(fabs((double)all[i]), 1e-20));
    print_message("the four kinds alone add up to all of them within %.3g (relative)\n", worst);
    assert_true(worst <= 1e-5);
    sss_scene_eval_set_kinds(ev, 0);
    sss_scene_eval_frame(ev, angle, one);
    sss_fx_gpu_frame(g, angle);
    sss_renderer_read_q(r, gq);
    for (size_t i = 0; i < n; i++) {
        assert_true(one[i] == 0.0f);
        assert_true(gq[i] == 0.0f);
    }
    free(all);
    free(one);
    free(gq);
    free(sum);
    sss_fx_gpu_destroy(g);
    sss_renderer_destroy(r);
    sss_scene_eval_destroy(ev);
    sss_file_free(&f);
    sss_scene_free(&sc);
}

/* Without the direction set every term is the C evaluator's double sum,
 * term for term: bit-identical on an IEEE GPU (the bound stays 1e-5). A
 * grey material: one channel, coloured lights by their mean colour, the
 * environment's R, G, B averaged. */
static void gpuSceneSumMatchesCpuGrey(void **state)
{
    (void)state;
    sss_scene sc;
    sss_bake_file f;
    bake_scene(OBJ("{\"sigma_a\":[0.01,0.01,0.01],\"sigmap_s\":[1.5,1.5,1.5],\"eta\":1.4}") "\"lights\":["
               "{\"type\":\"environment\",\"probe\":\"sky.exr\",\"intensity\":0.5,\"colour\":[1,0.8,0.6]},"
               "{\"type\":\"point\",\"position\":[1.5,0,1],\"moving\":true,\"colour\":[1,0.2,0.2]},"
               "{\"type\":\"directional\",\"direction\":[0.3,0.2,1],\"colour\":[0.5,1,1]}]," BAKE,
               &sc, &f);
    assert_int_equal(f.channels, 1);
    assert_false(f.fx.mask & SSS_FX_DIR_SET);
    double worst = compare(&f, &sc, "grey, no direction set", SSS_FXGPU_ROWS | SSS_FXGPU_SHELL | SSS_FXGPU_ENV);
    assert_true(worst <= 1e-5);
    sss_file_free(&f);
    sss_scene_free(&sc);
}

/* A file without ENVT and PSHL builds neither the environment nor the shell
 * program (nor their buffers): static and moving directional lights only.
 * And a file with ENVT alone builds the environment program only. */
static void fileWithoutEnvOrShellsBuildsNeitherProgram(void **state)
{
    (void)state;
    sss_scene sc;
    sss_bake_file f;
    bake_scene(OBJ("\"marble\"") "\"lights\":["
               "{\"type\":\"directional\",\"direction\":[0,0,1]},"
               "{\"type\":\"directional\",\"direction\":[1,0,0.3],\"moving\":true}]," BAKE,
               &sc, &f);
    assert_false(f.fx.mask & (SSS_FX_ENV_SH | SSS_FX_POINT_SHELLS));
    double worst = compare(&f, &sc, "directional only", SSS_FXGPU_ROWS);
    assert_true(worst <= 1e-5);
    sss_file_free(&f);
    sss_scene_free(&sc);

    bake_scene(OBJ("\"marble\"") "\"lights\":[{\"type\":\"environment\",\"probe\":\"sky.exr\"}]," BAKE, &sc, &f);
    assert_int_equal(f.fx.mask & (SSS_FX_DIR_EXACT | SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH),
                     SSS_FX_ENV_SH);
    worst = compare(&f, &sc, "environment only", SSS_FXGPU_ENV);
    assert_true(worst <= 1e-5);
    sss_file_free(&f);
    sss_scene_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpuSceneSumMatchesCpuAllEffects),
        cmocka_unit_test(sceneKindsSwitchEachEffect),
        cmocka_unit_test(gpuSceneSumMatchesCpuGrey),
        cmocka_unit_test(fileWithoutEnvOrShellsBuildsNeitherProgram),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
