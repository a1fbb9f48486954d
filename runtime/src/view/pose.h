/* pose.h: sss-view --scene S.json [--time T] [--offscreen] with no .sss
 * file (docs/deformable.md §4): a scene's deforming object posed at a time,
 * its q from the object-space per-frame path (sss/perframe.h), drawn by
 * the renderer as any q is drawn; one pose offscreen, or the window
 * playing time. */
#ifndef SSS_VIEW_POSE_H
#define SSS_VIEW_POSE_H

#include "sss/fileio.h"
#include "sss/render.h"

typedef struct sss_pose_view {
    const char *tool;
    const char *scene;      /* S.json */
    double time;            /* seconds */
    const char *out;        /* IMG.png|IMG.exr (offscreen) */
    const char *shot;       /* --screenshot (window) */
    int width, height;
    int exposure_given;     /* else 1 / the material's flat-slab q */
    const sss_inputs *inputs;
    int splat;              /* offscreen: q per pixel by the splatting (sss/splat_gpu.h), not per vertex */
    int splat_levels;       /* its levels (0: 3) */
    int splat_adaptive;     /* its adaptive selection */
    const char *save_scene; /* an editable object: --save-scene, where E writes the edited scene (NULL: NAME.edited.json) */
} sss_pose_view;

/* Renders the scene's one object at time v->time into v->out with the
 * view parameters p (its camera from the scene). Returns the exit status
 * (0; 1 after a failure; 2 for a scene it cannot draw), messages on stderr
 * in one line each. */
int sss_pose_offscreen(const sss_pose_view *v, sss_view_params *p);

/* The window (app.c) playing the scene's time from v->time: each frame the
 * pose and q at the app's clock (space pauses, '.' and ',' step). Returns
 * the exit status as sss_pose_offscreen does. */
int sss_pose_window(const sss_pose_view *v, sss_view_params *p);

/* Loads v->scene into sc, which must hold one object (the renderer draws
 * one mesh, docs/deformable.md §6); `what` names the object's kind in the
 * refusal ("deforming", "editable"). 0, or 2 after a one-line message. */
struct sss_scene;
int sss_pose_scene_one(const sss_pose_view *v, const char *what, struct sss_scene *sc);

#endif
