/* ref_walk.c: one path of the reference (docs/reference.md §2–§3): free
 * flights, Henyey–Greenstein scattering, Fresnel reflection and refraction
 * at the smooth boundary, Russian roulette, and the next-event estimate of
 * a directional light through the refractive boundary; the radiance
 * estimator (a path followed backwards from the surface point seen) and the
 * particle tracer (a path followed forwards from a beam) share them.
 *
 * Conventions: directions are unit; u is the direction a path travels. The
 * boundary is crossed with the radiance law L_inside = η² F_t L_outside
 * (radiance over n² is invariant, docs/reference.md §2), so a path followed
 * backwards gains η² when it leaves the medium and 1/η² when it enters.
 * Fresnel transmittance is docs/physics.md §3's F_t(η, cos θ) for light
 * arriving from outside and F_t(1/η, cos θ) from inside. */
#include "reference/ref_internal.h"

#include <math.h>
#include <string.h>

#include "sss/dipole.h"
#include "sss/field.h"
#include "sss/random.h"
#include "sss/single.h" /* sss_phase_hg */
#include "sss/vec3.h"

void ref_medium_init(const sss_ref_medium *m, double mm_per_unit, ref_medium *out)
{
    memset(out, 0, sizeof *out);
    const int het = m->hetero && m->hetero->field.kind != SSS_FIELD_NONE;
    int grey = 1;
    for (int c = 1; c < 3; c++)
        if (m->sigma_a[c] != m->sigma_a[0] || m->sigma_s[c] != m->sigma_s[0] ||
            (het && (m->hetero->inside.sigma_a[c] != m->hetero->inside.sigma_a[0] ||
                     m->hetero->inside.sigmap_s[c] != m->hetero->inside.sigmap_s[0])))
            grey = 0;
    out->C = grey ? 1 : 3;
    for (int c = 0; c < 3; c++) {
        out->sigma_a[c] = m->sigma_a[c];
        out->sigma_s[c] = m->sigma_s[c];
        out->sigma_t[c] = m->sigma_a[c] + m->sigma_s[c];
    }
    out->g = m->g;
    out->eta = m->eta;
    if (het) {
        out->het = m->hetero;
        out->mm_per_unit = mm_per_unit;
        for (int c = 0; c < 3; c++) {
            out->sigma_a1[c] = m->hetero->inside.sigma_a[c];
            out->sigma_s1[c] = m->hetero->inside.sigmap_s[c] / (1.0 - m->g); /* σ′s = σs (1 − g) */
            out->sigma_bar = fmax(out->sigma_bar, fmax(out->sigma_t[c], out->sigma_a1[c] + out->sigma_s1[c]));
        }
    }
}

/* σa and σs at x (mm, the scene's frame): the blend (1 − f) base + f inside
 * of docs/heterogeneous.md §3 at the field's value at x's rest-frame point. */
static void medium_at(const ref_medium *m, const double x_mm[3], double sa[3], double ss[3])
{
    const double p[3] = {x_mm[0] / m->mm_per_unit, x_mm[1] / m->mm_per_unit, x_mm[2] / m->mm_per_unit};
    double r[3];
    sss_hetero_to_rest(m->het, p, r);
    const double f = sss_field_eval(&m->het->field, r);
    for (int c = 0; c < 3; c++) {
        sa[c] = (1.0 - f) * m->sigma_a[c] + f * m->sigma_a1[c];
        ss[c] = (1.0 - f) * m->sigma_s[c] + f * m->sigma_s1[c];
    }
}

static uint64_t mix64(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

uint64_t ref_stream(uint64_t seed, uint64_t task, uint64_t path)
{
    uint64_t s = mix64(seed + 0x9E3779B97F4A7C15ull);
    s = mix64(s ^ mix64(task + 0x632BE59BD9B4E019ull));
    return mix64(s ^ mix64(path + 0x85EBCA77C2B2AE63ull));
}

/* ---- directions ---- */

/* An orthonormal pair a, b perpendicular to unit n (Duff et al. 2017). */
static void frame(const double n[3], double a[3], double b[3])
{
    const double sg = n[2] >= 0.0 ? 1.0 : -1.0, q = -1.0 / (sg + n[2]), r = n[0] * n[1] * q;
    a[0] = 1.0 + sg * n[0] * n[0] * q;
    a[1] = sg * r;
    a[2] = -sg * n[0];
    b[0] = r;
    b[1] = sg + n[1] * n[1] * q;
    b[2] = -n[1];
}

static void reflect(const double d[3], const double n[3], double r[3])
{
    const double c = 2.0 * sss_dot3(d, n);
    for (int k = 0; k < 3; k++) r[k] = d[k] - c * n[k];
}

/* Refraction of d into the side n faces (d·n > 0), ratio = n_from / n_to
 * (Snell: sin θ_to = ratio · sin θ_from). 0 under total internal
 * reflection. */
static int refract_to(const double d[3], const double n[3], double ratio, double t[3])
{
    const double c = sss_dot3(d, n), s2 = ratio * ratio * fmax(0.0, 1.0 - c * c);
    if (s2 >= 1.0) return 0;
    const double ct = sqrt(1.0 - s2);
    for (int k = 0; k < 3; k++) t[k] = ratio * d[k] + (ct - ratio * c) * n[k];
    sss_normalize3(t);
    return 1;
}

/* A direction about u whose angle follows Henyey–Greenstein exactly
 * (inverting its cumulative distribution). */
static void hg_sample(double g, const double u[3], uint64_t *rng, double out[3])
{
    const double xi = sss_rng_unit(rng), phi = 2.0 * SSS_PI * sss_rng_unit(rng);
    double ct;
    if (fabs(g) < 1e-3) {
        ct = 1.0 - 2.0 * xi;
    } else {
        const double sq = (1.0 - g * g) / (1.0 - g + 2.0 * g * xi);
        ct = (1.0 + g * g - sq * sq) / (2.0 * g);
    }
    ct = fmax(-1.0, fmin(1.0, ct));
    const double st = sqrt(fmax(0.0, 1.0 - ct * ct));
    double a[3], b[3];
    frame(u, a, b);
    for (int k = 0; k < 3; k++) out[k] = ct * u[k] + st * (cos(phi) * a[k] + sin(phi) * b[k]);
    sss_normalize3(out);
}

/* ---- free flights and throughput ---- */

/* A path's throughput across colour channels. Every flight samples its
 * distance from the hero channel's e^{−σt s}, the hero drawn once per path;
 * channel c's estimate weighs its own throughput f_c (the path's
 * contribution in c) by the balance heuristic over the C channels as hero,
 *     f_c / ((1/C) Σ_h p_h),
 * p_h the density of the path's flights had h been the hero (one-sample
 * multiple importance sampling over the hero choice; "hero wavelength"
 * spectral sampling, Wilkie et al. 2014). The weight is at most C times the
 * product of c's albedos, however long the walk, whereas a channel chosen
 * per flight leaves products of per-flight density ratios whose variance
 * grows with the walk's length. Directions, Fresnel choices and roulette do
 * not depend on the channel and cancel. f and p are kept scaled by the
 * largest p (the ratio is what counts). */
typedef struct ref_tp {
    double f[3], p[3];
    uint32_t hero, C;
} ref_tp;

static void tp_init(ref_tp *t, const ref_medium *m, double f0, uint64_t *rng)
{
    t->C = m->C;
    t->hero = 0;
    if (m->C > 1) {
        t->hero = (uint32_t)(sss_rng_unit(rng) * m->C);
        if (t->hero >= m->C) t->hero = m->C - 1;
    }
    for (int c = 0; c < 3; c++) {
        t->f[c] = f0;
        t->p[c] = 1.0;
    }
}

/* The weights of every channel: f_c / mean p. */
static void tp_weights(const ref_tp *t, double w[3])
{
    double mp = 0.0;
    for (uint32_t c = 0; c < t->C; c++) mp += t->p[c];
    mp /= t->C;
    for (uint32_t c = 0; c < t->C; c++) w[c] = mp > 0.0 ? t->f[c] / mp : 0.0;
}

static void tp_scale(ref_tp *t, double k)
{
    for (uint32_t c = 0; c < t->C; c++) t->f[c] *= k;
}

/* One flight of at most tb (the boundary): 1 and the distance in *s for a
 * collision before tb (f_c × σs e^{−σt s}, p_h × σt e^{−σt s}), 0 for the
 * boundary (both × e^{−σt tb}). */
static int flight_tracked(const ref_medium *m, const double x[3], const double u[3], double tb, uint64_t *rng,
                          ref_tp *t, double *s);

static int flight(const ref_medium *m, const double x[3], const double u[3], double tb, uint64_t *rng, ref_tp *t,
                  double *s)
{
    if (m->het) return flight_tracked(m, x, u, tb, rng, t, s);
    const double d = -log1p(-sss_rng_unit(rng)) / m->sigma_t[t->hero];
    const int hit = d < tb;
    double mx = 0.0;
    for (uint32_t c = 0; c < m->C; c++) {
        const double e = exp(-m->sigma_t[c] * (hit ? d : tb));
        t->f[c] *= hit ? m->sigma_s[c] * e : e;
        t->p[c] *= hit ? m->sigma_t[c] * e : e;
        mx = fmax(mx, t->p[c]);
    }
    if (mx > 0.0)
        for (uint32_t c = 0; c < m->C; c++) {
            t->f[c] /= mx;
            t->p[c] /= mx;
        }
    *s = d;
    return hit;
}

/* A flight through a material field (docs/reference.md §3.1): spectral
 * tracking (Kutz et al. 2017) against the one majorant σ̄ of every channel.
 * Tentative collisions at rate σ̄; at each, with σn = σ̄ − σt(x) ≥ 0 per
 * channel, the collision is real with probability P_s = S / (S + N), S =
 * Σ_c f_c σs_c and N = Σ_c f_c σn_c (the weights so far: channels that
 * still carry the path decide), and then f_c ×= σs_c / (σ̄ P_s); else null
 * and f_c ×= σn_c / (σ̄ P_n). Each channel's expected factor per tentative
 * collision is (σs + σn)/σ̄ = 1 − σa/σ̄: the absorption is weighted out, not
 * sampled, so the estimate is unbiased whatever the field. The hero's
 * densities p stay 1 (one distance law for all channels). */
static int flight_tracked(const ref_medium *m, const double x[3], const double u[3], double tb, uint64_t *rng,
                          ref_tp *t, double *s)
{
    double d = 0.0;
    for (;;) {
        d += -log1p(-sss_rng_unit(rng)) / m->sigma_bar;
        if (!(d < tb)) {
            *s = d;
            return 0;
        }
        const double y[3] = {x[0] + d * u[0], x[1] + d * u[1], x[2] + d * u[2]};
        double sa[3], ss[3], sn[3], S = 0.0, N = 0.0;
        medium_at(m, y, sa, ss);
        for (uint32_t c = 0; c < m->C; c++) {
            sn[c] = fmax(0.0, m->sigma_bar - sa[c] - ss[c]);
            S += t->f[c] * ss[c];
            N += t->f[c] * sn[c];
        }
        if (!(S + N > 0.0)) { /* every channel absorbed: the weights are 0 */
            for (uint32_t c = 0; c < m->C; c++) t->f[c] = 0.0;
            *s = d;
            return 1;
        }
        const double Ps = S / (S + N);
        if (sss_rng_unit(rng) < Ps) {
            for (uint32_t c = 0; c < m->C; c++) t->f[c] *= ss[c] / (m->sigma_bar * Ps);
            *s = d;
            return 1;
        }
        for (uint32_t c = 0; c < m->C; c++) t->f[c] *= sn[c] / (m->sigma_bar * (1.0 - Ps));
    }
}

/* The transmittance from x along u over a distance t, per channel: e^{−σt t}
 * in a homogeneous medium; in a field, ratio tracking (Novák et al. 2014):
 * the product of σn(x_i)/σ̄ over tentative collisions at rate σ̄, an
 * unbiased estimate of e^{−∫σt} in each channel. */
static void transmittance(const ref_medium *m, const double x[3], const double u[3], double t, uint64_t *rng,
                          double T[3])
{
    if (!m->het) {
        for (uint32_t c = 0; c < m->C; c++) T[c] = exp(-m->sigma_t[c] * t);
        return;
    }
    for (uint32_t c = 0; c < m->C; c++) T[c] = 1.0;
    for (double d = -log1p(-sss_rng_unit(rng)) / m->sigma_bar; d < t; d += -log1p(-sss_rng_unit(rng)) / m->sigma_bar) {
        const double y[3] = {x[0] + d * u[0], x[1] + d * u[1], x[2] + d * u[2]};
        double sa[3], ss[3], mx = 0.0;
        medium_at(m, y, sa, ss);
        for (uint32_t c = 0; c < m->C; c++) {
            T[c] *= fmax(0.0, m->sigma_bar - sa[c] - ss[c]) / m->sigma_bar;
            mx = fmax(mx, T[c]);
        }
        if (!(mx > 0.0)) return;
    }
}

/* Russian roulette once a path's largest weight falls below a tenth of
 * where it started: survive with probability max w / (0.1 w₀) and carry the
 * weights divided by it (unbiased; the weights are the same whichever
 * channel was the hero, so the roulette does not bias the mixture). Returns
 * 0 when the path ends. */
static int roulette(ref_tp *t, double w0, uint64_t *rng)
{
    double w[3], mw = 0.0;
    tp_weights(t, w);
    for (uint32_t c = 0; c < t->C; c++) mw = fmax(mw, w[c]);
    if (!(mw > 0.0)) return 0;
    const double th = 0.1 * w0;
    if (mw >= th) return 1;
    const double q = mw / th;
    if (sss_rng_unit(rng) >= q) return 0;
    tp_scale(t, 1.0 / q);
    return 1;
}

/* ---- the boundary ---- */

/* The normal a boundary event uses: the shading normal, unless the
 * direction d meets it from the wrong side (a shading normal tilted past
 * the path), where the geometric one is used (both unit, facing out).
 * Returns |d·n|. */
static double event_normal(const ref_hit *h, const double d[3], int leaving, double n[3])
{
    double c = sss_dot3(d, h->ns);
    if (leaving ? c > 0.0 : c < 0.0) {
        memcpy(n, h->ns, sizeof(double) * 3);
    } else {
        memcpy(n, h->ng, sizeof(double) * 3);
        c = sss_dot3(d, h->ng);
    }
    return fabs(c);
}

/* Reflects d at n, keeping it on the side it came from relative to the
 * geometric surface (about ng when the shading normal would send it
 * through). */
static void reflect_keep(const double d[3], const double n[3], const double ng[3], int inside, double r[3])
{
    reflect(d, n, r);
    const double s = sss_dot3(r, ng);
    if (inside ? s >= 0.0 : s <= 0.0) reflect(d, ng, r);
}

/* Passes the ray o + t·d, t > tnear, through every surface it meets from
 * the wrong side, up to 64: a surface seen from outside (want_out 1: a
 * walk inside wants the wall it leaves through) or from inside (want_out
 * 0: a ray in air wants a surface it enters). Those are the surfaces of a
 * mesh that is not one closed, consistently oriented surface: overlapping
 * closed parts, sheets inside the body, flipped triangles (the decimated
 * Stanford dragons have all three, docs/robustness.md); the medium is
 * taken to be continuous across them, and each one passed farther than a
 * few eps from the origin is counted (k->crossed). 1 with the first hit
 * from the right side in h, 0 when the ray leaves the scene first. */
int ref_hit_facing(const sss_ref_scene *s, const double o[3], const double d[3], double tnear, int want_out,
                   ref_hit *h, ref_counters *k)
{
    for (int i = 0; i < 64; i++) {
        k->rays++;
        if (!ref_intersect(s, o, d, tnear, h)) return 0;
        const double c = sss_dot3(h->ng, d);
        if (want_out ? c > 0.0 : c < 0.0) return 1;
        if (h->t > 4.0 * s->eps) k->crossed++;
        tnear = h->t + s->eps;
    }
    return 0;
}

/* The wall ahead of a point inside: the closest hit seen from inside
 * (ng·u > 0), passing surfaces seen from outside (ref_hit_facing; among them,
 * within a few eps, the wall a collision lies on when its float ray origin
 * was rounded to the outside). A ray from such a point heading out misses
 * that wall: it is then traced again from 4 eps behind, its distance
 * corrected. 0: no wall seen from inside (the path leaks out of the mesh). */
static int inside_hit(const sss_ref_scene *s, const double x[3], const double u[3], double tnear, ref_hit *h,
                      ref_counters *k)
{
    if (ref_hit_facing(s, x, u, tnear, 1, h, k)) return 1;
    const double back = 4.0 * s->eps;
    double xb[3];
    for (int q = 0; q < 3; q++) xb[q] = x[q] - back * u[q];
    if (!ref_hit_facing(s, xb, u, 0.0, 1, h, k)) return 0;
    h->t = fmax(0.0, h->t - back);
    return 1;
}

/* The origin of the ray leaving surface point h along d: h's point moved
 * eps along the geometric normal to the side d goes to, so that no float
 * rounding of the origin puts it on the other side (where the ray would
 * cross the surface it leaves, or miss the wall ahead). */
static void leave_surface(const sss_ref_scene *s, const ref_hit *h, const double d[3], double x[3])
{
    const double e = sss_dot3(d, h->ng) >= 0.0 ? s->eps : -s->eps;
    for (int q = 0; q < 3; q++) x[q] = h->p[q] + e * h->ng[q];
}

/* Radiance of the environment arriving along −d (d leaving the scene). */
static double env_radiance(const ref_ctx *c, const double d[3], int ch)
{
    const sss_probe *p = c->probe;
    if (!p) return 1.0;
    /* sss/probe.h: θ from +z, φ from +x towards +y, row 0 at θ = 0 */
    const double th = acos(fmax(-1.0, fmin(1.0, d[2])));
    double ph = atan2(d[1], d[0]);
    if (ph < 0) ph += 2.0 * SSS_PI;
    uint32_t x = (uint32_t)(ph / (2.0 * SSS_PI) * p->w), y = (uint32_t)(th / SSS_PI * p->h);
    if (x >= p->w) x = p->w - 1;
    if (y >= p->h) y = p->h - 1;
    return p->rgb[3 * ((size_t)y * p->w + x) + (size_t)ch];
}

/* ---- next-event estimation through the boundary (docs/reference.md §3) ---- */

/* Where the ray from z (inside) along v meets the plane of triangle f,
 * and the direction it leaves in after refraction about the shading normal
 * there, into w. 0 under total internal reflection or from the wrong side. */
static int leave_dir(const sss_ref_scene *s, uint32_t f, const double z[3], const double v[3], double eta,
                     double w[3])
{
    const double t = ref_plane_t(s, f, z, v);
    if (!(t > 0.0)) return 0;
    double p[3], n[3];
    for (int k = 0; k < 3; k++) p[k] = z[k] + t * v[k];
    if (!ref_shading_normal_at(s, f, p, n) || !(sss_dot3(v, n) > 0.0)) return 0;
    return refract_to(v, n, eta, w);
}

/* The derivative of the map v ↦ direction leaving the surface (leave_dir)
 * for the plane of triangle f with its interpolated normals, by central
 * differences (step 1e-4 rad: truncation ~1e-8, rounding ~1e-12) along the
 * pair a, b perpendicular to v: w0 the direction at v, wa and wb its
 * derivatives along a and b. 0 where the map is not defined nearby. */
static int leave_derivative(const sss_ref_scene *s, uint32_t f, const double z[3], const double v[3], double eta,
                            double a[3], double b[3], double w0[3], double wa[3], double wb[3])
{
    const double h = 1e-4;
    double w[4][3];
    frame(v, a, b);
    if (!leave_dir(s, f, z, v, eta, w0)) return 0;
    for (int i = 0; i < 4; i++) {
        const double *e = i < 2 ? a : b;
        const double sg = (i & 1) ? -h : h;
        double vv[3];
        for (int k = 0; k < 3; k++) vv[k] = v[k] + sg * e[k];
        sss_normalize3(vv);
        if (!leave_dir(s, f, z, vv, eta, w[i])) return 0;
    }
    for (int k = 0; k < 3; k++) {
        wa[k] = (w[0][k] - w[1][k]) / (2.0 * h);
        wb[k] = (w[2][k] - w[3][k]) / (2.0 * h);
    }
    return 1;
}

/* The direction from surface point y towards the light (unit), and, for
 * a point light, the distance to it (mm; 0 for a directional light). */
static double towards_light(const ref_ctx *c, const double y[3], double w[3])
{
    if (c->light != SSS_REF_POINT) {
        memcpy(w, c->wl, 3 * sizeof *w);
        return 0.0;
    }
    sss_sub3(w, c->P, y);
    return sss_normalize3(w);
}

/* For a point light: where the ray from z along v meets the plane of
 * triangle f, and the light's direction from there, into wp. 0 where the
 * ray does not meet the plane ahead. */
static int light_dir_on_plane(const ref_ctx *c, uint32_t f, const double z[3], const double v[3], double wp[3])
{
    const double t = ref_plane_t(c->s, f, z, v);
    if (!(t > 0.0)) return 0;
    double y[3];
    for (int k = 0; k < 3; k++) y[k] = z[k] + t * v[k];
    return towards_light(c, y, wp) > 0.0;
}

/* Light of the directional or point source scattered at z towards −u (u:
 * the direction the backward path arrived in), added to L with the path's
 * weights. The light reaches z unscattered only along its own refracted
 * ray: the ray direction v at z whose exit direction ω′(v) (refraction
 * about the shading normal where the ray meets the surface, at y) is the
 * light's direction ω_l(y) there (constant for a directional light,
 * towards P for a point light). It is solved by Newton's method on the two
 * angles of v for the residual e(v) = ω′(v) − ω_l(y(v)), from the straight
 * ray towards the light, with the derivative of e by central differences
 * on the triangle's plane and one ray per step to find the triangle (one
 * step on a flat surface with a directional light; two or three where the
 * interpolated normals curve or the light is near). A directional light's
 * radiance arriving along v is η² F_t E δ(ω′ − ω_l), which a direction at
 * z picks with density 1/|dω′/dω|, the determinant of that derivative; a
 * point light is a radiance I δ²(x⊥ − P) over the plane through P across
 * the ray, and the ray from y along ω′ passes P at the offset
 * x⊥ − P ≈ −r e⊥ (r = |P − y|), so its density is 1/(r² |de/dω|)
 * (docs/reference.md §3). */
static void nee_light(const ref_ctx *c, const double z[3], const double u[3], const ref_tp *tp, uint64_t *rng,
                      double L[3], ref_counters *k)
{
    const sss_ref_scene *s = c->s;
    const ref_medium *m = &c->m;
    const double eta = m->eta;
    const int point = c->light == SSS_REF_POINT;
    double v[3], a[3], b[3], w0[3], wa[3], wb[3], wl[3];
    if (point) {
        sss_sub3(v, c->P, z);
        if (!(sss_normalize3(v) > 0.0)) return;
    } else {
        memcpy(v, c->wl, sizeof v);
    }
    ref_hit h;
    int ok = 0;
    double scale = 1.0;
    k->nee++;
    for (int it = 0; it < 12; it++) {
        if (!inside_hit(s, z, v, 0.0, &h, k)) return;
        if (!(towards_light(c, h.p, wl) >= 0.0) || !(sss_dot3(h.ns, wl) > 0.0))
            return; /* the light is behind the shading normal */
        if (it == 0 && !c->no_nee_roulette) {
            /* where it pays: the light's path to z is at least about the
             * depth under the surface the straight ray meets, t0 cos θ_l
             * (exactly so under a flat surface, where cos θ_t ≤ 1), so a
             * transmittance below 1e-3 there makes the estimate negligible
             * next to one near the surface; it is then made with
             * probability T/1e-3 (at least 1 %) and weighted by its inverse
             * (unbiased), saving the rays of deep collisions */
            double smin = m->sigma_t[0];
            for (uint32_t ch = 1; ch < m->C; ch++) smin = fmin(smin, m->sigma_t[ch]);
            const double T = exp(-smin * h.t * fmax(0.1, sss_dot3(h.ns, wl)));
            if (T < 1e-3) {
                const double p = fmax(0.01, T / 1e-3);
                if (sss_rng_unit(rng) >= p) {
                    k->nee_skipped++;
                    return;
                }
                scale = 1.0 / p;
            }
        }
        if (it == 0 || !leave_derivative(s, h.tri, z, v, eta, a, b, w0, wa, wb)) {
            /* a fixed-point step: the light's refraction about the normal
             * met (from the straight ray towards the light, which may itself
             * be totally reflected, and wherever a ray would be) */
            double d[3], nin[3] = {-h.ns[0], -h.ns[1], -h.ns[2]}, wl_in[3] = {-wl[0], -wl[1], -wl[2]};
            if (!refract_to(wl_in, nin, 1.0 / eta, d)) return;
            for (int q = 0; q < 3; q++) v[q] = -d[q];
            continue;
        }
        if (point) { /* e's derivative: ω′'s less ω_l's, by the same central differences */
            const double hd = 1e-4;
            double lp[4][3];
            for (int i = 0; i < 4; i++) {
                const double *e = i < 2 ? a : b;
                const double sg = (i & 1) ? -hd : hd;
                double vv[3];
                for (int q = 0; q < 3; q++) vv[q] = v[q] + sg * e[q];
                sss_normalize3(vv);
                if (!light_dir_on_plane(c, h.tri, z, vv, lp[i])) return;
            }
            if (!light_dir_on_plane(c, h.tri, z, v, wl)) return;
            for (int q = 0; q < 3; q++) {
                wa[q] -= (lp[0][q] - lp[1][q]) / (2.0 * hd);
                wb[q] -= (lp[2][q] - lp[3][q]) / (2.0 * hd);
            }
        }
        double e[3];
        sss_sub3(e, w0, wl);
        if (sss_dot3(e, e) < 1e-12) { /* v leaves along ω_l to 1e-6 rad */
            ok = 1;
            break;
        }
        /* the step (α, β) along (a, b) that cancels e to first order, least
         * squares in 3-D; at most 0.3 rad */
        const double A = sss_dot3(wa, wa), B = sss_dot3(wa, wb), C = sss_dot3(wb, wb);
        const double ea = sss_dot3(wa, e), eb = sss_dot3(wb, e), det = A * C - B * B;
        if (!(fabs(det) > 1e-300)) break;
        double al = -(C * ea - B * eb) / det, be = -(A * eb - B * ea) / det;
        const double len = sqrt(al * al + be * be);
        if (len > 0.3) al *= 0.3 / len, be *= 0.3 / len;
        for (int q = 0; q < 3; q++) v[q] += al * a[q] + be * b[q];
        sss_normalize3(v);
    }
    if (!ok) {
        k->nee_unsolved++;
        return;
    }
    const double r = towards_light(c, h.p, wl); /* the hit point's own: the shadow ray's */
    if (!(sss_dot3(h.ng, wl) > 0.0)) return; /* the light is behind the triangle itself */
    k->rays++;
    double yo[3];
    leave_surface(s, &h, wl, yo);
    if (point ? ref_occluded_upto(s, yo, wl, 0.0, r) : ref_occluded(s, yo, wl, 0.0)) return;
    double cr[3];
    sss_cross3(wa, wb, cr);
    const double J = fabs(sss_dot3(cr, w0)) * (point ? r * r : 1.0); /* |dω′/dω|, or r² |de/dω| */
    if (!(J > 0.0) || !isfinite(J)) return;
    const double E = point ? c->I : 1.0;
    const double w = scale * E * sss_phase_hg(m->g, sss_dot3(v, u)) * eta * eta * sss_ft(eta, sss_dot3(h.ns, wl)) / J;
    double beta[3];
    tp_weights(tp, beta);
    double T[3];
    transmittance(m, z, v, h.t, rng, T);
    for (uint32_t ch = 0; ch < m->C; ch++) L[ch] += beta[ch] * w * T[ch];
    k->nee_hits++;
}

/* ---- the radiance estimator ---- */

void ref_radiance_path(const ref_ctx *c, const ref_hit *h0, const double wo[3], uint64_t *rng, double L[3],
                       ref_counters *k)
{
    const sss_ref_scene *s = c->s;
    const ref_medium *m = &c->m;
    const double eta = m->eta;
    L[0] = L[1] = L[2] = 0.0;
    const double cos_o = sss_dot3(h0->ns, wo);
    if (!(cos_o > 0.0) || !(sss_dot3(h0->ng, wo) > 0.0)) return;
    /* the view ray, reversed, refracts in: F_t by the radiance law / η² */
    double u[3], x[3];
    const double back[3] = {-wo[0], -wo[1], -wo[2]}, nin[3] = {-h0->ns[0], -h0->ns[1], -h0->ns[2]};
    if (!refract_to(back, nin, 1.0 / eta, u)) return;
    if (!(sss_dot3(u, h0->ng) < 0.0)) { /* the shading normal sent it along the surface: the geometric one */
        const double ngn[3] = {-h0->ng[0], -h0->ng[1], -h0->ng[2]};
        if (!refract_to(back, ngn, 1.0 / eta, u) || !(sss_dot3(u, h0->ng) < 0.0)) return;
    }
    const double beta0 = sss_ft(eta, cos_o) / (eta * eta);
    ref_tp tp;
    tp_init(&tp, m, beta0, rng);
    leave_surface(s, h0, u, x);
    double tnear = 0.0;
    int inside = 1;
    uint32_t order = 0;
    for (uint32_t ev = 0; ev < SSS_REF_MAX_EVENTS; ev++) {
        ref_hit h;
        if (inside) {
            if (!inside_hit(s, x, u, tnear, &h, k)) { /* inside, yet no wall ahead seen from inside */
                k->leaks++;
                goto done;
            }
            double d;
            if (flight(m, x, u, h.t, rng, &tp, &d)) {
                for (int q = 0; q < 3; q++) x[q] += d * u[q];
                tnear = 0.0;
                order++;
                k->scatterings++;
                if (!c->no_nee && c->light != SSS_REF_ENVIRONMENT) nee_light(c, x, u, &tp, rng, L, k);
                if (c->max_order && order >= c->max_order) goto done;
                if (!roulette(&tp, beta0, rng)) goto done;
                double un[3];
                hg_sample(m->g, u, rng, un);
                memcpy(u, un, sizeof u);
                continue;
            }
            /* the boundary from inside: reflect with F_r, else leave (× η²) */
            double n[3], un[3];
            const double ci = event_normal(&h, u, 1, n);
            const double ft = sss_ft(1.0 / eta, ci);
            if (sss_rng_unit(rng) >= ft || !refract_to(u, n, eta, un)) {
                reflect_keep(u, n, h.ng, 1, un);
            } else {
                if (!(sss_dot3(un, h.ng) > 0.0) && !refract_to(u, h.ng, eta, un)) reflect(u, h.ng, un);
                if (sss_dot3(un, h.ng) > 0.0) {
                    inside = 0;
                    tp_scale(&tp, eta * eta);
                }
            }
            memcpy(u, un, sizeof u);
            leave_surface(s, &h, u, x);
            tnear = 0.0;
        } else {
            if (!ref_hit_facing(s, x, u, tnear, 0, &h, k)) { /* escaped: the environment's radiance */
                if (c->light == SSS_REF_ENVIRONMENT) {
                    double beta[3];
                    tp_weights(&tp, beta);
                    for (uint32_t ch = 0; ch < m->C; ch++) L[ch] += beta[ch] * env_radiance(c, u, m->C == 1 ? 0 : (int)ch);
                }
                goto done;
            }
            /* another part of the mesh: reflect with F_r, else enter (× 1/η²) */
            double n[3], un[3], nn[3];
            const double co = event_normal(&h, u, 0, n);
            for (int q = 0; q < 3; q++) nn[q] = -n[q];
            const double ft = sss_ft(eta, co);
            if (sss_rng_unit(rng) >= ft || !refract_to(u, nn, 1.0 / eta, un)) {
                reflect_keep(u, n, h.ng, 0, un);
            } else {
                if (!(sss_dot3(un, h.ng) < 0.0)) {
                    const double ngn[3] = {-h.ng[0], -h.ng[1], -h.ng[2]};
                    if (!refract_to(u, ngn, 1.0 / eta, un)) reflect(u, h.ng, un);
                }
                if (sss_dot3(un, h.ng) < 0.0) {
                    inside = 1;
                    tp_scale(&tp, 1.0 / (eta * eta));
                }
            }
            memcpy(u, un, sizeof u);
            leave_surface(s, &h, u, x);
            tnear = 0.0;
        }
    }
    k->truncated++;
done:
    if (m->C == 1) L[1] = L[2] = L[0];
}

/* ---- the particle tracer ---- */

void ref_particle_path(const ref_ctx *c, const double bcentre_mm[3], double bradius_mm, uint64_t *rng,
                       sss_ref_tally *t, ref_counters *k)
{
    const sss_ref_scene *s = c->s;
    const ref_medium *m = &c->m;
    const double eta = m->eta;
    memset(t, 0, sizeof *t);
    /* a point of the beam's disk, started outside the scene's bounding sphere */
    double a[3], bb[3], o[3], u[3];
    frame(c->wl, a, bb);
    const double r = bradius_mm * sqrt(sss_rng_unit(rng)), phi = 2.0 * SSS_PI * sss_rng_unit(rng);
    double off[3];
    sss_sub3(off, bcentre_mm, s->centre);
    const double back = sqrt(sss_dot3(off, off)) + 2.0 * s->radius + 1.0;
    for (int q = 0; q < 3; q++) {
        o[q] = bcentre_mm[q] + r * (cos(phi) * a[q] + sin(phi) * bb[q]) + back * c->wl[q];
        u[q] = -c->wl[q];
    }
    ref_hit h;
    if (!ref_hit_facing(s, o, u, 0.0, 0, &h, k)) return;
    t->incident = 1.0;
    ref_tp tp;
    tp_init(&tp, m, 1.0, rng);
    double beta[3];
    /* the first surface: reflect (specular) or enter; power crosses as it is */
    double n[3], nn[3], un[3];
    const double co = event_normal(&h, u, 0, n);
    for (int q = 0; q < 3; q++) nn[q] = -n[q];
    if (sss_rng_unit(rng) >= sss_ft(eta, co) || !refract_to(u, nn, 1.0 / eta, un) || !(sss_dot3(un, h.ng) < 0.0)) {
        for (int q = 0; q < 3; q++) t->specular[q] = 1.0;
        return;
    }
    double x[3];
    memcpy(u, un, sizeof u);
    leave_surface(s, &h, u, x);
    for (uint32_t ev = 0; ev < SSS_REF_MAX_EVENTS; ev++) {
        tp_weights(&tp, beta);
        if (!inside_hit(s, x, u, 0.0, &h, k)) {
            for (uint32_t ch = 0; ch < m->C; ch++) t->lost[ch] += beta[ch];
            k->leaks++;
            goto done;
        }
        /* expected first-collision absorption along the flight, whatever is
         * sampled next: its own estimator, independent of the exits */
        for (uint32_t ch = 0; ch < m->C; ch++)
            t->absorbed[ch] += beta[ch] * m->sigma_a[ch] / m->sigma_t[ch] * -expm1(-m->sigma_t[ch] * h.t);
        double d;
        if (flight(m, x, u, h.t, rng, &tp, &d)) { /* homogeneous: sss_ref_particles refuses a field */
            for (int q = 0; q < 3; q++) x[q] += d * u[q];
            k->scatterings++;
            if (!roulette(&tp, 1.0, rng)) goto done;
            hg_sample(m->g, u, rng, un);
            memcpy(u, un, sizeof u);
            continue;
        }
        const double ci = event_normal(&h, u, 1, n);
        if (sss_rng_unit(rng) >= sss_ft(1.0 / eta, ci) || !refract_to(u, n, eta, un)) {
            reflect_keep(u, n, h.ng, 1, un);
            memcpy(u, un, sizeof u);
            leave_surface(s, &h, u, x);
            continue;
        }
        /* leaves: through a face the beam lights, or another */
        tp_weights(&tp, beta);
        double *bin = sss_dot3(h.ng, c->wl) > 0.0 ? t->front : t->back;
        for (uint32_t ch = 0; ch < m->C; ch++) bin[ch] += beta[ch];
        goto done;
    }
    tp_weights(&tp, beta);
    for (uint32_t ch = 0; ch < m->C; ch++) t->lost[ch] += beta[ch];
    k->truncated++;
done:
    if (m->C == 1)
        for (int q = 1; q < 3; q++) {
            t->specular[q] = t->specular[0];
            t->absorbed[q] = t->absorbed[0];
            t->front[q] = t->front[0];
            t->back[q] = t->back[0];
            t->lost[q] = t->lost[0];
        }
}
