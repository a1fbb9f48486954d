/* Renderer tests (offscreen, EGL): the GPU evaluation matches the C decoder
 * per vertex, and whole images rendered from both paths agree, for every
 * storage form: float, lloyd8, and the compressed forms of format 1.1
 * (Hao–Varshney 2004 §4: SH-only, references + SH-coded deltas). */
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
#include "sss/render.h"
#include "sss/bake.h"
#include "sss/compress.h"
#include "sss/gpu.h"
#include "sss/decode.h"
#include "sss/import.h"

#include "gl_fixture.h"
#include "sss/dipole.h"
#include "sss/vec3.h"
#include "sss/scene.h"
#include "test_util.h"

static uint64_t rng = 12345;


/* GPU q read back vs sss_decode_all for light directions on direction
 * samples, at both poles (where every m ≠ 0 SH term vanishes) and random:
 * within 1e-4 relative (docs/viewer.md), for each storage form and channel count.
 * As before, a difference below 1e-30 counts as none (0 vs 1e-38 is no
 * error), else it is relative to the C value, so a compressed value that
 * the clamp at 0 zeroes on one side only fails. The renderer folds the
 * light into its tables as the C decoder does, so on llvmpipe the two agree
 * to the bit; a GPU that rounded y_i(ω) to float first would not pass here
 * (a blend cancelled by its delta magnifies a last-bit difference). */
static void check_gpu_vs_c_interp(const sss_bake_file *f, const char *label, sss_interp interp)
{
    sss_renderer *r;
    sss_error err = {{0}};
    assert_int_equal(sss_renderer_create(f, &r, &err), SSS_OK);
    size_t n = (size_t)f->mesh.nv * f->channels;
    float *g = malloc(n * sizeof *g), *c = malloc(n * sizeof *c), *tri = malloc(n * sizeof *tri);
    sss_view_params p;
    sss_view_params_default(&p);
    p.interp = (int)interp;
    double worst = 0, cmax = 0;
    size_t nzero = 0, nval = 0, nother = 0;
    const int compressed = f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS;
    int schemes = 0;
    for (int t = 0; t < 40; t++) {
        if ((uint32_t)t < f->dirs.n && t < 5) memcpy(p.light, &f->dirs.dir[3 * t], sizeof p.light); /* exactly on samples too */
        else if (t == 5 || t == 6) p.light[0] = 0, p.light[1] = 0, p.light[2] = t == 5 ? 1 : -1;
        else test_random_dir(&rng, p.light);
        sss_renderer_evaluate(r, &p);
        sss_renderer_read_q(r, g);
        sss_decode_all_interp(f, p.light, interp, c);
        /* the SH tables as a uniform block and as a storage buffer
         * (docs/viewer.md, "SH tables on the GPU"): the same q to the bit */
        for (int st = 0; compressed && st < 2; st++) {
            p.sh_tables = st ? SSS_SH_TABLES_STORAGE : SSS_SH_TABLES_UNIFORM;
            sss_renderer_evaluate(r, &p);
            sss_renderer_read_q(r, tri);
            assert_memory_equal(tri, g, n * sizeof *g);
            schemes += t == 0;
        }
        p.sh_tables = 0;
        /* the other interpolation gives other values between the samples:
         * the switch reaches the evaluation */
        sss_decode_all_interp(f, p.light, interp == SSS_INTERP_NEAREST4 ? SSS_INTERP_TRIANGLE : SSS_INTERP_NEAREST4,
                              tri);
        for (size_t i = 0; i < n; i++) nother += fabsf(tri[i] - g[i]) > 1e-6f * fabsf(tri[i]);
        for (size_t i = 0; i < n; i++) {
            double den = fabs(c[i]) > 1e-30 ? fabs(c[i]) : 1e-30;
            double rel = fabs((double)g[i] - c[i]) / den;
            if (fabs((double)g[i] - c[i]) < 1e-30) rel = 0;
            if (rel > worst) worst = rel;
            if (c[i] > cmax) cmax = c[i];
            nzero += c[i] == 0.0f;
            nval++;
        }
    }
    print_message("GPU vs C decoder, %s: %u vertices x %u channels, %s: worst relative difference %.3g (max q %.3g, "
                  "%.1f%% zero, %.1f%% differ from the other interpolation)\n",
                  interp == SSS_INTERP_NEAREST4 ? "4-nearest" : "triangle", f->mesh.nv, f->channels, label, worst,
                  cmax, 100.0 * (double)nzero / (double)nval, 100.0 * (double)nother / (double)nval);
    assert_true(worst <= 1e-4);
    assert_true(cmax > 0); /* the comparison saw light */
    assert_int_equal(schemes, compressed ? 2 : 0);
    if (f->quant == SSS_QUANT_SH) assert_int_equal(nother, 0); /* no direction samples: nothing to choose */
    else assert_true(nother > nval / 10);
    free(g);
    free(c);
    free(tri);
    sss_renderer_destroy(r);
}

/* Both interpolations (sss_view_params.interp): the triangle's, and the
 * paper's 4 nearest samples (Hao–Varshney 2004 §3.2, Fig. 3). */
static void check_gpu_vs_c(const sss_bake_file *f, const char *label)
{
    check_gpu_vs_c_interp(f, label, SSS_INTERP_TRIANGLE);
    check_gpu_vs_c_interp(f, label, SSS_INTERP_NEAREST4);
}

static void gpuEvaluationMatchesCDecoderPerVertex(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    for (int q = 0; q < 2; q++)
        for (int grey = 0; grey < 2; grey++) {
            sss_bake_file f;
            bake_preset(&m, "skin1", grey, 20.0, 100, (sss_quant)q, -1, &f);
            assert_int_equal(f.channels, grey ? 1u : 3u);
            check_gpu_vs_c(&f, sss_quant_name(f.quant));
            sss_file_free(&f);
        }
    sss_mesh_free(&m);
}

/* sss_compress of the float bake src with the given options. */
static void compress(const sss_bake_file *src, uint32_t order, double fraction, uint32_t kind, uint32_t wbits,
                     int ls_weights, sss_bake_file *dst)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = order;
    o.fraction = fraction;
    o.sh_kind = kind;
    o.wbits = wbits;
    o.ls_weights = ls_weights;
    sss_error err = {{0}};
    sss_result res = sss_compress(src, &o, dst, &err);
    if (res != SSS_OK) fail_msg("sss_compress: %s", err.msg);
    assert_int_equal(dst->quant, fraction > 0 ? SSS_QUANT_REFS : SSS_QUANT_SH);
}

/* The compressed forms (§4.1 SH-only; §4.2–4.3 references, blend and
 * SH-coded delta, clamped at 0): every code width (the 4-bit codes are
 * packed two per byte, the 16-bit ones two per word and sign-extended), both weight widths, barycentric and least-squares
 * weights (which leave [0, 1], so the blend can cancel against the delta),
 * a reference form without SH part, RGB and grey. */
static void gpuEvaluationMatchesCDecoderCompressed(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 4, &err), SSS_OK);
    static const struct {
        int grey;
        uint32_t order;
        double fraction;
        uint32_t kind, wbits;
        int ls;
    } cases[] = {
        {0, 4, 0.0, SSS_SHQ_LLOYD4, 16, 0},  /* SH-only, lloyd4 */
        {0, 3, 0.0, SSS_SHQ_LINEAR8, 16, 0}, /* SH-only, linear8 (the paper's) */
        {1, 5, 0.0, SSS_SHQ_LLOYD4, 16, 0},  /* SH-only, grey, odd count of nibbles per vertex */
        {0, 3, 0.05, SSS_SHQ_LLOYD8, 16, 1}, /* references, least-squares weights, lloyd8 SH */
        {0, 3, 0.03, SSS_SHQ_LINEAR8, 16, 0},/* references, the paper's defaults */
        {1, 4, 0.1, SSS_SHQ_LLOYD4, 8, 1},   /* references, grey, 8-bit weights, lloyd4 */
        {0, 0, 0.1, SSS_SHQ_LINEAR8, 8, 0},  /* references only, no SH part */
        {0, 7, 0.0, SSS_SHQ_LINEAR16, 16, 0},/* SH-only, 16-bit codes: the paper's §4.1 storage */
        {1, 5, 0.0, SSS_SHQ_LINEAR16, 16, 0},/* SH-only, grey, 16-bit, odd count of codes per vertex */
        {0, 3, 0.05, SSS_SHQ_LINEAR16, 8, 1},/* references, 16-bit SH delta */
        {0, 3, 0.01, SSS_SHQ_LLOYD4, 8, 1},  /* references, lloyd4 at order 3 (the compact preset's): pair tables
                                                as a uniform block */
    };
    int seen[2] = {0, 0}; /* the frame's SH tables as a storage buffer, as a uniform block (sss/gpu.h) */
    sss_bake_file src[2];
    bake_preset(&m, "skin1", 0, 20.0, 100, SSS_QUANT_FLOAT, -1, &src[0]);
    bake_preset(&m, "skin1", 1, 20.0, 100, SSS_QUANT_FLOAT, -1, &src[1]);
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        sss_bake_file f;
        compress(&src[cases[k].grey], cases[k].order, cases[k].fraction, cases[k].kind, cases[k].wbits, cases[k].ls,
                 &f);
        char label[160];
        sss_storage_describe(&f, label, sizeof label);
        if (cases[k].ls) strncat(label, ", least squares", sizeof label - strlen(label) - 1);
        check_gpu_vs_c(&f, label);
        if (cases[k].order) {
            sss_gpu_layout L;
            assert_int_equal(sss_gpu_layout_create(&f, 16, &L, &err), SSS_OK);
            seen[L.sh_uniform != 0]++;
            sss_gpu_layout_free(&L);
        }
        sss_file_free(&f);
    }
    /* both ways of binding the tables ran against the C decoder */
    assert_true(seen[0] > 0 && seen[1] > 0);
    sss_file_free(&src[0]);
    sss_file_free(&src[1]);
    sss_mesh_free(&m);
}

static double image_rms(const float *a, const float *b, size_t n, double *mean)
{
    double s = 0, m = 0;
    for (size_t i = 0; i < n; i++) {
        double d = (double)a[i] - b[i];
        s += d * d;
        m += a[i];
    }
    *mean = m / n;
    return sqrt(s / n);
}

/* Offscreen image on the GPU path vs the image whose per-vertex q comes from
 * the C decoder: RMS ≤ 1e-3 on [0, 1] (docs/viewer.md), from several views and
 * lights, lit from behind included. */
static void check_images(const sss_bake_file *f, const char *name)
{
    sss_renderer *r;
    sss_error err = {{0}};
    assert_int_equal(sss_renderer_create(f, &r, &err), SSS_OK);
    const int W = 256, H = 192;
    const double lights[3][3] = {{0.3, 0.5, 1}, {0, 0.2, -1}, {0.2, 0.8, 0.5}};
    const double views[3][3] = {{0, 0, 1}, {0.5, 0.3, 1}, {1, 0, 0}};
    for (int k = 0; k < 3; k++) {
        sss_view_params p;
        sss_view_params_default(&p);
        memcpy(p.light, lights[k], sizeof p.light);
        memcpy(p.view, views[k], sizeof p.view);
        p.exposure = k == 1 ? 20.0 : 2.0; /* lit from behind: only what scatters through */
        float *gpu, *cpu;
        p.path = SSS_EVAL_GPU;
        assert_int_equal(sss_renderer_render_image(r, &p, W, H, &gpu, NULL, &err), SSS_OK);
        p.path = SSS_EVAL_CPU;
        assert_int_equal(sss_renderer_render_image(r, &p, W, H, &cpu, NULL, &err), SSS_OK);
        double mean, rms = image_rms(gpu, cpu, (size_t)W * H * 3, &mean);
        print_message("%s view %d: image mean %.4f, RMS(GPU - C decoder) %.3g\n", name, k, mean, rms);
        assert_true(mean > 0.002); /* something was drawn */
        assert_true(rms <= 1e-3);
        free(gpu);
        free(cpu);
    }
    sss_renderer_destroy(r);
}

/* The normalised exit (sss_view_params.exit_normalised) divides the
 * subsurface term by c(η), pixel for pixel in the HDR image; the specular
 * term stays as it was. */
static void normalisedExitDividesSubsurfaceTermByC(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 3, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "marble", 0, 30.0, 50, SSS_QUANT_FLOAT, -1, &f);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
    const int W = 64, H = 48;
    const double c = sss_exit_norm(f.material.eta);
    assert_true(c > 0.93 && c < 0.95);
    for (int spec = 0; spec < 2; spec++) {
        sss_view_params p;
        sss_view_params_default(&p);
        p.specular = spec;
        float *rgb, *a, *b;
        assert_int_equal(sss_renderer_render_image(r, &p, W, H, &rgb, &a, &err), SSS_OK);
        free(rgb);
        p.exit_normalised = 1;
        assert_int_equal(sss_renderer_render_image(r, &p, W, H, &rgb, &b, &err), SSS_OK);
        free(rgb);
        size_t lit = 0;
        double sa = 0, sb = 0;
        for (size_t i = 0; i < (size_t)W * H * 3; i++) {
            if (a[i] > 0) lit++;
            sa += a[i], sb += b[i];
            if (!spec) assert_true(fabs(b[i] - a[i] / c) <= 1e-5 * (1.0 + a[i]));
        }
        assert_true(lit > 100);
        if (spec) assert_true(sb > sa && sb < sa / c); /* the specular part is not divided */
        free(a);
        free(b);
    }
    sss_renderer_destroy(r);
    sss_file_free(&f);
    sss_mesh_free(&m);
}

/* The HDR image of the surface terms alone (no scatter) of r's mesh. */
static float *surface_image(sss_renderer *r, const double light[3], const double view[3], int specular,
                            double diffuse, int shadow, int W, int H)
{
    sss_view_params p;
    sss_view_params_default(&p);
    memcpy(p.light, light, sizeof p.light);
    memcpy(p.view, view, sizeof p.view);
    p.scatter = 0;
    p.specular = specular;
    p.diffuse = diffuse;
    p.surface_shadow = shadow;
    float *rgb, *hdr;
    sss_error err = {{0}};
    assert_int_equal(sss_renderer_render_image(r, &p, W, H, &rgb, &hdr, &err), SSS_OK);
    free(rgb);
    return hdr;
}

/* Direct surface light with shadows (Hao–Varshney 2004 §3.2; docs/viewer.md,
 * "Direct surface light"). A torus lit from just above its plane: the near
 * side of the tube blocks the light from the far side's inner wall, seen
 * through the hole. With the shadow, every pixel of the surface terms is
 * either the unshadowed value, unchanged, or 0 (no direct term at all), and
 * a good part of the inner wall is 0; the same for the specular lobe. On a
 * sphere nothing occludes: the shadowed image is the unshadowed one but for
 * a few pixels on the terminator, where the map's test is least sure
 * (shadow.c: the band within a texel of a shadow's outline at grazing
 * light); the Fresnel-weighted Lambert term is not small there, since F_r
 * grows towards grazing. */
static void surfaceTermsAreZeroWhereShadowedAndUnchangedElsewhere(void **state)
{
    (void)state;
    sss_error err = {{0}};
    const int W = 192, H = 144;
    const size_t n = (size_t)W * H * 3;
    for (int shape = 0; shape < 2; shape++) {
        sss_mesh m;
        if (shape == 0) assert_int_equal(sss_gen_torus(&m, 1.0, 0.4, 96, 48, &err), SSS_OK);
        else assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
        sss_bake_file f;
        bake_preset(&m, "marble", 0, 30.0, 20, SSS_QUANT_FLOAT, -1, &f);
        sss_renderer *r;
        assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
        const double light[3] = {1, 0, 0.25}, view[3] = {0.7, 0.2, 1};
        for (int lobe = 0; lobe < 2; lobe++) { /* Lambert alone, then specular alone */
            float *off = surface_image(r, light, view, lobe, lobe ? 0.0 : 1.0, 0, W, H);
            float *on = surface_image(r, light, view, lobe, lobe ? 0.0 : 1.0, 1, W, H);
            size_t lit = 0, zeroed = 0, other = 0, changed = 0;
            double max = 0;
            for (size_t i = 0; i < n; i++) if (off[i] > max) max = off[i];
            for (size_t i = 0; i < n; i++) {
                if (!(off[i] > 1e-3 * max)) continue;
                lit++;
                if (on[i] == off[i]) continue;
                changed++;
                if (on[i] == 0.0f) zeroed++;
                else other++;
            }
            print_message("%s, %s: %zu lit values, %zu zeroed by the shadow, %zu otherwise changed\n",
                          shape ? "sphere" : "torus", lobe ? "specular" : "Lambert", lit, zeroed, other);
            assert_true(lit > 1000);
            assert_int_equal(other, 0); /* the shadow takes the whole term or nothing */
            if (shape == 0 && lobe == 0) assert_true(zeroed > lit / 50); /* the inner wall */
            if (shape == 1) {
                assert_true(changed <= lit / 500); /* nothing occludes a sphere */
            }
            free(off);
            free(on);
        }
        sss_renderer_destroy(r);
        sss_file_free(&f);
        sss_mesh_free(&m);
    }
}

/* The energy split of the surface terms (docs/viewer.md): rho_d moves a
 * share of the Fresnel-reflected light from the specular lobe into the
 * Lambert one, so the picture with rho_d = 0 is the specular lobe's alone,
 * and with any rho_d it is the blend (1 − rho_d)·specular + rho_d·Lambert of
 * the two pure pictures. */
static void diffuseAlbedoSplitsTheReflectedLight(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh m;
    assert_int_equal(sss_gen_sphere(&m, 1.0, 3, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "marble", 0, 30.0, 20, SSS_QUANT_FLOAT, -1, &f);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
    const int W = 96, H = 72;
    const double light[3] = {0.3, 0.5, 1}, view[3] = {0, 0, 1};
    float *spec = surface_image(r, light, view, 1, 0.0, 1, W, H);
    float *lamb = surface_image(r, light, view, 0, 1.0, 1, W, H);
    float *mix = surface_image(r, light, view, 1, 0.25, 1, W, H);
    double sl = 0;
    for (size_t i = 0; i < (size_t)W * H * 3; i++) {
        sl += lamb[i];
        assert_true(fabs(mix[i] - (0.75 * spec[i] + 0.25 * lamb[i])) <= 1e-5 * (1.0 + spec[i] + lamb[i]));
    }
    assert_true(sl > 10.0); /* the Lambert lobe drew something */
    free(spec);
    free(lamb);
    free(mix);
    sss_renderer_destroy(r);
    sss_file_free(&f);
    sss_mesh_free(&m);
}

static void offscreenSphereMatchesCDecoderImage(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "marble", 0, 30.0, 200, SSS_QUANT_LLOYD8, -1, &f);
    check_images(&f, "sphere");
    sss_file_free(&f);
    sss_mesh_free(&m);
}

/* The reference form on the GPU path vs the C decoder, as an image. */
static void offscreenCompressedSphereMatchesCDecoderImage(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&m, 1.0, 4, &err), SSS_OK);
    sss_bake_file src, f;
    bake_preset(&m, "marble", 0, 30.0, 200, SSS_QUANT_FLOAT, -1, &src);
    compress(&src, 3, 0.05, SSS_SHQ_LINEAR8, 16, 0, &f);
    check_images(&f, "sphere, refs 5% + SH 3");
    sss_file_free(&f);
    compress(&src, 4, 0.0, SSS_SHQ_LLOYD4, 16, 0, &f);
    check_images(&f, "sphere, SH 4 lloyd4");
    sss_file_free(&f);
    sss_file_free(&src);
    sss_mesh_free(&m);
}

static void offscreenBunnyMatchesCDecoderImage(void **state)
{
    (void)state;
    const char *path = SSS_SOURCE_DIR "/data/stanford/bunny.ply";
    if (access(path, R_OK) != 0) fail_msg("%s is missing: run data/fetch.sh (scripts/test.sh does)", path);
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_import_mesh(path, &m, NULL, &err), SSS_OK);
    sss_bake_file f;
    bake_preset(&m, "marble", 0, 10.0, 200, SSS_QUANT_FLOAT, -1, &f);
    check_images(&f, "bunny");
    sss_file_free(&f);
    sss_mesh_free(&m);
}

/* A scene camera (docs/scenes.md): the renderer's eye lands on its
 * position, looks at its target, and keeps its up in the picture's up
 * (here +z, a z-up scene, and a target off the object's centre). */
static void sceneCameraPutsTheEyeAtItsPositionLookingAtItsTarget(void **state)
{
    (void)state;
    sss_bake_file f;
    memset(&f, 0, sizeof f);
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&f.mesh, 1.0, 2, &err), SSS_OK);
    for (uint32_t v = 0; v < f.mesh.nv; v++) f.mesh.pos[3 * v] += 0.4f; /* the centre off the origin */
    sss_scene sc;
    memset(&sc, 0, sizeof sc);
    sc.camera = (sss_scene_camera){.present = 1, .position = {3, -4, 1.5}, .target = {0.1, 0.2, -0.3},
                                   .up = {0, 0, 1}, .fov_deg = 30};
    sss_view_params p;
    sss_view_params_default(&p);
    sss_scene_camera_params(&sc, &f, &p);
    double c[3], eye[3], right[3], up[3], fwd[3];
    const double rad = sss_mesh_bounding_sphere(&f.mesh, c);
    sss_view_frame(&p, c, rad, eye, right, up, fwd);
    double d[3];
    for (int k = 0; k < 3; k++) {
        assert_true(fabs(eye[k] - sc.camera.position[k]) < 1e-9);
        d[k] = sc.camera.target[k] - sc.camera.position[k];
    }
    sss_normalize3(d);
    assert_true(sss_dot3(d, fwd) > 1 - 1e-12);
    /* the target on the axis of view: no part of it across the picture */
    double t[3];
    for (int k = 0; k < 3; k++) t[k] = sc.camera.target[k] - eye[k];
    assert_true(fabs(sss_dot3(t, right)) < 1e-9 && fabs(sss_dot3(t, up)) < 1e-9);
    /* +z up: the right axis horizontal, up leaning to +z */
    assert_true(fabs(right[2]) < 1e-12 && up[2] > 0.9);
    assert_true(fabs(p.fov_deg - 30) < 1e-12);
    /* no camera up given (0,0,0): +y, as before */
    sss_view_params q;
    sss_view_params_default(&q);
    sss_view_frame(&q, c, rad, eye, right, up, fwd);
    assert_true(fabs(right[1]) < 1e-12 && up[1] > 0.99);
    sss_mesh_free(&f.mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpuEvaluationMatchesCDecoderPerVertex),
        cmocka_unit_test(gpuEvaluationMatchesCDecoderCompressed),
        cmocka_unit_test(normalisedExitDividesSubsurfaceTermByC),
        cmocka_unit_test(surfaceTermsAreZeroWhereShadowedAndUnchangedElsewhere),
        cmocka_unit_test(diffuseAlbedoSplitsTheReflectedLight),
        cmocka_unit_test(offscreenSphereMatchesCDecoderImage),
        cmocka_unit_test(offscreenCompressedSphereMatchesCDecoderImage),
        cmocka_unit_test(offscreenBunnyMatchesCDecoderImage),
        cmocka_unit_test(sceneCameraPutsTheEyeAtItsPositionLookingAtItsTarget),
    };
    return cmocka_run_group_tests(tests, gl_setup, gl_teardown);
}
