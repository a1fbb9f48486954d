/* ownt.c: section OWNT (format 1.3), near terms added at run time
 * (docs/format.md §5.14, sss/nearterms.h): u32 mode (1: the q rows of any
 * storage form hold q minus the near terms; in a scene bake the direction
 * set's rows only), u32 rings (0 … 8). Its
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
    /* a scene bake splits them off its direction set's rows only (§5.14) */
    const uint32_t fxm = f->fx.mask;
    const int no_dirset = fxm && !(fxm & SSS_FX_DIR_SET);
    if (f->near_terms != SSS_NEAR_TERMS_RUNTIME || no_dirset || f->near_rings > SSS_NEAR_RINGS_MAX)
        return sss_fail(err, code, "%s: section OWNT: mode %u, %u rings%s", name, f->near_terms, f->near_rings,
                        no_dirset ? " in a scene bake without the direction-set effect (the near terms are split off "
                                    "the direction set's rows only)" : " is not a valid split");
    return SSS_OK;
}

void sss_sec_ownt_pack(const sss_bake_file *f, uint8_t *p)
{
    put_u32(p, SSS_NEAR_TERMS_RUNTIME);
    put_u32(p + 4, f->near_rings);
}

sss_result sss_sec_ownt_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != 8 || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section OWNT: %llu bytes, count %llu (expected 8 and 1)", name,
                        (unsigned long long)size, (unsigned long long)count);
    uint32_t mode = get_u32(p), rings = get_u32(p + 4);
    if (mode != SSS_NEAR_TERMS_RUNTIME)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section OWNT: mode %u is unknown to this reader", name, mode);
    if (rings > SSS_NEAR_RINGS_MAX)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section OWNT: %u rings (at most %u)", name, rings,
                        SSS_NEAR_RINGS_MAX);
    f->near_terms = mode;
    f->near_rings = rings;
    return sss_sec_ownt_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_ownt_free(sss_bake_file *f) { f->near_terms = f->near_rings = 0; }

int sss_sec_ownt_wants(const sss_bake_file *f) { return f->near_terms != 0; }

/* only with the direction set's rows: a cross-section rule (format.c, §5.14) */
sss_sec_need sss_sec_ownt_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
