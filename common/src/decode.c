/* decode.c: q(x_v, ω) for an arbitrary light direction from a decoded .sss
 * file (Hao–Varshney 2004 §3.2; interpolation inside the spherical Delaunay
 * triangle of the direction samples, see sss/dirset.h).
 *
 * The per-frame work is one weighted sum of three direction rows, each a
 * contiguous block of nv * channels values (format.h's direction-major
 * layout), so the loop streams through memory. Sums are formed in double and
 * rounded once to float: at a direction sample the weights are (1, 0, 0) up
 * to rounding, and the stored float comes back exactly.
 */
#include "sss/decode.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "sss/dirset.h"

float sss_decode_sample(const sss_bake_file *f, uint32_t j, uint32_t v, uint32_t c)
{
    assert(j < f->dirs.n && v < f->mesh.nv && c < f->channels);
    size_t i = ((size_t)j * f->mesh.nv + v) * f->channels + c;
    if (f->quant == SSS_QUANT_LLOYD8) return f->levels[(size_t)c * 256 + f->qidx[i]];
    return f->q[i];
}

/* Rows of at least this many values are split across OpenMP threads (when
 * the library is built with OpenMP); below it the fork costs more than it
 * saves. */
#define PAR_MIN 65536

void sss_decode_all(const sss_bake_file *f, const double light[3], float *out)
{
    const size_t ch = f->channels, nv = f->mesh.nv, row = nv * ch;
    double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (f->dirs.n == 0 || !(len > 0.0) || !isfinite(len)) {
        /* No samples, or no direction: nothing to interpolate. */
        memset(out, 0, row * sizeof *out);
        return;
    }
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};
    uint32_t idx[3];
    double w[3];
    sss_dirset_lookup(&f->dirs, d, idx, w);
    const double w0 = w[0], w1 = w[1], w2 = w[2];
    const ptrdiff_t nrow = (ptrdiff_t)row;

    if (f->quant == SSS_QUANT_LLOYD8) {
        const uint8_t *a = f->qidx + (size_t)idx[0] * row;
        const uint8_t *b = f->qidx + (size_t)idx[1] * row;
        const uint8_t *c = f->qidx + (size_t)idx[2] * row;
        const float *L = f->levels;
        if (ch == 3) {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
            for (ptrdiff_t v = 0; v < (ptrdiff_t)nv; v++) {
                const size_t i = 3 * (size_t)v;
                for (size_t k = 0; k < 3; k++) {
                    const float *Lk = L + 256 * k;
                    out[i + k] = (float)(w0 * Lk[a[i + k]] + w1 * Lk[b[i + k]] + w2 * Lk[c[i + k]]);
                }
            }
        } else {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
            for (ptrdiff_t i = 0; i < nrow; i++) {
                const float *Lk = L + 256 * ((size_t)i % ch);
                out[i] = (float)(w0 * Lk[a[i]] + w1 * Lk[b[i]] + w2 * Lk[c[i]]);
            }
        }
        return;
    }
    const float *a = f->q + (size_t)idx[0] * row;
    const float *b = f->q + (size_t)idx[1] * row;
    const float *c = f->q + (size_t)idx[2] * row;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nrow; i++) out[i] = (float)(w0 * a[i] + w1 * b[i] + w2 * c[i]);
}
