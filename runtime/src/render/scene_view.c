/* scene_view.c: the run-time sum over a scene's lights (several lights:
 * the sum), each evaluated with the
 * parameterisation the planner chose and the file records (docs/scenes.md):
 *   directional-exact  the stored values, no work per frame;
 *   direction-set      the §3.2 interpolation (sss_decode_all);
 *   point-shells       the §3.3 trilinear interpolation (sss_fx_point);
 *   environment-sh     Σ_i T_i L_i (sss_fx_env).
 * Only the parts a file carries are evaluated: a light kind the scene does
 * not have costs nothing per frame. This CPU sum is the fallback (--cpu) and
 * the reference of the GPU sum (fx_gpu.c), which takes each light's
 * parameters from sss_scene_eval_light as this file does; each light's term
 * is the cpu hook of its pass in the pass table (effects/), next to the
 * pass's GPU side.
 */
#include "sss/render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "effects/effects.h"
#include "sss/effects.h"
#include "sss/nearterms.h"
#include "sss/vec3.h"

typedef struct lightref {
    int kind;        /* 0 exact, 1 set, 2 point, 3 env */
    uint32_t exact;  /* QDIR index */
    double w[3];     /* colour × intensity per channel */
    const sss_scene_light *L;
} lightref;

struct sss_scene_eval {
    const sss_bake_file *f;
    uint32_t n;
    lightref *l;
    float *tmp, *env;
    char paths[160];
    sss_view_params view;  /* the near-term settings (sss_scene_eval_set_view) */
    unsigned kinds;        /* light kinds summed (sss_scene_eval_set_kinds) */
    /* a file with OWNT: its near-term rows, the BVH of the bake's rays, the
     * rays' offset, and per-vertex scratch (V, g V) */
    int has_near;
    sss_weights near;
    sss_bvh bvh;
    float delta;
    uint8_t *lit;
    float *gv;
};

/* The near terms of unit light `light` added to the row q (nv × channels):
 * every vertex's own visibility by the bake's ray (origin x + δn in float,
 * towards ω, blocked by a hit beyond δ) through the BVH the GPU traces,
 * with the arithmetic of its shader (sss_bvh_lit, near_vis.comp.glsl),
 * then Σ_i w̃(o, i) g_i V_i per row in sss_near_sum's order: what the
 * renderer's near pass adds on the GPU (Hao–Varshney 2004 §3.1's terms of
 * the vertex and its rings, docs/viewer.md). */
static void cpu_add_near(void *ctx, const double light[3], float *q)
{
    sss_scene_eval *e = ctx;
    const sss_bake_file *f = e->f;
    const uint32_t nv = f->mesh.nv;
    double d[3] = {light[0], light[1], light[2]};
    if (!(sss_normalize3(d) > 0)) return;
    for (uint32_t v = 0; v < nv; v++) e->lit[v] = sss_bvh_lit(&e->bvh, &f->mesh, e->delta, v, d);
    sss_near_transfer(f->mesh.nrm, nv, (float)f->material.eta, d, e->lit, e->gv);
    sss_near_add(&e->near, e->gv, q);
}

static void centre_of(const sss_bake_file *f, double c[3])
{
    double lo[3], hi[3];
    sss_mesh_bounds(&f->mesh, lo, hi);
    for (int k = 0; k < 3; k++) c[k] = 0.5 * (lo[k] + hi[k]);
}

static int find_exact(const sss_bake_file *f, const double d[3])
{
    for (uint32_t i = 0; i < f->fx.nexact; i++) {
        const double *e = &f->fx.exact_dir[3 * (size_t)i];
        if (e[0] * d[0] + e[1] * d[1] + e[2] * d[2] > 1.0 - 1e-9) return (int)i;
    }
    return -1;
}

sss_result sss_scene_eval_create(const sss_bake_file *f, const sss_scene *sc, sss_scene_eval **out, sss_error *err)
{
    *out = NULL;
    sss_scene_eval *e = calloc(1, sizeof *e);
    if (!e) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    e->f = f;
    e->kinds = SSS_SCENE_KINDS_ALL;
    e->l = calloc(sc->nlights + 1, sizeof *e->l);
    e->tmp = malloc((size_t)f->mesh.nv * 3 * sizeof(float));
    e->env = malloc((size_t)f->mesh.nv * 3 * sizeof(float));
    if (!e->l || !e->tmp || !e->env) { sss_scene_eval_destroy(e); return sss_fail(err, SSS_ERR_NOMEM, "out of memory"); }
    sss_view_params_default(&e->view);
    if (f->near_terms) {
        /* the CPU sum's near terms (cpu_add_near): built once, as the file
         * says (rings or radius, weight rule: sss_near_build_file), so that
         * they are the terms the bake took off the rows */
        sss_result nr = sss_near_build_file(f, &e->near, err);
        if (nr == SSS_OK) nr = sss_bvh_build(f->mesh.pos, f->mesh.nv, f->mesh.tri, f->mesh.nf, &e->bvh, err);
        e->lit = malloc((size_t)f->mesh.nv + 1);
        e->gv = malloc((size_t)f->mesh.nv * sizeof *e->gv + 1);
        e->has_near = 1;
        if (nr == SSS_OK && (!e->lit || !e->gv)) nr = sss_fail(err, SSS_ERR_NOMEM, "out of memory");
        if (nr != SSS_OK) {
            sss_scene_eval_destroy(e);
            return nr;
        }
        e->delta = sss_mesh_ray_offset(&f->mesh);
    }
    const uint32_t m = f->fx.mask ? f->fx.mask : SSS_FX_DIR_SET; /* a plain bake is a direction set */
    double c[3];
    centre_of(f, c);
    int used[4] = {0, 0, 0, 0}, env_done = 0;
    for (uint32_t i = 0; i < sc->nlights; i++) {
        const sss_scene_light *L = &sc->lights[i];
        if (L->intensity == 0) continue;
        lightref r = {0, 0, {0, 0, 0}, L};
        for (int k = 0; k < 3; k++) r.w[k] = L->intensity * L->colour[k];
        double d[3];
        int ex = -1;
        if (L->kind == SSS_LIGHT_DIRECTIONAL) {
            memcpy(d, L->direction, sizeof d);
            ex = L->moving ? -1 : find_exact(f, d);
        } else if (L->kind == SSS_LIGHT_POINT) {
            for (int k = 0; k < 3; k++) d[k] = L->position[k] - c[k];
            sss_normalize3(d);
            ex = L->moving ? -1 : find_exact(f, d);
        }
        if (L->kind == SSS_LIGHT_ENVIRONMENT) {
            if (!(m & SSS_FX_ENV_SH)) goto missing;
            if (env_done) continue; /* the file's probe already sums every environment light */
            env_done = 1;
            r.kind = 3;
        } else if (ex >= 0 && (m & SSS_FX_DIR_EXACT)) {
            r.kind = 0;
            r.exact = (uint32_t)ex;
            if (L->kind == SSS_LIGHT_POINT) {
                /* a far point light baked as a direction: its irradiance at
                 * the object's centre, I / d² */
                double d2 = 0;
                for (int k = 0; k < 3; k++) d2 += (L->position[k] - c[k]) * (L->position[k] - c[k]);
                for (int k = 0; k < 3; k++) r.w[k] /= d2;
            }
        } else if (L->kind == SSS_LIGHT_POINT && (m & SSS_FX_POINT_SHELLS)) {
            r.kind = 2;
        } else if (L->kind == SSS_LIGHT_DIRECTIONAL && (m & SSS_FX_DIR_SET)) {
            r.kind = 1;
        } else {
            goto missing;
        }
        used[r.kind] = 1;
        e->l[e->n++] = r;
        continue;
    missing:
        sss_scene_eval_destroy(e);
        return sss_fail(err, SSS_ERR_ARG, "%s: /lights/%u: the file has no data for this %s%s light (bake it with "
                        "this scene)", sc->path, i, L->moving ? "moving " : "static ", sss_light_kind_name(L->kind));
    }
    static const char *const nm[4] = {"directional-exact", "direction-set", "point-shells", "environment-sh"};
    size_t k = 0;
    for (int i = 0; i < 4; i++)
        if (used[i]) k += (size_t)snprintf(e->paths + k, sizeof e->paths - k, "%s%s", k ? " + " : "", nm[i]);
    *out = e;
    return SSS_OK;
}

void sss_scene_eval_set_view(sss_scene_eval *e, const sss_view_params *p)
{
    e->view.near_terms = p->near_terms;
    e->view.near_visibility = p->near_visibility;
    e->view.shadow_size = p->shadow_size;
}

const sss_view_params *sss_scene_eval_view(const sss_scene_eval *e) { return &e->view; }

void sss_scene_eval_destroy(sss_scene_eval *e)
{
    if (!e) return;
    if (e->has_near) {
        sss_weights_free(&e->near);
        sss_bvh_free(&e->bvh);
    }
    free(e->lit);
    free(e->gv);
    free(e->l);
    free(e->tmp);
    free(e->env);
    free(e);
}

const char *sss_scene_eval_paths(const sss_scene_eval *e) { return e->paths; }

uint32_t sss_scene_eval_count(const sss_scene_eval *e) { return e->n; }

void sss_scene_eval_light(const sss_scene_eval *e, uint32_t i, double angle, sss_scene_light_frame *o)
{
    const sss_bake_file *f = e->f;
    const lightref *r = &e->l[i];
    const uint32_t C = f->channels;
    memset(o, 0, sizeof *o);
    o->kind = r->kind;
    /* a grey file has one value per vertex: coloured lights add up with
     * their mean colour (docs/scenes.md) */
    for (int k = 0; k < 3; k++) o->w[k] = C == 3 ? r->w[k] : (r->w[0] + r->w[1] + r->w[2]) / 3.0;
    const double ca = cos(angle), sa = sin(angle);
    if (r->kind == 0) {
        o->exact = r->exact;
    } else if (r->kind == 1) {
        memcpy(o->dir, r->L->direction, sizeof o->dir);
        if (r->L->moving) o->dir[0] = ca * r->L->direction[0] - sa * r->L->direction[1], o->dir[1] = sa * r->L->direction[0] + ca * r->L->direction[1];
    } else if (r->kind == 2) {
        memcpy(o->pos, r->L->position, sizeof o->pos);
        if (r->L->moving) o->pos[0] = ca * r->L->position[0] - sa * r->L->position[1], o->pos[1] = sa * r->L->position[0] + ca * r->L->position[1];
    } else {
        /* the stored probe already holds intensity and colour; it is RGB.
         * A moving environment turns about +z: its coefficients rotate
         * (K² work per frame at most, none for a static one). */
        const uint32_t K = f->fx.env_order * f->fx.env_order;
        for (uint32_t k = 0; k < 3 * K && k < 3 * 64; k++) o->env_L[k] = f->fx.env_probe[k];
        if (r->L->moving && K) {
            double Lc[3 * 64];
            for (uint32_t k = 0; k < 3 * K; k++) Lc[k] = f->fx.env_probe[k];
            for (int ch = 0; ch < 3; ch++) sss_sh_rotate_z(f->fx.env_order, angle, &Lc[ch * K]);
            for (uint32_t k = 0; k < 3 * K; k++) o->env_L[k] = (float)Lc[k];
        }
    }
}

void sss_pass_cpu_add_row(const sss_bake_file *f, const double w[3], const float *src, float *q)
{
    const uint32_t nv = f->mesh.nv, C = f->channels;
    for (uint32_t v = 0; v < nv; v++)
        for (uint32_t c = 0; c < C; c++) q[(size_t)v * C + c] += (float)(w[c] * src[(size_t)v * C + c]);
}

void sss_scene_eval_set_kinds(sss_scene_eval *e, unsigned mask) { e->kinds = mask & SSS_SCENE_KINDS_ALL; }
unsigned sss_scene_eval_kinds(const sss_scene_eval *e) { return e->kinds; }

unsigned sss_scene_eval_kinds_present(const sss_scene_eval *e)
{
    unsigned m = 0;
    for (uint32_t i = 0; i < e->n; i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(e, i, 0.0, &lf);
        m |= 1u << lf.kind;
    }
    return m & SSS_SCENE_KINDS_ALL;
}

/* The CPU path and the reference of the GPU path (fx_gpu.c): lights in
 * order, each term rounded to float and added to q by the pass of its kind
 * (effects/: the cpu hook of the pass table). */
void sss_scene_eval_frame(sss_scene_eval *e, double angle, float *q)
{
    const sss_bake_file *f = e->f;
    const size_t n = (size_t)f->mesh.nv * f->channels;
    const int near = e->has_near && e->view.near_terms;
    const sss_effect_scratch scratch = {e->tmp, e->env, near ? cpu_add_near : NULL, e};
    memset(q, 0, n * sizeof *q);
    for (uint32_t i = 0; i < e->n; i++) {
        sss_scene_light_frame lf;
        sss_scene_eval_light(e, i, angle, &lf);
        if (!(e->kinds >> lf.kind & 1)) continue;
        const sss_effect *fx = sss_effect_for_light(lf.kind);
        if (fx && fx->cpu) fx->cpu(f, &lf, &scratch, q);
    }
}

void sss_scene_camera_params(const sss_scene *sc, const sss_bake_file *f, sss_view_params *p)
{
    if (!sc->camera.present) return;
    double c[3];
    const double rad = sss_mesh_bounding_sphere(&f->mesh, c);
    double d[3];
    for (int k = 0; k < 3; k++) d[k] = sc->camera.position[k] - sc->camera.target[k];
    const double dist = sss_normalize3(d);
    memcpy(p->up, sc->camera.up, sizeof p->up);
    p->fov_deg = sc->camera.fov_deg;
    if (!(dist > 0) || !(rad > 0)) return;
    memcpy(p->view, d, sizeof d);
    /* The renderer looks at the centre plus a pan in its screen plane
     * (draw.c camera()): the target's offset from the centre splits into
     * that pan and a part along the view, which moves the eye's distance,
     * so the eye lands on the camera's position. */
    sss_view_params frame = *p;
    frame.pan[0] = frame.pan[1] = 0;
    double eye[3], right[3], up[3], fwd[3], t[3];
    sss_view_frame(&frame, c, rad, eye, right, up, fwd);
    for (int k = 0; k < 3; k++) t[k] = sc->camera.target[k] - c[k];
    p->pan[0] = sss_dot3(t, right) / rad;
    p->pan[1] = sss_dot3(t, up) / rad;
    /* a target far behind the centre would put the eye past it: kept in front */
    p->distance = fmax(dist + sss_dot3(t, d), 1e-3 * rad) / rad;
}
