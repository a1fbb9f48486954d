/* planner.c: scene → effect set with a reason per decision (docs/scenes.md
 * lists the rules and their tests).
 *
 * The rules run in table order over each object. Each one reads the scene
 * and the geometry facts computed once per object (size, centre,
 * convexity) and appends decisions; the light rule also chooses the pass of
 * each light by asking the effect units (effects/effect.h). Adding an
 * effect is adding a unit there, not changing the rules here.
 */
#include "sss/planner.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "bake/bake_tree.h"
#include "effects/effect.h"
#include "sss/htsm.h"
#include "sss/memory.h"
#include "sss/jsontext.h"
#include "sss/probe.h"
#include "sss/sh.h"

typedef struct plan_in {
    const sss_scene *scene;
    const sss_mesh *world;
} plan_in;

static void decide(sss_object_plan *p, const char *effect, const char *choice, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
static void decide(sss_object_plan *p, const char *effect, const char *choice, const char *fmt, ...)
{
    if (p->ndecisions >= SSS_PLAN_MAX_DECISIONS) return;
    sss_decision *d = &p->decisions[p->ndecisions++];
    snprintf(d->effect, sizeof d->effect, "%s", effect);
    snprintf(d->choice, sizeof d->choice, "%s", choice);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->reason, sizeof d->reason, fmt, ap);
    va_end(ap);
}

/* ---- geometry facts --------------------------------------------------- */

typedef struct edge { uint32_t a, b, t; } edge;
static int edge_cmp(const void *x, const void *y)
{
    const edge *e = x, *f = y;
    if (e->a != f->a) return e->a < f->a ? -1 : 1;
    if (e->b != f->b) return e->b < f->b ? -1 : 1;
    return e->t < f->t ? -1 : e->t > f->t;
}

static void face_plane(const sss_mesh *m, uint32_t t, double n[3], double *d)
{
    const float *a = &m->pos[3 * (size_t)m->tri[3 * (size_t)t]], *b = &m->pos[3 * (size_t)m->tri[3 * (size_t)t + 1]],
                *c = &m->pos[3 * (size_t)m->tri[3 * (size_t)t + 2]];
    double u[3], v[3];
    for (int k = 0; k < 3; k++) u[k] = (double)b[k] - a[k], v[k] = (double)c[k] - a[k];
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    if (l > 0) for (int k = 0; k < 3; k++) n[k] /= l;
    *d = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
}

int sss_mesh_is_convex(const sss_mesh *m)
{
    if (!m || m->nf < 4) return 0;
    double lo[3], hi[3];
    const double tol = 1e-6 * sss_mesh_bounds(m, lo, hi);
    /* closed and locally convex: each undirected edge in exactly two
     * triangles, the far vertex of the neighbour behind this face's plane */
    const size_t ne = 3 * (size_t)m->nf;
    edge *e = malloc(ne * sizeof *e);
    if (!e) return 0;
    for (uint32_t t = 0; t < m->nf; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = m->tri[3 * (size_t)t + k], b = m->tri[3 * (size_t)t + (k + 1) % 3];
            e[3 * (size_t)t + k] = (edge){a < b ? a : b, a < b ? b : a, t};
        }
    qsort(e, ne, sizeof *e, edge_cmp);
    int ok = 1;
    for (size_t i = 0; i < ne && ok; i += 2) {
        if (i + 1 >= ne || e[i + 1].a != e[i].a || e[i + 1].b != e[i].b || (i + 2 < ne && e[i + 2].a == e[i].a &&
                                                                          e[i + 2].b == e[i].b)) {
            ok = 0;
            break;
        }
        for (int s = 0; s < 2 && ok; s++) {
            const uint32_t t = e[i + s].t, o = e[i + 1 - s].t;
            double n[3], d;
            face_plane(m, t, n, &d);
            for (int k = 0; k < 3; k++) {
                const float *p = &m->pos[3 * (size_t)m->tri[3 * (size_t)o + k]];
                if (n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d > tol) ok = 0;
            }
        }
    }
    free(e);
    /* globally: every vertex behind every (sampled) face plane, which rules
     * out locally convex surfaces that wrap around twice */
    const uint64_t budget = 50000000u;
    uint32_t stride = (uint64_t)m->nv * m->nf > budget ? (uint32_t)((uint64_t)m->nv * m->nf / budget) + 1 : 1;
    for (uint32_t t = 0; t < m->nf && ok; t += stride) {
        double n[3], d;
        face_plane(m, t, n, &d);
        for (uint32_t v = 0; v < m->nv && ok; v++) {
            const float *p = &m->pos[3 * (size_t)v];
            if (n[0] * p[0] + n[1] * p[1] + n[2] * p[2] - d > tol) ok = 0;
        }
    }
    return ok;
}

/* ---- rules ------------------------------------------------------------ */

/* Colour channels: the three dipole profiles are equal when σa and σ′s are
 * equal across channels, so one channel carries all the information
 * (Hao–Varshney 2004 §3.1 bakes per channel). */
static void rule_channels(const plan_in *in, sss_object_plan *p)
{
    const sss_material *m = &p->material;
    const sss_scene_object *ob = &in->scene->objects[p->object];
    /* a baked field blends with the inside material: grey only if both are */
    const int grey = sss_material_channels(m) == 1 &&
                     ((p->field != SSS_PLAN_FIELD_BAKED && p->field != SSS_PLAN_FIELD_PER_FRAME && p->field != SSS_PLAN_FIELD_RUNTIME) ||
                      sss_material_channels(&ob->hetero.inside) == 1);
    p->channels = grey ? 1 : 3;
    if (!grey) p->effects |= SSS_FX_RGB;
    if (grey)
        decide(p, "channels", "1 channel", "material '%s' has equal sigma_a and sigma'_s in R, G and B: one dipole "
               "profile serves all three", m->name);
    else
        decide(p, "channels", "3 channels", "material '%s' differs across channels (sigma_a %g/%g/%g, sigma'_s "
               "%g/%g/%g)", m->name, m->sigma_a[0], m->sigma_a[1], m->sigma_a[2], m->sigmap_s[0], m->sigmap_s[1],
               m->sigmap_s[2]);
}

/* A material field (docs/heterogeneous.md §5): a constant is the
 * homogeneous blend at c (σa, σ′s linear in c), baked as any homogeneous
 * object, without a field section; any other field on a static object
 * takes the baked path, the spatially varying kernel of §4 on the shared
 * rows. Runs first: the rules after it read p->material. */
static void rule_field(const plan_in *in, sss_object_plan *p)
{
    const sss_scene_object *ob = &in->scene->objects[p->object];
    const sss_field *f = &ob->hetero.field;
    p->material = ob->material;
    if (f->kind == SSS_FIELD_NONE) return;
    if (f->kind == SSS_FIELD_CONSTANT) {
        p->field = SSS_PLAN_FIELD_FOLDED;
        sss_material_blend(&ob->material, &ob->hetero.inside, f->value, &p->material);
        if (f->value != 0.0) snprintf(p->material.name, sizeof p->material.name, "custom");
        decide(p, "field", "folded", "a constant field c = %g is one material everywhere: the blend (1-c) '%s' + c "
               "inside (sigma_a %g/%g/%g, sigma'_s %g/%g/%g), baked as a homogeneous object", f->value,
               ob->material.name, p->material.sigma_a[0], p->material.sigma_a[1], p->material.sigma_a[2],
               p->material.sigmap_s[0], p->material.sigmap_s[1], p->material.sigmap_s[2]);
        return;
    }
    p->field = SSS_PLAN_FIELD_BAKED;
    if (ob->hetero.surface) {
        decide(p, "field", "baked", "surface texture (seed 001 sec. 5): endpoints' profiles, no volume march: the "
               "%s field is read at the vertices only, each pair's weight the geometric mean of its endpoints' "
               "profiles (docs/heterogeneous.md sec. 4.4); stored in section FELD", sss_field_kind_name(f->kind));
        return;
    }
    decide(p, "field", "baked", "static object with a %s field: every pair's weight takes the geometric mean of its "
           "endpoints' dipole profiles and the transmittance through the field between them (docs/heterogeneous.md "
           "sec. 4), stored with the field (section FELD)", sss_field_kind_name(f->kind));
}

/* "editable": true (seed 000, Shopf 2007 §4.3): the material is edited
 * live, so nothing baked for its q would hold after an edit; the viewer
 * evaluates it every frame from a light-space map and the field's texture
 * (docs/heterogeneous.md §9). */
static void rule_editable(const plan_in *in, sss_object_plan *p)
{
    const sss_scene *s = in->scene;
    const sss_scene_object *ob = &s->objects[p->object];
    p->per_frame = 1;
    p->field = SSS_PLAN_FIELD_RUNTIME;
    p->material = ob->material;
    decide(p, "field", "run-time", "editable object (%s field): its material is edited live, so no q is baked; "
           "each frame the viewer renders a light-space map (position, normal, transmitted irradiance, with mips) and "
           "sums, per pixel, the thesis's hierarchical samples, each marched through the field's mipmapped 3D "
           "texture (docs/heterogeneous.md sec. 9)", ob->hetero.field.kind != SSS_FIELD_NONE ?
           sss_field_kind_name(ob->hetero.field.kind) : "no");
    uint32_t drawn = 0;
    double R = 0.0;
    for (uint32_t l = 0; l < s->nlights; l++) {
        const sss_scene_light *L = &s->lights[l];
        char eff[32];
        snprintf(eff, sizeof eff, "light %u", l);
        p->light_pass[l] = UINT32_MAX;
        if (L->intensity == 0.0)
            decide(p, eff, "none", "intensity 0");
        else if (L->kind != SSS_LIGHT_DIRECTIONAL && L->kind != SSS_LIGHT_POINT)
            decide(p, eff, "none", "the run-time path takes directional and point lights only (this %s light is not "
                   "drawn on the object)", sss_light_kind_name(L->kind));
        else if (L->kind == SSS_LIGHT_POINT && !sss_htsm_point_drawn(&in->world[p->object], L->position, &R)) {
            char why[sizeof p->decisions[0].reason];
            sss_htsm_point_inside_msg(why, sizeof why, L->position, ob->name, R);
            decide(p, eff, "none", "%s", why);
        } else if (drawn++ >= SSS_HTSM_MAX_LIGHTS)
            decide(p, eff, "none", "the run-time path sums the first %d directional and point lights",
                   SSS_HTSM_MAX_LIGHTS);
        else if (L->kind == SSS_LIGHT_POINT)
            decide(p, eff, "run-time", "point light: its perspective light-space map (1/r^2 fall-off, each texel's "
                   "area by its depth) is rendered each frame, the lights' q and surface terms summed, each light's shadowed "
                   "by its own map (docs/heterogeneous.md sec. 9.1)");
        else
            decide(p, eff, "run-time", "directional light: its light-space map is rendered each frame, the lights' "
                   "q and surface terms summed, each light's shadowed by its own map (docs/heterogeneous.md sec. 9.1)");
    }
}

/* A material field on a deforming object (docs/deformable.md §10): a
 * constant folds as on a static one; any other is read at each vertex's
 * rest-pose position, so the material moves with the surface, and each
 * pair takes the endpoints' product alone (seed 003 Eq. 8), the model the
 * splatting computes too. */
static void rule_field_per_frame(const plan_in *in, sss_object_plan *p)
{
    const sss_field *f = &in->scene->objects[p->object].hetero.field;
    if (f->kind == SSS_FIELD_NONE || f->kind == SSS_FIELD_CONSTANT) {
        rule_field(in, p);
        return;
    }
    p->material = in->scene->objects[p->object].material;
    p->field = SSS_PLAN_FIELD_PER_FRAME;
    decide(p, "field", "per-frame", "deforming object with a %s field: each vertex takes the material of the field at "
           "its rest-pose position, so the material moves with the surface; every pair's weight takes the geometric "
           "mean of its endpoints' dipole profiles (seed 003 Eq. 8) without the transmittance between them, which a "
           "posed segment has no rest-frame path for (docs/deformable.md sec. 10)", sss_field_kind_name(f->kind));
}

/* Self-shadowing: V(x_i, ω) of §3.1 is 1 whenever n_i·ω > 0 on a convex
 * object (the supporting plane at x_i separates the ray from the object),
 * so the visibility pass against the object itself changes nothing. */
static void rule_self_shadow(const plan_in *in, sss_object_plan *p)
{
    (void)in;
    p->self_shadow = !p->convex;
    if (p->self_shadow) p->effects |= SSS_FX_SELF_SHADOW;
    if (p->convex)
        decide(p, "self-shadow", "off", "the mesh is closed and convex: every vertex sees every light above its "
               "tangent plane, so no visibility rays against itself are needed");
    else
        decide(p, "self-shadow", "on", "the mesh is not convex (or not closed): parts of it can shadow others");
}

/* Shadows from the other objects: baked only when neither the object nor
 * the occluder moves, since a baked shadow is fixed to the geometry. */
static void rule_scene_shadow(const plan_in *in, sss_object_plan *p)
{
    const sss_scene *s = in->scene;
    const sss_scene_object *o = &s->objects[p->object];
    uint32_t n = 0, moving = 0;
    for (uint32_t k = 0; k < s->nobjects; k++) {
        if (k == p->object) continue;
        /* a deforming object's shape changes: its shadow cannot be baked */
        if (o->moving || s->objects[k].moving || sss_scene_object_deforms(&s->objects[k])) { moving++; continue; }
        p->occluders[n++] = k;
    }
    p->noccluders = n;
    p->scene_shadow = n > 0;
    if (p->scene_shadow) p->effects |= SSS_FX_SCENE_SHADOW;
    if (s->nobjects == 1)
        decide(p, "scene-shadow", "off", "the object is alone in the scene");
    else if (n == 0)
        decide(p, "scene-shadow", "off", "%s moves (or deforms): shadows from the other objects are not fixed and "
               "are not baked", o->moving ? "the object" : "every other object");
    else {
        char list[200] = "";
        size_t k = 0;
        for (uint32_t i = 0; i < n && k < sizeof list - 40; i++)
            k += (size_t)snprintf(list + k, sizeof list - k, "%s'%s'", i ? ", " : "", s->objects[p->occluders[i]].name);
        decide(p, "scene-shadow", "on", "static scene: %s cast%s shadows onto it (rays traced against %u other "
               "object%s)%s", list, n == 1 ? "s" : "", n, n == 1 ? "" : "s",
               moving ? "; moving objects are left out" : "");
    }
}

/* A deforming object (docs/deformable.md §4): its neighbourhoods N(x_o),
 * areas ΔA and visibility V change with the pose, so nothing baked for one
 * pose holds; it takes the per-frame path instead (Hao–Varshney 2004
 * §2.3's run-time mode on each pose, sss/perframe.h), which traces the
 * object alone and takes directional lights. Replaces the shadow, light
 * and storage rules for the object. */
static void rule_per_frame(const plan_in *in, sss_object_plan *p)
{
    const sss_scene *s = in->scene;
    const sss_deform *d = &s->objects[p->object].deform;
    p->per_frame = 1;
    p->self_shadow = 1;
    if (d->kind == SSS_DEFORM_SKIN)
        decide(p, "deform", "per-frame", "the object deforms (skin of %d bones, docs/deformable.md sec. 2): "
               "neighbourhoods, areas and visibility change with the pose, so nothing is baked; q is evaluated on "
               "each frame's pose (docs/deformable.md sec. 3)", d->skin.nbones);
    else if (d->kind != SSS_DEFORM_NONE)
        decide(p, "deform", "per-frame", "the object deforms (%s about (%.3g, %.3g, %.3g), %g deg, period %g s): "
               "neighbourhoods, areas and visibility change with the pose, so nothing is baked; q is evaluated on "
               "each frame's pose (docs/deformable.md sec. 3)", sss_deform_kind_name(d->kind), d->axis[0], d->axis[1],
               d->axis[2], d->angle_deg, d->period_s);
    else
        decide(p, "deform", "per-frame", "the mesh is skinned and its clip moves it (glTF): neighbourhoods, areas and "
               "visibility change with the pose, so nothing is baked; q is evaluated on each frame's pose "
               "(docs/deformable.md sec. 3, 5)");
    decide(p, "self-shadow", "on", "the pose changes the shape (a convex rest pose need not stay convex): rays "
           "against each frame's pose");
    decide(p, "scene-shadow", "off", "the per-frame path traces the object alone (docs/deformable.md sec. 6)");
    for (uint32_t l = 0; l < s->nlights; l++) {
        const sss_scene_light *L = &s->lights[l];
        char eff[32];
        snprintf(eff, sizeof eff, "light %u", l);
        p->light_pass[l] = UINT32_MAX;
        if (L->intensity == 0.0 || (L->colour[0] == 0 && L->colour[1] == 0 && L->colour[2] == 0))
            decide(p, eff, "none", "%s light of zero intensity adds nothing", sss_light_kind_name(L->kind));
        else if (L->kind == SSS_LIGHT_DIRECTIONAL)
            decide(p, eff, "per-frame", "directional light: q for its direction on each frame's pose");
        else
            decide(p, eff, "none", "the per-frame path takes directional lights only (docs/deformable.md sec. 6): "
                   "this %s light is not drawn on the object", sss_light_kind_name(L->kind));
    }
}

/* Light parameterisation, per light; several lights add up at run time.
 * Each effect unit's rule (effects/effect.h) says whether it takes the
 * light and why; the rules exclude each other:
 *  - static directional: q for that one direction, exactly (§3.1 without
 *    the §3.2 direction set and its interpolation error; dir_exact.c);
 *  - moving directional: the direction set (§3.2; dir_set.c);
 *  - point light within near_factor object sizes, or moving: directions ×
 *    distance shells, interpolated trilinearly (§3.3; point_shells.c);
 *    farther: its direction from the object's centre, as a directional
 *    light (the falloff varies by less than 2/near_factor across the
 *    object; dir_exact.c);
 *  - environment: SH transfer of q, dotted with the probe's SH (env_sh.c). */
static void rule_lights(const plan_in *in, sss_object_plan *p)
{
    const sss_scene *s = in->scene;
    for (uint32_t l = 0; l < s->nlights; l++) {
        const sss_scene_light *L = &s->lights[l];
        char eff[32];
        snprintf(eff, sizeof eff, "light %u", l);
        p->light_pass[l] = UINT32_MAX;
        if (L->intensity == 0.0 || (L->colour[0] == 0 && L->colour[1] == 0 && L->colour[2] == 0)) {
            decide(p, eff, "none", "%s light of zero intensity adds nothing", sss_light_kind_name(L->kind));
            continue;
        }
        char reason[sizeof p->decisions[0].reason];
        for (int k = 0; k < SSS_PASS_KINDS; k++) {
            const sss_effect_unit *u = sss_effect_units[k];
            if (!u->claim(s, p, L, reason, sizeof reason)) continue;
            decide(p, eff, u->name, "%s", reason);
            p->light_pass[l] = (uint32_t)k;
            p->pass_lights[k]++;
            break;
        }
        if (p->light_pass[l] == UINT32_MAX)
            decide(p, eff, "none", "no effect takes a %s light", sss_light_kind_name(L->kind));
    }
    for (int k = 0; k < SSS_PASS_KINDS; k++)
        if (p->pass_lights[k]) p->effects |= sss_effect_units[k]->fx;
}

/* How the rows are computed and stored, per object: the plain bake's
 * defaults (docs/accuracy.md, "The defaults") unless the scene's "bake"
 * says otherwise (docs/scenes.md, "Schema").
 *  - weights: the hat-function weights W_oi = (1/pi) integral of phi_i R_d
 *    dA (docs/physics.md §9) for every pass, the paper's point samples
 *    (Hao-Varshney 2004 §3.1) on request;
 *  - the direction set's near terms at run time (sections OWNT, NRAD;
 *    docs/format.md §5.14, §5.17), as plain bakes: only where the viewer
 *    can add back what the bake took off, i.e. with no static occluder
 *    (the viewer's near terms trace the object alone). The other effects
 *    keep them baked (docs/scenes.md, "Rows, weights and near terms");
 *  - the direction set's rows: the compact compression (reference points +
 *    SH, §4; docs/compression.md) when they have lost their near terms, or
 *    when "compress": "compact" asks; else floats. The other effects' rows
 *    stay float: QDIR is one value per light, PSHL and ENVT have no
 *    compressed form. */
static void rule_storage(const plan_in *in, sss_object_plan *p)
{
    const sss_scene_bake *b = &in->scene->bake;
    p->weights = b->weights == SSS_SCENE_WEIGHTS_POINT ? SSS_WEIGHTS_POINT : SSS_WEIGHTS_HAT;
    if (p->weights == SSS_WEIGHTS_HAT)
        decide(p, "weights", "hat", "R_d integrated over each vertex's hat function (docs/physics.md sec. 9) in "
               "every pass: independent of the tessellation, the plain bake's default%s",
               b->weights ? " (bake.weights)" : "");
    else
        decide(p, "weights", "point", "bake.weights asks for the paper's point weights, R_d at the vertex times its "
               "area (Hao-Varshney 2004 sec. 3.1)");
    const int dirset = p->pass_lights[SSS_PASS_DIR_SET] > 0;
    /* a baked field's near terms too: readers weigh them with the file's
     * kernel κ (sss_near_build_file, docs/heterogeneous.md §4) */
    p->near_runtime = dirset && b->near_terms != SSS_SCENE_NEAR_BAKED && p->noccluders == 0;
    if (!dirset)
        decide(p, "near terms", "baked", "no direction set: a static light's row is exact for its one direction, and "
               "point shells and the SH transfer have no run-time near pass; every term stays in the rows");
    else if (p->near_runtime)
        decide(p, "near terms", "runtime", "direction set: the terms within the material's radius (95 %% of "
               "R_d,total, 97 %% for one channel) are added at run time for the light's actual direction, without "
               "the direction set's interpolation error, as in plain bakes%s; the other effects keep theirs baked",
               p->field == SSS_PLAN_FIELD_BAKED ? ", each weighed with the field's kernel kappa rebuilt from the file "
               "(docs/heterogeneous.md sec. 4)" : "");
    else if (b->near_terms == SSS_SCENE_NEAR_BAKED)
        decide(p, "near terms", "baked", "bake.near_terms is \"baked\": every term stays in the rows");
    else
        decide(p, "near terms", "baked", "static occluders shadow the object: the rows hold their shadows, which the "
               "viewer's near terms (traced against this object alone) would lose");
    /* compact by default only over rows without their near terms: it was
     * chosen for those (docs/compression.md); rows that keep the terms'
     * peak it codes at about 3x the direction set's own error (docs/scenes.md,
     * "Rows, weights and near terms") */
    p->compress = dirset && (b->compress == SSS_SCENE_COMPRESS_COMPACT ||
                             (b->compress == SSS_SCENE_COMPRESS_DEFAULT && p->near_runtime));
    if (!dirset)
        decide(p, "compression", "none", "no direction set: the other effects' rows (one per static light, point "
               "shells, SH transfer) are stored as floats");
    else if (p->compress)
        decide(p, "compression", "compact", "the direction set's rows are the bulk of the file: reference points + "
               "SH-coded deltas (Hao-Varshney 2004 sec. 4), the plain bake's default (docs/compression.md)%s; the "
               "other effects' rows stay float", b->compress ? " (bake.compress)" : "");
    else if (b->compress == SSS_SCENE_COMPRESS_NONE)
        decide(p, "compression", "none", "bake.compress is \"none\": the direction set's rows are stored as floats");
    else
        decide(p, "compression", "none", "the direction set's rows keep their near terms, whose peak the compact "
               "compression (chosen for rows without them) codes at about 3x the rows' own error: stored as floats "
               "(bake.compress \"compact\" asks for it anyway)");
}

/* How the passes sum their rows: the plain bake's choice
 * (sss_bake_choose_gather, bake_tree.c: the tree unless asked otherwise)
 * from the scene's "gather" or sss-bake's --gather. Every pass gathers its
 * own table of sources through the same hierarchy (bake_scene.c,
 * sss_pass_integrate); a field scales the tree's weights by κ
 * (docs/heterogeneous.md §4.5). */
static void rule_gather(const plan_in *in, sss_object_plan *p)
{
    const sss_scene_bake *b = &in->scene->bake;
    sss_bake_options o;
    memset(&o, 0, sizeof o);
    o.gather = (int)b->gather;
    p->gather = sss_bake_choose_gather(&o);
    const int fb = p->field == SSS_PLAN_FIELD_BAKED;
    if (p->gather == SSS_GATHER_DIRECT)
        decide(p, "gather", "direct", "bake.gather (or --gather) is \"direct\": every pass sums each vertex's "
               "neighbour rows, all held in memory%s", fb ? ", each entry scaled by the field's kappa "
               "(docs/heterogeneous.md sec. 4)" : "");
    else
        decide(p, "gather", "tree", "hierarchical gather, the plain bake's default: octree moments for far sources, "
               "dense blocks for near ones, no neighbour rows in memory (docs/benchmarks.md, \"Bake at scale\")%s%s",
               b->gather ? " (bake.gather)" : "", fb ? "; kappa exact per near pair, at the centroid per far node "
               "(docs/heterogeneous.md sec. 4.5)" : "");
}

void sss_plan_exact_direction(const sss_object_plan *p, const sss_scene_light *L, double d[3])
{
    if (L->kind == SSS_LIGHT_DIRECTIONAL) {
        memcpy(d, L->direction, 3 * sizeof *d);
        return;
    }
    double n = 0;
    for (int a = 0; a < 3; a++) d[a] = L->position[a] - p->centre[a], n += d[a] * d[a];
    n = sqrt(n);
    for (int a = 0; a < 3; a++) d[a] /= n;
}

/* Static lights with one direction share one QDIR row (the viewer finds a
 * light's row by its direction), and a file holds at most
 * SSS_PLAN_MAX_EXACT rows: refused here, naming the first light past the
 * limit, rather than after a bake of every other pass. */
static sss_result count_exact_rows(const sss_scene *s, sss_object_plan *p, sss_error *err)
{
    double *dirs = malloc(3 * (size_t)(SSS_PLAN_MAX_EXACT + 1) * sizeof *dirs);
    if (!dirs) return sss_fail(err, SSS_ERR_NOMEM, "planner: out of memory");
    uint32_t n = 0;
    sss_result r = SSS_OK;
    for (uint32_t l = 0; l < s->nlights && r == SSS_OK; l++) {
        if (p->light_pass[l] != SSS_PASS_DIR_EXACT) continue;
        double d[3];
        sss_plan_exact_direction(p, &s->lights[l], d);
        uint32_t k = 0;
        while (k < n && !sss_plan_same_direction(&dirs[3 * (size_t)k], d)) k++;
        if (k < n) continue;
        if (n == SSS_PLAN_MAX_EXACT) {
            r = sss_fail(err, SSS_ERR_ARG, "%s: /lights/%u: more than %d static lights of distinct directions for "
                         "object '%s' (a file holds at most %d: give lights one direction, or make some moving)",
                         s->path, l, SSS_PLAN_MAX_EXACT, s->objects[p->object].name, SSS_PLAN_MAX_EXACT);
            break;
        }
        memcpy(&dirs[3 * (size_t)n++], d, sizeof d);
    }
    free(dirs);
    p->exact_rows = n;
    return r;
}

/* Every environment probe of the scene read (with the memory plan) and
 * projected as the environment pass projects it (env_sh.c), at the order
 * the scene bakes: the sum of intensity × colour × L_i over the
 * environment lights must stay within what ENVT stores (SSS_PROBE_SH_MAX),
 * which a pixel of 3e38 exceeds; refused here, naming the light, not at the
 * writer after the bake. */
/* Environment lights in the order of their probes' paths (qsort has no
 * context argument in C11: the scene is passed through this file-scope
 * pointer, set and used only inside check_probes). */
static const sss_scene *g_probe_scene;

static int cmp_probe(const void *a, const void *b)
{
    const uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    const int c = strcmp(g_probe_scene->lights[x].probe, g_probe_scene->lights[y].probe);
    return c ? c : (x > y) - (x < y);
}

static sss_result check_probes(const sss_scene *s, uint64_t memory_limit, sss_error *err)
{
    const uint32_t order = s->bake.sh_order ? s->bake.sh_order : 4, K = order * order;
    double Lsum[3 * SSS_SH_MAX_COUNT] = {0};
    const uint64_t avail = sss_memory_available(memory_limit);
    /* each distinct probe is read and projected once, however many lights
     * name it */
    uint32_t *env = malloc(((size_t)s->nlights + 1) * sizeof *env), nenv = 0;
    if (!env) return sss_fail(err, SSS_ERR_NOMEM, "planner: out of memory");
    for (uint32_t l = 0; l < s->nlights; l++)
        if (s->lights[l].kind == SSS_LIGHT_ENVIRONMENT && s->lights[l].intensity != 0.0) env[nenv++] = l;
    g_probe_scene = s;
    qsort(env, nenv, sizeof *env, cmp_probe);
    double Ll[3 * SSS_SH_MAX_COUNT];
    for (uint32_t e = 0; e < nenv; e++) {
        const uint32_t l = env[e];
        const sss_scene_light *L = &s->lights[l];
        if (e == 0 || strcmp(L->probe, s->lights[env[e - 1]].probe) != 0) {
            sss_probe pr;
            sss_error e2 = {{0}};
            if (sss_probe_read_limited(L->probe, avail, &pr, &e2) != SSS_OK) {
                free(env);
                return sss_fail(err, SSS_ERR_ARG, "%s: /lights/%u/probe: %s", s->path, l, e2.msg);
            }
            sss_probe_sh(&pr, order, Ll);
            sss_probe_free(&pr);
        }
        for (int ch = 0; ch < 3; ch++)
            for (uint32_t i = 0; i < K; i++) {
                Lsum[ch * K + i] += L->intensity * L->colour[ch] * Ll[ch * K + i];
                if (!(fabs(Lsum[ch * K + i]) <= SSS_PROBE_SH_MAX)) {
                    free(env);
                    return sss_fail(err, SSS_ERR_ARG, "%s: /lights/%u: the probe's radiance times the intensity and "
                                    "colour reaches %g in its SH coefficients, beyond %g (section ENVT): scale the "
                                    "probe or the intensity down", s->path, l, fabs(Lsum[ch * K + i]),
                                    SSS_PROBE_SH_MAX);
                }
            }
    }
    free(env);
    return SSS_OK;
}

typedef void (*rule_fn)(const plan_in *, sss_object_plan *);
/* Single scattering (effects/single.c, docs/layers.md §4): on when its share
 * of the material's reflectance reaches SSS_SINGLE_SHARE_MIN, or as the
 * scene forces it. */
static void rule_single(const plan_in *in, sss_object_plan *p)
{
    const sss_scene_object *o = &in->scene->objects[p->object];
    char why[sizeof p->decisions[0].reason];
    int on;
    if (o->layers.n && !o->single_scattering) { /* layers show only through single scattering */
        on = 1;
        snprintf(why, sizeof why, "the material has %u layer%s over it, which only single scattering shows "
                 "(docs/layers.md 3)", o->layers.n, o->layers.n > 1 ? "s" : "");
    } else {
        on = sss_single_rule(&p->material, p->channels, o->single_scattering, why, sizeof why);
    }
    if (on) p->effects |= SSS_FX_SINGLE;
    decide(p, "single-scattering", on ? "on" : "off", "%s", why);
}

static const rule_fn rules[] = {rule_field,   rule_channels, rule_self_shadow, rule_scene_shadow, rule_lights,
                                rule_storage, rule_gather, rule_single};
/* the rules of a deforming object */
static const rule_fn rules_per_frame[] = {rule_field_per_frame, rule_channels, rule_per_frame};
/* the rules of an editable object */
static const rule_fn rules_editable[] = {rule_editable, rule_channels};

sss_result sss_plan_scene(const sss_scene *scene, const sss_mesh *world, sss_plan *out, sss_error *err)
{
    return sss_plan_scene_limited(scene, world, 0, out, err);
}

sss_result sss_plan_scene_limited(const sss_scene *scene, const sss_mesh *world, uint64_t memory_limit, sss_plan *out,
                                  sss_error *err)
{
    memset(out, 0, sizeof *out);
    if (scene->nlights == 0)
        return sss_fail(err, SSS_ERR_ARG, "%s: /lights: no light: nothing would be visible", scene->path);
    /* the plan's own memory, before it is allocated (docs/robustness.md,
     * item 7): per object its decisions and a row of every light and object */
    const uint64_t need = (uint64_t)scene->nobjects *
                          (sizeof(sss_object_plan) + 4u * ((uint64_t)scene->nobjects + scene->nlights));
    const uint64_t avail = sss_memory_available(memory_limit);
    if (avail && need > avail)
        return sss_fail(err, SSS_ERR_NOMEM, "%s: the plan needs at least %.2f GiB for %u objects x %u lights but %.2f "
                        "GiB is available (estimate before starting; SSS_MEMORY_LIMIT_MB lowers the limit)",
                        scene->path, need / 1073741824.0, scene->nobjects, scene->nlights, avail / 1073741824.0);
    sss_result pr = check_probes(scene, memory_limit, err);
    if (pr != SSS_OK) return pr;
    out->obj = calloc(scene->nobjects, sizeof *out->obj);
    if (!out->obj) return sss_fail(err, SSS_ERR_NOMEM, "planner: out of memory");
    out->nobjects = scene->nobjects;
    const plan_in in = {scene, world};
    for (uint32_t i = 0; i < scene->nobjects; i++) {
        sss_object_plan *p = &out->obj[i];
        p->object = i;
        p->occluders = calloc(scene->nobjects, sizeof *p->occluders);
        p->light_pass = calloc(scene->nlights, sizeof *p->light_pass);
        if (!p->occluders || !p->light_pass) {
            sss_plan_free(out);
            return sss_fail(err, SSS_ERR_NOMEM, "planner: out of memory");
        }
        double lo[3], hi[3];
        p->size = sss_mesh_bounds(&world[i], lo, hi);
        for (int k = 0; k < 3; k++) p->centre[k] = 0.5 * (lo[k] + hi[k]);
        p->convex = sss_mesh_is_convex(&world[i]);
        if (scene->objects[i].editable) {
            if (sss_scene_object_deforms(&scene->objects[i])) {
                sss_plan_free(out);
                return sss_fail(err, SSS_ERR_ARG, "%s: /objects/%u/editable: an editable object that deforms is not "
                                "supported yet (docs/heterogeneous.md sec. 9)", scene->path, i);
            }
            /* the run-time path marches the volume between the surfaces
             * (docs/heterogeneous.md §9.2): it has no surface-only model */
            if (scene->objects[i].hetero.surface && scene->objects[i].hetero.field.kind != SSS_FIELD_NONE) {
                sss_plan_free(out);
                return sss_fail(err, SSS_ERR_ARG, "%s: /objects/%u/material/field/surface: a surface texture on an "
                                "editable object is not supported (docs/heterogeneous.md sec. 9)", scene->path, i);
            }
            for (size_t r = 0; r < sizeof rules_editable / sizeof rules_editable[0]; r++) rules_editable[r](&in, p);
            continue;
        }
        /* the field's strength is the run-time path's scale of f; a bake
         * reads f as it is (docs/heterogeneous.md §9.6) */
        if (scene->objects[i].field_strength > 0.0 && scene->objects[i].field_strength != 1.0) {
            sss_plan_free(out);
            return sss_fail(err, SSS_ERR_ARG, "%s: /objects/%u/material/field/strength: a strength other than 1 is "
                            "drawn by the run-time path only (\"editable\": true; docs/heterogeneous.md sec. 9.6)",
                            scene->path, i);
        }
        if (sss_scene_object_deforms(&scene->objects[i])) {
            p->material = scene->objects[i].material;
            for (size_t r = 0; r < sizeof rules_per_frame / sizeof rules_per_frame[0]; r++) rules_per_frame[r](&in, p);
            uint32_t lit = 0;
            for (uint32_t l = 0; l < scene->nlights; l++) {
                const sss_scene_light *L = &scene->lights[l];
                lit += L->kind == SSS_LIGHT_DIRECTIONAL && L->intensity != 0.0 &&
                       (L->colour[0] != 0 || L->colour[1] != 0 || L->colour[2] != 0);
            }
            if (!lit) {
                sss_plan_free(out);
                return sss_fail(err, SSS_ERR_ARG, "%s: /objects/%u/%s: no directional light of non-zero intensity: "
                                "the per-frame path takes directional lights only (docs/deformable.md)", scene->path, i,
                                scene->objects[i].deform.kind != SSS_DEFORM_NONE ? "deform" : "mesh");
            }
            continue;
        }
        for (size_t r = 0; r < sizeof rules / sizeof rules[0]; r++) rules[r](&in, p);
        sss_result rr = count_exact_rows(scene, p, err);
        if (rr != SSS_OK) {
            sss_plan_free(out);
            return rr;
        }
        if (!(p->effects & (SSS_FX_DIR_EXACT | SSS_FX_DIR_SET | SSS_FX_POINT_SHELLS | SSS_FX_ENV_SH))) {
            sss_plan_free(out);
            return sss_fail(err, SSS_ERR_ARG, "%s: /lights: every light has zero intensity: nothing would be visible",
                            scene->path);
        }
    }
    return SSS_OK;
}

void sss_plan_free(sss_plan *p)
{
    if (!p) return;
    for (uint32_t i = 0; i < p->nobjects; i++) {
        free(p->obj[i].occluders);
        free(p->obj[i].light_pass);
    }
    free(p->obj);
    memset(p, 0, sizeof *p);
}

const char *sss_pass_name(sss_pass_kind k)
{
    return (unsigned)k < SSS_PASS_KINDS ? sss_effect_units[k]->name : "?";
}

static void effects_text(uint32_t m, char *buf, size_t n)
{
    size_t k = 0;
    buf[0] = 0;
    for (uint32_t b = 0; b < SSS_FX_COUNT; b++)
        if (m >> b & 1u) k += (size_t)snprintf(buf + k, k < n ? n - k : 0, "%s%s", k ? " " : "", sss_effect_name(b));
}

void sss_plan_print(const sss_scene *scene, const sss_plan *p, FILE *out)
{
    for (uint32_t i = 0; i < p->nobjects; i++) {
        const sss_object_plan *o = &p->obj[i];
        char fx[200];
        effects_text(o->effects, fx, sizeof fx);
        fprintf(out, "object %u '%s' (%s): effects: %s\n", i, scene->objects[i].name, scene->objects[i].mesh,
                o->per_frame ? "none (per-frame: nothing baked)" : fx);
        for (uint32_t d = 0; d < o->ndecisions; d++)
            fprintf(out, "  %-13s %-18s %s\n", o->decisions[d].effect, o->decisions[d].choice, o->decisions[d].reason);
        fprintf(out, "  passes:");
        int any = 0;
        for (int k = 0; k < SSS_PASS_KINDS; k++)
            if (o->pass_lights[k]) {
                fprintf(out, " %s (%u light%s)", sss_pass_name((sss_pass_kind)k), o->pass_lights[k],
                        o->pass_lights[k] == 1 ? "" : "s");
                any = 1;
            }
        fprintf(out, "%s\n", any ? "" : " none");
    }
}

void sss_plan_add_decisions_json(const sss_object_plan *o, struct cJSON *parent)
{
    cJSON *ds = cJSON_AddArrayToObject(parent, "decisions");
    for (uint32_t d = 0; d < o->ndecisions; d++) {
        cJSON *jd = cJSON_CreateObject();
        cJSON_AddStringToObject(jd, "effect", o->decisions[d].effect);
        cJSON_AddStringToObject(jd, "choice", o->decisions[d].choice);
        cJSON_AddStringToObject(jd, "reason", o->decisions[d].reason);
        cJSON_AddItemToArray(ds, jd);
    }
}

char *sss_plan_json(const sss_scene *scene, const sss_plan *p)
{
    cJSON *root = cJSON_CreateObject();
    if (!root) return NULL;
    cJSON_AddStringToObject(root, "scene", scene->path);
    cJSON *objs = cJSON_AddArrayToObject(root, "objects");
    for (uint32_t i = 0; objs && i < p->nobjects; i++) {
        const sss_object_plan *o = &p->obj[i];
        cJSON *jo = cJSON_CreateObject();
        cJSON_AddItemToArray(objs, jo);
        cJSON_AddStringToObject(jo, "name", scene->objects[i].name);
        cJSON_AddStringToObject(jo, "mesh", scene->objects[i].mesh);
        cJSON *fx = cJSON_AddArrayToObject(jo, "effects");
        for (uint32_t b = 0; b < SSS_FX_COUNT; b++)
            if (o->effects >> b & 1u) cJSON_AddItemToArray(fx, cJSON_CreateString(sss_effect_name(b)));
        cJSON_AddNumberToObject(jo, "channels", o->channels);
        cJSON_AddBoolToObject(jo, "per_frame", o->per_frame);
        cJSON_AddBoolToObject(jo, "convex", o->convex);
        cJSON_AddBoolToObject(jo, "self_shadow", o->self_shadow);
        cJSON_AddStringToObject(jo, "weights", o->weights == SSS_WEIGHTS_HAT ? "hat" : "point");
        cJSON_AddStringToObject(jo, "compression", o->compress ? "compact" : "none");
        cJSON_AddStringToObject(jo, "near_terms", o->near_runtime ? "runtime" : "baked");
        cJSON_AddStringToObject(jo, "gather", o->gather == SSS_GATHER_TREE ? "tree" : "direct");
        cJSON *occ = cJSON_AddArrayToObject(jo, "occluders");
        for (uint32_t k = 0; k < o->noccluders; k++)
            cJSON_AddItemToArray(occ, cJSON_CreateString(scene->objects[o->occluders[k]].name));
        cJSON *ps = cJSON_AddArrayToObject(jo, "passes");
        for (int k = 0; k < SSS_PASS_KINDS; k++)
            if (o->pass_lights[k]) {
                cJSON *jp = cJSON_CreateObject();
                cJSON_AddStringToObject(jp, "pass", sss_pass_name((sss_pass_kind)k));
                cJSON *ls = cJSON_AddArrayToObject(jp, "lights");
                for (uint32_t l = 0; l < scene->nlights; l++)
                    if (o->light_pass[l] == (uint32_t)k) cJSON_AddItemToArray(ls, cJSON_CreateNumber(l));
                cJSON_AddItemToArray(ps, jp);
            }
        sss_plan_add_decisions_json(o, jo);
    }
    sss_json_utf8(root); /* valid JSON whatever the bytes of a file name (sss/jsontext.h) */
    char *s = cJSON_Print(root);
    cJSON_Delete(root);
    return s;
}
