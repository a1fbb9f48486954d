/* probe.c: OpenEXR lat-long environment probes (sss/probe.h) and their SH
 * projection, the lighting side of the environment effect: the bake
 * stores T_i(x) = ∫ q(x, ω) y_i(ω) dω per vertex, the renderer dots it with
 * the probe's L_i (docs/scenes.md "environment-sh").
 */
#define _POSIX_C_SOURCE 200809L
#include "sss/probe.h"

#include <OpenEXR/openexr.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "sss/fileio.h"
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

/* The OpenEXR stream reads the descriptor sss_input_open gave (a regular
 * file, opened without blocking: sss/fileio.h), never the path again. */
typedef struct probe_stream {
    int fd;
    uint64_t size;
} probe_stream;

static int64_t stream_read(exr_const_context_t ctxt, void *user, void *buf, uint64_t sz, uint64_t off,
                           exr_stream_error_func_ptr_t error_cb)
{
    const probe_stream *s = user;
    uint8_t *p = buf;
    uint64_t got = 0;
    while (got < sz) {
        ssize_t n = pread(s->fd, p + got, (size_t)(sz - got), (off_t)(off + got));
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            if (error_cb) error_cb(ctxt, EXR_ERR_READ_IO, "read failed");
            return -1;
        }
        if (n == 0) break; /* end of file: a short read, which the library reports */
        got += (uint64_t)n;
    }
    return (int64_t)got;
}

static int64_t stream_size(exr_const_context_t ctxt, void *user)
{
    (void)ctxt;
    return (int64_t)((const probe_stream *)user)->size;
}

/* Channel name → 0, 1, 2 for R (or Y), G, B; 3 for any other (alpha, ...). */
static int rgb_index(const char *nm)
{
    return !strcmp(nm, "R") || !strcmp(nm, "Y") ? 0 : !strcmp(nm, "G") ? 1 : !strcmp(nm, "B") ? 2 : 3;
}

sss_result sss_probe_read(const char *path, sss_probe *out, sss_error *err)
{
    return sss_probe_read_limited(path, 0, out, err);
}

sss_result sss_probe_read_limited(const char *path, uint64_t max_bytes, sss_probe *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    probe_stream ps;
    sss_result r = sss_input_open(path, &ps.fd, &ps.size, err);
    if (r != SSS_OK) return r;
    exr_context_t f = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_handler;
    init.user_data = &ps;
    init.read_fn = stream_read;
    init.size_fn = stream_size;
    exr_result_t rv = exr_start_read(&f, path, &init);
    if (rv != EXR_ERR_SUCCESS) {
        close(ps.fd);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: cannot read as OpenEXR (%s)", path, exr_get_default_error_message(rv));
    }
    float *scratch = NULL;
    exr_attr_box2i_t dw;
    exr_storage_t st;
    const exr_attr_chlist_t *chl = NULL;
    if (exr_get_data_window(f, 0, &dw) != EXR_ERR_SUCCESS || exr_get_storage(f, 0, &st) != EXR_ERR_SUCCESS ||
        exr_get_channels(f, 0, &chl) != EXR_ERR_SUCCESS || !chl) {
        r = sss_fail(err, SSS_ERR_FORMAT, "%s: OpenEXR: no data window or channel list", path);
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
    for (int c = 0; c < chl->num_channels; c++)
        if (chl->entries[c].x_sampling != 1 || chl->entries[c].y_sampling != 1) {
            r = sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: channel %.*s is subsampled (%d x %d): only full-resolution "
                         "probes are supported", path, chl->entries[c].name.length > 32 ? 32 : chl->entries[c].name.length,
                         chl->entries[c].name.str, chl->entries[c].x_sampling, chl->entries[c].y_sampling);
            goto done;
        }
    int32_t lines = 1;
    if (exr_get_scanlines_per_chunk(f, 0, &lines) != EXR_ERR_SUCCESS || lines < 1 || lines > 4096) {
        r = sss_fail(err, SSS_ERR_FORMAT, "%s: OpenEXR: bad scanlines per chunk", path);
        goto done;
    }
    /* Memory planned before anything of the probe's size is allocated: the
     * image (3 floats a pixel) and one chunk of scratch rows, against the
     * caller's limit (the bake's, docs/robustness.md "Memory") */
    const uint64_t need = 12u * (uint64_t)w * (uint64_t)h + 4u * (uint64_t)w * (uint64_t)lines;
    if (max_bytes && need > max_bytes) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: the probe needs at least %.2f GiB for %lld x %lld pixels but %.2f GiB is "
                     "available (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the limit): use a smaller probe",
                     path, need / 1073741824.0, (long long)w, (long long)h, max_bytes / 1073741824.0);
        goto done;
    }
    out->rgb = malloc((size_t)(3 * w * h) * sizeof(float));
    scratch = malloc((size_t)w * (size_t)lines * sizeof(float));
    if (!out->rgb || !scratch) { r = sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path); goto done; }
    int have[3] = {0, 0, 0};
    for (int c = 0; c < chl->num_channels; c++) {
        const int k = rgb_index(chl->entries[c].name.str);
        if (k < 3) have[k] = 1;
    }
    if (!have[0]) { r = sss_fail(err, SSS_ERR_FORMAT, "%s: OpenEXR probe has no R or Y channel", path); goto done; }
    for (int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t ci;
        exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
        if (exr_read_scanline_chunk_info(f, 0, (int)y, &ci) != EXR_ERR_SUCCESS ||
            exr_decoding_initialize(f, 0, &ci, &dec) != EXR_ERR_SUCCESS) {
            exr_decoding_destroy(f, &dec);
            r = sss_fail(err, SSS_ERR_CORRUPT, "%s: OpenEXR: cannot read scanline %lld", path, (long long)y);
            break;
        }
        const int64_t row0 = (int64_t)ci.start_y - dw.min.y;
        if (row0 < 0 || ci.height < 1 || ci.height > lines || row0 + ci.height > h) {
            exr_decoding_destroy(f, &dec);
            r = sss_fail(err, SSS_ERR_CORRUPT, "%s: OpenEXR: scanline %lld: chunk outside the data window", path,
                         (long long)y);
            break;
        }
        /* Every channel gets a destination: R, G, B (or Y) straight into
         * the interleaved image, any other (alpha, depth, ...) into the
         * scratch rows. A channel without one makes OpenEXR 3.1's unpacking
         * routines for half RGBA write through a NULL pointer. */
        for (int16_t c = 0; c < dec.channel_count; c++) {
            const int k = rgb_index(dec.channels[c].channel_name);
            dec.channels[c].decode_to_ptr =
                k < 3 ? (uint8_t *)(out->rgb + 3 * (size_t)row0 * (size_t)w + (size_t)k) : (uint8_t *)scratch;
            dec.channels[c].user_pixel_stride = k < 3 ? 3 * (int32_t)sizeof(float) : (int32_t)sizeof(float);
            dec.channels[c].user_line_stride = (int32_t)((k < 3 ? 3 : 1) * w * (int64_t)sizeof(float));
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
    if (r != SSS_OK) goto done;
    out->w = (uint32_t)w;
    out->h = (uint32_t)h;
    for (int64_t p = 0; p < w * h; p++)
        for (int k = 0; k < 3; k++) {
            float *v = &out->rgb[3 * (size_t)p + (size_t)k];
            if (!have[k]) *v = out->rgb[3 * (size_t)p]; /* a missing G or B copies R; Y alone is grey */
            if (!isfinite(*v) || *v < 0.0f) {
                r = sss_fail(err, SSS_ERR_FORMAT, "%s: pixel (%lld, %lld) channel %d is %g (radiance must be finite "
                             "and >= 0)", path, (long long)(p % w), (long long)(p / w), k, (double)*v);
                goto done;
            }
        }
done:
    free(scratch);
    if (r != SSS_OK) sss_probe_free(out);
    exr_finish(&f);
    close(ps.fd);
    return r;
}

static int64_t stream_write(exr_const_context_t ctxt, void *user, const void *buf, uint64_t sz, uint64_t off,
                            exr_stream_error_func_ptr_t error_cb)
{
    const sss_atomic *a = user;
    if (sss_pwrite_all(a->fd, buf, (size_t)sz, off) != 0) {
        if (error_cb) error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed");
        return -1;
    }
    return (int64_t)sz;
}

sss_result sss_probe_write(const char *path, const sss_probe *p, sss_error *err)
{
    return sss_probe_write_with(path, p, NULL, err);
}

sss_result sss_probe_write_with(const char *path, const sss_probe *p, const struct sss_inputs *in, sss_error *err)
{
    /* atomically, to a path the output policy allows (sss/fileio.h) */
    sss_atomic at;
    sss_result r = sss_probe_write_staged(&at, path, p, in, err);
    return r != SSS_OK ? r : sss_atomic_commit(&at, err);
}

sss_result sss_probe_write_staged(sss_atomic *out, const char *path, const sss_probe *p, const struct sss_inputs *in,
                                  sss_error *err)
{
    sss_result r = sss_atomic_begin(out, path, in, err);
    if (r != SSS_OK) return r;
    exr_context_t f = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = quiet_handler;
    init.user_data = out;
    init.write_fn = stream_write;
    exr_result_t rv = exr_start_write(&f, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        sss_atomic_abort(out);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot create OpenEXR file", path);
    }
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
    if (rv != EXR_ERR_SUCCESS || fin != EXR_ERR_SUCCESS) {
        sss_atomic_abort(out);
        return sss_fail(err, SSS_ERR_IO, "%s: writing OpenEXR failed (%s)", path,
                        exr_get_default_error_message(rv != EXR_ERR_SUCCESS ? rv : fin));
    }
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
