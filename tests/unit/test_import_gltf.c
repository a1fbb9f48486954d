/* test_import_gltf.c: glTF 2.0 input (docs/robustness.md, "glTF"): files
 * from sss-genmesh's writer import as the PLY of the same mesh does, node
 * transforms place every instance, texture coordinates and colours are
 * kept, and damaged files are refused with one line naming the file and the
 * element. Hand-made files are written by the test itself. */
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
#include "gltf_write.h"
#include "sss/base64.h"
#include "sss/import.h"

static char g_dir[64];

static int setup_dir(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_gltf_XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static int teardown_dir(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", g_dir);
    return system(cmd) == 0 ? 0 : -1;
}

static const char *path_of(const char *name)
{
    static char buf[4][160];
    static int k;
    k = (k + 1) % 4;
    snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
    return buf[k];
}

static const char *write_file(const char *name, const void *data, size_t n)
{
    const char *p = path_of(name);
    FILE *f = fopen(p, "wb");
    assert_non_null(f);
    if (n) assert_int_equal(fwrite(data, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
    return p;
}

/* The cube sss-genmesh makes (res 2: 26 vertices, 48 triangles). */
static void cube(sss_mesh *m)
{
    sss_error err = {{0}};
    assert_int_equal(sss_gen_box(m, 1.0, 1.0, 1.0, 2, 0, &err), SSS_OK);
}

static void import_ok(const char *path, sss_mesh *m, sss_import_report *rep)
{
    sss_error err = {{0}};
    sss_result r = sss_import_mesh(path, m, rep, &err);
    if (r != SSS_OK) fprintf(stderr, "%s\n", err.msg);
    assert_int_equal(r, SSS_OK);
}

static void gltfBoxImportsAsItsPlyDoes(void **state)
{
    (void)state;
    sss_mesh src, ply, gl, glb;
    sss_error err = {{0}};
    cube(&src);
    const char *pp = path_of("box.ply"), *pg = path_of("box.gltf"), *pb = path_of("box.glb");
    assert_int_equal(sss_export_ply(pp, &src, &err), SSS_OK);
    assert_int_equal(sss_gltf_write(pg, &src, 0, &err), SSS_OK);
    assert_int_equal(sss_gltf_write(pb, &src, 0, &err), SSS_OK);
    sss_import_report rp, rg, rb;
    import_ok(pp, &ply, &rp);
    import_ok(pg, &gl, &rg);
    import_ok(pb, &glb, &rb);
    assert_int_equal(gl.nv, 26);
    assert_int_equal(gl.nf, 48);
    const sss_mesh *ms[2] = {&gl, &glb};
    for (int i = 0; i < 2; i++) {
        assert_int_equal(ms[i]->nv, ply.nv);
        assert_int_equal(ms[i]->nf, ply.nf);
        assert_memory_equal(ms[i]->pos, ply.pos, 3 * (size_t)ply.nv * sizeof(float));
        assert_memory_equal(ms[i]->tri, ply.tri, 3 * (size_t)ply.nf * sizeof(uint32_t));
        assert_memory_equal(ms[i]->nrm, ply.nrm, 3 * (size_t)ply.nv * sizeof(float));
        assert_null(ms[i]->uv);
        assert_null(ms[i]->rgba);
    }
    assert_int_equal(sss_import_repairs(&rg), sss_import_repairs(&rp));
    assert_int_equal(rg.texcoords, 0);
    assert_int_equal(rg.colours, 0);
    sss_mesh_free(&src); sss_mesh_free(&ply); sss_mesh_free(&gl); sss_mesh_free(&glb);
}

/* gltf_write.h: instance A at p + (-2, 0, 1), B at (-0.5 p_y + 2, 0.5 p_x,
 * 0.5 p_z + 1), in the order of the node tree. */
static void gltfTwoNodesPlaceEachInstanceInWorldSpace(void **state)
{
    (void)state;
    sss_mesh src, m;
    sss_error err = {{0}};
    cube(&src);
    const char *p = path_of("two.glb");
    assert_int_equal(sss_gltf_write(p, &src, SSS_GLTF_TWO_NODES, &err), SSS_OK);
    sss_import_report rep;
    import_ok(p, &m, &rep);
    assert_int_equal(m.nv, 2 * src.nv);
    assert_int_equal(m.nf, 2 * src.nf);
    for (uint32_t v = 0; v < src.nv; v++) {
        const float *q = src.pos + 3 * (size_t)v, *a = m.pos + 3 * (size_t)v, *b = m.pos + 3 * ((size_t)v + src.nv);
        const double ea[3] = {q[0] - 2.0, q[1], q[2] + 1.0};
        const double eb[3] = {-0.5 * q[1] + 2.0, 0.5 * q[0], 0.5 * q[2] + 1.0};
        for (int k = 0; k < 3; k++) {
            assert_true(fabs(a[k] - ea[k]) < 1e-6);
            assert_true(fabs(b[k] - eb[k]) < 1e-6);
        }
    }
    /* both instances keep the cube's outward winding: no repair */
    assert_int_equal(sss_import_repairs(&rep), 0);
    double lo[3], hi[3];
    sss_mesh_bounds(&m, lo, hi);
    assert_true(fabs(lo[0] + 2.5) < 1e-6 && fabs(hi[0] - 2.25) < 1e-6);
    assert_true(fabs(lo[2] - 0.5) < 1e-6 && fabs(hi[2] - 1.5) < 1e-6);
    sss_mesh_free(&src);
    sss_mesh_free(&m);
}

static void gltfKeepsTexcoordsAndColours(void **state)
{
    (void)state;
    sss_mesh src, m;
    sss_error err = {{0}};
    cube(&src);
    const char *p = path_of("attr.gltf");
    assert_int_equal(sss_gltf_write(p, &src, SSS_GLTF_ATTRIBUTES, &err), SSS_OK);
    sss_import_report rep;
    import_ok(p, &m, &rep);
    assert_int_equal(rep.texcoords, 1);
    assert_int_equal(rep.colours, 1);
    assert_non_null(m.uv);
    assert_non_null(m.rgba);
    assert_int_equal(m.nv, src.nv);
    for (uint32_t v = 0; v < m.nv; v++) {
        /* gltf_write.h: (u, v) = (x, y) over the box [-0.5, 0.5]; the mesh's
         * v points upward (sss/mesh.h): 1 - v */
        const double u = m.pos[3 * (size_t)v] + 0.5, w = m.pos[3 * (size_t)v + 1] + 0.5;
        assert_true(fabs(m.uv[2 * (size_t)v] - u) < 1e-6);
        assert_true(fabs(m.uv[2 * (size_t)v + 1] - (1.0 - w)) < 1e-6);
        const double c[4] = {u, w, 0.5, 1.0};
        for (int k = 0; k < 4; k++) assert_true(fabs(m.rgba[4 * (size_t)v + k] - c[k]) < 1e-6);
    }
    /* a copy carries them */
    sss_mesh c;
    assert_int_equal(sss_mesh_copy(&m, &c, &err), SSS_OK);
    assert_memory_equal(c.uv, m.uv, 2 * (size_t)m.nv * sizeof(float));
    assert_memory_equal(c.rgba, m.rgba, 4 * (size_t)m.nv * sizeof(float));
    sss_mesh_free(&c);
    sss_mesh_free(&src);
    sss_mesh_free(&m);
}

/* A hand-made file: one triangle (3 float positions, 36 bytes) and its
 * indices (3 unsigned bytes) in one buffer, embedded unless uri is given.
 * idx: the three indices; extra: more JSON before the closing brace. */
static const char *hand_gltf(const char *name, const unsigned char idx[3], const char *mode, const char *acc0_count,
                             const char *uri, const char *extra)
{
    unsigned char bin[40] = {0};
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(bin, pos, 36);
    memcpy(bin + 36, idx, 3);
    char b64[64], buffer[160], text[2048];
    sss_base64_encode(bin, 39, b64);
    if (uri) snprintf(buffer, sizeof buffer, "{\"byteLength\":39,\"uri\":\"%s\"}", uri);
    else snprintf(buffer, sizeof buffer, "{\"byteLength\":39,\"uri\":\"data:application/octet-stream;base64,%s\"}", b64);
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"indices\":1,\"mode\":%s}]}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%s,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5121,\"count\":3,\"type\":\"SCALAR\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":3}],"
             "\"buffers\":[%s]%s}",
             mode, acc0_count, buffer, extra);
    return write_file(name, text, strlen(text));
}

static void refused(const char *path, const char *what)
{
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_not_equal(sss_import_mesh(path, &m, NULL, &err), SSS_OK);
    if (!strstr(err.msg, path) || !strstr(err.msg, what) || strchr(err.msg, '\n'))
        fail_msg("'%s' should name %s and '%s' on one line", err.msg, path, what);
    assert_null(m.pos);
}

static void gltfRefusesDamagedFilesNamingTheElement(void **state)
{
    (void)state;
    const unsigned char good[3] = {0, 1, 2}, far[3] = {0, 9, 2};
    sss_mesh m;
    sss_import_report rep;
    import_ok(hand_gltf("ok.gltf", good, "4", "3", NULL, ""), &m, &rep);
    assert_int_equal(m.nv, 3);
    assert_int_equal(m.nf, 1);
    sss_mesh_free(&m);
    refused(hand_gltf("range.gltf", far, "4", "3", NULL, ""), "accessor 1: index 9 out of range [0, 3)");
    refused(hand_gltf("count.gltf", good, "4", "4", NULL, ""), "accessor 0: 4 elements from byte 0 need 48 bytes");
    refused(hand_gltf("missing.gltf", good, "4", "3", "missing.bin", ""), "buffer 0:");
    refused(hand_gltf("scheme.gltf", good, "4", "3", "http://example.com/a.bin", ""), "buffer 0: uri");
    refused(hand_gltf("strip.gltf", good, "5", "3", NULL, ""), "mesh 0 primitive 0: mode 5 (triangle strip)");
    refused(hand_gltf("lines.gltf", good, "1", "3", NULL, ""), "no triangles in the scene (1 primitives");
    refused(hand_gltf("required.gltf", good, "4", "3", NULL, ",\"extensionsRequired\":[\"KHR_draco_mesh_compression\"]"),
            "extensionsRequired: 'KHR_draco_mesh_compression'");
    const char *cyc = "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],"
                      "\"nodes\":[{\"children\":[1]},{\"children\":[2]},{\"children\":[1]}]}";
    refused(write_file("cycle.gltf", cyc, strlen(cyc)), "node 2: child 1 already has a parent");
    const char *loop = "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[]}],"
                       "\"nodes\":[{\"children\":[1]},{\"children\":[0]}]}";
    refused(write_file("loop.gltf", loop, strlen(loop)), "node 0: the hierarchy has a cycle");
    /* a chain of 300 nodes: deeper than Assimp's recursion is allowed */
    char chain[8192];
    size_t k = (size_t)snprintf(chain, sizeof chain, "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[");
    for (int i = 0; i < 300; i++)
        k += (size_t)snprintf(chain + k, sizeof chain - k, i < 299 ? "{\"children\":[%d]}," : "{}]}", i + 1);
    assert_true(k < sizeof chain);
    refused(write_file("chain.gltf", chain, k), "node 256: more than 256 levels deep");
    const char *v1 = "{\"asset\":{\"version\":\"1.0\"}}";
    refused(write_file("v1.gltf", v1, strlen(v1)), "asset: 'version'");
    refused(write_file("syntax.gltf", "{\"asset\":", 9), "JSON: syntax error");
}

static void glbRefusesTruncationAndBadChunks(void **state)
{
    (void)state;
    sss_mesh src;
    sss_error err = {{0}};
    cube(&src);
    const char *p = path_of("whole.glb");
    assert_int_equal(sss_gltf_write(p, &src, 0, &err), SSS_OK);
    FILE *f = fopen(p, "rb");
    assert_non_null(f);
    unsigned char buf[4096];
    size_t n = fread(buf, 1, sizeof buf, f);
    fclose(f);
    assert_true(n > 100 && n < sizeof buf);
    refused(write_file("cut.glb", buf, n - 10), "GLB header: length");
    refused(write_file("stub.glb", buf, 12), "GLB header:");
    /* the header's length agrees, but the binary chunk claims more than is left */
    unsigned char b2[4096];
    memcpy(b2, buf, n);
    uint32_t jlen = (uint32_t)b2[12] | (uint32_t)b2[13] << 8 | (uint32_t)b2[14] << 16 | (uint32_t)b2[15] << 24;
    b2[20 + jlen] = 0xff;
    b2[21 + jlen] = 0xff;
    refused(write_file("chunk.glb", b2, n), "GLB chunk 1: length");
    refused(write_file("text.glb", "{}", 2), "GLB header:");
    sss_mesh_free(&src);
}

static void gltfSkipsLinesBesideTrianglesWithAWarning(void **state)
{
    (void)state;
    /* the triangle's primitive twice: once as lines, once as triangles */
    unsigned char bin[40] = {0};
    const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
    memcpy(bin, pos, 36);
    bin[36] = 0; bin[37] = 1; bin[38] = 2;
    char b64[64], text[2048];
    sss_base64_encode(bin, 39, b64);
    snprintf(text, sizeof text,
             "{\"asset\":{\"version\":\"2.0\"},\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0},\"mode\":1},"
             "{\"attributes\":{\"POSITION\":0},\"indices\":1}]}],"
             "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\"},"
             "{\"bufferView\":1,\"componentType\":5121,\"count\":3,\"type\":\"SCALAR\"}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36},{\"buffer\":0,\"byteOffset\":36,\"byteLength\":3}],"
             "\"buffers\":[{\"byteLength\":39,\"uri\":\"data:application/octet-stream;base64,%s\"}]}", b64);
    sss_mesh m;
    sss_import_report rep;
    import_ok(write_file("mixed.gltf", text, strlen(text)), &m, &rep);
    assert_int_equal(m.nf, 1);
    assert_int_equal(rep.primitives_skipped, 1);
    char out[512] = {0};
    FILE *f = fmemopen(out, sizeof out - 1, "w");
    sss_import_print_warnings(&rep, "x", f);
    fclose(f);
    assert_non_null(strstr(out, "x: warning: 1 glTF primitive of points or lines skipped"));
    sss_mesh_free(&m);
}

static void base64RoundTripsAndRefusesBadText(void **state)
{
    (void)state;
    unsigned char in[7] = {0, 1, 2, 250, 251, 252, 255}, out[8];
    for (size_t n = 0; n <= 7; n++) {
        char t[16];
        sss_base64_encode(in, n, t);
        assert_int_equal(strlen(t), sss_base64_encoded_len(n));
        size_t at = 0;
        assert_int_equal(sss_base64_decode(t, strlen(t), out, &at), (long long)n);
        assert_memory_equal(out, in, n);
    }
    size_t at = 0;
    assert_int_equal(sss_base64_decode("AB=C", 4, out, &at), -1);
    assert_int_equal(at, 2);
    assert_int_equal(sss_base64_decode("ABC", 3, out, &at), -1);
    assert_int_equal(sss_base64_decode("AB*C", 4, out, &at), -1);
    assert_int_equal(at, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gltfBoxImportsAsItsPlyDoes),
        cmocka_unit_test(gltfTwoNodesPlaceEachInstanceInWorldSpace),
        cmocka_unit_test(gltfKeepsTexcoordsAndColours),
        cmocka_unit_test(gltfRefusesDamagedFilesNamingTheElement),
        cmocka_unit_test(glbRefusesTruncationAndBadChunks),
        cmocka_unit_test(gltfSkipsLinesBesideTrianglesWithAWarning),
        cmocka_unit_test(base64RoundTripsAndRefusesBadText),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
