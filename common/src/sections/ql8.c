/* ql8.c: section QL8, the integrals as 8-bit indices into a 256-level
 * Lloyd–Max table per channel (docs/format.md §5.5), in QFLT's layout. */
#include <stdlib.h>
#include <string.h>

#include "sections.h"

uint64_t sss_sec_ql8_size(const sss_bake_file *f)
{
    uint64_t nq, size;
    return sss_sec_q_count(f, &nq) && lin_u64(f->channels, 4 * SSS_SEC_NLEVELS, 1, nq, 4, &size) ? size : 0;
}

uint64_t sss_sec_ql8_count(const sss_bake_file *f)
{
    uint64_t nq;
    return sss_sec_q_count(f, &nq) ? nq : 0;
}

sss_result sss_sec_ql8_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!f->levels || !f->qidx) return sss_fail(err, code, "%s: section QL8 : levels or indices missing", name);
    uint64_t nq = 0;
    sss_result r = sss_sec_q_count_checked(f, name, &nq, err);
    if (r != SSS_OK) return r;
    const float *levels = f->levels;
    for (uint32_t c = 0; c < f->channels; c++)
        for (uint32_t k = 0; k < SSS_SEC_NLEVELS; k++) {
            float x = levels[c * SSS_SEC_NLEVELS + k];
            if (!(x >= 0.0f) || !isfinite(x))
                return sss_fail(err, code, "%s: section QL8 : channel %u: level %u (%g) is not a finite number >= 0",
                                name, c, k, (double)x);
            if (!(x <= SSS_VALUE_MAX)) /* the bound a decode survives (sss/format.h) */
                return sss_fail(err, code, "%s: section QL8 : channel %u: level %u (%g) is beyond %g", name, c, k,
                                (double)x, SSS_VALUE_MAX);
            if (k > 0 && x < levels[c * SSS_SEC_NLEVELS + k - 1])
                return sss_fail(err, code, "%s: section QL8 : channel %u: level %u (%g) is below level %u (%g)",
                                name, c, k, (double)x, k - 1, (double)levels[c * SSS_SEC_NLEVELS + k - 1]);
        }
    return SSS_OK;
}

void sss_sec_ql8_pack(const sss_bake_file *f, uint8_t *p)
{
    const size_t nq = (size_t)sss_sec_ql8_count(f);
    put_u32(p, f->channels);
    p += 4;
    for (size_t k = 0; k < (size_t)f->channels * SSS_SEC_NLEVELS; k++, p += 4) put_f32(p, f->levels[k]);
    if (nq) memcpy(p, f->qidx, nq);
}

sss_result sss_sec_ql8_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                             sss_error *err)
{
    if (size < 4)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QL8 : size %llu is too small for the channel count", name,
                        (unsigned long long)size);
    uint32_t ch = get_u32(p);
    if (ch != f->channels)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QL8 : %u channels, but section MATL says %u", name, ch,
                        f->channels);
    uint64_t nq, want;
    if (!sss_sec_q_count(f, &nq) || !lin_u64(ch, 4 * SSS_SEC_NLEVELS, 1, nq, 4, &want) || size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QL8 : size %llu does not match %u channels x 256 levels "
                        "and %u directions x %u vertices x %u channels of indices", name, (unsigned long long)size,
                        ch, f->dirs.n, f->mesh.nv, ch);
    if (count != nq) return sss_sec_count_mismatch(err, name, "QL8 ", count, nq, "indices");
    f->levels = malloc((size_t)ch * SSS_SEC_NLEVELS * sizeof(float));
    f->qidx = malloc((size_t)nq + 1);
    if (!f->levels || !f->qidx) return sss_sec_nomem(err, name, "QL8 ", size);
    p += 4;
    for (size_t k = 0; k < (size_t)ch * SSS_SEC_NLEVELS; k++, p += 4) f->levels[k] = get_f32(p);
    if (nq) memcpy(f->qidx, p, (size_t)nq);
    f->quant = SSS_QUANT_LLOYD8;
    return sss_sec_ql8_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_ql8_free(sss_bake_file *f)
{
    free(f->levels);
    free(f->qidx);
    f->levels = NULL;
    f->qidx = NULL;
}

int sss_sec_ql8_wants(const sss_bake_file *f)
{
    return sss_sec_fx_uses_q(f->fx.mask) && f->quant == SSS_QUANT_LLOYD8;
}

/* which q section a file holds is a cross-section rule (format.c, §5.9) */
sss_sec_need sss_sec_ql8_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
