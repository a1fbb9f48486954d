/* app.h: the interactive GLFW window of sss-view. */
#ifndef SSS_APP_H
#define SSS_APP_H

#include "sss/htsm.h"
#include "sss/render.h"

typedef struct sss_app_options {
    const char *file_path;       /* for the title and overlay */
    int width, height;           /* initial window size */
    const char *screenshot_path; /* where 'P' saves a PNG (NULL: sss-view-NNN.png in the cwd) */
    /* Optional (NULL: the renderer's own evaluation for the light under the
     * mouse): per-vertex q of each frame, t in seconds; sss-view --scene
     * sums the scene's lights here (scene_view.c, docs/scenes.md). */
    void (*frame_q)(void *user, const sss_view_params *p, double t, float *q);
    void *user;
    /* Optional: writes the frame's q into the renderer's q buffer on the GPU
     * (sss-view --scene: fx_gpu.c) and returns a one-line description for
     * the overlay, or NULL when it did not (frame_q is then used). Called
     * with r NULL before the renderer and context go, to release its GL
     * objects. Both sums hold the near terms of an OWNT file as p asks, so
     * the frame is drawn without adding them again. */
    const char *(*frame_gpu)(void *user, const sss_view_params *p, sss_renderer *r, double t);
    /* Optional: the scene sum behind frame_q / frame_gpu, whose light kinds
     * the panel switches on and off (sss_scene_eval_set_kinds). */
    sss_scene_eval *scene_eval;
    /* Optional: a key press (GLFW key code) the caller handles itself
     * before the window's own table; returns 1 when it did (sss-view on an
     * editable object: the live material keys, edit.c). */
    int (*key)(void *user, int key);
    /* Optional: an editable object's live material, which the panel edits
     * as the keys do (edit.c), and its transport distance, mm. */
    sss_htsm_material *edit;
    double transport_mm;
} sss_app_options;

/* Opens a window, runs the event loop until closed (Esc / Q / window close),
 * returns the process exit code (0 ok, 1 when no window or GL context could
 * be created, with a one-line message on stderr). f must stay alive. */
int sss_app_run(const sss_bake_file *f, const sss_view_params *initial, const sss_app_options *opt);

/* The controls, one per line, for --help. */
extern const char *sss_app_controls_help;

#endif
