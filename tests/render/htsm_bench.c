/* htsm_bench: the run-time path's frame time and accuracy (docs/heterogeneous.md
 * §9.4), a measurement, not a test.
 *   htsm_bench SCENE.json BAKED.exr WIDTH HEIGHT EXPOSURE [FRAMES [R0_MM [PATHS [RHO_D]]]]
 * SCENE.json: one editable object with a field and its lights, directional
 * or point (as data/scenes/editable_box.json); BAKED.exr: the same scene without
 * "editable", baked and drawn by sss-view at the same size and exposure
 * with --no-specular --single off. For n = 1, 5, 9, 13 samples and 2 … 32
 * steps: the median wall time of FRAMES (default 7) frames of the pass
 * (light-space map, its mips and the per-pixel estimate, glFinish before
 * and after; the first frame, which compiles, is not counted), and the
 * image's difference from the baked one over the pixels the object covers:
 * mean |run-time − baked| / mean baked, and the same against the run-time
 * path's own n = 13, 64 steps. Prints a markdown table.
 * PATHS > 0 adds the path-traced reference (sss/reference.h, docs/
 * reference.md): the same camera, light and field, PATHS paths per pixel,
 * and a column of each image's difference from it, measured on the means
 * of 8 × 8 pixel blocks (the reference's per-pixel noise averaged down;
 * its own relative standard error on those blocks is printed first, the
 * floor under that column), the baked image's in the table's heading.
 * RHO_D ≥ 0 draws every light's surface terms in the pass (specular, and
 * diffuse reflection of share RHO_D, each shadowed by its own map;
 * docs/heterogeneous.md §9.1) to time them; the error columns then hold
 * them too, against a baked image without them. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/htsm_gpu.h"
#include "sss/import.h"
#include "sss/probe.h"
#include "sss/reference.h"
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

/* The same on the means of B × B pixel blocks (the object's pixels only,
 * a block counted where b covers all of them): the reference's noise per
 * pixel averages down by B. */
#define BLOCK 8
/* Per channel the sum over the block at (bx, by) of v (of v², squared),
 * into s; 1 when `cover` (RGB) covers every pixel of it. */
static int block_sum(const float *v, int squared, const float *cover, int W, int bx, int by, double s[3])
{
    int full = 1;
    s[0] = s[1] = s[2] = 0.0;
    for (int y = by; y < by + BLOCK; y++)
        for (int x = bx; x < bx + BLOCK; x++) {
            const size_t i = (size_t)y * W + x;
            if (!(cover[3 * i] + cover[3 * i + 1] + cover[3 * i + 2] > 0.0f)) full = 0;
            for (int c = 0; c < 3; c++) s[c] += squared ? (double)v[3 * i + c] * v[3 * i + c] : v[3 * i + c];
        }
    return full;
}

static double block_error(const float *a, const float *b, int W, int H)
{
    double d = 0, s = 0;
    for (int by = 0; by + BLOCK <= H; by += BLOCK)
        for (int bx = 0; bx + BLOCK <= W; bx += BLOCK) {
            double ma[3], mb[3];
            if (!block_sum(b, 0, b, W, bx, by, mb)) continue;
            block_sum(a, 0, b, W, bx, by, ma);
            for (int c = 0; c < 3; c++) d += fabs(ma[c] - mb[c]), s += mb[c];
        }
    return s > 0 ? d / s : NAN;
}

static void die(const char *what, const sss_error *err)
{
    fprintf(stderr, "htsm_bench: %s: %s\n", what, err->msg);
    exit(1);
}

/* The path-traced image (E = 1 radiance, ×exposure × light_rgb as the
 * viewer's HDR image) through the camera of p: the viewer's frame
 * (sss_view_frame) and field of view, rows from the top. Prints its noise
 * and the baked image's difference from it. */
static float *reference_image(const sss_bake_file *f, const sss_hetero *h, const sss_view_params *p, int W, int H,
                              uint64_t paths, const float *baked)
{
    sss_error err = {{0}};
    sss_ref_medium med;
    if (sss_ref_medium_from_material(&f->material, 0.0, &med, &err) != SSS_OK) die("reference", &err);
    med.hetero = h;
    sss_ref_scene *rs = NULL;
    if (sss_ref_medium_validate(&med, &err) != SSS_OK || sss_ref_scene_create(&f->mesh, f->mm_per_unit, &rs, &err) != SSS_OK)
        die("reference", &err);
    double centre[3];
    const double radius = sss_mesh_bounding_sphere(&f->mesh, centre);
    sss_ref_camera cam = {.width = W, .height = H};
    sss_view_frame(p, centre, radius, cam.eye, cam.right, cam.up, cam.fwd);
    cam.tan_half_fov = tan(0.5 * (p->fov_deg > 0 ? p->fov_deg : 35.0) * 3.14159265358979323846 / 180.0);
    const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {p->light[0], p->light[1], p->light[2]}};
    sss_ref_options o = {.seed = 1, .paths = paths};
    const size_t n = (size_t)W * H;
    float *rgb = malloc(3 * n * sizeof *rgb), *se = malloc(3 * n * sizeof *se);
    if (!rgb || !se) {
        fprintf(stderr, "htsm_bench: out of memory\n");
        exit(1);
    }
    sss_ref_stats st;
    if (sss_ref_image(rs, &med, &l, &cam, &o, rgb, se, &st, &err) != SSS_OK) die("reference image", &err);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            const float k = (float)(p->exposure * p->light_rgb[c]);
            rgb[3 * i + c] *= k, se[3 * i + c] *= k;
        }
    /* the reference's relative standard error on the blocks: per block
     * sqrt(Σ se²) / B² against its mean, weighted as block_error weighs */
    double var = 0, s = 0;
    for (int by = 0; by + BLOCK <= H; by += BLOCK)
        for (int bx = 0; bx + BLOCK <= W; bx += BLOCK) {
            double v[3], m[3];
            if (!block_sum(rgb, 0, rgb, W, bx, by, m)) continue;
            block_sum(se, 1, rgb, W, bx, by, v);
            for (int c = 0; c < 3; c++) var += sqrt(v[c]), s += m[c];
        }
    double mr = 0, mb = 0;
    for (size_t i = 0; i < 3 * n; i++) mr += rgb[i], mb += baked[i];
    printf("path-traced reference: %llu paths per pixel, %.0f s; its noise on 8 × 8 blocks %.4f (relative standard "
           "error); the baked image against it %.4f; summed over the image, baked ÷ reference %.3f\n\n",
           (unsigned long long)st.paths, st.seconds, s > 0 ? var / s : NAN, block_error(baked, rgb, W, H), mb / mr);
    free(se);
    sss_ref_scene_destroy(rs);
    return rgb;
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: htsm_bench SCENE.json BAKED.exr WIDTH HEIGHT EXPOSURE [FRAMES [R0_MM [PATHS [RHO_D]]]]\n");
        return 2;
    }
    const int W = atoi(argv[3]), H = atoi(argv[4]), frames = argc > 6 ? atoi(argv[6]) : 7;
    const double r0 = argc > 7 ? atof(argv[7]) : 0.0; /* 0: the viewer's default */
    const long paths = argc > 8 ? atol(argv[8]) : 0;
    const double rho_d = argc > 9 ? atof(argv[9]) : -1.0; /* < 0: no surface terms */
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
    p.specular = rho_d >= 0.0;
    p.diffuse = rho_d > 0.0 ? rho_d : 0.0;
    p.single = -1;
    p.near_terms = 0;
    p.exposure = atof(argv[5]);
    /* the scene's lights as sss-view takes them: directional and point */
    sss_htsm_view lights;
    sss_htsm_view_default(&lights, &f, &o->hetero);
    uint32_t skipped = 0;
    if (!sss_htsm_view_lights(&lights, &p, &sc, &f.mesh, &skipped)) {
        fprintf(stderr, "htsm_bench: %s: no light the run-time path draws\n", argv[1]);
        return 1;
    }
    if (o->field_strength > 0.0) lights.mat.strength = o->field_strength;
    if (paths > 0 && (lights.no_p_light || lights.nmore)) {
        fprintf(stderr, "htsm_bench: %s: the path-traced reference takes one directional light\n", argv[1]);
        return 1;
    }
    sss_scene_camera_params(&sc, &f, &p);
    const char *tmp = "htsm_bench.tmp.exr";
    float *ref = NULL, *pt = NULL;
    const uint32_t ns[4] = {1, 5, 9, 13}, steps[5] = {2, 4, 8, 16, 32};
    printf("%s, %dx%d, light-space map 256², field 64³, %u light(s)%s\n\n", sss_gl_renderer_name(), W, H,
           (lights.no_p_light ? 0u : 1u) + lights.nmore, rho_d >= 0.0 ? ", surface terms on" : "");
    if (paths > 0) pt = reference_image(&f, &o->hetero, &p, W, H, (uint64_t)paths, baked.rgb);
    printf("| n | steps | frame ms (median of %d) | vs baked | vs n = 13, 64 steps |%s\n|---:|---:|---:|---:|---:|%s\n",
           frames, pt ? " vs path-traced (8 × 8 blocks) |" : "", pt ? "---:|" : "");
    for (int pass = 0; pass < 2; pass++)
        for (int a = 0; a < (pass ? 4 : 1); a++)
            for (int b = 0; b < (pass ? 5 : 1); b++) {
                sss_htsm_view v = lights;
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
                printf("| %u | %u | %.1f | %.4f | %.4f |", v.n, v.steps, ms[nf / 2],
                       image_error(img.rgb, baked.rgb, (size_t)W * H), image_error(img.rgb, ref, (size_t)W * H));
                if (pt) printf(" %.4f |", block_error(img.rgb, pt, W, H));
                printf("\n");
                free(img.rgb);
            }
    remove(tmp);
    free(ref);
    free(pt);
    free(baked.rgb);
    sss_htsm_gpu_destroy(g);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    sss_mesh_free(&f.mesh);
    sss_mesh_free(&rest);
    sss_scene_free(&sc);
    return 0;
}
