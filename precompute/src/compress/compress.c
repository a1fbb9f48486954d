/* compress.c: reference points + weights + SH-coded deltas (Hao–Varshney
 * 2004 §4), producing the format 1.1 storage forms; see sss/compress.h.
 *
 * §4.1: q(x, ω) over the direction samples is projected (least squares,
 * sss/sh.h) onto the first n² real SH.
 * §4.2: reference vertices keep their full rows; other vertices blend the
 * three references of the simplified triangle they project onto.
 * §4.3: the residual of that blend (the "delta") is SH-coded; it is formed
 * from the *quantised* reference rows and weights, so the SH part also
 * absorbs the quantisation error of both.
 */
#include "sss/compress.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "sss/lloyd.h"
#include "sss/refs.h"
#include "sss/sh.h"

/* Least-squares weights are stored in this range: wide enough for the
 * optimum of real meshes (a vertex beyond its triangle's edge extrapolates a
 * little), narrow enough that 16-bit codes stay fine (4.6e-5 steps). */
#define LS_W_LO (-1.0f)
#define LS_W_HI 2.0f

void sss_compress_opts_default(sss_compress_opts *o)
{
    memset(o, 0, sizeof *o);
    o->order = 3;
    o->fraction = 0.03;
    o->sh_kind = SSS_SHQ_LINEAR8;
    o->wbits = 16;
}

void sss_compress_preset_apply(sss_compress_opts *o, sss_compress_preset p, uint32_t channels, uint32_t n_dirs,
                               uint32_t given)
{
    sss_compress_opts d;
    sss_compress_opts_default(&d);
    if (p == SSS_COMPRESS_COMPACT) {
        /* docs/compression.md "compact": 4-bit Lloyd SH codes, 8-bit
         * least-squares weights, illumination-aware references; 3 %
         * references for one channel, 1 % for three (RGB shares triangles
         * and weights but not rows); the directions in float32 */
        d.fraction = channels == 1 ? 0.03 : 0.01;
        d.sh_kind = SSS_SHQ_LLOYD4;
        d.wbits = 8;
        d.ls_weights = 1;
        d.illum_weight = 1e-3;
        d.dirs_f32 = 1;
    } else if (p == SSS_COMPRESS_PAPER_SH) {
        /* Hao–Varshney 2004 §4.1: n = 7 (49 coefficients), each a
         * normalised short, no references: 49 · 2 = 98 bytes per vertex and
         * channel (docs/compression.md, "The paper's SH-only storage") */
        d.order = 7;
        d.fraction = 0.0;
        d.sh_kind = SSS_SHQ_LINEAR16;
    }
    if (!(given & SSS_CO_ORDER))
        for (o->order = d.order; o->order > 1 && o->order * o->order > n_dirs;) o->order--;
    if (!(given & SSS_CO_FRACTION)) o->fraction = d.fraction;
    if (!(given & SSS_CO_SH_KIND)) o->sh_kind = d.sh_kind;
    if (!(given & SSS_CO_WBITS)) o->wbits = d.wbits;
    if (!(given & SSS_CO_LS_WEIGHTS)) o->ls_weights = d.ls_weights;
    if (!(given & SSS_CO_ILLUM)) o->illum_weight = d.illum_weight;
    o->dirs_f32 = d.dirs_f32; /* the preset's storage, not a user's choice */
}

void sss_compress_opts_to_json(const sss_compress_opts *co, cJSON *params)
{
    cJSON *c = cJSON_AddObjectToObject(params, "compression");
    cJSON_AddNumberToObject(c, "sh_order", co->order);
    cJSON_AddNumberToObject(c, "refs_fraction", co->fraction);
    cJSON_AddStringToObject(c, "sh_quant", sss_shq_name(co->sh_kind));
    cJSON_AddNumberToObject(c, "weight_bits", co->wbits);
    cJSON_AddBoolToObject(c, "ls_weights", co->ls_weights);
    cJSON_AddNumberToObject(c, "illum_refs", co->illum_weight);
}

/* ---- copying what does not change ------------------------------------- */

static void *dup_bytes(const void *p, size_t n)
{
    void *q = malloc(n ? n : 1);
    if (q && n) memcpy(q, p, n);
    return q;
}

static int copy_base(const sss_bake_file *s, sss_bake_file *d)
{
    memset(d, 0, sizeof *d);
    if (sss_mesh_copy(&s->mesh, &d->mesh, NULL) != SSS_OK) return 0;
    d->material = s->material;
    d->layers = s->layers; /* section LAYR: the single scattering's layers */
    /* and their per-vertex depths (section LDEP) */
    if (s->layer_depth &&
        !(d->layer_depth = dup_bytes(s->layer_depth, (size_t)s->mesh.nv * s->layers.n * sizeof(float))))
        return 0;
    d->mm_per_unit = s->mm_per_unit;
    d->eps = s->eps;
    d->channels = s->channels;
    d->near_terms = s->near_terms; /* the rows compressed are what the source holds */
    d->near_rings = s->near_rings;
    /* and which near terms and weights (sections NRAD, QUAD): readers
     * rebuild the near terms and the exact evaluator the sums from them,
     * so a compressed file without them would add the wrong terms back */
    d->near_radius_mm = s->near_radius_mm;
    d->weights = s->weights;
    d->dirs.n = s->dirs.n;
    d->dirs.ntri = s->dirs.ntri;
    d->dirs.dir = dup_bytes(s->dirs.dir, 3 * (size_t)s->dirs.n * sizeof(double));
    d->dirs.tri = dup_bytes(s->dirs.tri, 3 * (size_t)s->dirs.ntri * sizeof(uint32_t));
    const char *j = s->params_json ? s->params_json : "";
    d->params_json = dup_bytes(j, strlen(j) + 1);
    return d->dirs.dir && d->dirs.tri && d->params_json;
}

/* ---- weights (§4.2) ---------------------------------------------------- */

static uint32_t wmax_of(uint32_t wbits) { return wbits == 16 ? 65535u : 255u; }

/* Codes of (w0, w1) in [lo, hi] with rounding. For barycentric weights
 * ([0, 1]) the implied w2 = 1 − w0 − w1 must stay ≥ 0: if rounding pushed
 * the sum past 1, the larger code is lowered. */
static void quantise_weights(double w0, double w1, const sss_refcode *r, int barycentric, uint16_t q[2])
{
    const double span = (double)r->w_hi - r->w_lo, m = wmax_of(r->wbits);
    long a = lround((w0 - r->w_lo) / span * m), b = lround((w1 - r->w_lo) / span * m);
    a = a < 0 ? 0 : a > (long)m ? (long)m : a;
    b = b < 0 ? 0 : b > (long)m ? (long)m : b;
    while (barycentric && a + b > (long)m) {
        if (a >= b) a--;
        else b--;
    }
    q[0] = (uint16_t)a;
    q[1] = (uint16_t)b;
}

/* The decoder's weights (decode.c coded_weights), in double. */
static void dequantise_weights(const sss_refcode *r, const uint16_t q[2], double w[3])
{
    const double span = (double)r->w_hi - r->w_lo, m = wmax_of(r->wbits);
    w[0] = r->w_lo + span * (q[0] / m);
    w[1] = r->w_lo + span * (q[1] / m);
    w[2] = 1.0 - w[0] - w[1];
}

/* Removes from x (nd samples at stride s) its least-squares SH part:
 * x ← x − Y P x, the component the SH order cannot represent. */
static void sh_residual(const sss_sh_projector *proj, const double *Y, uint32_t nd, uint32_t ncoef, double *x,
                        size_t s)
{
    double c[SSS_SH_MAX_COUNT];
    sss_sh_project_strided(proj, x, s, c);
    for (uint32_t j = 0; j < nd; j++) {
        double acc = 0.0;
        for (uint32_t i = 0; i < ncoef; i++) acc += Y[(size_t)j * ncoef + i] * c[i];
        x[j * s] -= acc;
    }
}

/* Least-squares weights (beyond the paper, its §6): with corners a, b, c of
 * the reference triangle and R_k their dequantised rows, minimise
 *     ‖P⊥ (q − R_c − w0 (R_a − R_c) − w1 (R_b − R_c))‖²
 * over all directions and channels, P⊥ removing what the SH order will
 * code anyway (identity at order 0). A 2×2 normal system; when it is
 * singular or ill-conditioned (references with equal rows, a degenerate
 * triangle) the barycentric weights are kept. u, a1, a2: scratch of nd·C. */
static void ls_weights(const double *qv, const double *Ra, const double *Rb, const double *Rc, size_t n, uint32_t C,
                       const sss_sh_projector *proj, const double *Y, uint32_t nd, uint32_t ncoef, double *u,
                       double *a1, double *a2, double w[2])
{
    for (size_t i = 0; i < n; i++) {
        u[i] = qv[i] - Rc[i];
        a1[i] = Ra[i] - Rc[i];
        a2[i] = Rb[i] - Rc[i];
    }
    if (ncoef)
        for (uint32_t c = 0; c < C; c++) {
            sh_residual(proj, Y, nd, ncoef, u + c, C);
            sh_residual(proj, Y, nd, ncoef, a1 + c, C);
            sh_residual(proj, Y, nd, ncoef, a2 + c, C);
        }
    double g00 = 0, g01 = 0, g11 = 0, b0 = 0, b1 = 0;
    for (size_t i = 0; i < n; i++) {
        g00 += a1[i] * a1[i];
        g01 += a1[i] * a2[i];
        g11 += a2[i] * a2[i];
        b0 += a1[i] * u[i];
        b1 += a2[i] * u[i];
    }
    const double det = g00 * g11 - g01 * g01;
    if (!(det > 1e-9 * g00 * g11) || !isfinite(det)) return; /* keep the barycentrics in w */
    double x0 = (g11 * b0 - g01 * b1) / det, x1 = (g00 * b1 - g01 * b0) / det;
    if (!isfinite(x0) || !isfinite(x1)) return;
    w[0] = fmin(fmax(x0, LS_W_LO), LS_W_HI);
    w[1] = fmin(fmax(x1, LS_W_LO), LS_W_HI);
}

/* ---- the compressor ---------------------------------------------------- */

static sss_result check_opts(const sss_bake_file *f, const sss_compress_opts *o, sss_error *err)
{
    if (f->quant != SSS_QUANT_FLOAT || !f->q)
        return sss_fail(err, SSS_ERR_ARG, "compress: needs a float bake (quant %d given)", (int)f->quant);
    if (f->channels < 1 || f->channels > SSS_MAX_CHANNELS)
        return sss_fail(err, SSS_ERR_ARG, "compress: %u channels (1 … %d allowed)", f->channels, SSS_MAX_CHANNELS);
    if (f->mesh.nv == 0 || f->dirs.n == 0 || !f->dirs.dir)
        return sss_fail(err, SSS_ERR_ARG, "compress: empty bake (%u vertices, %u directions)", f->mesh.nv, f->dirs.n);
    if (o->order > SSS_SH_MAX_ORDER)
        return sss_fail(err, SSS_ERR_ARG, "compress: SH order %u out of range 0 … %u", o->order, SSS_SH_MAX_ORDER);
    if (!(o->fraction >= 0.0 && o->fraction <= 1.0))
        return sss_fail(err, SSS_ERR_ARG, "compress: reference fraction %g out of range [0, 1]", o->fraction);
    if (o->fraction == 0.0 && o->order == 0)
        return sss_fail(err, SSS_ERR_ARG, "compress: SH-only mode (no references) needs SH order >= 1");
    if (o->sh_kind >= SSS_SHQ_KINDS)
        return sss_fail(err, SSS_ERR_ARG, "compress: unknown SH quantisation %u", o->sh_kind);
    if (o->wbits != 8 && o->wbits != 16)
        return sss_fail(err, SSS_ERR_ARG, "compress: %u bits per weight (8 or 16)", o->wbits);
    if (!(o->illum_weight >= 0.0) || !isfinite(o->illum_weight))
        return sss_fail(err, SSS_ERR_ARG, "compress: illumination weight %g is not a finite number >= 0",
                        o->illum_weight);
    if (sss_sh_count(o->order) > f->dirs.n)
        return sss_fail(err, SSS_ERR_ARG,
                        "compress: SH order %u has %u coefficients, more than the %u direction samples", o->order,
                        sss_sh_count(o->order), f->dirs.n);
    return SSS_OK;
}

/* References (§4.2): choose them, quantise their rows, list the coded
 * vertices with their triangles (weights are set later). `bary` gets the
 * closest-point barycentrics of every coded vertex (3 per vertex). */
sss_result sss_compress_choose_refs(const sss_bake_file *f, double fraction, double illum_weight, sss_refs *out,
                                   sss_error *err)
{
    if (out) memset(out, 0, sizeof *out);
    if (!f || !out || f->quant != SSS_QUANT_FLOAT || !f->q)
        return sss_fail(err, SSS_ERR_ARG, "compress: references need a float bake");
    const uint32_t nv = f->mesh.nv, C = f->channels, nd = f->dirs.n;
    if (!(illum_weight > 0.0)) return sss_refs_build(&f->mesh, fraction, 1, out, err);
    /* feature: q at every 4th direction sample, channels averaged, so that
     * the decimation sees where the integrals change fast */
    const uint32_t step = 4, dim = (nd + step - 1) / step;
    float *feat = malloc((size_t)nv * dim * sizeof *feat + 1);
    if (!feat) return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for illumination features");
    for (uint32_t v = 0; v < nv; v++)
        for (uint32_t t = 0; t < dim; t++) {
            double acc = 0.0;
            for (uint32_t c = 0; c < C; c++) acc += f->q[((size_t)(t * step) * nv + v) * C + c];
            feat[(size_t)v * dim + t] = (float)(acc / C);
        }
    sss_result res = sss_refs_build_ex(&f->mesh, fraction, 1, feat, dim, illum_weight, out, err);
    free(feat);
    return res;
}

static sss_result build_refs(const sss_bake_file *f, const sss_compress_opts *o, sss_bake_file *d, float **bary,
                             sss_error *err)
{
    const uint32_t nv = f->mesh.nv, C = f->channels, nd = f->dirs.n;
    sss_refcode *r = &d->ref;
    sss_refs built;
    memset(&built, 0, sizeof built);
    const sss_refs *src = o->refs;
    sss_result res = SSS_OK;
    if (src) {
        if (src->nv != nv || src->nref == 0 || !src->ref_vertex || !src->vtri || !src->w)
            return sss_fail(err, SSS_ERR_ARG, "compress: the given references are not for this mesh");
    } else {
        if ((res = sss_compress_choose_refs(f, o->fraction, o->illum_weight, &built, err)) != SSS_OK) return res;
        src = &built;
    }
    const sss_refs refs = *src; /* read-only view: vtri and w are read, the lists copied */
    r->nref = refs.nref;
    r->nrt = refs.nrt;
    r->ref_vertex = malloc((size_t)refs.nref * sizeof *r->ref_vertex + 1);
    r->ref_tri = malloc(3 * (size_t)refs.nrt * sizeof *r->ref_tri + 1);
    if (!r->ref_vertex || !r->ref_tri) {
        sss_refs_free(&built);
        return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for %u references", refs.nref);
    }
    memcpy(r->ref_vertex, refs.ref_vertex, (size_t)refs.nref * sizeof *r->ref_vertex);
    memcpy(r->ref_tri, refs.ref_tri, 3 * (size_t)refs.nrt * sizeof *r->ref_tri);
    r->tri_bytes = sss_refs_tri_bytes(r->nrt);
    r->wbits = o->wbits;
    r->w_lo = o->ls_weights ? LS_W_LO : 0.0f;
    r->w_hi = o->ls_weights ? LS_W_HI : 1.0f;
    const uint32_t ncoded = nv - r->nref;
    const size_t nrq = (size_t)nd * r->nref * C;
    float *refq = malloc(nrq * sizeof *refq + 1);
    r->idx = malloc(nrq + 1);
    r->levels = malloc((size_t)C * 256 * sizeof *r->levels);
    r->coded_vertex = malloc(((size_t)ncoded + 1) * sizeof *r->coded_vertex);
    r->vtri = malloc(((size_t)ncoded + 1) * sizeof *r->vtri);
    r->w = malloc((2 * (size_t)ncoded + 1) * sizeof *r->w);
    *bary = malloc((3 * (size_t)ncoded + 1) * sizeof **bary);
    if (!refq || !r->idx || !r->levels || !r->coded_vertex || !r->vtri || !r->w || !*bary) {
        free(refq);
        sss_refs_free(&built);
        return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for %u references", r->nref);
    }
    for (uint32_t j = 0; j < nd; j++)
        for (uint32_t k = 0; k < r->nref; k++)
            memcpy(refq + ((size_t)j * r->nref + k) * C, f->q + ((size_t)j * nv + r->ref_vertex[k]) * C,
                   C * sizeof *refq);
    /* one Lloyd table per channel, trained on the reference rows only */
    for (uint32_t c = 0; c < C && res == SSS_OK; c++)
        res = sss_lloyd8(refq + c, (uint64_t)nd * r->nref, C, r->levels + 256 * (size_t)c, r->idx + c, NULL, NULL,
                         err);
    free(refq);
    if (res != SSS_OK) {
        sss_refs_free(&built);
        return res;
    }
    uint32_t k = 0, q = 0;
    for (uint32_t v = 0; v < nv; v++) {
        if (q < r->nref && r->ref_vertex[q] == v) {
            q++;
            continue;
        }
        r->coded_vertex[k] = v;
        r->vtri[k] = refs.vtri[v];
        memcpy(*bary + 3 * (size_t)k, refs.w + 3 * (size_t)v, 3 * sizeof **bary);
        k++;
    }
    sss_refs_free(&built);
    return SSS_OK;
}

/* Quantises the coefficient array coef (ncoded × C × ncoef floats) into
 * d->sh per (channel, coefficient index). */
static sss_result quantise_sh(const float *coef, uint32_t kind, sss_bake_file *d, sss_error *err)
{
    sss_shcode *s = &d->sh;
    const size_t C = d->channels, ncoef = s->ncoef, ntab = C * ncoef, nk = s->ncoded, L = sss_shq_levels(kind);
    const size_t ncodes = nk * ntab;
    s->kind = kind;
    s->table = calloc(ntab * L + 1, sizeof *s->table);
    s->code = calloc((size_t)sss_shq_code_bytes(kind, ncodes) + 1, 1);
    const long M = (long)sss_shq_linear_max(kind); /* 127 or 32767 for the linear kinds, else 0 */
    if (M) s->scale = calloc(ntab + 1, sizeof *s->scale);
    if (!s->table || !s->code || (M && !s->scale))
        return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for SH codes");
    if (nk == 0 || ntab == 0) return SSS_OK;
    if (M) {
        /* the paper's: code = round(M c / scale), scale = max |c|, M = 127
         * (§4.3's normalised byte) or 32767 (§4.1's normalised short) */
        for (size_t e = 0; e < ncodes; e++) {
            float a = fabsf(coef[e]);
            if (a > s->scale[e % ntab]) s->scale[e % ntab] = a;
        }
        /* rounding to float may have lowered the scale below max |c| */
        for (size_t t = 0; t < ntab; t++)
            if (s->scale[t] > 0.0f) s->scale[t] = nextafterf(s->scale[t], INFINITY);
        for (size_t e = 0; e < ncodes; e++) {
            double sc = s->scale[e % ntab];
            long q = sc > 0.0 ? lround(coef[e] / sc * (double)M) : 0;
            q = q > M ? M : q < -M ? -M : q;
            if (kind == SSS_SHQ_LINEAR8) {
                s->code[e] = (uint8_t)(int8_t)q;
            } else { /* two bytes, little-endian two's complement */
                const uint16_t u = (uint16_t)(int16_t)q;
                s->code[2 * e] = (uint8_t)(u & 0xFFu);
                s->code[2 * e + 1] = (uint8_t)(u >> 8);
            }
        }
        if (kind == SSS_SHQ_LINEAR8) sss_shq_linear8_table(s->scale, (uint32_t)ntab, s->table);
        else sss_shq_linear16_table(s->scale, (uint32_t)ntab, s->table);
        return SSS_OK;
    }
    /* Lloyd-Max per (channel, coefficient): each column has its own
     * distribution (band 0 positive and wide, high bands narrow around 0) */
    uint8_t *idx = malloc(ncodes + 1);
    if (!idx) return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for SH codes");
    float lev[256];
    for (size_t t = 0; t < ntab; t++) {
        sss_result r = sss_lloyd(coef + t, nk, (uint32_t)ntab, (uint32_t)L, 0, lev, idx + t, NULL, NULL, err);
        if (r != SSS_OK) {
            free(idx);
            return r;
        }
        memcpy(s->table + t * L, lev, L * sizeof *lev);
    }
    if (kind == SSS_SHQ_LLOYD8) memcpy(s->code, idx, ncodes);
    else
        for (size_t e = 0; e < ncodes; e++) s->code[e >> 1] |= (uint8_t)((idx[e] & 15u) << ((e & 1u) * 4u));
    free(idx);
    return SSS_OK;
}

sss_result sss_compress(const sss_bake_file *f, const sss_compress_opts *o, sss_bake_file *d, sss_error *err)
{
    if (d) memset(d, 0, sizeof *d);
    if (!f || !o || !d) return sss_fail(err, SSS_ERR_ARG, "compress: NULL argument");
    sss_result r = check_opts(f, o, err);
    if (r != SSS_OK) return r;
    if (!copy_base(f, d)) {
        sss_file_free(d);
        return sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory copying the bake");
    }
    if (o->dirs_f32) sss_dirset_round_f32(&d->dirs);
    d->dirs_f32 = f->dirs_f32 || o->dirs_f32;
    const uint32_t nv = f->mesh.nv, C = f->channels, nd = f->dirs.n, ncoef = sss_sh_count(o->order);
    const int refmode = o->fraction > 0.0;
    d->quant = refmode ? SSS_QUANT_REFS : SSS_QUANT_SH;
    d->sh.order = o->order;
    d->sh.ncoef = ncoef;
    sss_sh_projector *proj = NULL;
    float *bary = NULL, *coef = NULL;
    double *Y = NULL;

    if (ncoef && (r = sss_sh_projector_create(&f->dirs, o->order, SSS_SH_LEAST_SQUARES, &proj, err)) != SSS_OK)
        goto fail;
    if (refmode && (r = build_refs(f, o, d, &bary, err)) != SSS_OK) goto fail;
    const uint32_t ncoded = refmode ? nv - d->ref.nref : nv;
    d->sh.ncoded = ncoded;
    coef = malloc(((size_t)ncoded * C * ncoef + 1) * sizeof *coef);
    Y = malloc(((size_t)nd * ncoef + 1) * sizeof *Y);
    if (!coef || !Y) {
        r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for %u coded vertices", ncoded);
        goto fail;
    }
    for (uint32_t j = 0; j < nd && ncoef; j++) sss_sh_eval(o->order, f->dirs.dir + 3 * (size_t)j, Y + (size_t)j * ncoef);

    /* ---- weights and deltas (§4.2–4.3), SH projection (§4.1) ----------- */
    {
        const size_t n = (size_t)nd * C;
        const ptrdiff_t ncod = (ptrdiff_t)ncoded;
        int nomem = 0;
        const sss_refcode *rc = &d->ref;
#ifdef _OPENMP
#pragma omp parallel
#endif
        {
            double *buf = malloc((7 * n + 1) * sizeof *buf);
            if (!buf) {
#ifdef _OPENMP
#pragma omp atomic write
#endif
                nomem = 1;
            }
            double *qv = buf, *R[3] = {buf + n, buf + 2 * n, buf + 3 * n}, *u = buf + 4 * n, *a1 = buf + 5 * n,
                   *a2 = buf + 6 * n;
            double cf[SSS_SH_MAX_COUNT];
#ifdef _OPENMP
#pragma omp for schedule(dynamic, 256)
#endif
            for (ptrdiff_t k = 0; k < ncod; k++) {
                if (!buf) continue;
                const uint32_t v = refmode ? rc->coded_vertex[k] : (uint32_t)k;
                for (size_t i = 0; i < n; i++) qv[i] = f->q[((i / C) * nv + v) * C + i % C];
                if (refmode) {
                    const uint32_t *t = rc->ref_tri + 3 * (size_t)rc->vtri[k];
                    for (int s = 0; s < 3; s++)
                        for (size_t i = 0; i < n; i++) {
                            const size_t j = i / C, c = i % C;
                            R[s][i] = rc->levels[256 * c + rc->idx[(j * rc->nref + t[s]) * C + c]];
                        }
                    double w[3] = {bary[3 * (size_t)k], bary[3 * (size_t)k + 1], 0.0};
                    if (o->ls_weights)
                        ls_weights(qv, R[0], R[1], R[2], n, C, proj, Y, nd, ncoef, u, a1, a2, w);
                    uint16_t wq[2];
                    quantise_weights(w[0], w[1], rc, !o->ls_weights, wq);
                    d->ref.w[2 * (size_t)k] = wq[0];
                    d->ref.w[2 * (size_t)k + 1] = wq[1];
                    dequantise_weights(rc, wq, w);
                    for (size_t i = 0; i < n; i++) qv[i] -= w[0] * R[0][i] + w[1] * R[1][i] + w[2] * R[2][i];
                }
                for (uint32_t c = 0; c < C && ncoef; c++) {
                    sss_sh_project_strided(proj, qv + c, C, cf);
                    for (uint32_t i = 0; i < ncoef; i++) coef[((size_t)k * C + c) * ncoef + i] = (float)cf[i];
                }
            }
            free(buf);
        }
        if (nomem) {
            r = sss_fail(err, SSS_ERR_NOMEM, "compress: out of memory for delta rows");
            goto fail;
        }
    }
    if ((r = quantise_sh(coef, o->sh_kind, d, err)) != SSS_OK) goto fail;

    free(Y);
    free(coef);
    free(bary);
    sss_sh_projector_destroy(proj);
    return SSS_OK;

fail:
    free(Y);
    free(coef);
    free(bary);
    sss_sh_projector_destroy(proj);
    sss_file_free(d);
    return r;
}
