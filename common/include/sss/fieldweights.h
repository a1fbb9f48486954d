/* sss/fieldweights.h: the spatially varying kernel of a heterogeneous
 * object (docs/heterogeneous.md §4): the weights of the sum of
 * Hao–Varshney 2004 §3.1 built for a reference material, then scaled pair
 * by pair to the geometric mean of the endpoints' own profiles (seed 003's
 * SubEdit model) times the transmittance through the field between them
 * (seed 000's march). The bake's passes and the exact evaluator both scale
 * their rows with it, so a file's q is recomputed from the file alone;
 * the readers' run-time near terms scale their weights with it too
 * (sss/nearterms.h), which is why it is part of libsss
 * (common/src/fieldweights.c) and not of the bake's kernels.
 */
#ifndef SSS_FIELDWEIGHTS_H
#define SSS_FIELDWEIGHTS_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/weights.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The march along a pair's segment takes at most this many steps: the
 * step is sss_field_step_mm, lengthened on long pairs (§4.2). */
#define SSS_FIELD_MARCH_MAX 64
/* The march grid of a procedural field has at most this many nodes per side. */
#define SSS_FIELD_MARCH_NODES 160
/* The far pairs' cache of a bake holds at most this many occupied cells
 * (their pairs' table: 1024² × 3 doubles, 24 MiB at most). */
#define SSS_FIELD_FAR_CELLS 1024
/* The march grid's floats per node: the channels, padded (SSS_MAX_CHANNELS ≤ 4). */
#define SSS_FIELD_TR_W 4
/* The march grid's early-out bricks have this many cells per side. */
#define SSS_FIELD_BRICK 2
/* The profiles' table (§4.1): levels per channel (evenly spaced in its
 * σtr) and distances; bilinear on ½ ln of the profile ratio keeps ln κ
 * within prof_tol of the exact profiles: 5.5·10⁻⁴ on the dragon's veins,
 * 1.4·10⁻³ where σa rises 100-fold (test_field). */
#define SSS_FIELD_PROFILE_F 129
#define SSS_FIELD_PROFILE_R 1025

typedef struct sss_field_kernel {
    const sss_hetero *h;     /* borrowed: the field, the inside material, the rest frame */
    sss_material base;       /* the material at f = 0 */
    uint32_t nv, C;
    double s;                /* mm per mesh unit */
    double f_min, f_max;     /* f over the vertices */
    double *f;               /* f at every vertex (nv) */
    double *sigma_tr;        /* σtr of every vertex's blend, nv × C (1/mm) */
    sss_dipole *dip;         /* every vertex's dipole, nv × C */
    sss_material ref;        /* the blend at f_min: the material the rows are built for */
    sss_dipole dip_ref[SSS_MAX_CHANNELS];
    double radius_mm;        /* the search radius: the larger of the radius rule at f_min and at f_max */
    double step_mm;          /* 0: nothing to march (a constant) */
    /* What the march reads (§4.2): σtr of every channel sampled once on a
     * grid of nodes over the object's rest-frame box at the step (at most
     * SSS_FIELD_MARCH_NODES per side), trilinear between nodes. Floats,
     * each rounded down from σtr so that a node never exceeds the σtr of
     * its f (a plateau's excess over its own mean stays exactly 0), the
     * channels of a node padded to SSS_FIELD_TR_W so that one aligned
     * 16-byte load reads them all and the lerps run on the channels at
     * once. Owned; NULL for a constant. */
    float *tr;               /* tn[0]·tn[1]·tn[2] × SSS_FIELD_TR_W, node (i, j, k) at ((k·tn1 + j)·tn0 + i)·W */
    uint32_t tn[3];
    double t_origin[3], t_voxel;
    /* The far pairs' cache (sss_field_kernel_far, §4.3): vertices binned
     * into cubic cells; a pair farther apart than far_mm takes the mean
     * excess σtr(x) − σtr_ref marched once between its cells' centroids. */
    uint32_t ncells;         /* 0: no cache, every pair marched */
    uint32_t *cell;          /* cell of every vertex (nv) */
    double far_mm, cell_mm;
    double *excess;          /* ncells × ncells × C, 1/mm: pair (a ≤ b) at (a·ncells + b)·C, filled on demand */
    double *cell_centre;     /* ncells × 4: the centroid of each cell's vertices (world units), its count */
    void *cell_state;        /* ncells × ncells atomic bytes: 2 where excess holds the pair (fieldweights.c) */
    double sigma_tr_ref[SSS_MAX_CHANNELS];
    /* The march's early-out (§4.2): the grid's cells grouped into bricks of
     * SSS_FIELD_BRICK³ cells, and per brick and channel a bound on any
     * trilinear read inside it: its nodes' largest σtr (exactly that value
     * when all its nodes hold it, else 10⁻⁵ above it, more than the float
     * rounding of three levels of lerps). A midpoint in a brick whose bound is at
     * most the pair's mean σ̄tr adds exactly 0 to τ's sum, so it is not
     * read. NULL: every midpoint is read (the plain march). */
    double *brick_hi;        /* bn[0]·bn[1]·bn[2] × C, brick (i, j, k) at ((k·bn1 + j)·bn0 + i)·C */
    uint32_t bn[3];
    /* Whether the march uses the bricks (a segment's box, then each
     * midpoint's brick): set where at least a quarter of the bricks are
     * flat (all their nodes equal: a plateau), since through a field that
     * varies everywhere the tests cost more than the reads they skip. The
     * sum's bits are the same either way. */
    int use_bricks;
    /* The profiles' table (docs/heterogeneous.md §4.1): ½ ln(R_d[f](r) /
     * R_d[f_ref](r)) per channel on SSS_FIELD_PROFILE_F levels of f over
     * [f_min, f_max] (per channel, evenly spaced in its σtr) and
     * SSS_FIELD_PROFILE_R distances over [0, radius_mm],
     * bilinear between them, for the pairs whose profiles are point values;
     * prof_tol its largest error (in ln κ) at the cells' centres against the
     * exact profiles. NULL when f is constant over the vertices. */
    float *prof;             /* level l, distance j, channel c at (l·SSS_FIELD_PROFILE_R + j)·C + c (float:
                                half the cache lines; 10⁻⁶ in ln κ, within prof_tol) */
    uint32_t *prof_l;        /* per vertex and channel: the level below its σtr (nv × C) */
    double *prof_w;          /* per vertex and channel: its weight towards the level above (nv × C) */
    double prof_dr, prof_tol;
} sss_field_kernel;

/* Evaluates the field at every vertex of mesh (world units; h->xf maps to
 * the rest frame), checks that the field covers the mesh (`name` in the
 * message), and derives the reference material and the search radius
 * with the neighbourhoods' radius rule for cutoff eps. A surface texture
 * (h->surface, docs/heterogeneous.md §4.4) gets τ ≡ 1 (step_mm 0): the
 * endpoints' product alone. */
sss_result sss_field_kernel_create(const sss_mesh *mesh, double mm_per_unit, const sss_material *base,
                                   const sss_hetero *h, uint32_t C, double eps, const char *name,
                                   sss_field_kernel *k, sss_error *err);

/* The kernel of a deforming object (docs/deformable.md §10): f read at
 * the rest-pose positions `rest` (nv × 3, the frame h->xf maps from), so
 * that the material moves with the surface, and the endpoints' product
 * alone, κ = sqrt(P_o(r) P_i(r)) / P_ref(r) with τ ≡ 1 (step_mm 0): a
 * straight segment between two posed vertices has no rest-frame
 * counterpart to march, and the splatting (sss/splat_gpu.h) cannot march
 * either. The radius rule and r come from mesh, the pose. */
sss_result sss_field_kernel_create_ends(const sss_mesh *mesh, const float *rest, double mm_per_unit,
                                        const sss_material *base, const sss_hetero *h, uint32_t C, double eps,
                                        const char *name, sss_field_kernel *k, sss_error *err);

void sss_field_kernel_free(sss_field_kernel *k);

/* Builds the far pairs' cache (§4.3) for a bake: at most max_cells occupied
 * cells of edge at least 4 march steps; pairs farther than 3 cell diagonals
 * then cost no march. The exact evaluator does not call it: it marches
 * every pair, and the difference is the cache's error (docs/heterogeneous.md
 * §7). */
sss_result sss_field_kernel_far(sss_field_kernel *k, const sss_mesh *mesh, uint32_t max_cells, sss_error *err);

/* The sum of τ's midpoint rule along the segment a → b (world units) in n
 * equal steps (§4.2): Σ_j max(0, σtr_c(x_j) − mean_c) per channel into
 * sum, σtr read trilinearly from the march grid; bricks whose bound is at
 * most mean_c are skipped, with the same bits as the plain march. */
void sss_field_march_sum(const sss_field_kernel *k, const double a[3], const double b[3], int n, const double *mean,
                         double *sum);

/* κ_c(o, i) for the pair (o, i), per channel (§4.1):
 *   κ = sqrt(P_o(r) P_i(r)) / P_ref(r) · τ(o, i),
 *   τ = exp(−∫ max(0, σtr(x) − (σtr(x_o) + σtr(x_i))/2) dξ) along the segment,
 * P the profile the row's weight used (R_d, or its disk integrals near
 * r = 0); point profiles within the radius come from the kernel's table
 * (prof, §4.1) where it has one. 1 exactly when the field is constant.
 * Symmetric in o, i. */
void sss_field_kappa(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double *kappa);
/* sss_field_kappa, returning 1 when κ(i, o) has exactly κ(o, i)'s bits
 * (neither endpoint within the other's area disk, so both orders take the
 * point profiles; the own term and the near disks are not symmetric), so
 * that a caller may keep one pair's κ for both its entries. */
int sss_field_kappa_sym(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double *kappa);

/* Scales every entry of rows (built for k->dip_ref over the same mesh,
 * row r = vertex r) by κ. Polls cancel. */
sss_result sss_field_weights_apply(const sss_field_kernel *k, const sss_mesh *mesh, sss_weights *rows,
                                   const sss_cancel_flag *cancel, sss_error *err);

/* A point of the object standing for a group of vertices: a far node of
 * the tree gather, at its area centroid (docs/heterogeneous.md §4.5). Its
 * position (world units), the field's f there, the blend's σtr and
 * dipole per channel. */
typedef struct sss_field_point {
    double x[3];
    double f;
    double sigma_tr[SSS_MAX_CHANNELS];
    sss_dipole dip[SSS_MAX_CHANNELS];
} sss_field_point;

/* pt at x (world units; read in the rest frame as the vertices are).
 * SSS_ERR_ARG when the blend there makes no dipole. */
sss_result sss_field_point_at(const sss_field_kernel *k, const double x[3], sss_field_point *pt);

/* κ_c(o, pt) per channel: §4.1's κ between vertex o and the point, the
 * point values R_d(r) of both ends' blends over the reference's, times τ
 * marched along the segment from x_o to the point (no far pairs' cache:
 * the point is not a vertex of a cell). 1 exactly when both ends are at
 * the reference's f and the segment holds no excess. */
void sss_field_kappa_point(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, const sss_field_point *pt,
                           double *kappa);

#ifdef __cplusplus
}
#endif
#endif
