/* point_shells.c: the point-shells effect (docs/scenes.md), Hao–Varshney 2004
 * §3.3: "we quantize the distance from the light source to the object
 * along with quantization of its direction. Then we can trilinearly
 * interpolate". A point light of intensity I at P gives vertex x_i the
 * irradiance I cos θ_i / |P − x_i|² from its own direction
 * l_i = (P − x_i)/|P − x_i|, so
 *     q_pt(x_o; P) = Σ_i w(o, i) F_t(η, n_i·l_i) max(0, n_i·l_i) V(x_i, P) / |P − x_i|²
 * (per unit intensity). It is baked at P = c + r_s ω_j for the direction
 * set ω_j and distance shells r_s around the object's centre c, stored as
 * r_s² q_pt (the shell's own 1/r² taken out, which leaves a quantity that
 * varies slowly with r), and interpolated at run time barycentrically over
 * directions and linearly over r, then divided by r² (common/src/effects.c).
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effect.h"
#include "sss/hatweights.h"

/* A point light near the object (its direction and 1/r² falloff vary
 * across it), or one that moves and may come near. */
static int claim(const sss_scene *s, const sss_object_plan *p, const sss_scene_light *L, char *reason, size_t n)
{
    if (L->kind != SSS_LIGHT_POINT) return 0;
    const double near = sss_near_factor(s), ratio = sss_point_ratio(p, L);
    if (!(ratio < near || L->moving)) return 0; /* the directional-exact effect's */
    if (ratio < near)
        snprintf(reason, n, "point light %.3g object sizes from the centre (< %g): the direction and 1/r^2 falloff "
                 "vary across the object, so q is baked over directions x distance shells and interpolated "
                 "trilinearly (sec. 3.3)", ratio, near);
    else
        snprintf(reason, n, "moving point light (now %.3g object sizes away) may come near: directions x distance "
                 "shells (sec. 3.3)", ratio);
    return 1;
}

/* G for a point light at P, times s2 (r_s² or 1). The shadow ray ends at
 * the light, so geometry behind it does not shadow. */
static float point_g(const sss_mesh *m, const sss_vis *vis, uint32_t i, const double P[3], double eta, double s2,
                     int *traced)
{
    const float *x = &m->pos[3 * (size_t)i], *n = &m->nrm[3 * (size_t)i];
    double l[3], d2 = 0;
    for (int k = 0; k < 3; k++) l[k] = P[k] - x[k], d2 += l[k] * l[k];
    const double d = sqrt(d2);
    *traced = 0;
    if (!(d > 0)) return 0.0f;
    for (int k = 0; k < 3; k++) l[k] /= d;
    const double cs = n[0] * l[0] + n[1] * l[1] + n[2] * l[2];
    if (!(cs > 0)) return 0.0f;
    *traced = vis != NULL;
    if (vis && sss_vis_occluded_upto(vis, i, l, d)) return 0.0f;
    return (float)(sss_ft(eta, cs) * cs / d2 * s2);
}

static sss_result bake(const sss_pass_ctx *c, sss_error *err)
{
    sss_bake_file *o = c->out;
    sss_effects *fx = &o->fx;
    if (!o->dirs.n) {
        sss_result r = sss_dirset_fibonacci(&o->dirs, c->n_dirs, err);
        if (r != SSS_OK) return r;
    }
    const uint32_t nv = c->mesh->nv, n = o->dirs.n, S = c->shells;
    /* shells from just outside the bounding sphere (radius = half the
     * diagonal) to near_factor object sizes, geometrically spaced: q_pt
     * changes fastest close to the object */
    const double rb = 0.5 * c->plan->size, r0 = 1.1 * rb, r1 = fmax(c->near_factor * c->plan->size, 1.5 * r0);
    fx->nshells = S;
    memcpy(fx->shell_centre, c->plan->centre, sizeof fx->shell_centre);
    fx->shell_radius = malloc(S * sizeof(double));
    fx->shell_q = malloc((size_t)S * n * nv * c->C * sizeof(float) + 1);
    float *G = malloc((size_t)nv * S * n * sizeof(float) + 1);
    if (!fx->shell_radius || !fx->shell_q || !G) {
        free(G);
        return sss_fail(err, SSS_ERR_NOMEM, "point-shells pass: out of memory for %u shells x %u directions x %u "
                        "vertices", S, n, nv);
    }
    for (uint32_t s = 0; s < S; s++) fx->shell_radius[s] = r0 * pow(r1 / r0, (double)s / (S - 1));
    const uint32_t SN = S * n;
    uint64_t rays = 0;
#pragma omp parallel for schedule(dynamic, 64) reduction(+ : rays)
    for (int64_t i = 0; i < (int64_t)nv; i++)
        for (uint32_t sj = 0; sj < SN; sj++) {
            const uint32_t s = sj / n, j = sj % n;
            const double r = fx->shell_radius[s], *w = &o->dirs.dir[3 * (size_t)j];
            const double P[3] = {fx->shell_centre[0] + r * w[0], fx->shell_centre[1] + r * w[1],
                                 fx->shell_centre[2] + r * w[2]};
            int traced;
            G[(size_t)i * SN + sj] = point_g(c->mesh, c->vis, (uint32_t)i, P, c->eta, r * r, &traced);
            rays += (uint64_t)traced;
        }
    c->st->rays += rays;
    /* layout ((s n + j) nv + v) C + c: shells × directions act as one axis */
    const sss_result r = sss_pass_integrate(c, G, SN, 0, fx->shell_q, err);
    free(G);
    return r;
}

static void provenance(const sss_pass_ctx *c, cJSON *params)
{
    cJSON_AddNumberToObject(params, "dirs", c->n_dirs);
    cJSON_AddNumberToObject(params, "shells", c->shells);
}

static void memory(const sss_pass_ctx *c, uint64_t *kept, uint64_t *transient)
{
    const uint64_t nv = c->mesh->nv, n = c->n_dirs, S = c->shells;
    *kept = S * n * nv * c->C * 4u + S * 8u + n * 36u;
    *transient = nv * S * n * 4u; /* G */
}

const sss_effect_unit sss_effect_point_shells = {SSS_PASS_POINT_SHELLS, "point-shells", SSS_FX_POINT_SHELLS, claim,
                                                 bake, provenance, memory};

sss_result sss_point_exact(const sss_bake_file *f, int self_shadow, const double P[3], float *out, sss_error *err)
{
    /* ε from NBHD (format 1.4), else PARM's text, else the bake's default */
    double eps = f->eps;
    if (!(eps > 0)) {
        eps = 1e-3;
        cJSON *pj = cJSON_Parse(f->params_json ? f->params_json : "");
        const cJSON *e = pj ? cJSON_GetObjectItemCaseSensitive(pj, "eps") : NULL;
        if (cJSON_IsNumber(e)) eps = e->valuedouble;
        cJSON_Delete(pj);
    }
    const uint32_t C = f->channels;
    sss_dipole dip[SSS_MAX_CHANNELS];
    for (uint32_t k = 0; k < C; k++)
        sss_dipole_init(&dip[k], f->material.sigma_a[k], f->material.sigmap_s[k], f->material.eta);
    sss_mesh m;
    const sss_mesh geom = {.nv = f->mesh.nv, .nf = f->mesh.nf, .pos = f->mesh.pos, .nrm = f->mesh.nrm, .tri = f->mesh.tri};
    sss_result r = sss_mesh_copy(&geom, &m, err);
    if (r != SSS_OK) return r;
    m.area = malloc((size_t)m.nv * sizeof(double));
    if (!m.area) { sss_mesh_free(&m); return sss_fail(err, SSS_ERR_NOMEM, "out of memory"); }
    sss_mesh_vertex_areas(&m, m.area);
    const double R = sss_nbhd_radii(&m, f->mm_per_unit, dip, C, eps, NULL);
    sss_weights nb = {0};
    sss_vis *vis = NULL;
    float *G = malloc((size_t)m.nv * sizeof(float) + 1);
    r = G ? sss_nbhd_build(&m, f->mm_per_unit, dip, C, R, NULL, 0, 0, NULL, &nb, err) : sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    /* the file's weight rule (section QUAD): the bake's corrections */
    sss_weights hat = {0};
    if (r == SSS_OK && f->weights == SSS_WEIGHTS_HAT)
        r = sss_hat_corrections(&m, f->mm_per_unit, dip, C, R, NULL, 0, NULL, &hat, err);
    if (r == SSS_OK && self_shadow) r = sss_vis_create(&m, &vis, err);
    if (r == SSS_OK) {
        for (uint32_t i = 0; i < m.nv; i++) {
            int t;
            G[i] = point_g(&m, vis, i, P, f->material.eta, 1.0, &t);
        }
        sss_integrate_hat(&nb, hat.nrows ? &hat : NULL, G, 1, out);
    }
    free(G);
    sss_vis_destroy(vis);
    sss_weights_free(&nb);
    sss_weights_free(&hat);
    sss_mesh_free(&m);
    return r;
}
