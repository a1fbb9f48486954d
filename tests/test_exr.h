/* test_exr.h: OpenEXR probes of any channel layout for the tests
 * (header-only; needs OpenEXR): sss_probe_write writes float RGB only, and
 * the probe reader must take what HDR tools write too (half-float RGBA,
 * luminance alone, extra channels, compression) — docs/robustness.md,
 * item 1. Pixel (x, y), channel k gets test_exr_value(base, x, y, k). */
#ifndef SSS_TEST_EXR_H
#define SSS_TEST_EXR_H

#include <OpenEXR/openexr.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The value written: distinct per pixel and channel, exact in half for
 * small images (a multiple of 1/64 below 2). */
static inline float test_exr_value(float base, int x, int y, int k)
{
    return base * (1.0f + (float)((x * 7 + y * 3 + k * 5) % 32) / 64.0f);
}

/* float → half for normal values (round to nearest even); 0 stays 0. */
static inline uint16_t test_exr_half(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    const uint32_t s = (u >> 16) & 0x8000u;
    const int e = (int)((u >> 23) & 0xffu) - 127 + 15;
    uint32_t m = u & 0x7fffffu;
    if ((u & 0x7fffffffu) == 0) return (uint16_t)s;
    if (e <= 0) return (uint16_t)s;
    if (e >= 31) return (uint16_t)(s | 0x7c00u);
    uint32_t h = s | (uint32_t)e << 10 | m >> 13;
    const uint32_t rest = m & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (h & 1u))) h++;
    return (uint16_t)h;
}

/* Writes a scanline EXR of w x h pixels with the channels named by the
 * letters of chans (each one letter: "RGBA", "Y", "RGBZ" ...), all of
 * pixel type half (half != 0) or float, ZIP compressed when zip. 0 on
 * success. */
static inline int test_exr_write(const char *path, int w, int h, int half, const char *chans, float base, int zip)
{
    exr_context_t f;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    int part = 0;
    if (exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init) != EXR_ERR_SUCCESS) return -1;
    exr_result_t rv = exr_add_part(f, "main", EXR_STORAGE_SCANLINE, &part);
    if (!rv) rv = exr_initialize_required_attr_simple(f, part, w, h, zip ? EXR_COMPRESSION_ZIP : EXR_COMPRESSION_NONE);
    const int nc = (int)strlen(chans);
    for (int c = 0; c < nc && !rv; c++) {
        const char nm[2] = {chans[c], 0};
        rv = exr_add_channel(f, part, nm, half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
    }
    if (!rv) rv = exr_write_header(f);
    int32_t lines = 1;
    if (!rv) rv = exr_get_scanlines_per_chunk(f, part, &lines);
    const size_t es = half ? 2 : 4;
    uint8_t *buf = malloc((size_t)w * (size_t)lines * es * (size_t)(nc ? nc : 1));
    if (!buf) rv = EXR_ERR_OUT_OF_MEMORY;
    for (int y0 = 0; y0 < h && !rv; y0 += lines) {
        exr_chunk_info_t ci;
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        rv = exr_write_scanline_chunk_info(f, part, y0, &ci);
        if (!rv) rv = exr_encoding_initialize(f, part, &ci, &enc);
        if (rv) break;
        for (int c = 0; c < enc.channel_count; c++) {
            const int k = (int)(strchr(chans, enc.channels[c].channel_name[0]) - chans);
            uint8_t *plane = buf + (size_t)c * w * lines * es;
            for (int y = 0; y < ci.height; y++)
                for (int x = 0; x < w; x++) {
                    const float v = test_exr_value(base, x, y0 + y, k);
                    uint8_t *p = plane + ((size_t)y * w + x) * es;
                    if (half) {
                        const uint16_t hv = test_exr_half(v);
                        memcpy(p, &hv, 2);
                    } else {
                        memcpy(p, &v, 4);
                    }
                }
            enc.channels[c].encode_from_ptr = plane;
            enc.channels[c].user_pixel_stride = (int32_t)es;
            enc.channels[c].user_line_stride = (int32_t)(w * es);
            enc.channels[c].user_data_type = half ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
            enc.channels[c].user_bytes_per_element = (int16_t)es;
        }
        rv = exr_encoding_choose_default_routines(f, part, &enc);
        if (!rv) rv = exr_encoding_run(f, part, &enc);
        exr_encoding_destroy(f, &enc);
    }
    free(buf);
    exr_result_t fin = exr_finish(&f);
    return rv || fin ? -1 : 0;
}

#endif
