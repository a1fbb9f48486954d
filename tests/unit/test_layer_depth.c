/* test_layer_depth.c: layers of variable depth (docs/layers.md §3): depth
 * maps (PNG written by the test itself) and procedural depths evaluated
 * per vertex at bake time, and the single scattering of the CPU oracle
 * with each vertex's own stack. */
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
#include "sss/bvh.h"
#include "sss/depthmap.h"
#include "sss/format.h"
#include "sss/import.h"
#include "sss/layer_depth.h"
#include "sss/layer_depths.h"
#include "sss/scene.h"
#include "sss/single_mesh.h"

static char g_dir[64];

static int setup_dir(void **state)
{
    (void)state;
    strcpy(g_dir, "/tmp/sss_test_layer_depth_XXXXXX");
    return mkdtemp(g_dir) ? 0 : -1;
}

static const char *path_of(const char *name)
{
    static char buf[8][160];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", g_dir, name);
    return buf[k];
}

static int teardown_dir(void **state)
{
    (void)state;
    static const char *const names[] = {"m8.png", "m16.png", "one.png", "rgb.png", "text.png", "plane.ply", "box.ply",
                                        "s.json", NULL};
    for (const char *const *n = names; *n; n++) unlink(path_of(*n));
    rmdir(g_dir);
    return 0;
}

static void write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
    assert_int_equal(fclose(f), 0);
}

/* A w × h map of the given values written as a grey PNG of `bits`. */
static void write_map(const char *path, uint32_t w, uint32_t h, const float *values, int bits)
{
    sss_depth_image im = {w, h, (float *)values};
    sss_error err = {{0}};
    if (sss_depth_map_write(path, &im, bits, &err) != SSS_OK) fail_msg("%s", err.msg);
}

/* ---- maps --------------------------------------------------------------- */

/* What the writer stores comes back quantised to 1/255 or 1/65535, and
 * the sample at a texel's centre is that texel (v upward: row 0 at v = 1). */
static void mapsReadBackAndSampleAtTexelCentres(void **state)
{
    (void)state;
    const float v[8] = {0.0f, 0.25f, 0.5f, 1.0f, 0.1f, 0.2f, 0.3f, 0.9f};
    const int bits[2] = {8, 16};
    for (int b = 0; b < 2; b++) {
        const char *p = path_of(b ? "m16.png" : "m8.png");
        write_map(p, 4, 2, v, bits[b]);
        sss_depth_image im;
        sss_error err = {{0}};
        assert_int_equal(sss_depth_map_read(p, &im, &err), SSS_OK);
        assert_int_equal(im.w, 4);
        assert_int_equal(im.h, 2);
        const double top = b ? 65535.0 : 255.0;
        for (int i = 0; i < 8; i++) assert_float_equal(im.value[i], lround(v[i] * top) / top, 1e-7);
        for (uint32_t j = 0; j < 2; j++)
            for (uint32_t i = 0; i < 4; i++)
                assert_float_equal(sss_depth_image_sample(&im, (i + 0.5) / 4.0, 1.0 - (j + 0.5) / 2.0),
                                   im.value[j * 4 + i], 1e-7);
        /* between two texels of row 0: their mean; and u wraps */
        assert_float_equal(sss_depth_image_sample(&im, 0.25, 0.75), 0.5 * (im.value[0] + im.value[1]), 1e-7);
        assert_float_equal(sss_depth_image_sample(&im, 1.125, 0.75), sss_depth_image_sample(&im, 0.125, 0.75), 1e-7);
        sss_depth_image_free(&im);
    }
}

/* Bad maps: one line naming the file and what is wrong. The colour type
 * and bit depth are edited in the header the writer made, its CRC redone. */
static void badMapsAreRefusedNamingTheFile(void **state)
{
    (void)state;
    sss_depth_image im;
    sss_error err = {{0}};
    const char *missing = path_of("missing.png");
    assert_int_equal(sss_depth_map_read(missing, &im, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, missing));
    const char *text = path_of("text.png");
    write_text(text, "P2 4 2 255\n");
    assert_int_equal(sss_depth_map_read(text, &im, &err), SSS_ERR_FORMAT);
    assert_non_null(strstr(err.msg, text));
    assert_non_null(strstr(err.msg, "not a PNG file"));
    /* IHDR: 8 signature bytes, length, "IHDR", w, h, then bit depth at 24
     * and colour type at 25; its CRC (over type and data) at 29 */
    const float v[4] = {0.1f, 0.2f, 0.3f, 0.4f};
    const char *rgb = path_of("rgb.png");
    const struct { uint8_t depth, colour; const char *want; } cases[3] = {
        {8, 2, "RGB, 8-bit: a depth map is an 8- or 16-bit grey PNG"},
        {8, 4, "grey with alpha, 8-bit"},
        {4, 0, "grey, 4-bit"},
    };
    for (int k = 0; k < 3; k++) {
        write_map(rgb, 2, 2, v, 8);
        FILE *f = fopen(rgb, "r+b");
        assert_non_null(f);
        uint8_t hdr[33];
        assert_int_equal(fread(hdr, 1, 33, f), 33);
        hdr[24] = cases[k].depth;
        hdr[25] = cases[k].colour;
        const uint32_t crc = sss_crc32(0, hdr + 12, 17);
        for (int i = 0; i < 4; i++) hdr[29 + i] = (uint8_t)(crc >> (24 - 8 * i));
        assert_int_equal(fseek(f, 0, SEEK_SET), 0);
        assert_int_equal(fwrite(hdr, 1, 33, f), 33);
        assert_int_equal(fclose(f), 0);
        assert_int_equal(sss_depth_map_read(rgb, &im, &err), SSS_ERR_UNSUPPORTED);
        assert_non_null(strstr(err.msg, rgb));
        if (!strstr(err.msg, cases[k].want)) fail_msg("\"%s\" lacks \"%s\"", err.msg, cases[k].want);
        assert_null(strchr(err.msg, '\n'));
    }
}

/* ---- per-vertex depths of a scene object -------------------------------- */

/* Table 1's dermis, blood and organs (seed 002), or three copies of the
 * dermis (`same`), the depths as given. */
static void scene_text(char *out, size_t n, const char *mesh, int same, const char *d0, const char *d1, const char *d2,
                       const char *transform)
{
    const char *dermis = "\"sigma_s\":[2,1,1],\"sigma_a\":[0.6,0.6,0.6],\"g\":0.25";
    snprintf(out, n,
             "{\"objects\":[{\"name\":\"o\",\"mesh\":\"%s\",%s\"material\":{\"preset\":\"skin1\",\"layers\":["
             "{%s,\"depth_mm\":%s},{%s,\"depth_mm\":%s},{%s,\"depth_mm\":%s}]}}]}",
             mesh, transform, dermis, d0, same ? dermis : "\"sigma_s\":[6,3,2],\"sigma_a\":[0.6,0.6,0.6],\"g\":0.4", d1,
             same ? dermis : "\"sigma_s\":[1,1,2],\"sigma_a\":[0.5,0.5,0.5],\"g\":0.8", d2);
}

/* The scene's object placed, and its per-vertex depths (NULL: constant). */
typedef struct placed {
    sss_scene sc;
    sss_mesh world;
    float *depth;
} placed;

static sss_result place(placed *p, const char *json, sss_error *err)
{
    memset(p, 0, sizeof *p);
    write_text(path_of("s.json"), json);
    if (sss_scene_load(path_of("s.json"), &p->sc, err) != SSS_OK) fail_msg("%s", err->msg);
    sss_mesh m;
    if (sss_import_mesh(p->sc.objects[0].mesh, &m, NULL, err) != SSS_OK) fail_msg("%s", err->msg);
    if (sss_scene_object_world(&p->sc.objects[0], &m, &p->world, err) != SSS_OK) fail_msg("%s", err->msg);
    sss_mesh_free(&m);
    return sss_layer_depths_eval(&p->sc, 0, &p->world, &p->depth, &p->sc.objects[0].layers, err);
}

static void unplace(placed *p)
{
    free(p->depth);
    sss_mesh_free(&p->world);
    sss_scene_free(&p->sc);
}

/* Single scattering at vertex v of the placed object, its own stack. */
static void ss_at(const placed *p, const sss_bvh *bvh, uint32_t v, double out[3])
{
    const double light[3] = {0.3, -0.2, 0.93}, view[3] = {-0.25, 0.1, 0.96};
    sss_layer_stack st;
    sss_layer_stack_at(&p->sc.objects[0].layers, p->depth, v, &st);
    sss_error err = {{0}};
    sss_material mat = p->sc.objects[0].material;
    if (sss_ss_mesh_vertex(&p->world, bvh, sss_scene_object_mm_per_world_unit(&p->sc.objects[0]), &mat, &st, 3, v, light,
                           view, NULL, out, &err) != SSS_OK)
        fail_msg("%s", err.msg);
}

/* The plane of sss-genmesh, 40 mm, with its texture coordinates. */
static const char *plane_mesh(void)
{
    const char *p = path_of("plane.ply");
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_plane(&m, 40.0, 40.0, 8, 8, &err), SSS_OK);
    assert_int_equal(sss_export_ply(p, &m, &err), SSS_OK);
    sss_mesh_free(&m);
    return p;
}

/* A map of one value everywhere gives that depth at every vertex, and
 * the same single scattering (bit for bit) as the number; its LAYR depth
 * is the number too. */
static void constantMapEqualsTheNumericDepth(void **state)
{
    (void)state;
    const char *mesh = plane_mesh();
    float ones[16];
    for (int i = 0; i < 16; i++) ones[i] = 1.0f;
    write_map(path_of("one.png"), 4, 4, ones, 16);
    char json[2048];
    placed a, b;
    sss_error err = {{0}};
    scene_text(json, sizeof json, mesh, 0, "0.3", "{\"map\":\"one.png\",\"scale_mm\":0.75}", "3", "");
    assert_int_equal(place(&a, json, &err), SSS_OK);
    scene_text(json, sizeof json, mesh, 0, "0.3", "0.75", "3", "");
    assert_int_equal(place(&b, json, &err), SSS_OK);
    assert_non_null(a.depth);
    assert_null(b.depth); /* numbers only: no per-vertex depths, no LDEP */
    assert_true(a.sc.objects[0].layers.layer[1].depth == 0.75);
    sss_bvh bvh;
    assert_int_equal(sss_bvh_build(a.world.pos, a.world.nv, a.world.tri, a.world.nf, &bvh, &err), SSS_OK);
    for (uint32_t v = 0; v < a.world.nv; v++) {
        assert_true(a.depth[3 * v] == 0.3f && a.depth[3 * v + 1] == 0.75f && a.depth[3 * v + 2] == 3.0f);
        if (v % 7) continue;
        double x[3], y[3];
        ss_at(&a, &bvh, v, x);
        ss_at(&b, &bvh, v, y);
        /* 0.3f is not 0.3: the dermis' depth differs by float rounding */
        for (int c = 0; c < 3; c++) assert_float_equal(x[c], y[c], 1e-7 * y[c]);
        assert_true(x[0] > 0.0);
    }
    sss_bvh_free(&bvh);
    unplace(&a);
    unplace(&b);
}

/* Identical layers give the picture of one layer down to the deepest,
 * whatever the depths above it: a map, a procedural pattern, both. */
static void identicalLayersGiveTheSameWhateverTheDepthMap(void **state)
{
    (void)state;
    const char *mesh = plane_mesh();
    float ramp[64];
    for (int i = 0; i < 64; i++) ramp[i] = (float)((i * 37) % 64) / 63.0f;
    write_map(path_of("m16.png"), 8, 8, ramp, 16);
    char json[2048];
    placed a, one;
    sss_error err = {{0}};
    scene_text(json, sizeof json, mesh, 1, "{\"map\":\"m16.png\",\"scale_mm\":1.2}",
               "{\"procedural\":\"veins\",\"seed\":3,\"scale_mm\":10,\"depth_mm\":[0.2,1.6]}", "2", "");
    assert_int_equal(place(&a, json, &err), SSS_OK);
    scene_text(json, sizeof json, mesh, 1, "2", "2", "2", "");
    assert_int_equal(place(&one, json, &err), SSS_OK);
    sss_bvh bvh;
    assert_int_equal(sss_bvh_build(a.world.pos, a.world.nv, a.world.tri, a.world.nf, &bvh, &err), SSS_OK);
    float lo = INFINITY, hi = 0.0f;
    double worst = 0.0;
    for (uint32_t v = 0; v < a.world.nv; v++) {
        lo = fminf(lo, a.depth[3 * v + 1]);
        hi = fmaxf(hi, a.depth[3 * v + 1]);
        double x[3], y[3];
        ss_at(&a, &bvh, v, x);
        ss_at(&one, &bvh, v, y);
        /* the rim, where the oracle's rays beside K (its focusing,
         * docs/layers.md §5) leave the plane at shallow samples, is left out */
        const float *p = &a.world.pos[3 * v];
        if (fabsf(p[0]) > 19.0f || fabsf(p[1]) > 19.0f) continue;
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(x[c] - y[c]) / y[c]);
    }
    /* the layer crossings move the march's sample points, whose entry
     * points are float ray casts (docs/layers.md §5): a few 10⁻⁹ */
    printf("identical layers, largest relative difference from one layer: %.2g\n", worst);
    assert_true(worst < 1e-7);
    assert_true(hi - lo > 0.3f); /* the depths did vary */
    sss_bvh_free(&bvh);
    unplace(&a);
    unplace(&one);
}

/* A procedural depth lies in [min, max], is the same on every run, and is
 * evaluated in the object's rest frame: rotating and moving the object
 * leaves every vertex's depth as it was (to the world positions' float
 * rounding). A layer below it whose number lies inside the range is
 * raised to it where it is deeper (depths made non-decreasing). */
static void proceduralDepthIsDeterministicAndMovesWithTheObject(void **state)
{
    (void)state;
    const char *mesh = plane_mesh();
    char json[2048];
    placed a, b, c;
    sss_error err = {{0}};
    const char *bumps = "{\"procedural\":\"bumps\",\"seed\":11,\"scale_mm\":6,\"depth_mm\":[0.2,1.0]}";
    scene_text(json, sizeof json, mesh, 0, bumps, "0.6", "3", "");
    assert_int_equal(place(&a, json, &err), SSS_OK);
    assert_int_equal(place(&b, json, &err), SSS_OK);
    scene_text(json, sizeof json, mesh, 0, bumps, "0.6", "3",
               "\"transform\":{\"rotate_deg\":[30,-45,70],\"translate\":[120,-7,33]},");
    assert_int_equal(place(&c, json, &err), SSS_OK);
    assert_memory_equal(a.depth, b.depth, (size_t)a.world.nv * 3 * sizeof(float));
    uint32_t raised = 0, kept = 0;
    float lo = INFINITY, hi = 0.0f;
    for (uint32_t v = 0; v < a.world.nv; v++) {
        const float d0 = a.depth[3 * v], d1 = a.depth[3 * v + 1];
        assert_true(d0 >= 0.2f && d0 <= 1.0f);
        lo = fminf(lo, d0);
        hi = fmaxf(hi, d0);
        assert_true(d1 == fmaxf(d0, 0.6f));
        raised += d0 > 0.6f;
        kept += d0 <= 0.6f;
        for (int k = 0; k < 3; k++) assert_float_equal(c.depth[3 * v + k], a.depth[3 * v + k], 1e-5);
    }
    assert_true(raised > 0 && kept > 0 && hi - lo > 0.2f);
    /* LAYR's depths: each layer's deepest */
    assert_true(a.sc.objects[0].layers.layer[0].depth == hi);
    assert_true(a.sc.objects[0].layers.layer[1].depth == fmaxf(hi, 0.6f));
    unplace(&a);
    unplace(&b);
    unplace(&c);
}

/* Each pattern gives what its field gives: veins and blobs through
 * sss/field.h's kinds, bumps its noise, all mapped onto [min, max]. */
static void patternsAreTheFieldsOnTheRange(void **state)
{
    (void)state;
    sss_depth_spec s;
    memset(&s, 0, sizeof s);
    s.kind = SSS_DEPTH_PROCEDURAL;
    s.seed = 5;
    s.scale_mm = 4.0;
    s.range_mm[0] = 0.5;
    s.range_mm[1] = 2.5;
    const double x[3] = {1.3, -2.2, 0.7};
    sss_field f;
    memset(&f, 0, sizeof f);
    f.seed = 5;
    f.scale_mm = 4.0;
    s.pattern = SSS_DEPTH_VEINS;
    f.kind = SSS_FIELD_VEINS;
    assert_float_equal(sss_depth_procedural(&s, x), 0.5 + 2.0 * sss_field_eval(&f, x), 1e-15);
    s.pattern = SSS_DEPTH_BLOBS;
    f.kind = SSS_FIELD_INCLUSIONS;
    f.thickness_mm = 1.2;
    f.edge_mm = 0.4;
    assert_float_equal(sss_depth_procedural(&s, x), 0.5 + 2.0 * sss_field_eval(&f, x), 1e-15);
    s.pattern = SSS_DEPTH_BUMPS;
    assert_float_equal(sss_depth_procedural(&s, x), 0.5 + 2.0 * sss_field_noise(x, 4.0, 5), 1e-15);
    /* and the monotone rule */
    float d[4] = {0.5f, 0.2f, 0.9f, 0.1f};
    sss_layer_depths_monotone(d, 4);
    assert_true(d[0] == 0.5f && d[1] == 0.5f && d[2] == 0.9f && d[3] == 0.9f);
}

/* A map on a mesh without texture coordinates, and a map that is missing:
 * one line naming the layer and the files. */
static void mapOnMeshWithoutTexcoordsIsRefused(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_box(&m, 10, 10, 10, 2, 0, &err), SSS_OK);
    const char *box = path_of("box.ply");
    assert_int_equal(sss_export_ply(box, &m, &err), SSS_OK);
    sss_mesh_free(&m);
    write_map(path_of("one.png"), 1, 1, (const float[]){1.0f}, 8);
    char json[2048];
    placed a;
    scene_text(json, sizeof json, box, 0, "0.3", "{\"map\":\"one.png\",\"scale_mm\":1}", "3", "");
    assert_int_equal(place(&a, json, &err), SSS_ERR_MESH);
    assert_non_null(strstr(err.msg, "material/layers/1/depth_mm: the depth map"));
    assert_non_null(strstr(err.msg, "one.png"));
    assert_non_null(strstr(err.msg, box));
    assert_null(a.depth);
    unplace(&a);
    scene_text(json, sizeof json, plane_mesh(), 0, "0.3", "0.5", "{\"map\":\"nothere.png\",\"scale_mm\":4}", "");
    assert_int_equal(place(&a, json, &err), SSS_ERR_IO);
    assert_non_null(strstr(err.msg, "material/layers/2/depth_mm/map: "));
    assert_non_null(strstr(err.msg, "nothere.png: cannot open the depth map"));
    assert_null(strchr(err.msg, '\n'));
    unplace(&a);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(mapsReadBackAndSampleAtTexelCentres),
        cmocka_unit_test(badMapsAreRefusedNamingTheFile),
        cmocka_unit_test(constantMapEqualsTheNumericDepth),
        cmocka_unit_test(identicalLayersGiveTheSameWhateverTheDepthMap),
        cmocka_unit_test(proceduralDepthIsDeterministicAndMovesWithTheObject),
        cmocka_unit_test(patternsAreTheFieldsOnTheRange),
        cmocka_unit_test(mapOnMeshWithoutTexcoordsIsRefused),
    };
    return cmocka_run_group_tests(tests, setup_dir, teardown_dir);
}
