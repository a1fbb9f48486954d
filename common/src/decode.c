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
        /* Per frame, fold the weights into the level tables:
         * T_r[k][x] = w_r · level_k[x] (3 rows × ≤ 3 channels × 256 floats,
         * 9 KiB, stays in L1), so each value costs three table loads and
         * two adds: the loop is bound by streaming the index rows. */
        float T[3][SSS_MAX_CHANNELS][256];
        for (size_t k = 0; k < ch; k++)
            for (int x = 0; x < 256; x++) {
                double L = f->levels[256 * k + (size_t)x];
                T[0][k][x] = (float)(w0 * L);
                T[1][k][x] = (float)(w1 * L);
                T[2][k][x] = (float)(w2 * L);
            }
        if (ch == 3) {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
            for (ptrdiff_t v = 0; v < (ptrdiff_t)nv; v++) {
                const size_t i = 3 * (size_t)v;
                out[i] = T[0][0][a[i]] + T[1][0][b[i]] + T[2][0][c[i]];
                out[i + 1] = T[0][1][a[i + 1]] + T[1][1][b[i + 1]] + T[2][1][c[i + 1]];
                out[i + 2] = T[0][2][a[i + 2]] + T[1][2][b[i + 2]] + T[2][2][c[i + 2]];
            }
        } else if (ch == 1) {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
            for (ptrdiff_t i = 0; i < nrow; i++) out[i] = T[0][0][a[i]] + T[1][0][b[i]] + T[2][0][c[i]];
        } else {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
            for (ptrdiff_t i = 0; i < nrow; i++) {
                const size_t k = (size_t)i % ch;
                out[i] = T[0][k][a[i]] + T[1][k][b[i]] + T[2][k][c[i]];
            }
        }
        return;
    }
    const float *a = f->q + (size_t)idx[0] * row;
    const float *b = f->q + (size_t)idx[1] * row;
    const float *c = f->q + (size_t)idx[2] * row;
    /* float weights: four-wide SIMD without conversions; the GPU computes
     * the same float expression */
    const float fw0 = (float)w0, fw1 = (float)w1, fw2 = (float)w2;
#ifdef _OPENMP
#pragma omp parallel for simd schedule(static) if (nrow >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nrow; i++) out[i] = fw0 * a[i] + fw1 * b[i] + fw2 * c[i];
}
