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

/* ---------------------------------------------------------------------------
 * Temporary files
 * ------------------------------------------------------------------------- */

static char g_dir[64];
static char g_files[64][160];
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
    if (!known && g_nfiles < 64) snprintf(g_files[g_nfiles++], sizeof g_files[0], "%s", p);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(importReadsAsciiPlyCubeAndTriangulatesQuads),
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
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
