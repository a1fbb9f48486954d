/* edit.c: an editable scene object drawn without a .sss file (edit.h,
 * docs/heterogeneous.md §9). The mesh is imported and placed once; the
 * renderer draws a file that holds only the mesh and the base material,
 * and q comes per pixel from seed 000's run-time path (sss/htsm_gpu.h),
 * whose materials are uniforms: a key's edit shows in the next frame.
 */
#include "edit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE /* epoxy provides the GL declarations */
#include <GLFW/glfw3.h>

#include "app.h"
#include "sss/cli.h"
#include "sss/clock.h"
#include "sss/htsm_gpu.h"
#include "sss/import.h"
#include "sss/scene.h"
#include "sss/scene_edit.h"

/* The transport colours Y steps through (Shopf 2007 §4.3.3's examples:
 * wax, juice, jade, milk), reached after the base's transport distance. */
static const double TRANSPORT[4][3] = {{0.85, 0.55, 0.25}, {0.9, 0.3, 0.15}, {0.35, 0.8, 0.45}, {0.8, 0.8, 0.8}};
#define TRANSPORT_MM 10.0

typedef struct edit_state {
    const sss_pose_view *v;
    sss_scene sc;
    sss_bake_file f;
    sss_htsm_view hv;
    sss_htsm_gpu *g;
    int transport; /* the next of TRANSPORT for Y */
    char desc[200];
} edit_state;

static int save_scene(const edit_state *s);

int sss_edit_wanted(const char *scene_path)
{
    sss_scene sc;
    sss_error err = {{0}};
    if (sss_scene_load(scene_path, &sc, &err) != SSS_OK) return 0;
    const int yes = sc.nobjects >= 1 && sc.objects[0].editable;
    sss_scene_free(&sc);
    return yes;
}

static void state_free(edit_state *s)
{
    sss_mesh_free(&s->f.mesh);
    sss_scene_free(&s->sc);
}

static int state_open(const sss_pose_view *v, edit_state *s, sss_view_params *p)
{
    const char *T = v->tool;
    memset(s, 0, sizeof *s);
    s->v = v;
    sss_error err = {{0}};
    if (sss_pose_scene_one(v, "editable", &s->sc) != 0) return 2;
    const sss_scene_object *o = &s->sc.objects[0];
    if (sss_scene_object_deforms(o)) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/editable: an editable object that deforms is not supported yet\n",
                       T, v->scene);
        return 2;
    }
    sss_mesh rest = {0};
    sss_import_report rep;
    if (sss_import_mesh_at(o->mesh, 0.0, &rest, &rep, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: %s\n", T, v->scene, err.msg);
        return 1;
    }
    sss_result r = sss_scene_object_posed(o, &rest, 0.0, &s->f.mesh, &err);
    sss_mesh_free(&rest);
    if (r != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0: %s\n", T, v->scene, err.msg);
        return 1;
    }
    /* the file the renderer draws: the mesh and the base material, no rows */
    s->f.material = o->material;
    s->f.mm_per_unit = sss_scene_object_mm_per_world_unit(o);
    s->f.channels = 3;
    s->f.quant = SSS_QUANT_FLOAT;
    sss_htsm_view_default(&s->hv, &s->f, &o->hetero);
    if (o->field_strength > 0.0) s->hv.mat.strength = o->field_strength;
    uint32_t skipped = 0;
    const uint32_t drawn = sss_htsm_view_lights(&s->hv, p, &s->sc, &s->f.mesh, &skipped);
    /* each point light left out for its place, in the planner's words (--plan) */
    for (uint32_t l = 0; l < s->sc.nlights; l++) {
        const sss_scene_light *L = &s->sc.lights[l];
        double R = 0.0;
        if (L->kind == SSS_LIGHT_POINT && L->intensity != 0.0 && !sss_htsm_point_drawn(&s->f.mesh, L->position, &R)) {
            char why[320];
            sss_htsm_point_inside_msg(why, sizeof why, L->position, o->name, R);
            sss_cli_printf(stderr, "%s: %s: /lights/%u: %s\n", T, v->scene, l, why);
        }
    }
    if (!drawn) {
        sss_cli_printf(stderr, "%s: %s: /lights: no directional or point light of non-zero intensity outside the "
                       "object: the run-time path draws no other\n", T, v->scene);
        return 2;
    }
    if (skipped)
        sss_cli_printf(stderr, "%s: %s: /lights: %u light(s) not drawn: the run-time path sums up to %d directional "
                       "and point lights, no environment light and no point light within the object's bounding "
                       "sphere\n", T, v->scene, skipped, SSS_HTSM_MAX_LIGHTS);
    if (!v->exposure_given) {
        const double qs = sss_material_slab_q(&o->material, 3);
        p->exposure = qs > 0.0 && isfinite(1.0 / qs) ? 1.0 / qs : 1.0;
    }
    p->near_terms = 0;
    p->single = -1;
    sss_scene_camera_params(&s->sc, &s->f, p);
    return 0;
}

static sss_result make_gpu(edit_state *s, sss_renderer *r, sss_error *err)
{
    const sss_hetero *h = &s->sc.objects[0].hetero;
    return sss_htsm_gpu_create(r, h->field.kind != SSS_FIELD_NONE ? h : NULL, 0, 0, &s->g, err);
}

int sss_edit_offscreen(const sss_pose_view *v, sss_view_params *p)
{
    const char *T = v->tool;
    edit_state s;
    int rc = state_open(v, &s, p);
    if (rc != 0) {
        state_free(&s);
        return rc;
    }
    sss_error err = {{0}};
    sss_offscreen *ctx = NULL;
    sss_renderer *r = NULL;
    float *rgb = NULL, *hdr = NULL;
    double ms = 0;
    sss_result res = sss_offscreen_create(&ctx, &err);
    if (res == SSS_OK) res = sss_renderer_create(&s.f, &r, &err);
    if (res == SSS_OK) res = make_gpu(&s, r, &err);
    if (res == SSS_OK) res = sss_htsm_gpu_frame(s.g, &s.hv, p, v->width, v->height, &ms, &err);
    if (res == SSS_OK) res = sss_htsm_gpu_render_image(s.g, &s.hv, p, v->width, v->height, &rgb, &hdr, &err);
    if (res == SSS_OK) res = sss_write_image_with(v->out, rgb, hdr, v->width, v->height, v->inputs, &err);
    if (res != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", T, err.msg);
        rc = 1;
    } else {
        sss_cli_printf(stderr, "%s: %s: %dx%d, %s, '%s' editable, %u vertices, q per pixel by the run-time path "
                       "(%u samples, %u steps) in %.1f ms\n", T, v->out, v->width, v->height, sss_gl_renderer_name(),
                       s.sc.objects[0].name, s.f.mesh.nv, s.hv.n, s.hv.steps, ms);
        if (v->save_scene) rc = save_scene(&s);
    }
    free(rgb);
    free(hdr);
    sss_htsm_gpu_destroy(s.g);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    state_free(&s);
    return rc;
}

/* The scene with the live material written to v->save_scene, or
 * NAME.edited.json next to it (docs/heterogeneous.md §9.6): its path in one
 * line, or the reason it was not written. 0 or 1. */
static int save_scene(const edit_state *s)
{
    const char *T = s->v->tool;
    char def[SSS_SCENE_PATH_MAX + 16];
    sss_error err = {{0}};
    const char *out = s->v->save_scene;
    if (!out && sss_scene_edited_path(s->v->scene, def, sizeof def, &err) == SSS_OK) out = def;
    if (!out || sss_scene_write_edited(s->v->scene, 0, &s->hv.mat, out, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: edited scene not written: %s\n", T, err.msg);
        return 1;
    }
    sss_cli_printf(stderr, "%s: edited scene written to %s\n", T, out);
    return 0;
}

/* J / K, U / I, Y: the live edits (edit.h); E: the edit written back. */
static int on_key(void *user, int key)
{
    edit_state *s = user;
    sss_htsm_material *m = &s->hv.mat;
    switch (key) {
    case GLFW_KEY_J:
    case GLFW_KEY_K:
        for (int c = 0; c < 3; c++) m->inside.sigma_a[c] *= key == GLFW_KEY_K ? 1.5 : 1.0 / 1.5;
        return 1;
    case GLFW_KEY_U:
    case GLFW_KEY_I: m->strength = fmin(64.0, fmax(1.0 / 64.0, m->strength * (key == GLFW_KEY_I ? 1.25 : 0.8))); return 1;
    case GLFW_KEY_E: save_scene(s); return 1;
    case GLFW_KEY_Y: {
        double sa[3];
        sss_error err = {{0}};
        if (sss_transport_sigma_a(TRANSPORT[s->transport], TRANSPORT_MM, m->base.sigmap_s, sa, &err) == SSS_OK)
            memcpy(m->base.sigma_a, sa, sizeof sa);
        s->transport = (s->transport + 1) % 4;
        return 1;
    }
    default: return 0;
    }
}

/* Each frame: the pass at the window's size into the q the draw shades. */
static const char *window_frame(void *user, const sss_view_params *p, sss_renderer *r, double t)
{
    (void)t;
    edit_state *s = user;
    if (!r) {
        sss_htsm_gpu_destroy(s->g);
        s->g = NULL;
        return NULL;
    }
    sss_error err = {{0}};
    if (!s->g && make_gpu(s, r, &err) != SSS_OK) {
        snprintf(s->desc, sizeof s->desc, "run-time path unavailable: %.150s", err.msg);
        return s->desc;
    }
    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    double ms = 0;
    if (sss_htsm_gpu_frame(s->g, &s->hv, p, vp[2], vp[3], &ms, &err) != SSS_OK ||
        sss_htsm_gpu_attach(s->g, 1) != SSS_OK) {
        snprintf(s->desc, sizeof s->desc, "run-time path failed: %.150s", err.msg);
        return s->desc;
    }
    const sss_htsm_material *m = &s->hv.mat;
    snprintf(s->desc, sizeof s->desc, "editable: inside sigma_a %.3g/%.3g/%.3g, strength %.3g, base sigma_a "
             "%.3g/%.3g/%.3g; %u samples x %u steps, %.1f ms", m->inside.sigma_a[0], m->inside.sigma_a[1],
             m->inside.sigma_a[2], m->strength, m->base.sigma_a[0], m->base.sigma_a[1], m->base.sigma_a[2], s->hv.n,
             s->hv.steps, ms);
    return s->desc;
}

int sss_edit_window(const sss_pose_view *v, sss_view_params *p)
{
    edit_state s;
    int rc = state_open(v, &s, p);
    if (rc == 0) {
        sss_app_options ao = {.file_path = v->scene, .width = v->width, .height = v->height,
                              .screenshot_path = v->shot, .user = &s, .frame_gpu = window_frame, .key = on_key,
                              .edit = &s.hv.mat, .transport_mm = TRANSPORT_MM};
        rc = sss_app_run(&s.f, p, &ao);
    }
    sss_htsm_gpu_destroy(s.g);
    state_free(&s);
    return rc;
}
