/* scene_edit.c: an edited material written back to a scene file
 * (sss/scene_edit.h, docs/heterogeneous.md §9.6). The scene's own JSON is
 * rewritten, not regenerated from the parsed scene, so that every key the
 * edit does not touch (lights, camera, bake settings, the other objects)
 * stays as the author wrote it.
 */
#define _XOPEN_SOURCE 700 /* realpath */
#include "sss/scene_edit.h"

#include <cjson/cJSON.h>
#include <errno.h>
#include <libgen.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/field.h"
#include "sss/fileio.h"
#include "sss/scene.h"

sss_result sss_scene_edited_path(const char *path, char *out, size_t n, sss_error *err)
{
    size_t len = strlen(path);
    if (len > 5 && strcmp(path + len - 5, ".json") == 0) len -= 5;
    const int w = snprintf(out, n, "%.*s.edited.json", (int)len, path);
    if (w < 0 || (size_t)w >= n) return sss_fail(err, SSS_ERR_ARG, "%s: the edited scene's path is too long", path);
    return SSS_OK;
}

/* The folder of p, resolved (realpath of its dirname), into d. */
static int folder_of(const char *p, char d[PATH_MAX])
{
    char *c = strdup(p);
    if (!c) return 0;
    const int ok = realpath(dirname(c), d) != NULL;
    free(c);
    return ok;
}

sss_result sss_scene_edited_check(const char *path, const char *out, sss_error *err)
{
    const char *const ins[1] = {path};
    const sss_inputs in = {ins, 1};
    sss_result r = sss_output_check(out, &in, NULL, err);
    if (r != SSS_OK) return r;
    char d[PATH_MAX];
    /* the write (sss_scene_write_edited) resolves the same folder */
    if (!folder_of(out, d)) return sss_fail(err, SSS_ERR_IO, "%s: its folder does not exist (%s)", out, strerror(errno));
    return SSS_OK;
}

/* x as the shortest decimal that reads back as x exactly (cJSON's own
 * printer accepts a last-bit difference): the written scene holds the
 * edited numbers bit for bit. */
static cJSON *number(double x)
{
    char buf[40];
    for (int digits = 15; digits <= 17; digits++) {
        snprintf(buf, sizeof buf, "%.*g", digits, x);
        if (strtod(buf, NULL) == x) break;
    }
    return cJSON_CreateRaw(buf);
}

static cJSON *triple(const double v[3])
{
    cJSON *a = cJSON_CreateArray();
    for (int k = 0; a && k < 3; k++) {
        cJSON *n = number(v[k]);
        if (!n || !cJSON_AddItemToArray(a, n)) {
            cJSON_Delete(n);
            cJSON_Delete(a);
            return NULL;
        }
    }
    return a;
}

/* obj[key] = v, replacing any value there; 0 when out of memory. */
static int put(cJSON *obj, const char *key, cJSON *v)
{
    if (!v) return 0;
    if (cJSON_GetObjectItemCaseSensitive(obj, key)) return cJSON_ReplaceItemInObjectCaseSensitive(obj, key, v) != 0;
    return cJSON_AddItemToObject(obj, key, v) != 0;
}

/* The material as numbers (what the edits leave), the field and every
 * other key of the old one (layers) kept. */
static int material_json(cJSON *ob, const sss_htsm_material *m, int has_field)
{
    cJSON *old = cJSON_DetachItemFromObjectCaseSensitive(ob, "material");
    cJSON *mj = cJSON_IsObject(old) ? old : cJSON_CreateObject();
    if (mj != old) cJSON_Delete(old);
    if (!mj || !cJSON_AddItemToObject(ob, "material", mj)) return 0;
    /* the keys that made the old numbers: the new numbers replace them all */
    static const char *const made[] = {"preset", "sigma_a", "sigmap_s", "sigma_s", "g", "transport", "eta", "inside"};
    for (size_t k = 0; k < sizeof made / sizeof made[0]; k++) cJSON_DeleteItemFromObjectCaseSensitive(mj, made[k]);
    if (!put(mj, "sigma_a", triple(m->base.sigma_a)) || !put(mj, "sigmap_s", triple(m->base.sigmap_s)) ||
        !put(mj, "eta", number(m->base.eta)))
        return 0;
    if (!has_field) return 1;
    /* min(1, s f) = s f for s ≤ 1 (f ≤ 1), and the blend is linear in f:
     * base + s f (inside − base) = base + f (blend(base, inside, s) − base) */
    sss_material in = m->inside;
    if (m->strength <= 1.0) sss_material_blend(&m->base, &m->inside, m->strength, &in);
    cJSON *ij = cJSON_CreateObject();
    if (!ij || !cJSON_AddItemToObject(mj, "inside", ij)) {
        cJSON_Delete(ij);
        return 0;
    }
    if (!put(ij, "sigma_a", triple(in.sigma_a)) || !put(ij, "sigmap_s", triple(in.sigmap_s))) return 0;
    cJSON *fj = cJSON_GetObjectItemCaseSensitive(mj, "field");
    if (!cJSON_IsObject(fj)) return 0;
    if (m->strength <= 1.0) {
        cJSON_DeleteItemFromObjectCaseSensitive(fj, "strength");
        return 1;
    }
    return put(fj, "strength", number(m->strength));
}

/* j[key], where present, = the absolute form of the resolved path p. */
static sss_result absolute(cJSON *j, const char *key, const char *p, const char *scene, sss_error *err)
{
    if (!cJSON_IsObject(j) || !cJSON_GetObjectItemCaseSensitive(j, key) || !p[0]) return SSS_OK;
    char abs[PATH_MAX];
    if (!realpath(p, abs)) return sss_fail(err, SSS_ERR_IO, "%s: %s: cannot be resolved", scene, p);
    return put(j, key, cJSON_CreateString(abs)) ? SSS_OK : sss_fail(err, SSS_ERR_NOMEM, "out of memory");
}

sss_result sss_scene_write_edited(const char *path, uint32_t object, const sss_htsm_material *m, const char *out,
                                  sss_error *err)
{
    sss_scene sc;
    sss_result r = sss_scene_load(path, &sc, err);
    if (r != SSS_OK) return r;
    char *text = NULL, *printed = NULL;
    size_t len = 0;
    cJSON *root = NULL;
    if (object >= sc.nobjects) {
        r = sss_fail(err, SSS_ERR_ARG, "%s: /objects/%u: no such object", path, object);
        goto done;
    }
    if ((r = sss_input_read_all(path, (uint64_t)64 << 20, &text, &len, err)) != SSS_OK) goto done;
    root = cJSON_ParseWithLength(text, len);
    cJSON *objs = root ? cJSON_GetObjectItemCaseSensitive(root, "objects") : NULL;
    cJSON *ob = cJSON_GetArrayItem(objs, (int)object);
    if (!material_json(ob, m, sc.objects[object].hetero.field.kind != SSS_FIELD_NONE)) {
        r = sss_fail(err, SSS_ERR_NOMEM, "%s: /objects/%u/material: cannot be rewritten (out of memory)", path, object);
        goto done;
    }
    /* relative paths hold from the scene's folder only */
    char din[PATH_MAX], dout[PATH_MAX];
    if (!folder_of(path, din) || !folder_of(out, dout)) {
        r = sss_fail(err, SSS_ERR_IO, "%s: its folder cannot be resolved", folder_of(path, din) ? out : path);
        goto done;
    }
    if (strcmp(din, dout) != 0) {
        for (uint32_t i = 0; r == SSS_OK && i < sc.nobjects; i++) {
            cJSON *o = cJSON_GetArrayItem(objs, (int)i);
            r = absolute(o, "mesh", sc.objects[i].mesh, path, err);
            cJSON *mj = cJSON_IsObject(o) ? cJSON_GetObjectItemCaseSensitive(o, "material") : NULL;
            if (r == SSS_OK) r = absolute(cJSON_GetObjectItemCaseSensitive(mj, "field"), "vdb",
                                          sc.objects[i].field_path, path, err);
        }
        cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
        for (uint32_t l = 0; r == SSS_OK && l < sc.nlights; l++)
            r = absolute(cJSON_GetArrayItem(lights, (int)l), "probe", sc.lights[l].probe, path, err);
        if (r != SSS_OK) goto done;
    }
    printed = cJSON_Print(root);
    if (!printed) {
        r = sss_fail(err, SSS_ERR_NOMEM, "out of memory");
        goto done;
    }
    const char *const ins[1] = {path};
    const sss_inputs in = {ins, 1};
    sss_atomic a;
    if ((r = sss_atomic_begin(&a, out, &in, err)) != SSS_OK) goto done;
    r = sss_atomic_write(&a, printed, strlen(printed), err);
    if (r == SSS_OK) r = sss_atomic_write(&a, "\n", 1, err);
    if (r == SSS_OK) r = sss_atomic_commit(&a, err);
    else sss_atomic_abort(&a);
done:
    free(printed);
    cJSON_Delete(root);
    free(text);
    sss_scene_free(&sc);
    return r;
}
