/* test_splat_gpu: the GPU multiresolution splatting (sss/splat_gpu.h,
 * Chen et al. 2012 §4; docs/deformable.md §9) against the object-space
 * per-frame path (sss/perframe.h, exact mode: the exact evaluator on the
 * pose), both drawn by the renderer with the same camera and light, the
 * subsurface term alone. The error is the image RMS over the pixels the
 * object covers, relative to the RMS of the reference there. */
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
#include "gl_fixture.h"
#include "sss/deform.h"
#include "sss/field.h"
#include "sss/import.h"
#include "sss/perframe.h"
#include "sss/splat_gpu.h"
#include "sss/vec3.h"

/* the pictures' size. A splat costs pixels × texels in reach, and every
 * bound below is on an RMS over the covered pixels relative to the
 * reference's, which the pixel count barely moves: at 64² rather than 96²
 * the tube's error is 0.0227/0.0166 (0.0229/0.0172), the rigid motion's
 * change 0.0011 (0.0011), the flicker ratio 1.557 (1.516), for half the
 * time. The tests that draw another size set it and put this one back. */
#define W_BASE 64
static int W = W_BASE, H = W_BASE;

/* A posed mesh drawn both ways: the renderer holds the file, sp the splatting. */
typedef struct scene {
    sss_bake_file f;
    sss_renderer *r;
    sss_splat_gpu *sp;
    sss_view_params p;
} scene;

static void scene_open(scene *s, sss_mesh *m, double mm, const sss_splat_options *o)
{
    memset(s, 0, sizeof *s);
    assert_int_equal(sss_material_preset("skin1", &s->f.material, NULL), SSS_OK);
    s->f.mesh = *m; /* owned by the scene from here */
    memset(m, 0, sizeof *m);
    s->f.mm_per_unit = mm;
    s->f.channels = 3;
    s->f.quant = SSS_QUANT_FLOAT;
    sss_error err = {{0}};
    if (sss_renderer_create(&s->f, &s->r, &err) != SSS_OK) fail_msg("renderer: %s", err.msg);
    if (sss_splat_gpu_create(s->r, o, &s->sp, &err) != SSS_OK) fail_msg("splatting: %s", err.msg);
    sss_view_params_default(&s->p);
    s->p.specular = 0; /* the subsurface term alone: the one the two paths compute differently */
    s->p.view[0] = 0.3, s->p.view[1] = 1.0, s->p.view[2] = 0.3;
    s->p.distance = 2.6;
    s->p.exposure = 1.0 / sss_material_slab_q(&s->f.material, 3);
}

static void scene_close(scene *s)
{
    sss_splat_gpu_destroy(s->sp);
    sss_renderer_destroy(s->r);
    sss_mesh_free(&s->f.mesh);
}

/* The object-space image: q of the pose by the exact per-frame path; with
 * h, the field read at the rest positions rest (docs/deformable.md §10). */
static float *image_exact_field(scene *s, const double L[3], const sss_hetero *h, const float *rest)
{
    const uint32_t nv = s->f.mesh.nv;
    float *q = malloc((size_t)nv * 3 * sizeof *q);
    assert_non_null(q);
    /* hat weights: the point rule underestimates R_d's integral by a few
     * per cent at these spacings (docs/physics.md §9), the image-space sum
     * at its far finer texels does not */
    sss_perframe_options po = {.weights = SSS_WEIGHTS_HAT, .hetero = h, .rest = rest};
    sss_error err = {{0}};
    if (sss_perframe_q(&s->f.mesh, &s->f.material, 3, s->f.mm_per_unit, L, &po, q, NULL, &err) != SSS_OK)
        fail_msg("per-frame: %s", err.msg);
    memcpy(s->p.light, L, sizeof s->p.light);
    float *rgb = NULL, *hdr = NULL;
    if (sss_renderer_render_q_image(s->r, &s->p, q, W, H, &rgb, &hdr, &err) != SSS_OK) fail_msg("draw: %s", err.msg);
    free(q);
    free(rgb);
    return hdr;
}

static float *image_exact(scene *s, const double L[3])
{
    return image_exact_field(s, L, NULL, NULL);
}

static float *image_splat(scene *s, const double L[3])
{
    const double w[1][3] = {{1, 1, 1}};
    double d[1][3] = {{L[0], L[1], L[2]}};
    memcpy(s->p.light, L, sizeof s->p.light);
    float *rgb = NULL, *hdr = NULL;
    sss_error err = {{0}};
    if (sss_splat_gpu_render_image(s->sp, &s->p, (const double(*)[3])d, w, 1, W, H, &rgb, &hdr, &err) != SSS_OK)
        fail_msg("splat: %s", err.msg);
    free(rgb);
    return hdr;
}

/* RMS of a − b over the pixels either covers, relative to the RMS of ref
 * there; *mean_ratio the ratio of the means (a's over b's). */
static double rel_rms(const float *a, const float *b, const float *ref, double *mean_ratio)
{
    double d2 = 0, r2 = 0, sa = 0, sb = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        if (a[i] <= 0 && b[i] <= 0) continue;
        d2 += (double)(a[i] - b[i]) * (a[i] - b[i]);
        r2 += (double)ref[i] * ref[i];
        sa += a[i];
        sb += b[i];
    }
    if (mean_ratio) *mean_ratio = sb > 0 ? sa / sb : 0;
    return r2 > 0 ? sqrt(d2 / r2) : INFINITY;
}

/* The tube of docs/deformable.md §7 (sss-genmesh tube 16 … 0.25: 25 mm
 * across, 10 cm long at 100 mm per unit), bent by 70° about its axis at t. */
static void tube_pose(double t, sss_mesh *out)
{
    sss_mesh rest = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_gen_by_name("tube", 16, 0.25, &rest, &err), SSS_OK);
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {0, 0, 1}, .angle_deg = 70.0, .period_s = 4.0};
    if (sss_deform_pose(&d, t, &rest, "tube", out, &err) != SSS_OK) fail_msg("pose: %s", err.msg);
    sss_mesh_free(&rest);
}

static const double LIGHT[3] = {-0.6, 0.5, 0.6};

/* The tube bent by 70° (t = 1 s) under LIGHT with the default splatting,
 * both pictures at W_BASE²: the bent-tube, rigid-motion and flicker checks
 * each start from this pair, drawn once for the three (a splat and an
 * object-space image are deterministic: the same inputs, the same bytes). */
static float *tube70_exact, *tube70_splat;
static void tube70_images(const float **e, const float **g)
{
    assert_int_equal(W, W_BASE);
    assert_int_equal(H, W_BASE);
    if (!tube70_exact) {
        sss_mesh m;
        tube_pose(1.0, &m);
        scene s;
        scene_open(&s, &m, 100.0, NULL);
        tube70_exact = image_exact(&s, LIGHT);
        tube70_splat = image_splat(&s, LIGHT);
        scene_close(&s);
    }
    *e = tube70_exact;
    *g = tube70_splat;
}

/* Bounds of the tests below, each above what was measured (docs/deformable.md §9). */
#define TUBE_RMS_MAX 0.050
#define SPHERE_RMS_MAX 0.010

static void splatting_matches_object_space_on_bent_tube(void **state)
{
    (void)state;
    /* straight and bent the furthest (the strata check below takes the
     * middle pose) */
    const double ts[2] = {0.0, 1.0}; /* θ = 0°, 70° */
    for (int i = 0; i < 2; i++) {
        const float *e, *g;
        float *e0 = NULL, *g0 = NULL;
        scene s;
        if (i == 0) {
            sss_mesh m;
            tube_pose(ts[i], &m);
            scene_open(&s, &m, 100.0, NULL);
            e = e0 = image_exact(&s, LIGHT);
            g = g0 = image_splat(&s, LIGHT);
            scene_close(&s);
        } else {
            tube70_images(&e, &g);
        }
        double ratio;
        const double rms = rel_rms(g, e, e, &ratio);
        fprintf(stderr, "tube t = %.1f s: relative image RMS %.4f, mean ratio %.4f\n", ts[i], rms, ratio);
        assert_true(rms < TUBE_RMS_MAX);
        assert_true(fabs(ratio - 1) < 0.02);
        free(e0);
        free(g0);
    }
}

static void splatting_matches_object_space_on_sphere(void **state)
{
    (void)state;
    sss_mesh m = {0};
    sss_error err = {{0}};
    /* 2,562 vertices, radius 20 mm: R_d's reach (21 mm in red) spans half the sphere */
    assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
    assert_int_equal(sss_mesh_compute_normals_areas(&m, "sphere", &err), SSS_OK);
    /* a 256² irradiance buffer: R_d's reach spans half the sphere, so each
     * pixel's walk covers most of the buffer, and 512² cost six times as
     * long on llvmpipe for the same error (0.0027 there, 0.0026 here;
     * docs/deformable.md §9). For the same reason the picture is 48²: the
     * error is 0.0031 there (0.0027 at 96²), a third of the bound, in a
     * third of the time. */
    sss_splat_options o;
    sss_splat_options_default(&o);
    o.light_size = 256;
    W = H = 48;
    scene s;
    scene_open(&s, &m, 20.0, &o);
    float *e = image_exact(&s, LIGHT), *g = image_splat(&s, LIGHT);
    double ratio;
    const double rms = rel_rms(g, e, e, &ratio);
    fprintf(stderr, "sphere: relative image RMS %.4f, mean ratio %.4f\n", rms, ratio);
    assert_true(rms < SPHERE_RMS_MAX);
    free(e);
    free(g);
    scene_close(&s);
    W = H = W_BASE;
}

/* Each acceleration alone (Chen et al. 2012 Table 1's columns): the
 * multiresolution splatting (3 levels, every texel a sample), the adaptive
 * selection (1 level), both; against the brute-force estimate (1 level,
 * every texel of the irradiance buffer a sample; drawn at 48² to keep it
 * short: the largest change against it is 0.0056 there, 0.0043 at 64², the
 * smallest 0.0005 at both) and against the object-space image. */
#define ACCEL_CHANGE_MAX 0.005
#define ACCEL_IMAGE_MAX 0.010
static void each_acceleration_changes_error_by_bounded_amount(void **state)
{
    (void)state;
    const struct { int levels, adaptive; const char *name; } cfg[4] = {
        {1, 0, "brute force"}, {3, 0, "multiresolution"}, {1, 1, "adaptive"}, {3, 1, "both"}};
    float *img[4] = {0}, *e = NULL;
    double err[4];
    W = H = 48;
    for (int i = 0; i < 4; i++) {
        sss_mesh m;
        tube_pose(1.0, &m);
        sss_splat_options o;
        sss_splat_options_default(&o);
        o.levels = cfg[i].levels;
        o.adaptive = cfg[i].adaptive;
        scene s;
        scene_open(&s, &m, 100.0, &o);
        if (!e) e = image_exact(&s, LIGHT);
        img[i] = image_splat(&s, LIGHT);
        err[i] = rel_rms(img[i], e, e, NULL);
        const double d = i ? rel_rms(img[i], img[0], e, NULL) : 0.0;
        const sss_splat_times t = sss_splat_gpu_times(s.sp);
        fprintf(stderr, "%-16s error %.4f, change of the image against brute force %.4f; ms: buffers %.1f, levels "
                "%.1f/%.1f/%.1f, accumulation %.1f\n", cfg[i].name, err[i], d, t.buffers_ms, t.level_ms[0],
                t.level_ms[1], t.level_ms[2], t.accum_ms);
        assert_true(fabs(err[i] - err[0]) < ACCEL_CHANGE_MAX);
        assert_true(d < ACCEL_IMAGE_MAX);
        scene_close(&s);
    }
    /* the accelerations are not a no-op: each changes the picture */
    for (int i = 1; i < 4; i++) assert_true(rel_rms(img[i], img[0], e, NULL) > 1e-4);
    for (int i = 0; i < 4; i++) free(img[i]);
    free(e);
    W = H = W_BASE;
}

/* Rotates positions by R (row-major) about the origin and moves them by t;
 * normals and areas recomputed. */
static void move_mesh(sss_mesh *m, const double R[9], const double t[3])
{
    for (uint32_t v = 0; v < m->nv; v++) {
        double x[3], y[3];
        for (int k = 0; k < 3; k++) x[k] = m->pos[3 * (size_t)v + k];
        for (int k = 0; k < 3; k++) y[k] = R[3 * k] * x[0] + R[3 * k + 1] * x[1] + R[3 * k + 2] * x[2] + t[k];
        for (int k = 0; k < 3; k++) m->pos[3 * (size_t)v + k] = (float)y[k];
    }
    sss_error err = {{0}};
    assert_int_equal(sss_mesh_compute_normals_areas(m, "moved", &err), SSS_OK);
}

static void rot(const double R[9], const double a[3], double b[3])
{
    for (int k = 0; k < 3; k++) b[k] = R[3 * k] * a[0] + R[3 * k + 1] * a[1] + R[3 * k + 2] * a[2];
}

/* Object, light and view turned together about +y (the camera's up, so the
 * picture stays upright) and moved: the same picture but for sampling (the
 * irradiance buffer's texels fall elsewhere on the surface). */
#define RIGID_CHANGE_MAX 0.005
static void rigid_motion_changes_nothing_beyond_sampling(void **state)
{
    (void)state;
    /* a quarter turn: the bounding box (whose centre the camera frames)
     * turns into the moved object's own */
    const double a = 0.5 * SSS_PI;
    const double R[9] = {cos(a), 0, sin(a), 0, 1, 0, -sin(a), 0, cos(a)}, t[3] = {0.3, -0.2, 0.5};
    sss_mesh m1;
    tube_pose(1.0, &m1);
    move_mesh(&m1, R, t);
    scene s1;
    scene_open(&s1, &m1, 100.0, NULL);
    const double view0[3] = {s1.p.view[0], s1.p.view[1], s1.p.view[2]}; /* the unmoved scene's camera */
    rot(R, view0, s1.p.view);
    double L1[3];
    rot(R, LIGHT, L1);
    const float *e0, *g0;
    tube70_images(&e0, &g0);
    float *e1 = image_exact(&s1, L1), *g1 = image_splat(&s1, L1);
    const double de = rel_rms(e1, e0, e0, NULL), dg = rel_rms(g1, g0, e0, NULL), err0 = rel_rms(g0, e0, e0, NULL);
    fprintf(stderr, "rigid motion: splatting's image changes by %.4f (object space: %.4f; splatting's error %.4f)\n",
            dg, de, err0);
    assert_true(dg < RIGID_CHANGE_MAX);
    free(e1), free(g1);
    scene_close(&s1);
}

/* The light turning about +y in two 0.5° steps: the splatting's change from
 * frame to frame against the object-space path's (flicker). */
#define FLICKER_RATIO_MAX 2.0
static void light_steps_flicker_bounded(void **state)
{
    (void)state;
    sss_mesh m;
    tube_pose(1.0, &m);
    scene s;
    scene_open(&s, &m, 100.0, NULL);
    const float *e[3], *g[3];
    tube70_images(&e[0], &g[0]); /* the first step's light is LIGHT */
    for (int i = 1; i < 3; i++) {
        const double a = 0.5 * i * SSS_PI / 180.0;
        const double L[3] = {cos(a) * LIGHT[0] + sin(a) * LIGHT[2], LIGHT[1], -sin(a) * LIGHT[0] + cos(a) * LIGHT[2]};
        e[i] = image_exact(&s, L);
        g[i] = image_splat(&s, L);
    }
    double worst = 0;
    for (int i = 0; i < 2; i++) {
        const double de = rel_rms(e[i + 1], e[i], e[0], NULL), dg = rel_rms(g[i + 1], g[i], e[0], NULL);
        fprintf(stderr, "step %d: change %.3e (object space %.3e), ratio %.3f\n", i, dg, de, dg / de);
        assert_true(de > 0);
        worst = fmax(worst, dg / de);
    }
    fprintf(stderr, "flicker: largest ratio %.3f\n", worst);
    assert_true(worst <= FLICKER_RATIO_MAX);
    for (int i = 1; i < 3; i++) free((float *)e[i]), free((float *)g[i]);
    scene_close(&s);
}

/* The tube with strata of ketchup across its length in skin1 (10 mm thick
 * every 25 mm, 3 mm edges, in the rest frame: they bend with the tube),
 * at two poses: the splatting with per-sample materials against the
 * object-space path with the same model (the endpoints' product, no
 * transmittance; docs/deformable.md §10). Small pictures and a 256²
 * irradiance buffer keep it short. */
#define FIELD_RMS_MAX 0.06
static void splatting_with_a_field_matches_object_space_on_bent_tube(void **state)
{
    (void)state;
    sss_hetero h;
    memset(&h, 0, sizeof h);
    h.field.kind = SSS_FIELD_LAYERS;
    h.field.normal[2] = 1.0;
    h.field.thickness_mm = 10.0;
    h.field.scale_mm = 25.0;
    h.field.edge_mm = 3.0;
    assert_int_equal(sss_material_preset("ketchup", &h.inside, NULL), SSS_OK);
    h.xf[0] = h.xf[5] = h.xf[10] = 100.0; /* units → mm */
    sss_mesh rest = {0};
    sss_error err = {{0}};
    assert_int_equal(sss_gen_by_name("tube", 16, 0.25, &rest, &err), SSS_OK);
    float *f = malloc(rest.nv * sizeof *f);
    assert_non_null(f);
    uint32_t n_in = 0;
    for (uint32_t v = 0; v < rest.nv; v++) {
        double x[3], p[3] = {rest.pos[3 * v], rest.pos[3 * v + 1], rest.pos[3 * v + 2]};
        sss_hetero_to_rest(&h, p, x);
        f[v] = (float)sss_field_eval(&h.field, x);
        n_in += f[v] > 0.5f;
    }
    assert_true(n_in > rest.nv / 5 && n_in < rest.nv * 4 / 5);
    W = H = 64; /* 0.0329/0.0324 against the bound 0.06 (0.0333/0.0330 at 80²) */
    sss_splat_options o;
    sss_splat_options_default(&o);
    o.light_size = 256;
    /* one renderer and splatting for two poses: the second is copied into
     * the renderer's mesh (sss_renderer_update_geometry), as sss-view's
     * window does, and f stays that of the rest pose */
    const double ts[2] = {0.0, 0.5}; /* θ = 0°, 49.5° */
    scene s;
    for (int i = 0; i < 2; i++) {
        sss_mesh m;
        tube_pose(ts[i], &m);
        if (i == 0) {
            scene_open(&s, &m, 100.0, &o);
        } else {
            memcpy(s.f.mesh.pos, m.pos, 3 * (size_t)m.nv * sizeof *m.pos);
            memcpy(s.f.mesh.nrm, m.nrm, 3 * (size_t)m.nv * sizeof *m.nrm);
            memcpy(s.f.mesh.area, m.area, (size_t)m.nv * sizeof *m.area);
            sss_mesh_free(&m);
            sss_renderer_update_geometry(s.r);
        }
        /* the homogeneous splat at the first pose: what the field changes,
         * its cost, and that dropping the field gives it back */
        float *hom = i == 0 ? image_splat(&s, LIGHT) : NULL;
        const sss_splat_times th = sss_splat_gpu_times(s.sp);
        if (sss_splat_gpu_set_field(s.sp, &h.inside, f, &err) != SSS_OK) fail_msg("%s", err.msg);
        float *e = image_exact_field(&s, LIGHT, &h, rest.pos), *g = image_splat(&s, LIGHT);
        const sss_splat_times t = sss_splat_gpu_times(s.sp);
        double ratio;
        const double rms = rel_rms(g, e, e, &ratio), change = hom ? rel_rms(hom, e, e, NULL) : 0.0;
        fprintf(stderr, "strata, tube t = %.1f s: relative image RMS %.4f, mean ratio %.4f; ms: buffers %.1f, levels "
                "%.1f/%.1f/%.1f, accumulation %.1f\n", ts[i], rms, ratio, t.buffers_ms, t.level_ms[0], t.level_ms[1],
                t.level_ms[2], t.accum_ms);
        if (hom)
            fprintf(stderr, "  the homogeneous splat: %.4f from the field's object-space image; ms: buffers %.1f, "
                    "levels %.1f/%.1f/%.1f, accumulation %.1f\n", change, th.buffers_ms, th.level_ms[0],
                    th.level_ms[1], th.level_ms[2], th.accum_ms);
        assert_true(rms < FIELD_RMS_MAX);
        assert_true(fabs(ratio - 1) < 0.03);
        if (hom) {
            assert_true(change > 3 * FIELD_RMS_MAX); /* the field changes the picture far beyond the bound */
            /* back to the homogeneous material: its picture again */
            assert_int_equal(sss_splat_gpu_set_field(s.sp, NULL, NULL, &err), SSS_OK);
            float *back = image_splat(&s, LIGHT);
            assert_memory_equal(back, hom, (size_t)W * H * 3 * sizeof *back);
            free(back);
        }
        free(e), free(g), free(hom);
    }
    f[3] = 1.5f; /* refused, naming the vertex */
    assert_int_equal(sss_splat_gpu_set_field(s.sp, &h.inside, f, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "vertex 3"));
    scene_close(&s);
    W = H = W_BASE;
    free(f);
    sss_mesh_free(&rest);
}

/* The Stanford bunny at its real size (10.1 mm per unit, 10 cm), bent by
 * 40° about x, skin1, then with ketchup veins (S = 20 mm) read at the rest
 * pose: the splatting against the object-space path at 120 × 90 pixels
 * with a 256² irradiance buffer (docs/deformable.md §9, §10; the errors
 * 0.0452 and 0.0487 here, 0.0451 and 0.0486 at 160 × 120). */
#define BUNNY_RMS_MAX 0.06
static void splatting_matches_object_space_on_bunny(void **state)
{
    (void)state;
    const char *path = SSS_SOURCE_DIR "/data/stanford/bunny.ply";
    if (access(path, R_OK) != 0) fail_msg("%s is missing: run data/fetch.sh (scripts/test.sh does)", path);
    sss_mesh rest, m;
    sss_error err = {{0}};
    if (sss_import_mesh(path, &rest, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_deform d = {.kind = SSS_DEFORM_BEND, .axis = {1, 0, 0}, .angle_deg = 40.0, .period_s = 4.0};
    if (sss_deform_pose(&d, 1.0, &rest, "bunny", &m, &err) != SSS_OK) fail_msg("pose: %s", err.msg);
    sss_hetero h;
    memset(&h, 0, sizeof h);
    h.field.kind = SSS_FIELD_VEINS;
    h.field.scale_mm = 20.0;
    h.field.seed = 3;
    assert_int_equal(sss_material_preset("ketchup", &h.inside, NULL), SSS_OK);
    h.xf[0] = h.xf[5] = h.xf[10] = 10.094;
    float *f = malloc(rest.nv * sizeof *f);
    assert_non_null(f);
    for (uint32_t v = 0; v < rest.nv; v++) {
        double x[3], p[3] = {rest.pos[3 * v], rest.pos[3 * v + 1], rest.pos[3 * v + 2]};
        sss_hetero_to_rest(&h, p, x);
        f[v] = (float)sss_field_eval(&h.field, x);
    }
    sss_splat_options o;
    sss_splat_options_default(&o);
    o.light_size = 256;
    W = 120, H = 90;
    scene s;
    scene_open(&s, &m, 10.094, &o);
    const double L[3] = {0.3, 0.2, 0.93};
    float *e = image_exact(&s, L), *g = image_splat(&s, L);
    const sss_splat_times t = sss_splat_gpu_times(s.sp);
    double ratio;
    const double rms = rel_rms(g, e, e, &ratio);
    fprintf(stderr, "bunny: relative image RMS %.4f, mean ratio %.4f; ms: buffers %.1f, levels %.1f/%.1f/%.1f, "
            "accumulation %.1f\n", rms, ratio, t.buffers_ms, t.level_ms[0], t.level_ms[1], t.level_ms[2], t.accum_ms);
    assert_true(rms < BUNNY_RMS_MAX);
    assert_true(fabs(ratio - 1) < 0.03);
    if (sss_splat_gpu_set_field(s.sp, &h.inside, f, &err) != SSS_OK) fail_msg("%s", err.msg);
    float *ef = image_exact_field(&s, L, &h, rest.pos), *gf = image_splat(&s, L);
    const sss_splat_times tf = sss_splat_gpu_times(s.sp);
    const double rmsf = rel_rms(gf, ef, ef, &ratio), change = rel_rms(e, ef, ef, NULL);
    fprintf(stderr, "bunny with veins: relative image RMS %.4f, mean ratio %.4f (the field changes the object-space "
            "image by %.4f); ms: buffers %.1f, levels %.1f/%.1f/%.1f, accumulation %.1f\n", rmsf, ratio, change,
            tf.buffers_ms, tf.level_ms[0], tf.level_ms[1], tf.level_ms[2], tf.accum_ms);
    assert_true(rmsf < BUNNY_RMS_MAX);
    assert_true(fabs(ratio - 1) < 0.03);
    assert_true(change > 2 * BUNNY_RMS_MAX);
    free(e), free(g), free(ef), free(gf), free(f);
    sss_mesh_free(&rest);
    scene_close(&s);
    W = H = W_BASE;
}

static int teardown(void **state)
{
    free(tube70_exact);
    free(tube70_splat);
    return gl_teardown(state);
}

int main(void)
{
    (void)bake_preset; /* gl_fixture.h's, for the tests that bake */
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(splatting_matches_object_space_on_bent_tube),
        cmocka_unit_test(splatting_matches_object_space_on_sphere),
        cmocka_unit_test(each_acceleration_changes_error_by_bounded_amount),
        cmocka_unit_test(rigid_motion_changes_nothing_beyond_sampling),
        cmocka_unit_test(light_steps_flicker_bounded),
        cmocka_unit_test(splatting_with_a_field_matches_object_space_on_bent_tube),
        cmocka_unit_test(splatting_matches_object_space_on_bunny),
    };
    return cmocka_run_group_tests(tests, gl_setup, teardown);
}
