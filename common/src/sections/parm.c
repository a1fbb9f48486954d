/* parm.c: section PARM, the bake parameters as JSON text, for provenance
 * (docs/format.md §5.6). The reader does not parse it and does not check
 * its encoding (a path in it may hold any bytes), but refuses a NUL byte,
 * so that the NUL-terminated copy it returns is the whole text. Not
 * required-flagged: a reader may skip it. Written last, as the only
 * section of arbitrary length (§1). */
#include <stdlib.h>
#include <string.h>

#include "sections.h"

uint64_t sss_sec_parm_size(const sss_bake_file *f) { return f->params_json ? strlen(f->params_json) : 0; }

uint64_t sss_sec_parm_count(const sss_bake_file *f) { return sss_sec_parm_size(f); }

/* any C string is valid text for PARM (NULL is written as an empty section) */
sss_result sss_sec_parm_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    (void)f;
    (void)name;
    (void)code;
    (void)err;
    return SSS_OK;
}

void sss_sec_parm_pack(const sss_bake_file *f, uint8_t *p)
{
    const uint64_t n = sss_sec_parm_size(f);
    if (n) memcpy(p, f->params_json, (size_t)n);
}

sss_result sss_sec_parm_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (count != size) return sss_sec_count_mismatch(err, name, "PARM", count, size, "bytes");
    const uint8_t *nul = size ? memchr(p, 0, (size_t)size) : NULL;
    if (nul)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section PARM: NUL byte at offset %llu inside the JSON text", name,
                        (unsigned long long)(nul - p));
    f->params_json = malloc((size_t)size + 1);
    if (!f->params_json) return sss_sec_nomem(err, name, "PARM", size);
    if (size) memcpy(f->params_json, p, (size_t)size);
    f->params_json[size] = 0;
    return sss_sec_parm_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_parm_free(sss_bake_file *f)
{
    free(f->params_json);
    f->params_json = NULL;
}

int sss_sec_parm_wants(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

sss_sec_need sss_sec_parm_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_PRESENT;
}
