/* pshl.c: section PSHL (format 1.2), point-light shells (docs/format.md
 * §5.13): for a near point light, the point-light integral at centre +
 * r_s ω_j for every direction ω_j of DIRS and distance shell r_s, stored
 * as r_s² · q_pt so that shells interpolate linearly (the extension of
 * Hao–Varshney 2004 §3.3); sss_fx_point (effects.c) interpolates it. */
#include <stdlib.h>

#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT

uint64_t sss_sec_pshl_size(const sss_bake_file *f)
{
    uint64_t n, r;
    if (!mul_u64((uint64_t)f->fx.nshells * f->dirs.n, f->mesh.nv, &n) || !mul_u64(n, f->channels, &n)) return 0;
    return lin_u64(8, f->fx.nshells, 4, n, 32, &r) ? r : 0;
}

uint64_t sss_sec_pshl_count(const sss_bake_file *f) { return f->fx.nshells; }

sss_result sss_sec_pshl_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_effects *x = &f->fx;
    if (x->nshells < 2 || x->nshells > 64 || !x->shell_radius || !x->shell_q)
        return sss_fail(err, code, "%s: section PSHL: %u distance shells (2 ... 64 expected)", name, x->nshells);
    for (int k = 0; k < 3; k++)
        if (!(fabs(x->shell_centre[k]) <= SSS_COORD_MAX))
            return sss_fail(err, code, "%s: section PSHL: centre is not finite or beyond %g", name, SSS_COORD_MAX);
    /* radii within the geometry's range (sss/mesh.h): the decoder divides by
     * at least the first one squared (sss_fx_point) */
    for (uint32_t s = 0; s < x->nshells; s++)
        if (!(x->shell_radius[s] <= 2.0 * SSS_COORD_MAX) || !(x->shell_radius[s] >= SSS_SHELL_RADIUS_MIN) ||
            !(x->shell_radius[s] > (s ? x->shell_radius[s - 1] : 0.0)))
            return sss_fail(err, code, "%s: section PSHL: radius %u (%g) is not in [%g, %g] and larger "
                            "than the previous one", name, s, x->shell_radius[s], SSS_SHELL_RADIUS_MIN,
                            2.0 * SSS_COORD_MAX);
    if (f->dirs.n < 4)
        return sss_fail(err, code, "%s: section PSHL: needs a triangulated direction set (%u directions)", name,
                        f->dirs.n);
    return sss_sec_check_floats(x->shell_q, (uint64_t)f->mesh.nv * f->channels * f->dirs.n * x->nshells, 1,
                                SSS_VALUE_MAX, name, "PSHL", code, err);
}

void sss_sec_pshl_pack(const sss_bake_file *f, uint8_t *p)
{
    const sss_effects *x = &f->fx;
    put_u32(p, f->channels);
    put_u32(p + 4, x->nshells);
    p += 8;
    for (int k = 0; k < 3; k++, p += 8) put_f64(p, x->shell_centre[k]);
    for (size_t k = 0; k < x->nshells; k++, p += 8) put_f64(p, x->shell_radius[k]);
    const size_t n = (size_t)x->nshells * f->dirs.n * f->mesh.nv * f->channels;
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, x->shell_q[k]);
}

/* Values are checked once every section is read (CHECK_LAST, §5.10). */
sss_result sss_sec_pshl_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t ns = 0;
    sss_result r = sss_sec_fx_head(p, size, name, "PSHL", f, &ns, err);
    if (r != SSS_OK) return r;
    if (ns < 2 || ns > 64) return sss_fail(err, CORRUPT, "%s: section PSHL: %u shells (2 ... 64 expected)", name, ns);
    f->fx.nshells = ns;
    const uint64_t want = sss_sec_pshl_size(f);
    if (!want || size != want) { f->fx.nshells = 0; return sss_sec_fx_size_mismatch(err, name, "PSHL", size, want); }
    if (count != ns)
        return sss_fail(err, CORRUPT, "%s: section PSHL: count %llu, expected %u", name, (unsigned long long)count, ns);
    const size_t n = (size_t)ns * f->dirs.n * f->mesh.nv * f->channels;
    f->fx.shell_radius = malloc(ns * sizeof(double));
    f->fx.shell_q = malloc(n * sizeof(float) + 1);
    if (!f->fx.shell_radius || !f->fx.shell_q)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: section PSHL: out of memory", name);
    p += 8;
    for (int k = 0; k < 3; k++, p += 8) f->fx.shell_centre[k] = get_f64(p);
    for (size_t k = 0; k < ns; k++, p += 8) f->fx.shell_radius[k] = get_f64(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.shell_q[k] = get_f32(p);
    return SSS_OK;
}

void sss_sec_pshl_free(sss_bake_file *f)
{
    free(f->fx.shell_radius);
    free(f->fx.shell_q);
    f->fx.shell_radius = NULL;
    f->fx.shell_q = NULL;
    f->fx.nshells = 0;
}

int sss_sec_pshl_wants(const sss_bake_file *f) { return (f->fx.mask & SSS_FX_POINT_SHELLS) != 0; }

sss_sec_need sss_sec_pshl_needs(const sss_bake_file *f)
{
    return f->fx.mask & SSS_FX_POINT_SHELLS ? SSS_SEC_PRESENT : SSS_SEC_ABSENT;
}
