/* format_effects.h (internal): sections EFCT, QDIR, ENVT and PSHL of format
 * 1.2, written by scene bakes (docs/format.md §5.10–5.13, docs/scenes.md):
 * the effect set a planner chose and the data of the light
 * parameterisations other than the direction set of Hao–Varshney 2004 §3.2.
 * Used by format.c, like format_compressed.h; `code` is SSS_ERR_ARG when
 * checking what a caller asks to write, SSS_ERR_CORRUPT when checking what
 * was read. */
#ifndef SSS_FORMAT_EFFECTS_H
#define SSS_FORMAT_EFFECTS_H
#include <stdint.h>
#include "sss/format.h"

/* Section sizes from f's counts; 0 on overflow. */
uint64_t sss_fmt_efct_size(const sss_bake_file *f);
uint64_t sss_fmt_qdir_size(const sss_bake_file *f);
uint64_t sss_fmt_envt_size(const sss_bake_file *f);
uint64_t sss_fmt_pshl_size(const sss_bake_file *f);

/* Checks f->fx against the mesh, channels and directions: the mask has no
 * unknown bit, each effect's data is present and valid, and no data is
 * present for an effect the mask does not name. */
sss_result sss_fmt_check_effects(const sss_bake_file *f, const char *name, sss_result code, sss_error *err);

void sss_fmt_pack_efct(const sss_bake_file *f, uint8_t *p);
void sss_fmt_pack_qdir(const sss_bake_file *f, uint8_t *p);
void sss_fmt_pack_envt(const sss_bake_file *f, uint8_t *p);
void sss_fmt_pack_pshl(const sss_bake_file *f, uint8_t *p);

sss_result sss_fmt_parse_efct(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err);
sss_result sss_fmt_parse_qdir(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err);
sss_result sss_fmt_parse_envt(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err);
sss_result sss_fmt_parse_pshl(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err);

void sss_fmt_free_effects(sss_bake_file *f);

#endif
