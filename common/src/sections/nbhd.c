/* nbhd.c: section NBHD (format 1.4), what fixes the scattering
 * neighbourhoods of the bake (docs/format.md §5.15): f64 ε, the energy
 * cutoff of the neighbourhood radius (per channel the disk that holds
 * 1 − ε of R_d's total; Hao–Varshney 2004 §3.1 sums over a neighbourhood
 * N(x_o)). The exact evaluator recomputes the bake's neighbourhoods from
 * it, so it is stored as binary, required-flagged data rather than only in
 * the provenance text of PARM, which a reader may skip. */
#include "sections.h"

#define NBHD_SIZE 8u  /* f64 eps */
#define NBHD_SINCE 4u /* the minor version that introduced it (its row in sections.h) */

uint64_t sss_sec_nbhd_size(const sss_bake_file *f)
{
    (void)f;
    return NBHD_SIZE;
}

uint64_t sss_sec_nbhd_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_result sss_sec_nbhd_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    if (!(f->eps > 0.0 && f->eps < 1.0))
        return sss_fail(err, code, "%s: section NBHD: eps %g is not a number in (0, 1)", name, f->eps);
    return SSS_OK;
}

void sss_sec_nbhd_pack(const sss_bake_file *f, uint8_t *p) { put_f64(p, f->eps); }

sss_result sss_sec_nbhd_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != NBHD_SIZE || count != 1)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section NBHD: %llu bytes, count %llu (expected %u and 1)", name,
                        (unsigned long long)size, (unsigned long long)count, NBHD_SIZE);
    f->eps = get_f64(p);
    return sss_sec_nbhd_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_nbhd_free(sss_bake_file *f) { f->eps = 0.0; }

int sss_sec_nbhd_wants(const sss_bake_file *f) { return f->eps != 0.0; }

/* A file is written with the newest minor of its sections (§7), and NBHD
 * is the only section of 1.4: a 1.4 file without it was not written by a
 * conforming writer. Older files do not have it (ε is then only in PARM);
 * what a newer minor promises, this reader cannot know. */
sss_sec_need sss_sec_nbhd_needs(const sss_bake_file *f)
{
    return f->version_minor == NBHD_SINCE ? SSS_SEC_PRESENT : SSS_SEC_EITHER;
}
