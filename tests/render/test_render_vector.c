/* Renderer tests of the vector integral Q (section QVEC, Hao–Varshney
 * 2004 §3.2): a file with Q is drawn from Q on both paths, the GPU's
 * interpolated and dotted Q read back equal to the C decoder's
 * (sss_decode_vector_range) and the CPU path's upload equal to it to the
 * bit; sss_renderer_create_scalar draws the same file's q rows instead,
 * equal to sss_decode_all, and that differs from Q between the samples;
 * baking Q leaves q's rows as they were. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/bake.h"
#include "sss/decode.h"
#include "sss/render.h"

#include "gl_fixture.h"
#include "test_util.h"

static uint64_t rng = 4242;

static void bake_vector(const sss_mesh *m, sss_quant q, sss_bake_file *f)
{
    sss_material mat;
    assert_int_equal(sss_material_preset("skin1", &mat, NULL), SSS_OK);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = 20.0;
    o.n_dirs = 60;
    o.quant = q;
    o.threads = 2;
    o.vector = 1;
    sss_error err = {{0}};
    if (sss_bake(m, "test", &mat, &o, f, NULL, &err) != SSS_OK) fail_msg("bake: %s", err.msg);
    assert_non_null(f->qvec);
}

/* worst relative difference of a against c (a difference below 1e-30 is none) */
static double worst_rel(const float *a, const float *c, size_t n, double *cmax)
{
    double worst = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double d = fabs((double)a[i] - c[i]);
        const double rel = d < 1e-30 ? 0.0 : d / fmax(fabs(c[i]), 1e-30);
        worst = fmax(worst, rel);
        *cmax = fmax(*cmax, c[i]);
    }
    return worst;
}

static void gpuVectorMatchesCDecoderAndCpuPath(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 3, &err), SSS_OK);
    for (int q = 0; q < 2; q++) { /* Q beside float or lloyd8 rows: Q is drawn either way */
        sss_bake_file f;
        bake_vector(&m, (sss_quant)q, &f);
        sss_renderer *r;
        assert_int_equal(sss_renderer_create(&f, &r, &err), SSS_OK);
        assert_int_equal(sss_renderer_vector(r), 1);
        const size_t n = (size_t)f.mesh.nv * f.channels;
        float *g = malloc(n * sizeof *g), *c = malloc(n * sizeof *c);
        assert_non_null(g);
        assert_non_null(c);
        sss_view_params p;
        sss_view_params_default(&p);
        double worst = 0.0, cmax = 0.0;
        for (int t = 0; t < 60; t++) {
            /* the triangle's interpolation, then the paper's 4-nearest */
            p.interp = t < 30 ? SSS_INTERP_TRIANGLE : SSS_INTERP_NEAREST4;
            if (t % 30 < 4) memcpy(p.light, &f.dirs.dir[3 * (t % 30)], sizeof p.light); /* on samples too */
            else test_random_dir(&rng, p.light);
            p.path = SSS_EVAL_GPU;
            sss_renderer_evaluate(r, &p);
            sss_renderer_read_q(r, g);
            sss_decode_vector_range(&f, p.light, (sss_interp)p.interp, 0, f.mesh.nv, c);
            worst = fmax(worst, worst_rel(g, c, n, &cmax));
            p.path = SSS_EVAL_CPU;
            sss_renderer_evaluate(r, &p);
            sss_renderer_read_q(r, g);
            assert_memory_equal(g, c, n * sizeof *g);
        }
        print_message("GPU vs C decoder of Q, %s rows: worst relative difference %.3g (max q %.3g)\n",
                      sss_quant_name(f.quant), worst, cmax);
        assert_true(worst <= 1e-4); /* the bound of q's own GPU test (docs/viewer.md) */
        assert_true(cmax > 0.0);
        sss_renderer_destroy(r);
        free(g);
        free(c);
        sss_file_free(&f);
    }
    sss_mesh_free(&m);
}

static void scalarRendererDrawsTheQRowsOfAVectorFile(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 3, &err), SSS_OK);
    sss_bake_file f, plain;
    bake_vector(&m, SSS_QUANT_FLOAT, &f);
    /* --vector adds Q and leaves q's rows as a bake without it makes them */
    bake_preset(&m, "skin1", 0, 20.0, 60, SSS_QUANT_FLOAT, -1, &plain);
    assert_null(plain.qvec);
    assert_memory_equal(plain.q, f.q, (size_t)f.dirs.n * f.mesh.nv * f.channels * sizeof *f.q);
    sss_file_free(&plain);
    sss_renderer *r;
    assert_int_equal(sss_renderer_create_scalar(&f, &r, &err), SSS_OK);
    assert_int_equal(sss_renderer_vector(r), 0);
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *g = malloc(n * sizeof *g), *c = malloc(n * sizeof *c), *v = malloc(n * sizeof *v);
    assert_non_null(g);
    assert_non_null(c);
    assert_non_null(v);
    sss_view_params p;
    sss_view_params_default(&p);
    double worst = 0.0, cmax = 0.0, qdiff = 0.0;
    for (int t = 0; t < 10; t++) {
        test_random_dir(&rng, p.light);
        sss_renderer_evaluate(r, &p);
        sss_renderer_read_q(r, g);
        sss_decode_all(&f, p.light, c);
        worst = fmax(worst, worst_rel(g, c, n, &cmax));
        sss_decode_vector_range(&f, p.light, SSS_INTERP_TRIANGLE, 0, f.mesh.nv, v);
        for (size_t i = 0; i < n; i++) qdiff = fmax(qdiff, fabs((double)v[i] - c[i]));
    }
    assert_true(worst <= 1e-4);
    /* between the samples q and Q differ: the renderer really drew q's rows */
    assert_true(qdiff > 1e-6 * cmax);
    sss_renderer_destroy(r);
    free(g);
    free(c);
    free(v);
    sss_file_free(&f);
    sss_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpuVectorMatchesCDecoderAndCpuPath),
        cmocka_unit_test(scalarRendererDrawsTheQRowsOfAVectorFile),
    };
    return cmocka_run_group_tests(tests, gl_setup, gl_teardown);
}
