/* sss/format.h: the .sss baked-scattering file, format version 1.
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

#ifdef __cplusplus
extern "C" {
#endif

#define SSS_FORMAT_MAJOR 1
#define SSS_FORMAT_MINOR 0
#define SSS_MAX_SECTIONS 32

typedef enum sss_quant {
    SSS_QUANT_FLOAT = 0,   /* q stored as float32 */
    SSS_QUANT_LLOYD8 = 1   /* q stored as 8-bit indices into a 256-level Lloyd table per channel */
} sss_quant;

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
    double mm_per_unit;       /* millimetres per mesh unit */
    uint32_t channels;        /* 1 (grey) or 3 (RGB) */
    sss_dirset dirs;          /* directions ω_j and their triangulation */
    sss_quant quant;
    /* Integrals q(x_v, ω_j) per channel c (Hao–Varshney 2004 §3.1, units 1/sr
     * per unit irradiance); layout direction-major: element (j, v, c) is at
     * (j * nv + v) * channels + c, so one light direction's values are
     * contiguous for the per-frame interpolation. */
    float *q;                 /* SSS_QUANT_FLOAT: n * nv * channels values, owned */
    float *levels;            /* SSS_QUANT_LLOYD8: channels * 256 reconstruction levels, owned */
    uint8_t *qidx;            /* SSS_QUANT_LLOYD8: n * nv * channels indices, owned */
    char *params_json;        /* bake parameters as JSON text (provenance), NUL-terminated, owned */
    /* Filled by the reader (ignored by the writer): */
    uint64_t file_size;
    uint32_t nsections;
    sss_section_info sections[SSS_MAX_SECTIONS];
} sss_bake_file;

/* Serialises f into a newly malloc'ed buffer (*buf, *len; caller frees). */
sss_result sss_file_encode(const sss_bake_file *f, uint8_t **buf, size_t *len, sss_error *err);

/* Writes f to path atomically: a temporary file in the same directory,
 * fsync, rename, fsync of the directory. On failure the previous file under
 * path (if any) is untouched and no temporary is left behind. */
sss_result sss_file_write(const char *path, const sss_bake_file *f, sss_error *err);

/* Decodes a complete file image. Checks every size, offset, count, checksum
 * and value range before use; never reads out of bounds. `name` is used in
 * error messages. On failure *f is left zeroed. */
sss_result sss_file_decode(const void *buf, size_t len, const char *name, sss_bake_file *f, sss_error *err);

/* Reads and decodes the file at path. */
sss_result sss_file_read(const char *path, sss_bake_file *f, sss_error *err);

/* Frees everything owned by f and zeroes it. NULL-safe. */
void sss_file_free(sss_bake_file *f);

/* Bytes per vertex taken by the stored integrals (values plus, for lloyd8,
 * the level tables spread over the vertices); geometry not included. */
double sss_file_integral_bytes_per_vertex(const sss_bake_file *f);

/* CRC-32 (IEEE 802.3, reflected, init and xorout 0xFFFFFFFF), chainable:
 * crc = sss_crc32(crc, data, n) starting from 0. */
uint32_t sss_crc32(uint32_t crc, const void *data, size_t n);

#ifdef __cplusplus
}
#endif
#endif
