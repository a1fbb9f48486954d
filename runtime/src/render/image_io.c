/* image_io.c: PNG (libpng) and OpenEXR (C API, openexr.h) writers (sss_write_*, sss/render.h). */
#include "sss/render.h"

#include <ctype.h>
#include <math.h>
#include <openexr.h>
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

float sss_srgb_encode(float x)
{
    x = x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
    return x <= 0.0031308f ? 12.92f * x : 1.055f * powf(x, 1.0f / 2.4f) - 0.055f;
}

sss_result sss_write_png(const char *path, const float *rgb, int width, int height, sss_error *err)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return sss_fail(err, SSS_ERR_IO, "%s: cannot open for writing", path);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    unsigned char *row = malloc((size_t)width * 3);
    if (!png || !info || !row) {
        png_destroy_write_struct(&png, &info);
        free(row);
        fclose(fp);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        free(row);
        fclose(fp);
        return sss_fail(err, SSS_ERR_IO, "%s: PNG write failed", path);
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)width, (png_uint_32)height, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    for (int y = height - 1; y >= 0; y--) { /* GL rows are bottom-up */
        const float *src = rgb + (size_t)y * width * 3;
        for (int i = 0; i < width * 3; i++) row[i] = (unsigned char)lrintf(255.0f * sss_srgb_encode(src[i]));
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(row);
    if (fclose(fp) != 0) return sss_fail(err, SSS_ERR_IO, "%s: write failed", path);
    return SSS_OK;
}

sss_result sss_write_exr(const char *path, const float *rgb, int width, int height, sss_error *err)
{
    /* EXR rows are top-down, GL's bottom-up: write from a flipped copy. */
    size_t rowf = (size_t)width * 3;
    float *img = malloc(rowf * (size_t)height * sizeof(float) + 1);
    if (!img) return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    for (int y = 0; y < height; y++) memcpy(img + rowf * y, rgb + rowf * (height - 1 - y), rowf * sizeof(float));
    exr_context_t ctx;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int part = 0;
    if (exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS) {
        free(img);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot open for writing", path);
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
    if (rv || fin) return sss_fail(err, SSS_ERR_IO, "%s: EXR write failed (%s)", path, exr_get_default_error_message(rv ? rv : fin));
    return SSS_OK;
}

static int ends_with(const char *s, const char *ext)
{
    size_t n = strlen(s), m = strlen(ext);
    if (n < m) return 0;
    for (size_t i = 0; i < m; i++)
        if (tolower((unsigned char)s[n - m + i]) != ext[i]) return 0;
    return 1;
}

sss_result sss_write_image(const char *path, const float *ldr, const float *hdr, int width, int height, sss_error *err)
{
    if (ends_with(path, ".png")) return sss_write_png(path, ldr, width, height, err);
    if (ends_with(path, ".exr")) return sss_write_exr(path, hdr ? hdr : ldr, width, height, err);
    return sss_fail(err, SSS_ERR_ARG, "%s: unknown image type (use .png or .exr)", path);
}
