/* ownterm.c: the vertex's own term of q, split off at bake time and added
 * back at run time (sss/ownterm.h; Hao–Varshney 2004 §3.1). */
#define _DEFAULT_SOURCE /* M_PI */
#include "sss/ownterm.h"

#include <math.h>
#include <stdlib.h>

sss_result sss_own_weights(const sss_mesh *mesh, const sss_material *mat, double mm_per_unit, uint32_t channels,
                           float *w, sss_error *err)
{
    if (!mesh || !mat || !w || (channels != 1 && channels != 3) || !(mm_per_unit > 0.0) || !isfinite(mm_per_unit))
        return sss_fail(err, SSS_ERR_ARG, "own-term weights: bad argument");
    const uint32_t nv = mesh->nv;
    double *area = malloc((size_t)nv * sizeof *area + 1);
    if (!area) return sss_fail(err, SSS_ERR_NOMEM, "own-term weights: out of memory for %u vertices", nv);
    sss_mesh_vertex_areas(mesh, area);
    for (uint32_t c = 0; c < channels; c++) {
        sss_dipole dip;
        if (sss_dipole_init(&dip, mat->sigma_a[c], mat->sigmap_s[c], mat->eta) != SSS_OK) {
            free(area);
            return sss_fail(err, SSS_ERR_ARG, "own-term weights: invalid material in channel %u", c);
        }
        for (uint32_t v = 0; v < nv; v++) {
            /* the disk of the vertex's own area ΔA_o (physics sheet §2 (a):
             * a point sample at r = 0 is wrong), radius in mm */
            const double rho = sqrt(area[v] * mm_per_unit * mm_per_unit / M_PI);
            w[(size_t)v * channels + c] = area[v] > 0.0 ? (float)(sss_rd_disk(&dip, rho) / M_PI) : 0.0f;
        }
    }
    free(area);
    return SSS_OK;
}

float sss_own_transfer(float eta, const float n[3], const float d[3])
{
    /* F_t(η, c) max(0, c): the Fresnel transmittance of dipole.c's
     * sss_ft, in float, term for term as the vertex shader writes it */
    float c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
    if (!(c > 0.0f)) return 0.0f;
    if (c > 1.0f) c = 1.0f;
    float g2 = eta * eta - 1.0f + c * c;
    if (g2 < 0.0f) return 0.0f;
    float g = sqrtf(g2);
    float a = (g - c) / (g + c);
    float b = (c * (g + c) - 1.0f) / (c * (g - c) + 1.0f);
    float fr = fminf(0.5f * a * a * (1.0f + b * b), 1.0f);
    return (1.0f - fr) * c;
}

void sss_own_add(const float *w, const float *nrm, uint32_t nv, uint32_t channels, float eta, const double d[3],
                 const uint8_t *lit, float *out)
{
    const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nv >= 16384)
#endif
    for (int64_t v = 0; v < (int64_t)nv; v++) {
        if (lit && !lit[v]) continue;
        const float g = sss_own_transfer(eta, nrm + 3 * (size_t)v, df);
        if (g == 0.0f) continue;
        for (uint32_t c = 0; c < channels; c++) out[(size_t)v * channels + c] += w[(size_t)v * channels + c] * g;
    }
}
