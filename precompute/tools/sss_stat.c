/* sss-stat: what a .sss file holds and where its bytes go; with --query,
 * the exact q at one vertex for one light direction next to what the stored
 * data reconstruct there (Hao–Varshney 2004 §3.1 against §3.2 / §4); with
 * --error, the per-vertex and the image-space error of the whole file
 * against the exact evaluator (§3.3's protocol; image_error.h). */
#include <cjson/cJSON.h>
#include <ctype.h>
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/cli.h"
#include "image_error.h"
#include "deform_error.h"
#include "sss/render.h" /* SSS_SHADOW_SIZE, the viewer's default map */
#include "sss/decode.h"
#include "sss/vertex_error.h"
#include "sss/env_error.h"
#include "sss/exact.h"
#include "sss/reconstruct.h"
#include "sss/fileio.h"
#include "sss/jsontext.h"
#include "sss/format.h"
#include "sss/random.h"
#include "sss/reference.h"
#include "sss/bake_scene.h" /* sss_point_exact */
#include "sss/effects.h"     /* sss_fx_point */
#include "sss/single_mesh.h" /* --query --view: the single-scattering term */
#include "sss/layer_depth.h" /* and the vertex's layer depths */

static const char *TOOL = "sss-stat";

static void usage(FILE *f)
{
    fprintf(f, "usage: sss-stat FILE.sss [--json]\n"
               "       sss-stat FILE.sss --query VERTEX --light X,Y,Z [--view X,Y,Z] [--json]\n"
               "       sss-stat FILE.sss --error [--views N] [--seed S] [--json] [--image-views N]\n"
               "                [--image-size N] [--exposure E] [--error-images DIR] [--no-image]\n"
               "                [--image-visibility viewer|rays|map[:N]] [--backlit]\n"
               "                [--interp triangle|nearest4] [--no-vector]\n"
               "       sss-stat --scene S.json --error [--time T] [--views N] [--seed S] [--json]\n"
               "       sss-stat FILE.sss --model-error --light X,Y,Z --view X,Y,Z [--query VERTEX | --vertices N]\n"
               "                [--paths N] [--seed S] [--exit jensen|normalised] [--json]\n"
               "Prints vertex count, channels, directions, storage, material, the bytes of every\n"
               "section, and every part of the scattering data (directions, reference indices,\n"
               "triangles, weights, tables, codes) in total and per vertex, with the compression\n"
               "ratio against 8-bit and float storage. --json prints one JSON object on stdout.\n"
               "\n"
               "--query VERTEX --light X,Y,Z: q(x_v, w) per channel at vertex VERTEX (0 ... vertices-1)\n"
               "for a light from direction (X,Y,Z) (towards the light, any non-zero length): the\n"
               "exact value, recomputed from the file's mesh, material and bake parameters with the\n"
               "bake's neighbourhoods and visibility rays (no direction samples, no quantisation),\n"
               "the value reconstructed from the stored data (interpolated between the three\n"
               "nearest direction samples, decoded from any storage form), and their difference\n"
               "(reconstructed - exact). Builds the neighbourhoods of the whole mesh first.\n"
               "With --view X,Y,Z (towards the viewer) also every term of the radiance leaving the\n"
               "vertex that way, per unit irradiance (1/sr): multiple scattering as the viewer\n"
               "shows it (q F_t(eta, n.w_o)), single scattering (marched through the mesh with the\n"
               "file's g; docs/layers.md) and their total, and the surface's Fresnel reflectance\n"
               "(sent into the mirror direction only).\n"
               "\n"
               "--scene S.json --error [--time T]: for each deforming object of the scene (docs/deformable.md),\n"
               "the per-vertex error of the q sss-view draws for its pose at T (default 0; the per-frame\n"
               "path: tree gather) against the exact evaluator on that pose, at --views random lights.\n"
               "\n"
               "--error: per-vertex error of the stored data against that exact evaluator at N\n"
               "random light directions (--views, default 100; --seed, default 1), none on a\n"
               "direction sample: area-weighted RMS, relative RMS and max |difference| per\n"
               "channel and over all channels, with the RMS of q itself for scale.\n"
               "Then the image-space error of Hao-Varshney 2004 section 3.3: the viewer's renderer\n"
               "(EGL offscreen; Mesa llvmpipe without a GPU) draws the subsurface term with the exact q\n"
               "and with the file's q at --image-views random view and light directions (default: the\n"
               "--views value), --image-size N x N pixels (default 256), clamped to [0,1] at one fixed\n"
               "--exposure (default: 1 / the 99.9th percentile of the exact q at the six axis lights);\n"
               "the RMS over the pixels of each image, the maximum (the paper's representative), mean\n"
               "and median. --error-images DIR writes the worst view's exact, approx and error images\n"
               "(PNG and EXR). Without OpenGL the image error is reported unavailable (one line) and\n"
               "the per-vertex error still printed; --no-image skips it. --interp nearest4 uses the\n"
               "paper's 4-nearest-direction interpolation instead of the stored triangle's (study only).\n"
               "A file baked with --vector is measured as readers show it, from the vector integrals Q\n"
               "(interpolated, dotted with the light: section QVEC); --no-vector measures its q rows.\n"
               "--backlit: every image view is back-lit, its light drawn within 30 degrees of the\n"
               "direction opposite the camera (translucency and the terminators facing the camera).\n"
               "Scene bakes: --error also measures every static directional light's exact values (QDIR),\n"
               "its point shells (PSHL: up to 16 random point lights, interpolated vs exact) and its\n"
               "environment transfer (ENVT: T_i at up to 64 random vertices against the exact q projected\n"
               "over 4x the bake's Fibonacci directions, randomly rotated; and the radiance sum T_i L_i\n"
               "under the file's probe and up to 8 random band-limited environments) against the exact\n"
               "evaluator.\n"
               "Files with near terms at run time (OWNT): the per-vertex error adds them with the bake's\n"
               "ray visibility; the image error as the viewer adds them (its GPU rays; map[:N]: its\n"
               "shadow map of N x N texels, default 2048; rays: the bake's ray on the CPU).\n"
               "\n"
               "--model-error: the radiance the viewer shows, L = E q F_t(eta, n.w_o) with E = 1 (q\n"
               "reconstructed from the file, as sss-view draws it), against the path-traced reference\n"
               "of the same mesh, material (g = 0), size and light (sss-ref, docs/reference.md) at N\n"
               "vertices (--vertices, default 64; or the --query vertex) facing --view, drawn by area\n"
               "(--seed), each with --paths paths (default 4096): the model error of the dipole, next\n"
               "to the approximation error against the exact evaluator at the same vertices. Per\n"
               "channel: mean radiance of each, their ratios, and the relative RMS over the vertices\n"
               "(the model error's with the reference's own noise taken out). --exit normalised divides\n"
               "the exit term by c(eta) = 2 int F_t mu dmu, as sss-view --exit normalised.\n"
               "\n"
               "Exit status: 0 success, 1 unreadable or unusable file, 2 bad arguments.\n");
}

/* The vertex index of --query, checked against the file: a plain decimal
 * integer below nv. */
static int parse_vertex(const char *path, const char *s, uint32_t nv, uint32_t *out)
{
    const char *p = s;
    while (isspace((unsigned char)*p)) p++;
    if (*p == '-') {
        sss_cli_printf(stderr, "%s: %s: --query '%s': a vertex index cannot be negative (the file has vertices 0 ... %u)\n",
                TOOL, path, s, nv - 1);
        return 0;
    }
    int digits = *p != 0;
    for (const char *q = p; *q; q++)
        if (!isdigit((unsigned char)*q)) digits = 0;
    if (!digits) {
        sss_cli_printf(stderr, "%s: %s: --query '%s' is not a vertex index (an integer in [0, %u])\n", TOOL, path, s, nv - 1);
        return 0;
    }
    errno = 0;
    unsigned long long v = strtoull(p, NULL, 10);
    if (errno || v >= nv) {
        sss_cli_printf(stderr, "%s: %s: --query %s: vertex index out of range: the file has %u vertices (0 ... %u)\n", TOOL,
                path, s, nv, nv - 1);
        return 0;
    }
    *out = (uint32_t)v;
    return 1;
}

/* --light X,Y,Z: three finite numbers, not all zero (a direction). */
static int parse_light(const char *path, const char *s, double l[3])
{
    const char *p = s;
    for (int k = 0; k < 3; k++) {
        char *end;
        l[k] = strtod(p, &end);
        if (end == p || (k < 2 ? *end != ',' : *end != 0)) {
            sss_cli_printf(stderr, "%s: %s: --light '%s' must be three numbers X,Y,Z\n", TOOL, path, s);
            return 0;
        }
        p = end + 1;
    }
    if (!isfinite(l[0]) || !isfinite(l[1]) || !isfinite(l[2])) {
        sss_cli_printf(stderr, "%s: %s: --light '%s': every component must be a finite number\n", TOOL, path, s);
        return 0;
    }
    if (l[0] == 0.0 && l[1] == 0.0 && l[2] == 0.0) {
        sss_cli_printf(stderr, "%s: %s: --light '%s' is the zero vector: give a direction towards the light\n", TOOL, path, s);
        return 0;
    }
    /* normalising must neither overflow nor divide by an underflowed length */
    const double l2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
    if (!(l2 >= DBL_MIN && l2 <= DBL_MAX)) {
        sss_cli_printf(stderr, "%s: %s: --light '%s': its length is too small or too large to be a direction\n", TOOL, path,
                s);
        return 0;
    }
    return 1;
}

/* The terms of the radiance leaving vertex v towards view (unit) for a
 * light of unit irradiance from d (unit), per channel (docs/layers.md §5):
 * multiple scattering as the viewer shows it, L = E q F_t(η, n·ω_o) with
 * the reconstructed q; single scattering (sss/single_mesh.h, 64 segments);
 * and the share of the light the surface reflects, which a directional
 * light sends into the mirror direction only. 0 when it cannot build the
 * mesh's hierarchy. */
typedef struct query_terms {
    double ms[SSS_MAX_CHANNELS], ss[SSS_MAX_CHANNELS];
    double fresnel_r, mirror_deg;
} query_terms;

static int query_terms_eval(const char *path, const sss_bake_file *f, uint32_t v, const double d[3],
                            const double view[3], const float *rec, query_terms *t)
{
    memset(t, 0, sizeof *t);
    const float *nf = &f->mesh.nrm[3 * (size_t)v];
    const double n[3] = {nf[0], nf[1], nf[2]};
    const double ci = n[0] * d[0] + n[1] * d[1] + n[2] * d[2], co = n[0] * view[0] + n[1] * view[1] + n[2] * view[2];
    const double ft_o = sss_ft(f->material.eta, co);
    for (uint32_t c = 0; c < f->channels; c++) t->ms[c] = (double)rec[c] * ft_o;
    t->fresnel_r = ci > 0.0 ? 1.0 - sss_ft(f->material.eta, ci) : 0.0;
    double mirror[3], cm = 0.0;
    for (int k = 0; k < 3; k++) mirror[k] = 2.0 * ci * n[k] - d[k];
    for (int k = 0; k < 3; k++) cm += mirror[k] * view[k];
    t->mirror_deg = acos(fmin(1.0, fmax(-1.0, cm))) * 180.0 / 3.14159265358979323846;
    sss_bvh bvh;
    sss_error err = {{0}};
    /* the vertex's own layer depths (section LDEP), constant along the
     * march (docs/layers.md §3) */
    sss_layer_stack layers;
    sss_layer_stack_at(&f->layers, f->layer_depth, v, &layers);
    if (sss_bvh_build(f->mesh.pos, f->mesh.nv, f->mesh.tri, f->mesh.nf, &bvh, &err) != SSS_OK ||
        sss_ss_mesh_vertex(&f->mesh, &bvh, f->mm_per_unit, &f->material, &layers, f->channels, v, d, view, NULL, t->ss, &err) !=
            SSS_OK) {
        sss_bvh_free(&bvh);
        sss_cli_printf(stderr, "%s: %s: single scattering at vertex %u: %s\n", TOOL, path, v, err.msg);
        return 0;
    }
    sss_bvh_free(&bvh);
    return 1;
}

/* --query: the exact evaluator against the stored data at one vertex; with
 * --view, every term of the radiance towards the viewer too. */
static int query(const char *path, const sss_bake_file *f, const char *vs, const char *ls, const double *view_in,
                 int json)
{
    uint32_t v;
    double light[3];
    if (!parse_vertex(path, vs, f->mesh.nv, &v) || !parse_light(path, ls, light)) return 2;
    sss_exact *e;
    sss_error err = {{0}};
    if (sss_exact_create_limited(f, sss_cli_memory_limit(), &e, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: exact evaluator: %s\n", TOOL, path, err.msg);
        return 1;
    }
    sss_reconstruct *rc = NULL;
    if (sss_reconstruct_create(f, &rc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: reconstruction: %s\n", TOOL, path, err.msg);
        sss_exact_destroy(e);
        return 1;
    }
    const uint32_t C = f->channels;
    float ex[SSS_MAX_CHANNELS], rec[SSS_MAX_CHANNELS];
    sss_exact_eval_vertex(e, v, light, ex);
    sss_reconstruct_eval_vertex(rc, v, light, rec); /* the stored rows, plus the own term of an OWNT file */
    sss_reconstruct_destroy(rc);
    /* the unit direction and the nearest stored sample, so a reader can see
     * whether the light sits on a sample (where a float file has no
     * interpolation error) */
    const double m = fmax(fabs(light[0]), fmax(fabs(light[1]), fabs(light[2])));
    double d[3], dl = 0.0;
    for (int k = 0; k < 3; k++) { d[k] = light[k] / m; dl += d[k] * d[k]; }
    dl = sqrt(dl);
    for (int k = 0; k < 3; k++) d[k] /= dl;
    uint32_t jn = 0;
    double best = -2.0;
    for (uint32_t j = 0; j < f->dirs.n; j++) {
        const double *w = &f->dirs.dir[3 * (size_t)j];
        double c = d[0] * w[0] + d[1] * w[1] + d[2] * w[2];
        if (c > best) { best = c; jn = j; }
    }
    const double angle = acos(fmin(1.0, fmax(-1.0, best))) * 180.0 / 3.14159265358979323846;
    double diff[SSS_MAX_CHANNELS], maxdiff = 0.0;
    for (uint32_t c = 0; c < C; c++) {
        diff[c] = (double)rec[c] - (double)ex[c];
        maxdiff = fmax(maxdiff, fabs(diff[c]));
    }
    static const char *const rgb[3] = {"R", "G", "B"};
    query_terms qt;
    double view[3] = {0.0, 0.0, 0.0};
    if (view_in) {
        const double vl = sqrt(view_in[0] * view_in[0] + view_in[1] * view_in[1] + view_in[2] * view_in[2]);
        for (int k = 0; k < 3; k++) view[k] = view_in[k] / vl;
        if (!query_terms_eval(path, f, v, d, view, rec, &qt)) {
            sss_exact_destroy(e);
            return 1;
        }
    }
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "file", path);
        cJSON_AddNumberToObject(o, "vertex", v);
        cJSON_AddNumberToObject(o, "vertices", f->mesh.nv);
        cJSON_AddItemToObject(o, "light", cJSON_CreateDoubleArray(light, 3));
        cJSON_AddItemToObject(o, "direction", cJSON_CreateDoubleArray(d, 3));
        cJSON_AddStringToObject(o, "quant", sss_quant_name(f->quant));
        cJSON_AddNumberToObject(o, "directions", f->dirs.n);
        cJSON *nd = cJSON_AddObjectToObject(o, "nearest_direction");
        cJSON_AddNumberToObject(nd, "index", jn);
        cJSON_AddNumberToObject(nd, "angle_deg", angle);
        cJSON_AddNumberToObject(o, "channels", C);
        cJSON_AddNumberToObject(o, "eps", sss_exact_eps(e));
        cJSON_AddNumberToObject(o, "search_radius_mm", sss_exact_search_radius_mm(e));
        cJSON *a = cJSON_AddArrayToObject(o, "exact"), *b = cJSON_AddArrayToObject(o, "reconstructed"),
              *dd = cJSON_AddArrayToObject(o, "difference"), *rr = cJSON_AddArrayToObject(o, "relative_difference");
        for (uint32_t c = 0; c < C; c++) {
            cJSON_AddItemToArray(a, cJSON_CreateNumber(ex[c]));
            cJSON_AddItemToArray(b, cJSON_CreateNumber(rec[c]));
            cJSON_AddItemToArray(dd, cJSON_CreateNumber(diff[c]));
            /* relative to the exact value; null where that is 0 (shadowed) */
            cJSON_AddItemToArray(rr, ex[c] != 0.0f ? cJSON_CreateNumber(diff[c] / ex[c]) : cJSON_CreateNull());
        }
        cJSON_AddNumberToObject(o, "max_abs_difference", maxdiff);
        if (view_in) { /* radiance per unit irradiance across the light's beam, 1/sr (docs/layers.md §5) */
            cJSON *tt = cJSON_AddObjectToObject(o, "terms");
            cJSON_AddItemToObject(tt, "view", cJSON_CreateDoubleArray(view, 3));
            cJSON *ms = cJSON_AddArrayToObject(tt, "multiple_scattering"), *ss = cJSON_AddArrayToObject(tt, "single_scattering"),
                  *tot = cJSON_AddArrayToObject(tt, "total");
            for (uint32_t c = 0; c < C; c++) {
                cJSON_AddItemToArray(ms, cJSON_CreateNumber(qt.ms[c]));
                cJSON_AddItemToArray(ss, cJSON_CreateNumber(qt.ss[c]));
                cJSON_AddItemToArray(tot, cJSON_CreateNumber(qt.ms[c] + qt.ss[c]));
            }
            cJSON_AddNumberToObject(tt, "surface_reflectance", qt.fresnel_r);
            cJSON_AddNumberToObject(tt, "mirror_angle_deg", qt.mirror_deg);
            cJSON_AddNumberToObject(tt, "g", f->material.g);
            cJSON_AddBoolToObject(tt, "single_scattering_in_effects", (f->fx.mask & SSS_FX_SINGLE) != 0);
        }
        sss_json_utf8(o); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
        char *s = cJSON_PrintUnformatted(o);
        puts(s);
        free(s);
        cJSON_Delete(o);
    } else {
        printf("%s: vertex %u of %u, light (%g, %g, %g), storage %s, %u directions\n", path, v, f->mesh.nv, light[0],
               light[1], light[2], sss_quant_name(f->quant), f->dirs.n);
        printf("  nearest direction sample %u at %.4g deg; exact evaluator: eps %g, search radius %.4g mm\n", jn,
               angle, sss_exact_eps(e), sss_exact_search_radius_mm(e));
        printf("  %-8s %15s %15s %15s %12s\n", "channel", "exact", "reconstructed", "difference", "relative");
        for (uint32_t c = 0; c < C; c++) {
            char rel[32];
            if (ex[c] != 0.0f) snprintf(rel, sizeof rel, "%.4g", diff[c] / ex[c]);
            else snprintf(rel, sizeof rel, "-");
            printf("  %-8s %15.9g %15.9g %15.6g %12s\n", C == 1 ? "grey" : rgb[c], (double)ex[c], (double)rec[c],
                   diff[c], rel);
        }
        printf("  max |difference| %.6g\n", maxdiff);
        if (view_in) {
            printf("  towards view (%g, %g, %g), per unit irradiance (1/sr):\n", view[0], view[1], view[2]);
            printf("  %-8s %15s %15s %15s\n", "channel", "multiple", "single", "total");
            for (uint32_t c = 0; c < C; c++)
                printf("  %-8s %15.9g %15.9g %15.9g\n", C == 1 ? "grey" : rgb[c], qt.ms[c], qt.ss[c], qt.ms[c] + qt.ss[c]);
            printf("  surface reflectance %.6g into the mirror direction, %.4g deg from the view\n", qt.fresnel_r,
                   qt.mirror_deg);
        }
    }
    sss_exact_destroy(e);
    return 0;
}

/* --error: the file's reconstruction against the exact evaluator. */
typedef struct error_args {
    uint32_t views, image_views; /* image_views 0: views */
    uint64_t seed;
    int image_size;              /* 0: default */
    double exposure;             /* 0: automatic */
    const char *images_dir;
    int no_image;
    sss_interp interp;
    int near_mode;               /* --image-visibility viewer (0) | rays (1) | map[:N] (2) */
    int shadow_size;             /* --image-visibility map:N */
    int backlit;                 /* --backlit: lights within 30° of opposite the camera */
} error_args;

static int error_report(const char *path, const sss_bake_file *f, const error_args *a, int json)
{
    const uint32_t views = a->views;
    const uint64_t seed = a->seed;

    sss_exact *e;
    sss_error err = {{0}};
    const char *inputs[1] = {path};
    const sss_inputs ins = {inputs, 1};
    /* the image paths before anything is measured (sss/fileio.h) */
    if (a->images_dir && !a->no_image && sss_image_error_check_outputs(a->images_dir, &ins, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    if (sss_exact_create_limited(f, sss_cli_memory_limit(), &e, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: exact evaluator: %s\n", TOOL, path, err.msg);
        return 1;
    }
    /* a scene bake without a moving directional light has no direction
     * set: only its other effects are measured (below) */
    const int dirset = !f->fx.mask || (f->fx.mask & SSS_FX_DIR_SET);
    sss_vertex_error ve;
    memset(&ve, 0, sizeof ve);
    sss_result r = dirset ? sss_vertex_error_vs_exact_interp(f, e, views, seed, a->interp, &ve, &err) : SSS_OK;
    if (r != SSS_OK) {
        sss_exact_destroy(e);
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, path, err.msg);
        return 1;
    }
    /* image-space error (§3.3): unavailable without OpenGL, which is said
     * in one line; the per-vertex figures are reported either way */
    sss_image_error ie;
    memset(&ie, 0, sizeof ie);
    char image_status[600] = "skipped (--no-image)";
    if (!dirset) snprintf(image_status, sizeof image_status, "skipped (no direction set)");
    int have_image = 0;
    if (!a->no_image && dirset) {
        sss_image_error_opts io = {a->image_views ? a->image_views : views, seed, a->image_size, a->image_size,
                                   a->exposure, a->interp, a->images_dir, a->near_mode, a->shadow_size, &ins,
                                   a->backlit ? 30.0 : 0.0, NULL, NULL};
        sss_error ierr = {{0}};
        r = sss_image_error_measure(f, e, &io, &ie, &ierr);
        if (r == SSS_OK) {
            have_image = 1;
            snprintf(image_status, sizeof image_status, "ok");
        } else if (r == SSS_ERR_UNSUPPORTED) {
            snprintf(image_status, sizeof image_status, "unavailable: %s", ierr.msg);
            sss_cli_printf(stderr, "%s: %s: image error unavailable (no OpenGL 4.3 context): %s\n", TOOL, path, ierr.msg);
        } else {
            sss_exact_destroy(e);
            sss_cli_printf(stderr, "%s: %s: image error: %s\n", TOOL, path, ierr.msg);
            return 1;
        }
    }
    /* Static directional lights (QDIR, a scene bake's directional-exact
     * effect, docs/scenes.md): each stored row against the exact evaluator
     * at its own direction, so the file's every kind of q is measured, not
     * only the direction set (docs/accuracy.md, "How the error is
     * measured"). Plain RMS over vertices and channels. */
    const uint32_t C = f->channels;
    const uint32_t nl = (f->fx.mask & SSS_FX_DIR_EXACT) ? f->fx.nexact : 0;
    double *lerr = nl ? calloc(3 * (size_t)nl, sizeof *lerr) : NULL; /* rms diff, rel. rms, max |diff| */
    float *qx = nl ? malloc((size_t)f->mesh.nv * C * sizeof *qx + 1) : NULL;
    if (nl && (!lerr || !qx)) {
        free(lerr);
        free(qx);
        sss_exact_destroy(e);
        sss_cli_printf(stderr, "%s: %s: out of memory for the static lights' error\n", TOOL, path);
        return 1;
    }
    for (uint32_t l = 0; l < nl; l++) {
        sss_exact_eval(e, f->fx.exact_dir + 3 * (size_t)l, qx);
        const float *qs = f->fx.exact_q + (size_t)l * f->mesh.nv * C;
        double d2 = 0.0, x2 = 0.0, mx = 0.0;
        for (size_t k = 0; k < (size_t)f->mesh.nv * C; k++) {
            const double d = (double)qs[k] - qx[k];
            d2 += d * d;
            x2 += (double)qx[k] * qx[k];
            mx = fmax(mx, fabs(d));
        }
        const double n = (double)f->mesh.nv * C;
        lerr[3 * l] = n > 0 ? sqrt(d2 / n) : 0.0;
        lerr[3 * l + 1] = x2 > 0 ? sqrt(d2 / x2) : 0.0;
        lerr[3 * l + 2] = mx;
    }
    free(qx);
    /* The environment's SH transfer (ENVT, docs/scenes.md "Accuracy"):
     * T_i at a random sample of vertices against the exact q projected
     * over a denser, rotated Fibonacci quadrature than the bake's
     * (sss/env_error.h), and the radiance Σ T_i L_i under the file's probe
     * and min(--views, 8) random band-limited environments. */
    sss_env_error ee;
    memset(&ee, 0, sizeof ee);
    const int have_env = (f->fx.mask & SSS_FX_ENV_SH) != 0;
    if (have_env) {
        r = sss_env_error_measure(f, e, views < SSS_ENV_ERROR_RANDOM_MAX ? views : SSS_ENV_ERROR_RANDOM_MAX, seed, &ee,
                                  &err);
        if (r != SSS_OK) {
            free(lerr);
            sss_exact_destroy(e);
            sss_cli_printf(stderr, "%s: %s: environment transfer's error: %s\n", TOOL, path, err.msg);
            return 1;
        }
    }
    sss_exact_destroy(e);
    /* Point shells (PSHL, Hao–Varshney 2004 §3.3): the trilinear
     * interpolation the viewer does (sss_fx_point) against the exact q of a
     * point light (sss_point_exact, the bake's own sum and shadow rule) at
     * random positions between the first and the last shell, uniform in
     * direction and radius: relative RMS per light, worst and mean. */
    double pt_max = 0.0, pt_mean = 0.0;
    uint32_t npt = 0;
    if (f->fx.mask & SSS_FX_POINT_SHELLS && f->fx.nshells > 0) {
        npt = views < 16 ? views : 16; /* each exact light rebuilds the neighbourhoods */
        const size_t n = (size_t)f->mesh.nv * C;
        float *qa = malloc(n * sizeof *qa + 1), *qe = malloc(n * sizeof *qe + 1);
        if (!qa || !qe) {
            free(qa);
            free(qe);
            free(lerr);
            sss_cli_printf(stderr, "%s: %s: out of memory for the point shells' error\n", TOOL, path);
            return 1;
        }
        uint64_t st = seed ^ 0x5053484cu; /* "PSHL": a stream of its own, the same for a seed */
        const double r0 = f->fx.shell_radius[0], r1 = f->fx.shell_radius[f->fx.nshells - 1];
        for (uint32_t l = 0; l < npt; l++) {
            double d[3], P[3];
            sss_rng_direction(&st, d);
            const double r = r0 + (r1 - r0) * sss_rng_unit(&st);
            for (int k = 0; k < 3; k++) P[k] = f->fx.shell_centre[k] + r * d[k];
            sss_fx_point(f, P, qa);
            sss_error perr = {{0}};
            if (sss_point_exact(f, (f->fx.mask & SSS_FX_SELF_SHADOW) != 0, P, qe, &perr) != SSS_OK) {
                free(qa);
                free(qe);
                free(lerr);
                sss_cli_printf(stderr, "%s: %s: point shells' exact values: %s\n", TOOL, path, perr.msg);
                return 1;
            }
            double d2 = 0.0, x2 = 0.0;
            for (size_t k = 0; k < n; k++) {
                const double dd = (double)qa[k] - qe[k];
                d2 += dd * dd;
                x2 += (double)qe[k] * qe[k];
            }
            const double rel = x2 > 0 ? sqrt(d2 / x2) : 0.0;
            pt_max = fmax(pt_max, rel);
            pt_mean += rel / npt;
        }
        free(qa);
        free(qe);
    }
    static const char *const rgb[3] = {"R", "G", "B"};
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "file", path);
        cJSON_AddNumberToObject(o, "vertices", f->mesh.nv);
        cJSON_AddNumberToObject(o, "channels", C);
        cJSON_AddStringToObject(o, "quant", sss_quant_name(f->quant));
        cJSON_AddNumberToObject(o, "directions", f->dirs.n);
        cJSON_AddNumberToObject(o, "views", views);
        cJSON_AddNumberToObject(o, "seed", (double)seed);
        cJSON_AddNumberToObject(o, "bytes_per_vertex", sss_file_integral_bytes_per_vertex(f));
        cJSON *v = dirset ? cJSON_AddObjectToObject(o, "vertex_error") : NULL;
        if (!dirset) cJSON_AddNullToObject(o, "vertex_error");
        else {
        cJSON_AddItemToObject(v, "rms", cJSON_CreateDoubleArray(ve.rms, (int)C));
        cJSON_AddItemToObject(v, "rel_rms", cJSON_CreateDoubleArray(ve.rel_rms, (int)C));
        cJSON_AddItemToObject(v, "max_abs", cJSON_CreateDoubleArray(ve.max_abs, (int)C));
        cJSON_AddItemToObject(v, "rms_exact", cJSON_CreateDoubleArray(ve.rms_exact, (int)C));
        cJSON_AddNumberToObject(v, "rms_all", ve.rms[C]);
        cJSON_AddNumberToObject(v, "rel_rms_all", ve.rel_rms[C]);
        cJSON_AddNumberToObject(v, "max_abs_all", ve.max_abs[C]);
        }
        cJSON_AddStringToObject(o, "interp", a->interp == SSS_INTERP_NEAREST4 ? "nearest4" : "triangle");
        cJSON_AddStringToObject(o, "image_error_status", image_status);
        if (have_image) {
            cJSON *im = cJSON_AddObjectToObject(o, "image_error");
            sss_image_error_json(&ie, im);
            if (ie.vector) { /* section QVEC: the file's q rows drawn too (docs/accuracy.md, "Vector integral Q") */
                cJSON *sv = cJSON_AddObjectToObject(im, "scalar_q");
                cJSON_AddNumberToObject(sv, "rms_max", ie.scalar_rms_max);
                cJSON_AddNumberToObject(sv, "rms_mean", ie.scalar_rms_mean);
                cJSON_AddNumberToObject(sv, "q_vs_Q_rms_max", ie.q_vs_Q_rms_max);
                cJSON_AddNumberToObject(sv, "q_vs_Q_rms_mean", ie.q_vs_Q_rms_mean);
            }
            cJSON_AddStringToObject(im, "lights", a->backlit ? "backlit: within 30 degrees of opposite the camera" : "random");
            /* files with OWNT: where the near terms' visibility came from */
            if (f->near_terms && a->near_mode == 1) cJSON_AddStringToObject(im, "near_visibility", "rays (CPU, Embree)");
            else if (f->near_terms && a->near_mode == 2) {
                char mv[48];
                snprintf(mv, sizeof mv, "shadow map %d", a->shadow_size ? a->shadow_size : SSS_SHADOW_SIZE);
                cJSON_AddStringToObject(im, "near_visibility", mv);
            } else if (f->near_terms)
                cJSON_AddStringToObject(im, "near_visibility", "rays (viewer, GPU)");
            else
                cJSON_AddNullToObject(im, "near_visibility");
            if (a->images_dir) {
                cJSON_AddStringToObject(im, "images_dir", a->images_dir);
                cJSON_AddNumberToObject(im, "error_map_gain", ie.error_map_gain);
            }
        } else {
            cJSON_AddNullToObject(o, "image_error");
        }
        if (f->fx.mask) { /* a scene bake: its static lights, and what is not measured */
            cJSON *sl = cJSON_AddArrayToObject(o, "static_lights");
            for (uint32_t l = 0; l < nl; l++) {
                cJSON *li = cJSON_CreateObject();
                cJSON_AddItemToObject(li, "direction", cJSON_CreateDoubleArray(f->fx.exact_dir + 3 * (size_t)l, 3));
                cJSON_AddNumberToObject(li, "rms", lerr[3 * l]);
                cJSON_AddNumberToObject(li, "rel_rms", lerr[3 * l + 1]);
                cJSON_AddNumberToObject(li, "max_abs", lerr[3 * l + 2]);
                cJSON_AddItemToArray(sl, li);
            }
            if (npt) {
                cJSON *ps = cJSON_AddObjectToObject(o, "point_shells");
                cJSON_AddNumberToObject(ps, "lights", npt);
                cJSON_AddNumberToObject(ps, "rel_rms_max", pt_max);
                cJSON_AddNumberToObject(ps, "rel_rms_mean", pt_mean);
            }
            if (have_env) {
                cJSON *en = cJSON_AddObjectToObject(o, "environment");
                cJSON_AddNumberToObject(en, "order", ee.order);
                cJSON_AddNumberToObject(en, "bake_directions", ee.bake_dirs);
                cJSON_AddNumberToObject(en, "reference_directions", ee.ref_dirs);
                cJSON_AddStringToObject(en, "reference", "exact q over a randomly rotated spherical Fibonacci set");
                cJSON_AddNumberToObject(en, "vertices", ee.vertices);
                cJSON_AddNumberToObject(en, "sources", (double)ee.sources);
                cJSON_AddBoolToObject(en, "shadows", ee.shadows);
                cJSON *tt = cJSON_AddObjectToObject(en, "transfer");
                cJSON_AddNumberToObject(tt, "rms", ee.t_rms[C]);
                cJSON_AddNumberToObject(tt, "rel_rms", ee.t_rel_rms[C]);
                cJSON_AddNumberToObject(tt, "max_abs", ee.t_max_abs[C]);
                cJSON_AddNumberToObject(tt, "rms_exact", ee.t_rms_exact[C]);
                if (ee.have_probe) {
                    cJSON *pr = cJSON_AddObjectToObject(en, "probe");
                    cJSON_AddNumberToObject(pr, "rms", ee.probe_rms[3]);
                    cJSON_AddNumberToObject(pr, "rel_rms", ee.probe_rel_rms[3]);
                    cJSON_AddNumberToObject(pr, "max_abs", ee.probe_max_abs[3]);
                } else {
                    cJSON_AddNullToObject(en, "probe");
                }
                cJSON *ra = cJSON_AddObjectToObject(en, "random");
                cJSON_AddNumberToObject(ra, "environments", ee.nrandom);
                cJSON_AddNumberToObject(ra, "rel_rms_max", ee.random_rel_rms_max);
                cJSON_AddNumberToObject(ra, "rel_rms_mean", ee.random_rel_rms_mean);
            }
            /* every effect is measured; the key stays, empty, for readers
             * of the earlier output */
            cJSON_AddStringToObject(o, "not_measured", "");
        }
        sss_json_utf8(o); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
        char *s = cJSON_PrintUnformatted(o);
        puts(s);
        free(s);
        cJSON_Delete(o);
    } else {
        if (dirset) {
            printf("%s: %u vertices, storage %s, %u directions: error against the exact evaluator at %u random "
                   "light directions (seed %llu)\n", path, f->mesh.nv, sss_quant_name(f->quant), f->dirs.n, views,
                   (unsigned long long)seed);
            printf("  %-8s %12s %12s %12s %12s\n", "channel", "RMS", "rel. RMS", "max |diff|", "RMS of q");
            for (uint32_t c = 0; c <= C; c++)
                printf("  %-8s %12.4g %12.4g %12.4g %12.4g\n", c == C ? "all" : C == 1 ? "grey" : rgb[c], ve.rms[c],
                       ve.rel_rms[c], ve.max_abs[c], ve.rms_exact[c]);
        } else {
            printf("%s: %u vertices, no direction set (scene bake): its other effects against the exact evaluator\n",
                   path, f->mesh.nv);
        }
        if (have_image) {
            printf("  image RMS (section 3.3) over %u %sviews, %dx%d, exposure %.4g: max %.4g, mean %.4g, median %.4g"
                   " (worst view %u; over its covered pixels %.4g; %s)\n", ie.views, a->backlit ? "back-lit " : "",
                   ie.width, ie.height, ie.exposure, ie.rms_max, ie.rms_mean, ie.rms_median, ie.worst,
                   ie.rms_max_covered, ie.gl_renderer);
            if (ie.vector)
                printf("  drawn from Q (section QVEC); its q rows: image RMS max %.4g, mean %.4g; q against Q: max "
                       "%.4g, mean %.4g\n", ie.scalar_rms_max, ie.scalar_rms_mean, ie.q_vs_Q_rms_max,
                       ie.q_vs_Q_rms_mean);
            if (a->images_dir)
                printf("  worst view's images in %s: exact, approx, error (x %.4g) as .png and .exr\n", a->images_dir,
                       ie.error_map_gain);
        } else {
            printf("  image RMS: %s\n", image_status);
        }
        for (uint32_t l = 0; l < nl; l++)
            printf("  static light %u (%.4g, %.4g, %.4g), exact values (QDIR): RMS %.4g, rel. RMS %.4g, max |diff| %.4g\n",
                   l, f->fx.exact_dir[3 * l], f->fx.exact_dir[3 * l + 1], f->fx.exact_dir[3 * l + 2], lerr[3 * l],
                   lerr[3 * l + 1], lerr[3 * l + 2]);
        if (npt)
            printf("  point shells (PSHL), %u point lights between the first and last shell: rel. RMS max %.4g, mean "
                   "%.4g\n", npt, pt_max, pt_mean);
        if (have_env) {
            printf("  environment (ENVT), SH order %u: %u of %u vertices against the exact q projected over %u "
                   "directions (the bake's %u x %u, rotated%s)\n", ee.order, ee.vertices, f->mesh.nv, ee.ref_dirs,
                   ee.bake_dirs, SSS_ENV_ERROR_REF_FACTOR, ee.shadows ? "" : "; no self-shadow, as baked");
            printf("    transfer T_i: RMS %.4g, rel. RMS %.4g, max |diff| %.4g\n", ee.t_rms[C], ee.t_rel_rms[C],
                   ee.t_max_abs[C]);
            if (ee.have_probe)
                printf("    radiance under the file's probe: RMS %.4g, rel. RMS %.4g, max |diff| %.4g\n", ee.probe_rms[3],
                       ee.probe_rel_rms[3], ee.probe_max_abs[3]);
            if (ee.nrandom)
                printf("    radiance under %u random band-limited environments: rel. RMS max %.4g, mean %.4g\n",
                       ee.nrandom, ee.random_rel_rms_max, ee.random_rel_rms_mean);
        }
    }
    free(lerr);
    return 0;
}

/* --model-error: what the viewer shows against the light transport
 * itself (docs/reference.md; docs/accuracy.md, "Model error"). */
typedef struct model_args {
    double view[3];
    uint32_t vertices, paths;
    uint64_t seed;
    int exit_normalised; /* --exit normalised: F_t / c(η), as sss-view --exit */
} model_args;

/* n vertices facing view (n·view > 0), drawn with probability ∝ ΔA
 * (the per-vertex error's area weighting) by the seeded generator; 0 when
 * none faces it. */
static uint32_t draw_vertices(const sss_bake_file *f, const double view[3], uint32_t n, uint64_t seed, uint32_t *out)
{
    const sss_mesh *m = &f->mesh;
    double *cdf = malloc(sizeof(double) * (m->nv ? m->nv : 1));
    if (!cdf) return 0;
    sss_mesh_vertex_areas(m, cdf);
    double total = 0.0;
    for (uint32_t v = 0; v < m->nv; v++) {
        const float *nv = &m->nrm[3 * (size_t)v];
        total += nv[0] * view[0] + nv[1] * view[1] + nv[2] * view[2] > 0.0 ? cdf[v] : 0.0;
        cdf[v] = total;
    }
    uint32_t k = 0;
    uint64_t st = seed;
    for (; total > 0.0 && k < n; k++) {
        const double x = sss_rng_unit(&st) * total;
        uint32_t lo = 0, hi = m->nv - 1;
        while (lo < hi) {
            const uint32_t mid = lo + (hi - lo) / 2;
            if (cdf[mid] > x) hi = mid;
            else lo = mid + 1;
        }
        out[k] = lo;
    }
    free(cdf);
    return k;
}

static int model_error_report(const char *path, const sss_bake_file *f, const char *vs, const char *ls,
                              const model_args *ma, int json)
{
    double light[3], view[3];
    if (!parse_light(path, ls, light)) return 2;
    memcpy(view, ma->view, sizeof view);
    const double vl = sqrt(view[0] * view[0] + view[1] * view[1] + view[2] * view[2]);
    for (int k = 0; k < 3; k++) view[k] /= vl;
    uint32_t n = vs ? 1 : ma->vertices;
    uint32_t *vert = malloc(sizeof(uint32_t) * n);
    sss_ref_query *q = malloc(sizeof(sss_ref_query) * n);
    sss_ref_estimate *ref = malloc(sizeof(sss_ref_estimate) * n);
    float *rt = malloc(sizeof(float) * 3 * n), *ex = malloc(sizeof(float) * 3 * n);
    double *ftv = malloc(sizeof(double) * n);
    int rc = 1;
    sss_exact *e = NULL;
    sss_reconstruct *rc_ = NULL;
    sss_ref_scene *sc = NULL;
    sss_error err = {{0}};
    if (!vert || !q || !ref || !rt || !ex || !ftv) {
        sss_cli_printf(stderr, "%s: %s: out of memory\n", TOOL, path);
        goto done;
    }
    if (vs) {
        if (!parse_vertex(path, vs, f->mesh.nv, &vert[0])) {
            rc = 2;
            goto done;
        }
    } else if ((n = draw_vertices(f, view, n, ma->seed, vert)) == 0) {
        sss_cli_printf(stderr, "%s: %s: no vertex faces the view (%g, %g, %g)\n", TOOL, path, view[0], view[1], view[2]);
        goto done;
    }
    if (sss_exact_create(f, &e, &err) != SSS_OK || sss_reconstruct_create(f, &rc_, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, path, err.msg);
        goto done;
    }
    /* the reference of the same mesh (the file's, with its normals), size,
     * material (σ′s as baked, g = 0) and light */
    sss_ref_medium med;
    if (sss_ref_medium_from_material(&f->material, 0.0, &med, &err) == SSS_OK)
        med.hetero = &f->hetero; /* the file's field (FELD), if any: the reference tracks it */
    if (sss_ref_medium_validate(&med, &err) != SSS_OK ||
        sss_ref_scene_create(&f->mesh, f->mm_per_unit, &sc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: reference: %s\n", TOOL, path, err.msg);
        goto done;
    }
    const uint32_t C = f->channels;
    for (uint32_t i = 0; i < n; i++) {
        float a[SSS_MAX_CHANNELS], b[SSS_MAX_CHANNELS];
        sss_reconstruct_eval_vertex(rc_, vert[i], light, a);
        sss_exact_eval_vertex(e, vert[i], light, b);
        const float *nv = &f->mesh.nrm[3 * (size_t)vert[i]];
        /* L = E · q · F_t(η, n·ω_o), E = 1, or divided by c(η) for the
         * normalised exit (docs/physics.md §4) */
        ftv[i] = sss_ft(f->material.eta, nv[0] * view[0] + nv[1] * view[1] + nv[2] * view[2]) /
                 (ma->exit_normalised ? sss_exit_norm(f->material.eta) : 1.0);
        for (int c = 0; c < 3; c++) {
            rt[3 * i + c] = (float)(a[C == 1 ? 0 : c] * ftv[i]);
            ex[3 * i + c] = (float)(b[C == 1 ? 0 : c] * ftv[i]);
        }
        q[i].vertex = vert[i];
        memcpy(q[i].view, view, sizeof view);
    }
    const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {light[0], light[1], light[2]}};
    sss_ref_options o = {0};
    o.seed = ma->seed;
    o.paths = ma->paths;
    o.progress = !json;
    sss_ref_stats st;
    if (sss_ref_queries(sc, &med, &l, q, n, &o, ref, &st, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: reference: %s\n", TOOL, path, err.msg);
        goto done;
    }
    /* per channel: means, their ratios, relative RMS over the vertices (the
     * model error's with the reference's variance Σ se² taken out) */
    double m_rt[3], m_ex[3], m_ref[3], se_ref[3], approx[3], model[3], noise[3], ratio[3], ratio_se[3], aratio[3];
    for (int c = 0; c < 3; c++) {
        double srt = 0, sex = 0, sref = 0, sse = 0, dax = 0, dmo = 0, ex2 = 0, ref2 = 0;
        for (uint32_t i = 0; i < n; i++) {
            const double a = rt[3 * i + c], b = ex[3 * i + c], r = ref[i].mean[c], se = ref[i].se[c];
            srt += a, sex += b, sref += r, sse += se * se;
            dax += (a - b) * (a - b), dmo += (a - r) * (a - r), ex2 += b * b, ref2 += r * r;
        }
        m_rt[c] = srt / n, m_ex[c] = sex / n, m_ref[c] = sref / n, se_ref[c] = sqrt(sse) / n;
        approx[c] = ex2 > 0 ? sqrt(dax / ex2) : 0.0;
        model[c] = ref2 > 0 ? sqrt(fmax(0.0, dmo - sse) / ref2) : 0.0;
        noise[c] = ref2 > 0 ? sqrt(sse / ref2) : 0.0;
        ratio[c] = sref > 0 ? srt / sref : 0.0;
        ratio_se[c] = sref > 0 ? ratio[c] * se_ref[c] / m_ref[c] : 0.0;
        aratio[c] = sex > 0 ? srt / sex : 0.0;
    }
    if (json) {
        cJSON *o2 = cJSON_CreateObject();
        cJSON_AddStringToObject(o2, "file", path);
        cJSON_AddNumberToObject(o2, "vertices", f->mesh.nv);
        cJSON_AddStringToObject(o2, "material", f->material.name);
        cJSON_AddNumberToObject(o2, "mm_per_unit", f->mm_per_unit);
        cJSON_AddStringToObject(o2, "quant", sss_quant_name(f->quant));
        cJSON_AddItemToObject(o2, "light", cJSON_CreateDoubleArray(light, 3));
        cJSON_AddItemToObject(o2, "view", cJSON_CreateDoubleArray(view, 3));
        cJSON_AddStringToObject(o2, "exit", ma->exit_normalised ? "normalised" : "jensen");
        cJSON_AddNumberToObject(o2, "sampled_vertices", n);
        cJSON_AddNumberToObject(o2, "paths", (double)st.paths);
        cJSON_AddNumberToObject(o2, "seed", (double)ma->seed);
        cJSON_AddNumberToObject(o2, "reference_seconds", st.seconds);
        cJSON_AddNumberToObject(o2, "reference_leaks", (double)st.leaks);
        cJSON_AddNumberToObject(o2, "reference_crossed", (double)st.crossed);
        cJSON *mr = cJSON_AddObjectToObject(o2, "mean_radiance");
        cJSON_AddItemToObject(mr, "realtime", cJSON_CreateDoubleArray(m_rt, 3));
        cJSON_AddItemToObject(mr, "exact", cJSON_CreateDoubleArray(m_ex, 3));
        cJSON_AddItemToObject(mr, "reference", cJSON_CreateDoubleArray(m_ref, 3));
        cJSON_AddItemToObject(mr, "reference_stderr", cJSON_CreateDoubleArray(se_ref, 3));
        cJSON *ae = cJSON_AddObjectToObject(o2, "approximation_error");
        cJSON_AddItemToObject(ae, "ratio_of_means", cJSON_CreateDoubleArray(aratio, 3));
        cJSON_AddItemToObject(ae, "rel_rms", cJSON_CreateDoubleArray(approx, 3));
        cJSON *me = cJSON_AddObjectToObject(o2, "model_error");
        cJSON_AddItemToObject(me, "ratio_of_means", cJSON_CreateDoubleArray(ratio, 3));
        cJSON_AddItemToObject(me, "ratio_stderr", cJSON_CreateDoubleArray(ratio_se, 3));
        cJSON_AddItemToObject(me, "rel_rms", cJSON_CreateDoubleArray(model, 3));
        cJSON_AddItemToObject(me, "reference_noise_rel_rms", cJSON_CreateDoubleArray(noise, 3));
        cJSON *vv = cJSON_AddArrayToObject(o2, "per_vertex");
        for (uint32_t i = 0; i < n; i++) {
            cJSON *x = cJSON_CreateObject();
            double a[3], b[3];
            for (int c = 0; c < 3; c++) a[c] = rt[3 * i + c], b[c] = ex[3 * i + c];
            cJSON_AddNumberToObject(x, "vertex", vert[i]);
            cJSON_AddItemToObject(x, "realtime", cJSON_CreateDoubleArray(a, 3));
            cJSON_AddItemToObject(x, "exact", cJSON_CreateDoubleArray(b, 3));
            cJSON_AddItemToObject(x, "reference", cJSON_CreateDoubleArray(ref[i].mean, 3));
            cJSON_AddItemToObject(x, "reference_stderr", cJSON_CreateDoubleArray(ref[i].se, 3));
            cJSON_AddItemToArray(vv, x);
        }
        char *str = cJSON_PrintUnformatted(o2);
        puts(str);
        free(str);
        cJSON_Delete(o2);
    } else {
        printf("%s: %u vertices facing (%g, %g, %g), light (%g, %g, %g), storage %s: the viewer's radiance "
               "against the exact evaluator (approximation) and the path-traced reference (model), %llu paths "
               "per vertex, %.3g s\n", path, n, view[0], view[1], view[2], light[0], light[1], light[2],
               sss_quant_name(f->quant), (unsigned long long)st.paths, st.seconds);
        printf("  %-8s %11s %11s %18s | %12s %12s | %12s %12s %12s\n", "channel", "mean L rt", "exact", "reference",
               "approx ratio", "approx RMS", "model ratio", "model RMS", "ref. noise");
        static const char *const rgb[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; c++)
            printf("  %-8s %11.5g %11.5g %11.5g+-%-6.2g | %12.4f %12.4g | %12.4f %12.4g %12.4g\n", rgb[c], m_rt[c], m_ex[c],
                   m_ref[c], se_ref[c], aratio[c], approx[c], ratio[c], model[c], noise[c]);
        if (st.leaks)
            printf("  warning: %llu of %llu reference paths left the mesh through a hole (an open mesh)\n",
                   (unsigned long long)st.leaks, (unsigned long long)st.walks);
    }
    rc = 0;
done:
    sss_ref_scene_destroy(sc);
    sss_reconstruct_destroy(rc_);
    sss_exact_destroy(e);
    free(vert);
    free(q);
    free(ref);
    free(rt);
    free(ex);
    free(ftv);
    return rc;
}

/* "N.Nx smaller", "N.Nx larger" or "the size", of bytes b against raw
 * bytes r: a ratio below 1 is a file larger than the raw values (small
 * meshes, scene bakes), said so, not "0.2x smaller"; one that prints as
 * 1.0 either way is the same size. */
static void size_ratio(double r, double b, char *out, size_t n)
{
    const double x = r / b;
    if (x >= 0.95 && x < 1.05) snprintf(out, n, "the size of");
    else if (x >= 1.0) snprintf(out, n, "%.1fx smaller than", x);
    else snprintf(out, n, "%.1fx larger than", 1.0 / x);
}

/* The summary: what the file holds and where its bytes go. */
static int summary(const char *path, const sss_bake_file *f, int json)
{
    const double nv = f->mesh.nv;
    const char *quant = sss_quant_name(f->quant);
    /* every byte of the scattering data, by part (docs/format.md §5) */
    sss_storage st;
    sss_file_storage(f, &st);
    const struct { const char *name; uint64_t bytes; } part[] = {
        {"directions", st.dirs},           {"values", st.values},         {"lloyd_tables", st.lloyd_tables},
        {"section_headers", st.section_headers}, {"ref_vertex_indices", st.ref_vertex},
        {"ref_triangles", st.ref_tri},     {"vertex_triangle_indices", st.vertex_tri},
        {"weights", st.weights},           {"ref_values", st.ref_values}, {"sh_tables", st.sh_tables},
        {"sh_codes", st.sh_codes},
    };
    const size_t nparts = sizeof part / sizeof part[0];
    const double raw8 = (double)f->dirs.n * f->channels, rawf = 4.0 * raw8; /* bytes/vertex, uncompressed */
    const double sbpv = (double)st.total / nv; /* scattering data incl. directions, per vertex */
    /* every byte of the file but the mesh: the scattering data above and
     * the header, section table, material, parameters and small sections */
    uint64_t geom = 0;
    for (uint32_t s = 0; s < f->nsections; s++)
        if (memcmp(f->sections[s].tag, "GEOM", 4) == 0) geom = f->sections[s].size;
    const uint64_t apart = f->file_size - geom;
    if (json) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "file", path);
        char ver[32];
        snprintf(ver, sizeof ver, "%u.%u", f->version_major, f->version_minor);
        cJSON_AddStringToObject(o, "format_version", ver);
        cJSON_AddNumberToObject(o, "vertices", f->mesh.nv);
        cJSON_AddNumberToObject(o, "triangles", f->mesh.nf);
        cJSON_AddNumberToObject(o, "channels", f->channels);
        cJSON_AddNumberToObject(o, "directions", f->dirs.n);
        cJSON_AddStringToObject(o, "quant", quant);
        cJSON_AddStringToObject(o, "material", f->material.name);
        cJSON_AddNumberToObject(o, "mm_per_unit", f->mm_per_unit);
        /* null: every term baked (the paper); else the mesh rings whose
         * terms a reader adds at run time (sss/nearterms.h) */
        if (f->near_terms) cJSON_AddNumberToObject(o, "runtime_rings", f->near_rings);
        else cJSON_AddNullToObject(o, "runtime_rings");
        /* null unless the near terms are sized in mm (section NRAD) */
        if (f->near_radius_mm > 0.0) cJSON_AddNumberToObject(o, "near_radius_mm", f->near_radius_mm);
        else cJSON_AddNullToObject(o, "near_radius_mm");
        /* the weight rule (section QUAD; docs/physics.md §4, §9) */
        cJSON_AddStringToObject(o, "weights", f->weights == SSS_WEIGHTS_HAT ? "hat" : "point");
        /* a heterogeneous object's field (section FELD, docs/heterogeneous.md): its kind, or null */
        if (f->hetero.field.kind) cJSON_AddStringToObject(o, "field", sss_field_kind_name(f->hetero.field.kind));
        else cJSON_AddNullToObject(o, "field");
        cJSON_AddNumberToObject(o, "file_bytes", (double)f->file_size);
        cJSON_AddNumberToObject(o, "bytes_per_vertex", (double)f->file_size / nv);
        cJSON_AddNumberToObject(o, "bytes_apart_geometry", (double)apart);
        cJSON_AddNumberToObject(o, "bytes_apart_geometry_per_vertex", (double)apart / nv);
        cJSON *secs = cJSON_AddArrayToObject(o, "sections");
        for (uint32_t s = 0; s < f->nsections; s++) {
            cJSON *e = cJSON_CreateObject();
            cJSON_AddStringToObject(e, "tag", f->sections[s].tag);
            cJSON_AddNumberToObject(e, "bytes", (double)f->sections[s].size);
            cJSON_AddNumberToObject(e, "bytes_per_vertex", (double)f->sections[s].size / nv);
            cJSON_AddNumberToObject(e, "count", (double)f->sections[s].count);
            cJSON_AddItemToArray(secs, e);
        }
        cJSON *sto = cJSON_AddObjectToObject(o, "storage");
        for (size_t k = 0; k < nparts; k++) {
            if (!part[k].bytes) continue;
            cJSON *e = cJSON_AddObjectToObject(sto, part[k].name);
            cJSON_AddNumberToObject(e, "bytes", (double)part[k].bytes);
            cJSON_AddNumberToObject(e, "bytes_per_vertex", (double)part[k].bytes / nv);
        }
        cJSON_AddNumberToObject(o, "scattering_bytes", (double)st.total);
        cJSON_AddNumberToObject(o, "scattering_bytes_per_vertex", sbpv);
        cJSON_AddNumberToObject(o, "ratio_vs_8bit", raw8 / sbpv);
        cJSON_AddNumberToObject(o, "ratio_vs_float", rawf / sbpv);
        if (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS) {
            cJSON *c = cJSON_AddObjectToObject(o, "compression");
            cJSON_AddNumberToObject(c, "sh_order", f->sh.order);
            cJSON_AddNumberToObject(c, "sh_coefficients", f->sh.ncoef);
            cJSON_AddStringToObject(c, "sh_quant", sss_shq_name(f->sh.kind));
            cJSON_AddNumberToObject(c, "coded_vertices", f->sh.ncoded);
            if (f->quant == SSS_QUANT_REFS) {
                cJSON_AddNumberToObject(c, "refs", f->ref.nref);
                cJSON_AddNumberToObject(c, "refs_fraction", f->ref.nref / nv);
                cJSON_AddNumberToObject(c, "ref_triangles", f->ref.nrt);
                cJSON_AddNumberToObject(c, "weight_bits", f->ref.wbits);
                cJSON_AddItemToObject(c, "weight_range", cJSON_CreateDoubleArray((double[]){f->ref.w_lo, f->ref.w_hi}, 2));
            }
        }
        cJSON *p = f->params_json ? cJSON_Parse(f->params_json) : NULL;
        if (p) cJSON_AddItemToObject(o, "params", p);
        sss_json_utf8(o); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
        char *s = cJSON_PrintUnformatted(o);
        puts(s);
        free(s);
        cJSON_Delete(o);
    } else {
        printf("%s: format %u.%u, %llu bytes\n", path, f->version_major, f->version_minor, (unsigned long long)f->file_size);
        printf("  vertices %u, triangles %u, channels %u, directions %u, storage %s\n", f->mesh.nv, f->mesh.nf,
               f->channels, f->dirs.n, quant);
        printf("  material %s (eta %g), %g mm per unit\n", f->material.name, f->material.eta, f->mm_per_unit);
        if (f->material.g != 0.0) /* section PHAS (docs/layers.md §2) */
            printf("  phase function Henyey-Greenstein, g %g (sigma_s = sigma'_s / (1 - g))\n", f->material.g);
        if (f->layers.n) { /* section LAYR (docs/layers.md §3) */
            printf("  %u layer%s over the material (single scattering), lower boundaries at", f->layers.n,
                   f->layers.n > 1 ? "s" : "");
            for (uint32_t i = 0; i < f->layers.n; i++) printf(" %g", f->layers.layer[i].depth);
            printf(" mm%s\n", f->layer_depth ? " (the deepest of each)" : "");
        }
        if (f->layer_depth) { /* section LDEP (docs/layers.md §3) */
            printf("  per-vertex layer depths (section LDEP):");
            for (uint32_t k = 0; k < f->layers.n; k++) {
                float lo = INFINITY, hi = 0.0f;
                for (uint32_t v = 0; v < f->mesh.nv; v++) {
                    const float x = f->layer_depth[(size_t)v * f->layers.n + k];
                    lo = x < lo ? x : lo;
                    hi = x > hi ? x : hi;
                }
                printf("%s layer %u %g to %g mm", k ? "," : "", k, (double)lo, (double)hi);
            }
            printf("\n");
        }
        if (f->near_terms && f->near_radius_mm > 0.0)
            printf("  near terms added at run time: every vertex within %g mm (sections OWNT, NRAD)\n",
                   f->near_radius_mm);
        else if (f->near_terms)
            printf("  near terms added at run time: the vertex's own term and %u mesh ring%s (section OWNT)\n",
                   f->near_rings, f->near_rings == 1 ? "" : "s");
        printf("  weights: %s\n", f->weights == SSS_WEIGHTS_HAT
                                      ? "integrals over the vertices' hat functions (section QUAD, docs/physics.md 9)"
                                      : "point samples (Hao-Varshney 2004 3.1)");
        if (f->hetero.field.kind)
            printf("  field: %s%s, inside sigma_a %g/%g/%g, sigma'_s %g/%g/%g (section FELD, docs/heterogeneous.md)\n",
                   sss_field_kind_name(f->hetero.field.kind),
                   f->hetero.surface ? " surface texture (endpoints only, sec. 4.4)" : "", f->hetero.inside.sigma_a[0],
                   f->hetero.inside.sigma_a[1],
                   f->hetero.inside.sigma_a[2], f->hetero.inside.sigmap_s[0], f->hetero.inside.sigmap_s[1],
                   f->hetero.inside.sigmap_s[2]);
        printf("  %-6s %14s %12s %14s\n", "section", "bytes", "bytes/vertex", "count");
        for (uint32_t s = 0; s < f->nsections; s++)
            printf("  %-6s %14llu %12.2f %14llu\n", f->sections[s].tag, (unsigned long long)f->sections[s].size,
                   (double)f->sections[s].size / nv, (unsigned long long)f->sections[s].count);
        printf("  total  %14llu %12.2f\n", (unsigned long long)f->file_size, (double)f->file_size / nv);
        printf("  all but GEOM %8llu %12.2f\n", (unsigned long long)apart, (double)apart / nv);
        if (f->quant == SSS_QUANT_REFS)
            printf("  compression: %u references (%.2f%%), %u triangles, %u-bit weights in [%g, %g], SH order %u (%s)\n",
                   f->ref.nref, 100.0 * f->ref.nref / nv, f->ref.nrt, f->ref.wbits, (double)f->ref.w_lo,
                   (double)f->ref.w_hi, f->sh.order, sss_shq_name(f->sh.kind));
        if (f->quant == SSS_QUANT_SH)
            printf("  compression: SH order %u (%s) at every vertex\n", f->sh.order, sss_shq_name(f->sh.kind));
        printf("  scattering data by part:\n  %-24s %14s %12s\n", "part", "bytes", "bytes/vertex");
        for (size_t k = 0; k < nparts; k++)
            if (part[k].bytes)
                printf("  %-24s %14llu %12.3f\n", part[k].name, (unsigned long long)part[k].bytes,
                       (double)part[k].bytes / nv);
        char r8[48], rf[48];
        size_ratio(raw8, sbpv, r8, sizeof r8);
        size_ratio(rawf, sbpv, rf, sizeof rf);
        printf("  %-24s %14llu %12.3f  (%s 8-bit, %s float)\n", "all", (unsigned long long)st.total, sbpv, r8,
               rf);
    }
    return 0;
}

/* The command line, as the option table fills it. */
typedef struct stat_args {
    const char *path, *qvertex, *qlight;
    int json, want_error, want_model;
    model_args ma;         /* --model-error: --view, --vertices, --paths */
    int have_view, model_opt;
    uint32_t views, seed;
    int interp;    /* --interp: SSS_INTERP_TRIANGLE (the default) or SSS_INTERP_NEAREST4 */
    int no_vector; /* --no-vector: measure q's rows of a file that holds Q too */
    int image_opt; /* given: --image-views, --image-size, --exposure, --error-images or --image-visibility */
    error_args ea; /* the image options; views, seed and interp join them for the run */
    const char *scene; /* --scene S.json without FILE.sss: a deforming object's pose (deform_error.c) */
    double time;       /* --time T */
    int time_given;
} stat_args;

/* --image-visibility viewer|rays|map|map:N (N = 256 ... 8192); "viewer",
 * "rays" and "map" keep an earlier map:N's size, as they always have. */
static int read_image_visibility(const sss_cli *cli, const sss_cli_opt *o, const char *opt, const char *text)
{
    (void)cli;
    (void)opt;
    error_args *ea = o->dest;
    unsigned sz = 0;
    char tail;
    if (!strcmp(text, "viewer")) ea->near_mode = 0;
    else if (!strcmp(text, "rays")) ea->near_mode = 1;
    else if (!strcmp(text, "map")) ea->near_mode = 2;
    else if (sscanf(text, "map:%u%c", &sz, &tail) == 1 && sz >= 256 && sz <= 8192) ea->near_mode = 2, ea->shadow_size = (int)sz;
    else return 0;
    return 1;
}

/* SSS_CLI_RUN, or the exit status after --help (0) or a message (2). */
static int parse_args(int argc, char **argv, stat_args *a)
{
    static const char *const interps[] = {"triangle", "nearest4", NULL};
    static const int interp_values[] = {SSS_INTERP_TRIANGLE, SSS_INTERP_NEAREST4};
    memset(a, 0, sizeof *a);
    a->views = 100;
    a->seed = 1;
    a->ma.vertices = 64;
    a->ma.paths = 4096;
    static const char *const exits[] = {"jensen", "normalised", NULL};
    const sss_cli_opt opts[] = {
        {.name = "--json", .kind = SSS_CLI_FLAG, .dest = &a->json},
        {.name = "--query", .kind = SSS_CLI_STRING, .dest = &a->qvertex}, /* checked against the file: query() */
        {.name = "--light", .kind = SSS_CLI_STRING, .dest = &a->qlight},
        {.name = "--error", .kind = SSS_CLI_FLAG, .dest = &a->want_error},
        {.name = "--views", .kind = SSS_CLI_U32, .dest = &a->views, .lo = 1, .hi = 100000},
        {.name = "--seed", .kind = SSS_CLI_U32, .dest = &a->seed, .lo = 0, .hi = UINT32_MAX},
        {.name = "--image-views", .kind = SSS_CLI_U32, .dest = &a->ea.image_views, .lo = 1, .hi = 100000,
         .given = &a->image_opt},
        {.name = "--image-size", .kind = SSS_CLI_INT, .dest = &a->ea.image_size, .lo = 16, .hi = 4096,
         .given = &a->image_opt},
        /* strtod's own reading: an underflow to a tiny positive number is taken */
        /* at most SSS_VIEW_GAIN_MAX: q · exposure stays inside float (1e38 drew NaN images) */
        {.name = "--exposure", .kind = SSS_CLI_DOUBLE, .dest = &a->ea.exposure, .lo = 0, .hi = SSS_VIEW_GAIN_MAX,
         .flags = SSS_CLI_ABOVE_LO | SSS_CLI_LAX, .given = &a->image_opt,
         .msg = "%s: %s '%s' must be a positive number\n"},
        {.name = "--error-images", .kind = SSS_CLI_STRING, .dest = &a->ea.images_dir, .flags = SSS_CLI_NONEMPTY,
         .given = &a->image_opt, .need_msg = "%s: %s needs a directory (see --help)\n"},
        {.name = "--no-image", .kind = SSS_CLI_FLAG, .dest = &a->ea.no_image},
        {.name = "--image-visibility", .kind = SSS_CLI_CUSTOM, .dest = &a->ea, .parse = read_image_visibility,
         .given = &a->image_opt, .msg = "%s: %s '%s' must be viewer, rays, map or map:N (N = 256 ... 8192)\n"},
        {.name = "--backlit", .kind = SSS_CLI_FLAG, .dest = &a->ea.backlit, .given = &a->image_opt},
        {.name = "--interp", .kind = SSS_CLI_CHOICE, .dest = &a->interp, .choices = interps, .values = interp_values,
         .msg = "%s: %s '%s' must be triangle or nearest4\n"},
        {.name = "--no-vector", .kind = SSS_CLI_FLAG, .dest = &a->no_vector},
        {.name = "--model-error", .kind = SSS_CLI_FLAG, .dest = &a->want_model},
        {.name = "--view", .kind = SSS_CLI_TRIPLE, .dest = a->ma.view, .flags = SSS_CLI_NONZERO, .given = &a->have_view},
        {.name = "--vertices", .kind = SSS_CLI_U32, .dest = &a->ma.vertices, .lo = 1, .hi = 1000000, .given = &a->model_opt},
        {.name = "--paths", .kind = SSS_CLI_U32, .dest = &a->ma.paths, .lo = 1, .hi = 1u << 30, .given = &a->model_opt},
        {.name = "--exit", .kind = SSS_CLI_CHOICE, .dest = &a->ma.exit_normalised, .choices = exits,
         .given = &a->model_opt},
        {.name = "--scene", .kind = SSS_CLI_STRING, .dest = &a->scene},
        {.name = "--time", .kind = SSS_CLI_DOUBLE, .dest = &a->time, .lo = -1e9, .hi = 1e9, .given = &a->time_given},
    };
    const sss_cli_opt pos[] = {{.name = "FILE.sss", .kind = SSS_CLI_STRING, .dest = &a->path}};
    const sss_cli cli = {
        .tool = TOOL, .opts = opts, .nopts = SSS_CLI_COUNT(opts), .pos = pos, .npos = SSS_CLI_COUNT(pos),
        .min_pos = 0, .usage = usage,
        .need_msg = "%s: %s needs a value (see --help)\n",
        .extra_msg = "%s: unexpected argument '%s'\n",
        .missing_msg = "%s: missing FILE.sss (see --help)\n",
    };
    const int rc = sss_cli_parse(&cli, argc, argv);
    if (rc != SSS_CLI_RUN) return rc;
    /* FILE.sss, or a deforming scene without a file (docs/deformable.md §4) */
    if (a->path && (a->scene || a->time_given)) {
        sss_cli_printf(stderr, "%s: --scene and --time measure a deforming scene without FILE.sss\n", TOOL);
        return 2;
    }
    if (!a->path && !a->scene) {
        sss_cli_printf(stderr, "%s: missing FILE.sss (see --help)\n", TOOL);
        return 2;
    }
    return rc;
}

/* --query and --error measure the stored direction set (Hao–Varshney 2004
 * §3.2) against the exact evaluator, which recomputes q from the file's
 * mesh alone. A scene bake without a direction set (its lights are other
 * effects: a static light's exact row, shells, SH) has nothing to
 * interpolate, and one whose shadows come from other objects of its scene
 * cannot be recomputed from the file: either would be measured as a 100 %
 * error that is not one, so they are refused. 1 when measurable. */
static int measurable(const char *path, const sss_bake_file *f, int error)
{
    /* --error measures the other effects of a scene bake without one too
     * (static lights, point shells, the environment: error_report) */
    const int others = f->fx.mask & (SSS_FX_DIR_EXACT | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH);
    if (f->fx.mask && !(f->fx.mask & SSS_FX_DIR_SET) && !(error && others)) {
        sss_cli_printf(stderr, "%s: %s: --query measures a direction set, --error one or static lights, point shells "
                       "or an environment, and this scene bake has none of them (its lights are baked by other "
                       "effects: see sss-stat without options)\n", TOOL, path);
        return 0;
    }
    if (f->fx.mask & SSS_FX_SCENE_SHADOW) {
        sss_cli_printf(stderr, "%s: %s: --query and --error recompute q from this file alone, and its shadows come from "
                       "other objects of its scene (effect scene-shadow)\n", TOOL, path);
        return 0;
    }
    return 1;
}

/* The combinations of options, checked once the file has been read (an
 * unreadable file is reported first, exit status 1). 1 if they go together,
 * else 0 after the message. */
static int combinations_ok(const stat_args *a)
{
    if ((a->image_opt || a->ea.no_image || a->interp != SSS_INTERP_TRIANGLE) && !a->want_error) {
        sss_cli_printf(stderr, "%s: --image-views, --image-size, --exposure, --error-images, --image-visibility, --backlit, --no-image and --interp go with --error\n", TOOL);
        return 0;
    }
    if (a->ea.no_image && a->image_opt) {
        sss_cli_printf(stderr, "%s: --no-image excludes the image options\n", TOOL);
        return 0;
    }
    if (a->qvertex && a->want_error) {
        sss_cli_printf(stderr, "%s: --query and --error exclude each other\n", TOOL);
        return 0;
    }
    if (a->want_model && a->want_error) {
        sss_cli_printf(stderr, "%s: --model-error and --error exclude each other\n", TOOL);
        return 0;
    }
    if (((a->have_view && !a->qvertex) || a->model_opt) && !a->want_model) {
        sss_cli_printf(stderr, "%s: --view, --vertices, --paths and --exit go with --model-error (--view also with --query)\n", TOOL);
        return 0;
    }
    if (a->want_model && (!a->qlight || !a->have_view)) {
        sss_cli_printf(stderr, "%s: --model-error needs --light X,Y,Z and --view X,Y,Z (see --help)\n", TOOL);
        return 0;
    }
    if (a->want_model && a->qvertex && a->model_opt && a->ma.vertices != 64) {
        sss_cli_printf(stderr, "%s: --query and --vertices exclude each other\n", TOOL);
        return 0;
    }
    return 1;
}

int main(int argc, char **argv)
{
    stat_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc != SSS_CLI_RUN) return rc;
    if (!a.path) {
        if (!a.want_error || a.qvertex || a.qlight || a.want_model || a.image_opt || a.interp || a.no_vector) {
            sss_cli_printf(stderr, "%s: --scene S.json takes --error [--time T] [--views N] [--seed S] [--json] "
                           "only\n", TOOL);
            return 2;
        }
        return sss_deform_error_report(TOOL, a.scene, a.time, a.views, a.seed, a.json);
    }
    if (!a.want_model && !a.qvertex != !a.qlight) {
        sss_cli_printf(stderr, "%s: %s needs %s (see --help)\n", TOOL, a.qvertex ? "--query" : "--light",
                a.qvertex ? "--light X,Y,Z" : "--query VERTEX");
        return 2;
    }
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(a.path, &f, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        return 1;
    }
    if (a.no_vector) { /* readers take Q when the file holds it (sss/decode.h) */
        free(f.qvec);
        f.qvec = NULL;
    }
    if (!combinations_ok(&a)) rc = 2;
    else if ((a.qvertex || a.want_error || a.want_model) && !measurable(a.path, &f, a.want_error)) rc = 1;
    else if (a.want_model) {
        a.ma.seed = a.seed;
        rc = model_error_report(a.path, &f, a.qvertex, a.qlight, &a.ma, a.json);
    } else if (a.qvertex) rc = query(a.path, &f, a.qvertex, a.qlight, a.have_view ? a.ma.view : NULL, a.json);
    else if (a.want_error) {
        a.ea.views = a.views;
        a.ea.seed = a.seed;
        a.ea.interp = (sss_interp)a.interp;
        rc = error_report(a.path, &f, &a.ea, a.json);
    } else {
        rc = summary(a.path, &f, a.json);
    }
    sss_file_free(&f);
    return rc;
}
