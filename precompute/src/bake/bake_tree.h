/* bake_tree.h: the bake's integrals phase through the hierarchical
 * gather (sss/gather.h), called from bake.c. Not a public header. */
#ifndef SSS_BAKE_TREE_H
#define SSS_BAKE_TREE_H

#include "sss/bake.h"
#include "sss/gather.h"

/* SSS_GATHER_DIRECT or SSS_GATHER_TREE for these options. */
int sss_bake_choose_gather(const sss_bake_options *o);

/* Visibility of rows [v0, v1) of the transfer table G (nv x D, indexed as
 * sss_transfer_compute's) with its progress bar; sets st->rays and
 * st->occluded_fraction. */
sss_result sss_bake_visibility(const sss_mesh *mesh, double eta, const double *dirs, uint32_t D, uint32_t v0,
                               uint32_t v1, const sss_cancel_flag *cancel, float *G, sss_bake_stats *st,
                               sss_error *err);

/* q += Σ_i C(v, i) G[i, j] for directions [j0, j0 + Dc) of q's layout
 * ((j · nv + v) · C + c), Gm the transfer rows in the gather tree's order
 * (row inv[i] is vertex i; Dc values per row): the hat-function
 * corrections (docs/physics.md §9) on top of the point weights the gather
 * used, each element in double from q's float and, with clamp, clamped at
 * 0 (sss_integrate_hat's rule). Shared by the bake's tree path and the
 * per-frame path (perframe.c). Returns 0 when out of memory. */
int sss_bake_add_hat(const sss_weights *hat, const uint32_t *inv, const float *Gm, uint32_t nv, uint32_t C,
                     uint32_t j0, uint32_t Dc, int clamp, float *q);

/* Visibility, tree and gather: fills out->q (rank 0 only under MPI) and the
 * stats' timings. avail: bytes that may be used (0: unknown). When the
 * transfer rows and tree moments of all directions do not fit next to q,
 * the directions are taken in chunks (same bytes); refused only when not
 * even one direction at a time fits. hat (NULL: none): the hat-function
 * corrections (sss/hatweights.h) added to q after the gather. */
sss_result sss_bake_tree(const sss_mesh *mesh, const sss_material *mat, const sss_bake_options *o,
                         const sss_dipole *dip, uint32_t C, uint64_t avail, const sss_weights *hat,
                         sss_bake_file *out, sss_bake_stats *st, sss_error *err);

/* The vector integrals Q of the direct sum (options.vector; section QVEC,
 * sss/format.h layout) from the neighbourhood rows nb, the hat-function
 * corrections (NULL: none) and the transfer table G (nv x n) of q: plane a
 * sums sss_transfer_axis's source term H_a with sss_integrate_hat_signed.
 * Allocates *qvec. */
sss_result sss_bake_vector_direct(const sss_mesh *mesh, const sss_dirset *ds, const sss_weights *nb,
                                  const sss_weights *hat, const float *G, float **qvec, sss_error *err);

#endif
