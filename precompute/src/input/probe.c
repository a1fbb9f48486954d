/* probe.c: OpenEXR lat-long environment probes (sss/probe.h) and their SH
 * projection, the lighting side of the environment effect: the bake
 * stores T_i(x) = ∫ q(x, ω) y_i(ω) dω per vertex, the renderer dots it with
 * the probe's L_i (docs/scenes.md "environment-sh").
 */
#include "sss/probe.h"

#include <OpenEXR/openexr.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/sh.h"
#include "sss/vec3.h"

void sss_probe_free(sss_probe *p)
{
    if (!p) return;
    free(p->rgb);
    memset(p, 0, sizeof *p);
}

/* silence OpenEXR's default error printer: we report through sss_error */
static void quiet_handler(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt, (void)code, (void)msg;
}

sss_result sss_probe_read(const char *path, sss_probe *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    exr_context_t f = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_handler;
    exr_result_t rv = exr_start_read(&f, path, &init);
    if (rv != EXR_ERR_SUCCESS) return sss_fail(err, SSS_ERR_IO, "%s: cannot read as OpenEXR (%s)", path, exr_get_default_error_message(rv));
    sss_result r = SSS_OK;
    exr_attr_box2i_t dw;
    exr_storage_t st;
    if (exr_get_data_window(f, 0, &dw) != EXR_ERR_SUCCESS || exr_get_storage(f, 0, &st) != EXR_ERR_SUCCESS) {
        r = sss_fail(err, SSS_ERR_FORMAT, "%s: OpenEXR: no data window", path);
        goto done;
    }
    if (st != EXR_STORAGE_SCANLINE) {
        r = sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: only scanline OpenEXR probes are supported", path);
        goto done;
    }
    const int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;
    if (w < 2 || h < 1 || w > 65536 || h > 65536) {
        r = sss_fail(err, SSS_ERR_FORMAT, "%s: probe size %lld x %lld out of range", path, (long long)w, (long long)h);
        goto done;
    }
    float *buf = calloc((size_t)(3 * w * h), sizeof(float)); /* R, G, B planes */
    if (!buf) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path); goto done; }
    int32_t lines = 1;
    exr_get_scanlines_per_chunk(f, 0, &lines);
    int have[3] = {0, 0, 0};
    for (int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t ci;
        exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
        if (exr_read_scanline_chunk_info(f, 0, (int)y, &ci) != EXR_ERR_SUCCESS ||
            exr_decoding_initialize(f, 0, &ci, &dec) != EXR_ERR_SUCCESS) {
            r = sss_fail(err, SSS_ERR_CORRUPT, "%s: OpenEXR: cannot read scanline %lld", path, (long long)y);
            break;
        }
        for (int16_t c = 0; c < dec.channel_count; c++) {
            const char *nm = dec.channels[c].channel_name;
            int k = !strcmp(nm, "R") || !strcmp(nm, "Y") ? 0 : !strcmp(nm, "G") ? 1 : !strcmp(nm, "B") ? 2 : 3;
            if (k < 3) have[k] = 1;
            dec.channels[c].decode_to_ptr = /* other channels: NULL, skipped */
                k < 3 ? (uint8_t *)(buf + (size_t)k * w * h + (size_t)(ci.start_y - dw.min.y) * w) : NULL;
            dec.channels[c].user_pixel_stride = sizeof(float);
            dec.channels[c].user_line_stride = (int32_t)(w * sizeof(float));
            dec.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            dec.channels[c].user_bytes_per_element = sizeof(float);
        }
        rv = exr_decoding_choose_default_routines(f, 0, &dec);
        if (rv == EXR_ERR_SUCCESS) rv = exr_decoding_run(f, 0, &dec);
        exr_decoding_destroy(f, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            r = sss_fail(err, SSS_ERR_CORRUPT, "%s: OpenEXR: scanline %lld: %s", path, (long long)y, exr_get_default_error_message(rv));
            break;
        }
    }
    if (r == SSS_OK && !have[0]) r = sss_fail(err, SSS_ERR_FORMAT, "%s: OpenEXR probe has no R or Y channel", path);
    if (r != SSS_OK) { free(buf); goto done; }
    out->w = (uint32_t)w;
    out->h = (uint32_t)h;
    out->rgb = malloc((size_t)(3 * w * h) * sizeof(float));
    if (!out->rgb) { free(buf); r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path); goto done; }
    for (int64_t p = 0; p < w * h; p++)
        for (int k = 0; k < 3; k++) {
            float v = buf[(size_t)(have[k] ? k : 0) * w * h + p];
            if (!isfinite(v) || v < 0.0f) {
                free(buf);
                sss_probe_free(out);
                r = sss_fail(err, SSS_ERR_FORMAT, "%s: pixel (%lld, %lld) channel %d is %g (radiance must be finite "
                             "and >= 0)", path, (long long)(p % w), (long long)(p / w), k, (double)v);
                goto done;
            }
            out->rgb[3 * p + k] = v;
        }
    free(buf);
done:
    exr_finish(&f);
    return r;
}

sss_result sss_probe_write(const char *path, const sss_probe *p, sss_error *err)
{
    exr_context_t f = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_handler;
    exr_result_t rv = exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) return sss_fail(err, SSS_ERR_IO, "%s: cannot create OpenEXR file", path);
    int part = 0;
    const char *names[3] = {"B", "G", "R"}; /* OpenEXR keeps channels sorted */
    rv = exr_add_part(f, "main", EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS) rv = exr_initialize_required_attr_simple(f, part, (int32_t)p->w, (int32_t)p->h, EXR_COMPRESSION_NONE);
    for (int c = 0; c < 3 && rv == EXR_ERR_SUCCESS; c++)
        rv = exr_add_channel(f, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
    if (rv == EXR_ERR_SUCCESS) rv = exr_write_header(f);
    float *planes = rv == EXR_ERR_SUCCESS ? malloc((size_t)3 * p->w * p->h * sizeof(float)) : NULL;
    if (rv == EXR_ERR_SUCCESS && !planes) rv = EXR_ERR_OUT_OF_MEMORY;
    if (planes)
        for (size_t k = 0; k < (size_t)p->w * p->h; k++)
            for (int c = 0; c < 3; c++) planes[(size_t)c * p->w * p->h + k] = p->rgb[3 * k + (size_t)(2 - c)];
    int32_t lines = 1;
    if (rv == EXR_ERR_SUCCESS) exr_get_scanlines_per_chunk(f, part, &lines);
    for (int32_t y = 0; y < (int32_t)p->h && rv == EXR_ERR_SUCCESS; y += lines) {
        exr_chunk_info_t ci;
        exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
        rv = exr_write_scanline_chunk_info(f, part, y, &ci);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_initialize(f, part, &ci, &enc);
        if (rv != EXR_ERR_SUCCESS) break;
        for (int16_t c = 0; c < enc.channel_count; c++) {
            int k = !strcmp(enc.channels[c].channel_name, "B") ? 0 : !strcmp(enc.channels[c].channel_name, "G") ? 1 : 2;
            enc.channels[c].encode_from_ptr = (const uint8_t *)(planes + (size_t)k * p->w * p->h + (size_t)y * p->w);
            enc.channels[c].user_pixel_stride = sizeof(float);
            enc.channels[c].user_line_stride = (int32_t)(p->w * sizeof(float));
            enc.channels[c].user_data_type = EXR_PIXEL_FLOAT;
            enc.channels[c].user_bytes_per_element = sizeof(float);
        }
        rv = exr_encoding_choose_default_routines(f, part, &enc);
        if (rv == EXR_ERR_SUCCESS) rv = exr_encoding_run(f, part, &enc);
        exr_encoding_destroy(f, &enc);
    }
    free(planes);
    exr_result_t fin = exr_finish(&f);
    if (rv != EXR_ERR_SUCCESS || fin != EXR_ERR_SUCCESS)
        return sss_fail(err, SSS_ERR_IO, "%s: writing OpenEXR failed (%s)", path,
                        exr_get_default_error_message(rv != EXR_ERR_SUCCESS ? rv : fin));
    return SSS_OK;
}

void sss_probe_pixel_dir(uint32_t w, uint32_t h, uint32_t x, uint32_t y, double d[3], double *domega)
{
    const double th = SSS_PI * (y + 0.5) / h, ph = 2.0 * SSS_PI * (x + 0.5) / w;
    d[0] = sin(th) * cos(ph);
    d[1] = sin(th) * sin(ph);
    d[2] = cos(th);
    /* exact solid angle of the pixel's latitude band slice */
    const double t0 = SSS_PI * y / h, t1 = SSS_PI * (y + 1.0) / h;
    *domega = (2.0 * SSS_PI / w) * (cos(t0) - cos(t1));
}

void sss_probe_sh(const sss_probe *p, uint32_t order, double *L)
{
    const uint32_t K = sss_sh_count(order);
    memset(L, 0, 3 * (size_t)K * sizeof *L);
    double y[SSS_SH_MAX_COUNT];
    for (uint32_t py = 0; py < p->h; py++)
        for (uint32_t px = 0; px < p->w; px++) {
            double d[3], dw;
            sss_probe_pixel_dir(p->w, p->h, px, py, d, &dw);
            sss_sh_eval(order, d, y);
            const float *c = &p->rgb[3 * ((size_t)py * p->w + px)];
            for (int k = 0; k < 3; k++)
                for (uint32_t i = 0; i < K; i++) L[(size_t)k * K + i] += c[k] * y[i] * dw;
        }
}
