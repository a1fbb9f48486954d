/* qflt.c: section QFLT, the integrals q(x_v, ω_j) as float32 (docs/format.md
 * §5.4; Hao–Varshney 2004 §3.1), direction-major so that one light
 * direction's values are contiguous for the per-frame interpolation. */
#include <stdlib.h>

#include "sections.h"

uint64_t sss_sec_qflt_size(const sss_bake_file *f)
{
    uint64_t nq, size;
    return sss_sec_q_count(f, &nq) && mul_u64(nq, 4, &size) ? size : 0;
}

uint64_t sss_sec_qflt_count(const sss_bake_file *f)
{
    uint64_t nq;
    return sss_sec_q_count(f, &nq) ? nq : 0;
}

sss_result sss_sec_qflt_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!f->q) return sss_fail(err, code, "%s: section QFLT: values missing", name);
    uint64_t nq = 0;
    sss_result r = sss_sec_q_count_checked(f, name, &nq, err);
    if (r != SSS_OK) return r;
    for (uint64_t i = 0; i < nq; i++)
        if (!(f->q[i] >= 0.0f) || !isfinite(f->q[i]))
            return sss_fail(err, code, "%s: section QFLT: value %llu (%g) is not a finite number >= 0", name,
                            (unsigned long long)i, (double)f->q[i]);
        else if (!(f->q[i] <= SSS_VALUE_MAX)) /* the bound a decode survives (sss/format.h) */
            return sss_fail(err, code, "%s: section QFLT: value %llu (%g) is beyond %g", name, (unsigned long long)i,
                            (double)f->q[i], SSS_VALUE_MAX);
    return SSS_OK;
}

void sss_sec_qflt_pack(const sss_bake_file *f, uint8_t *p)
{
    const size_t nq = (size_t)sss_sec_qflt_count(f);
    for (size_t k = 0; k < nq; k++, p += 4) put_f32(p, f->q[k]);
}

sss_result sss_sec_qflt_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint64_t nq, want;
    if (!sss_sec_q_count(f, &nq) || !mul_u64(nq, 4, &want) || size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QFLT: size %llu does not match %u directions x %u "
                        "vertices x %u channels of float32", name, (unsigned long long)size, f->dirs.n, f->mesh.nv,
                        f->channels);
    if (count != nq) return sss_sec_count_mismatch(err, name, "QFLT", count, nq, "values");
    f->q = malloc((size_t)size + 1);
    if (!f->q) return sss_sec_nomem(err, name, "QFLT", size);
    for (size_t k = 0; k < (size_t)nq; k++, p += 4) f->q[k] = get_f32(p);
    f->quant = SSS_QUANT_FLOAT;
    return sss_sec_qflt_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_qflt_free(sss_bake_file *f)
{
    free(f->q);
    f->q = NULL;
}

int sss_sec_qflt_wants(const sss_bake_file *f)
{
    return sss_sec_fx_uses_q(f->fx.mask) && f->quant == SSS_QUANT_FLOAT;
}

/* which q section a file holds is a cross-section rule (format.c, §5.9) */
sss_sec_need sss_sec_qflt_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
