/* decode_error.c: how far one stored form of q is from another (e.g. a
 * compressed file from the float bake it came from), measured per vertex
 * at random light directions that are not direction samples. The metric is
 * area-weighted so that a densely tessellated region does not count more
 * than its share of the surface. */
#include "sss/decode.h"

#include <math.h>
#include <stdlib.h>

#include "sss/random.h"

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
    double num[SSS_MAX_CHANNELS] = {0}, den[SSS_MAX_CHANNELS] = {0}, mx = 0.0, asum = 0.0;
    int anynan = 0;
    uint64_t s = seed;
    for (uint32_t t = 0; t < ndirs; t++) {
        double light[3];
        sss_rng_direction(&s, light);
        sss_decode_all(ref, light, r);
        sss_decode_all(approx, light, a);
        for (size_t v = 0; v < nv; v++)
            for (size_t c = 0; c < C; c++) {
                double e = (double)a[v * C + c] - r[v * C + c];
                num[c] += area[v] * e * e;
                den[c] += area[v] * (double)r[v * C + c] * r[v * C + c];
                if (isnan(e)) anynan = 1;
                else if (fabs(e) > mx) mx = fabs(e);
            }
    }
    for (size_t v = 0; v < nv; v++) asum += area[v];
    double tn = 0.0, td = 0.0;
    for (size_t c = 0; c < C; c++) {
        rel_rms[c] = den[c] > 0.0 ? sqrt(num[c] / den[c]) : sqrt(num[c]);
        if (rms) rms[c] = asum > 0.0 ? sqrt(num[c] / (asum * ndirs)) : 0.0;
        tn += num[c];
        td += den[c];
    }
    rel_rms[C] = td > 0.0 ? sqrt(tn / td) : sqrt(tn);
    if (rms) rms[C] = asum > 0.0 ? sqrt(tn / (asum * ndirs * (double)C)) : 0.0;
    if (anynan) {
        mx = NAN;
        for (size_t c = 0; c <= C; c++) rel_rms[c] = NAN;
    }
    if (max_abs) *max_abs = mx;
    free(area);
    free(a);
    free(r);
    return SSS_OK;
}
