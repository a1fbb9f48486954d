/* decode_error.c: how far one stored form of q is from another (e.g. a
 * compressed file from the float bake it came from), measured per vertex
 * at random light directions that are not direction samples. The metric is
 * area-weighted so that a densely tessellated region does not count more
 * than its share of the surface. */
#include "sss/decode.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/random.h"

void sss_err_accum_init(sss_err_accum *acc, uint32_t channels, const double *area, uint32_t nv)
{
    memset(acc, 0, sizeof *acc);
    acc->channels = channels;
    for (uint32_t v = 0; v < nv; v++) acc->area_sum += area[v];
    if (!(acc->area_sum > 0.0)) {
        acc->unweighted = 1;
        acc->area_sum = nv;
    }
}

void sss_err_accum_add(sss_err_accum *acc, const double *area, const float *a, const float *r, uint32_t nv)
{
    const size_t C = acc->channels;
    for (size_t v = 0; v < nv; v++)
        for (size_t c = 0; c < C; c++) {
            const double x = r[v * C + c], e = (double)a[v * C + c] - x, wv = acc->unweighted ? 1.0 : area[v];
            acc->num[c] += wv * e * e;
            acc->den[c] += wv * x * x;
            /* NaN must not hide behind a comparison */
            acc->max_abs[c] = isnan(e) || isnan(acc->max_abs[c]) ? NAN : fmax(acc->max_abs[c], fabs(e));
        }
    acc->ndirs++;
}

void sss_err_accum_result(const sss_err_accum *acc, double *rms, double *rel_rms, double *max_abs, double *rms_ref)
{
    const size_t C = acc->channels;
    double tn = 0.0, td = 0.0, tm = 0.0;
    for (size_t c = 0; c <= C; c++) {
        const double n = c < C ? acc->num[c] : tn, d = c < C ? acc->den[c] : td;
        const double m = c < C ? acc->max_abs[c] : tm;
        const double w = acc->area_sum * acc->ndirs * (c < C ? 1.0 : (double)C);
        if (c < C) {
            tn += n;
            td += d;
            tm = isnan(m) || isnan(tm) ? NAN : fmax(tm, m);
        }
        if (rms) rms[c] = w > 0.0 ? sqrt(n / w) : 0.0;
        if (rms_ref) rms_ref[c] = w > 0.0 ? sqrt(d / w) : 0.0;
        if (rel_rms) rel_rms[c] = isnan(m) ? NAN : d > 0.0 ? sqrt(n / d) : sqrt(n);
        if (max_abs) max_abs[c] = m;
    }
}

sss_result sss_decode_error(const sss_bake_file *approx, const sss_bake_file *ref, uint32_t ndirs, uint64_t seed,
                            double *rel_rms, double *rms, double *max_abs, sss_error *err)
{
    if (!approx || !ref || !rel_rms) return sss_fail(err, SSS_ERR_ARG, "decode error: NULL argument");
    if (ndirs == 0) return sss_fail(err, SSS_ERR_ARG, "decode error: no test directions");
    if (approx->mesh.nv != ref->mesh.nv || approx->channels != ref->channels || !ref->mesh.tri)
        return sss_fail(err, SSS_ERR_ARG, "decode error: files differ (%u vertices, %u channels vs %u, %u)",
                        approx->mesh.nv, approx->channels, ref->mesh.nv, ref->channels);
    const size_t nv = ref->mesh.nv, C = ref->channels;
    double *area = calloc(nv, sizeof *area);
    float *a = malloc(nv * C * sizeof *a), *r = malloc(nv * C * sizeof *r);
    if (!area || !a || !r) {
        free(area);
        free(a);
        free(r);
        return sss_fail(err, SSS_ERR_NOMEM, "decode error: out of memory for %zu vertices", nv);
    }
    sss_mesh_vertex_areas(&ref->mesh, area);
    sss_err_accum acc;
    sss_err_accum_init(&acc, (uint32_t)C, area, (uint32_t)nv);
    uint64_t s = seed;
    for (uint32_t t = 0; t < ndirs; t++) {
        double light[3];
        sss_rng_direction(&s, light);
        sss_decode_all(ref, light, r);
        sss_decode_all(approx, light, a);
        sss_err_accum_add(&acc, area, a, r, (uint32_t)nv);
    }
    double mx[SSS_MAX_CHANNELS + 1];
    sss_err_accum_result(&acc, rms, rel_rms, mx, NULL);
    if (max_abs) *max_abs = mx[C];
    free(area);
    free(a);
    free(r);
    return SSS_OK;
}
