/* refs.c: section REFS (format 1.1), the reference part of the compressed
 * form of Hao–Varshney 2004 §4.2: a subset of the vertices (the references)
 * keeps its rows of integrals as Lloyd–Max indices; every other vertex (a
 * coded vertex) stores the reference triangle it projects onto and two
 * weights, and gets the rest of its row from section SHC (shc.c). Layout
 * and rules: docs/format.md §5.7.
 *
 * As everywhere in the reader the bytes are hostile: sizes are computed in
 * overflow-checked 64-bit arithmetic from counts and compared with the
 * section size before anything is allocated, and every index and value is
 * range-checked before the file is handed out.
 */
#include <stdlib.h>
#include <string.h>

#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT
#define REFS_HEADER 28u /* channels, nref, nrt, tri_bytes, wbits, w_lo, w_hi */
/* Stored weights must lie in [-W_BOUND, W_BOUND]: least-squares weights
 * (docs/compression.md) may leave [0, 1] but a blend of three rows with
 * huge weights would amplify their quantisation error without bound. */
#define W_BOUND 16.0f

uint32_t sss_refs_tri_bytes(uint32_t nrt)
{
    if (nrt <= (1u << 16)) return 2;
    if (nrt <= (1u << 24)) return 3;
    return 4;
}

/* 28 + 4·C·256 + 4·nref + 12·nrt + tb·ncoded + 2·(wbits/8)·ncoded + n·nref·C */
static uint64_t refs_size_of(uint32_t C, uint32_t nd, uint32_t nref, uint32_t nrt, uint32_t tb, uint32_t wbits,
                             uint64_t ncoded)
{
    uint64_t s = REFS_HEADER + 4ull * C * SSS_SEC_NLEVELS, x;
    if (!lin_u64(4, nref, 12, nrt, s, &s)) return 0;
    if (!lin_u64(tb, ncoded, 2ull * (wbits / 8), ncoded, s, &s)) return 0;
    if (!mul_u64((uint64_t)nd * nref, C, &x) || !add_u64(s, x, &s)) return 0;
    return s;
}

uint64_t sss_sec_refs_size(const sss_bake_file *f)
{
    return refs_size_of(f->channels, f->dirs.n, f->ref.nref, f->ref.nrt, f->ref.tri_bytes, f->ref.wbits,
                        sss_sec_ncoded(f));
}

uint64_t sss_sec_refs_count(const sss_bake_file *f) { return f->ref.nref; }

/* Every count, index and value of f->ref against f's mesh, channels and
 * directions. */
sss_result sss_sec_refs_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
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
        for (uint32_t x = 0; x < SSS_SEC_NLEVELS; x++) {
            float l = r->levels[c * SSS_SEC_NLEVELS + x];
            if (!(l >= 0.0f) || !isfinite(l))
                return sss_fail(err, code, "%s: section REFS: channel %u: level %u (%g) is not a finite number >= 0",
                                name, c, x, (double)l);
            if (!(l <= SSS_VALUE_MAX)) /* the bound a decode survives (sss/format.h) */
                return sss_fail(err, code, "%s: section REFS: channel %u: level %u (%g) is beyond %g", name, c, x,
                                (double)l, SSS_VALUE_MAX);
            if (x > 0 && l < r->levels[c * SSS_SEC_NLEVELS + x - 1])
                return sss_fail(err, code, "%s: section REFS: channel %u: level %u is below level %u", name, c, x,
                                x - 1);
        }
    return SSS_OK;
}

void sss_sec_refs_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_refcode *r = &f->ref;
    const uint64_t ncoded = sss_sec_ncoded(f), C = f->channels;
    put_u32(p, f->channels);
    put_u32(p + 4, r->nref);
    put_u32(p + 8, r->nrt);
    put_u32(p + 12, r->tri_bytes);
    put_u32(p + 16, r->wbits);
    put_f32(p + 20, r->w_lo);
    put_f32(p + 24, r->w_hi);
    p += REFS_HEADER;
    /* 4-byte arrays first so they stay aligned when the section is */
    for (uint64_t k = 0; k < C * SSS_SEC_NLEVELS; k++, p += 4) put_f32(p, r->levels[k]);
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

sss_result sss_sec_refs_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
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
    r->levels = malloc(C * SSS_SEC_NLEVELS * sizeof *r->levels);
    r->ref_vertex = malloc((size_t)r->nref * sizeof *r->ref_vertex);
    r->ref_tri = malloc((3 * (size_t)r->nrt + 1) * sizeof *r->ref_tri);
    r->vtri = malloc(((size_t)ncoded + 1) * sizeof *r->vtri);
    r->w = malloc((2 * (size_t)ncoded + 1) * sizeof *r->w);
    r->idx = malloc((size_t)nidx + 1);
    r->coded_vertex = malloc(((size_t)ncoded + 1) * sizeof *r->coded_vertex);
    if (!r->levels || !r->ref_vertex || !r->ref_tri || !r->vtri || !r->w || !r->idx || !r->coded_vertex)
        return sss_sec_nomem(err, name, "REFS", size);
    p += REFS_HEADER;
    for (uint64_t k = 0; k < C * SSS_SEC_NLEVELS; k++, p += 4) r->levels[k] = get_f32(p);
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
    sss_result res = sss_sec_refs_check(f, name, CORRUPT, err);
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

void sss_sec_refs_free(sss_bake_file *f)
{
    sss_refcode *r = &f->ref;
    free(r->ref_vertex);
    free(r->ref_tri);
    free(r->vtri);
    free(r->w);
    free(r->levels);
    free(r->idx);
    free(r->coded_vertex);
    free(r->blend);
    memset(r, 0, sizeof *r);
}

int sss_sec_refs_wants(const sss_bake_file *f)
{
    return sss_sec_fx_uses_q(f->fx.mask) && f->quant == SSS_QUANT_REFS;
}

/* REFS only with SHC is a cross-section rule (format.c, §5.9) */
sss_sec_need sss_sec_refs_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
