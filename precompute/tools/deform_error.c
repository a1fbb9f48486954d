/* deform_error.c: sss-stat --scene S.json --time T --error
 * (deform_error.h, docs/deformable.md §4). For each deforming object: the
 * pose at T (sss_scene_object_posed), q from the per-frame path as sss-view
 * runs it (tree gather, the paper's point weights unless the scene asks for
 * hat weights: runtime/src/view/pose.c) against the exact evaluator
 * (sss/exact.h) built on a file holding that pose, at random light
 * directions; the error figures are sss_err_accum's, as for a file's
 * --error (area-weighted RMS, relative RMS, max). */
#include "deform_error.h"
#include "image_error.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/cli.h"
#include "sss/decode.h"
#include "sss/deform.h"
#include "sss/exact.h"
#include "sss/import.h"
#include "sss/jsontext.h"
#include "sss/perframe.h"
#include "sss/random.h"
#include "sss/scene.h"
#include "sss/vec3.h"

/* The approximate image's q (image_error.h): the per-frame path on the pose. */
typedef struct perframe_ctx {
    const sss_mesh *pose;
    const sss_material *m;
    uint32_t C;
    double mpw;
    const sss_perframe_options *po;
} perframe_ctx;

static sss_result perframe_approx(void *ctx, const double light[3], float *q, sss_error *err)
{
    const perframe_ctx *c = ctx;
    return sss_perframe_q(c->pose, c->m, c->C, c->mpw, light, c->po, q, NULL, err);
}

/* One object: 0, or 1 after a message; *measured 0 when it does not
 * deform (its mesh read at t, where a glTF's rig may move it). */
static int measure(const char *tool, sss_scene *sc, uint32_t i, double t, uint32_t views, uint64_t seed, cJSON *arr,
                   int *measured)
{
    sss_scene_object *o = &sc->objects[i];
    sss_error err = {{0}};
    sss_mesh rest = {0}, pose = {0};
    sss_exact *e = NULL;
    float *x = NULL, *r = NULL;
    double *area = NULL;
    int rc = 1;
    sss_import_report rep;
    *measured = 0;
    if (sss_import_mesh_at(o->mesh, t, &rest, &rep, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/%u/mesh: %s\n", tool, sc->path, i, err.msg);
        goto done;
    }
    o->animated = rep.animated;
    if (!sss_scene_object_deforms(o)) {
        rc = 0;
        goto done;
    }
    *measured = 1;
    /* with a field the per-frame path is the exact sum of the endpoints'
     * product (docs/deformable.md §10), and the exact evaluator of a file
     * reads FELD at the pose with the transmittance: no tree to measure,
     * and not the same model */
    if (o->hetero.field.kind != SSS_FIELD_NONE) {
        sss_cli_printf(stderr, "%s: %s: /objects/%u/material/field: a deforming object with a field is evaluated by "
                       "the exact sum already (docs/deformable.md sec. 10): --error has nothing to measure\n", tool,
                       sc->path, i);
        goto done;
    }
    if (sss_scene_object_posed(o, &rest, t, &pose, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/%u: %s\n", tool, sc->path, i, err.msg);
        goto done;
    }
    const uint32_t C = sss_material_channels(&o->material), nv = pose.nv;
    const uint32_t weights = sc->bake.weights == SSS_SCENE_WEIGHTS_HAT ? SSS_WEIGHTS_HAT : SSS_WEIGHTS_POINT;
    const double eps = sc->bake.eps > 0 ? sc->bake.eps : 1e-3, mpw = sss_scene_object_mm_per_world_unit(o);
    /* the exact evaluator reads a file: this one holds the pose and what
     * the per-frame path was given */
    sss_bake_file f;
    memset(&f, 0, sizeof f);
    f.mesh = pose;
    f.mesh.area = NULL;
    f.material = o->material;
    f.mm_per_unit = mpw;
    f.channels = C;
    f.eps = eps;
    f.weights = weights;
    if (sss_exact_create(&f, &e, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/%u: %s\n", tool, sc->path, i, err.msg);
        goto done;
    }
    x = malloc((size_t)nv * C * sizeof *x);
    r = malloc((size_t)nv * C * sizeof *r);
    area = malloc((size_t)nv * sizeof *area);
    if (!x || !r || !area) {
        sss_cli_printf(stderr, "%s: out of memory for %u vertices\n", tool, nv);
        goto done;
    }
    sss_mesh_vertex_areas(&pose, area);
    sss_err_accum acc;
    sss_err_accum_init(&acc, C, area, nv);
    const sss_perframe_options po = {.mode = SSS_PERFRAME_TREE, .weights = weights, .eps = eps};
    uint64_t state = seed;
    for (uint32_t k = 0; k < views; k++) {
        double d[3];
        sss_rng_direction(&state, d);
        sss_exact_eval(e, d, x);
        if (sss_perframe_q(&pose, &o->material, C, mpw, d, &po, r, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s: /objects/%u: %s\n", tool, sc->path, i, err.msg);
            goto done;
        }
        sss_err_accum_add(&acc, area, r, x, nv);
    }
    double rms[SSS_MAX_CHANNELS + 1], rel[SSS_MAX_CHANNELS + 1], mx[SSS_MAX_CHANNELS + 1], ref[SSS_MAX_CHANNELS + 1];
    sss_err_accum_result(&acc, rms, rel, mx, ref);
    /* the image error (Hao–Varshney 2004 §3.3, image_error.c's protocol):
     * the per-frame path's picture of the pose against the exact one's,
     * one line saying why when there is no OpenGL */
    sss_image_error ie;
    memset(&ie, 0, sizeof ie);
    char image_status[600] = "ok";
    {
        perframe_ctx pc = {&pose, &o->material, C, mpw, &po};
        sss_image_error_opts io;
        memset(&io, 0, sizeof io);
        io.views = views;
        io.seed = seed;
        io.approx = perframe_approx;
        io.approx_ctx = &pc;
        sss_error ierr = {{0}};
        const sss_result ir = sss_image_error_measure(&f, e, &io, &ie, &ierr);
        if (ir == SSS_ERR_UNSUPPORTED) {
            snprintf(image_status, sizeof image_status, "unavailable: %s", ierr.msg);
            sss_cli_printf(stderr, "%s: %s: /objects/%u: image error unavailable (no OpenGL 4.3 context): %s\n", tool,
                           sc->path, i, ierr.msg);
        } else if (ir != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s: /objects/%u: image error: %s\n", tool, sc->path, i, ierr.msg);
            goto done;
        }
    }
    const int have_image = !strcmp(image_status, "ok");
    const double theta = sss_deform_angle(&o->deform, t) * 180.0 / SSS_PI;
    const char *wn = weights == SSS_WEIGHTS_HAT ? "hat" : "point";
    if (arr) {
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "object", o->name);
        cJSON_AddStringToObject(j, "deform", sss_deform_kind_name(o->deform.kind));
        cJSON_AddBoolToObject(j, "animated", o->animated);
        cJSON_AddNumberToObject(j, "time", t);
        cJSON_AddNumberToObject(j, "theta_deg", theta);
        cJSON_AddNumberToObject(j, "vertices", nv);
        cJSON_AddNumberToObject(j, "channels", C);
        cJSON_AddNumberToObject(j, "views", views);
        cJSON_AddStringToObject(j, "path", "tree");
        cJSON_AddStringToObject(j, "weights", wn);
        cJSON_AddNumberToObject(j, "rms", rms[C]);
        cJSON_AddNumberToObject(j, "rel_rms", rel[C]);
        cJSON_AddNumberToObject(j, "max_abs", mx[C]);
        cJSON_AddNumberToObject(j, "rms_exact", ref[C]);
        cJSON_AddStringToObject(j, "image_error_status", image_status);
        if (have_image) sss_image_error_json(&ie, cJSON_AddObjectToObject(j, "image_error"));
        else cJSON_AddNullToObject(j, "image_error");
        cJSON_AddItemToArray(arr, j);
    } else {
        char motion[96];
        sss_scene_object_motion(o, t, motion, sizeof motion);
        printf("%s: object '%s' at t = %g s (%s), %u vertices, %u views: per-frame q (tree gather, "
               "%s weights) against the exact evaluator on the pose: relative RMS %.3e, RMS %.3e, max |diff| %.3e "
               "(RMS of q %.3e)\n", sc->path, o->name, t, motion, nv, views, wn,
               rel[C], rms[C], mx[C], ref[C]);
        if (have_image)
            printf("  image RMS (section 3.3) over %u views, %dx%d, exposure %.4g: max %.4g, mean %.4g, median %.4g "
                   "(worst view %u; over its covered pixels %.4g; %s)\n", ie.views, ie.width, ie.height, ie.exposure,
                   ie.rms_max, ie.rms_mean, ie.rms_median, ie.worst, ie.rms_max_covered, ie.gl_renderer);
    }
    rc = 0;
done:
    sss_exact_destroy(e);
    free(x);
    free(r);
    free(area);
    sss_mesh_free(&rest);
    sss_mesh_free(&pose);
    return rc;
}

int sss_deform_error_report(const char *tool, const char *scene, double t, uint32_t views, uint64_t seed, int json)
{
    sss_scene sc;
    sss_error err = {{0}};
    if (sss_scene_load(scene, &sc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
        return 2;
    }
    cJSON *root = json ? cJSON_CreateObject() : NULL, *arr = NULL;
    if (root) {
        cJSON_AddStringToObject(root, "scene", scene);
        arr = cJSON_AddArrayToObject(root, "objects");
    }
    int rc = 0;
    uint32_t n = 0;
    for (uint32_t i = 0; i < sc.nobjects && rc == 0; i++) {
        int measured = 0;
        rc = measure(tool, &sc, i, t, views, seed, arr, &measured);
        n += (uint32_t)measured;
    }
    if (rc == 0 && !n) {
        sss_cli_printf(stderr, "%s: %s: /objects: no object deforms: measure each baked file (sss-stat FILE.sss "
                       "--error)\n", tool, scene);
        rc = 2;
    }
    if (root && rc == 0) {
        sss_json_utf8(root);
        char *s = cJSON_PrintUnformatted(root);
        if (s) puts(s);
        free(s);
    }
    cJSON_Delete(root);
    sss_scene_free(&sc);
    return rc;
}
