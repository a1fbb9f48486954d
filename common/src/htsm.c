/* htsm.c: seed 000's run-time estimator on the CPU (sss/htsm.h,
 * docs/heterogeneous.md §9): the oracle the viewer's GPU pass is tested
 * against, and the definition of what that pass computes. */
#include "sss/htsm.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/vec3.h"

sss_result sss_htsm_map_init(sss_htsm_map *m, uint32_t size, sss_error *err)
{
    memset(m, 0, sizeof *m);
    if (size < 2 || size > 4096 || (size & (size - 1)))
        return sss_fail(err, SSS_ERR_ARG, "light-space map size %u is not a power of two in [2, 4096]", size);
    m->size = size;
    m->ref_w = 1.0;
    for (uint32_t s = size; s >= 1 && m->levels < SSS_HTSM_MAX_LEVELS; s >>= 1) {
        const size_t n = (size_t)s * s * 4;
        const uint32_t l = m->levels++;
        m->pos[l] = calloc(n, sizeof(float));
        m->nrm[l] = calloc(n, sizeof(float));
        m->irr[l] = calloc(n, sizeof(float));
        if (!m->pos[l] || !m->nrm[l] || !m->irr[l]) {
            sss_htsm_map_free(m);
            return sss_fail(err, SSS_ERR_NOMEM, "out of memory for a %u² light-space map", size);
        }
    }
    return SSS_OK;
}

void sss_htsm_map_free(sss_htsm_map *m)
{
    if (!m) return;
    for (uint32_t l = 0; l < SSS_HTSM_MAX_LEVELS; l++) {
        free(m->pos[l]);
        free(m->nrm[l]);
        free(m->irr[l]);
    }
    memset(m, 0, sizeof *m);
}

static void mip_down(const float *a, uint32_t sa, float *b)
{
    const uint32_t sb = sa / 2;
    for (uint32_t j = 0; j < sb; j++)
        for (uint32_t i = 0; i < sb; i++)
            for (int c = 0; c < 4; c++) {
                const size_t r0 = ((size_t)(2 * j) * sa + 2 * i) * 4 + (size_t)c, r1 = r0 + (size_t)sa * 4;
                b[((size_t)j * sb + i) * 4 + (size_t)c] = 0.25f * ((a[r0] + a[r0 + 4]) + (a[r1] + a[r1 + 4]));
            }
}

void sss_htsm_map_mips(sss_htsm_map *m)
{
    for (uint32_t l = 0; l + 1 < m->levels; l++) {
        const uint32_t s = m->size >> l;
        mip_down(m->pos[l], s, m->pos[l + 1]);
        mip_down(m->nrm[l], s, m->nrm[l + 1]);
        mip_down(m->irr[l], s, m->irr[l + 1]);
    }
}

double sss_htsm_texel_mm(const sss_htsm_map *m, double mm_per_unit)
{
    /* s = (row 0 · x) / (row 3 · x) spans [0, 1] over the map's width; its
     * gradient where s = ½ at the depth w = ref_w is (row 0 − ½ row 3) / ref_w
     * (row 3 = (0, 0, 0, 1) and ref_w = 1 on an orthographic map) */
    const float *L = m->lookup;
    const double a = L[0] - 0.5 * L[3], b = L[4] - 0.5 * L[7], c = L[8] - 0.5 * L[11];
    const double w = m->ref_w > 0.0 ? m->ref_w : 1.0;
    const double inv_w = sqrt(a * a + b * b + c * c) / w;
    return inv_w > 0.0 ? mm_per_unit / (inv_w * m->size) : 0.0;
}

/* --- the field's volume ------------------------------------------------ */

void sss_htsm_volume_free(sss_htsm_volume *v)
{
    if (!v) return;
    for (uint32_t l = 0; l < SSS_HTSM_MAX_LEVELS; l++) free(v->f[l]);
    memset(v, 0, sizeof *v);
}

/* Level l + 1 of the volume: the mean of each 2 × 2 × 2 block of level l
 * (n voxels per side), as glGenerateMipmap builds a power-of-two texture. */
static void volume_down(const float *a, uint32_t n, float *b)
{
    const uint32_t m = n / 2;
    for (uint32_t k = 0; k < m; k++)
        for (uint32_t j = 0; j < m; j++)
            for (uint32_t i = 0; i < m; i++) {
                float s = 0.0f;
                for (int c = 0; c < 8; c++)
                    s += a[((size_t)(2 * k + (c >> 2)) * n + 2 * j + ((c >> 1) & 1)) * n + 2 * i + (c & 1)];
                b[((size_t)k * m + j) * m + i] = 0.125f * s;
            }
}

sss_result sss_htsm_volume_build(const sss_hetero *h, const double lo[3], const double hi[3], uint32_t log2n,
                                 sss_htsm_volume *v, sss_error *err)
{
    memset(v, 0, sizeof *v);
    if (log2n < 1 || log2n > 8) return sss_fail(err, SSS_ERR_ARG, "field volume of 2^%u voxels per side", log2n);
    const uint32_t n0 = 1u << log2n;
    for (int a = 0; a < 3; a++) {
        if (!isfinite(lo[a]) || !isfinite(hi[a]) || !(hi[a] >= lo[a]))
            return sss_fail(err, SSS_ERR_ARG, "field volume bounds are not a box");
        v->lo[a] = lo[a];
        /* a flat object (a plane) still gets a positive voxel */
        v->h[a] = hi[a] > lo[a] ? (hi[a] - lo[a]) / n0 : 1.0;
    }
    for (uint32_t n = n0; n >= 2 && v->levels < SSS_HTSM_MAX_LEVELS; n /= 2) {
        const uint32_t l = v->levels++;
        v->n[l] = n;
        v->f[l] = malloc((size_t)n * n * n * sizeof(float));
        if (!v->f[l]) {
            sss_htsm_volume_free(v);
            return sss_fail(err, SSS_ERR_NOMEM, "out of memory for a %u³ field volume", n);
        }
    }
    float *f0 = v->f[0];
    for (uint32_t k = 0; k < n0; k++)
        for (uint32_t j = 0; j < n0; j++)
            for (uint32_t i = 0; i < n0; i++) {
                const double p[3] = {lo[0] + v->h[0] * (i + 0.5), lo[1] + v->h[1] * (j + 0.5),
                                     lo[2] + v->h[2] * (k + 0.5)};
                double x_mm[3];
                sss_hetero_to_rest(h, p, x_mm);
                f0[((size_t)k * n0 + j) * n0 + i] = (float)sss_field_eval(&h->field, x_mm);
            }
    for (uint32_t l = 1; l < v->levels; l++) volume_down(v->f[l - 1], v->n[l - 1], v->f[l]);
    return SSS_OK;
}

double sss_htsm_volume_at(const sss_htsm_volume *v, uint32_t level, const double x[3])
{
    if (!v || !v->levels) return 0.0;
    const uint32_t l = level < v->levels ? level : v->levels - 1;
    const uint32_t n = v->n[l];
    const double scale = (double)(1u << l);
    uint32_t i0[3];
    double fr[3];
    for (int a = 0; a < 3; a++) {
        /* values at voxel centres, as a texture's texels */
        double u = (x[a] - v->lo[a]) / (v->h[a] * scale) - 0.5;
        u = u < 0.0 ? 0.0 : u > (double)(n - 1) ? (double)(n - 1) : u;
        uint32_t i = (uint32_t)floor(u);
        if (i > n - 2) i = n - 2;
        i0[a] = i;
        fr[a] = u - i;
    }
    const float *f = v->f[l];
    double s = 0.0;
    for (int c = 0; c < 8; c++) {
        const uint32_t i = i0[0] + (c & 1), j = i0[1] + ((c >> 1) & 1), k = i0[2] + ((c >> 2) & 1);
        const double w = ((c & 1) ? fr[0] : 1.0 - fr[0]) * (((c >> 1) & 1) ? fr[1] : 1.0 - fr[1]) *
                         (((c >> 2) & 1) ? fr[2] : 1.0 - fr[2]);
        s += w * f[((size_t)k * n + j) * n + i];
    }
    return s;
}

/* --- the pattern -------------------------------------------------------- */

/* The level whose bilinear read, a tent two texels wide each way, spans
 * about the sample's area: texel side nearest sqrt(area)/2 (one of side
 * sqrt(area) spread the read over 4 areas and pulled in the next samples'
 * light and empty texels near an edge; docs/heterogeneous.md §9.2). */
static uint32_t level_for(double area, double texel_mm, uint32_t levels)
{
    if (!(texel_mm > 0.0)) return 0;
    const double l = floor(log2(0.5 * sqrt(area) / texel_mm) + 0.5);
    return l < 0.0 ? 0u : l > (double)(levels - 1) ? levels - 1 : (uint32_t)l;
}

sss_result sss_htsm_pattern_make(uint32_t n, double r0_mm, double texel_mm, uint32_t map_levels,
                                 sss_htsm_pattern *p, sss_error *err)
{
    memset(p, 0, sizeof *p);
    if (n != 1 && n != 5 && n != 9 && n != 13)
        return sss_fail(err, SSS_ERR_ARG, "sample pattern of %u samples: the thesis's are 1, 5, 9 and 13", n);
    if (!(r0_mm > 0.0) || !isfinite(r0_mm))
        return sss_fail(err, SSS_ERR_ARG, "sample pattern radius %g mm must be positive", r0_mm);
    if (map_levels < 1) map_levels = 1;
    p->n = n;
    p->area[0] = SSS_PI * r0_mm * r0_mm;
    for (uint32_t k = 1; 4 * k + 1 <= n; k++) {
        const double a = r0_mm * ldexp(1.0, (int)k - 1), b = 2.0 * a;
        /* the radius that halves the quarter annulus's area */
        const double rm = sqrt(0.5 * (a * a + b * b));
        for (uint32_t j = 0; j < 4; j++) {
            const double th = 0.5 * SSS_PI * j + ((k & 1) ? 0.25 * SSS_PI : 0.0);
            const uint32_t i = 4 * (k - 1) + 1 + j;
            p->off[i][0] = rm * cos(th);
            p->off[i][1] = rm * sin(th);
            p->area[i] = 0.25 * SSS_PI * (b * b - a * a);
            p->vol_level[i] = k;
        }
    }
    for (uint32_t i = 0; i < n; i++) {
        p->rho[i] = sqrt(p->area[i] / SSS_PI);
        p->map_level[i] = level_for(p->area[i], texel_mm, map_levels);
    }
    return SSS_OK;
}

/* --- the estimate --------------------------------------------------------- */

/* The map's bilinear mean at (s, t) on level l (texels outside the map are
 * empty): sums of position × coverage, coverage and E_t. */
static void map_read(const sss_htsm_map *m, uint32_t l, double s, double t, double pos[4], double irr[3])
{
    const uint32_t S = m->size >> l;
    const double u = s * S - 0.5, v = t * S - 0.5;
    const double fu = floor(u), fv = floor(v);
    const double wu = u - fu, wv = v - fv;
    memset(pos, 0, 4 * sizeof *pos);
    memset(irr, 0, 3 * sizeof *irr);
    for (int c = 0; c < 4; c++) {
        const double i = fu + (c & 1), j = fv + (c >> 1);
        if (i < 0.0 || j < 0.0 || i >= S || j >= S) continue;
        const double w = ((c & 1) ? wu : 1.0 - wu) * ((c >> 1) ? wv : 1.0 - wv);
        const size_t at = ((size_t)j * S + (size_t)i) * 4;
        for (int k = 0; k < 4; k++) pos[k] += w * m->pos[l][at + (size_t)k];
        for (int k = 0; k < 3; k++) irr[k] += w * m->irr[l][at + (size_t)k];
    }
}

/* ∫ R_d dA of the blend at f over the sample's disk (radius ρ across the
 * light, x_o at height h above its plane and ℓ from its centre along it;
 * docs/heterogeneous.md §9.2): where x_o's foot lies inside the disk, the
 * disk about the foot that fits inside (radius ρ − ℓ) exactly, and the
 * crescent left as a share of the disk at ρ from the foot; beyond, the disk
 * on its axis at the whole distance. */
static double disk_at(const sss_dipole *dp, double h, double l, double rho)
{
    if (!dp) return 0.0;
    if (!(l < rho)) return sss_rd_disk_axis(dp, sqrt(h * h + l * l), rho);
    const double in = (rho - l) / rho;
    return sss_rd_disk_axis(dp, h, rho - l) + (1.0 - in * in) * sss_rd_disk_axis(dp, sqrt(h * h + rho * rho), rho);
}

/* The blend at f's dipole per channel into dp; out[c] points at dp[c], or
 * is NULL for a channel whose coefficients make no dipole (it adds 0). */
static void dipoles_at(const sss_htsm_material *mat, double f, sss_dipole dp[3], const sss_dipole *out[3])
{
    sss_material b;
    sss_material_blend(&mat->base, &mat->inside, f, &b);
    for (int c = 0; c < 3; c++)
        out[c] = sss_dipole_init(&dp[c], b.sigma_a[c], b.sigmap_s[c], b.eta) == SSS_OK ? &dp[c] : NULL;
}

/* Map coordinates (s, t) of x (mesh units): the map's lookup applied and
 * divided by its w (1 on an orthographic map, the depth along a
 * perspective map's axis). */
static void map_st(const float L[16], const double x[3], double st[2])
{
    const double w = L[3] * x[0] + L[7] * x[1] + L[11] * x[2] + L[15];
    st[0] = (L[0] * x[0] + L[4] * x[1] + L[8] * x[2] + L[12]) / w;
    st[1] = (L[1] * x[0] + L[5] * x[1] + L[9] * x[2] + L[13]) / w;
}

/* Sample i's geometry from the light (docs/heterogeneous.md §9.2): u the
 * unit direction of the light's ray at x_i (away from the light), and the
 * ratio of the area the sample stands for across that ray to the
 * pattern's A_i: 1 from a directional light; from a point light P the texel's side grows
 * with its depth w_i along the axis, and the ray meets the plane across the
 * axis at cos θ = w_i / |x_i − P|, so (w_i / ref_w)² w_i / |x_i − P|. */
static double ray_at(const sss_htsm_map *m, const double xi[3], double u[3])
{
    const double *L = m->light;
    if (L[3] == 0.0) {
        u[0] = -L[0], u[1] = -L[1], u[2] = -L[2];
        return 1.0;
    }
    const double r[3] = {xi[0] - L[0], xi[1] - L[1], xi[2] - L[2]};
    const double n = sqrt(sss_dot3(r, r));
    if (!(n > 0.0)) {
        u[0] = u[1] = u[2] = 0.0;
        return 0.0;
    }
    for (int k = 0; k < 3; k++) u[k] = r[k] / n;
    const float *M = m->lookup;
    const double w = M[3] * xi[0] + M[7] * xi[1] + M[11] * xi[2] + M[15], k = w / m->ref_w;
    return k * k * w / n;
}

/* The blend's weight at x on level l: the field scaled by the strength. */
static double weight_at(const sss_htsm_volume *vol, const sss_htsm_material *mat, uint32_t l, const double x[3])
{
    return vol ? fmin(1.0, mat->strength * sss_htsm_volume_at(vol, l, x)) : 0.0;
}

void sss_htsm_q(const sss_htsm_map *map, const sss_htsm_volume *vol, const sss_htsm_material *mat,
                const sss_htsm_pattern *pat, uint32_t steps, const double xo[3], double q[3])
{
    q[0] = q[1] = q[2] = 0.0;
    if (steps < 1) steps = 1;
    if (steps > SSS_HTSM_MAX_STEPS) steps = SSS_HTSM_MAX_STEPS;
    double so[2];
    map_st(map->lookup, xo, so);
    const double mm = mat->mm_per_unit;
    const double span = sss_htsm_texel_mm(map, mm) * map->size; /* mm across the map */
    if (!(span > 0.0)) return;
    const double fo = weight_at(vol, mat, 0, xo);
    sss_dipole dpo[3], dpi[3];
    const sss_dipole *Po[3], *Pi[3];
    dipoles_at(mat, fo, dpo, Po); /* x_o's profiles, the same for every sample */
    for (uint32_t i = 0; i < pat->n; i++) {
        double pos[4], E[3];
        map_read(map, pat->map_level[i], so[0] + pat->off[i][0] / span, so[1] + pat->off[i][1] / span, pos, E);
        if (!(pos[3] > 1e-6)) continue; /* nothing lit there */
        const double xi[3] = {pos[0] / pos[3], pos[1] / pos[3], pos[2] / pos[3]};
        const double dx[3] = {xo[0] - xi[0], xo[1] - xi[1], xo[2] - xi[2]};
        const double d = sqrt(sss_dot3(dx, dx)) * mm;
        /* h along the light's ray at x_i, ℓ across it; the disk's radius at
         * the area the sample covers there */
        double u[3];
        const double a = ray_at(map, xi, u), hu = sss_dot3(dx, u);
        const double across[3] = {dx[0] - hu * u[0], dx[1] - hu * u[1], dx[2] - hu * u[2]};
        const double h = fabs(hu) * mm, l = sqrt(sss_dot3(across, across)) * mm;
        const double rho = pat->rho[i] * sqrt(a);
        if (!(rho > 0.0)) continue;
        const uint32_t lv = pat->vol_level[i];
        const double fi = weight_at(vol, mat, lv, xi);
        dipoles_at(mat, fi, dpi, Pi);
        double tau_sum[3] = {0, 0, 0};
        const double sbar[3] = {
            0.5 * (sss_material_sigma_tr(&mat->base, &mat->inside, fo, 0) +
                   sss_material_sigma_tr(&mat->base, &mat->inside, fi, 0)),
            0.5 * (sss_material_sigma_tr(&mat->base, &mat->inside, fo, 1) +
                   sss_material_sigma_tr(&mat->base, &mat->inside, fi, 1)),
            0.5 * (sss_material_sigma_tr(&mat->base, &mat->inside, fo, 2) +
                   sss_material_sigma_tr(&mat->base, &mat->inside, fi, 2))};
        if (vol) {
            for (uint32_t j = 0; j < steps; j++) {
                const double a = (j + 0.5) / steps;
                const double x[3] = {xi[0] + a * dx[0], xi[1] + a * dx[1], xi[2] + a * dx[2]};
                const double f = weight_at(vol, mat, lv, x);
                for (int c = 0; c < 3; c++)
                    tau_sum[c] += fmax(0.0, sss_material_sigma_tr(&mat->base, &mat->inside, f, (uint32_t)c) - sbar[c]);
            }
        }
        for (int c = 0; c < 3; c++) {
            const double tau = exp(-tau_sum[c] * d / steps);
            /* the sample stands for a disk of radius ρ (area A_i) at distance
             * d: each endpoint's profile integrated over it, their geometric
             * mean (§9.2) */
            const double P = sqrt(disk_at(Po[c], h, l, rho) * disk_at(Pi[c], h, l, rho));
            /* the baked weight's 1/π (docs/physics.md §4): q in the bake's units */
            q[c] += E[c] * P * tau / SSS_PI;
        }
    }
}

int sss_htsm_point_drawn(const sss_mesh *m, const double P[3], double *R)
{
    double c[3];
    const double r = sss_mesh_bounding_sphere(m, c) * (1.0 + SSS_HTSM_MAP_MARGIN);
    const double d[3] = {P[0] - c[0], P[1] - c[1], P[2] - c[2]};
    if (R) *R = r;
    return sqrt(sss_dot3(d, d)) > r;
}

void sss_htsm_point_inside_msg(char *buf, size_t n, const double P[3], const char *object, double R)
{
    snprintf(buf, n, "the point light at (%g, %g, %g) lies within object '%s''s bounding sphere (radius %g): the "
             "run-time path does not draw it, since no light-space map from there sees the object whole "
             "(docs/heterogeneous.md sec. 9.1)", P[0], P[1], P[2], object, R);
}
