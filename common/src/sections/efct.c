/* format_effects.c: sections of format 1.2 written by scene bakes
 * (docs/format.md §5.10–5.13). EFCT records the effect set the planner
 * chose (docs/scenes.md), so a renderer builds only the shader paths the
 * file needs; QDIR, ENVT and PSHL hold the light parameterisations that are
 * not the direction set of Hao–Varshney 2004 §3.2: an exact value per
 * static directional light, an SH transfer vector per vertex for an
 * environment, and directions × distance shells for a near point light
 * (the §3.3 extension). All are required-flagged: a 1.1 reader refuses them
 * by name instead of misreading the file.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../format_bytes.h"
#include "../format_effects.h"

#define CORRUPT SSS_ERR_CORRUPT

static const char *const fx_names[SSS_FX_COUNT] = {"rgb",           "self-shadow", "scene-shadow",  "directional-exact",
                                                   "direction-set", "point-shells", "environment-sh"};

const char *sss_effect_name(uint32_t bit) { return bit < SSS_FX_COUNT ? fx_names[bit] : "?"; }

static uint32_t ncoef(uint32_t order) { return order * order; }

uint64_t sss_fmt_efct_size(const sss_bake_file *f)
{
    (void)f;
    return 8;
}

uint64_t sss_fmt_qdir_size(const sss_bake_file *f)
{
    uint64_t n, r;
    if (!mul_u64((uint64_t)f->fx.nexact * f->mesh.nv, f->channels, &n)) return 0;
    return lin_u64(24, f->fx.nexact, 4, n, 8, &r) ? r : 0;
}

uint64_t sss_fmt_envt_size(const sss_bake_file *f)
{
    uint64_t n, r;
    const uint32_t K = ncoef(f->fx.env_order);
    if (!mul_u64((uint64_t)f->mesh.nv * f->channels, K, &n)) return 0;
    return lin_u64(12, K, 4, n, 8, &r) ? r : 0;
}

uint64_t sss_fmt_pshl_size(const sss_bake_file *f)
{
    uint64_t n, r;
    if (!mul_u64((uint64_t)f->fx.nshells * f->dirs.n, f->mesh.nv, &n) || !mul_u64(n, f->channels, &n)) return 0;
    return lin_u64(8, f->fx.nshells, 4, n, 32, &r) ? r : 0;
}

static sss_result check_floats(const float *x, uint64_t n, int nonneg, const char *name, const char *sec,
                               sss_result code, sss_error *err)
{
    for (uint64_t k = 0; k < n; k++)
        if (!isfinite(x[k]) || (nonneg && x[k] < 0.0f))
            return sss_fail(err, code, "%s: section %s: value %llu (%g) is not a finite number%s", name, sec,
                            (unsigned long long)k, (double)x[k], nonneg ? " >= 0" : "");
    return SSS_OK;
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

sss_result sss_fmt_check_effects(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
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
    const uint64_t nvc = (uint64_t)f->mesh.nv * f->channels;
    if (m & SSS_FX_DIR_EXACT) {
        if (x->nexact < 1 || x->nexact > 1024 || !x->exact_dir || !x->exact_q)
            return sss_fail(err, code, "%s: section QDIR: %u static directions (1 ... 1024 expected)", name,
                            x->nexact);
        for (uint32_t l = 0; l < x->nexact; l++) {
            const double *d = &x->exact_dir[3 * (size_t)l];
            const double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            if (!isfinite(len) || fabs(len - 1.0) > 1e-6)
                return sss_fail(err, code, "%s: section QDIR: direction %u is not a unit vector", name, l);
        }
        sss_result r = check_floats(x->exact_q, nvc * x->nexact, 1, name, "QDIR", code, err);
        if (r != SSS_OK) return r;
    } else if (x->nexact || x->exact_q) {
        return sss_fail(err, code, "%s: section QDIR present but effect directional-exact is not set", name);
    }
    if (m & SSS_FX_ENV_SH) {
        if (x->env_order < 1 || x->env_order > 8 || !x->env_t)
            return sss_fail(err, code, "%s: section ENVT: SH order %u (1 ... 8 expected)", name, x->env_order);
        sss_result r = check_floats(x->env_probe, 3 * (uint64_t)ncoef(x->env_order), 0, name, "ENVT", code, err);
        if (r == SSS_OK) r = check_floats(x->env_t, nvc * ncoef(x->env_order), 0, name, "ENVT", code, err);
        if (r != SSS_OK) return r;
    } else if (x->env_order || x->env_t) {
        return sss_fail(err, code, "%s: section ENVT present but effect environment-sh is not set", name);
    }
    if (m & SSS_FX_POINT_SHELLS) {
        if (x->nshells < 2 || x->nshells > 64 || !x->shell_radius || !x->shell_q)
            return sss_fail(err, code, "%s: section PSHL: %u distance shells (2 ... 64 expected)", name, x->nshells);
        for (int k = 0; k < 3; k++)
            if (!isfinite(x->shell_centre[k]))
                return sss_fail(err, code, "%s: section PSHL: centre is not finite", name);
        for (uint32_t s = 0; s < x->nshells; s++)
            if (!isfinite(x->shell_radius[s]) || !(x->shell_radius[s] > (s ? x->shell_radius[s - 1] : 0.0)))
                return sss_fail(err, code, "%s: section PSHL: radius %u (%g) is not finite, positive and larger "
                                "than the previous one", name, s, x->shell_radius[s]);
        if (f->dirs.n < 4)
            return sss_fail(err, code, "%s: section PSHL: needs a triangulated direction set (%u directions)", name,
                            f->dirs.n);
        sss_result r = check_floats(x->shell_q, nvc * f->dirs.n * x->nshells, 1, name, "PSHL", code, err);
        if (r != SSS_OK) return r;
    } else if (x->nshells || x->shell_q) {
        return sss_fail(err, code, "%s: section PSHL present but effect point-shells is not set", name);
    }
    return SSS_OK;
}

void sss_fmt_pack_efct(const sss_bake_file *f, uint8_t *p)
{
    put_u32(p, f->fx.mask);
    put_u32(p + 4, 0);
}

void sss_fmt_pack_qdir(const sss_bake_file *f, uint8_t *p)
{
    const sss_effects *x = &f->fx;
    put_u32(p, f->channels);
    put_u32(p + 4, x->nexact);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)x->nexact; k++, p += 8) put_f64(p, x->exact_dir[k]);
    const size_t n = (size_t)x->nexact * f->mesh.nv * f->channels;
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, x->exact_q[k]);
}

void sss_fmt_pack_envt(const sss_bake_file *f, uint8_t *p)
{
    const sss_effects *x = &f->fx;
    const uint32_t K = ncoef(x->env_order);
    put_u32(p, f->channels);
    put_u32(p + 4, x->env_order);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)K; k++, p += 4) put_f32(p, x->env_probe[k]);
    const size_t n = (size_t)f->mesh.nv * f->channels * K;
    for (size_t k = 0; k < n; k++, p += 4) put_f32(p, x->env_t[k]);
}

void sss_fmt_pack_pshl(const sss_bake_file *f, uint8_t *p)
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

static sss_result size_mismatch(sss_error *err, const char *name, const char *sec, uint64_t size, uint64_t want)
{
    return sss_fail(err, CORRUPT, "%s: section %s: size %llu does not match its counts (%llu bytes)", name, sec,
                    (unsigned long long)size, (unsigned long long)want);
}

static sss_result head(const uint8_t *p, uint64_t size, const char *name, const char *sec, const sss_bake_file *f,
                       uint32_t *second, sss_error *err)
{
    if (size < 8) return sss_fail(err, CORRUPT, "%s: section %s: size %llu is too small", name, sec, (unsigned long long)size);
    if (get_u32(p) != f->channels)
        return sss_fail(err, CORRUPT, "%s: section %s: %u channels, but section MATL says %u", name, sec, get_u32(p),
                        f->channels);
    *second = get_u32(p + 4);
    return SSS_OK;
}

sss_result sss_fmt_parse_efct(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    if (size != 8) return size_mismatch(err, name, "EFCT", size, 8);
    if (count != 1) return sss_fail(err, CORRUPT, "%s: section EFCT: count %llu, expected 1", name, (unsigned long long)count);
    f->fx.mask = get_u32(p);
    if (get_u32(p + 4) != 0) return sss_fail(err, CORRUPT, "%s: section EFCT: reserved field is not 0", name);
    return check_known(f->fx.mask, name, SSS_ERR_UNSUPPORTED, err);
}

sss_result sss_fmt_parse_qdir(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t nl = 0;
    sss_result r = head(p, size, name, "QDIR", f, &nl, err);
    if (r != SSS_OK) return r;
    if (nl < 1 || nl > 1024) return sss_fail(err, CORRUPT, "%s: section QDIR: %u directions (1 ... 1024 expected)", name, nl);
    f->fx.nexact = nl;
    const uint64_t want = sss_fmt_qdir_size(f);
    if (!want || size != want) { f->fx.nexact = 0; return size_mismatch(err, name, "QDIR", size, want); }
    if (count != nl) return sss_fail(err, CORRUPT, "%s: section QDIR: count %llu, expected %u", name, (unsigned long long)count, nl);
    const size_t n = (size_t)nl * f->mesh.nv * f->channels;
    f->fx.exact_dir = malloc(3 * (size_t)nl * sizeof(double));
    f->fx.exact_q = malloc(n * sizeof(float) + 1);
    if (!f->fx.exact_dir || !f->fx.exact_q) return sss_fail(err, SSS_ERR_NOMEM, "%s: section QDIR: out of memory", name);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)nl; k++, p += 8) f->fx.exact_dir[k] = get_f64(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.exact_q[k] = get_f32(p);
    return SSS_OK;
}

sss_result sss_fmt_parse_envt(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t order = 0;
    sss_result r = head(p, size, name, "ENVT", f, &order, err);
    if (r != SSS_OK) return r;
    if (order < 1 || order > 8) return sss_fail(err, CORRUPT, "%s: section ENVT: SH order %u (1 ... 8 expected)", name, order);
    f->fx.env_order = order;
    const uint64_t want = sss_fmt_envt_size(f);
    if (!want || size != want) { f->fx.env_order = 0; return size_mismatch(err, name, "ENVT", size, want); }
    if (count != f->mesh.nv)
        return sss_fail(err, CORRUPT, "%s: section ENVT: count %llu, expected %u vertices", name, (unsigned long long)count, f->mesh.nv);
    const uint32_t K = ncoef(order);
    const size_t n = (size_t)f->mesh.nv * f->channels * K;
    f->fx.env_t = malloc(n * sizeof(float) + 1);
    if (!f->fx.env_t) return sss_fail(err, SSS_ERR_NOMEM, "%s: section ENVT: out of memory", name);
    p += 8;
    for (size_t k = 0; k < 3 * (size_t)K; k++, p += 4) f->fx.env_probe[k] = get_f32(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.env_t[k] = get_f32(p);
    return SSS_OK;
}

sss_result sss_fmt_parse_pshl(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    uint32_t ns = 0;
    sss_result r = head(p, size, name, "PSHL", f, &ns, err);
    if (r != SSS_OK) return r;
    if (ns < 2 || ns > 64) return sss_fail(err, CORRUPT, "%s: section PSHL: %u shells (2 ... 64 expected)", name, ns);
    f->fx.nshells = ns;
    const uint64_t want = sss_fmt_pshl_size(f);
    if (!want || size != want) { f->fx.nshells = 0; return size_mismatch(err, name, "PSHL", size, want); }
    if (count != ns) return sss_fail(err, CORRUPT, "%s: section PSHL: count %llu, expected %u", name, (unsigned long long)count, ns);
    const size_t n = (size_t)ns * f->dirs.n * f->mesh.nv * f->channels;
    f->fx.shell_radius = malloc(ns * sizeof(double));
    f->fx.shell_q = malloc(n * sizeof(float) + 1);
    if (!f->fx.shell_radius || !f->fx.shell_q) return sss_fail(err, SSS_ERR_NOMEM, "%s: section PSHL: out of memory", name);
    p += 8;
    for (int k = 0; k < 3; k++, p += 8) f->fx.shell_centre[k] = get_f64(p);
    for (size_t k = 0; k < ns; k++, p += 8) f->fx.shell_radius[k] = get_f64(p);
    for (size_t k = 0; k < n; k++, p += 4) f->fx.shell_q[k] = get_f32(p);
    return SSS_OK;
}

void sss_fmt_free_effects(sss_bake_file *f)
{
    free(f->fx.exact_dir);
    free(f->fx.exact_q);
    free(f->fx.env_t);
    free(f->fx.shell_radius);
    free(f->fx.shell_q);
    memset(&f->fx, 0, sizeof f->fx);
}
