/* halfspace_terms: the dipole's normalisation and boundary terms against
 * sss-ref on a flat half-space (docs/accuracy.md, "Model error", "What the
 * truth shows"), where geometry plays no part: a 400 × 400 × 200 mm box
 * (20 times marble's longest scattering length 1/σtr), lit and seen at the
 * centre of its top face.
 *
 *   halfspace_terms [PATHS] [SEED]       (default 20000 paths, seed 1)
 *
 * For marble and skin1 (η = 1.3, g = 0) it prints the reference's radiance
 * for light at μ_i = 1 and 0.5 (unit irradiance across the beam) towards
 * three view angles, and its total diffuse reflectance at normal incidence
 * (particles, specular part excluded), next to three forms of the dipole's
 * prediction for a flat surface,
 *     L(μ_o) = F_t(η, μ_i) μ_i F_t(η, μ_o) R / (π c):
 *   jensen      R = R_d,total of Jensen et al. 2001 (docs/physics.md §2),
 *               c = 1: the toolkit's (docs/physics.md §4);
 *   normalised  the same R, c = 1 − 2 C1(1/η), the hemispherical Fresnel
 *               transmittance of the exit, so that the radiance integrates
 *               to the dipole's exitance (pbrt-v3's SeparableBSSRDF);
 *   better      d'Eon's "A better dipole" (2012): D = (2σa + σ′s)/(3σ′t²),
 *               A = (1 + 3 C2(η))/(1 − 2 C1(η)), the exitance
 *               R = C_φ φ + C_E E with C_φ = (1 − 2 C1(η))/4 and
 *               C_E = (1 − 3 C2(η))/2, and c as `normalised`;
 * C_i the Fresnel moments ∫₀¹ F_r μ^i dμ, computed here by quadrature of
 * docs/physics.md §3's F_r (C_i(η) for light meeting the surface from
 * inside, C_i(1/η) from outside). The total diffuse reflectance predicted
 * is F_t(η, μ_i) R (1 − 2 C1(1/η)) / c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "genmesh.h"
#include "sss/dipole.h"
#include "sss/reference.h"
#include "sss/vec3.h"

/* ∫₀¹ F_r(η, μ) μ^i dμ by the midpoint rule (F_r for light arriving from
 * the side of index 1 at a boundary of relative index η). */
static double fresnel_moment(double eta, int i)
{
    const int n = 100000;
    double s = 0.0;
    for (int k = 0; k < n; k++) {
        const double mu = (k + 0.5) / n;
        s += (1.0 - sss_ft(eta, mu)) * pow(mu, i);
    }
    return s / n;
}

/* Total exitance per unit power entering, of the dipole with sources at
 * z_r and z_v = z_r + 4AD: the flux term E and the fluence term φ
 * integrated over the plane (∫ e^{−σd}/d 2πr dr = 2π e^{−σz}/σ). */
static void dipole_totals(double sa, double sps, double D, double A, double *E, double *phi)
{
    const double st = sa + sps, ap = sps / st, str = sqrt(sa / D), zr = 1.0 / st, zv = zr + 4.0 * A * D;
    *E = 0.5 * ap * (exp(-str * zr) + exp(-str * zv));
    *phi = ap / (2.0 * D * str) * (exp(-str * zr) - exp(-str * zv));
}

int main(int argc, char **argv)
{
    const uint64_t paths = argc > 1 ? strtoull(argv[1], NULL, 10) : 20000;
    const uint64_t seed = argc > 2 ? strtoull(argv[2], NULL, 10) : 1;
    sss_error err = {{0}};
    sss_mesh box;
    sss_ref_scene *sc;
    if (sss_gen_box(&box, 400.0, 400.0, 200.0, 4, 0, &err) != SSS_OK || sss_ref_scene_create(&box, 1.0, &sc, &err) != SSS_OK) {
        fprintf(stderr, "halfspace_terms: %s\n", err.msg);
        return 1;
    }
    uint32_t top = 0;
    for (uint32_t v = 0; v < box.nv; v++)
        if (box.pos[3 * v] == 0.0f && box.pos[3 * v + 1] == 0.0f && box.pos[3 * v + 2] == 100.0f) top = v;
    const double eta = 1.3;
    const double C1i = fresnel_moment(1.0 / eta, 1), C2i = fresnel_moment(1.0 / eta, 2), C1o = fresnel_moment(eta, 1);
    const double c = 1.0 - 2.0 * C1o;
    printf("eta %.2f: C1 inside %.5f, C2 inside %.5f, C1 outside %.5f; exit normalisation c = %.5f; "
           "better dipole A = %.4f (Jensen's %.4f)\n", eta, C1i, C2i, C1o, c, (1 + 3 * C2i) / (1 - 2 * C1i),
           (1 + sss_fdr(eta)) / (1 - sss_fdr(eta)));
    const char *mats[2] = {"marble", "skin1"};
    const double mus[3] = {1.0, 0.7, 0.4};
    for (int mi = 0; mi < 2; mi++) {
        sss_material mat;
        sss_ref_medium med;
        if (sss_material_preset(mats[mi], &mat, &err) != SSS_OK || sss_ref_medium_from_material(&mat, 0.0, &med, &err) != SSS_OK) {
            fprintf(stderr, "halfspace_terms: %s\n", err.msg);
            return 1;
        }
        double Rj[3], Rb[3];
        for (int ch = 0; ch < 3; ch++) {
            sss_dipole d;
            sss_dipole_init(&d, mat.sigma_a[ch], mat.sigmap_s[ch], eta);
            Rj[ch] = sss_rd_total(&d);
            const double st = mat.sigma_a[ch] + mat.sigmap_s[ch], D = (2 * mat.sigma_a[ch] + mat.sigmap_s[ch]) / (3 * st * st);
            double E, phi;
            dipole_totals(mat.sigma_a[ch], mat.sigmap_s[ch], D, (1 + 3 * C2i) / (1 - 2 * C1i), &E, &phi);
            Rb[ch] = 0.25 * (1 - 2 * C1i) * phi + 0.5 * (1 - 3 * C2i) * E;
        }
        printf("\n%s: R_d,total (Jensen) %.4f / %.4f / %.4f; better dipole %.4f / %.4f / %.4f\n", mats[mi], Rj[0], Rj[1],
               Rj[2], Rb[0], Rb[1], Rb[2]);
        printf("  %-30s %-26s %-26s %-26s %-26s\n", "quantity", "reference (± s.e.)", "jensen / ref", "normalised / ref",
               "better / ref");
        for (int k = 0; k < 6; k++) {
            /* light at μ_i = 1 or 0.5 in the x-z plane, the view at μ_o
             * across it (azimuth 90°) */
            const double mi = k < 3 ? 1.0 : 0.5, mo = mus[k % 3];
            const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {sqrt(1 - mi * mi), 0, mi}};
            const sss_ref_query q = {top, {0, sqrt(1 - mo * mo), mo}};
            sss_ref_options o = {0};
            o.seed = seed + (uint64_t)k;
            o.paths = paths;
            sss_ref_estimate e;
            if (sss_ref_queries(sc, &med, &l, &q, 1, &o, &e, NULL, &err) != SSS_OK) {
                fprintf(stderr, "halfspace_terms: %s\n", err.msg);
                return 1;
            }
            char what[40];
            snprintf(what, sizeof what, "L, light mu %.1f, view mu %.1f", mi, mo);
            printf("  %-30s", what);
            for (int ch = 0; ch < 3; ch++) printf("%s%.4f±%.4f", ch ? " " : "", e.mean[ch], e.se[ch]);
            for (int f = 0; f < 3; f++) {
                printf("  ");
                for (int ch = 0; ch < 3; ch++) {
                    const double R = f == 2 ? Rb[ch] : Rj[ch], cc = f == 0 ? 1.0 : c;
                    const double pred = sss_ft(eta, mi) * mi * sss_ft(eta, mo) * R / (SSS_PI * cc);
                    printf("%s%.3f", ch ? " / " : "", pred / e.mean[ch]);
                }
                printf("        ");
            }
            printf("\n");
        }
        const sss_ref_beam b = {{0, 0, 100}, 0.0, {0, 0, 1}};
        sss_ref_options o = {0};
        o.seed = seed + 10;
        o.paths = paths;
        sss_ref_tally mean, se;
        if (sss_ref_particles(sc, &med, &b, &o, &mean, &se, NULL, &err) != SSS_OK) {
            fprintf(stderr, "halfspace_terms: %s\n", err.msg);
            return 1;
        }
        printf("  %-30s", "diffuse reflectance, mu 1");
        for (int ch = 0; ch < 3; ch++) printf("%s%.4f±%.4f", ch ? " " : "", mean.front[ch], se.front[ch]);
        for (int f = 0; f < 3; f++) {
            printf("  ");
            for (int ch = 0; ch < 3; ch++) {
                const double R = f == 2 ? Rb[ch] : Rj[ch], cc = f == 0 ? 1.0 : c;
                printf("%s%.3f", ch ? " / " : "", sss_ft(eta, 1.0) * R * (1 - 2 * C1o) / cc / mean.front[ch]);
            }
            printf("        ");
        }
        printf("\n");
    }
    sss_ref_scene_destroy(sc);
    sss_mesh_free(&box);
    return 0;
}
