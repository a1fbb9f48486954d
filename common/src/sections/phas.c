/* phas.c: section PHAS (format 1.8), the material's phase function
 * (docs/format.md §5.20): f64 g, the Henyey–Greenstein mean cosine of the
 * material of MATL. MATL's σ′s = σs (1 − g) is all the dipole needs, so a
 * reader that does not know PHAS shows the multiple scattering exactly as
 * before: the section is optional, and written only when g ≠ 0, so that
 * every file of an isotropic material keeps its bytes and its minor. A
 * file without it has g = 0 (the presets', every older file's). */
#include "sections.h"

#define PHAS_SIZE 8u

uint64_t sss_sec_phas_size(const sss_bake_file *f)
{
    (void)f;
    return PHAS_SIZE;
}

uint64_t sss_sec_phas_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_phas_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!(fabs(f->material.g) <= SSS_G_MAX))
        return sss_fail(err, code, "%s: section PHAS: g %g is outside [%g, %g]", name, f->material.g, -SSS_G_MAX,
                        SSS_G_MAX);
    return SSS_OK;
}

void sss_sec_phas_pack(const sss_bake_file *f, uint8_t *p) { put_f64(p, f->material.g); }

sss_result sss_sec_phas_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != PHAS_SIZE || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section PHAS: %llu bytes, count %llu (expected %u and 1)", name,
                        (unsigned long long)size, (unsigned long long)count, PHAS_SIZE);
    f->material.g = get_f64(p);
    return sss_sec_phas_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_phas_free(sss_bake_file *f) { f->material.g = 0.0; }

int sss_sec_phas_wants(const sss_bake_file *f) { return f->material.g != 0.0; }

sss_sec_need sss_sec_phas_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
