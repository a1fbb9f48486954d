/* test_hatweights.c: the weights of Hao–Varshney 2004 §3.1 integrated over
 * the vertices' hat functions (sss/hatweights.h, docs/physics.md §9): the
 * profile's polynomial tables, the adaptive quadrature of one triangle, the
 * restricted rows against the full ones, and a triangle soup against the
 * welded surface. The slab and sphere checks are in test_bake.c. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/hatweights.h"
#include "sss/nbhd.h"
#include "sss/vec3.h"

static void preset_dipoles(const char *name, sss_dipole d[3])
{
    sss_material m;
    assert_int_equal(sss_material_preset(name, &m, NULL), SSS_OK);
    for (int c = 0; c < 3; c++) assert_int_equal(sss_dipole_init(&d[c], m.sigma_a[c], m.sigmap_s[c], m.eta), SSS_OK);
}

/* The quadrature's tables of (1/π) R_d in r² agree with sss_rd to 1e-7
 * relative for every preset channel from 1 µm to the 1e-3 cutoff radius,
 * and to 1e-5 up to twice it, where the exponential varies by a few e-folds
 * over an octave (docs/physics.md §9); beyond their range they are
 * sss_rd. */
static void profileTablesMatchTheFormula(void **state)
{
    (void)state;
    double worst = 0.0;
    for (int p = 0; p < sss_material_preset_count(); p++) {
        sss_dipole d[3];
        preset_dipoles(sss_material_preset_name(p), d);
        for (int c = 0; c < 3; c++) {
            const double R = sss_rd_radius(&d[c], 1e-3, 1e4), xmax = 4.0 * R * R;
            for (double r = 1e-3; r <= 2.0 * R; r *= 1.01) {
                const double want = sss_rd(&d[c], r) / SSS_PI, got = sss_hat_rdpoly_check(&d[c], xmax, r * r);
                worst = fmax(worst, fabs(got / want - 1.0) * (r <= R ? 1.0 : 1e-2));
            }
            const double far = 3.0 * R;
            assert_true(sss_hat_rdpoly_check(&d[c], xmax, far * far) == sss_rd(&d[c], far) / SSS_PI);
        }
    }
    print_message("profile tables: worst relative error %.3g\n", worst);
    assert_true(worst <= 1e-7);
}

/* The degree-5 7-point rule (Radon) with sss_rd itself on every piece of
 * a uniform subdivision into 4^depth triangles: a reference independent of
 * the adaptive criterion and of the tables. */
static void uniform_reference(const sss_dipole *d, uint32_t C, const double p[3][3], const double xo[3], int depth,
                              double *out)
{
    const double r15 = sqrt(15.0);
    const double A1 = (6.0 - r15) / 21.0, B1 = (9.0 + 2.0 * r15) / 21.0, A2 = (6.0 + r15) / 21.0,
                 B2 = (9.0 - 2.0 * r15) / 21.0, W0 = 9.0 / 40.0, W1 = (155.0 - r15) / 1200.0,
                 W2 = (155.0 + r15) / 1200.0;
    double e1[3], e2[3], cr[3];
    sss_sub3(e1, p[1], p[0]);
    sss_sub3(e2, p[2], p[0]);
    sss_cross3(e1, e2, cr);
    const int n = 1 << depth;
    const double ap = 0.5 * sqrt(sss_dot3(cr, cr)) / ((double)n * n) / SSS_PI;
    for (uint32_t k = 0; k < 3 * C; k++) out[k] = 0.0;
    /* pieces of the grid in (λ1, λ2) = (i, j) / n: up and down triangles */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n - i; j++)
            for (int up = 1; up >= 0; up--) {
                if (!up && j == n - i - 1) continue;
                const double c1[3] = {(double)i, i + 1.0, (double)i}, c2[3] = {(double)j, (double)j, j + 1.0};
                const double u1[3] = {i + 1.0, (double)i, i + 1.0}, u2[3] = {j + 1.0, j + 1.0, (double)j};
                double b[3][3];
                for (int m = 0; m < 3; m++) {
                    const double l1 = (up ? c1[m] : u1[m]) / n, l2 = (up ? c2[m] : u2[m]) / n;
                    b[m][0] = 1.0 - l1 - l2;
                    b[m][1] = l1;
                    b[m][2] = l2;
                }
                for (int q = 0; q < 7; q++) {
                    double beta[3] = {1.0 / 3, 1.0 / 3, 1.0 / 3}, w = W0;
                    if (q >= 1 && q <= 3) beta[0] = beta[1] = beta[2] = A1, beta[q - 1] = B1, w = W1;
                    if (q >= 4) beta[0] = beta[1] = beta[2] = A2, beta[q - 4] = B2, w = W2;
                    double lam[3], x[3], dx[3];
                    for (int k = 0; k < 3; k++) lam[k] = beta[0] * b[0][k] + beta[1] * b[1][k] + beta[2] * b[2][k];
                    for (int k = 0; k < 3; k++) x[k] = lam[0] * p[0][k] + lam[1] * p[1][k] + lam[2] * p[2][k];
                    sss_sub3(dx, x, xo);
                    const double r = sqrt(sss_dot3(dx, dx));
                    for (uint32_t c = 0; c < C; c++) {
                        const double f = w * ap * sss_rd(&d[c], r);
                        for (int k = 0; k < 3; k++) out[k * C + c] += lam[k] * f;
                    }
                }
            }
}

/* A needle 10^10 mm long and 2 mm wide with x_o at its wide end (a mesh
 * with one vertex sent far away): the pieces near x_o must resolve the
 * profile along the length without splitting the width 2^30 times over
 * (docs/robustness.md, "Degenerate triangles"). Its integral is the
 * strip's near x_o, by a midpoint rule in the plane 10 µm fine; the far
 * corner's hat weight, ~ x/L, is below 1e-8 of it. Before slivers were
 * bisected this call did not finish in hours. */
static void needleTriangleIntegratesLikeItsStrip(void **state)
{
    (void)state;
    sss_dipole d[3];
    preset_dipoles("skin1", d);
    const double L = 1e10, w = 2.0, X = 60.0, dx = 0.01;
    const double p[3][3] = {{0, 0, 0}, {L, 0, 0}, {0, w, 0}}, xo[3] = {0.5, 0.7, 0};
    double a[9];
    sss_hat_triangle(d, 3, p, xo, a);
    for (int c = 0; c < 3; c++) {
        double ref = 0.0;
        for (double x = 0.5 * dx; x < X; x += dx)
            for (double y = 0.5 * dx; y < w * (1.0 - x / L); y += dx)
                ref += sss_rd(&d[c], hypot(x - xo[0], y - xo[1])) / SSS_PI * dx * dx;
        const double got = a[c] + a[3 + c] + a[6 + c];
        print_message("needle, channel %d: %.6g against the strip's %.6g\n", c, got, ref);
        assert_true(isfinite(got) && fabs(got / ref - 1.0) <= 1e-3);
        assert_true(a[3 + c] >= 0.0 && a[3 + c] <= 1e-8 * ref);
    }
}

/* The adaptive rule against a uniform subdivision 4^7 pieces deep: x_o at a
 * corner (the receiver's own triangles), just off a triangle's plane
 * (curved surfaces), and farther away; skin1 (z_r 0.67–1.3 mm) on
 * triangles of 0.5 to 8 mm. Each of the three hat integrals within 1e-4 of
 * the triangle's total (or of 1e-3 of a slab's q for a far triangle). */
static void triangleQuadratureMatchesFineSubdivision(void **state)
{
    (void)state;
    sss_dipole d[3];
    preset_dipoles("skin1", d);
    const double sizes[] = {0.5, 2.0, 8.0};
    const double offs[][3] = {{0, 0, 0}, {0.3, 0.2, 0.1}, {-1.0, 2.5, 0.4}};
    double worst = 0.0;
    for (int si = 0; si < 3; si++)
        for (int oi = 0; oi < 3; oi++) {
            const double h = sizes[si];
            const double p[3][3] = {{0, 0, 0}, {h, 0.1 * h, 0}, {0.3 * h, 0.8 * h, 0.05 * h}};
            const double xo[3] = {offs[oi][0] * h, offs[oi][1] * h, offs[oi][2] * h};
            double a[9], ref[9];
            sss_hat_triangle(d, 3, p, xo, a);
            uniform_reference(d, 3, p, xo, 7, ref);
            for (int c = 0; c < 3; c++) {
                /* against the triangle's integral, or 1e-3 of a flat
                 * slab's q where the triangle holds less (a far one) */
                const double tot = fmax(ref[c] + ref[3 + c] + ref[6 + c], 1e-3 * sss_rd_total(&d[c]) / SSS_PI);
                for (int k = 0; k < 3; k++) worst = fmax(worst, fabs(a[k * 3 + c] - ref[k * 3 + c]) / tot);
                if (getenv("QDBG")) printf("h %g off %d c %d: adaptive %.6g %.6g %.6g ref %.6g %.6g %.6g\n", h, oi, c, a[c], a[3+c], a[6+c], ref[c], ref[3+c], ref[6+c]);
            }
        }
    print_message("triangle quadrature: worst error %.3g of the triangle's integral\n", worst);
    assert_true(worst <= 1e-4);
}

/* Rows restricted to chosen entries (the near terms' need) hold the very
 * bits of the full rows for those entries. */
static void restrictedRowsEqualFullRows(void **state)
{
    (void)state;
    sss_mesh m;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_blob(&m, 1.0, 3, &err), SSS_OK);
    sss_dipole d[3];
    preset_dipoles("skin1", d);
    const double s = 15.0, R = sss_nbhd_radii(&m, s, d, 3, 1e-3, NULL);
    sss_weights full, sel, part;
    assert_int_equal(sss_hat_corrections(&m, s, d, 3, R, NULL, 0, NULL, &full, &err), SSS_OK);
    /* the selection: every third entry of each full row, and the receiver */
    sel.nrows = m.nv;
    sel.channels = 3;
    sel.start = calloc((size_t)m.nv + 1, sizeof *sel.start);
    sel.idx = malloc((size_t)full.start[m.nv] * sizeof *sel.idx + m.nv * sizeof *sel.idx + 1);
    sel.w = NULL;
    assert_true(sel.start && sel.idx);
    for (uint32_t o = 0; o < m.nv; o++) {
        uint64_t n = sel.start[o];
        sel.idx[n++] = o;
        for (uint64_t a = full.start[o]; a < full.start[o + 1]; a++)
            if (a % 3 == 0 && full.idx[a] != o) sel.idx[n++] = full.idx[a];
        sel.start[o + 1] = n;
    }
    assert_int_equal(sss_hat_corrections_of(&m, s, d, 3, R, &sel, NULL, &part, &err), SSS_OK);
    uint64_t checked = 0;
    for (uint32_t o = 0; o < m.nv; o++)
        for (uint64_t a = part.start[o]; a < part.start[o + 1]; a++) {
            uint64_t b = full.start[o];
            while (b < full.start[o + 1] && full.idx[b] != part.idx[a]) b++;
            assert_true(b < full.start[o + 1]);
            assert_memory_equal(&part.w[a * 3], &full.w[b * 3], 3 * sizeof(float));
            checked++;
        }
    print_message("restricted rows: %llu entries equal to the full rows' bits\n", (unsigned long long)checked);
    assert_true(checked > m.nv);
    free(sel.start);
    free(sel.idx);
    sss_weights_free(&full);
    sss_weights_free(&part);
    sss_mesh_free(&m);
}

/* An unwelded copy of a slab (every triangle with its own three vertices,
 * as STL files are) is the same surface: each copy's hat function covers
 * its own triangle, so Σ_i W(o, i) at the centre is the welded slab's
 * within 0.1 %, with no special rule for coincident vertices. */
static void triangleSoupIntegratesLikeWeldedSurface(void **state)
{
    (void)state;
    sss_dipole d[3];
    preset_dipoles("skin1", d);
    sss_error err = {{0}};
    const unsigned n = 24; /* 2.5 mm cells: coarse against z_r */
    sss_mesh w, u;
    assert_int_equal(sss_gen_plane(&w, 60.0, 60.0, n, n, &err), SSS_OK);
    assert_int_equal(sss_mesh_alloc(&u, 3 * w.nf, w.nf, &err), SSS_OK);
    uint32_t uc = UINT32_MAX;
    for (uint32_t t = 0; t < w.nf; t++)
        for (int k = 0; k < 3; k++) {
            const uint32_t v = w.tri[3 * t + k], nu = 3 * t + (uint32_t)k;
            memcpy(u.pos + 3 * (size_t)nu, w.pos + 3 * (size_t)v, 3 * sizeof(float));
            u.tri[nu] = nu;
            if (w.pos[3 * v] == 0.0f && w.pos[3 * v + 1] == 0.0f && uc == UINT32_MAX) uc = nu;
        }
    assert_int_equal(sss_mesh_compute_normals_areas(&w, "welded", &err), SSS_OK);
    assert_int_equal(sss_mesh_compute_normals_areas(&u, "soup", &err), SSS_OK);
    const uint32_t wc = (n / 2) * (n + 1) + n / 2;
    double R = 0.0;
    for (int c = 0; c < 3; c++) R = fmax(R, sss_rd_radius(&d[c], 1e-3, 1e4));
    double sum[2][3] = {{0}};
    for (int k = 0; k < 2; k++) {
        sss_mesh *m = k ? &u : &w;
        uint32_t o = k ? uc : wc;
        sss_weights nb, hc;
        assert_int_equal(sss_nbhd_build(m, 1.0, d, 3, R, &o, 1, 0, NULL, &nb, &err), SSS_OK);
        assert_int_equal(sss_hat_corrections(m, 1.0, d, 3, R, &o, 1, NULL, &hc, &err), SSS_OK);
        for (int c = 0; c < 3; c++) {
            for (uint64_t a = 0; a < nb.start[1]; a++) sum[k][c] += nb.w[a * 3 + c];
            for (uint64_t a = 0; a < hc.start[1]; a++) sum[k][c] += hc.w[a * 3 + c];
        }
        sss_weights_free(&nb);
        sss_weights_free(&hc);
    }
    for (int c = 0; c < 3; c++) {
        print_message("soup vs welded, channel %d: %.6g / %.6g\n", c, sum[1][c], sum[0][c]);
        assert_true(fabs(sum[1][c] / sum[0][c] - 1.0) <= 1e-3);
    }
    sss_mesh_free(&w);
    sss_mesh_free(&u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(profileTablesMatchTheFormula),
        cmocka_unit_test(triangleQuadratureMatchesFineSubdivision),
        cmocka_unit_test(needleTriangleIntegratesLikeItsStrip),
        cmocka_unit_test(restrictedRowsEqualFullRows),
        cmocka_unit_test(triangleSoupIntegratesLikeWeldedSurface),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
