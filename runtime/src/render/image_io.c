/* image_io.c: PNG (libpng) and OpenEXR (C API, openexr.h) writers
 * (sss_write_*, sss/render.h). Every image is written atomically to a path
 * the output policy allows (sss/fileio.h): encoded into a temporary file in
 * the target's directory, which replaces the target only when complete, so
 * a full disk or a failure leaves the old file or none, never a truncated
 * image under the final name. The libraries' own printers are silenced:
 * their messages come back through sss_error as one line. */
#include "sss/render.h"

#include <ctype.h>
#include <math.h>
#include <openexr.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/fileio.h"

float sss_srgb_encode(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
}

/* An image with a value that is not a finite number is refused, not
 * written: Inf or NaN in a picture means the radiance overflowed the
 * renderer's float range (docs/robustness.md, "Images"), and a file that
 * looks fine (PNG clamps) would hide it. */
static sss_result check_finite(const char *path, const float *rgb, int width, int height, sss_error *err)
{
    const size_t n = (size_t)width * (size_t)height * 3;
    for (size_t i = 0; i < n; i++)
        if (!isfinite(rgb[i]))
            return sss_fail(err, SSS_ERR_ARG, "%s: pixel (%zu, %zu) channel %zu is %s: not written (the radiance "
                            "overflows float: lower --exposure or the light's intensity)", path,
                            (i / 3) % (size_t)width, (size_t)height - 1 - (i / 3) / (size_t)width, i % 3,
                            isnan(rgb[i]) ? "nan" : "inf");
    return SSS_OK;
}

static int size_ok(int width, int height) { return width > 0 && height > 0 && width <= 65536 && height <= 65536; }

/* ---- PNG ------------------------------------------------------------------ */

typedef struct png_sink {
    sss_atomic *a;
    sss_error *err;
    int failed;
    char msg[200];
} png_sink;

static void png_write_cb(png_structp png, png_bytep data, png_size_t n)
{
    png_sink *s = png_get_io_ptr(png);
    if (s->failed) return;
    if (sss_atomic_write(s->a, data, n, s->err) != SSS_OK) {
        s->failed = 1;
        png_error(png, "write failed");
    }
}

static void png_flush_cb(png_structp png) { (void)png; }

static void png_error_cb(png_structp png, png_const_charp msg)
{
    png_sink *s = png_get_error_ptr(png);
    if (s && !s->failed) snprintf(s->msg, sizeof s->msg, "%s", msg ? msg : "error");
    png_longjmp(png, 1);
}

static void png_warning_cb(png_structp png, png_const_charp msg) { (void)png, (void)msg; }

/* Rows come bottom-up (GL); row(y, out) fills the 3·width bytes of image
 * row y counted from the bottom. */
typedef void (*png_row_fn)(const void *src, int width, int y, unsigned char *out);

static void row_linear(const void *src, int width, int y, unsigned char *out)
{
    const float *s = (const float *)src + (size_t)y * width * 3;
    for (int i = 0; i < width * 3; i++) out[i] = (unsigned char)lrintf(255.0f * sss_srgb_encode(s[i]));
}

static void row_rgb8(const void *src, int width, int y, unsigned char *out)
{
    memcpy(out, (const unsigned char *)src + (size_t)y * width * 3, (size_t)width * 3);
}

/* Encodes into the temporary file of a (begun); on failure a is aborted. */
static sss_result png_encode(sss_atomic *a, const char *path, const void *src, png_row_fn rowf, int width, int height,
                             sss_error *err)
{
    png_sink sink = {a, err, 0, ""};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, png_error_cb, png_warning_cb);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    unsigned char *volatile row = malloc((size_t)width * 3);
    if (!png || !info || !row) {
        png_destroy_write_struct(&png, &info);
        free(row);
        sss_atomic_abort(a);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(row);
        sss_atomic_abort(a);
        if (sink.failed) return SSS_ERR_IO; /* err holds the write's message */
        return sss_fail(err, SSS_ERR_IO, "%s: PNG write failed: %s", path, sink.msg);
    }
    png_set_write_fn(png, &sink, png_write_cb, png_flush_cb);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = height - 1; y >= 0; y--) { /* GL rows are bottom-up */
        rowf(src, width, y, row);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(row);
    return SSS_OK;
}

static sss_result png_stage(sss_atomic *a, const char *path, const void *src, png_row_fn rowf, int width, int height,
                            const sss_inputs *in, sss_error *err)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
    if (!size_ok(width, height)) return sss_fail(err, SSS_ERR_ARG, "%s: image size %dx%d", path, width, height);
    sss_result r = sss_atomic_begin(a, path, in, err);
    return r != SSS_OK ? r : png_encode(a, path, src, rowf, width, height, err);
}

/* Stages and commits one image. */
static sss_result commit_staged(sss_result r, sss_atomic *a, sss_error *err)
{
    return r != SSS_OK ? r : sss_atomic_commit(a, err);
}

/* Checks the pixels, begins a and encodes the image into it: PNG (png = 1)
 * or EXR. */
static sss_result exr_encode(sss_atomic *a, const char *path, const float *rgb, int width, int height, sss_error *err);
static sss_result stage(sss_atomic *a, int png, const char *path, const float *px, int width, int height,
                        const sss_inputs *in, sss_error *err)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
    if (!px) return sss_fail(err, SSS_ERR_ARG, "%s: no pixels", path);
    if (!size_ok(width, height)) return sss_fail(err, SSS_ERR_ARG, "%s: image size %dx%d", path, width, height);
    sss_result r = check_finite(path, px, width, height, err);
    if (r != SSS_OK) return r;
    if ((r = sss_atomic_begin(a, path, in, err)) != SSS_OK) return r;
    return png ? png_encode(a, path, px, row_linear, width, height, err) : exr_encode(a, path, px, width, height, err);
}

sss_result sss_write_png_with(const char *path, const float *rgb, int width, int height, const sss_inputs *in,
                              sss_error *err)
{
    sss_atomic a;
    return commit_staged(stage(&a, 1, path, rgb, width, height, in, err), &a, err);
}

sss_result sss_write_png(const char *path, const float *rgb, int width, int height, sss_error *err)
{
    return sss_write_png_with(path, rgb, width, height, NULL, err);
}

sss_result sss_write_png_rgb8(const char *path, const unsigned char *px, int width, int height, const sss_inputs *in,
                              sss_error *err)
{
    sss_atomic a;
    return commit_staged(png_stage(&a, path, px, row_rgb8, width, height, in, err), &a, err);
}

/* ---- OpenEXR ---------------------------------------------------------------- */

static int64_t exr_write_cb(exr_const_context_t ctxt, void *user, const void *buf, uint64_t sz, uint64_t off,
                            exr_stream_error_func_ptr_t error_cb)
{
    sss_atomic *a = user;
    if (sss_pwrite_all(a->fd, buf, (size_t)sz, off) != 0) {
        if (error_cb) error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed");
        return -1;
    }
    return (int64_t)sz;
}

static void exr_quiet(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt, (void)code, (void)msg;
}

/* Encodes into the temporary file of a (begun); on failure a is aborted. */
static sss_result exr_encode(sss_atomic *a, const char *path, const float *rgb, int width, int height, sss_error *err)
{
    /* EXR rows are top-down, GL's bottom-up: write from a flipped copy. */
    size_t rowf = (size_t)width * 3;
    float *img = malloc(rowf * (size_t)height * sizeof(float) + 1);
    if (!img) {
        sss_atomic_abort(a);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    for (int y = 0; y < height; y++) memcpy(img + rowf * y, rgb + rowf * (height - 1 - y), rowf * sizeof(float));
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_quiet;
    init.user_data = a;
    init.write_fn = exr_write_cb; /* into the temporary file, not a file OpenEXR opens */
    int part = 0;
    if (exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS) {
        free(img);
        sss_atomic_abort(a);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot start an OpenEXR file", path);
    }
    exr_result_t rv = exr_add_part(ctx, "rgb", EXR_STORAGE_SCANLINE, &part);
    if (!rv) rv = exr_initialize_required_attr_simple(ctx, part, width, height, EXR_COMPRESSION_ZIP);
    static const char *names[3] = {"B", "G", "R"}; /* EXR keeps channels sorted by name */
    for (int c = 0; c < 3 && !rv; c++) rv = exr_add_channel(ctx, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    if (!rv) rv = exr_set_version(ctx, part, 1);
    if (!rv) rv = exr_write_header(ctx);
    int32_t lines = 1;
    if (!rv) rv = exr_get_scanlines_per_chunk(ctx, part, &lines);
    exr_encode_pipeline_t enc;
    memset(&enc, 0, sizeof enc);
    int have_enc = 0;
    for (int y = 0; y < height && !rv; y += lines) {
        exr_chunk_info_t ci;
        rv = exr_write_scanline_chunk_info(ctx, part, y, &ci);
        if (rv) break;
        rv = have_enc ? exr_encoding_update(ctx, part, &ci, &enc) : exr_encoding_initialize(ctx, part, &ci, &enc);
        if (rv) break;
        const float *top = img + rowf * y;
        for (int c = 0; c < enc.channel_count; c++) {
            int k = enc.channels[c].channel_name[0] == 'R' ? 0 : enc.channels[c].channel_name[0] == 'G' ? 1 : 2;
            enc.channels[c].encode_from_ptr = (const uint8_t *)(top + k);
            enc.channels[c].user_pixel_stride = 3 * sizeof(float);
            enc.channels[c].user_line_stride = (int32_t)(rowf * sizeof(float));
            enc.channels[c].user_bytes_per_element = sizeof(float);
            enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
        }
        if (!have_enc) {
            rv = exr_encoding_choose_default_routines(ctx, part, &enc);
            have_enc = 1;
        }
        if (!rv) rv = exr_encoding_run(ctx, part, &enc);
    }
    if (have_enc) exr_encoding_destroy(ctx, &enc);
    exr_result_t fin = exr_finish(&ctx);
    free(img);
    if (rv || fin) {
        sss_atomic_abort(a);
        return sss_fail(err, SSS_ERR_IO, "%s: EXR write failed (%s)", path, exr_get_default_error_message(rv ? rv : fin));
    }
    return SSS_OK;
}

sss_result sss_write_exr_with(const char *path, const float *rgb, int width, int height, const sss_inputs *in,
                              sss_error *err)
{
    sss_atomic a;
    return commit_staged(stage(&a, 0, path, rgb, width, height, in, err), &a, err);
}

sss_result sss_write_exr(const char *path, const float *rgb, int width, int height, sss_error *err)
{
    return sss_write_exr_with(path, rgb, width, height, NULL, err);
}

static int ends_with(const char *s, const char *ext)
{
    size_t n = strlen(s), m = strlen(ext);
    if (n < m) return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != ext[i]) return 0;
    return 1;
}

int sss_image_type_known(const char *path) { return path && (ends_with(path, ".png") || ends_with(path, ".exr")); }

sss_result sss_image_stage(sss_atomic *a, const char *path, const float *ldr, const float *hdr, int width, int height,
                           const sss_inputs *in, sss_error *err)
{
    memset(a, 0, sizeof *a);
    a->fd = -1;
    const int png = ends_with(path, ".png");
    if (!png && !ends_with(path, ".exr"))
        return sss_fail(err, SSS_ERR_ARG, "%s: unknown image type (use .png or .exr)", path);
    return stage(a, png, path, png ? ldr : hdr ? hdr : ldr, width, height, in, err);
}

sss_result sss_write_image_with(const char *path, const float *ldr, const float *hdr, int width, int height,
                                const sss_inputs *in, sss_error *err)
{
    sss_atomic a;
    return commit_staged(sss_image_stage(&a, path, ldr, hdr, width, height, in, err), &a, err);
}

sss_result sss_write_image(const char *path, const float *ldr, const float *hdr, int width, int height, sss_error *err)
{
    return sss_write_image_with(path, ldr, hdr, width, height, NULL, err);
}
