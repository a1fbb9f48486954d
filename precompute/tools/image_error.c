/* image_error.c: image-space error against the exact evaluator
 * (image_error.h; Hao–Varshney 2004 §3.3, the protocol behind Fig. 5):
 *
 *   e_rms = [ 1/(M N) Σ_x Σ_y (f̂(x, y) − f(x, y))² ]^½,  f, f̂ in [0, 1],
 *
 * f the image drawn with the exact q, f̂ with the file's reconstruction, per
 * colour channel as well (the mean over the 3 channels of M·N pixels), for
 * `views` random view directions, each with its own random light direction;
 * the maximum over the views is the paper's representative figure.
 *
 * Conventions (docs/accuracy.md):
 *  - the subsurface term alone (L = E q F_t, §3.2): the specular term is
 *    the same in both images and would only hide error where it clips;
 *  - clamp tone mapping (the measurement convention of renderer.h), black
 *    background, every pixel counted (as the paper's formula does);
 *  - one exposure for every image: given, or automatic = 1 / P99.9, the
 *    99.9th percentile of the positive exact q over all vertices and
 *    channels pooled over the six axis light directions, so that the
 *    brightest 0.1 % of lit values reach 1;
 *  - light directions never on a direction sample (sss_vertex_error_draw_direction);
 *  - a file with OWNT (near terms at run time): the renderer adds them as
 *    the viewer does (its GPU rays, or its shadow map on request), or the
 *    tool adds them with the bake's ray on the CPU (sss_reconstruct_eval).
 *
 * The renderer is given a geometry-only view of the file (no direction
 * rows): q is always supplied per vertex (sss_renderer_upload_q), so the
 * scattering data need not be uploaded, whatever its size.
 */
#define _POSIX_C_SOURCE 200809L /* mkdir under -std=c11 */
#include <cjson/cJSON.h>

#include "sss/clock.h"
#include "image_error.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sss/fileio.h"
#include "sss/random.h"
#include "sss/vec3.h"
#include "sss/reconstruct.h"
#include "sss/render.h"
#include "sss/vertex_error.h"

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Automatic exposure (see the top of this file). */
static double auto_exposure(const sss_exact *e, size_t n, float *q)
{
    static const double axis[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    float *pos = malloc(6 * n * sizeof *pos);
    if (!pos) return 1.0;
    size_t m = 0;
    for (int a = 0; a < 6; a++) {
        sss_exact_eval(e, axis[a], q);
        for (size_t i = 0; i < n; i++)
            if (q[i] > 0.0f && isfinite(q[i])) pos[m++] = q[i];
    }
    double s = 0.0;
    if (m) {
        qsort(pos, m, sizeof *pos, cmp_float);
        s = pos[(size_t)floor(0.999 * (double)(m - 1))];
    }
    free(pos);
    return s > 0.0 && isfinite(s) ? 1.0 / s : 1.0;
}

/* A light uniform on the cap within deg degrees of −view, off every
 * direction sample (as sss_vertex_error_draw_direction). */
static void draw_backlit(const sss_dirset *ds, uint64_t *state, const double view[3], double deg, double light[3])
{
    const double cmax = cos(deg * SSS_PI / 180.0);
    for (;;) {
        double d[3];
        sss_rng_direction(state, d);
        if (-(d[0] * view[0] + d[1] * view[1] + d[2] * view[2]) < cmax) continue;
        double best = -2.0;
        for (uint32_t j = 0; j < ds->n; j++) {
            const double *w = ds->dir + 3 * (size_t)j;
            best = fmax(best, d[0] * w[0] + d[1] * w[1] + d[2] * w[2]);
        }
        if (best < cos(1e-6)) {
            for (int k = 0; k < 3; k++) light[k] = d[k];
            return;
        }
    }
}

/* The worst view's images, by name and extension (--error-images DIR). */
static const char *const image_names[6] = {"exact.png", "exact.exr", "approx.png", "approx.exr", "error.png",
                                           "error.exr"};

static void image_path(char *path, size_t n, const char *dir, int k) { snprintf(path, n, "%s/%s", dir, image_names[k]); }

sss_result sss_image_error_check_outputs(const char *dir, const sss_inputs *in, sss_error *err)
{
    for (int k = 0; k < 6; k++) {
        char path[4096];
        image_path(path, sizeof path, dir, k);
        sss_result r = sss_output_check(path, in, NULL, err);
        if (r != SSS_OK) return r;
    }
    return SSS_OK;
}

/* All six images, or none: each is staged into a temporary file first,
 * and they replace their targets only when every one is complete
 * (sss/fileio.h). img[k/2·2] is the ldr image of pair k/2, img[k/2·2+1]
 * its hdr one. */
static sss_result write_images(const char *dir, const float *const img[6], int w, int h, const sss_inputs *in,
                               sss_error *err)
{
    sss_atomic a[6];
    int staged = 0;
    sss_result r = SSS_OK;
    for (int k = 0; k < 6 && r == SSS_OK; k++) {
        char path[4096];
        image_path(path, sizeof path, dir, k);
        const float *ldr = img[k / 2 * 2], *hdr = img[k / 2 * 2 + 1];
        r = sss_image_stage(&a[k], path, ldr, hdr, w, h, in, err);
        if (r == SSS_OK) staged = k + 1;
    }
    for (int k = 0; k < staged; k++) {
        if (r == SSS_OK) r = sss_atomic_commit(&a[k], err);
        else sss_atomic_abort(&a[k]);
    }
    return r;
}

sss_result sss_image_error_measure(const sss_bake_file *f, const sss_exact *e, const sss_image_error_opts *o,
                                   sss_image_error *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (!f || !e || !o) return sss_fail(err, SSS_ERR_ARG, "image error: NULL argument");
    const double t0 = sss_now();
    const uint32_t views = o->views ? o->views : 100;
    const int W = o->width > 0 ? o->width : 256, H = o->height > 0 ? o->height : 256;
    const size_t nv = f->mesh.nv, C = f->channels, npx = (size_t)W * H;
    if (o->images_dir && mkdir(o->images_dir, 0777) != 0 && errno != EEXIST)
        return sss_fail(err, SSS_ERR_IO, "%s: cannot create the image directory: %s", o->images_dir, strerror(errno));
    /* every image path checked before the measurement (sss/fileio.h);
     * the writer checks each again */
    if (o->images_dir) {
        sss_result rc = sss_image_error_check_outputs(o->images_dir, o->inputs, err);
        if (rc != SSS_OK) return rc;
    }

    sss_offscreen *ctx = NULL;
    sss_result res = sss_offscreen_create(&ctx, err);
    if (res != SSS_OK) return SSS_ERR_UNSUPPORTED;
    snprintf(out->gl_renderer, sizeof out->gl_renderer, "%s", sss_gl_renderer_name());
    /* geometry only: q comes from outside (see the top of this file) */
    sss_bake_file g = *f;
    g.quant = SSS_QUANT_FLOAT;
    g.dirs.n = 0;
    g.q = NULL;
    g.qvec = NULL; /* Q too (section QVEC): both images' q is uploaded */
    /* with OWNT and the viewer's visibility the renderer adds the near terms
     * itself (its shadow map); otherwise q is supplied whole */
    const int map_vis = f->near_terms && o->near_mode != 1; /* the renderer adds the near terms */
    if (!map_vis) g.near_terms = 0;
    sss_renderer *ren = NULL;
    res = sss_renderer_create(&g, &ren, err);
    if (res != SSS_OK) {
        sss_offscreen_destroy(ctx);
        return res == SSS_ERR_NOMEM ? res : SSS_ERR_UNSUPPORTED;
    }

    float *qx = malloc(nv * C * sizeof *qx), *qa = malloc(nv * C * sizeof *qa);
    double *rms = malloc(views * sizeof *rms);
    float *worst[4] = {NULL, NULL, NULL, NULL}; /* exact ldr, exact hdr, approx ldr, approx hdr */
    /* what a reader shows (sss/reconstruct.h): the rows, plus the own term of an
     * OWNT file with the vertex's own visibility by a ray */
    sss_reconstruct *rc = NULL;
    /* a file with Q: its q rows drawn too (rs), the same file without QVEC */
    sss_bake_file fs = *f;
    fs.qvec = NULL;
    sss_reconstruct *rs = NULL;
    float *qs = f->qvec ? malloc(nv * C * sizeof *qs) : NULL;
    out->vector = f->qvec != NULL;
    if (!qx || !qa || !rms || (f->qvec && !qs)) {
        res = sss_fail(err, SSS_ERR_NOMEM, "image error: out of memory for %zu vertices", nv);
        goto done;
    }
    if (!o->approx && (res = sss_reconstruct_create(f, &rc, err)) != SSS_OK) goto done;
    if (!o->approx && f->qvec && (res = sss_reconstruct_create(&fs, &rs, err)) != SSS_OK) goto done;
    out->exposure = o->exposure > 0.0 ? o->exposure : auto_exposure(e, nv * C, qx);
    out->views = views;
    out->width = W;
    out->height = H;

    sss_view_params p;
    sss_view_params_default(&p);
    p.specular = 0;
    p.exposure = out->exposure;
    p.tonemap = SSS_TONEMAP_CLAMP;
    p.shadow_size = o->shadow_size;
    p.near_visibility = o->near_mode == 2 ? SSS_NEAR_MAP : SSS_NEAR_RAYS;
    /* a stream of its own, so that the per-vertex measure's directions
     * (same seed) are not these */
    uint64_t state = o->seed ^ 0x696d616765657272ull; /* "imageerr" */
    double cover_sum = 0.0;
    out->rms_max = -1.0;
    for (uint32_t v = 0; v < views; v++) {
        double view[3], light[3];
        sss_rng_direction(&state, view);
        if (o->backlit_deg > 0.0) draw_backlit(&f->dirs, &state, view, o->backlit_deg, light);
        else sss_vertex_error_draw_direction(&f->dirs, &state, light);
        for (int k = 0; k < 3; k++) p.view[k] = view[k], p.light[k] = light[k];
        sss_exact_eval(e, light, qx);
        if (o->approx) {
            if ((res = o->approx(o->approx_ctx, light, qa, err)) != SSS_OK) goto done;
        } else if (map_vis) {
            sss_reconstruct_eval_rows(rc, light, o->interp, qa);
        } else {
            sss_reconstruct_eval(rc, light, o->interp, qa);
        }
        float *ex = NULL, *exh = NULL, *ap = NULL, *aph = NULL;
        p.near_terms = 0; /* the exact q is whole */
        res = sss_renderer_render_q_image(ren, &p, qx, W, H, &ex, &exh, err);
        p.near_terms = map_vis;
        if (res == SSS_OK) res = sss_renderer_render_q_image(ren, &p, qa, W, H, &ap, &aph, err);
        if (res != SSS_OK) {
            free(ex); free(exh); free(ap); free(aph);
            goto done;
        }
        double s = 0.0, sc = 0.0;
        size_t covered = 0;
        for (size_t i = 0; i < npx; i++) {
            double d2 = 0.0;
            int cov = 0;
            for (int c = 0; c < 3; c++) {
                double d = (double)ap[3 * i + c] - (double)ex[3 * i + c];
                d2 += d * d;
                /* covered: a mesh pixel lit in either image (an unlit mesh
                 * pixel is black like the background and has no error) */
                cov |= ex[3 * i + c] > 0.0f || ap[3 * i + c] > 0.0f;
            }
            s += d2;
            if (cov) sc += d2, covered++;
        }
        rms[v] = sqrt(s / (3.0 * (double)npx));
        cover_sum += (double)covered / (double)npx;
        if (rms[v] > out->rms_max) {
            out->rms_max = rms[v];
            out->rms_max_covered = covered ? sqrt(sc / (3.0 * (double)covered)) : 0.0;
            out->worst = v;
            for (int k = 0; k < 3; k++) out->worst_light[k] = light[k], out->worst_view[k] = view[k];
            if (o->images_dir) {
                for (int k = 0; k < 4; k++) free(worst[k]);
                worst[0] = ex, worst[1] = exh, worst[2] = ap, worst[3] = aph;
                ex = exh = ap = aph = NULL;
            }
        }
        if (rs) { /* q's rows: against exact, and against Q's image */
            if (map_vis) sss_reconstruct_eval_rows(rs, light, o->interp, qs);
            else sss_reconstruct_eval(rs, light, o->interp, qs);
            float *sp = NULL, *sph = NULL;
            res = sss_renderer_render_q_image(ren, &p, qs, W, H, &sp, &sph, err);
            if (res != SSS_OK) {
                free(ex); free(exh); free(ap); free(aph);
                goto done;
            }
            double se = 0.0, sq = 0.0;
            for (size_t i = 0; i < 3 * npx; i++) {
                const double a = (double)sp[i] - (double)ex[i], b = (double)sp[i] - (double)ap[i];
                se += a * a;
                sq += b * b;
            }
            se = sqrt(se / (3.0 * (double)npx));
            sq = sqrt(sq / (3.0 * (double)npx));
            out->scalar_rms_max = fmax(out->scalar_rms_max, se);
            out->q_vs_Q_rms_max = fmax(out->q_vs_Q_rms_max, sq);
            out->scalar_rms_mean += se / views;
            out->q_vs_Q_rms_mean += sq / views;
            free(sp);
            free(sph);
        }
        free(ex); free(exh); free(ap); free(aph);
    }
    {
        double sum = 0.0;
        for (uint32_t v = 0; v < views; v++) sum += rms[v];
        out->rms_mean = sum / views;
        qsort(rms, views, sizeof *rms, cmp_double);
        out->rms_median = views % 2 ? rms[views / 2] : 0.5 * (rms[views / 2 - 1] + rms[views / 2]);
        out->coverage_mean = cover_sum / views;
    }
    if (o->images_dir && worst[0]) {
        /* error map: |approx − exact| per channel, scaled so the largest
         * difference is 1 (the gain is reported); the EXR holds the raw
         * signed difference approx − exact of the tone-mapped images */
        float *em = malloc(npx * 3 * sizeof *em), *ed = malloc(npx * 3 * sizeof *ed);
        if (!em || !ed) {
            free(em); free(ed);
            res = sss_fail(err, SSS_ERR_NOMEM, "image error: out of memory for the error map");
            goto done;
        }
        double mx = 0.0;
        for (size_t i = 0; i < 3 * npx; i++) {
            ed[i] = worst[2][i] - worst[0][i];
            mx = fmax(mx, fabs(ed[i]));
        }
        out->error_map_gain = mx > 0.0 ? 1.0 / mx : 0.0;
        for (size_t i = 0; i < 3 * npx; i++) em[i] = (float)(fabs(ed[i]) * out->error_map_gain);
        const float *const img[6] = {worst[0], worst[1], worst[2], worst[3], em, ed};
        res = write_images(o->images_dir, img, W, H, o->inputs, err);
        free(em);
        free(ed);
        if (res != SSS_OK) goto done;
    }
    res = SSS_OK;
done:
    for (int k = 0; k < 4; k++) free(worst[k]);
    free(qx);
    free(qa);
    free(qs);
    free(rms);
    sss_reconstruct_destroy(rc);
    sss_reconstruct_destroy(rs);
    sss_renderer_destroy(ren);
    sss_offscreen_destroy(ctx);
    out->seconds = sss_now() - t0;
    return res;
}

void sss_image_error_json(const sss_image_error *ie, cJSON *im)
{
    cJSON_AddNumberToObject(im, "views", ie->views);
    cJSON_AddNumberToObject(im, "width", ie->width);
    cJSON_AddNumberToObject(im, "height", ie->height);
    cJSON_AddNumberToObject(im, "exposure", ie->exposure);
    cJSON_AddNumberToObject(im, "rms_max", ie->rms_max);
    cJSON_AddNumberToObject(im, "rms_mean", ie->rms_mean);
    cJSON_AddNumberToObject(im, "rms_median", ie->rms_median);
    cJSON_AddNumberToObject(im, "rms_max_covered", ie->rms_max_covered);
    cJSON_AddNumberToObject(im, "coverage_mean", ie->coverage_mean);
    cJSON *w = cJSON_AddObjectToObject(im, "worst_view");
    cJSON_AddNumberToObject(w, "index", ie->worst);
    cJSON_AddItemToObject(w, "light", cJSON_CreateDoubleArray(ie->worst_light, 3));
    cJSON_AddItemToObject(w, "view", cJSON_CreateDoubleArray(ie->worst_view, 3));
    cJSON_AddStringToObject(im, "gl_renderer", ie->gl_renderer);
}
