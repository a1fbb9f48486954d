/* matl.c: section MATL, the material (docs/format.md §5.2): preset name,
 * σa and σ′s per channel in 1/mm, the relative index of refraction η,
 * millimetres per mesh unit and the channel count, which sizes every
 * per-channel array of the other sections. */
#include <string.h>

#include "sections.h"

#define MATL_SIZE 100u /* 32 + 3*8 + 3*8 + 8 + 8 + 4 */

uint64_t sss_sec_matl_size(const sss_bake_file *f)
{
    (void)f;
    return MATL_SIZE;
}

uint64_t sss_sec_matl_count(const sss_bake_file *f) { return f->channels; }

/* The material as the bake accepts it (sss_material_check: the ranges the
 * dipole and the float gather survive), mm per unit in the bake's own
 * range, and the mesh of GEOM (read before) spanning at most
 * SSS_EXTENT_MM_MAX in mm: what the exact evaluator and the viewer
 * recompute from must be what a bake could have used (docs/format.md §6). */
sss_result sss_sec_matl_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_material *mat = &f->material;
    const uint32_t channels = f->channels;
    if (!memchr(mat->name, 0, sizeof mat->name))
        return sss_fail(err, code, "%s: section MATL: material name is not NUL-terminated within 32 bytes", name);
    if (channels != 1 && channels != 3)
        return sss_fail(err, code, "%s: section MATL: channel count %u is not 1 or 3", name, channels);
    for (int c = 0; c < SSS_MAX_CHANNELS; c++)
        if (!isfinite(mat->sigma_a[c]) || !isfinite(mat->sigmap_s[c]))
            return sss_fail(err, code, "%s: section MATL: channel %d: coefficients are not finite", name, c);
    sss_error e2 = {{0}};
    if (sss_material_check(mat, channels, code, &e2) != SSS_OK)
        return sss_fail(err, code, "%s: section MATL: %s", name, e2.msg);
    if (!(f->mm_per_unit >= SSS_MM_PER_UNIT_MIN && f->mm_per_unit <= SSS_MM_PER_UNIT_MAX))
        return sss_fail(err, code, "%s: section MATL: mm_per_unit %g is outside [%g, %g]", name, f->mm_per_unit,
                        SSS_MM_PER_UNIT_MIN, SSS_MM_PER_UNIT_MAX);
    if (f->mesh.nv && f->mesh.pos && sss_mesh_check_range(&f->mesh, f->mm_per_unit, "", &e2) != SSS_OK)
        return sss_fail(err, code, "%s: section MATL%s", name, e2.msg);
    return SSS_OK;
}

void sss_sec_matl_pack(const sss_bake_file *f, uint8_t *p)
{
    memcpy(p, f->material.name, 32);
    p += 32;
    for (int c = 0; c < 3; c++, p += 8) put_f64(p, f->material.sigma_a[c]);
    for (int c = 0; c < 3; c++, p += 8) put_f64(p, f->material.sigmap_s[c]);
    put_f64(p, f->material.eta);
    put_f64(p + 8, f->mm_per_unit);
    put_u32(p + 16, f->channels);
}

sss_result sss_sec_matl_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != MATL_SIZE)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section MATL: size %llu, expected %u", name,
                        (unsigned long long)size, MATL_SIZE);
    memcpy(f->material.name, p, 32);
    p += 32;
    for (int c = 0; c < 3; c++, p += 8) f->material.sigma_a[c] = get_f64(p);
    for (int c = 0; c < 3; c++, p += 8) f->material.sigmap_s[c] = get_f64(p);
    f->material.eta = get_f64(p);
    f->mm_per_unit = get_f64(p + 8);
    f->channels = get_u32(p + 16);
    sss_result r = sss_sec_matl_check(f, name, SSS_ERR_CORRUPT, err);
    if (r != SSS_OK) return r;
    if (count != f->channels) return sss_sec_count_mismatch(err, name, "MATL", count, f->channels, "channels");
    return SSS_OK;
}

void sss_sec_matl_free(sss_bake_file *f) { (void)f; /* owns no memory */ }

int sss_sec_matl_wants(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_sec_need sss_sec_matl_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_PRESENT;
}
