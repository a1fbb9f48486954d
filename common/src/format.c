/* format.c: the .sss baked-scattering file, format version 1 (spec:
 * docs/format.md). Encoder, decoder, atomic writer and reader.
 *
 * Each section has its codec in sections/ (size, count, check, pack,
 * parse, free), listed in the table of sections/sections.h. This file lays
 * out the header and the section table with their CRCs (§2–3), walks the
 * table to write and to read the sections, and holds the rules that tie
 * several sections together (§5.9, §5.10, §5.14).
 *
 * Everything is packed and unpacked byte by byte in little-endian order, so
 * the bytes do not depend on the host. The decoder treats its input as
 * hostile: every offset, size and count is checked in 64-bit arithmetic with
 * overflow checks against the bytes actually present before anything is
 * allocated or read, and every value is range-checked before the file is
 * handed out.
 */
#define _POSIX_C_SOURCE 200809L

#include "sss/format.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/decode.h"
#include "sss/fileio.h"

#include "sections/sections.h"

/* ---- layout constants (docs/format.md §1) ---------------------------- */

static const uint8_t SSS_MAGIC[8] = {0x89, 'S', 'S', 'S', '\r', '\n', 0x1A, '\n'};

#define HDR_FIXED 24u      /* magic, major, minor, nsections, file size */
#define ENTRY_SIZE 40u     /* one section table entry */
#define HDR_CRC_SIZE 4u

/* Header bytes for n sections: fixed part, table, header CRC. */
static uint64_t header_size(uint64_t nsec) { return HDR_FIXED + ENTRY_SIZE * nsec + HDR_CRC_SIZE; }

/* ---- sections known to format 1 (sections/sections.h) ------------------ */

typedef struct section_codec {
    char tag[5];
    uint32_t flags;  /* SSS_SEC_*: the written bit and the reader's steering bits */
    uint16_t since;  /* minor version that introduced it */
    uint64_t (*size)(const sss_bake_file *f);
    uint64_t (*count)(const sss_bake_file *f);
    sss_result (*check)(const sss_bake_file *f, const char *name, sss_result code, sss_error *err);
    void (*pack)(const sss_bake_file *f, uint8_t *p);
    sss_result (*parse)(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                        sss_error *err);
    void (*free)(sss_bake_file *f);
    int (*wants)(const sss_bake_file *f);
    sss_sec_need (*needs)(const sss_bake_file *f);
} section_codec;

#define SECTION_ROW(id, tag, flags, since, codec)                                                                \
    [SSS_SEC_##id] = {tag, flags, since, sss_sec_##codec##_size, sss_sec_##codec##_count,                       \
                      sss_sec_##codec##_check, sss_sec_##codec##_pack, sss_sec_##codec##_parse,                 \
                      sss_sec_##codec##_free, sss_sec_##codec##_wants, sss_sec_##codec##_needs},
static const section_codec sections[SSS_SEC_COUNT] = {SSS_SECTIONS(SECTION_ROW)};
#undef SECTION_ROW

static int known_index(const char tag[4])
{
    for (int k = 0; k < SSS_SEC_COUNT; k++)
        if (memcmp(tag, sections[k].tag, 4) == 0) return k;
    return -1;
}

/* ---- encoder --------------------------------------------------------- */

static sss_result encode_named(const sss_bake_file *f, const char *name, uint8_t **out, size_t *outlen,
                               sss_error *err)
{
    *out = NULL;
    *outlen = 0;
    const sss_result A = SSS_ERR_ARG;
    const sss_dirset *ds = &f->dirs;
    const uint32_t fxm = f->fx.mask;

    /* Rules across sections first (§5.9, §5.10): a known storage form, and
     * no direction set or integrals over it that the effect set does not
     * call for (a section that is not written must not be silently lost). */
    if (f->quant != SSS_QUANT_FLOAT && f->quant != SSS_QUANT_LLOYD8 && f->quant != SSS_QUANT_SH &&
        f->quant != SSS_QUANT_REFS)
        return sss_fail(err, A, "%s: unknown quantisation mode %d", name, (int)f->quant);
    if (!sss_sec_fx_uses_dirs(fxm) && ds->n)
        return sss_fail(err, A, "%s: section DIRS: directions given but no effect uses a direction set", name);
    if (!sss_sec_fx_uses_dirs(fxm) && ds->ntri)
        return sss_fail(err, A, "%s: section DIRS: %u triangles for %u directions, expected %llu", name, ds->ntri,
                        ds->n, (unsigned long long)sss_sec_dirs_ntri(ds->n));
    if (!sss_sec_fx_uses_q(fxm) && (f->q || f->qidx || f->sh.code || f->quant != SSS_QUANT_FLOAT))
        return sss_fail(err, A, "%s: integrals over a direction set given but effect direction-set is not set", name);
    uint64_t nq = 0;
    sss_result r = sss_sec_q_count_checked(f, name, &nq, err);
    if (r != SSS_OK) return r;

    /* Then each section written, in the order a reader checks them (§6),
     * so that a writer refuses what a reader would refuse (and names the
     * fault the reader would name first). */
    int want[SSS_SEC_COUNT];
    for (int k = 0; k < SSS_SEC_COUNT; k++) want[k] = sections[k].wants(f);
    for (int late = 0; late < 2; late++)
        for (int k = 0; k < SSS_SEC_COUNT; k++)
            if (want[k] && ((sections[k].flags & SSS_SEC_CHECK_LAST) != 0) == late &&
                (r = sections[k].check(f, name, A, err)) != SSS_OK)
                return r;

    /* Sizes, in writing order (table order, docs/format.md §1: float arrays
     * stay 4-byte aligned because PARM, the only section of arbitrary
     * length, is last). The minor version is the newest of the sections
     * written, so older readers refuse a file only when it holds a section
     * they do not know, by its required flag (§4). */
    uint64_t size[SSS_SEC_COUNT] = {0}, count[SSS_SEC_COUNT] = {0};
    uint32_t nsec = 0;
    uint16_t minor = 0;
    int ok = 1;
    for (int k = 0; k < SSS_SEC_COUNT; k++) {
        if (!want[k]) continue;
        nsec++;
        size[k] = sections[k].size(f);
        count[k] = sections[k].count(f);
        ok = ok && (size[k] != 0 || (sections[k].flags & SSS_SEC_MAY_BE_EMPTY));
        if (sections[k].since > minor) minor = sections[k].since;
    }
    /* SHC's 16-bit codes (docs/format.md §5.8) are a kind a 1.1–1.6 reader
     * refuses by its number: the file says 1.7 */
    if (want[SSS_SEC_SHC] && f->sh.kind == SSS_SHQ_LINEAR16 && minor < 7) minor = 7;
    uint64_t total = header_size(nsec);
    for (int k = 0; k < SSS_SEC_COUNT && ok; k++)
        if (want[k]) ok = add_u64(total, size[k], &total);
    if (!ok || total > SIZE_MAX)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: file size overflows", name);
    uint8_t *buf = malloc((size_t)total);
    if (!buf)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu bytes", name, (unsigned long long)total);

    /* Header. */
    memcpy(buf, SSS_MAGIC, 8);
    put_u16(buf + 8, SSS_FORMAT_MAJOR);
    put_u16(buf + 10, minor);
    put_u32(buf + 12, nsec);
    put_u64(buf + 16, total);

    /* Sections and their table entries. */
    uint64_t off = header_size(nsec);
    uint32_t i = 0;
    for (int k = 0; k < SSS_SEC_COUNT; k++) {
        if (!want[k]) continue;
        sections[k].pack(f, buf + off);
        uint8_t *e = buf + HDR_FIXED + (size_t)ENTRY_SIZE * i++;
        memcpy(e, sections[k].tag, 4);
        put_u32(e + 4, sections[k].flags & SSS_SEC_FILE_FLAGS);
        put_u64(e + 8, off);
        put_u64(e + 16, size[k]);
        put_u64(e + 24, count[k]);
        put_u32(e + 32, sss_crc32(0, buf + off, (size_t)size[k]));
        put_u32(e + 36, 0);
        off += size[k];
    }
    size_t hcrc = HDR_FIXED + (size_t)ENTRY_SIZE * nsec;
    put_u32(buf + hcrc, sss_crc32(0, buf, hcrc));
    *out = buf;
    *outlen = (size_t)total;
    return SSS_OK;
}

sss_result sss_file_encode(const sss_bake_file *f, uint8_t **buf, size_t *len, sss_error *err)
{
    if (!f || !buf || !len) return sss_fail(err, SSS_ERR_ARG, "sss_file_encode: NULL argument");
    return encode_named(f, "sss_file_encode", buf, len, err);
}

sss_result sss_file_encode_named(const sss_bake_file *f, const char *name, uint8_t **buf, size_t *len, sss_error *err)
{
    if (!f || !buf || !len) return sss_fail(err, SSS_ERR_ARG, "sss_file_encode: NULL argument");
    return encode_named(f, name ? name : "sss_file_encode", buf, len, err);
}

/* ---- decoder --------------------------------------------------------- */

#define CORRUPT SSS_ERR_CORRUPT

static sss_result decode_impl(const uint8_t *b, size_t len, const char *name, sss_bake_file *f, sss_error *err)
{
    /* Bytes 0-11 (magic and version) mean the same in every major version;
     * everything after them is only interpreted once the major is known. */
    if (len < 8 || memcmp(b, SSS_MAGIC, 8) != 0) {
        size_t k = len < 8 ? len : 8;
        if (memcmp(b, SSS_MAGIC, k) == 0)
            return sss_fail(err, CORRUPT, "%s: truncated: %zu bytes, the header alone needs %u", name, len,
                            (unsigned)header_size(0));
        if (len >= 8 && memcmp(b + 1, SSS_MAGIC + 1, 3) == 0)
            return sss_fail(err, SSS_ERR_FORMAT, "%s: not a .sss file: bad magic (altered by a text-mode "
                            "transfer?)", name);
        return sss_fail(err, SSS_ERR_FORMAT, "%s: not a .sss file (bad magic)", name);
    }
    if (len < 12)
        return sss_fail(err, CORRUPT, "%s: truncated: %zu bytes, the header alone needs %u", name, len,
                        (unsigned)header_size(0));
    uint16_t major = get_u16(b + 8), minor = get_u16(b + 10);
    if (major > SSS_FORMAT_MAJOR)
        return sss_fail(err, SSS_ERR_VERSION, "%s: format version %u.%u is newer than this reader (%d.x)", name,
                        major, minor, SSS_FORMAT_MAJOR);
    if (major < SSS_FORMAT_MAJOR)
        return sss_fail(err, SSS_ERR_VERSION, "%s: format version %u.%u is older than this reader (%d.x)", name,
                        major, minor, SSS_FORMAT_MAJOR);
    if (len < header_size(0))
        return sss_fail(err, CORRUPT, "%s: truncated: %zu bytes, the header alone needs %u", name, len,
                        (unsigned)header_size(0));
    uint32_t nsec = get_u32(b + 12);
    if (nsec > SSS_MAX_SECTIONS)
        return sss_fail(err, CORRUPT, "%s: %u sections, at most %d allowed", name, nsec, SSS_MAX_SECTIONS);
    uint64_t hsize = header_size(nsec);
    if (len < hsize)
        return sss_fail(err, CORRUPT, "%s: truncated: %zu bytes, the header with %u sections needs %llu", name,
                        len, nsec, (unsigned long long)hsize);
    size_t hcrc_at = HDR_FIXED + (size_t)ENTRY_SIZE * nsec;
    uint32_t hcrc = get_u32(b + hcrc_at), hcrc_want = sss_crc32(0, b, hcrc_at);
    if (hcrc != hcrc_want)
        return sss_fail(err, CORRUPT, "%s: header checksum mismatch (stored %08x, computed %08x)", name, hcrc,
                        hcrc_want);
    uint64_t fsize = get_u64(b + 16);
    if (fsize != len)
        return sss_fail(err, CORRUPT, "%s: %s: %zu bytes, the header says %llu", name,
                        len < fsize ? "truncated" : "trailing data", len, (unsigned long long)fsize);
    f->version_major = major;
    f->version_minor = minor;
    f->file_size = fsize;
    f->nsections = nsec;

    /* Section table: tags, exact tiling of [hsize, len), checksums. */
    int where[SSS_SEC_COUNT];
    for (int k = 0; k < SSS_SEC_COUNT; k++) where[k] = -1;
    uint64_t expect = hsize;
    for (uint32_t i = 0; i < nsec; i++) {
        const uint8_t *e = b + HDR_FIXED + (size_t)ENTRY_SIZE * i;
        sss_section_info *si = &f->sections[i];
        for (int k = 0; k < 4; k++) {
            if (e[k] < 0x20 || e[k] > 0x7E)
                return sss_fail(err, CORRUPT, "%s: section %u: tag byte %d (0x%02x) is not printable ASCII", name,
                                i, k, e[k]);
            si->tag[k] = (char)e[k];
        }
        si->tag[4] = 0;
        si->flags = get_u32(e + 4);
        si->offset = get_u64(e + 8);
        si->size = get_u64(e + 16);
        si->count = get_u64(e + 24);
        si->crc32 = get_u32(e + 32);
        if (si->offset != expect)
            return sss_fail(err, CORRUPT, "%s: section %s: offset %llu, expected %llu (sections must follow the "
                            "header and each other without gaps)", name, si->tag,
                            (unsigned long long)si->offset, (unsigned long long)expect);
        if (si->size > len - si->offset)
            return sss_fail(err, CORRUPT, "%s: section %s: size %llu at offset %llu extends past the end of the "
                            "file (%zu bytes)", name, si->tag, (unsigned long long)si->size,
                            (unsigned long long)si->offset, len);
        expect = si->offset + si->size;
    }
    if (expect != len)
        return sss_fail(err, CORRUPT, "%s: %llu bytes after the last section are not covered by any section", name,
                        (unsigned long long)(len - expect));
    for (uint32_t i = 0; i < nsec; i++) {
        const sss_section_info *si = &f->sections[i];
        uint32_t c = sss_crc32(0, b + si->offset, (size_t)si->size);
        if (c != si->crc32)
            return sss_fail(err, CORRUPT, "%s: section %s: checksum mismatch (stored %08x, computed %08x)", name,
                            si->tag, si->crc32, c);
    }
    for (uint32_t i = 0; i < nsec; i++) {
        const sss_section_info *si = &f->sections[i];
        int k = known_index(si->tag);
        if (k < 0) {
            if (si->flags & SSS_SEC_REQUIRED)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section %s is marked required but is unknown to "
                                "this reader (format %d.%d)", name, si->tag, SSS_FORMAT_MAJOR, SSS_FORMAT_MINOR);
            continue; /* unknown optional section: skipped */
        }
        if (where[k] >= 0)
            return sss_fail(err, CORRUPT, "%s: section %s appears more than once", name, si->tag);
        where[k] = (int)i;
    }
#define PARSE(k)                                                                                                    \
    sections[k].parse(b + f->sections[where[k]].offset, f->sections[where[k]].size, f->sections[where[k]].count, \
                      name, f, err)
    sss_result r;
    for (int k = 0; k < SSS_SEC_COUNT; k++)
        if ((sections[k].flags & SSS_SEC_EVERY_FILE) && where[k] < 0)
            return sss_fail(err, CORRUPT, "%s: missing required section %s", name, sections[k].tag);
    /* EFCT says which sections the effects need (docs/format.md §5.10):
     * read first because the presence rules below depend on it. */
    for (int k = 0; k < SSS_SEC_COUNT; k++)
        if ((sections[k].flags & SSS_SEC_READ_FIRST) && where[k] >= 0 && (r = PARSE(k)) != SSS_OK) return r;
    const uint32_t fxm = f->fx.mask;
    for (int k = 0; k < SSS_SEC_COUNT; k++) {
        if (sections[k].flags & SSS_SEC_EVERY_FILE) continue;
        const sss_sec_need need = sections[k].needs(f);
        if (need == SSS_SEC_PRESENT && where[k] < 0)
            return sss_fail(err, CORRUPT, "%s: missing required section %s", name, sections[k].tag);
        if (need == SSS_SEC_ABSENT && where[k] >= 0)
            return sss_fail(err, CORRUPT, "%s: section %s without %s", name, sections[k].tag,
                            fxm ? "the effect that uses it" : "section EFCT");
    }
    /* §5.10, §5.17: one storage form of the directions, for the effects
     * that use a direction set (the needs above refused it for the others) */
    const int ndir_sections = (where[SSS_SEC_DIRS] >= 0) + (where[SSS_SEC_DIRC] >= 0);
    if (sss_sec_fx_uses_dirs(fxm) && ndir_sections == 0)
        return sss_fail(err, CORRUPT, "%s: missing required section DIRS or DIRC (one is needed)", name);
    if (ndir_sections > 1)
        return sss_fail(err, CORRUPT, "%s: both sections DIRS and DIRC (exactly one is allowed)", name);
    /* §5.9 and §5.10: one storage form of the direction-set integrals, for
     * the direction-set effect; §5.14: the own term only off those rows. */
    const int need_q = sss_sec_fx_uses_q(fxm);
    int nq_sections = (where[SSS_SEC_QFLT] >= 0) + (where[SSS_SEC_QL8] >= 0) + (where[SSS_SEC_SHC] >= 0);
    if (!need_q && nq_sections)
        return sss_fail(err, CORRUPT, "%s: integrals over a direction set without effect direction-set", name);
    if (need_q && nq_sections == 0)
        return sss_fail(err, CORRUPT, "%s: missing required section QFLT, QL8 or SHC (one is needed)", name);
    if (nq_sections > 1)
        return sss_fail(err, CORRUPT, "%s: more than one of sections QFLT, QL8 and SHC (exactly one is allowed)",
                        name);
    if (where[SSS_SEC_REFS] >= 0 && where[SSS_SEC_SHC] < 0)
        return sss_fail(err, CORRUPT, "%s: section REFS without section SHC", name);
    if (where[SSS_SEC_OWNT] >= 0 && !need_q)
        return sss_fail(err, CORRUPT, "%s: section OWNT without effect direction-set (the near terms are split off "
                        "the direction set's rows only)", name);

    /* Contents, in dependency order (table order: the q sections' sizes
     * follow from GEOM (nv), DIRS (n) and MATL (channels)); then the checks
     * that need every section read (the effect set against MATL and DIRS). */
    for (int k = 0; k < SSS_SEC_COUNT; k++)
        if (!(sections[k].flags & SSS_SEC_READ_FIRST) && where[k] >= 0 && (r = PARSE(k)) != SSS_OK) return r;
#undef PARSE
    for (int k = 0; k < SSS_SEC_COUNT; k++)
        if ((sections[k].flags & SSS_SEC_CHECK_LAST) && where[k] >= 0 &&
            (r = sections[k].check(f, name, CORRUPT, err)) != SSS_OK)
            return r;
    return SSS_OK;
}

sss_result sss_file_decode(const void *buf, size_t len, const char *name, sss_bake_file *f, sss_error *err)
{
    if (!name) name = "<memory>";
    if (!f) return sss_fail(err, SSS_ERR_ARG, "%s: sss_file_decode: NULL output", name);
    memset(f, 0, sizeof *f);
    if (!buf && len) return sss_fail(err, SSS_ERR_ARG, "%s: sss_file_decode: NULL buffer", name);
    static const uint8_t empty[1] = {0};
    sss_result r = decode_impl(buf ? buf : empty, len, name, f, err);
    if (r != SSS_OK) sss_file_free(f);
    /* the decoder's load-time layout of SH codes; without memory for it
     * the decoder takes its per-vertex loop (the same values, slower) */
    else (void)sss_decode_prepare(f);
    return r;
}

void sss_file_free(sss_bake_file *f)
{
    if (!f) return;
    for (int k = 0; k < SSS_SEC_COUNT; k++) sections[k].free(f);
    memset(f, 0, sizeof *f);
}

/* ---- files ----------------------------------------------------------- */

sss_result sss_file_write(const char *path, const sss_bake_file *f, sss_error *err)
{
    return sss_file_write_with(path, f, NULL, err);
}

sss_result sss_file_write_with(const char *path, const sss_bake_file *f, const sss_inputs *in, sss_error *err)
{
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "sss_file_write: empty path");
    if (!f) return sss_fail(err, SSS_ERR_ARG, "%s: sss_file_write: NULL file", path);
    /* the output is checked before the encoding, so that a path that may
     * not be written is named first (sss/fileio.h), and again at the rename */
    sss_result r = sss_output_check(path, in, NULL, err);
    if (r != SSS_OK) return r;
    uint8_t *buf;
    size_t len;
    r = encode_named(f, path, &buf, &len, err);
    if (r != SSS_OK) return r;
    r = sss_write_file(path, buf, len, in, err);
    free(buf);
    return r;
}

sss_result sss_file_read(const char *path, sss_bake_file *f, sss_error *err)
{
    if (!f) return sss_fail(err, SSS_ERR_ARG, "sss_file_read: NULL output");
    memset(f, 0, sizeof *f);
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "sss_file_read: empty path");
    char *buf;
    size_t len;
    /* a regular file only, opened without blocking (sss/fileio.h) */
    sss_result r = sss_input_read_all(path, 0, &buf, &len, err);
    if (r != SSS_OK) return r;
    r = sss_file_decode(buf, len, path, f, err);
    free(buf);
    return r;
}

const char *sss_quant_name(sss_quant q)
{
    switch (q) {
    case SSS_QUANT_FLOAT: return "float";
    case SSS_QUANT_LLOYD8: return "lloyd8";
    case SSS_QUANT_SH: return "sh";
    case SSS_QUANT_REFS: return "refs";
    default: return "?";
    }
}

double sss_file_integral_bytes_per_vertex(const sss_bake_file *f)
{
    if (!f->mesh.nv) return 0.0;
    if (f->fx.mask) { /* scene bake (1.2): every effect's data */
        sss_storage s;
        sss_file_storage(f, &s);
        return (double)s.scattering / f->mesh.nv;
    }
    const double values = (double)f->dirs.n * f->channels;
    const double qvec = f->qvec ? 3.0 * sizeof(float) * values : 0.0; /* section QVEC (§5.19) */
    if (f->quant == SSS_QUANT_LLOYD8) return values + 256.0 * sizeof(float) * f->channels / f->mesh.nv + qvec;
    if (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS) {
        sss_storage s;
        sss_file_storage(f, &s);
        return (double)s.scattering / f->mesh.nv;
    }
    return values * sizeof(float) + qvec;
}

void sss_file_storage(const sss_bake_file *f, sss_storage *s)
{
    memset(s, 0, sizeof *s);
    if (!f) return;
    const uint64_t C = f->channels, nd = f->dirs.n, nv = f->mesh.nv;
    s->dirs = sss_sec_directions_size(f);
    switch (sss_sec_fx_uses_q(f->fx.mask) ? f->quant : (sss_quant)-1) {
    default:
        break;
    case SSS_QUANT_FLOAT:
        s->values = nd * nv * C * 4;
        break;
    case SSS_QUANT_LLOYD8:
        s->section_headers = 4;
        s->lloyd_tables = C * SSS_SEC_NLEVELS * 4;
        s->values = nd * nv * C;
        break;
    case SSS_QUANT_REFS: {
        const sss_refcode *r = &f->ref;
        const uint64_t ncoded = nv - r->nref;
        s->section_headers += 28;
        s->lloyd_tables = C * SSS_SEC_NLEVELS * 4;
        s->ref_vertex = 4ull * r->nref;
        s->ref_tri = 12ull * r->nrt;
        s->vertex_tri = (uint64_t)r->tri_bytes * ncoded;
        s->weights = 2ull * (r->wbits / 8) * ncoded;
        s->ref_values = nd * r->nref * C;
    } /* fall through: the SH part */
    /* FALLTHROUGH */
    case SSS_QUANT_SH: {
        const sss_shcode *h = &f->sh;
        const uint64_t ntab = C * h->ncoef;
        s->section_headers += 16;
        s->sh_tables = 4 * ntab * (sss_shq_linear_max(h->kind) ? 1 : sss_shq_levels(h->kind));
        s->sh_codes = sss_shq_code_bytes(h->kind, (uint64_t)h->ncoded * ntab);
        break;
    }
    }
    if (f->fx.mask)
        s->effects = sss_sec_efct_size(f) + (f->fx.mask & SSS_FX_DIR_EXACT ? sss_sec_qdir_size(f) : 0) +
                     (f->fx.mask & SSS_FX_ENV_SH ? sss_sec_envt_size(f) : 0) +
                     (f->fx.mask & SSS_FX_POINT_SHELLS ? sss_sec_pshl_size(f) : 0);
    s->scattering = s->effects + s->values + s->lloyd_tables + s->section_headers + s->ref_vertex + s->ref_tri + s->vertex_tri +
                    s->weights + s->ref_values + s->sh_tables + s->sh_codes;
    s->total = s->scattering + s->dirs;
}
