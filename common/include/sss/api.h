/* sss/api.h: the runtime API an engine embeds (CPU side): open a baked
 * scattering file (.sss, docs/format.md), ask what it holds, and decode the
 * per-vertex scattering q(x_v, ω) for a light into a buffer of the caller's.
 * The GPU side (the buffers laid out for upload and the GLSL that evaluates
 * them) is sss/gpu.h; sss_asset_file hands it the decoded file.
 *
 * Part of libsss: C11, no GL, no other library of the toolkit. Every type
 * a call takes is a plain C type, a fixed-size struct or the opaque handle,
 * so that foreign-function layers (Python's ctypes) bind it directly; no
 * call takes a callback or a variable argument list.
 *
 * What the values are. q(x_v, ω) is the light that leaves vertex x_v after
 * scattering under the surface, per unit irradiance arriving from direction
 * ω (Hao–Varshney 2004 §3.1; docs/physics.md §4): a fraction per steradian,
 * ≥ 0, one value per channel (1: grey, 3: RGB). A renderer multiplies it by
 * the light's intensity and colour and by the Fresnel transmittance towards
 * the eye, F_t(η, n·ω_o) (docs/format.md §5.4). Directions are in the
 * mesh's own coordinates (the positions of sss_asset_positions), as unit
 * vectors towards the light; the API normalises them, so any length > 0
 * will do.
 *
 * Memory. The asset owns everything it hands out by pointer (geometry, the
 * file) until sss_asset_close; the caller owns every buffer it passes in.
 * Decoding allocates only temporary memory, freed before it returns.
 *
 * Threads. An open asset is read-only: any number of threads may call the
 * decode, visibility, info and accessor functions on one asset at once,
 * each with its own output buffers (no call keeps state between calls).
 * sss_asset_close must not run concurrently with any other call on the
 * same asset. Opening is re-entrant (several assets may be opened at once
 * on several threads). A decode may itself run on OpenMP threads when the
 * library is built with OpenMP and it is called outside a parallel region.
 *
 * Errors. Every call that can fail returns sss_result (sss/result.h: SSS_OK
 * = 0) and, given a non-NULL sss_error, one line that names the file and
 * the argument or element at fault. NULL, zero-length and out-of-range
 * arguments give SSS_ERR_ARG; a file that is damaged or not a .sss gives
 * the reader's codes (SSS_ERR_FORMAT, SSS_ERR_CORRUPT, ...). No input
 * crashes the library or reads outside a buffer the caller described.
 * docs/api.md sums these rules up; examples/decode_print.c is a whole program.
 */
#ifndef SSS_API_H
#define SSS_API_H

#include <stddef.h>
#include <stdint.h>
#include "sss/format.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* An opened .sss file with everything decoding needs, built once. */
typedef struct sss_asset sss_asset;

#define SSS_ASSET_NAME_MAX 16

/* What an asset holds (sss_asset_info). Fixed-size fields only. */
typedef struct sss_asset_desc {
    uint32_t nv;                 /* vertices */
    uint32_t nf;                 /* triangles */
    uint32_t channels;           /* 1 (grey) or 3 (RGB): values per vertex of sss_asset_decode */
    uint32_t quant;              /* storage form of the direction set's rows: sss_quant (sss/format.h) */
    char quant_name[SSS_ASSET_NAME_MAX];   /* "float", "lloyd8", "sh", "refs" */
    uint32_t sh_order;           /* SH order of the coded part (SSS_QUANT_SH / _REFS; 0 otherwise) */
    char sh_kind_name[SSS_ASSET_NAME_MAX]; /* "linear8", "lloyd8", "lloyd4", "linear16"; "" without an SH part */
    uint32_t ndirs;              /* direction samples ω_j of the rows (and of the point-light shells) */
    uint32_t effects;            /* SSS_FX_* bits of a scene bake (docs/scenes.md); 0 for a plain bake */
    uint32_t has_dir_set;        /* 1: sss_asset_decode works (a plain bake, or SSS_FX_DIR_SET) */
    uint32_t near_terms;         /* 1: the near terms are evaluated at run time (section OWNT): sss_asset_decode
                                  * adds them, and needs every vertex's visibility (its `lit`) */
    uint32_t near_rings;         /* with near_terms and near_radius_mm 0: mesh rings split off (0: own term only) */
    double near_radius_mm;       /* with near_terms: > 0 when the terms are every vertex within this distance, mm */
    uint32_t nexact;             /* static directional lights baked exactly (QDIR): sss_asset_decode_exact */
    uint32_t nshells;            /* point-light distance shells (PSHL): sss_asset_decode_point; 0 without */
    uint32_t env_order;          /* environment SH order (ENVT): sss_asset_decode_env takes 3·env_order² floats; 0 without */
    uint32_t version_major, version_minor; /* the file's format version */
    uint64_t file_bytes;         /* size of the file */
    double integral_bytes_per_vertex; /* bytes of the stored integrals per vertex (sss_file_integral_bytes_per_vertex) */
    double mm_per_unit;          /* millimetres per mesh unit */
    char material_name[32];      /* preset name or "custom" */
    double sigma_a[3];           /* absorption σa per channel, 1/mm (the first `channels` are meaningful) */
    double sigmap_s[3];          /* reduced scattering σ′s per channel, 1/mm */
    double eta;                  /* relative index of refraction η (one for all channels) */
    /* single scattering's material (docs/layers.md §2–§3), added after the
     * fields above so that their offsets stay */
    double g;                    /* Henyey–Greenstein mean cosine of the material (section PHAS; 0 without) */
    uint32_t nlayers;            /* seed 002's layers over the material (section LAYR; 0 without) */
    uint32_t layer_depths;       /* 1: per-vertex layer depths (section LDEP, format 1.9) */
} sss_asset_desc;

/* Opens the .sss file at `path` (a regular file; read whole, checked and
 * decoded: every size, offset, checksum and value range) and builds what
 * decoding needs: for a file with run-time near terms their weight rows
 * and the triangle hierarchy of the visibility rays (sss/bvh.h), O(n log n)
 * in the triangles. *out receives the asset (NULL on failure); free it
 * with sss_asset_close. Errors: SSS_ERR_ARG (NULL path or out, empty
 * path), SSS_ERR_IO, SSS_ERR_NOMEM, and the reader's for a bad file. */
sss_result sss_asset_open(const char *path, sss_asset **out, sss_error *err);

/* The same from the len bytes at buf, the whole image of a .sss file (read
 * by the caller: an archive, a network, an engine's asset system). The
 * bytes are copied out while decoding: the caller may free buf as soon as
 * this returns. `name` labels error messages (NULL: "<memory>"). An asset
 * opened this way equals one opened from a path holding the same bytes.
 * Errors: SSS_ERR_ARG (NULL buf or out, len 0), then as sss_asset_open. */
sss_result sss_asset_open_memory(const void *buf, size_t len, const char *name, sss_asset **out, sss_error *err);

/* Frees the asset and everything it owns. NULL-safe. Pointers it handed
 * out (geometry, file, name) are invalid afterwards. */
void sss_asset_close(sss_asset *a);

/* Fills *info with what the asset holds. Errors: SSS_ERR_ARG (NULL). */
sss_result sss_asset_info(const sss_asset *a, sss_asset_desc *info, sss_error *err);

/* The name the asset was opened under (its path, or sss_asset_open_memory's
 * name); owned by the asset. NULL for a NULL asset. */
const char *sss_asset_name(const sss_asset *a);

/* Geometry, owned by the asset (NULL for a NULL asset), in mesh units:
 * positions and unit normals nv × 3 floats (x, y, z per vertex),
 * triangles nf × 3 vertex indices (counter-clockwise seen from outside). */
const float *sss_asset_positions(const sss_asset *a);
const float *sss_asset_normals(const sss_asset *a);
const uint32_t *sss_asset_triangles(const sss_asset *a);

/* The bake's parameters as JSON text (provenance), NUL-terminated, owned by
 * the asset; "" when the file holds none, NULL for a NULL asset. */
const char *sss_asset_params_json(const sss_asset *a);

/* The decoded file itself, owned by the asset, for advanced use: the GPU
 * layout (sss/gpu.h) takes it, as do the decoders of sss/decode.h and
 * sss/effects.h. Read-only. NULL for a NULL asset. */
const sss_bake_file *sss_asset_file(const sss_asset *a);

/* ---- the direction set: a directional light from any direction -------- */

/* q(x_v, ω) for vertices [first, first + count) into out[(v − first) ·
 * channels + c], the value the viewer shows: the stored rows interpolated
 * over the spherical triangle of direction samples around ω (§3.2) and
 * decoded as sss_decode_all decodes them, to the bit (for a file with the
 * vector integrals Q, section QVEC: Q interpolated so and dotted with ω,
 * sss_decode_vector_range's bits, as the viewer draws it), plus, for a file whose
 * near terms are evaluated at run time (desc.near_terms), those terms for
 * ω (sss/nearterms.h; the sum sss_near_add forms).
 *
 * light: 3 doubles, towards the light in mesh coordinates, any length > 0.
 * first, count: count ≥ 1 and first + count ≤ nv.
 * lit: only read for a file with run-time near terms, else ignored (may be
 *   NULL). NULL: libsss traces each vertex's own visibility V(x_v, ω) with
 *   the bake's ray (sss/bvh.h; the same answer as the viewer's GPU rays),
 *   only for the vertices the range's near terms involve. Non-NULL: nv
 *   bytes, the caller's own shadow test for every vertex (non-zero: lit),
 *   e.g. an engine's shadow map, or sss_asset_visibility's result reused.
 * out: count × channels floats, written in full on success.
 * Errors: SSS_ERR_ARG (NULL a, light or out; a zero or non-finite light;
 * count 0 or a range beyond nv; an asset without a direction set),
 * SSS_ERR_NOMEM (the near terms' scratch, nv floats and nv bytes). */
sss_result sss_asset_decode(const sss_asset *a, const double light[3], uint32_t first, uint32_t count,
                            const uint8_t *lit, float *out, sss_error *err);

/* Every vertex's own visibility V(x_v, ω) as sss_asset_decode traces it
 * with lit NULL: lit[v] = 1 where x_v faces the light (n_v·ω > 0) and the
 * bake's ray from it towards ω is not blocked by the mesh, else 0; nv
 * bytes. Only for a file with run-time near terms (the others bake
 * visibility into their rows and build no hierarchy): else SSS_ERR_ARG.
 * Errors also SSS_ERR_ARG for NULL arguments or a zero or non-finite
 * light. */
sss_result sss_asset_visibility(const sss_asset *a, const double light[3], uint8_t *lit, sss_error *err);

/* ---- the other light kinds of a scene bake (docs/scenes.md) ------------ */

/* Static directional light `index` (0 … nexact − 1) of section QDIR: its
 * unit direction towards the light into dir[3] (mesh coordinates). */
sss_result sss_asset_exact_direction(const sss_asset *a, uint32_t index, double dir[3], sss_error *err);

/* Its exact q for vertices [first, first + count) into out[(v − first) ·
 * channels + c] (the stored values; no interpolation). SSS_ERR_ARG when the
 * file holds no such light, for a bad range or NULL arguments. */
sss_result sss_asset_decode_exact(const sss_asset *a, uint32_t index, uint32_t first, uint32_t count, float *out,
                                  sss_error *err);

/* A point light of unit intensity at `position` (mesh coordinates): the
 * shells of section PSHL interpolated (§3.3; sss_fx_point, to the bit) and
 * divided by r², per unit intensity (no near terms: they belong to the
 * direction set). Out as sss_asset_decode_exact. A light at the shells'
 * centre gives 0. SSS_ERR_ARG when the file holds no point-light shells, for
 * a non-finite position, a bad range or NULL arguments. */
sss_result sss_asset_decode_point(const sss_asset *a, const double position[3], uint32_t first, uint32_t count,
                                  float *out, sss_error *err);

/* An environment: out[(v − first) · 3 + k] = max(0, Σ_i T_i(x_v) L[k ·
 * env_order² + i]) for RGB channel k (three values per vertex even for a
 * grey file, whose one transfer serves all three), the radiance leaving x_v
 * under the environment whose real SH coefficients (sss/sh.h basis) are
 * `probe`: 3 · env_order² floats, or NULL for the probe the bake stored
 * (sss_fx_env, to the bit). SSS_ERR_ARG when the file holds no environment
 * transfer (ENVT), for a bad range or NULL arguments. */
sss_result sss_asset_decode_env(const sss_asset *a, const float *probe, uint32_t first, uint32_t count, float *out,
                                sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
