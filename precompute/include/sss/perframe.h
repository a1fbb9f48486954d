/* sss/perframe.h: the object-space per-frame path for deforming objects
 * (docs/deformable.md §3): Hao–Varshney 2004's run-time mode (§2.3)
 * evaluated on a posed mesh with the bake's own pieces and nothing
 * baked. For one directional light ω:
 *
 *   G(x_i, ω)  = F_t(η, n_i·ω) · max(0, n_i·ω) · V(x_i, ω)     (irradiance per vertex, with visibility)
 *   q(x_o, ω)  = Σ_{x_i ∈ N(x_o)} w_c(o, i) · G(x_i, ω)          (the gather)
 *
 * with the neighbourhoods, weights (point or hat, docs/physics.md §4, §9),
 * Fresnel term and ray rule of the bake, all rebuilt on the pose because
 * every one of them depends on the geometry. Two modes:
 *
 * - SSS_PERFRAME_EXACT: N(x_o) built as the bake builds it and the sparse
 *   sum sss_integrate / sss_integrate_hat. It is the exact evaluator's sum
 *   (sss/exact.h) on the same mesh: equal to it to float rounding (the test
 *   oracle; tests/unit/test_perframe.c).
 * - SSS_PERFRAME_TREE: the hierarchical gather of the bake (sss/gather.h,
 *   octree far field of second order, θ = 0.4), with the hat corrections
 *   added as the bake's tree path adds them: no neighbourhood rows, so it
 *   is the faster one on large meshes; its error against the exact mode is
 *   measured in docs/deformable.md §3.
 *
 * Part of libsss_bake (bake/perframe.c).
 */
#ifndef SSS_PERFRAME_H
#define SSS_PERFRAME_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

enum { SSS_PERFRAME_EXACT = 0, SSS_PERFRAME_TREE = 1 };

/* Zero means the default for every field. */
typedef struct sss_perframe_options {
    int mode;            /* SSS_PERFRAME_EXACT (default) or SSS_PERFRAME_TREE */
    uint32_t weights;    /* SSS_WEIGHTS_HAT (1) or SSS_WEIGHTS_POINT (0, the default: the paper's) */
    double eps;          /* neighbourhood energy cutoff ε (default 1e-3, the bake's) */
    double theta;        /* tree opening threshold (default SSS_GATHER_THETA_DEFAULT) */
    int no_shadows;      /* 1: V ≡ 1 (a convex object, the planner's self-shadow rule) */
    /* A material field (docs/deformable.md §10): with hetero's field not
     * NONE, each vertex takes the blend at f of its rest-pose position
     * rest[3v..3v+2] (the frame hetero->xf maps from) and every pair the
     * endpoints' product sqrt(R_d(r; m_o) R_d(r; m_i)) (seed 003 Eq. 8,
     * sss_field_kernel_create_ends: no transmittance τ). Exact mode only:
     * the tree's far field takes one kernel for all pairs. */
    const sss_hetero *hetero; /* NULL: homogeneous */
    const float *rest;
    const sss_cancel_flag *cancel;
} sss_perframe_options;

/* What a frame cost, wall-clock seconds per stage. */
typedef struct sss_perframe_stats {
    double t_neighbourhoods; /* N(x_o) and weights (exact mode), hat corrections (both modes) */
    double t_visibility;     /* the BVH of the pose and G with its rays */
    double t_gather;         /* the sparse sum, or tree build + gather */
    double t_total;
    double radius_mm;        /* the neighbourhood cutoff R */
    uint64_t rays;
    uint64_t pairs;          /* neighbourhood entries (exact mode) */
} sss_perframe_stats;

/* q(x_o, ω) into q[v · channels + c] for every vertex of mesh (normals and
 * areas computed: sss_mesh_compute_normals_areas, or sss_deform_pose),
 * with material mat over `channels` (1 or 3) channels, mm_per_unit mm per
 * mesh unit, and light the direction towards the light (any length ≠ 0;
 * zero or non-finite gives zeros). q is per unit irradiance, as a bake's.
 * stats may be NULL. Errors: SSS_ERR_ARG, SSS_ERR_NOMEM, SSS_ERR_INTERRUPTED
 * and the kernels' own, one line each. */
sss_result sss_perframe_q(const sss_mesh *mesh, const sss_material *mat, uint32_t channels, double mm_per_unit,
                          const double light[3], const sss_perframe_options *o, float *q, sss_perframe_stats *stats,
                          sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
