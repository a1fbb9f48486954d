/* test_exact.c: the exact evaluator of q(x_v, ω) (Hao–Varshney 2004 §3.1)
 * built from a .sss file alone: it reproduces a float bake at its direction
 * samples, agrees with itself vertex by vertex and across thread counts, and
 * measures the direction-interpolation error of §3.2, which must shrink
 * from 25 to 200 directions. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/decode.h"
#include "sss/exact.h"
#include "sss/random.h"

/* Blob (subdiv 3, 642 vertices), skin1, 20 mm per unit, 50 directions,
 * float: the bake of test_compress.c. g_file is what a reader sees (the bake
 * encoded and decoded), so the evaluator gets nothing but the file. */
static sss_mesh g_mesh;
static sss_bake_file g_file;
static sss_exact *g_exact;

static void bake_or_fail(const sss_mesh *m, const char *material, uint32_t ndirs, sss_quant quant, sss_bake_file *out)
{
    sss_material mat;
    sss_error err = {{0}};
    if (sss_material_preset(material, &mat, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 20.0;
    opt.n_dirs = ndirs;
    opt.quant = quant;
    opt.threads = 2;
    sss_bake_file baked;
    if (sss_bake(m, "blob", &mat, &opt, &baked, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    uint8_t *buf;
    size_t len;
    if (sss_file_encode(&baked, &buf, &len, &err) != SSS_OK) fail_msg("encode: %s", err.msg);
    sss_file_free(&baked);
    if (sss_file_decode(buf, len, "blob.sss", out, &err) != SSS_OK) fail_msg("decode: %s", err.msg);
    free(buf);
}

static sss_exact *exact_or_fail(const sss_bake_file *f)
{
    sss_exact *e;
    sss_error err = {{0}};
    if (sss_exact_create(f, &e, &err) != SSS_OK) fail_msg("exact: %s", err.msg);
    return e;
}

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    if (sss_gen_blob(&g_mesh, 1.0, 3, &err) != SSS_OK) return -1;
    bake_or_fail(&g_mesh, "skin1", 50, SSS_QUANT_FLOAT, &g_file);
    g_exact = exact_or_fail(&g_file);
    return 0;
}

static int teardown(void **state)
{
    (void)state;
    sss_exact_destroy(g_exact);
    sss_file_free(&g_file);
    sss_mesh_free(&g_mesh);
    return 0;
}

static float *alloc_q(const sss_bake_file *f)
{
    float *q = malloc((size_t)f->mesh.nv * f->channels * sizeof *q);
    assert_non_null(q);
    return q;
}

/* At every direction sample ω_j the evaluator recomputes the bake's sum with
 * the same weights, transfer terms and summation order: the stored floats,
 * to within 1e-5 of the largest value (in practice bit for bit). */
static void samplesMatchStoredFloats(void **state)
{
    (void)state;
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels, nd = g_file.dirs.n;
    assert_int_equal(sss_exact_vertices(g_exact), nv);
    assert_int_equal(sss_exact_channels(g_exact), C);
    float *q = alloc_q(&g_file);
    double qmax = 0.0, worst = 0.0;
    uint64_t equal = 0, total = (uint64_t)nd * nv * C;
    for (size_t k = 0; k < total; k++) qmax = fmax(qmax, g_file.q[k]);
    assert_true(qmax > 0.0);
    for (uint32_t j = 0; j < nd; j++) {
        sss_exact_eval(g_exact, g_file.dirs.dir + 3 * (size_t)j, q);
        for (size_t k = 0; k < (size_t)nv * C; k++) {
            float want = g_file.q[(size_t)j * nv * C + k];
            worst = fmax(worst, fabs((double)q[k] - want));
            equal += q[k] == want;
        }
    }
    print_message("exact vs stored at %u samples: max |diff| = %.3g (%.3g of max q %.4g), %llu of %llu bit-equal\n", nd,
                  worst, worst / qmax, qmax, (unsigned long long)equal, (unsigned long long)total);
    assert_true(worst <= 1e-5 * qmax);
    free(q);
}

/* With the hat-function weights (section QUAD) the evaluator sums the bake's
 * rows and corrections in the bake's order: a direct-sum bake's stored
 * floats bit for bit, and the tree gather's within 1e-5 of the largest
 * value; the near terms at run time (by radius) do not change that. */
static void hatWeightsSamplesMatchStoredFloats(void **state)
{
    (void)state;
    for (int gather = SSS_GATHER_DIRECT; gather <= SSS_GATHER_TREE; gather++) {
        sss_material mat;
        sss_error err = {{0}};
        assert_int_equal(sss_material_preset("skin1", &mat, &err), SSS_OK);
        sss_bake_options opt;
        memset(&opt, 0, sizeof opt);
        opt.mm_per_unit = 20.0;
        opt.n_dirs = 12;
        opt.threads = 2;
        opt.weights = SSS_WEIGHTS_HAT;
        opt.gather = gather;
        sss_bake_file baked, f;
        if (sss_bake(&g_mesh, "blob", &mat, &opt, &baked, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
        uint8_t *buf;
        size_t len;
        assert_int_equal(sss_file_encode(&baked, &buf, &len, &err), SSS_OK);
        sss_file_free(&baked);
        assert_int_equal(sss_file_decode(buf, len, "hat.sss", &f, &err), SSS_OK);
        free(buf);
        assert_int_equal(f.weights, SSS_WEIGHTS_HAT);
        sss_exact *e = exact_or_fail(&f);
        const uint32_t nv = f.mesh.nv, C = f.channels, nd = f.dirs.n;
        float *q = alloc_q(&f);
        double qmax = 0.0, worst = 0.0;
        uint64_t equal = 0, total = (uint64_t)nd * nv * C;
        for (size_t k = 0; k < total; k++) qmax = fmax(qmax, f.q[k]);
        for (uint32_t j = 0; j < nd; j++) {
            sss_exact_eval(e, f.dirs.dir + 3 * (size_t)j, q);
            for (size_t k = 0; k < (size_t)nv * C; k++) {
                const float want = f.q[(size_t)j * nv * C + k];
                worst = fmax(worst, fabs((double)q[k] - want));
                equal += q[k] == want;
            }
        }
        print_message("hat weights, %s gather: exact vs stored max |diff| %.3g of max q, %llu of %llu bit-equal\n",
                      gather == SSS_GATHER_DIRECT ? "direct" : "tree", worst / qmax, (unsigned long long)equal,
                      (unsigned long long)total);
        if (gather == SSS_GATHER_DIRECT) assert_true(equal == total);
        assert_true(worst <= 1e-5 * qmax);
        free(q);
        sss_exact_destroy(e);
        sss_file_free(&f);
    }
}

/* eval_vertex traces only one vertex's neighbours but must give the very
 * floats eval writes; and eval must not depend on the thread count. */
static void vertexEqualsAllAndThreadsAgree(void **state)
{
    (void)state;
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels;
    float *a = alloc_q(&g_file), *b = alloc_q(&g_file);
    uint64_t seed = 11;
    for (int t = 0; t < 4; t++) {
        double l[3];
        if (t == 0) memcpy(l, g_file.dirs.dir + 3 * 7, sizeof l); /* a sample */
        else sss_rng_direction(&seed, l);
        if (t == 3) for (int k = 0; k < 3; k++) l[k] *= 3.5; /* need not be unit */
        sss_exact_eval(g_exact, l, a);
        for (uint32_t v = 0; v < nv; v++) {
            float o[SSS_MAX_CHANNELS];
            sss_exact_eval_vertex(g_exact, v, l, o);
            if (memcmp(o, &a[(size_t)v * C], C * sizeof *o) != 0)
                fail_msg("direction %d vertex %u: eval_vertex %.9g, eval %.9g", t, v, o[0], a[(size_t)v * C]);
        }
#ifdef _OPENMP
        int saved = omp_get_max_threads();
        omp_set_num_threads(1);
        sss_exact_eval(g_exact, l, b);
        omp_set_num_threads(3);
        float *c = alloc_q(&g_file);
        sss_exact_eval(g_exact, l, c);
        omp_set_num_threads(saved);
        assert_memory_equal(a, b, (size_t)nv * C * sizeof *a);
        assert_memory_equal(a, c, (size_t)nv * C * sizeof *a);
        free(c);
#endif
    }
    /* a non-unit multiple of a direction gives the unit direction's values
     * up to the rounding of the normalisation */
    double l[3], l2[3];
    sss_rng_direction(&seed, l);
    for (int k = 0; k < 3; k++) l2[k] = l[k] * 1e7;
    sss_exact_eval(g_exact, l, a);
    sss_exact_eval(g_exact, l2, b);
    double qmax = 0.0, d = 0.0;
    for (size_t k = 0; k < (size_t)nv * C; k++) {
        qmax = fmax(qmax, a[k]);
        d = fmax(d, fabs((double)a[k] - b[k]));
    }
    assert_true(qmax > 0.0);
    assert_true(d <= 1e-5 * qmax);
    free(a);
    free(b);
}

/* A subset of receivers (sss_exact_subset, the environment's reference)
 * traces each shared neighbour once per light but must give the very floats
 * eval_vertex writes, for any batch of lights and thread count; the source
 * limit takes a prefix of the receivers, never none. */
static void subsetEqualsEvalVertex(void **state)
{
    (void)state;
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels;
    const uint32_t verts[5] = {5, 100, 5, nv - 1, 0};
    sss_error err = {{0}};
    sss_exact_subset *s;
    assert_int_equal(sss_exact_subset_create(g_exact, verts, 5, 0, &s, &err), SSS_OK);
    assert_int_equal(sss_exact_subset_vertices(s), 5);
    assert_true(sss_exact_subset_sources(s) > 0 && sss_exact_subset_sources(s) <= nv);
    /* 300 lights: more than one batch of the table; one zero, one sample,
     * one not unit */
    enum { NL = 300 };
    double *l = malloc(3 * NL * sizeof *l);
    uint64_t seed = 23;
    for (uint32_t j = 0; j < NL; j++) sss_rng_direction(&seed, &l[3 * j]);
    memcpy(&l[3 * 7], g_file.dirs.dir + 3 * 3, 3 * sizeof *l);
    for (int k = 0; k < 3; k++) l[3 * 11 + k] = 0.0, l[3 * 12 + k] *= 4.0;
    float *a = malloc((size_t)NL * 5 * C * sizeof *a), *b = malloc((size_t)NL * 5 * C * sizeof *b);
    sss_exact_subset_eval(s, l, NL, a);
    for (uint32_t j = 0; j < NL; j++)
        for (uint32_t k = 0; k < 5; k++) {
            float o[SSS_MAX_CHANNELS];
            sss_exact_eval_vertex(g_exact, verts[k], &l[3 * j], o);
            if (memcmp(o, &a[((size_t)j * 5 + k) * C], C * sizeof *o) != 0)
                fail_msg("light %u receiver %u: subset %.9g, eval_vertex %.9g", j, k, a[((size_t)j * 5 + k) * C], o[0]);
        }
#ifdef _OPENMP
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    sss_exact_subset_eval(s, l, NL, b);
    omp_set_num_threads(saved);
    assert_memory_equal(a, b, (size_t)NL * 5 * C * sizeof *a);
#endif
    /* one light at a time: the same values */
    for (uint32_t j = 0; j < NL; j += 37) {
        sss_exact_subset_eval(s, &l[3 * j], 1, b);
        assert_memory_equal(&a[(size_t)j * 5 * C], b, 5 * C * sizeof *a);
    }
    const uint64_t all = sss_exact_subset_sources(s);
    sss_exact_subset_destroy(s);
    /* a limit of 1 source still takes the first receiver (all its row) */
    assert_int_equal(sss_exact_subset_create(g_exact, verts, 5, 1, &s, &err), SSS_OK);
    assert_int_equal(sss_exact_subset_vertices(s), 1);
    const uint64_t first = sss_exact_subset_sources(s);
    assert_true(first > 1 && first <= all);
    sss_exact_subset_destroy(s);
    /* exactly the first receiver's sources: the second, vertex 100, is
     * left out when it adds any; vertex 5 again adds none */
    assert_int_equal(sss_exact_subset_create(g_exact, verts, 2, 0, &s, &err), SSS_OK);
    const uint64_t two = sss_exact_subset_sources(s);
    sss_exact_subset_destroy(s);
    assert_int_equal(sss_exact_subset_create(g_exact, verts, 5, first, &s, &err), SSS_OK);
    print_message("subset: %llu sources of vertex 5, %llu with vertex 100, %llu with all five\n",
                  (unsigned long long)first, (unsigned long long)two, (unsigned long long)all);
    assert_int_equal(sss_exact_subset_vertices(s), two > first ? 1 : 2);
    sss_exact_subset_destroy(s);
    const uint32_t twice[2] = {5, 5};
    assert_int_equal(sss_exact_subset_create(g_exact, twice, 2, first, &s, &err), SSS_OK);
    assert_int_equal(sss_exact_subset_vertices(s), 2);
    assert_int_equal(sss_exact_subset_sources(s), first);
    sss_exact_subset_destroy(s);
    /* bad receivers */
    const uint32_t bad[2] = {0, nv};
    assert_int_equal(sss_exact_subset_create(g_exact, bad, 2, 0, &s, &err), SSS_ERR_ARG);
    assert_null(s);
    assert_non_null(strstr(err.msg, "beyond the mesh"));
    assert_int_equal(sss_exact_subset_create(g_exact, bad, 0, 0, &s, &err), SSS_ERR_ARG);
    sss_exact_subset_destroy(NULL);
    free(l);
    free(a);
    free(b);
}

/* Area-weighted RMS over vertices, channels and random directions of the
 * interpolated reconstruction (sss_decode_all) against the evaluator, relative
 * to the RMS of the exact values. */
static double interpolation_error(const sss_bake_file *f, const sss_exact *e, uint32_t ndirs, uint64_t seed,
                                  double *max_abs)
{
    const uint32_t nv = f->mesh.nv, C = f->channels;
    double *area = malloc((size_t)nv * sizeof *area);
    float *x = alloc_q(f), *r = alloc_q(f);
    assert_non_null(area);
    sss_mesh_vertex_areas(&f->mesh, area);
    double num = 0.0, den = 0.0, mx = 0.0;
    for (uint32_t t = 0; t < ndirs; t++) {
        double l[3];
        sss_rng_direction(&seed, l);
        sss_exact_eval(e, l, x);
        sss_decode_all(f, l, r);
        for (uint32_t v = 0; v < nv; v++)
            for (uint32_t c = 0; c < C; c++) {
                double ex = x[(size_t)v * C + c], d = r[(size_t)v * C + c] - ex;
                num += area[v] * d * d;
                den += area[v] * ex * ex;
                mx = fmax(mx, fabs(d));
            }
    }
    free(area);
    free(x);
    free(r);
    assert_true(den > 0.0);
    if (max_abs) *max_abs = mx;
    return sqrt(num / den);
}

/* Off the samples the stored interpolation is an approximation (§3.2): the
 * error against the evaluator is non-zero, and 200 directions beat 25. */
static void interpolationErrorShrinksWithDirections(void **state)
{
    (void)state;
    double mx50;
    double e50 = interpolation_error(&g_file, g_exact, 20, 5, &mx50);
    assert_true(e50 > 1e-4);
    assert_true(mx50 > 0.0);

    sss_bake_file f25, f200;
    bake_or_fail(&g_mesh, "skin1", 25, SSS_QUANT_FLOAT, &f25);
    bake_or_fail(&g_mesh, "skin1", 200, SSS_QUANT_FLOAT, &f200);
    /* one evaluator serves both: it depends on neither file's samples */
    sss_exact *e25 = exact_or_fail(&f25);
    float *a = alloc_q(&f25), *b = alloc_q(&f25);
    const double l[3] = {0.36, -0.48, 0.8};
    sss_exact_eval(e25, l, a);
    sss_exact_eval(g_exact, l, b);
    assert_memory_equal(a, b, (size_t)f25.mesh.nv * f25.channels * sizeof *a);
    free(a);
    free(b);

    double mx25, mx200;
    double e25v = interpolation_error(&f25, e25, 20, 5, &mx25);
    double e200v = interpolation_error(&f200, e25, 20, 5, &mx200);
    print_message("relative area-weighted RMS interpolation error: 25 dirs %.4g (max %.3g), 50 dirs %.4g (max %.3g), "
                  "200 dirs %.4g (max %.3g)\n", e25v, mx25, e50, mx50, e200v, mx200);
    assert_true(e25v > e50);
    assert_true(e50 > e200v);
    assert_true(e200v > 0.0);
    assert_true(e25v > 2.0 * e200v);
    sss_exact_destroy(e25);
    sss_file_free(&f25);
    sss_file_free(&f200);
}

/* A zero or non-finite light gives zeros; so does a vertex out of range. */
static void badLightGivesZeros(void **state)
{
    (void)state;
    const uint32_t nv = g_file.mesh.nv, C = g_file.channels;
    const double bad[][3] = {{0, 0, 0}, {NAN, 0, 1}, {0, INFINITY, 0}, {-INFINITY, 1, 1}, {1e-320, 0, 0}};
    float *q = alloc_q(&g_file);
    for (size_t t = 0; t < sizeof bad / sizeof bad[0]; t++) {
        if (t == 4) { /* a tiny but non-zero light is a direction */
            sss_exact_eval(g_exact, bad[t], q);
            double s = 0;
            for (size_t k = 0; k < (size_t)nv * C; k++) s += q[k];
            assert_true(s > 0.0);
            continue;
        }
        for (size_t k = 0; k < (size_t)nv * C; k++) q[k] = 1.0f;
        sss_exact_eval(g_exact, bad[t], q);
        for (size_t k = 0; k < (size_t)nv * C; k++)
            if (q[k] != 0.0f) fail_msg("light %zu: q[%zu] = %g", t, k, q[k]);
        float o[SSS_MAX_CHANNELS] = {1, 1, 1};
        sss_exact_eval_vertex(g_exact, 3, bad[t], o);
        for (uint32_t c = 0; c < C; c++) assert_true(o[c] == 0.0f);
    }
    float o[SSS_MAX_CHANNELS] = {1, 1, 1};
    const double l[3] = {0, 0, 1};
    sss_exact_eval_vertex(g_exact, nv, l, o);
    for (uint32_t c = 0; c < C; c++) assert_true(o[c] == 0.0f);
    free(q);
}

/* The evaluator ignores the stored values: a lloyd8 bake of the same mesh
 * gives the same exact values as the float one. */
static void lloyd8FileGivesSameExactValues(void **state)
{
    (void)state;
    sss_bake_file f8;
    bake_or_fail(&g_mesh, "skin1", 50, SSS_QUANT_LLOYD8, &f8);
    assert_int_equal(f8.quant, SSS_QUANT_LLOYD8);
    assert_null(f8.q);
    sss_exact *e8 = exact_or_fail(&f8);
    float *a = alloc_q(&f8), *b = alloc_q(&f8);
    uint64_t seed = 99;
    for (int t = 0; t < 3; t++) {
        double l[3];
        sss_rng_direction(&seed, l);
        sss_exact_eval(e8, l, a);
        sss_exact_eval(g_exact, l, b);
        assert_memory_equal(a, b, (size_t)f8.mesh.nv * f8.channels * sizeof *a);
    }
    free(a);
    free(b);
    sss_exact_destroy(e8);
    sss_file_free(&f8);
}

/* ε comes from section NBHD; in a file without it (before format 1.4) from
 * PARM: a larger cutoff means a smaller radius; an empty PARM means the
 * bake's default; a PARM that is not JSON, or a bad "eps", is refused with a
 * message naming the section. */
static void epsReadFromParams(void **state)
{
    (void)state;
    assert_true(fabs(sss_exact_eps(g_exact) - 1e-3) < 1e-15);
    const double r_default = sss_exact_search_radius_mm(g_exact);
    assert_true(r_default > 0.0);
    char *saved = g_file.params_json;
    const double saved_eps = g_file.eps;
    assert_true(saved_eps == 1e-3);
    {   /* NBHD wins over PARM, whatever PARM holds */
        g_file.eps = 0.05;
        g_file.params_json = (char *)"not json";
        sss_exact *e = NULL;
        sss_error err = {{0}};
        if (sss_exact_create(&g_file, &e, &err) != SSS_OK) fail_msg("%s", err.msg);
        assert_true(sss_exact_eps(e) == 0.05);
        assert_true(sss_exact_search_radius_mm(e) < r_default);
        sss_exact_destroy(e);
    }
    g_file.eps = 0.0;
    const char *cases[] = {"", "{\"eps\":0.05}", "{\"mesh\":\"x\"}", "not json", "[1,2]", "{\"eps\":\"small\"}",
                           "{\"eps\":1.5}", "{\"eps\":0}"};
    for (size_t t = 0; t < sizeof cases / sizeof cases[0]; t++) {
        g_file.params_json = (char *)cases[t];
        sss_exact *e = NULL;
        sss_error err = {{0}};
        sss_result r = sss_exact_create(&g_file, &e, &err);
        if (t < 3) {
            if (r != SSS_OK) fail_msg("PARM '%s': %s", cases[t], err.msg);
            double eps = t == 1 ? 0.05 : 1e-3;
            assert_true(fabs(sss_exact_eps(e) - eps) < 1e-15);
            if (t == 1) assert_true(sss_exact_search_radius_mm(e) < r_default);
            else assert_true(sss_exact_search_radius_mm(e) == r_default);
            sss_exact_destroy(e);
        } else {
            assert_int_equal(r, SSS_ERR_CORRUPT);
            assert_null(e);
            assert_non_null(strstr(err.msg, "PARM"));
        }
    }
    g_file.params_json = saved;
    g_file.eps = saved_eps;
    sss_exact *e = NULL;
    sss_error err = {{0}};
    sss_bake_file empty;
    memset(&empty, 0, sizeof empty);
    assert_int_equal(sss_exact_create(&empty, &e, &err), SSS_ERR_ARG);
    assert_null(e);
    sss_exact_destroy(NULL);
}

/* A grey material is baked as one channel; the evaluator follows. */
static void greyMaterialOneChannel(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    if (sss_gen_sphere(&m, 1.0, 2, &err) != SSS_OK) fail_msg("%s", err.msg);
    sss_material mat = {"custom", {0.05, 0.05, 0.05}, {1.0, 1.0, 1.0}, 1.3, 0.0};
    sss_bake_options opt;
    memset(&opt, 0, sizeof opt);
    opt.mm_per_unit = 10.0;
    opt.n_dirs = 12;
    opt.eps = 0.01;
    sss_bake_file f;
    if (sss_bake(&m, "sphere", &mat, &opt, &f, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    assert_int_equal(f.channels, 1);
    sss_exact *e = exact_or_fail(&f);
    assert_int_equal(sss_exact_channels(e), 1);
    assert_true(fabs(sss_exact_eps(e) - 0.01) < 1e-15);
    float *q = alloc_q(&f);
    for (uint32_t j = 0; j < f.dirs.n; j++) {
        sss_exact_eval(e, f.dirs.dir + 3 * (size_t)j, q);
        for (uint32_t v = 0; v < f.mesh.nv; v++) {
            float want = f.q[(size_t)j * f.mesh.nv + v];
            if (!(fabs((double)q[v] - want) <= 1e-5 * fabs(want) + 1e-12))
                fail_msg("dir %u vertex %u: %.9g, stored %.9g", j, v, q[v], want);
        }
    }
    free(q);
    sss_exact_destroy(e);
    sss_file_free(&f);
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(samplesMatchStoredFloats),
        cmocka_unit_test(hatWeightsSamplesMatchStoredFloats),
        cmocka_unit_test(vertexEqualsAllAndThreadsAgree),
        cmocka_unit_test(subsetEqualsEvalVertex),
        cmocka_unit_test(interpolationErrorShrinksWithDirections),
        cmocka_unit_test(badLightGivesZeros),
        cmocka_unit_test(lloyd8FileGivesSameExactValues),
        cmocka_unit_test(epsReadFromParams),
        cmocka_unit_test(greyMaterialOneChannel),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
