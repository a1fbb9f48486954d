/* fuzz_scene.c: libFuzzer harness for the scene parser (docs/robustness.md, "the
 * scene/material parser"; scene files: docs/scenes.md). The input
 * is the text of a scene file. sss_scene_parse must refuse it with a message
 * that starts with the file name and names a JSON path, or return a scene
 * whose numbers are finite and inside the ranges docs/scenes.md promises:
 * unit light directions, non-negative intensities and colours, materials
 * that pass sss_material_validate, positive scale and mm per unit. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sss/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The parser takes NUL-terminated text, as sss_scene_load hands it. */
    char *text = malloc(size + 1);
    if (!text) return 0;
    memcpy(text, data, size);
    text[size] = 0;
    static const char path[] = "fuzz/scene.json";
    sss_scene sc;
    sss_error err = {{0}};
    sss_result r = sss_scene_parse(text, path, &sc, &err);
    free(text);
    if (r != SSS_OK) {
        /* One line, naming the file first. */
        if (strncmp(err.msg, path, sizeof path - 1) != 0) abort();
        if (strchr(err.msg, '\n')) abort();
        return 0;
    }
    if (sc.nobjects == 0 || !sc.objects) abort();
    for (uint32_t i = 0; i < sc.nobjects; i++) {
        const sss_scene_object *o = &sc.objects[i];
        sss_error e2 = {{0}};
        if (sss_material_validate(&o->material, &e2) != SSS_OK) abort();
        if (!(o->mm_per_unit > 0) || !isfinite(o->mm_per_unit)) abort();
        if (!(o->scale > 0) || !isfinite(o->scale)) abort();
        if (!finite3(o->translate) || !finite3(o->rotate_deg)) abort();
        if (!memchr(o->name, 0, sizeof o->name) || !memchr(o->mesh, 0, sizeof o->mesh)) abort();
        /* layer depths (docs/layers.md §3): a number, a map with a path and
         * a positive scale, or a pattern with 0 <= min <= max */
        for (uint32_t k = 0; k < o->layers.n; k++) {
            const sss_depth_spec *d = &o->layer_depth[k];
            if (!(o->layers.layer[k].depth >= 0) || !(o->layers.layer[k].depth <= SSS_DEPTH_MAX_MM)) abort();
            if (d->kind == SSS_DEPTH_MAP && (!d->map[0] || !memchr(d->map, 0, sizeof d->map) || !(d->scale_mm > 0)))
                abort();
            if (d->kind == SSS_DEPTH_PROCEDURAL &&
                (d->pattern < SSS_DEPTH_VEINS || d->pattern > SSS_DEPTH_BUMPS || !(d->scale_mm > 0) ||
                 !(d->range_mm[0] >= 0) || !(d->range_mm[1] >= d->range_mm[0]) || !(d->range_mm[1] <= SSS_DEPTH_MAX_MM)))
                abort();
            if (d->kind > SSS_DEPTH_PROCEDURAL) abort();
        }
        /* a skin the parser accepts is a chain the pose accepts
         * (docs/deformable.md §2, sss_skin_check) */
        int bone;
        const char *key;
        if (o->deform.kind == SSS_DEFORM_SKIN && sss_skin_check(&o->deform.skin, &bone, &key, &e2) != SSS_OK) abort();
    }
    for (uint32_t i = 0; i < sc.nlights; i++) {
        const sss_scene_light *l = &sc.lights[i];
        if (!(l->intensity >= 0) || !isfinite(l->intensity)) abort();
        for (int k = 0; k < 3; k++)
            if (!(l->colour[k] >= 0) || !isfinite(l->colour[k])) abort();
        if (l->kind == SSS_LIGHT_DIRECTIONAL) {
            const double *d = l->direction;
            double n = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if (!(fabs(n - 1.0) < 1e-9)) abort();
        }
        if (l->kind == SSS_LIGHT_POINT && !finite3(l->position)) abort();
        if (!memchr(l->probe, 0, sizeof l->probe)) abort();
    }
    sss_scene_free(&sc);
    return 0;
}
