/* efct.c: section EFCT (format 1.2), the effect set of a scene bake
 * (docs/format.md §5.10, docs/scenes.md): which effects the planner chose
 * for the object, so that a renderer builds only the passes the file needs
 * and a reader knows which of the other sections the file must hold. The
 * light parameterisations it names other than the direction set of
 * Hao–Varshney 2004 §3.2 have a section each: QDIR (qdir.c), ENVT
 * (envt.c) and PSHL (pshl.c). All are required-flagged: a 1.1 reader
 * refuses a scene bake by name instead of misreading it.
 */
#include "sections.h"

#define CORRUPT SSS_ERR_CORRUPT

static const char *const fx_names[SSS_FX_COUNT] = {"rgb",           "self-shadow", "scene-shadow",  "directional-exact",
                                                   "direction-set", "point-shells", "environment-sh",
                                                   "single-scattering"};

const char *sss_effect_name(uint32_t bit) { return bit < SSS_FX_COUNT ? fx_names[bit] : "?"; }

uint64_t sss_sec_efct_size(const sss_bake_file *f)
{
    (void)f;
    return 8;
}

uint64_t sss_sec_efct_count(const sss_bake_file *f)
{
    (void)f;
    return 1;
}

/* Fails with `code`, naming the lowest bit of mask this reader does not know;
 * SSS_OK when every bit is known. */
static sss_result check_known(uint32_t mask, const char *name, sss_result code, sss_error *err)
{
    const uint32_t unknown = mask & ~SSS_FX_KNOWN;
    if (!unknown) return SSS_OK;
    uint32_t b = 0;
    while (!(unknown >> b & 1u)) b++;
    return sss_fail(err, code, "%s: section EFCT: effect bit %u is unknown to this reader (format %d.%d)", name, b,
                    SSS_FORMAT_MAJOR, SSS_FORMAT_MINOR);
}

/* The effect set as a whole: no unknown bit (refused as unsupported when
 * read: an effect cannot be skipped without rendering the object wrongly),
 * at least one light effect, rgb as MATL says, and no data for an effect
 * the mask does not name. The data of the effects it names is checked by
 * their own sections. */
sss_result sss_sec_efct_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_effects *x = &f->fx;
    const uint32_t m = x->mask;
    if (m & ~SSS_FX_KNOWN) return check_known(m, name, code == SSS_ERR_CORRUPT ? SSS_ERR_UNSUPPORTED : code, err);
    if (!(m & (SSS_FX_DIR_EXACT | SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH)))
        return sss_fail(err, code, "%s: section EFCT: no light effect (directional-exact, direction-set, "
                        "point-shells or environment-sh) is set", name);
    if (!!(m & SSS_FX_RGB) != (f->channels == 3))
        return sss_fail(err, code, "%s: section EFCT: effect rgb is %s but section MATL has %u channels", name,
                        m & SSS_FX_RGB ? "set" : "clear", f->channels);
    if (!(m & SSS_FX_DIR_EXACT) && (x->nexact || x->exact_q))
        return sss_fail(err, code, "%s: section QDIR present but effect directional-exact is not set", name);
    if (!(m & SSS_FX_ENV_SH) && (x->env_order || x->env_t))
        return sss_fail(err, code, "%s: section ENVT present but effect environment-sh is not set", name);
    if (!(m & SSS_FX_POINT_SHELLS) && (x->nshells || x->shell_q))
        return sss_fail(err, code, "%s: section PSHL present but effect point-shells is not set", name);
    return SSS_OK;
}

void sss_sec_efct_pack(const sss_bake_file *f, uint8_t *p)
{
    put_u32(p, f->fx.mask);
    put_u32(p + 4, 0);
}

sss_result sss_sec_efct_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != 8) return sss_sec_fx_size_mismatch(err, name, "EFCT", size, 8);
    if (count != 1)
        return sss_fail(err, CORRUPT, "%s: section EFCT: count %llu, expected 1", name, (unsigned long long)count);
    f->fx.mask = get_u32(p);
    if (get_u32(p + 4) != 0) return sss_fail(err, CORRUPT, "%s: section EFCT: reserved field is not 0", name);
    sss_result r = check_known(f->fx.mask, name, SSS_ERR_UNSUPPORTED, err);
    if (r != SSS_OK) return r;
    if (!f->fx.mask) return sss_fail(err, CORRUPT, "%s: section EFCT: empty effect set", name);
    return SSS_OK;
}

void sss_sec_efct_free(sss_bake_file *f) { f->fx.mask = 0; }

int sss_sec_efct_wants(const sss_bake_file *f) { return f->fx.mask != 0; }

/* a plain bake has none; a scene bake is recognised by it */
sss_sec_need sss_sec_efct_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
