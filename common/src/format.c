/* format.c: the .sss baked-scattering file, format version 1 (spec:
 * docs/format.md). Encoder, decoder, atomic writer and reader.
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

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

/* ---- layout constants (docs/format.md §1) ---------------------------- */

static const uint8_t SSS_MAGIC[8] = {0x89, 'S', 'S', 'S', '\r', '\n', 0x1A, '\n'};

#define HDR_FIXED 24u      /* magic, major, minor, nsections, file size */
#define ENTRY_SIZE 40u     /* one section table entry */
#define HDR_CRC_SIZE 4u
#define FLAG_REQUIRED 1u
#define MATL_SIZE 100u     /* 32 + 3*8 + 3*8 + 8 + 8 + 4 */
#define NLEVELS 256u

/* Header bytes for n sections: fixed part, table, header CRC. */
static uint64_t header_size(uint64_t nsec) { return HDR_FIXED + ENTRY_SIZE * nsec + HDR_CRC_SIZE; }

#include "format_bytes.h"
#include "format_compressed.h"
#include "format_effects.h"

/* ---- sections known to format 1 -------------------------------------- */

enum { S_GEOM, S_MATL, S_DIRS, S_QFLT, S_QL8, S_PARM, S_REFS, S_SHC, S_EFCT, S_QDIR, S_ENVT, S_PSHL, S_OWNT, S_KNOWN };
static const char *const known_tag[S_KNOWN] = {"GEOM", "MATL", "DIRS", "QFLT", "QL8 ", "PARM",
                                               "REFS", "SHC ", "EFCT", "QDIR", "ENVT", "PSHL", "OWNT"};
/* Flag bit 0 as written: PARM is provenance only, a reader may skip it.
 * REFS and SHC (1.1) are required, so a 1.0 reader refuses a compressed file
 * by naming the section instead of misreading it. */
static const uint32_t known_flags[S_KNOWN] = {FLAG_REQUIRED, FLAG_REQUIRED, FLAG_REQUIRED, FLAG_REQUIRED,
                                              FLAG_REQUIRED, 0, FLAG_REQUIRED, FLAG_REQUIRED,
                                              /* 1.2, scene bakes: all required (format_effects.c) */
                                              FLAG_REQUIRED, FLAG_REQUIRED, FLAG_REQUIRED, FLAG_REQUIRED,
                                              /* 1.3: OWNT changes what the q rows mean, so a reader
                                               * that does not know it must refuse the file */
                                              FLAG_REQUIRED};

static int known_index(const char tag[4])
{
    for (int k = 0; k < S_KNOWN; k++)
        if (memcmp(tag, known_tag[k], 4) == 0) return k;
    return -1;
}

/* Which 1.0/1.1 sections an effect mask implies (docs/format.md §5.10): a
 * plain bake (mask 0) has both; a scene bake has DIRS only for the effects
 * that use a direction set, and a q section only for direction-set. */
static int fx_uses_dirs(uint32_t m) { return !m || (m & (SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS)); }
static int fx_uses_q(uint32_t m) { return !m || (m & SSS_FX_DIR_SET); }

static uint64_t geom_size(uint32_t nv, uint32_t nf) { return 8u + 24u * (uint64_t)nv + 12u * (uint64_t)nf; }
static uint64_t dirs_size(uint32_t n, uint32_t ntri) { return 8u + 24u * (uint64_t)n + 12u * (uint64_t)ntri; }
/* 2n - 4 triangles (Euler, closed triangulated sphere); in 64 bits, as a hostile
 * n near 2^32 must not wrap onto a small stored ntri. */
static uint64_t dirs_ntri(uint32_t n) { return n >= 4 ? 2u * (uint64_t)n - 4u : 0u; }

/* ---- value checks shared by encoder and decoder ---------------------- *
 * `code` is SSS_ERR_ARG when checking what a caller asked to write and
 * SSS_ERR_CORRUPT when checking what was read. */

static sss_result check_mesh(const sss_mesh *m, const char *name, sss_result code, sss_error *err)
{
    for (uint32_t v = 0; v < m->nv; v++)
        for (int k = 0; k < 3; k++) {
            if (!isfinite(m->pos[3 * (size_t)v + k]))
                return sss_fail(err, code, "%s: section GEOM: vertex %u: position coordinate %d is not finite",
                                name, v, k);
            if (!isfinite(m->nrm[3 * (size_t)v + k]))
                return sss_fail(err, code, "%s: section GEOM: vertex %u: normal coordinate %d is not finite",
                                name, v, k);
        }
    for (uint32_t t = 0; t < m->nf; t++)
        for (int k = 0; k < 3; k++)
            if (m->tri[3 * (size_t)t + k] >= m->nv)
                return sss_fail(err, code, "%s: section GEOM: triangle %u: vertex index %u out of range (%u vertices)",
                                name, t, m->tri[3 * (size_t)t + k], m->nv);
    return SSS_OK;
}

static sss_result check_material(const sss_material *mat, double mm_per_unit, uint32_t channels,
                                 const char *name, sss_result code, sss_error *err)
{
    if (!memchr(mat->name, 0, sizeof mat->name))
        return sss_fail(err, code, "%s: section MATL: material name is not NUL-terminated within 32 bytes", name);
    if (channels != 1 && channels != 3)
        return sss_fail(err, code, "%s: section MATL: channel count %u is not 1 or 3", name, channels);
    for (int c = 0; c < SSS_MAX_CHANNELS; c++) {
        double a = mat->sigma_a[c], s = mat->sigmap_s[c];
        if (!isfinite(a) || !isfinite(s))
            return sss_fail(err, code, "%s: section MATL: channel %d: coefficients are not finite", name, c);
        if ((uint32_t)c >= channels) continue; /* unused channel: stored as given, only required finite */
        if (a < 0.0)
            return sss_fail(err, code, "%s: section MATL: channel %d: sigma_a %g is negative", name, c, a);
        if (s < 0.0)
            return sss_fail(err, code, "%s: section MATL: channel %d: sigma'_s %g is negative", name, c, s);
        if (!(a + s > 0.0))
            return sss_fail(err, code, "%s: section MATL: channel %d: sigma_a + sigma'_s is not positive", name, c);
    }
    if (!isfinite(mat->eta) || !(mat->eta > 0.0))
        return sss_fail(err, code, "%s: section MATL: eta %g is not a positive finite number", name, mat->eta);
    if (!isfinite(mm_per_unit) || !(mm_per_unit > 0.0))
        return sss_fail(err, code, "%s: section MATL: mm_per_unit %g is not a positive finite number", name,
                        mm_per_unit);
    return SSS_OK;
}

static sss_result check_dirs(const sss_dirset *s, const char *name, sss_result code, sss_error *err)
{
    for (uint32_t i = 0; i < s->n; i++) {
        const double *d = &s->dir[3 * (size_t)i];
        if (!isfinite(d[0]) || !isfinite(d[1]) || !isfinite(d[2]))
            return sss_fail(err, code, "%s: section DIRS: direction %u is not finite", name, i);
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!(fabs(len - 1.0) <= 1e-6))
            return sss_fail(err, code, "%s: section DIRS: direction %u has length %.9g, not 1 (tolerance 1e-6)",
                            name, i, len);
    }
    for (uint32_t t = 0; t < s->ntri; t++) {
        const uint32_t *x = &s->tri[3 * (size_t)t];
        for (int k = 0; k < 3; k++)
            if (x[k] >= s->n)
                return sss_fail(err, code, "%s: section DIRS: triangle %u: index %u out of range (%u directions)",
                                name, t, x[k], s->n);
        if (x[0] == x[1] || x[1] == x[2] || x[0] == x[2])
            return sss_fail(err, code, "%s: section DIRS: triangle %u repeats a direction (%u %u %u)", name, t,
                            x[0], x[1], x[2]);
    }
    return SSS_OK;
}

static sss_result check_q(const float *q, uint64_t nq, const char *name, sss_result code, sss_error *err)
{
    for (uint64_t i = 0; i < nq; i++)
        if (!(q[i] >= 0.0f) || !isfinite(q[i]))
            return sss_fail(err, code, "%s: section QFLT: value %llu (%g) is not a finite number >= 0", name,
                            (unsigned long long)i, (double)q[i]);
    return SSS_OK;
}

static sss_result check_levels(const float *levels, uint32_t channels, const char *name, sss_result code,
                               sss_error *err)
{
    for (uint32_t c = 0; c < channels; c++)
        for (uint32_t k = 0; k < NLEVELS; k++) {
            float x = levels[c * NLEVELS + k];
            if (!(x >= 0.0f) || !isfinite(x))
                return sss_fail(err, code, "%s: section QL8 : channel %u: level %u (%g) is not a finite number >= 0",
                                name, c, k, (double)x);
            if (k > 0 && x < levels[c * NLEVELS + k - 1])
                return sss_fail(err, code, "%s: section QL8 : channel %u: level %u (%g) is below level %u (%g)",
                                name, c, k, (double)x, k - 1, (double)levels[c * NLEVELS + k - 1]);
        }
    return SSS_OK;
}

/* ---- encoder --------------------------------------------------------- */

static sss_result encode_named(const sss_bake_file *f, const char *name, uint8_t **out, size_t *outlen,
                               sss_error *err)
{
    *out = NULL;
    *outlen = 0;
    const sss_result A = SSS_ERR_ARG;
    const sss_mesh *m = &f->mesh;
    const sss_dirset *ds = &f->dirs;

    /* Structure first: counts and pointers. */
    if (m->nv == 0 || m->nf == 0)
        return sss_fail(err, A, "%s: section GEOM: mesh has %u vertices and %u triangles (need at least 1 each)",
                        name, m->nv, m->nf);
    if (!m->pos || !m->nrm || !m->tri)
        return sss_fail(err, A, "%s: section GEOM: positions, normals or triangles missing", name);
    const uint32_t fxm = f->fx.mask;
    const int want_dirs = fx_uses_dirs(fxm), want_q = fx_uses_q(fxm);
    if (want_dirs && (ds->n == 0 || !ds->dir))
        return sss_fail(err, A, "%s: section DIRS: no directions", name);
    if (!want_dirs && ds->n)
        return sss_fail(err, A, "%s: section DIRS: directions given but no effect uses a direction set", name);
    if (ds->ntri != dirs_ntri(ds->n))
        return sss_fail(err, A, "%s: section DIRS: %u triangles for %u directions, expected %llu", name, ds->ntri,
                        ds->n, (unsigned long long)dirs_ntri(ds->n));
    if (ds->ntri > 0 && !ds->tri)
        return sss_fail(err, A, "%s: section DIRS: triangles missing", name);
    if (f->quant != SSS_QUANT_FLOAT && f->quant != SSS_QUANT_LLOYD8 && f->quant != SSS_QUANT_SH &&
        f->quant != SSS_QUANT_REFS)
        return sss_fail(err, A, "%s: unknown quantisation mode %d", name, (int)f->quant);
    if (!want_q && (f->q || f->qidx || f->sh.code || f->quant != SSS_QUANT_FLOAT))
        return sss_fail(err, A, "%s: integrals over a direction set given but effect direction-set is not set", name);
    if (want_q && f->quant == SSS_QUANT_FLOAT && !f->q)
        return sss_fail(err, A, "%s: section QFLT: values missing", name);
    if (f->quant == SSS_QUANT_LLOYD8 && (!f->levels || !f->qidx))
        return sss_fail(err, A, "%s: section QL8 : levels or indices missing", name);
    if (f->own_term && (f->own_term != SSS_OWN_TERM_RUNTIME || fxm || f->own_rings > SSS_OWN_RINGS_MAX))
        return sss_fail(err, A, "%s: section OWNT: mode %u, %u rings%s", name, f->own_term, f->own_rings,
                        fxm ? " in a scene bake (plain bakes only)" : " is not a valid split");

    /* Values: refuse to write what the reader would reject. */
    sss_result r;
    if ((r = check_material(&f->material, f->mm_per_unit, f->channels, name, A, err)) != SSS_OK) return r;
    if ((r = check_mesh(m, name, A, err)) != SSS_OK) return r;
    if (want_dirs && (r = check_dirs(ds, name, A, err)) != SSS_OK) return r;
    if (fxm && (r = sss_fmt_check_effects(f, name, A, err)) != SSS_OK) return r;
    uint64_t nq;
    if (!mul_u64((uint64_t)ds->n * m->nv, f->channels, &nq))
        return sss_fail(err, SSS_ERR_NOMEM, "%s: %u directions x %u vertices x %u channels overflows", name, ds->n,
                        m->nv, f->channels);
    if (!want_q) {
        /* no direction-set integrals */
    } else if (f->quant == SSS_QUANT_FLOAT) {
        if ((r = check_q(f->q, nq, name, A, err)) != SSS_OK) return r;
    } else if (f->quant == SSS_QUANT_LLOYD8) {
        if ((r = check_levels(f->levels, f->channels, name, A, err)) != SSS_OK) return r;
    } else {
        if (f->quant == SSS_QUANT_REFS && (r = sss_fmt_check_refs(f, name, A, err)) != SSS_OK) return r;
        if ((r = sss_fmt_check_shc(f, name, A, err)) != SSS_OK) return r;
    }
    const char *json = f->params_json ? f->params_json : "";
    size_t jlen = strlen(json);

    /* Sizes, in writing order (docs/format.md §3: float arrays stay 4-byte
     * aligned because PARM, the only section of arbitrary length, is last). */
    int order[S_KNOWN];
    uint32_t nsec = 0;
    order[nsec++] = S_GEOM;
    order[nsec++] = S_MATL;
    if (fxm) order[nsec++] = S_EFCT;
    if (want_dirs) order[nsec++] = S_DIRS;
    if (want_q) {
        if (f->quant == SSS_QUANT_FLOAT) order[nsec++] = S_QFLT;
        if (f->quant == SSS_QUANT_LLOYD8) order[nsec++] = S_QL8;
        if (f->quant == SSS_QUANT_REFS) order[nsec++] = S_REFS;
        if (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS) order[nsec++] = S_SHC;
    }
    if (fxm & SSS_FX_DIR_EXACT) order[nsec++] = S_QDIR;
    if (fxm & SSS_FX_ENV_SH) order[nsec++] = S_ENVT;
    if (fxm & SSS_FX_POINT_SHELLS) order[nsec++] = S_PSHL;
    if (f->own_term) order[nsec++] = S_OWNT;
    order[nsec++] = S_PARM;
    uint64_t size[S_KNOWN] = {0}, count[S_KNOWN] = {0};
    size[S_GEOM] = geom_size(m->nv, m->nf);
    count[S_GEOM] = m->nv;
    size[S_MATL] = MATL_SIZE;
    count[S_MATL] = f->channels;
    size[S_DIRS] = dirs_size(ds->n, ds->ntri);
    count[S_DIRS] = ds->n;
    int ok = 1;
    if (fxm) {
        size[S_EFCT] = sss_fmt_efct_size(f);
        count[S_EFCT] = 1;
        size[S_QDIR] = sss_fmt_qdir_size(f);
        count[S_QDIR] = f->fx.nexact;
        size[S_ENVT] = sss_fmt_envt_size(f);
        count[S_ENVT] = f->mesh.nv;
        size[S_PSHL] = sss_fmt_pshl_size(f);
        count[S_PSHL] = f->fx.nshells;
        ok = (!(fxm & SSS_FX_DIR_EXACT) || size[S_QDIR]) && (!(fxm & SSS_FX_ENV_SH) || size[S_ENVT]) &&
             (!(fxm & SSS_FX_POINT_SHELLS) || size[S_PSHL]);
    }
    if (!want_q) {
        /* nothing */
    } else if (f->quant == SSS_QUANT_FLOAT) {
        ok = mul_u64(nq, 4, &size[S_QFLT]);
        count[S_QFLT] = nq;
    } else if (f->quant == SSS_QUANT_LLOYD8) {
        ok = lin_u64(f->channels, 4 * NLEVELS, 1, nq, 4, &size[S_QL8]);
        count[S_QL8] = nq;
    } else {
        if (f->quant == SSS_QUANT_REFS) {
            size[S_REFS] = sss_fmt_refs_size(f);
            count[S_REFS] = f->ref.nref;
            ok = size[S_REFS] != 0;
        }
        size[S_SHC] = sss_fmt_shc_size(f);
        count[S_SHC] = f->sh.ncoded;
        ok = ok && size[S_SHC] != 0;
    }
    size[S_OWNT] = 8;
    count[S_OWNT] = 1;
    size[S_PARM] = jlen;
    count[S_PARM] = jlen;
    uint64_t total = header_size(nsec);
    for (uint32_t i = 0; i < nsec && ok; i++) ok = add_u64(total, size[order[i]], &total);
    if (!ok || total > SIZE_MAX)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: file size overflows", name);
    uint8_t *buf = malloc((size_t)total);
    if (!buf)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %llu bytes", name, (unsigned long long)total);

    /* Header. */
    memcpy(buf, SSS_MAGIC, 8);
    put_u16(buf + 8, SSS_FORMAT_MAJOR);
    /* Files that only use 1.0 sections say 1.0, so 1.0 readers keep reading
     * them; the compressed forms need 1.1. */
    put_u16(buf + 10, f->own_term ? 3 : fxm ? 2 : f->quant == SSS_QUANT_FLOAT || f->quant == SSS_QUANT_LLOYD8 ? 0 : 1);
    put_u32(buf + 12, nsec);
    put_u64(buf + 16, total);

    /* Sections. */
    uint64_t off = header_size(nsec);
    for (uint32_t i = 0; i < nsec; i++) {
        int s = order[i];
        uint8_t *p = buf + off;
        switch (s) {
        case S_GEOM:
            put_u32(p, m->nv);
            put_u32(p + 4, m->nf);
            p += 8;
            for (size_t k = 0; k < 3 * (size_t)m->nv; k++, p += 4) put_f32(p, m->pos[k]);
            for (size_t k = 0; k < 3 * (size_t)m->nv; k++, p += 4) put_f32(p, m->nrm[k]);
            for (size_t k = 0; k < 3 * (size_t)m->nf; k++, p += 4) put_u32(p, m->tri[k]);
            break;
        case S_MATL:
            memcpy(p, f->material.name, 32);
            p += 32;
            for (int c = 0; c < 3; c++, p += 8) put_f64(p, f->material.sigma_a[c]);
            for (int c = 0; c < 3; c++, p += 8) put_f64(p, f->material.sigmap_s[c]);
            put_f64(p, f->material.eta);
            put_f64(p + 8, f->mm_per_unit);
            put_u32(p + 16, f->channels);
            break;
        case S_DIRS:
            put_u32(p, ds->n);
            put_u32(p + 4, ds->ntri);
            p += 8;
            for (size_t k = 0; k < 3 * (size_t)ds->n; k++, p += 8) put_f64(p, ds->dir[k]);
            for (size_t k = 0; k < 3 * (size_t)ds->ntri; k++, p += 4) put_u32(p, ds->tri[k]);
            break;
        case S_QFLT:
            for (size_t k = 0; k < (size_t)nq; k++, p += 4) put_f32(p, f->q[k]);
            break;
        case S_QL8:
            put_u32(p, f->channels);
            p += 4;
            for (size_t k = 0; k < (size_t)f->channels * NLEVELS; k++, p += 4) put_f32(p, f->levels[k]);
            if (nq) memcpy(p, f->qidx, (size_t)nq);
            break;
        case S_PARM:
            if (jlen) memcpy(p, json, jlen);
            break;
        case S_REFS:
            sss_fmt_pack_refs(f, p);
            break;
        case S_SHC:
            sss_fmt_pack_shc(f, p);
            break;
        case S_EFCT: sss_fmt_pack_efct(f, p); break;
        case S_QDIR: sss_fmt_pack_qdir(f, p); break;
        case S_ENVT: sss_fmt_pack_envt(f, p); break;
        case S_PSHL: sss_fmt_pack_pshl(f, p); break;
        case S_OWNT:
            put_u32(p, SSS_OWN_TERM_RUNTIME);
            put_u32(p + 4, f->own_rings);
            break;
        }
        uint8_t *e = buf + HDR_FIXED + (size_t)ENTRY_SIZE * i;
        memcpy(e, known_tag[s], 4);
        put_u32(e + 4, known_flags[s]);
        put_u64(e + 8, off);
        put_u64(e + 16, size[s]);
        put_u64(e + 24, count[s]);
        put_u32(e + 32, sss_crc32(0, buf + off, (size_t)size[s]));
        put_u32(e + 36, 0);
        off += size[s];
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

/* ---- decoder --------------------------------------------------------- */

#define CORRUPT SSS_ERR_CORRUPT

static sss_result nomem(sss_error *err, const char *name, const char *sec, uint64_t bytes)
{
    return sss_fail(err, SSS_ERR_NOMEM, "%s: section %s: out of memory for %llu bytes", name, sec,
                    (unsigned long long)bytes);
}

static sss_result count_mismatch(sss_error *err, const char *name, const sss_section_info *si, uint64_t want,
                                 const char *what)
{
    return sss_fail(err, CORRUPT, "%s: section %s: count %llu does not match %llu %s", name, si->tag,
                    (unsigned long long)si->count, (unsigned long long)want, what);
}

static sss_result parse_geom(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (si->size < 8)
        return sss_fail(err, CORRUPT, "%s: section GEOM: size %llu is too small for the vertex and triangle counts",
                        name, (unsigned long long)si->size);
    uint32_t nv = get_u32(p), nf = get_u32(p + 4);
    if (nv == 0) return sss_fail(err, CORRUPT, "%s: section GEOM: mesh has no vertices", name);
    if (nf == 0) return sss_fail(err, CORRUPT, "%s: section GEOM: mesh has no triangles", name);
    if (si->size != geom_size(nv, nf))
        return sss_fail(err, CORRUPT, "%s: section GEOM: size %llu does not match %u vertices and %u triangles "
                        "(%llu bytes)", name, (unsigned long long)si->size, nv, nf,
                        (unsigned long long)geom_size(nv, nf));
    if (si->count != nv) return count_mismatch(err, name, si, nv, "vertices");
    /* Sizes now agree with bytes that exist, so these allocations are
     * bounded by the file size. */
    sss_mesh *m = &f->mesh;
    if (sss_mesh_alloc(m, nv, nf, NULL) != SSS_OK) return nomem(err, name, "GEOM", si->size);
    m->nrm = malloc(3 * (size_t)nv * sizeof(float));
    if (!m->nrm) return nomem(err, name, "GEOM", si->size);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)nv; k++, p += 4) m->pos[k] = get_f32(p);
    for (size_t k = 0; k < 3 * (size_t)nv; k++, p += 4) m->nrm[k] = get_f32(p);
    for (size_t k = 0; k < 3 * (size_t)nf; k++, p += 4) m->tri[k] = get_u32(p);
    return check_mesh(m, name, CORRUPT, err);
}

static sss_result parse_matl(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (si->size != MATL_SIZE)
        return sss_fail(err, CORRUPT, "%s: section MATL: size %llu, expected %u", name,
                        (unsigned long long)si->size, MATL_SIZE);
    memcpy(f->material.name, p, 32);
    p += 32;
    for (int c = 0; c < 3; c++, p += 8) f->material.sigma_a[c] = get_f64(p);
    for (int c = 0; c < 3; c++, p += 8) f->material.sigmap_s[c] = get_f64(p);
    f->material.eta = get_f64(p);
    f->mm_per_unit = get_f64(p + 8);
    f->channels = get_u32(p + 16);
    sss_result r = check_material(&f->material, f->mm_per_unit, f->channels, name, CORRUPT, err);
    if (r != SSS_OK) return r;
    if (si->count != f->channels) return count_mismatch(err, name, si, f->channels, "channels");
    return SSS_OK;
}

static sss_result parse_dirs(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (si->size < 8)
        return sss_fail(err, CORRUPT, "%s: section DIRS: size %llu is too small for the direction and triangle "
                        "counts", name, (unsigned long long)si->size);
    uint32_t n = get_u32(p), ntri = get_u32(p + 4);
    if (n == 0) return sss_fail(err, CORRUPT, "%s: section DIRS: no directions", name);
    if (ntri != dirs_ntri(n))
        return sss_fail(err, CORRUPT, "%s: section DIRS: %u triangles for %u directions, expected %llu", name, ntri,
                        n, (unsigned long long)dirs_ntri(n));
    if (si->size != dirs_size(n, ntri))
        return sss_fail(err, CORRUPT, "%s: section DIRS: size %llu does not match %u directions and %u triangles "
                        "(%llu bytes)", name, (unsigned long long)si->size, n, ntri,
                        (unsigned long long)dirs_size(n, ntri));
    if (si->count != n) return count_mismatch(err, name, si, n, "directions");
    sss_dirset *s = &f->dirs;
    s->dir = malloc(3 * (size_t)n * sizeof(double));
    s->tri = malloc((3 * (size_t)ntri + 1) * sizeof(uint32_t));
    if (!s->dir || !s->tri) return nomem(err, name, "DIRS", si->size);
    s->n = n;
    s->ntri = ntri;
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)n; k++, p += 8) s->dir[k] = get_f64(p);
    for (size_t k = 0; k < 3 * (size_t)ntri; k++, p += 4) s->tri[k] = get_u32(p);
    return check_dirs(s, name, CORRUPT, err);
}

/* Number of q values, n * nv * channels (GEOM, MATL and DIRS parsed). */
static int q_count(const sss_bake_file *f, uint64_t *nq)
{
    return mul_u64((uint64_t)f->dirs.n * f->mesh.nv, f->channels, nq);
}

static sss_result parse_qflt(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    uint64_t nq, want;
    if (!q_count(f, &nq) || !mul_u64(nq, 4, &want) || si->size != want)
        return sss_fail(err, CORRUPT, "%s: section QFLT: size %llu does not match %u directions x %u vertices x %u "
                        "channels of float32", name, (unsigned long long)si->size, f->dirs.n, f->mesh.nv,
                        f->channels);
    if (si->count != nq) return count_mismatch(err, name, si, nq, "values");
    f->q = malloc((size_t)si->size + 1);
    if (!f->q) return nomem(err, name, "QFLT", si->size);
    for (size_t k = 0; k < (size_t)nq; k++, p += 4) f->q[k] = get_f32(p);
    f->quant = SSS_QUANT_FLOAT;
    return check_q(f->q, nq, name, CORRUPT, err);
}

static sss_result parse_ql8(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                            sss_error *err)
{
    if (si->size < 4)
        return sss_fail(err, CORRUPT, "%s: section QL8 : size %llu is too small for the channel count", name,
                        (unsigned long long)si->size);
    uint32_t ch = get_u32(p);
    if (ch != f->channels)
        return sss_fail(err, CORRUPT, "%s: section QL8 : %u channels, but section MATL says %u", name, ch,
                        f->channels);
    uint64_t nq, want;
    if (!q_count(f, &nq) || !lin_u64(ch, 4 * NLEVELS, 1, nq, 4, &want) || si->size != want)
        return sss_fail(err, CORRUPT, "%s: section QL8 : size %llu does not match %u channels x 256 levels and %u "
                        "directions x %u vertices x %u channels of indices", name, (unsigned long long)si->size,
                        ch, f->dirs.n, f->mesh.nv, ch);
    if (si->count != nq) return count_mismatch(err, name, si, nq, "indices");
    f->levels = malloc((size_t)ch * NLEVELS * sizeof(float));
    f->qidx = malloc((size_t)nq + 1);
    if (!f->levels || !f->qidx) return nomem(err, name, "QL8 ", si->size);
    p += 4;
    for (size_t k = 0; k < (size_t)ch * NLEVELS; k++, p += 4) f->levels[k] = get_f32(p);
    if (nq) memcpy(f->qidx, p, (size_t)nq);
    f->quant = SSS_QUANT_LLOYD8;
    return check_levels(f->levels, ch, name, CORRUPT, err);
}

static sss_result parse_parm(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (si->count != si->size) return count_mismatch(err, name, si, si->size, "bytes");
    const uint8_t *nul = si->size ? memchr(p, 0, (size_t)si->size) : NULL;
    if (nul)
        return sss_fail(err, CORRUPT, "%s: section PARM: NUL byte at offset %llu inside the JSON text", name,
                        (unsigned long long)(nul - p));
    f->params_json = malloc((size_t)si->size + 1);
    if (!f->params_json) return nomem(err, name, "PARM", si->size);
    if (si->size) memcpy(f->params_json, p, (size_t)si->size);
    f->params_json[si->size] = 0;
    return SSS_OK;
}

/* OWNT (1.3): u32 mode (1 = the q rows hold q minus the near terms), u32
 * rings (0 … 8) (sss/ownterm.h, docs/format.md §5.14). */
static sss_result parse_ownt(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (si->size != 8 || si->count != 1)
        return sss_fail(err, CORRUPT, "%s: section OWNT: %llu bytes, count %llu (expected 8 and 1)", name,
                        (unsigned long long)si->size, (unsigned long long)si->count);
    uint32_t mode = get_u32(p), rings = get_u32(p + 4);
    if (mode != SSS_OWN_TERM_RUNTIME)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section OWNT: mode %u is unknown to this reader", name, mode);
    if (rings > SSS_OWN_RINGS_MAX)
        return sss_fail(err, CORRUPT, "%s: section OWNT: %u rings (at most %u)", name, rings, SSS_OWN_RINGS_MAX);
    f->own_term = mode;
    f->own_rings = rings;
    return SSS_OK;
}

static sss_result parse_refs(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    return sss_fmt_parse_refs(p, si->size, si->count, name, f, err);
}

static sss_result parse_shc(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                            sss_error *err)
{
    return sss_fmt_parse_shc(p, si->size, si->count, name, f, err);
}

static sss_result parse_qdir(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    return sss_fmt_parse_qdir(p, si->size, si->count, name, f, err);
}

static sss_result parse_envt(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    return sss_fmt_parse_envt(p, si->size, si->count, name, f, err);
}

static sss_result parse_pshl(const uint8_t *p, const sss_section_info *si, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    return sss_fmt_parse_pshl(p, si->size, si->count, name, f, err);
}

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
    int where[S_KNOWN];
    for (int k = 0; k < S_KNOWN; k++) where[k] = -1;
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
            if (si->flags & FLAG_REQUIRED)
                return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section %s is marked required but is unknown to "
                                "this reader (format %d.%d)", name, si->tag, SSS_FORMAT_MAJOR, SSS_FORMAT_MINOR);
            continue; /* unknown optional section: skipped */
        }
        if (where[k] >= 0)
            return sss_fail(err, CORRUPT, "%s: section %s appears more than once", name, si->tag);
        where[k] = (int)i;
    }
    static const int must[] = {S_GEOM, S_MATL, S_PARM};
    for (size_t i = 0; i < sizeof must / sizeof must[0]; i++)
        if (where[must[i]] < 0)
            return sss_fail(err, CORRUPT, "%s: missing required section %s", name, known_tag[must[i]]);
    /* 1.2: EFCT says which sections the effects need (docs/format.md §5.10);
     * read first because the presence rules below depend on it. */
    uint32_t fxm = 0;
    if (where[S_EFCT] >= 0) {
        const sss_section_info *si = &f->sections[where[S_EFCT]];
        sss_result r = sss_fmt_parse_efct(b + si->offset, si->size, si->count, name, f, err);
        if (r != SSS_OK) return r;
        fxm = f->fx.mask;
        if (!fxm) return sss_fail(err, CORRUPT, "%s: section EFCT: empty effect set", name);
    }
    const int need_dirs = fx_uses_dirs(fxm), need_q = fx_uses_q(fxm);
    {
        const struct { int sec, need; } rule[] = {{S_DIRS, need_dirs},
                                                   {S_QDIR, !!(fxm & SSS_FX_DIR_EXACT)},
                                                   {S_ENVT, !!(fxm & SSS_FX_ENV_SH)},
                                                   {S_PSHL, !!(fxm & SSS_FX_POINT_SHELLS)}};
        for (size_t i = 0; i < sizeof rule / sizeof rule[0]; i++) {
            if (rule[i].need && where[rule[i].sec] < 0)
                return sss_fail(err, CORRUPT, "%s: missing required section %s", name, known_tag[rule[i].sec]);
            if (!rule[i].need && where[rule[i].sec] >= 0)
                return sss_fail(err, CORRUPT, "%s: section %s without %s", name, known_tag[rule[i].sec],
                                fxm ? "the effect that uses it" : "section EFCT");
        }
    }
    int nq_sections = (where[S_QFLT] >= 0) + (where[S_QL8] >= 0) + (where[S_SHC] >= 0);
    if (!need_q && nq_sections)
        return sss_fail(err, CORRUPT, "%s: integrals over a direction set without effect direction-set", name);
    if (need_q && nq_sections == 0)
        return sss_fail(err, CORRUPT, "%s: missing required section QFLT, QL8 or SHC (one is needed)", name);
    if (nq_sections > 1)
        return sss_fail(err, CORRUPT, "%s: more than one of sections QFLT, QL8 and SHC (exactly one is allowed)",
                        name);
    if (where[S_REFS] >= 0 && where[S_SHC] < 0)
        return sss_fail(err, CORRUPT, "%s: section REFS without section SHC", name);
    if (where[S_OWNT] >= 0 && (fxm || !need_q))
        return sss_fail(err, CORRUPT, "%s: section OWNT in a scene bake (only plain bakes split off the own term)",
                        name);

    /* Contents, in dependency order: the q sections' sizes follow from GEOM
     * (nv), DIRS (n) and MATL (channels). */
    static const int order[] = {S_GEOM, S_MATL, S_DIRS, S_QFLT, S_QL8, S_REFS, S_SHC, S_QDIR, S_ENVT, S_PSHL, S_OWNT, S_PARM};
    typedef sss_result (*parser)(const uint8_t *, const sss_section_info *, const char *, sss_bake_file *,
                                 sss_error *);
    static const parser parse[S_KNOWN] = {parse_geom, parse_matl, parse_dirs, parse_qflt, parse_ql8,  parse_parm,
                                          parse_refs, parse_shc,  NULL,       parse_qdir, parse_envt, parse_pshl,
                                          parse_ownt};
    for (size_t i = 0; i < sizeof order / sizeof order[0]; i++) {
        int k = order[i];
        if (where[k] < 0) continue;
        const sss_section_info *si = &f->sections[where[k]];
        sss_result r = parse[k](b + si->offset, si, name, f, err);
        if (r != SSS_OK) return r;
    }
    if (fxm) return sss_fmt_check_effects(f, name, CORRUPT, err);
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
    return r;
}

void sss_file_free(sss_bake_file *f)
{
    if (!f) return;
    sss_mesh_free(&f->mesh);
    free(f->dirs.dir);
    free(f->dirs.tri);
    free(f->q);
    free(f->levels);
    free(f->qidx);
    free(f->params_json);
    sss_fmt_free_compressed(f);
    sss_fmt_free_effects(f);
    memset(f, 0, sizeof *f);
}

/* ---- files ----------------------------------------------------------- */

static int write_all(int fd, const uint8_t *p, size_t n)
{
    while (n > 0) {
        size_t chunk = n > ((size_t)1 << 30) ? ((size_t)1 << 30) : n;
        ssize_t w = write(fd, p, chunk);
        if (w < 0) {
            if (errno == EINTR) continue;
            return -1;
        }
        if (w == 0) {
            errno = EIO;
            return -1;
        }
        p += w;
        n -= (size_t)w;
    }
    return 0;
}

/* fsync of the directory holding path, so the rename itself is durable. */
static int sync_parent_dir(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir;
    if (!slash) {
        dir = malloc(2);
        if (dir) strcpy(dir, ".");
    } else {
        size_t n = slash == path ? 1 : (size_t)(slash - path);
        dir = malloc(n + 1);
        if (dir) { memcpy(dir, path, n); dir[n] = 0; }
    }
    if (!dir) { errno = ENOMEM; return -1; }
    int fd = open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    free(dir);
    if (fd < 0) return -1;
    int rc = fsync(fd);
    int e = errno;
    close(fd);
    /* Some file systems cannot sync directories; the rename has happened. */
    if (rc != 0 && (e == EINVAL || e == ENOTSUP || e == EROFS)) rc = 0;
    errno = e;
    return rc;
}

sss_result sss_file_write(const char *path, const sss_bake_file *f, sss_error *err)
{
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "sss_file_write: empty path");
    if (!f) return sss_fail(err, SSS_ERR_ARG, "%s: sss_file_write: NULL file", path);
    uint8_t *buf;
    size_t len;
    sss_result r = encode_named(f, path, &buf, &len, err);
    if (r != SSS_OK) return r;

    static const char suffix[] = ".tmp.XXXXXX";
    size_t pl = strlen(path);
    char *tmp = malloc(pl + sizeof suffix);
    if (!tmp) {
        free(buf);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory", path);
    }
    memcpy(tmp, path, pl);
    memcpy(tmp + pl, suffix, sizeof suffix);
    int fd = mkstemp(tmp);
    if (fd < 0) {
        int e = errno;
        free(buf);
        free(tmp);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot create temporary file: %s", path, strerror(e));
    }
    /* mkstemp creates 0600; keep the mode of the file being replaced, else 0644. */
    struct stat st;
    mode_t mode = 0644;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) mode = st.st_mode & 0777;
    (void)fchmod(fd, mode);

    const char *what = NULL;
    if (write_all(fd, buf, len) != 0) what = "write";
    else if (fsync(fd) != 0) what = "fsync";
    int e = errno;
    if (close(fd) != 0 && !what) { what = "close"; e = errno; }
    if (!what && rename(tmp, path) != 0) { what = "rename"; e = errno; }
    free(buf);
    if (what) {
        unlink(tmp);
        free(tmp);
        return sss_fail(err, SSS_ERR_IO, "%s: %s of temporary file failed: %s", path, what, strerror(e));
    }
    free(tmp);
    if (sync_parent_dir(path) != 0)
        return sss_fail(err, SSS_ERR_IO, "%s: written, but syncing its directory failed: %s", path,
                        strerror(errno));
    return SSS_OK;
}

sss_result sss_file_read(const char *path, sss_bake_file *f, sss_error *err)
{
    if (!f) return sss_fail(err, SSS_ERR_ARG, "sss_file_read: NULL output");
    memset(f, 0, sizeof *f);
    if (!path || !*path) return sss_fail(err, SSS_ERR_ARG, "sss_file_read: empty path");
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return sss_fail(err, SSS_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return sss_fail(err, SSS_ERR_IO, "%s: cannot stat: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) {
        close(fd);
        return sss_fail(err, SSS_ERR_IO, "%s: not a regular file", path);
    }
    if (st.st_size < 0 || (uint64_t)st.st_size > SIZE_MAX) {
        close(fd);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: file of %lld bytes does not fit in memory", path,
                        (long long)st.st_size);
    }
    size_t len = (size_t)st.st_size;
    uint8_t *buf = malloc(len ? len : 1);
    if (!buf) {
        close(fd);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: out of memory for %zu bytes", path, len);
    }
    size_t got = 0;
    while (got < len) {
        size_t chunk = len - got > ((size_t)1 << 30) ? ((size_t)1 << 30) : len - got;
        ssize_t n = read(fd, buf + got, chunk);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            int e = n < 0 ? errno : 0;
            close(fd);
            free(buf);
            if (n == 0)
                return sss_fail(err, SSS_ERR_IO, "%s: file shrank while reading (%zu of %zu bytes)", path, got, len);
            return sss_fail(err, SSS_ERR_IO, "%s: read failed: %s", path, strerror(e));
        }
        got += (size_t)n;
    }
    close(fd);
    sss_result r = sss_file_decode(buf, len, path, f, err);
    free(buf);
    return r;
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
    if (f->quant == SSS_QUANT_LLOYD8) return values + 256.0 * sizeof(float) * f->channels / f->mesh.nv;
    if (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS) {
        sss_storage s;
        sss_file_storage(f, &s);
        return (double)s.scattering / f->mesh.nv;
    }
    return values * sizeof(float);
}

void sss_file_storage(const sss_bake_file *f, sss_storage *s)
{
    memset(s, 0, sizeof *s);
    if (!f) return;
    const uint64_t C = f->channels, nd = f->dirs.n, nv = f->mesh.nv;
    s->dirs = f->dirs.n ? dirs_size(f->dirs.n, f->dirs.ntri) : 0;
    switch (fx_uses_q(f->fx.mask) ? f->quant : (sss_quant)-1) {
    default:
        break;
    case SSS_QUANT_FLOAT:
        s->values = nd * nv * C * 4;
        break;
    case SSS_QUANT_LLOYD8:
        s->section_headers = 4;
        s->lloyd_tables = C * NLEVELS * 4;
        s->values = nd * nv * C;
        break;
    case SSS_QUANT_REFS: {
        const sss_refcode *r = &f->ref;
        const uint64_t ncoded = nv - r->nref;
        s->section_headers += 28;
        s->lloyd_tables = C * NLEVELS * 4;
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
        s->sh_tables = 4 * ntab * (h->kind == SSS_SHQ_LINEAR8 ? 1 : sss_shq_levels(h->kind));
        s->sh_codes = sss_shq_code_bytes(h->kind, (uint64_t)h->ncoded * ntab);
        break;
    }
    }
    if (f->fx.mask)
        s->effects = sss_fmt_efct_size(f) + (f->fx.mask & SSS_FX_DIR_EXACT ? sss_fmt_qdir_size(f) : 0) +
                     (f->fx.mask & SSS_FX_ENV_SH ? sss_fmt_envt_size(f) : 0) +
                     (f->fx.mask & SSS_FX_POINT_SHELLS ? sss_fmt_pshl_size(f) : 0);
    s->scattering = s->effects + s->values + s->lloyd_tables + s->section_headers + s->ref_vertex + s->ref_tri + s->vertex_tri +
                    s->weights + s->ref_values + s->sh_tables + s->sh_codes;
    s->total = s->scattering + s->dirs;
}
