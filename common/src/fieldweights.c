/* fieldweights.c: the spatially varying kernel of a heterogeneous object
 * (docs/heterogeneous.md §4). The rows of the sum of Hao–Varshney 2004
 * §3.1 are built once for a reference material, as for any object; every
 * entry is then scaled by
 *
 *   κ(o, i) = sqrt(P_o(r) P_i(r)) / P_ref(r) · τ(o, i),
 *
 * so that its profile becomes the geometric mean of the two endpoints' own
 * dipole profiles (seed 003, SubEdit: symmetric, hence reciprocal) and the
 * light pays for what lies between them (seed 000, Shopf 2007 §4.3.2: the
 * density marched between the surfaces):
 *
 *   τ(o, i) = exp(−∫₀^r max(0, σtr(x(ξ)) − σ̄tr) dξ),  σ̄tr = (σtr(x_o) + σtr(x_i)) / 2.
 *
 * The geometric mean already decays like exp(−σ̄tr r); τ charges what the
 * segment holds beyond that mean, so material between the endpoints only
 * ever takes light away (τ ≤ 1): without the max, a thin absorbing skin
 * at one endpoint raised σ̄tr over the whole segment and brightened far
 * pairs by up to 23 % (docs/heterogeneous.md §4.1). A constant field gives
 * κ = 1 exactly: sqrt(P²) = P in IEEE arithmetic and every difference
 * under the integral is 0.
 */
#include "sss/fieldweights.h"

#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/hatweights.h"
#include "sss/vec3.h"

/* Vertex v of the positions pos (world units) in the rest frame (mm). */
static void rest_at(const sss_hetero *h, const float *pos, uint32_t v, double x[3])
{
    const double p[3] = {pos[3 * (size_t)v], pos[3 * (size_t)v + 1], pos[3 * (size_t)v + 2]};
    sss_hetero_to_rest(h, p, x);
}

static void rest_of(const sss_hetero *h, const sss_mesh *m, uint32_t v, double x[3])
{
    rest_at(h, m->pos, v, x);
}

void sss_field_kernel_free(sss_field_kernel *k)
{
    if (!k) return;
    free(k->f);
    free(k->sigma_tr);
    free(k->dip);
    free(k->cell);
    free(k->excess);
    free(k->cell_centre);
    free(k->cell_state);
    free(k->tr);
    free(k->brick_hi);
    free(k->prof);
    free(k->prof_l);
    free(k->prof_w);
    memset(k, 0, sizeof *k);
}

/* The bricks of the march grid (§4.2): per brick of SSS_FIELD_BRICK³
 * cells and channel, the bound hi on every trilinear read between its
 * nodes. A read is a convex combination of the eight nodes around it,
 * computed in floats by three levels of lerps a + w (b − a), each at most
 * 3 units in the last place (2⁻²⁴) of the largest node above it, so a
 * read is below the largest node times 1 + 5.4·10⁻⁷: hi is the largest
 * node when all the brick's nodes are equal (each lerp then returns it
 * exactly), else the largest times 1 + 10⁻⁵. So a read inside a brick
 * with hi ≤ σ̄tr is below or at σ̄tr, and its term max(0, σtr − σ̄tr) is
 * exactly +0. */
static sss_result build_bricks(sss_field_kernel *k)
{
    const uint32_t C = k->C, B = SSS_FIELD_BRICK;
    for (int a = 0; a < 3; a++) k->bn[a] = k->tn[a] > 1 ? (k->tn[a] - 2) / B + 1 : 1;
    const size_t nb = (size_t)k->bn[0] * k->bn[1] * k->bn[2];
    if (!(k->brick_hi = malloc(nb * C * sizeof *k->brick_hi))) return SSS_ERR_NOMEM;
    int64_t flat = 0;
#pragma omp parallel for schedule(static) reduction(+ : flat)
    for (int64_t q = 0; q < (int64_t)nb; q++) {
        const uint32_t b[3] = {(uint32_t)((size_t)q % k->bn[0]), (uint32_t)((size_t)q / k->bn[0] % k->bn[1]),
                               (uint32_t)((size_t)q / ((size_t)k->bn[0] * k->bn[1]))};
        uint32_t n0[3], n1[3]; /* the nodes a read in the brick's cells can touch */
        for (int a = 0; a < 3; a++) {
            n0[a] = b[a] * B;
            n1[a] = n0[a] + B < k->tn[a] - 1 ? n0[a] + B : k->tn[a] - 1;
        }
        int all_flat = 1;
        for (uint32_t c = 0; c < C; c++) {
            double lo = INFINITY, hi = -INFINITY;
            for (uint32_t z = n0[2]; z <= n1[2]; z++)
                for (uint32_t y = n0[1]; y <= n1[1]; y++)
                    for (uint32_t x = n0[0]; x <= n1[0]; x++) {
                        const double v = k->tr[(((size_t)z * k->tn[1] + y) * k->tn[0] + x) * SSS_FIELD_TR_W + c];
                        lo = fmin(lo, v);
                        hi = fmax(hi, v);
                    }
            k->brick_hi[(size_t)q * C + c] = lo == hi ? hi : hi * (1.0 + 1e-5);
            all_flat = all_flat && lo == hi;
        }
        flat += all_flat;
    }
    /* The early-out pays where the field has plateaus (strata, inclusions,
     * a grid's slabs: half to nine tenths of the midpoints skipped, often
     * in runs); through veins, which vary everywhere, its tests (a segment's
     * box, then every midpoint's brick, an unpredictable branch) cost more
     * than the reads they saved, about a quarter of the march on the dragon
     * (docs/heterogeneous.md §4.2). A plateau shows as bricks whose nodes
     * are all equal. */
    k->use_bricks = 4 * flat >= (int64_t)nb;
    return SSS_OK;
}

/* ½ ln(R_d[d](r) / R_d[ref](r)): what the profiles' table holds. */
static double half_log_ratio(const sss_dipole *d, const sss_dipole *ref, double r)
{
    return 0.5 * log(sss_rd(d, r) / sss_rd(ref, r));
}

/* The table's coordinate of channel c along f (build_profiles): σtr_c(f)
 * when that is strictly monotone over [f_min, f_max], else f itself. */
static double prof_param(const sss_field_kernel *k, uint32_t c, int by_sigma, double f)
{
    return by_sigma ? sss_material_sigma_tr(&k->base, &k->h->inside, f, c) : f;
}

/* The f in [f_min, f_max] where channel c's coordinate is p (bisection). */
static double prof_f_at(const sss_field_kernel *k, uint32_t c, int by_sigma, double p)
{
    double lo = k->f_min, hi = k->f_max;
    const double p0 = prof_param(k, c, by_sigma, lo), up = prof_param(k, c, by_sigma, hi) > p0 ? 1.0 : -1.0;
    for (int it = 0; it < 64; it++) {
        const double m = 0.5 * (lo + hi);
        if (up * (prof_param(k, c, by_sigma, m) - p) < 0.0) lo = m;
        else hi = m;
    }
    return 0.5 * (lo + hi);
}

/* The dipole of channel c of the blend at f. */
static int blend_dipole(const sss_field_kernel *k, uint32_t c, double f, sss_dipole *d)
{
    sss_material m;
    sss_material_blend(&k->base, &k->h->inside, f, &m);
    return sss_dipole_init(d, m.sigma_a[c], m.sigmap_s[c], k->base.eta) == SSS_OK;
}

/* The profiles' table (docs/heterogeneous.md §4.1): κ's profile part
 * sqrt(P_o P_i) / P_ref is exp(g(f_o, r) + g(f_i, r)) with g = ½ ln(R_d[f] /
 * R_d[f_ref]) when both profiles are point values. An entry cost nine
 * dipole profiles (two exponentials each) per channel where the endpoints
 * differ in f (a veined surface: almost every pair), about 40 % of the
 * field's work in perf on the dragon. g is nearly linear in r (the ratio
 * of two profiles that both decay like exp(−σtr r)) and in the channel's
 * σtr, not in f (σtr = sqrt(3 σa σ′t) with σa linear in f bends sharply
 * where σa is small: levels evenly spaced in f erred by 0.016 in ln κ on
 * the test's ball, levels evenly spaced in Σ_c σtr_c by 0.005), so each
 * channel's SSS_FIELD_PROFILE_F levels are evenly spaced in its own σtr
 * (prof_param) and a vertex is placed between two levels by its own σtr;
 * g is read bilinearly in (σtr, r) from SSS_FIELD_PROFILE_R distances over
 * [0, radius_mm]. Level 0 is f_min, the reference, where g = 0 exactly,
 * and a vertex at f_min sits on it with weight 0: an endpoint at the
 * reference contributes exactly nothing, as before. prof_tol is the
 * largest error in ln κ (twice g's, one per endpoint) at the centres of
 * the table's cells, where a bilinear read of a smooth function errs
 * most. On failure (a blend without a dipole, a non-finite ratio, no
 * memory) the kernel keeps the exact profiles (prof NULL). */
static void build_profiles(sss_field_kernel *k)
{
    const uint32_t C = k->C, NF = SSS_FIELD_PROFILE_F, NR = SSS_FIELD_PROFILE_R;
    if (!(k->f_max > k->f_min) || !(k->radius_mm > 0.0)) return;
    int by_sigma[SSS_MAX_CHANNELS];
    double P0[SSS_MAX_CHANNELS], dp[SSS_MAX_CHANNELS];
    for (uint32_t c = 0; c < C; c++) {
        /* σtr_c strictly monotone over the range, on 1024 samples? */
        const double s0 = prof_param(k, c, 1, k->f_min), s1 = prof_param(k, c, 1, k->f_max), up = s1 > s0 ? 1.0 : -1.0;
        double prev = s0;
        by_sigma[c] = 1;
        for (int q = 1; q <= 1024 && by_sigma[c]; q++) {
            const double sq = prof_param(k, c, 1, k->f_min + (k->f_max - k->f_min) * q / 1024.0);
            by_sigma[c] = up * (sq - prev) > 0.0;
            prev = sq;
        }
        P0[c] = prof_param(k, c, by_sigma[c], k->f_min);
        dp[c] = (prof_param(k, c, by_sigma[c], k->f_max) - P0[c]) / (NF - 1);
    }
    k->prof_dr = k->radius_mm / (NR - 1);
    k->prof = malloc((size_t)NF * NR * C * sizeof *k->prof);
    k->prof_l = malloc((size_t)k->nv * C * sizeof *k->prof_l);
    k->prof_w = malloc((size_t)k->nv * C * sizeof *k->prof_w);
    double *err = calloc((size_t)NF * C, sizeof *err);
    int ok = k->prof && k->prof_l && k->prof_w && err;
    for (uint32_t c = 0; c < C; c++) ok = ok && dp[c] != 0.0;
    if (ok) {
        for (uint32_t j = 0; j < NR * C; j++) k->prof[j] = 0.0f; /* level 0: the reference itself */
#pragma omp parallel for schedule(dynamic, 1) reduction(&& : ok)
        for (int64_t q = 0; q < (int64_t)(NF - 1) * C; q++) {
            const uint32_t l = (uint32_t)(q / C) + 1, c = (uint32_t)(q % C);
            const double f = l == NF - 1 ? k->f_max : prof_f_at(k, c, by_sigma[c], P0[c] + dp[c] * l);
            /* the level below (written by another iteration: recomputed
             * here, the same bits) and the centre between the two */
            const double fl = l == 1 ? k->f_min : prof_f_at(k, c, by_sigma[c], P0[c] + dp[c] * (l - 1));
            const double fm = prof_f_at(k, c, by_sigma[c], P0[c] + dp[c] * (l - 0.5));
            sss_dipole d, dl, dm;
            if (!blend_dipole(k, c, f, &d) || !blend_dipole(k, c, fl, &dl) || !blend_dipole(k, c, fm, &dm)) {
                ok = 0;
                continue;
            }
            const sss_dipole *ref = &k->dip_ref[c];
            double worst = 0.0;
            for (uint32_t j = 0; j < NR; j++) {
                const double g = half_log_ratio(&d, ref, k->prof_dr * j);
                ok = ok && isfinite(g) && fabs(g) < 1e30;
                k->prof[((size_t)l * NR + j) * C + c] = (float)g;
            }
            for (uint32_t j = 0; j + 1 < NR; j++) {
                double corner = 0.0;
                for (uint32_t e = 0; e < 2; e++)
                    corner += (double)k->prof[((size_t)l * NR + j + e) * C + c] +
                              (l > 1 ? half_log_ratio(&dl, ref, k->prof_dr * (j + e)) : 0.0);
                worst = fmax(worst, fabs(0.25 * corner - half_log_ratio(&dm, ref, k->prof_dr * (j + 0.5))));
            }
            err[q] = worst;
        }
    }
    double tol = 0.0;
    for (uint32_t q = 0; ok && q < (NF - 1) * C; q++) tol = fmax(tol, err[q]);
    free(err);
    if (!ok || !isfinite(tol)) {
        free(k->prof), free(k->prof_l), free(k->prof_w);
        k->prof = NULL, k->prof_l = NULL, k->prof_w = NULL;
        return;
    }
    k->prof_tol = 2.0 * tol;
    for (uint32_t v = 0; v < k->nv; v++)
        for (uint32_t c = 0; c < C; c++) {
            /* the vertex's coordinate from its own σtr (the same function of
             * the same f, so a vertex at f_min lands on level 0 with weight
             * 0 exactly) */
            const double p = by_sigma[c] ? k->sigma_tr[(size_t)v * C + c] : k->f[v];
            double u = (p - P0[c]) / dp[c];
            u = u < 0.0 ? 0.0 : u > NF - 1 ? NF - 1 : u;
            uint32_t l = (uint32_t)u;
            l = l > NF - 2 ? NF - 2 : l;
            k->prof_l[(size_t)v * C + c] = l;
            k->prof_w[(size_t)v * C + c] = u - l;
        }
}

/* g(f_v, r) of channel c from the table: vertex v's level for c and the
 * one above, distances j and j + 1 (weight rw towards j + 1). */
static inline double prof_at(const sss_field_kernel *k, uint32_t v, size_t j, double rw, uint32_t c)
{
    const size_t C = k->C, L = (size_t)SSS_FIELD_PROFILE_R * C, vc = (size_t)v * C + c;
    const float *p = k->prof + ((size_t)k->prof_l[vc] * SSS_FIELD_PROFILE_R + j) * C + c;
    const double a = p[0] + rw * ((double)p[C] - p[0]);
    const double b = p[L] + rw * ((double)p[L + C] - p[L]);
    return a + k->prof_w[vc] * (b - a);
}

/* The kernel for the vertices of mesh with f read at the positions `at`
 * (mesh->pos for a static object, the rest pose for a deforming one);
 * march 0 leaves out τ (step 0, no march grid). */
static sss_result kernel_create(const sss_mesh *mesh, const float *at, int march, double s, const sss_material *base,
                                const sss_hetero *h, uint32_t C, double eps, const char *name, sss_field_kernel *k,
                                sss_error *err)
{
    memset(k, 0, sizeof *k);
    if (!mesh->nv || !mesh->area || C < 1 || C > SSS_MAX_CHANNELS || !(s > 0.0))
        return sss_fail(err, SSS_ERR_ARG, "%s: field: invalid arguments", name);
    sss_result r = sss_field_check(&h->field, err);
    if (r != SSS_OK) return sss_fail(err, r, "%s: field: %s", name, err ? err->msg : "invalid");
    k->h = h;
    k->base = *base;
    k->nv = mesh->nv;
    k->C = C;
    k->s = s;
    k->f = malloc((size_t)mesh->nv * sizeof *k->f);
    k->sigma_tr = malloc((size_t)mesh->nv * C * sizeof *k->sigma_tr);
    k->dip = malloc((size_t)mesh->nv * C * sizeof *k->dip);
    if (!k->f || !k->sigma_tr || !k->dip) {
        sss_field_kernel_free(k);
        return sss_fail(err, SSS_ERR_NOMEM, "%s: field: out of memory for %u vertices", name, mesh->nv);
    }
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t v = 0; v < mesh->nv; v++) {
        double x[3];
        rest_at(h, at, v, x);
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], x[a]), hi[a] = fmax(hi[a], x[a]);
    }
    char why[300];
    if (!sss_field_covers(&h->field, lo, hi, why, sizeof why)) {
        sss_field_kernel_free(k);
        return sss_fail(err, SSS_ERR_ARG, "%s: field: %s", name, why);
    }
    k->f_min = 1.0;
    k->f_max = 0.0;
#pragma omp parallel for schedule(static)
    for (int64_t v = 0; v < (int64_t)mesh->nv; v++) {
        double x[3];
        rest_at(h, at, (uint32_t)v, x);
        k->f[v] = sss_field_eval(&h->field, x);
    }
    for (uint32_t v = 0; v < mesh->nv; v++) {
        k->f_min = fmin(k->f_min, k->f[v]);
        k->f_max = fmax(k->f_max, k->f[v]);
        sss_material m;
        sss_material_blend(base, &h->inside, k->f[v], &m);
        for (uint32_t c = 0; c < C; c++) {
            k->sigma_tr[(size_t)v * C + c] = sss_material_sigma_tr(base, &h->inside, k->f[v], c);
            if (sss_dipole_init(&k->dip[(size_t)v * C + c], m.sigma_a[c], m.sigmap_s[c], base->eta) != SSS_OK) {
                sss_field_kernel_free(k);
                return sss_fail(err, SSS_ERR_ARG, "%s: field: vertex %u: the blend at f = %g makes no dipole", name,
                                v, k->f[v]);
            }
        }
    }
    /* the rows are built for the blend at f_min: a constant field's rows
     * are then exactly the homogeneous rows of its blend */
    sss_material_blend(base, &h->inside, k->f_min, &k->ref);
    sss_dipole dmax[SSS_MAX_CHANNELS];
    sss_material mmax;
    sss_material_blend(base, &h->inside, k->f_max, &mmax);
    for (uint32_t c = 0; c < C; c++) {
        sss_dipole_init(&k->dip_ref[c], k->ref.sigma_a[c], k->ref.sigmap_s[c], base->eta);
        sss_dipole_init(&dmax[c], mmax.sigma_a[c], mmax.sigmap_s[c], base->eta);
    }
    const double r0 = sss_cutoff_radius_mm(mesh, s, k->dip_ref, C, eps, NULL);
    const double r1 = k->f_max > k->f_min ? sss_cutoff_radius_mm(mesh, s, dmax, C, eps, NULL) : r0;
    k->radius_mm = r0 > r1 ? r0 : r1;
    k->step_mm = march ? sss_field_step_mm(&h->field) : 0.0;
    for (uint32_t c = 0; c < C; c++) k->sigma_tr_ref[c] = sss_material_sigma_tr(base, &h->inside, k->f_min, c);
    /* The march reads σtr from a grid sampled once at the step over the
     * rest box (every segment between two vertices lies inside it): a
     * procedural field costs up to five octaves of noise per sample, and
     * σtr a square root per channel. */
    if (k->step_mm > 0.0) {
        double ext = 0.0;
        for (int a = 0; a < 3; a++) ext = fmax(ext, hi[a] - lo[a]);
        const double nodes = fmin((double)SSS_FIELD_MARCH_NODES, fmax(2.0, ceil(ext / k->step_mm) + 1.0));
        k->t_voxel = ext > 0.0 ? ext / (nodes - 1.0) : 1.0;
        for (int a = 0; a < 3; a++) {
            k->t_origin[a] = lo[a];
            k->tn[a] = (uint32_t)fmin(nodes, ceil((hi[a] - lo[a]) / k->t_voxel - 1e-9) + 1.0);
            if (k->tn[a] < 1) k->tn[a] = 1;
        }
        const size_t nn = (size_t)k->tn[0] * k->tn[1] * k->tn[2];
        /* 16-byte aligned: a node's padded channels in one aligned load
         * (march_sum), never across two cache lines */
        if (!(k->tr = aligned_alloc(16, nn * SSS_FIELD_TR_W * sizeof *k->tr))) {
            sss_field_kernel_free(k);
            return sss_fail(err, SSS_ERR_NOMEM, "%s: field: out of memory for the march grid (%zu nodes)", name, nn);
        }
#pragma omp parallel for schedule(static)
        for (int64_t q = 0; q < (int64_t)nn; q++) {
            const size_t i = (size_t)q % k->tn[0], j = (size_t)q / k->tn[0] % k->tn[1],
                         l = (size_t)q / ((size_t)k->tn[0] * k->tn[1]);
            const double x[3] = {lo[0] + k->t_voxel * i, lo[1] + k->t_voxel * j, lo[2] + k->t_voxel * l};
            const double f = sss_field_eval(&h->field, x);
            float *node = &k->tr[(size_t)q * SSS_FIELD_TR_W];
            for (uint32_t c = 0; c < SSS_FIELD_TR_W; c++) {
                if (c >= C) {
                    node[c] = 0.0f; /* padding: read, never summed */
                    continue;
                }
                /* rounded down: a node never exceeds the σtr its f gives a
                 * vertex, so a plateau's excess over its own mean stays
                 * exactly 0 (a constant field through the kernel is still
                 * the homogeneous bake bit for bit) */
                const double v = sss_material_sigma_tr(base, &h->inside, f, c);
                float fv = (float)v;
                if ((double)fv > v) fv = nextafterf(fv, -INFINITY);
                node[c] = fv;
            }
        }
        if (build_bricks(k) != SSS_OK) {
            sss_field_kernel_free(k);
            return sss_fail(err, SSS_ERR_NOMEM, "%s: field: out of memory for the march grid's bricks", name);
        }
    }
    return SSS_OK;
}

sss_result sss_field_kernel_create(const sss_mesh *mesh, double s, const sss_material *base, const sss_hetero *h,
                                   uint32_t C, double eps, const char *name, sss_field_kernel *k, sss_error *err)
{
    /* a surface texture (Hao–Varshney 2004 §5) has no volume to march:
     * the endpoints' profiles alone (docs/heterogeneous.md §4.4) */
    sss_result r = kernel_create(mesh, mesh->pos, !h->surface, s, base, h, C, eps, name, k, err);
    /* the profiles' table for a bake's and an exact evaluator's many pairs;
     * a deforming object's per-frame kernel keeps the exact profiles
     * (docs/deformable.md §10) */
    if (r == SSS_OK) build_profiles(k);
    return r;
}

sss_result sss_field_kernel_create_ends(const sss_mesh *mesh, const float *rest, double s, const sss_material *base,
                                        const sss_hetero *h, uint32_t C, double eps, const char *name,
                                        sss_field_kernel *k, sss_error *err)
{
    if (!rest) {
        memset(k, 0, sizeof *k);
        return sss_fail(err, SSS_ERR_ARG, "%s: field: no rest-pose positions to read the field at", name);
    }
    return kernel_create(mesh, rest, 0, s, base, h, C, eps, name, k, err);
}

/* The march grid's cell of coordinate u (grid units) along axis x, as
 * march_sum reads it: clamped to the grid, the last node's cell the one
 * below it. Non-decreasing in u. */
static double cell_floor(const sss_field_kernel *k, int x, double *u)
{
    const double top = (double)(k->tn[x] - 1);
    *u = *u < 0.0 ? 0.0 : *u > top ? top : *u;
    double fl = (double)(int64_t)*u; /* floor(u) for u ≥ 0, without a call into libm */
    if (fl >= top && k->tn[x] > 1) fl = top - 1.0;
    return fl;
}

/* Whether every brick of the box between grid points g and e is at most
 * mean in every channel (then no midpoint between them adds anything);
 * 0 without looking when the box holds more than 64 bricks. */
static int box_below(const sss_field_kernel *k, const double g[3], const double e[3], const double *mean)
{
    const uint32_t C = k->C;
    size_t b0[3], b1[3], count = 1;
    for (int x = 0; x < 3; x++) {
        double lo = fmin(g[x], e[x]), hi = fmax(g[x], e[x]);
        b0[x] = (size_t)cell_floor(k, x, &lo) / SSS_FIELD_BRICK;
        b1[x] = (size_t)cell_floor(k, x, &hi) / SSS_FIELD_BRICK;
        count *= b1[x] - b0[x] + 1;
    }
    if (count > 64) return 0;
    for (size_t z = b0[2]; z <= b1[2]; z++)
        for (size_t y = b0[1]; y <= b1[1]; y++)
            for (size_t x = b0[0]; x <= b1[0]; x++) {
                const double *hb = k->brick_hi + ((z * k->bn[1] + y) * k->bn[0] + x) * C;
                for (uint32_t c = 0; c < C; c++)
                    if (hb[c] > mean[c]) return 0;
            }
    return 1;
}

/* The last midpoint j' ≥ j of the march (midpoint m at t_m = (m + ½)/n of
 * g0 + t dg, grid units) that surely lies in the brick of cell cl, whose
 * bound is at most the pair's mean: march_sum skips j … j' at once, a
 * 3D-DDA step from brick to brick (docs/heterogeneous.md §4.2) instead of
 * a brick test per midpoint. Each midpoint's cell is monotone in t along
 * every axis (every rounded operation of g0 + t dg is), so the run ends
 * where the first axis crosses its brick face; a face on the grid's edge
 * is never crossed (cell_floor clamps). The face is taken 10⁻⁹ cell
 * inside, far beyond the few units in the last place (of coordinates below
 * SSS_FIELD_MARCH_NODES) that the rounding of g0 + t dg and of t_m adds, so
 * every midpoint skipped lies in the brick: the skipped terms are +0 as
 * before, and the sum keeps the plain march's bits. */
static int brick_run_end(const sss_field_kernel *k, const double g0[3], const double dg[3], const double inv_dg[3],
                         const size_t cl[3], int j, int n)
{
    const double B = SSS_FIELD_BRICK, margin = 1e-9;
    double t_out = INFINITY;
    for (int x = 0; x < 3; x++) {
        const size_t b = cl[x] / SSS_FIELD_BRICK;
        double t = INFINITY;
        /* times 1/Δg rather than over Δg: a unit in the last place more,
         * still far inside the margin */
        if (dg[x] > 0.0 && b + 1 < k->bn[x]) t = ((double)(b + 1) * B - margin - g0[x]) * inv_dg[x];
        else if (dg[x] < 0.0 && b > 0) t = ((double)b * B + margin - g0[x]) * inv_dg[x];
        t_out = t < t_out ? t : t_out;
    }
    if (!(t_out < 1.0)) return n - 1;
    const double last = t_out * n - 0.5; /* the last m with t_m ≤ t_out */
    if (!(last >= (double)j + 1.0)) return j;
    return (int)last < n - 1 ? (int)last : n - 1;
}

/* The trilinear read of every channel at once: q a node of the march
 * grid (SSS_FIELD_TR_W floats, 16-byte aligned), st the node strides
 * along x, y, z in floats (0 along an axis of one node), w the weights;
 * seven lerps a + w (b − a) per channel. The SSE2 path and the plain one
 * do the same float operations in the same order, and then the same
 * double ones per channel (march_sum), so both give the same bits. */
_Static_assert(SSS_MAX_CHANNELS <= SSS_FIELD_TR_W, "the march grid pads a node's channels to SSS_FIELD_TR_W");
#if defined(__SSE2__)
#include <emmintrin.h>
#define MARCH_SSE2 1
static inline __m128 lerp4(__m128 a, __m128 b, __m128 w)
{
    return _mm_add_ps(a, _mm_mul_ps(w, _mm_sub_ps(b, a)));
}
static inline __m128 trilinear4(const float *q, const size_t st[3], const float w[3])
{
    const __m128 wx = _mm_set1_ps(w[0]), wy = _mm_set1_ps(w[1]), wz = _mm_set1_ps(w[2]);
    const __m128 c00 = lerp4(_mm_load_ps(q), _mm_load_ps(q + st[0]), wx);
    const __m128 c01 = lerp4(_mm_load_ps(q + st[1]), _mm_load_ps(q + st[1] + st[0]), wx);
    const __m128 c10 = lerp4(_mm_load_ps(q + st[2]), _mm_load_ps(q + st[2] + st[0]), wx);
    const __m128 c11 = lerp4(_mm_load_ps(q + st[2] + st[1]), _mm_load_ps(q + st[2] + st[1] + st[0]), wx);
    return lerp4(lerp4(c00, c01, wy), lerp4(c10, c11, wy), wz);
}
#else
static inline float lerp1(float a, float b, float w)
{
    return a + w * (b - a);
}
static inline void trilinear4(const float *q, const size_t st[3], const float w[3], float out[SSS_FIELD_TR_W])
{
    for (int c = 0; c < SSS_FIELD_TR_W; c++) {
        const float c00 = lerp1(q[c], q[st[0] + c], w[0]);
        const float c01 = lerp1(q[st[1] + c], q[st[1] + st[0] + c], w[0]);
        const float c10 = lerp1(q[st[2] + c], q[st[2] + st[0] + c], w[0]);
        const float c11 = lerp1(q[st[2] + st[1] + c], q[st[2] + st[1] + st[0] + c], w[0]);
        out[c] = lerp1(lerp1(c00, c01, w[1]), lerp1(c10, c11, w[1]), w[2]);
    }
}
#endif

/* Sums over the n midpoints of the segment a → b (world units) of σtr from
 * the march grid (trilinear): with mean, Σ max(0, σtr − mean_c); without,
 * Σ (σtr − σtr_ref). The points advance by a constant step in grid
 * coordinates, so each costs one trilinear read of the C channels (one
 * vector read, trilinear4). With
 * mean, midpoints in bricks at most mean (build_bricks) are not read, a
 * brick's run of them skipped at once (brick_run_end):
 * their terms are +0, and adding +0 to a sum of non-negative terms leaves
 * its bits, so the sum is the plain march's bit for bit. */
static void march_sum(const sss_field_kernel *k, const double a[3], const double b[3], int n, const double *mean,
                      double *out)
{
    const uint32_t C = k->C;
    double ua[3], ub[3], g0[3], dg[3], g1[3];
    sss_hetero_to_rest(k->h, a, ua);
    sss_hetero_to_rest(k->h, b, ub);
    const double inv = 1.0 / k->t_voxel;
    for (int x = 0; x < 3; x++) {
        g0[x] = (ua[x] - k->t_origin[x]) * inv;
        dg[x] = (ub[x] - ua[x]) * inv;
        g1[x] = g0[x] + dg[x]; /* every midpoint g0 + t dg, 0 < t < 1, lies between g0 and g1 */
    }
    for (uint32_t c = 0; c < C; c++) out[c] = 0.0;
    const double *bh = mean && k->use_bricks ? k->brick_hi : NULL;
    if (bh && box_below(k, g0, g1, mean)) return;
    /* the sums in a local array: out may alias the grid for all the
     * compiler knows, which made it store and reload every term */
    double acc[SSS_FIELD_TR_W] = {0};
    const size_t W = SSS_FIELD_TR_W, s0 = W, s1 = (size_t)k->tn[0] * W, s2 = (size_t)k->tn[0] * k->tn[1] * W;
    const size_t st[3] = {k->tn[0] > 1 ? s0 : 0, k->tn[1] > 1 ? s1 : 0, k->tn[2] > 1 ? s2 : 0};
    const size_t stride[3] = {s0, s1, s2};
    /* A brick holds more than one midpoint only where a step moves less
     * than a brick along every axis; elsewhere the run's end is not worth
     * its three products (the skipped midpoints are the same either way). */
    double inv_dg[3] = {0}, longest = 0.0;
    /* Whether every midpoint lies inside the grid, away from its last
     * node by far more than the rounding of g0 + t dg: then cell_floor's
     * clamps change nothing and the cell is the truncation alone (the
     * same bits, fewer operations per midpoint). Comparisons written out:
     * libm's fmin and fmax are calls, once per pair. */
    int inside = 1;
    for (int x = 0; x < 3; x++) {
        const double lo = g0[x] < g1[x] ? g0[x] : g1[x], hi = g0[x] < g1[x] ? g1[x] : g0[x];
        const double top = (double)(k->tn[x] - 1);
        inside = inside && k->tn[x] > 1 && lo >= 1e-6 && hi <= top - 1e-6;
        if (!bh) continue; /* the runs are the bricks' */
        inv_dg[x] = dg[x] != 0.0 ? 1.0 / dg[x] : 0.0;
        longest = longest > fabs(dg[x]) ? longest : fabs(dg[x]);
    }
    const int runs = bh && longest < (double)SSS_FIELD_BRICK * n;
    /* t_j = (j + ½) / n as a product: the division per midpoint was the
     * march's slowest operation (brick_run_end's margin covers the unit in
     * the last place this moves t_j by) */
    const double inv_n = 1.0 / n;
    const size_t B = SSS_FIELD_BRICK, bs1 = k->bn[0], bs2 = (size_t)k->bn[0] * k->bn[1];
#ifdef MARCH_SSE2
    /* the channels in two pairs of doubles; the padding's lanes sum
     * 0 − 0 and are not read */
    double m4[SSS_FIELD_TR_W] = {0};
    for (uint32_t c = 0; c < C; c++) m4[c] = mean ? mean[c] : k->sigma_tr_ref[c];
    const __m128d zero = _mm_setzero_pd(), m01 = _mm_loadu_pd(m4), m23 = _mm_loadu_pd(m4 + 2);
    __m128d a01 = zero, a23 = zero;
#else
    float v[SSS_FIELD_TR_W];
#endif
#ifdef MARCH_SSE2
    if (inside && !bh && mean) {
        /* The common case (a segment inside the grid, no bricks: veins)
         * in its own loop, with the arithmetic below in the same order on
         * the same values, so the same bits: no branches per midpoint, and
         * few enough live values that the compiler keeps them in
         * registers (the general loop reloaded five from the stack per
         * midpoint); x and y's coordinates as one pair of doubles (the
         * same IEEE operations per lane), j + ½ counted in doubles (exact:
         * n ≤ SSS_FIELD_MARCH_MAX). */
        const __m128d g01 = _mm_loadu_pd(g0), d01 = _mm_loadu_pd(dg);
        const double g2 = g0[2], d2 = dg[2];
        const int32_t sx = (int32_t)stride[0], sy = (int32_t)stride[1], sz = (int32_t)stride[2];
        const float *tr = k->tr;
        double jh = 0.5;
        for (int j = 0; j < n; j++, jh += 1.0) {
            const double t = jh * inv_n;
            const __m128d u01 = _mm_add_pd(g01, _mm_mul_pd(_mm_set1_pd(t), d01));
            const __m128i i01 = _mm_cvttpd_epi32(u01);
            const __m128 w01 = _mm_cvtpd_ps(_mm_sub_pd(u01, _mm_cvtepi32_pd(i01)));
            const double u2 = g2 + t * d2;
            const int32_t i2 = (int32_t)u2;
            const float w2 = (float)(u2 - (double)i2);
            const int32_t ix = _mm_cvtsi128_si32(i01), iy = _mm_cvtsi128_si32(_mm_shuffle_epi32(i01, 0x55));
            const float *q = tr + ((size_t)ix * sx + (size_t)iy * sy + (size_t)i2 * sz);
            const __m128 wx = _mm_shuffle_ps(w01, w01, 0x00), wy = _mm_shuffle_ps(w01, w01, 0x55), wz = _mm_set1_ps(w2);
            const __m128 c00 = lerp4(_mm_load_ps(q), _mm_load_ps(q + sx), wx);
            const __m128 c01 = lerp4(_mm_load_ps(q + sy), _mm_load_ps(q + sy + sx), wx);
            const __m128 c10 = lerp4(_mm_load_ps(q + sz), _mm_load_ps(q + sz + sx), wx);
            const __m128 c11 = lerp4(_mm_load_ps(q + sz + sy), _mm_load_ps(q + sz + sy + sx), wx);
            const __m128 r = lerp4(lerp4(c00, c01, wy), lerp4(c10, c11, wy), wz);
            a01 = _mm_add_pd(a01, _mm_max_pd(_mm_sub_pd(_mm_cvtps_pd(r), m01), zero));
            a23 = _mm_add_pd(a23, _mm_max_pd(_mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(r, r)), m23), zero));
        }
        _mm_storeu_pd(acc, a01);
        _mm_storeu_pd(acc + 2, a23);
        for (uint32_t c = 0; c < C; c++) out[c] = acc[c];
        return;
    }
#endif
    for (int j = 0; j < n; j++) {
        const double t = (j + 0.5) * inv_n;
        size_t base = 0, cl[3];
        float w[3];
        if (inside)
            for (int x = 0; x < 3; x++) {
                /* through a 32-bit integer (the grid has at most
                 * SSS_FIELD_MARCH_NODES nodes per side): the conversions
                 * both ways without the sign tests an unsigned one needs */
                const double u = g0[x] + t * dg[x];
                const int32_t ci = (int32_t)u;
                w[x] = (float)(u - (double)ci);
                cl[x] = (size_t)ci;
                base += cl[x] * stride[x];
            }
        else
            for (int x = 0; x < 3; x++) {
                double u = g0[x] + t * dg[x];
                const double fl = cell_floor(k, x, &u);
                w[x] = k->tn[x] > 1 ? (float)(u - fl) : 0.0f;
                cl[x] = (size_t)fl;
                base += cl[x] * stride[x];
            }
        if (bh) {
            const double *hb = bh + ((cl[2] / B) * bs2 + (cl[1] / B) * bs1 + cl[0] / B) * C;
            uint32_t c = 0;
            while (c < C && hb[c] <= mean[c]) c++;
            if (c == C) {
                if (runs) j = brick_run_end(k, g0, dg, inv_dg, cl, j, n);
                continue;
            }
        }
#ifdef MARCH_SSE2
        const __m128 r = trilinear4(k->tr + base, st, w);
        const __m128d d01 = _mm_sub_pd(_mm_cvtps_pd(r), m01), d23 = _mm_sub_pd(_mm_cvtps_pd(_mm_movehl_ps(r, r)), m23);
        if (mean) {
            /* max(0, d) as MAXPD(d, +0) computes it: d where d > 0, else +0,
             * the plain path's d > 0 ? d : 0 without a branch */
            a01 = _mm_add_pd(a01, _mm_max_pd(d01, zero));
            a23 = _mm_add_pd(a23, _mm_max_pd(d23, zero));
        } else {
            a01 = _mm_add_pd(a01, d01);
            a23 = _mm_add_pd(a23, d23);
        }
#else
        trilinear4(k->tr + base, st, w, v);
        if (mean)
            for (uint32_t c = 0; c < C; c++) {
                /* max(0, ·) written out: libm's fmax is a call; the
                 * difference of two positive σtr is never −0 */
                const double d = (double)v[c] - mean[c];
                acc[c] += d > 0.0 ? d : 0.0;
            }
        else
            for (uint32_t c = 0; c < C; c++) acc[c] += (double)v[c] - k->sigma_tr_ref[c];
#endif
    }
#ifdef MARCH_SSE2
    _mm_storeu_pd(acc, a01);
    _mm_storeu_pd(acc + 2, a23);
#endif
    for (uint32_t c = 0; c < C; c++) out[c] = acc[c];
}

void sss_field_march_sum(const sss_field_kernel *k, const double a[3], const double b[3], int n, const double *mean,
                         double *sum)
{
    march_sum(k, a, b, n, mean, sum);
}

static int march_steps(const sss_field_kernel *k, double L_mm)
{
    double n = ceil(L_mm / k->step_mm);
    n = n < 1.0 ? 1.0 : n > SSS_FIELD_MARCH_MAX ? SSS_FIELD_MARCH_MAX : n;
    return (int)n;
}

/* τ's exponent per channel along the segment a → b (world units, r mm
 * long) between ends of σtr sa and sb: the midpoint rule of §4.2 over the
 * excess above their mean (pair_tau, sss_field_kappa_point). */
static void march_tau(const sss_field_kernel *k, const double a[3], const double b[3], double r, const double *sa,
                      const double *sb, double *tau_exp)
{
    const int n = march_steps(k, r);
    double mean[SSS_MAX_CHANNELS] = {0};
    for (uint32_t c = 0; c < k->C; c++) mean[c] = 0.5 * (sa[c] + sb[c]);
    march_sum(k, a, b, n, mean, tau_exp);
    for (uint32_t c = 0; c < k->C; c++) tau_exp[c] *= r / n;
}

/* ∫ (σtr(x) − σtr_ref) dξ / L along the segment a → b (world units). */
static void mean_excess(const sss_field_kernel *k, const double a[3], const double b[3], double L_mm, double *out)
{
    const int n = march_steps(k, L_mm);
    march_sum(k, a, b, n, NULL, out);
    for (uint32_t c = 0; c < k->C; c++) out[c] /= n;
}

sss_result sss_field_kernel_far(sss_field_kernel *k, const sss_mesh *mesh, uint32_t max_cells, sss_error *err)
{
    if (!(k->step_mm > 0.0) || max_cells < 8) return SSS_OK; /* a constant: nothing to march anyway */
    /* cells in the rest frame, so that they move with the object and a
     * rigid motion leaves every pair's cells as they were */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double *rest = malloc((size_t)mesh->nv * 3 * sizeof *rest);
    uint32_t *cell = malloc((size_t)mesh->nv * sizeof *cell);
    if (!cell || !rest) {
        free(cell), free(rest);
        return sss_fail(err, SSS_ERR_NOMEM, "field: out of memory for the far pairs' cells");
    }
    for (uint32_t v = 0; v < mesh->nv; v++) {
        rest_of(k->h, mesh, v, &rest[3 * (size_t)v]);
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], rest[3 * (size_t)v + a]), hi[a] = fmax(hi[a], rest[3 * (size_t)v + a]);
    }
    const double diag = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                             (hi[2] - lo[2]) * (hi[2] - lo[2]));
    /* the smallest cells (at least 4 march steps) whose occupied count fits */
    double edge = fmax(4.0 * k->step_mm, diag / 64.0);
    double lo0[3];
    memcpy(lo0, lo, sizeof lo0);
    uint32_t K = 0;
    for (int tries = 0; tries < 40; tries++, edge *= 1.25) {
        uint32_t n[3];
        /* the grid shifted off the box by an irrational share of a cell:
         * a symmetric mesh's vertices then do not sit on cell faces, where
         * the last bit of a moved position would pick the cell */
        for (int a = 0; a < 3; a++) lo[a] = lo0[a] - 0.38196601125 * edge;
        for (int a = 0; a < 3; a++) n[a] = (uint32_t)fmin(1024.0, floor((hi[a] - lo[a]) / edge) + 1.0);
        const size_t total = (size_t)n[0] * n[1] * n[2];
        uint32_t *id = malloc(total * sizeof *id);
        if (!id) break;
        memset(id, 0xff, total * sizeof *id);
        K = 0;
        for (uint32_t v = 0; v < mesh->nv && K <= max_cells; v++) {
            size_t g = 0;
            for (int a = 2; a >= 0; a--) {
                uint32_t ia = (uint32_t)((rest[3 * (size_t)v + a] - lo[a]) / edge);
                g = g * n[a] + (ia < n[a] ? ia : n[a] - 1);
            }
            if (id[g] == UINT32_MAX) id[g] = K++; /* numbered in vertex order: deterministic */
            cell[v] = id[g];
        }
        free(id);
        if (K <= max_cells) break;
    }
    free(rest);
    if (K == 0 || K > max_cells) {
        free(cell);
        return SSS_OK; /* no cache: every pair is marched */
    }
    double *cen = calloc((size_t)K * 4, sizeof *cen);
    double *ex = malloc((size_t)K * K * k->C * sizeof *ex);
    unsigned char *state = calloc((size_t)K * K, 1);
    if (!cen || !ex || !state) {
        free(cell), free(cen), free(ex), free(state);
        return sss_fail(err, SSS_ERR_NOMEM, "field: out of memory for %u x %u cell pairs", K, K);
    }
    for (uint32_t v = 0; v < mesh->nv; v++) {
        for (int a = 0; a < 3; a++) cen[4 * (size_t)cell[v] + a] += mesh->pos[3 * (size_t)v + a];
        cen[4 * (size_t)cell[v] + 3] += 1.0;
    }
    for (uint32_t c = 0; c < K; c++)
        for (int a = 0; a < 3; a++) cen[4 * (size_t)c + a] /= cen[4 * (size_t)c + 3];
    /* The cell pairs' excesses are marched when a far pair first asks for
     * them (cell_excess): most of the K² pairs are nearer than far_mm or
     * beyond the neighbourhoods' radius and are never read, and on a small
     * mesh (the bunny: 1839 vertices in up to 1024 cells) marching them
     * all was a fifth of the field's bake in perf. */
    k->ncells = K;
    k->cell = cell;
    k->excess = ex;
    k->cell_centre = cen;
    k->cell_state = state;
    k->cell_mm = edge;
    k->far_mm = 3.0 * edge * sqrt(3.0); /* endpoints within a cell diagonal of the centroids' segment, 1/3 of it */
    return SSS_OK;
}

/* The mean excess σtr(x) − σtr_ref between the centroids of cells ca and
 * cb (1/mm per channel), marched from the lower cell to the higher on the
 * first request and kept: the slot's state goes 0 → 1 (one thread writes
 * it) → 2 (readable). A thread that finds it 0 or 1 marches for itself
 * into tmp; the march is a pure function of the two cells, so every
 * caller gets the same bits whoever wrote the table. */
static const double *cell_excess(const sss_field_kernel *k, uint32_t ca, uint32_t cb, double *tmp)
{
    const uint32_t a = ca < cb ? ca : cb, b = ca < cb ? cb : ca, C = k->C;
    const size_t ab = (size_t)a * k->ncells + b;
    _Atomic unsigned char *st = (_Atomic unsigned char *)k->cell_state;
    double *slot = k->excess + ab * C;
    if (atomic_load_explicit(&st[ab], memory_order_acquire) == 2) return slot;
    const double *pa = &k->cell_centre[4 * (size_t)a], *pb = &k->cell_centre[4 * (size_t)b];
    double d2 = 0.0;
    for (int x = 0; x < 3; x++) d2 += (pb[x] - pa[x]) * (pb[x] - pa[x]);
    mean_excess(k, pa, pb, sqrt(d2) * k->s, tmp);
    unsigned char none = 0;
    if (atomic_compare_exchange_strong_explicit(&st[ab], &none, 1, memory_order_acq_rel, memory_order_acquire)) {
        memcpy(slot, tmp, C * sizeof *tmp);
        atomic_store_explicit(&st[ab], 2, memory_order_release);
    }
    return tmp;
}

/* The profile the neighbourhood rows used for the pair (nbhd.c): the disk
 * of x_o's own area for the own term, the disk of x_i's area when it
 * covers x_o, the point value R_d(r) otherwise. */
static double profile(const sss_dipole *d, double r, double rho_o, double rho_i)
{
    if (r == 0.0) return sss_rd_disk(d, rho_o);
    if (r < rho_i) return sss_rd_disk_offset(d, r, rho_i);
    return sss_rd(d, r);
}

/* What κ(o, i) and κ(i, o) share (§4.1): the pair's distance r (mm) and
 * the exponent of τ per channel, computed from the lower index to the
 * higher, so both orders get the same bits. */
static double pair_tau(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double *tau_exp)
{
    const uint32_t C = k->C;
    /* the segment from the lower index to the higher, so that (o, i) and
     * (i, o) sum the same terms in the same order */
    const uint32_t a = o < i ? o : i, b = o < i ? i : o;
    double pa[3], pb[3], d2 = 0.0;
    for (int x = 0; x < 3; x++) {
        pa[x] = mesh->pos[3 * (size_t)a + x];
        pb[x] = mesh->pos[3 * (size_t)b + x];
        const double dx = (pb[x] - pa[x]) * k->s;
        d2 += dx * dx;
    }
    const double r = sqrt(d2);
    double cached[SSS_MAX_CHANNELS] = {0};
    for (uint32_t c = 0; c < C; c++) tau_exp[c] = 0.0;
    /* far pairs (§4.3): the cells' mean excess over σtr_ref, relative to
     * the endpoints' mean (exactly 0 when the field is constant); between
     * far_mm and 1.5 far_mm blended with the march, so that q does not jump
     * where a pair's length crosses the threshold (a rigid motion moves
     * lengths by rounding) */
    double wc = 0.0;
    if (k->ncells && r > k->far_mm) {
        const double u = (r - k->far_mm) / (0.5 * k->far_mm);
        wc = u >= 1.0 ? 1.0 : u * u * (3.0 - 2.0 * u);
        double mt[SSS_MAX_CHANNELS];
        const double *m = cell_excess(k, k->cell[a], k->cell[b], mt);
        for (uint32_t c = 0; c < C; c++) {
            /* max(0, ·) written out, as in march_sum: libm's fmax is a
             * call per far pair and channel (the sign of a zero does not
             * reach κ: exp(±0) = 1, and ±0 added to a sum leaves it) */
            const double e = m[c] + (k->sigma_tr_ref[c] - 0.5 * (k->sigma_tr[(size_t)a * C + c] +
                                                                   k->sigma_tr[(size_t)b * C + c]));
            cached[c] = r * (e > 0.0 ? e : 0.0);
        }
    }
    if (wc < 1.0 && k->step_mm > 0.0 && r > 0.0)
        march_tau(k, pa, pb, r, &k->sigma_tr[(size_t)a * C], &k->sigma_tr[(size_t)b * C], tau_exp);
    if (wc > 0.0)
        for (uint32_t c = 0; c < C; c++) tau_exp[c] = wc >= 1.0 ? cached[c] : (1.0 - wc) * tau_exp[c] + wc * cached[c];
    return r;
}

/* The radius (mm) of the disk of vertex v's area, which profile() reads. */
static double rho_of(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t v)
{
    return sqrt(mesh->area[v] * k->s * k->s / SSS_PI);
}

/* κ(o, i) from the pair's shared part: the profiles, which depend on the
 * order (the own-area disks), times τ. Returns whether κ(i, o) has the
 * same bits: neither disk covers the other endpoint, so every profile is
 * the point value R_d(r) in both orders, and the sum of the two ends' g
 * and the product under the root commute. */
static int kappa_from(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double r,
                       const double *tau_exp, double *kappa)
{
    const uint32_t C = k->C;
    const double rho_o = rho_of(k, mesh, o), rho_i = rho_of(k, mesh, i);
    const int sym = r > 0.0 && r >= rho_o && r >= rho_i;
    /* Both endpoints at the reference's f (most of a surface that an
     * inclusion or a stratum does not reach): the profile ratio is 1, as
     * sqrt(P²)/P computes it, without three profiles per channel. */
    const int ref_ends = k->f[o] == k->f_min && k->f[i] == k->f_min;
    if (!ref_ends && k->prof && r > 0.0 && r >= rho_i && r <= k->radius_mm) {
        /* point profiles within the table's range: exp(g(f_o, r) + g(f_i, r)
         * − τ's exponent), one exponential per channel (build_profiles);
         * the sum commutes, so κ(i, o) keeps κ(o, i)'s bits */
        const double u = r / k->prof_dr;
        size_t j = (size_t)u;
        j = j > SSS_FIELD_PROFILE_R - 2 ? SSS_FIELD_PROFILE_R - 2 : j;
        const double rw = u - (double)j;
        for (uint32_t c = 0; c < C; c++) kappa[c] = exp(prof_at(k, o, j, rw, c) + prof_at(k, i, j, rw, c) - tau_exp[c]);
        return sym;
    }
    for (uint32_t c = 0; c < C; c++) {
        /* τ = 1 exactly where nothing on the segment exceeds the mean
         * (exp(−0) = 1 in IEEE arithmetic): most pairs of a field that
         * the bricks' early-out skips whole, without a call into libm */
        const double tau = tau_exp[c] == 0.0 ? 1.0 : exp(-tau_exp[c]);
        if (ref_ends) {
            kappa[c] = tau;
            continue;
        }
        /* an endpoint at f_min has the reference's dipole, bit for bit
         * (the same blend of the same f): its profile is P_ref's, which a
         * plateau of the field (strata, inclusions) makes common */
        const double pr = profile(&k->dip_ref[c], r, rho_o, rho_i);
        const double po = k->f[o] == k->f_min ? pr : profile(&k->dip[(size_t)o * C + c], r, rho_o, rho_i);
        const double pi = k->f[i] == k->f[o] ? po
                          : k->f[i] == k->f_min ? pr
                                                : profile(&k->dip[(size_t)i * C + c], r, rho_o, rho_i);
        kappa[c] = pr > 0.0 ? sqrt(po * pi) / pr * tau : 0.0;
    }
    return sym;
}

int sss_field_kappa_sym(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double *kappa)
{
    double tau_exp[SSS_MAX_CHANNELS];
    const double r = pair_tau(k, mesh, o, i, tau_exp);
    return kappa_from(k, mesh, o, i, r, tau_exp, kappa);
}

void sss_field_kappa(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, uint32_t i, double *kappa)
{
    (void)sss_field_kappa_sym(k, mesh, o, i, kappa);
}

/* The entry of source i in row o of sorted rows, or UINT64_MAX. */
static uint64_t find_entry(const sss_weights *rows, uint32_t o, uint32_t i)
{
    uint64_t lo = rows->start[o], hi = rows->start[o + 1];
    while (lo < hi) {
        const uint64_t m = lo + (hi - lo) / 2;
        if (rows->idx[m] < i) lo = m + 1;
        else hi = m;
    }
    return lo < rows->start[o + 1] && rows->idx[lo] == i ? lo : UINT64_MAX;
}

/* find_entry(rows, v, x) from cur[v], the offset in row v of the first
 * source at least the thread's previous query there: forward from it when
 * x is not below that query, else from the row's start. cur NULL: a binary
 * search. */
static uint64_t find_from(const sss_weights *rows, uint32_t *cur, uint32_t v, uint32_t x)
{
    if (!cur) return find_entry(rows, v, x);
    const uint64_t s = rows->start[v], end = rows->start[v + 1];
    uint64_t p = s + cur[v];
    if (p > s && rows->idx[p - 1] >= x) p = s;
    while (p < end && rows->idx[p] < x) p++;
    cur[v] = (uint32_t)(p - s);
    return p < end && rows->idx[p] == x ? p : UINT64_MAX;
}

/* A hint to the cache; nothing where the compiler has none. */
#if defined(__GNUC__) || defined(__clang__)
#define PREFETCH(p) __builtin_prefetch(p)
#else
#define PREFETCH(p) ((void)(p))
#endif
/* How many entries ahead of the one scaled its partner is prefetched. */
#define PARTNER_AHEAD 4

/* Scales entry e = (o, i) of rows by κ(o, i) and, when mirror is not
 * UINT64_MAX, the entry mirror = (i, o) by κ(i, o), from one march. */
static void scale_pair(const sss_field_kernel *k, const sss_mesh *mesh, sss_weights *rows, uint32_t o, uint32_t i,
                       uint64_t e, uint64_t mirror)
{
    const uint32_t C = k->C;
    double tau_exp[SSS_MAX_CHANNELS], kap[SSS_MAX_CHANNELS];
    const double r = pair_tau(k, mesh, o, i, tau_exp);
    const int sym = kappa_from(k, mesh, o, i, r, tau_exp, kap);
    float *w = &rows->w[e * C];
    for (uint32_t c = 0; c < C; c++) w[c] = (float)((double)w[c] * kap[c]);
    if (mirror == UINT64_MAX) return;
    /* κ(i, o) has κ(o, i)'s bits where neither disk covers the other
     * endpoint: its profiles are not evaluated again */
    if (!sym) kappa_from(k, mesh, i, o, r, tau_exp, kap);
    w = &rows->w[mirror * C];
    for (uint32_t c = 0; c < C; c++) w[c] = (float)((double)w[c] * kap[c]);
}

sss_result sss_field_weights_apply(const sss_field_kernel *k, const sss_mesh *mesh, sss_weights *rows,
                                   const sss_cancel_flag *cancel, sss_error *err)
{
    if (rows->nrows != k->nv || rows->channels != k->C)
        return sss_fail(err, SSS_ERR_ARG, "field weights: %u rows of %u channels for %u vertices of %u", rows->nrows,
                        rows->channels, k->nv, k->C);
    /* Each pair's march once for both its entries (o, i) and (i, o) when
     * the rows are sorted (the neighbourhoods are): the march is most of
     * the field's cost (docs/heterogeneous.md §8), and κ's bits do not
     * depend on which row computed it (pair_tau runs from the lower
     * index). The entry (i, o) is scaled with (o, i) by row min(o, i) when
     * row min holds the pair, else alone by its own row: each entry
     * exactly once. */
    int sorted = 1;
    for (uint32_t o = 0; o < rows->nrows && sorted; o++)
        for (uint64_t e = rows->start[o] + 1; e < rows->start[o + 1]; e++)
            if (rows->idx[e] <= rows->idx[e - 1]) {
                sorted = 0;
                break;
            }
#pragma omp parallel
    {
        /* The partner (i, o) is found from a cursor per row and thread
         * rather than by a binary search per entry (a cache miss per
         * halving: 23 % of the blob's field bake in perf). A thread takes
         * its rows in increasing o, so its queries into each row increase
         * and its cursor there only moves forward: O(entries) per thread.
         * Without the cursors' memory it searches. */
        uint32_t *cur = sorted ? calloc(rows->nrows, sizeof *cur) : NULL;
#pragma omp for schedule(dynamic, 64)
        for (int64_t o = 0; o < (int64_t)rows->nrows; o++) {
            if (sss_cancelled(cancel)) continue;
            for (uint64_t e = rows->start[o]; e < rows->start[o + 1]; e++) {
                const uint32_t i = rows->idx[e];
                if (cur && e + PARTNER_AHEAD < rows->start[o + 1]) {
                    /* the partner's row is elsewhere in memory: ask for the
                     * lines find_from and scale_pair will read a few
                     * entries from now, so the misses (9 % of the
                     * dragon's field bake in perf) overlap the marches */
                    const uint32_t i2 = rows->idx[e + PARTNER_AHEAD];
                    const uint64_t p2 = rows->start[i2] + cur[i2];
                    PREFETCH(&rows->idx[p2]);
                    PREFETCH(&rows->w[p2 * rows->channels]);
                }
                uint64_t mirror = UINT64_MAX;
                if (sorted && i != (uint32_t)o) {
                    mirror = find_from(rows, cur, i, (uint32_t)o);
                    if (i < (uint32_t)o && mirror != UINT64_MAX) continue; /* scaled with row i */
                }
                scale_pair(k, mesh, rows, (uint32_t)o, i, e, mirror);
            }
        }
        free(cur);
    }
    if (sss_cancelled(cancel)) return sss_fail(err, SSS_ERR_INTERRUPTED, "interrupted during the field's weights");
    return SSS_OK;
}

sss_result sss_field_point_at(const sss_field_kernel *k, const double x[3], sss_field_point *pt)
{
    memset(pt, 0, sizeof *pt);
    memcpy(pt->x, x, sizeof pt->x);
    double xr[3];
    sss_hetero_to_rest(k->h, x, xr);
    pt->f = sss_field_eval(&k->h->field, xr);
    sss_material m;
    sss_material_blend(&k->base, &k->h->inside, pt->f, &m);
    for (uint32_t c = 0; c < k->C; c++) {
        pt->sigma_tr[c] = sss_material_sigma_tr(&k->base, &k->h->inside, pt->f, c);
        if (sss_dipole_init(&pt->dip[c], m.sigma_a[c], m.sigmap_s[c], k->base.eta) != SSS_OK) return SSS_ERR_ARG;
    }
    return SSS_OK;
}

void sss_field_kappa_point(const sss_field_kernel *k, const sss_mesh *mesh, uint32_t o, const sss_field_point *pt,
                           double *kappa)
{
    const uint32_t C = k->C;
    double po[3], d2 = 0.0;
    for (int x = 0; x < 3; x++) {
        po[x] = mesh->pos[3 * (size_t)o + x];
        const double dx = (pt->x[x] - po[x]) * k->s;
        d2 += dx * dx;
    }
    const double r = sqrt(d2);
    double tau_exp[SSS_MAX_CHANNELS] = {0};
    if (k->step_mm > 0.0 && r > 0.0) /* from x_o to the point */
        march_tau(k, po, pt->x, r, &k->sigma_tr[(size_t)o * C], pt->sigma_tr, tau_exp);
    /* both ends at the reference's f: the ratio is 1 (kappa_from) */
    const int ref_ends = k->f[o] == k->f_min && pt->f == k->f_min;
    for (uint32_t c = 0; c < C; c++) {
        if (ref_ends) {
            kappa[c] = exp(-tau_exp[c]);
            continue;
        }
        const double pr = sss_rd(&k->dip_ref[c], r);
        const double pa = k->f[o] == k->f_min ? pr : sss_rd(&k->dip[(size_t)o * C + c], r);
        const double pb = pt->f == k->f_min ? pr : sss_rd(&pt->dip[c], r);
        kappa[c] = pr > 0.0 ? sqrt(pa * pb) / pr * exp(-tau_exp[c]) : 0.0;
    }
}
