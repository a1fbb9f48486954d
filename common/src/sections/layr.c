/* layr.c: section LAYR (format 1.8), seed 002's flat layers over the
 * material (docs/format.md §5.21, docs/layers.md §3): u32 n, u32 phase
 * (0 Henyey–Greenstein, 1 Schlick), then per layer f64 σs[3], σt[3] (1/mm),
 * g and the depth of its lower boundary (mm). Only single scattering sees
 * them (the dipole sees MATL), so the section is optional: a reader
 * without it shows the same multiple scattering. Written only when a scene
 * gives layers. */
#include "sections.h"

#define LAYR_HEAD 8u
#define LAYR_EACH 64u /* 3 + 3 + 1 + 1 f64 */

uint64_t sss_sec_layr_size(const sss_bake_file *f) { return LAYR_HEAD + (uint64_t)LAYR_EACH * f->layers.n; }

uint64_t sss_sec_layr_count(const sss_bake_file *f) { return f->layers.n; }

sss_result sss_sec_layr_check(const sss_bake_file *f, const char *name, sss_result code, sss_error *err)
{
    const sss_layer_stack *L = &f->layers;
    if (L->n < 1 || L->n > SSS_MAX_LAYERS)
        return sss_fail(err, code, "%s: section LAYR: %u layers, expected 1 to %d", name, L->n, SSS_MAX_LAYERS);
    if (L->phase != SSS_PHASE_HG && L->phase != SSS_PHASE_SCHLICK)
        return sss_fail(err, code, "%s: section LAYR: phase %u is not 0 (Henyey-Greenstein) or 1 (Schlick)", name,
                        (unsigned)L->phase);
    double top = 0.0;
    for (uint32_t i = 0; i < L->n; i++) {
        const sss_layer *l = &L->layer[i];
        for (int c = 0; c < 3; c++)
            if (!(l->sigma_s[c] >= 0.0 && l->sigma_t[c] >= l->sigma_s[c] && l->sigma_t[c] <= 2.0 * SSS_SIGMA_MAX))
                return sss_fail(err, code, "%s: section LAYR: layer %u channel %d: sigma_s %g, sigma_t %g are not "
                                "0 <= sigma_s <= sigma_t <= %g", name, i, c, l->sigma_s[c], l->sigma_t[c],
                                2.0 * SSS_SIGMA_MAX);
        if (!(fabs(l->g) <= SSS_G_MAX))
            return sss_fail(err, code, "%s: section LAYR: layer %u: g %g is outside [%g, %g]", name, i, l->g,
                            -SSS_G_MAX, SSS_G_MAX);
        if (!(l->depth >= top) || isnan(l->depth))
            return sss_fail(err, code, "%s: section LAYR: layer %u: depth %g mm is above the layer before it (%g mm)",
                            name, i, l->depth, top);
        top = l->depth;
    }
    return SSS_OK;
}

void sss_sec_layr_pack(const sss_bake_file *f, uint8_t *p)
{
    put_u32(p, f->layers.n);
    put_u32(p + 4, (uint32_t)f->layers.phase);
    p += LAYR_HEAD;
    for (uint32_t i = 0; i < f->layers.n; i++) {
        const sss_layer *l = &f->layers.layer[i];
        for (int c = 0; c < 3; c++, p += 8) put_f64(p, l->sigma_s[c]);
        for (int c = 0; c < 3; c++, p += 8) put_f64(p, l->sigma_t[c]);
        put_f64(p, l->g);
        put_f64(p + 8, l->depth);
        p += 16;
    }
}

sss_result sss_sec_layr_parse(const uint8_t *p, uint64_t size, uint64_t count, const char *name, sss_bake_file *f,
                              sss_error *err)
{
    const uint32_t n = size >= LAYR_HEAD ? get_u32(p) : 0;
    if (size < LAYR_HEAD || n < 1 || n > SSS_MAX_LAYERS || size != LAYR_HEAD + (uint64_t)LAYR_EACH * n || count != n)
        return sss_fail(err, SSS_ERR_CORRUPT, "%s: section LAYR: %llu bytes, count %llu for %u layers (expected %u "
                        "bytes per layer after %u, 1 to %d layers)", name, (unsigned long long)size,
                        (unsigned long long)count, n, LAYR_EACH, LAYR_HEAD, SSS_MAX_LAYERS);
    sss_layer_stack *L = &f->layers;
    L->n = n;
    L->phase = (sss_phase_kind)get_u32(p + 4);
    p += LAYR_HEAD;
    for (uint32_t i = 0; i < n; i++) {
        sss_layer *l = &L->layer[i];
        for (int c = 0; c < 3; c++, p += 8) l->sigma_s[c] = get_f64(p);
        for (int c = 0; c < 3; c++, p += 8) l->sigma_t[c] = get_f64(p);
        l->g = get_f64(p);
        l->depth = get_f64(p + 8);
        p += 16;
    }
    return sss_sec_layr_check(f, name, SSS_ERR_CORRUPT, err);
}

void sss_sec_layr_free(sss_bake_file *f) { memset(&f->layers, 0, sizeof f->layers); }

int sss_sec_layr_wants(const sss_bake_file *f) { return f->layers.n != 0; }

sss_sec_need sss_sec_layr_needs(const sss_bake_file *f)
{
    (void)f;
    return SSS_SEC_EITHER;
}
