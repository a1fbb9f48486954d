/* quad.c: section QUAD (format 1.5), the weight rule of the bake's sum
 * (docs/format.md §5.16, sss/hatweights.h): u32 rule, 1 = the weights
 * integrated over the vertices' hat functions (docs/physics.md §9) with
 * the constants of sss/hatweights.h. Without it a file holds the paper's
 * point samples (Hao–Varshney 2004 §3.1). The exact evaluator and the near
 * terms recompute the bake's weights from it, so it is required-flagged:
 * an older reader, which would sum other weights, refuses the file. */
#include "sections.h"
#include "sss/hatweights.h"

#define QUAD_SIZE 4u

uint64_t sss_sec_quad_size(const sss_bake_file *f)
{
    (void)f;
    return QUAD_SIZE;
}

uint64_t sss_sec_quad_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_quad_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (f->weights != SSS_WEIGHTS_HAT)
        return sss_fail(err, code, "%s: section QUAD: weight rule %u is not a known rule", name, f->weights);
    return SSS_OK;
}

void sss_sec_quad_pack(const sss_bake_file *f, uint8_t *p) { put_u32(p, f->weights); }

sss_result sss_sec_quad_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != QUAD_SIZE || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section QUAD: %llu bytes, count %llu (expected %u and 1)", name,
                        (unsigned long long)size, (unsigned long long)count, QUAD_SIZE);
    f->weights = get_u32(p);
    if (f->weights != SSS_WEIGHTS_HAT)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "%s: section QUAD: weight rule %u is unknown to this reader", name,
                        f->weights);
    return SSS_OK;
}

void sss_sec_quad_free(sss_bake_file *f) { f->weights = SSS_WEIGHTS_POINT; }

int sss_sec_quad_wants(const sss_bake_file *f) { return f->weights != SSS_WEIGHTS_POINT; }

sss_sec_need sss_sec_quad_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
