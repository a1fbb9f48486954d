/* sss/bake.h: the precompute pipeline of Hao–Varshney 2004 §3:
 * scattering neighbourhoods → visibility from each light direction →
 * integrals q(x_o, ω_j) → quantisation, producing an sss_bake_file.
 *
 * The steps are exposed separately so that tests and the exact evaluator can
 * run them on a subset of vertices or directions.
 */
#ifndef SSS_BAKE_H
#define SSS_BAKE_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/dirset.h"
#include "sss/format.h"
#include "sss/mesh.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Options; a zero field means its default. */
typedef struct sss_bake_options {
    double mm_per_unit;  /* millimetres per mesh unit (default 1) */
    uint32_t n_dirs;     /* light directions (default 200) */
    double eps;          /* neighbourhood energy cutoff ε: radius captures 1−ε of R_d,total (default 1e-3) */
    sss_quant quant;     /* SSS_QUANT_FLOAT (default) or SSS_QUANT_LLOYD8 */
    int threads;         /* OpenMP threads (default: OpenMP's own) */
    int progress;        /* non-zero: progress bar with ETA on stderr when it is a terminal */
    /* Integrals (issue 8, sss/gather.h): SSS_GATHER_DIRECT sums every
     * neighbour (nbhd.c + sss_integrate); SSS_GATHER_TREE takes far sources
     * through an octree of flux moments and the rest as dense matrix-product
     * blocks (gather_gemm.c).
     * SSS_GATHER_AUTO (0, default): the tree (measured: docs/benchmarks.md). */
    int gather;
    double theta;        /* tree opening threshold (default SSS_GATHER_THETA_DEFAULT) */
    /* MPI (sss-bake under mpirun): this process is rank `rank` of `nranks`
     * (0/0: alone); the tree gather splits its receiver blocks across ranks
     * and `comm` (set by the tool) moves the pieces; rank 0 gets all. */
    int rank, nranks;
    const struct sss_bake_comm *comm;
    /* Near terms (sss/ownterm.h, docs/format.md §5.14): SSS_OWN_TERM_RUNTIME
     * stores q minus the vertex's own term and its `own_rings` mesh rings
     * and marks the file (OWNT, format 1.3) so that readers add them back
     * with every vertex's own shadow test; 0 (default) stores q itself, as
     * the paper does. */
    uint32_t own_term;
    uint32_t own_rings;
} sss_bake_options;

enum { SSS_GATHER_AUTO = 0, SSS_GATHER_DIRECT = 1, SSS_GATHER_TREE = 2 };

/* Collective operations the bake needs under MPI, supplied by the tool (so
 * that libsss_bake does not link MPI). */
typedef struct sss_bake_comm {
    /* every rank passes its part [my_off, my_off + my_len) of buf (bytes);
     * afterwards every rank holds all of buf (parts in rank order) */
    int (*allgather)(void *buf, const uint64_t *offs, const uint64_t *lens, void *ctx);
    /* every rank sends its part (lens[rank] bytes); rank 0 receives all of
     * them into full (parts at offs[r]; full is NULL on the other ranks) */
    int (*gather0)(const void *part, void *full, const uint64_t *offs, const uint64_t *lens, void *ctx);
    void *ctx;
} sss_bake_comm;

/* What a bake measured (seconds are wall-clock). */
typedef struct sss_bake_stats {
    double t_neighbourhoods, t_visibility, t_integrals, t_quantise;
    double radius_mm[SSS_MAX_CHANNELS];  /* neighbourhood radius per channel */
    double search_radius_mm;             /* max over channels: the one searched */
    uint64_t neighbours_total;           /* Σ |N(x_o)| including x_o itself */
    double neighbours_mean;
    uint32_t neighbours_max;
    uint64_t rays;                       /* occlusion rays traced */
    double occluded_fraction;            /* of the traced rays */
    double lloyd_snr_db[SSS_MAX_CHANNELS]; /* lloyd8 only: 10 log10(Σq² / Σ(q − q̂)²) per channel */
    double lloyd_snr_db_all;             /* same over all channels */
    /* Vertices with an incident edge longer than 2/σtr of the channel with
     * the longest range: there the per-vertex sum (Hao–Varshney 2004 §3.1,
     * "each vertex represents a small area") does not resolve even the
     * smoothest profile, and q comes out too large (docs/robustness.md B3).
     * The tool warns with this count. */
    uint32_t coarse_vertices;
    double longest_edge_mm;              /* the longest edge of the mesh */
    double range_mm;                     /* 1/σtr of that channel (∞ for σa = 0 is reported as the radius) */
    /* Vertices whose thickness (from the vertex along −n to the next
     * surface) is below thin_limit_mm = range_mm: the semi-infinite dipole
     * counts light through such parts twice (docs/robustness.md B8). The
     * tool warns with this count. */
    uint32_t thin_vertices;
    double thin_limit_mm;
    double thinnest_mm;                  /* smallest thickness found (∞: no ray hit) */
    /* Issue 8: the gather used, its measurements and the memory. */
    int gather;                          /* SSS_GATHER_DIRECT or SSS_GATHER_TREE */
    double theta;
    double t_tree;                       /* tree build (Morton order, nodes, moments) */
    /* tree: GFLOP/s inside the block products (packing Ψ included; named
     * when they were OpenBLAS's sgemm), direct: multiply-adds × 2 / s */
    double gather_gflops;
    double sgemm_fraction;               /* share of the integrals' thread time spent in the block products */
    /* tree: the near field as a whole, assembly included: 2 · C · B · rows
     * · D flops of the block products (B receivers, rows = near sources +
     * 10 per far node, D directions) over the thread-seconds of everything
     * done per block (interaction lists, Ψ's row pointers, the weights,
     * the product, writing q): GFLOP/s per thread, to set against
     * sgemm_peak */
    double near_gflops;
    double rows_mean;                    /* tree: dense rows per receiver block */
    uint32_t tree_nodes, tree_blocks;
    uint64_t near_pairs, far_pairs;      /* tree: receiver × near source, receiver × far node */
    uint64_t predicted_peak_bytes;       /* estimate made before starting */
    /* tree: the light directions were processed in this many chunks of at
     * most direction_chunk_width (1 and all of them when everything fits;
     * more when the transfer rows and tree moments of every direction would
     * not fit next to q: same bytes, docs/benchmarks.md) */
    uint32_t direction_chunks, direction_chunk_width;
} sss_bake_stats;

/* Scattering neighbourhoods N(x_o) in compressed-row form with the per-channel
 * weights w_c(o, i) = (1/π) R_d,c(‖x_i − x_o‖) ΔA(x_i) (mm² · 1/mm² = sr⁻¹ units
 * of q), and for i = o the self term (1/π) ∫_disk R_d dA over a disk of x_o's
 * own area (physics sheet §2 (a)). Rows list neighbours in increasing index
 * order, so sums are taken in the same order whatever the thread count. */
typedef struct sss_nbhd {
    uint32_t nrows;       /* number of target vertices */
    uint32_t channels;
    uint64_t *start;      /* nrows + 1 offsets into idx / w */
    uint32_t *idx;        /* neighbour vertex indices */
    float *w;             /* channels weights per entry, interleaved */
} sss_nbhd;

/* Builds neighbourhoods for `targets` (ntargets vertex indices; NULL means all
 * vertices in order). mesh must have area computed. radius_mm is the search
 * radius; dip[c] the channel models. Counts first: if the rows would take
 * more than max_bytes (0: no limit), fails with SSS_ERR_NOMEM and a message
 * giving the size before allocating them. */
sss_result sss_nbhd_build(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t channels,
                          double radius_mm, const uint32_t *targets, uint32_t ntargets, uint64_t max_bytes,
                          sss_nbhd *out, sss_error *err);
void sss_nbhd_free(sss_nbhd *nb);

/* The neighbourhood radius rule, shared by the bake, the exact evaluator and
 * the scene passes so that all of them find the same neighbourhoods: per
 * channel the disk holding 1−ε of R_d,total (physics sheet §2 (b)), clamped
 * to the object's diagonal (α′ → 1). Fills radius_mm[c] (may be NULL) and
 * returns the largest, the radius searched. */
double sss_nbhd_radii(const sss_mesh *mesh, double mm_per_unit, const sss_dipole *dip, uint32_t channels, double eps,
                      double *radius_mm);

/* Visibility V(x_i, ω_j) by occlusion rays (Embree). The paper used shadow
 * maps (§3.1); rays are exact up to the origin offset. */
typedef struct sss_vis sss_vis;
sss_result sss_vis_create(const sss_mesh *mesh, sss_vis **out, sss_error *err);
void sss_vis_destroy(sss_vis *vis);
/* Is vertex v's light from direction d (unit, towards the light) blocked? */
int sss_vis_occluded(const sss_vis *vis, uint32_t v, const double d[3]);
/* Every vertex's own visibility towards unit d, lit[v] = 1 when it faces d
 * (n_v·d > 0, in double) and its ray is not blocked — the rule of the
 * bake's transfer rows, where back-facing vertices trace no ray. mesh is
 * the one vis was built on (its normals). Returns the rays traced. */
uint64_t sss_vis_lit_all(const sss_vis *vis, const sss_mesh *mesh, const double d[3], uint8_t *lit);
/* Visibility for a scene (docs/scenes.md): rays start at mesh's vertices
 * (offset as above, from mesh's own diagonal) and are tested against mesh
 * itself when self != 0 and against the nocc occluder meshes (same world
 * units). sss_vis_create(m) is sss_vis_create_scene(m, 1, NULL, 0). */
sss_result sss_vis_create_scene(const sss_mesh *mesh, int self, const sss_mesh *const *occ, uint32_t nocc,
                                sss_vis **out, sss_error *err);
/* The same test with the ray ending at distance tfar (mesh units): a point
 * light's shadow ends at the light. */
int sss_vis_occluded_upto(const sss_vis *vis, uint32_t v, const double d[3], double tfar);

/* Per-vertex light transport towards each direction, independent of x_o:
 * G[i * n + j] = F_t(η, n_i·ω_j) · max(0, n_i·ω_j) · V(x_i, ω_j)
 * for all vertices i (Hao–Varshney 2004 §3.1, eq. for q). rays/occluded
 * (may be NULL) count the rays traced and blocked. */
sss_result sss_transfer_compute(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n, double eta,
                                float *G, uint64_t *rays, uint64_t *occluded, sss_error *err);

/* q for every neighbourhood row and direction: q[(j * nrows + r) * channels + c]
 * = Σ_i w_c(r, i) G[i * n + j], accumulated in double. */
void sss_integrate(const sss_nbhd *nb, const float *G, uint32_t n, float *q);

/* Lloyd–Max scalar quantiser with 256 levels for one channel: trains on
 * (a deterministic subsample of) x[k * stride], k < count, writes levels in
 * increasing order (level 0 pinned to the minimum, so shadowed zeros decode
 * as zeros) and idx[k * stride]. Returns Σx² and Σ(x − x̂)² via the pointers. */
sss_result sss_lloyd8(const float *x, uint64_t count, uint32_t stride, float levels[256], uint8_t *idx,
                      double *signal, double *noise, sss_error *err);

/* The same quantiser with nlevels (2 … 256) levels; pin_min pins level 0 to
 * the minimum (what sss_lloyd8 does), else every level is a free centroid
 * (signed data such as SH coefficients). */
sss_result sss_lloyd(const float *x, uint64_t count, uint32_t stride, uint32_t nlevels, int pin_min, float *levels,
                     uint8_t *idx, double *signal, double *noise, sss_error *err);

/* The whole bake: writes out (mesh copy, material, dirs, q or levels+qidx,
 * params JSON) and stats. `mesh_name` goes into the params JSON. */
sss_result sss_bake(const sss_mesh *mesh, const char *mesh_name, const sss_material *mat,
                    const sss_bake_options *opt, sss_bake_file *out, sss_bake_stats *stats, sss_error *err);

/* Set by a SIGINT handler to stop a bake early (returns SSS_ERR_INTERRUPTED). */
extern volatile int sss_bake_interrupted;

#ifdef __cplusplus
}
#endif
#endif
