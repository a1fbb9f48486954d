/* single_gpu_error: the image error of single scattering per pixel
 * (docs/layers.md §8) and which entry estimate is right.
 *   single_gpu_error [WIDTH HEIGHT]
 * Ketchup (g = 0) on spheres of radius 20 and 5 mm from sss-genmesh's
 * generator, front and grazing light, every pixel that shows the sphere:
 * the truth is sss_ss_mesh_point's default (exact ray casts, the light
 * refracted at K, the beam's focusing; within 0.7 % of the path tracer,
 * docs/layers.md §6) at N = 128. Against it: the GPU pass (light-space map)
 * at N = 10, 16, 32, 50, 100 (per-segment closed form) and 10, 50, 100
 * (Algorithm 1), the CPU's own alternatives at N = 128 (seed 002's fitted
 * planes, the light refracted at the vertex, no focusing) and the CPU at
 * N = 10. RMS and largest relative error over the pixel channels whose
 * truth is at least 2 % of the image's largest. Prints a markdown table.
 * (Algorithm 1 against the closed form on a flat box: test_render_single.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "single_pixels.h"
#include "sss/bake.h"
#include "sss/single.h"
#include "sss/single_mesh.h"

static int W = 128, H = 96;

typedef struct acc {
    double sum2, worst;
    long n;
} acc;

static void add(acc *a, double got, double want)
{
    const double e = fabs(got - want) / want;
    a->sum2 += e * e;
    a->worst = fmax(a->worst, e);
    a->n++;
}

static void die(const char *what, const sss_error *e)
{
    fprintf(stderr, "single_gpu_error: %s: %s\n", what, e->msg);
    exit(1);
}

static float *render(sss_renderer *r, const sss_view_params *p)
{
    float *rgb = NULL, *hdr = NULL;
    sss_error err = {{0}};
    if (sss_renderer_render_image(r, p, W, H, &rgb, &hdr, &err) != SSS_OK) die("render", &err);
    free(rgb);
    return hdr;
}

int main(int argc, char **argv)
{
    if (argc == 3) W = atoi(argv[1]), H = atoi(argv[2]);
    if (W < 8 || H < 8 || W > 4096 || H > 4096) {
        fprintf(stderr, "usage: single_gpu_error [WIDTH HEIGHT]\n");
        return 2;
    }
    sss_offscreen *ctx;
    sss_error err = {{0}};
    if (sss_offscreen_create(&ctx, &err) != SSS_OK) die("GL", &err);
    const double radii[2] = {20.0, 5.0};
    const double lights[2][3] = {{0.3, 0.5, 1.0}, {1.0, 0.2, 0.15}};
    const char *lname[2] = {"front", "grazing"};
    /* the GPU runs: per-segment closed form at 5 N, Algorithm 1 at 3 */
    const int ns[8] = {10, 16, 32, 50, 100, 10, 50, 100};
    printf("| sphere | light | pixel ch. (edge px left out) | GPU segments N=10 | 16 | 32 | 50 | 100 | GPU Alg. 1 N=10 | 50 | 100 | CPU fitted planes | CPU refracted at P | CPU no focusing | CPU segments N=10 |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int ri = 0; ri < 2; ri++) {
        sss_mesh m;
        sss_bvh bvh;
        if (sss_gen_sphere(&m, 1.0, 5, &err) != SSS_OK) die("sphere", &err);
        if (!m.nrm && sss_mesh_compute_normals_areas(&m, "sphere", &err) != SSS_OK) die("normals", &err);
        if (sss_bvh_build(m.pos, m.nv, m.tri, m.nf, &bvh, &err) != SSS_OK) die("bvh", &err);
        sss_material mat;
        sss_material_preset("ketchup", &mat, NULL);
        sss_bake_options o;
        memset(&o, 0, sizeof o);
        o.mm_per_unit = radii[ri];
        o.n_dirs = 6;
        o.quant = SSS_QUANT_FLOAT;
        o.threads = 2;
        sss_bake_file f;
        if (sss_bake(&m, "sphere", &mat, &o, &f, NULL, &err) != SSS_OK) die("bake", &err);
        sss_renderer *r;
        if (sss_renderer_create(&f, &r, &err) != SSS_OK) die("renderer", &err);
        for (int li = 0; li < 2; li++) {
            sss_view_params p;
            sss_view_params_default(&p);
            p.scatter = 0, p.specular = 0, p.surface_shadow = 0, p.single = 1, p.distance = 2.6;
            p.view[0] = 0.3, p.view[1] = 0.35, p.view[2] = 1.0;
            memcpy(p.light, lights[li], sizeof p.light);
            double l[3] = {p.light[0], p.light[1], p.light[2]};
            sss_normalize3(l);
            /* the truth per pixel */
            double *truth = calloc((size_t)W * H * 3, sizeof *truth), peak = 0.0;
            double *pts = calloc((size_t)W * H * 9, sizeof *pts);
            unsigned char *hit = calloc((size_t)W * H, 1);
            const sss_ss_mesh_opts ot = {.samples = 128};
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    double *q = &pts[9 * (size_t)(y * W + x)];
                    if (!pixel_point(r, &m, &bvh, &p, W, H, x, y, q, q + 3, q + 6)) continue;
                    hit[y * W + x] = 1;
                    sss_ss_mesh_point(&m, &bvh, f.mm_per_unit, &f.material, NULL, 3, q, q + 3, l, q + 6, &ot,
                                      &truth[3 * (size_t)(y * W + x)], &err);
                    for (int c = 0; c < 3; c++) peak = fmax(peak, truth[3 * (size_t)(y * W + x) + c]);
                }
            acc a[12];
            memset(a, 0, sizeof a);
            int edge = 0;
            for (int k = 0; k < 8; k++) {
                p.single_samples = ns[k];
                p.single_march = k < 5 ? SSS_SINGLE_MARCH_SEGMENTS : SSS_SINGLE_MARCH_SEED;
                float *img = render(r, &p);
                /* pixels whose centre's ray grazes the silhouette: the BVH hits
                 * the mesh where the rasteriser drew none (the image is 0);
                 * left out of every column */
                if (k == 0)
                    for (int i = 0; i < W * H; i++)
                        if (hit[i] && img[3 * i] == 0.0f && img[3 * i + 1] == 0.0f && img[3 * i + 2] == 0.0f)
                            hit[i] = 0, edge++;
                for (int i = 0; i < W * H * 3; i++)
                    if (hit[i / 3] && truth[i] >= 0.02 * peak) add(&a[k], img[i], truth[i]);
                free(img);
            }
            const sss_ss_mesh_opts alt[4] = {{.samples = 128, .fitted_planes = 1},
                                             {.samples = 128, .vertex_refraction = 1},
                                             {.samples = 128, .no_focusing = 1},
                                             {.samples = 10}};
            for (int i = 0; i < W * H; i++) {
                if (!hit[i]) continue;
                const double *q = &pts[9 * (size_t)i];
                for (int k = 0; k < 4; k++) {
                    double v[3];
                    sss_ss_mesh_point(&m, &bvh, f.mm_per_unit, &f.material, NULL, 3, q, q + 3, l, q + 6, &alt[k], v,
                                      &err);
                    for (int c = 0; c < 3; c++)
                        if (truth[3 * i + c] >= 0.02 * peak) add(&a[8 + k], v[c], truth[3 * i + c]);
                }
            }
            printf("| R %g mm | %s | %ld (%d) |", radii[ri], lname[li], a[0].n, edge);
            for (int k = 0; k < 12; k++) printf(" %.3g %% (max %.3g %%) |", 100 * sqrt(a[k].sum2 / a[k].n), 100 * a[k].worst);
            printf("\n");
            fflush(stdout);
            free(truth), free(pts), free(hit);
        }
        sss_renderer_destroy(r);
        sss_file_free(&f);
        sss_bvh_free(&bvh);
        sss_mesh_free(&m);
    }
    sss_offscreen_destroy(ctx);
    return 0;
}
