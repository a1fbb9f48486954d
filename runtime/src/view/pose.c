/* pose.c: one pose of a deforming scene object drawn offscreen without a
 * .sss file (docs/deformable.md §4). The mesh is imported, posed at time t
 * (sss/deform.h) and placed (sss_scene_object_world); q of every
 * directional light comes from the object-space per-frame path
 * (sss/perframe.h, Hao–Varshney 2004 §2.3's run-time mode), summed with
 * each light's intensity × colour as the scene's lights are summed for a
 * file (scene_view.c), and handed to the renderer as q computed elsewhere
 * (sss_renderer_render_q_image). sss-view is a tool, so like sss-stat it
 * links the precompute library for the importer and the per-frame path
 * (docs/architecture.md §1); the render library does not.
 */
#include "pose.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/cli.h"
#include "sss/clock.h"
#include "sss/deform.h"
#include "sss/import.h"
#include "sss/perframe.h"
#include "sss/scene.h"
#include "sss/vec3.h"

int sss_pose_offscreen(const sss_pose_view *v, sss_view_params *p)
{
    const char *T = v->tool;
    sss_error err = {{0}};
    sss_scene sc;
    if (sss_scene_load(v->scene, &sc, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", T, err.msg);
        return 2;
    }
    int rc = 2;
    sss_mesh rest = {0}, posed = {0}, world = {0};
    float *q = NULL, *ql = NULL, *rgb = NULL, *hdr = NULL;
    sss_offscreen *ctx = NULL;
    sss_renderer *r = NULL;
    /* one object: the renderer draws one mesh (docs/deformable.md §6) */
    if (sc.nobjects != 1) {
        sss_cli_printf(stderr, "%s: %s: /objects: %u objects: without a .sss file sss-view draws a scene of one "
                       "deforming object\n", T, v->scene, sc.nobjects);
        goto done;
    }
    const sss_scene_object *o = &sc.objects[0];
    /* a static object is drawn from its bake, which holds what this path
     * would recompute every frame */
    if (o->deform.kind == SSS_DEFORM_NONE) {
        sss_cli_printf(stderr, "%s: %s: /objects/0: '%s' does not deform: bake it (sss-bake --scene %s -o DIR) and "
                       "draw DIR/%s.sss\n", T, v->scene, o->name, v->scene, o->name);
        goto done;
    }
    uint32_t ndir = 0;
    for (uint32_t l = 0; l < sc.nlights; l++) ndir += sc.lights[l].kind == SSS_LIGHT_DIRECTIONAL;
    if (!ndir) {
        sss_cli_printf(stderr, "%s: %s: /lights: no directional light: the per-frame path takes directional lights "
                       "only\n", T, v->scene);
        goto done;
    }
    rc = 1;
    if (sss_import_mesh(o->mesh, &rest, NULL, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0/mesh: %s\n", T, v->scene, err.msg);
        goto done;
    }
    const double tp0 = sss_now();
    if (sss_deform_pose(&o->deform, v->time, &rest, o->name, &posed, &err) != SSS_OK ||
        sss_scene_object_world(o, &posed, &world, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: /objects/0: %s\n", T, v->scene, err.msg);
        goto done;
    }
    const uint32_t C = sss_material_channels(&o->material), nv = world.nv;
    q = calloc((size_t)nv * C, sizeof *q);
    ql = malloc((size_t)nv * C * sizeof *ql);
    if (!q || !ql) {
        sss_cli_printf(stderr, "%s: out of memory for %u vertices\n", T, nv);
        goto done;
    }
    /* the paper's point weights unless the scene asks for hat weights,
     * whose corrections cost 30x the rest of a frame on the 100K dragon,
     * and the tree gather (within 2e-3 of the direct sum; both measured in
     * docs/deformable.md §3, §7) */
    sss_perframe_options po = {.mode = SSS_PERFRAME_TREE,
                               .weights = sc.bake.weights == SSS_SCENE_WEIGHTS_HAT ? SSS_WEIGHTS_HAT
                                                                                   : SSS_WEIGHTS_POINT,
                               .eps = sc.bake.eps};
    const double mpw = sss_scene_object_mm_per_world_unit(o);
    const double t0 = sss_now();
    const double t_pose = t0 - tp0;
    for (uint32_t l = 0; l < sc.nlights; l++) {
        const sss_scene_light *L = &sc.lights[l];
        if (L->kind != SSS_LIGHT_DIRECTIONAL || L->intensity == 0.0) continue;
        if (sss_perframe_q(&world, &o->material, C, mpw, L->direction, &po, ql, NULL, &err) != SSS_OK) {
            sss_cli_printf(stderr, "%s: %s: /objects/0: %s\n", T, v->scene, err.msg);
            goto done;
        }
        /* a grey object has one value per vertex: coloured lights add up
         * with their mean colour (docs/scenes.md), as for a file */
        double w[3];
        for (int k = 0; k < 3; k++) w[k] = L->intensity * L->colour[k];
        if (C == 1) w[0] = (w[0] + w[1] + w[2]) / 3.0;
        for (size_t i = 0; i < (size_t)nv * C; i++) q[i] += (float)(w[i % C] * ql[i]);
    }
    const double tq = sss_now() - t0;
    /* the renderer draws a file: this one holds the pose and the material,
     * and no stored rows (q is supplied) */
    sss_bake_file f;
    memset(&f, 0, sizeof f);
    f.mesh = world;
    f.material = o->material;
    f.mm_per_unit = mpw;
    f.channels = C;
    f.quant = SSS_QUANT_FLOAT;
    /* drawn as sss-view draws a scene's summed q from a file
     * (sss_scene_render_image): q whole, E and the surface terms' light
     * from the command line (--intensity, --light), so that the two images
     * of one pose agree (view_deform) */
    p->near_terms = 0;
    if (!v->exposure_given) {
        const double qs = sss_material_slab_q(&o->material, C);
        p->exposure = qs > 0.0 && isfinite(1.0 / qs) ? 1.0 / qs : 1.0;
    }
    sss_scene_camera_params(&sc, &f, p);
    double td = 0;
    if (sss_offscreen_create(&ctx, &err) != SSS_OK || sss_renderer_create(&f, &r, &err) != SSS_OK ||
        (td = sss_now(), sss_renderer_render_q_image(r, p, q, v->width, v->height, &rgb, &hdr, &err)) != SSS_OK ||
        (td = sss_now() - td, sss_write_image_with(v->out, rgb, hdr, v->width, v->height, v->inputs, &err)) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", T, err.msg);
        goto done;
    }
    sss_cli_printf(stderr, "%s: %s: %dx%d, %s, '%s' at t = %g s (%s, theta %.4g deg), %u vertices, q per frame on "
                   "the CPU (tree gather, %s weights) in %.3f s; pose %.3f s, draw %.3f s\n", T, v->out, v->width,
                   v->height, sss_gl_renderer_name(), o->name, v->time, sss_deform_kind_name(o->deform.kind),
                   sss_deform_angle(&o->deform, v->time) * 180.0 / SSS_PI, nv,
                   po.weights == SSS_WEIGHTS_HAT ? "hat" : "point", tq, t_pose, td);
    rc = 0;
done:
    free(rgb);
    free(hdr);
    free(q);
    free(ql);
    sss_renderer_destroy(r);
    sss_offscreen_destroy(ctx);
    sss_mesh_free(&rest);
    sss_mesh_free(&posed);
    sss_mesh_free(&world);
    sss_scene_free(&sc);
    return rc;
}
