/* An editable object's edited material written back to its scene
 * (sss/scene_edit.h, docs/heterogeneous.md §9.6): the written scene loads
 * with the edited numbers; a strength at most 1 is folded into the inside,
 * which gives the same material at every f; one above 1 is kept as the
 * field's key; every other key stays; the input is never written, and a
 * failure leaves no file; another folder gets absolute paths. */
#define _XOPEN_SOURCE 700 /* mkdtemp, realpath */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <dirent.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sss/field.h"
#include "sss/fileio.h"
#include "sss/scene.h"
#include "sss/scene_edit.h"

static char dir[256], scene[300];

static const char *SCENE =
    "{\"objects\": [{\"name\": \"block\", \"mesh\": \"block.ply\", \"mm_per_unit\": 10, \"editable\": true,\n"
    "  \"material\": {\"preset\": \"marble\", \"inside\": \"ketchup\",\n"
    "               \"field\": {\"procedural\": \"sphere\", \"centre_mm\": [1, 0, 0], \"radius_mm\": 3, "
    "\"edge_mm\": 1}}}],\n"
    " \"lights\": [{\"type\": \"point\", \"position\": [0, 0, -4], \"intensity\": 16}],\n"
    " \"camera\": {\"position\": [0.6, 0.5, 4.5], \"target\": [0, 0, 0], \"up\": [0, 1, 0]}}\n";

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fputs(text, f) >= 0, 1);
    assert_int_equal(fclose(f), 0);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/sss_test_scene_edit_XXXXXX");
    if (!mkdtemp(dir)) return -1;
    snprintf(scene, sizeof scene, "%s/box.json", dir);
    char mesh[300];
    snprintf(mesh, sizeof mesh, "%s/block.ply", dir);
    write_text(scene, SCENE);
    write_text(mesh, "ply\n"); /* named, never read: the scene's paths resolve to it */
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

/* The scene's material with the three live edits: the base's σa (as Y's
 * transport colour sets it), the inside's σa × 1.5 (K), strength s. */
static void edited(const sss_scene *sc, double s, sss_htsm_material *m)
{
    memset(m, 0, sizeof *m);
    m->base = sc->objects[0].material;
    m->inside = sc->objects[0].hetero.inside;
    const double wax[3] = {0.85, 0.55, 0.25};
    sss_error err = {{0}};
    assert_int_equal(sss_transport_sigma_a(wax, 10.0, m->base.sigmap_s, m->base.sigma_a, &err), SSS_OK);
    for (int c = 0; c < 3; c++) m->inside.sigma_a[c] *= 1.5;
    m->strength = s;
    m->mm_per_unit = 10.0;
}

static char *slurp(const char *path)
{
    char *buf = NULL;
    size_t len = 0;
    sss_error err = {{0}};
    assert_int_equal(sss_input_read_all(path, 0, &buf, &len, &err), SSS_OK);
    return buf;
}

/* The entries of dir, hidden ones (a temporary file) included. */
static int entries(void)
{
    DIR *d = opendir(dir);
    assert_non_null(d);
    int n = 0;
    while (readdir(d)) n++;
    closedir(d);
    return n;
}

/* s = 0.6: the inside becomes the blend at s, and the material at every f
 * is the one min(1, s f) gave, to rounding; the base's numbers exactly. */
static void strengthBelowOneFoldsIntoTheInside(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_scene sc, out;
    assert_int_equal(sss_scene_load(scene, &sc, &err), SSS_OK);
    sss_htsm_material m;
    edited(&sc, 0.6, &m);
    char *before = slurp(scene);
    const int n0 = entries();
    char path[400];
    assert_int_equal(sss_scene_edited_path(scene, path, sizeof path, &err), SSS_OK);
    assert_non_null(strstr(path, "/box.edited.json"));
    assert_int_equal(sss_scene_write_edited(scene, 0, &m, path, &err), SSS_OK);
    char *after = slurp(scene);
    assert_string_equal(before, after);
    assert_int_equal(sss_scene_load(path, &out, &err), SSS_OK);
    const sss_scene_object *o = &out.objects[0];
    assert_int_equal(o->editable, 1);
    assert_true(o->field_strength == 1.0);
    assert_int_equal(o->hetero.field.kind, SSS_FIELD_SPHERE);
    assert_true(o->hetero.field.half_mm[0] == 3.0 && o->hetero.field.centre_mm[0] == 1.0);
    assert_true(out.nlights == 1 && out.lights[0].kind == SSS_LIGHT_POINT && out.lights[0].intensity == 16.0);
    for (int c = 0; c < 3; c++) {
        assert_true(o->material.sigma_a[c] == m.base.sigma_a[c]);
        assert_true(o->material.sigmap_s[c] == m.base.sigmap_s[c]);
        assert_true(o->material.sigma_a[c] != sc.objects[0].material.sigma_a[c]);
    }
    assert_true(o->material.eta == m.base.eta);
    for (double f = 0.0; f <= 1.0; f += 0.125) {
        sss_material a, b;
        sss_material_blend(&m.base, &m.inside, fmin(1.0, m.strength * f), &a);
        sss_material_blend(&o->material, &o->hetero.inside, f, &b);
        for (int c = 0; c < 3; c++) {
            assert_true(fabs(a.sigma_a[c] - b.sigma_a[c]) <= 1e-15 * a.sigma_a[c]);
            assert_true(fabs(a.sigmap_s[c] - b.sigmap_s[c]) <= 1e-15 * a.sigmap_s[c]);
        }
    }
    assert_int_equal(entries(), n0 + 1); /* the written scene, no temporary */
    free(before);
    free(after);
    sss_scene_free(&out);
    sss_scene_free(&sc);
}

/* s = 2.5 cannot fold (min(1, s f) is not linear): the field's "strength",
 * the inside as edited; a bake's planner is left to refuse it. */
static void strengthAboveOneIsTheFieldsKey(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_scene sc, out;
    assert_int_equal(sss_scene_load(scene, &sc, &err), SSS_OK);
    sss_htsm_material m;
    edited(&sc, 2.5, &m);
    char path[400];
    snprintf(path, sizeof path, "%s/strong.json", dir);
    assert_int_equal(sss_scene_write_edited(scene, 0, &m, path, &err), SSS_OK);
    assert_int_equal(sss_scene_load(path, &out, &err), SSS_OK);
    assert_true(out.objects[0].field_strength == 2.5);
    for (int c = 0; c < 3; c++) assert_true(out.objects[0].hetero.inside.sigma_a[c] == m.inside.sigma_a[c]);
    /* and written again at s = 1 the key goes */
    m.strength = 1.0;
    assert_int_equal(sss_scene_write_edited(path, 0, &m, path, &err) == SSS_OK, 0); /* never over its input */
    char again[400];
    snprintf(again, sizeof again, "%s/again.json", dir);
    assert_int_equal(sss_scene_write_edited(path, 0, &m, again, &err), SSS_OK);
    char *t = slurp(again);
    assert_null(strstr(t, "strength"));
    free(t);
    sss_scene_free(&out);
    sss_scene_free(&sc);
}

/* The input as the target, a folder that is not there, an object that is
 * not there: refused naming the file, nothing left behind. Another folder:
 * the mesh's path written absolute, so the scene loads from there. */
static void refusalsLeaveNoFileAndAnotherFolderGetsAbsolutePaths(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_scene sc;
    assert_int_equal(sss_scene_load(scene, &sc, &err), SSS_OK);
    sss_htsm_material m;
    edited(&sc, 1.0, &m);
    char *before = slurp(scene);
    const int n0 = entries();
    assert_int_not_equal(sss_scene_write_edited(scene, 0, &m, scene, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "box.json"));
    char path[400];
    snprintf(path, sizeof path, "%s/no/such/x.json", dir);
    assert_int_not_equal(sss_scene_write_edited(scene, 0, &m, path, &err), SSS_OK);
    assert_non_null(strstr(err.msg, "x.json"));
    snprintf(path, sizeof path, "%s/x.json", dir);
    assert_int_equal(sss_scene_write_edited(scene, 1, &m, path, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "/objects/1"));
    assert_int_equal(entries(), n0);
    char *after = slurp(scene);
    assert_string_equal(before, after);
    snprintf(path, sizeof path, "%s/sub", dir);
    assert_int_equal(mkdir(path, 0700), 0);
    snprintf(path, sizeof path, "%s/sub/moved.json", dir);
    assert_int_equal(sss_scene_write_edited(scene, 0, &m, path, &err), SSS_OK);
    sss_scene out;
    assert_int_equal(sss_scene_load(path, &out, &err), SSS_OK);
    char a[PATH_MAX], b[PATH_MAX];
    assert_non_null(realpath(sc.objects[0].mesh, a));
    assert_non_null(realpath(out.objects[0].mesh, b));
    assert_string_equal(a, b);
    assert_int_equal(out.objects[0].mesh[0], '/');
    assert_int_equal(sss_scene_edited_path("a/b", path, sizeof path, &err), SSS_OK);
    assert_string_equal(path, "a/b.edited.json");
    assert_int_equal(sss_scene_edited_path("a/b.json", path, 10, &err), SSS_ERR_ARG);
    free(before);
    free(after);
    sss_scene_free(&out);
    sss_scene_free(&sc);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(strengthBelowOneFoldsIntoTheInside),
        cmocka_unit_test(strengthAboveOneIsTheFieldsKey),
        cmocka_unit_test(refusalsLeaveNoFileAndAnotherFolderGetsAbsolutePaths),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
