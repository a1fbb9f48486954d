/* test_import.c: mesh import (PLY/OBJ/OFF/STL through OpenMesh), validation,
 * counted repairs and the PLY exporter. Every test writes small files into a
 * temporary directory and imports them. */
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
#include <time.h>
#include <unistd.h>

#include "genmesh.h"
#include "sss/import.h"
#include "sss/vec3.h"

/* ---------------------------------------------------------------------------
 * Temporary files
 * ------------------------------------------------------------------------- */

static char g_dir[64];
static char g_files[128][160];
static int g_nfiles;

static int setup_dir(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_import_XXXXXX");
    if (!mkdtemp(g_dir)) return -1;
    g_nfiles = 0;
    return 0;
}

static int teardown_dir(void **state)
{
    (void)state;
    if (getenv("SSS_KEEP_TEST_FILES")) return 0;
    for (int i = 0; i < g_nfiles; i++) unlink(g_files[i]);
    rmdir(g_dir);
    return 0;
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
    int known = 0;
    for (int i = 0; i < g_nfiles; i++) known |= strcmp(g_files[i], p) == 0;
    if (!known && g_nfiles < 128) snprintf(g_files[g_nfiles++], sizeof g_files[0], "%s", p);
    return p;
}

static const char *write_text(const char *name, const char *text) { return write_file(name, text, strlen(text)); }

/* Growable byte buffer for binary files. */
typedef struct bytes {
    unsigned char *b;
    size_t n, cap;
} bytes;

static void put(bytes *B, const void *p, size_t n)
{
    if (B->n + n > B->cap) {
        B->cap = (B->n + n) * 2 + 64;
        B->b = realloc(B->b, B->cap);
        assert_non_null(B->b);
    }
    memcpy(B->b + B->n, p, n);
    B->n += n;
}

static void put_str(bytes *B, const char *s) { put(B, s, strlen(s)); }

static void put_u8(bytes *B, unsigned v)
{
    unsigned char c = (unsigned char)v;
    put(B, &c, 1);
}

static void put_u32(bytes *B, uint32_t v, int big)
{
    unsigned char c[4];
    for (int i = 0; i < 4; i++) c[big ? 3 - i : i] = (unsigned char)(v >> (8 * i));
    put(B, c, 4);
}

static void put_f32(bytes *B, float f, int big)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    put_u32(B, u, big);
}

/* ---------------------------------------------------------------------------
 * The unit cube: 8 vertices, 6 quads (outward, counter-clockwise), area 6.
 * ------------------------------------------------------------------------- */

static const float CUBE_V[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                   {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
static const int CUBE_Q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                 {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

/* Triangle k of the fan-triangulated cube. */
static void cube_tri(int k, int t[3])
{
    const int *q = CUBE_Q[k / 2];
    t[0] = q[0];
    t[1] = q[1 + k % 2];
    t[2] = q[2 + k % 2];
}

static double total_area(const sss_mesh *m)
{
    double a = 0;
    for (uint32_t v = 0; v < m->nv; v++) a += m->area[v];
    return a;
}

static void assert_cube(const sss_mesh *m)
{
    assert_int_equal(m->nv, 8);
    assert_int_equal(m->nf, 12);
    assert_non_null(m->nrm);
    assert_non_null(m->area);
    assert_true(fabs(total_area(m) - 6.0) < 1e-9);
}

/* Ascii PLY from vertices and face lines ("4 0 3 2 1"). */
static void ply_text(char *out, size_t cap, const char *list_decl, const float (*v)[3], int nv,
                     const char *const *faces, int nf)
{
    size_t n = (size_t)snprintf(out, cap,
                                "ply\nformat ascii 1.0\ncomment test mesh\nelement vertex %d\nproperty float x\n"
                                "property float y\nproperty float z\nelement face %d\n%s\nend_header\n",
                                nv, nf, list_decl);
    for (int i = 0; i < nv; i++) n += (size_t)snprintf(out + n, cap - n, "%g %g %g\n", v[i][0], v[i][1], v[i][2]);
    for (int f = 0; f < nf; f++) n += (size_t)snprintf(out + n, cap - n, "%s\n", faces[f]);
    assert_true(n < cap);
}

static const char *const CUBE_FACES[6] = {"4 0 3 2 1", "4 4 5 6 7", "4 0 1 5 4",
                                          "4 1 2 6 5", "4 2 3 7 6", "4 3 0 4 7"};

static void cube_ascii_ply(char *out, size_t cap, const char *list_decl)
{
    ply_text(out, cap, list_decl, CUBE_V, 8, CUBE_FACES, 6);
}

/* Binary cube as 12 triangles (list length uchar, or int when list_decl says
 * "list int"); extras add a vertex normal, a face colour and
 * a comment right before end_header (all of which OpenMesh's reader gets
 * wrong unless the header is rewritten). */
static void cube_binary_ply(bytes *B, int big, int extras, const char *list_decl)
{
    put_str(B, "ply\n");
    put_str(B, big ? "format binary_big_endian 1.0\n" : "format binary_little_endian 1.0\n");
    put_str(B, "element vertex 8\nproperty float x\nproperty float y\nproperty float z\n");
    if (extras) put_str(B, "property float nx\n");
    put_str(B, "element face 12\n");
    put_str(B, list_decl);
    put_str(B, "\n");
    if (extras) put_str(B, "property uchar red\ncomment written by test_import\n");
    put_str(B, "end_header\n");
    for (int v = 0; v < 8; v++) {
        for (int k = 0; k < 3; k++) put_f32(B, CUBE_V[v][k], big);
        if (extras) put_f32(B, 0.5f, big);
    }
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        if (strstr(list_decl, "list int ")) put_u32(B, 3, big);
        else put_u8(B, 3);
        for (int i = 0; i < 3; i++) put_u32(B, (uint32_t)t[i], big);
        if (extras) put_u8(B, 200);
    }
}

static void cube_binary_stl(bytes *B, uint32_t declared)
{
    char hdr[80];
    memset(hdr, 0, sizeof hdr);
    strcpy(hdr, "solid cube written as binary STL");
    put(B, hdr, 80);
    put_u32(B, declared, 0);
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        for (int i = 0; i < 3; i++) put_f32(B, 0.0f, 0); /* normal: unused */
        for (int i = 0; i < 3; i++)
            for (int c = 0; c < 3; c++) put_f32(B, CUBE_V[t[i]][c], 0);
        put_u8(B, 0);
        put_u8(B, 0);
    }
}

static sss_result import(const char *path, sss_mesh *m, sss_import_report *rep, sss_error *err)
{
    memset(err, 0, sizeof *err);
    return sss_import_mesh(path, m, rep, err);
}

/* ---------------------------------------------------------------------------
 * Reading each format
 * ------------------------------------------------------------------------- */

static void importReadsAsciiPlyCubeAndTriangulatesQuads(void **state)
{
    (void)state;
    char text[2048];
    cube_ascii_ply(text, sizeof text, "property list uchar int vertex_indices");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("cube.ply", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.vertices_read, 8);
    assert_int_equal(rep.faces_read, 6);
    assert_int_equal(rep.polygons_triangulated, 6);
    assert_int_equal(sss_import_repairs(&rep), 6);
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        for (int i = 0; i < 3; i++) assert_int_equal(m.tri[3 * k + i], t[i]);
    }
    sss_mesh_free(&m);
}

static void importReadsBinaryLittleEndianPlyCube(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_ply(&B, 0, 0, "property list uchar int vertex_indices");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_file("cube_le.ply", B.b, B.n), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(sss_import_repairs(&rep), 0);
    assert_memory_equal(m.pos, CUBE_V, sizeof CUBE_V);
    sss_mesh_free(&m);
    free(B.b);
}

static void importReadsBinaryBigEndianPlyWithUintIndices(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_ply(&B, 1, 0, "property list uchar uint vertex_index");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_file("cube_be.ply", B.b, B.n), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_memory_equal(m.pos, CUBE_V, sizeof CUBE_V);
    sss_mesh_free(&m);
    free(B.b);
}

static void importReadsBinaryPlyWithCommentBeforeEndHeaderAndExtraProperties(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_ply(&B, 0, 1, "property list int int vertex_indices");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_file("cube_extras.ply", B.b, B.n), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_memory_equal(m.pos, CUBE_V, sizeof CUBE_V);
    sss_mesh_free(&m);
    free(B.b);
}

static void importReadsAsciiPlyWithExtraPropertiesAndRecordsSpanningLines(void **state)
{
    (void)state;
    /* Vertex colour, a texcoord list and a flag on faces, an edge element
     * after the faces; records broken over lines (ascii PLY is a token
     * stream). */
    char text[4096];
    size_t n = (size_t)snprintf(text, sizeof text,
                                "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
                                "property float z\nproperty uchar red\nelement face 6\n"
                                "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
                                "property int flags\nelement edge 1\nproperty int a\nproperty int b\nend_header\n");
    for (int v = 0; v < 8; v++)
        n += (size_t)snprintf(text + n, sizeof text - n, "%g %g %g 7\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    for (int f = 0; f < 6; f++)
        n += (size_t)snprintf(text + n, sizeof text - n, "4 %d %d\n  %d %d 8 .5 .5 .5 .5\n.5 .5 .5 .5 -1\n",
                              CUBE_Q[f][0], CUBE_Q[f][1], CUBE_Q[f][2], CUBE_Q[f][3]);
    snprintf(text + n, sizeof text - n, "0 1\n");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("extras_ascii.ply", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.polygons_triangulated, 6);
    assert_int_equal(sss_import_repairs(&rep), 6);
    assert_memory_equal(m.pos, CUBE_V, sizeof CUBE_V);
    sss_mesh_free(&m);
}

static void importReadsObjWithQuadsRelativeIndicesAndAttributes(void **state)
{
    (void)state;
    const char *obj =
        "# cube\nmtllib does_not_exist.mtl\no cube\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
        "vt 0.5\nvn 0 0 1\nusemtl none\ns off\n"
        "f 1/1/1 4/1/1 3/1/1 2/1/1\n"
        "f 5//1 6//1 7//1 8//1\n"
        "f -8 -7 -3 -4\n" /* 1 2 6 5, relative */
        "f 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("cube.obj", obj), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.faces_read, 6);
    assert_int_equal(rep.polygons_triangulated, 6);
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        for (int i = 0; i < 3; i++) assert_int_equal(m.tri[3 * k + i], t[i]);
    }
    sss_mesh_free(&m);
}

static void importReadsOffCube(void **state)
{
    (void)state;
    char text[1024];
    size_t n = (size_t)snprintf(text, sizeof text, "OFF\n8 6 12\n");
    for (int v = 0; v < 8; v++) n += (size_t)snprintf(text + n, sizeof text - n, "%g %g %g\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    for (int f = 0; f < 6; f++)
        n += (size_t)snprintf(text + n, sizeof text - n, "4 %d %d %d %d\n", CUBE_Q[f][0], CUBE_Q[f][1], CUBE_Q[f][2], CUBE_Q[f][3]);
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("cube.off", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.polygons_triangulated, 6);
    sss_mesh_free(&m);
}

static void importReadsOffWithCountsOnKeywordLineCommentsAndFaceColours(void **state)
{
    (void)state;
    char text[1024];
    size_t n = (size_t)snprintf(text, sizeof text, "# a comment\nNOFF 8 6 0 # counts\n");
    for (int v = 0; v < 8; v++)
        n += (size_t)snprintf(text + n, sizeof text - n, "%g %g %g 0 0 1\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    for (int f = 0; f < 6; f++)
        n += (size_t)snprintf(text + n, sizeof text - n, "4 %d %d %d %d 255 0 0\n", CUBE_Q[f][0], CUBE_Q[f][1],
                              CUBE_Q[f][2], CUBE_Q[f][3]);
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("cube_noff.off", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    sss_mesh_free(&m);
}

static void importReadsBinaryStlCubeAndMergesCorners(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_stl(&B, 12);
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_file("cube_bin.stl", B.b, B.n), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.faces_read, 12);
    assert_int_equal(sss_import_repairs(&rep), 0);
    sss_mesh_free(&m);
    free(B.b);
}

static void importReadsAsciiStlCube(void **state)
{
    (void)state;
    char text[8192];
    size_t n = (size_t)snprintf(text, sizeof text, "solid outer_shell\n");
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        n += (size_t)snprintf(text + n, sizeof text - n, "  facet normal 0 0 0\n    outer loop\n");
        for (int i = 0; i < 3; i++)
            n += (size_t)snprintf(text + n, sizeof text - n, "      vertex %g %g %g\n", CUBE_V[t[i]][0], CUBE_V[t[i]][1],
                                  CUBE_V[t[i]][2]);
        n += (size_t)snprintf(text + n, sizeof text - n, "    endloop\n  endfacet\n");
    }
    snprintf(text + n, sizeof text - n, "endsolid outer_shell\n");
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("cube_ascii.STL", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.faces_read, 12);
    sss_mesh_free(&m);
}

/* ---------------------------------------------------------------------------
 * Rejections
 * ------------------------------------------------------------------------- */

static void importRejectsHugeDeclaredVertexCount(void **state)
{
    (void)state;
    const char *ply = "ply\nformat binary_little_endian 1.0\nelement vertex 2147483648\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n";
    const char *path = write_text("big.ply", ply);
    sss_mesh m;
    sss_error err;
    clock_t t0 = clock();
    assert_int_equal(import(path, &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 0.5);
    assert_non_null(strstr(err.msg, "big.ply: element vertex: declares 2147483648 vertices"));
    assert_non_null(strstr(err.msg, "the file has only"));
    assert_null(m.pos);
}

static void importRejectsHugeFaceListLength(void **state)
{
    (void)state;
    const char *ply = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                      "element face 1\nproperty list uint int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n"
                      "4000000000 0 1 2\n";
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_text("longlist.ply", ply), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "face 0"));
    assert_non_null(strstr(err.msg, "truncated"));
}

static void importRejectsTruncatedBinaryPly(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_ply(&B, 0, 0, "property list uchar int vertex_indices");
    sss_mesh m;
    sss_error err;
    /* Cut inside the faces: the declared counts still fit the size check. */
    assert_int_equal(import(write_file("cut_faces.ply", B.b, B.n - 20), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut_faces.ply: element face: file ends inside face 10 of 12 (truncated)"));
    /* Cut inside the vertices: caught by the size check. */
    size_t hdr = (size_t)(strstr((char *)B.b, "end_header\n") - (char *)B.b) + 11;
    assert_int_equal(import(write_file("cut_vertices.ply", B.b, hdr + 40), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut_vertices.ply: element vertex: declares 8 vertices"));
    free(B.b);
}

static void importRejectsBinaryStlWithWrongTriangleCount(void **state)
{
    (void)state;
    bytes B = {0};
    cube_binary_stl(&B, 13);
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_file("wrong.stl", B.b, B.n), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "wrong.stl: binary STL: declares 13 triangles (734 bytes) but the file has 684 bytes"));
    free(B.b);
}

static void importRejectsNanCoordinateNamingVertex(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    /* binary: the value itself */
    bytes B = {0};
    cube_binary_ply(&B, 0, 0, "property list uchar int vertex_indices");
    size_t hdr = (size_t)(strstr((char *)B.b, "end_header\n") - (char *)B.b) + 11;
    float nan = NAN;
    memcpy(B.b + hdr + 5 * 12 + 4, &nan, 4); /* vertex 5, y */
    assert_int_equal(import(write_file("nan.ply", B.b, B.n), &m, NULL, &err), SSS_ERR_MESH);
    assert_string_equal(err.msg, path_of("nan.ply: vertex 5: coordinate is not finite"));
    free(B.b);
    /* ascii: OpenMesh would read "nan" as 0 and every later number as 0 */
    float v[8][3];
    memcpy(v, CUBE_V, sizeof v);
    v[5][0] = NAN;
    char text[2048];
    ply_text(text, sizeof text, "property list uchar int vertex_indices", (const float (*)[3])v, 8, CUBE_FACES, 6);
    assert_non_null(strstr(text, "\nnan 0 1\n"));
    assert_int_equal(import(write_text("nan_ascii.ply", text), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "nan_ascii.ply: vertex 5: coordinate is not finite ('nan', line 16)"));
    /* off: a value beyond float range is as unusable as inf */
    assert_int_equal(import(write_text("big.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1e39 0\n3 0 1 2\n"), &m, NULL, &err),
                     SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "big.off: vertex 2: coordinate is not finite ('1e39', line 5)"));
    /* obj: OpenMesh would skip the vertex and shift every later index */
    const char *obj = "v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n";
    assert_int_equal(import(write_text("inf.obj", obj), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "inf.obj: vertex 2: coordinate is not finite"));
}

static void importRejectsOutOfRangeFaceIndexNamingFace(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    char text[2048];
    const char *faces[6];
    memcpy(faces, CUBE_FACES, sizeof faces);
    faces[3] = "4 1 2 6 8";
    ply_text(text, sizeof text, "property list uchar int vertex_indices", CUBE_V, 8, faces, 6);
    assert_int_equal(import(write_text("range.ply", text), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "range.ply: face 3: vertex index 8 out of range [0, 8)"));
    /* binary: checked on the soup the reader delivers */
    bytes B = {0};
    cube_binary_ply(&B, 0, 0, "property list uchar int vertex_indices");
    size_t fdata = (size_t)(strstr((char *)B.b, "end_header\n") - (char *)B.b) + 11 + 8 * 12;
    unsigned char idx[4] = {0x29, 0x23, 0, 0}; /* 9001 */
    memcpy(B.b + fdata + 7 * 13 + 1 + 4, idx, 4);
    assert_int_equal(import(write_file("range_bin.ply", B.b, B.n), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "range_bin.ply: face 7: vertex index 9001 out of range [0, 8)"));
    free(B.b);
    /* obj indices are 1-based; 0 is never valid */
    assert_int_equal(import(write_text("zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), &m, NULL, &err),
                     SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "zero.obj: face 0: vertex index 0 out of range"));
}

static void importDropsAndCountsDegenerateFaces(void **state)
{
    (void)state;
    /* The cube's 6 quads, then a 2-gon, a triangle using vertex 0 twice, a
     * quad using vertex 1 twice, and a zero-area triangle through vertex 8,
     * the midpoint of the edge 0-1. */
    float v[9][3];
    memcpy(v, CUBE_V, sizeof CUBE_V);
    v[8][0] = 0.5f; v[8][1] = 0.0f; v[8][2] = 0.0f;
    const char *faces[10] = {CUBE_FACES[0], CUBE_FACES[1], CUBE_FACES[2], CUBE_FACES[3], CUBE_FACES[4],
                             CUBE_FACES[5], "2 0 1", "3 0 0 1", "4 1 2 1 3", "3 0 1 8"};
    char text[4096];
    ply_text(text, sizeof text, "property list uchar uint vertex_index", (const float (*)[3])v, 9, faces, 10);
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("degenerate.ply", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.vertices_read, 9);
    assert_int_equal(rep.faces_read, 10);
    assert_int_equal(rep.polygons_triangulated, 6);
    assert_int_equal(rep.faces_too_small, 1);
    assert_int_equal(rep.faces_repeated_index, 2);
    assert_int_equal(rep.faces_zero_area, 1);
    assert_int_equal(rep.vertices_unreferenced, 1); /* the midpoint only served the dropped triangle */
    assert_int_equal(sss_import_repairs(&rep), 11);
    sss_mesh_free(&m);
}

static void importCountsObjFacesTheReaderWouldMergeOrDrop(void **state)
{
    (void)state;
    const char *obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                      "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n" /* tetrahedron */
                      "f 1 2\n"                             /* too small */
                      "f 1 1 2\n"                           /* repeated; OpenMesh drops it */
                      "f 1 2 2 3\n";                        /* repeated; OpenMesh would keep 1 2 3 */
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("tet.obj", obj), &m, &rep, &err), SSS_OK);
    assert_int_equal(m.nv, 4);
    assert_int_equal(m.nf, 4);
    assert_int_equal(rep.faces_read, 7);
    assert_int_equal(rep.faces_too_small, 1);
    assert_int_equal(rep.faces_repeated_index, 2);
    sss_mesh_free(&m);
}

static void importRemovesUnreferencedVertexKeepingOrder(void **state)
{
    (void)state;
    /* Cube with a stray vertex inserted at index 3 (OFF: indices shifted). */
    char text[1024];
    size_t n = (size_t)snprintf(text, sizeof text, "OFF\n9 6 0\n");
    for (int v = 0; v < 8; v++) {
        if (v == 3) n += (size_t)snprintf(text + n, sizeof text - n, "5 5 5\n");
        n += (size_t)snprintf(text + n, sizeof text - n, "%g %g %g\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    }
    for (int f = 0; f < 6; f++) {
        n += (size_t)snprintf(text + n, sizeof text - n, "4");
        for (int i = 0; i < 4; i++) n += (size_t)snprintf(text + n, sizeof text - n, " %d", CUBE_Q[f][i] + (CUBE_Q[f][i] >= 3));
        n += (size_t)snprintf(text + n, sizeof text - n, "\n");
    }
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("stray.off", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.vertices_read, 9);
    assert_int_equal(rep.vertices_unreferenced, 1);
    assert_memory_equal(m.pos, CUBE_V, sizeof CUBE_V);
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        for (int i = 0; i < 3; i++) assert_int_equal(m.tri[3 * k + i], t[i]);
    }
    sss_mesh_free(&m);
}

static void importRejectsMeshWithNoTrianglesLeft(void **state)
{
    (void)state;
    const char *off = "OFF\n3 2 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n2 0 1\n";
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_text("flat.off", off), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "flat.off: no triangles left after repair (2 faces read)"));
    assert_null(m.pos);
}

static void importRejectsEmptyFile(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_file("empty.ply", "", 0), &m, NULL, &err), SSS_ERR_FORMAT);
    assert_non_null(strstr(err.msg, "empty.ply: file is empty"));
}

static void importRejectsUnknownOrMissingExtension(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_text("mesh.xyz", "0 0 0\n"), &m, NULL, &err), SSS_ERR_FORMAT);
    assert_non_null(strstr(err.msg, "mesh.xyz: unknown extension '.xyz'"));
    assert_int_equal(import(write_text("mesh", "0 0 0\n"), &m, NULL, &err), SSS_ERR_FORMAT);
    assert_non_null(strstr(err.msg, "no file extension"));
}

static void importRejectsMissingFile(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(path_of("missing.ply"), &m, NULL, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, "missing.ply: cannot open"));
}

static void importRejectsNonPlyContentWithPlyExtension(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_text("fake.ply", "solid x\nendsolid x\n"), &m, NULL, &err), SSS_ERR_FORMAT);
    assert_non_null(strstr(err.msg, "fake.ply: not a PLY file"));
}

/* ---------------------------------------------------------------------------
 * Export and reporting
 * ------------------------------------------------------------------------- */

static void exportPlyThenImportRoundTripIsExact(void **state)
{
    (void)state;
    sss_mesh a, b;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(sss_gen_blob(&a, 1.7, 3, &err), SSS_OK);
    const char *path = path_of("blob.ply");
    assert_int_equal(sss_export_ply(path, &a, &err), SSS_OK);
    snprintf(g_files[g_nfiles++], sizeof g_files[0], "%s", path);
    assert_int_equal(import(path, &b, &rep, &err), SSS_OK);
    assert_int_equal(sss_import_repairs(&rep), 0);
    assert_int_equal(b.nv, a.nv);
    assert_int_equal(b.nf, a.nf);
    assert_memory_equal(b.pos, a.pos, (size_t)a.nv * 3 * sizeof(float));
    assert_memory_equal(b.tri, a.tri, (size_t)a.nf * 3 * sizeof(uint32_t));
    assert_memory_equal(b.area, a.area, (size_t)a.nv * sizeof(double));
    sss_mesh_free(&a);
    sss_mesh_free(&b);
}

static void printRepairsWritesOneLinePerNonZeroCounter(void **state)
{
    (void)state;
    sss_import_report rep;
    memset(&rep, 0, sizeof rep);
    rep.polygons_triangulated = 12;
    rep.faces_zero_area = 1;
    FILE *f = tmpfile();
    assert_non_null(f);
    sss_import_print_repairs(&rep, "sss-bake: bunny.ply", f);
    rewind(f);
    char buf[512];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    assert_string_equal(buf,
                        "sss-bake: bunny.ply: repaired: 12 polygons with more than 3 vertices fan-triangulated\n"
                        "sss-bake: bunny.ply: repaired: 1 zero-area triangle dropped\n");
}

/* ---------------------------------------------------------------------------
 * Orientation, duplicates, non-convex polygons, far-off meshes (docs/robustness.md B5-B7)
 * ------------------------------------------------------------------------- */

/* Writes m as OFF text (positions %.9g, or %.17g plus offset when far),
 * with triangle t reversed where rev(t) says so. */
static const char *write_off_mesh(const char *name, const sss_mesh *m, double offset, int (*rev)(uint32_t t))
{
    size_t cap = 256 + (size_t)m->nv * 80 + (size_t)m->nf * 40, n = 0;
    char *text = malloc(cap);
    assert_non_null(text);
    n += (size_t)snprintf(text + n, cap - n, "OFF\n%u %u 0\n", m->nv, m->nf);
    for (uint32_t v = 0; v < m->nv; v++)
        n += (size_t)snprintf(text + n, cap - n, "%.17g %.17g %.17g\n", offset + m->pos[3 * v], offset + m->pos[3 * v + 1],
                              offset + m->pos[3 * v + 2]);
    for (uint32_t t = 0; t < m->nf; t++) {
        const uint32_t *x = m->tri + 3 * t;
        if (rev && rev(t)) n += (size_t)snprintf(text + n, cap - n, "3 %u %u %u\n", x[0], x[2], x[1]);
        else n += (size_t)snprintf(text + n, cap - n, "3 %u %u %u\n", x[0], x[1], x[2]);
    }
    assert_true(n < cap);
    const char *p = write_text(name, text);
    free(text);
    return p;
}

static int rev_all(uint32_t t) { (void)t; return 1; }
static int rev_odd(uint32_t t) { return (int)(t & 1u); }
static int rev_few(uint32_t t) { return t == 3 || t == 10 || t == 17; }

/* Every vertex normal of a closed convex mesh around c points away from c. */
static void assert_normals_outward(const sss_mesh *m, const double c[3])
{
    for (uint32_t v = 0; v < m->nv; v++) {
        double d = 0;
        for (int k = 0; k < 3; k++) d += (m->pos[3 * v + k] - c[k]) * m->nrm[3 * v + k];
        assert_true(d > 0);
    }
}

static void importTurnsInsideOutCubeOutward(void **state)
{
    (void)state;
    /* B5's reproducer: every quad of the cube wound inward. */
    const char *off = "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
                      "4 1 2 3 0\n4 7 6 5 4\n4 4 5 1 0\n4 6 7 3 2\n4 3 7 4 0\n4 5 6 2 1\n";
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("inside_out.off", off), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.faces_flipped, 12);
    assert_int_equal(rep.surfaces_inside_out, 1);
    assert_int_equal(rep.open_faces_flipped, 0);
    assert_int_equal(rep.orientation_conflicts, 0);
    const double c[3] = {0.5, 0.5, 0.5};
    assert_normals_outward(&m, c);
    sss_mesh_free(&m);
}

static void importMakesFlippedTrianglesOfSphereConsistent(void **state)
{
    (void)state;
    sss_mesh s, m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 3, &err), SSS_OK);
    const double c[3] = {0, 0, 0};
    /* Half the triangles reversed (B5: mean q -60 % before), then all of them. */
    int (*revs[2])(uint32_t) = {rev_odd, rev_all};
    const char *names[2] = {"half_flipped.off", "all_flipped.off"};
    for (int i = 0; i < 2; i++) {
        assert_int_equal(import(write_off_mesh(names[i], &s, 0.0, revs[i]), &m, &rep, &err), SSS_OK);
        assert_int_equal(m.nf, s.nf);
        assert_int_equal(rep.faces_flipped, i == 0 ? s.nf / 2 : s.nf);
        assert_int_equal(rep.surfaces_inside_out, i == 0 ? 0 : 1);
        assert_normals_outward(&m, c);
        /* flipping back restores the generator's triangles exactly */
        assert_memory_equal(m.tri, s.tri, (size_t)s.nf * 3 * sizeof(uint32_t));
        sss_mesh_free(&m);
    }
    /* A consistent outward sphere is left alone: nothing flipped. */
    assert_int_equal(import(write_off_mesh("sphere.off", &s, 0.0, NULL), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.faces_flipped + rep.open_faces_flipped + rep.faces_duplicate, 0);
    assert_int_equal(sss_import_repairs(&rep), 0);
    assert_memory_equal(m.tri, s.tri, (size_t)s.nf * 3 * sizeof(uint32_t));
    sss_mesh_free(&m);
    sss_mesh_free(&s);
}

static void importOpenSurfaceTakesItsMajorityWinding(void **state)
{
    (void)state;
    sss_mesh s, m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(sss_gen_plane(&s, 1.0, 1.0, 4, 4, &err), SSS_OK); /* 32 triangles, normal +z */
    /* 3 of 32 reversed: flipped back to the majority */
    assert_int_equal(import(write_off_mesh("plane_few.off", &s, 0.0, rev_few), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.open_faces_flipped, 3);
    assert_int_equal(rep.faces_flipped, 0);
    assert_memory_equal(m.tri, s.tri, (size_t)s.nf * 3 * sizeof(uint32_t));
    sss_mesh_free(&m);
    /* all reversed: consistent already; which side is outside cannot be
     * told for an open surface, so the file's winding stays */
    assert_int_equal(import(write_off_mesh("plane_down.off", &s, 0.0, rev_all), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.open_faces_flipped + rep.faces_flipped, 0);
    for (uint32_t v = 0; v < m.nv; v++) assert_true(m.nrm[3 * v + 2] < -0.99f);
    sss_mesh_free(&m);
    sss_mesh_free(&s);
}

/* Appends b to a, with b's triangles reversed when inward. */
static void append(sss_mesh *a, const sss_mesh *b, int inward)
{
    sss_error err;
    sss_mesh c;
    assert_int_equal(sss_mesh_copy(b, &c, &err), SSS_OK);
    if (inward)
        for (uint32_t t = 0; t < c.nf; t++) {
            uint32_t x = c.tri[3 * t + 1];
            c.tri[3 * t + 1] = c.tri[3 * t + 2];
            c.tri[3 * t + 2] = x;
        }
    assert_int_equal(sss_mesh_append(a, &c, &err), SSS_OK);
    sss_mesh_free(&c);
}

static void importLeavesCavityInsideClosedSurfaceAlone(void **state)
{
    (void)state;
    sss_mesh outer, inner, m;
    sss_import_report rep;
    sss_error err;
    /* A hollow shell: its inner wall faces the cavity (negative volume,
     * nested): left as it is. */
    assert_int_equal(sss_gen_sphere(&outer, 2.0, 2, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&inner, 1.0, 2, &err), SSS_OK);
    append(&outer, &inner, 1);
    assert_int_equal(import(write_off_mesh("hollow.off", &outer, 0.0, NULL), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.faces_flipped + rep.surfaces_inside_out, 0);
    assert_memory_equal(m.tri, outer.tri, (size_t)outer.nf * 3 * sizeof(uint32_t));
    sss_mesh_free(&m);
    sss_mesh_free(&outer);
    /* The same inward sphere on its own is inside out: turned outward. */
    assert_int_equal(sss_gen_sphere(&outer, 1.0, 2, &err), SSS_OK);
    memset(&m, 0, sizeof m);
    assert_int_equal(import(write_off_mesh("inward.off", &inner, 0.0, rev_all), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.faces_flipped, inner.nf);
    assert_int_equal(rep.surfaces_inside_out, 1);
    sss_mesh_free(&m);
    sss_mesh_free(&outer);
    sss_mesh_free(&inner);
}

static void importWarnsOnNonOrientableStrip(void **state)
{
    (void)state;
    /* A Moebius strip of 12 quads: one edge is left inconsistent whatever
     * is flipped. */
    enum { K = 12 };
    char text[4096];
    size_t n = (size_t)snprintf(text, sizeof text, "OFF\n%d %d 0\n", 2 * K, K);
    for (int i = 0; i < K; i++) {
        double a = 2 * SSS_PI * i / K, h = a / 2;
        for (int s = -1; s <= 1; s += 2) {
            double r = 2 + 0.5 * s * cos(h);
            n += (size_t)snprintf(text + n, sizeof text - n, "%.9g %.9g %.9g\n", r * cos(a), r * sin(a), 0.5 * s * sin(h));
        }
    }
    for (int i = 0; i < K; i++) {
        int j = (i + 1) % K;
        /* the last quad joins the strip's two sides crosswise */
        int b0 = 2 * j + (j == 0), b1 = 2 * j + (j != 0);
        n += (size_t)snprintf(text + n, sizeof text - n, "4 %d %d %d %d\n", 2 * i, b0, b1, 2 * i + 1);
    }
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("moebius.off", text), &m, &rep, &err), SSS_OK);
    assert_int_equal(m.nf, 2 * K);
    assert_true(rep.orientation_conflicts >= 1);
    for (uint32_t v = 0; v < m.nv; v++) assert_true(isfinite(m.nrm[3 * v]) && m.area[v] > 0);
    FILE *f = tmpfile();
    assert_non_null(f);
    sss_import_print_warnings(&rep, "sss-bake: moebius.off", f);
    rewind(f);
    char buf[512];
    size_t got = fread(buf, 1, sizeof buf - 1, f);
    buf[got] = '\0';
    fclose(f);
    assert_non_null(strstr(buf, "sss-bake: moebius.off: warning: "));
    assert_non_null(strstr(buf, "non-orientable"));
    sss_mesh_free(&m);
}

static void importDropsDuplicateTrianglesInEitherWinding(void **state)
{
    (void)state;
    /* The cube, then its first four triangles again: two as they are, two
     * reversed (B5: copies doubled the areas, reversed copies cancelled the
     * normals). */
    char text[2048];
    size_t n = (size_t)snprintf(text, sizeof text, "OFF\n8 16 0\n");
    for (int v = 0; v < 8; v++) n += (size_t)snprintf(text + n, sizeof text - n, "%g %g %g\n", CUBE_V[v][0], CUBE_V[v][1], CUBE_V[v][2]);
    for (int k = 0; k < 16; k++) {
        int t[3];
        cube_tri(k % 12, t);
        if (k >= 14) n += (size_t)snprintf(text + n, sizeof text - n, "3 %d %d %d\n", t[0], t[2], t[1]);
        else n += (size_t)snprintf(text + n, sizeof text - n, "3 %d %d %d\n", t[0], t[1], t[2]);
    }
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    assert_int_equal(import(write_text("dups.off", text), &m, &rep, &err), SSS_OK);
    assert_cube(&m);
    assert_int_equal(rep.faces_duplicate, 4);
    assert_int_equal(rep.faces_flipped, 0);
    const double c[3] = {0.5, 0.5, 0.5};
    assert_normals_outward(&m, c);
    for (int k = 0; k < 12; k++) {
        int t[3];
        cube_tri(k, t);
        for (int i = 0; i < 3; i++) assert_int_equal(m.tri[3 * k + i], t[i]);
    }
    sss_mesh_free(&m);
}

/* Signed area of triangle t in the z = 0 plane. */
static double tri_area_z(const sss_mesh *m, uint32_t t)
{
    const float *a = m->pos + 3 * m->tri[3 * t], *b = m->pos + 3 * m->tri[3 * t + 1], *c = m->pos + 3 * m->tri[3 * t + 2];
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
}

static void importEarClipsNonConvexPolygons(void **state)
{
    (void)state;
    struct { const char *name, *off; double area; } cases[] = {
        /* B7's L-shaped hexagon, listed from a corner next to the reflex one:
         * its fan gave areas -0.5, 0.5, 2, 1 */
        {"l_hexagon.off", "OFF\n6 1 0\n0 0 0\n2 0 0\n2 1 0\n1 1 0\n1 2 0\n0 2 0\n6 2 3 4 5 0 1\n", 3.0},
        /* a dart (non-convex quad) fanned from its reflex corner's neighbour */
        {"dart.off", "OFF\n4 1 0\n0 0 0\n2 1 0\n0 2 0\n0.5 1 0\n4 1 2 3 0\n", 1.5},
        /* an arrow-shaped pentagon, tilted out of the axis planes */
        {"arrow.off", "OFF\n5 1 0\n0 0 0\n4 0 0\n4 2 0\n2 0.5 0\n0 2 0\n5 3 4 0 1 2\n", 5.0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        sss_mesh m;
        sss_import_report rep;
        sss_error err;
        assert_int_equal(import(write_text(cases[i].name, cases[i].off), &m, &rep, &err), SSS_OK);
        assert_int_equal(rep.polygons_triangulated, 1);
        assert_int_equal(rep.polygons_ear_clipped, 1);
        assert_int_equal(rep.polygons_unclipped, 0);
        double sum = 0;
        for (uint32_t t = 0; t < m.nf; t++) {
            double a = tri_area_z(&m, t);
            assert_true(a > 0); /* no flipped triangle */
            sum += a;
        }
        assert_true(fabs(sum - cases[i].area) < 1e-6); /* no overlap: the area is kept */
        assert_true(fabs(total_area(&m) - cases[i].area) < 1e-6);
        for (uint32_t v = 0; v < m.nv; v++) assert_true(m.nrm[3 * v + 2] > 0.999f);
        sss_mesh_free(&m);
    }
    /* Convex polygons are still fanned from their first corner: the cube
     * tests above check the exact triangles. A pentagram (self-intersecting)
     * cannot be ear-clipped: fanned and warned. */
    sss_mesh m;
    sss_import_report rep;
    sss_error err;
    char text[512];
    size_t n = (size_t)snprintf(text, sizeof text, "OFF\n5 1 0\n");
    for (int k = 0; k < 5; k++)
        n += (size_t)snprintf(text + n, sizeof text - n, "%.9g %.9g 0\n", cos(2 * SSS_PI * k / 5), sin(2 * SSS_PI * k / 5));
    snprintf(text + n, sizeof text - n, "5 0 2 4 1 3\n");
    assert_int_equal(import(write_text("star.off", text), &m, &rep, &err), SSS_OK);
    assert_int_equal(rep.polygons_ear_clipped + rep.polygons_unclipped, 1);
    for (uint32_t v = 0; v < m.nv; v++) assert_true(isfinite(m.nrm[3 * v]));
    sss_mesh_free(&m);
}

static void importRecentresFarMeshInDoubleBeforeFloat(void **state)
{
    (void)state;
    sss_mesh s, near, far;
    sss_import_report rn, rf;
    sss_error err;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 4, &err), SSS_OK); /* 2562 vertices, 5120 triangles */
    assert_int_equal(import(write_off_mesh("origin.off", &s, 0.0, NULL), &near, &rn, &err), SSS_OK);
    assert_int_equal(rn.recentred, 0);
    assert_memory_equal(near.pos, s.pos, (size_t)s.nv * 3 * sizeof(float));
    /* B6: at 10^6, float32 spacing is 1/16; 9,152 of 16,128 triangles of a
     * unit UV sphere collapsed before. The file has %.17g coordinates. */
    assert_int_equal(import(write_off_mesh("far.off", &s, 1e6, NULL), &far, &rf, &err), SSS_OK);
    assert_int_equal(rf.recentred, 1);
    for (int k = 0; k < 3; k++) assert_true(fabs(rf.offset[k] - 1e6) < 1e-6);
    assert_int_equal(rf.faces_zero_area, 0);
    assert_int_equal(far.nv, s.nv);
    assert_int_equal(far.nf, s.nf);
    assert_memory_equal(far.tri, s.tri, (size_t)s.nf * 3 * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * (size_t)s.nv; i++) assert_true(fabs(far.pos[i] - s.pos[i]) < 1e-9);
    for (uint32_t v = 0; v < s.nv; v++) assert_true(fabs(far.area[v] - near.area[v]) < 1e-6 * near.area[v]);
    sss_mesh_free(&far);
    /* Binary PLY with double coordinates and OBJ keep the precision too. */
    bytes B = {0};
    char hdr[256];
    snprintf(hdr, sizeof hdr, "ply\nformat binary_little_endian 1.0\nelement vertex %u\nproperty double x\n"
             "property double y\nproperty double z\nelement face %u\nproperty list uchar int vertex_indices\nend_header\n",
             s.nv, s.nf);
    put_str(&B, hdr);
    for (size_t i = 0; i < 3 * (size_t)s.nv; i++) {
        double d = 1e6 + s.pos[i];
        uint64_t u;
        memcpy(&u, &d, 8);
        put_u32(&B, (uint32_t)u, 0);
        put_u32(&B, (uint32_t)(u >> 32), 0);
    }
    for (uint32_t t = 0; t < s.nf; t++) {
        put_u8(&B, 3);
        for (int k = 0; k < 3; k++) put_u32(&B, s.tri[3 * t + k], 0);
    }
    assert_int_equal(import(write_file("far_double.ply", B.b, B.n), &far, &rf, &err), SSS_OK);
    assert_int_equal(rf.recentred, 1);
    assert_int_equal(rf.faces_zero_area, 0);
    for (size_t i = 0; i < 3 * (size_t)s.nv; i++) assert_true(fabs(far.pos[i] - s.pos[i]) < 1e-9);
    sss_mesh_free(&far);
    free(B.b);
    /* A mesh 10 sizes away keeps its coordinates (and its bakes' bytes). */
    assert_int_equal(import(write_off_mesh("near.off", &s, 10.0, NULL), &far, &rf, &err), SSS_OK);
    assert_int_equal(rf.recentred, 0);
    for (size_t i = 0; i < 3 * (size_t)s.nv; i++) assert_true(fabs(far.pos[i] - (10.0 + s.pos[i])) < 1e-6);
    sss_mesh_free(&far);
    sss_mesh_free(&near);
    sss_mesh_free(&s);
}

static void importRejectsTruncatedAsciiFilesNamingElement(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    char text[2048];
    cube_ascii_ply(text, sizeof text, "property list uchar int vertex_indices");
    /* ascii PLY cut inside the faces, and inside the vertices */
    text[strlen(text) - 6] = '\0';
    assert_int_equal(import(write_text("cut.ply", text), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut.ply: element face: file ends inside face 5 of 6 (truncated)"));
    assert_int_equal(import(write_text("cut_v.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                                                    "property float y\nproperty float z\nelement face 1\n"
                                                    "property list uchar int vertex_indices\nend_header\n"
                                                    "0 0 0\n1 0 0\n0 1 0\n3 0 1\n"), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut_v.ply: element face: file ends inside face 0 of 1"));
    /* OFF */
    assert_int_equal(import(write_text("cut.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1\n"), &m, NULL, &err),
                     SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut.off: element face: file ends inside face 1 of 2 (truncated)"));
    assert_int_equal(import(write_text("cut_v.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0    0         \n"), &m, NULL, &err),
                     SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut_v.off: element vertex: file ends inside vertex 3 of 4 (truncated)"));
    /* shorter still: caught by the size check, naming the faces */
    assert_int_equal(import(write_text("cut_s.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n0 0\n"), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut_s.off: element face: declares 1 faces but the file has only"));
    /* OBJ: a vertex line cut short */
    assert_int_equal(import(write_text("cut.obj", "v 0 0 0\nv 1 0 0\nv 0 1"), &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut.obj: vertex 2 (line 3): fewer than 3 coordinates"));
    /* ascii STL: a facet cut inside its loop */
    assert_int_equal(import(write_text("cut.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"),
                            &m, NULL, &err), SSS_ERR_CORRUPT);
    assert_non_null(strstr(err.msg, "cut.stl: triangle 0: expected 'vertex x y z'"));
}

static void importRejectsNanInStlAndHugeCountInOff(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err;
    assert_int_equal(import(write_text("nan.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                                  "vertex 0 nan 0\nendloop\nendfacet\nendsolid s\n"), &m, NULL, &err),
                     SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "nan.stl: triangle 0: vertex 2: coordinate is not finite ('nan', line 6)"));
    bytes B = {0};
    cube_binary_stl(&B, 12);
    float inf = INFINITY;
    memcpy(B.b + 84 + 50 * 1 + 12 + 4 * 4, &inf, 4); /* triangle 1, vertex 1, y */
    assert_int_equal(import(write_file("inf.stl", B.b, B.n), &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "inf.stl: triangle 1: vertex 1: coordinate is not finite"));
    free(B.b);
    /* 2^31 vertices declared in a ~40-byte OFF: refused before allocating */
    clock_t t0 = clock();
    assert_int_equal(import(write_text("huge.off", "OFF\n2147483648 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"), &m, NULL, &err),
                     SSS_ERR_CORRUPT);
    assert_true((double)(clock() - t0) / CLOCKS_PER_SEC < 0.5);
    assert_non_null(strstr(err.msg, "huge.off: element vertex: declares 2147483648 vertices but the file has only"));
    assert_null(m.pos);
}

static void printRepairsAndWarningsNameTheNewCounters(void **state)
{
    (void)state;
    sss_import_report rep;
    memset(&rep, 0, sizeof rep);
    rep.polygons_triangulated = 2;
    rep.polygons_ear_clipped = 1;
    rep.faces_flipped = 12;
    rep.surfaces_inside_out = 1;
    rep.recentred = 1;
    rep.offset[0] = rep.offset[1] = rep.offset[2] = 1e6;
    rep.polygons_unclipped = 1;
    assert_int_equal(sss_import_repairs(&rep), 2 + 12 + 1);
    FILE *f = tmpfile();
    assert_non_null(f);
    sss_import_print_repairs(&rep, "t", f);
    sss_import_print_warnings(&rep, "t", f);
    rewind(f);
    char buf[2048];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = '\0';
    fclose(f);
    assert_non_null(strstr(buf, "t: repaired: 1 non-convex polygon ear-clipped in its plane instead"));
    assert_non_null(strstr(buf, "t: repaired: 12 triangles of closed surfaces flipped to face outward consistently\n"));
    assert_non_null(strstr(buf, "t: repaired: 1 closed surface was inside out as a whole\n"));
    assert_non_null(strstr(buf, "t: repaired: mesh recentred: (1000000, 1000000, 1000000) subtracted"));
    assert_non_null(strstr(buf, "t: warning: 1 non-convex polygon could not be ear-clipped"));
}

/* A UTF-8 byte-order mark at the start of a text file is not part of its
 * first token: the mesh read is the one without it, in every text format
 * (an OBJ's first "v" became an unknown statement and every face index
 * shifted by one, with exit 0; docs/robustness.md item 4). */
static void importDropsUtf8ByteOrderMarkInEveryTextFormat(void **state)
{
    (void)state;
    static const char *const obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 5 5 5\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    static const char *const off = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    static const char *const ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                   "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
                                   "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    static const char *const stl =
        "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
        "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
        "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
        "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\nendsolid t\n";
    const char *const text[4] = {obj, off, ply, stl}, *const ext[4] = {"obj", "off", "ply", "stl"};
    for (int k = 0; k < 4; k++) {
        char plain[40], marked[40], buf[1200];
        snprintf(plain, sizeof plain, "plain.%s", ext[k]);
        snprintf(marked, sizeof marked, "bom.%s", ext[k]);
        snprintf(buf, sizeof buf, "\xEF\xBB\xBF%s", text[k]);
        const char *pa = write_text(plain, text[k]), *pb = write_text(marked, buf);
        sss_mesh a, b;
        sss_import_report ra, rb;
        sss_error err = {{0}};
        if (sss_import_mesh(pa, &a, &ra, &err) != SSS_OK) fail_msg("%s", err.msg);
        if (sss_import_mesh(pb, &b, &rb, &err) != SSS_OK) fail_msg("%s with a byte-order mark: %s", ext[k], err.msg);
        assert_int_equal(a.nv, b.nv);
        assert_int_equal(a.nf, b.nf);
        assert_memory_equal(a.pos, b.pos, 3 * (size_t)a.nv * sizeof(float));
        assert_memory_equal(a.tri, b.tri, 3 * (size_t)a.nf * sizeof(uint32_t));
        sss_mesh_free(&a);
        sss_mesh_free(&b);
    }
}

/* Coordinates beyond 1e15 reach Embree, which asserts (aborting the
 * process) on rays near 1.8e18: refused at import, naming the vertex; a
 * far but small mesh is recentred first and kept (docs/robustness.md item 3). */
static void importRejectsCoordinatesBeyondTheRange(void **state)
{
    (void)state;
    const char *p = write_text("huge.off", "OFF\n4 4 0\n2e18 0 0\n-1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_import_mesh(p, &m, NULL, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "huge.off: vertex 0: coordinate 0 is"));
    assert_non_null(strstr(err.msg, "beyond 1e+15"));
    p = write_text("far.off", "OFF\n4 4 0\n3e18 0 0\n3e18 1 0\n3e18 0 1\n3.0000000000000001e18 1 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    sss_import_report rep;
    if (sss_import_mesh(p, &m, &rep, &err) != SSS_OK) fail_msg("%s", err.msg);
    assert_int_equal(rep.recentred, 1);
    sss_mesh_free(&m);
}

/* Signed volume of a closed mesh (the divergence theorem over its triangles). */
static double mesh_volume(const sss_mesh *m)
{
    double v = 0;
    for (uint32_t f = 0; f < m->nf; f++) {
        const float *a = &m->pos[3 * (size_t)m->tri[3 * f]], *b = &m->pos[3 * (size_t)m->tri[3 * f + 1]],
                    *c = &m->pos[3 * (size_t)m->tri[3 * f + 2]];
        v += (a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) - a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
              a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0])) / 6.0;
    }
    return v;
}

/* sss_gen_subdivide (sss-genmesh subdivide, tests/bench/table1.sh): n² triangles
 * per triangle, V + E (n − 1) + T (n − 1)(n − 2)/2 vertices with the edge
 * points shared (a closed mesh stays closed: Euler's V − E + F = 2 with
 * E = 3F/2), the same surface (area and enclosed volume, the winding kept). */
static void subdivisionCutsEveryTriangleIntoNSquaredOnTheSameSurface(void **state)
{
    (void)state;
    sss_error err;
    sss_mesh s, d;
    assert_int_equal(sss_gen_sphere(&s, 1.0, 1, &err), SSS_OK); /* 42 vertices, 120 edges, 80 triangles */
    double area = 0, area3 = 0;
    for (uint32_t v = 0; v < s.nv; v++) area += s.area[v];
    for (unsigned n = 1; n <= 4; n++) {
        assert_int_equal(sss_gen_subdivide(&s, n, &d, &err), SSS_OK);
        assert_int_equal(d.nf, 80u * n * n);
        assert_int_equal(d.nv, 42u + 120u * (n - 1) + 80u * (n - 1) * (n - 2) / 2);
        assert_int_equal((int64_t)d.nv - 3 * (int64_t)d.nf / 2 + d.nf, 2);
        area3 = 0;
        for (uint32_t v = 0; v < d.nv; v++) area3 += d.area[v];
        assert_true(fabs(area3 - area) < 1e-6 * area);
        assert_true(fabs(mesh_volume(&d) - mesh_volume(&s)) < 1e-6 * mesh_volume(&s));
        assert_true(mesh_volume(&d) > 0); /* outward, as the input */
        sss_mesh_free(&d);
    }
    assert_int_equal(sss_gen_subdivide(&s, 0, &d, &err), SSS_ERR_ARG);
    sss_mesh_free(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(subdivisionCutsEveryTriangleIntoNSquaredOnTheSameSurface),
        cmocka_unit_test(importReadsAsciiPlyCubeAndTriangulatesQuads),
        cmocka_unit_test(importDropsUtf8ByteOrderMarkInEveryTextFormat),
        cmocka_unit_test(importRejectsCoordinatesBeyondTheRange),
        cmocka_unit_test(importReadsBinaryLittleEndianPlyCube),
        cmocka_unit_test(importReadsBinaryBigEndianPlyWithUintIndices),
        cmocka_unit_test(importReadsBinaryPlyWithCommentBeforeEndHeaderAndExtraProperties),
        cmocka_unit_test(importReadsAsciiPlyWithExtraPropertiesAndRecordsSpanningLines),
        cmocka_unit_test(importReadsObjWithQuadsRelativeIndicesAndAttributes),
        cmocka_unit_test(importReadsOffCube),
        cmocka_unit_test(importReadsOffWithCountsOnKeywordLineCommentsAndFaceColours),
        cmocka_unit_test(importReadsBinaryStlCubeAndMergesCorners),
        cmocka_unit_test(importReadsAsciiStlCube),
        cmocka_unit_test(importRejectsHugeDeclaredVertexCount),
        cmocka_unit_test(importRejectsHugeFaceListLength),
        cmocka_unit_test(importRejectsTruncatedBinaryPly),
        cmocka_unit_test(importRejectsBinaryStlWithWrongTriangleCount),
        cmocka_unit_test(importRejectsNanCoordinateNamingVertex),
        cmocka_unit_test(importRejectsOutOfRangeFaceIndexNamingFace),
        cmocka_unit_test(importDropsAndCountsDegenerateFaces),
        cmocka_unit_test(importCountsObjFacesTheReaderWouldMergeOrDrop),
        cmocka_unit_test(importRemovesUnreferencedVertexKeepingOrder),
        cmocka_unit_test(importRejectsMeshWithNoTrianglesLeft),
        cmocka_unit_test(importRejectsEmptyFile),
        cmocka_unit_test(importRejectsUnknownOrMissingExtension),
        cmocka_unit_test(importRejectsMissingFile),
        cmocka_unit_test(importRejectsNonPlyContentWithPlyExtension),
        cmocka_unit_test(exportPlyThenImportRoundTripIsExact),
        cmocka_unit_test(printRepairsWritesOneLinePerNonZeroCounter),
        cmocka_unit_test(importTurnsInsideOutCubeOutward),
        cmocka_unit_test(importMakesFlippedTrianglesOfSphereConsistent),
        cmocka_unit_test(importOpenSurfaceTakesItsMajorityWinding),
        cmocka_unit_test(importLeavesCavityInsideClosedSurfaceAlone),
        cmocka_unit_test(importWarnsOnNonOrientableStrip),
        cmocka_unit_test(importDropsDuplicateTrianglesInEitherWinding),
        cmocka_unit_test(importEarClipsNonConvexPolygons),
        cmocka_unit_test(importRecentresFarMeshInDoubleBeforeFloat),
        cmocka_unit_test(importRejectsTruncatedAsciiFilesNamingElement),
        cmocka_unit_test(importRejectsNanInStlAndHugeCountInOff),
        cmocka_unit_test(printRepairsAndWarningsNameTheNewCounters),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
