/* fuzz_view.c: libFuzzer harness for the viewer's file upload path,
 * offscreen (EGL; Mesa llvmpipe in CI; docs/robustness.md item 5). The
 * input is a .sss file image, tried as given and with its checksums
 * repaired (fuzz_sss_crc.h). An accepted file goes where sss-view takes it:
 * sss_renderer_create uploads its geometry, its rows in their storage form
 * and, with OWNT, the near terms' weights and the BVH; then a small image
 * is drawn on the GPU path and on the CPU path, an uploaded q (the C
 * decoder's) is drawn, and a scene bake's effects are summed on the GPU and
 * the CPU for a scene made of one light per effect the file carries. Every
 * picture must hold finite values only: an accepted file decodes to finite
 * q >= 0 (sss/format.h, SSS_VALUE_MAX) and the exposure is 1. The GL
 * context is made once. The work per input is bounded by the 1 MiB input
 * (at most ~40,000 vertices) and a 16 x 12 image. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_sss_crc.h"
#include "sss/decode.h"
#include "sss/format.h"
#include "sss/render.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define IW 16
#define IH 12

static sss_offscreen *ctx;

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    sss_error err = {{0}};
    if (sss_offscreen_create(&ctx, &err) != SSS_OK) {
        fprintf(stderr, "fuzz_view: no offscreen GL context: %s\n", err.msg);
        abort();
    }
    return 0;
}

static void check_image(float *rgb, float *hdr)
{
    for (size_t i = 0; i < (size_t)IW * IH * 3; i++)
        if (!isfinite(rgb[i]) || (hdr && !isfinite(hdr[i]))) abort();
    free(rgb);
    free(hdr);
}

/* One light per effect f carries, as a scene of the file's own (the viewer
 * refuses a light the file has no data for). */
static void scene_of(const sss_bake_file *f, sss_scene *sc, sss_scene_light *lights)
{
    memset(sc, 0, sizeof *sc);
    snprintf(sc->path, sizeof sc->path, "fuzz.json");
    sc->lights = lights;
    const uint32_t m = f->fx.mask ? f->fx.mask : SSS_FX_DIR_SET;
    sss_scene_light base;
    memset(&base, 0, sizeof base);
    base.intensity = 1.0;
    base.colour[0] = base.colour[1] = base.colour[2] = 1.0;
    for (uint32_t l = 0; (m & SSS_FX_DIR_EXACT) && l < f->fx.nexact && l < 4; l++) {
        sss_scene_light *L = &lights[sc->nlights++];
        *L = base;
        L->kind = SSS_LIGHT_DIRECTIONAL;
        memcpy(L->direction, &f->fx.exact_dir[3 * (size_t)l], sizeof L->direction);
    }
    if (m & SSS_FX_DIR_SET) {
        sss_scene_light *L = &lights[sc->nlights++];
        *L = base;
        L->kind = SSS_LIGHT_DIRECTIONAL;
        L->moving = 1;
        L->direction[0] = 0.3, L->direction[1] = -0.4, L->direction[2] = 0.866;
    }
    if (m & SSS_FX_POINT_SHELLS) {
        sss_scene_light *L = &lights[sc->nlights++];
        *L = base;
        L->kind = SSS_LIGHT_POINT;
        L->moving = 1;
        for (int k = 0; k < 3; k++) L->position[k] = f->fx.shell_centre[k] + (k == 2 ? 1.5 * f->fx.shell_radius[0] : 0);
    }
    if (m & SSS_FX_ENV_SH) {
        sss_scene_light *L = &lights[sc->nlights++];
        *L = base;
        L->kind = SSS_LIGHT_ENVIRONMENT;
    }
}

static void view_one(const uint8_t *data, size_t size)
{
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_decode(data, size, "fuzz.sss", &f, &err) != SSS_OK) return;
    sss_renderer *r = NULL;
    if (sss_renderer_create(&f, &r, &err) != SSS_OK) {
        /* a file the GL cannot hold is refused in one line, not drawn */
        if (!err.msg[0] || strchr(err.msg, '\n')) abort();
        sss_file_free(&f);
        return;
    }
    sss_view_params p;
    sss_view_params_default(&p);
    p.light[0] = 0.2, p.light[1] = 0.5, p.light[2] = 0.8;
    float *rgb, *hdr;
    for (int path = 0; path < 2; path++) {
        p.path = path ? SSS_EVAL_CPU : SSS_EVAL_GPU;
        if (sss_renderer_render_image(r, &p, IW, IH, &rgb, &hdr, &err) != SSS_OK) abort();
        check_image(rgb, hdr);
    }
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *q = malloc(n * sizeof *q + 1);
    if (q && f.dirs.n) {
        sss_decode_all(&f, p.light, q);
        if (sss_renderer_render_q_image(r, &p, q, IW, IH, &rgb, &hdr, &err) != SSS_OK) abort();
        check_image(rgb, hdr);
    }
    free(q);
    sss_scene_light lights[8];
    sss_scene sc;
    scene_of(&f, &sc, lights);
    sss_scene_eval *ev = NULL;
    if (sc.nlights && sss_scene_eval_create(&f, &sc, &ev, &err) == SSS_OK) {
        sss_fx_gpu *g = NULL;
        if (sss_fx_gpu_create(&f, ev, r, &g, &err) != SSS_OK) g = NULL; /* then the CPU sum alone */
        for (int path = 0; path < 2; path++) {
            if (path == 0 && !g) continue;
            if (sss_scene_render_image(r, ev, path ? NULL : g, &p, 0.4, IW, IH, &rgb, &hdr, &err) != SSS_OK) abort();
            check_image(rgb, hdr);
        }
        sss_fx_gpu_destroy(g);
        sss_scene_eval_destroy(ev);
    }
    sss_renderer_destroy(r);
    sss_file_free(&f);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    view_one(data, size);
    uint8_t *copy = malloc(size + 1);
    if (!copy) return 0;
    if (size) memcpy(copy, data, size);
    fuzz_repair_crcs(copy, size);
    view_one(copy, size);
    free(copy);
    return 0;
}
