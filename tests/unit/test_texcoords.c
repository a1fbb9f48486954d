/* test_texcoords.c: texture coordinates and tangent frames (docs/layers.md
 * §3, what a layer's depth map is read at): sss-genmesh's meshes carry
 * them, sss_mesh_tangents derives the frame from them, and the PLY and OBJ
 * importers keep them (read back from what the writer and the test wrote). */
#define _POSIX_C_SOURCE 200809L
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "genmesh.h"
#include "sss/import.h"
#include "sss/vec3.h"

static char g_dir[64];

static int setup_dir(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_texcoords_XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static const char *path_of(const char *name)
{
    static char buf[4][160];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
    return buf[k];
}

static int teardown_dir(void **state)
{
    (void)state;
    static const char *const names[] = {"sphere.ply", "torus.ply", "quad.obj", "quad_novt.obj", "quad_mixed.obj",
                                        "st.ply", "nan.ply", "neg.obj", NULL};
    for (const char *const *n = names; *n; n++) unlink(path_of(*n));
    rmdir(g_dir);
    return 0;
}

static const char *write_text(const char *name, const char *text)
{
    const char *p = path_of(name);
    FILE *f = fopen(p, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    assert_int_equal(fclose(f), 0);
    return p;
}

static double dot3f(const float *a, const double *b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/* The plane's u runs along +x and v along +y (genmesh.h): every tangent is
 * ∂p/∂u's direction, +x, and the frame right-handed (B = N × T = +y). */
static void planeTangentIsAlongDpDu(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_plane(&m, 3.0, 2.0, 6, 4, &err), SSS_OK);
    assert_non_null(m.uv);
    float *t = malloc(4 * sizeof(float) * m.nv);
    assert_int_equal(sss_mesh_tangents(&m, t, "plane", &err), SSS_OK);
    for (uint32_t v = 0; v < m.nv; v++) {
        assert_float_equal(t[4 * v], 1.0, 1e-6);
        assert_float_equal(t[4 * v + 1], 0.0, 1e-6);
        assert_float_equal(t[4 * v + 2], 0.0, 1e-6);
        assert_float_equal(t[4 * v + 3], 1.0, 0.0);
        /* and u, v are where the vertex sits on the sx × sy plane */
        assert_float_equal(m.uv[2 * v], m.pos[3 * v] / 3.0 + 0.5, 1e-6);
        assert_float_equal(m.uv[2 * v + 1], m.pos[3 * v + 1] / 2.0 + 0.5, 1e-6);
    }
    /* mirrored u: the tangent turns to −x and the handedness to −1 */
    for (uint32_t v = 0; v < m.nv; v++) m.uv[2 * v] = 1.0f - m.uv[2 * v];
    assert_int_equal(sss_mesh_tangents(&m, t, "plane", &err), SSS_OK);
    for (uint32_t v = 0; v < m.nv; v++) {
        assert_float_equal(t[4 * v], -1.0, 1e-6);
        assert_float_equal(t[4 * v + 3], -1.0, 0.0);
    }
    free(t);
    sss_mesh_free(&m);
}

/* On the torus and the sphere every tangent is a unit vector orthogonal to
 * the vertex normal; on the torus, away from its seams, it is the analytic
 * ∂p/∂u direction (−sin u, cos u, 0) to within the mesh's resolution, and
 * on the sphere it is east, (−y, x, 0)/|…|, away from the poles. */
static void tangentsAreUnitOrthogonalAndFollowU(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh m;
    assert_int_equal(sss_gen_torus(&m, 3.0, 1.0, 48, 24, &err), SSS_OK);
    float *t = malloc(4 * sizeof(float) * m.nv);
    assert_int_equal(sss_mesh_tangents(&m, t, "torus", &err), SSS_OK);
    uint32_t checked = 0;
    for (uint32_t v = 0; v < m.nv; v++) {
        const float *tv = &t[4 * v];
        const double n[3] = {m.nrm[3 * v], m.nrm[3 * v + 1], m.nrm[3 * v + 2]};
        assert_true(fabs(dot3f(tv, n)) < 1e-6);
        assert_float_equal(sqrt(tv[0] * tv[0] + tv[1] * tv[1] + tv[2] * tv[2]), 1.0, 1e-6);
        const uint32_t i = v / 24;
        if (i == 0 || i == 47) continue; /* next to the u seam, half the triangles are skipped */
        const double u = 2 * SSS_PI * i / 48, du[3] = {-sin(u), cos(u), 0.0};
        assert_true(dot3f(tv, du) > 0.99);
        checked++;
    }
    assert_int_equal(checked, 46 * 24);
    free(t);
    sss_mesh_free(&m);

    assert_int_equal(sss_gen_sphere(&m, 2.0, 4, &err), SSS_OK);
    t = malloc(4 * sizeof(float) * m.nv);
    assert_int_equal(sss_mesh_tangents(&m, t, "sphere", &err), SSS_OK);
    checked = 0;
    for (uint32_t v = 0; v < m.nv; v++) {
        const float *tv = &t[4 * v], *p = &m.pos[3 * v];
        const double n[3] = {m.nrm[3 * v], m.nrm[3 * v + 1], m.nrm[3 * v + 2]};
        assert_true(fabs(dot3f(tv, n)) < 1e-6);
        assert_float_equal(sqrt(tv[0] * tv[0] + tv[1] * tv[1] + tv[2] * tv[2]), 1.0, 1e-6);
        const double rxy = hypot(p[0], p[1]);
        if (rxy < 1.0 || m.uv[2 * v] < 0.05f || m.uv[2 * v] > 0.95f) continue; /* poles, seam */
        const double east[3] = {-p[1] / rxy, p[0] / rxy, 0.0};
        assert_true(dot3f(tv, east) > 0.98);
        checked++;
    }
    assert_true(checked > m.nv / 2);
    free(t);
    sss_mesh_free(&m);

    /* no texture coordinates: refused, naming the mesh */
    assert_int_equal(sss_gen_box(&m, 1, 1, 1, 2, 0, &err), SSS_OK);
    assert_null(m.uv);
    float dummy[4 * 64];
    assert_int_equal(sss_mesh_tangents(&m, dummy, "box.ply", &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "box.ply"));
    sss_mesh_free(&m);
}

/* What sss_export_ply writes from sss-genmesh's meshes comes back with the
 * same texture coordinates, vertex for vertex. */
static void plyKeepsWhatGenmeshWrote(void **state)
{
    (void)state;
    sss_error err = {{0}};
    const char *names[2] = {"sphere.ply", "torus.ply"};
    for (int k = 0; k < 2; k++) {
        sss_mesh m, r;
        assert_int_equal(k ? sss_gen_torus(&m, 3.0, 1.0, 12, 8, &err) : sss_gen_sphere(&m, 1.5, 2, &err), SSS_OK);
        const char *p = path_of(names[k]);
        assert_int_equal(sss_export_ply(p, &m, &err), SSS_OK);
        sss_import_report rep;
        assert_int_equal(sss_import_mesh(p, &r, &rep, &err), SSS_OK);
        assert_true(rep.texcoords);
        assert_int_equal(r.nv, m.nv);
        assert_non_null(r.uv);
        for (uint32_t v = 0; v < m.nv; v++) {
            assert_memory_equal(&r.pos[3 * v], &m.pos[3 * v], 3 * sizeof(float));
            assert_memory_equal(&r.uv[2 * v], &m.uv[2 * v], 2 * sizeof(float));
        }
        sss_mesh_free(&m);
        sss_mesh_free(&r);
    }
}

/* ASCII PLY with "s t" properties, and a texture coordinate that is not a
 * number: the importer names the file and the vertex. */
static void plyReadsSTAndRefusesNonFinite(void **state)
{
    (void)state;
    sss_error err = {{0}};
    const char *head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                       "property float s\nproperty float t\nelement face 1\nproperty list uchar int vertex_indices\n"
                       "end_header\n";
    char text[512];
    snprintf(text, sizeof text, "%s0 0 0 0.25 0.5\n1 0 0 0.75 0.5\n0 1 0 0.25 1\n3 0 1 2\n", head);
    sss_mesh r;
    assert_int_equal(sss_import_mesh(write_text("st.ply", text), &r, NULL, &err), SSS_OK);
    assert_non_null(r.uv);
    const float want[6] = {0.25f, 0.5f, 0.75f, 0.5f, 0.25f, 1.0f};
    assert_memory_equal(r.uv, want, sizeof want);
    sss_mesh_free(&r);
    snprintf(text, sizeof text, "%s0 0 0 0.25 0.5\n1 0 0 nan 0.5\n0 1 0 0.25 1\n3 0 1 2\n", head);
    const char *p = write_text("nan.ply", text);
    assert_int_not_equal(sss_import_mesh(p, &r, NULL, &err), SSS_OK);
    assert_non_null(strstr(err.msg, p));
    assert_non_null(strstr(err.msg, "vertex 1"));
    assert_non_null(strstr(err.msg, "texture coordinate"));
    assert_null(strchr(err.msg, '\n'));
}

/* OBJ: each vertex takes its first corner's vt (relative indices too); a
 * file without vt, or with a used vertex whose first corner has none, gives
 * a mesh without texture coordinates. */
static void objKeepsFirstCornerTexcoords(void **state)
{
    (void)state;
    sss_error err = {{0}};
    sss_mesh r;
    assert_int_equal(sss_import_mesh(write_text("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                                            "vt 0.1 0.2\nvt 0.9 0.2\nvt 0.9 0.8\nvt 0.1 0.8\n"
                                                            "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\n"),
                                     &r, NULL, &err),
                     SSS_OK);
    assert_int_equal(r.nv, 4);
    assert_non_null(r.uv);
    const float want[8] = {0.1f, 0.2f, 0.9f, 0.2f, 0.9f, 0.8f, 0.1f, 0.8f};
    assert_memory_equal(r.uv, want, sizeof want);
    sss_mesh_free(&r);
    /* negative (relative) vt indices and v/vt/vn corners */
    assert_int_equal(sss_import_mesh(write_text("neg.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvn 0 0 1\n"
                                                           "vt 0.5 0.25\nvt 0.75\nvt 0 1\n"
                                                           "f 1/-3/1 2/-2/1 3/-1/1\n"),
                                     &r, NULL, &err),
                     SSS_OK);
    assert_non_null(r.uv);
    const float want2[6] = {0.5f, 0.25f, 0.75f, 0.0f, 0.0f, 1.0f};
    assert_memory_equal(r.uv, want2, sizeof want2);
    sss_mesh_free(&r);
    assert_int_equal(sss_import_mesh(write_text("quad_novt.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 3\n"), &r, NULL, &err),
                     SSS_OK);
    assert_null(r.uv);
    sss_mesh_free(&r);
    assert_int_equal(sss_import_mesh(write_text("quad_mixed.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\n"
                                                                  "f 1/1 2/2 3\n"),
                                     &r, NULL, &err),
                     SSS_OK);
    assert_null(r.uv);
    sss_mesh_free(&r);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(planeTangentIsAlongDpDu),
        cmocka_unit_test(tangentsAreUnitOrthogonalAndFollowU),
        cmocka_unit_test(plyKeepsWhatGenmeshWrote),
        cmocka_unit_test(plyReadsSTAndRefusesNonFinite),
        cmocka_unit_test(objKeepsFirstCornerTexcoords),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
