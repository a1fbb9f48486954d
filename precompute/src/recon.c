/* recon.c: a file's reconstruction of q as a reader shows it (sss/recon.h). */
#include "sss/recon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/bake.h"
#include "sss/ownterm.h"

struct sss_recon {
    const sss_bake_file *f;
    float *w;     /* own-term weights w̃ (nv × channels), NULL without OWNT */
    sss_vis *vis; /* the file's mesh: the bake's ray rule */
};

sss_result sss_recon_create(const sss_bake_file *f, sss_recon **out, sss_error *err)
{
    *out = NULL;
    if (!f) return sss_fail(err, SSS_ERR_ARG, "reconstruction: NULL file");
    sss_recon *r = calloc(1, sizeof *r);
    if (!r) return sss_fail(err, SSS_ERR_NOMEM, "reconstruction: out of memory");
    r->f = f;
    if (f->own_term) {
        const size_t n = (size_t)f->mesh.nv * f->channels;
        r->w = malloc(n * sizeof *r->w + 1);
        if (!r->w) {
            free(r);
            return sss_fail(err, SSS_ERR_NOMEM, "reconstruction: out of memory for %u vertices", f->mesh.nv);
        }
        sss_result e = sss_own_weights(&f->mesh, &f->material, f->mm_per_unit, f->channels, r->w, err);
        if (e == SSS_OK) e = sss_vis_create(&f->mesh, &r->vis, err);
        if (e != SSS_OK) {
            sss_recon_destroy(r);
            return e;
        }
    }
    *out = r;
    return SSS_OK;
}

int sss_recon_has_own_term(const sss_recon *r) { return r && r->w; }

/* Unit light, or 0 for a zero or non-finite one (then nothing is added). */
static int unit(const double l[3], double d[3])
{
    double n = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!(n > 0.0) || !isfinite(n)) return 0;
    for (int k = 0; k < 3; k++) d[k] = l[k] / n;
    return 1;
}

void sss_recon_own_lit(const sss_recon *r, const double light[3], uint8_t *lit)
{
    const uint32_t nv = r->f->mesh.nv;
    double d[3];
    if (!r->vis || !unit(light, d)) {
        memset(lit, r->vis ? 0 : 1, nv);
        return;
    }
    const float *nrm = r->f->mesh.nrm;
    /* a ray only where the vertex faces the light (as the bake traces) */
#pragma omp parallel for schedule(dynamic, 1024)
    for (int64_t v = 0; v < (int64_t)nv; v++) {
        const float *n = nrm + 3 * (size_t)v;
        const double c = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
        lit[v] = c > 0.0 && !sss_vis_occluded(r->vis, (uint32_t)v, d);
    }
}

void sss_recon_eval_rows(const sss_recon *r, const double light[3], sss_interp interp, float *out)
{
    sss_decode_all_interp(r->f, light, interp, out);
}

void sss_recon_eval(const sss_recon *r, const double light[3], sss_interp interp, float *out)
{
    sss_decode_all_interp(r->f, light, interp, out);
    double d[3];
    if (!r->w || !unit(light, d)) return;
    const uint32_t nv = r->f->mesh.nv;
    uint8_t *lit = malloc(nv + 1u);
    if (lit) sss_recon_own_lit(r, d, lit);
    /* without memory for the flags, every facing vertex traces inside the add */
    if (!lit) {
        const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
        const uint32_t C = r->f->channels;
        for (uint32_t v = 0; v < nv; v++) {
            const float g = sss_own_transfer((float)r->f->material.eta, r->f->mesh.nrm + 3 * (size_t)v, df);
            if (g == 0.0f || sss_vis_occluded(r->vis, v, d)) continue;
            for (uint32_t c = 0; c < C; c++) out[(size_t)v * C + c] += r->w[(size_t)v * C + c] * g;
        }
        return;
    }
    sss_own_add(r->w, r->f->mesh.nrm, nv, r->f->channels, (float)r->f->material.eta, d, lit, out);
    free(lit);
}

void sss_recon_eval_vertex(const sss_recon *r, uint32_t v, const double light[3], float *out)
{
    sss_decode_vertex(r->f, v, light, out);
    double d[3];
    if (!r->w || v >= r->f->mesh.nv || !unit(light, d)) return;
    const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
    const float g = sss_own_transfer((float)r->f->material.eta, r->f->mesh.nrm + 3 * (size_t)v, df);
    if (g == 0.0f || sss_vis_occluded(r->vis, v, d)) return;
    for (uint32_t c = 0; c < r->f->channels; c++) out[c] += r->w[(size_t)v * r->f->channels + c] * g;
}

void sss_recon_destroy(sss_recon *r)
{
    if (!r) return;
    sss_vis_destroy(r->vis);
    free(r->w);
    free(r);
}
