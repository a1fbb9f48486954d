/* ref_compare: the viewer's image against sss-ref's (docs/accuracy.md,
 * "Model error"): the statistics of their difference over the pixels that
 * see the mesh, and a picture real-time | reference | difference.
 *
 *   ref_compare RT.exr REF.exr REF.stderr.exr OUT.png [EXPOSURE]
 *
 * RT.exr: sss-view --offscreen --no-specular (linear radiance, E = 1,
 * exposure 1); REF.exr and its standard error: sss-ref --out with the same
 * size, light and view. The picture shows both at one exposure (default:
 * 0.9 / the 99.5th percentile of the reference's luminance), clamped and
 * sRGB-encoded, and their difference rt − ref at 4× that exposure, red
 * where the real-time image is brighter, blue where darker. Prints one JSON
 * object: per channel the means over the covered pixels, their ratio
 * rt/ref with its standard error, the relative RMS of the difference with
 * the reference's own noise taken out, and that noise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/probe.h"
#include "sss/render.h"

static int cmp_float(const void *a, const void *b)
{
    const float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    if (argc < 5) {
        fprintf(stderr, "usage: ref_compare RT.exr REF.exr REF.stderr.exr OUT.png [EXPOSURE]\n");
        return 2;
    }
    sss_probe rt = {0}, ref = {0}, se = {0};
    sss_error err = {{0}};
    if (sss_probe_read(argv[1], &rt, &err) != SSS_OK || sss_probe_read(argv[2], &ref, &err) != SSS_OK ||
        sss_probe_read(argv[3], &se, &err) != SSS_OK) {
        fprintf(stderr, "ref_compare: %s\n", err.msg);
        return 1;
    }
    if (rt.w != ref.w || rt.h != ref.h || se.w != ref.w || se.h != ref.h) {
        fprintf(stderr, "ref_compare: the images differ in size\n");
        return 1;
    }
    const size_t w = ref.w, h = ref.h, np = w * h;
    /* covered: the reference saw the mesh there (a value or a standard
     * error), or the viewer drew something */
    unsigned char *mask = calloc(np, 1);
    float *lum = malloc(sizeof(float) * np);
    size_t nm = 0;
    double s_rt[3] = {0}, s_ref[3] = {0}, s_se2[3] = {0}, s_d2[3] = {0}, s_ref2[3] = {0};
    for (size_t i = 0; i < np; i++) {
        const float *a = &rt.rgb[3 * i], *b = &ref.rgb[3 * i], *e = &se.rgb[3 * i];
        if (!(a[0] || a[1] || a[2] || b[0] || b[1] || b[2] || e[0] || e[1] || e[2])) continue;
        mask[i] = 1;
        lum[nm++] = (b[0] + b[1] + b[2]) / 3.0f;
        for (int c = 0; c < 3; c++) {
            s_rt[c] += a[c];
            s_ref[c] += b[c];
            s_se2[c] += (double)e[c] * e[c];
            s_d2[c] += (double)(a[c] - b[c]) * (a[c] - b[c]);
            s_ref2[c] += (double)b[c] * b[c];
        }
    }
    if (!nm) {
        fprintf(stderr, "ref_compare: no pixel sees the mesh\n");
        return 1;
    }
    qsort(lum, nm, sizeof(float), cmp_float);
    const double p995 = lum[(size_t)(0.995 * (nm - 1))];
    const double expo = argc > 5 ? atof(argv[5]) : (p995 > 0 ? 0.9 / p995 : 1.0);
    /* the picture, rows from the top, then flipped for the PNG writer
     * (bottom-up rows, sss/render.h) */
    const size_t W = 3 * w;
    float *pic = calloc(3 * W * h, sizeof(float)), *flip = malloc(3 * W * h * sizeof(float));
    for (size_t y = 0; y < h; y++)
        for (size_t x = 0; x < w; x++) {
            const size_t i = y * w + x;
            for (int c = 0; c < 3; c++) {
                pic[3 * (y * W + x) + c] = (float)fmin(1.0, expo * rt.rgb[3 * i + c]);
                pic[3 * (y * W + w + x) + c] = (float)fmin(1.0, expo * ref.rgb[3 * i + c]);
            }
            double d = 0.0;
            for (int c = 0; c < 3; c++) d += rt.rgb[3 * i + c] - ref.rgb[3 * i + c];
            d = fmin(1.0, fabs(4.0 * expo * d / 3.0));
            float *p = &pic[3 * (y * W + 2 * w + x)];
            const double base = mask[i] ? 0.08 : 0.0; /* the silhouette, faintly */
            const double pos = rt.rgb[3 * i] + rt.rgb[3 * i + 1] + rt.rgb[3 * i + 2] >=
                               ref.rgb[3 * i] + ref.rgb[3 * i + 1] + ref.rgb[3 * i + 2];
            p[0] = (float)(base + (pos ? d : 0.0));
            p[1] = (float)base;
            p[2] = (float)(base + (pos ? 0.0 : d));
        }
    for (size_t y = 0; y < h; y++) memcpy(flip + 3 * W * (h - 1 - y), pic + 3 * W * y, 3 * W * sizeof(float));
    if (sss_write_png(argv[4], flip, (int)W, (int)h, &err) != SSS_OK) {
        fprintf(stderr, "ref_compare: %s\n", err.msg);
        return 1;
    }
    printf("{\"covered_pixels\":%zu,\"exposure\":%.6g", nm, expo);
    const char *keys[] = {"mean_realtime", "mean_reference", "ratio", "ratio_stderr", "rel_rms", "reference_noise_rel_rms"};
    for (int k = 0; k < 6; k++) {
        printf(",\"%s\":[", keys[k]);
        for (int c = 0; c < 3; c++) {
            const double mr = s_ref[c] / nm, ratio = s_ref[c] > 0 ? s_rt[c] / s_ref[c] : 0.0;
            const double v[6] = {s_rt[c] / nm, mr, ratio, s_ref[c] > 0 ? ratio * sqrt(s_se2[c]) / s_ref[c] : 0.0,
                                 s_ref2[c] > 0 ? sqrt(fmax(0.0, s_d2[c] - s_se2[c]) / s_ref2[c]) : 0.0,
                                 s_ref2[c] > 0 ? sqrt(s_se2[c] / s_ref2[c]) : 0.0};
            printf("%s%.6g", c ? "," : "", v[k]);
        }
        printf("]");
    }
    printf("}\n");
    free(mask);
    free(lum);
    free(pic);
    free(flip);
    sss_probe_free(&rt);
    sss_probe_free(&ref);
    sss_probe_free(&se);
    return 0;
}
