/* Bake tests: the planar-slab physics check, shadowing inside a closed box,
 * and byte-identical output whatever the thread count. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <omp.h>

#include "genmesh.h"
#include "sss/bake.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* q at the centre of a flat square of side `size` mm tessellated with
 * spacing h mm, lit head-on, for channel c, through the bake's own
 * neighbourhood, visibility and integral code. */
static double slab_centre_q(const sss_material *m, int c, double size, double h, double *radius_out)
{
    sss_dipole d[3];
    for (int k = 0; k < 3; k++) assert_int_equal(sss_dipole_init(&d[k], m->sigma_a[k], m->sigmap_s[k], m->eta), SSS_OK);
    double R = sss_rd_radius(&d[c], 1e-3, 1e4);
    if (radius_out) *radius_out = R;
    unsigned n = (unsigned)ceil(size / h);
    n += n & 1; /* even: a vertex sits exactly at the centre */
    sss_mesh mesh;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_plane(&mesh, size, size, n, n, &err), SSS_OK);
    uint32_t centre = (n / 2) * (n + 1) + n / 2;
    assert_true(mesh.pos[3 * centre] == 0.0f && mesh.pos[3 * centre + 1] == 0.0f);
    sss_nbhd nb;
    assert_int_equal(sss_nbhd_build(&mesh, 1.0, d, 3, R, &centre, 1, 0, &nb, &err), SSS_OK);
    sss_vis *vis;
    assert_int_equal(sss_vis_create(&mesh, &vis, &err), SSS_OK);
    const double up[3] = {0, 0, 1};
    float *G = malloc(mesh.nv * sizeof(float));
    assert_non_null(G);
    assert_int_equal(sss_transfer_compute(&mesh, vis, up, 1, m->eta, G, NULL, NULL, &err), SSS_OK);
    float q[3];
    sss_integrate(&nb, G, 1, q);
    free(G);
    sss_vis_destroy(vis);
    sss_nbhd_free(&nb);
    sss_mesh_free(&mesh);
    return q[c];
}

/* physics sheet §4: an infinite flat surface lit head-on scatters
 * q = F_t(η, 1) · R_d,total / π (the 1−ε cutoff and the discretisation must
 * stay within 2%). */
static void check_slab(const char *name, double h)
{
    sss_material m;
    assert_int_equal(sss_material_preset(name, &m, NULL), SSS_OK);
    for (int c = 0; c < 3; c++) {
        sss_dipole d;
        sss_dipole_init(&d, m.sigma_a[c], m.sigmap_s[c], m.eta);
        double R;
        slab_centre_q(&m, c, 1.0, 1.0, &R); /* radius only */
        double q = slab_centre_q(&m, c, 2.0 * R + 4.0 * h, h, NULL);
        double want = sss_ft(m.eta, 1.0) * sss_rd_total(&d) / M_PI;
        double rel = fabs(q - want) / want;
        printf("slab %s channel %d: h %.3g mm, radius %.2f mm, q %.6g, expected %.6g, rel %.2e\n", name, c, h, R, q, want, rel);
        assert_true(rel <= 0.02);
    }
}

static void planarSlabMatchesTotalReflectanceForMarble(void **state) { (void)state; check_slab("marble", 0.25); }
static void planarSlabMatchesTotalReflectanceForSkin1(void **state) { (void)state; check_slab("skin1", 0.25); }

static void vertexInsideClosedBoxIsFullyShadowed(void **state)
{
    (void)state;
    sss_mesh box, ball;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_box(&box, 10, 10, 10, 8, 0, &err), SSS_OK);
    assert_int_equal(sss_gen_sphere(&ball, 1.0, 2, &err), SSS_OK);
    uint32_t first_ball = box.nv;
    assert_int_equal(sss_mesh_append(&box, &ball, &err), SSS_OK);
    sss_dirset ds;
    assert_int_equal(sss_dirset_fibonacci(&ds, 200, &err), SSS_OK);
    sss_vis *vis;
    assert_int_equal(sss_vis_create(&box, &vis, &err), SSS_OK);
    float *G = malloc((size_t)box.nv * ds.n * sizeof(float));
    uint64_t rays = 0, occ = 0;
    assert_int_equal(sss_transfer_compute(&box, vis, ds.dir, ds.n, 1.3, G, &rays, &occ, &err), SSS_OK);
    for (uint32_t v = first_ball; v < box.nv; v++)
        for (uint32_t j = 0; j < ds.n; j++) {
            assert_true(G[(size_t)v * ds.n + j] == 0.0f);
            assert_true(sss_vis_occluded(vis, v, &ds.dir[3 * j]));
        }
    /* the box's own outside is lit: a convex object does not shadow itself */
    for (uint32_t v = 0; v < first_ball; v++) {
        int lit = 0;
        for (uint32_t j = 0; j < ds.n; j++) lit |= G[(size_t)v * ds.n + j] > 0.0f;
        assert_true(lit);
    }
    free(G);
    sss_vis_destroy(vis);
    sss_dirset_free(&ds);
    sss_mesh_free(&box);
    sss_mesh_free(&ball);
}

static void bake_bytes(const sss_mesh *mesh, int threads, sss_quant quant, uint8_t **buf, size_t *len)
{
    sss_material m;
    assert_int_equal(sss_material_preset("skin1", &m, NULL), SSS_OK);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = 10.0;
    o.n_dirs = 64;
    o.quant = quant;
    o.threads = threads;
    sss_bake_file f;
    sss_error err = {{0}};
    assert_int_equal(sss_bake(mesh, "blob", &m, &o, &f, NULL, &err), SSS_OK);
    assert_int_equal(sss_file_encode(&f, buf, len, &err), SSS_OK);
    sss_file_free(&f);
}

static void bakeIsByteIdenticalWithOneAndTwoThreads(void **state)
{
    (void)state;
    sss_mesh mesh;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&mesh, 1.0, 4, &err), SSS_OK);
    for (int qm = 0; qm < 2; qm++) {
        uint8_t *a, *b;
        size_t la, lb;
        bake_bytes(&mesh, 1, (sss_quant)qm, &a, &la);
        bake_bytes(&mesh, 2, (sss_quant)qm, &b, &lb);
        assert_int_equal(la, lb);
        assert_memory_equal(a, b, la);
        free(a);
        free(b);
    }
    omp_set_num_threads(2);
    sss_mesh_free(&mesh);
}

static void bakedIntegralsAreFiniteNonNegativeAndShadowed(void **state)
{
    (void)state;
    sss_mesh mesh;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&mesh, 1.0, 4, &err), SSS_OK);
    sss_material m;
    sss_material_preset("skin1", &m, NULL);
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.mm_per_unit = 10.0;
    o.n_dirs = 64;
    sss_bake_file f;
    sss_bake_stats st;
    assert_int_equal(sss_bake(&mesh, "blob", &m, &o, &f, &st, &err), SSS_OK);
    size_t n = (size_t)f.dirs.n * f.mesh.nv * 3;
    double maxq[3] = {0};
    for (size_t k = 0; k < n; k++) {
        assert_true(isfinite(f.q[k]) && f.q[k] >= 0.0f);
        if (f.q[k] > maxq[k % 3]) maxq[k % 3] = f.q[k];
    }
    /* energy: no vertex scatters more than a flat slab lit head-on would,
     * plus a margin for curvature (concave regions gather from both sides) */
    for (int c = 0; c < 3; c++) {
        sss_dipole d;
        sss_dipole_init(&d, m.sigma_a[c], m.sigmap_s[c], m.eta);
        assert_true(maxq[c] > 0.0);
        assert_true(maxq[c] <= 1.5 * sss_ft(m.eta, 1.0) * sss_rd_total(&d) / M_PI);
    }
    assert_true(st.occluded_fraction > 0.01); /* the blob has concavities */
    assert_true(st.neighbours_mean > 2.0);
    sss_file_free(&f);
    sss_mesh_free(&mesh);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(planarSlabMatchesTotalReflectanceForMarble),
        cmocka_unit_test(planarSlabMatchesTotalReflectanceForSkin1),
        cmocka_unit_test(vertexInsideClosedBoxIsFullyShadowed),
        cmocka_unit_test(bakeIsByteIdenticalWithOneAndTwoThreads),
        cmocka_unit_test(bakedIntegralsAreFiniteNonNegativeAndShadowed),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
