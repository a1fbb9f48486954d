/* envt.c: section ENVT (format 1.2), SH transfer for an environment
 * (docs/format.md §5.12): per vertex and channel T_i(x_v) = ∫ q(x_v, ω)
 * y_i(ω) dω in the sss/sh.h basis, and the scene's probe radiance in SH;
 * sss_fx_env (effects.c) evaluates Σ_i T_i L_i. */
#include <stdlib.h>

#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT

static uint32_t ncoef(uint32_t order) { return order * order; }

uint64_t sss_sec_envt_size(const sss_bake_file *f)
{
    uint64_t n, r;
    const uint32_t K = ncoef(f->fx.env_order);
    if (!mul_u64((uint64_t)f->mesh.nv * f->channels, K, &n)) return 0;
    return lin_u64(12, K, 4, n, 8, &r) ? r : 0;
}

uint64_t sss_sec_envt_count(const sss_bake_file *f) { return f->mesh.nv; }

sss_result sss_sec_envt_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_effects *x = &f->fx;
    if (x->env_order < 1 || x->env_order > 8 || !x->env_t)
        return sss_fail(err, code, "%s: section ENVT: SH order %u (1 ... 8 expected)", name, x->env_order);
    const uint64_t K = ncoef(x->env_order);
    sss_result r = sss_sec_check_floats(x->env_probe, 3 * K, 0, SSS_PROBE_SH_MAX, name, "ENVT", code, err);
    if (r == SSS_OK)
        r = sss_sec_check_floats(x->env_t, (uint64_t)f->mesh.nv * f->channels * K, 0, SSS_VALUE_MAX, name, "ENVT", code,
                                   err);
    return r;
}

void sss_sec_envt_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_effects *x = &f->fx;
    const uint32_t K = ncoef(x->env_order);
    put_u32(p, f->channels);
    put_u32(p + 4, x->env_order);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)K; k++, p += 4) put_f32(p, x->env_probe[k]);
    const size_t n = (size_t)f->mesh.nv * f->channels * K;
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, x->env_t[k]);
}

/* Values are checked once every section is read (CHECK_LAST, §5.10). */
sss_result sss_sec_envt_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t order = 0;
    sss_result r = sss_sec_fx_head(p, size, name, "ENVT", f, &order, err);
    if (r != SSS_OK) return r;
    if (order < 1 || order > 8)
        return sss_fail(err, CORRUPT, "%s: section ENVT: SH order %u (1 ... 8 expected)", name, order);
    f->fx.env_order = order;
    const uint64_t want = sss_sec_envt_size(f);
    if (!want || size != want) { f->fx.env_order = 0; return sss_sec_fx_size_mismatch(err, name, "ENVT", size, want); }
    if (count != f->mesh.nv)
        return sss_fail(err, CORRUPT, "%s: section ENVT: count %llu, expected %u vertices", name,
                        (unsigned long long)count, f->mesh.nv);
    const uint32_t K = ncoef(order);
    const size_t n = (size_t)f->mesh.nv * f->channels * K;
    f->fx.env_t = malloc(n * sizeof(float) + 1);
    if (!f->fx.env_t) return sss_fail(err, SSS_ERR_NOMEM, "%s: section ENVT: out of memory", name);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)K; k++, p += 4) f->fx.env_probe[k] = get_f32(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.env_t[k] = get_f32(p);
    return SSS_OK;
}

void sss_sec_envt_free(sss_bake_file *f)
{
    free(f->fx.env_t);
    f->fx.env_t = NULL;
    f->fx.env_order = 0;
}

int sss_sec_envt_wants(const sss_bake_file *f) { return (f->fx.mask & SSS_FX_ENV_SH) != 0; }

sss_sec_need sss_sec_envt_needs(const sss_bake_file *f)
{
    return f->fx.mask & SSS_FX_ENV_SH ? SSS_SEC_PRESENT : SSS_SEC_ABSENT;
}
