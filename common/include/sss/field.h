/* sss/field.h: scalar material fields f(x) ∈ [0, 1] inside an object and
 * the material they blend (seed 000, Shopf 2007 §4.3.2: a polygonal mesh
 * with a scalar volume describing the density of the material;
 * docs/heterogeneous.md §1–§3). Positions are in millimetres in the
 * object's rest frame, so a field moves rigidly with its object.
 *
 * A field is a small record: a constant, one of five procedural kinds with
 * their parameters (deterministic noise of this file, no table), or a
 * sampled grid (trilinear, as OpenVDB dense grids are read). It owns the
 * grid's samples; sss_field_free releases them.
 */
#ifndef SSS_FIELD_H
#define SSS_FIELD_H

#include <stddef.h>
#include <stdint.h>
#include "sss/dipole.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum sss_field_kind {
    SSS_FIELD_NONE = 0,       /* no field: a homogeneous object */
    SSS_FIELD_CONSTANT = 1,   /* f = value */
    SSS_FIELD_VEINS = 2,      /* marble veins from turbulence (docs/heterogeneous.md §2.2) */
    SSS_FIELD_INCLUSIONS = 3, /* Worley inclusions: a ball around one random point per cell */
    SSS_FIELD_BOX = 4,        /* an embedded box, SDF with a smooth edge */
    SSS_FIELD_SPHERE = 5,     /* an embedded ball, SDF with a smooth edge */
    SSS_FIELD_LAYERS = 6,     /* planar strata */
    SSS_FIELD_GRID = 7        /* sampled values, trilinear between nodes */
} sss_field_kind;
#define SSS_FIELD_KINDS 8

/* The largest grid accepted: 512³ nodes (512 MiB of float32 would be more
 * than any scene needs; a hostile header must not allocate it). */
#define SSS_FIELD_GRID_MAX_NODES (512u * 512u * 512u)

typedef struct sss_field {
    uint32_t kind;          /* sss_field_kind */
    uint32_t seed;          /* veins, inclusions: the noise's seed */
    double value;           /* constant: c ∈ [0, 1] */
    double scale_mm;        /* veins: period; inclusions: cell size; layers: period (0: one stratum) */
    double centre_mm[3];    /* box, sphere: centre */
    double half_mm[3];      /* box: half extents; sphere: radius in [0] */
    double normal[3];       /* layers: unit normal of the strata */
    double thickness_mm;    /* layers: thickness of the f = 1 stratum; inclusions: radius of each ball */
    double offset_mm;       /* layers: signed distance of the first stratum's lower face from the origin */
    double edge_mm;         /* box, sphere, layers, inclusions: width of the smooth edge (0: a step) */
    /* grid: n[0] × n[1] × n[2] nodes, node (i, j, k) at origin + voxel · (i, j, k),
     * value at data[(k · n[1] + j) · n[0] + i] */
    uint32_t n[3];
    double origin_mm[3];
    double voxel_mm;
    float *data;            /* owned */
} sss_field;

/* What a heterogeneous object adds to its (base) material: the field, the
 * material at f = 1, and where the field sits (docs/heterogeneous.md §3). */
typedef struct sss_hetero {
    sss_field field;        /* kind SSS_FIELD_NONE: homogeneous */
    sss_material inside;    /* the material at f = 1; η is the base's (one surface) */
    double xf[12];          /* world (bake) units → rest-frame mm, row-major 3 × 4 */
    /* 1: a surface texture (Hao–Varshney 2004 §5: "the marble texture is
     * on-surface, and will affect both x_i and x_o"): f is read at the
     * endpoints only and nothing is marched between them
     * (docs/heterogeneous.md §4.4); 0: a volume field */
    int surface;
} sss_hetero;

const char *sss_field_kind_name(uint32_t kind);

/* Checks the parameters of f (ranges in docs/heterogeneous.md §2); the
 * message names the parameter. */
sss_result sss_field_check(const sss_field *f, sss_error *err);

/* f(x) ∈ [0, 1] at x (rest-frame mm). NONE gives 0. */
double sss_field_eval(const sss_field *f, const double x_mm[3]);

/* The smooth value noise the procedural kinds are built from
 * (docs/heterogeneous.md §2.1), n(x / scale_mm) ∈ [0, 1) at x (mm): one
 * octave, C¹, features about scale_mm apart. */
double sss_field_noise(const double x_mm[3], double scale_mm, uint32_t seed);

/* The step (mm) that resolves f along a segment: half the finest feature
 * (docs/heterogeneous.md §4.2); 0 for a constant (nothing to march). */
double sss_field_step_mm(const sss_field *f);

/* Whether f has anything inside the box [lo, hi] (rest-frame mm): a grid
 * must cover the box (within half a voxel), a box or sphere must meet it.
 * 0 and a message ("the grid's box ... does not cover ...") otherwise. */
int sss_field_covers(const sss_field *f, const double lo_mm[3], const double hi_mm[3], char *why, size_t n);

/* Samples f on a grid of nodes spanning [lo, hi] with at most nmax nodes
 * along the longest side (cubic voxels): what the .vdb writer stores. */
sss_result sss_field_sample(const sss_field *f, const double lo_mm[3], const double hi_mm[3], uint32_t nmax,
                            sss_field *grid, sss_error *err);

/* Deep copy (the grid's samples too). */
sss_result sss_field_copy(const sss_field *src, sss_field *dst, sss_error *err);

/* Frees the grid's samples and zeroes f. NULL-safe. */
void sss_field_free(sss_field *f);

/* The material at f: σa and σ′s linear in f between a (f = 0) and b
 * (f = 1), η and the name of a (docs/heterogeneous.md §3). Exact at f = 0
 * and f = 1. */
void sss_material_blend(const sss_material *a, const sss_material *b, double f, sss_material *out);

/* σtr = sqrt(3 σa σ′t) of channel c of the blend at f (1/mm). */
double sss_material_sigma_tr(const sss_material *a, const sss_material *b, double f, uint32_t c);

/* Shopf 2007 §4.3.3's transport colour T_c reached after a transport
 * distance T_d: exp(−σtr,c T_d) = T_c,c gives σtr, and with the material's
 * σ′s, σa = 2σtr²/3 / (σ′s + sqrt(σ′s² + 4σtr²/3)) (the root of
 * 3σa(σa + σ′s) = σtr²; docs/heterogeneous.md §3.1). Colours in (0, 1),
 * distance > 0. */
sss_result sss_transport_sigma_a(const double colour[3], double distance_mm, const double sigmap_s[3],
                                 double sigma_a[3], sss_error *err);

/* xf applied to a world point (units) → rest-frame mm. */
void sss_hetero_to_rest(const sss_hetero *h, const double p[3], double x_mm[3]);

#ifdef __cplusplus
}
#endif
#endif
