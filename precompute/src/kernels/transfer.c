/* transfer.c: the part of the Hao–Varshney 2004 §3.1 integrand that depends
 * only on the incident point x_i and the light direction ω_j,
 *   G(x_i, ω_j) = F_t(η, n_i·ω_j) · max(0, n_i·ω_j) · V(x_i, ω_j),
 * so that q(x_o, ω_j) = Σ_i w(o, i) G(x_i, ω_j) is a sparse × dense product.
 */
#include "sss/transfer.h"

#include <math.h>
#include <stdlib.h>

#include "kernels/progress.h"
#include "kernels/transfer.h"

float sss_transfer_one(const sss_mesh *mesh, const sss_vis *vis, uint32_t i, const double d[3], double eta,
                       int *traced, int *blocked)
{
    const float *nv = &mesh->nrm[3 * (size_t)i];
    double c = nv[0] * d[0] + nv[1] * d[1] + nv[2] * d[2];
    int t = c > 0.0, b = 0;
    float g = 0.0f;
    if (t) {
        b = vis && sss_vis_occluded(vis, i, d);
        if (!b) g = (float)(sss_ft(eta, c) * c);
    }
    if (traced) *traced = t;
    if (blocked) *blocked = b;
    return g;
}

sss_result sss_transfer_rows_ordered(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n,
                                     double eta, const uint32_t *order, uint32_t m0, uint32_t m1,
                                     const sss_cancel_flag *cancel, float *G, uint64_t *rays_out, uint64_t *occ_out,
                                     sss_error *err)
{
    if (!mesh->nrm) return sss_fail(err, SSS_ERR_ARG, "transfer: mesh has no normals");
    uint64_t rays = 0, occ = 0;
    int stop = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : rays, occ)
    for (int64_t m = m0; m < (int64_t)m1; m++) {
        if (stop) continue;
        if (sss_cancelled(cancel)) { stop = 1; continue; }
        const uint32_t i = order ? order[m] : (uint32_t)m;
        for (uint32_t j = 0; j < n; j++) {
            int traced, blocked;
            G[(size_t)m * n + j] = sss_transfer_one(mesh, vis, i, &dirs[3 * (size_t)j], eta, &traced, &blocked);
            rays += (uint64_t)traced;
            occ += (uint64_t)blocked;
        }
        sss_progress_tick(1);
    }
    if (stop) return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during visibility");
    if (rays_out) *rays_out = rays;
    if (occ_out) *occ_out = occ;
    return SSS_OK;
}

sss_result sss_transfer_rows(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n, double eta,
                             uint32_t v0, uint32_t v1, const sss_cancel_flag *cancel, float *G, uint64_t *rays_out,
                             uint64_t *occ_out, sss_error *err)
{
    return sss_transfer_rows_ordered(mesh, vis, dirs, n, eta, NULL, v0, v1, cancel, G, rays_out, occ_out, err);
}

sss_result sss_transfer_compute(const sss_mesh *mesh, const sss_vis *vis, const double *dirs, uint32_t n, double eta,
                                const sss_cancel_flag *cancel, float *G, uint64_t *rays_out, uint64_t *occ_out,
                                sss_error *err)
{
    return sss_transfer_rows(mesh, vis, dirs, n, eta, 0, mesh->nv, cancel, G, rays_out, occ_out, err);
}

void sss_transfer_axis(const sss_mesh *mesh, const double *dirs, uint32_t n, const uint32_t *order, uint32_t m0,
                       uint32_t m1, const float *G, int a, float *H)
{
#pragma omp parallel for schedule(static)
    for (int64_t m = m0; m < (int64_t)m1; m++) {
        const uint32_t i = order ? order[m] : (uint32_t)m;
        const float *nv = &mesh->nrm[3 * (size_t)i];
        for (uint32_t j = 0; j < n; j++) {
            const double *d = &dirs[3 * (size_t)j];
            const double c = nv[0] * d[0] + nv[1] * d[1] + nv[2] * d[2];
            const float g = G[(size_t)m * n + j];
            /* G ≠ 0 only where n_i·ω_j > 0 (μ_i = 1, sss_transfer_one) */
            H[(size_t)m * n + j] = g != 0.0f && c > 0.0 ? (float)((double)g / c * nv[a]) : 0.0f;
        }
    }
}

void sss_integrate(const sss_weights *nb, const float *G, uint32_t n, float *q)
{
    sss_integrate_hat(nb, NULL, G, n, q);
}

static void integrate_rows(const sss_weights *nb, const sss_weights *hat, const float *G, uint32_t n, int clamp,
                           float *q)
{
    const uint32_t C = nb->channels;
#pragma omp parallel
    {
        double *acc = calloc((size_t)n * C + 1, sizeof(double));
#pragma omp for schedule(dynamic, 64)
        for (int64_t r = 0; r < (int64_t)nb->nrows; r++) {
            if (!acc) continue;
            for (size_t k = 0; k < (size_t)n * C; k++) acc[k] = 0.0;
            /* Neighbours in increasing index order, then the row's
             * hat-function corrections in theirs (sss/hatweights.h): the
             * sum's rounding does not depend on the thread count. */
            for (int part = 0; part < (hat ? 2 : 1); part++) {
                const sss_weights *rw = part ? hat : nb;
                for (uint64_t e = rw->start[r]; e < rw->start[r + 1]; e++) {
                    const float *g = &G[(size_t)rw->idx[e] * n];
                    const float *w = &rw->w[e * C];
                    for (uint32_t c = 0; c < C; c++) {
                        double wc = w[c];
                        double *a = &acc[(size_t)c * n];
                        for (uint32_t j = 0; j < n; j++) a[j] += wc * g[j];
                    }
                }
            }
            /* W ≥ 0, so q ≥ 0; only the float weights' rounding can take a
             * sum with corrections below */
            for (uint32_t j = 0; j < n; j++)
                for (uint32_t c = 0; c < C; c++) {
                    const float x = (float)acc[(size_t)c * n + j];
                    q[((size_t)j * nb->nrows + (size_t)r) * C + c] = clamp && !(x > 0.0f) ? 0.0f : x;
                }
            sss_progress_tick(nb->start[r + 1] - nb->start[r]); /* a row costs its neighbours */
        }
        free(acc);
    }
}

void sss_integrate_hat(const sss_weights *nb, const sss_weights *hat, const float *G, uint32_t n, float *q)
{
    integrate_rows(nb, hat, G, n, hat != NULL, q);
}

void sss_integrate_hat_signed(const sss_weights *nb, const sss_weights *hat, const float *G, uint32_t n, float *q)
{
    integrate_rows(nb, hat, G, n, 0, q);
}
