/* fuzz_plan.c: libFuzzer harness for scene files end to end through the
 * planner (common/src/scene.c, precompute/src/bake/planner.c;
 * docs/robustness.md items 8, 9): the input is the text of a scene file in
 * a directory that holds a small mesh (m.ply, a 42-vertex sphere; c.ply, a
 * cube) and a small probe (sky.exr). What sss-bake --scene --plan does runs
 * on it: load (sss_scene_load, from a file), import every object's mesh and
 * place it (sss_scene_object_world), plan (sss_plan_scene_limited, 256 MiB),
 * and print the plan as text and JSON. Each step must refuse with one line
 * or hand out what the next one relies on: a plan whose every object has a
 * light effect, every light a valid pass or none, at most 1024 rows of
 * static directions, decisions within their array, and JSON that parses. */
#define _POSIX_C_SOURCE 200809L
#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "genmesh.h"
#include "sss/import.h"
#include "sss/planner.h"
#include "sss/probe.h"
#include "sss/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[128], scene_path[200];

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc, (void)argv;
    snprintf(dir, sizeof dir, "/tmp/sss-fuzz-plan-%ld", (long)getpid());
    mkdir(dir, 0700);
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", dir);
    char p[256];
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_sphere(&m, 1.0, 1, &err) != SSS_OK) abort();
    snprintf(p, sizeof p, "%s/m.ply", dir);
    if (sss_export_ply(p, &m, &err) != SSS_OK) abort();
    sss_mesh_free(&m);
    if (sss_gen_by_name("cube", 1, 1.0, &m, &err) != SSS_OK) abort();
    snprintf(p, sizeof p, "%s/c.ply", dir);
    if (sss_export_ply(p, &m, &err) != SSS_OK) abort();
    sss_mesh_free(&m);
    sss_probe pr = {8, 4, NULL};
    pr.rgb = malloc(3 * 8 * 4 * sizeof(float));
    if (!pr.rgb) abort();
    for (int i = 0; i < 3 * 8 * 4; i++) pr.rgb[i] = 0.25f + 0.01f * (float)i;
    snprintf(p, sizeof p, "%s/sky.exr", dir);
    if (sss_probe_write(p, &pr, &err) != SSS_OK) abort();
    sss_probe_free(&pr);
    return 0;
}

static int one_line_naming(const char *msg, const char *what) { return strstr(msg, what) && !strchr(msg, '\n'); }

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    FILE *fp = fopen(scene_path, "wb");
    if (!fp) return 0;
    if (size && fwrite(data, 1, size, fp) != size) {
        fclose(fp);
        return 0;
    }
    fclose(fp);
    sss_scene sc;
    sss_error err = {{0}};
    if (sss_scene_load(scene_path, &sc, &err) != SSS_OK) {
        if (!one_line_naming(err.msg, scene_path)) abort();
        return 0;
    }
    /* bounded work per input: the harness's meshes are small, but a scene
     * may name one mesh many times */
    if (sc.nobjects > 16 || sc.nlights > 4096) {
        sss_scene_free(&sc);
        return 0;
    }
    sss_mesh *world = calloc(sc.nobjects, sizeof *world);
    if (!world) abort();
    uint32_t placed = 0;
    sss_result r = SSS_OK;
    for (; placed < sc.nobjects && r == SSS_OK; placed++) {
        sss_mesh m;
        r = sss_import_mesh(sc.objects[placed].mesh, &m, NULL, &err);
        if (r != SSS_OK) {
            if (strchr(err.msg, '\n')) abort();
            break;
        }
        r = sss_scene_object_world(&sc.objects[placed], &m, &world[placed], &err);
        sss_mesh_free(&m);
        if (r != SSS_OK) {
            if (strchr(err.msg, '\n')) abort();
            break;
        }
        for (size_t i = 0; i < 3 * (size_t)world[placed].nv; i++)
            if (!(fabs((double)world[placed].pos[i]) <= SSS_COORD_MAX)) abort(); /* placed within range */
    }
    if (r == SSS_OK) {
        sss_plan plan;
        r = sss_plan_scene_limited(&sc, world, (uint64_t)256 << 20, &plan, &err);
        if (r != SSS_OK) {
            if (!one_line_naming(err.msg, scene_path) && !strstr(err.msg, "planner:")) abort();
        } else {
            if (plan.nobjects != sc.nobjects) abort();
            for (uint32_t i = 0; i < plan.nobjects; i++) {
                const sss_object_plan *o = &plan.obj[i];
                if (!(o->effects & (SSS_FX_DIR_EXACT | SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH))) abort();
                if (o->channels != 1 && o->channels != 3) abort();
                if (o->ndecisions > SSS_PLAN_MAX_DECISIONS || o->exact_rows > SSS_PLAN_MAX_EXACT) abort();
                if (!!(o->effects & SSS_FX_DIR_EXACT) != (o->exact_rows > 0)) abort();
                uint32_t counted[SSS_PASS_KINDS] = {0};
                for (uint32_t l = 0; l < sc.nlights; l++) {
                    if (o->light_pass[l] == UINT32_MAX) continue;
                    if (o->light_pass[l] >= SSS_PASS_KINDS) abort();
                    counted[o->light_pass[l]]++;
                }
                for (int k = 0; k < SSS_PASS_KINDS; k++)
                    if (counted[k] != o->pass_lights[k]) abort();
            }
            FILE *devnull = fopen("/dev/null", "w");
            if (devnull) {
                sss_plan_print(&sc, &plan, devnull);
                fclose(devnull);
            }
            char *json = sss_plan_json(&sc, &plan);
            if (json) {
                cJSON *back = cJSON_Parse(json);
                if (!back) abort(); /* the plan's JSON is JSON */
                cJSON_Delete(back);
                free(json);
            }
            sss_plan_free(&plan);
        }
    }
    for (uint32_t i = 0; i < sc.nobjects; i++) sss_mesh_free(&world[i]);
    free(world);
    sss_scene_free(&sc);
    return 0;
}
