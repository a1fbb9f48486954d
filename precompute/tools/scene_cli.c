/* scene_cli.c: `sss-bake --scene S.json [--plan [--json]] -o DIR` (docs/scenes.md):
 * load the scene, import and place every object, plan, then print the plan
 * or bake each object on its own into DIR/NAME.sss (scattering stays inside
 * an object, seed 001 §2.1, so objects never share a file). */
#define _POSIX_C_SOURCE 200809L
#include "sss/clock.h"
#include "scene_cli.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sss/bake_scene.h"
#include "sss/cli.h"
#include "sss/fileio.h"
#include "sss/jsontext.h"
#include "sss/import.h"
#include "sss/planner.h"

/* An object's failure, one line: a scene's names the object by its JSON
 * path; a plain bake's (--point-light, one object) the mesh alone, as the
 * plain bake's messages do. */
static void object_error(const char *tool, const sss_scene *sc, int plain, uint32_t i, const char *key, const char *msg)
{
    if (plain) sss_cli_printf(stderr, "%s: %s\n", tool, msg);
    else sss_cli_printf(stderr, "%s: %s: /objects/%u%s: %s\n", tool, sc->path, i, key, msg);
}

static int bake_scene(const char *tool, sss_scene *sc_in, const char *scene_path, const char *outdir,
                      const char *outfile, int plan_only, int json, int quiet, const sss_bake_options *opt);

int scene_main(const char *tool, const char *scene_path, const char *outdir, int plan_only, int json, int quiet,
               const sss_bake_options *opt)
{
    sss_error err = {{0}};
    sss_scene sc;
    if (sss_scene_load(scene_path, &sc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
        return 2;
    }
    return bake_scene(tool, &sc, scene_path, outdir, NULL, plan_only, json, quiet, opt);
}

int points_main(const char *tool, const char *mesh, const char *out, const sss_material *mat, double mm_per_unit,
                const double (*points)[4], int npoints, int json, int quiet, const sss_bake_options *opt)
{
    sss_scene sc;
    memset(&sc, 0, sizeof sc);
    if (strlen(mesh) >= sizeof sc.path) {
        sss_cli_printf(stderr, "%s: MESH: path longer than %d bytes\n", tool, SSS_SCENE_PATH_MAX - 1);
        return 2;
    }
    snprintf(sc.path, sizeof sc.path, "%s", mesh);
    sc.objects = calloc(1, sizeof *sc.objects);
    sc.lights = calloc((size_t)npoints + 1, sizeof *sc.lights);
    if (!sc.objects || !sc.lights) {
        sss_scene_free(&sc);
        sss_cli_printf(stderr, "%s: out of memory\n", tool);
        return 1;
    }
    sc.nobjects = 1;
    sss_scene_object *o = &sc.objects[0];
    snprintf(o->name, sizeof o->name, "object0");
    snprintf(o->mesh, sizeof o->mesh, "%s", mesh);
    o->material = *mat;
    o->mm_per_unit = mm_per_unit > 0 ? mm_per_unit : 1.0;
    o->scale = 1.0;
    /* what a plain bake holds, the direction set for --light (a moving
     * directional light: docs/scenes.md, the planner's light rule), and
     * each point light marked moving, so that the planner gives it the
     * point-shells effect (§3.3) wherever it stands and the viewer may
     * move it (docs/viewer.md) */
    sc.nlights = (uint32_t)npoints + 1;
    sc.lights[0] = (sss_scene_light){.kind = SSS_LIGHT_DIRECTIONAL, .moving = 1, .direction = {0, 0, 1},
                                     .intensity = 1, .colour = {1, 1, 1}};
    for (int k = 0; k < npoints; k++)
        sc.lights[k + 1] = (sss_scene_light){.kind = SSS_LIGHT_POINT, .moving = 1,
                                             .position = {points[k][0], points[k][1], points[k][2]},
                                             .intensity = points[k][3] > 0 ? points[k][3] : 1, .colour = {1, 1, 1}};
    sc.bake.dirs = opt->n_dirs;
    return bake_scene(tool, &sc, NULL, NULL, out, 0, json, quiet, opt);
}

/* The bake of a loaded scene (freed here): every object into DIR/NAME.sss
 * (outdir), or the one object into outfile (points_main); scene_path, when
 * there is one, is an input no output may be. */
static int bake_scene(const char *tool, sss_scene *sc_in, const char *scene_path, const char *outdir,
                      const char *outfile, int plan_only, int json, int quiet, const sss_bake_options *opt)
{
    sss_error err = {{0}};
    sss_scene sc = *sc_in;
    /* --gather where the scene's "bake" says nothing (the planner's gather
     * rule); one that contradicts the scene is refused, as the plain bake's
     * options are (docs/scenes.md, "Bake"), rather than ignored */
    if (opt && opt->gather && sc.bake.gather && sc.bake.gather != (uint32_t)opt->gather) {
        static const char *const name[] = {"", "direct", "tree"};
        sss_cli_printf(stderr, "%s: %s: /bake/gather is \"%s\": --gather %s contradicts it\n", tool,
                       scene_path ? scene_path : "scene", name[sc.bake.gather <= 2 ? sc.bake.gather : 0],
                       name[opt->gather <= 2 ? opt->gather : 0]);
        sss_scene_free(&sc);
        return 2;
    }
    if (!sc.bake.gather && opt) sc.bake.gather = (uint32_t)opt->gather;
    const int plain = outfile != NULL;
    if (!plan_only && !plain) {
        struct stat sb;
        if (!outdir) {
            sss_cli_printf(stderr, "%s: --scene needs -o DIR (one NAME.sss per object) or --plan\n", tool);
            sss_scene_free(&sc);
            return 2;
        }
        if (stat(outdir, &sb) != 0 || !S_ISDIR(sb.st_mode)) {
            sss_cli_printf(stderr, "%s: %s: -o with --scene must be an existing directory\n", tool, outdir);
            sss_scene_free(&sc);
            return 2;
        }
    }
    int rc = 0;
    sss_mesh *world = calloc(sc.nobjects, sizeof *world);
    sss_plan plan = {0};
    cJSON *report = json && !plan_only ? cJSON_CreateArray() : NULL;
    /* every file the bake reads (the scene, its meshes and probes): no
     * output may be one of them (sss/fileio.h) */
    const char **inputs = calloc((size_t)sc.nobjects + sc.nlights + 1, sizeof *inputs);
    sss_atomic *pending = calloc((size_t)sc.nobjects + 1, sizeof *pending);
    char (*outpath)[2048] = calloc((size_t)sc.nobjects + 1, sizeof *outpath);
    uint32_t npending = 0;
    sss_inputs ins = {inputs, 0};
    if (!world || !inputs || !pending || !outpath) { sss_cli_printf(stderr, "%s: out of memory\n", tool); rc = 1; goto done; }
    if (scene_path) inputs[ins.n++] = scene_path;
    for (uint32_t i = 0; i < sc.nobjects; i++) inputs[ins.n++] = sc.objects[i].mesh;
    for (uint32_t l = 0; l < sc.nlights; l++)
        if (sc.lights[l].kind == SSS_LIGHT_ENVIRONMENT) inputs[ins.n++] = sc.lights[l].probe;
    /* every output checked before anything is baked (the writer checks
     * each again) */
    for (uint32_t i = 0; !plan_only && i < sc.nobjects; i++) {
        if (sc.objects[i].deform.kind != SSS_DEFORM_NONE) continue; /* per-frame: no file (docs/deformable.md §4) */
        const int n = plain ? snprintf(outpath[i], sizeof outpath[i], "%s", outfile)
                            : snprintf(outpath[i], sizeof outpath[i], "%s/%s.sss", outdir, sc.objects[i].name);
        if (n < 0 || (size_t)n >= sizeof outpath[i]) {
            sss_cli_printf(stderr, "%s: %s: -o %s too long\n", tool, plain ? outfile : outdir, plain ? "file name" :
                           "directory name");
            rc = 2;
            goto done;
        }
        if (sss_output_check(outpath[i], &ins, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
            rc = 1;
            goto done;
        }
    }
    for (uint32_t i = 0; i < sc.nobjects; i++) {
        sss_mesh m;
        sss_import_report rep;
        /* a scene's glTF is read at t = 0 of its clip, and an animated
         * rig makes the object deform (docs/deformable.md §5); a plain bake
         * reads the mesh as it is */
        if ((plain ? sss_import_mesh(sc.objects[i].mesh, &m, &rep, &err)
                   : sss_import_mesh_at(sc.objects[i].mesh, 0.0, &m, &rep, &err)) != SSS_OK) {
            object_error(tool, &sc, plain, i, "/mesh", err.msg);
            rc = 1;
            goto done;
        }
        {
            char prefix[1200], shown[1100];
            snprintf(prefix, sizeof prefix, "%s: %s", tool, sss_cli_shown(sc.objects[i].mesh, shown, sizeof shown));
            sss_import_print_warnings(&rep, prefix, stderr); /* as a plain bake prints them */
        }
        sc.objects[i].animated = !plain && rep.animated;
        sss_result r = sss_scene_object_world(&sc.objects[i], &m, &world[i], &err);
        sss_mesh_free(&m);
        if (r != SSS_OK) {
            object_error(tool, &sc, plain, i, "", err.msg);
            rc = 1;
            goto done;
        }
    }
    if (sss_plan_scene_limited(&sc, world, opt->memory_limit, &plan, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
        rc = 2;
        goto done;
    }
    if (plan_only) {
        if (json) {
            char *s = sss_plan_json(&sc, &plan);
            if (s) puts(s);
            free(s);
        } else {
            sss_plan_print(&sc, &plan, stdout);
        }
        goto done;
    }
    /* Each object's file is encoded into a temporary file as soon as it is
     * baked; all of them replace their targets only once every object is
     * baked (sss/fileio.h), so a failure leaves no part of the set. */
    for (uint32_t i = 0; i < sc.nobjects; i++) {
        const char *path = outpath[i];
        if (plan.obj[i].per_frame) {
            /* a deforming object: nothing of one pose holds for the next, so
             * no file; its q is evaluated per frame (docs/deformable.md §4) */
            if (!quiet)
                sss_cli_printf(stderr, "%s: object '%s' %s: evaluated per frame, nothing baked (see --plan)\n",
                               tool, sc.objects[i].name, sc.objects[i].editable ? "is editable" : "deforms");
            if (report) {
                cJSON *o = cJSON_CreateObject();
                cJSON_AddStringToObject(o, "object", sc.objects[i].name);
                cJSON_AddBoolToObject(o, "per_frame", 1);
                cJSON_AddItemToArray(report, o);
            }
            continue;
        }
        sss_bake_file f;
        sss_bake_stats st;
        double t0 = sss_now();
        if (sss_bake_object(&sc, &plan, world, i, opt, &f, &st, &err) != SSS_OK) {
            object_error(tool, &sc, plain, i, "", err.msg);
            rc = 1;
            goto done;
        }
        double tb = sss_now() - t0;
        uint8_t *buf = NULL;
        size_t len = 0;
        sss_result r = sss_file_encode_named(&f, path, &buf, &len, &err);
        if (r == SSS_OK) r = sss_atomic_begin(&pending[npending], path, &ins, &err);
        if (r == SSS_OK) {
            npending++;
            r = sss_atomic_write(&pending[npending - 1], buf, len, &err);
        }
        free(buf);
        if (r != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
            sss_file_free(&f);
            rc = 1;
            goto done;
        }
        const double bytes = (double)len;
        if (!quiet)
            sss_cli_printf(stderr, "%s: %s: %u vertices, %u channel%s, rays %llu, bake %.3fs, %.0f bytes (%.1f/vertex)\n",
                    tool, path, f.mesh.nv, f.channels, f.channels == 1 ? "" : "s", (unsigned long long)st.rays, tb,
                    bytes, bytes / f.mesh.nv);
        if (report) {
            cJSON *o = cJSON_CreateObject();
            cJSON_AddStringToObject(o, "object", sc.objects[i].name);
            cJSON_AddStringToObject(o, "output", path);
            cJSON_AddNumberToObject(o, "vertices", f.mesh.nv);
            cJSON_AddNumberToObject(o, "channels", f.channels);
            cJSON *fx = cJSON_AddArrayToObject(o, "effects");
            for (uint32_t b = 0; b < SSS_FX_COUNT; b++)
                if (f.fx.mask >> b & 1u) cJSON_AddItemToArray(fx, cJSON_CreateString(sss_effect_name(b)));
            /* what the planner's storage rule did (docs/scenes.md) */
            cJSON_AddStringToObject(o, "weights", f.weights == SSS_WEIGHTS_HAT ? "hat" : "point");
            if (f.fx.mask & SSS_FX_DIR_SET) cJSON_AddStringToObject(o, "storage", sss_quant_name(f.quant));
            if (f.near_terms) cJSON_AddNumberToObject(o, "near_radius_mm", f.near_radius_mm);
            cJSON_AddNumberToObject(o, "rays", (double)st.rays);
            cJSON_AddNumberToObject(o, "bake_seconds", tb);
            /* the plain bake's keys: which gather summed the rows (the
             * planner's gather rule), and the process's peak so far */
            cJSON_AddStringToObject(o, "gather", st.gather == SSS_GATHER_TREE ? "tree" : "direct");
            cJSON_AddNumberToObject(o, "peak_rss_mib", sss_cli_peak_rss_mib());
            cJSON_AddNumberToObject(o, "file_bytes", bytes);
            cJSON_AddNumberToObject(o, "bytes_per_vertex", bytes / f.mesh.nv);
            cJSON_AddItemToArray(report, o);
        }
        sss_file_free(&f);
    }
    for (uint32_t i = 0; i < npending; i++) {
        sss_result r = sss_atomic_commit(&pending[i], &err);
        if (r != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s\n", tool, err.msg);
            rc = 1;
            for (uint32_t k = i + 1; k < npending; k++) sss_atomic_abort(&pending[k]);
            npending = 0;
            goto done;
        }
    }
    npending = 0;
    if (report) {
        sss_json_utf8(report); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
        char *s = cJSON_PrintUnformatted(report);
        if (s) puts(s);
        free(s);
    }
done:
    for (uint32_t i = 0; i < npending; i++) sss_atomic_abort(&pending[i]);
    free(pending);
    free(inputs);
    free(outpath);
    cJSON_Delete(report);
    sss_plan_free(&plan);
    for (uint32_t i = 0; world && i < sc.nobjects; i++) sss_mesh_free(&world[i]);
    free(world);
    sss_scene_free(&sc);
    return rc;
}
