/* reference.c: the drivers of the path-traced reference (sss/reference.h):
 * materials into media, the viewer's camera, and one scheduler for
 * queries, pixels and particles that makes the result a function of the
 * seed and the path count alone (docs/reference.md §4).
 *
 * Scheduling: a task (a query, a pixel, a beam) runs its paths in blocks of
 * REF_BLOCK; a round gives every task `lanes` blocks (lanes depends on the
 * task count only), each block one item, the items of a round spread over
 * threads (and over processes, item i on rank i mod nranks). A block sums
 * its paths in order; after the round each task adds its blocks in lane
 * order. So no sum depends on which thread or rank computed what, and a
 * time budget stops between rounds. */
#include "sss/reference.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#include "kernels/progress.h"
#include "reference/ref_internal.h"
#include "sss/field.h"
#include "sss/vec3.h"

/* paths per block, and blocks per round over all tasks at least (when
 * there are fewer tasks, each gets several lanes) */
#define REF_BLOCK 16
#define REF_ROUND_BLOCKS 64

sss_result sss_ref_medium_validate(const sss_ref_medium *m, sss_error *err)
{
    for (int c = 0; c < 3; c++) {
        if (!isfinite(m->sigma_a[c]) || !isfinite(m->sigma_s[c]) || m->sigma_a[c] < 0.0 || m->sigma_s[c] < 0.0 ||
            !(m->sigma_a[c] + m->sigma_s[c] > 0.0) || m->sigma_a[c] > SSS_SIGMA_MAX || m->sigma_s[c] > SSS_SIGMA_MAX)
            return sss_fail(err, SSS_ERR_ARG, "medium: channel %d: sigma_a %g, sigma_s %g: need 0 <= each <= %g and a positive sum",
                            c, m->sigma_a[c], m->sigma_s[c], SSS_SIGMA_MAX);
    }
    if (!(fabs(m->g) < 1.0)) return sss_fail(err, SSS_ERR_ARG, "medium: g %g must lie in (-1, 1)", m->g);
    if (!(m->eta >= SSS_ETA_MIN && m->eta <= SSS_ETA_MAX))
        return sss_fail(err, SSS_ERR_ARG, "medium: eta %g must lie in [%g, %g]", m->eta, SSS_ETA_MIN, SSS_ETA_MAX);
    if (m->hetero && m->hetero->field.kind != SSS_FIELD_NONE) {
        /* a surface texture (Hao–Varshney 2004 §5) changes the material at
         * the surface points only: a medium whose paths go between them
         * has no such material to track (docs/reference.md §3.1) */
        if (m->hetero->surface)
            return sss_fail(err, SSS_ERR_UNSUPPORTED, "a surface texture (section FELD) has no volume for the paths to "
                            "track: no reference for it (docs/reference.md sec. 3.1)");
        sss_result r = sss_field_check(&m->hetero->field, err);
        if (r != SSS_OK) return r;
        const sss_material *in = &m->hetero->inside;
        for (int c = 0; c < 3; c++) {
            const double sa = in->sigma_a[c], ss = in->sigmap_s[c] / (1.0 - m->g);
            if (!isfinite(sa) || !isfinite(ss) || sa < 0.0 || ss < 0.0 || !(sa + ss > 0.0) || sa > SSS_SIGMA_MAX ||
                ss > SSS_SIGMA_MAX)
                return sss_fail(err, SSS_ERR_ARG, "medium: the field's inside material, channel %d: sigma_a %g, "
                                "sigma_s %g: need 0 <= each <= %g and a positive sum", c, sa, ss, SSS_SIGMA_MAX);
        }
    }
    return SSS_OK;
}

sss_result sss_ref_medium_from_material(const sss_material *m, double g, sss_ref_medium *out, sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (!(fabs(g) < 1.0)) return sss_fail(err, SSS_ERR_ARG, "medium: g %g must lie in (-1, 1)", g);
    sss_result r = sss_material_validate(m, err);
    if (r != SSS_OK) return r;
    for (int c = 0; c < 3; c++) {
        out->sigma_a[c] = m->sigma_a[c];
        out->sigma_s[c] = m->sigmap_s[c] / (1.0 - g); /* σ′s = σs (1 − g), docs/physics.md §1 */
    }
    out->g = g;
    out->eta = m->eta;
    return sss_ref_medium_validate(out, err);
}

void sss_ref_camera_view(const sss_mesh *m, const double view[3], int width, int height, sss_ref_camera *cam)
{
    /* the renderer's frame (runtime's draw.c: sss_view_frame) about the
     * bounding sphere the viewer and the light-space maps use */
    double centre[3];
    const double radius = sss_mesh_bounding_sphere(m, centre);
    double v[3] = {view[0], view[1], view[2]};
    sss_normalize3(v);
    if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.5)) v[0] = 0, v[1] = 0, v[2] = 1;
    double wup[3] = {0, 1, 0};
    if (fabs(v[1]) > 0.999) wup[1] = 0, wup[2] = 1;
    for (int k = 0; k < 3; k++) cam->fwd[k] = -v[k];
    sss_cross3(cam->fwd, wup, cam->right);
    sss_normalize3(cam->right);
    sss_cross3(cam->right, cam->fwd, cam->up);
    for (int k = 0; k < 3; k++) cam->eye[k] = centre[k] + v[k] * 3.6 * radius;
    cam->tan_half_fov = tan(0.5 * 35.0 * SSS_PI / 180.0);
    cam->width = width;
    cam->height = height;
}

/* ---- the scheduler ---- */

/* One path of task `task` into vals[nvals]. */
typedef void (*ref_path_fn)(const void *job, uint64_t task, uint64_t path, double *vals, ref_counters *k);

typedef struct ref_run {
    uint64_t ntasks;
    uint32_t nvals;
    ref_path_fn fn;
    const void *job;
    double *s1, *s2; /* ntasks × nvals sums of the values and of their squares */
    uint64_t n;      /* paths per task summed */
} ref_run;

static int nthreads(const sss_ref_options *o) { return o->threads > 0 ? o->threads : omp_get_max_threads(); }

static void add_counters(sss_ref_stats *st, const ref_counters *k)
{
    st->walks += k->walks;
    st->rays += k->rays;
    st->scatterings += k->scatterings;
    st->nee += k->nee;
    st->nee_hits += k->nee_hits;
    st->nee_unsolved += k->nee_unsolved;
    st->nee_skipped += k->nee_skipped;
    st->leaks += k->leaks;
    st->truncated += k->truncated;
    st->crossed += k->crossed;
}

static sss_result schedule(ref_run *run, const sss_ref_options *o, sss_ref_stats *st, sss_error *err)
{
    const double t0 = sss_now();
    const uint64_t nt = run->ntasks;
    const uint32_t nv = run->nvals;
    const uint64_t lanes = nt >= REF_ROUND_BLOCKS ? 1 : (REF_ROUND_BLOCKS + nt - 1) / nt;
    const int timed = o->seconds > 0.0;
    const uint64_t N = o->paths ? o->paths : timed ? UINT64_MAX : 1024;
    const uint64_t nb = N == UINT64_MAX ? UINT64_MAX : (N + REF_BLOCK - 1) / REF_BLOCK;
    const uint64_t items = nt * lanes;
    const int nranks = o->comm && o->nranks > 1 ? o->nranks : 1, rank = nranks > 1 ? o->rank : 0;
    if (items > (uint64_t)1 << 40) return sss_fail(err, SSS_ERR_ARG, "reference: %llu tasks is too many", (unsigned long long)nt);
    double *buf = calloc((size_t)items * 2 * nv, sizeof(double));
    run->s1 = calloc((size_t)nt * nv, sizeof(double));
    run->s2 = calloc((size_t)nt * nv, sizeof(double));
    if (!buf || !run->s1 || !run->s2) {
        free(buf);
        return sss_fail(err, SSS_ERR_NOMEM, "reference: out of memory for %llu tasks", (unsigned long long)nt);
    }
    run->n = 0;
    const uint64_t rounds = nb == UINT64_MAX ? UINT64_MAX : (nb + lanes - 1) / lanes;
    const int show = o->progress && rank == 0;
    sss_progress_enable(show, show ? o->progress_log : NULL);
    if (show) sss_progress_begin(timed ? "paths (time)" : "paths", timed ? (uint64_t)(o->seconds * 1000.0) : rounds * items);
    sss_result res = SSS_OK;
    uint32_t r = 0;
    uint64_t shown_ms = 0;
    for (uint64_t round = 0; round < rounds; round++) {
        memset(buf, 0, (size_t)items * 2 * nv * sizeof(double));
        ref_counters tot = {0};
        int stop = 0;
#pragma omp parallel num_threads(nthreads(o))
        {
            ref_counters k = {0};
            double *vals = malloc(sizeof(double) * nv);
#pragma omp for schedule(dynamic, 1)
            for (int64_t i = rank; i < (int64_t)items; i += nranks) {
                if (!vals || sss_cancelled(o->cancel)) continue;
                const uint64_t task = (uint64_t)i / lanes, block = round * lanes + (uint64_t)i % lanes;
                if (block >= nb) continue;
                const uint64_t p0 = block * REF_BLOCK, p1 = N - p0 < REF_BLOCK ? N : p0 + REF_BLOCK;
                double *b1 = buf + (size_t)i * 2 * nv, *b2 = b1 + nv;
                k.walks += p1 - p0;
                for (uint64_t p = p0; p < p1; p++) {
                    run->fn(run->job, task, p, vals, &k);
                    for (uint32_t j = 0; j < nv; j++) {
                        b1[j] += vals[j];
                        b2[j] += vals[j] * vals[j];
                    }
                }
                if (show && !timed) sss_progress_tick(1);
            }
            free(vals);
#pragma omp critical(sss_ref_counters)
            {
                tot.walks += k.walks;
                tot.rays += k.rays;
                tot.scatterings += k.scatterings;
                tot.nee += k.nee;
                tot.nee_hits += k.nee_hits;
                tot.nee_unsolved += k.nee_unsolved;
                tot.nee_skipped += k.nee_skipped;
                tot.leaks += k.leaks;
                tot.truncated += k.truncated;
                tot.crossed += k.crossed;
            }
        }
        add_counters(st, &tot);
        if (sss_cancelled(o->cancel)) {
            res = sss_fail(err, SSS_ERR_INTERRUPTED, "reference: interrupted");
            break;
        }
        if (nranks > 1 && o->comm->allsum(buf, items * 2 * nv, o->comm->ctx) != 0) {
            res = sss_fail(err, SSS_ERR_IO, "reference: collective failed");
            break;
        }
        /* every task the same number of paths this round */
        const uint64_t b0 = round * lanes, b1 = b0 + lanes < nb ? b0 + lanes : nb;
        const uint64_t pend = b1 * REF_BLOCK < N ? b1 * REF_BLOCK : N;
        run->n = pend;
        for (uint64_t t = 0; t < nt; t++)
            for (uint64_t l = 0; l < lanes; l++) {
                const double *s = buf + (size_t)(t * lanes + l) * 2 * nv;
                for (uint32_t j = 0; j < nv; j++) {
                    run->s1[t * nv + j] += s[j];
                    run->s2[t * nv + j] += s[nv + j];
                }
            }
        r++;
        if (timed) {
            const double el = sss_now() - t0;
            const uint64_t ms = (uint64_t)(fmin(el, o->seconds) * 1000.0);
            if (show && ms > shown_ms) {
                sss_progress_tick(ms - shown_ms);
                shown_ms = ms;
            }
            stop = el >= o->seconds;
            if (nranks > 1 && o->comm->bcast(&stop, o->comm->ctx) != 0) {
                res = sss_fail(err, SSS_ERR_IO, "reference: collective failed");
                break;
            }
            if (stop) break;
        }
    }
    if (show) sss_progress_end();
    free(buf);
    st->paths = run->n;
    st->rounds = r;
    st->seconds = sss_now() - t0;
    return res;
}

/* mean and standard error from the sums of n values */
static void finish(const double *s1, const double *s2, uint64_t n, double *mean, double *se)
{
    if (n == 0) {
        *mean = 0.0;
        if (se) *se = 0.0;
        return;
    }
    const double m = *s1 / (double)n;
    *mean = m;
    if (se) {
        const double var = n > 1 ? fmax(0.0, (*s2 - *s1 * m) / (double)(n - 1)) : 0.0;
        *se = sqrt(var / (double)n);
    }
}

/* ---- radiance: queries and pixels ---- */

static sss_result make_ctx(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                           const sss_ref_options *o, ref_ctx *c, sss_error *err)
{
    memset(c, 0, sizeof *c);
    sss_result r = sss_ref_medium_validate(m, err);
    if (r != SSS_OK) return r;
    c->s = s;
    ref_medium_init(m, s->mm_per_unit, &c->m);
    c->light = l->kind;
    if (l->kind == SSS_REF_DIRECTIONAL) {
        memcpy(c->wl, l->dir, sizeof c->wl);
        if (!(sss_normalize3(c->wl) > 0.0) || !isfinite(c->wl[0] + c->wl[1] + c->wl[2]))
            return sss_fail(err, SSS_ERR_ARG, "reference: the light direction is not a direction");
    } else if (l->kind == SSS_REF_ENVIRONMENT) {
        c->probe = l->probe;
    } else if (l->kind == SSS_REF_POINT) {
        for (int k = 0; k < 3; k++) c->P[k] = l->pos[k] * s->mm_per_unit;
        c->I = l->intensity * s->mm_per_unit * s->mm_per_unit;
        if (!isfinite(c->P[0] + c->P[1] + c->P[2]) || fabs(l->pos[0]) > SSS_COORD_MAX ||
            fabs(l->pos[1]) > SSS_COORD_MAX || fabs(l->pos[2]) > SSS_COORD_MAX)
            return sss_fail(err, SSS_ERR_ARG, "reference: the point light's position (%g, %g, %g) is out of range",
                            l->pos[0], l->pos[1], l->pos[2]);
        if (!(l->intensity > 0.0 && isfinite(c->I)))
            return sss_fail(err, SSS_ERR_ARG, "reference: the point light's intensity %g must be finite and > 0",
                            l->intensity);
        /* the light must be outside: the first wall a ray from P meets is
         * then seen from outside; three rays vote, for a mesh with holes */
        static const double probe_dir[3][3] = {{0.48, 0.6, 0.64}, {-0.8, 0.36, -0.48}, {0.0, -0.6, 0.8}};
        int inside = 0;
        for (int i = 0; i < 3; i++) {
            ref_hit h;
            if (ref_intersect(s, c->P, probe_dir[i], 0.0, &h) && sss_dot3(probe_dir[i], h.ng) > 0.0) inside++;
        }
        if (inside >= 2)
            return sss_fail(err, SSS_ERR_ARG, "reference: the point light at (%g, %g, %g) is inside the mesh",
                            l->pos[0], l->pos[1], l->pos[2]);
    } else {
        return sss_fail(err, SSS_ERR_ARG, "reference: unknown light kind %d", (int)l->kind);
    }
    c->max_order = o->max_order;
    c->no_nee = o->no_nee;
    c->no_nee_roulette = o->no_nee_roulette;
    return SSS_OK;
}

/* Per task, the surface point and the direction towards the eye. */
typedef struct ref_radiance_job {
    const ref_ctx *c;
    const ref_hit *pt;  /* ntasks points (NULL entries marked by tri == UINT32_MAX - 1: nothing seen) */
    const double *wo;   /* 3 × ntasks */
    uint64_t seed;
} ref_radiance_job;

#define REF_NOTHING (UINT32_MAX - 1)

static void radiance_fn(const void *job, uint64_t task, uint64_t path, double *vals, ref_counters *k)
{
    const ref_radiance_job *j = job;
    if (j->pt[task].tri == REF_NOTHING) {
        vals[0] = vals[1] = vals[2] = 0.0;
        return;
    }
    uint64_t rng = ref_stream(j->seed, task, path);
    ref_radiance_path(j->c, &j->pt[task], &j->wo[3 * task], &rng, vals, k);
}

static sss_result run_radiance(const ref_ctx *c, const ref_hit *pt, const double *wo, uint64_t ntasks,
                               const sss_ref_options *o, double **s1, double **s2, sss_ref_stats *st, sss_error *err)
{
    ref_radiance_job job = {c, pt, wo, o->seed};
    ref_run run = {ntasks, 3, radiance_fn, &job, NULL, NULL, 0};
    sss_result r = schedule(&run, o, st, err);
    *s1 = run.s1;
    *s2 = run.s2;
    return r;
}

sss_result sss_ref_queries(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                           const sss_ref_query *q, uint32_t nq, const sss_ref_options *o, sss_ref_estimate *out,
                           sss_ref_stats *st, sss_error *err)
{
    sss_ref_stats dummy;
    if (!st) st = &dummy;
    memset(st, 0, sizeof *st);
    ref_ctx c;
    sss_result r = make_ctx(s, m, l, o, &c, err);
    if (r != SSS_OK) return r;
    ref_hit *pt = calloc(nq ? nq : 1, sizeof *pt);
    double *wo = calloc(3 * (size_t)(nq ? nq : 1), sizeof(double));
    if (!pt || !wo) {
        free(pt);
        free(wo);
        return sss_fail(err, SSS_ERR_NOMEM, "reference: out of memory");
    }
    for (uint32_t i = 0; i < nq && r == SSS_OK; i++) {
        if (q[i].vertex >= s->nv) {
            r = sss_fail(err, SSS_ERR_ARG, "query %u: vertex %u out of range [0, %u)", i, q[i].vertex, s->nv);
            break;
        }
        /* at a vertex the geometric normal is its shading normal */
        const uint32_t v = q[i].vertex;
        for (int k = 0; k < 3; k++) {
            pt[i].p[k] = s->pos[3 * (size_t)v + k];
            pt[i].ns[k] = pt[i].ng[k] = s->nrm[3 * (size_t)v + k];
            wo[3 * (size_t)i + k] = q[i].view[k];
        }
        pt[i].tri = UINT32_MAX;
        if (!(sss_normalize3(&wo[3 * (size_t)i]) > 0.0) || !isfinite(wo[3 * (size_t)i]))
            r = sss_fail(err, SSS_ERR_ARG, "query %u: the view direction is not a direction", i);
    }
    double *s1 = NULL, *s2 = NULL;
    if (r == SSS_OK) r = run_radiance(&c, pt, wo, nq, o, &s1, &s2, st, err);
    if (r == SSS_OK)
        for (uint32_t i = 0; i < nq; i++)
            for (int ch = 0; ch < 3; ch++)
                finish(&s1[3 * (size_t)i + ch], &s2[3 * (size_t)i + ch], st->paths, &out[i].mean[ch], &out[i].se[ch]);
    free(s1);
    free(s2);
    free(pt);
    free(wo);
    return r;
}

sss_result sss_ref_image(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                         const sss_ref_camera *cam, const sss_ref_options *o, float *rgb, float *se,
                         sss_ref_stats *st, sss_error *err)
{
    sss_ref_stats dummy;
    if (!st) st = &dummy;
    memset(st, 0, sizeof *st);
    if (cam->width < 1 || cam->height < 1 || cam->width > 16384 || cam->height > 16384)
        return sss_fail(err, SSS_ERR_ARG, "reference: image size %dx%d out of range", cam->width, cam->height);
    ref_ctx c;
    sss_result r = make_ctx(s, m, l, o, &c, err);
    if (r != SSS_OK) return r;
    const uint64_t np = (uint64_t)cam->width * (uint64_t)cam->height;
    ref_hit *pt = calloc(np, sizeof *pt);
    double *wo = calloc(3 * np, sizeof(double));
    if (!pt || !wo) {
        free(pt);
        free(wo);
        return sss_fail(err, SSS_ERR_NOMEM, "reference: out of memory for a %dx%d image", cam->width, cam->height);
    }
    /* the surface each pixel centre sees (the renderer's: no antialiasing),
     * in mm about the camera in mesh units */
    const double aspect = (double)cam->width / cam->height, mm = s->mm_per_unit;
    ref_counters k0 = {0};
#pragma omp parallel for schedule(dynamic, 64) num_threads(nthreads(o))
    for (int64_t i = 0; i < (int64_t)np; i++) {
        const int px = (int)(i % cam->width), py = (int)(i / cam->width);
        const double sx = (2.0 * (px + 0.5) / cam->width - 1.0) * aspect * cam->tan_half_fov;
        const double sy = (1.0 - 2.0 * (py + 0.5) / cam->height) * cam->tan_half_fov;
        double d[3], org[3];
        for (int k = 0; k < 3; k++) {
            d[k] = cam->fwd[k] + sx * cam->right[k] + sy * cam->up[k];
            org[k] = cam->eye[k] * mm;
        }
        sss_normalize3(d);
        pt[i].tri = REF_NOTHING;
        ref_hit h;
        ref_counters kk = {0};
        if (ref_hit_facing(s, org, d, 0.0, 0, &h, &kk)) {
            pt[i] = h;
            for (int k = 0; k < 3; k++) wo[3 * i + k] = -d[k];
        }
    }
    k0.rays = np;
    double *s1 = NULL, *s2 = NULL;
    r = run_radiance(&c, pt, wo, np, o, &s1, &s2, st, err);
    st->rays += k0.rays;
    if (r == SSS_OK)
        for (uint64_t i = 0; i < np; i++)
            for (int ch = 0; ch < 3; ch++) {
                double mean, e;
                finish(&s1[3 * i + ch], &s2[3 * i + ch], st->paths, &mean, &e);
                if (rgb) rgb[3 * i + ch] = (float)mean;
                if (se) se[3 * i + ch] = (float)e;
            }
    free(s1);
    free(s2);
    free(pt);
    free(wo);
    return r;
}

int sss_ref_sample_ray(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_light *l,
                       const double org[3], const double dir[3], const sss_ref_options *o, uint64_t *stream,
                       double L[SSS_MAX_CHANNELS], sss_ref_stats *st)
{
    L[0] = L[1] = L[2] = 0.0;
    ref_ctx c;
    if (make_ctx(s, m, l, o, &c, NULL) != SSS_OK) return 0;
    double o_mm[3], d[3] = {dir[0], dir[1], dir[2]};
    if (!(sss_normalize3(d) > 0.0)) return 0;
    for (int k = 0; k < 3; k++) o_mm[k] = org[k] * s->mm_per_unit;
    ref_hit h;
    ref_counters k = {0};
    k.walks = 1;
    int ok = ref_hit_facing(s, o_mm, d, 0.0, 0, &h, &k);
    if (ok) {
        const double wo[3] = {-d[0], -d[1], -d[2]};
        ref_radiance_path(&c, &h, wo, stream, L, &k);
    }
    if (st) add_counters(st, &k);
    return ok;
}

/* ---- particles ---- */

typedef struct ref_particle_job {
    const ref_ctx *c;
    double centre[3], radius; /* mm */
    uint64_t seed;
} ref_particle_job;

#define REF_TALLY_VALS 19 /* incident and six tallies of three channels */

static void particle_fn(const void *job, uint64_t task, uint64_t path, double *vals, ref_counters *k)
{
    const ref_particle_job *j = job;
    uint64_t rng = ref_stream(j->seed, task, path);
    sss_ref_tally t;
    ref_particle_path(j->c, j->centre, j->radius, &rng, &t, k);
    vals[0] = t.incident;
    for (int ch = 0; ch < 3; ch++) {
        vals[1 + ch] = t.specular[ch];
        vals[4 + ch] = t.absorbed[ch];
        vals[7 + ch] = t.front[ch];
        vals[10 + ch] = t.back[ch];
        vals[13 + ch] = t.lost[ch];
        vals[16 + ch] = t.specular[ch] + t.absorbed[ch] + t.front[ch] + t.back[ch];
    }
}

static void tally_from(const double *v, sss_ref_tally *t)
{
    t->incident = v[0];
    for (int ch = 0; ch < 3; ch++) {
        t->specular[ch] = v[1 + ch];
        t->absorbed[ch] = v[4 + ch];
        t->front[ch] = v[7 + ch];
        t->back[ch] = v[10 + ch];
        t->lost[ch] = v[13 + ch];
        t->balance[ch] = v[16 + ch];
    }
}

sss_result sss_ref_particles(const sss_ref_scene *s, const sss_ref_medium *m, const sss_ref_beam *b,
                             const sss_ref_options *o, sss_ref_tally *mean, sss_ref_tally *se, sss_ref_stats *st,
                             sss_error *err)
{
    sss_ref_stats dummy;
    if (!st) st = &dummy;
    memset(st, 0, sizeof *st);
    const sss_ref_light l = {.kind = SSS_REF_DIRECTIONAL, .dir = {b->dir[0], b->dir[1], b->dir[2]}};
    if (m->hetero && m->hetero->field.kind != SSS_FIELD_NONE)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "reference: particles in a material field (radiance only, docs/reference.md §3.1)");
    ref_ctx c;
    sss_result r = make_ctx(s, m, &l, o, &c, err);
    if (r != SSS_OK) return r;
    if (!(b->radius >= 0.0) || !isfinite(b->radius)) return sss_fail(err, SSS_ERR_ARG, "reference: beam radius %g", b->radius);
    ref_particle_job job = {&c, {0, 0, 0}, b->radius * s->mm_per_unit, o->seed};
    for (int k = 0; k < 3; k++) job.centre[k] = b->centre[k] * s->mm_per_unit;
    ref_run run = {1, REF_TALLY_VALS, particle_fn, &job, NULL, NULL, 0};
    r = schedule(&run, o, st, err);
    if (r == SSS_OK) {
        double mv[REF_TALLY_VALS], sv[REF_TALLY_VALS];
        for (int j = 0; j < REF_TALLY_VALS; j++) finish(&run.s1[j], &run.s2[j], run.n, &mv[j], &sv[j]);
        tally_from(mv, mean);
        if (se) tally_from(sv, se);
    }
    free(run.s1);
    free(run.s2);
    return r;
}
