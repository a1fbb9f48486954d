/* single.c: the planner's rule for single scattering (docs/layers.md §4).
 *
 * Single scattering (Jensen et al. 2001 §2.3, seed 002) is not a light
 * parameterisation like the other units of this folder: it is added at run
 * time from the material (sections MATL and PHAS) and the geometry, for
 * every light, so it has no bake pass and claims no light. What the
 * planner decides is whether an object needs it at all: when the
 * single-scattering albedo of the material's half-space is a large enough
 * share of its total reflectance, leaving it out darkens the picture by
 * more than the dipole's own error. The choice is the effect bit
 * SSS_FX_SINGLE of the file's effect set.
 */
#include "effects/effect.h"

#include <stdio.h>

#include "sss/single.h"

double sss_single_share(const sss_material *m, uint32_t channels, uint32_t *channel)
{
    double best = 0.0;
    if (channel) *channel = 0;
    for (uint32_t c = 0; c < channels && c < 3; c++) {
        sss_dipole d;
        if (sss_dipole_init(&d, m->sigma_a[c], m->sigmap_s[c], m->eta) != SSS_OK) continue;
        const double sigma_s = sss_material_sigma_s(m, (int)c), sigma_t = m->sigma_a[c] + sigma_s;
        /* both as radiant exitance over the irradiance, lit head-on: the
         * dipole's F_t(η, 1) R_d,total let out through the exit's c(η)
         * (docs/physics.md §4), single scattering's R_ss (sss/single.h) */
        const double R_ms = sss_ft(m->eta, 1.0) * sss_rd_total(&d) * sss_exit_norm(m->eta);
        const double R_ss = sss_ss_albedo(sigma_s, sigma_t, m->g, m->eta);
        const double share = R_ss + R_ms > 0.0 ? R_ss / (R_ss + R_ms) : 0.0;
        if (share > best) {
            best = share;
            if (channel) *channel = c;
        }
    }
    return best;
}

int sss_single_rule(const sss_material *m, uint32_t channels, int force, char *reason, size_t n)
{
    uint32_t c = 0;
    const double share = sss_single_share(m, channels, &c);
    static const char rgb[] = "RGB";
    const char ch = channels == 1 ? 'Y' : rgb[c];
    if (force)
        snprintf(reason, n, "the scene sets \"single_scattering\": %s (its share of the reflectance would be %.3f "
                 "in %c, threshold %.2f)", force > 0 ? "true" : "false", share, ch, SSS_SINGLE_SHARE_MIN);
    else if (share >= SSS_SINGLE_SHARE_MIN)
        snprintf(reason, n, "single scattering is %.3f of the reflectance of material '%s' in %c (half-space lit "
                 "head-on, g %g), at least %.2f, more than the dipole's own error", share, m->name, ch, m->g,
                 SSS_SINGLE_SHARE_MIN);
    else
        snprintf(reason, n, "single scattering is at most %.3f of the reflectance of material '%s' (%c; half-space "
                 "lit head-on, g %g), below %.2f, within the dipole's own error", share, m->name, ch, m->g,
                 SSS_SINGLE_SHARE_MIN);
    return force ? force > 0 : share >= SSS_SINGLE_SHARE_MIN;
}
