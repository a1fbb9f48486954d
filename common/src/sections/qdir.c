/* qdir.c: section QDIR (format 1.2), exact values for static directional
 * lights (docs/format.md §5.11): per light direction ω_l the integral
 * q(x_v, ω_l) of Hao–Varshney 2004 §3.1 baked for exactly that direction,
 * with the normalisation of §5.4 and no interpolation. */
#include <stdlib.h>

#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT

uint64_t sss_sec_qdir_size(const sss_bake_file *f)
{
    uint64_t n, r;
    if (!mul_u64((uint64_t)f->fx.nexact * f->mesh.nv, f->channels, &n)) return 0;
    return lin_u64(24, f->fx.nexact, 4, n, 8, &r) ? r : 0;
}

uint64_t sss_sec_qdir_count(const sss_bake_file *f) { return f->fx.nexact; }

sss_result sss_sec_qdir_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_effects *x = &f->fx;
    if (x->nexact < 1 || x->nexact > 1024 || !x->exact_dir || !x->exact_q)
        return sss_fail(err, code, "%s: section QDIR: %u static directions (1 ... 1024 expected)", name, x->nexact);
    for (uint32_t l = 0; l < x->nexact; l++) {
        const double *d = &x->exact_dir[3 * (size_t)l];
        const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (!isfinite(len) || fabs(len - 1.0) > 1e-6)
            return sss_fail(err, code, "%s: section QDIR: direction %u is not a unit vector", name, l);
    }
    return sss_sec_check_floats(x->exact_q, (uint64_t)f->mesh.nv * f->channels * x->nexact, 1, SSS_VALUE_MAX, name,
                                "QDIR", code, err);
}

void sss_sec_qdir_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_effects *x = &f->fx;
    put_u32(p, f->channels);
    put_u32(p + 4, x->nexact);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)x->nexact; k++, p += 8) put_f64(p, x->exact_dir[k]);
    const size_t n = (size_t)x->nexact * f->mesh.nv * f->channels;
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, x->exact_q[k]);
}

/* Values are checked once every section is read (CHECK_LAST, §5.10). */
sss_result sss_sec_qdir_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t nl = 0;
    sss_result r = sss_sec_fx_head(p, size, name, "QDIR", f, &nl, err);
    if (r != SSS_OK) return r;
    if (nl < 1 || nl > 1024)
        return sss_fail(err, CORRUPT, "%s: section QDIR: %u directions (1 ... 1024 expected)", name, nl);
    f->fx.nexact = nl;
    const uint64_t want = sss_sec_qdir_size(f);
    if (!want || size != want) { f->fx.nexact = 0; return sss_sec_fx_size_mismatch(err, name, "QDIR", size, want); }
    if (count != nl)
        return sss_fail(err, CORRUPT, "%s: section QDIR: count %llu, expected %u", name, (unsigned long long)count, nl);
    const size_t n = (size_t)nl * f->mesh.nv * f->channels;
    f->fx.exact_dir = malloc(3 * (size_t)nl * sizeof(double));
    f->fx.exact_q = malloc(n * sizeof(float) + 1);
    if (!f->fx.exact_dir || !f->fx.exact_q)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: section QDIR: out of memory", name);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)nl; k++, p += 8) f->fx.exact_dir[k] = get_f64(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.exact_q[k] = get_f32(p);
    return SSS_OK;
}

void sss_sec_qdir_free(sss_bake_file *f)
{
    free(f->fx.exact_dir);
    free(f->fx.exact_q);
    f->fx.exact_dir = NULL;
    f->fx.exact_q = NULL;
    f->fx.nexact = 0;
}

int sss_sec_qdir_wants(const sss_bake_file *f) { return (f->fx.mask & SSS_FX_DIR_EXACT) != 0; }

sss_sec_need sss_sec_qdir_needs(const sss_bake_file *f)
{
    return f->fx.mask & SSS_FX_DIR_EXACT ? SSS_SEC_PRESENT : SSS_SEC_ABSENT;
}
