/* format_compressed.h (internal): sections REFS and SHC of format 1.1, the
 * compressed forms of Hao–Varshney 2004 §4 (docs/format.md §5.7–5.8).
 * Used by format.c; every function takes the file name for its messages and
 * `code` (SSS_ERR_ARG when checking what a caller asks to write,
 * SSS_ERR_CORRUPT when checking what was read). */
#ifndef SSS_FORMAT_COMPRESSED_H
#define SSS_FORMAT_COMPRESSED_H
#include <stdint.h>
#include "sss/format.h"


/* Section sizes in bytes from f's counts; 0 on 64-bit overflow. */
uint64_t sss_fmt_refs_size(const sss_bake_file *f);
uint64_t sss_fmt_shc_size(const sss_bake_file *f);

/* Checks every count, index and value of f->ref / f->sh against f's mesh,
 * channels and directions (the checks the reader makes, so that a writer
 * never writes what a reader would refuse). */
sss_result sss_fmt_check_refs(const sss_bake_file *f, const char *name, sss_result code, sss_error *err);
sss_result sss_fmt_check_shc(const sss_bake_file *f, const char *name, sss_result code, sss_error *err);

/* Packs the section into p (exactly the size above). */
void sss_fmt_pack_refs(const sss_bake_file *f, uint8_t *p);
void sss_fmt_pack_shc(const sss_bake_file *f, uint8_t *p);

/* Parses a section of `size` bytes and `count` elements into f (GEOM,
 * MATL, DIRS, and for SHC also REFS when present, already parsed). */
sss_result sss_fmt_parse_refs(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err);
sss_result sss_fmt_parse_shc(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                             sss_error *err);

/* Frees f->ref and f->sh. */
void sss_fmt_free_compressed(sss_bake_file *f);

#endif
