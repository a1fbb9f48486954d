/* image_io.h: writing rendered images. Input pixels are linear RGB floats,
 * 3 per pixel, rows bottom-up (as glReadPixels returns them). */
#ifndef SSS_IMAGE_IO_H
#define SSS_IMAGE_IO_H

#include "sss/result.h"

/* 8-bit sRGB PNG of values clamped to [0, 1]. */
sss_result sss_write_png(const char *path, const float *rgb, int width, int height, sss_error *err);

/* 32-bit float RGB OpenEXR (ZIP compression), through the
 * OpenEXR C API. Values are written as they are (no clamp, no curve). */
sss_result sss_write_exr(const char *path, const float *rgb, int width, int height, sss_error *err);

/* Chooses PNG or EXR from the extension (case-insensitive). */
sss_result sss_write_image(const char *path, const float *ldr, const float *hdr, int width, int height,
                           sss_error *err);

/* sRGB transfer function of a linear value in [0, 1]. */
float sss_srgb_encode(float x);

#endif
