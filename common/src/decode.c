/* decode.c: q(x_v, ω) for an arbitrary light direction from a decoded .sss
 * file (Hao–Varshney 2004 §3.2; interpolation inside the spherical Delaunay
 * triangle of the direction samples, see sss/dirset.h; the paper's own
 * 4-nearest blend is kept beside it for the accuracy study, docs/accuracy.md).
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
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sss/dirset.h"
#include "sss/sh.h"

#if defined(__x86_64__) && defined(__GNUC__)
#define DECODE_X86 1 /* the wider copies of the block loops (sss_decode_isa) */
#include <immintrin.h>
#endif

float sss_decode_sample(const sss_bake_file *f, uint32_t j, uint32_t v, uint32_t c)
{
    assert(j < f->dirs.n && v < f->mesh.nv && c < f->channels);
    size_t i = ((size_t)j * f->mesh.nv + v) * f->channels + c;
    if (f->quant == SSS_QUANT_LLOYD8) return f->levels[(size_t)c * 256 + f->qidx[i]];
    if (f->quant == SSS_QUANT_FLOAT) return f->q[i];
    float out[SSS_MAX_CHANNELS];
    sss_decode_vertex(f, v, f->dirs.dir + 3 * (size_t)j, out);
    return out[c];
}

/* Rows of at least this many values are split across OpenMP threads (when
 * the library is built with OpenMP); below it the fork costs more than it
 * saves. */
#define PAR_MIN 65536

static void decode_compressed(const sss_bake_file *f, const double d[3], sss_interp interp, size_t first, size_t count,
                              float *out);

/* The paper's 4-nearest blend of lloyd8 rows of `row` codes each (rows j at
 * codes + j·row, channel i mod ch): out[i] = Σ_t w_t · levels_k[code_t[i]],
 * the weights folded into the level tables as the barycentric path does.
 * Shared by lloyd8 files and the reference values of refs files. */
static void nearest4_lloyd8(const sss_dirset *ds, const double d[3], const float *levels, const uint8_t *codes,
                            size_t row, size_t ch, float *out)
{
    uint32_t idx[4];
    double w[4];
    sss_dirset_nearest4(ds, d, idx, w);
    float T[4][SSS_MAX_CHANNELS][256];
    for (size_t t = 0; t < 4; t++)
        for (size_t k = 0; k < ch; k++)
            for (int x = 0; x < 256; x++) T[t][k][x] = (float)(w[t] * levels[256 * k + (size_t)x]);
    const uint8_t *r[4];
    for (int t = 0; t < 4; t++) r[t] = codes + (size_t)idx[t] * row;
    const ptrdiff_t nrow = (ptrdiff_t)row;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nrow >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nrow; i++) {
        const size_t k = (size_t)i % ch;
        out[i] = T[0][k][r[0][i]] + T[1][k][r[1][i]] + T[2][k][r[2][i]] + T[3][k][r[3][i]];
    }
}

/* The paper's 4-nearest blend of the stored rows (SSS_INTERP_NEAREST4) for
 * float and lloyd8 files: per value Σ_k w_k · q_k, the terms formed as the
 * barycentric path forms them (float products; lloyd8 folded tables). */
static void decode_nearest4(const sss_bake_file *f, const double d[3], float *out)
{
    const size_t ch = f->channels, row = (size_t)f->mesh.nv * ch;
    if (f->quant == SSS_QUANT_LLOYD8) {
        nearest4_lloyd8(&f->dirs, d, f->levels, f->qidx, row, ch, out);
        return;
    }
    uint32_t idx[4];
    double w[4];
    sss_dirset_nearest4(&f->dirs, d, idx, w);
    const ptrdiff_t nrow = (ptrdiff_t)row;
    const float *r[4];
    float fw[4];
    for (int t = 0; t < 4; t++) r[t] = f->q + (size_t)idx[t] * row, fw[t] = (float)w[t];
#ifdef _OPENMP
#pragma omp parallel for simd schedule(static) if (nrow >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nrow; i++) out[i] = fw[0] * r[0][i] + fw[1] * r[1][i] + fw[2] * r[2][i] + fw[3] * r[3][i];
}

void sss_decode_all(const sss_bake_file *f, const double light[3], float *out)
{
    sss_decode_all_interp(f, light, SSS_INTERP_TRIANGLE, out);
}

/* Vertices [first, first + count) of sss_decode_all_interp into out[0 …
 * count·channels − 1]: the whole mesh and any part of it run the same
 * loops over the same values, so a range is the slice of the whole to the
 * bit. NEAREST4 (the study's) is only asked for over the whole mesh. */
static void decode_span(const sss_bake_file *f, const double light[3], sss_interp interp, size_t first, size_t count,
                        float *out)
{
    const size_t ch = f->channels, nv = f->mesh.nv, row = nv * ch, off = first * ch, nval = count * ch;
    double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (f->dirs.n == 0 || !(len > 0.0) || !isfinite(len)) {
        /* No samples, or no direction: nothing to interpolate. */
        memset(out, 0, nval * sizeof *out);
        return;
    }
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};
    if (f->quant == SSS_QUANT_SH || f->quant == SSS_QUANT_REFS) {
        decode_compressed(f, d, interp, first, count, out);
        return;
    }
    if (interp == SSS_INTERP_NEAREST4) {
        decode_nearest4(f, d, out);
        return;
    }
    uint32_t idx[3];
    double w[3];
    sss_dirset_lookup(&f->dirs, d, idx, w);
    const double w0 = w[0], w1 = w[1], w2 = w[2];
    const ptrdiff_t nrow = (ptrdiff_t)nval;

    if (f->quant == SSS_QUANT_LLOYD8) {
        const uint8_t *a = f->qidx + (size_t)idx[0] * row + off;
        const uint8_t *b = f->qidx + (size_t)idx[1] * row + off;
        const uint8_t *c = f->qidx + (size_t)idx[2] * row + off;
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
            for (ptrdiff_t v = 0; v < (ptrdiff_t)count; v++) {
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
                const size_t k = (size_t)i % ch; /* off is a multiple of ch */
                out[i] = T[0][k][a[i]] + T[1][k][b[i]] + T[2][k][c[i]];
            }
        }
        return;
    }
    const float *a = f->q + (size_t)idx[0] * row + off;
    const float *b = f->q + (size_t)idx[1] * row + off;
    const float *c = f->q + (size_t)idx[2] * row + off;
    /* float weights: four-wide SIMD without conversions; the GPU computes
     * the same float expression */
    const float fw0 = (float)w0, fw1 = (float)w1, fw2 = (float)w2;
#ifdef _OPENMP
#pragma omp parallel for simd schedule(static) if (nrow >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nrow; i++) out[i] = fw0 * a[i] + fw1 * b[i] + fw2 * c[i];
}

void sss_decode_all_interp(const sss_bake_file *f, const double light[3], sss_interp interp, float *out)
{
    decode_span(f, light, interp, 0, f->mesh.nv, out);
}

void sss_decode_range(const sss_bake_file *f, const double light[3], uint32_t first, uint32_t count, float *out)
{
    if (first > f->mesh.nv || count > f->mesh.nv - first) return;
    decode_span(f, light, SSS_INTERP_TRIANGLE, first, count, out);
}

/* ---- the vector integral Q (format 1.7, Hao–Varshney 2004 §3.2) --------- */

int sss_decode_has_vector(const sss_bake_file *f) { return f && f->qvec != NULL; }

void sss_decode_vector_sample(const sss_bake_file *f, uint32_t j, uint32_t v, uint32_t c, float out[3])
{
    out[0] = out[1] = out[2] = 0.0f;
    if (!f->qvec || j >= f->dirs.n || v >= f->mesh.nv || c >= f->channels) return;
    const size_t i = ((size_t)j * f->mesh.nv + v) * f->channels + c;
    for (int a = 0; a < 3; a++) out[a] = f->qvec[3 * i + (size_t)a];
}

void sss_decode_vector_range(const sss_bake_file *f, const double light[3], sss_interp interp, uint32_t first,
                             uint32_t count, float *out)
{
    if (first > f->mesh.nv || count > f->mesh.nv - first) return;
    if (interp == SSS_INTERP_NEAREST4 && (first != 0 || count != f->mesh.nv)) return;
    const double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (!f->qvec || f->dirs.n == 0 || !(len > 0.0) || !isfinite(len)) {
        decode_span(f, light, interp, first, count, out); /* q's rows, or zeros without a direction */
        return;
    }
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};
    /* the samples and weights q's float path takes: three of the spherical
     * triangle, or the paper's four nearest (a zero fourth weight for the
     * triangle) */
    uint32_t idx[4] = {0, 0, 0, 0};
    double w[4] = {0, 0, 0, 0};
    if (interp == SSS_INTERP_NEAREST4) sss_dirset_nearest4(&f->dirs, d, idx, w);
    else sss_dirset_lookup(&f->dirs, d, idx, w);
    const int nt = interp == SSS_INTERP_NEAREST4 ? 4 : 3;
    const size_t ch = f->channels, row = 3 * (size_t)f->mesh.nv * ch, off = 3 * (size_t)first * ch;
    const float *r[4];
    float fw[4];
    for (int t = 0; t < nt; t++) {
        fw[t] = (float)w[t];
        r[t] = f->qvec + (size_t)idx[t] * row + off;
    }
    const float dx = (float)d[0], dy = (float)d[1], dz = (float)d[2];
    const ptrdiff_t nval = (ptrdiff_t)((size_t)count * ch);
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nval >= PAR_MIN)
#endif
    for (ptrdiff_t i = 0; i < nval; i++) {
        float Q[3];
        for (size_t a = 0; a < 3; a++) {
            /* q's float expression (decode_span, decode_nearest4) per
             * component; the GPU's (scatter.comp.glsl, VECTOR) */
            const size_t k = 3 * (size_t)i + a;
            Q[a] = nt == 4 ? fw[0] * r[0][k] + fw[1] * r[1][k] + fw[2] * r[2][k] + fw[3] * r[3][k]
                           : fw[0] * r[0][k] + fw[1] * r[1][k] + fw[2] * r[2][k];
        }
        /* q ≥ 0; Q̃·ω can fall below only between samples, or by rounding */
        const float q = Q[0] * dx + Q[1] * dy + Q[2] * dz;
        out[i] = q > 0.0f ? q : 0.0f;
    }
}

/* ---- compressed forms (format 1.1, Hao–Varshney 2004 §4) -------------- *
 * SH part (§4.1): q̃ = Σ_i c_i y_i(ω). Per call the SH basis is evaluated
 * once and folded into the dequantisation tables, T_c,i[x] = table_c,i[x] ·
 * y_i(ω), so a vertex costs ncoef table loads and adds per channel.
 * References (§4.2): their rows are interpolated over the direction triangle
 * exactly as an uncompressed lloyd8 file's; a coded vertex blends the three
 * reference values of its triangle with its weights, then adds its SH
 * delta (§4.3). q is physically ≥ 0, so the sum is clamped at 0; the GPU
 * path does the same. */

float sss_decode_ref_weight(const sss_refcode *r, uint32_t code)
{
    const double span = (double)r->w_hi - r->w_lo, wmax = r->wbits == 16 ? 65535.0 : 255.0;
    return (float)(r->w_lo + span * (code / wmax));
}

/* Weights of coded vertex k (sss_decode_ref_weight), the third
 * 1 − w0 − w1 in float. */
static void coded_weights(const sss_refcode *r, size_t k, float w[3])
{
    w[0] = sss_decode_ref_weight(r, r->w[2 * k]);
    w[1] = sss_decode_ref_weight(r, r->w[2 * k + 1]);
    w[2] = 1.0f - w[0] - w[1];
}

/* sss_decode_fold_sh, and for LLOYD4 each coefficient's 16 folded levels
 * into terms[(c·ncoef + i)·16 + x] (NULL: not wanted), the terms every pair
 * table entry is the float sum of. */
static void fold_sh_terms(const sss_bake_file *f, const double d[3], float *T, float *terms)
{
    const sss_shcode *s = &f->sh;
    const size_t L = sss_decode_fold_levels(s->kind), ntab = (size_t)f->channels * s->ncoef;
    double y[SSS_SH_MAX_COUNT];
    sss_sh_eval(s->order, d, y);
    const uint32_t M = sss_shq_linear_max(s->kind);
    if (M) {
        /* the linear kinds: one level, the step scale / M times y_i, in
         * double from the stored scale and rounded once; a coefficient then
         * costs one product code · T, which for a block of vertices is a
         * vector loop (the load-time layout below) where a 256-entry table
         * is one scalar load per code */
        for (size_t t = 0; t < ntab; t++) T[t] = (float)((double)s->scale[t] * y[t % s->ncoef] / M);
        return;
    }
    if (s->kind == SSS_SHQ_LLOYD4) {
        /* two coefficients a table: pair m of channel c (coefficients 2m,
         * 2m + 1) at T[(c·P + m)·256 + (x0 | x1 << 4)] = t_2m[x0] + t_2m+1[x1],
         * each term as below; an odd last coefficient's 16 levels after all
         * pairs, at T[C·P·256 + c·16 + x]. A pair of codes then costs one
         * load where it cost two (sss_decode_fold_floats). */
        const size_t N = s->ncoef, P = N / 2, C = f->channels;
        float own[SSS_MAX_CHANNELS * SSS_SH_MAX_COUNT * 16];
        float *t = terms ? terms : own;
        for (size_t e = 0; e < C * N; e++)
            for (size_t x = 0; x < 16; x++) t[e * 16 + x] = (float)(s->table[e * 16 + x] * y[e % N]);
        for (size_t c = 0; c < C; c++) {
            for (size_t m = 0; m < P; m++) {
                const float *t0 = t + (c * N + 2 * m) * 16, *t1 = t0 + 16;
                float *Tm = T + (c * P + m) * 256;
                for (size_t x1 = 0; x1 < 16; x1++)
                    for (size_t x0 = 0; x0 < 16; x0++) Tm[x0 | x1 << 4] = t0[x0] + t1[x1];
            }
            if (N & 1)
                for (size_t x = 0; x < 16; x++) T[C * P * 256 + c * 16 + x] = t[(c * N + N - 1) * 16 + x];
        }
        return;
    }
    for (size_t t = 0; t < ntab; t++) {
        const double yi = y[t % s->ncoef];
        for (size_t x = 0; x < L; x++) T[t * L + x] = (float)(s->table[t * L + x] * yi);
    }
}

void sss_decode_fold_sh(const sss_bake_file *f, const double d[3], float *T) { fold_sh_terms(f, d, T, NULL); }

uint32_t sss_decode_fold_levels(uint32_t kind) { return sss_shq_linear_max(kind) ? 1 : sss_shq_levels(kind); }

uint64_t sss_decode_fold_floats(uint32_t kind, uint32_t channels, uint32_t ncoef)
{
    if (kind == SSS_SHQ_LLOYD4) return (uint64_t)channels * ((uint64_t)ncoef / 2 * 256 + (ncoef & 1u) * 16);
    return (uint64_t)channels * ncoef * sss_decode_fold_levels(kind);
}

/* Folded SH tables for direction d, allocated (NULL when out of memory);
 * for LLOYD4 followed by the 16-level term tables (fold_sh_terms) at
 * T + sss_decode_fold_floats, which the wider copies of the block loops
 * look up with vector permutes (planes_nibble_avx2, _avx512). */
static float *fold_sh(const sss_bake_file *f, const double d[3])
{
    const size_t n = (size_t)sss_decode_fold_floats(f->sh.kind, f->channels, f->sh.ncoef);
    const size_t nt = f->sh.kind == SSS_SHQ_LLOYD4 ? (size_t)f->channels * f->sh.ncoef * 16 : 0;
    float *T = malloc((n + nt + 1) * sizeof *T);
    if (T) fold_sh_terms(f, d, T, nt ? T + n : NULL);
    return T;
}

/* Σ_i T[(c·ncoef + i)·L + code_i] for every channel c of coded vertex k,
 * into acc[0 … C−1]: each channel summed in coefficient order in float, as
 * the coded shader sums (so the GPU's result stays the C decoder's to the
 * bit). A sum of ncoef terms is a chain of dependent adds, so with three
 * channels the three chains advance together, one term each per step
 * (the latency of one add covers three loads); one loop per kind, the table
 * width a constant. TERM(e) is the term of code element e of the vertex. */
#define SH_SUMS(TERM)                                                                                                  \
    do {                                                                                                               \
        if (C == 3) {                                                                                                  \
            float a0 = 0.0f, a1 = 0.0f, a2 = 0.0f;                                                                     \
            for (size_t i = 0; i < ncoef; i++) {                                                                       \
                a0 += TERM(i);                                                                                         \
                a1 += TERM(ncoef + i);                                                                                 \
                a2 += TERM(2 * ncoef + i);                                                                             \
            }                                                                                                          \
            acc[0] = a0, acc[1] = a1, acc[2] = a2;                                                                     \
        } else {                                                                                                       \
            for (size_t c = 0; c < C; c++) {                                                                           \
                float a = 0.0f;                                                                                        \
                for (size_t i = 0; i < ncoef; i++) a += TERM(c * ncoef + i);                                           \
                acc[c] = a;                                                                                            \
            }                                                                                                          \
        }                                                                                                              \
    } while (0)

/* The linear kinds: the product rounded, then summed (the GPU's precise
 * order) */
static inline float l16_term(const uint8_t *p, const float *T, size_t e)
{
    const float prod = (float)(int16_t)(uint16_t)(p[2 * e] | p[2 * e + 1] << 8) * T[e];
    return prod;
}
static inline float l8_term(const uint8_t *p, const float *T, size_t e)
{
    const float prod = (float)(int8_t)p[e] * T[e];
    return prod;
}

static inline void sh_sums(const sss_shcode *s, const float *T, size_t C, size_t k, float *acc)
{
    const size_t ncoef = s->ncoef, e0 = k * C * ncoef;
    switch (s->kind) {
    case SSS_SHQ_LINEAR16: {
        const uint8_t *p = s->code + 2 * e0;
#define TERM_L16(e) l16_term(p, T, (e))
        SH_SUMS(TERM_L16);
#undef TERM_L16
        break;
    }
    case SSS_SHQ_LLOYD4: { /* the pairs' tables, then an odd last coefficient's (sss_decode_fold_sh) */
        const size_t P = ncoef / 2;
        for (size_t c = 0; c < C; c++) {
            const size_t e = e0 + c * ncoef;
            float a = 0.0f;
            for (size_t m = 0; m < P; m++)
                a += T[(c * P + m) * 256 + (sss_shq_code(s->code, s->kind, e + 2 * m) |
                                            sss_shq_code(s->code, s->kind, e + 2 * m + 1) << 4)];
            if (ncoef & 1) a += T[C * P * 256 + c * 16 + sss_shq_code(s->code, s->kind, e + ncoef - 1)];
            acc[c] = a;
        }
        break;
    }
    case SSS_SHQ_LINEAR8: {
        const uint8_t *p = s->code + e0;
#define TERM_L8(e) l8_term(p, T, (e))
        SH_SUMS(TERM_L8);
#undef TERM_L8
        break;
    }
    default: { /* LLOYD8: one byte per code, 256 levels */
        const uint8_t *p = s->code + e0;
#define TERM_B(e) T[(e) * 256 + p[(e)]]
        SH_SUMS(TERM_B);
#undef TERM_B
    }
    }
}
#undef SH_SUMS

/* Reference values at d: R[k·C + c] for every reference k (lloyd8
 * interpolation between the three direction rows). */
static void ref_values(const sss_bake_file *f, const double d[3], sss_interp interp, float *R)
{
    const sss_refcode *r = &f->ref;
    const size_t C = f->channels, row = (size_t)r->nref * C;
    uint32_t idx[3];
    double w[3];
    if (interp == SSS_INTERP_NEAREST4) {
        /* the paper's four nearest rows (§3.2), for the study only */
        nearest4_lloyd8(&f->dirs, d, r->levels, r->idx, row, C, R);
        return;
    }
    sss_dirset_lookup(&f->dirs, d, idx, w);
    const uint8_t *a = r->idx + idx[0] * row, *b = r->idx + idx[1] * row, *c = r->idx + idx[2] * row;
    float T[3][SSS_MAX_CHANNELS][256];
    for (size_t k = 0; k < C; k++)
        for (int x = 0; x < 256; x++) {
            double L = r->levels[256 * k + (size_t)x];
            T[0][k][x] = (float)(w[0] * L);
            T[1][k][x] = (float)(w[1] * L);
            T[2][k][x] = (float)(w[2] * L);
        }
    /* reference by reference, the channels inner: no division per value
     * to find its channel */
    const ptrdiff_t nref = (ptrdiff_t)r->nref;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if ((ptrdiff_t)row >= PAR_MIN)
#endif
    for (ptrdiff_t k = 0; k < nref; k++)
        for (size_t ch = 0; ch < C; ch++) {
            const size_t i = (size_t)k * C + ch;
            R[i] = T[0][ch][a[i]] + T[1][ch][b[i]] + T[2][ch][c[i]];
        }
}

/* The blend of coded vertex k's three reference values (§4.2), every
 * channel, into x[0 … C−1]: weights from wt (8-bit codes, tabulated per
 * call) or coded_weights, each channel's sum in float, the products and
 * sums in this order (the coded shader's). Float, not double: its rounding
 * (a few float ulps of the largest reference value) is far below the
 * reference values' 8-bit quantisation (measured in docs/benchmarks.md,
 * "Run-time instruction sets, 4-bit codes by permutes, the references'
 * blend in float"), and a software GPU emulates double lane by lane. The
 * triangle and weights are shared by the channels: read once. */
static inline void coded_blend(const sss_bake_file *f, const float *R, const float *wt, size_t k, size_t C, float *x)
{
    const sss_refcode *r = &f->ref;
    float w[3];
    if (wt) {
        w[0] = wt[r->w[2 * k]];
        w[1] = wt[r->w[2 * k + 1]];
        w[2] = 1.0f - w[0] - w[1];
    } else {
        coded_weights(r, k, w);
    }
    const uint32_t *t = r->ref_tri + 3 * (size_t)r->vtri[k];
    const float *R0 = R + t[0] * C, *R1 = R + t[1] * C, *R2 = R + t[2] * C;
    for (size_t c = 0; c < C; c++) x[c] = w[0] * R0[c] + w[1] * R1[c] + w[2] * R2[c];
}

/* Values of coded vertex k, all channels, into out[0 … C−1], from the
 * reference values R (NULL without references) and the vertex's SH sums
 * sh[0 … C−1]: blend + SH delta (§4.3), clamped at 0. */
static inline void coded_finish(const sss_bake_file *f, const float *R, const float *wt, size_t k, const float *sh,
                                float *out)
{
    const size_t C = f->channels;
    float x[SSS_MAX_CHANNELS] = {0};
    if (f->quant == SSS_QUANT_REFS) coded_blend(f, R, wt, k, C, x);
    for (size_t c = 0; c < C; c++) {
        x[c] += sh[c];
        out[c] = x[c] > 0.0f ? x[c] : 0.0f;
    }
}

/* coded_finish with the SH sums of the per-vertex loop (sh_sums); T may be
 * NULL when there is no SH part. */
static inline void coded_values(const sss_bake_file *f, const float *R, const float *T, const float *wt, size_t k,
                                float *out)
{
    float sh[SSS_MAX_CHANNELS] = {0};
    if (T && f->sh.ncoef) sh_sums(&f->sh, T, f->channels, k, sh);
    coded_finish(f, R, wt, k, sh, out);
}

/* ---- the load-time layout (sss_decode_prepare) ------------------------ *
 * The file keeps each vertex's C·ncoef codes together (format.h), so the
 * per-vertex loop above is one chain of dependent adds per channel.
 * Transposed once at load, code e of a block's coded vertices contiguous
 * (plane_at), one step of the loop over e serves the block: the adds of
 * different vertices are independent, and for the linear kinds (one
 * product per code) the loop over the block is a vector loop, one vertex
 * per lane. Each vertex's terms are still formed and added in coefficient
 * order (a = 0; a += term_0; a += term_1 …), so the result is sh_sums's to
 * the bit, and the GPU's (scatter_coded.comp.glsl). */

/* Vertices per block: the block's C sums (3 KiB) stay in L1 while the
 * loop walks the C·ncoef planes. */
#define SH_BLOCK 256

/* Where the load-time layouts keep element e (of P per vertex) of coded
 * vertex k: in groups of G vertices (G a multiple of SH_BLOCK), the P
 * planes of a group contiguous (G apart), then the next group's. With G =
 * SH_BLOCK a block's codes are one run of memory, read front to back: the
 * hardware prefetcher follows one stream, where P planes ncoded apart (27
 * for SH order 3 in RGB) were P streams, too many for it, so that with the
 * codes out of cache (the viewer decodes between draws) each plane's loads
 * waited on memory (docs/benchmarks.md, "The references' blend from a
 * load-time table"). The last group is padded to G. */
static inline size_t plane_at(size_t k, size_t e, size_t P, size_t G) { return ((k / G) * P + e) * G + k % G; }

/* Elements of such a layout of P planes over n coded vertices. */
static inline size_t planes_size(size_t n, size_t P, size_t G) { return (n + G - 1) / G * G * P; }

/* Planes per coded vertex of f's SH layout (LLOYD4: one per pair of a
 * channel's codes and one for an odd last code). */
static inline size_t sh_nplanes(const sss_shcode *s, size_t C)
{
    return s->kind == SSS_SHQ_LLOYD4 ? C * ((s->ncoef + 1) / 2) : C * s->ncoef;
}

/* The SH layout's group: blocks (SH_BLOCK) up to 64 bytes of codes a
 * vertex, where they measured faster (SH order 3: 27 bytes in RGB linear8,
 * 15 in lloyd4); above, one group of all the coded vertices, plain
 * coefficient-major (order 7 in linear16, 294 bytes a vertex, measured
 * 20 % slower in blocks, docs/benchmarks.md). */
static inline size_t sh_group(const sss_shcode *s, size_t C)
{
    const size_t bytes = sh_nplanes(s, C) * (s->kind == SSS_SHQ_LINEAR16 ? 2 : 1);
    return bytes <= 64 ? SH_BLOCK : (s->ncoded + SH_BLOCK - 1) / SH_BLOCK * SH_BLOCK;
}

/* The load-time layout of the references' blend (sss_refcode.blend): per
 * coded vertex one 16-byte record, in order, of its first two weights as
 * the floats coded_blend forms from the codes (sss_decode_ref_weight; the
 * third, 1 − w0 − w1, is formed per frame as before) and its triangle's
 * three references as 16-bit indices. A frame's blend then no longer
 * converts 16-bit weight codes (two double divisions a vertex) nor follows
 * vtri into ref_tri. One stream over the whole frame: as five planes per
 * block (two of weights, three of references, 256 vertices each) the
 * blend's loads of memory the viewer's draw had evicted waited on five
 * short streams per block that the hardware prefetcher had to find anew
 * each time (docs/benchmarks.md, "The blend's records in one stream").
 * Built when the references number at most 65536 (3 % of 2.1 million
 * vertices); above, the blend reads the codes (blend_block_c). Returns 0,
 * or −1 when out of memory (nothing built). */
static int prepare_blend(sss_bake_file *f)
{
    sss_refcode *r = &f->ref;
    const size_t n = f->sh.ncoded;
    if (f->quant != SSS_QUANT_REFS || !n || !r->w || !r->vtri || !r->ref_tri || r->nref > 65536) return 0;
    struct sss_blend_rec *rec = calloc(n, sizeof *rec);
    if (!rec) return -1;
    for (size_t k = 0; k < n; k++) {
        float w[3];
        coded_weights(r, k, w);
        const uint32_t *t = r->ref_tri + 3 * (size_t)r->vtri[k];
        rec[k].w0 = w[0], rec[k].w1 = w[1];
        for (size_t j = 0; j < 3; j++) rec[k].t[j] = (uint16_t)t[j];
    }
    r->blend = rec;
    r->blend_of = r->w;
    return 0;
}

int sss_decode_prepare(sss_bake_file *f)
{
    sss_shcode *s = &f->sh;
    free(s->planes);
    s->planes = NULL;
    s->planes_of = NULL;
    free(f->ref.blend);
    f->ref.blend = NULL;
    f->ref.blend_of = NULL;
    if ((f->quant != SSS_QUANT_SH && f->quant != SSS_QUANT_REFS) || !s->ncoef || !s->ncoded || !s->code ||
        !sss_shq_levels(s->kind))
        return 0;
    const size_t n = s->ncoded, C = f->channels, N = s->ncoef, E = C * N;
    const int wide = s->kind == SSS_SHQ_LINEAR16;
    const size_t Np = sh_nplanes(s, C), G = sh_group(s, C);
    void *p = calloc(planes_size(n, Np, G), wide ? sizeof(int16_t) : 1);
    if (!p) return -1;
    if (s->kind == SSS_SHQ_LLOYD4) {
        /* one plane per pair of a channel's codes, the byte x0 | x1 << 4
         * (the index into the pair's folded table), then an odd last code:
         * channel c's planes from c·Q, Q = ⌈N / 2⌉ */
        const size_t P = N / 2, Q = (N + 1) / 2;
        uint8_t *b = p;
        for (size_t k = 0; k < n; k++)
            for (size_t c = 0; c < C; c++) {
                const uint64_t e = (uint64_t)k * E + c * N;
                for (size_t m = 0; m < P; m++)
                    b[plane_at(k, c * Q + m, Np, G)] = (uint8_t)(sss_shq_code(s->code, s->kind, e + 2 * m) |
                                                       sss_shq_code(s->code, s->kind, e + 2 * m + 1) << 4);
                if (N & 1) b[plane_at(k, c * Q + P, Np, G)] = (uint8_t)sss_shq_code(s->code, s->kind, e + N - 1);
            }
    } else {
        for (size_t k = 0; k < n; k++)
            for (size_t e = 0; e < E; e++) {
                const uint32_t x = sss_shq_code(s->code, s->kind, (uint64_t)k * E + e);
                if (wide) ((int16_t *)p)[plane_at(k, e, E, G)] = (int16_t)(uint16_t)x;
                else ((uint8_t *)p)[plane_at(k, e, E, G)] = (uint8_t)x;
            }
    }
    s->planes = p;
    s->planes_of = s->code;
    return prepare_blend(f);
}


/* The block loops below are compiled once per instruction set (coded_block
 * and its callers, forced inline into block_baseline, block_avx2 and
 * block_avx512), so each copy is vectorised for its set. */
#if defined(__GNUC__)
#define BLOCK_INLINE static inline __attribute__((always_inline))
#else
#define BLOCK_INLINE static inline
#endif

/* a[b] += term(plane i, b) for the m planes from p (n codes apart), for
 * b < nb, plane after plane: three planes per pass over the block, each
 * vertex's adds still one after the other in plane order, so that a[] is
 * loaded and stored once per three terms. TERM(q, i, b) is code b of plane
 * q's term (the folded step's product for the linear kinds, the folded
 * table's entry for the Lloyd kinds). */
#define PLANE_SUMS(NAME, CODE, TERM)                                                                                   \
    BLOCK_INLINE void NAME(float *restrict a, const CODE *restrict p, size_t n, const float *restrict T, size_t L, size_t m, \
                     size_t nb)                                                                                        \
    {                                                                                                                  \
        (void)L;                                                                                                       \
        size_t i = 0;                                                                                                  \
        for (; i + 3 <= m; i += 3) {                                                                                   \
            const CODE *restrict p0 = p + i * n, *restrict p1 = p0 + n, *restrict p2 = p1 + n;                         \
            for (size_t b = 0; b < nb; b++) {                                                                          \
                float x = a[b];                                                                                        \
                const float y0 = TERM(p0, i, b);                                                                       \
                x += y0;                                                                                               \
                const float y1 = TERM(p1, i + 1, b);                                                                   \
                x += y1;                                                                                               \
                const float y2 = TERM(p2, i + 2, b);                                                                   \
                x += y2;                                                                                               \
                a[b] = x;                                                                                              \
            }                                                                                                          \
        }                                                                                                              \
        for (; i < m; i++) {                                                                                           \
            const CODE *restrict p0 = p + i * n;                                                                       \
            for (size_t b = 0; b < nb; b++) {                                                                          \
                const float y0 = TERM(p0, i, b);                                                                       \
                a[b] += y0;                                                                                            \
            }                                                                                                          \
        }                                                                                                              \
    }
#define TERM_LINEAR(q, i, b) ((float)(q)[b] * T[i]) /* l8_term, l16_term */
#define TERM_TABLE(q, i, b) (T[(i) * L + (q)[b]])
PLANE_SUMS(planes_linear8, int8_t, TERM_LINEAR)
PLANE_SUMS(planes_linear16, int16_t, TERM_LINEAR)
PLANE_SUMS(planes_table, uint8_t, TERM_TABLE)
#undef TERM_LINEAR
#undef TERM_TABLE
#undef PLANE_SUMS

/* 4-bit codes on the wider sets: a[b] += t_2m[x0] + t_2m+1[x1] for each
 * pair plane m < P of the channel (codes x0 | x1 << 4, planes n apart from
 * p), then a[b] += t_N−1[x] for an odd last plane (odd), t the channel's
 * 16-level term tables (t + i·16 for coefficient i). The pair tables hold
 * exactly these float sums t_2m[x0] + t_2m+1[x1] (fold_sh_terms), so this is
 * planes_table's sum to the bit, with the 16-entry lookups done by vector
 * permutes (16 lanes in one on AVX-512, two of 8 and a blend on AVX2) where
 * no baseline instruction looks up a table. Vertices past the last full
 * vector: the same sums, one at a time. */
#ifdef DECODE_X86
static inline void nibble_tail(float *restrict a, const uint8_t *restrict p, size_t n, const float *restrict t,
                               size_t P, int odd, size_t b0, size_t nb)
{
    for (size_t b = b0; b < nb; b++) {
        float x = a[b];
        for (size_t m = 0; m < P; m++) {
            const uint8_t v = p[m * n + b];
            const float y = t[2 * m * 16 + (v & 15u)] + t[(2 * m + 1) * 16 + (v >> 4)];
            x += y;
        }
        if (odd) x += t[2 * P * 16 + p[P * n + b]];
        a[b] = x;
    }
}

__attribute__((target("avx2"))) static void planes_nibble_avx2(float *restrict a, const uint8_t *restrict p, size_t n,
                                                              const float *restrict t, size_t P, int odd, size_t nb)
{
    const __m256i lo4 = _mm256_set1_epi32(15);
    size_t b = 0;
    for (; b + 8 <= nb; b += 8) {
        __m256 x = _mm256_loadu_ps(a + b);
        for (size_t m = 0; m <= P; m++) {
            if (m == P && !odd) break;
            const __m256i v = _mm256_cvtepu8_epi32(_mm_loadl_epi64((const __m128i *)(p + m * n + b)));
            /* 16 levels as two 8-lane permutes, bit 3 of the code picks the half */
            const float *t0 = t + (m == P ? 2 * P : 2 * m) * 16;
            const __m256i x0 = m == P ? v : _mm256_and_si256(v, lo4);
            __m256 y = _mm256_blendv_ps(_mm256_permutevar8x32_ps(_mm256_loadu_ps(t0), x0),
                                        _mm256_permutevar8x32_ps(_mm256_loadu_ps(t0 + 8), x0),
                                        _mm256_castsi256_ps(_mm256_slli_epi32(x0, 28)));
            if (m < P) {
                const float *t1 = t0 + 16;
                const __m256i x1 = _mm256_srli_epi32(v, 4);
                const __m256 y1 = _mm256_blendv_ps(_mm256_permutevar8x32_ps(_mm256_loadu_ps(t1), x1),
                                                   _mm256_permutevar8x32_ps(_mm256_loadu_ps(t1 + 8), x1),
                                                   _mm256_castsi256_ps(_mm256_slli_epi32(x1, 28)));
                y = _mm256_add_ps(y, y1);
            }
            x = _mm256_add_ps(x, y);
        }
        _mm256_storeu_ps(a + b, x);
    }
    nibble_tail(a, p, n, t, P, odd, b, nb);
}

__attribute__((target("avx512f"))) static void planes_nibble_avx512(float *restrict a, const uint8_t *restrict p,
                                                                   size_t n, const float *restrict t, size_t P, int odd,
                                                                   size_t nb)
{
    const __m512i lo4 = _mm512_set1_epi32(15);
    size_t b = 0;
    for (; b + 16 <= nb; b += 16) {
        __m512 x = _mm512_loadu_ps(a + b);
        for (size_t m = 0; m < P; m++) {
            const __m512i v = _mm512_cvtepu8_epi32(_mm_loadu_si128((const __m128i *)(p + m * n + b)));
            const float *t0 = t + 2 * m * 16;
            const __m512 y = _mm512_add_ps(_mm512_permutexvar_ps(_mm512_and_si512(v, lo4), _mm512_loadu_ps(t0)),
                                           _mm512_permutexvar_ps(_mm512_srli_epi32(v, 4), _mm512_loadu_ps(t0 + 16)));
            x = _mm512_add_ps(x, y);
        }
        if (odd) {
            const __m512i v = _mm512_cvtepu8_epi32(_mm_loadu_si128((const __m128i *)(p + P * n + b)));
            x = _mm512_add_ps(x, _mm512_permutexvar_ps(v, _mm512_loadu_ps(t + 2 * P * 16)));
        }
        _mm512_storeu_ps(a + b, x);
    }
    nibble_tail(a, p, n, t, P, odd, b, nb);
}
#endif

/* The linear kinds on the wider sets, in blocks (n = SH_BLOCK): a[b] += Σ_i
 * (float)code_i · T[i], the m planes' terms added in plane order, as
 * planes_linear8 / planes_linear16 add them: three planes a pass over the
 * block, each vector's three terms summed in a register, one code load,
 * widening and conversion per plane and vector, where the compiler's
 * copies widened 8-bit codes through 16 bits and the halves of 256-bit
 * vectors (SH order 3 in linear8: the one-thread decode 0.19 → 0.12 ms on
 * the 100K dragon). All planes a vector was faster with the codes in cache
 * but, hopping across the block's planes, slower with them evicted
 * (docs/benchmarks.md, "The blend four vertices a vector"). The AVX2 and
 * AVX-512 copies are one macro at two vector widths (the same machine code
 * as when they were written out).
 * Vertices past the last full vector: the same sums, one at a time. */
#ifdef DECODE_X86
#define LINEAR_TAIL(CODE)                                                                                              \
    for (; b < nb; b++) {                                                                                              \
        float x = a[b];                                                                                                \
        for (size_t i = 0; i < m; i++) {                                                                               \
            const float y = (float)((const CODE *)p)[i * n + b] * T[i];                                                \
            x += y;                                                                                                    \
        }                                                                                                              \
        a[b] = x;                                                                                                      \
    }
/* One pass over the block for planes [i0, i1) (at most three); three
 * written out, since GCC keeps the loop over them, and its counter and
 * branch per plane and vector were a third of the loop's instructions. */
#define LINEAR_PASS(VEC, W, LOAD, WIDEN, CVT, MUL, ADD, SET1, LD, ST, CODE)                                          \
    {                                                                                                                \
    if (i1 - i0 == 3) {                                                                                              \
        const CODE *q0 = (const CODE *)p + i0 * n, *q1 = q0 + n, *q2 = q1 + n;                                       \
        const VEC t0 = SET1(T[i0]), t1 = SET1(T[i0 + 1]), t2 = SET1(T[i0 + 2]);                                      \
        for (size_t b = 0; b + W <= nb; b += W) {                                                                    \
            VEC x = ADD(LD(a + b), MUL(CVT(WIDEN(LOAD(q0 + b))), t0));                                               \
            x = ADD(x, MUL(CVT(WIDEN(LOAD(q1 + b))), t1));                                                           \
            ST(a + b, ADD(x, MUL(CVT(WIDEN(LOAD(q2 + b))), t2)));                                                    \
        }                                                                                                            \
    } else                                                                                                           \
        for (size_t b = 0; b + W <= nb; b += W) {                                                                    \
            VEC x = LD(a + b);                                                                                       \
            for (size_t i = i0; i < i1; i++)                                                                         \
                x = ADD(x, MUL(CVT(WIDEN(LOAD((const CODE *)p + i * n + b))), SET1(T[i])));                          \
            ST(a + b, x);                                                                                            \
        }                                                                                                            \
    }
/* planes_linear_avx2 and planes_linear_avx512: the passes, then the tail;
 * X the intrinsics' prefix, LOAD16 and LOAD8 W codes' load. */
#define PLANES_LINEAR(NAME, TARGET, VEC, W, X, LOAD16, LOAD8)                                                         \
    __attribute__((target(TARGET))) static void NAME(float *restrict a, const void *restrict p, int wide, size_t n,   \
                                                     const float *restrict T, size_t m, size_t nb)                     \
    {                                                                                                                \
        for (size_t i0 = 0; i0 < m; i0 += 3) {                                                                       \
            const size_t i1 = i0 + 3 < m ? i0 + 3 : m;                                                               \
            if (wide)                                                                                                \
                LINEAR_PASS(VEC, W, LOAD16, X##_cvtepi16_epi32, X##_cvtepi32_ps, X##_mul_ps, X##_add_ps,             \
                            X##_set1_ps, X##_loadu_ps, X##_storeu_ps, int16_t)                                       \
            else                                                                                                     \
                LINEAR_PASS(VEC, W, LOAD8, X##_cvtepi8_epi32, X##_cvtepi32_ps, X##_mul_ps, X##_add_ps,               \
                            X##_set1_ps, X##_loadu_ps, X##_storeu_ps, int8_t)                                        \
        }                                                                                                            \
        size_t b = nb / W * W;                                                                                       \
        if (wide) LINEAR_TAIL(int16_t) else LINEAR_TAIL(int8_t)                                                      \
    }
#define LOAD_128(q) _mm_loadu_si128((const __m128i *)(q))
#define LOAD_64(q) _mm_loadl_epi64((const __m128i *)(q))
#define LOAD_256(q) _mm256_loadu_si256((const __m256i *)(q))
PLANES_LINEAR(planes_linear_avx2, "avx2", __m256, 8, _mm256, LOAD_128, LOAD_64)
PLANES_LINEAR(planes_linear_avx512, "avx512f", __m512, 16, _mm512, LOAD_256, LOAD_128)
#undef LOAD_128
#undef LOAD_64
#undef LOAD_256
#undef PLANES_LINEAR
#undef LINEAR_PASS
#undef LINEAR_TAIL
#endif

/* The SH sums of coded vertices [k0, k0 + nb), nb ≤ SH_BLOCK, from the
 * planes: channel c of the block's vertex b into acc[c·SH_BLOCK + b]. isa
 * is the copy's instruction set (a constant once inlined); T is fold_sh's. */
BLOCK_INLINE void sh_block(const sss_shcode *s, const float *T, size_t C, size_t k0, size_t nb, float *acc, int isa)
{
    /* the block's planes, n apart (plane_at; k0 … k0 + nb − 1 lie in one
     * group of the layout) */
    const size_t n = sh_group(s, C), N = s->ncoef, L = sss_decode_fold_levels(s->kind);
    const size_t at = plane_at(k0, 0, sh_nplanes(s, C), n);
    for (size_t c = 0; c < C; c++) {
        float *a = acc + c * SH_BLOCK;
        for (size_t b = 0; b < nb; b++) a[b] = 0.0f;
        const size_t e = c * N; /* the channel's first code element */
#ifdef DECODE_X86
        const int linear = s->kind == SSS_SHQ_LINEAR16 || s->kind == SSS_SHQ_LINEAR8;
        if (linear && isa != SSS_DECODE_ISA_BASELINE && n == SH_BLOCK) {
            const int wide = s->kind == SSS_SHQ_LINEAR16;
            const void *pl = wide ? (const void *)((const int16_t *)s->planes + at + e * n)
                                  : (const void *)((const int8_t *)s->planes + at + e * n);
            if (isa == SSS_DECODE_ISA_AVX512) planes_linear_avx512(a, pl, wide, n, T + e, N, nb);
            else planes_linear_avx2(a, pl, wide, n, T + e, N, nb);
            continue;
        }
#endif
        if (s->kind == SSS_SHQ_LINEAR16)
            planes_linear16(a, (const int16_t *)s->planes + at + e * n, n, T + e, L, N, nb);
        else if (s->kind == SSS_SHQ_LINEAR8)
            planes_linear8(a, (const int8_t *)s->planes + at + e * n, n, T + e, L, N, nb);
        else if (s->kind == SSS_SHQ_LLOYD4) { /* the pairs, then an odd last code (sss_decode_prepare) */
            const size_t P = N / 2, Q = (N + 1) / 2;
            const uint8_t *pl = (const uint8_t *)s->planes + at + c * Q * n;
#ifdef DECODE_X86
            const float *terms = T + sss_decode_fold_floats(s->kind, (uint32_t)C, (uint32_t)N) + e * 16;
            if (isa == SSS_DECODE_ISA_AVX512) {
                planes_nibble_avx512(a, pl, n, terms, P, (int)(N & 1), nb);
                continue;
            }
            if (isa == SSS_DECODE_ISA_AVX2) {
                planes_nibble_avx2(a, pl, n, terms, P, (int)(N & 1), nb);
                continue;
            }
#endif
            (void)isa;
            planes_table(a, pl, n, T + c * P * 256, 256, P, nb);
            if (N & 1) planes_table(a, pl + P * n, n, T + (C * P * 256 + c * 16), 16, 1, nb);
        } else
            planes_table(a, (const uint8_t *)s->planes + at + e * n, n, T + e * L, L, N, nb);
    }
}

/* Whether f's SH codes have a current load-time layout. */
static int has_planes(const sss_bake_file *f)
{
    return f->sh.planes && f->sh.planes_of == f->sh.code && f->sh.ncoef;
}

/* The references' blend for coded vertices [kb, kb + nb) (§4.2–4.3), added
 * to their SH sums acc[c·SH_BLOCK + b]: coded_blend's arithmetic, split in
 * loops: each vertex's weights (a table look-up, or coded_weights's
 * expression over the block), the third weight, the triangle's offsets
 * (32-bit: decode_compressed takes this path only when nref·C fits), then
 * per channel one loop over the block whose lanes are vertices. C is a
 * constant in the RGB copy. */
BLOCK_INLINE void blend_block_c(const sss_bake_file *f, const float *R, const float *wt, size_t kb, size_t nb,
                                float *acc, size_t C)
{
    const sss_refcode *r = &f->ref;
    float w0[SH_BLOCK], w1[SH_BLOCK], w2[SH_BLOCK];
    int32_t o0[SH_BLOCK], o1[SH_BLOCK], o2[SH_BLOCK];
    const uint16_t *wc = r->w + 2 * kb;
    if (wt) {
        for (size_t b = 0; b < nb; b++) w0[b] = wt[wc[2 * b]], w1[b] = wt[wc[2 * b + 1]];
    } else {
        /* sss_decode_ref_weight's expression, as a loop over the block (a
         * vector division instead of two scalar ones per vertex) */
        const double lo = r->w_lo, span = (double)r->w_hi - r->w_lo, wmax = r->wbits == 16 ? 65535.0 : 255.0;
        for (size_t b = 0; b < nb; b++) {
            w0[b] = (float)(lo + span * (wc[2 * b] / wmax));
            w1[b] = (float)(lo + span * (wc[2 * b + 1] / wmax));
        }
    }
    for (size_t b = 0; b < nb; b++) w2[b] = 1.0f - w0[b] - w1[b];
    const uint32_t *vt = r->vtri + kb;
    for (size_t b = 0; b < nb; b++) {
        const uint32_t *t = r->ref_tri + 3 * (size_t)vt[b];
        o0[b] = (int32_t)(t[0] * C), o1[b] = (int32_t)(t[1] * C), o2[b] = (int32_t)(t[2] * C);
    }
    for (size_t c = 0; c < C; c++) {
        float *a = acc + c * SH_BLOCK;
        const float *Rc = R + c;
        for (size_t b = 0; b < nb; b++) {
            float x = w0[b] * Rc[o0[b]] + w1[b] * Rc[o1[b]] + w2[b] * Rc[o2[b]];
            x += a[b];
            a[b] = x;
        }
    }
}

/* Whether f's references have a current load-time blend layout. */
static int has_blend(const sss_bake_file *f) { return f->ref.blend && f->ref.blend_of == f->ref.w; }

/* The next block's SH codes, fetched while the blend runs: k cache lines
 * at each step of four vertices, n bytes from p (n 0: none). A block's
 * codes are one run of memory (plane_at), and between two blocks' SH sums
 * the blend and the stores leave that stream idle, so the hardware
 * prefetcher, which runs ahead of the loads it sees, had fetched little of
 * the next block when its sums began: with the viewer's draw evicting the
 * codes between frames, the paper preset's decode waited there for about
 * a third of its time (docs/benchmarks.md, "The blend four vertices a
 * vector"). */
typedef struct blend_ahead {
    const char *p;
    size_t n, k;
} blend_ahead;

static inline void ahead_step(const blend_ahead *a, size_t step)
{
    for (size_t j = step * a->k, e = j + a->k; j < e && 64 * j < a->n; j++) __builtin_prefetch(a->p + 64 * j, 0, 3);
}

/* RGB: the blend of four vertices at a time with the channels in the lanes
 * of a 4-float vector: a reference's three values are adjacent in R (R[t·3
 * + c]), so one unaligned load brings all three (the fourth lane reads the
 * next value, or R's padding, and is dropped), three loads a vertex where
 * the plane loop below gathers nine scalars. Each lane forms its channel's
 * sum as blend_block_planes does (w0·R0 + w1·R1, then + w2·R2, each
 * rounded; w2 = 1 − w0 − w1 in float), a 4 × 4 transpose puts the
 * channels back in acc's planes, and x + acc is acc + x to the bit (IEEE
 * addition commutes). Returns the first vertex left to the plane loop. */
#ifdef DECODE_X86
BLOCK_INLINE size_t blend_rgb_lanes(const float *R, const struct sss_blend_rec *restrict rec, size_t nb, float *acc,
                                    const blend_ahead *ah)
{
    size_t b = 0;
    for (; b + 4 <= nb; b += 4) {
        ahead_step(ah, b / 4);
        __m128 v[4];
        for (size_t i = 0; i < 4; i++) {
            const struct sss_blend_rec *e = rec + b + i;
            const float a = e->w0, c = e->w1, w2 = 1.0f - a - c;
            const __m128 x = _mm_add_ps(_mm_mul_ps(_mm_set1_ps(a), _mm_loadu_ps(R + 3 * (size_t)e->t[0])),
                                        _mm_mul_ps(_mm_set1_ps(c), _mm_loadu_ps(R + 3 * (size_t)e->t[1])));
            v[i] = _mm_add_ps(x, _mm_mul_ps(_mm_set1_ps(w2), _mm_loadu_ps(R + 3 * (size_t)e->t[2])));
        }
        _MM_TRANSPOSE4_PS(v[0], v[1], v[2], v[3]);
        for (size_t c = 0; c < 3; c++) {
            float *a = acc + c * SH_BLOCK + b;
            _mm_storeu_ps(a, _mm_add_ps(v[c], _mm_loadu_ps(a)));
        }
    }
    return b;
}

/* blend_rgb_lanes on the wider sets: two vertices a vector on AVX2 (one in
 * each 128-bit half), four on AVX-512 (one in each quarter). Two (four)
 * records are one load; their weights go to their vertex's lanes by a
 * permute; each reference's three values are one 128-bit load into the
 * vertex's part. Every lane forms its channel's sum as blend_rgb_lanes
 * does, so the floats are the same; per vertex about half the
 * instructions (docs/benchmarks.md, "The blend four vertices a vector").
 * Records are 16 bytes, w0 and w1 the first two floats. */
__attribute__((target("avx2"))) static size_t blend_rgb_avx2(const float *R, const struct sss_blend_rec *restrict rec,
                                                            size_t nb, float *acc, const blend_ahead *ah)
{
    const __m256 one = _mm256_set1_ps(1.0f);
    const __m256i i0 = _mm256_set_epi32(4, 4, 4, 4, 0, 0, 0, 0), i1 = _mm256_set_epi32(5, 5, 5, 5, 1, 1, 1, 1);
    const __m256i planes = _mm256_set_epi32(7, 3, 6, 2, 5, 1, 4, 0);
    size_t b = 0;
    for (; b + 4 <= nb; b += 4) {
        ahead_step(ah, b / 4);
        __m256 v[2];
        for (size_t h = 0; h < 2; h++) {
            const struct sss_blend_rec *e = rec + b + 2 * h;
            const __m256 q = _mm256_loadu_ps(&e->w0); /* records e[0] and e[1] */
            const __m256 w0 = _mm256_permutevar8x32_ps(q, i0), w1 = _mm256_permutevar8x32_ps(q, i1);
            const __m256 w2 = _mm256_sub_ps(_mm256_sub_ps(one, w0), w1);
#define PAIR(j)                                                                                                        \
    _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(R + 3 * (size_t)e[0].t[j])),                              \
                         _mm_loadu_ps(R + 3 * (size_t)e[1].t[j]), 1)
            const __m256 x = _mm256_add_ps(_mm256_mul_ps(w0, PAIR(0)), _mm256_mul_ps(w1, PAIR(1)));
            v[h] = _mm256_add_ps(x, _mm256_mul_ps(w2, PAIR(2)));
#undef PAIR
        }
        /* [r0 g0 b0 · | r1 g1 b1 ·], [r2 … | r3 …] → r0…r3 g0…g3, b0…b3 */
        const __m256 rg = _mm256_permutevar8x32_ps(_mm256_unpacklo_ps(v[0], v[1]), planes);
        const __m256 bx = _mm256_permutevar8x32_ps(_mm256_unpackhi_ps(v[0], v[1]), planes);
        float *a = acc + b;
        _mm_storeu_ps(a, _mm_add_ps(_mm256_castps256_ps128(rg), _mm_loadu_ps(a)));
        _mm_storeu_ps(a + SH_BLOCK, _mm_add_ps(_mm256_extractf128_ps(rg, 1), _mm_loadu_ps(a + SH_BLOCK)));
        _mm_storeu_ps(a + 2 * SH_BLOCK, _mm_add_ps(_mm256_castps256_ps128(bx), _mm_loadu_ps(a + 2 * SH_BLOCK)));
    }
    return b;
}

__attribute__((target("avx512f"))) static size_t blend_rgb_avx512(const float *R,
                                                                 const struct sss_blend_rec *restrict rec, size_t nb,
                                                                 float *acc, const blend_ahead *ah)
{
    const __m512 one = _mm512_set1_ps(1.0f);
    const __m512i i0 = _mm512_set_epi32(12, 12, 12, 12, 8, 8, 8, 8, 4, 4, 4, 4, 0, 0, 0, 0);
    const __m512i i1 = _mm512_set_epi32(13, 13, 13, 13, 9, 9, 9, 9, 5, 5, 5, 5, 1, 1, 1, 1);
    const __m512i planes = _mm512_set_epi32(15, 11, 7, 3, 14, 10, 6, 2, 13, 9, 5, 1, 12, 8, 4, 0);
    size_t b = 0;
    for (; b + 4 <= nb; b += 4) {
        ahead_step(ah, b / 4);
        const struct sss_blend_rec *e = rec + b;
        const __m512 q = _mm512_loadu_ps(&e->w0); /* records e[0] … e[3] */
        const __m512 w0 = _mm512_permutexvar_ps(i0, q), w1 = _mm512_permutexvar_ps(i1, q);
        const __m512 w2 = _mm512_sub_ps(_mm512_sub_ps(one, w0), w1);
#define QUAD(j)                                                                                                        \
    _mm512_insertf32x4(                                                                                                \
        _mm512_insertf32x4(_mm512_insertf32x4(_mm512_castps128_ps512(_mm_loadu_ps(R + 3 * (size_t)e[0].t[j])),        \
                                              _mm_loadu_ps(R + 3 * (size_t)e[1].t[j]), 1),                             \
                           _mm_loadu_ps(R + 3 * (size_t)e[2].t[j]), 2),                                                \
        _mm_loadu_ps(R + 3 * (size_t)e[3].t[j]), 3)
        __m512 x = _mm512_add_ps(_mm512_mul_ps(w0, QUAD(0)), _mm512_mul_ps(w1, QUAD(1)));
        x = _mm512_add_ps(x, _mm512_mul_ps(w2, QUAD(2)));
#undef QUAD
        x = _mm512_permutexvar_ps(planes, x); /* r0…r3 g0…g3 b0…b3 · */
        float *a = acc + b;
        _mm_storeu_ps(a, _mm_add_ps(_mm512_castps512_ps128(x), _mm_loadu_ps(a)));
        _mm_storeu_ps(a + SH_BLOCK, _mm_add_ps(_mm512_extractf32x4_ps(x, 1), _mm_loadu_ps(a + SH_BLOCK)));
        _mm_storeu_ps(a + 2 * SH_BLOCK, _mm_add_ps(_mm512_extractf32x4_ps(x, 2), _mm_loadu_ps(a + 2 * SH_BLOCK)));
    }
    return b;
}
#endif

/* blend_block_c through the load-time layout (prepare_blend): the same
 * weights and offsets, read from the records, so the arithmetic per channel
 * and vertex is the same to the bit. */
BLOCK_INLINE void blend_block_planes(const sss_bake_file *f, const float *R, size_t kb, size_t nb, float *acc,
                                     size_t C, int isa, const blend_ahead *ah)
{
    const struct sss_blend_rec *restrict rec = f->ref.blend + kb;
    size_t b0 = 0;
#ifdef DECODE_X86
    if (C == 3)
        b0 = isa == SSS_DECODE_ISA_AVX512 ? blend_rgb_avx512(R, rec, nb, acc, ah)
             : isa == SSS_DECODE_ISA_AVX2 ? blend_rgb_avx2(R, rec, nb, acc, ah)
                                          : blend_rgb_lanes(R, rec, nb, acc, ah);
#else
    (void)isa;
#endif
    float w0[SH_BLOCK], w1[SH_BLOCK], w2[SH_BLOCK];
    int32_t o0[SH_BLOCK], o1[SH_BLOCK], o2[SH_BLOCK];
    for (size_t b = b0; b < nb; b++) {
        if (b % 4 == 0) ahead_step(ah, b / 4);
        w0[b] = rec[b].w0, w1[b] = rec[b].w1;
        w2[b] = 1.0f - w0[b] - w1[b];
        o0[b] = (int32_t)(rec[b].t[0] * C), o1[b] = (int32_t)(rec[b].t[1] * C), o2[b] = (int32_t)(rec[b].t[2] * C);
    }
    for (size_t c = 0; c < C; c++) {
        float *restrict a = acc + c * SH_BLOCK;
        const float *restrict Rc = R + c;
        for (size_t b = b0; b < nb; b++) {
            float x = w0[b] * Rc[o0[b]] + w1[b] * Rc[o1[b]] + w2[b] * Rc[o2[b]];
            x += a[b];
            a[b] = x;
        }
    }
}

BLOCK_INLINE void blend_block(const sss_bake_file *f, const float *R, const float *wt, size_t kb, size_t nb,
                              float *acc, int isa)
{
    if (has_blend(f)) {
        /* the next block's codes (sh_group: blocks of SH_BLOCK), spread
         * over this block's steps of four vertices */
        const sss_shcode *s = &f->sh;
        const size_t C = f->channels, B = kb / SH_BLOCK + 1, steps = nb / 4 ? nb / 4 : 1;
        blend_ahead ah = {NULL, 0, 0};
        if (sh_group(s, C) == SH_BLOCK && B * SH_BLOCK < s->ncoded) {
            ah.n = sh_nplanes(s, C) * SH_BLOCK * (s->kind == SSS_SHQ_LINEAR16 ? 2 : 1);
            ah.p = (const char *)s->planes + B * ah.n;
            ah.k = (ah.n / 64 + steps - 1) / steps;
        }
        if (C == 3) blend_block_planes(f, R, kb, nb, acc, 3, isa, &ah);
        else blend_block_planes(f, R, kb, nb, acc, C, isa, &ah);
        return;
    }
    if (f->channels == 3) blend_block_c(f, R, wt, kb, nb, acc, 3);
    else blend_block_c(f, R, wt, kb, nb, acc, f->channels);
}

/* The block's values acc[c·SH_BLOCK + b] of b in [b0, b0 + len) to
 * o[(b − b0)·C + c]: channels interleaved again, vertex after vertex. */
BLOCK_INLINE void store_run(float *restrict o, const float *restrict acc, size_t b0, size_t len, size_t C)
{
    const float *restrict a = acc + b0;
    if (C == 3)
        for (size_t b = 0; b < len; b++) {
            o[3 * b] = a[b];
            o[3 * b + 1] = a[SH_BLOCK + b];
            o[3 * b + 2] = a[2 * SH_BLOCK + b];
        }
    else
        for (size_t c = 0; c < C; c++)
            for (size_t b = 0; b < len; b++) o[b * C + c] = a[c * SH_BLOCK + b];
}

/* Coded vertices [kb, kb + nb), nb ≤ SH_BLOCK, through the planes: the SH
 * sums, the references' blend (R non-NULL), the clamp at 0 as a vector
 * loop (a data-dependent branch per value cost more than the sums), then
 * coded vertex k's C values to out + (v − first)·C, v its vertex. */
BLOCK_INLINE void coded_block(const sss_bake_file *f, const float *R, const float *T, const float *wt, size_t kb,
                              size_t nb, size_t first, size_t end, float *out, int isa)
{
    const size_t C = f->channels;
    float acc[SSS_MAX_CHANNELS * SH_BLOCK];
    sh_block(&f->sh, T, C, kb, nb, acc, isa);
    if (R) blend_block(f, R, wt, kb, nb, acc, isa);
    for (size_t c = 0; c < C; c++) {
        float *a = acc + c * SH_BLOCK;
        for (size_t b = 0; b < nb; b++) a[b] = a[b] > 0.0f ? a[b] : 0.0f;
    }
    if (R) {
        /* The coded vertices are the mesh's vertices less the references,
         * in order: between two references they are consecutive, so the
         * block is stored as runs of consecutive vertices (3 % references:
         * about eight runs of 30 a block), each as the SH-only path stores,
         * not value by value through coded_vertex. */
        const sss_refcode *r = &f->ref;
        const uint32_t *rv = r->ref_vertex;
        /* The runs follow from the references alone: coded vertex kb is
         * vertex v with v − kb references before it, and after a run the
         * next run starts at the next vertex that is not a reference.
         * Reading coded_vertex at each run (and searching ref_vertex per
         * block) made each run wait for a load of memory that the viewer's
         * draw had evicted, one after the other (perf on decode_bench
         * --evict, docs/benchmarks.md "The blend's records in one
         * stream"). */
        size_t v = r->coded_vertex[kb], j = v - kb;
        for (size_t b = 0;;) {
            /* after each run, the references up to the next coded vertex
             * (after the block's last run: the next block's, or the end of
             * the range): their own values */
            if (b)
                for (; j < r->nref && rv[j] == v && v < end; j++, v++)
                    for (size_t c = 0; c < C; c++) out[(v - first) * C + c] = R[j * C + c];
            if (b == nb) break;
            const size_t gap = j < r->nref ? rv[j] - v : nb - b, len = gap < nb - b ? gap : nb - b;
            store_run(out + (v - first) * C, acc, b, len, C);
            b += len;
            v += len;
        }
        return;
    }
    store_run(out + (kb - first) * C, acc, 0, nb, C);
}

/* ---- run-time instruction sets (sss_decode_isa) ------------------------ *
 * The project builds for the x86-64 baseline (SSE2), where an int8 → float
 * conversion takes three instructions per four vertices and no table load
 * vectorises. The CPU running it may have more: coded_block is compiled
 * again for AVX2 and for AVX-512 and the widest present is taken per call.
 * The copies must give the same floats (the decoded q, and the GPU path's
 * equality to this decoder, may not depend on the CPU): the same C, every
 * operation IEEE-rounded in the same order. Neither copy may contract a
 * product and a sum into a fused multiply-add: "avx2" does not enable FMA,
 * but AVX-512F includes it, so this unit is compiled with
 * -ffp-contract=off (common/CMakeLists.txt). */
typedef void (*block_fn)(const sss_bake_file *, const float *, const float *, const float *, size_t, size_t, size_t,
                         size_t, float *);

static void block_baseline(const sss_bake_file *f, const float *R, const float *T, const float *wt, size_t kb,
                           size_t nb, size_t first, size_t end, float *out)
{
    coded_block(f, R, T, wt, kb, nb, first, end, out, SSS_DECODE_ISA_BASELINE);
}

#ifdef DECODE_X86
__attribute__((target("avx2"))) static void block_avx2(const sss_bake_file *f, const float *R, const float *T,
                                                      const float *wt, size_t kb, size_t nb, size_t first, size_t end,
                                                      float *out)
{
    coded_block(f, R, T, wt, kb, nb, first, end, out, SSS_DECODE_ISA_AVX2);
}

__attribute__((target("avx512f"))) static void block_avx512(const sss_bake_file *f, const float *R, const float *T,
                                                           const float *wt, size_t kb, size_t nb, size_t first, size_t end,
                                                           float *out)
{
    coded_block(f, R, T, wt, kb, nb, first, end, out, SSS_DECODE_ISA_AVX512);
}
#endif

static int cpu_has(int isa)
{
#ifdef DECODE_X86
    __builtin_cpu_init();
    if (isa == SSS_DECODE_ISA_AVX512) return __builtin_cpu_supports("avx512f");
    if (isa == SSS_DECODE_ISA_AVX2) return __builtin_cpu_supports("avx2");
#endif
    return isa == SSS_DECODE_ISA_BASELINE;
}

static int g_isa_forced = -1;

int sss_decode_force_isa(int isa)
{
    if (isa != -1 && !cpu_has(isa)) return -1;
    g_isa_forced = isa;
    return 0;
}

int sss_decode_isa(void)
{
    if (g_isa_forced >= 0) return g_isa_forced;
    static const char *const names[] = {"baseline", "avx2", "avx512"};
    const char *e = getenv("SSS_DECODE_ISA");
    if (e)
        for (int i = 0; i < 3; i++)
            if (!strcmp(e, names[i]) && cpu_has(i)) return i;
    return cpu_has(SSS_DECODE_ISA_AVX512) ? SSS_DECODE_ISA_AVX512
           : cpu_has(SSS_DECODE_ISA_AVX2) ? SSS_DECODE_ISA_AVX2
                                          : SSS_DECODE_ISA_BASELINE;
}

static block_fn block_for(int isa)
{
#ifdef DECODE_X86
    if (isa == SSS_DECODE_ISA_AVX512) return block_avx512;
    if (isa == SSS_DECODE_ISA_AVX2) return block_avx2;
#endif
    (void)isa;
    return block_baseline;
}

/* decode_compressed's loop over coded vertices [k0, k1) through the
 * planes, in blocks (coded_block); R NULL without references. */
static void coded_blocks(const sss_bake_file *f, const float *R, const float *T, const float *wt, size_t k0,
                         size_t k1, size_t first, size_t end, float *out)
{
    const size_t C = f->channels;
    const block_fn block = block_for(sss_decode_isa());
    /* the layout's blocks that [k0, k1) meets, each cut to the range */
    const size_t B0 = k0 / SH_BLOCK;
    const ptrdiff_t nblk = k1 > k0 ? (ptrdiff_t)((k1 - 1) / SH_BLOCK - B0 + 1) : 0;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if ((ptrdiff_t)(k1 - k0) * (ptrdiff_t)C >= PAR_MIN / 4)
#endif
    for (ptrdiff_t blk = 0; blk < nblk; blk++) {
        const size_t B = B0 + (size_t)blk, kb = B * SH_BLOCK > k0 ? B * SH_BLOCK : k0,
                     ke = (B + 1) * SH_BLOCK < k1 ? (B + 1) * SH_BLOCK : k1;
        block(f, R, T, wt, kb, ke - kb, first, end, out);
    }
}

/* The first of the n increasing values a[] that is ≥ x (n when none). */
static size_t lower_bound_u32(const uint32_t *a, size_t n, size_t x)
{
    size_t lo = 0, hi = n;
    while (lo < hi) {
        const size_t mid = lo + (hi - lo) / 2;
        if (a[mid] < x) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}

/* Vertices [first, first + count) into out[(v − first)·C + c]. */
static void decode_compressed(const sss_bake_file *f, const double d[3], sss_interp interp, size_t first, size_t count,
                              float *out)
{
    const size_t C = f->channels, end = first + count;
    float *R = NULL, *T = NULL;
    if (f->sh.ncoef && !(T = fold_sh(f, d))) goto oom;
    if (f->quant == SSS_QUANT_REFS) {
        const sss_refcode *r = &f->ref;
        if (!(R = malloc(((size_t)r->nref * C + 1) * sizeof *R))) goto oom;
        R[(size_t)r->nref * C] = 0.0f; /* the padding blend_rgb_lanes's last load may read */
        ref_values(f, d, interp, R);
        const ptrdiff_t k0 = (ptrdiff_t)lower_bound_u32(r->coded_vertex, f->sh.ncoded, first);
        const ptrdiff_t k1 = (ptrdiff_t)lower_bound_u32(r->coded_vertex, f->sh.ncoded, end);
        const int blocks = T && has_planes(f) && (size_t)r->nref * C <= INT32_MAX; /* blend_block's offsets */
        /* the references' own values: through the blocks each block
         * stores those after its coded vertices, in order with its runs
         * (coded_block); here those before the range's first coded vertex,
         * or all of them */
        const size_t vr = blocks && k0 < k1 ? r->coded_vertex[k0] : end;
        const size_t r1 = lower_bound_u32(r->ref_vertex, r->nref, vr);
        for (size_t k = lower_bound_u32(r->ref_vertex, r->nref, first); k < r1; k++)
            for (size_t c = 0; c < C; c++) out[((size_t)r->ref_vertex[k] - first) * C + c] = R[k * C + c];
        /* 8-bit weight codes: their 256 weights once per call, as
         * coded_weights computes each (a division per weight saved) */
        float wt8[256];
        const float *wt = NULL;
        if (r->wbits == 8) {
            for (uint32_t x = 0; x < 256; x++) wt8[x] = sss_decode_ref_weight(r, x);
            wt = wt8;
        }
        if (blocks) {
            coded_blocks(f, R, T, wt, (size_t)k0, (size_t)k1, first, end, out);
        } else {
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if ((k1 - k0) * (ptrdiff_t)C >= PAR_MIN / 4)
#endif
            for (ptrdiff_t k = k0; k < k1; k++)
                coded_values(f, R, T, wt, (size_t)k, out + ((size_t)r->coded_vertex[k] - first) * C);
        }
    } else if (T && has_planes(f)) {
        coded_blocks(f, NULL, T, NULL, first, end, first, end, out);
    } else {
        const ptrdiff_t n = (ptrdiff_t)count;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (n * (ptrdiff_t)C >= PAR_MIN / 4)
#endif
        for (ptrdiff_t v = 0; v < n; v++) coded_values(f, NULL, T, NULL, first + (size_t)v, out + (size_t)v * C);
    }
    free(R);
    free(T);
    return;
oom:
    /* a few hundred KiB of per-call tables could not be had: say "no
     * light" rather than return garbage */
    free(R);
    free(T);
    memset(out, 0, count * C * sizeof *out);
}

/* Position of vertex v among the coded vertices, or SIZE_MAX for a
 * reference (binary search: both lists increase). */
static size_t coded_index(const sss_bake_file *f, uint32_t v, size_t *ref)
{
    *ref = SIZE_MAX;
    if (f->quant != SSS_QUANT_REFS) return v;
    const sss_refcode *r = &f->ref;
    const size_t lo = lower_bound_u32(r->ref_vertex, r->nref, v);
    if (lo < r->nref && r->ref_vertex[lo] == v) {
        *ref = lo;
        return SIZE_MAX;
    }
    return (size_t)v - lo; /* v minus the references before it */
}

void sss_decode_vertex(const sss_bake_file *f, uint32_t v, const double light[3], float *out)
{
    const size_t C = f->channels;
    double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (v >= f->mesh.nv || f->dirs.n == 0 || !(len > 0.0) || !isfinite(len)) {
        for (size_t c = 0; c < C; c++) out[c] = 0.0f;
        return;
    }
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};
    if (f->quant == SSS_QUANT_FLOAT || f->quant == SSS_QUANT_LLOYD8) {
        uint32_t idx[3];
        double w[3];
        sss_dirset_lookup(&f->dirs, d, idx, w);
        for (size_t c = 0; c < C; c++) {
            if (f->quant == SSS_QUANT_FLOAT) {
                /* the float expression sss_decode_all uses, so both agree to the bit */
                const float *q = f->q;
                const size_t nv = f->mesh.nv;
                out[c] = (float)w[0] * q[(idx[0] * nv + v) * C + c] + (float)w[1] * q[(idx[1] * nv + v) * C + c] +
                         (float)w[2] * q[(idx[2] * nv + v) * C + c];
            } else {
                float s = 0.0f; /* as the folded tables: each term rounded, float sums */
                for (int t = 0; t < 3; t++)
                    s += (float)(w[t] * f->levels[256 * c + f->qidx[(idx[t] * f->mesh.nv + v) * C + c]]);
                out[c] = s;
            }
        }
        return;
    }
    /* compressed: the same arithmetic as decode_compressed, for one vertex */
    float *T = NULL;
    if (f->sh.ncoef && !(T = fold_sh(f, d))) {
        for (size_t c = 0; c < C; c++) out[c] = 0.0f;
        return;
    }
    size_t ref, k = coded_index(f, v, &ref);
    float R[3 * SSS_MAX_CHANNELS * 3];
    if (f->quant == SSS_QUANT_REFS) {
        const sss_refcode *r = &f->ref;
        uint32_t idx[3];
        double w[3];
        sss_dirset_lookup(&f->dirs, d, idx, w);
        /* reference values of the (up to three) references needed, computed
         * as ref_values does */
        uint32_t need[3];
        int nneed = 1;
        if (ref != SIZE_MAX) need[0] = (uint32_t)ref;
        else {
            const uint32_t *t = r->ref_tri + 3 * (size_t)r->vtri[k];
            need[0] = t[0], need[1] = t[1], need[2] = t[2];
            nneed = 3;
        }
        for (int n = 0; n < nneed; n++)
            for (size_t c = 0; c < C; c++) {
                float acc = 0.0f;
                for (int t = 0; t < 3; t++)
                    acc += (float)(w[t] * r->levels[256 * c + r->idx[(idx[t] * (size_t)r->nref + need[n]) * C + c]]);
                R[n * C + c] = acc;
            }
        if (ref != SIZE_MAX) {
            for (size_t c = 0; c < C; c++) out[c] = R[c];
        } else {
            float wk[3];
            float sh[SSS_MAX_CHANNELS] = {0};
            coded_weights(r, k, wk);
            if (T) sh_sums(&f->sh, T, C, k, sh);
            for (size_t c = 0; c < C; c++) {
                float x = wk[0] * R[c] + wk[1] * R[C + c] + wk[2] * R[2 * C + c];
                x += sh[c];
                out[c] = x > 0.0f ? x : 0.0f;
            }
        }
    } else {
        float sh[SSS_MAX_CHANNELS] = {0};
        if (T) sh_sums(&f->sh, T, C, k, sh);
        for (size_t c = 0; c < C; c++) out[c] = sh[c] > 0.0f ? sh[c] : 0.0f;
    }
    free(T);
}
