/* test_scene_util.h: what the scene-bake tests start from (header-only,
 * as test_util.h): a scene parsed from its text as if read from
 * DIR/scene.json, each object's mesh imported and placed in the world, and
 * the plan made. */
#ifndef SSS_TEST_SCENE_UTIL_H
#define SSS_TEST_SCENE_UTIL_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/import.h"
#include "sss/planner.h"
#include "sss/scene.h"

typedef struct test_scene {
    sss_scene sc;
    sss_mesh *world; /* one per object, world units */
    sss_plan plan;
} test_scene;

static inline sss_result test_scene_load(test_scene *b, const char *dir, const char *json, sss_error *err)
{
    char path[400];
    snprintf(path, sizeof path, "%s/scene.json", dir);
    memset(b, 0, sizeof *b);
    sss_result r = sss_scene_parse(json, path, &b->sc, err);
    if (r != SSS_OK) return r;
    b->world = calloc(b->sc.nobjects ? b->sc.nobjects : 1, sizeof *b->world);
    if (!b->world) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    for (uint32_t i = 0; i < b->sc.nobjects; i++) {
        sss_mesh m;
        if ((r = sss_import_mesh(b->sc.objects[i].mesh, &m, NULL, err)) != SSS_OK) return r;
        r = sss_scene_object_world(&b->sc.objects[i], &m, &b->world[i], err);
        sss_mesh_free(&m);
        if (r != SSS_OK) return r;
    }
    return sss_plan_scene(&b->sc, b->world, &b->plan, err);
}

static inline void test_scene_unload(test_scene *b)
{
    for (uint32_t i = 0; b->world && i < b->sc.nobjects; i++) sss_mesh_free(&b->world[i]);
    free(b->world);
    sss_plan_free(&b->plan);
    sss_scene_free(&b->sc);
}

#endif
