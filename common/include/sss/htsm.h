/* sss/htsm.h: the run-time estimator of a heterogeneous object, seed 000's
 * heterogeneous translucent shadow maps (Shopf 2007 §4.3; docs/heterogeneous.md
 * §9). Written once here, on the CPU: it is the oracle of the viewer's GPU
 * pass (runtime/shaders/htsm.frag.glsl), which computes the same sum with the
 * same pattern, the same mip levels and the same march.
 *
 * Inputs, as the GPU has them each frame:
 *   - the light-space map (Shopf 2007 Fig. 4.2): per texel of a view from
 *     the light (orthographic along a directional light, perspective from a
 *     point light), the surface nearest the light: its position and normal
 *     (both times the texel's coverage, with the coverage in w) and the flux
 *     it lets in per unit area across the light's ray (E_t = E₀ F_t(η, n·l),
 *     or I F_t(η, n·l) / r² from a point light; r, g, b), with mip levels,
 *     each the 2 × 2 mean of the one below;
 *   - the field f sampled on the nodes of a grid over the object's bounds
 *     (mesh units), 2^m + 1 nodes per side, with node-centred mip levels.
 *
 * The estimate at an exit point x_o (docs/heterogeneous.md §9.2):
 *
 *   q_c(x_o) = (1/π) Σ_i A_i E_i,c sqrt(R_d[f_o](r_i) R_d[f_i](r_i)) τ_i,c
 *   τ_i,c    = exp(−Σ_j max(0, σtr,c(f(ξ_j)) − σ̄tr,c) Δ)
 *
 * over the thesis's hierarchical pattern of n = 1, 5, 9 or 13 samples about
 * x_o's light-space projection; A_i the area (across the light's ray)
 * sample i stands for, E_i, x_i the map's mean over it; R_d integrated over
 * the sample's disk (docs/heterogeneous.md §9.2); ξ_j the midpoints of
 * `steps` equal steps from x_i to x_o; σ̄tr the mean of the endpoints'. A
 * point light's map is a perspective one: a sample's area is its map area
 * at the depth it reads (docs/heterogeneous.md §9.2, "Point lights").
 */
#ifndef SSS_HTSM_H
#define SSS_HTSM_H

#include <stddef.h>
#include <stdint.h>
#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_HTSM_MAX_LEVELS 16
#define SSS_HTSM_MAX_SAMPLES 13  /* the thesis's largest pattern (Fig. 5.7) */
#define SSS_HTSM_MAX_STEPS 1024
#define SSS_HTSM_MAX_LIGHTS 8 /* directional and point lights summed per frame (docs/heterogeneous.md §9.1) */
/* The light-space maps are fitted to the mesh's bounding sphere
 * (sss_mesh_bounding_sphere) enlarged by this share, as the renderer's
 * shadow map (its SSS_SHADOW_MARGIN): no triangle is clipped. */
#define SSS_HTSM_MAP_MARGIN 0.02

/* The light-space map: `levels` mip levels, level l of size >> l texels
 * per side, 4 floats per texel in each of the three images. */
typedef struct sss_htsm_map {
    uint32_t size, levels;
    float *pos[SSS_HTSM_MAX_LEVELS]; /* position (mesh units) × coverage, coverage */
    float *nrm[SSS_HTSM_MAX_LEVELS]; /* normal × coverage, coverage */
    float *irr[SSS_HTSM_MAX_LEVELS]; /* E_t r, g, b per unit area across the light, coverage */
    /* column-major: mesh units → (s, t) ∈ [0, 1]² of the map after the
     * division by row 3's w (1 on an orthographic map) */
    float lookup[16];
    /* the light the map was drawn from: (l, 0) with l the unit direction
     * towards a directional light, or (P, 1) with P a point light's
     * position (mesh units) */
    double light[4];
    /* row 3's w where the pattern's millimetres hold: 1 on an orthographic
     * map; a perspective map's distance to the object's centre along its
     * axis (mesh units), where a sample's area is the pattern's */
    double ref_w;
} sss_htsm_map;

/* Allocates every level of a size × size map (size a power of two, 2 to
 * 4096), zeroed, with ref_w 1 (the caller sets lookup and light). */
sss_result sss_htsm_map_init(sss_htsm_map *m, uint32_t size, sss_error *err);
/* Level l + 1 as the 2 × 2 mean of level l, for every level (as
 * glGenerateMipmap builds them for a power-of-two texture). */
void sss_htsm_map_mips(sss_htsm_map *m);
void sss_htsm_map_free(sss_htsm_map *m);

/* The field as a mipmapped 3D texture over the object's bounds [lo, hi]
 * (mesh units): level 0 has 2^m voxels per side, voxel (i, j, k) holding f
 * at its centre lo + h·(i + ½, j + ½, k + ½); level l + 1 the mean of each
 * 2 × 2 × 2 block of level l (glGenerateMipmap's box), down to 2 voxels. */
typedef struct sss_htsm_volume {
    uint32_t levels;
    uint32_t n[SSS_HTSM_MAX_LEVELS];
    double lo[3], h[3];
    float *f[SSS_HTSM_MAX_LEVELS];
} sss_htsm_volume;

/* Samples h's field (through its rest-frame map h->xf) at the centres of
 * 2^log2n voxels per side over [lo, hi] (mesh units; log2n 1 to 8) and
 * builds the levels. */
sss_result sss_htsm_volume_build(const sss_hetero *h, const double lo[3], const double hi[3], uint32_t log2n,
                                 sss_htsm_volume *v, sss_error *err);
void sss_htsm_volume_free(sss_htsm_volume *v);
/* f at x (mesh units) on level l (clamped to the last): trilinear between
 * voxel centres, clamped to the edge (GL_CLAMP_TO_EDGE, GL_LINEAR). */
double sss_htsm_volume_at(const sss_htsm_volume *v, uint32_t level, const double x[3]);

/* The hierarchical pattern (Shopf 2007 Fig. 4.3, after Dachsbacher and
 * Stamminger's translucent shadow maps): sample 0 the disk of radius r0
 * about x_o's projection; ring k = 1, 2, 3 the annulus [r0 2^{k−1}, r0 2^k]
 * cut in four quarters, one sample each at the radius that halves the
 * quarter's area, rotated by 45° on odd rings. Each sample reads the map's
 * mip level whose texel side is nearest the square root of its area, and
 * the field's level k. */
typedef struct sss_htsm_pattern {
    uint32_t n;
    double off[SSS_HTSM_MAX_SAMPLES][2]; /* offset along the map's s and t, mm */
    double area[SSS_HTSM_MAX_SAMPLES];   /* mm² across the light */
    double rho[SSS_HTSM_MAX_SAMPLES];    /* sqrt(area / π), mm */
    uint32_t map_level[SSS_HTSM_MAX_SAMPLES];
    uint32_t vol_level[SSS_HTSM_MAX_SAMPLES];
} sss_htsm_pattern;

/* n ∈ {1, 5, 9, 13}, r0 > 0 (mm); texel_mm the side of a level-0 texel,
 * levels the map's mip levels. */
sss_result sss_htsm_pattern_make(uint32_t n, double r0_mm, double texel_mm, uint32_t map_levels,
                                 sss_htsm_pattern *p, sss_error *err);

/* The side of one level-0 texel of m in mm (from its lookup), at the depth
 * ref_w on a perspective map. */
double sss_htsm_texel_mm(const sss_htsm_map *m, double mm_per_unit);

/* The material of an estimate: base (f = 0), inside (f = 1), blended by
 * min(1, strength · f) as docs/heterogeneous.md §3 blends by f (strength 1:
 * the field as given; the viewer's keys edit it live with the two
 * materials). */
typedef struct sss_htsm_material {
    sss_material base, inside;
    double strength;
    double mm_per_unit;
} sss_htsm_material;

/* q(x_o), 3 channels, at x_o (mesh units). vol NULL: f = 0 everywhere (the
 * base material alone). steps 1 to SSS_HTSM_MAX_STEPS. */
void sss_htsm_q(const sss_htsm_map *map, const sss_htsm_volume *vol, const sss_htsm_material *mat,
                const sss_htsm_pattern *pat, uint32_t steps, const double xo[3], double q[3]);

/* Whether the run-time path draws a point light at P (world = mesh
 * units) on the mesh m: 1 when P lies outside the maps' sphere (above);
 * 0 when within it, where no perspective view sees the object whole
 * (docs/heterogeneous.md §9.1). *R: that sphere's radius (may be NULL). */
int sss_htsm_point_drawn(const sss_mesh *m, const double P[3], double *R);

/* The one sentence the planner's reason and sss-view's message give for a
 * point light at P within object `object`'s sphere of radius R, into buf
 * (n bytes). */
void sss_htsm_point_inside_msg(char *buf, size_t n, const double P[3], const char *object, double R);

#ifdef __cplusplus
}
#endif
#endif
