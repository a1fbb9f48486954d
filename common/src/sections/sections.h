/* sections.h (internal): the sections of the .sss file (docs/format.md §5),
 * one codec file each in this folder, tied together by one table that
 * format.c walks to write and to read a file.
 *
 * ---- The table ------------------------------------------------------------
 *
 * SSS_SECTIONS below has one row per known section:
 *
 *     X(ID, TAG, FLAGS, SINCE, CODEC)
 *
 *   ID     enum name (SSS_SEC_ID) and index of the row;
 *   TAG    the four bytes of the section table entry (§2.2), space-padded;
 *   FLAGS  SSS_SEC_REQUIRED: flag bit 0 as written (§4: a reader that does
 *            not know the tag must refuse the file); the other bits steer
 *            the reader and never reach a file:
 *          SSS_SEC_EVERY_FILE: every file holds it; a file without it is
 *            refused before any section is read;
 *          SSS_SEC_READ_FIRST: read right after the section table, before
 *            the presence rules, which depend on it (EFCT, §5.10);
 *          SSS_SEC_CHECK_LAST: its values are checked once every section is
 *            read, because they are checked against sections read after it
 *            (the effect set, §5.10);
 *          SSS_SEC_MAY_BE_EMPTY: size 0 is valid (PARM), not an overflow;
 *   SINCE  the minor version that introduced it: a file is written with the
 *          largest SINCE of its sections (§4, §7), so a reader older than a
 *          section meets the section's required flag, not a misread file;
 *   CODEC  prefix of the section's functions, sss_sec_CODEC_COLUMN, in
 *          sections/CODEC.c.
 *
 * The order of the rows is both orders the driver needs:
 *   writing order (§7): sections are laid out in row order; PARM, the only
 *     section of arbitrary length, is last, so the f32/u32 arrays of the
 *     others stay 4-byte aligned (§1);
 *   reading order (§6 step 9): contents are parsed in row order, which is
 *     a dependency order (q sections after GEOM, MATL and DIRS, which give
 *     nv, channels and n; SHC after REFS), except that READ_FIRST rows are
 *     parsed before all others and CHECK_LAST rows are checked after all
 *     others, in row order.
 *
 * ---- The columns: one signature each --------------------------------------
 *
 *   size   bytes of the section as f would be written; 0 when the formula
 *          overflows 64 bits (for MAY_BE_EMPTY rows 0 is a size);
 *   count  the table entry's element count (§5, per section);
 *   check  every count, pointer and value of f that the section stores;
 *          `code` is SSS_ERR_ARG when checking what a caller asks to write,
 *          SSS_ERR_CORRUPT when checking what was read; the message names
 *          the file (`name`) and the section;
 *   pack   writes exactly size bytes at p (field by field, little-endian);
 *   parse  reads a section of `size` bytes and table count `count` into f,
 *          checking sizes before allocating (the sections before it in
 *          reading order are already in f), and checks what it read with
 *          the section's check, except for CHECK_LAST rows, whose check the
 *          reader calls once every section is read;
 *   free   frees what the section owns in f and clears those fields;
 *   wants  writing: whether f is written with this section (from f's quant,
 *          effect mask, own term ...);
 *   needs  reading: whether the file must hold it (SSS_SEC_PRESENT), must
 *          not (SSS_SEC_ABSENT), or may (SSS_SEC_EITHER: no rule, or a
 *          cross-section rule of format.c decides), from what the reader
 *          knows before the contents: f->version_* and f->fx.mask (EFCT).
 *
 * What stays in format.c: the header, the section table of the file and
 * the CRCs (§2–3), the rules that tie several sections together (§5.9,
 * §5.10: exactly one q section, REFS only with SHC, OWNT only in plain
 * bakes, no data for what the effect set does not name), the atomic writer
 * and the reader (§6–7).
 *
 * ---- Adding a section -----------------------------------------------------
 *
 *  1. sections/NAME.c: its layout and the eight functions above (the
 *     existing files are the templates: ownt.c for a small fixed record,
 *     qdir.c for arrays sized by other sections);
 *  2. one row in SSS_SECTIONS, at the place that gives its writing and
 *     reading order, with SINCE = the new minor version (and
 *     SSS_FORMAT_MINOR raised to it in sss/format.h) and
 *     SSS_SEC_REQUIRED unless a reader may ignore it;
 *  3. its fields in sss_bake_file (sss/format.h) and its subsection in
 *     docs/format.md §5, with the version table (§4, §5.9) and the reading
 *     and writing lists (§6, §7).
 * Nothing else changes: the driver, the free, the version written and the
 * refusal by older readers follow from the row.
 */
#ifndef SSS_SECTIONS_H
#define SSS_SECTIONS_H

#include <math.h>
#include <stdint.h>

#include "sss/format.h"
#include "../format_bytes.h"

/* ---- the table ---------------------------------------------------------- */

#define SSS_SEC_REQUIRED 1u       /* flag bit 0 of the file (§2.2) */
#define SSS_SEC_EVERY_FILE 0x100u /* reader: refused when missing, before anything is read */
#define SSS_SEC_READ_FIRST 0x200u /* reader: parsed before the presence rules */
#define SSS_SEC_CHECK_LAST 0x400u /* reader: checked once every section is read */
#define SSS_SEC_MAY_BE_EMPTY 0x800u /* writer: size 0 is valid, not an overflow */
#define SSS_SEC_FILE_FLAGS SSS_SEC_REQUIRED /* the bits that are written */

#define SSS_SECTIONS(X)                                                                          \
    /* ID    TAG     FLAGS                                                  SINCE CODEC */      \
    X(GEOM, "GEOM", SSS_SEC_REQUIRED | SSS_SEC_EVERY_FILE,                      0, geom)       \
    X(MATL, "MATL", SSS_SEC_REQUIRED | SSS_SEC_EVERY_FILE,                      0, matl)       \
    X(PHAS, "PHAS", 0,                                                          8, phas)       \
    X(LAYR, "LAYR", 0,                                                          8, layr)       \
    X(LDEP, "LDEP", 0,                                                          9, ldep)       \
    X(EFCT, "EFCT", SSS_SEC_REQUIRED | SSS_SEC_READ_FIRST | SSS_SEC_CHECK_LAST, 2, efct)       \
    X(DIRS, "DIRS", SSS_SEC_REQUIRED,                                           0, dirs)       \
    X(DIRC, "DIRC", SSS_SEC_REQUIRED,                                           6, dirc)       \
    X(QFLT, "QFLT", SSS_SEC_REQUIRED,                                           0, qflt)       \
    X(QL8,  "QL8 ", SSS_SEC_REQUIRED,                                           0, ql8)        \
    X(REFS, "REFS", SSS_SEC_REQUIRED,                                           1, refs)       \
    X(SHC,  "SHC ", SSS_SEC_REQUIRED,                                           1, shc)        \
    X(QVEC, "QVEC", SSS_SEC_REQUIRED,                                           7, qvec)       \
    X(QDIR, "QDIR", SSS_SEC_REQUIRED | SSS_SEC_CHECK_LAST,                      2, qdir)       \
    X(ENVT, "ENVT", SSS_SEC_REQUIRED | SSS_SEC_CHECK_LAST,                      2, envt)       \
    X(PSHL, "PSHL", SSS_SEC_REQUIRED | SSS_SEC_CHECK_LAST,                      2, pshl)       \
    X(OWNT, "OWNT", SSS_SEC_REQUIRED,                                           3, ownt)       \
    X(NBHD, "NBHD", SSS_SEC_REQUIRED,                                           4, nbhd)       \
    X(QUAD, "QUAD", SSS_SEC_REQUIRED,                                           5, quad)       \
    X(NRAD, "NRAD", SSS_SEC_REQUIRED,                                           5, nrad)       \
    X(FELD, "FELD", SSS_SEC_REQUIRED,                                           8, feld)       \
    X(PARM, "PARM", SSS_SEC_EVERY_FILE | SSS_SEC_MAY_BE_EMPTY,                  0, parm)

#define SSS_SEC_ENUM(id, tag, flags, since, codec) SSS_SEC_##id,
typedef enum sss_sec_id { SSS_SECTIONS(SSS_SEC_ENUM) SSS_SEC_COUNT } sss_sec_id;
#undef SSS_SEC_ENUM

/* Reading: whether a file must hold a section. */
typedef enum sss_sec_need { SSS_SEC_ABSENT = 0, SSS_SEC_PRESENT = 1, SSS_SEC_EITHER = 2 } sss_sec_need;

#define SSS_SEC_DECLARE(id, tag, flags, since, codec)                                                     \
    uint64_t sss_sec_##codec##_size(const sss_bake_file *f);                                               \
    uint64_t sss_sec_##codec##_count(const sss_bake_file *f);                                              \
    sss_result sss_sec_##codec##_check(const sss_bake_file *f, const char *name, sss_result code,          \
                                       sss_error *err);                                                    \
    void sss_sec_##codec##_pack(const sss_bake_file *f, uint8_t *p);                                       \
    sss_result sss_sec_##codec##_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name,  \
                                       sss_bake_file *f, sss_error *err);                                  \
    void sss_sec_##codec##_free(sss_bake_file *f);                                                         \
    int sss_sec_##codec##_wants(const sss_bake_file *f);                                                   \
    sss_sec_need sss_sec_##codec##_needs(const sss_bake_file *f);
SSS_SECTIONS(SSS_SEC_DECLARE)
#undef SSS_SEC_DECLARE

/* ---- what several codecs share -------------------------------------------- */

#define SSS_SEC_NLEVELS 256u /* Lloyd-Max levels per channel (QL8, REFS) */

/* Which sections an effect mask implies (§5.10): a plain bake (mask 0) has
 * a direction set and its integrals; a scene bake has DIRS only for the
 * effects that use a direction set, and a q section only for direction-set. */
static inline int sss_sec_fx_uses_dirs(uint32_t m) { return !m || (m & (SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS)); }
static inline int sss_sec_fx_uses_q(uint32_t m) { return !m || (m & SSS_FX_DIR_SET); }

/* 2n - 4 triangles (Euler, closed triangulated sphere); in 64 bits, as a hostile
 * n near 2^32 must not wrap onto a small stored ntri. */
static inline uint64_t sss_sec_dirs_ntri(uint32_t n) { return n >= 4 ? 2u * (uint64_t)n - 4u : 0u; }

/* The bytes of whichever of DIRS and DIRC the writer takes for f's set (0
 * without directions). */
uint64_t sss_sec_directions_size(const sss_bake_file *f);

/* Number of q values, n * nv * channels (GEOM, MATL and DIRS known); 0 on overflow. */
static inline int sss_sec_q_count(const sss_bake_file *f, uint64_t *nq)
{
    return mul_u64((uint64_t)f->dirs.n * f->mesh.nv, f->channels, nq);
}

/* The same, refused (SSS_ERR_NOMEM) when it overflows: the q sections'
 * sizes and the writer's loops are counted in it. */
static inline sss_result sss_sec_q_count_checked(const sss_bake_file *f, const char *name, uint64_t *nq,
                                                 sss_error *err)
{
    if (!sss_sec_q_count(f, nq))
        return sss_fail(err, SSS_ERR_NOMEM, "%s: %u directions x %u vertices x %u channels overflows", name,
                        f->dirs.n, f->mesh.nv, f->channels);
    return SSS_OK;
}

/* Vertices with an SH code (§5.8): all of them, or the non-references with REFS. */
static inline uint64_t sss_sec_ncoded(const sss_bake_file *f)
{
    return f->quant == SSS_QUANT_REFS ? (uint64_t)f->mesh.nv - f->ref.nref : f->mesh.nv;
}

static inline sss_result sss_sec_nomem(sss_error *err, const char *name, const char *tag, uint64_t bytes)
{
    return sss_fail(err, SSS_ERR_NOMEM, "%s: section %s: out of memory for %llu bytes", name, tag,
                    (unsigned long long)bytes);
}

static inline sss_result sss_sec_count_mismatch(sss_error *err, const char *name, const char *tag, uint64_t count,
                                                uint64_t want, const char *what)
{
    return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: count %llu does not match %llu %s", name, tag,
                    (unsigned long long)count, (unsigned long long)want, what);
}

/* ---- the effect sections QDIR, ENVT, PSHL (§5.11–5.13) -------------------- */

/* n floats finite (and >= 0 if nonneg), each at most max in magnitude
 * (SSS_VALUE_MAX, SSS_PROBE_SH_MAX: the bounds a decode survives). */
static inline sss_result sss_sec_check_floats(const float *x, uint64_t n, int nonneg, double max, const char *name,
                                              const char *tag, sss_result code, sss_error *err)
{
    for (uint64_t k = 0; k < n; k++) {
        if (!isfinite(x[k]) || (nonneg && x[k] < 0.0f))
            return sss_fail(err, code, "%s: section %s: value %llu (%g) is not a finite number%s", name, tag,
                            (unsigned long long)k, (double)x[k], nonneg ? " >= 0" : "");
        if (!(fabs((double)x[k]) <= max))
            return sss_fail(err, code, "%s: section %s: value %llu (%g) is beyond %g in magnitude", name, tag,
                            (unsigned long long)k, (double)x[k], max);
    }
    return SSS_OK;
}

static inline sss_result sss_sec_fx_size_mismatch(sss_error *err, const char *name, const char *tag, uint64_t size,
                                                  uint64_t want)
{
    return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: size %llu does not match its counts (%llu bytes)", name,
                    tag, (unsigned long long)size, (unsigned long long)want);
}

/* Their common head: u32 channels (= MATL's), then one u32 count. */
static inline sss_result sss_sec_fx_head(const uint8_t *p, uint64_t size, const char *name, const char *tag,
                                         const sss_bake_file *f, uint32_t *second, sss_error *err)
{
    if (size < 8)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: size %llu is too small", name, tag,
                        (unsigned long long)size);
    if (get_u32(p) != f->channels)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section %s: %u channels, but section MATL says %u", name, tag,
                        get_u32(p), f->channels);
    *second = get_u32(p + 4);
    return SSS_OK;
}

#endif
