/* image_error.h: image-space error of a .sss file's reconstruction against
 * the exact evaluator, following Hao–Varshney 2004 §3.3: images in [0, 1]
 * at one fixed exposure, ~100 random view and light directions, the RMS
 * over the pixels of each image, the maximum reported as the
 * representative (the mean and median too). Both images of a view are
 * drawn by the viewer's renderer (sss/render.h, EGL offscreen)
 * from per-vertex q supplied from outside: the exact q (sss/exact.h) and
 * the file's reconstruction (sss_decode_all_interp, bit for bit what the
 * viewer's GPU path computes for the default interpolation).
 *
 * This module belongs to the sss-stat tool, not to libsss_bake: it is the
 * one place where the precompute side draws with the runtime renderer
 * (docs/accuracy.md, "Why sss-stat links the renderer").
 */
#ifndef SSS_IMAGE_ERROR_H
#define SSS_IMAGE_ERROR_H

#include <stdint.h>
#include "sss/decode.h"
#include "sss/exact.h"
#include "sss/format.h"

typedef struct sss_image_error_opts {
    uint32_t views;         /* random (view, light) pairs; 0: 100 */
    uint64_t seed;          /* the pairs are drawn from this seed (a stream of their own) */
    int width, height;      /* image size; 0: 256 × 256 */
    double exposure;        /* fixed for every image; 0: automatic (see image_error.c) */
    sss_interp interp;      /* direction interpolation of the approximate image */
    const char *images_dir; /* if set: the worst view's exact, approx and error images go here */
    /* Files with OWNT: whose visibility the near terms of the approximate
     * image use — 0: the viewer's default (the renderer's GPU rays, what
     * sss-view shows); 1: the bake's ray on the CPU (sss_reconstruct_eval, as the
     * per-vertex error); 2: the renderer's shadow map of shadow_size². */
    int near_mode;
    int shadow_size;        /* near_mode 2: texels per side (0: the renderer's default) */
    const struct sss_inputs *inputs; /* files no image may be (the .sss measured: sss/fileio.h) */
    /* > 0: back-lit views, each light drawn uniformly within this many
     * degrees of the direction opposite the camera (the light behind the
     * object, its translucency and the terminators facing the camera);
     * 0: light and view independent and uniform */
    double backlit_deg;
    /* If set, the approximate image's q for a light comes from here (a
     * deforming object's per-frame path, deform_error.c) instead of f's
     * reconstruction, and f need hold the geometry only; 0 or an error */
    sss_result (*approx)(void *ctx, const double light[3], float *q, sss_error *err);
    void *approx_ctx;
} sss_image_error_opts;

typedef struct sss_image_error {
    uint32_t views;
    int width, height;
    double exposure;        /* the one used */
    double rms_max;         /* max over views of the per-image RMS: the paper's representative figure */
    double rms_mean, rms_median;
    double rms_max_covered; /* the worst image's RMS over the pixels the mesh covers only */
    double coverage_mean;   /* mean fraction of pixels covered by the mesh */
    uint32_t worst;         /* index of the worst view */
    double worst_light[3], worst_view[3];
    double error_map_gain;  /* error image = |approx − exact| × gain (the worst difference maps to 1) */
    /* A file with the vector integrals Q (section QVEC): approx is drawn
     * from Q, and each view is drawn from the same file's q rows too: their
     * image RMS against exact, and between the two (Hao–Varshney 2004
     * Fig. 4: q against Q); 0 without Q */
    int vector;
    double scalar_rms_max, scalar_rms_mean;
    double q_vs_Q_rms_max, q_vs_Q_rms_mean;
    char gl_renderer[128];  /* GL_RENDERER of the context used */
    double seconds;         /* wall time of the measurement */
} sss_image_error;

/* Measures f against e (built from f). Errors: SSS_ERR_UNSUPPORTED when no
 * OpenGL ≥ 4.3 context can be had (err says why: callers report the image
 * error as unavailable and go on), SSS_ERR_IO when an image cannot be
 * written (err names the path), SSS_ERR_NOMEM, SSS_ERR_ARG. Deterministic
 * for a given renderer (llvmpipe gives the same images on every run). */
sss_result sss_image_error_measure(const sss_bake_file *f, const sss_exact *e, const sss_image_error_opts *o,
                                   sss_image_error *out, sss_error *err);

/* The measure's figures as JSON members of im (the keys of `sss-stat
 * --json`'s "image_error": views, width, height, exposure, rms_max,
 * rms_mean, rms_median, rms_max_covered, coverage_mean, worst_view,
 * gl_renderer), for a file's measure and a deforming scene's alike. */
struct cJSON;
void sss_image_error_json(const sss_image_error *ie, struct cJSON *im);

/* Whether the six images of images_dir (exact, approx and error, as .png
 * and .exr) may be written (sss_output_check): for a refusal before the
 * measurement starts. */
sss_result sss_image_error_check_outputs(const char *images_dir, const struct sss_inputs *in, sss_error *err);

#endif
