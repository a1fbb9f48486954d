/* format_compressed.c: sections REFS and SHC (format 1.1), the compressed
 * forms of Hao–Varshney 2004 §4: reference vertices that keep their rows
 * (§4.2), per-vertex reference triangles and weights, and SH coefficients of
 * q or of the delta left after blending (§4.1, §4.3). Layout and rules:
 * docs/format.md §5.7–5.8.
 *
 * As in format.c the decoder treats the bytes as hostile: sizes are computed
 * in overflow-checked 64-bit arithmetic from counts and compared with the
 * section size before anything is allocated, and every index and value is
 * range-checked before the file is handed out.
 */
#include "../format_compressed.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../format_bytes.h"

#define CORRUPT SSS_ERR_CORRUPT
#define REFS_HEADER 28u /* channels, nref, nrt, tri_bytes, wbits, w_lo, w_hi */
#define SHC_HEADER 16u  /* channels, order, ncoded, kind */
#define NLEVELS 256u
/* Stored weights must lie in [-W_BOUND, W_BOUND]: least-squares weights
 * (docs/compression.md) may leave [0, 1] but a blend of three rows with
 * huge weights would amplify their quantisation error without bound. */
#define W_BOUND 16.0f

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

const char *sss_shq_name(uint32_t kind)
{
    static const char *const n[] = {"linear8", "lloyd8", "lloyd4"};
    return kind < 3 ? n[kind] : "?";
}

uint32_t sss_shq_levels(uint32_t kind)
{
    switch (kind) {
    case SSS_SHQ_LINEAR8:
    case SSS_SHQ_LLOYD8: return 256;
    case SSS_SHQ_LLOYD4: return 16;
    default: return 0;
    }
}

uint64_t sss_shq_code_bytes(uint32_t kind, uint64_t n) { return kind == SSS_SHQ_LLOYD4 ? n / 2 + (n & 1) : n; }

uint32_t sss_refs_tri_bytes(uint32_t nrt)
{
    if (nrt <= (1u << 16)) return 2;
    if (nrt <= (1u << 24)) return 3;
    return 4;
}

void sss_shq_linear8_table(const float *scale, uint32_t n, float *table)
{
    for (uint32_t i = 0; i < n; i++)
        for (uint32_t b = 0; b < 256; b++) /* code byte b means the int8 (int8_t)b */
            table[(size_t)i * 256 + b] = (float)((double)(b < 128 ? (int)b : (int)b - 256) * scale[i] / 127.0);
}

static uint64_t ncoded_of(const sss_bake_file *f)
{
    return f->quant == SSS_QUANT_REFS ? (uint64_t)f->mesh.nv - f->ref.nref : f->mesh.nv;
}

/* 28 + 4·C·256 + 4·nref + 12·nrt + tb·ncoded + 2·(wbits/8)·ncoded + n·nref·C */
static uint64_t refs_size_of(uint32_t C, uint32_t nd, uint32_t nref, uint32_t nrt, uint32_t tb, uint32_t wbits,
                             uint64_t ncoded)
{
    uint64_t s = REFS_HEADER + 4ull * C * NLEVELS, x;
    if (!lin_u64(4, nref, 12, nrt, s, &s)) return 0;
    if (!lin_u64(tb, ncoded, 2ull * (wbits / 8), ncoded, s, &s)) return 0;
    if (!mul_u64((uint64_t)nd * nref, C, &x) || !add_u64(s, x, &s)) return 0;
    return s;
}

uint64_t sss_fmt_refs_size(const sss_bake_file *f)
{
    return refs_size_of(f->channels, f->dirs.n, f->ref.nref, f->ref.nrt, f->ref.tri_bytes, f->ref.wbits,
                        ncoded_of(f));
}

static uint64_t shc_size_of(uint32_t C, uint32_t order, uint32_t kind, uint64_t ncoded)
{
    const uint64_t ncoef = (uint64_t)order * order;
    const uint64_t per = kind == SSS_SHQ_LINEAR8 ? 1 : sss_shq_levels(kind);
    uint64_t n, s = SHC_HEADER + 4ull * C * ncoef * per;
    if (!mul_u64(ncoded, C * ncoef, &n) || !add_u64(s, sss_shq_code_bytes(kind, n), &s)) return 0;
    return s;
}

uint64_t sss_fmt_shc_size(const sss_bake_file *f)
{
    return shc_size_of(f->channels, f->sh.order, f->sh.kind, f->sh.ncoded);
}

/* ---- checks shared by writer and reader ------------------------------ */

sss_result sss_fmt_check_refs(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_refcode *r = &f->ref;
    const uint32_t nv = f->mesh.nv, C = f->channels;
    if (r->nref == 0 || r->nref > nv)
        return sss_fail(err, code, "%s: section REFS: %u reference vertices (1 … %u allowed)", name, r->nref, nv);
    const uint64_t ncoded = (uint64_t)nv - r->nref;
    if (ncoded > 0 && r->nrt == 0)
        return sss_fail(err, code, "%s: section REFS: %llu vertices need a reference triangle, but there are none",
                        name, (unsigned long long)ncoded);
    if (r->tri_bytes != sss_refs_tri_bytes(r->nrt))
        return sss_fail(err, code, "%s: section REFS: %u bytes per triangle index, expected %u for %u triangles",
                        name, r->tri_bytes, sss_refs_tri_bytes(r->nrt), r->nrt);
    if (r->wbits != 8 && r->wbits != 16)
        return sss_fail(err, code, "%s: section REFS: %u bits per weight (8 or 16 allowed)", name, r->wbits);
    if (!(r->w_lo >= -W_BOUND && r->w_hi <= W_BOUND && r->w_lo < r->w_hi))
        return sss_fail(err, code, "%s: section REFS: weight range [%g, %g] is not an interval inside [-%g, %g]",
                        name, (double)r->w_lo, (double)r->w_hi, (double)W_BOUND, (double)W_BOUND);
    if (!r->ref_vertex || (r->nrt && !r->ref_tri) || (ncoded && (!r->vtri || !r->w)) || !r->levels || !r->idx)
        return sss_fail(err, code, "%s: section REFS: arrays missing", name);
    for (uint32_t k = 0; k < r->nref; k++) {
        if (r->ref_vertex[k] >= nv)
            return sss_fail(err, code, "%s: section REFS: reference %u: vertex %u out of range (%u vertices)", name,
                            k, r->ref_vertex[k], nv);
        if (k > 0 && r->ref_vertex[k] <= r->ref_vertex[k - 1])
            return sss_fail(err, code, "%s: section REFS: reference %u: vertex %u does not follow %u (must increase)",
                            name, k, r->ref_vertex[k], r->ref_vertex[k - 1]);
    }
    for (uint64_t t = 0; t < 3ull * r->nrt; t++)
        if (r->ref_tri[t] >= r->nref)
            return sss_fail(err, code, "%s: section REFS: reference triangle %llu: index %u out of range (%u "
                            "references)", name, (unsigned long long)(t / 3), r->ref_tri[t], r->nref);
    const uint32_t wmax = r->wbits == 16 ? 65535u : 255u;
    for (uint64_t k = 0; k < ncoded; k++) {
        if (r->vtri[k] >= r->nrt)
            return sss_fail(err, code, "%s: section REFS: coded vertex %llu: triangle %u out of range (%u "
                            "triangles)", name, (unsigned long long)k, r->vtri[k], r->nrt);
        if (r->w[2 * k] > wmax || r->w[2 * k + 1] > wmax)
            return sss_fail(err, code, "%s: section REFS: coded vertex %llu: weight code above %u", name,
                            (unsigned long long)k, wmax);
    }
    for (uint32_t c = 0; c < C; c++)
        for (uint32_t x = 0; x < NLEVELS; x++) {
            float l = r->levels[c * NLEVELS + x];
            if (!(l >= 0.0f) || !isfinite(l))
                return sss_fail(err, code, "%s: section REFS: channel %u: level %u (%g) is not a finite number >= 0",
                                name, c, x, (double)l);
            if (x > 0 && l < r->levels[c * NLEVELS + x - 1])
                return sss_fail(err, code, "%s: section REFS: channel %u: level %u is below level %u", name, c, x,
                                x - 1);
        }
    return SSS_OK;
}

sss_result sss_fmt_check_shc(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
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
    if (s->ncoded != ncoded_of(f))
        return sss_fail(err, code, "%s: section SHC : %u coded vertices, expected %llu", name, s->ncoded,
                        (unsigned long long)ncoded_of(f));
    const uint64_t ntab = (uint64_t)C * s->ncoef;
    const uint64_t ncodes = (uint64_t)s->ncoded * ntab;
    if ((ntab && !s->table) || (s->kind == SSS_SHQ_LINEAR8 && ntab && !s->scale) || (ncodes && !s->code))
        return sss_fail(err, code, "%s: section SHC : arrays missing", name);
    if (s->kind == SSS_SHQ_LINEAR8) {
        for (uint64_t i = 0; i < ntab; i++)
            if (!(s->scale[i] >= 0.0f) || !isfinite(s->scale[i]))
                return sss_fail(err, code, "%s: section SHC : scale %llu (%g) is not a finite number >= 0", name,
                                (unsigned long long)i, (double)s->scale[i]);
    } else {
        for (uint64_t i = 0; i < ntab * L; i++)
            if (!isfinite(s->table[i]))
                return sss_fail(err, code, "%s: section SHC : table entry %llu is not finite", name,
                                (unsigned long long)i);
    }
    /* An odd count of 4-bit codes leaves the last byte's high nibble unused:
     * it must be 0, so that one content has one encoding. */
    if (s->kind == SSS_SHQ_LLOYD4 && (ncodes & 1) && (s->code[ncodes / 2] >> 4) != 0)
        return sss_fail(err, code, "%s: section SHC : unused high nibble of the last code byte is not 0", name);
    return SSS_OK;
}

/* ---- writer ------------------------------------------------------------ */

void sss_fmt_pack_refs(const sss_bake_file *f, uint8_t *p)
{
    const sss_refcode *r = &f->ref;
    const uint64_t ncoded = ncoded_of(f), C = f->channels;
    put_u32(p, f->channels);
    put_u32(p + 4, r->nref);
    put_u32(p + 8, r->nrt);
    put_u32(p + 12, r->tri_bytes);
    put_u32(p + 16, r->wbits);
    put_f32(p + 20, r->w_lo);
    put_f32(p + 24, r->w_hi);
    p += REFS_HEADER;
    /* 4-byte arrays first so they stay aligned when the section is */
    for (uint64_t k = 0; k < C * NLEVELS; k++, p += 4) put_f32(p, r->levels[k]);
    for (uint32_t k = 0; k < r->nref; k++, p += 4) put_u32(p, r->ref_vertex[k]);
    for (uint64_t k = 0; k < 3ull * r->nrt; k++, p += 4) put_u32(p, r->ref_tri[k]);
    for (uint64_t k = 0; k < ncoded; k++)
        for (uint32_t b = 0; b < r->tri_bytes; b++) *p++ = (uint8_t)(r->vtri[k] >> (8 * b));
    for (uint64_t k = 0; k < 2 * ncoded; k++) {
        if (r->wbits == 16) {
            put_u16(p, r->w[k]);
            p += 2;
        } else {
            *p++ = (uint8_t)r->w[k];
        }
    }
    const uint64_t nidx = (uint64_t)f->dirs.n * r->nref * C;
    if (nidx) memcpy(p, r->idx, (size_t)nidx);
}

void sss_fmt_pack_shc(const sss_bake_file *f, uint8_t *p)
{
    const sss_shcode *s = &f->sh;
    const uint64_t ntab = (uint64_t)f->channels * s->ncoef;
    put_u32(p, f->channels);
    put_u32(p + 4, s->order);
    put_u32(p + 8, s->ncoded);
    put_u32(p + 12, s->kind);
    p += SHC_HEADER;
    if (s->kind == SSS_SHQ_LINEAR8)
        for (uint64_t i = 0; i < ntab; i++, p += 4) put_f32(p, s->scale[i]);
    else
        for (uint64_t i = 0; i < ntab * sss_shq_levels(s->kind); i++, p += 4) put_f32(p, s->table[i]);
    uint64_t nb = sss_shq_code_bytes(s->kind, (uint64_t)s->ncoded * ntab);
    if (nb) memcpy(p, s->code, (size_t)nb);
}

/* ---- reader ------------------------------------------------------------ */

static sss_result nomem(sss_error *err, const char *name, const char *sec, uint64_t bytes)
{
    return sss_fail(err, SSS_ERR_NOMEM, "%s: section %s: out of memory for %llu bytes", name, sec,
                    (unsigned long long)bytes);
}

sss_result sss_fmt_parse_refs(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size < REFS_HEADER)
        return sss_fail(err, CORRUPT, "%s: section REFS: size %llu is too small for its %u-byte header", name,
                        (unsigned long long)size, REFS_HEADER);
    sss_refcode *r = &f->ref;
    uint32_t ch = get_u32(p);
    if (ch != f->channels)
        return sss_fail(err, CORRUPT, "%s: section REFS: %u channels, but section MATL says %u", name, ch,
                        f->channels);
    r->nref = get_u32(p + 4);
    r->nrt = get_u32(p + 8);
    r->tri_bytes = get_u32(p + 12);
    r->wbits = get_u32(p + 16);
    r->w_lo = get_f32(p + 20);
    r->w_hi = get_f32(p + 24);
    const uint32_t nv = f->mesh.nv;
    if (r->nref == 0 || r->nref > nv)
        return sss_fail(err, CORRUPT, "%s: section REFS: %u reference vertices (1 … %u allowed)", name, r->nref, nv);
    if (r->tri_bytes != sss_refs_tri_bytes(r->nrt))
        return sss_fail(err, CORRUPT, "%s: section REFS: %u bytes per triangle index, expected %u for %u triangles",
                        name, r->tri_bytes, sss_refs_tri_bytes(r->nrt), r->nrt);
    if (r->wbits != 8 && r->wbits != 16)
        return sss_fail(err, CORRUPT, "%s: section REFS: %u bits per weight (8 or 16 allowed)", name, r->wbits);
    const uint64_t ncoded = (uint64_t)nv - r->nref, C = ch;
    uint64_t want = refs_size_of(ch, f->dirs.n, r->nref, r->nrt, r->tri_bytes, r->wbits, ncoded);
    if (want == 0 || size != want)
        return sss_fail(err, CORRUPT, "%s: section REFS: size %llu does not match %u references, %u triangles, "
                        "%llu coded vertices and %u directions (%llu bytes)", name, (unsigned long long)size,
                        r->nref, r->nrt, (unsigned long long)ncoded, f->dirs.n, (unsigned long long)want);
    if (count != r->nref)
        return sss_fail(err, CORRUPT, "%s: section REFS: count %llu does not match %u references", name,
                        (unsigned long long)count, r->nref);
    /* sizes agree with bytes that exist: these allocations are bounded by
     * the file size */
    const uint64_t nidx = (uint64_t)f->dirs.n * r->nref * C;
    r->levels = malloc(C * NLEVELS * sizeof *r->levels);
    r->ref_vertex = malloc((size_t)r->nref * sizeof *r->ref_vertex);
    r->ref_tri = malloc((3 * (size_t)r->nrt + 1) * sizeof *r->ref_tri);
    r->vtri = malloc(((size_t)ncoded + 1) * sizeof *r->vtri);
    r->w = malloc((2 * (size_t)ncoded + 1) * sizeof *r->w);
    r->idx = malloc((size_t)nidx + 1);
    r->coded_vertex = malloc(((size_t)ncoded + 1) * sizeof *r->coded_vertex);
    if (!r->levels || !r->ref_vertex || !r->ref_tri || !r->vtri || !r->w || !r->idx || !r->coded_vertex)
        return nomem(err, name, "REFS", size);
    p += REFS_HEADER;
    for (uint64_t k = 0; k < C * NLEVELS; k++, p += 4) r->levels[k] = get_f32(p);
    for (uint32_t k = 0; k < r->nref; k++, p += 4) r->ref_vertex[k] = get_u32(p);
    for (uint64_t k = 0; k < 3ull * r->nrt; k++, p += 4) r->ref_tri[k] = get_u32(p);
    for (uint64_t k = 0; k < ncoded; k++) {
        uint32_t t = 0;
        for (uint32_t b = 0; b < r->tri_bytes; b++) t |= (uint32_t)*p++ << (8 * b);
        r->vtri[k] = t;
    }
    for (uint64_t k = 0; k < 2 * ncoded; k++) {
        if (r->wbits == 16) {
            r->w[k] = get_u16(p);
            p += 2;
        } else {
            r->w[k] = *p++;
        }
    }
    if (nidx) memcpy(r->idx, p, (size_t)nidx);
    f->quant = SSS_QUANT_REFS;
    sss_result res = sss_fmt_check_refs(f, name, CORRUPT, err);
    if (res != SSS_OK) return res;
    /* coded vertices: the complement of the (increasing) reference list */
    uint64_t k = 0;
    uint32_t q = 0;
    for (uint32_t v = 0; v < nv; v++) {
        if (q < r->nref && r->ref_vertex[q] == v) q++;
        else r->coded_vertex[k++] = v;
    }
    return SSS_OK;
}

sss_result sss_fmt_parse_shc(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
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
    if (s->ncoded != ncoded_of(f))
        return sss_fail(err, CORRUPT, "%s: section SHC : %u coded vertices, expected %llu", name, s->ncoded,
                        (unsigned long long)ncoded_of(f));
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
    if (s->kind == SSS_SHQ_LINEAR8) s->scale = malloc((size_t)(ntab + 1) * sizeof *s->scale);
    if (!s->table || !s->code || (s->kind == SSS_SHQ_LINEAR8 && !s->scale)) return nomem(err, name, "SHC ", size);
    p += SHC_HEADER;
    if (s->kind == SSS_SHQ_LINEAR8) {
        for (uint64_t i = 0; i < ntab; i++, p += 4) s->scale[i] = get_f32(p);
    } else {
        for (uint64_t i = 0; i < ntab * L; i++, p += 4) s->table[i] = get_f32(p);
    }
    if (nb) memcpy(s->code, p, (size_t)nb);
    sss_result res = sss_fmt_check_shc(f, name, CORRUPT, err);
    if (res != SSS_OK) return res;
    if (s->kind == SSS_SHQ_LINEAR8) sss_shq_linear8_table(s->scale, (uint32_t)ntab, s->table);
    return SSS_OK;
}

void sss_fmt_free_compressed(sss_bake_file *f)
{
    sss_refcode *r = &f->ref;
    free(r->ref_vertex);
    free(r->ref_tri);
    free(r->vtri);
    free(r->w);
    free(r->levels);
    free(r->idx);
    free(r->coded_vertex);
    memset(r, 0, sizeof *r);
    free(f->sh.table);
    free(f->sh.scale);
    free(f->sh.code);
    memset(&f->sh, 0, sizeof f->sh);
}
