/* sss/format.h: the .sss baked-scattering file, format version 1 (minor 1
 * adds the compressed forms of Hao–Varshney 2004 §4, minor 2 the effect
 * sections of scene bakes, docs/scenes.md, minor 3 the near terms added at
 * run time, minor 4 the neighbourhood cutoff ε as binary data, minor 5 the
 * hat-function weights and the near terms' radius in mm, minor 6 the
 * directions in float32 with 16-bit indices).
 * Spec: docs/format.md. Little-endian, magic + version, a section table with
 * 64-bit offsets and sizes and a CRC-32 per section; written atomically.
 */
#ifndef SSS_FORMAT_H
#define SSS_FORMAT_H

#include <stddef.h>
#include <stdint.h>
#include "sss/result.h"
#include "sss/mesh.h"
#include "sss/dipole.h"
#include "sss/dirset.h"
#include "sss/single.h"
#include "sss/field.h"

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_FORMAT_MAJOR 1
#define SSS_FORMAT_MINOR 9
/* The minor version plain bakes record in PARM ("format"), kept at 1 so
 * that their bytes do not change with 1.2, which only scene bakes use. */
#define SSS_FORMAT_MINOR_PLAIN 1
#define SSS_MAX_SECTIONS 32
/* The largest magnitude of any stored value of q, or of a quantity built
 * from q alone (Lloyd levels, SH codes' tables and scales, the exact
 * values of QDIR, the transfer T_i of ENVT, the shells of PSHL), and of the
 * probe coefficients L_i of ENVT. q is a fraction of the irradiance per sr
 * (Hao–Varshney 2004 §3.1; a physical bake stays below about 10), so 1e6
 * is far above anything a bake makes; with it every sum a decoder forms
 * (three rows, 64 SH terms, blended references with weights within ±16,
 * Σ_i T_i L_i) stays finite in float: an accepted file decodes to finite q
 * >= 0 by construction (docs/format.md §6, docs/robustness.md "Values"). */
#define SSS_VALUE_MAX 1e6
#define SSS_PROBE_SH_MAX 1e30
/* The smallest point-light shell radius (PSHL, world units): q_pt = stored
 * / r² with r clamped at the first shell stays below 1e36 (sss_fx_point). */
#define SSS_SHELL_RADIUS_MIN 1e-15
/* sss_bake_file.near_terms: own term split off (section OWNT, format 1.3) */
#define SSS_NEAR_TERMS_RUNTIME 1u
#define SSS_NEAR_RINGS_MAX 8u
/* sss_bake_file.weights (section QUAD, format 1.5): the paper's point
 * samples, or the weights integrated over the vertices' hat functions
 * (sss/hatweights.h) */
#define SSS_WEIGHTS_POINT 0u
#define SSS_WEIGHTS_HAT 1u

typedef enum sss_quant {
    SSS_QUANT_FLOAT = 0,   /* q stored as float32 */
    SSS_QUANT_LLOYD8 = 1,  /* q stored as 8-bit indices into a 256-level Lloyd table per channel */
    SSS_QUANT_SH = 2,      /* (1.1) every vertex: quantised SH coefficients of q (§4.1), section SHC */
    SSS_QUANT_REFS = 3     /* (1.1) reference vertices keep Lloyd-8 rows; the others blend three of
                              them and add an SH-coded delta (§4.2-4.3), sections REFS + SHC */
} sss_quant;

/* How SH coefficients are quantised (section SHC). */
typedef enum sss_shq {
    SSS_SHQ_LINEAR8 = 0,   /* the paper's: int8 code, one scale per (channel, coefficient) */
    SSS_SHQ_LLOYD8 = 1,    /* 8-bit code into a 256-level Lloyd-Max table per (channel, coefficient) */
    SSS_SHQ_LLOYD4 = 2,    /* 4-bit code (two per byte, low nibble first) into a 16-level table */
    SSS_SHQ_LINEAR16 = 3   /* (1.7) the paper's §4.1 precision: int16 code (little-endian) in −32767 … 32767,
                              one scale per (channel, coefficient) */
} sss_shq;
#define SSS_SHQ_KINDS 4

#define SSS_SH_FILE_MAX_ORDER 8

/* SH-coded part: for the "coded" vertices (all vertices in SSS_QUANT_SH,
 * the non-references in SSS_QUANT_REFS, in increasing vertex order), the
 * first order² real SH coefficients (sss/sh.h basis) of q, or of the delta,
 * per channel. */
typedef struct sss_shcode {
    uint32_t order;        /* 0 … 8 (0: no SH part, SSS_QUANT_REFS only) */
    uint32_t ncoef;        /* order² */
    uint32_t kind;         /* sss_shq */
    uint32_t ncoded;       /* coded vertices */
    /* Dequantisation tables, always filled in memory: coefficient i of
     * channel c with code x is table[(c * ncoef + i) * levels + x], levels =
     * sss_shq_levels(kind): 256 or 16. For LINEAR8 the file stores only the
     * scales and the reader builds table[b] = (int8_t)b · scale / 127 for
     * each code byte b. LINEAR16 has one level, the step: coefficient =
     * (int16_t)x · table[c * ncoef + i], table = scale / 32767 (a 65536-entry
     * table per coefficient would be 12 MiB at order 7 in RGB). */
    float *table;          /* channels * ncoef * levels, owned */
    float *scale;          /* linear kinds only: channels * ncoef scales (what the file stores), owned */
    uint8_t *code;         /* code bytes as in the file: element e = (k * channels + c) * ncoef + i,
                              one byte each (8-bit kinds), nibble e%2 of byte e/2 (LLOYD4) or bytes 2e, 2e+1
                              little-endian (LINEAR16); owned */
    /* Not in the file: the decoder's load-time layout of the codes
     * (sss_decode_prepare, docs/benchmarks.md "Compressed forms' per-frame
     * cost"), coefficient-major in groups of G coded vertices: element e
     * of coded vertex k at planes[((k / G) * E + e) * G + k % G], E the
     * elements per vertex, one code a byte (8-bit kinds; LLOYD4: a pair's
     * byte) or an int16_t (LINEAR16), so that one loop step serves a run of
     * vertices; G = 256 (a block's codes one run of memory) up to 64 code
     * bytes a vertex, else all coded vertices rounded up to 256 (decode.c,
     * sh_group).
     * NULL when not built; used only while planes_of == code. Owned. */
    void *planes;
    const uint8_t *planes_of;
} sss_shcode;

/* Reference part (SSS_QUANT_REFS). */
typedef struct sss_refcode {
    uint32_t nref;         /* reference vertices */
    uint32_t nrt;          /* reference triangles */
    uint32_t tri_bytes;    /* bytes per stored triangle index: 2, 3 or 4 (the fewest that hold nrt − 1) */
    uint32_t wbits;        /* bits per stored weight: 8 or 16 */
    float w_lo, w_hi;      /* weight w = w_lo + (w_hi − w_lo) · code / (2^wbits − 1); the third is 1 − w0 − w1 */
    uint32_t *ref_vertex;  /* nref vertex indices, strictly increasing; owned */
    uint32_t *ref_tri;     /* 3 * nrt indices into ref_vertex; owned */
    uint32_t *vtri;        /* ncoded reference-triangle indices (< nrt); owned */
    uint16_t *w;           /* 2 * ncoded weight codes (< 2^wbits); owned */
    float *levels;         /* channels * 256 Lloyd levels, ascending; owned */
    uint8_t *idx;          /* ndirs * nref * channels codes, ((j * nref + r) * channels + c); owned */
    uint32_t *coded_vertex;/* derived by the reader: the ncoded non-reference vertices, increasing; owned */
    /* Not in the file: the decoder's load-time layout of the blend
     * (sss_decode_prepare, docs/benchmarks.md "The references' blend from a
     * load-time table" and "The blend's records in one stream"): per coded
     * vertex k, in order, one 16-byte record of its first two weights as
     * the floats the decoder blends with (sss_decode_ref_weight; the third
     * is 1 − w0 − w1) and its triangle's three references (ref_tri[3 *
     * vtri[k] + j]). NULL when not built (more than 65536 references); used
     * only while blend_of == w. Owned. */
    struct sss_blend_rec {
        float w0, w1;
        uint16_t t[3], pad;
    } *blend;
    const uint16_t *blend_of;
} sss_refcode;

/* (1.2) The effect set of a scene bake (docs/scenes.md, docs/format.md
 * §5.10): which passes the planner ran, and the data of the light
 * parameterisations other than the direction set. mask 0 means a plain bake
 * (no section EFCT; DIRS and one of QFLT / QL8 / SHC hold the direction
 * set). */
#define SSS_FX_RGB          (1u << 0) /* three colour channels (else one: grey material) */
#define SSS_FX_SELF_SHADOW  (1u << 1) /* visibility rays against the object itself were traced */
#define SSS_FX_SCENE_SHADOW (1u << 2) /* other static objects of the scene occlude (baked in) */
#define SSS_FX_DIR_EXACT    (1u << 3) /* static directional lights: one exact value each (QDIR) */
#define SSS_FX_DIR_SET      (1u << 4) /* moving directional light: DIRS + QFLT / QL8 / SHC (§3.2) */
#define SSS_FX_POINT_SHELLS (1u << 5) /* near point light: DIRS x distance shells (PSHL, §3.3) */
#define SSS_FX_ENV_SH       (1u << 6) /* environment: SH transfer (ENVT) */
#define SSS_FX_SINGLE       (1u << 7) /* (1.8) single scattering added at run time from MATL, PHAS and GEOM (docs/layers.md) */
#define SSS_FX_KNOWN        0xFFu
#define SSS_FX_COUNT        8

typedef struct sss_effects {
    uint32_t mask;           /* SSS_FX_* */
    /* QDIR: static directional lights, each baked exactly for its direction */
    uint32_t nexact;
    double *exact_dir;       /* 3 * nexact unit vectors towards the lights; owned */
    float *exact_q;          /* q(x_v, ω_l) at ((l * nv + v) * channels + c); owned */
    /* ENVT: per-vertex SH transfer T_i(x_v) = ∫ q(x_v, ω) y_i(ω) dω */
    uint32_t env_order;      /* 1 … 8; ncoef = order² */
    float env_probe[3 * 64]; /* the probe's radiance SH L_i per RGB channel at c * ncoef + i (bake time) */
    float *env_t;            /* (v * channels + c) * ncoef + i; owned */
    /* PSHL: point light at centre + r_s ω_j: stored value is r_s² · q_pt
     * (the 1/r² falloff of the shell taken out so shells interpolate
     * linearly); directions ω_j are DIRS */
    uint32_t nshells;
    double shell_centre[3];  /* world units */
    double *shell_radius;    /* nshells radii, strictly increasing, > 0; owned */
    float *shell_q;          /* ((s * n + j) * nv + v) * channels + c; owned */
} sss_effects;

/* Name of effect bit k (0 … SSS_FX_COUNT-1): "rgb", "self-shadow", … */
const char *sss_effect_name(uint32_t bit);

/* One entry of the section table, as found in a file. */
typedef struct sss_section_info {
    char tag[5];        /* four ASCII characters + NUL */
    uint32_t flags;     /* bit 0: required (a reader that does not know it must reject) */
    uint64_t offset;    /* from the start of the file */
    uint64_t size;      /* bytes */
    uint64_t count;     /* elements (meaning depends on the section) */
    uint32_t crc32;     /* CRC-32 (IEEE) of the section's bytes */
} sss_section_info;

/* The whole content of a .sss file, decoded into memory. */
typedef struct sss_bake_file {
    uint16_t version_major, version_minor;  /* set by the reader */
    sss_mesh mesh;            /* pos, nrm, tri (area is not stored: NULL after reading) */
    sss_material material;
    sss_layer_stack layers;   /* (1.8, LAYR) seed 002's flat layers over the material; n = 0: none */
    /* (1.9, LDEP) per-vertex layer depths: nv · layers.n float mm, layer k
     * of vertex v at v · layers.n + k, each vertex's non-decreasing; NULL:
     * the constant depths of LAYR apply (docs/layers.md §3,
     * sss_layer_stack_at). Owned. */
    float *layer_depth;
    double mm_per_unit;       /* millimetres per mesh unit */
    uint32_t channels;        /* 1 (grey) or 3 (RGB) */
    sss_dirset dirs;          /* directions ω_j and their triangulation */
    int dirs_f32;             /* 1: stored as float32 with 16-bit indices (DIRC, docs/format.md
                               * §5.18; every component must then be a float32, as
                               * sss_dirset_round_f32 leaves it); 0: as float64 (DIRS) */
    sss_quant quant;
    /* Integrals q(x_v, ω_j) per channel c (Hao–Varshney 2004 §3.1, units 1/sr
     * per unit irradiance); layout direction-major: element (j, v, c) is at
     * (j * nv + v) * channels + c, so one light direction's values are
     * contiguous for the per-frame interpolation. */
    float *q;                 /* SSS_QUANT_FLOAT: n * nv * channels values, owned */
    float *levels;            /* SSS_QUANT_LLOYD8: channels * 256 reconstruction levels, owned */
    uint8_t *qidx;            /* SSS_QUANT_LLOYD8: n * nv * channels indices, owned */
    sss_shcode sh;            /* SSS_QUANT_SH and SSS_QUANT_REFS */
    sss_refcode ref;          /* SSS_QUANT_REFS */
    /* (1.7) Section QVEC, or NULL: the vector integrals Q(x_v, ω_j) of
     * Hao–Varshney 2004 §3.1 (q_j = Q_j·ω_j), 3 * n * nv * channels values,
     * direction-major as q with the three components of each value
     * together: component a of (j, v, c) at ((j * nv + v) * channels + c) *
     * 3 + a, so one direction's row is contiguous, as q's is; plain bakes
     * with q as float or lloyd8 only (docs/format.md §5.19). Owned. */
    float *qvec;
    char *params_json;        /* bake parameters as JSON text (provenance), NUL-terminated, owned */
    sss_effects fx;           /* (1.2) effect set of a scene bake; mask 0 for a plain bake */
    uint32_t near_terms;        /* (1.3) 0, or SSS_NEAR_TERMS_RUNTIME: section OWNT, the q rows (any storage
                               * form) hold q minus the near terms (the vertex's own term and its rings),
                               * which the reader adds for the actual light with every vertex's own
                               * visibility (sss/nearterms.h) */
    uint32_t near_rings;       /* (1.3) with near_terms: mesh rings around the vertex split off too (0 … 8) */
    double eps;               /* (1.4) the bake's neighbourhood energy cutoff ε in (0, 1) (section NBHD):
                               * each vertex's neighbourhood is the disk holding 1 − ε of R_d's total, which
                               * the exact evaluator needs to recompute q; 0 when the file does not hold it
                               * (files before 1.4 keep ε only in params_json, "eps") */
    uint32_t weights;         /* (1.5) SSS_WEIGHTS_POINT (0: the paper's point samples) or SSS_WEIGHTS_HAT
                               * (section QUAD): the weights of the sum integrated over the vertices' hat
                               * functions (sss/hatweights.h), which the exact evaluator and the near
                               * terms must use too */
    double near_radius_mm;    /* (1.5) with near_terms: > 0 when the near terms are every vertex within this
                               * distance, connected or not (section NRAD), rather than near_rings rings */
    /* (1.8) Section FELD: a heterogeneous object's field, inside material and
     * rest frame (docs/heterogeneous.md; field.kind SSS_FIELD_NONE: none);
     * material above is the base (f = 0). Owned (the grid's samples). */
    sss_hetero hetero;
    /* Filled by the reader (ignored by the writer): */
    uint64_t file_size;
    uint32_t nsections;
    sss_section_info sections[SSS_MAX_SECTIONS];
} sss_bake_file;

/* Serialises f into a newly malloc'ed buffer (*buf, *len; caller frees). */
sss_result sss_file_encode(const sss_bake_file *f, uint8_t **buf, size_t *len, sss_error *err);
/* The same, with messages naming `name` (the file it is for). */
sss_result sss_file_encode_named(const sss_bake_file *f, const char *name, uint8_t **buf, size_t *len, sss_error *err);

/* Writes f to path atomically: a temporary file in the same directory,
 * fsync, rename, fsync of the directory. On failure the previous file under
 * path (if any) is untouched and no temporary is left behind. Only a path
 * sss_output_check accepts is written (sss/fileio.h: a new or regular
 * file, a symbolic link followed to one; never a directory or a device). */
sss_result sss_file_write(const char *path, const sss_bake_file *f, sss_error *err);

/* The same, refusing also a path that is the same file as one of the
 * inputs (a bake's mesh, say). */
struct sss_inputs;
sss_result sss_file_write_with(const char *path, const sss_bake_file *f, const struct sss_inputs *in,
                               sss_error *err);

/* Decodes a complete file image. Checks every size, offset, count, checksum
 * and value range before use; never reads out of bounds. `name` is used in
 * error messages. On failure *f is left zeroed. */
sss_result sss_file_decode(const void *buf, size_t len, const char *name, sss_bake_file *f, sss_error *err);

/* Reads and decodes the file at path: a regular file only, opened without
 * blocking (sss/fileio.h). */
sss_result sss_file_read(const char *path, sss_bake_file *f, sss_error *err);

/* Frees everything owned by f and zeroes it. NULL-safe. */
void sss_file_free(sss_bake_file *f);

/* Bytes per vertex taken by the stored integrals (values plus, for lloyd8,
 * the level tables spread over the vertices; for the compressed forms every
 * byte of sections REFS and SHC); geometry not included. */
double sss_file_integral_bytes_per_vertex(const sss_bake_file *f);

/* Exact byte count of every stored part of the scattering data, as encoded
 * (docs/format.md §5): what sss-stat reports. */
typedef struct sss_storage {
    uint64_t dirs;          /* section DIRS (directions and their triangulation) */
    uint64_t values;        /* QFLT values, or QL8 indices */
    uint64_t lloyd_tables;  /* QL8 / REFS level tables */
    uint64_t section_headers; /* fixed fields at the start of QL8, REFS and SHC */
    uint64_t ref_vertex;    /* REFS: reference vertex indices */
    uint64_t ref_tri;       /* REFS: reference triangles */
    uint64_t vertex_tri;    /* REFS: per-vertex reference-triangle indices */
    uint64_t weights;       /* REFS: per-vertex weights */
    uint64_t ref_values;    /* REFS: reference rows */
    uint64_t sh_tables;     /* SHC: scales or Lloyd tables */
    uint64_t sh_codes;      /* SHC: coefficient codes */
    uint64_t scattering;    /* the integrals: everything above except dirs */
    uint64_t total;         /* scattering + dirs */
    uint64_t effects;       /* (1.2) sections EFCT, QDIR, ENVT, PSHL (included in scattering) */
} sss_storage;
void sss_file_storage(const sss_bake_file *f, sss_storage *s);

/* "float", "lloyd8", "sh", "refs" ("?" for an unknown value). */
const char *sss_quant_name(sss_quant q);

/* "linear8", "lloyd8", "lloyd4", "linear16" ("?" for an unknown value). */
const char *sss_shq_name(uint32_t kind);

/* Number of SH dequantisation levels held in memory per coefficient (256
 * or 16; 1 for LINEAR16, whose one level is the step; 0 if unknown). */
uint32_t sss_shq_levels(uint32_t kind);

/* Largest code magnitude of a linear kind (127 LINEAR8, 32767 LINEAR16),
 * 0 for a table (Lloyd) kind: a linear code x stands for x · scale / max. */
uint32_t sss_shq_linear_max(uint32_t kind);

/* Fewest bytes (2, 3 or 4) that hold every reference-triangle index below
 * nrt: the stored width of sss_refcode.vtri. */
uint32_t sss_refs_tri_bytes(uint32_t nrt);

/* Builds the LINEAR8 dequantisation tables (256 entries per scale) from n
 * scales; reader and compressor both use it, so they agree to the bit. */
void sss_shq_linear8_table(const float *scale, uint32_t n, float *table);

/* LINEAR16's one level per scale, the step scale / 32767 (n floats); the
 * decoders fold y_i(ω) · scale / 32767 from the scale itself, in double. */
void sss_shq_linear16_table(const float *scale, uint32_t n, float *table);

/* Bytes of the SH code array for n elements of a kind. */
uint64_t sss_shq_code_bytes(uint32_t kind, uint64_t n);

/* Code of element e of an SH code array (LINEAR16: the raw 16 bits, the
 * signed code is (int16_t) of it). */
static inline uint32_t sss_shq_code(const uint8_t *code, uint32_t kind, uint64_t e)
{
    if (kind == SSS_SHQ_LINEAR16) return (uint32_t)code[2 * e] | (uint32_t)code[2 * e + 1] << 8;
    return kind == SSS_SHQ_LLOYD4 ? (uint32_t)(code[e >> 1] >> ((e & 1u) * 4u)) & 15u : code[e];
}

/* CRC-32 (IEEE 802.3, reflected, init and xorout 0xFFFFFFFF), chainable:
 * crc = sss_crc32(crc, data, n) starting from 0. */
uint32_t sss_crc32(uint32_t crc, const void *data, size_t n);

#ifdef __cplusplus
}
#endif
#endif
