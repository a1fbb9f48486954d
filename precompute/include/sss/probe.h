/* sss/probe.h: environment probes, OpenEXR lat-long images (docs/scenes.md),
 * read and written with the OpenEXR 3.1 core C API, and projected onto the
 * real SH basis of sss/sh.h.
 *
 * Lat-long convention: +z is up; row y (0 at the top) is the polar angle
 * θ = π (y + ½) / H from +z, column x the azimuth φ = 2π (x + ½) / W from +x
 * towards +y; ω = (sin θ cos φ, sin θ sin φ, cos θ). Pixels hold radiance
 * (linear RGB) arriving from ω.
 */
#ifndef SSS_PROBE_H
#define SSS_PROBE_H

#include <stdint.h>
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sss_probe {
    uint32_t w, h;
    float *rgb;      /* 3 * w * h, row-major from the top row; owned */
} sss_probe;

/* Reads R, G, B (a missing G or B copies R; Y alone is grey; any other
 * channel, alpha included, is read and dropped) of the first part of a
 * scanline EXR of full-resolution channels (any pixel type). The file is
 * opened as every input is (sss/fileio.h: a regular file only, never
 * blocking). Pixels must be finite and >= 0. Errors name the file. */
sss_result sss_probe_read(const char *path, sss_probe *out, sss_error *err);

/* The same, refusing before allocating (SSS_ERR_NOMEM, the bake's one-line
 * wording) a probe whose pixels need more than max_bytes (0: no limit). */
sss_result sss_probe_read_limited(const char *path, uint64_t max_bytes, sss_probe *out, sss_error *err);

/* Writes a scanline EXR with float R, G, B, no compression (tests),
 * atomically (sss/fileio.h). */
sss_result sss_probe_write(const char *path, const sss_probe *p, sss_error *err);
/* The same, refusing a path that is one of the files in (sss/fileio.h). */
struct sss_inputs;
sss_result sss_probe_write_with(const char *path, const sss_probe *p, const struct sss_inputs *in, sss_error *err);
/* The same, staged: the file is written to *out's temporary file and becomes
 * the content of path only at sss_atomic_commit(out) (sss_atomic_abort
 * throws it away), so that a tool writing several files writes all or none.
 * On failure nothing is left and *out is released. */
struct sss_atomic;
sss_result sss_probe_write_staged(struct sss_atomic *out, const char *path, const sss_probe *p,
                                  const struct sss_inputs *in, sss_error *err);

void sss_probe_free(sss_probe *p);

/* Direction of pixel (x, y) and its solid angle. */
void sss_probe_pixel_dir(uint32_t w, uint32_t h, uint32_t x, uint32_t y, double d[3], double *domega);

/* L_i = Σ_pixels L(ω_p) y_i(ω_p) dΩ_p for i < order², per channel:
 * L[c * order² + i]. */
void sss_probe_sh(const sss_probe *p, uint32_t order, double *L);

#ifdef __cplusplus
}
#endif
#endif
