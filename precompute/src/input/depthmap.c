/* depthmap.c: grey PNG depth maps (sss/depthmap.h; docs/layers.md §3),
 * read and written through libpng. */
#include "sss/depthmap.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/fileio.h"

/* libpng's errors end the read through this: the message is kept for the
 * one line naming the file. */
typedef struct png_failure {
    jmp_buf jump;
    char msg[200];
} png_failure;

static void on_error(png_structp png, png_const_charp msg)
{
    png_failure *f = png_get_error_ptr(png);
    snprintf(f->msg, sizeof f->msg, "%s", msg);
    longjmp(f->jump, 1);
}

static void on_warning(png_structp png, png_const_charp msg)
{
    (void)png;
    (void)msg; /* warnings (an unknown chunk, a gamma note) do not change the samples */
}

static const char *colour_name(int t)
{
    switch (t) {
    case PNG_COLOR_TYPE_GRAY: return "grey";
    case PNG_COLOR_TYPE_GRAY_ALPHA: return "grey with alpha";
    case PNG_COLOR_TYPE_RGB: return "RGB";
    case PNG_COLOR_TYPE_RGB_ALPHA: return "RGBA";
    case PNG_COLOR_TYPE_PALETTE: return "palette";
    default: return "unknown colour type";
    }
}

sss_result sss_depth_map_read(const char *path, sss_depth_image *im, sss_error *err)
{
    memset(im, 0, sizeof *im);
    FILE *fp = fopen(path, "rb");
    if (!fp) return sss_fail(err, SSS_ERR_IO, "%s: cannot open the depth map (%s)", path, strerror(errno));
    unsigned char sig[8];
    if (fread(sig, 1, 8, fp) != 8 || png_sig_cmp(sig, 0, 8)) {
        fclose(fp);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: not a PNG file (a depth map is an 8- or 16-bit grey PNG)", path);
    }
    png_failure fail = {.msg = ""};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &fail, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    float *volatile value = NULL;
    unsigned char *volatile row = NULL;
    png_bytep *volatile rows = NULL;
    volatile sss_result r = SSS_OK;
    if (!png || !info) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the PNG reader", path);
        goto done;
    }
    if (setjmp(fail.jump)) {
        r = sss_fail(err, SSS_ERR_CORRUPT, "%s: damaged PNG (%s)", path, fail.msg);
        goto done;
    }
    png_init_io(png, fp);
    png_set_sig_bytes(png, 8);
    png_read_info(png, info);
    const png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    const int depth = png_get_bit_depth(png, info), colour = png_get_color_type(png, info);
    if (colour != PNG_COLOR_TYPE_GRAY || (depth != 8 && depth != 16)) {
        r = sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %s, %d-bit: a depth map is an 8- or 16-bit grey PNG", path,
                     colour_name(colour), depth);
        goto done;
    }
    if (!w || !h || (uint64_t)w * h > SSS_DEPTH_MAP_MAX_SAMPLES) {
        r = sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: %u x %u samples (at most %llu)", path, (unsigned)w, (unsigned)h,
                     (unsigned long long)SSS_DEPTH_MAP_MAX_SAMPLES);
        goto done;
    }
    const int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    const size_t bpp = (size_t)depth / 8, stride = (size_t)w * bpp;
    value = malloc((size_t)w * h * sizeof(float));
    /* interlaced files: every pass over the whole image, so all rows */
    row = malloc(passes > 1 ? stride * h : stride);
    if (!value || !row) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %u x %u samples", path, (unsigned)w, (unsigned)h);
        goto done;
    }
    const double top = depth == 16 ? 65535.0 : 255.0;
    if (passes > 1) {
        rows = malloc(h * sizeof *rows);
        if (!rows) {
            r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
            goto done;
        }
        for (png_uint_32 j = 0; j < h; j++) rows[j] = row + j * stride;
        png_read_image(png, rows);
    }
    for (png_uint_32 j = 0; j < h; j++) {
        const unsigned char *p = passes > 1 ? row + j * stride : row;
        if (passes == 1) png_read_row(png, row, NULL);
        for (png_uint_32 i = 0; i < w; i++) /* PNG samples are big-endian */
            value[(size_t)j * w + i] = (float)((depth == 16 ? (p[2 * i] << 8 | p[2 * i + 1]) : p[i]) / top);
    }
    png_read_end(png, NULL);
    im->w = w;
    im->h = h;
    im->value = value;
    value = NULL;
done:
    png_destroy_read_struct(png ? &png : NULL, info ? &info : NULL, NULL);
    free(rows);
    free(row);
    free(value);
    fclose(fp);
    return r;
}

/* ---- writing (the tests' and sss-genmesh's maps) ------------------------ */

typedef struct png_sink {
    unsigned char *b;
    size_t n, cap;
    int failed;
} png_sink;

static void sink_write(png_structp png, png_bytep data, png_size_t len)
{
    png_sink *s = png_get_io_ptr(png);
    if (s->failed) return;
    if (s->n + len > s->cap) {
        size_t cap = s->cap ? s->cap : 4096;
        while (cap < s->n + len) cap *= 2;
        unsigned char *nb = realloc(s->b, cap);
        if (!nb) {
            s->failed = 1;
            return;
        }
        s->b = nb;
        s->cap = cap;
    }
    memcpy(s->b + s->n, data, len);
    s->n += len;
}

static void sink_flush(png_structp png) { (void)png; }

sss_result sss_depth_map_write(const char *path, const sss_depth_image *im, int bits, sss_error *err)
{
    if (!im || !im->value || !im->w || !im->h || (bits != 8 && bits != 16))
        return sss_fail(err, SSS_ERR_ARG, "%s: a depth map needs samples and 8 or 16 bits", path);
    const size_t bpp = (size_t)bits / 8, stride = (size_t)im->w * bpp;
    unsigned char *volatile row = malloc(stride);
    png_sink sink = {0};
    png_failure fail = {.msg = ""};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &fail, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    volatile sss_result r = SSS_OK;
    if (!png || !info || !row) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for the PNG writer", path);
        goto done;
    }
    if (setjmp(fail.jump)) {
        r = sss_fail(err, SSS_ERR_IO, "%s: PNG encoding failed (%s)", path, fail.msg);
        goto done;
    }
    png_set_write_fn(png, &sink, sink_write, sink_flush);
    png_set_IHDR(png, info, im->w, im->h, bits, PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    const double top = bits == 16 ? 65535.0 : 255.0;
    for (uint32_t j = 0; j < im->h; j++) {
        for (uint32_t i = 0; i < im->w; i++) {
            double x = im->value[(size_t)j * im->w + i];
            x = x < 0.0 ? 0.0 : x > 1.0 ? 1.0 : x; /* NaN reads as 0 */
            const unsigned s = (unsigned)lround(x * top);
            if (bits == 16) {
                row[2 * i] = (unsigned char)(s >> 8);
                row[2 * i + 1] = (unsigned char)(s & 0xffu);
            } else {
                row[i] = (unsigned char)s;
            }
        }
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    if (sink.failed) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory encoding the PNG", path);
        goto done;
    }
    /* written atomically, to a path the output policy allows (sss/fileio.h) */
    sss_atomic a;
    if ((r = sss_atomic_begin(&a, path, NULL, err)) != SSS_OK) goto done;
    if ((r = sss_atomic_write(&a, sink.b, sink.n, err)) != SSS_OK) {
        sss_atomic_abort(&a);
        goto done;
    }
    r = sss_atomic_commit(&a, err);
done:
    png_destroy_write_struct(png ? &png : NULL, info ? &info : NULL);
    free(row);
    free(sink.b);
    return r;
}
