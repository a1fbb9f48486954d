/* Single scattering tests (sss/single.h, docs/layers.md): the phase
 * functions' normalisation and sign convention, seed 002's flat layered
 * model against its closed form written out here, the invariances a layer
 * stack must keep, the march's convergence order, and Jensen 2001's S⁽¹⁾
 * for a half-space against an independent quadrature (the path-traced
 * reference checks the same function: test_reference). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <string.h>

#include "sss/single.h"
#include "sss/vec3.h"

static double rel_err(double a, double b) { return fabs(a - b) / fmax(fabs(b), 1e-300); }

/* Seed 002's Table 1 (the fish): dermis, blood, organs; σs and σt in 1/mm. */
static const sss_layer table1[3] = {
    {{2.0, 1.0, 1.0}, {2.6, 1.6, 1.6}, 0.25, 0.0},
    {{6.0, 3.0, 2.0}, {6.6, 3.6, 2.6}, 0.40, 0.0},
    {{1.0, 1.0, 2.0}, {1.5, 1.5, 2.5}, 0.80, 0.0},
};

static sss_layer_stack stack_of(const sss_layer *ly, const double *depth, uint32_t n, sss_phase_kind kind)
{
    sss_layer_stack st;
    memset(&st, 0, sizeof st);
    st.n = n;
    st.phase = kind;
    for (uint32_t k = 0; k < n; k++) {
        st.layer[k] = ly[k];
        st.layer[k].depth = depth[k];
    }
    return st;
}

/* A flat geometry without refraction from polar angles (radians) and the
 * azimuth between light and view. */
static sss_ss_geom flat_geom(double theta_i, double theta_o, double phi)
{
    const double n[3] = {0, 0, 1};
    const double wi[3] = {sin(theta_i), 0, cos(theta_i)};
    const double wo[3] = {sin(theta_o) * cos(phi), sin(theta_o) * sin(phi), cos(theta_o)};
    sss_ss_geom g;
    assert_int_equal(sss_ss_geometry(n, wi, wo, 1.0, 0, &g), 1);
    return g;
}

static void phaseHgIsNormalisedWithMeanCosineG(void **state)
{
    (void)state;
    const double gs[] = {-0.5, 0.0, 0.25, 0.8};
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++) {
        const int cells = 200000;
        double norm = 0, mean = 0;
        for (int k = 0; k < cells; k++) {
            const double mu = -1.0 + 2.0 * (k + 0.5) / cells, p = sss_phase_hg(gs[i], mu);
            norm += p;
            mean += p * mu;
        }
        norm *= 2.0 * SSS_PI * 2.0 / cells;
        mean *= 2.0 * SSS_PI * 2.0 / cells;
        assert_true(fabs(norm - 1.0) < 1e-6);
        assert_true(fabs(mean - gs[i]) < 1e-6);
    }
    assert_true(fabs(sss_phase_hg(0.0, 0.3) - 1.0 / (4.0 * SSS_PI)) < 1e-15);
    /* g > 0: forward (cos θ = 1 between propagation directions) dominates */
    assert_true(sss_phase_hg(0.5, 1.0) > 10.0 * sss_phase_hg(0.5, -1.0));
}

static void phaseSchlickIsNormalisedAndForwardForPositiveK(void **state)
{
    (void)state;
    const double ks[] = {-0.6, 0.25, 0.8};
    for (size_t i = 0; i < sizeof ks / sizeof ks[0]; i++) {
        const int cells = 200000;
        double norm = 0;
        for (int k = 0; k < cells; k++) norm += sss_phase_schlick(ks[i], -1.0 + 2.0 * (k + 0.5) / cells);
        assert_true(fabs(norm * 4.0 * SSS_PI / cells - 1.0) < 1e-6);
    }
    assert_true(sss_phase_schlick(0.4, 1.0) > sss_phase_schlick(0.4, -1.0));
    assert_true(sss_phase_schlick(-0.4, 1.0) < sss_phase_schlick(-0.4, -1.0));
    /* seed 002 §3 writes (1 − g²)/(4π (1 + g cos θ')²) with θ' between ω_in
     * (towards the light) and ω_out (towards the viewer): on a flat surface
     * the geometry's cos_phase is −ω_in·ω_out, so both read the same */
    const double th_i = 0.7, th_o = 0.3, phi = 2.0, g = 0.4;
    const sss_ss_geom geo = flat_geom(th_i, th_o, phi);
    const double wi[3] = {sin(th_i), 0, cos(th_i)};
    const double wo[3] = {sin(th_o) * cos(phi), sin(th_o) * sin(phi), cos(th_o)};
    const double c_seed = sss_dot3(wi, wo), den = 1.0 + g * c_seed;
    const double p_seed = (1.0 - g * g) / (4.0 * SSS_PI * den * den);
    assert_true(rel_err(sss_phase_eval(SSS_PHASE_SCHLICK, g, geo.cos_phase), p_seed) < 1e-14);
}

static void oneLayerMatchesSeedClosedForm(void **state)
{
    (void)state;
    const double D[] = {0.05, 0.4, 3.0};
    const double th[][2] = {{0.0, 0.0}, {0.5, 1.1}, {1.2, 0.2}};
    for (size_t a = 0; a < 3; a++)
        for (size_t b = 0; b < 3; b++)
            for (uint32_t c = 0; c < 3; c++) {
                const sss_layer_stack st = stack_of(table1, &D[a], 1, SSS_PHASE_HG);
                const sss_ss_geom g = flat_geom(th[b][0], th[b][1], 0.8);
                const double mi = g.mu_i, mo = g.mu_o, ss = table1[0].sigma_s[c], stt = table1[0].sigma_t[c];
                const double p = sss_phase_hg(table1[0].g, g.cos_phase);
                const double want = ss / stt * p * mi / (mi + mo) * (1.0 - exp(-stt * D[a] * (1.0 / mi + 1.0 / mo)));
                assert_true(rel_err(sss_layers_closed(&st, c, &g), want) < 1e-13);
            }
}

static void twoLayersMatchTheirClosedForm(void **state)
{
    (void)state;
    /* dermis 0.3 mm over blood 0.5 mm thick: the blood's term is its own
     * one-layer closed form seen through the dermis, e^{−σt1 D1 m} */
    const double depth[2] = {0.3, 0.8};
    const sss_layer_stack st = stack_of(table1, depth, 2, SSS_PHASE_SCHLICK);
    const sss_ss_geom g = flat_geom(0.6, 0.9, 2.5);
    const double mi = g.mu_i, mo = g.mu_o, m = 1.0 / mi + 1.0 / mo;
    for (uint32_t c = 0; c < 3; c++) {
        const double s1 = table1[0].sigma_s[c], t1 = table1[0].sigma_t[c];
        const double s2 = table1[1].sigma_s[c], t2 = table1[1].sigma_t[c];
        const double p1 = sss_phase_schlick(table1[0].g, g.cos_phase);
        const double p2 = sss_phase_schlick(table1[1].g, g.cos_phase);
        const double L1 = s1 / t1 * p1 * mi / (mi + mo) * (1.0 - exp(-t1 * 0.3 * m));
        const double L2 = exp(-t1 * 0.3 * m) * s2 / t2 * p2 * mi / (mi + mo) * (1.0 - exp(-t2 * 0.5 * m));
        assert_true(rel_err(sss_layers_closed(&st, c, &g), L1 + L2) < 1e-13);
        /* the segment march is exact for flat layers at any sample count,
         * the crossing at 0.3 mm falling inside a segment */
        sss_ss_flat f = {&st, mi, mo};
        const double s_max = 0.8 / mo;
        assert_true(rel_err(sss_ss_march_segments(&st, c, &g, s_max, 1, sss_ss_locate_flat, &f), L1 + L2) < 1e-10);
        assert_true(rel_err(sss_ss_march_segments(&st, c, &g, s_max, 7, sss_ss_locate_flat, &f), L1 + L2) < 1e-10);
    }
}

static void identicalLayersGiveTheSameResultWhateverTheDepths(void **state)
{
    (void)state;
    sss_layer same[4];
    for (int k = 0; k < 4; k++) same[k] = table1[1];
    const double one[1] = {1.2}, split[4] = {0.1, 0.37, 0.371, 1.2};
    const sss_layer_stack a = stack_of(same, one, 1, SSS_PHASE_HG), b = stack_of(same, split, 4, SSS_PHASE_HG);
    const sss_ss_geom g = flat_geom(0.4, 0.8, 1.0);
    sss_ss_flat fa = {&a, g.mu_i, g.mu_o}, fb = {&b, g.mu_i, g.mu_o};
    const double s_max = 1.2 / g.mu_o;
    for (uint32_t c = 0; c < 3; c++) {
        assert_true(rel_err(sss_layers_closed(&b, c, &g), sss_layers_closed(&a, c, &g)) < 1e-12);
        assert_true(rel_err(sss_ss_march(&b, c, &g, s_max, 50, sss_ss_locate_flat, &fb),
                            sss_ss_march(&a, c, &g, s_max, 50, sss_ss_locate_flat, &fa)) < 1e-12);
        assert_true(rel_err(sss_ss_march_segments(&b, c, &g, s_max, 50, sss_ss_locate_flat, &fb),
                            sss_ss_march_segments(&a, c, &g, s_max, 50, sss_ss_locate_flat, &fa)) < 1e-10);
    }
}

static void zeroThicknessLayerEqualsNoLayer(void **state)
{
    (void)state;
    /* a blood layer of zero thickness between dermis and organs */
    const sss_layer with[3] = {table1[0], table1[1], table1[2]}, without[2] = {table1[0], table1[2]};
    const double dw[3] = {0.4, 0.4, INFINITY}, dn[2] = {0.4, INFINITY};
    const sss_layer_stack a = stack_of(with, dw, 3, SSS_PHASE_HG), b = stack_of(without, dn, 2, SSS_PHASE_HG);
    const sss_ss_geom g = flat_geom(0.3, 0.5, 0.0);
    sss_ss_flat fa = {&a, g.mu_i, g.mu_o}, fb = {&b, g.mu_i, g.mu_o};
    for (uint32_t c = 0; c < 3; c++) {
        const double base = sss_layers_closed(&b, c, &g);
        assert_true(base > 0.0);
        assert_true(sss_layers_closed(&a, c, &g) == base);
        assert_true(sss_ss_march(&a, c, &g, 3.0, 64, sss_ss_locate_flat, &fa) ==
                    sss_ss_march(&b, c, &g, 3.0, 64, sss_ss_locate_flat, &fb));
        assert_true(rel_err(sss_ss_march_segments(&a, c, &g, 3.0, 64, sss_ss_locate_flat, &fa),
                            sss_ss_march_segments(&b, c, &g, 3.0, 64, sss_ss_locate_flat, &fb)) < 1e-12);
    }
}

static void swappingLightAndViewIsSymmetricWithIsotropicPhase(void **state)
{
    (void)state;
    sss_layer iso[3];
    for (int k = 0; k < 3; k++) iso[k] = table1[k], iso[k].g = 0.0;
    const double depth[3] = {0.2, 0.45, INFINITY};
    const sss_layer_stack st = stack_of(iso, depth, 3, SSS_PHASE_HG);
    const double pairs[][2] = {{0.2, 1.0}, {0.9, 1.3}, {0.0, 0.7}};
    for (size_t i = 0; i < 3; i++) {
        const sss_ss_geom g = flat_geom(pairs[i][0], pairs[i][1], 0.6);
        const sss_ss_geom h = flat_geom(pairs[i][1], pairs[i][0], 0.6);
        sss_ss_flat fg = {&st, g.mu_i, g.mu_o}, fh = {&st, h.mu_i, h.mu_o};
        for (uint32_t c = 0; c < 3; c++) {
            const double a = sss_layers_closed(&st, c, &g) / g.mu_i, b = sss_layers_closed(&st, c, &h) / h.mu_i;
            assert_true(a > 0.0);
            assert_true(rel_err(a, b) < 1e-13);
            /* the segment march over the same depth (5 mm: beyond it the
             * light is below e^{-13}) keeps the symmetry too */
            const double sa = sss_ss_march_segments(&st, c, &g, 5.0 / g.mu_o, 40, sss_ss_locate_flat, &fg) / g.mu_i;
            const double sb = sss_ss_march_segments(&st, c, &h, 5.0 / h.mu_o, 40, sss_ss_locate_flat, &fh) / h.mu_i;
            assert_true(rel_err(sa, sb) < 1e-10);
        }
    }
}

/* The least-squares slope of log |error| against log N. */
static double march_order(const sss_layer_stack *st, uint32_t c, const sss_ss_geom *g, double depth, double *err_min)
{
    sss_ss_flat f = {st, g->mu_i, g->mu_o};
    const double exact = sss_layers_closed(st, c, g);
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const int K = 7;
    for (int k = 0; k < K; k++) {
        const uint32_t n = 10u << k;
        const double e = fabs(sss_ss_march(st, c, g, depth / g->mu_o, n, sss_ss_locate_flat, &f) - exact) / exact;
        const double x = log((double)n), y = log(e);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
        *err_min = e;
    }
    return (K * sxy - sx * sy) / (K * sxx - sx * sx);
}

static void marchConvergesToClosedFormAtFirstOrder(void **state)
{
    (void)state;
    const sss_ss_geom g = flat_geom(0.5, 0.3, 1.5);
    const double d1[1] = {1.0}, d2[2] = {0.33, 1.0};
    const sss_layer_stack one = stack_of(table1, d1, 1, SSS_PHASE_SCHLICK);
    const sss_layer_stack two = stack_of(table1, d2, 2, SSS_PHASE_SCHLICK);
    for (uint32_t c = 0; c < 3; c++) {
        double e1, e2;
        const double o1 = march_order(&one, c, &g, 1.0, &e1), o2 = march_order(&two, c, &g, 1.0, &e2);
        print_message("channel %u: order %.3f (one layer, error %.2e at N=640), %.3f (two layers, %.2e)\n", c, o1,
                      e1, o2, e2);
        /* Algorithm 1 is a left Riemann sum: error ∝ 1/N */
        assert_true(o1 < -0.95 && o1 > -1.05);
        assert_true(o2 < -0.9 && o2 > -1.1);
        assert_true(e1 < 0.01 && e2 < 0.01);
    }
}

/* Fresnel reflectance from Snell's law and the two polarisations, the
 * textbook form (not sss_ft's, which uses Jensen's g-substitution). */
static double fresnel_t(double eta, double theta)
{
    const double st = sin(theta) / eta, tt = asin(st), ci = cos(theta), ct = cos(tt);
    const double rs = (ci - eta * ct) / (ci + eta * ct), rp = (eta * ci - ct) / (eta * ci + ct);
    return 1.0 - 0.5 * (rs * rs + rp * rp);
}

/* The single scattering of a half-space summed along the refracted view
 * ray by composite Simpson, directions from angles (Snell in polar form):
 * Jensen's S⁽¹⁾ integrand (eq. 4) with the irradiance F_t E cos θ_i across
 * the surface spread over the refracted beam (÷ cos θ′_i) and the radiance
 * leaving the denser medium divided by η². */
static double jensen_quadrature(double ss, double stt, double g, double eta, double th_i, double th_o, double phi)
{
    const double ti = asin(sin(th_i) / eta), to = asin(sin(th_o) / eta);
    /* propagation directions inside: the light going down, the scattered
     * light going up towards the exit point */
    const double di[3] = {-sin(ti), 0, -cos(ti)};
    const double dout[3] = {sin(to) * cos(phi), sin(to) * sin(phi), cos(to)};
    const double p = sss_phase_hg(g, sss_dot3(di, dout));
    const double F = fresnel_t(eta, th_i) * fresnel_t(eta, th_o);
    const double smax = 60.0 / stt;
    const int n = 20000;
    double sum = 0;
    for (int k = 0; k <= n; k++) {
        const double s = smax * k / n, z = s * cos(to), s_in = z / cos(ti);
        const double w = (k == 0 || k == n) ? 1.0 : (k % 2 ? 4.0 : 2.0);
        sum += w * exp(-stt * s_in) * exp(-stt * s);
    }
    return ss * p * F * cos(th_i) / (cos(ti) * eta * eta) * sum * smax / (3.0 * n);
}

static void halfspaceMatchesQuadratureWithRefractionAndFresnel(void **state)
{
    (void)state;
    const double n[3] = {0, 0, 1}, eta = 1.3;
    const double cases[][4] = {{0.0, 0.0, 0.0, 0.0}, {0.6, 0.2, 1.0, 0.5}, {1.2, 0.9, 3.0, -0.3}, {0.3, 1.4, 0.4, 0.8}};
    for (size_t i = 0; i < 4; i++) {
        const double ti = cases[i][0], to = cases[i][1], phi = cases[i][2], g = cases[i][3];
        const double wi[3] = {sin(ti), 0, cos(ti)};
        const double wo[3] = {sin(to) * cos(phi), sin(to) * sin(phi), cos(to)};
        sss_ss_geom geo;
        assert_int_equal(sss_ss_geometry(n, wi, wo, eta, 1, &geo), 1);
        const double got = sss_ss_halfspace(1.7, 2.3, g, &geo), want = jensen_quadrature(1.7, 2.3, g, eta, ti, to, phi);
        print_message("case %zu: closed %.12g quadrature %.12g\n", i, got, want);
        assert_true(rel_err(got, want) < 1e-9);
    }
}

static void halfspaceAtEtaOneIsTheSeedClosedForm(void **state)
{
    (void)state;
    const double n[3] = {0, 0, 1}, wi[3] = {0.6, 0, 0.8}, wo[3] = {-0.28, 0.0, 0.96};
    sss_ss_geom a, b;
    assert_int_equal(sss_ss_geometry(n, wi, wo, 1.0, 1, &a), 1);
    assert_int_equal(sss_ss_geometry(n, wi, wo, 1.0, 0, &b), 1);
    assert_true(fabs(a.boundary - 1.0) < 1e-15 && fabs(a.mu_i - b.mu_i) < 1e-15 && fabs(a.cos_phase - b.cos_phase) < 1e-15);
    const double depth[1] = {INFINITY};
    const sss_layer_stack st = stack_of(table1, depth, 1, SSS_PHASE_HG);
    for (uint32_t c = 0; c < 3; c++)
        assert_true(rel_err(sss_ss_halfspace(table1[0].sigma_s[c], table1[0].sigma_t[c], table1[0].g, &a),
                            sss_layers_closed(&st, c, &b)) < 1e-14);
    /* a light or a viewer below the surface sees nothing */
    const double below[3] = {0, 0.6, -0.8};
    assert_int_equal(sss_ss_geometry(n, below, wo, 1.3, 1, &a), 0);
}

static void albedoAtEtaOneMatchesAnalyticIntegral(void **state)
{
    (void)state;
    /* isotropic, η = 1: 2π ∫₀¹ ω/(4π) μ/(1+μ) dμ = (ω/2)(1 − ln 2) */
    const double omega = 0.8;
    assert_true(rel_err(sss_ss_albedo(0.8, 1.0, 0.0, 1.0), 0.5 * omega * (1.0 - log(2.0))) < 1e-6);
    /* Fresnel at both crossings only removes light */
    assert_true(sss_ss_albedo(0.8, 1.0, 0.0, 1.3) < sss_ss_albedo(0.8, 1.0, 0.0, 1.0));
    /* forward scattering sends the light down, away from the viewer */
    assert_true(sss_ss_albedo(0.8, 1.0, 0.8, 1.3) < sss_ss_albedo(0.8, 1.0, 0.0, 1.3));
}

static void tauClampsPathsAboveALayer(void **state)
{
    (void)state;
    const double depth[3] = {0.3, 0.8, INFINITY};
    sss_layer ly[3] = {table1[0], table1[1], table1[2]};
    ly[2].sigma_t[0] = 1e6;
    const sss_layer_stack st = stack_of(ly, depth, 3, SSS_PHASE_HG);
    const double mu = 0.5;
    /* a point in the first layer: the layers below add nothing (Eq. 12's
     * second term would go negative without the clamp) */
    assert_true(rel_err(sss_layers_tau(&st, 0, 0.2, mu), 2.6 * 0.2 / mu) < 1e-14);
    /* a point in the second layer: all of the first, part of the second */
    assert_true(rel_err(sss_layers_tau(&st, 0, 0.5, mu), (2.6 * 0.3 + 6.6 * 0.2) / mu) < 1e-14);
    assert_int_equal(sss_layers_find(&st, 0.0), 0);
    assert_int_equal(sss_layers_find(&st, 0.3), 1);
    assert_int_equal(sss_layers_find(&st, 5.0), 2);
}

/* A locate that shades the light's entry for s < 0.5 mm (what the mesh
 * march reports for a shaded K: a huge optical depth), lit beyond. */
static void locate_half_shaded(void *user, uint32_t c, double s, sss_ss_point *out)
{
    sss_ss_locate_flat(user, c, s, out);
    if (s < 0.5) out->tau_light = 1e30;
}

static void segmentMarchStaysFiniteAcrossAShadowEdge(void **state)
{
    (void)state;
    const double depth[1] = {INFINITY};
    const sss_layer_stack st = stack_of(table1, depth, 1, SSS_PHASE_HG);
    const sss_ss_geom g = flat_geom(0.3, 0.2, 1.0);
    sss_ss_flat f = {&st, g.mu_i, g.mu_o};
    for (uint32_t n = 1; n <= 64; n *= 4) {
        const double lit = sss_ss_march_segments(&st, 0, &g, 4.0, n, sss_ss_locate_flat, &f);
        const double half = sss_ss_march_segments(&st, 0, &g, 4.0, n, locate_half_shaded, &f);
        const double seed = sss_ss_march(&st, 0, &g, 4.0, n, locate_half_shaded, &f);
        assert_true(isfinite(half) && half >= 0.0 && half < lit);
        assert_true(isfinite(seed) && seed >= 0.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(phaseHgIsNormalisedWithMeanCosineG),
        cmocka_unit_test(phaseSchlickIsNormalisedAndForwardForPositiveK),
        cmocka_unit_test(oneLayerMatchesSeedClosedForm),
        cmocka_unit_test(twoLayersMatchTheirClosedForm),
        cmocka_unit_test(identicalLayersGiveTheSameResultWhateverTheDepths),
        cmocka_unit_test(zeroThicknessLayerEqualsNoLayer),
        cmocka_unit_test(swappingLightAndViewIsSymmetricWithIsotropicPhase),
        cmocka_unit_test(marchConvergesToClosedFormAtFirstOrder),
        cmocka_unit_test(halfspaceMatchesQuadratureWithRefractionAndFresnel),
        cmocka_unit_test(halfspaceAtEtaOneIsTheSeedClosedForm),
        cmocka_unit_test(albedoAtEtaOneMatchesAnalyticIntegral),
        cmocka_unit_test(tauClampsPathsAboveALayer),
        cmocka_unit_test(segmentMarchStaysFiniteAcrossAShadowEdge),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
