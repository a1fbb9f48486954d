#define _POSIX_C_SOURCE 200809L
/* test_api.c: the runtime API an engine embeds (sss/api.h; docs/api.md).
 * Files of every storage form are baked here with the bake library, then
 * opened through the API from memory and from a path:
 *  - without near terms, sss_asset_decode gives sss_decode_all's bytes for
 *    every storage form (float, lloyd8, SH with each code kind, references
 *    with and without an SH delta), lights of any length;
 *  - with run-time near terms (own term, 1-ring, a radius with the hat
 *    weights, references), it gives precompute's sss_reconstruct_eval to
 *    the bit when handed the same visibility, and its own rays (sss/bvh.h,
 *    the viewer's) disagree with the bake's Embree rays at few vertices
 *    (counted and bounded);
 *  - a range is the slice of the whole, memory equals path, several OpenMP
 *    threads decoding one asset give the serial bytes;
 *  - a scene bake's static light, point light and environment decode as
 *    effects.c does;
 *  - bad arguments and bad bytes give errors naming the argument, no
 *    crash. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "genmesh.h"
#include "sss/api.h"
#include "sss/bake.h"
#include "sss/bake_scene.h"
#include "sss/compress.h"
#include "sss/decode.h"
#include "sss/effects.h"
#include "sss/import.h"
#include "sss/nearterms.h"
#include "sss/probe.h"
#include "sss/reconstruct.h"
#include "test_util.h"

static char tmpdir[256];

/* One test file: its bytes, the reader's decoding of them, and the asset
 * opened from memory and from a path. */
typedef struct tfile {
    const char *label;
    uint8_t *bytes;
    size_t len;
    sss_bake_file f;
    sss_asset *mem, *path;
} tfile;

enum { F_FLOAT, F_LLOYD8, F_SH_LIN8, F_SH_LLOYD8, F_SH_LLOYD4, F_REFS, F_REFS_ONLY, /* no near terms */
       F_OWN, F_RING, F_RADIUS, F_REFS_NEAR, F_SCENE, F_VECTOR, NFILES };
static tfile g[NFILES];
#define FIRST_NEAR F_OWN

static void take(tfile *t, const char *label, sss_bake_file *baked)
{
    sss_error err = {{0}};
    t->label = label;
    if (sss_file_encode(baked, &t->bytes, &t->len, &err) != SSS_OK) fail_msg("%s: encode: %s", label, err.msg);
    if (sss_file_decode(t->bytes, t->len, label, &t->f, &err) != SSS_OK) fail_msg("%s: decode: %s", label, err.msg);
    if (sss_asset_open_memory(t->bytes, t->len, label, &t->mem, &err) != SSS_OK)
        fail_msg("%s: open_memory: %s", label, err.msg);
    char path[512];
    snprintf(path, sizeof path, "%s/%s.sss", tmpdir, label);
    FILE *fp = fopen(path, "wb");
    if (!fp || fwrite(t->bytes, 1, t->len, fp) != t->len || fclose(fp) != 0) fail_msg("%s: cannot write", path);
    if (sss_asset_open(path, &t->path, &err) != SSS_OK) fail_msg("%s: open: %s", label, err.msg);
}

static void bake_mesh(const sss_mesh *m, const char *name, sss_quant quant, uint32_t near, uint32_t rings,
                      double radius, uint32_t weights, sss_bake_file *out)
{
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset("skin1", &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = 100;
    opt.quant = quant;
    opt.threads = 2;
    opt.near_terms = near;
    opt.near_rings = rings;
    opt.near_radius_mm = radius;
    opt.weights = weights;
    if (sss_bake(m, name, &mat, &opt, out, NULL, &err) != SSS_OK) fail_msg("bake %s: %s", name, err.msg);
}

static void compress(const sss_bake_file *in, uint32_t order, double fraction, uint32_t kind, sss_bake_file *out)
{
    sss_compress_opts o;
    sss_compress_opts_default(&o);
    o.order = order;
    o.fraction = fraction;
    o.sh_kind = kind;
    sss_error err = {{0}};
    if (sss_compress(in, &o, out, &err) != SSS_OK) fail_msg("compress: %s", err.msg);
}

static void write_file(const char *name, const char *text)
{
    char p[512];
    snprintf(p, sizeof p, "%s/%s", tmpdir, name);
    FILE *fp = fopen(p, "w");
    if (!fp || fputs(text, fp) < 0 || fclose(fp) != 0) fail_msg("cannot write %s", p);
}

/* A scene bake holding a static directional light (QDIR), a moving point
 * light (PSHL) and an environment (ENVT) on one sphere. */
static void bake_scene(sss_bake_file *out)
{
    sss_error err = {{0}};
    sss_mesh m;
    char p[512];
    if (sss_gen_sphere(&m, 1.0, 2, &err) != SSS_OK) fail_msg("%s", err.msg);
    snprintf(p, sizeof p, "%s/sphere.ply", tmpdir);
    if (sss_export_ply(p, &m, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_mesh_free(&m);
    sss_probe pr = {16, 8, NULL};
    pr.rgb = malloc(3 * (size_t)pr.w * pr.h * sizeof(float));
    for (uint32_t y = 0; y < pr.h; y++)
        for (uint32_t x = 0; x < pr.w; x++) {
            double d[3], dw;
            sss_probe_pixel_dir(pr.w, pr.h, x, y, d, &dw);
            for (int c = 0; c < 3; c++)
                pr.rgb[3 * ((size_t)y * pr.w + x) + c] = (float)((1 + 0.6 * d[2] + 0.3 * d[0]) * (1.0 - 0.2 * c));
        }
    snprintf(p, sizeof p, "%s/probe.exr", tmpdir);
    if (sss_probe_write(p, &pr, &err) != SSS_OK) fail_msg("%s", err.msg);
    free(pr.rgb);
    write_file("scene.json", "{\"objects\":[{\"mesh\":\"sphere.ply\",\"material\":\"marble\",\"mm_per_unit\":5}],"
                             "\"lights\":[{\"type\":\"directional\",\"direction\":[0.4,0.5,0.7]},"
                             "{\"type\":\"point\",\"position\":[0,0,3],\"moving\":true},"
                             "{\"type\":\"environment\",\"probe\":\"probe.exr\"}],"
                             "\"bake\":{\"dirs\":100,\"shells\":4,\"sh_order\":2}}");
    snprintf(p, sizeof p, "%s/scene.json", tmpdir);
    sss_scene sc;
    if (sss_scene_load(p, &sc, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_mesh world;
    if (sss_import_mesh(sc.objects[0].mesh, &m, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (sss_scene_object_world(&sc.objects[0], &m, &world, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_mesh_free(&m);
    sss_plan plan;
    if (sss_plan_scene(&sc, &world, &plan, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    if (sss_bake_object(&sc, &plan, &world, 0, &o, out, NULL, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_plan_free(&plan);
    sss_mesh_free(&world);
    sss_scene_free(&sc);
}

static int setup(void **state)
{
    (void)state;
    snprintf(tmpdir, sizeof tmpdir, "/tmp/sss_test_api_XXXXXX");
    if (!mkdtemp(tmpdir)) return -1;
    sss_error err = {{0}};
    sss_mesh blob, torus;
    if (sss_gen_blob(&blob, 1.0, 3, &err) != SSS_OK) return -1;
    /* the torus's inner side shadows itself (test_near_terms.c) */
    if (sss_gen_torus(&torus, 1.0, 0.45, 48, 24, &err) != SSS_OK) return -1;
    sss_bake_file fl, l8, c, own, ring, rad;
    bake_mesh(&blob, "blob", SSS_QUANT_FLOAT, 0, 0, 0.0, SSS_WEIGHTS_POINT, &fl);
    bake_mesh(&blob, "blob", SSS_QUANT_LLOYD8, 0, 0, 0.0, SSS_WEIGHTS_POINT, &l8);
    take(&g[F_FLOAT], "float", &fl);
    take(&g[F_LLOYD8], "lloyd8", &l8);
    compress(&fl, 3, 0.0, SSS_SHQ_LINEAR8, &c), take(&g[F_SH_LIN8], "sh_linear8", &c), sss_file_free(&c);
    compress(&fl, 4, 0.0, SSS_SHQ_LLOYD8, &c), take(&g[F_SH_LLOYD8], "sh_lloyd8", &c), sss_file_free(&c);
    compress(&fl, 3, 0.0, SSS_SHQ_LLOYD4, &c), take(&g[F_SH_LLOYD4], "sh_lloyd4", &c), sss_file_free(&c);
    compress(&fl, 2, 0.05, SSS_SHQ_LINEAR8, &c), take(&g[F_REFS], "refs", &c), sss_file_free(&c);
    compress(&fl, 0, 0.05, SSS_SHQ_LINEAR8, &c), take(&g[F_REFS_ONLY], "refs_only", &c), sss_file_free(&c);
    bake_mesh(&torus, "torus", SSS_QUANT_FLOAT, SSS_NEAR_TERMS_RUNTIME, 0, 0.0, SSS_WEIGHTS_POINT, &own);
    bake_mesh(&torus, "torus", SSS_QUANT_LLOYD8, SSS_NEAR_TERMS_RUNTIME, 1, 0.0, SSS_WEIGHTS_POINT, &ring);
    bake_mesh(&torus, "torus", SSS_QUANT_FLOAT, SSS_NEAR_TERMS_RUNTIME, 0, 5.0, SSS_WEIGHTS_HAT, &rad);
    take(&g[F_OWN], "near_own", &own);
    take(&g[F_RING], "near_ring", &ring);
    take(&g[F_RADIUS], "near_radius", &rad);
    compress(&own, 2, 0.05, SSS_SHQ_LLOYD8, &c), take(&g[F_REFS_NEAR], "near_refs", &c), sss_file_free(&c);
    bake_scene(&c), take(&g[F_SCENE], "scene", &c), sss_file_free(&c);
    {   /* the vector integrals Q beside float rows (sss-bake --vector) */
        sss_material mat;
        sss_bake_options opt;
        memset(&opt, 0, sizeof opt);
        opt.mm_per_unit = 20.0, opt.n_dirs = 100, opt.quant = SSS_QUANT_FLOAT, opt.threads = 2, opt.vector = 1;
        if (sss_material_preset("skin1", &mat, &err) != SSS_OK ||
            sss_bake(&blob, "blob", &mat, &opt, &c, NULL, &err) != SSS_OK)
            fail_msg("bake vector: %s", err.msg);
        take(&g[F_VECTOR], "vector", &c), sss_file_free(&c);
    }
    sss_file_free(&fl), sss_file_free(&l8), sss_file_free(&own), sss_file_free(&ring), sss_file_free(&rad);
    sss_mesh_free(&blob);
    sss_mesh_free(&torus);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    for (int i = 0; i < NFILES; i++) {
        sss_asset_close(g[i].mem);
        sss_asset_close(g[i].path);
        sss_file_free(&g[i].f);
        free(g[i].bytes);
    }
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
    return system(cmd) == 0 ? 0 : -1;
}

/* Lights of several lengths (the API normalises), random directions plus
 * the axes and the stored samples' neighbourhood. */
#define NLIGHTS 24
static void lights(double L[NLIGHTS][3])
{
    uint64_t s = 12345;
    for (int i = 0; i < NLIGHTS; i++) {
        test_random_dir(&s, L[i]);
        const double scale = i % 3 == 0 ? 1.0 : i % 3 == 1 ? 3.7 : 0.02;
        for (int k = 0; k < 3; k++) L[i][k] *= scale;
    }
    L[0][0] = 0, L[0][1] = 0, L[0][2] = 1;
    L[1][0] = -1, L[1][1] = 0, L[1][2] = 0;
}

static float *decode_all_api(const tfile *t, const sss_asset *a, const double light[3], const uint8_t *lit)
{
    const size_t n = (size_t)t->f.mesh.nv * t->f.channels;
    float *out = malloc(n * sizeof *out);
    sss_error err = {{0}};
    if (sss_asset_decode(a, light, 0, t->f.mesh.nv, lit, out, &err) != SSS_OK) fail_msg("%s: %s", t->label, err.msg);
    return out;
}

static void decodesEveryStorageFormBitIdentically(void **state)
{
    (void)state;
    double L[NLIGHTS][3];
    lights(L);
    const sss_quant want[FIRST_NEAR] = {SSS_QUANT_FLOAT, SSS_QUANT_LLOYD8, SSS_QUANT_SH, SSS_QUANT_SH, SSS_QUANT_SH,
                                        SSS_QUANT_REFS, SSS_QUANT_REFS};
    for (int i = 0; i < FIRST_NEAR; i++) {
        const tfile *t = &g[i];
        assert_int_equal(t->f.quant, want[i]);
        assert_int_equal(t->f.near_terms, 0);
        const size_t n = (size_t)t->f.mesh.nv * t->f.channels;
        float *ref = malloc(n * sizeof *ref);
        double maxq = 0;
        for (int l = 0; l < NLIGHTS; l++) {
            sss_decode_all(&t->f, L[l], ref);
            float *q = decode_all_api(t, t->mem, L[l], NULL);
            assert_memory_equal(q, ref, n * sizeof *q);
            for (size_t e = 0; e < n; e++) maxq = fmax(maxq, q[e]);
            free(q);
        }
        assert_true(maxq > 0.01); /* the comparisons compared light, not zeros */
        free(ref);
    }
    /* the SH kinds and orders are those asked for */
    assert_int_equal(g[F_SH_LIN8].f.sh.kind, SSS_SHQ_LINEAR8);
    assert_int_equal(g[F_SH_LLOYD8].f.sh.kind, SSS_SHQ_LLOYD8);
    assert_int_equal(g[F_SH_LLOYD4].f.sh.kind, SSS_SHQ_LLOYD4);
    assert_int_equal(g[F_REFS_ONLY].f.sh.order, 0);
    sss_asset_desc d;
    assert_int_equal(sss_asset_info(g[F_SH_LLOYD4].mem, &d, NULL), SSS_OK);
    assert_string_equal(d.quant_name, "sh");
    assert_string_equal(d.sh_kind_name, "lloyd4");
    assert_int_equal(d.sh_order, 3);
    assert_int_equal(sss_asset_info(g[F_REFS_ONLY].mem, &d, NULL), SSS_OK);
    assert_string_equal(d.quant_name, "refs");
    assert_string_equal(d.sh_kind_name, "");
}

/* A file with Q decodes Q·ω (sss_decode_vector_range's bits, what the
 * viewer draws), not its q rows, which differ between the samples. */
static void vectorFileDecodesQ(void **state)
{
    (void)state;
    const tfile *t = &g[F_VECTOR];
    assert_non_null(t->f.qvec);
    double L[NLIGHTS][3];
    lights(L);
    const size_t n = (size_t)t->f.mesh.nv * t->f.channels;
    float *want = malloc(n * sizeof *want), *rows = malloc(n * sizeof *rows);
    assert_non_null(want);
    assert_non_null(rows);
    double differ = 0.0, maxq = 0.0;
    for (int l = 0; l < NLIGHTS; l++) {
        sss_decode_vector_range(&t->f, L[l], SSS_INTERP_TRIANGLE, 0, t->f.mesh.nv, want);
        sss_decode_all(&t->f, L[l], rows);
        float *q = decode_all_api(t, t->path, L[l], NULL);
        assert_memory_equal(q, want, n * sizeof *q);
        for (size_t e = 0; e < n; e++) differ = fmax(differ, fabs((double)q[e] - rows[e])), maxq = fmax(maxq, q[e]);
        free(q);
    }
    print_message("vector file: Q against its q rows, largest difference %.3g (max %.3g)\n", differ, maxq);
    assert_true(maxq > 0.01 && differ > 0.0);
    free(want);
    free(rows);
}

/* The unit light exactly as reconstruct.c forms it. */
static void unit_of(const double l[3], double d[3])
{
    const double n = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    for (int k = 0; k < 3; k++) d[k] = l[k] / n;
}

static void nearTermsEqualPrecomputeReconstruction(void **state)
{
    (void)state;
    double L[NLIGHTS][3];
    lights(L);
    uint64_t pairs = 0, lit_differ = 0, lit_total = 0;
    uint64_t values = 0, values_differ = 0;
    double worst = 0.0;
    for (int i = FIRST_NEAR; i < F_SCENE; i++) {
        const tfile *t = &g[i];
        assert_int_equal(t->f.near_terms, SSS_NEAR_TERMS_RUNTIME);
        const uint32_t nv = t->f.mesh.nv;
        const size_t n = (size_t)nv * t->f.channels;
        sss_reconstruct *r;
        sss_error err = {{0}};
        if (sss_reconstruct_create(&t->f, &r, &err) != SSS_OK) fail_msg("%s", err.msg);
        float *ref = malloc(n * sizeof *ref), *rows = malloc(n * sizeof *rows);
        uint8_t *lb = malloc(nv), *la = malloc(nv);
        for (int l = 0; l < NLIGHTS; l++) {
            double d[3];
            unit_of(L[l], d);
            sss_reconstruct_eval(r, L[l], SSS_INTERP_TRIANGLE, ref);
            /* the bake's own visibility (Embree), as reconstruct_eval forms it */
            sss_reconstruct_near_lit(r, d, lb);
            /* handed that visibility the API adds the very same sums */
            float *q = decode_all_api(t, t->mem, L[l], lb);
            assert_memory_equal(q, ref, n * sizeof *q);
            free(q);
            /* its own rays: the viewer's BVH test against Embree's */
            assert_int_equal(sss_asset_visibility(t->mem, L[l], la, &err), SSS_OK);
            uint32_t nd = 0, nlit = 0;
            for (uint32_t v = 0; v < nv; v++) nd += la[v] != lb[v], nlit += lb[v] != 0;
            lit_differ += nd, lit_total += nv, pairs++;
            assert_true(nlit > 0 && nlit < nv); /* a real shadow test: some lit, some not */
            q = decode_all_api(t, t->mem, L[l], NULL);
            /* the rows alone are smaller: the near terms were added */
            sss_reconstruct_eval_rows(r, L[l], SSS_INTERP_TRIANGLE, rows);
            double added = 0;
            for (size_t e = 0; e < n; e++) added += (double)q[e] - rows[e];
            assert_true(added > 0);
            for (size_t e = 0; e < n; e++) {
                values++;
                if (q[e] != ref[e]) {
                    values_differ++;
                    worst = fmax(worst, fabs((double)q[e] - ref[e]) / fmax(1e-30, fabs((double)ref[e])));
                }
            }
            if (nd == 0) assert_memory_equal(q, ref, n * sizeof *q);
            free(q);
        }
        free(ref), free(rows), free(lb), free(la);
        sss_reconstruct_destroy(r);
    }
    print_message("near terms: the API's rays and the bake's Embree rays disagree at %llu of %llu vertex visibilities "
                  "(%llu lights x files); %llu of %llu values differ from sss_reconstruct_eval, largest relative "
                  "difference %.3g\n",
                  (unsigned long long)lit_differ, (unsigned long long)lit_total, (unsigned long long)pairs,
                  (unsigned long long)values_differ, (unsigned long long)values, worst);
    /* the viewer's test repeats Embree's arithmetic (bvh.c): at most a
     * grazing vertex in ten thousand may go the other way */
    assert_true(lit_differ * 10000 <= lit_total);
}

static void rangeIsSliceOfWhole(void **state)
{
    (void)state;
    double L[NLIGHTS][3];
    lights(L);
    uint64_t s = 99;
    for (int i = 0; i < NFILES; i++) {
        const tfile *t = &g[i];
        if (i == F_SCENE) continue; /* no direction set: its effects are tested below */
        const uint32_t nv = t->f.mesh.nv, C = t->f.channels;
        for (int l = 0; l < 4; l++) {
            float *whole = decode_all_api(t, t->mem, L[l], NULL);
            for (int k = 0; k < 6; k++) {
                uint32_t first = (uint32_t)(test_urand(&s) * nv), count = 1 + (uint32_t)(test_urand(&s) * (nv - first));
                if (k == 0) first = 0, count = 1;
                if (k == 1) first = nv - 1, count = 1;
                if (first + count > nv) count = nv - first;
                float *part = malloc((size_t)count * C * sizeof *part);
                assert_int_equal(sss_asset_decode(t->path, L[l], first, count, NULL, part, NULL), SSS_OK);
                assert_memory_equal(part, whole + (size_t)first * C, (size_t)count * C * sizeof *part);
                free(part);
            }
            free(whole);
        }
    }
}

static void memoryEqualsPath(void **state)
{
    (void)state;
    double L[NLIGHTS][3];
    lights(L);
    for (int i = 0; i < NFILES; i++) {
        const tfile *t = &g[i];
        sss_asset_desc a, b;
        assert_int_equal(sss_asset_info(t->mem, &a, NULL), SSS_OK);
        assert_int_equal(sss_asset_info(t->path, &b, NULL), SSS_OK);
        assert_memory_equal(&a, &b, sizeof a);
        assert_int_equal(a.nv, t->f.mesh.nv);
        assert_int_equal(a.file_bytes, t->len);
        assert_true(a.integral_bytes_per_vertex == sss_file_integral_bytes_per_vertex(&t->f));
        const size_t nv = a.nv, nf = a.nf;
        assert_memory_equal(sss_asset_positions(t->mem), sss_asset_positions(t->path), nv * 3 * sizeof(float));
        assert_memory_equal(sss_asset_normals(t->mem), sss_asset_normals(t->path), nv * 3 * sizeof(float));
        assert_memory_equal(sss_asset_triangles(t->mem), sss_asset_triangles(t->path), nf * 3 * sizeof(uint32_t));
        assert_memory_equal(sss_asset_positions(t->mem), t->f.mesh.pos, nv * 3 * sizeof(float));
        assert_string_equal(sss_asset_params_json(t->mem), sss_asset_params_json(t->path));
        assert_string_equal(sss_asset_name(t->mem), t->label);
        assert_non_null(strstr(sss_asset_name(t->path), t->label));
        if (!a.has_dir_set) continue;
        for (int l = 0; l < 4; l++) {
            float *p = decode_all_api(t, t->path, L[l], NULL), *m = decode_all_api(t, t->mem, L[l], NULL);
            assert_memory_equal(p, m, nv * a.channels * sizeof *p);
            free(p), free(m);
        }
    }
    /* the info of a file with near terms and of the scene */
    sss_asset_desc d;
    assert_int_equal(sss_asset_info(g[F_RING].mem, &d, NULL), SSS_OK);
    assert_int_equal(d.near_terms, 1);
    assert_int_equal(d.near_rings, 1);
    assert_string_equal(d.quant_name, "lloyd8");
    assert_int_equal(d.channels, 3);
    assert_true(d.eta == g[F_RING].f.material.eta && d.sigma_a[2] == g[F_RING].f.material.sigma_a[2]);
    assert_true(d.mm_per_unit == 20.0);
    assert_true(d.g == 0.0); /* an isotropic file: no PHAS, no layers */
    assert_int_equal(d.nlayers, 0);
    assert_int_equal(d.layer_depths, 0);
    {
        /* the same file with a phase, two layers and their per-vertex depths
         * (sections PHAS, LAYR, LDEP) */
        sss_bake_file f = g[F_RING].f;
        f.material.g = 0.4;
        f.layers.n = 2;
        f.layers.phase = SSS_PHASE_HG;
        for (uint32_t k = 0; k < 2; k++)
            f.layers.layer[k] = (sss_layer){{2, 1, 1}, {2.6, 1.6, 1.6}, 0.25, 0.3 * (k + 1)};
        float *ld = calloc((size_t)f.mesh.nv * 2, sizeof(float));
        assert_non_null(ld);
        for (uint32_t v = 0; v < f.mesh.nv; v++) ld[2 * v] = 0.1f, ld[2 * v + 1] = 0.6f;
        f.layer_depth = ld;
        uint8_t *buf = NULL;
        size_t len = 0;
        sss_error err = {{0}};
        assert_int_equal(sss_file_encode(&f, &buf, &len, &err), SSS_OK);
        sss_asset *a = NULL;
        assert_int_equal(sss_asset_open_memory(buf, len, "phase.sss", &a, &err), SSS_OK);
        assert_int_equal(sss_asset_info(a, &d, NULL), SSS_OK);
        assert_true(d.g == 0.4);
        assert_int_equal(d.nlayers, 2);
        assert_int_equal(d.layer_depths, 1);
        assert_int_equal(d.version_minor, 9);
        sss_asset_close(a);
        free(buf);
        free(ld);
    }
    assert_int_equal(sss_asset_info(g[F_RADIUS].mem, &d, NULL), SSS_OK);
    assert_true(d.near_radius_mm > 0.0);
    assert_int_equal(sss_asset_info(g[F_SCENE].mem, &d, NULL), SSS_OK);
    assert_int_equal(d.effects & (SSS_FX_DIR_EXACT | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH),
                     SSS_FX_DIR_EXACT | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH);
    assert_int_equal(d.nexact, 1);
    assert_int_equal(d.nshells, 4);
    assert_int_equal(d.env_order, 2);
}

static void concurrentDecodesEqualSerial(void **state)
{
    (void)state;
    double L[NLIGHTS][3];
    lights(L);
    const int files[3] = {F_REFS, F_RING, F_REFS_NEAR};
    for (int fi = 0; fi < 3; fi++) {
        const tfile *t = &g[files[fi]];
        const size_t n = (size_t)t->f.mesh.nv * t->f.channels;
        float *serial = malloc(NLIGHTS * n * sizeof *serial), *par = malloc(NLIGHTS * n * sizeof *par);
        for (int l = 0; l < NLIGHTS; l++) {
            float *q = decode_all_api(t, t->mem, L[l], NULL);
            memcpy(serial + l * n, q, n * sizeof *q);
            free(q);
        }
        int failures = 0, threads = 0;
        /* several threads at once on one asset, each light on some thread */
#pragma omp parallel num_threads(4) reduction(+ : failures)
        {
#pragma omp single
            threads = omp_get_num_threads();
#pragma omp for schedule(dynamic, 1)
            for (int l = 0; l < NLIGHTS; l++)
                failures += sss_asset_decode(t->mem, L[l], 0, t->f.mesh.nv, NULL, par + l * n, NULL) != SSS_OK;
        }
        assert_int_equal(failures, 0);
        assert_int_equal(threads, 4);
        assert_memory_equal(par, serial, NLIGHTS * n * sizeof *par);
        free(serial), free(par);
    }
}

static void sceneEffectsDecodeAsEffectsC(void **state)
{
    (void)state;
    const tfile *t = &g[F_SCENE];
    const uint32_t nv = t->f.mesh.nv, C = t->f.channels;
    sss_error err = {{0}};
    float *ref = malloc((size_t)nv * 3 * sizeof *ref), *q = malloc((size_t)nv * 3 * sizeof *q);
    /* static light */
    double dir[3];
    assert_int_equal(sss_asset_exact_direction(t->mem, 0, dir, &err), SSS_OK);
    assert_memory_equal(dir, t->f.fx.exact_dir, sizeof dir);
    assert_int_equal(sss_asset_decode_exact(t->mem, 0, 0, nv, q, &err), SSS_OK);
    assert_memory_equal(q, sss_fx_exact(&t->f, 0), (size_t)nv * C * sizeof *q);
    assert_int_equal(sss_asset_decode_exact(t->mem, 0, 5, 7, q, &err), SSS_OK);
    assert_memory_equal(q, sss_fx_exact(&t->f, 0) + 5 * C, 7 * C * sizeof *q);
    /* point light at several distances, inside the first shell too */
    const double P[4][3] = {{0, 0, 3}, {1.2, -0.4, 0.9}, {0.1, 0.2, 0.05}, {-4, 2, 1}};
    for (int p = 0; p < 4; p++) {
        sss_fx_point(&t->f, P[p], ref);
        assert_int_equal(sss_asset_decode_point(t->mem, P[p], 0, nv, q, &err), SSS_OK);
        assert_memory_equal(q, ref, (size_t)nv * C * sizeof *q);
        assert_int_equal(sss_asset_decode_point(t->path, P[p], 10, nv - 10, q, &err), SSS_OK);
        assert_memory_equal(q, ref + 10 * C, (size_t)(nv - 10) * C * sizeof *q);
        double m = 0;
        for (size_t e = 0; e < (size_t)nv * C; e++) m = fmax(m, ref[e]);
        assert_true(m > 0);
    }
    /* environment: the stored probe and another */
    const uint32_t K = t->f.fx.env_order * t->f.fx.env_order;
    float probe[3 * 64];
    for (uint32_t i = 0; i < 3 * K; i++) probe[i] = (float)(0.5 + 0.1 * i);
    for (int pass = 0; pass < 2; pass++) {
        const float *pr = pass ? probe : NULL;
        sss_fx_env(&t->f, pr, ref);
        assert_int_equal(sss_asset_decode_env(t->mem, pr, 0, nv, q, &err), SSS_OK);
        assert_memory_equal(q, ref, (size_t)nv * 3 * sizeof *q);
        assert_int_equal(sss_asset_decode_env(t->mem, pr, nv / 2, nv - nv / 2, q, &err), SSS_OK);
        assert_memory_equal(q, ref + (size_t)(nv / 2) * 3, (size_t)(nv - nv / 2) * 3 * sizeof *q);
    }
    free(ref), free(q);
}

/* r is the result, and err names `want`. */
static void expect(sss_result r, sss_result code, const sss_error *err, const char *want)
{
    if (r != code || !strstr(err->msg, want))
        fail_msg("got %d '%s', expected %d naming '%s'", (int)r, err->msg, (int)code, want);
}

static void badArgumentsGiveErrors(void **state)
{
    (void)state;
    sss_error err = {{0}};
    const tfile *t = &g[F_OWN];
    const sss_asset *a = t->mem;
    const uint32_t nv = t->f.mesh.nv;
    float *out = malloc((size_t)nv * 3 * sizeof *out);
    uint8_t *lit = malloc(nv);
    const double light[3] = {0, 0, 1}, zero[3] = {0, 0, 0}, nan3[3] = {NAN, 0, 1}, inf3[3] = {INFINITY, 0, 0};
    sss_asset *o = (sss_asset *)1;
    expect(sss_asset_open(NULL, &o, &err), SSS_ERR_ARG, &err, "path is NULL");
    assert_null(o);
    expect(sss_asset_open("", &o, &err), SSS_ERR_ARG, &err, "path is empty");
    expect(sss_asset_open("x.sss", NULL, &err), SSS_ERR_ARG, &err, "out is NULL");
    char missing[512];
    snprintf(missing, sizeof missing, "%s/missing.sss", tmpdir);
    expect(sss_asset_open(missing, &o, &err), SSS_ERR_IO, &err, "missing.sss");
    expect(sss_asset_open(tmpdir, &o, &err), SSS_ERR_IO, &err, tmpdir); /* a directory */
    assert_null(o);
    expect(sss_asset_open_memory(NULL, 10, "m.sss", &o, &err), SSS_ERR_ARG, &err, "m.sss: sss_asset_open_memory: buf");
    expect(sss_asset_open_memory(t->bytes, 0, "m.sss", &o, &err), SSS_ERR_ARG, &err, "len is 0");
    expect(sss_asset_open_memory(t->bytes, t->len, NULL, NULL, &err), SSS_ERR_ARG, &err, "<memory>");
    /* damaged bytes: every truncation in steps, and flipped bytes */
    for (size_t len = 1; len < t->len; len += 1 + len / 7) {
        assert_int_not_equal(sss_asset_open_memory(t->bytes, len, "cut.sss", &o, &err), SSS_OK);
        assert_null(o);
        assert_non_null(strstr(err.msg, "cut.sss"));
    }
    uint8_t *bad = malloc(t->len);
    uint64_t s = 7;
    for (int k = 0; k < 64; k++) {
        memcpy(bad, t->bytes, t->len);
        bad[(size_t)(test_urand(&s) * t->len)] ^= (uint8_t)(1 + test_urand(&s) * 255);
        if (sss_asset_open_memory(bad, t->len, "flip.sss", &o, &err) == SSS_OK) sss_asset_close(o);
        else assert_non_null(strstr(err.msg, "flip.sss"));
    }
    free(bad);
    /* decode */
    expect(sss_asset_decode(NULL, light, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "asset is NULL");
    expect(sss_asset_decode(a, NULL, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "light is NULL");
    expect(sss_asset_decode(a, zero, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "light (0, 0, 0) is zero");
    expect(sss_asset_decode(a, nan3, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "not finite");
    expect(sss_asset_decode(a, inf3, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "not finite");
    expect(sss_asset_decode(a, light, 0, 1, NULL, NULL, &err), SSS_ERR_ARG, &err, "out is NULL");
    expect(sss_asset_decode(a, light, 0, 0, NULL, out, &err), SSS_ERR_ARG, &err, "near_own: sss_asset_decode: count is 0");
    expect(sss_asset_decode(a, light, nv, 1, NULL, out, &err), SSS_ERR_ARG, &err, "beyond the mesh");
    expect(sss_asset_decode(a, light, 1, nv, NULL, out, &err), SSS_ERR_ARG, &err, "beyond the mesh");
    expect(sss_asset_decode(a, light, UINT32_MAX, UINT32_MAX, NULL, out, &err), SSS_ERR_ARG, &err, "beyond the mesh");
    expect(sss_asset_decode(g[F_SCENE].mem, light, 0, 1, NULL, out, &err), SSS_ERR_ARG, &err, "no direction set");
    /* visibility */
    expect(sss_asset_visibility(g[F_FLOAT].mem, light, lit, &err), SSS_ERR_ARG, &err, "float: sss_asset_visibility: the file has no run-time near terms");
    expect(sss_asset_visibility(a, light, NULL, &err), SSS_ERR_ARG, &err, "lit is NULL");
    expect(sss_asset_visibility(a, zero, lit, &err), SSS_ERR_ARG, &err, "zero or not finite");
    /* effects the file does not hold, indices beyond those it does */
    double dir[3];
    expect(sss_asset_exact_direction(a, 0, dir, &err), SSS_ERR_ARG, &err, "no static directional lights (section QDIR)");
    expect(sss_asset_decode_exact(a, 0, 0, 1, out, &err), SSS_ERR_ARG, &err, "section QDIR");
    expect(sss_asset_decode_point(a, light, 0, 1, out, &err), SSS_ERR_ARG, &err, "no point-light shells (section PSHL)");
    expect(sss_asset_decode_env(a, NULL, 0, 1, out, &err), SSS_ERR_ARG, &err, "no environment transfer (section ENVT)");
    const sss_asset *sc = g[F_SCENE].mem;
    expect(sss_asset_exact_direction(sc, 1, dir, &err), SSS_ERR_ARG, &err, "index 1 beyond the file's 1");
    expect(sss_asset_exact_direction(sc, 0, NULL, &err), SSS_ERR_ARG, &err, "dir is NULL");
    expect(sss_asset_decode_exact(sc, 0, 0, g[F_SCENE].f.mesh.nv + 1, out, &err), SSS_ERR_ARG, &err, "beyond the mesh");
    expect(sss_asset_decode_point(sc, NULL, 0, 1, out, &err), SSS_ERR_ARG, &err, "position is NULL");
    expect(sss_asset_decode_point(sc, nan3, 0, 1, out, &err), SSS_ERR_ARG, &err, "not finite");
    expect(sss_asset_decode_env(sc, NULL, 0, 1, NULL, &err), SSS_ERR_ARG, &err, "out is NULL");
    /* info and accessors */
    sss_asset_desc d;
    expect(sss_asset_info(NULL, &d, &err), SSS_ERR_ARG, &err, "asset is NULL");
    expect(sss_asset_info(a, NULL, &err), SSS_ERR_ARG, &err, "info is NULL");
    assert_null(sss_asset_positions(NULL));
    assert_null(sss_asset_file(NULL));
    assert_ptr_equal(sss_asset_file(a)->mesh.pos, sss_asset_positions(a));
    sss_asset_close(NULL);
    free(out);
    free(lit);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(decodesEveryStorageFormBitIdentically),
        cmocka_unit_test(nearTermsEqualPrecomputeReconstruction),
        cmocka_unit_test(rangeIsSliceOfWhole),
        cmocka_unit_test(memoryEqualsPath),
        cmocka_unit_test(concurrentDecodesEqualSerial),
        cmocka_unit_test(sceneEffectsDecodeAsEffectsC),
        cmocka_unit_test(badArgumentsGiveErrors),
        cmocka_unit_test(vectorFileDecodesQ),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
