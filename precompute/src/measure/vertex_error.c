/* vertex_error.c: error of a file's reconstruction against the exact
 * evaluator, per vertex (see sss/vertex_error.h). The exact q has no direction interpolation (§3.2)
 * and no compression (§4), so this one number covers every approximation
 * the file makes. */
#include "sss/vertex_error.h"
#include "sss/reconstruct.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/decode.h"
#include "sss/random.h"

/* A random unit direction not within 1e-6 rad of a direction sample (at a
 * sample the interpolation error vanishes, which would flatter the file). */
void sss_vertex_error_draw_direction(const sss_dirset *s, uint64_t *state, double d[3])
{
    for (;;) {
        sss_rng_direction(state, d);
        double best = -2.0;
        for (uint32_t j = 0; j < s->n; j++) {
            const double *w = s->dir + 3 * (size_t)j;
            best = fmax(best, d[0] * w[0] + d[1] * w[1] + d[2] * w[2]);
        }
        if (best < cos(1e-6)) return;
    }
}

sss_result sss_vertex_error_vs_exact(const sss_bake_file *f, const sss_exact *e, uint32_t ndirs, uint64_t seed,
                                     sss_vertex_error *out, sss_error *err)
{
    return sss_vertex_error_vs_exact_interp(f, e, ndirs, seed, SSS_INTERP_TRIANGLE, out, err);
}

sss_result sss_vertex_error_vs_exact_interp(const sss_bake_file *f, const sss_exact *e, uint32_t ndirs, uint64_t seed,
                                            sss_interp interp, sss_vertex_error *out, sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!f || !e || !out) return sss_fail(err, SSS_ERR_ARG, "vertex error: NULL argument");
    if (ndirs == 0) return sss_fail(err, SSS_ERR_ARG, "vertex error: no light directions");
    if (sss_exact_vertices(e) != f->mesh.nv || sss_exact_channels(e) != f->channels)
        return sss_fail(err, SSS_ERR_ARG, "vertex error: exact evaluator (%u vertices, %u channels) is not for this "
                        "file (%u, %u)", sss_exact_vertices(e), sss_exact_channels(e), f->mesh.nv, f->channels);
    const size_t nv = f->mesh.nv, C = f->channels;
    double *area = calloc(nv, sizeof *area);
    float *x = malloc(nv * C * sizeof *x), *r = malloc(nv * C * sizeof *r);
    if (!area || !x || !r) {
        free(area);
        free(x);
        free(r);
        return sss_fail(err, SSS_ERR_NOMEM, "vertex error: out of memory for %zu vertices", nv);
    }
    /* what a reader shows: the rows, plus the own term for an OWNT file */
    sss_reconstruct *rc = NULL;
    sss_result res = sss_reconstruct_create(f, &rc, err);
    if (res != SSS_OK) {
        free(area);
        free(x);
        free(r);
        return res;
    }
    sss_mesh_vertex_areas(&f->mesh, area);
    sss_err_accum acc;
    sss_err_accum_init(&acc, (uint32_t)C, area, (uint32_t)nv);
    uint64_t state = seed;
    for (uint32_t t = 0; t < ndirs; t++) {
        double d[3];
        sss_vertex_error_draw_direction(&f->dirs, &state, d);
        sss_exact_eval(e, d, x);
        sss_reconstruct_eval(rc, d, interp, r);
        sss_err_accum_add(&acc, area, r, x, (uint32_t)nv);
    }
    out->channels = (uint32_t)C;
    out->ndirs = ndirs;
    sss_err_accum_result(&acc, out->rms, out->rel_rms, out->max_abs, out->rms_exact);
    sss_reconstruct_destroy(rc);
    free(area);
    free(x);
    free(r);
    return SSS_OK;
}
