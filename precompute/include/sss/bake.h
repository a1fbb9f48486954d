/* sss/bake.h: the precompute pipeline of Hao–Varshney 2004 §3:
 * scattering neighbourhoods → visibility from each light direction →
 * integrals q(x_o, ω_j) → quantisation or compression (§4), producing an
 * sss_bake_file with its provenance.
 *
 * The steps are kernels with headers of their own (sss/nbhd.h,
 * sss/visibility.h, sss/transfer.h, sss/lloyd.h, sss/gather.h,
 * sss/compress.h), so that tests and the exact evaluator can run them on a
 * subset of vertices or directions; sss/precompute.h includes them all.
 */
#ifndef SSS_BAKE_H
#define SSS_BAKE_H

#include <stdint.h>
#include "sss/dipole.h"
#include "sss/dirset.h"
#include "sss/format.h"
#include "sss/hatweights.h"
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
    /* Integrals (docs/benchmarks.md, "Bake at scale"; sss/gather.h): SSS_GATHER_DIRECT sums every
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
    /* Near terms (sss/nearterms.h, docs/format.md §5.14): SSS_NEAR_TERMS_RUNTIME
     * stores q minus the vertex's own term and its `near_rings` mesh rings
     * and marks the file (OWNT, format 1.3) so that readers add them back
     * with every vertex's own shadow test; 0 (default) stores q itself, as
     * the paper does. */
    uint32_t near_terms;
    uint32_t near_rings;
    /* > 0 (with near_terms): the near terms are every vertex within this
     * many mm of x_o, connected or not (sss_near_spec, section NRAD),
     * instead of near_rings rings */
    double near_radius_mm;
    /* In (0, 1), with near_terms and near_radius_mm 0: the radius is chosen
     * from the material, the disk that holds this fraction of R_d,total in
     * every channel (sss_near_radius_material; docs/accuracy.md, "Near terms
     * sized by the material"), so that a fine and a coarse mesh of one
     * object split off the same neighbourhood. 0: rings or near_radius_mm. */
    double near_fraction;
    /* The weights of the sum (sss/hatweights.h): SSS_WEIGHTS_POINT (0, the
     * paper's point samples) or SSS_WEIGHTS_HAT (integrated over the
     * vertices' hat functions; section QUAD, docs/physics.md §9). */
    uint32_t weights;
    /* Compression (sss/compress.h) as the last stage, after any preset was
     * applied (sss_compress_preset); NULL: q stays as `quant` says (which
     * must then be SSS_QUANT_FLOAT when this is set). */
    const struct sss_compress_opts *compress;
    /* What the importer subtracted from every position (sss_import_report
     * .offset when .recentred), recorded in the provenance; NULL: nothing. */
    const double *import_offset;
    /* Bytes the bake may use; 0: what the system reports available
     * (MemAvailable). A smaller system figure wins. */
    uint64_t memory_limit;
    /* With progress: also append every redraw of the bar to this file
     * (kernels/progress.h has the line format); NULL: no log. */
    const char *progress_log;
    /* Non-zero: also the vector integrals Q(x_o, ω_j) of Hao–Varshney 2004
     * §3.1 (section QVEC, docs/format.md §5.19), three sums per direction
     * and channel through the same gather, weights, visibility and near
     * terms as q (sss-bake --vector). Not with compression, nor under MPI. */
    int vector;
    int verbose;         /* non-zero: the gather's own figures on stderr */
    const sss_cancel_flag *cancel; /* polled by every phase (sss/result.h); NULL: never */
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
    double t_compress;                   /* the compression stage (options.compress) */
    double radius_mm[SSS_MAX_CHANNELS];  /* neighbourhood radius per channel */
    double search_radius_mm;             /* max over channels: the one searched */
    uint64_t neighbours_total;           /* Σ |N(x_o)| including x_o itself */
    double neighbours_mean;
    uint32_t neighbours_max;
    uint64_t rays;                       /* occlusion rays traced */
    double occluded_fraction;            /* of the traced rays */
    double lloyd_snr_db[SSS_MAX_CHANNELS]; /* lloyd8 only: 10 log10(Σq² / Σ(q − q̂)²) per channel */
    double lloyd_snr_db_all;             /* same over all channels */
    /* Point weights: vertices with an incident edge longer than 2/σtr of
     * the channel with the longest range, where the per-vertex sum
     * (Hao–Varshney 2004 §3.1, "each vertex represents a small area") does
     * not resolve even the smoothest profile and q comes out too large
     * (docs/robustness.md B3). Hat weights, which integrate R_d over such
     * triangles: only where such an edge also bends by more than 30°
     * between its ends' normals, which the irradiance, linear along the
     * edge, cannot follow. The tool warns with this count. */
    uint32_t coarse_vertices;
    /* Near terms at run time: their entries over all rows, which every
     * reader builds (an index and a float per channel each) and sums each
     * frame; the tool warns when the weights exceed the 128 MiB storage
     * block that OpenGL 4.3 guarantees (GL_MAX_SHADER_STORAGE_BLOCK_SIZE ≥
     * 2^27), beyond which the viewer uploads them in chunks. */
    uint64_t near_entries;
    /* With the radius from the material: the fraction of R_d,total it
     * holds, and 1 where SSS_NEAR_ENTRIES_MAX shrank it (sss/nearterms.h) */
    double near_fraction_held;
    int near_capped;
    double longest_edge_mm;              /* the longest edge of the mesh */
    double range_mm;                     /* 1/σtr of that channel (∞ for σa = 0 is reported as the radius) */
    /* Vertices whose thickness (from the vertex along −n to the next
     * surface) is below thin_limit_mm = range_mm: the semi-infinite dipole
     * counts light through such parts twice (docs/robustness.md B8). The
     * tool warns with this count. */
    uint32_t thin_vertices;
    double thin_limit_mm;
    double thinnest_mm;                  /* smallest thickness found (∞: no ray hit) */
    /* The gather used (docs/benchmarks.md, "Bake at scale"), its measurements and the memory. */
    int gather;                          /* SSS_GATHER_DIRECT or SSS_GATHER_TREE */
    double theta;
    double t_tree;                       /* tree build (Morton order, nodes, moments) */
    /* tree: GFLOP/s inside the block products (packing Ψ included; named
     * when they were OpenBLAS's sgemm), direct: multiply-adds × 2 / s */
    double gather_gflops;
    double sgemm_fraction;               /* share of the integrals' thread time spent in the block products */
    /* tree: the dense blocks as a whole, assembly included: 2 · C · B · rows
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
    /* SSS_WEIGHTS_HAT: the corrections' time and entries (receiver, source) */
    double t_hat;
    uint64_t hat_entries;
    /* options.vector: the time of Q's three gathers (within t_integrals) */
    double t_vector;
} sss_bake_stats;

/* The whole bake: writes out (mesh copy, material, dirs, q or levels+qidx
 * or the compressed form, the provenance JSON built from the options and
 * stats) and stats. `mesh_name` goes into the provenance. Cancelled through
 * opt->cancel: SSS_ERR_INTERRUPTED and nothing in out. */
sss_result sss_bake(const sss_mesh *mesh, const char *mesh_name, const sss_material *mat,
                    const sss_bake_options *opt, sss_bake_file *out, sss_bake_stats *stats, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
