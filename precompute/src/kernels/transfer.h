/* transfer.h (internal): the transfer term G(x_i, ω) of one vertex for one
 * direction, shared by the bake's table (sss_transfer_compute) and the exact
 * evaluator (exact.c), so both apply the same cosine, Fresnel and visibility
 * rule with the same float rounding (Hao–Varshney 2004 §3.1).
 */
#ifndef SSS_KERNELS_TRANSFER_H
#define SSS_KERNELS_TRANSFER_H

#include "sss/transfer.h"

/* G(x_i, ω) = F_t(η, n_i·ω) · max(0, n_i·ω) · V(x_i, ω), rounded to float as
 * the bake stores it; d is a unit vector towards the light. vis NULL means
 * no occlusion test. *traced / *blocked (may be NULL) are set to whether a
 * ray was traced (n_i·ω > 0) and whether it was blocked. */
float sss_transfer_one(const sss_mesh *mesh, const sss_vis *vis, uint32_t i, const double d[3], double eta,
                       int *traced, int *blocked);

/* Rows [v0, v1) of the table of sss_transfer_compute (G[i * n + j], the
 * same indexing), for a rank that owns part of the vertices (docs/benchmarks.md, "Bake at scale"; MPI)
 * or the whole mesh (sss_transfer_compute). */
sss_result sss_transfer_rows(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n, double eta,
                             uint32_t v0, uint32_t v1, const sss_cancel_flag *cancel, float *G, uint64_t *rays_out,
                             uint64_t *occ_out, sss_error *err);
/* The same with row m (m0 <= m < m1) for vertex order[m] (NULL: vertex m):
 * the hierarchical gather fills its Morton-ordered rows directly
 * (bake_tree.c), each value computed as sss_transfer_one computes it, so
 * with the same bits whichever rows or directions are computed together. */
sss_result sss_transfer_rows_ordered(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n,
                                     double eta, const uint32_t *order, uint32_t m0, uint32_t m1,
                                     const sss_cancel_flag *cancel, float *G, uint64_t *rays_out, uint64_t *occ_out,
                                     sss_error *err);

/* The source term of component a of the vector integral Q (Hao–Varshney
 * 2004 §3.1): H_a(x_i, ω_j) = F_t(η, n_i·ω_j) μ_i V(x_i, ω_j) n_i[a], i.e.
 * G without its cosine, times the normal's component, so that
 * Σ_a H_a ω_j[a] = G and Q_j·ω_j = q_j. Formed from a table of G (rows m
 * for vertex order[m], NULL: vertex m; n directions dirs) as G / (n_i·ω_j)
 * · n_i[a], the cosine recomputed as sss_transfer_one computes it, so the
 * shadow test and the Fresnel factor are the ones q used. Signed. */
void sss_transfer_axis(const sss_mesh *mesh, const double *dirs, uint32_t n, const uint32_t *order, uint32_t m0,
                       uint32_t m1, const float *G, int a, float *H);

#endif
