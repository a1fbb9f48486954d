/* reconstruct.c: a file's reconstruction of q as a reader shows it
 * (sss/reconstruct.h). */
#include "sss/reconstruct.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/visibility.h"
#include "sss/nearterms.h"

struct sss_reconstruct {
    const sss_bake_file *f;
    int near_on;  /* the file splits off the near terms */
    sss_weights nr;  /* their rows and weights */
    sss_vis *vis; /* the file's mesh: the bake's ray rule */
};

sss_result sss_reconstruct_create(const sss_bake_file *f, sss_reconstruct **out, sss_error *err)
{
    *out = NULL;
    if (!f) return sss_fail(err, SSS_ERR_ARG, "reconstruction: NULL file");
    sss_reconstruct *r = calloc(1, sizeof *r);
    if (!r) return sss_fail(err, SSS_ERR_NOMEM, "reconstruction: out of memory");
    r->f = f;
    if (f->near_terms) {
        sss_result e = sss_near_build_file(f, &r->nr, err);
        if (e == SSS_OK) e = sss_vis_create(&f->mesh, &r->vis, err);
        if (e != SSS_OK) {
            sss_reconstruct_destroy(r);
            return e;
        }
        r->near_on = 1;
    }
    *out = r;
    return SSS_OK;
}

int sss_reconstruct_has_near_terms(const sss_reconstruct *r) { return r && r->near_on; }

/* Unit light, or 0 for a zero or non-finite one (then nothing is added). */
static int unit(const double l[3], double d[3])
{
    double n = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
    if (!(n > 0.0) || !isfinite(n)) return 0;
    for (int k = 0; k < 3; k++) d[k] = l[k] / n;
    return 1;
}

/* Own visibility of vertex v, one vertex of sss_vis_lit_all. */
static uint8_t lit_one(const sss_reconstruct *r, uint32_t v, const double d[3])
{
    const float *n = r->f->mesh.nrm + 3 * (size_t)v;
    return n[0] * d[0] + n[1] * d[1] + n[2] * d[2] > 0.0 && !sss_vis_occluded(r->vis, v, d);
}

void sss_reconstruct_near_lit(const sss_reconstruct *r, const double light[3], uint8_t *lit)
{
    const uint32_t nv = r->f->mesh.nv;
    double d[3];
    if (!r->near_on || !unit(light, d)) {
        memset(lit, r->near_on ? 0 : 1, nv);
        return;
    }
    sss_vis_lit_all(r->vis, &r->f->mesh, d, lit);
}

/* The rows for the light: Q's (section QVEC, dotted with the light,
 * Hao–Varshney 2004 §3.2) when the file holds them, else q's. */
static void rows(const sss_bake_file *f, const double light[3], sss_interp interp, float *out)
{
    if (sss_decode_has_vector(f)) sss_decode_vector_range(f, light, interp, 0, f->mesh.nv, out);
    else sss_decode_all_interp(f, light, interp, out);
}

void sss_reconstruct_eval_rows(const sss_reconstruct *r, const double light[3], sss_interp interp, float *out)
{
    rows(r->f, light, interp, out);
}

void sss_reconstruct_eval(const sss_reconstruct *r, const double light[3], sss_interp interp, float *out)
{
    rows(r->f, light, interp, out);
    double d[3];
    if (!r->near_on || !unit(light, d)) return;
    const uint32_t nv = r->f->mesh.nv;
    uint8_t *lit = malloc(nv + 1u);
    float *gv = malloc((size_t)nv * sizeof *gv + 1);
    if (lit && gv) {
        sss_reconstruct_near_lit(r, d, lit);
        sss_near_transfer(r->f->mesh.nrm, nv, (float)r->f->material.eta, d, lit, gv);
        sss_near_add(&r->nr, gv, out);
    } else {
        /* without memory for the per-vertex arrays: vertex by vertex */
        for (uint32_t v = 0; v < nv; v++) {
            float s[SSS_MAX_CHANNELS];
            sss_reconstruct_eval_vertex(r, v, d, s);
            for (uint32_t c = 0; c < r->f->channels; c++) out[(size_t)v * r->f->channels + c] = s[c];
        }
    }
    free(lit);
    free(gv);
}

void sss_reconstruct_eval_vertex(const sss_reconstruct *r, uint32_t v, const double light[3], float *out)
{
    if (sss_decode_has_vector(r->f) && v < r->f->mesh.nv)
        sss_decode_vector_range(r->f, light, SSS_INTERP_TRIANGLE, v, 1, out);
    else sss_decode_vertex(r->f, v, light, out);
    double d[3];
    if (!r->near_on || v >= r->f->mesh.nv || !unit(light, d)) return;
    /* the transfer of this row's vertices only; the same float sum as
     * sss_near_sum over a full gv */
    const float df[3] = {(float)d[0], (float)d[1], (float)d[2]};
    const uint32_t C = r->f->channels;
    float s[SSS_MAX_CHANNELS] = {0};
    for (uint64_t a = r->nr.start[v]; a < r->nr.start[v + 1]; a++) {
        const uint32_t i = r->nr.idx[a];
        const float g = lit_one(r, i, d) ? sss_near_g((float)r->f->material.eta, r->f->mesh.nrm + 3 * (size_t)i, df)
                                         : 0.0f;
        for (uint32_t c = 0; c < C; c++) s[c] += r->nr.w[(size_t)a * C + c] * g;
    }
    for (uint32_t c = 0; c < C; c++) out[c] += s[c];
}

void sss_reconstruct_destroy(sss_reconstruct *r)
{
    if (!r) return;
    sss_vis_destroy(r->vis);
    sss_weights_free(&r->nr);
    free(r);
}
