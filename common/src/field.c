/* field.c: scalar material fields f(x) ∈ [0, 1] and the material blend
 * they drive (seed 000, Shopf 2007 §4.3.2–§4.3.3; docs/heterogeneous.md
 * §2–§3). Every procedural kind is a closed formula over an integer hash,
 * so a field is the same on every machine and thread count, and the exact
 * evaluator recomputes it from the few numbers the file stores.
 */
#include "sss/field.h"
#include "sss/vec3.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *sss_field_kind_name(uint32_t kind)
{
    static const char *const names[SSS_FIELD_KINDS] = {"none", "constant", "veins", "inclusions",
                                                       "box",  "sphere",   "layers", "grid"};
    return kind < SSS_FIELD_KINDS ? names[kind] : "?";
}

/* ---- noise (docs/heterogeneous.md §2.1) ---------------------------------- */

/* A 32-bit integer mix (the finaliser of MurmurHash3): every input bit
 * changes about half the output bits. */
static uint32_t mix32(uint32_t h)
{
    h ^= h >> 16;
    h *= 0x85ebca6bu;
    h ^= h >> 13;
    h *= 0xc2b2ae35u;
    h ^= h >> 16;
    return h;
}

static uint32_t hash3(int64_t x, int64_t y, int64_t z, uint32_t seed)
{
    uint32_t h = mix32(seed ^ 0x9e3779b9u);
    h = mix32(h ^ (uint32_t)x);
    h = mix32(h ^ (uint32_t)y);
    h = mix32(h ^ (uint32_t)z);
    return h;
}

/* Uniform in [0, 1) from a lattice point (24 bits: exact in double). */
static double lattice(int64_t x, int64_t y, int64_t z, uint32_t seed)
{
    return (double)(hash3(x, y, z, seed) >> 8) * (1.0 / 16777216.0);
}

static double fade(double t) { return t * t * (3.0 - 2.0 * t); }

/* Value noise n(p) ∈ [0, 1): the lattice values interpolated trilinearly
 * with the fade weights s(t) = t²(3 − 2t) (C¹ across cells). */
static double value_noise(const double p[3], uint32_t seed)
{
    const double fx = floor(p[0]), fy = floor(p[1]), fz = floor(p[2]);
    const int64_t x = (int64_t)fx, y = (int64_t)fy, z = (int64_t)fz;
    const double u = fade(p[0] - fx), v = fade(p[1] - fy), w = fade(p[2] - fz);
    double c[2][2];
    for (int b = 0; b < 2; b++)
        for (int a = 0; a < 2; a++) {
            const double l0 = lattice(x, y + a, z + b, seed), l1 = lattice(x + 1, y + a, z + b, seed);
            c[b][a] = l0 + u * (l1 - l0);
        }
    const double e0 = c[0][0] + v * (c[0][1] - c[0][0]), e1 = c[1][0] + v * (c[1][1] - c[1][0]);
    return e0 + w * (e1 - e0);
}

double sss_field_noise(const double x[3], double scale_mm, uint32_t seed)
{
    const double p[3] = {x[0] / scale_mm, x[1] / scale_mm, x[2] / scale_mm};
    return value_noise(p, seed);
}

#define TURB_OCTAVES 5
/* Turbulence T(p) = Σ_k 2^−k |2 n(2^k p) − 1| / Σ_k 2^−k ∈ [0, 1],
 * k = 0 … 4 (Perlin's turbulence, octaves seeded apart). */
static double turbulence(const double p[3], uint32_t seed)
{
    double t = 0.0, amp = 1.0, norm = 0.0, q[3] = {p[0], p[1], p[2]};
    for (int k = 0; k < TURB_OCTAVES; k++) {
        t += amp * fabs(2.0 * value_noise(q, seed + (uint32_t)k * 7919u) - 1.0);
        norm += amp;
        amp *= 0.5;
        for (int a = 0; a < 3; a++) q[a] *= 2.0;
    }
    return t / norm;
}

/* 1 inside (d ≤ −e/2), 0 outside (d ≥ e/2), smoothstep between: a signed
 * distance d (mm) turned into f with an edge of width e. */
static double inside_of(double d, double e)
{
    if (!(e > 0.0)) return d <= 0.0 ? 1.0 : 0.0;
    double t = 0.5 - d / e;
    t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
    return fade(t);
}

/* ---- the kinds ------------------------------------------------------------ */

#define VEIN_SHARPNESS 8.0
#define VEIN_WARP 2.0

static double eval_veins(const sss_field *f, const double x[3])
{
    const double p[3] = {x[0] / f->scale_mm, x[1] / f->scale_mm, x[2] / f->scale_mm};
    /* Perlin's marble: a sine along x whose phase turbulence displaces;
     * the veins are where the sine crosses zero. */
    const double s = sin(SSS_PI * (p[0] + VEIN_WARP * turbulence(p, f->seed)));
    return pow(1.0 - fabs(s), VEIN_SHARPNESS);
}

static double eval_inclusions(const sss_field *f, const double x[3])
{
    const double S = f->scale_mm;
    const double p[3] = {x[0] / S, x[1] / S, x[2] / S};
    const int64_t cx = (int64_t)floor(p[0]), cy = (int64_t)floor(p[1]), cz = (int64_t)floor(p[2]);
    double best = INFINITY;
    /* Worley: one feature point per unit cell at a hashed position; the
     * nearest lies in the 3 × 3 × 3 block around p's cell. */
    for (int64_t k = cz - 1; k <= cz + 1; k++)
        for (int64_t j = cy - 1; j <= cy + 1; j++)
            for (int64_t i = cx - 1; i <= cx + 1; i++) {
                const uint32_t h = hash3(i, j, k, f->seed);
                const double q[3] = {(double)i + (double)(mix32(h) >> 8) * (1.0 / 16777216.0),
                                     (double)j + (double)(mix32(h ^ 0x68e31da4u) >> 8) * (1.0 / 16777216.0),
                                     (double)k + (double)(mix32(h ^ 0xb5297a4du) >> 8) * (1.0 / 16777216.0)};
                const double d = (p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) +
                                 (p[2] - q[2]) * (p[2] - q[2]);
                if (d < best) best = d;
            }
    return inside_of(sqrt(best) * S - f->thickness_mm, f->edge_mm);
}

static double eval_box(const sss_field *f, const double x[3])
{
    double q[3], out2 = 0.0, in = -INFINITY;
    for (int a = 0; a < 3; a++) {
        q[a] = fabs(x[a] - f->centre_mm[a]) - f->half_mm[a];
        if (q[a] > 0.0) out2 += q[a] * q[a];
        if (q[a] > in) in = q[a];
    }
    const double d = sqrt(out2) + (in < 0.0 ? in : 0.0); /* the box's signed distance */
    return inside_of(d, f->edge_mm);
}

static double eval_sphere(const sss_field *f, const double x[3])
{
    const double dx = x[0] - f->centre_mm[0], dy = x[1] - f->centre_mm[1], dz = x[2] - f->centre_mm[2];
    return inside_of(sqrt(dx * dx + dy * dy + dz * dz) - f->half_mm[0], f->edge_mm);
}

static double eval_layers(const sss_field *f, const double x[3])
{
    const double t = f->thickness_mm;
    /* height above the first stratum's centre plane, wrapped to the
     * nearest stratum when they repeat */
    double c = f->normal[0] * x[0] + f->normal[1] * x[1] + f->normal[2] * x[2] - f->offset_mm - 0.5 * t;
    if (f->scale_mm > 0.0) c -= f->scale_mm * floor(c / f->scale_mm + 0.5);
    return inside_of(fabs(c) - 0.5 * t, f->edge_mm);
}

static double eval_grid(const sss_field *f, const double x[3])
{
    size_t i0[3];
    double w[3];
    for (int a = 0; a < 3; a++) {
        double u = (x[a] - f->origin_mm[a]) / f->voxel_mm;
        const double top = (double)(f->n[a] - 1);
        u = u < 0.0 ? 0.0 : u > top ? top : u; /* clamped to the edge: sss_field_covers says where that is valid */
        double fl = floor(u);
        if (fl >= top && f->n[a] > 1) fl = top - 1.0;
        i0[a] = (size_t)fl;
        w[a] = f->n[a] > 1 ? u - fl : 0.0;
    }
    const size_t nx = f->n[0], nxy = (size_t)f->n[0] * f->n[1];
    const size_t sx = f->n[0] > 1, sy = f->n[1] > 1 ? nx : 0, sz = f->n[2] > 1 ? nxy : 0;
    const float *b = f->data + i0[2] * nxy + i0[1] * nx + i0[0];
    const double c00 = b[0] + w[0] * ((double)b[sx] - b[0]), c01 = b[sy] + w[0] * ((double)b[sy + sx] - b[sy]);
    const double c10 = b[sz] + w[0] * ((double)b[sz + sx] - b[sz]),
                 c11 = b[sz + sy] + w[0] * ((double)b[sz + sy + sx] - b[sz + sy]);
    const double e0 = c00 + w[1] * (c01 - c00), e1 = c10 + w[1] * (c11 - c10);
    return e0 + w[2] * (e1 - e0);
}

double sss_field_eval(const sss_field *f, const double x[3])
{
    double v;
    switch (f->kind) {
    case SSS_FIELD_CONSTANT: v = f->value; break;
    case SSS_FIELD_VEINS: v = eval_veins(f, x); break;
    case SSS_FIELD_INCLUSIONS: v = eval_inclusions(f, x); break;
    case SSS_FIELD_BOX: v = eval_box(f, x); break;
    case SSS_FIELD_SPHERE: v = eval_sphere(f, x); break;
    case SSS_FIELD_LAYERS: v = eval_layers(f, x); break;
    case SSS_FIELD_GRID: v = eval_grid(f, x); break;
    default: return 0.0;
    }
    return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
}

double sss_field_step_mm(const sss_field *f)
{
    double h;
    switch (f->kind) {
    case SSS_FIELD_VEINS: h = f->scale_mm / 16.0; break; /* five octaves: the finest is scale/16 */
    case SSS_FIELD_INCLUSIONS: h = fmin(f->scale_mm / 4.0, f->thickness_mm / 2.0); break;
    case SSS_FIELD_BOX: h = fmin(f->half_mm[0], fmin(f->half_mm[1], f->half_mm[2])) / 2.0; break;
    case SSS_FIELD_SPHERE: h = f->half_mm[0] / 2.0; break;
    case SSS_FIELD_LAYERS: h = f->thickness_mm / 2.0; break;
    case SSS_FIELD_GRID: return f->voxel_mm / 2.0;
    default: return 0.0;
    }
    /* a smooth edge narrower than the feature sets the step */
    if (f->edge_mm > 0.0 && f->edge_mm / 2.0 < h) h = f->edge_mm / 2.0;
    return h;
}

static int finite3(const double v[3]) { return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]); }

#define FIELD_MM_MAX 1e9

sss_result sss_field_check(const sss_field *f, sss_error *err)
{
    if (f->kind >= SSS_FIELD_KINDS) return sss_fail(err, SSS_ERR_ARG, "field kind %u is not known", f->kind);
    if (!(f->edge_mm >= 0.0 && f->edge_mm <= FIELD_MM_MAX))
        return sss_fail(err, SSS_ERR_ARG, "edge_mm %g is out of range [0, %g]", f->edge_mm, FIELD_MM_MAX);
    switch (f->kind) {
    case SSS_FIELD_CONSTANT:
        if (!(f->value >= 0.0 && f->value <= 1.0))
            return sss_fail(err, SSS_ERR_ARG, "constant %g is out of range [0, 1]", f->value);
        break;
    case SSS_FIELD_VEINS:
    case SSS_FIELD_INCLUSIONS:
        if (!(f->scale_mm > 0.0 && f->scale_mm <= FIELD_MM_MAX))
            return sss_fail(err, SSS_ERR_ARG, "scale_mm %g must be in (0, %g]", f->scale_mm, FIELD_MM_MAX);
        if (f->kind == SSS_FIELD_INCLUSIONS && !(f->thickness_mm > 0.0 && f->thickness_mm <= f->scale_mm))
            return sss_fail(err, SSS_ERR_ARG, "radius_mm %g must be in (0, scale_mm = %g]", f->thickness_mm,
                            f->scale_mm);
        break;
    case SSS_FIELD_BOX:
    case SSS_FIELD_SPHERE:
        if (!finite3(f->centre_mm) || fabs(f->centre_mm[0]) > FIELD_MM_MAX || fabs(f->centre_mm[1]) > FIELD_MM_MAX ||
            fabs(f->centre_mm[2]) > FIELD_MM_MAX)
            return sss_fail(err, SSS_ERR_ARG, "centre_mm must be 3 finite numbers within ±%g", FIELD_MM_MAX);
        for (int a = 0; a < (f->kind == SSS_FIELD_BOX ? 3 : 1); a++)
            if (!(f->half_mm[a] > 0.0 && f->half_mm[a] <= FIELD_MM_MAX))
                return sss_fail(err, SSS_ERR_ARG, "%s %g must be in (0, %g]",
                                f->kind == SSS_FIELD_BOX ? "half_mm" : "radius_mm", f->half_mm[a], FIELD_MM_MAX);
        break;
    case SSS_FIELD_LAYERS: {
        const double n2 = f->normal[0] * f->normal[0] + f->normal[1] * f->normal[1] + f->normal[2] * f->normal[2];
        if (!finite3(f->normal) || !(fabs(n2 - 1.0) < 1e-9))
            return sss_fail(err, SSS_ERR_ARG, "normal must be a unit vector");
        if (!(f->thickness_mm > 0.0 && f->thickness_mm <= FIELD_MM_MAX))
            return sss_fail(err, SSS_ERR_ARG, "thickness_mm %g must be in (0, %g]", f->thickness_mm, FIELD_MM_MAX);
        if (!(f->scale_mm == 0.0 || (f->scale_mm > f->thickness_mm && f->scale_mm <= FIELD_MM_MAX)))
            return sss_fail(err, SSS_ERR_ARG, "period_mm %g must be 0 (one stratum) or in (thickness_mm, %g]",
                            f->scale_mm, FIELD_MM_MAX);
        if (!(fabs(f->offset_mm) <= FIELD_MM_MAX))
            return sss_fail(err, SSS_ERR_ARG, "offset_mm %g is out of range", f->offset_mm);
        break;
    }
    case SSS_FIELD_GRID: {
        const uint64_t nn = (uint64_t)f->n[0] * f->n[1] * f->n[2];
        if (!f->n[0] || !f->n[1] || !f->n[2] || nn > SSS_FIELD_GRID_MAX_NODES)
            return sss_fail(err, SSS_ERR_ARG, "grid of %u x %u x %u nodes (1 to %u nodes)", f->n[0], f->n[1], f->n[2],
                            SSS_FIELD_GRID_MAX_NODES);
        if (!(f->voxel_mm > 0.0 && f->voxel_mm <= FIELD_MM_MAX) || !finite3(f->origin_mm))
            return sss_fail(err, SSS_ERR_ARG, "grid voxel %g mm must be in (0, %g] and the origin finite",
                            f->voxel_mm, FIELD_MM_MAX);
        if (!f->data) return sss_fail(err, SSS_ERR_ARG, "grid without samples");
        for (uint64_t k = 0; k < nn; k++)
            if (!(f->data[k] >= 0.0f && f->data[k] <= 1.0f))
                return sss_fail(err, SSS_ERR_ARG, "grid value %llu is %g, outside [0, 1]", (unsigned long long)k,
                                f->data[k]);
        break;
    }
    default: break;
    }
    return SSS_OK;
}

int sss_field_covers(const sss_field *f, const double lo[3], const double hi[3], char *why, size_t n)
{
    if (f->kind == SSS_FIELD_GRID) {
        const double tol = 0.5 * f->voxel_mm;
        for (int a = 0; a < 3; a++) {
            const double g0 = f->origin_mm[a], g1 = f->origin_mm[a] + f->voxel_mm * (f->n[a] - 1);
            if (lo[a] < g0 - tol || hi[a] > g1 + tol) {
                snprintf(why, n, "the grid spans [%g, %g] mm along %c but the object [%g, %g] mm: the field does not "
                         "cover the mesh", g0, g1, "xyz"[a], lo[a], hi[a]);
                return 0;
            }
        }
    } else if (f->kind == SSS_FIELD_BOX || f->kind == SSS_FIELD_SPHERE) {
        for (int a = 0; a < 3; a++) {
            const double h = f->kind == SSS_FIELD_BOX ? f->half_mm[a] : f->half_mm[0];
            if (f->centre_mm[a] + h < lo[a] || f->centre_mm[a] - h > hi[a]) {
                snprintf(why, n, "the %s [%g, %g] mm along %c lies outside the object [%g, %g] mm",
                         sss_field_kind_name(f->kind), f->centre_mm[a] - h, f->centre_mm[a] + h, "xyz"[a], lo[a],
                         hi[a]);
                return 0;
            }
        }
    }
    return 1;
}

sss_result sss_field_sample(const sss_field *f, const double lo[3], const double hi[3], uint32_t nmax,
                            sss_field *g, sss_error *err)
{
    memset(g, 0, sizeof *g);
    double ext = 0.0;
    for (int a = 0; a < 3; a++) {
        if (!(hi[a] >= lo[a]) || !isfinite(lo[a]) || !isfinite(hi[a]))
            return sss_fail(err, SSS_ERR_ARG, "field sampling: an empty or non-finite box");
        if (hi[a] - lo[a] > ext) ext = hi[a] - lo[a];
    }
    if (nmax < 2 || nmax > 512 || !(ext > 0.0))
        return sss_fail(err, SSS_ERR_ARG, "field sampling: %u nodes along the longest side (2 to 512) of a box of "
                        "size %g mm", nmax, ext);
    g->kind = SSS_FIELD_GRID;
    g->voxel_mm = ext / (nmax - 1);
    for (int a = 0; a < 3; a++) {
        g->origin_mm[a] = lo[a];
        g->n[a] = (uint32_t)ceil((hi[a] - lo[a]) / g->voxel_mm - 1e-9) + 1;
        if (g->n[a] > nmax) g->n[a] = nmax;
    }
    const size_t nn = (size_t)g->n[0] * g->n[1] * g->n[2];
    if (!(g->data = malloc(nn * sizeof *g->data)))
        return sss_fail(err, SSS_ERR_NOMEM, "field sampling: out of memory for %zu nodes", nn);
    for (uint32_t k = 0; k < g->n[2]; k++)
        for (uint32_t j = 0; j < g->n[1]; j++)
            for (uint32_t i = 0; i < g->n[0]; i++) {
                const double x[3] = {lo[0] + g->voxel_mm * i, lo[1] + g->voxel_mm * j, lo[2] + g->voxel_mm * k};
                g->data[((size_t)k * g->n[1] + j) * g->n[0] + i] = (float)sss_field_eval(f, x);
            }
    return SSS_OK;
}

sss_result sss_field_copy(const sss_field *src, sss_field *dst, sss_error *err)
{
    *dst = *src;
    dst->data = NULL;
    if (src->kind != SSS_FIELD_GRID || !src->data) return SSS_OK;
    const size_t nn = (size_t)src->n[0] * src->n[1] * src->n[2];
    if (!(dst->data = malloc(nn * sizeof *dst->data)))
        return sss_fail(err, SSS_ERR_NOMEM, "field: out of memory for %zu nodes", nn);
    memcpy(dst->data, src->data, nn * sizeof *dst->data);
    return SSS_OK;
}

void sss_field_free(sss_field *f)
{
    if (!f) return;
    free(f->data);
    memset(f, 0, sizeof *f);
}

/* ---- the material ------------------------------------------------------- */

void sss_material_blend(const sss_material *a, const sss_material *b, double f, sss_material *out)
{
    sss_material m = *a;
    /* (1 − f) a + f b: exactly a at f = 0 and exactly b at f = 1 */
    for (int c = 0; c < SSS_MAX_CHANNELS; c++) {
        m.sigma_a[c] = (1.0 - f) * a->sigma_a[c] + f * b->sigma_a[c];
        m.sigmap_s[c] = (1.0 - f) * a->sigmap_s[c] + f * b->sigmap_s[c];
    }
    *out = m;
}

double sss_material_sigma_tr(const sss_material *a, const sss_material *b, double f, uint32_t c)
{
    const double sa = (1.0 - f) * a->sigma_a[c] + f * b->sigma_a[c];
    const double ss = (1.0 - f) * a->sigmap_s[c] + f * b->sigmap_s[c];
    return sqrt(3.0 * sa * (sa + ss));
}

sss_result sss_transport_sigma_a(const double colour[3], double distance_mm, const double sigmap_s[3],
                                 double sigma_a[3], sss_error *err)
{
    if (!(distance_mm > 0.0 && distance_mm <= FIELD_MM_MAX))
        return sss_fail(err, SSS_ERR_ARG, "distance_mm %g must be in (0, %g]", distance_mm, FIELD_MM_MAX);
    for (int c = 0; c < 3; c++)
        if (!(colour[c] > 0.0 && colour[c] < 1.0))
            return sss_fail(err, SSS_ERR_ARG, "colour %d is %g: a transport colour lies in (0, 1)", c, colour[c]);
    for (int c = 0; c < 3; c++) {
        const double str = -log(colour[c]) / distance_mm;
        const double s2 = str * str * (4.0 / 3.0);
        /* the root of σa² + σ′s σa − σtr²/3 = 0, in the form that does not
         * cancel when σtr ≪ σ′s */
        sigma_a[c] = 0.5 * s2 / (sigmap_s[c] + sqrt(sigmap_s[c] * sigmap_s[c] + s2));
    }
    return SSS_OK;
}

void sss_hetero_to_rest(const sss_hetero *h, const double p[3], double x[3])
{
    for (int a = 0; a < 3; a++)
        x[a] = h->xf[4 * a] * p[0] + h->xf[4 * a + 1] * p[1] + h->xf[4 * a + 2] * p[2] + h->xf[4 * a + 3];
}
