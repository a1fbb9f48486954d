/* nrad.c: section NRAD (format 1.5), the near terms' radius (docs/format.md
 * §5.17, sss/nearterms.h): f64 radius in mm. With section OWNT, the terms
 * split off the rows and added back at run time are those of every vertex
 * within this distance of x_o through the mesh, instead of OWNT's mesh
 * rings, so that a fine and a coarse mesh of one object split off the same
 * physical neighbourhood. Required-flagged: an older reader would add the
 * rings' terms instead. */
#include "sections.h"

#define NRAD_SIZE 8u

uint64_t sss_sec_nrad_size(const sss_bake_file *f)
{
    (void)f;
    return NRAD_SIZE;
}

uint64_t sss_sec_nrad_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_nrad_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!(f->near_radius_mm > 0.0) || !isfinite(f->near_radius_mm))
        return sss_fail(err, code, "%s: section NRAD: radius %g mm is not a finite number > 0", name,
                        f->near_radius_mm);
    if (f->near_terms != SSS_NEAR_TERMS_RUNTIME)
        return sss_fail(err, code, "%s: section NRAD without section OWNT (a near-terms radius needs the split)",
                        name);
    return SSS_OK;
}

void sss_sec_nrad_pack(const sss_bake_file *f, uint8_t *p) { put_f64(p, f->near_radius_mm); }

sss_result sss_sec_nrad_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != NRAD_SIZE || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section NRAD: %llu bytes, count %llu (expected %u and 1)", name,
                        (unsigned long long)size, (unsigned long long)count, NRAD_SIZE);
    f->near_radius_mm = get_f64(p);
    return sss_sec_nrad_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_nrad_free(sss_bake_file *f) { f->near_radius_mm = 0.0; }

int sss_sec_nrad_wants(const sss_bake_file *f) { return f->near_radius_mm != 0.0; }

sss_sec_need sss_sec_nrad_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
