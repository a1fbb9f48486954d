/* lloyd.c: 8-bit Lloyd–Max scalar quantiser for the baked integrals
 * (Hao–Varshney 2004 §4.1 quantises q to 8 bits with Lloyd's algorithm and
 * reports 50.99 dB SNR on its teapot).
 *
 * Training works on the sorted samples with double prefix sums, so one
 * Lloyd iteration costs 256 binary searches instead of a pass over the data.
 * More than 4 Mi samples are subsampled with a fixed stride: deterministic.
 */
#include "sss/lloyd.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define LEVELS 256
#define MAX_TRAIN (4u << 20)

/* Order-preserving map of a float to an unsigned key (negatives included). */
static uint32_t fkey(float f)
{
    uint32_t u;
    memcpy(&u, &f, 4);
    return (u & 0x80000000u) ? ~u : (u | 0x80000000u);
}

/* LSD radix sort of keys (4 passes of 8 bits). */
static int radix_sort(uint32_t *a, size_t n)
{
    uint32_t *b = malloc(n * sizeof *b + 1);
    if (!b) return 0;
    for (int shift = 0; shift < 32; shift += 8) {
        size_t cnt[257] = {0};
        for (size_t i = 0; i < n; i++) cnt[((a[i] >> shift) & 255) + 1]++;
        for (int k = 0; k < 256; k++) cnt[k + 1] += cnt[k];
        for (size_t i = 0; i < n; i++) b[cnt[(a[i] >> shift) & 255]++] = a[i];
        uint32_t *t = a; a = b; b = t;
    }
    free(b); /* after 4 passes the sorted data is back in the caller's array */
    return 1;
}

static float kfloat(uint32_t k)
{
    uint32_t u = (k & 0x80000000u) ? (k & 0x7FFFFFFFu) : ~k;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

/* First index in y[0, n) with y > t. */
static size_t upper(const float *y, size_t n, double t)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        size_t mid = lo + (hi - lo) / 2;
        if ((double)y[mid] > t) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

/* Index of the level nearest to x: the number of thresholds below x. */
static uint8_t encode(const double *thr, int nlev, float x)
{
    int lo = 0, hi = nlev - 1; /* thresholds thr[0 .. nlev-2] */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if ((double)x > thr[mid]) lo = mid + 1;
        else hi = mid;
    }
    return (uint8_t)lo;
}

/* Initial levels from high-resolution quantisation theory: the
 * MSE-optimal density of levels is proportional to p(x)^{1/3} (Panter–Dite),
 * so levels 1..255 go to the quantiles of the normalised p^{1/3} of a fine
 * histogram; level 0 is the minimum. Lloyd then only polishes. Starting from
 * plain sample quantiles (density ∝ p) crowds the levels where the data
 * crowds (near zero for baked integrals) and Lloyd is too slow to undo it. */
static int init_levels(const float *y, size_t n, int nlev, int pin, double *L)
{
    enum { B = 1 << 16 };
    double lo = y[0], hi = y[n - 1];
    for (int k = 0; k < nlev; k++) L[k] = lo;
    if (!(hi > lo)) return 1;
    double *h = calloc(B, sizeof *h);
    if (!h) return 0;
    double w = (hi - lo) / B;
    for (size_t k = 0; k < n; k++) {
        if (pin && (double)y[k] == lo) continue; /* the minimum's mass belongs to level 0 */
        long b = (long)(((double)y[k] - lo) / w);
        h[b < 0 ? 0 : b >= B ? B - 1 : b] += 1.0;
    }
    double tot = 0;
    for (int b = 0; b < B; b++) tot += (h[b] = cbrt(h[b]));
    double acc = 0;
    int k = pin ? 1 : 0;
    const int nfree = pin ? nlev - 1 : nlev; /* levels placed by quantile */
    const double off = pin ? 0.5 : -0.5;    /* quantile of level k: (k - off) / nfree */
    for (int b = 0; b < B && k < nlev; b++) {
        double next = acc + h[b];
        while (k < nlev && (k - off) / nfree * tot <= next) {
            double f = h[b] > 0 ? ((k - off) / nfree * tot - acc) / h[b] : 0.5;
            L[k++] = lo + (b + f) * w;
        }
        acc = next;
    }
    for (; k < nlev; k++) L[k] = hi;
    free(h);
    return 1;
}

sss_result sss_lloyd(const float *x, uint64_t count, uint32_t stride, uint32_t nlevels, int pin_min, float *levels,
                     uint8_t *idx, double *signal, double *noise, sss_error *err)
{
    if (count == 0 || stride == 0) return sss_fail(err, SSS_ERR_ARG, "lloyd8: no data");
    if (nlevels < 2 || nlevels > LEVELS) return sss_fail(err, SSS_ERR_ARG, "lloyd: %u levels (2 … 256)", nlevels);
    const int nlev = (int)nlevels, pin = pin_min != 0;
    uint64_t step = (count + MAX_TRAIN - 1) / MAX_TRAIN;
    size_t n = (size_t)((count + step - 1) / step);
    uint32_t *key = malloc(n * sizeof *key + 1);
    double *P = malloc((n + 1) * sizeof *P);
    if (!key || !P) { free(key); free(P); return sss_fail(err, SSS_ERR_NOMEM, "lloyd8: out of memory for %zu samples", n); }
    for (size_t k = 0; k < n; k++) key[k] = fkey(x[(size_t)(k * step) * stride]);
    if (!radix_sort(key, n)) { free(key); free(P); return sss_fail(err, SSS_ERR_NOMEM, "lloyd8: out of memory"); }
    float *y = (float *)key; /* sorted values, in place */
    for (size_t k = 0; k < n; k++) y[k] = kfloat(key[k]);
    P[0] = 0;
    for (size_t k = 0; k < n; k++) P[k + 1] = P[k] + y[k];

    double L[LEVELS];
    if (!init_levels(y, n, nlev, pin, L)) {
        free(key); free(P);
        return sss_fail(err, SSS_ERR_NOMEM, "lloyd8: out of memory");
    }
    /* Lloyd iterations: decision thresholds at midpoints, levels at the cell
     * centroids; level 0 stays pinned to the minimum when asked. */
    for (int it = 0; it < 5000; it++) {
        double change = 0, scale = fmax(fabs(L[nlev - 1]), fabs(L[0])) + 1e-300;
        size_t a = 0;
        for (int k = 0; k < nlev; k++) {
            size_t b = k + 1 < nlev ? upper(y, n, 0.5 * (L[k] + L[k + 1])) : n;
            if (b > a && (k > 0 || !pin)) {
                double c = (P[b] - P[a]) / (double)(b - a);
                change = fmax(change, fabs(c - L[k]) / scale);
                L[k] = c;
            }
            a = b;
        }
        if (change < 1e-13) break;
    }
    free(key);
    free(P);

    for (int k = 0; k < nlev; k++) levels[k] = (float)L[k];
    for (int k = 1; k < nlev; k++)
        if (levels[k] < levels[k - 1]) levels[k] = levels[k - 1];
    double thr[LEVELS];
    for (int k = 0; k + 1 < nlev; k++) thr[k] = 0.5 * ((double)levels[k] + (double)levels[k + 1]);
    thr[nlev - 1] = INFINITY;

    double S = 0, N = 0;
#pragma omp parallel for reduction(+ : S, N) schedule(static)
    for (int64_t k = 0; k < (int64_t)count; k++) {
        float v = x[(size_t)k * stride];
        uint8_t q = encode(thr, nlev, v);
        idx[(size_t)k * stride] = q;
        double e = (double)v - (double)levels[q];
        S += (double)v * v;
        N += e * e;
    }
    if (signal) *signal = S;
    if (noise) *noise = N;
    return SSS_OK;
}

sss_result sss_lloyd8(const float *x, uint64_t count, uint32_t stride, float levels[256], uint8_t *idx,
                      double *signal, double *noise, sss_error *err)
{
    return sss_lloyd(x, count, stride, LEVELS, 1, levels, idx, signal, noise, err);
}
