/* single_mesh.c: single scattering at a mesh vertex (sss/single_mesh.h):
 * Jensen et al. 2001's S⁽¹⁾ marched along the refracted view ray as seed
 * 002 (Algorithm 1) does, with the light's entry point K found by casting
 * a ray through the mesh instead of the paper's fitted planes (Eqs. 7–10),
 * and the per-segment closed form of sss/single.h by default.
 * docs/layers.md §5 lists the choices.
 */
#include "sss/single_mesh.h"
#include "sss/single.h"
#include "sss/vec3.h"

#include <math.h>
#include <string.h>

typedef struct march_ctx {
    const sss_bvh *bvh;
    double x[3];        /* the vertex, mesh units */
    double dir_i[3];    /* the light's propagation inside */
    double dir_o[3];    /* the view ray inside */
    double light[3];    /* towards the light, outside */
    double mu_i, mu_o;  /* their cosines with the vertex normal */
    double n[3];        /* the vertex normal */
    double mm_per_unit;
    float delta;        /* the bake's ray offset (sss_mesh_ray_offset), mesh units */
    const sss_layer_stack *stack;
    const sss_mesh *mesh;
    int refine;         /* refract the light at its entry point K, not at the vertex */
    int planes;         /* seed 002's fitted planes instead of the cast (Eqs. 9, 10) */
    int focus;          /* weigh the entry by the focusing of the refracted beam */
    double fit_n[3], fit_p[3]; /* the vertex's least-squares plane (Eqs. 7, 8): unit normal, point (mesh units) */
    double s_max;       /* the march's end, mm (Eq. 9's |M M_max|) */
    double eta, entry_v, cos_phase_v; /* the vertex's entry factor F_t cos θ_i / μ_i and phase cosine */
} march_ctx;

/* Seed 002's per-vertex plane (Eqs. 7, 8): the least-squares plane of the
 * vertices within radius r (mesh units) of the point x (normal nx): through their
 * centroid, normal along the smallest eigenvector of their scatter matrix
 * (Jacobi rotations), turned to the vertex normal's side. Fewer than three
 * neighbours: the tangent plane. */
static void fit_plane(const sss_mesh *m, const double x[3], const double nx[3], double r, double n[3], double p[3])
{
    double S[3][3] = {{0}}, c[3] = {0, 0, 0};
    uint32_t cnt = 0;
    for (int pass = 0; pass < 2; pass++) {
        for (uint32_t i = 0; i < m->nv; i++) {
            const float *y = &m->pos[3 * (size_t)i];
            const double d[3] = {y[0] - x[0], y[1] - x[1], y[2] - x[2]};
            if (sss_dot3(d, d) > r * r) continue;
            if (pass == 0) {
                for (int a = 0; a < 3; a++) c[a] += y[a];
                cnt++;
            } else {
                const double e[3] = {y[0] - c[0], y[1] - c[1], y[2] - c[2]};
                for (int a = 0; a < 3; a++)
                    for (int b = 0; b < 3; b++) S[a][b] += e[a] * e[b];
            }
        }
        if (pass == 0 && cnt)
            for (int a = 0; a < 3; a++) c[a] /= cnt;
    }
    for (int a = 0; a < 3; a++) n[a] = nx[a], p[a] = x[a];
    if (cnt < 3) return;
    double V[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 50; sweep++) {
        double off = fabs(S[0][1]) + fabs(S[0][2]) + fabs(S[1][2]);
        if (off < 1e-30) break;
        for (int a = 0; a < 2; a++)
            for (int b = a + 1; b < 3; b++) {
                if (fabs(S[a][b]) < 1e-300) continue;
                const double th = 0.5 * atan2(2.0 * S[a][b], S[b][b] - S[a][a]);
                const double cs = cos(th), sn = sin(th);
                for (int k = 0; k < 3; k++) { /* S ← Jᵀ S J, V ← V J */
                    const double ska = S[k][a], skb = S[k][b];
                    S[k][a] = cs * ska - sn * skb;
                    S[k][b] = sn * ska + cs * skb;
                }
                for (int k = 0; k < 3; k++) {
                    const double sak = S[a][k], sbk = S[b][k];
                    S[a][k] = cs * sak - sn * sbk;
                    S[b][k] = sn * sak + cs * sbk;
                }
                for (int k = 0; k < 3; k++) {
                    const double vka = V[k][a], vkb = V[k][b];
                    V[k][a] = cs * vka - sn * vkb;
                    V[k][b] = sn * vka + cs * vkb;
                }
            }
    }
    int lo = 0;
    for (int a = 1; a < 3; a++)
        if (S[a][a] < S[lo][lo]) lo = a;
    double f[3] = {V[0][lo], V[1][lo], V[2][lo]};
    if (sss_dot3(f, n) < 0.0)
        for (int a = 0; a < 3; a++) f[a] = -f[a];
    sss_normalize3(f);
    for (int a = 0; a < 3; a++) n[a] = f[a], p[a] = c[a];
}

/* The light refracted into the medium at surface point p of triangle t
 * (its interpolated normal), and the cosines of the light outside (*c) and
 * of the refracted direction (*ct) with that normal (NULL: not wanted); 0
 * when p faces away from the light. */
static int refract_at(const march_ctx *k, uint32_t t, const double p[3], double d[3], double *c, double *ct)
{
    double nK[3];
    sss_mesh_normal_at(k->mesh, t, p, nK);
    const double ci = sss_dot3(nK, k->light);
    if (!(ci > 0.0)) return 0;
    const double co = sss_ss_refract(nK, k->light, k->eta, d);
    if (c) *c = ci;
    if (ct) *ct = co;
    return 1;
}

/* How much a curved surface concentrates the refracted beam on its way from
 * K to M: the cross-section (normal to the ray) of a small bundle entering
 * around K over its cross-section at M, both of the rays refracted at
 * their own interpolated normals (K and two points δ away on K's tangent
 * plane). 1 on a flat surface, > 1 under a convex one (a lens of focal
 * length ηR/(η − 1) for a sphere of radius R); clamped to [0.01, 100],
 * which only caustics reach. */
static double focusing(const march_ctx *k, uint32_t prim, const float M[3], double t, const float back[3],
                       const double tK[3])
{
    double K0[3], nK[3], u[3], v[3], Kj[3][3], tj[3][3], P[3][3];
    for (int a = 0; a < 3; a++) K0[a] = M[a] + t * back[a];
    sss_mesh_normal_at(k->mesh, prim, K0, nK);
    /* a tangent basis at K */
    const double h[3] = {fabs(nK[0]) < 0.9 ? 1.0 : 0.0, fabs(nK[0]) < 0.9 ? 0.0 : 1.0, 0.0};
    sss_cross3(nK, h, u);
    sss_normalize3(u);
    sss_cross3(nK, u, v);
    const double delta = 1e-3 * t;
    for (int j = 0; j < 3; j++) {
        for (int a = 0; a < 3; a++) Kj[j][a] = K0[a] + (j == 1 ? delta * u[a] : j == 2 ? delta * v[a] : 0.0);
        if (!refract_at(k, prim, Kj[j], tj[j], NULL, NULL)) return 1.0;
        /* where it crosses the plane through M normal to tK */
        double mk[3];
        for (int a = 0; a < 3; a++) mk[a] = M[a] - Kj[j][a];
        const double lam = sss_dot3(mk, tK) / sss_dot3(tj[j], tK);
        for (int a = 0; a < 3; a++) P[j][a] = Kj[j][a] + lam * tj[j][a];
    }
    double e1[3], e2[3], cr[3], f1[3], f2[3], cf[3];
    sss_sub3(e1, P[1], P[0]);
    sss_sub3(e2, P[2], P[0]);
    sss_cross3(e1, e2, cr);
    sss_sub3(f1, Kj[1], Kj[0]);
    sss_sub3(f2, Kj[2], Kj[0]);
    sss_cross3(f1, f2, cf);
    const double at_M = sqrt(sss_dot3(cr, cr)), at_K = fabs(sss_dot3(cf, tK));
    if (!(at_M > 0.0) || !(at_K > 0.0)) return 1.0;
    return fmin(100.0, fmax(0.01, at_K / at_M));
}

/* The light's path to the point s mm along the view ray: back along the
 * light's inside direction to the surface (K), and whether K sees the
 * light. A ray that finds no surface beyond the ray offset (a point within
 * the offset of the surface, or a float leak at a grazing triangle) falls
 * back on the vertex's tangent plane, depth / μ_i. */
static void locate_mesh(void *user, uint32_t c, double s, sss_ss_point *out)
{
    const march_ctx *k = user;
    /* the layer by the depth below the vertex's tangent plane (seed 002
     * §2.1: depths along the normal) */
    out->layer = sss_layers_find(k->stack, s * k->mu_o);
    const double su = s / k->mm_per_unit;
    float M[3], back[3];
    for (int a = 0; a < 3; a++) {
        M[a] = (float)(k->x[a] + su * k->dir_o[a]);
        back[a] = (float)-k->dir_i[a];
    }
    if (k->planes) {
        /* Eq. 9: the plane for M blended from the tangent plane at P (the
         * vertex) and the fitted plane by α = |M M_max|, β = |M P|; Eq. 10:
         * the distance to it along the light. No shadow test: the paper has
         * none, and its K may lie off the surface. */
        const double beta = s, alpha = fmax(0.0, k->s_max - s), w = alpha + beta > 0.0 ? 1.0 / (alpha + beta) : 0.0;
        double nM[3], pM[3], pm[3];
        for (int a = 0; a < 3; a++) {
            nM[a] = w * (alpha * k->n[a] + beta * k->fit_n[a]);
            pM[a] = w * (alpha * k->x[a] + beta * k->fit_p[a]);
            pm[a] = M[a] - pM[a];
        }
        sss_normalize3(nM);
        const double cth = fabs(sss_dot3(nM, k->dir_i));
        const double km = cth > 1e-6 ? fabs(sss_dot3(pm, nM)) / cth * k->mm_per_unit : 1e30;
        out->tau_light = sss_layers_tau_path(k->stack, c, km, k->mu_i);
        return;
    }
    /* hits closer than the ray offset are the surface the point lies on
     * (where the view ray leaves, at s_max), not where the light enters */
    uint32_t prim = UINT32_MAX;
    double t = su > 0.0 ? (double)sss_bvh_nearest(k->bvh, M, back, k->delta, &prim) : 0.0;
    double weight = 1.0;    /* the entry at K against the vertex's (refine) */
    double mu_path = k->mu_i; /* the light path's cosine with the vertex normal (Eq. 12's cos θ) */
    if (!isfinite(t)) {
        t = su * k->mu_o / k->mu_i;
    } else if (k->refine && su > 0.0) {
        /* The light refracts where it enters, at K's own normal, not at the
         * vertex's: two fixed-point steps, each refracting the light at the
         * last K and casting back from M along the new direction. The
         * entry's F_t cos θ / μ′ and the phase angle are K's too; their ratio
         * to the vertex's weights the light (docs/layers.md §5). */
        double tK[3] = {0, 0, 0};
        int refracted = 0;
        for (int it = 0; it < 2; it++) {
            double Kd[3], cK, ct;
            for (int a = 0; a < 3; a++) Kd[a] = M[a] + t * back[a];
            if (!refract_at(k, prim, Kd, tK, &cK, &ct)) break; /* K faces away from the light: keep the last path */
            float bk[3] = {(float)-tK[0], (float)-tK[1], (float)-tK[2]};
            uint32_t p2 = UINT32_MAX;
            const double t2 = (double)sss_bvh_nearest(k->bvh, M, bk, k->delta, &p2);
            if (!isfinite(t2)) break;
            t = t2;
            prim = p2;
            memcpy(back, bk, sizeof bk);
            const double gl = k->stack->layer[out->layer < k->stack->n ? out->layer : 0].g;
            const double ph = sss_phase_eval(k->stack->phase, gl, -sss_dot3(tK, k->dir_o));
            const double ph_v = sss_phase_eval(k->stack->phase, gl, k->cos_phase_v);
            weight = sss_ft(k->eta, cK) * cK / ct / k->entry_v * (ph_v > 0.0 ? ph / ph_v : 1.0);
            mu_path = fmax(1e-6, -sss_dot3(tK, k->n));
            refracted = 1;
        }
        if (refracted && k->focus) weight *= focusing(k, prim, M, t, back, tK);
    }
    float K[3];
    const float L[3] = {(float)k->light[0], (float)k->light[1], (float)k->light[2]};
    for (int a = 0; a < 3; a++) K[a] = (float)(M[a] + t * back[a]);
    /* shaded K, or no light entering: a large optical depth, finite so that
     * the segment rule's differences stay numbers */
    if (!(weight > 0.0) || sss_bvh_occluded(k->bvh, K, L, k->delta)) {
        out->tau_light = 1e30;
        return;
    }
    out->tau_light = sss_layers_tau_path(k->stack, c, t * k->mm_per_unit, mu_path) - log(weight);
}

sss_result sss_ss_mesh_vertex(const sss_mesh *mesh, const sss_bvh *bvh, double mm_per_unit, const sss_material *m,
                              const sss_layer_stack *layers, uint32_t channels, uint32_t v, const double light[3],
                              const double view[3], const sss_ss_mesh_opts *opts, double *out, sss_error *err)
{
    if (v >= mesh->nv || !mesh->nrm)
        return sss_fail(err, SSS_ERR_ARG, "single scattering: vertex %u out of range [0, %u) or no normals", v,
                        mesh->nv);
    double n[3], x[3];
    for (int a = 0; a < 3; a++) {
        n[a] = mesh->nrm[3 * (size_t)v + a];
        x[a] = mesh->pos[3 * (size_t)v + a];
    }
    return sss_ss_mesh_point(mesh, bvh, mm_per_unit, m, layers, channels, x, n, light, view, opts, out, err);
}

sss_result sss_ss_mesh_point(const sss_mesh *mesh, const sss_bvh *bvh, double mm_per_unit, const sss_material *m,
                             const sss_layer_stack *layers, uint32_t channels, const double x[3], const double nrm[3],
                             const double light[3], const double view[3], const sss_ss_mesh_opts *opts,
                             double *out, sss_error *err)
{
    if (!mesh->nrm) return sss_fail(err, SSS_ERR_ARG, "single scattering: the mesh has no normals");
    if (!(mm_per_unit > 0.0) || !isfinite(mm_per_unit))
        return sss_fail(err, SSS_ERR_ARG, "single scattering: mm_per_unit %g must be > 0", mm_per_unit);
    sss_result r = sss_material_check(m, channels, SSS_ERR_ARG, err);
    if (r != SSS_OK) return r;
    const uint32_t N = opts && opts->samples ? opts->samples : 64;
    const double tau_max = opts && opts->tau_max > 0.0 ? opts->tau_max : 16.0;
    for (uint32_t c = 0; c < channels; c++) out[c] = 0.0;

    double n[3] = {nrm[0], nrm[1], nrm[2]};
    sss_normalize3(n);
    sss_ss_geom g;
    if (!sss_ss_geometry(n, light, view, m->eta, 1, &g)) return SSS_OK;

    /* the layers (if any) over the material, a half-space of HG phase */
    sss_layer_stack st;
    memset(&st, 0, sizeof st);
    st.phase = SSS_PHASE_HG;
    if (layers && layers->n) {
        if (layers->n > SSS_MAX_LAYERS)
            return sss_fail(err, SSS_ERR_ARG, "single scattering: %u layers, at most %d", layers->n, SSS_MAX_LAYERS);
        st = *layers;
    }
    sss_layer *base = &st.layer[st.n++];
    base->g = m->g;
    base->depth = INFINITY;
    for (uint32_t c = 0; c < channels; c++) {
        base->sigma_s[c] = sss_material_sigma_s(m, (int)c);
        base->sigma_t[c] = m->sigma_a[c] + base->sigma_s[c];
    }
    const double ci = sss_dot3(n, light);
    march_ctx k = {.bvh = bvh, .mu_i = g.mu_i, .mu_o = g.mu_o, .mm_per_unit = mm_per_unit,
                   .delta = sss_mesh_ray_offset(mesh), .stack = &st, .mesh = mesh,
                   .refine = !(opts && opts->vertex_refraction), .focus = !(opts && opts->no_focusing),
                   .eta = m->eta,
                   .entry_v = sss_ft(m->eta, ci) * ci / g.mu_i, .cos_phase_v = g.cos_phase};
    memcpy(k.x, x, sizeof k.x);
    memcpy(k.n, n, sizeof n);
    memcpy(k.dir_i, g.dir_i, sizeof g.dir_i);
    memcpy(k.dir_o, g.dir_o, sizeof g.dir_o);
    memcpy(k.light, light, sizeof k.light);

    if (opts && opts->fitted_planes) {
        k.planes = 1;
        double sigma_t_min = INFINITY;
        for (uint32_t c = 0; c < channels; c++) sigma_t_min = fmin(sigma_t_min, st.layer[0].sigma_t[c]);
        fit_plane(mesh, x, n, -log(0.01) / sigma_t_min / mm_per_unit, k.fit_n, k.fit_p);
    }
    /* where the view ray leaves the object: the march ends there at most */
    float xo[3], d[3];
    for (int a = 0; a < 3; a++) xo[a] = (float)x[a], d[a] = (float)g.dir_o[a];
    const double s_exit = (double)sss_bvh_nearest(bvh, xo, d, k.delta, NULL) * mm_per_unit;
    for (uint32_t c = 0; c < channels; c++) {
        /* the march ends at s_exit, or where even the least extinguishing
         * layer (none above counted) would have taken e^{−tau_max} */
        double sigma_t = INFINITY;
        for (uint32_t i = 0; i < st.n; i++)
            for (uint32_t cc = 0; cc < channels; cc++)
                if (cc == c || (opts && opts->shared_end)) sigma_t = fmin(sigma_t, st.layer[i].sigma_t[cc]);
        if (!(sigma_t > 0.0)) sigma_t = base->sigma_t[c];
        if (!(sigma_t > 0.0)) continue;
        const double s_max = fmin(s_exit, tau_max / sigma_t);
        k.s_max = s_max;
        out[c] = opts && opts->seed_march ? sss_ss_march(&st, c, &g, s_max, N, locate_mesh, &k)
                                          : sss_ss_march_segments(&st, c, &g, s_max, N, locate_mesh, &k);
    }
    return SSS_OK;
}
