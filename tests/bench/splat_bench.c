/* splat_bench: the GPU splatting's accuracy against its time
 * (docs/deformable.md §9): one pose of a mesh bent about an axis, the
 * object-space reference (the exact per-frame path with hat weights,
 * sss/perframe.h) drawn once, then the splatting (sss/splat_gpu.h) over its
 * levels, with and without the adaptive selection, and over α and z0;
 * for each the image RMS against the reference over the covered pixels
 * (relative to the reference's RMS there) and the stage times. Subsurface
 * term alone, skin1, light (0.3, 0.2, 0.93), seen from (0.3, 1, 0.3) (the
 * tube from its side: end-on, its cap's fan of long triangles makes the
 * reference's interpolation across them the largest error).
 *
 *   splat_bench MESH|tube MM_PER_UNIT AXIS(x|y|z) ANGLE_DEG WIDTH HEIGHT [LX,LY,LZ] [--frames N]
 *
 * MESH is imported (sss/import.h); "tube" is sss-genmesh tube 24 … 0.25.
 *
 * --frames N: instead, the stage times of docs/deformable.md §9's table
 * ("Measurements": 3 levels, adaptive, α = 15, z0 = 0.03, seen from
 * sss-view's default camera, as `sss-view --scene --splat` draws it) for N
 * frames of the same pose, each frame's line and then the median of each
 * stage over the frames: one frame is at the mercy of the shared machine's
 * load, the median of several less so. No reference is drawn. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/deform.h"
#include "sss/import.h"
#include "sss/perframe.h"
#include "sss/splat_gpu.h"

static double rel_rms(const float *a, const float *b, size_t n)
{
    double d2 = 0, r2 = 0;
    for (size_t i = 0; i < n; i++) {
        if (a[i] <= 0 && b[i] <= 0) continue;
        d2 += (double)(a[i] - b[i]) * (a[i] - b[i]);
        r2 += (double)b[i] * b[i];
    }
    return r2 > 0 ? sqrt(d2 / r2) : INFINITY;
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The median of n values (sorted in place; the mean of the middle two
 * for even n). */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, by_value);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* --frames: N frames of the default splatting, their stage times and the
 * medians (the "Measurements" table of docs/deformable.md §9). */
static int frames(sss_renderer *rd, const sss_view_params *p, const double (*L)[3], const double (*wl)[3], int w,
                  int h, int n)
{
    enum { STAGES = 6 }; /* buffers, levels 0, 1, 2, accumulation, frame */
    double col[STAGES][64]; /* n ≤ 64 (main) */
    sss_splat_options o;
    sss_splat_options_default(&o);
    sss_splat_gpu *sp = NULL;
    sss_error err = {{0}};
    if (sss_splat_gpu_create(rd, &o, &sp, &err) != SSS_OK) {
        fprintf(stderr, "splat_bench: %s\n", err.msg);
        return 1;
    }
    printf("| frame | buffers ms | level 0 / 1 / 2 ms | accumulation ms | frame ms |\n|---|---|---|---|---|\n");
    for (int i = 0; i < n; i++) {
        float *rgb = NULL, *img = NULL;
        if (sss_splat_gpu_render_image(sp, p, L, wl, 1, w, h, &rgb, &img, &err) != SSS_OK) {
            fprintf(stderr, "splat_bench: frame %d: %s\n", i, err.msg);
            sss_splat_gpu_destroy(sp);
            return 1;
        }
        free(rgb);
        free(img);
        const sss_splat_times t = sss_splat_gpu_times(sp);
        const double s[STAGES] = {t.buffers_ms, t.level_ms[0], t.level_ms[1], t.level_ms[2], t.accum_ms,
                                  t.buffers_ms + t.level_ms[0] + t.level_ms[1] + t.level_ms[2] + t.accum_ms};
        for (int k = 0; k < STAGES; k++) col[k][i] = s[k];
        printf("| %d | %.0f | %.0f / %.0f / %.0f | %.0f | %.0f |\n", i + 1, s[0], s[1], s[2], s[3], s[4], s[5]);
        fflush(stdout);
    }
    double m[STAGES];
    for (int k = 0; k < STAGES; k++) m[k] = median(col[k], n);
    printf("| median of %d | %.0f | %.0f / %.0f / %.0f | %.0f | %.0f |\n", n, m[0], m[1], m[2], m[3], m[4], m[5]);
    sss_splat_gpu_destroy(sp);
    return 0;
}

int main(int argc, char **argv)
{
    int nframes = 0;
    if (argc >= 9 && strcmp(argv[argc - 2], "--frames") == 0) {
        nframes = atoi(argv[argc - 1]);
        argc -= 2;
        if (nframes < 1 || nframes > 64) {
            fprintf(stderr, "splat_bench: --frames %s: expected 1 to 64 frames\n", argv[argc + 1]);
            return 2;
        }
    }
    if (argc != 7 && argc != 8) {
        fprintf(stderr, "usage: splat_bench MESH|tube MM_PER_UNIT x|y|z ANGLE_DEG WIDTH HEIGHT [LX,LY,LZ] [--frames N]\n");
        return 2;
    }
    const double mm = atof(argv[2]), angle = atof(argv[4]);
    const int w = atoi(argv[5]), h = atoi(argv[6]);
    sss_error err = {{0}};
    sss_mesh rest = {0}, m = {0};
    sss_result r = strcmp(argv[1], "tube") == 0 ? sss_gen_by_name("tube", 24, 0.25, &rest, &err)
                                                 : sss_import_mesh(argv[1], &rest, NULL, &err);
    sss_deform d = {.kind = SSS_DEFORM_BEND,
                    .axis = {argv[3][0] == 'x', argv[3][0] == 'y', argv[3][0] == 'z'},
                    .angle_deg = angle,
                    .period_s = 4.0};
    if (r == SSS_OK) r = sss_deform_pose(&d, 1.0, &rest, argv[1], &m, &err);
    if (r != SSS_OK || !(mm > 0) || w < 1 || h < 1) {
        fprintf(stderr, "splat_bench: %s\n", r != SSS_OK ? err.msg : "bad size or mm per unit");
        return 1;
    }
    sss_mesh_free(&rest);
    sss_bake_file f = {0};
    sss_material_preset("skin1", &f.material, NULL);
    f.mesh = m;
    f.mm_per_unit = mm;
    f.channels = 3;
    f.quant = SSS_QUANT_FLOAT;
    sss_offscreen *ctx = NULL;
    sss_renderer *rd = NULL;
    if (sss_offscreen_create(&ctx, &err) != SSS_OK || sss_renderer_create(&f, &rd, &err) != SSS_OK) {
        fprintf(stderr, "splat_bench: %s\n", err.msg);
        return 1;
    }
    sss_view_params p;
    sss_view_params_default(&p);
    p.specular = 0;
    p.view[0] = 0.3, p.view[1] = 1.0, p.view[2] = 0.3;
    p.exposure = 1.0 / sss_material_slab_q(&f.material, 3);
    double L[1][3] = {{0.3, 0.2, 0.93}};
    const double wl[1][3] = {{1, 1, 1}};
    if (argc == 8 && sscanf(argv[7], "%lf,%lf,%lf", &L[0][0], &L[0][1], &L[0][2]) != 3) {
        fprintf(stderr, "splat_bench: light '%s' is not LX,LY,LZ\n", argv[7]);
        return 2;
    }
    memcpy(p.light, L[0], sizeof p.light);
    if (nframes) { /* sss-view's default camera, as the stage table */
        sss_view_params dv;
        sss_view_params_default(&dv);
        memcpy(p.view, dv.view, sizeof p.view);
        const int rc = frames(rd, &p, (const double(*)[3])L, wl, w, h, nframes);
        sss_renderer_destroy(rd);
        sss_offscreen_destroy(ctx);
        sss_mesh_free(&f.mesh);
        return rc;
    }
    float *q = malloc((size_t)m.nv * 3 * sizeof *q), *rgb = NULL, *ref = NULL;
    sss_perframe_options po = {.weights = SSS_WEIGHTS_HAT};
    if (!q || sss_perframe_q(&f.mesh, &f.material, 3, mm, L[0], &po, q, NULL, &err) != SSS_OK ||
        sss_renderer_render_q_image(rd, &p, q, w, h, &rgb, &ref, &err) != SSS_OK) {
        fprintf(stderr, "splat_bench: %s\n", err.msg);
        return 1;
    }
    free(q);
    free(rgb);
    printf("| levels | selection | alpha | z0 | image RMS | buffers ms | level 0 / 1 / 2 ms | accumulation ms | total ms |\n");
    printf("|---|---|---|---|---|---|---|---|---|\n");
    const struct { int levels, adaptive; double alpha, z0; } cfg[] = {
        {1, 0, 15, 0.03}, {2, 0, 15, 0.03}, {3, 0, 15, 0.03}, {1, 1, 15, 0.03}, {2, 1, 15, 0.03},
        {3, 1, 15, 0.03}, {3, 1, 5, 0.03},  {3, 1, 45, 0.03}, {3, 1, 15, 0.01}, {3, 1, 15, 0.1}};
    for (size_t i = 0; i < sizeof cfg / sizeof cfg[0]; i++) {
        sss_splat_options o;
        sss_splat_options_default(&o);
        o.levels = cfg[i].levels;
        o.adaptive = cfg[i].adaptive;
        o.alpha = cfg[i].alpha;
        o.z0 = cfg[i].z0;
        sss_splat_gpu *sp = NULL;
        float *img = NULL;
        if (sss_splat_gpu_create(rd, &o, &sp, &err) != SSS_OK ||
            sss_splat_gpu_render_image(sp, &p, (const double(*)[3])L, wl, 1, w, h, &rgb, &img, &err) != SSS_OK) {
            fprintf(stderr, "splat_bench: %s\n", err.msg);
            return 1;
        }
        const sss_splat_times t = sss_splat_gpu_times(sp);
        printf("| %d | %s | %g | %g | %.4f | %.0f | %.0f / %.0f / %.0f | %.0f | %.0f |\n", cfg[i].levels,
               cfg[i].adaptive ? "adaptive" : "every texel", cfg[i].alpha, cfg[i].z0,
               rel_rms(img, ref, (size_t)w * h * 3), t.buffers_ms, t.level_ms[0], t.level_ms[1], t.level_ms[2],
               t.accum_ms, t.buffers_ms + t.level_ms[0] + t.level_ms[1] + t.level_ms[2] + t.accum_ms);
        fflush(stdout);
        free(rgb);
        free(img);
        sss_splat_gpu_destroy(sp);
    }
    free(ref);
    sss_renderer_destroy(rd);
    sss_offscreen_destroy(ctx);
    sss_mesh_free(&f.mesh);
    return 0;
}
