/* pose.c: a deforming scene object drawn without a .sss file
 * (docs/deformable.md §4). The mesh is imported once, then for each time t
 * posed (sss/deform.h) and placed (sss_scene_object_world); q of every
 * directional light comes from the object-space per-frame path
 * (sss/perframe.h, Hao–Varshney 2004 §2.3's run-time mode), summed with
 * each light's intensity × colour as the scene's lights are summed for a
 * file (scene_view.c), and handed to the renderer as q computed elsewhere.
 * One pose offscreen (sss_pose_offscreen), or the window playing time
 * (sss_pose_window: the app's clock, space pauses, '.' and ',' step).
 * sss-view is a tool, so like sss-stat it links the precompute library for
 * the importer and the per-frame path (docs/architecture.md §1); the
 * render library does not.
 */
#include "pose.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "sss/cli.h"
#include "sss/clock.h"
#include "sss/deform.h"
#include "sss/field.h"
#include "sss/fieldio.h"
#include "sss/import.h"
#include "sss/perframe.h"
#include "sss/scene.h"
#include "sss/splat_gpu.h"
#include "sss/vec3.h"

/* The scene, its object's rest mesh, the file the renderer draws (its mesh
 * is the pose, updated in place) and the frame's q. */
typedef struct pose_state {
    const sss_pose_view *v;
    sss_scene sc;
    sss_mesh rest;
    sss_bake_file f;
    float *q, *ql;
    uint32_t C;
    sss_perframe_options po;
    double t_pose, t_q; /* seconds of the last frame's stages */
    double shown_t;     /* the time f and q hold (window: NAN before the first) */
    int failed;         /* window: a pose failed; the last one stays */
    char desc[160];
    /* a material field (docs/deformable.md §10): the rest (bind) pose
     * placed in the world, where the field is read, and f there */
    sss_mesh rest_world;
    float *fv;
} pose_state;

static void state_free(pose_state *s)
{
    free(s->q);
    free(s->ql);
    sss_mesh_free(&s->rest);
    sss_mesh_free(&s->f.mesh);
    sss_mesh_free(&s->rest_world);
    free(s->fv);
    sss_scene_free(&s->sc);
}

/* A field: the mesh in its rest (bind) pose placed by the object's
 * transform, and f at each vertex there, so that the material moves with
 * the surface (docs/deformable.md §10). 0, or 1 after a message. */
static int field_open(pose_state *s)
{
    const char *T = s->v->tool;
    sss_scene_object *o = &s->sc.objects[0];
    sss_error err = {{0}};
    sss_mesh bind = {0};
    if (o->field_path[0] && sss_field_load(o->field_path, o->field_grid, &o->hetero.field, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/material/field: %s\n", T, s->v->scene, err.msg);
        return 1;
    }
    if (sss_import_mesh(o->mesh, &bind, NULL, &err) != SSS_OK ||
        sss_scene_object_world(o, &bind, &s->rest_world, &err) != SSS_OK) {
        sss_mesh_free(&bind);
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: %s\n", T, s->v->scene, err.msg);
        return 1;
    }
    sss_mesh_free(&bind);
    if (s->rest_world.nv != s->rest.nv) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: the rest pose has %u vertices, the pose %u\n", T,
                       s->v->scene, s->rest_world.nv, s->rest.nv);
        return 1;
    }
    if (!(s->fv = malloc((size_t)s->rest.nv * sizeof *s->fv))) {
        sss_cli_printf(stderr, "%s: out of memory for %u vertices\n", T, s->rest.nv);
        return 1;
    }
    for (uint32_t v = 0; v < s->rest.nv; v++) {
        const float *p = &s->rest_world.pos[3 * (size_t)v];
        double x[3];
        sss_hetero_to_rest(&o->hetero, (const double[3]){p[0], p[1], p[2]}, x);
        s->fv[v] = (float)sss_field_eval(&o->hetero.field, x);
    }
    return 0;
}

/* The pose at time t into s->f.mesh (positions, normals, areas) and its q
 * into s->q. 0, or 1 after a message. */
static int pose_frame(pose_state *s, double t)
{
    const char *T = s->v->tool;
    const sss_scene_object *o = &s->sc.objects[0];
    sss_error err = {{0}};
    sss_mesh world = {0};
    const double tp0 = sss_now();
    if (o->animated && s->f.mesh.pos) { /* the rig's pose at t: the glTF read again (docs/deformable.md §5) */
        sss_mesh again;
        if (sss_import_mesh_at(o->mesh, t, &again, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: %s\n", T, s->v->scene, err.msg);
            return 1;
        }
        sss_mesh_free(&s->rest);
        s->rest = again;
    }
    if (s->f.mesh.pos && (s->rest.nv != s->f.mesh.nv || s->rest.nf != s->f.mesh.nf)) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: the pose at t = %g s has %u vertices and %u triangles, the "
                       "first had %u and %u\n", T, s->v->scene, t, s->rest.nv, s->rest.nf, s->f.mesh.nv, s->f.mesh.nf);
        return 1;
    }
    if (sss_scene_object_posed(o, &s->rest, t, &world, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0: %s\n", T, s->v->scene, err.msg);
        return 1;
    }
    if (s->f.mesh.pos) { /* the renderer's file keeps its arrays: the pose is copied in */
        memcpy(s->f.mesh.pos, world.pos, 3 * (size_t)world.nv * sizeof(float));
        memcpy(s->f.mesh.nrm, world.nrm, 3 * (size_t)world.nv * sizeof(float));
        memcpy(s->f.mesh.area, world.area, (size_t)world.nv * sizeof(double));
        sss_mesh_free(&world);
    } else {
        s->f.mesh = world;
    }
    const double t0 = sss_now();
    s->t_pose = t0 - tp0;
    const uint32_t nv = s->f.mesh.nv, C = s->C;
    memset(s->q, 0, (size_t)nv * C * sizeof *s->q);
    if (s->v->splat) { /* the splatting computes q on the GPU from the pose itself */
        s->t_q = 0;
        s->shown_t = t;
        return 0;
    }
    const double mpw = sss_scene_object_mm_per_world_unit(o);
    for (uint32_t l = 0; l < s->sc.nlights; l++) {
        const sss_scene_light *L = &s->sc.lights[l];
        if (L->kind != SSS_LIGHT_DIRECTIONAL || L->intensity == 0.0) continue;
        if (sss_perframe_q(&s->f.mesh, &o->material, C, mpw, L->direction, &s->po, s->ql, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s: /objects/0: %s\n", T, s->v->scene, err.msg);
            return 1;
        }
        /* a grey object has one value per vertex: coloured lights add up
         * with their mean colour (docs/scenes.md), as for a file */
        double w[3];
        for (int k = 0; k < 3; k++) w[k] = L->intensity * L->colour[k];
        if (C == 1) w[0] = (w[0] + w[1] + w[2]) / 3.0;
        for (size_t i = 0; i < (size_t)nv * C; i++) s->q[i] += (float)(w[i % C] * s->ql[i]);
    }
    s->t_q = sss_now() - t0;
    s->shown_t = t;
    return 0;
}

int sss_pose_scene_one(const sss_pose_view *v, const char *what, sss_scene *sc)
{
    sss_error err = {{0}};
    if (sss_scene_load(v->scene, sc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", v->tool, err.msg);
        return 2;
    }
    if (sc->nobjects != 1) {
        sss_cli_printf(stderr, "%s: %s: /objects: %u objects: without a .sss file sss-view draws a scene of one "
                       "%s object\n", v->tool, v->scene, sc->nobjects, what);
        return 2;
    }
    return 0;
}

/* Loads and checks the scene, imports the rest mesh and makes the pose at
 * v->time. Returns 0, or the exit status after a message (2: a scene it
 * cannot draw; 1: a failure). */
static int state_open(const sss_pose_view *v, pose_state *s)
{
    const char *T = v->tool;
    memset(s, 0, sizeof *s);
    s->v = v;
    sss_error err = {{0}};
    if (sss_pose_scene_one(v, "deforming", &s->sc) != 0) return 2;
    sss_scene_object *o = &s->sc.objects[0];
    /* the mesh at the first time (a glTF's rig posed there) */
    sss_import_report rep;
    if (sss_import_mesh_at(o->mesh, v->time, &s->rest, &rep, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: %s\n", T, v->scene, err.msg);
        return 1;
    }
    o->animated = rep.animated;
    /* a static object is drawn from its bake, which holds what this path
     * would recompute every frame */
    if (!sss_scene_object_deforms(o)) {
        sss_cli_printf(stderr, "%s: %s: /objects/0: '%s' does not deform: bake it (sss-bake --scene %s -o DIR) and "
                       "draw DIR/%s.sss\n", T, v->scene, o->name, v->scene, o->name);
        return 2;
    }
    uint32_t ndir = 0;
    for (uint32_t l = 0; l < s->sc.nlights; l++) ndir += s->sc.lights[l].kind == SSS_LIGHT_DIRECTIONAL;
    if (!ndir) {
        sss_cli_printf(stderr, "%s: %s: /lights: no directional light: the per-frame path takes directional lights "
                       "only\n", T, v->scene);
        return 2;
    }
    s->C = sss_material_channels(&o->material);
    s->q = calloc((size_t)s->rest.nv * s->C, sizeof *s->q);
    s->ql = malloc((size_t)s->rest.nv * s->C * sizeof *s->ql);
    if (!s->q || !s->ql) {
        sss_cli_printf(stderr, "%s: out of memory for %u vertices\n", T, s->rest.nv);
        return 1;
    }
    /* the paper's point weights unless the scene asks for hat weights,
     * whose corrections cost 30x the rest of a frame on the 100K dragon,
     * and the tree gather (within 2e-3 of the direct sum; both measured in
     * docs/deformable.md §3, §7) */
    s->po = (sss_perframe_options){.mode = SSS_PERFRAME_TREE,
                                   .weights = s->sc.bake.weights == SSS_SCENE_WEIGHTS_HAT ? SSS_WEIGHTS_HAT
                                                                                          : SSS_WEIGHTS_POINT,
                                   .eps = s->sc.bake.eps};
    if (o->hetero.field.kind != SSS_FIELD_NONE) {
        /* the field's kernel varies pair by pair, which the tree's far
         * field cannot take: the exact sum (docs/deformable.md §10) */
        if (field_open(s) != 0) return 1;
        s->po.mode = SSS_PERFRAME_EXACT;
        s->po.hetero = &o->hetero;
        s->po.rest = s->rest_world.pos;
    }
    if (pose_frame(s, v->time) != 0) return 1;
    /* the renderer draws a file: this one holds the pose and the material,
     * and no stored rows (q is supplied) */
    s->f.material = o->material;
    s->f.mm_per_unit = sss_scene_object_mm_per_world_unit(o);
    s->f.channels = s->C;
    s->f.quant = SSS_QUANT_FLOAT;
    return 0;
}

/* The view parameters as sss-view draws a scene's summed q from a file
 * (sss_scene_render_image): q whole, E and the surface terms' light from
 * the command line (--intensity, --light), the scene's camera. */
static void view_params(pose_state *s, sss_view_params *p)
{
    p->near_terms = 0;
    if (!s->v->exposure_given) {
        const double qs = sss_material_slab_q(&s->sc.objects[0].material, s->C);
        p->exposure = qs > 0.0 && isfinite(1.0 / qs) ? 1.0 / qs : 1.0;
    }
    sss_scene_camera_params(&s->sc, &s->f, p);
}

static const char *weights_name(const pose_state *s) { return s->po.weights == SSS_WEIGHTS_HAT ? "hat" : "point"; }

/* The scene's directional lights for the splatting, weighted as pose_frame
 * weighs them (intensity × colour; a grey object: the mean); returns how
 * many (at most SSS_SCENE_LIGHTS_MAX). */
static uint32_t splat_lights(const pose_state *s, double (*dirs)[3], double (*w)[3], uint32_t max)
{
    uint32_t n = 0;
    for (uint32_t l = 0; l < s->sc.nlights && n < max; l++) {
        const sss_scene_light *L = &s->sc.lights[l];
        if (L->kind != SSS_LIGHT_DIRECTIONAL || L->intensity == 0.0) continue;
        for (int k = 0; k < 3; k++) dirs[n][k] = L->direction[k], w[n][k] = L->intensity * L->colour[k];
        if (s->C == 1) w[n][0] = (w[n][0] + w[n][1] + w[n][2]) / 3.0;
        n++;
    }
    return n;
}

#define POSE_SPLAT_LIGHTS 64

int sss_pose_offscreen(const sss_pose_view *v, sss_view_params *p)
{
    const char *T = v->tool;
    pose_state s;
    int rc = state_open(v, &s);
    if (rc != 0) {
        state_free(&s);
        return rc;
    }
    view_params(&s, p);
    sss_error err = {{0}};
    sss_offscreen *ctx = NULL;
    sss_renderer *r = NULL;
    sss_splat_gpu *sp = NULL;
    float *rgb = NULL, *hdr = NULL;
    double td = 0;
    rc = 1;
    sss_result res = sss_offscreen_create(&ctx, &err);
    if (res == SSS_OK) res = sss_renderer_create(&s.f, &r, &err);
    if (res == SSS_OK && v->splat) {
        sss_splat_options so;
        sss_splat_options_default(&so);
        so.levels = v->splat_levels;
        so.adaptive = v->splat_adaptive;
        res = sss_splat_gpu_create(r, &so, &sp, &err);
        if (res == SSS_OK && s.fv) res = sss_splat_gpu_set_field(sp, &s.sc.objects[0].hetero.inside, s.fv, &err);
        if (res == SSS_OK) {
            double dirs[POSE_SPLAT_LIGHTS][3], w[POSE_SPLAT_LIGHTS][3];
            const uint32_t n = splat_lights(&s, dirs, w, POSE_SPLAT_LIGHTS);
            td = sss_now();
            res = sss_splat_gpu_render_image(sp, p, (const double(*)[3])dirs, (const double(*)[3])w, n, v->width,
                                             v->height, &rgb, &hdr, &err);
            td = sss_now() - td;
        }
    } else if (res == SSS_OK) {
        td = sss_now();
        res = sss_renderer_render_q_image(r, p, s.q, v->width, v->height, &rgb, &hdr, &err);
        td = sss_now() - td;
    }
    if (res == SSS_OK) res = sss_write_image_with(v->out, rgb, hdr, v->width, v->height, v->inputs, &err);
    if (res != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", T, err.msg);
    } else {
        char motion[96], how[192];
        sss_scene_object_motion(&s.sc.objects[0], v->time, motion, sizeof motion);
        if (sp) {
            const sss_splat_times st = sss_splat_gpu_times(sp);
            snprintf(how, sizeof how, "q per pixel by the GPU splatting (%d levels, %s selection; GPU ms: buffers "
                     "%.1f, levels %.1f/%.1f/%.1f, accumulation %.1f)", v->splat_levels ? v->splat_levels : 3,
                     v->splat_adaptive ? "adaptive" : "uniform", st.buffers_ms, st.level_ms[0], st.level_ms[1],
                     st.level_ms[2], st.accum_ms);
        } else {
            snprintf(how, sizeof how, "q per frame on the CPU (%s, %s weights) in %.3f s",
                     s.fv ? "exact sum, the field read at the rest pose" : "tree gather", weights_name(&s), s.t_q);
        }
        sss_cli_printf(stderr, "%s: %s: %dx%d, %s, '%s' at t = %g s (%s), %u vertices, %s; pose %.3f s, draw %.3f s\n",
                       T, v->out, v->width, v->height, sss_gl_renderer_name(), s.sc.objects[0].name, v->time, motion,
                       s.f.mesh.nv, how, s.t_pose, td);
        rc = 0;
    }
    free(rgb);
    free(hdr);
    sss_splat_gpu_destroy(sp);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    state_free(&s);
    return rc;
}

/* The window's frame: the pose and q at the app's clock (recomputed only
 * when it moved: a paused clock costs nothing), uploaded into the
 * renderer (app.h's frame_gpu hook). */
static const char *window_frame(void *user, const sss_view_params *p, sss_renderer *r, double t)
{
    (void)p;
    pose_state *s = user;
    if (!r) return NULL;
    t += s->v->time; /* the clock starts at --time */
    if (t != s->shown_t && !s->failed) {
        /* a failure (said once) leaves the last pose on screen: the
         * renderer has no stored rows to fall back on */
        if (pose_frame(s, t) != 0) {
            s->failed = 1;
            snprintf(s->desc, sizeof s->desc, "t = %.2f s: the pose failed (see the terminal)", t);
            return s->desc;
        }
        sss_renderer_update_geometry(r);
        char motion[96];
        sss_scene_object_motion(&s->sc.objects[0], t, motion, sizeof motion);
        snprintf(s->desc, sizeof s->desc, "t = %.2f s (%s): pose %.0f ms, q %.0f ms on the CPU", t, motion,
                 1e3 * s->t_pose, 1e3 * s->t_q);
    }
    sss_renderer_upload_q(r, s->q);
    return s->desc;
}

int sss_pose_window(const sss_pose_view *v, sss_view_params *p)
{
    pose_state s;
    int rc = state_open(v, &s);
    if (rc == 0) {
        view_params(&s, p);
        s.shown_t = NAN; /* the first frame uploads the pose */
        sss_app_options ao = {.file_path = v->scene, .width = v->width, .height = v->height,
                              .screenshot_path = v->shot, .user = &s, .frame_gpu = window_frame};
        rc = sss_app_run(&s.f, p, &ao);
    }
    state_free(&s);
    return rc;
}
