/* compress.c: reference points + barycentric weights + SH-coded deltas
 * (Hao–Varshney 2004 §4), see sss/compress.h.
 *
 * §4.1: q(x, ω) over the direction samples is projected (least squares,
 * sss_sh.h) onto the first n² real SH.
 * §4.2: reference vertices keep their full integrals; other vertices are
 * barycentric blends of a reference triangle.
 * §4.3: the residual of that blend (the "delta") is SH-coded; here it is
 * formed from the *quantised* reference rows and weights, so the SH part also
 * absorbs quantisation error of both.
 */
#include "sss/compress.h"
#include "sss/random.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/bake.h"
#include "sss/decode.h"
#include "sss/refs.h"
#include "sss/sh.h"

void sss_compressed_free(sss_compressed *cq)
{
    if (!cq) return;
    sss_dirset_free(&cq->dirs);
    free(cq->ref_vertex);
    free(cq->ref_tri);
    free(cq->levels);
    free(cq->ref_idx);
    free(cq->coded_vertex);
    free(cq->vtri);
    free(cq->w16);
    free(cq->sh_code);
    free(cq->sh_scale);
    memset(cq, 0, sizeof *cq);
}

/* Quantises weights (§4.2 barycentric weights) to 2 × uint16 with rounding;
 * the third is implied as 1 − w0 − w1 and is kept ≥ 0 by lowering the larger
 * stored one when rounding pushed the sum past 65535. */
static void quantise_weights(const float w[3], uint16_t q[2])
{
    long a = lround((double)w[0] * 65535.0), b = lround((double)w[1] * 65535.0);
    if (a < 0) a = 0;
    if (b < 0) b = 0;
    if (a > 65535) a = 65535;
    if (b > 65535) b = 65535;
    while (a + b > 65535) {
        if (a >= b) a--;
        else b--;
    }
    q[0] = (uint16_t)a;
    q[1] = (uint16_t)b;
}

static void dequantise_weights(const uint16_t q[2], double w[3])
{
    w[0] = q[0] / 65535.0;
    w[1] = q[1] / 65535.0;
    w[2] = (double)(65535 - (uint32_t)q[0] - (uint32_t)q[1]) / 65535.0;
}

static sss_result copy_dirset(const sss_dirset *s, sss_dirset *d, sss_error *err)
{
    memset(d, 0, sizeof *d);
    d->n = s->n;
    d->ntri = s->ntri;
    d->dir = malloc(3 * (size_t)s->n * sizeof *d->dir);
    d->tri = s->ntri ? malloc(3 * (size_t)s->ntri * sizeof *d->tri) : NULL;
    if (!d->dir || (s->ntri && !d->tri)) {
        sss_dirset_free(d);
        return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory copying %u directions", s->n);
    }
    memcpy(d->dir, s->dir, 3 * (size_t)s->n * sizeof *d->dir);
    if (s->ntri) memcpy(d->tri, s->tri, 3 * (size_t)s->ntri * sizeof *d->tri);
    return SSS_OK;
}

sss_result sss_compress(const sss_bake_file *f, uint32_t order, double fraction, sss_compressed *out,
                        sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!f || !out) return sss_fail(err, SSS_ERR_ARG, "compress: NULL argument");
    if (f->quant != SSS_QUANT_FLOAT || !f->q)
        return sss_fail(err, SSS_ERR_ARG, "compress: needs a float bake (quant %d given)", (int)f->quant);
    if (f->channels < 1 || f->channels > SSS_MAX_CHANNELS)
        return sss_fail(err, SSS_ERR_ARG, "compress: %u channels (1 … %d allowed)", f->channels, SSS_MAX_CHANNELS);
    if (f->mesh.nv == 0 || f->dirs.n == 0 || !f->dirs.dir)
        return sss_fail(err, SSS_ERR_ARG, "compress: empty bake (%u vertices, %u directions)", f->mesh.nv, f->dirs.n);
    if (order > SSS_SH_MAX_ORDER)
        return sss_fail(err, SSS_ERR_ARG, "compress: SH order %u out of range 0 … %u", order, SSS_SH_MAX_ORDER);
    if (!(fraction >= 0.0 && fraction <= 1.0))
        return sss_fail(err, SSS_ERR_ARG, "compress: reference fraction %g out of range [0, 1]", fraction);
    if (fraction == 0.0 && order == 0)
        return sss_fail(err, SSS_ERR_ARG, "compress: SH-only mode (fraction 0) needs SH order >= 1");
    const uint32_t ncoef = sss_sh_count(order);
    if (ncoef > f->dirs.n)
        return sss_fail(err, SSS_ERR_ARG,
                        "compress: SH order %u has %u coefficients, more than the %u direction samples", order, ncoef,
                        f->dirs.n);

    sss_result r = SSS_OK;
    const uint32_t nv = f->mesh.nv, C = f->channels, nd = f->dirs.n;
    sss_compressed cq;
    memset(&cq, 0, sizeof cq);
    cq.nv = nv;
    cq.channels = C;
    cq.order = order;
    cq.ncoef = ncoef;
    cq.fraction = fraction;
    sss_sh_projector *proj = NULL;
    sss_refs refs;
    memset(&refs, 0, sizeof refs);
    float *refq = NULL;
    double *coef = NULL;
    uint32_t *refof = NULL;

    if ((r = copy_dirset(&f->dirs, &cq.dirs, err)) != SSS_OK) goto fail;
    if (ncoef && (r = sss_sh_projector_create(&f->dirs, order, SSS_SH_LEAST_SQUARES, &proj, err)) != SSS_OK) goto fail;

    /* ---- references (§4.2) ---------------------------------------------- */
    if (fraction > 0.0) {
        if ((r = sss_refs_build(&f->mesh, fraction, 1, &refs, err)) != SSS_OK) goto fail;
        cq.nref = refs.nref;
        cq.nrt = refs.nrt;
        cq.ref_vertex = refs.ref_vertex;
        cq.ref_tri = refs.ref_tri;
        refs.ref_vertex = NULL;
        refs.ref_tri = NULL;
        const size_t nrq = (size_t)nd * cq.nref * C;
        refq = malloc(nrq * sizeof *refq);
        cq.ref_idx = malloc(nrq);
        cq.levels = malloc((size_t)C * 256 * sizeof *cq.levels);
        if (!refq || !cq.ref_idx || !cq.levels) {
            r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for %u reference rows", cq.nref);
            goto fail;
        }
        for (uint32_t j = 0; j < nd; j++)
            for (uint32_t k = 0; k < cq.nref; k++)
                memcpy(refq + ((size_t)j * cq.nref + k) * C, f->q + ((size_t)j * nv + cq.ref_vertex[k]) * C,
                       C * sizeof *refq);
        /* one Lloyd table per channel, trained on the reference rows only */
        for (uint32_t c = 0; c < C; c++) {
            double sig, noi;
            r = sss_lloyd8(refq + c, (uint64_t)nd * cq.nref, C, cq.levels + 256 * (size_t)c, cq.ref_idx + c, &sig, &noi,
                           err);
            if (r != SSS_OK) goto fail;
        }
    }

    /* ---- coded vertices: all (SH-only) or the non-references ------------ */
    refof = malloc((size_t)nv * sizeof *refof);
    if (!refof) {
        r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory");
        goto fail;
    }
    for (uint32_t v = 0; v < nv; v++) refof[v] = UINT32_MAX;
    for (uint32_t k = 0; k < cq.nref; k++) refof[cq.ref_vertex[k]] = k;
    cq.ncoded = nv - cq.nref;
    cq.coded_vertex = malloc(((size_t)cq.ncoded + 1) * sizeof *cq.coded_vertex);
    if (fraction > 0.0) {
        cq.vtri = malloc(((size_t)cq.ncoded + 1) * sizeof *cq.vtri);
        cq.w16 = malloc(2 * ((size_t)cq.ncoded + 1) * sizeof *cq.w16);
    }
    const size_t ncodes = (size_t)cq.ncoded * C * ncoef;
    cq.sh_code = malloc(ncodes + 1);
    cq.sh_scale = calloc((size_t)C * ncoef + 1, sizeof *cq.sh_scale);
    coef = malloc((ncodes + 1) * sizeof *coef);
    if (!cq.coded_vertex || (fraction > 0.0 && (!cq.vtri || !cq.w16)) || !cq.sh_code || !cq.sh_scale || !coef) {
        r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for %u coded vertices", cq.ncoded);
        goto fail;
    }
    {
        uint32_t k = 0;
        for (uint32_t v = 0; v < nv; v++)
            if (refof[v] == UINT32_MAX) cq.coded_vertex[k++] = v;
    }
    for (uint32_t k = 0; k < cq.ncoded && cq.vtri; k++) {
        uint32_t v = cq.coded_vertex[k];
        cq.vtri[k] = refs.vtri[v];
        quantise_weights(refs.w + 3 * (size_t)v, cq.w16 + 2 * (size_t)k);
    }

    /* ---- deltas and their SH projection (§4.1, §4.3) --------------------- */
    if (ncoef) {
        int nomem = 0;
        const ptrdiff_t ncod = (ptrdiff_t)cq.ncoded;
#ifdef _OPENMP
#pragma omp parallel
#endif
        {
            double *d = malloc((size_t)nd * C * sizeof *d);
            if (!d) {
#ifdef _OPENMP
#pragma omp atomic write
#endif
                nomem = 1;
            }
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 256)
#endif
            for (ptrdiff_t k = 0; k < ncod; k++) {
                if (!d) continue;
                const uint32_t v = cq.coded_vertex[k];
                double w[3] = {0, 0, 0};
                uint32_t rk[3] = {0, 0, 0};
                if (cq.vtri) {
                    dequantise_weights(cq.w16 + 2 * (size_t)k, w);
                    for (int t = 0; t < 3; t++) rk[t] = cq.ref_tri[3 * (size_t)cq.vtri[k] + t];
                }
                for (uint32_t j = 0; j < nd; j++)
                    for (uint32_t c = 0; c < C; c++) {
                        double x = f->q[((size_t)j * nv + v) * C + c];
                        if (cq.vtri)
                            for (int t = 0; t < 3; t++) {
                                uint8_t q8 = cq.ref_idx[((size_t)j * cq.nref + rk[t]) * C + c];
                                x -= w[t] * (double)cq.levels[256 * (size_t)c + q8];
                            }
                        d[(size_t)j * C + c] = x;
                    }
                for (uint32_t c = 0; c < C; c++)
                    sss_sh_project_strided(proj, d + c, C, coef + ((size_t)k * C + c) * ncoef);
            }
            free(d);
        }
        if (nomem) {
            r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for delta rows");
            goto fail;
        }
        /* 8-bit codes, one scale per (channel, coefficient index) */
        for (size_t k = 0; k < cq.ncoded; k++)
            for (uint32_t c = 0; c < C; c++)
                for (uint32_t i = 0; i < ncoef; i++) {
                    double a = fabs(coef[(k * C + c) * ncoef + i]);
                    if (a > cq.sh_scale[c * ncoef + i]) cq.sh_scale[c * ncoef + i] = (float)a;
                }
        /* rounding the scale to float may lower it below max |c|: nudge up */
        for (size_t i = 0; i < (size_t)C * ncoef; i++)
            if (cq.sh_scale[i] > 0.0f) cq.sh_scale[i] = nextafterf(cq.sh_scale[i], INFINITY);
        for (size_t k = 0; k < cq.ncoded; k++)
            for (uint32_t c = 0; c < C; c++)
                for (uint32_t i = 0; i < ncoef; i++) {
                    double s = cq.sh_scale[c * ncoef + i], x = coef[(k * C + c) * ncoef + i];
                    long q = s > 0.0 ? lround(x / s * 127.0) : 0;
                    if (q > 127) q = 127;
                    if (q < -127) q = -127;
                    cq.sh_code[(k * C + c) * ncoef + i] = (int8_t)q;
                }
    }

    free(coef);
    free(refof);
    free(refq);
    sss_refs_free(&refs);
    sss_sh_projector_destroy(proj);
    *out = cq;
    return SSS_OK;

fail:
    free(coef);
    free(refof);
    free(refq);
    sss_refs_free(&refs);
    sss_sh_projector_destroy(proj);
    sss_compressed_free(&cq);
    return r;
}

void sss_compressed_bytes_of(const sss_compressed *cq, sss_compressed_bytes *b)
{
    memset(b, 0, sizeof *b);
    if (!cq) return;
    const uint64_t C = cq->channels, nd = cq->dirs.n;
    b->header = 7 * 4;
    b->directions = nd * 3 * 4;
    b->ref_integrals = nd * cq->nref * C;
    b->lloyd_tables = cq->nref ? C * 256 * 4 : 0;
    b->ref_vertex_list = (uint64_t)cq->nref * 4;
    b->vertex_tri = cq->vtri ? (uint64_t)cq->ncoded * 4 : 0;
    b->ref_tri_table = (uint64_t)cq->nrt * 3 * 4;
    b->weights = cq->w16 ? (uint64_t)cq->ncoded * 2 * 2 : 0;
    b->sh_codes = (uint64_t)cq->ncoded * C * cq->ncoef;
    b->sh_scales = C * cq->ncoef * 4;
    b->total = b->header + b->directions + b->ref_integrals + b->lloyd_tables + b->ref_vertex_list + b->vertex_tri +
               b->ref_tri_table + b->weights + b->sh_codes + b->sh_scales;
    b->per_vertex = cq->nv ? (double)b->total / cq->nv : 0.0;
}

void sss_compressed_eval(const sss_compressed *cq, const double light[3], float *out)
{
    const size_t C = cq->channels, nv = cq->nv, ncoef = cq->ncoef;
    double len = sqrt(light[0] * light[0] + light[1] * light[1] + light[2] * light[2]);
    if (cq->dirs.n == 0 || !(len > 0.0) || !isfinite(len)) {
        memset(out, 0, nv * C * sizeof *out);
        return;
    }
    const double d[3] = {light[0] / len, light[1] / len, light[2] / len};

    /* references: interpolate the three direction rows, as sss_decode_all */
    if (cq->nref) {
        uint32_t idx[3];
        double w[3];
        sss_dirset_lookup(&cq->dirs, d, idx, w);
        const size_t row = (size_t)cq->nref * C;
        const uint8_t *a = cq->ref_idx + idx[0] * row, *b = cq->ref_idx + idx[1] * row, *c = cq->ref_idx + idx[2] * row;
        const ptrdiff_t nref = (ptrdiff_t)cq->nref;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (nref >= 16384)
#endif
        for (ptrdiff_t k = 0; k < nref; k++)
            for (size_t ch = 0; ch < C; ch++) {
                const size_t i = (size_t)k * C + ch;
                const float *L = cq->levels + 256 * ch;
                out[(size_t)cq->ref_vertex[k] * C + ch] = (float)(w[0] * L[a[i]] + w[1] * L[b[i]] + w[2] * L[c[i]]);
            }
    }

    /* coded vertices: blend + SH delta; fold scale/127 into y once per call */
    float ys[SSS_MAX_CHANNELS * SSS_SH_MAX_COUNT];
    if (ncoef) {
        double y[SSS_SH_MAX_COUNT];
        sss_sh_eval(cq->order, d, y);
        for (size_t ch = 0; ch < C; ch++)
            for (size_t i = 0; i < ncoef; i++) ys[ch * ncoef + i] = (float)(y[i] * cq->sh_scale[ch * ncoef + i] / 127.0);
    }
    const ptrdiff_t ncod = (ptrdiff_t)cq->ncoded;
#ifdef _OPENMP
#pragma omp parallel for schedule(static) if (ncod >= 16384)
#endif
    for (ptrdiff_t k = 0; k < ncod; k++) {
        const size_t v = cq->coded_vertex[k];
        double w[3] = {0, 0, 0};
        size_t rv[3] = {0, 0, 0};
        if (cq->vtri) {
            dequantise_weights(cq->w16 + 2 * (size_t)k, w);
            for (int t = 0; t < 3; t++) rv[t] = cq->ref_vertex[cq->ref_tri[3 * (size_t)cq->vtri[k] + t]];
        }
        for (size_t ch = 0; ch < C; ch++) {
            float s = 0.0f;
            if (cq->vtri) s = (float)(w[0] * out[rv[0] * C + ch] + w[1] * out[rv[1] * C + ch] + w[2] * out[rv[2] * C + ch]);
            const int8_t *code = cq->sh_code + ((size_t)k * C + ch) * ncoef;
            const float *yy = ys + ch * ncoef;
            float acc = 0.0f;
            for (size_t i = 0; i < ncoef; i++) acc += (float)code[i] * yy[i];
            out[v * C + ch] = s + acc;
        }
    }
}


sss_result sss_compressed_error(const sss_compressed *cq, const sss_bake_file *f, uint32_t ndirs_test, uint64_t seed,
                                double *rel_rms, double *max_abs, double *max_rel, sss_error *err)
{
    if (!cq || !f || !rel_rms) return sss_fail(err, SSS_ERR_ARG, "compress error: NULL argument");
    if (ndirs_test == 0) return sss_fail(err, SSS_ERR_ARG, "compress error: no test directions");
    if (f->mesh.nv != cq->nv || f->channels != cq->channels || f->dirs.n != cq->dirs.n || !f->mesh.tri)
        return sss_fail(err, SSS_ERR_ARG, "compress error: bake (%u vertices, %u channels) does not match (%u, %u)",
                        f->mesh.nv, f->channels, cq->nv, cq->channels);
    const size_t nv = cq->nv, C = cq->channels;
    double *area = calloc(nv, sizeof *area);
    float *u = malloc(nv * C * sizeof *u), *rc = malloc(nv * C * sizeof *rc);
    if (!area || !u || !rc) {
        free(area);
        free(u);
        free(rc);
        return sss_fail(err, SSS_ERR_NOMEM, "compress error: out of memory");
    }
    sss_mesh_vertex_areas(&f->mesh, area); /* ΔA: 1/3 of the incident triangle areas */
    double num[SSS_MAX_CHANNELS] = {0}, den[SSS_MAX_CHANNELS] = {0}, mx = 0.0;
    int anynan = 0;
    uint64_t s = seed;
    for (uint32_t t = 0; t < ndirs_test; t++) {
        double light[3];
        sss_rng_direction(&s, light);
        sss_decode_all(f, light, u);
        sss_compressed_eval(cq, light, rc);
        for (size_t v = 0; v < nv; v++)
            for (size_t c = 0; c < C; c++) {
                double e = (double)rc[v * C + c] - u[v * C + c];
                num[c] += area[v] * e * e;
                den[c] += area[v] * (double)u[v * C + c] * u[v * C + c];
                if (isnan(e)) anynan = 1;
                else if (fabs(e) > mx) mx = fabs(e);
            }
    }
    double tn = 0.0, td = 0.0, asum = 0.0;
    for (size_t v = 0; v < nv; v++) asum += area[v];
    for (size_t c = 0; c < C; c++) {
        rel_rms[c] = den[c] > 0.0 ? sqrt(num[c] / den[c]) : sqrt(num[c]);
        tn += num[c];
        td += den[c];
    }
    rel_rms[C] = td > 0.0 ? sqrt(tn / td) : sqrt(tn);
    if (anynan) mx = NAN;
    if (max_abs) *max_abs = mx;
    if (max_rel) {
        double rms_u = sqrt(td / (asum * ndirs_test * (double)C));
        *max_rel = rms_u > 0.0 ? mx / rms_u : mx;
    }
    free(area);
    free(u);
    free(rc);
    return SSS_OK;
}
