/* shc.c: section SHC (format 1.1), the spherical-harmonic part of the
 * compressed forms of Hao–Varshney 2004 §4.1 and §4.3: per coded vertex and
 * channel, the first order² real SH coefficients (sss/sh.h basis) of q
 * itself (SH-only files) or of the delta left after blending the
 * references of section REFS (refs.c), quantised linearly (the paper's
 * §4.3 int8 scheme, or §4.1's "normalized short integer", int16, format
 * 1.7) or with Lloyd–Max tables. Layout and rules:
 * docs/format.md §5.8.
 */
#include <stdlib.h>
#include <string.h>

#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT
#define SHC_HEADER 16u /* channels, order, ncoded, kind */

const char *sss_shq_name(uint32_t kind)
{
    static const char *const n[SSS_SHQ_KINDS] = {"linear8", "lloyd8", "lloyd4", "linear16"};
    return kind < SSS_SHQ_KINDS ? n[kind] : "?";
}

uint32_t sss_shq_levels(uint32_t kind)
{
    switch (kind) {
    case SSS_SHQ_LINEAR8:
    case SSS_SHQ_LLOYD8: return 256;
    case SSS_SHQ_LLOYD4: return 16;
    case SSS_SHQ_LINEAR16: return 1;
    default: return 0;
    }
}

uint32_t sss_shq_linear_max(uint32_t kind)
{
    return kind == SSS_SHQ_LINEAR8 ? 127u : kind == SSS_SHQ_LINEAR16 ? 32767u : 0u;
}

uint64_t sss_shq_code_bytes(uint32_t kind, uint64_t n)
{
    if (kind == SSS_SHQ_LINEAR16) return n <= UINT64_MAX / 2 ? 2 * n : 0;
    return kind == SSS_SHQ_LLOYD4 ? n / 2 + (n & 1) : n;
}

void sss_shq_linear16_table(const float *scale, uint32_t n, float *table)
{
    for (uint32_t i = 0; i < n; i++) table[i] = (float)((double)scale[i] / 32767.0);
}

void sss_shq_linear8_table(const float *scale, uint32_t n, float *table)
{
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t b = 0; b < 256; b++) /* code byte b means the int8 (int8_t)b */
            table[(size_t)i * 256 + b] = (float)((double)(b < 128 ? (int)b : (int)b - 256) * scale[i] / 127.0);
}

static uint64_t shc_size_of(uint32_t C, uint32_t order, uint32_t kind, uint64_t ncoded)
{
    const uint64_t ncoef = (uint64_t)order * order;
    const uint64_t per = sss_shq_linear_max(kind) ? 1 : sss_shq_levels(kind);
    uint64_t n, s = SHC_HEADER + 4ull * C * ncoef * per;
    if (!mul_u64(ncoded, C * ncoef, &n) || (n && !sss_shq_code_bytes(kind, n)) ||
        !add_u64(s, sss_shq_code_bytes(kind, n), &s))
        return 0;
    return s;
}

uint64_t sss_sec_shc_size(const sss_bake_file *f)
{
    return shc_size_of(f->channels, f->sh.order, f->sh.kind, f->sh.ncoded);
}

uint64_t sss_sec_shc_count(const sss_bake_file *f) { return f->sh.ncoded; }

/* Every count and value of f->sh against f's mesh, channels and (with
 * REFS) its references. */
sss_result sss_sec_shc_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_shcode *s = &f->sh;
    const uint32_t C = f->channels;
    if (s->order > SSS_SH_FILE_MAX_ORDER)
        return sss_fail(err, code, "%s: section SHC : SH order %u out of range 0 … %d", name, s->order,
                        SSS_SH_FILE_MAX_ORDER);
    if (s->ncoef != s->order * s->order)
        return sss_fail(err, code, "%s: section SHC : %u coefficients for order %u", name, s->ncoef, s->order);
    if (f->quant == SSS_QUANT_SH && s->order == 0)
        return sss_fail(err, code, "%s: section SHC : SH order 0 stores nothing (SH-only files need order >= 1)",
                        name);
    const uint32_t L = sss_shq_levels(s->kind);
    if (!L) return sss_fail(err, code, "%s: section SHC : unknown quantisation kind %u", name, s->kind);
    if (s->ncoded != sss_sec_ncoded(f))
        return sss_fail(err, code, "%s: section SHC : %u coded vertices, expected %llu", name, s->ncoded,
                        (unsigned long long)sss_sec_ncoded(f));
    const uint64_t ntab = (uint64_t)C * s->ncoef;
    const uint64_t ncodes = (uint64_t)s->ncoded * ntab;
    const int linear = sss_shq_linear_max(s->kind) != 0;
    if ((ntab && !s->table) || (linear && ntab && !s->scale) || (ncodes && !s->code))
        return sss_fail(err, code, "%s: section SHC : arrays missing", name);
    /* scales and table entries at most SSS_VALUE_MAX: the bound a decode
     * survives (sss/format.h) */
    if (linear) {
        for (uint64_t i = 0; i < ntab; i++)
            if (!(s->scale[i] >= 0.0f) || !(s->scale[i] <= SSS_VALUE_MAX))
                return sss_fail(err, code, "%s: section SHC : scale %llu (%g) is not a number in [0, %g]", name,
                                (unsigned long long)i, (double)s->scale[i], SSS_VALUE_MAX);
    } else {
        for (uint64_t i = 0; i < ntab * L; i++)
            if (!(fabs((double)s->table[i]) <= SSS_VALUE_MAX))
                return sss_fail(err, code, "%s: section SHC : table entry %llu (%g) is not finite or beyond %g", name,
                                (unsigned long long)i, (double)s->table[i], SSS_VALUE_MAX);
    }
    /* An odd count of 4-bit codes leaves the last byte's high nibble unused:
     * it must be 0, so that one content has one encoding. */
    if (s->kind == SSS_SHQ_LLOYD4 && (ncodes & 1) && (s->code[ncodes / 2] >> 4) != 0)
        return sss_fail(err, code, "%s: section SHC : unused high nibble of the last code byte is not 0", name);
    /* 16-bit codes are symmetric, −32767 … 32767, as the 8-bit ones are
     * (−127 … 127): −32768 has no meaning, so one content has one encoding */
    if (s->kind == SSS_SHQ_LINEAR16)
        for (uint64_t e = 0; e < ncodes; e++)
            if (sss_shq_code(s->code, s->kind, e) == 0x8000u)
                return sss_fail(err, code, "%s: section SHC : code %llu is -32768, outside -32767 … 32767", name,
                                (unsigned long long)e);
    return SSS_OK;
}

void sss_sec_shc_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_shcode *s = &f->sh;
    const uint64_t ntab = (uint64_t)f->channels * s->ncoef;
    put_u32(p, f->channels);
    put_u32(p + 4, s->order);
    put_u32(p + 8, s->ncoded);
    put_u32(p + 12, s->kind);
    p += SHC_HEADER;
    if (sss_shq_linear_max(s->kind))
        for (uint64_t i = 0; i < ntab; i++, p += 4) put_f32(p, s->scale[i]);
    else
        for (uint64_t i = 0; i < ntab * sss_shq_levels(s->kind); i++, p += 4) put_f32(p, s->table[i]);
    uint64_t nb = sss_shq_code_bytes(s->kind, (uint64_t)s->ncoded * ntab);
    if (nb) memcpy(p, s->code, (size_t)nb);
}

sss_result sss_sec_shc_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (size < SHC_HEADER)
        return sss_fail(err, CORRUPT, "%s: section SHC : size %llu is too small for its %u-byte header", name,
                        (unsigned long long)size, SHC_HEADER);
    sss_shcode *s = &f->sh;
    uint32_t ch = get_u32(p);
    if (ch != f->channels)
        return sss_fail(err, CORRUPT, "%s: section SHC : %u channels, but section MATL says %u", name, ch,
                        f->channels);
    s->order = get_u32(p + 4);
    s->ncoded = get_u32(p + 8);
    s->kind = get_u32(p + 12);
    if (f->quant != SSS_QUANT_REFS) f->quant = SSS_QUANT_SH;
    if (s->order > SSS_SH_FILE_MAX_ORDER)
        return sss_fail(err, CORRUPT, "%s: section SHC : SH order %u out of range 0 … %d", name, s->order,
                        SSS_SH_FILE_MAX_ORDER);
    s->ncoef = s->order * s->order;
    const uint32_t L = sss_shq_levels(s->kind);
    if (!L) return sss_fail(err, CORRUPT, "%s: section SHC : unknown quantisation kind %u", name, s->kind);
    if (s->ncoded != sss_sec_ncoded(f))
        return sss_fail(err, CORRUPT, "%s: section SHC : %u coded vertices, expected %llu", name, s->ncoded,
                        (unsigned long long)sss_sec_ncoded(f));
    uint64_t want = shc_size_of(ch, s->order, s->kind, s->ncoded);
    if (want == 0 || size != want)
        return sss_fail(err, CORRUPT, "%s: section SHC : size %llu does not match %u coded vertices x %u channels x "
                        "%u coefficients (%llu bytes)", name, (unsigned long long)size, s->ncoded, ch, s->ncoef,
                        (unsigned long long)want);
    if (count != s->ncoded)
        return sss_fail(err, CORRUPT, "%s: section SHC : count %llu does not match %u coded vertices", name,
                        (unsigned long long)count, s->ncoded);
    const uint64_t ntab = (uint64_t)ch * s->ncoef;
    const uint64_t nb = sss_shq_code_bytes(s->kind, (uint64_t)s->ncoded * ntab);
    s->table = malloc((size_t)(ntab * L + 1) * sizeof *s->table);
    s->code = malloc((size_t)nb + 1);
    const int linear = sss_shq_linear_max(s->kind) != 0;
    if (linear) s->scale = malloc((size_t)(ntab + 1) * sizeof *s->scale);
    if (!s->table || !s->code || (linear && !s->scale))
        return sss_sec_nomem(err, name, "SHC ", size);
    p += SHC_HEADER;
    if (linear) {
        for (uint64_t i = 0; i < ntab; i++, p += 4) s->scale[i] = get_f32(p);
    } else {
        for (uint64_t i = 0; i < ntab * L; i++, p += 4) s->table[i] = get_f32(p);
    }
    if (nb) memcpy(s->code, p, (size_t)nb);
    sss_result res = sss_sec_shc_check(f, name, CORRUPT, err);
    if (res != SSS_OK) return res;
    if (s->kind == SSS_SHQ_LINEAR8) sss_shq_linear8_table(s->scale, (uint32_t)ntab, s->table);
    if (s->kind == SSS_SHQ_LINEAR16) sss_shq_linear16_table(s->scale, (uint32_t)ntab, s->table);
    return SSS_OK;
}

void sss_sec_shc_free(sss_bake_file *f)
{
    free(f->sh.table);
    free(f->sh.scale);
    free(f->sh.code);
    free(f->sh.planes);
    memset(&f->sh, 0, sizeof f->sh);
}

int sss_sec_shc_wants(const sss_bake_file *f)
{
    return sss_sec_fx_uses_q(f->fx.mask) && (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS);
}

/* which q section a file holds is a cross-section rule (format.c, §5.9) */
sss_sec_need sss_sec_shc_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
