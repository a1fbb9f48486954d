/* sss/hatweights.h: the weights of the sum of Hao–Varshney 2004 §3.1 as
 * integrals over the surface rather than point samples (docs/physics.md
 * §9).
 *
 * The paper's weight of source x_i for receiver x_o is a point sample,
 * (1/π) R_d(‖x_i − x_o‖) ΔA(x_i). R_d peaks at r = 0 with a width of about
 * z_r (0.3–1.3 mm for the measured materials), so where the triangles are
 * not well below z_r the sum depends on the tessellation: a planar slab
 * at 1.25 mm spacing comes out 4–5 % dark, 10:1 triangles can double q.
 * With the irradiance known at the vertices and linear over each triangle
 * (the hat function φ_i of every vertex), the integral the sum stands for is
 *
 *   W(o, i) = (1/π) ∫ φ_i(x) R_d(‖x − x_o‖) dA     over the triangles of x_i,
 *
 * and Σ_i W(o, i) G_i is then ∫ R_d G dA over the piecewise-flat surface,
 * whatever the triangles. Per triangle T the paper's sample is the vertex
 * rule (1/π) R_d(‖x_k − x_o‖) A_T / 3, exact for an R_d linear over T, so
 * it is kept wherever T is small against both its distance to x_o and
 * z_r; only the "close" triangles, diam(T) > κ · max(dist(x_o, T), z_min),
 * are integrated (adaptive subdivision with a degree-5 rule).
 *
 * The bake keeps its point weights everywhere (the gather's fast and
 * byte-deterministic kernels) and adds, per receiver, the sparse
 * corrections C(o, i) = W(o, i) − w(o, i), w the weight the point rule of
 * precompute/src/kernels/nbhd.c gives (its self-term disk and close-neighbour
 * disks included; 0 beyond the cutoff radius). Every user of the weights —
 * the bake's gathers, the exact evaluator, the near terms of every reader —
 * adds the same corrections, so they all sum the same W.
 */
#ifndef SSS_HATWEIGHTS_H
#define SSS_HATWEIGHTS_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/format.h"
#include "sss/mesh.h"
#include "sss/result.h"
#include "sss/weights.h"

#ifdef __cplusplus
extern "C" {
#endif

/* κ of the close test: a triangle is integrated for a receiver when its
 * diameter exceeds κ · max(distance, z_min); farther or smaller triangles
 * keep the vertex rule, whose relative error is of order (diam / scale)²
 * (docs/physics.md §9 has the measurement that fixed it). */
#define SSS_HAT_KAPPA 0.25
/* Leaf size of the adaptive subdivision, against the same scale: measured
 * on the 23K dragon at 1000 mm per unit in marble, the corrections then
 * differ from those of leaves 5× smaller by at most 1e-5 of q. */
#define SSS_HAT_KAPPA_LEAF 1.0

/* out[k · C + c] = (1/π) ∫_T λ_k(x) R_d,c(‖x − x_o‖) dA for the triangle
 * with corners p[0..2] (mm; λ_k its barycentric coordinates), receiver
 * xo (mm), channels dip[0..C−1]. Adaptive 4-way subdivision until a piece's
 * diameter is at most SSS_HAT_KAPPA_LEAF times the profile's scale there —
 * its distance to x_o, but at least the smallest z_r and at most the
 * exponential's decay length 1/σtr — then the 7-point degree-5 rule on each
 * piece, in a fixed order (deterministic). */
void sss_hat_triangle(const sss_dipole *dip, uint32_t C, const double p[3][3], const double xo[3], double *out);

/* (1/π) R_d(√x) from the polynomial table the quadrature uses, built for
 * x up to xmax (test hook: the table against sss_rd). */
double sss_hat_rdpoly_check(const sss_dipole *d, double xmax, double x);

/* The smallest z_r of the channels: the width of R_d's sharpest peak. */
double sss_hat_zmin(const sss_dipole *dip, uint32_t C);

/* The corrections C(o, i) = W(o, i) − w(o, i) as weight rows (sss/weights.h)
 * for the receivers `targets` (NULL: every vertex in order; row t is
 * target t), entries in increasing source index, zeros left out. mesh must
 * have its areas; radius_mm is the neighbourhood cutoff of the point rule
 * (w = 0 beyond it, so W is then the whole entry). Deterministic whatever
 * the thread count; polls cancel. Errors: SSS_ERR_ARG, SSS_ERR_NOMEM,
 * SSS_ERR_INTERRUPTED. */
sss_result sss_hat_corrections(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t C,
                               double radius_mm, const uint32_t *targets, uint32_t ntargets,
                               const sss_cancel_flag *cancel, sss_weights *out, sss_error *err);

/* The same entries for the sources `sel` names only (one row per vertex,
 * sel->idx of row o the wanted sources of receiver o, any order; its
 * weights are not read), each with the bits sss_hat_corrections gives it,
 * at a fraction of the cost when the selection is small: the near terms
 * of a reader (sss_near_build_spec) need no more. */
sss_result sss_hat_corrections_of(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t C,
                                  double radius_mm, const sss_weights *sel, const sss_cancel_flag *cancel,
                                  sss_weights *out, sss_error *err);

/* The neighbourhood cutoff of the bake (Hao–Varshney 2004 §3.1's N(x_o)):
 * per channel the radius holding 1 − ε of R_d's total (docs/physics.md
 * §2 (b)), clamped to the object's bounding-box diagonal; fills
 * radius_mm[c] (may be NULL) and returns the largest, the one searched. */
double sss_cutoff_radius_mm(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t C, double eps,
                            double *radius_mm);

/* The point rule of nbhd.c in double for a source i ≠ o at distance r (mm)
 * with area dA (mm²), not coincident with o and inside the cutoff:
 * (1/π) ∫ R_d over i's area as a disk when that disk covers x_o, else
 * (1/π) R_d(r) ΔA (Hao–Varshney 2004 §3.1). */
double sss_point_weight(const sss_dipole *d, double r, double dA);

#ifdef __cplusplus
}
#endif
#endif
