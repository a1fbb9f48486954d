/* ownt.c: section OWNT (format 1.3), near terms added at run time
 * (docs/format.md §5.14, sss/ownterm.h): u32 mode (1: the q rows of any
 * storage form hold q minus the near terms), u32 rings (0 … 8). Its
 * presence changes what every q section means, so it is required-flagged:
 * an older reader refuses the file by naming it. */
#include "sections.h"

uint64_t sss_sec_ownt_size(const sss_bake_file *f)
{
    (void)f;
    return 8;
}

uint64_t sss_sec_ownt_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_ownt_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const uint32_t fxm = f->fx.mask;
    if (f->own_term != SSS_OWN_TERM_RUNTIME || fxm || f->own_rings > SSS_OWN_RINGS_MAX)
        return sss_fail(err, code, "%s: section OWNT: mode %u, %u rings%s", name, f->own_term, f->own_rings,
                        fxm ? " in a scene bake (plain bakes only)" : " is not a valid split");
    return SSS_OK;
}

void sss_sec_ownt_pack(const sss_bake_file *f, uint8_t *p)
{
    put_u32(p, SSS_OWN_TERM_RUNTIME);
    put_u32(p + 4, f->own_rings);
}

sss_result sss_sec_ownt_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != 8 || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section OWNT: %llu bytes, count %llu (expected 8 and 1)", name,
                        (unsigned long long)size, (unsigned long long)count);
    uint32_t mode = get_u32(p), rings = get_u32(p + 4);
    if (mode != SSS_OWN_TERM_RUNTIME)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section OWNT: mode %u is unknown to this reader", name, mode);
    if (rings > SSS_OWN_RINGS_MAX)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section OWNT: %u rings (at most %u)", name, rings,
                        SSS_OWN_RINGS_MAX);
    f->own_term = mode;
    f->own_rings = rings;
    return sss_sec_ownt_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_ownt_free(sss_bake_file *f) { f->own_term = f->own_rings = 0; }

int sss_sec_ownt_wants(const sss_bake_file *f) { return f->own_term != 0; }

/* only in plain bakes with a direction set: a cross-section rule (format.c, §5.14) */
sss_sec_need sss_sec_ownt_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
