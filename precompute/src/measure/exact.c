/* exact.c: q(x_o, ω) for an arbitrary light direction, recomputed from a
 * .sss file with the bake's own pieces (Hao–Varshney 2004 §3.1): the
 * neighbourhoods and weights of nbhd.c, the transfer term of transfer.c and
 * the occlusion rays of visibility.c. It is the reference against which the
 * direction interpolation (§3.2), the Lloyd quantisation and the compressed
 * forms (§4) are measured, so it must not share their approximations: no
 * direction samples, no quantisation.
 */
#include "sss/exact.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sss/fieldweights.h"
#include "sss/hatweights.h"
#include "sss/memory.h"
#include "sss/nbhd.h"
#include "sss/transfer.h"
#include "sss/vec3.h"
#include "sss/visibility.h"
#include "kernels/transfer.h"

/* The bake's default cutoff (sss_bake_options.eps = 0 means this). */
#define EXACT_DEFAULT_EPS 1e-3

struct sss_exact {
    sss_mesh mesh;   /* own copy: positions, stored normals, tri, recomputed ΔA */
    uint32_t channels;
    double eta;
    double eps, search_radius_mm;
    sss_weights nb;     /* one row per vertex, rows in vertex order */
    sss_weights hat;    /* files with section QUAD: the hat-function corrections per row (sss/hatweights.h) */
    sss_vis *vis;    /* refers to mesh */
    int shadows;     /* 0: V ≡ 1 (sss_exact_set_shadows; diagnostics only) */
};

/* ε from the bake parameters. The bake writes every input it used into PARM
 * (bake.c params_json); an empty PARM (a file from another writer) means the
 * bake's default. A PARM that is not JSON, or an "eps" that is not a valid
 * cutoff, is refused: silently falling back would make the "exact"
 * reference use a different neighbourhood than the bake did. */
static sss_result read_eps(const char *json, double *eps, sss_error *err)
{
    *eps = EXACT_DEFAULT_EPS;
    if (!json) return SSS_OK;
    const char *p = json;
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') p++;
    if (!*p) return SSS_OK;
    cJSON *o = cJSON_Parse(json);
    if (!o || !cJSON_IsObject(o)) {
        cJSON_Delete(o);
        return sss_fail(err, SSS_ERR_CORRUPT, "section PARM: bake parameters are not a JSON object");
    }
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(o, "eps");
    sss_result r = SSS_OK;
    if (e) {
        if (!cJSON_IsNumber(e) || !(e->valuedouble > 0.0 && e->valuedouble < 1.0))
            r = sss_fail(err, SSS_ERR_CORRUPT, "section PARM: \"eps\" must be a number in (0, 1)");
        else
            *eps = e->valuedouble;
    }
    cJSON_Delete(o);
    return r;
}

/* The mesh as the bake used it: the file's positions, triangles and normals
 * (GEOM stores the bake's own normals) and ΔA recomputed from the float
 * positions with the same sums in the same order (docs/format.md §5.1). */
static sss_result copy_mesh(const sss_mesh *src, sss_mesh *dst, sss_error *err)
{
    const sss_mesh geom = {.nv = src->nv, .nf = src->nf, .pos = src->pos, .nrm = src->nrm, .tri = src->tri}; /* ΔA recomputed */
    sss_result r = sss_mesh_copy(&geom, dst, err);
    if (r != SSS_OK) return r;
    if (!(dst->area = malloc((size_t)src->nv * sizeof(double)))) {
        sss_mesh_free(dst);
        return sss_fail(err, SSS_ERR_NOMEM, "exact evaluator: out of memory for %u vertices", src->nv);
    }
    sss_mesh_vertex_areas(dst, dst->area);
    return SSS_OK;
}

static sss_result create(const sss_bake_file *f, int plan, uint64_t memory_limit, sss_exact **out, sss_error *err);

sss_result sss_exact_create(const sss_bake_file *f, sss_exact **out, sss_error *err)
{
    return create(f, 0, 0, out, err);
}

sss_result sss_exact_create_limited(const sss_bake_file *f, uint64_t memory_limit, sss_exact **out, sss_error *err)
{
    return create(f, 1, memory_limit, out, err);
}

static sss_result create(const sss_bake_file *f, int plan, uint64_t memory_limit, sss_exact **out, sss_error *err)
{
    *out = NULL;
    if (!f || f->mesh.nv == 0 || f->mesh.nf == 0 || !f->mesh.pos || !f->mesh.nrm || !f->mesh.tri)
        return sss_fail(err, SSS_ERR_ARG, "exact evaluator: the file has no mesh");
    if (f->channels < 1 || f->channels > SSS_MAX_CHANNELS)
        return sss_fail(err, SSS_ERR_ARG, "exact evaluator: %u channels (1 or 3 expected)", f->channels);
    if (!(f->mm_per_unit > 0) || !isfinite(f->mm_per_unit))
        return sss_fail(err, SSS_ERR_ARG, "exact evaluator: mm per unit %g must be a finite number > 0", f->mm_per_unit);
    /* ε from section NBHD (docs/format.md §5.15); files before 1.4 hold it
     * only in PARM */
    double eps = f->eps;
    sss_result r = eps != 0.0 ? SSS_OK : read_eps(f->params_json, &eps, err);
    if (r != SSS_OK) return r;
    sss_dipole dip[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < f->channels; c++) {
        r = sss_dipole_init(&dip[c], f->material.sigma_a[c], f->material.sigmap_s[c], f->material.eta);
        if (r != SSS_OK)
            return sss_fail(err, r, "section MATL: channel %u: sigma_a %g, sigma'_s %g, eta %g do not make a dipole", c,
                            f->material.sigma_a[c], f->material.sigmap_s[c], f->material.eta);
    }

    sss_exact *e = calloc(1, sizeof *e);
    if (!e) return sss_fail(err, SSS_ERR_NOMEM, "exact evaluator: out of memory");
    e->channels = f->channels;
    e->eta = f->material.eta;
    e->shadows = 1;
    e->eps = eps;
    r = copy_mesh(&f->mesh, &e->mesh, err);
    if (r != SSS_OK) { free(e); return r; }

    /* The bake's radius rule (bake.c): per channel the disk holding 1−ε of
     * R_d,total (docs/physics.md §2 (b)), clamped to the object's diagonal;
     * the search uses the largest. Recomputed, not read from PARM, where it
     * is rounded to 9 digits: the membership test r ≤ radius must match. */
    e->search_radius_mm = sss_nbhd_radii(&e->mesh, f->mm_per_unit, dip, f->channels, eps, NULL);
    /* A heterogeneous object (section FELD): the bake's rows for the
     * reference material, scaled by the spatially varying kernel
     * (sss/fieldweights.h, docs/heterogeneous.md §4), as the scene bake
     * built them. */
    sss_field_kernel fk;
    memset(&fk, 0, sizeof fk);
    if (f->hetero.field.kind != SSS_FIELD_NONE) {
        r = sss_field_kernel_create(&e->mesh, f->mm_per_unit, &f->material, &f->hetero, f->channels, eps,
                                    "section FELD", &fk, err);
        if (r != SSS_OK) {
            sss_exact_destroy(e);
            return r;
        }
        memcpy(dip, fk.dip_ref, sizeof dip);
        e->search_radius_mm = fk.radius_mm;
    }
    /* The neighbourhood rows are counted before they are allocated and
     * refused, as the bake refuses them (bake.c), beyond 90 % of what is
     * left after the mesh copy and one row of G per vertex: for σa → 0 they
     * hold every pair of vertices (docs/robustness.md, "Memory"). */
    uint64_t max_bytes = 0;
    const uint64_t avail = plan ? sss_memory_available(memory_limit) : 0;
    if (avail) {
        const uint64_t fixed = (uint64_t)f->mesh.nv * (12u + 12u + 8u + 4u) + (uint64_t)f->mesh.nf * 12u;
        max_bytes = avail > fixed ? (avail - fixed) / 10 * 9 : 1;
    }
    r = sss_nbhd_build(&e->mesh, f->mm_per_unit, dip, f->channels, e->search_radius_mm, NULL, 0, max_bytes, NULL,
                       &e->nb, err);
    /* the bake's weight rule (section QUAD): its corrections, as the bake
     * computed them */
    if (r == SSS_OK && f->weights == SSS_WEIGHTS_HAT)
        r = sss_hat_corrections(&e->mesh, f->mm_per_unit, dip, f->channels, e->search_radius_mm, NULL, 0, NULL,
                                &e->hat, err);
    if (r == SSS_OK && fk.f) r = sss_field_weights_apply(&fk, &e->mesh, &e->nb, NULL, err);
    if (r == SSS_OK && fk.f && e->hat.nrows) r = sss_field_weights_apply(&fk, &e->mesh, &e->hat, NULL, err);
    sss_field_kernel_free(&fk);
    if (r == SSS_OK) r = sss_vis_create(&e->mesh, &e->vis, err);
    if (r != SSS_OK) {
        sss_exact_destroy(e);
        return r;
    }
    *out = e;
    return SSS_OK;
}

void sss_exact_destroy(sss_exact *e)
{
    if (!e) return;
    sss_vis_destroy(e->vis);
    sss_weights_free(&e->nb);
    sss_weights_free(&e->hat);
    sss_mesh_free(&e->mesh);
    free(e);
}

uint32_t sss_exact_vertices(const sss_exact *e) { return e->mesh.nv; }
uint32_t sss_exact_channels(const sss_exact *e) { return e->channels; }
double sss_exact_eps(const sss_exact *e) { return e->eps; }
double sss_exact_search_radius_mm(const sss_exact *e) { return e->search_radius_mm; }
void sss_exact_set_shadows(sss_exact *e, int on) { e->shadows = on != 0; }

/* Row v of the sparse sum q = Σ_i w(v, i) G(x_i, ω) with G taken from g
 * (a table over all vertices) or, when g is NULL, traced on the fly. The
 * products and their order are sss_integrate's (double accumulation,
 * neighbours in increasing index order), so a direction sample gives the
 * bake's float exactly. */
static void row_sum(const sss_exact *e, uint32_t v, const double d[3], const float *g, float *out)
{
    const uint32_t C = e->channels;
    double acc[SSS_MAX_CHANNELS] = {0};
    const int hat = e->hat.nrows > 0;
    for (int part = 0; part < (hat ? 2 : 1); part++) { /* the neighbours, then the corrections (sss_integrate_hat) */
        const sss_weights *rw = part ? &e->hat : &e->nb;
        for (uint64_t k = rw->start[v]; k < rw->start[v + 1]; k++) {
            const uint32_t i = rw->idx[k];
            const float gi = g ? g[i] : sss_transfer_one(&e->mesh, e->shadows ? e->vis : NULL, i, d, e->eta, NULL, NULL);
            const float *w = &rw->w[k * C];
            for (uint32_t c = 0; c < C; c++) {
                double wc = w[c];
                acc[c] += wc * gi;
            }
        }
    }
    for (uint32_t c = 0; c < C; c++) {
        const float x = (float)acc[c];
        out[c] = hat && !(x > 0.0f) ? 0.0f : x;
    }
}

void sss_exact_eval_vertex(const sss_exact *e, uint32_t v, const double light[3], float *out)
{
    double d[3];
    if (v >= e->mesh.nv || !sss_light_unit(light, d)) {
        for (uint32_t c = 0; c < e->channels; c++) out[c] = 0.0f;
        return;
    }
    row_sum(e, v, d, NULL, out);
}

void sss_exact_eval(const sss_exact *e, const double light[3], float *out)
{
    const uint32_t nv = e->mesh.nv, C = e->channels;
    double d[3];
    if (!sss_light_unit(light, d)) {
        memset(out, 0, (size_t)nv * C * sizeof *out);
        return;
    }
    /* G for every vertex once (each is shared by all the neighbourhoods that
     * hold it: one ray per vertex), then the sparse sums. Without memory for
     * the table, every row traces its own rays: slower, same values. */
    float *g = malloc((size_t)nv * sizeof *g);
    if (g) {
#pragma omp parallel for schedule(dynamic, 256)
        for (int64_t i = 0; i < (int64_t)nv; i++)
            g[i] = sss_transfer_one(&e->mesh, e->shadows ? e->vis : NULL, (uint32_t)i, d, e->eta, NULL, NULL);
    }
#pragma omp parallel for schedule(dynamic, 64)
    for (int64_t v = 0; v < (int64_t)nv; v++) row_sum(e, (uint32_t)v, d, g, &out[(size_t)v * C]);
    free(g);
}

/* G tables of the subset: at most this many floats (16 MiB), one row of nv
 * per light, so that a batch of lights takes one parallel region (a region
 * per light costs more than the light on a busy machine). */
#define SUBSET_TABLE_FLOATS (1u << 22)
#define SUBSET_BATCH_MAX 256u

struct sss_exact_subset {
    const sss_exact *e;
    uint32_t n;        /* receivers */
    uint32_t *verts;
    uint64_t nsrc;     /* sources: the union of the receivers' rows (and hat corrections) */
    uint32_t *src;     /* in increasing index order */
    uint32_t batch;    /* lights per table */
    float *g;          /* G at the sources, light b of the batch at g[b * nv + i] */
    double *d;         /* the batch's unit lights */
    int *ok;           /* 0: a zero or non-finite light */
};

sss_result sss_exact_subset_create(const sss_exact *e, const uint32_t *verts, uint32_t n, uint64_t max_sources,
                                   sss_exact_subset **out, sss_error *err)
{
    *out = NULL;
    if (!e || !verts || n == 0) return sss_fail(err, SSS_ERR_ARG, "exact evaluator: an empty set of receivers");
    const uint32_t nv = e->mesh.nv;
    for (uint32_t k = 0; k < n; k++)
        if (verts[k] >= nv)
            return sss_fail(err, SSS_ERR_ARG, "exact evaluator: receiver %u is vertex %u, beyond the mesh's %u", k,
                            verts[k], nv);
    sss_exact_subset *s = calloc(1, sizeof *s);
    uint32_t *stamp = calloc(nv, sizeof *stamp); /* k + 1: first taken by receiver k; 0: not a source */
    if (s) {
        s->batch = SUBSET_TABLE_FLOATS / nv;
        if (s->batch < 1) s->batch = 1;
        if (s->batch > SUBSET_BATCH_MAX) s->batch = SUBSET_BATCH_MAX;
        s->verts = malloc((size_t)n * sizeof *s->verts);
        s->g = calloc((size_t)nv * s->batch, sizeof *s->g);
        s->d = malloc(3 * (size_t)s->batch * sizeof *s->d);
        s->ok = malloc((size_t)s->batch * sizeof *s->ok);
    }
    if (!s || !stamp || !s->verts || !s->g || !s->d || !s->ok) {
        free(stamp);
        sss_exact_subset_destroy(s);
        return sss_fail(err, SSS_ERR_NOMEM, "exact evaluator: out of memory for %u receivers", n);
    }
    s->e = e;
    const int hat = e->hat.nrows > 0;
    uint64_t total = 0;
    uint32_t k = 0;
    for (; k < n; k++) {
        const uint32_t v = verts[k];
        uint64_t added = 0;
        for (int part = 0; part < (hat ? 2 : 1); part++) {
            const sss_weights *rw = part ? &e->hat : &e->nb;
            for (uint64_t j = rw->start[v]; j < rw->start[v + 1]; j++)
                if (!stamp[rw->idx[j]]) stamp[rw->idx[j]] = k + 1, added++;
        }
        if (k > 0 && max_sources && total + added > max_sources) { /* over the limit: not taken */
            for (int part = 0; part < (hat ? 2 : 1); part++) {
                const sss_weights *rw = part ? &e->hat : &e->nb;
                for (uint64_t j = rw->start[v]; j < rw->start[v + 1]; j++)
                    if (stamp[rw->idx[j]] == k + 1) stamp[rw->idx[j]] = 0;
            }
            break;
        }
        total += added;
        s->verts[k] = v;
    }
    s->n = k;
    s->nsrc = total;
    s->src = malloc((size_t)(total ? total : 1) * sizeof *s->src);
    if (!s->src) {
        free(stamp);
        sss_exact_subset_destroy(s);
        return sss_fail(err, SSS_ERR_NOMEM, "exact evaluator: out of memory for %llu sources",
                        (unsigned long long)total);
    }
    uint64_t m = 0;
    for (uint32_t i = 0; i < nv; i++)
        if (stamp[i]) s->src[m++] = i;
    free(stamp);
    *out = s;
    return SSS_OK;
}

uint32_t sss_exact_subset_vertices(const sss_exact_subset *s) { return s->n; }
uint64_t sss_exact_subset_sources(const sss_exact_subset *s) { return s->nsrc; }

void sss_exact_subset_eval(sss_exact_subset *s, const double *lights, uint32_t nlights, float *out)
{
    const sss_exact *e = s->e;
    const uint32_t C = e->channels, nv = e->mesh.nv, n = s->n;
    for (uint32_t l0 = 0; l0 < nlights; l0 += s->batch) {
        const uint32_t B = nlights - l0 < s->batch ? nlights - l0 : s->batch;
        for (uint32_t b = 0; b < B; b++) s->ok[b] = sss_light_unit(&lights[3 * ((size_t)l0 + b)], &s->d[3 * (size_t)b]);
        /* G once per source and light (sss_exact_eval's table, restricted
         * to the rows that are read), then each receiver's row in its own
         * order: every value is computed by one thread, so the result does
         * not depend on their number */
#pragma omp parallel for schedule(dynamic, 16)
        for (int64_t t = 0; t < (int64_t)s->nsrc * B; t++) {
            const uint32_t b = (uint32_t)(t % B), i = s->src[t / B];
            s->g[(size_t)b * nv + i] = s->ok[b] ? sss_transfer_one(&e->mesh, e->shadows ? e->vis : NULL, i,
                                                                    &s->d[3 * (size_t)b], e->eta, NULL, NULL)
                                                : 0.0f;
        }
#pragma omp parallel for schedule(dynamic, 16)
        for (int64_t t = 0; t < (int64_t)n * B; t++) {
            const uint32_t b = (uint32_t)(t / n), k = (uint32_t)(t % n);
            float *o = &out[(((size_t)l0 + b) * n + k) * C];
            if (s->ok[b]) row_sum(e, s->verts[k], &s->d[3 * (size_t)b], &s->g[(size_t)b * nv], o);
            else memset(o, 0, C * sizeof *o);
        }
    }
}

void sss_exact_subset_destroy(sss_exact_subset *s)
{
    if (!s) return;
    free(s->verts);
    free(s->src);
    free(s->g);
    free(s->d);
    free(s->ok);
    free(s);
}
