/* png_stats: numbers that tell a rendered picture from a blank one, for the
 * window tests.
 *
 *   sss-pngstats IMG.png
 *     prints "WIDTH HEIGHT MEAN STDDEV NONBG": mean and standard deviation
 *     of all 8-bit samples (R, G and B together), and the fraction of pixels
 *     whose colour differs from the background, taken to be the most
 *     frequent colour (a clear colour fills every pixel nothing was drawn on,
 *     so it wins unless the picture is nearly all object).
 *   sss-pngstats A.png B.png
 *     prints the fraction of pixels that differ between two images of the
 *     same size (exit 1 if the sizes differ).
 *   sss-pngstats --diff A.png B.png
 *     prints "MAX MEAN FRACTION" over all 8-bit samples of two images of the
 *     same size: the largest and the mean absolute difference in levels, and
 *     the fraction of pixels that differ (as above).
 *   sss-pngstats --range IMG.png
 *     prints "MAX CLIPPED" over the object's pixels (those that differ from
 *     the background): the largest 8-bit sample, and the fraction of them
 *     with a channel at 255 (a first render neither black nor clipped).
 *
 * "Differs" means some channel differs by more than 2 levels, so that a
 * background that is merely dithered would still count as background.
 */
#include <png.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TOL 2

static uint8_t *load(const char *path, unsigned *w, unsigned *h)
{
    png_image im;
    memset(&im, 0, sizeof im);
    im.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&im, path)) {
        fprintf(stderr, "sss-pngstats: %s: %s\n", path, im.message);
        return NULL;
    }
    im.format = PNG_FORMAT_RGB; /* whatever is stored, read 8-bit RGB */
    uint8_t *px = malloc(PNG_IMAGE_SIZE(im));
    if (!px || !png_image_finish_read(&im, NULL, px, 0, NULL)) {
        fprintf(stderr, "sss-pngstats: %s: %s\n", path, px ? im.message : "out of memory");
        free(px);
        png_image_free(&im);
        return NULL;
    }
    *w = im.width;
    *h = im.height;
    return px;
}

static int differs(const uint8_t *a, const uint8_t *b)
{
    for (int c = 0; c < 3; c++)
        if (abs((int)a[c] - (int)b[c]) > TOL) return 1;
    return 0;
}

static int cmp_u32(const void *x, const void *y)
{
    uint32_t a = *(const uint32_t *)x, b = *(const uint32_t *)y;
    return (a > b) - (a < b);
}

/* The most frequent colour (the background): sort packed RGB values, take
 * the longest run. UINT32_MAX when out of memory. */
static uint32_t background(const uint8_t *px, size_t n)
{
    uint32_t *c = malloc((n ? n : 1) * sizeof *c);
    if (!c) return UINT32_MAX;
    for (size_t i = 0; i < n; i++) c[i] = (uint32_t)px[3 * i] << 16 | (uint32_t)px[3 * i + 1] << 8 | px[3 * i + 2];
    qsort(c, n, sizeof *c, cmp_u32);
    uint32_t bg = n ? c[0] : 0;
    for (size_t i = 0, best = 0; i < n;) {
        size_t j = i;
        while (j < n && c[j] == c[i]) j++;
        if (j - i > best) { best = j - i; bg = c[i]; }
        i = j;
    }
    free(c);
    return bg;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--range") == 0) {
        unsigned w, h;
        uint8_t *px = load(argv[2], &w, &h);
        if (!px) return 1;
        const size_t n = (size_t)w * h;
        const uint32_t bg = background(px, n);
        if (bg == UINT32_MAX) { free(px); fprintf(stderr, "sss-pngstats: out of memory\n"); return 1; }
        const uint8_t bgp[3] = {(uint8_t)(bg >> 16), (uint8_t)(bg >> 8), (uint8_t)bg};
        size_t obj = 0, clipped = 0;
        int mx = 0;
        for (size_t i = 0; i < n; i++) {
            if (!differs(px + 3 * i, bgp)) continue;
            obj++;
            int top = 0;
            for (int k = 0; k < 3; k++) top = px[3 * i + k] > top ? px[3 * i + k] : top;
            mx = top > mx ? top : mx;
            clipped += top == 255;
        }
        printf("%d %.6f\n", mx, obj ? (double)clipped / (double)obj : 0.0);
        free(px);
        return 0;
    }
    if (argc == 4 && strcmp(argv[1], "--diff") == 0) {
        unsigned w, h, w2, h2;
        uint8_t *a = load(argv[2], &w, &h);
        if (!a) return 1;
        uint8_t *b = load(argv[3], &w2, &h2);
        if (!b || w2 != w || h2 != h) {
            if (b) fprintf(stderr, "sss-pngstats: sizes differ: %ux%u vs %ux%u\n", w, h, w2, h2);
            free(a); free(b);
            return 1;
        }
        const size_t n = (size_t)w * h;
        size_t d = 0;
        int mx = 0;
        double sum = 0.0;
        for (size_t i = 0; i < n; i++) {
            d += (size_t)differs(a + 3 * i, b + 3 * i);
            for (int c = 0; c < 3; c++) {
                const int e = abs((int)a[3 * i + c] - (int)b[3 * i + c]);
                mx = e > mx ? e : mx;
                sum += e;
            }
        }
        printf("%d %.6f %.6f\n", mx, n ? sum / (3.0 * (double)n) : 0.0, n ? (double)d / (double)n : 0.0);
        free(a); free(b);
        return 0;
    }
    if (argc != 2 && argc != 3) {
        fprintf(stderr, "usage: sss-pngstats IMG.png        -> WIDTH HEIGHT MEAN STDDEV NONBG\n"
                        "       sss-pngstats A.png B.png    -> fraction of pixels that differ\n"
                        "       sss-pngstats --diff A.png B.png -> MAX MEAN FRACTION of the differences\n"
                        "       sss-pngstats --range IMG.png -> MAX CLIPPED over the object's pixels\n");
        return 2;
    }
    unsigned w, h;
    uint8_t *px = load(argv[1], &w, &h);
    if (!px) return 1;
    size_t n = (size_t)w * h;
    if (argc == 3) {
        unsigned w2, h2;
        uint8_t *q = load(argv[2], &w2, &h2);
        if (!q) { free(px); return 1; }
        if (w2 != w || h2 != h) {
            fprintf(stderr, "sss-pngstats: sizes differ: %ux%u vs %ux%u\n", w, h, w2, h2);
            free(px); free(q);
            return 1;
        }
        size_t d = 0;
        for (size_t i = 0; i < n; i++) d += (size_t)differs(px + 3 * i, q + 3 * i);
        printf("%.6f\n", n ? (double)d / (double)n : 0.0);
        free(px); free(q);
        return 0;
    }
    double sum = 0, sum2 = 0;
    for (size_t i = 0; i < 3 * n; i++) {
        sum += px[i];
        sum2 += (double)px[i] * px[i];
    }
    double mean = n ? sum / (3.0 * (double)n) : 0, var = n ? sum2 / (3.0 * (double)n) - mean * mean : 0;
    const uint32_t bg = background(px, n);
    if (bg == UINT32_MAX) { free(px); fprintf(stderr, "sss-pngstats: out of memory\n"); return 1; }
    const uint8_t bgp[3] = {(uint8_t)(bg >> 16), (uint8_t)(bg >> 8), (uint8_t)bg};
    size_t other = 0;
    for (size_t i = 0; i < n; i++) other += (size_t)differs(px + 3 * i, bgp);
    printf("%u %u %.3f %.3f %.6f\n", w, h, mean, sqrt(var > 0 ? var : 0), n ? (double)other / (double)n : 0.0);
    free(px);
    return 0;
}
