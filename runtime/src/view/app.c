/* app.c: the interactive window of sss-view (app.h).
 *
 * One GLFW window with an OpenGL 4.5 (or 4.3) core context. Every frame
 * re-evaluates the scattering for the current light (that per-frame
 * evaluation is what the viewer exists to show and time), draws the mesh
 * into the default framebuffer, draws the text overlay on top and swaps.
 * Input only edits the sss_view_params; nothing else is cached, so a frame
 * is always a pure function of those parameters.
 */
#define _POSIX_C_SOURCE 200809L /* stat() under -std=c11 */
#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE /* epoxy provides the GL declarations */
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "app.h"
#include "font.h"
#include "panel.h"
#include "sss/decode.h" /* sss_interp */
#include "sss/cli.h"
#include "sss/fileio.h"
#include "sss/render.h"
#include "sss/vec3.h"

static const char *TOOL = "sss-view";

const char *sss_app_controls_help =
    "  left drag                     orbit the camera\n"
    "  right drag, Shift+left drag   pan\n"
    "  scroll wheel                  zoom (distance 1.2 to 20 bounding radii)\n"
    "  Ctrl+left drag, L+left drag   move the light (in the camera frame)\n"
    "  arrow keys                    rotate the light (left/right: world up axis, up/down: camera right axis)\n"
    "  + / -                         light intensity x1.25 / /1.25 (keypad too)\n"
    "  [ / ]                         exposure /1.25 / x1.25\n"
    "  1 / 2 / 3                     scattering only / reflection only / both\n"
    "  C                             toggle CPU / GPU evaluation path\n"
    "  W                             toggle wireframe\n"
    "  O                             toggle the near terms of a file baked with --own-term runtime\n"
    "  V                             their visibility: the bake's rays / a shadow map\n"
    "  S                             toggle the shadow of the surface terms (specular, diffuse)\n"
    "  X                             toggle single scattering per pixel (docs/layers.md section 8)\n"
    "  D                             diffuse share of the reflected light: 0 / 0.25 / 0.5 / 1\n"
    "  N                             interpolation of q: triangle / the paper's 4 nearest samples\n"
    "  T                             toggle tone map clamp / Reinhard\n"
    "  R                             reset camera and light (direction and intensity)\n"
    "  P                             save a screenshot PNG (--screenshot FILE, else sss-view-NNN.png)\n"
    "  space                         pause / play the scene's time (moving lights, a deforming object)\n"
    "  . / ,                         step the time by +1/30 s / -1/30 s (and pause)\n"
    "  H                             toggle the overlay\n"
    "  G                             toggle the panel (light, exposure, effects, frame times, the file)\n"
    "  J / K                         editable object: inside material's absorption /1.5 / x1.5\n"
    "  U / I                         editable object: the field's strength /1.25 / x1.25\n"
    "  Y                             editable object: the next transport colour of the base material\n"
    "  E                             editable object: write the scene with the edited material (--save-scene)\n"
    "  Esc, Q                        quit\n";

typedef enum drag_mode { DRAG_NONE, DRAG_ORBIT, DRAG_PAN, DRAG_LIGHT } drag_mode;

typedef struct app {
    GLFWwindow *win;
    sss_renderer *r;
    sss_text *text;
    sss_panel *panel;  /* NULL when ImGui could not start: keys and overlay only */
    const sss_bake_file *f;
    const sss_app_options *opt;
    const char *scene_desc; /* the GPU scene sum's line for the overlay, or NULL */
    char storage[128];      /* sss_storage_describe of f, for the overlay */
    sss_view_params p, initial;
    drag_mode drag;
    int drag_button;
    double mx, my;     /* last cursor position, window coordinates */
    int overlay;
    int show_panel;
    int want_shot;     /* 'P' seen: save after the next frame is drawn */
    int edit_save;     /* the panel's "write the scene" pressed: handled as the key E */
    double last_t;     /* start of the previous frame, seconds */
    /* the time the frame callbacks get: runs with the wall clock unless
     * paused (space); '.' and ',' step it by 1/30 s (docs/deformable.md §4) */
    double clock;
    int paused;
    double frame_ms, scatter_ms, draw_ms, near_ms; /* smoothed for a readable overlay */
    int frames;
} app;

/* ---- rotations ----------------------------------------------------------- */

/* Rotates v by angle (radians, right-handed) around the unit axis a (Rodrigues). */
static void rotate3(double v[3], const double a[3], double angle)
{
    double c = cos(angle), s = sin(angle), d = a[0] * v[0] + a[1] * v[1] + a[2] * v[2];
    double x[3] = {a[1] * v[2] - a[2] * v[1], a[2] * v[0] - a[0] * v[2], a[0] * v[1] - a[1] * v[0]};
    for (int k = 0; k < 3; k++) v[k] = v[k] * c + x[k] * s + a[k] * d * (1 - c);
}

static double clampd(double x, double lo, double hi) { return x < lo ? lo : x > hi ? hi : x; }

/* ---- camera and light edits -------------------------------------------- */

/* The world's up: the view's (a scene camera's "up"), else +y. */
static void world_up(const app *a, double u[3])
{
    memcpy(u, a->p.up, 3 * sizeof *u);
    if (!(sss_normalize3(u) > 0)) u[0] = 0, u[1] = 1, u[2] = 0;
}

/* Orbit in azimuth/elevation: a horizontal drag turns around the world up
 * axis, a vertical one around the camera's right axis. The elevation stops
 * short of the poles because the renderer switches its up vector there,
 * which would flip the picture under the cursor. */
static void orbit(app *a, double dx, double dy, double rad_per_px)
{
    double u[3], v[3] = {a->p.view[0], a->p.view[1], a->p.view[2]};
    world_up(a, u);
    sss_normalize3(v);
    const double el = clampd(asin(clampd(sss_dot3(v, u), -1, 1)) + dy * rad_per_px, -1.50, 1.50);
    double h[3]; /* the view's horizontal part, turned about up */
    for (int k = 0; k < 3; k++) h[k] = v[k] - sss_dot3(v, u) * u[k];
    if (!(sss_normalize3(h) > 0)) return;
    rotate3(h, u, -dx * rad_per_px);
    for (int k = 0; k < 3; k++) a->p.view[k] = cos(el) * h[k] + sin(el) * u[k];
}

/* Pan so the point under the cursor follows it: the visible height at the
 * target is 2·d·tan(fov/2) bounding radii. */
static void pan(app *a, double dx, double dy, int win_h)
{
    double fov = (a->p.fov_deg > 0 ? a->p.fov_deg : 35.0) * SSS_PI / 180.0;
    double per_px = 2.0 * a->p.distance * tan(0.5 * fov) / win_h;
    a->p.pan[0] = clampd(a->p.pan[0] - dx * per_px, -10, 10);
    a->p.pan[1] = clampd(a->p.pan[1] + dy * per_px, -10, 10);
}

/* Rotates the light around the camera's up (horizontal motion) and right
 * (vertical motion) axes, so it moves the way the hand does on screen
 * whatever the camera orientation. */
static void move_light(app *a, double yaw, double pitch)
{
    double eye[3], right[3], up[3], fwd[3];
    sss_renderer_camera(a->r, &a->p, eye, right, up, fwd);
    sss_normalize3(a->p.light);
    rotate3(a->p.light, up, yaw);
    rotate3(a->p.light, right, pitch);
    sss_normalize3(a->p.light);
}

static void scale_intensity(app *a, double s)
{
    for (int k = 0; k < 3; k++) a->p.light_rgb[k] = clampd(a->p.light_rgb[k] * s, 1e-4, 1e4);
}

/* ---- GLFW callbacks ---------------------------------------------------- */

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    (void)scancode;
    (void)mods;
    app *a = glfwGetWindowUserPointer(w);
    if (action == GLFW_RELEASE) return;
    if (a->panel && sss_panel_wants_keyboard(a->panel)) return; /* a value being typed into the panel */
    if (a->opt->key && a->opt->key(a->opt->user, key)) return;
    const double step = 5.0 * SSS_PI / 180.0;
    double wup[3], eye[3], right[3], up[3], fwd[3];
    world_up(a, wup);
    /* Continuous adjustments follow key repeat; toggles act once per press
     * so that holding a key does not make them flicker. */
    switch (key) {
    case GLFW_KEY_LEFT:
    case GLFW_KEY_RIGHT:
        rotate3(a->p.light, wup, key == GLFW_KEY_RIGHT ? step : -step);
        return;
    case GLFW_KEY_UP:
    case GLFW_KEY_DOWN:
        sss_renderer_camera(a->r, &a->p, eye, right, up, fwd);
        rotate3(a->p.light, right, key == GLFW_KEY_UP ? -step : step);
        return;
    case GLFW_KEY_EQUAL:
    case GLFW_KEY_KP_ADD: scale_intensity(a, 1.25); return;
    case GLFW_KEY_MINUS:
    case GLFW_KEY_KP_SUBTRACT: scale_intensity(a, 1 / 1.25); return;
    case GLFW_KEY_LEFT_BRACKET: a->p.exposure = clampd(a->p.exposure / 1.25, 1e-4, 1e4); return;
    case GLFW_KEY_RIGHT_BRACKET: a->p.exposure = clampd(a->p.exposure * 1.25, 1e-4, 1e4); return;
    default: break;
    }
    if (action == GLFW_REPEAT) return;
    switch (key) {
    case GLFW_KEY_1:
    case GLFW_KEY_KP_1: a->p.scatter = 1, a->p.specular = 0; break;
    case GLFW_KEY_2:
    case GLFW_KEY_KP_2: a->p.scatter = 0, a->p.specular = 1; break;
    case GLFW_KEY_3:
    case GLFW_KEY_KP_3: a->p.scatter = 1, a->p.specular = 1; break;
    case GLFW_KEY_C: a->p.path = a->p.path == SSS_EVAL_GPU ? SSS_EVAL_CPU : SSS_EVAL_GPU; break;
    case GLFW_KEY_W: a->p.wireframe = !a->p.wireframe; break;
    case GLFW_KEY_O: a->p.near_terms = !a->p.near_terms; break;
    case GLFW_KEY_V: a->p.near_visibility = a->p.near_visibility == SSS_NEAR_MAP ? SSS_NEAR_RAYS : SSS_NEAR_MAP; break;
    case GLFW_KEY_S: a->p.surface_shadow = !a->p.surface_shadow; break;
    case GLFW_KEY_X: { /* from what is drawn now (auto follows the file's effect bit) to the other */
        const int drawn = a->p.single > 0 || (a->p.single == 0 && (a->f->fx.mask & SSS_FX_SINGLE));
        a->p.single = drawn ? -1 : 1;
        break;
    }
    case GLFW_KEY_D: /* the next of 0, 0.25, 0.5, 1 above the current share */
        a->p.diffuse = a->p.diffuse >= 1.0 ? 0.0 : a->p.diffuse >= 0.5 ? 1.0 : a->p.diffuse >= 0.25 ? 0.5 : 0.25;
        break;
    case GLFW_KEY_N:
        a->p.interp = a->p.interp == SSS_INTERP_NEAREST4 ? SSS_INTERP_TRIANGLE : SSS_INTERP_NEAREST4;
        break;
    case GLFW_KEY_T:
        a->p.tonemap = a->p.tonemap == SSS_TONEMAP_CLAMP ? SSS_TONEMAP_REINHARD : SSS_TONEMAP_CLAMP;
        break;
    case GLFW_KEY_R:
        memcpy(a->p.view, a->initial.view, sizeof a->p.view);
        memcpy(a->p.pan, a->initial.pan, sizeof a->p.pan);
        memcpy(a->p.light, a->initial.light, sizeof a->p.light);
        memcpy(a->p.light_rgb, a->initial.light_rgb, sizeof a->p.light_rgb);
        a->p.distance = a->initial.distance;
        break;
    case GLFW_KEY_P: a->want_shot = 1; break;
    case GLFW_KEY_SPACE: a->paused = !a->paused; break;
    case GLFW_KEY_PERIOD: a->paused = 1, a->clock += 1.0 / 30.0; break;
    case GLFW_KEY_COMMA: a->paused = 1, a->clock -= 1.0 / 30.0; break;
    case GLFW_KEY_H: a->overlay = !a->overlay; break;
    case GLFW_KEY_G: a->show_panel = !a->show_panel; break;
    case GLFW_KEY_ESCAPE:
    case GLFW_KEY_Q: glfwSetWindowShouldClose(w, GLFW_TRUE); break;
    default: break;
    }
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    app *a = glfwGetWindowUserPointer(w);
    if (action == GLFW_RELEASE) {
        if (button == a->drag_button) a->drag = DRAG_NONE;
        return;
    }
    if (a->drag != DRAG_NONE) return; /* a second button during a drag changes nothing */
    if (a->panel && sss_panel_wants_mouse(a->panel, a->mx, a->my)) return; /* a click on the panel */
    /* The drag starts from a->mx/my as last set by on_cursor, not from
     * glfwGetCursorPos: on X11 that asks the server where the pointer is
     * now, which may already be past motion events still queued for us
     * (fast or scripted input), and their deltas would be lost. The mode
     * is fixed here, so releasing Ctrl in the middle of a light drag does
     * not swing the camera instead. */
    if (button == GLFW_MOUSE_BUTTON_LEFT) {
        if ((mods & GLFW_MOD_CONTROL) || glfwGetKey(w, GLFW_KEY_L) == GLFW_PRESS) a->drag = DRAG_LIGHT;
        else if (mods & GLFW_MOD_SHIFT) a->drag = DRAG_PAN;
        else a->drag = DRAG_ORBIT;
    } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
        a->drag = DRAG_PAN;
    } else {
        return;
    }
    a->drag_button = button;
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    app *a = glfwGetWindowUserPointer(w);
    double dx = x - a->mx, dy = y - a->my;
    a->mx = x;
    a->my = y;
    int ww, wh;
    glfwGetWindowSize(w, &ww, &wh);
    if (a->drag == DRAG_NONE || wh < 1) return;
    /* a drag over the full window height turns by 180 degrees */
    double k = SSS_PI / wh;
    if (a->drag == DRAG_ORBIT) orbit(a, dx, dy, k);
    else if (a->drag == DRAG_PAN) pan(a, dx, dy, wh);
    else move_light(a, dx * k, dy * k);
}

static void on_scroll(GLFWwindow *w, double xoff, double yoff)
{
    (void)xoff;
    app *a = glfwGetWindowUserPointer(w);
    if (a->panel && sss_panel_wants_mouse(a->panel, a->mx, a->my)) return; /* scrolls the panel */
    a->p.distance = clampd(a->p.distance * pow(0.9, yoff), 1.2, 20.0);
}

/* GLFW reports why something failed through this callback; the last
 * message is appended to our own one-line error. */
static char glfw_error[256];

static void on_glfw_error(int code, const char *desc)
{
    (void)code;
    snprintf(glfw_error, sizeof glfw_error, "%s", desc ? desc : "");
    for (char *c = glfw_error; *c; c++) /* our message must stay one line */
        if (*c == '\n' || *c == '\r') *c = ' ';
}

/* ---- screenshots -------------------------------------------------------- */

/* Reads the back buffer just drawn (scene + overlay) and saves it, atomically
 * (sss_write_png_rgb8: anything watching for the file never sees half of
 * it), never over the .sss file shown (sss/fileio.h). The pixels are already
 * sRGB-encoded by the shader. */
static void save_screenshot(const app *a, int w, int h)
{
    char path[4096];
    if (a->opt->screenshot_path) {
        if (strlen(a->opt->screenshot_path) >= sizeof path) {
            sss_cli_printf(stderr, "%s: screenshot not saved: --screenshot path too long\n", TOOL);
            return;
        }
        snprintf(path, sizeof path, "%s", a->opt->screenshot_path);
    } else {
        int n;
        struct stat st;
        for (n = 1; n <= 999; n++) {
            snprintf(path, sizeof path, "sss-view-%03d.png", n);
            if (stat(path, &st) != 0) break;
        }
        if (n > 999) {
            sss_cli_printf(stderr, "%s: screenshot not saved: sss-view-001.png ... sss-view-999.png all exist\n", TOOL);
            return;
        }
    }
    unsigned char *px = malloc((size_t)w * (size_t)h * 3);
    if (!px) {
        sss_cli_printf(stderr, "%s: screenshot not saved: out of memory for %dx%d\n", TOOL, w, h);
        return;
    }
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1); /* tightly packed RGB rows of any width */
    glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, px);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    sss_error err = {{0}};
    const char *inputs[1] = {a->opt->file_path};
    const sss_inputs in = {inputs, 1};
    if (sss_write_png_rgb8(path, px, w, h, &in, &err) != SSS_OK)
        sss_cli_printf(stderr, "%s: screenshot not saved: %s\n", TOOL, err.msg);
    else
        sss_cli_printf(stderr, "%s: saved %s\n", TOOL, path);
    free(px);
}

/* ---- overlay ------------------------------------------------------------ */

static void draw_overlay(app *a, int fw, int fh)
{
    const sss_bake_file *f = a->f;
    int s = fw > 1600 ? 2 : 1; /* stay legible on large framebuffers */
    double l[3] = {a->p.light[0], a->p.light[1], a->p.light[2]};
    sss_normalize3(l);
    const char *terms = a->p.scatter && a->p.specular ? "scatter+reflection"
                        : a->p.scatter                ? "scatter only"
                        : a->p.specular               ? "reflection only"
                                                      : "none";
    const char *base = strrchr(a->opt->file_path, '/');
    base = base ? base + 1 : a->opt->file_path;
    /* files baked with --own-term runtime: the near terms the viewer adds
     * back, with the visibility of the bake's rays or of a shadow map
     * (sss/render.h) */
    char own[160] = "", vis[48] = "rays";
    if (a->p.near_visibility == SSS_NEAR_MAP)
        snprintf(vis, sizeof vis, "shadow map %d^2", a->p.shadow_size ? a->p.shadow_size : SSS_SHADOW_SIZE);
    if (f->near_terms && f->near_radius_mm > 0.0)
        snprintf(own, sizeof own, "near terms (within %.3g mm, %s, V): %s\n", f->near_radius_mm, vis,
                 a->p.near_terms ? "on" : "off (O)");
    else if (f->near_terms)
        snprintf(own, sizeof own, "near terms (own + %u ring%s, %s, V): %s\n", f->near_rings,
                 f->near_rings == 1 ? "" : "s", vis, a->p.near_terms ? "on" : "off (O)");
    if (f->near_terms && a->p.near_terms)
        snprintf(own + strlen(own) - 1, sizeof own - (strlen(own) - 1), ", %.2f ms\n", a->near_ms);
    /* the surface terms' shadow and diffuse share, and the interpolation,
     * when they differ from the defaults */
    char surf[96];
    snprintf(surf, sizeof surf, "%s%s%s", a->p.surface_shadow ? "" : "  unshadowed (S)",
             a->p.interp == SSS_INTERP_NEAREST4 ? "  4-nearest (N)" : "", a->p.diffuse > 0 ? "  diffuse " : "");
    if (a->p.diffuse > 0) snprintf(surf + strlen(surf), sizeof surf - strlen(surf), "%.2g (D)", a->p.diffuse);
    char buf[1536];
    snprintf(buf, sizeof buf,
             "%.60s  %dx%d\n"
             "%.1f fps  %.2f ms/frame\n"
             "scatter %.2f ms (%s) / draw %.2f ms\n"
             "vertices %u  channels %u  directions %u\n"
             "bytes/vertex %.1f (%s)\n"
             "material %.31s  eta %.3f\n"
             "%s"
             "exposure %.3g  intensity %.3g  tonemap %s\n"
             "light (%.2f, %.2f, %.2f)\n"
             "%s%.100s%s"
             "%s%s%s\n"
             "H: help/overlay  G: panel  P: screenshot",
             base, fw, fh, a->frame_ms > 0 ? 1e3 / a->frame_ms : 0.0, a->frame_ms, a->scatter_ms,
             a->p.path == SSS_EVAL_CPU ? "CPU" : "GPU", a->draw_ms, f->mesh.nv, f->channels, f->dirs.n,
             sss_renderer_bytes_per_vertex(a->r), a->storage,
             f->material.name, f->material.eta, own, a->p.exposure, a->p.light_rgb[0],
             a->p.tonemap == SSS_TONEMAP_REINHARD ? "reinhard" : "clamp", l[0], l[1], l[2],
             a->scene_desc ? "scene: " : "", a->scene_desc ? a->scene_desc : "", a->scene_desc ? "\n" : "", terms,
             a->p.wireframe ? "  wireframe" : "", surf);
    int lines = 1;
    for (const char *c = buf; *c; c++) lines += *c == '\n';
    float pad = 6.0f * s, x = 8.0f * s, y = 8.0f * s;
    float w = (float)sss_font_text_width(buf, s) + 2 * pad;
    float h = (float)((lines - 1) * SSS_FONT_LINE + SSS_FONT_GLYPH_H) * s + 2 * pad;
    const float box[4] = {0.0f, 0.0f, 0.0f, 0.62f}, ink[4] = {0.93f, 0.93f, 0.88f, 1.0f};
    sss_text_begin(a->text, fw, fh);
    sss_text_box(a->text, x, y, w, h, box);
    sss_text_print(a->text, x + pad, y + pad, s, ink, buf);
    sss_text_flush(a->text);
}

/* Exponential smoothing: the overlay would be unreadable at raw per-frame values. */
static double smooth(double prev, double x, int first)
{
    return first ? x : 0.92 * prev + 0.08 * x;
}

/* ---- window ------------------------------------------------------------ */

static void no_window(void)
{
    sss_cli_printf(stderr, "%s: cannot open a window (no display?); use --offscreen%s%s%s\n", TOOL,
            glfw_error[0] ? " [GLFW: " : "", glfw_error, glfw_error[0] ? "]" : "");
}

/* 4.5 core first (what the renderer is written against), then 4.3, the
 * minimum for compute shaders; forward-compatible as macOS-style drivers
 * require for core profiles. */
static GLFWwindow *open_window(int w, int h, const char *title)
{
    static const int versions[2][2] = {{4, 5}, {4, 3}};
    for (int i = 0; i < 2; i++) {
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, versions[i][0]);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, versions[i][1]);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_DOUBLEBUFFER, GLFW_TRUE);
        glfwWindowHint(GLFW_DEPTH_BITS, 24);
        /* the shader sRGB-encodes for framebuffer 0 itself: no GL_FRAMEBUFFER_SRGB */
        glfwWindowHint(GLFW_SRGB_CAPABLE, GLFW_FALSE);
        GLFWwindow *win = glfwCreateWindow(w, h, title, NULL, NULL);
        if (win) return win;
    }
    return NULL;
}

int sss_app_run(const sss_bake_file *f, const sss_view_params *initial, const sss_app_options *opt)
{
    glfwSetErrorCallback(on_glfw_error);
    if (!glfwInit()) {
        no_window();
        return 1;
    }
    char title[4200];
    snprintf(title, sizeof title, "sss-view \xE2\x80\x94 %s", opt->file_path); /* U+2014 em dash, UTF-8 */
    GLFWwindow *win = open_window(opt->width, opt->height, title);
    if (!win) {
        no_window();
        glfwTerminate();
        return 1;
    }
    glfwMakeContextCurrent(win);
    glfwSwapInterval(1); /* vsync: no point drawing frames the display never shows */

    app a;
    memset(&a, 0, sizeof a);
    a.win = win;
    a.f = f;
    a.opt = opt;
    sss_storage_describe(f, a.storage, sizeof a.storage);
    a.p = *initial;
    if (!(a.p.distance > 0)) a.p.distance = 2.8;
    if (!(a.p.exposure > 0)) a.p.exposure = 1.0;
    a.initial = a.p;
    a.overlay = 1;

    int rc = 0;
    sss_error err = {{0}};
    if (sss_renderer_create(f, &a.r, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s: %s\n", TOOL, opt->file_path, err.msg);
        rc = 1;
    } else if (sss_text_create(&a.text, &err) != SSS_OK) {
        sss_cli_printf(stderr, "%s: %s\n", TOOL, err.msg);
        rc = 1;
    } else {
        GLenum e = glGetError();
        if (e != GL_NO_ERROR) {
            sss_cli_printf(stderr, "%s: OpenGL error 0x%04X while setting up the window (%s)\n", TOOL, (unsigned)e,
                    (const char *)glGetString(GL_RENDERER));
            rc = 1;
        }
    }
    if (rc) {
        sss_text_destroy(a.text);
        sss_renderer_destroy(a.r);
        glfwDestroyWindow(win);
        glfwTerminate();
        return rc;
    }

    glfwSetWindowUserPointer(win, &a);
    glfwSetKeyCallback(win, on_key);
    glfwSetMouseButtonCallback(win, on_button);
    glfwSetCursorPosCallback(win, on_cursor);
    glfwSetScrollCallback(win, on_scroll);
    glfwGetCursorPos(win, &a.mx, &a.my);
    /* after the app's callbacks: ImGui's call them first, then its own */
    a.panel = sss_panel_create(win, &err);
    if (!a.panel) sss_cli_printf(stderr, "%s: no panel (G): %s\n", TOOL, err.msg);
    sss_panel_info pinfo = {f, opt->file_path, a.storage, sss_renderer_bytes_per_vertex(a.r), NULL,
                            opt->frame_q != NULL || opt->frame_gpu != NULL, a.initial.exposure, {0, 0, 0}, 0.0,
                            opt->scene_eval, opt->edit, opt->transport_mm, &a.edit_save};
    float *scene_q = opt->frame_q ? malloc((size_t)f->mesh.nv * f->channels * sizeof(float) + 1) : NULL;

    while (!glfwWindowShouldClose(win)) {
        int fw, fh;
        glfwGetFramebufferSize(win, &fw, &fh);
        /* Minimised (or resized to nothing): no zero-sized viewport or
         * read-back; sleep on events instead of spinning. */
        if (fw < 1 || fh < 1 || glfwGetWindowAttrib(win, GLFW_ICONIFIED)) {
            glfwWaitEventsTimeout(0.1);
            a.last_t = 0;
            continue;
        }
        double t = glfwGetTime();
        if (!a.paused && a.last_t > 0) a.clock += t - a.last_t;
        pinfo.frame_ms = a.last_t > 0 ? 1e3 * (t - a.last_t) : 0.0;
        if (a.last_t > 0) a.frame_ms = smooth(a.frame_ms, pinfo.frame_ms, a.frame_ms == 0);
        a.last_t = t;
        if (a.frames > 0) {
            /* The previous frame's timer queries: normally complete by the
             * time the next frame starts, so reading them here rarely waits,
             * where reading this frame's right after its draw always would. */
            sss_frame_times ft = sss_renderer_times(a.r);
            pinfo.times = ft;
            a.scatter_ms = smooth(a.scatter_ms, ft.scatter_ms, a.frames == 1);
            a.draw_ms = smooth(a.draw_ms, ft.draw_ms, a.frames == 1);
            a.near_ms = smooth(a.near_ms, ft.near_ms, a.frames == 1);
        }
        /* the panel's edits apply to this frame; it is drawn over it below */
        pinfo.scene_desc = a.scene_desc;
        if (a.panel) sss_panel_frame(a.panel, a.show_panel, &a.p, &pinfo);
        if (a.edit_save && opt->key) opt->key(opt->user, GLFW_KEY_E);
        a.edit_save = 0;
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        sss_view_params dp = a.p;
        /* single scattering: the frame's one directional light only, never a
         * scene's sum (docs/layers.md §7), whichever of its lights are on */
        if (opt->frame_gpu || scene_q) dp.single = -1;
        if (opt->frame_gpu && (a.scene_desc = opt->frame_gpu(opt->user, &a.p, a.r, a.clock)) != NULL) {
            /* the scene's lights summed on the GPU, straight into q */
            dp.near_terms = 0; /* the sum holds each light's near terms */
        } else if (scene_q) {
            opt->frame_q(opt->user, &a.p, a.clock, scene_q);
            sss_renderer_upload_q(a.r, scene_q);
            dp.near_terms = 0; /* the sum holds each light's near terms */
        } else {
            sss_renderer_evaluate(a.r, &a.p);
        }
        sss_renderer_draw(a.r, &dp, fw, fh);
        if (a.overlay) draw_overlay(&a, fw, fh);
        if (a.panel) sss_panel_render(a.panel);
        if (a.want_shot) {
            a.want_shot = 0;
            save_screenshot(&a, fw, fh);
        }
        glfwSwapBuffers(win);
        a.frames++;
        glfwPollEvents();
    }

    free(scene_q);
    if (opt->frame_gpu) opt->frame_gpu(opt->user, NULL, NULL, 0.0);
    sss_panel_destroy(a.panel);
    sss_text_destroy(a.text);
    sss_renderer_destroy(a.r);
    glfwDestroyWindow(win);
    glfwTerminate();
    return 0;
}
