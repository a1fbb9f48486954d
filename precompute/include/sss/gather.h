/* sss/gather.h: the hierarchical gather of the bake. It computes the same
 * integrals as sss_nbhd_build + sss_integrate,
 *   q_c(x_o, ω_j) = Σ_{i: ‖x_i − x_o‖ ≤ R} w_c(o, i) G[i, j]
 * (Hao–Varshney 2004 §3.1, w_c = (1/π) R_d,c(r) ΔA(x_i), self term and
 * near disks as in nbhd.c), without visiting every (x_o, x_i) pair:
 *
 * - Far field (gather_tree.c): an octree over the source vertices in Morton
 *   order. Each node stores per direction its aggregated flux
 *   Φ_j = Σ G[i, j] ΔA_i and the first and second moments of that flux
 *   about the node's area centroid. A node far from a block of receivers
 *   (node radius < θ × distance) contributes (1/π) times the Taylor
 *   expansion of R_d about the centroid to second order, applied to the
 *   moments: the octree of Jensen & Buhler 2002 §4 (their nodes keep total
 *   irradiance and an irradiance-weighted centre, i.e. the monopole), one
 *   order further so that θ = 0.5 meets a 10⁻³ relative error. The paper
 *   itself (seed 001 §3.1) points to that octree for O(N log N).
 * - Dense blocks (gather_blocks.c): receivers are grouped in Morton blocks; a
 *   block's near sources and the rows of its far nodes form one dense
 *   weight matrix W (channels × receivers by rows), multiplied by the stacked
 *   flux rows (rows × directions), one register-tiled product per block
 *   (gather_gemm.c; OpenBLAS's sgemm before, measured in docs/benchmarks.md).
 *
 * Cutoff: a source farther than R from x_o contributes nothing, as in the
 * direct sum; near sources are tested one by one (exactly nbhd.c's test),
 * a far node by its centroid (a node straddling the sphere is included for
 * the receivers whose distance to its centroid is ≤ R; errors of either sign
 * along the sphere, where R_d has fallen to ε of its energy, measured in
 * docs/benchmarks.md).
 *
 * Determinism: each block is computed by one thread in a fixed order, and
 * every element of the product is one chain of fused multiply-adds in row
 * order on every vector width, so q does not depend on the thread count,
 * on the number of MPI ranks or on the CPU's vector extensions.
 *
 * Directions in chunks (docs/benchmarks.md, "Bake at scale"; memory): the hierarchy does not depend on
 * the light directions. A bake that cannot hold the transfer rows and the
 * moments of all directions next to q builds it once
 * (sss_gather_tree_create) and loads a chunk of directions at a time
 * (sss_gather_tree_rows, sss_gather_tree_moments, sss_gather_run_chunk),
 * with the same bits as one pass over all of them (a column of the block
 * product does not depend on the other columns, gather_gemm.c).
 */
#ifndef SSS_GATHER_H
#define SSS_GATHER_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/fieldweights.h"
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Default opening threshold θ: a node of radius r_n at distance d from a
 * receiver block (minus the block's radius) is far when r_n < θ d. */
#define SSS_GATHER_THETA_DEFAULT 0.4

/* Rows of flux moments stored per node and direction: Φ, M1 (x, y, z),
 * M2 (xx, yy, zz, xy, xz, yz). */
#define SSS_GATHER_MOMENTS 10

typedef struct sss_gather_params {
    double theta;        /* opening threshold in (0, 1) (default SSS_GATHER_THETA_DEFAULT) */
    uint32_t leaf_size;  /* most sources in a leaf (default 32) */
    uint32_t block_size; /* most receivers in a block (default 128: 64 before; measured, docs/benchmarks.md
                          * "dense blocks": blocks of 47 receivers on average instead of 19, the rows of Ψ
                          * copied and packed once for more receivers, 20 % more rows per block) */
    const sss_cancel_flag *cancel; /* polled per receiver block by sss_gather_run (sss/result.h); NULL: never */
    /* Non-zero: the sources take either sign (the components of the vector
     * integral Q, Hao–Varshney 2004 §3.1) and the sums are written as they
     * are; 0: q, a sum of non-negative terms, clamped at 0 */
    int signed_sources;
} sss_gather_params;

/* What the gather measured. */
typedef struct sss_gather_stats {
    uint32_t nodes, leaves, blocks;
    uint64_t near_pairs;      /* Σ over blocks of receivers × near sources */
    uint64_t far_pairs;       /* Σ over blocks of receivers × far nodes */
    double rows_mean;         /* mean rows (near sources + 10 per far node) per block */
    uint64_t field_kept;      /* with a field: near κ read from the group's table, not computed (§4.5 of
                               * docs/heterogeneous.md) */
    double flops;             /* 2 · C · B · rows · directions summed over the block products */
    double t_build;           /* Morton order, nodes, moments (s) */
    /* thread-seconds: CPU time of the threads (CLOCK_THREAD_CPUTIME_ID), so
     * that other jobs on a shared machine do not inflate them */
    double t_lists;           /* interaction lists and stacking the rows of Ψ */
    double t_weights;         /* weight matrices */
    double t_sgemm;           /* inside the block product (gather_gemm.c; the name is from when it was sgemm) */
    double t_scatter;         /* writing q out */
} sss_gather_stats;

/* The source hierarchy with its per-direction flux moments. */
typedef struct sss_gather_tree sss_gather_tree;

/* Builds the hierarchy over all vertices of mesh (areas computed) in mm
 * (positions × mm_per_unit) and its moments from G (nv × n_dirs, the
 * transfer table of sss_transfer_compute). The tree keeps its own copy of
 * G in Morton order (near rows are read from it): the caller may free G.
 * The same as sss_gather_tree_create, sss_gather_tree_rows filled from G,
 * sss_gather_tree_moments. */
sss_result sss_gather_tree_build(const sss_mesh *mesh, double mm_per_unit, const float *G, uint32_t n_dirs,
                                 const sss_gather_params *p, sss_gather_tree **out, sss_error *err);
/* The hierarchy alone (Morton order, nodes, receiver blocks): it does not
 * depend on the light directions, so a bake that cannot hold the transfer
 * rows and moments of every direction at once builds it once and loads
 * the directions a chunk at a time (bake_tree.c). */
sss_result sss_gather_tree_create(const sss_mesh *mesh, double mm_per_unit, const sss_gather_params *p,
                                  sss_gather_tree **out, sss_error *err);
/* Morton position → vertex (nv entries): row m of sss_gather_tree_rows is
 * vertex order[m]. */
const uint32_t *sss_gather_tree_order(const sss_gather_tree *t);
/* The tree's transfer rows for n_dirs directions (nv × n_dirs floats, row m
 * for vertex order[m], G[i, j] of sss_transfer_compute), for the caller to
 * fill before sss_gather_tree_moments; owned by the tree, reused when the
 * next chunk is no wider. NULL when out of memory. */
float *sss_gather_tree_rows(sss_gather_tree *t, uint32_t n_dirs);
/* Switches params.signed_sources of a built tree: the bake gathers q and
 * then Q's components through one hierarchy (bake_tree.c). */
void sss_gather_tree_set_signed(sss_gather_tree *t, int signed_sources);
/* A heterogeneous object's kernel κ (docs/heterogeneous.md §4, §4.5) for
 * every later sss_gather_run: each near pair's weight scaled by κ(o, i)
 * exactly as the direct rows scale it (sss_field_kappa), each far node's
 * moment weights by κ between the receiver and the node's area centroid,
 * with the field's f read at the centroid (sss_field_kappa_point). k is
 * borrowed (built for the same mesh, its reference dipoles and radius the
 * run's) and must outlive the runs; NULL removes it. gather_field.c. */
sss_result sss_gather_tree_set_field(sss_gather_tree *t, const sss_mesh *mesh, const sss_field_kernel *k,
                                     sss_error *err);
/* Every node's flux moments from the rows loaded. */
sss_result sss_gather_tree_moments(sss_gather_tree *t, const sss_mesh *mesh, sss_error *err);
void sss_gather_tree_destroy(sss_gather_tree *t);

/* Receiver blocks (Morton order) and the vertices of block b. */
uint32_t sss_gather_tree_blocks(const sss_gather_tree *t);
/* Receivers of blocks [b0, b1): their count, and (if vertices != NULL)
 * their vertex indices in block order. */
uint32_t sss_gather_tree_block_vertices(const sss_gather_tree *t, uint32_t b0, uint32_t b1, uint32_t *vertices);

/* Bytes the tree takes for nv vertices and n_dirs directions (an upper
 * bound, for the memory estimate before the bake). */
uint64_t sss_gather_tree_bytes(uint32_t nv, uint32_t n_dirs, const sss_gather_params *p);

/* q for the receivers of blocks [b0, b1): out[(k · n_dirs + j) · C + c]
 * for the k-th receiver in block order (sss_gather_tree_block_vertices),
 * or, when out_q_full is set, q[(j · nv + v) · C + c] for its vertex v
 * (the layout of sss_integrate and the file). radius_mm is the cutoff R,
 * dip[c] the channel models. Progress ticks each block's work
 * (sss_gather_block_work). */
sss_result sss_gather_run(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip, uint32_t channels,
                          double radius_mm, uint32_t b0, uint32_t b1, float *out, int out_q_full,
                          sss_gather_stats *stats, sss_error *err);
/* The same for a chunk of directions: the tree holds directions
 * [j0, j0 + D) of n_total (D = the width loaded by sss_gather_tree_rows).
 * out_q_full: q[((j0 + j) · nv + v) · C + c] of the whole q (n_total
 * directions); else out[(k · D + j) · C + c], the chunk alone. The values
 * have the same bits as those of one sss_gather_run over all n_total
 * directions (gather_gemm.c: a column's bits do not depend on the others). */
sss_result sss_gather_run_chunk(const sss_gather_tree *t, const sss_mesh *mesh, const sss_dipole *dip,
                                uint32_t channels, double radius_mm, uint32_t b0, uint32_t b1, uint32_t j0,
                                uint32_t n_total, float *out, int out_q_full, sss_gather_stats *stats, sss_error *err);

/* Rows of each block's dense product (near sources + SSS_GATHER_MOMENTS per
 * far node) for blocks [b0, b1), into rows[b − b0]: the interaction lists
 * alone, without weights or products (a tree walk per block, about 1 % of
 * the gather). Blocks' work differs by 100× and more between a dense and a
 * sparse region, so progress and the MPI split weigh blocks by it. */
sss_result sss_gather_block_rows(const sss_gather_tree *t, double radius_mm, uint32_t b0, uint32_t b1, uint32_t *rows,
                                 sss_error *err);
/* Estimated work of block b with `rows` rows for a chunk of n_dirs
 * directions (the units of sss_gather_run's progress ticks: about one flop
 * of the block product; the weights, the rows packed and q written counted
 * at their measured cost per element, docs/benchmarks.md). */
uint64_t sss_gather_block_work(const sss_gather_tree *t, uint32_t b, uint32_t rows, uint32_t channels, uint32_t n_dirs);

/* Bytes the built tree t takes with n_dirs directions loaded (exact, but
 * for malloc's own overhead). */
uint64_t sss_gather_tree_size(const sss_gather_tree *t, uint32_t n_dirs);
/* Bytes of the work space of sss_gather_run over `threads` threads when no
 * block has more than max_rows rows (sss_gather_block_rows): an upper
 * bound, the buffers growing by half again when they grow. */
uint64_t sss_gather_workspace_rows_bytes(uint32_t max_rows, uint32_t n_dirs, uint32_t channels,
                                         const sss_gather_params *p, int threads);
/* Bytes of per-thread work space of sss_gather_run (an estimate). */
uint64_t sss_gather_workspace_bytes(uint32_t nv, uint32_t n_dirs, uint32_t channels, const sss_gather_params *p,
                                    int threads);
/* Bytes a field (sss_gather_tree_set_field) adds to sss_gather_run's work
 * space over `threads` threads: each thread's near pairs' κ within the
 * group of blocks it runs (docs/heterogeneous.md §4.5). */
uint64_t sss_gather_field_workspace_bytes(int threads);

#ifdef __cplusplus
}
#endif
#endif
