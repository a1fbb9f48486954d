/* panel.h: the viewer's control panel (Dear ImGui, panel.cpp), for the C app.
 *
 * The panel shows what the file holds (docs/viewer.md, "The panel") and
 * edits the sss_view_params the app draws with: light direction, intensity
 * and colour, exposure and tone map, the effects the file carries, the exit
 * term, and a graph of the frame time per stage; for an editable object,
 * its live material. It exists in the window
 * only (app.c); offscreen rendering never creates it.
 *
 * Per frame: sss_panel_frame before the scene is evaluated (its edits apply
 * to this very frame), sss_panel_render after the scene and the overlay are
 * drawn (the panel lies on top of both).
 *
 * Layout is fixed and nothing is saved between runs (no imgui.ini): the
 * panel sits at the window's top right corner, 300 pixels wide, so a script
 * clicks known coordinates (tests/integration/window_xvfb.sh).
 */
#ifndef SSS_PANEL_H
#define SSS_PANEL_H

#include "sss/htsm.h"
#include "sss/render.h"

#ifdef __cplusplus
extern "C" {
#endif

struct GLFWwindow;
typedef struct sss_panel sss_panel;

/* What the panel shows but does not edit, for one frame. */
typedef struct sss_panel_info {
    const sss_bake_file *f;
    const char *file_path;
    const char *storage;       /* sss_storage_describe of f */
    double bytes_per_vertex;   /* sss_renderer_bytes_per_vertex */
    const char *scene_desc;    /* the scene's GPU sum, or NULL */
    int scene;                 /* 1: a scene's lights are drawn (sss-view --scene) */
    double exposure0;          /* the exposure the viewer started with: the slider's centre */
    sss_frame_times times;     /* the previous frame's, as sss_renderer_times gives them */
    double frame_ms;           /* the previous frame's wall-clock time */
    sss_scene_eval *scene_eval; /* the scene's sum (NULL without one): its light kinds are switched here */
    /* an editable object's live material (edit.c, docs/heterogeneous.md
     * §9.1), edited here as by its keys; NULL otherwise */
    sss_htsm_material *edit;
    double transport_mm;       /* the distance at which edit's base reaches its transport colour */
    int *edit_save;            /* set to 1 by the live material's "write the scene" button (the app acts as on E) */
} sss_panel_info;

/* Creates the ImGui context on win (whose GL context is current) and installs
 * ImGui's GLFW callbacks, which call the ones set on win before (so the app
 * sets its own first). Returns NULL with a one-line reason in err when the
 * GL backend cannot be set up. */
sss_panel *sss_panel_create(struct GLFWwindow *win, sss_error *err);
/* Restores win's callbacks, frees every ImGui object and the context. NULL-safe. */
void sss_panel_destroy(sss_panel *pn);

/* Starts the frame; when show is set, lays the panel out and applies its
 * edits to p. Hidden, the panel still runs an empty frame, so ImGui's input
 * state stays current and a click made while it was hidden never lands on
 * a control when it opens. */
void sss_panel_frame(sss_panel *pn, int show, sss_view_params *p, const sss_panel_info *info);
/* Draws the frame's panel into the bound framebuffer (GL state restored). */
void sss_panel_render(sss_panel *pn);

/* 1 when the point (window coordinates) is over the panel or ImGui owns the
 * mouse (a slider being dragged): the app then starts no camera or light
 * drag and no zoom. */
int sss_panel_wants_mouse(const sss_panel *pn, double x, double y);
/* 1 while a control takes typed text (a value entered after Ctrl+click):
 * the app's keys wait until it is done. */
int sss_panel_wants_keyboard(const sss_panel *pn);

#ifdef __cplusplus
}
#endif
#endif
