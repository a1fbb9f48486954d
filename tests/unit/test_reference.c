/* test_reference.c: the path-traced reference (sss/reference.h) against
 * results that are exact for the radiative transfer equation, each with a
 * small fixed budget and a bound of a few standard errors
 * (docs/reference.md §5 lists the tables and where their numbers come from):
 *
 *  - Chandrasekhar's H-function for isotropic scattering, solved here from
 *    its closed form (docs/reference.md §5.1), against his tabulated
 *    H(1) = 2.9078 (ω = 1), 1.8501 (ω = 0.9), 1.2513 (ω = 0.5);
 *  - the total diffuse reflectance of an index-matched half-space,
 *    1 − H(μ₀) √(1 − ω), for three albedos at once (particles);
 *  - the radiance it reflects, ω μ₀ H(μ) H(μ₀) / (4π (μ + μ₀)) (the radiance
 *    estimator, every order of scattering);
 *  - its single scattering, ω p μ₀ / (μ₀ + μ) at η = 1 and its refracted
 *    form at η = 1.3 (the next-event estimate through the boundary);
 *  - the single scattering of a point light near it (η = 1, a quadrature
 *    along the view ray), and of a far one at η = 1.3 (the closed form);
 *  - a purely absorbing slab against Beer–Lambert with the Fresnel series of
 *    its internal reflections;
 *  - energy conservation on a closed sphere;
 *  - reciprocity of the reflected radiance of a flat slab;
 *  - a white furnace under a uniform sky;
 *  - results independent of the thread count.
 * The half-space is a box far larger than the diffusion length, lit and
 * seen at the centre of its top face, whose vertex normals there are the
 * face's own. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "genmesh.h"
#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/reference.h"
#include "sss/single.h"
#include "sss/vec3.h"

/* ---- Chandrasekhar's H-function for isotropic scattering ----
 * ln H(μ) = −(μ/π) ∫₀^{π/2} ln(1 − ω t cot t) / (cos² t + μ² sin² t) dt
 * (Chandrasekhar, Radiative Transfer, 1950), by the midpoint rule on 2·10⁵
 * cells: the integrand is smooth but for ln t² at t → 0 when ω = 1, which
 * the rule integrates to ~1e-5 of a cell. */
static double chandrasekhar_h(double mu, double omega)
{
    const int n = 200000;
    const double h = 0.5 * SSS_PI / n;
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        const double t = (i + 0.5) * h, c = cos(t), sn = sin(t);
        s += log(1.0 - omega * t * c / sn) / (c * c + mu * mu * sn * sn);
    }
    return exp(-mu / SSS_PI * s * h);
}

static void check_within(const char *what, double got, double se, double want, double k)
{
    printf("  %-44s %.5f ± %.5f  (exact %.5f, %+.2f se)\n", what, got, se, want, se > 0 ? (got - want) / se : 0.0);
    if (!(fabs(got - want) <= k * se)) fail_msg("%s: %.6f ± %.6f, exact %.6f (%.1f standard errors)", what, got, se, want, (got - want) / se);
}

static void chandrasekharHMatchesTabulatedValues(void **state)
{
    (void)state;
    /* Chandrasekhar's tabulated H(1) (Radiative Transfer, 1950;
     * docs/reference.md §5.1) */
    assert_true(fabs(chandrasekhar_h(1.0, 1.0) - 2.9078) < 1e-4);
    assert_true(fabs(chandrasekhar_h(1.0, 0.9) - 1.8501) < 1e-4);
    assert_true(fabs(chandrasekhar_h(1.0, 0.5) - 1.2513) < 1e-4);
    /* and H(0) = 1 whatever ω */
    assert_true(fabs(chandrasekhar_h(0.0, 0.7) - 1.0) < 1e-12);
}

/* A box of 400 × 400 × 200 mm with 4 × 4 quads a face: the top face's
 * centre vertex (0, 0, 100) has the face's normal, and a walk from there
 * reaches the sides or the bottom with a probability far below the bounds
 * below for every medium used here (diffusion length ≤ 12 mm). */
static sss_mesh g_box;
static sss_ref_scene *g_half;
static uint32_t g_top; /* the vertex at the top face's centre */

static int setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    if (sss_gen_box(&g_box, 400.0, 400.0, 200.0, 4, 0, &err) != SSS_OK) return -1;
    if (sss_ref_scene_create(&g_box, 1.0, &g_half, &err) != SSS_OK) return -1;
    double best = INFINITY;
    for (uint32_t v = 0; v < g_box.nv; v++) {
        const float *p = &g_box.pos[3 * (size_t)v];
        const double d = fabs(p[0]) + fabs(p[1]) + fabs(p[2] - 100.0);
        if (d < best) best = d, g_top = v;
    }
    return best == 0.0 ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    sss_ref_scene_destroy(g_half);
    sss_mesh_free(&g_box);
    return 0;
}

/* Three albedos in one medium, each channel with its own σt, so that the
 * channel-mixture flights are checked too (the half-space's reflectance
 * depends on ω alone). */
static const double k_omega[3] = {0.5, 0.9, 0.99};
static const double k_sigma_t[3] = {1.0, 2.0, 0.5};

static sss_ref_medium albedo_medium(double eta, double g)
{
    sss_ref_medium m;
    memset(&m, 0, sizeof m);
    for (int c = 0; c < 3; c++) {
        m.sigma_s[c] = k_omega[c] * k_sigma_t[c];
        m.sigma_a[c] = (1.0 - k_omega[c]) * k_sigma_t[c];
    }
    m.g = g;
    m.eta = eta;
    return m;
}

static void halfSpaceReflectanceMatchesChandrasekhar(void **state)
{
    (void)state;
    const sss_ref_medium m = albedo_medium(1.0, 0.0);
    const sss_ref_beam b = {{0.0, 0.0, 100.0}, 0.0, {0.0, 0.0, 1.0}}; /* a pencil beam at normal incidence */
    sss_ref_options o = {0};
    o.seed = 7;
    o.paths = 20000;
    sss_ref_tally mean, se;
    sss_ref_stats st;
    sss_error err = {{0}};
    assert_int_equal(sss_ref_particles(g_half, &m, &b, &o, &mean, &se, &st, &err), SSS_OK);
    assert_true(mean.incident == 1.0);
    for (int c = 0; c < 3; c++) {
        char what[64];
        snprintf(what, sizeof what, "half-space reflectance, omega %.2f", k_omega[c]);
        /* exits through the top face; the specular part is 0 at η = 1 */
        assert_true(mean.specular[c] == 0.0);
        check_within(what, mean.front[c], se.front[c], 1.0 - chandrasekhar_h(1.0, k_omega[c]) * sqrt(1.0 - k_omega[c]), 4.0);
        assert_true(mean.lost[c] == 0.0);
    }
}

static sss_ref_estimate query_light(const sss_ref_medium *m, const sss_ref_light *l, const double view[3],
                                    uint64_t paths, uint64_t seed, uint32_t max_order, int threads);

static sss_ref_estimate query(const sss_ref_medium *m, const double light[3], const double view[3], uint64_t paths,
                              uint64_t seed, uint32_t max_order, int threads)
{
    const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {light[0], light[1], light[2]}};
    return query_light(m, &l, view, paths, seed, max_order, threads);
}

static sss_ref_estimate query_light(const sss_ref_medium *m, const sss_ref_light *l, const double view[3],
                                    uint64_t paths, uint64_t seed, uint32_t max_order, int threads)
{
    const sss_ref_query q = {g_top, {view[0], view[1], view[2]}};
    sss_ref_options o = {0};
    o.seed = seed;
    o.paths = paths;
    o.max_order = max_order;
    o.threads = threads;
    sss_ref_estimate e;
    sss_ref_stats st;
    sss_error err = {{0}};
    if (sss_ref_queries(g_half, m, l, &q, 1, &o, &e, &st, &err) != SSS_OK) fail_msg("%s", err.msg);
    if (st.leaks || st.truncated) fail_msg("%llu leaks, %llu truncated", (unsigned long long)st.leaks, (unsigned long long)st.truncated);
    return e;
}

static void dir_at(double mu, double azimuth, double d[3])
{
    const double s = sqrt(1.0 - mu * mu);
    d[0] = s * cos(azimuth);
    d[1] = s * sin(azimuth);
    d[2] = mu;
}

static void halfSpaceRadianceMatchesChandrasekhar(void **state)
{
    (void)state;
    const sss_ref_medium m = albedo_medium(1.0, 0.0);
    const double cases[2][2] = {{1.0, 1.0}, {0.5, 0.8}}; /* μ₀ of the light, μ of the view */
    for (int i = 0; i < 2; i++) {
        const double mu0 = cases[i][0], mu = cases[i][1];
        double l[3], v[3];
        dir_at(mu0, 0.0, l);
        dir_at(mu, 2.0, v);
        const sss_ref_estimate e = query(&m, l, v, 6000, 11 + i, 0, 0);
        for (int c = 0; c < 3; c++) {
            const double w = k_omega[c];
            /* unit irradiance across the beam: μ₀ on the surface */
            const double L = w * mu0 * chandrasekhar_h(mu, w) * chandrasekhar_h(mu0, w) / (4.0 * SSS_PI * (mu + mu0));
            char what[80];
            snprintf(what, sizeof what, "half-space radiance mu0 %.1f mu %.1f omega %.2f", mu0, mu, w);
            check_within(what, e.mean[c], e.se[c], L, 4.0);
        }
    }
}

/* Single scattering in a flat half-space, light at μ₀ (outside), view at μ:
 * the light refracts to μ′₀ inside with irradiance F_t cos θ₀ / μ′₀ across
 * its beam, the view ray to μ′; a collision at depth z scatters p(cos θ′)
 * (θ′ between the refracted directions) and both rays are attenuated, so
 *     L⁽¹⁾ = ω p F_t(μ₀) F_t(μ) μ₀ / (η² (μ′₀ + μ′)),
 * which at η = 1 is ω p μ₀ / (μ₀ + μ) (Jensen et al. 2001, eq. 4–5, for a
 * flat surface; docs/reference.md §5.4). */

/* D = 0: the directional light; D > 0: a point light at distance D along
 * it with intensity D² (unit irradiance), whose answer tends to the same. */
static void single_scattering_case(double eta, double g, double mu0, double mu, double az, uint64_t seed, double D)
{
    const sss_ref_medium m = albedo_medium(eta, g);
    double l[3], v[3];
    dir_at(mu0, 0.0, l);
    dir_at(mu, az, v);
    const sss_ref_light pl = {.kind = SSS_REF_POINT, .pos = {D * l[0], D * l[1], 100.0 + D * l[2]}, .intensity = D * D};
    const sss_ref_estimate e = D > 0 ? query_light(&m, &pl, v, 6000, seed, 1, 0) : query(&m, l, v, 6000, seed, 1, 0);
    /* refracted propagation directions inside: the light's going down, the
     * view's (reversed) going down too */
    const double s0 = sqrt(1.0 - mu0 * mu0) / eta, s1 = sqrt(1.0 - mu * mu) / eta;
    const double mu0p = sqrt(1.0 - s0 * s0), mup = sqrt(1.0 - s1 * s1);
    /* the light propagates along (−s0 cos 0, −s0 sin 0, −μ′₀); the scattered
     * light towards the eye along (s1 cos az, s1 sin az, μ′) */
    const double p = sss_phase_hg(g, -s0 * s1 * cos(az) - mu0p * mup);
    /* libsss's single scattering (sss/single.h) is the same closed form */
    const double nz[3] = {0.0, 0.0, 1.0};
    sss_ss_geom geo;
    assert_int_equal(sss_ss_geometry(nz, l, v, eta, 1, &geo), 1);
    for (int c = 0; c < 3; c++) {
        const double L = k_omega[c] * p * sss_ft(eta, mu0) * sss_ft(eta, mu) * mu0 / (eta * eta * (mu0p + mup));
        assert_true(fabs(sss_ss_halfspace(k_omega[c], 1.0, g, &geo) - L) < 1e-12 * L);
        char what[96];
        snprintf(what, sizeof what, D > 0 ? "far point light, eta %.1f g %.1f omega %.2f" : "single scattering eta %.1f g %.1f omega %.2f",
                 eta, g, k_omega[c]);
        check_within(what, e.mean[c], e.se[c], L, 4.0);
    }
}

static void singleScatteringMatchesClosedForm(void **state)
{
    (void)state;
    single_scattering_case(1.0, 0.0, 0.7, 0.9, 2.5, 21, 0.0);
    single_scattering_case(1.0, 0.6, 0.6, 0.8, 3.0, 22, 0.0);
    single_scattering_case(1.3, 0.6, 0.5, 0.8, 2.8, 23, 0.0);
}

/* A point light near the half-space at η = 1: single scattering along the
 * view ray, at depth position s (distance inside), from light that comes
 * straight from P through the medium:
 *     L⁽¹⁾ = ∫₀^∞ σs p(cos θ) e^{−σt s} I e^{−σt t_l} / |P − z|² ds,
 * z = x₀ − s ω_o, t_l the light's length inside (depth · |P − z| / (P − z)_z),
 * θ between the light's travel (z − P) and ω_o; integrated here by the
 * midpoint rule (docs/reference.md §5.4). The next-event estimate's
 * positional Jacobian r²|de/dω| is |P − z|² there. */
static void pointLightNearHalfSpaceMatchesSingleScatteringIntegral(void **state)
{
    (void)state;
    const double g = 0.4;
    const sss_ref_medium m = albedo_medium(1.0, g);
    const double P[3] = {30.0, -10.0, 100.0 + 25.0}, I = 625.0; /* 1 unit of irradiance 25 mm above */
    double v[3];
    dir_at(0.8, 2.6, v);
    const sss_ref_light l = {.kind = SSS_REF_POINT, .pos = {P[0], P[1], P[2]}, .intensity = I};
    const sss_ref_estimate e = query_light(&m, &l, v, 6000, 31, 1, 0);
    for (int c = 0; c < 3; c++) {
        const double st = k_sigma_t[c], ss = k_omega[c] * st, smax = 40.0 / st;
        const int n = 200000;
        double sum = 0.0;
        for (int i = 0; i < n; i++) {
            const double sd = (i + 0.5) * smax / n;
            const double z[3] = {-sd * v[0], -sd * v[1], 100.0 - sd * v[2]};
            double d[3];
            sss_sub3(d, z, P); /* the light's travel */
            const double r = sqrt(sss_dot3(d, d)), depth = 100.0 - z[2], tl = depth * r / (P[2] - z[2]);
            const double ct = sss_dot3(d, v) / r;
            sum += ss * sss_phase_hg(g, ct) * exp(-st * (sd + tl)) * I / (r * r);
        }
        char what[96];
        snprintf(what, sizeof what, "near point light, single scattering, omega %.2f", k_omega[c]);
        check_within(what, e.mean[c], e.se[c], sum * smax / n, 4.0);
    }
}

/* A point light far away (distance D = 10⁴ mm, intensity D²: unit
 * irradiance) gives what the directional light gives, at η = 1.3 where the
 * light refracts: the same closed form of single scattering, within the
 * standard error and the light's spread over the lit part (∼ 1/D). */
static void farPointLightMatchesDirectionalLight(void **state)
{
    (void)state;
    single_scattering_case(1.3, 0.6, 0.5, 0.8, 2.8, 23, 1e4);
}

/* A point light inside the mesh, or with no intensity, is refused. */
static void pointLightInsideOrDarkIsRefused(void **state)
{
    (void)state;
    const sss_ref_medium m = albedo_medium(1.3, 0.0);
    const sss_ref_query q = {g_top, {0.0, 0.0, 1.0}};
    sss_ref_options o = {0};
    o.paths = 16;
    sss_ref_estimate e;
    sss_ref_stats st;
    sss_error err = {{0}};
    const sss_ref_light inside = {.kind = SSS_REF_POINT, .pos = {0.0, 0.0, 50.0}, .intensity = 1.0};
    assert_int_equal(sss_ref_queries(g_half, &m, &inside, &q, 1, &o, &e, &st, &err), SSS_ERR_ARG);
    assert_non_null(strstr(err.msg, "inside the mesh"));
    const sss_ref_light dark = {.kind = SSS_REF_POINT, .pos = {0.0, 0.0, 150.0}, .intensity = 0.0};
    assert_int_equal(sss_ref_queries(g_half, &m, &dark, &q, 1, &o, &e, &st, &err), SSS_ERR_ARG);
}

static void absorbingSlabFollowsBeerLambert(void **state)
{
    (void)state;
    /* a 2 mm slab, 400 mm wide, lit at its centre at μ = 0.6 */
    sss_mesh slab;
    sss_ref_scene *s;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_box(&slab, 400.0, 400.0, 2.0, 4, 0, &err), SSS_OK);
    assert_int_equal(sss_ref_scene_create(&slab, 1.0, &s, &err), SSS_OK);
    const double sigma_a[3] = {0.1, 0.5, 1.0}, d = 2.0, mu = 0.6;
    for (int k = 0; k < 2; k++) {
        const double eta = k ? 1.3 : 1.0;
        sss_ref_medium m;
        memset(&m, 0, sizeof m);
        for (int c = 0; c < 3; c++) m.sigma_a[c] = sigma_a[c];
        m.eta = eta;
        sss_ref_beam b = {{0.0, 0.0, 1.0}, 0.0, {0.0, 0.0, 0.0}};
        dir_at(mu, 0.0, b.dir);
        sss_ref_options o = {0};
        o.seed = 31 + k;
        o.paths = 20000;
        sss_ref_tally mean, se;
        assert_int_equal(sss_ref_particles(s, &m, &b, &o, &mean, &se, NULL, &err), SSS_OK);
        /* R: Fresnel reflectance at μ (the same inside at the refracted
         * angle); τ: one crossing at the refracted μ′; the internal
         * reflections sum to a geometric series */
        const double R = 1.0 - sss_ft(eta, mu), sp = sqrt(1.0 - mu * mu) / eta, mup = sqrt(1.0 - sp * sp);
        for (int c = 0; c < 3; c++) {
            const double tau = exp(-sigma_a[c] * d / mup);
            const double T = (1 - R) * (1 - R) * tau / (1 - R * R * tau * tau);
            const double Rback = (1 - R) * (1 - R) * R * tau * tau / (1 - R * R * tau * tau);
            char what[80];
            snprintf(what, sizeof what, "slab transmittance eta %.1f sigma_a %.1f", eta, sigma_a[c]);
            check_within(what, mean.back[c], se.back[c], T, 4.0);
            snprintf(what, sizeof what, "slab reflectance eta %.1f sigma_a %.1f", eta, sigma_a[c]);
            check_within(what, mean.specular[c] + mean.front[c], se.specular[c] + se.front[c], R + Rback, 4.0);
        }
    }
    sss_ref_scene_destroy(s);
    sss_mesh_free(&slab);
}

static void closedSphereConservesEnergy(void **state)
{
    (void)state;
    /* a 10 mm sphere (2562 vertices) of skin1 with a forward phase function,
     * under a beam wider than it */
    sss_mesh sph;
    sss_ref_scene *s;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&sph, 10.0, 4, &err), SSS_OK);
    assert_int_equal(sss_ref_scene_create(&sph, 1.0, &s, &err), SSS_OK);
    sss_material mat;
    assert_int_equal(sss_material_preset("skin1", &mat, &err), SSS_OK);
    sss_ref_medium m;
    assert_int_equal(sss_ref_medium_from_material(&mat, 0.8, &m, &err), SSS_OK);
    const sss_ref_beam b = {{0.0, 0.0, 0.0}, 10.5, {0.3, -0.2, 0.9}};
    sss_ref_options o = {0};
    o.seed = 41;
    o.paths = 16000;
    sss_ref_tally mean, se;
    assert_int_equal(sss_ref_particles(s, &m, &b, &o, &mean, &se, NULL, &err), SSS_OK);
    for (int c = 0; c < 3; c++) {
        char what[64];
        snprintf(what, sizeof what, "sphere: reflected+transmitted+absorbed, ch %d", c);
        check_within(what, mean.balance[c] / mean.incident, se.balance[c] / mean.incident, 1.0, 4.0);
        assert_true(mean.lost[c] == 0.0);
        /* every part carries some of it */
        assert_true(mean.specular[c] > 0.0 && mean.absorbed[c] > 0.0 && mean.front[c] > 0.0 && mean.back[c] > 0.0);
    }
    sss_ref_scene_destroy(s);
    sss_mesh_free(&sph);
}

/* The reflected radiance of a large flat slab lit uniformly is a BRDF times
 * the irradiance on it: f(ω_l, ω_v) = L(ω_v; ω_l) / μ_l must not change
 * when light and view swap (Helmholtz reciprocity), here with refraction
 * (η = 1.3) and a forward phase function, where the next-event estimate's
 * refraction Jacobian is asymmetric in the two directions. */
static void flatSlabRadianceIsReciprocal(void **state)
{
    (void)state;
    const sss_ref_medium m = albedo_medium(1.3, 0.5);
    double a[3], b[3];
    dir_at(1.0, 0.0, a);
    dir_at(0.45, 1.0, b);
    const sss_ref_estimate ab = query(&m, a, b, 6000, 51, 0, 0); /* light a, view b */
    const sss_ref_estimate ba = query(&m, b, a, 6000, 52, 0, 0);
    for (int c = 0; c < 3; c++) {
        const double f1 = ab.mean[c] / a[2], f2 = ba.mean[c] / b[2];
        const double e = sqrt(ab.se[c] / a[2] * ab.se[c] / a[2] + ba.se[c] / b[2] * ba.se[c] / b[2]);
        char what[64];
        snprintf(what, sizeof what, "reciprocity, omega %.2f: f(a,b) - f(b,a)", k_omega[c]);
        check_within(what, f1 - f2, e, 0.0, 4.0);
    }
}

/* A white furnace: a closed sphere of non-absorbing medium (η = 1.3,
 * forward scattering) under a uniform sky of radiance 1. Every path ends by
 * leaving, each carrying F_t/η² in and η² out, so the radiance through the
 * surface is F_t(η, n·ω_o) exactly, path by path (the rest of the sky's 1
 * is the surface reflection, which the estimator leaves out); with
 * absorption it is less. Checks the environment light, the boundary's
 * radiance law and the mesh's closedness (no path lost). */
static void uniformSkyFurnaceGivesFresnelTransmittance(void **state)
{
    (void)state;
    sss_mesh sph;
    sss_ref_scene *s;
    sss_error err = {{0}};
    assert_int_equal(sss_gen_sphere(&sph, 5.0, 3, &err), SSS_OK);
    assert_int_equal(sss_ref_scene_create(&sph, 1.0, &s, &err), SSS_OK);
    const sss_ref_light sky = {.kind = SSS_REF_ENVIRONMENT};
    sss_ref_medium m;
    memset(&m, 0, sizeof m);
    for (int c = 0; c < 3; c++) m.sigma_s[c] = 1.0;
    m.g = 0.5;
    m.eta = 1.3;
    /* vertex 7, seen 40 degrees or so off its normal */
    const float *n = &sph.nrm[3 * 7];
    const double view[3] = {n[0] + 0.5, n[1] - 0.3, n[2] + 0.4};
    const sss_ref_query q = {7, {view[0], view[1], view[2]}};
    const double ft = sss_ft(1.3, (n[0] * view[0] + n[1] * view[1] + n[2] * view[2]) / sqrt(sss_dot3(view, view)));
    sss_ref_options o = {0};
    o.seed = 71;
    o.paths = 400;
    sss_ref_estimate e;
    sss_ref_stats st;
    assert_int_equal(sss_ref_queries(s, &m, &sky, &q, 1, &o, &e, &st, &err), SSS_OK);
    assert_true(ft > 0.5);
    for (int c = 0; c < 3; c++) {
        printf("  furnace, grey: %.12f (F_t %.12f), s.e. %.2g\n", e.mean[c], ft, e.se[c]);
        assert_true(fabs(e.mean[c] - ft) < 1e-9);
    }
    assert_true(st.leaks == 0 && st.truncated == 0);
    /* channels of different σs: the hero channel's weights make each path's
     * value vary (docs/reference.md §3) but not their sum over the channels,
     * which is C F_t path by path when nothing is absorbed (the balance
     * heuristic's weights f_c / mean p sum to C when every f_c = p_c); each
     * mean stays F_t */
    for (int c = 0; c < 3; c++) m.sigma_s[c] = 0.5 + 0.5 * c;
    o.paths = 8000;
    assert_int_equal(sss_ref_queries(s, &m, &sky, &q, 1, &o, &e, NULL, &err), SSS_OK);
    assert_true(fabs(e.mean[0] + e.mean[1] + e.mean[2] - 3.0 * ft) < 1e-9);
    for (int c = 0; c < 3; c++) {
        char what[64];
        snprintf(what, sizeof what, "furnace, sigma_s %.1f", m.sigma_s[c]);
        check_within(what, e.mean[c], e.se[c], ft, 4.0);
    }
    /* absorbing: darker, still positive */
    for (int c = 0; c < 3; c++) m.sigma_a[c] = 0.05;
    assert_int_equal(sss_ref_queries(s, &m, &sky, &q, 1, &o, &e, NULL, &err), SSS_OK);
    for (int c = 0; c < 3; c++) assert_true(e.mean[c] > 0.1 * ft && e.mean[c] < ft - 5.0 * e.se[c]);
    sss_ref_scene_destroy(s);
    sss_mesh_free(&sph);
}

static void resultDoesNotDependOnThreadCount(void **state)
{
    (void)state;
    const sss_ref_medium m = albedo_medium(1.3, 0.3);
    double l[3], v[3];
    dir_at(0.8, 0.0, l);
    dir_at(0.9, 1.5, v);
    const sss_ref_estimate e1 = query(&m, l, v, 300, 61, 0, 1);
    const sss_ref_estimate e2 = query(&m, l, v, 300, 61, 0, 2);
    const sss_ref_estimate e3 = query(&m, l, v, 300, 62, 0, 2);
    assert_memory_equal(&e1, &e2, sizeof e1);
    assert_true(memcmp(&e1, &e3, sizeof e1) != 0); /* the seed does change it */
}

/* ---- a material field (docs/reference.md §3.1) ---- */

/* The half-space's medium with a field: inside σa = ka × the base's + da
 * (1/mm) and σs = ks × the base's, the rest frame the scene's (mm per
 * unit 1). */
static sss_hetero field_of(const sss_ref_medium *base, const sss_field *f, double ka, double da, double ks)
{
    sss_hetero h;
    memset(&h, 0, sizeof h);
    h.field = *f;
    for (int c = 0; c < 3; c++) {
        h.inside.sigma_a[c] = ka * base->sigma_a[c] + da;
        h.inside.sigmap_s[c] = ks * base->sigma_s[c]; /* g = 0: σ′s = σs */
    }
    h.inside.eta = base->eta;
    h.xf[0] = h.xf[5] = h.xf[10] = 1.0;
    return h;
}

static void check_same(const char *what, const sss_ref_estimate *a, const sss_ref_estimate *b, double k)
{
    for (int c = 0; c < 3; c++) {
        const double se = sqrt(a->se[c] * a->se[c] + b->se[c] * b->se[c]);
        printf("  %-44s ch %d: %.5f against %.5f (%+.2f se)\n", what, c, a->mean[c], b->mean[c],
               (a->mean[c] - b->mean[c]) / se);
        if (!(fabs(a->mean[c] - b->mean[c]) <= k * se))
            fail_msg("%s, channel %d: %.6f against %.6f (%.1f standard errors)", what, c, a->mean[c], b->mean[c],
                     (a->mean[c] - b->mean[c]) / se);
    }
}

/* A constant field c is the homogeneous blend (1 − c) base + c inside,
 * through the tracking's null collisions and the ratio-tracked next-event
 * transmittance; at c = 0 and c = 1 it is either material. Each pair is two
 * independent estimates, compared by their combined standard error. */
static void constantFieldTracksLikeTheHomogeneousBlend(void **state)
{
    (void)state;
    const sss_ref_medium base = albedo_medium(1.3, 0.0);
    double l[3], v[3];
    dir_at(0.8, 0.0, l);
    dir_at(0.9, 2.0, v);
    const double cs[3] = {0.0, 0.4, 1.0};
    for (int i = 0; i < 3; i++) {
        const sss_field f = {.kind = SSS_FIELD_CONSTANT, .value = cs[i]};
        const sss_hetero h = field_of(&base, &f, 3.0, 0.0, 0.5);
        sss_ref_medium het = base, blend = base;
        het.hetero = &h;
        for (int c = 0; c < 3; c++) {
            blend.sigma_a[c] = (1.0 - cs[i]) * base.sigma_a[c] + cs[i] * h.inside.sigma_a[c];
            blend.sigma_s[c] = (1.0 - cs[i]) * base.sigma_s[c] + cs[i] * h.inside.sigmap_s[c];
        }
        const sss_ref_estimate a = query(&het, l, v, 6000, 41 + i, 0, 0), b = query(&blend, l, v, 6000, 51 + i, 0, 0);
        char what[80];
        snprintf(what, sizeof what, "constant field c = %.1f against the blend", cs[i]);
        check_same(what, &a, &b, 4.0);
        /* the particle tracer's absorption tally is the homogeneous closed form: refused */
        sss_ref_beam beam = {{0.0, 0.0, -1.0}, 0.0, {0.0, 0.0, 0.0}};
        sss_ref_options o = {0};
        o.paths = 10;
        sss_ref_tally mean;
        sss_error err = {{0}};
        assert_int_equal(sss_ref_particles(g_half, &het, &beam, &o, &mean, NULL, NULL, &err), SSS_ERR_UNSUPPORTED);
        assert_non_null(strstr(err.msg, "material field"));
    }
}

/* Single scattering (max_order 1, η = 1, g = 0) under a flat surface
 * with an absorbing stratum on top: σs unchanged, σt1 = σt + 2/mm down to
 * depth t = 0.5 mm, σt below. With K = 1/μ₀ + 1/μ the light and view
 * paths to depth z attenuate together, so
 *     L⁽¹⁾ = p σs / μ · [(1 − e^{−σt1 K t}) / (σt1 K) + e^{−σt1 K t} / (σt K)]
 * (docs/reference.md §5.4 with the depth integral split at t): the
 * tracked flights and the ratio-tracked next-event transmittance must
 * reproduce a spatially varying σt, within 4 standard errors per channel. */
static void absorbingStratumFollowsTheSingleScatteringIntegral(void **state)
{
    (void)state;
    const sss_ref_medium base = albedo_medium(1.0, 0.0);
    const double mu0 = 0.8, mu = 0.9, t = 0.5, da = 2.0;
    double l[3], v[3];
    dir_at(mu0, 0.0, l);
    dir_at(mu, 2.0, v);
    const sss_field top = {.kind = SSS_FIELD_LAYERS, .normal = {0, 0, 1}, .offset_mm = 100.0 - t, .thickness_mm = t};
    const sss_hetero h = field_of(&base, &top, 1.0, da, 1.0);
    sss_ref_medium m = base;
    m.hetero = &h;
    const sss_ref_estimate e = query(&m, l, v, 8000, 71, 1, 0);
    const double K = 1.0 / mu0 + 1.0 / mu, p = 1.0 / (4.0 * SSS_PI);
    for (int c = 0; c < 3; c++) {
        const double st = base.sigma_a[c] + base.sigma_s[c], st1 = st + da, a = st1 * K * t;
        const double L = p * base.sigma_s[c] / mu * (-expm1(-a) / (st1 * K) + exp(-a) / (st * K));
        char what[80];
        snprintf(what, sizeof what, "single scattering under a stratum, omega %.2f", k_omega[c]);
        check_within(what, e.mean[c], e.se[c], L, 4.0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(chandrasekharHMatchesTabulatedValues),
        cmocka_unit_test(halfSpaceReflectanceMatchesChandrasekhar),
        cmocka_unit_test(halfSpaceRadianceMatchesChandrasekhar),
        cmocka_unit_test(singleScatteringMatchesClosedForm),
        cmocka_unit_test(pointLightNearHalfSpaceMatchesSingleScatteringIntegral),
        cmocka_unit_test(farPointLightMatchesDirectionalLight),
        cmocka_unit_test(pointLightInsideOrDarkIsRefused),
        cmocka_unit_test(absorbingSlabFollowsBeerLambert),
        cmocka_unit_test(closedSphereConservesEnergy),
        cmocka_unit_test(flatSlabRadianceIsReciprocal),
        cmocka_unit_test(uniformSkyFurnaceGivesFresnelTransmittance),
        cmocka_unit_test(resultDoesNotDependOnThreadCount),
        cmocka_unit_test(constantFieldTracksLikeTheHomogeneousBlend),
        cmocka_unit_test(absorbingStratumFollowsTheSingleScatteringIntegral),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
