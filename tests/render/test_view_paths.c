#define _POSIX_C_SOURCE 200809L
/* Every path of the viewer draws the C decoder's picture (docs/robustness.md
 * item 10): the plain view and `--scene`, each effect alone and all of them
 * together, on the GPU and on the CPU, with the near terms of a file baked
 * with --own-term runtime on and off (--no-own-term). The viewer's picture
 * comes from the functions sss-view calls (sss_renderer_render_image for a
 * plain view, sss_scene_render_image for a scene); the reference picture
 * is the renderer's draw of a q computed here from the C decoders alone
 * (sss_decode_all, sss_fx_exact, sss_fx_point, sss_fx_env, and the near
 * terms with sss_near_transfer + sss_near_add, their visibility by the
 * bake's ray through the CPU BVH: sss_bvh_occluded, the GPU shader's
 * arithmetic), drawn without adding anything (near_terms 0).
 *
 * The pictures compare per value of the tone-mapped image: at most 2e-3
 * apart (float sums on the GPU against double sums in C). The GPU sum of a
 * scene added the near terms twice, mean 1.05 instead of 0.54 on the front
 * lit bunny, which is far outside. */
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
#include "sss/decode.h"
#include "sss/effects.h"
#include "sss/import.h"
#include "sss/nearterms.h"
#include "sss/planner.h"
#include "sss/probe.h"
#include "sss/render.h"
#include "sss/vec3.h"

#include "gl_fixture.h"

#define W 96
#define H 72
#define TOL 2e-3

static char tmpdir[128];

static int setup(void **state)
{
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_view_paths_XXXXXX");
    if (!mkdtemp(tmpdir)) return -1;
    sss_mesh m;
    sss_error err = {{0}};
    char p[256];
    if (sss_gen_blob(&m, 1.0, 2, &err) != SSS_OK) return -1;
    snprintf(p, sizeof p, "%s/blob.ply", tmpdir);
    sss_result r = sss_export_ply(p, &m, &err);
    sss_mesh_free(&m);
    if (r != SSS_OK) return -1;
    sss_probe pr = {16, 8, NULL};
    pr.rgb = malloc(3 * (size_t)pr.w * pr.h * sizeof(float));
    if (!pr.rgb) return -1;
    for (uint32_t y = 0; y < pr.h; y++)
        for (uint32_t x = 0; x < pr.w; x++) {
            double d[3], dw;
            sss_probe_pixel_dir(pr.w, pr.h, x, y, d, &dw);
            for (int c = 0; c < 3; c++) pr.rgb[3 * ((size_t)y * pr.w + x) + c] = (float)((1 + 0.7 * d[2] + 0.4 * d[0]) * (1 - 0.2 * c));
        }
    snprintf(p, sizeof p, "%s/sky.exr", tmpdir);
    r = sss_probe_write(p, &pr, &err);
    sss_probe_free(&pr);
    return r == SSS_OK ? gl_setup(state) : -1;
}

static int teardown(void **state)
{
    char cmd[200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    if (system(cmd) != 0) return -1;
    return gl_teardown(state);
}

/* ---- the C reference ------------------------------------------------------ */

/* The near terms of unit light l added to q, from the file alone: the
 * weights of sss_near_build, every vertex's visibility by the bake's ray
 * (origin x + δn, towards l, blocked beyond δ) through the CPU BVH. */
static void c_near(const sss_bake_file *f, const double l[3], float *q)
{
    sss_weights nw;
    sss_bvh bvh;
    sss_error err = {{0}};
    /* as the file says: rings or radius (NRAD, a scene's direction set), weight rule */
    assert_int_equal(sss_near_build_file(f, &nw, &err), SSS_OK);
    assert_int_equal(sss_bvh_build(f->mesh.pos, f->mesh.nv, f->mesh.tri, f->mesh.nf, &bvh, &err), SSS_OK);
    const float delta = sss_mesh_ray_offset(&f->mesh), lf[3] = {(float)l[0], (float)l[1], (float)l[2]};
    uint8_t *lit = malloc(f->mesh.nv);
    float *gv = malloc(f->mesh.nv * sizeof *gv);
    assert_non_null(lit);
    assert_non_null(gv);
    for (uint32_t v = 0; v < f->mesh.nv; v++) {
        const float *x = &f->mesh.pos[3 * (size_t)v], *n = &f->mesh.nrm[3 * (size_t)v];
        const double c = (double)n[0] * l[0] + (double)n[1] * l[1] + (double)n[2] * l[2];
        const float o[3] = {x[0] + delta * n[0], x[1] + delta * n[1], x[2] + delta * n[2]};
        lit[v] = c > 0.0 && !sss_bvh_occluded(&bvh, o, lf, delta);
    }
    sss_near_transfer(f->mesh.nrm, f->mesh.nv, (float)f->material.eta, l, lit, gv);
    sss_near_add(&nw, gv, q);
    free(lit);
    free(gv);
    sss_weights_free(&nw);
    sss_bvh_free(&bvh);
}

/* q += w · src over nv × C values. */
static void add_weighted(const sss_bake_file *f, const double w[3], const float *src, float *q)
{
    const size_t C = f->channels;
    for (size_t i = 0; i < (size_t)f->mesh.nv * C; i++) q[i] += (float)(w[C == 3 ? i % 3 : 0] * src[i]);
}

/* The reference q of a scene's lights at angle 0, from the decoders: each
 * light's term by the effect the file records for it (the row of a static
 * direction, the direction set plus the near terms of an OWNT file, the
 * shells, the environment's SH), times its intensity and colour (a grey
 * file: their mean). */
static void c_scene(const sss_bake_file *f, const sss_scene *sc, int near, float *q)
{
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *t = calloc(n, sizeof *t);
    float *env = calloc((size_t)f->mesh.nv * 3, sizeof *env);
    assert_non_null(t);
    assert_non_null(env);
    memset(q, 0, n * sizeof *q);
    double lo[3], hi[3], c[3];
    sss_mesh_bounds(&f->mesh, lo, hi);
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]);
    const uint32_t mask = f->fx.mask ? f->fx.mask : SSS_FX_DIR_SET;
    int env_done = 0;
    for (uint32_t i = 0; i < sc->nlights; i++) {
        const sss_scene_light *L = &sc->lights[i];
        double w[3];
        for (int k = 0; k < 3; k++) w[k] = L->intensity * L->colour[k];
        if (f->channels == 1) w[0] = w[1] = w[2] = (w[0] + w[1] + w[2]) / 3.0;
        double d[3];
        if (L->kind == SSS_LIGHT_DIRECTIONAL) memcpy(d, L->direction, sizeof d);
        else for (int k = 0; k < 3; k++) d[k] = L->position[k] - c[k];
        sss_normalize3(d);
        int row = -1;
        for (uint32_t e = 0; !L->moving && L->kind != SSS_LIGHT_ENVIRONMENT && e < f->fx.nexact && row < 0; e++)
            if (sss_plan_same_direction(&f->fx.exact_dir[3 * (size_t)e], d)) row = (int)e;
        if (L->kind == SSS_LIGHT_ENVIRONMENT) {
            if (env_done++) continue; /* the stored probe sums every environment */
            sss_fx_env(f, NULL, env); /* the probe holds intensity and colour already */
            for (size_t v = 0; v < f->mesh.nv; v++)
                for (uint32_t ch = 0; ch < f->channels; ch++)
                    q[v * f->channels + ch] +=
                        f->channels == 3 ? env[3 * v + ch] : (env[3 * v] + env[3 * v + 1] + env[3 * v + 2]) / 3.0f;
            continue;
        }
        if (row >= 0 && (mask & SSS_FX_DIR_EXACT)) {
            if (L->kind == SSS_LIGHT_POINT) {
                double d2 = 0;
                for (int k = 0; k < 3; k++) d2 += (L->position[k] - c[k]) * (L->position[k] - c[k]);
                for (int k = 0; k < 3; k++) w[k] /= d2;
            }
            add_weighted(f, w, sss_fx_exact(f, (uint32_t)row), q);
        } else if (L->kind == SSS_LIGHT_POINT) {
            sss_fx_point(f, L->position, t);
            add_weighted(f, w, t, q);
        } else {
            sss_decode_all(f, d, t);
            if (near && f->near_terms) c_near(f, d, t);
            add_weighted(f, w, t, q);
        }
    }
    free(t);
    free(env);
}

/* ---- comparing pictures ---------------------------------------------------- */

/* lit: the reference's least mean (the picture saw light) */
static double compare_lit(const float *a, const float *b, const char *what, double lit)
{
    double worst = 0, sum = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        worst = fmax(worst, fabs((double)a[i] - b[i]));
        sum += b[i];
    }
    print_message("%-58s max difference %.3g (reference mean %.4f)\n", what, worst, sum / (W * H * 3));
    assert_true(sum > lit * W * H * 3); /* the picture saw light */
    return worst;
}

static double compare(const float *a, const float *b, const char *what) { return compare_lit(a, b, what, 1e-3); }

static void view_params(sss_view_params *p, const double light[3], int near, sss_eval_path path)
{
    sss_view_params_default(p);
    memcpy(p->light, light, sizeof p->light);
    p->view[0] = 0.3, p->view[1] = -0.4, p->view[2] = 1.0;
    p->exposure = 3.0;
    p->specular = 0;
    p->near_terms = near;
    p->path = path;
    p->single = -1; /* q's paths are compared; single scattering is per pixel (test_render_single) */
}

/* The reference picture of q: drawn as given. */
static void reference(sss_renderer *r, const double light[3], const float *q, float **rgb)
{
    sss_view_params p;
    view_params(&p, light, 0, SSS_EVAL_GPU);
    sss_error err = {{0}};
    if (sss_renderer_render_q_image(r, &p, q, W, H, rgb, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
}

/* ---- the plain view ---------------------------------------------------------- */

static void plainViewMatchesCDecoderOnEveryPath(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 2, &err), SSS_OK);
    for (int own = 0; own < 2; own++) {
        sss_bake_file f;
        bake_preset(&m, "skin1", 0, 10.0, 40, SSS_QUANT_FLOAT, own ? 1 : -1, &f);
        sss_renderer *r;
        assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
        const size_t n = (size_t)f.mesh.nv * f.channels;
        float *q = malloc(n * sizeof *q);
        assert_non_null(q);
        static const double lights[2][3] = {{0.2, -0.3, 1.0}, {-0.9, 0.4, 0.3}};
        for (int li = 0; li < 2; li++)
            for (int near = 0; near < 2; near++) {
                double l[3] = {lights[li][0], lights[li][1], lights[li][2]};
                sss_normalize3(l);
                sss_decode_all(&f, l, q);
                if (near && f.near_terms) c_near(&f, l, q);
                float *ref;
                reference(r, l, q, &ref);
                for (int path = 0; path < 2; path++) {
                    sss_view_params p;
                    view_params(&p, l, near, path ? SSS_EVAL_CPU : SSS_EVAL_GPU);
                    float *rgb;
                    if (sss_renderer_render_image(r, &p, W, H, &rgb, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
                    char what[96];
                    snprintf(what, sizeof what, "plain %s, %s, light %d, near terms %s", own ? "OWNT" : "float",
                             path ? "CPU" : "GPU", li, near ? "on" : "off");
                    assert_true(compare(rgb, ref, what) <= TOL);
                    free(rgb);
                }
                free(ref);
            }
        free(q);
        sss_renderer_destroy(r);
        sss_file_free(&f);
    }
    sss_mesh_free(&m);
}

/* ---- scenes -------------------------------------------------------------------- */

/* The scene's picture on the GPU and the CPU against the reference, for
 * the view's near terms on and off. */
static void check_scene(const sss_bake_file *f, const char *json, const char *label)
{
    sss_scene sc;
    sss_error err = {{0}};
    char path[256];
    snprintf(path, sizeof path, "%s/scene.json", tmpdir);
    if (sss_scene_parse(json, path, &sc, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_scene_eval *ev;
    if (sss_scene_eval_create(f, &sc, &ev, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create(f, &r, &err), SSS_OK);
    sss_fx_gpu *g;
    if (sss_fx_gpu_create(f, ev, r, &g, &err) != SSS_OK) fail_msg("%s", err.msg);
    const size_t n = (size_t)f->mesh.nv * f->channels;
    float *q = malloc(n * sizeof *q);
    assert_non_null(q);
    static const double unused[3] = {0, 0, 1}; /* a scene's lights come from the scene */
    for (int near = 0; near < (f->near_terms ? 2 : 1); near++) {
        c_scene(f, &sc, near, q);
        float *ref;
        reference(r, unused, q, &ref);
        for (int path = 0; path < 2; path++) {
            sss_view_params p;
            view_params(&p, unused, near, SSS_EVAL_GPU);
            float *rgb;
            if (sss_scene_render_image(r, ev, path ? NULL : g, &p, 0.0, W, H, &rgb, NULL, &err) != SSS_OK)
                fail_msg("%s", err.msg);
            char what[96];
            snprintf(what, sizeof what, "--scene %s, %s%s", label, path ? "CPU" : "GPU",
                     f->near_terms ? (near ? ", near terms on" : ", near terms off") : "");
            /* without their near terms the rows of a scene's direction set
             * hold what lies beyond 95 % of R_d,total: a dimmer picture */
            assert_true(compare_lit(rgb, ref, what, near || !f->near_terms ? 1e-3 : 1e-4) <= TOL);
            free(rgb);
        }
        free(ref);
    }
    free(q);
    sss_fx_gpu_destroy(g);
    sss_renderer_destroy(r);
    sss_scene_eval_destroy(ev);
    sss_scene_free(&sc);
}

static void bake_scene(const char *json, sss_bake_file *f)
{
    sss_scene sc;
    sss_error err = {{0}};
    char path[256];
    snprintf(path, sizeof path, "%s/scene.json", tmpdir);
    if (sss_scene_parse(json, path, &sc, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_mesh m, world;
    if (sss_import_mesh(sc.objects[0].mesh, &m, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(sss_scene_object_world(&sc.objects[0], &m, &world, &err), SSS_OK);
    sss_mesh_free(&m);
    sss_plan plan;
    if (sss_plan_scene(&sc, &world, &plan, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.threads = 2;
    if (sss_bake_object(&sc, &plan, &world, 0, &o, f, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_plan_free(&plan);
    sss_mesh_free(&world);
    sss_scene_free(&sc);
}

#define OBJ "{\"objects\":[{\"name\":\"blob\",\"mesh\":\"blob.ply\",\"material\":\"skin1\",\"mm_per_unit\":10}],"
#define BAKE "\"bake\":{\"dirs\":40,\"shells\":3,\"sh_order\":3}}"
#define SUN "{\"type\":\"directional\",\"direction\":[0.2,-0.3,1],\"intensity\":1.5}"
#define SET "{\"type\":\"directional\",\"direction\":[-0.8,0.2,0.5],\"moving\":true,\"colour\":[1,0.6,0.3]}"
#define POINT "{\"type\":\"point\",\"position\":[0.3,-0.5,2],\"moving\":true,\"intensity\":4}"
#define ENV "{\"type\":\"environment\",\"probe\":\"sky.exr\",\"intensity\":0.4}"

/* Each effect alone, then all of them: a scene bake's every light kind. */
static void sceneViewMatchesCDecoderForEachEffect(void **state)
{
    (void)state;
    static const char *const lights[5][2] = {{SUN, "directional-exact"},
                                             {SET, "direction-set"},
                                             {POINT, "point-shells"},
                                             {ENV, "environment-sh"},
                                             {SUN "," SET "," POINT "," ENV, "every effect"}};
    for (int k = 0; k < 5; k++) {
        char json[1024];
        snprintf(json, sizeof json, OBJ "\"lights\":[%s]," BAKE, lights[k][0]);
        sss_bake_file f;
        bake_scene(json, &f);
        /* the plan's defaults: a direction set loses its near terms to run
         * time and is compressed (docs/scenes.md, "Rows, weights and near
         * terms"); every pass sums the hat weights */
        const int set = strstr(lights[k][0], "moving\":true,\"colour") != NULL;
        assert_int_equal(f.near_terms != 0, set);
        assert_int_equal(f.quant == SSS_QUANT_REFS, set);
        assert_int_equal(f.weights, SSS_WEIGHTS_HAT);
        check_scene(&f, json, lights[k][1]);
        sss_file_free(&f);
    }
}

/* A plain bake with near terms at run time viewed with a scene: a static
 * light and a moving one, both from its direction set (a plain bake is
 * one), each with its own near terms, on and off. The GPU sum added them
 * twice. */
static void sceneViewOfOwntFileMatchesCDecoder(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 2, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "skin1", 0, 10.0, 40, SSS_QUANT_FLOAT, 1, &f);
    check_scene(&f, OBJ "\"lights\":[{\"type\":\"directional\",\"direction\":[0,0,1],\"moving\":true}]}",
                "OWNT, one light from the front");
    check_scene(&f, OBJ "\"lights\":[" SET ",{\"type\":\"directional\",\"direction\":[0.2,-0.3,1],\"moving\":true,"
                        "\"intensity\":0.5}]}", "OWNT, two coloured lights");
    sss_file_free(&f);
    bake_preset(&m, "skin1", 1, 10.0, 40, SSS_QUANT_LLOYD8, 2, &f); /* grey, lloyd8, two rings */
    check_scene(&f, OBJ "\"lights\":[" SET "]}", "OWNT grey lloyd8, two rings");
    sss_file_free(&f);
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(plainViewMatchesCDecoderOnEveryPath),
        cmocka_unit_test(sceneViewMatchesCDecoderForEachEffect),
        cmocka_unit_test(sceneViewOfOwntFileMatchesCDecoder),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
