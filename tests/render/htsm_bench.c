/* htsm_bench: the run-time path's frame time and accuracy (docs/heterogeneous.md
 * §9.4), a measurement, not a test.
 *   htsm_bench SCENE.json BAKED.exr WIDTH HEIGHT EXPOSURE [FRAMES [R0_MM]]
 * SCENE.json: one editable object with a field, one directional light (as
 * data/scenes/editable_box.json); BAKED.exr: the same scene without
 * "editable", baked and drawn by sss-view at the same size and exposure
 * with --no-specular --single off. For n = 1, 5, 9, 13 samples and 2 … 32
 * steps: the median wall time of FRAMES (default 7) frames of the pass
 * (light-space map, its mips and the per-pixel estimate, glFinish before
 * and after; the first frame, which compiles, is not counted), and the
 * image's difference from the baked one over the pixels the object covers:
 * mean |run-time − baked| / mean baked, and the same against the run-time
 * path's own n = 13, 64 steps. Prints a markdown table. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/htsm_gpu.h"
#include "sss/import.h"
#include "sss/probe.h"
#include "sss/scene.h"

static int cmp(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* mean |a − b| / mean b over the pixels where b > 0 */
static double image_error(const float *a, const float *b, size_t n)
{
    double d = 0, s = 0;
    for (size_t i = 0; i < n; i++) {
        if (!(b[3 * i] + b[3 * i + 1] + b[3 * i + 2] > 0.0f)) continue;
        for (int c = 0; c < 3; c++) d += fabs(a[3 * i + c] - b[3 * i + c]), s += b[3 * i + c];
    }
    return s > 0 ? d / s : NAN;
}

static void die(const char *what, const sss_error *err)
{
    fprintf(stderr, "htsm_bench: %s: %s\n", what, err->msg);
    exit(1);
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: htsm_bench SCENE.json BAKED.exr WIDTH HEIGHT EXPOSURE [FRAMES [R0_MM]]\n");
        return 2;
    }
    const int W = atoi(argv[3]), H = atoi(argv[4]), frames = argc > 6 ? atoi(argv[6]) : 7;
    const double r0 = argc > 7 ? atof(argv[7]) : 0.0; /* 0: the viewer's default */
    sss_error err = {{0}};
    sss_scene sc;
    if (sss_scene_load(argv[1], &sc, &err) != SSS_OK) die(argv[1], &err);
    const sss_scene_object *o = &sc.objects[0];
    sss_mesh rest = {0};
    sss_bake_file f;
    memset(&f, 0, sizeof f);
    if (sss_import_mesh_at(o->mesh, 0.0, &rest, NULL, &err) != SSS_OK) die(o->mesh, &err);
    if (sss_scene_object_posed(o, &rest, 0.0, &f.mesh, &err) != SSS_OK) die("pose", &err);
    f.material = o->material;
    f.mm_per_unit = sss_scene_object_mm_per_world_unit(o);
    f.channels = 3;
    f.quant = SSS_QUANT_FLOAT;
    sss_probe baked;
    if (sss_probe_read(argv[2], &baked, &err) != SSS_OK) die(argv[2], &err);
    if ((int)baked.w != W || (int)baked.h != H) {
        fprintf(stderr, "htsm_bench: %s is %ux%u, not %dx%d\n", argv[2], baked.w, baked.h, W, H);
        return 1;
    }
    sss_offscreen *ctx;
    sss_renderer *r;
    sss_htsm_gpu *g;
    if (sss_offscreen_create(&ctx, &err) != SSS_OK) die("context", &err);
    if (sss_renderer_create(&f, &r, &err) != SSS_OK) die("renderer", &err);
    if (sss_htsm_gpu_create(r, &o->hetero, 0, 0, &g, &err) != SSS_OK) die("htsm", &err);
    sss_view_params p;
    sss_view_params_default(&p);
    p.specular = 0;
    p.single = -1;
    p.near_terms = 0;
    p.exposure = atof(argv[5]);
    for (uint32_t l = 0; l < sc.nlights; l++)
        if (sc.lights[l].kind == SSS_LIGHT_DIRECTIONAL) {
            for (int k = 0; k < 3; k++)
                p.light[k] = sc.lights[l].direction[k], p.light_rgb[k] = sc.lights[l].intensity * sc.lights[l].colour[k];
            break;
        }
    sss_scene_camera_params(&sc, &f, &p);
    const char *tmp = "htsm_bench.tmp.exr";
    float *ref = NULL;
    const uint32_t ns[4] = {1, 5, 9, 13}, steps[5] = {2, 4, 8, 16, 32};
    printf("%s, %dx%d, light-space map 256², field 64³\n\n", sss_gl_renderer_name(), W, H);
    printf("| n | steps | frame ms (median of %d) | vs baked | vs n = 13, 64 steps |\n|---:|---:|---:|---:|---:|\n",
           frames);
    for (int pass = 0; pass < 2; pass++)
        for (int a = 0; a < (pass ? 4 : 1); a++)
            for (int b = 0; b < (pass ? 5 : 1); b++) {
                sss_htsm_view v;
                sss_htsm_view_default(&v, &f, &o->hetero);
                v.n = pass ? ns[a] : 13;
                v.steps = pass ? steps[b] : 64;
                v.r0_mm = r0;
                double ms[64];
                const int nf = frames < 64 ? frames : 64;
                sss_htsm_gpu_frame(g, &v, &p, W, H, NULL, &err); /* compiles */
                for (int k = 0; k < nf; k++)
                    if (sss_htsm_gpu_frame(g, &v, &p, W, H, &ms[k], &err) != SSS_OK) die("frame", &err);
                qsort(ms, (size_t)nf, sizeof *ms, cmp);
                float *rgb = NULL, *hdr = NULL;
                if (sss_htsm_gpu_render_image(g, &v, &p, W, H, &rgb, &hdr, &err) != SSS_OK) die("image", &err);
                /* through the EXR writer and the reader, as sss-view's image went */
                if (sss_write_exr(tmp, hdr, W, H, &err) != SSS_OK) die(tmp, &err);
                sss_probe img;
                if (sss_probe_read(tmp, &img, &err) != SSS_OK) die(tmp, &err);
                free(rgb);
                free(hdr);
                if (!pass) {
                    ref = img.rgb;
                    continue;
                }
                printf("| %u | %u | %.1f | %.4f | %.4f |\n", v.n, v.steps, ms[nf / 2],
                       image_error(img.rgb, baked.rgb, (size_t)W * H), image_error(img.rgb, ref, (size_t)W * H));
                free(img.rgb);
            }
    remove(tmp);
    free(ref);
    free(baked.rgb);
    sss_htsm_gpu_destroy(g);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    sss_mesh_free(&f.mesh);
    sss_mesh_free(&rest);
    sss_scene_free(&sc);
    return 0;
}
