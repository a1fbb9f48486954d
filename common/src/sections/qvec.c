/* qvec.c: section QVEC (format 1.7), the vector integrals Q(x_v, ω_j) of
 * Hao–Varshney 2004 §3.1 as float32 (docs/format.md §5.19): per direction
 * sample, vertex and channel the three components of
 *   Q = Σ_i F_t(η, n_i·ω_j) (R_d/π) μ_i V(x_i, ω_j) n_i ΔA(x_i),
 * which a reader interpolates between samples and dots with the actual
 * light direction (§3.2). Laid out as QFLT's rows (direction-major) with
 * the three components of each value together, so that one direction's
 * row is contiguous and a GPU binds three rows as it binds q's. Next to
 * the q rows (QFLT or QL8) of a plain bake. */
#include <stdlib.h>

#include "sections.h"

/* 3 · n · nv · channels values; 0 on overflow */
static int qvec_count(const sss_bake_file *f, uint64_t *n)
{
    uint64_t nq;
    return sss_sec_q_count(f, &nq) && mul_u64(nq, 3, n);
}

uint64_t sss_sec_qvec_size(const sss_bake_file *f)
{
    uint64_t n, size;
    return qvec_count(f, &n) && mul_u64(n, 4, &size) ? size : 0;
}

uint64_t sss_sec_qvec_count(const sss_bake_file *f)
{
    uint64_t n;
    return qvec_count(f, &n) ? n : 0;
}

sss_result sss_sec_qvec_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!f->qvec) return sss_fail(err, code, "%s: section QVEC: values missing", name);
    /* Q sits next to rows a reader interpolates the same way (§5.19): the
     * compressed forms have no rows per direction sample to pair it with */
    if (f->fx.mask || (f->quant != SSS_QUANT_FLOAT && f->quant != SSS_QUANT_LLOYD8))
        return sss_fail(err, code, "%s: section QVEC: only in a plain bake with q as float or lloyd8 (this file: "
                        "%s%s)", name, sss_quant_name(f->quant), f->fx.mask ? ", a scene bake" : "");
    uint64_t n;
    if (!qvec_count(f, &n))
        return sss_fail(err, SSS_ERR_NOMEM, "%s: section QVEC: 3 x %u directions x %u vertices x %u channels "
                        "overflows", name, f->dirs.n, f->mesh.nv, f->channels);
    /* components take either sign (n_i does); bounded as q is (sss/format.h) */
    return sss_sec_check_floats(f->qvec, n, 0, SSS_VALUE_MAX, name, "QVEC", code, err);
}

void sss_sec_qvec_pack(const sss_bake_file *f, uint8_t *p)
{
    const size_t n = (size_t)sss_sec_qvec_count(f);
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, f->qvec[k]);
}

sss_result sss_sec_qvec_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint64_t n, want;
    if (!qvec_count(f, &n) || !mul_u64(n, 4, &want) || size != want)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QVEC: size %llu does not match 3 x %u directions x %u "
                        "vertices x %u channels of float32", name, (unsigned long long)size, f->dirs.n, f->mesh.nv,
                        f->channels);
    if (count != n) return sss_sec_count_mismatch(err, name, "QVEC", count, n, "values");
    f->qvec = malloc((size_t)size + 1);
    if (!f->qvec) return sss_sec_nomem(err, name, "QVEC", size);
    for (size_t k = 0; k < (size_t)n; k++, p += 4) f->qvec[k] = get_f32(p);
    return sss_sec_qvec_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_qvec_free(sss_bake_file *f)
{
    free(f->qvec);
    f->qvec = NULL;
}

int sss_sec_qvec_wants(const sss_bake_file *f) { return f->qvec != NULL; }

/* a plain bake's only: a scene bake's direction set keeps q alone */
sss_sec_need sss_sec_qvec_needs(const sss_bake_file *f) { return f->fx.mask ? SSS_SEC_ABSENT : SSS_SEC_EITHER; }
