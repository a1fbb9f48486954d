/* sss/render.h: the OpenGL 4.3+ core renderer for baked translucent meshes
 * (library sss_render), the one header its users include: the viewer
 * (runtime/src/view/), sss-stat's image error and the tests.
 *
 * Per frame (Hao–Varshney 2004 §3.2, moved to the GPU as its §6 suggests):
 * the CPU finds the direction-set triangle containing the light direction
 * and its barycentric weights once (and, for the compressed forms of §4, the
 * SH basis at the light); the GPU (compute shaders) or the CPU (the C decoder
 * in libsss) reconstructs q(x_v, ω) for every vertex and channel into one
 * buffer, from any storage form (float, lloyd8, sh, refs); the draw shades
 *     L = E · q · F_t(η, n·ω_o)  +  Fresnel-weighted specular
 * per colour channel, with exposure and tone mapping.
 *
 * Files baked with `--own-term runtime [--rings K]` (section OWNT,
 * sss/nearterms.h) store q without its near terms, the vertex's own entry of
 * the §3.1 sum and those of its K mesh rings; the renderer adds
 * Σ_i w̃(o, i) · F_t(η, n_i·ω) max(0, n_i·ω) · V(x_i, ω) back for the actual
 * light ω in two more compute passes, with every vertex's own visibility V
 * from the bake's own ray, traced on the GPU through a BVH of the mesh, or
 * on request from a shadow map along ω (the paper's visibility test, §3.1;
 * docs/viewer.md). Files without OWNT build nothing of it and run no extra
 * pass.
 *
 * Scene bakes (format 1.2, docs/scenes.md) carry other light
 * parameterisations besides the direction set (static directional lights,
 * point-light shells, environment SH transfer): sss_scene_eval_* sums a
 * scene's lights on the CPU, sss_fx_gpu_* on the GPU into the renderer's q.
 *
 * Conventions:
 *  - World space is the mesh's own space (mesh units). Directions need not
 *    be normalised; a zero or non-finite light direction lights nothing.
 *  - Per-vertex arrays are q[v * channels + c], channels = f->channels (1 or
 *    3), nv = f->mesh.nv: the layout sss_decode_all (sss/decode.h) writes.
 *  - Images are linear RGB floats, 3 per pixel, rows bottom-up as
 *    glReadPixels returns them.
 *  - Errors are values (sss/result.h): a failing call returns a code other
 *    than SSS_OK and writes one line into err when err is non-NULL.
 *  - Unless a function says otherwise it needs a current OpenGL context of
 *    version ≥ 4.3 core (a window's, or sss_offscreen_create's) on the
 *    calling thread, the same one for every call on an object; the renderer
 *    never creates or destroys contexts.
 */
#ifndef SSS_RENDER_H
#define SSS_RENDER_H

#include <stddef.h>
#include <stdint.h>
#include "sss/bvh.h" /* the BVH the near terms trace (sss_bvh_build, sss_bvh_lit) */
#include "sss/format.h"
#include "sss/result.h"
#include "sss/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- offscreen context ------------------------------------------------- */

/* A windowless OpenGL 4.5 core context through EGL on the surfaceless
 * platform (Mesa llvmpipe without a GPU, or a GPU driver's EGL device), for
 * scripts, tests and benchmarks. */
typedef struct sss_offscreen sss_offscreen;

/* Creates the context and makes it current on this thread. Needs no
 * context. Fails with SSS_ERR_UNSUPPORTED (err says what is missing) when no
 * EGL display or no 4.5 core context can be had. Destroy with
 * sss_offscreen_destroy (NULL-safe), after every GL object made in it. */
sss_result sss_offscreen_create(sss_offscreen **out, sss_error *err);
void sss_offscreen_destroy(sss_offscreen *o);

/* GL_RENDERER string of the current context (storage owned by GL;
 * "unknown" when GL returns none). */
const char *sss_gl_renderer_name(void);

/* ---- view parameters ---------------------------------------------------- */

typedef struct sss_renderer sss_renderer;

typedef enum sss_eval_path {
    SSS_EVAL_GPU = 0, /* compute shader (default) */
    SSS_EVAL_CPU = 1  /* sss_decode_all (OpenMP + SIMD), then upload */
} sss_eval_path;

/* Where the near terms' V(x_i, ω) comes from (sss_view_params.near_visibility). */
enum {
    SSS_NEAR_RAYS = 0, /* the bake's ray (precompute/src/kernels/visibility.c), traced on the GPU: V as baked (default) */
    SSS_NEAR_MAP = 1   /* a shadow map of shadow_size² texels: wrong within about a texel of a shadow's outline */
};

/* The near terms' default shadow-map resolution (texels per side), used
 * where sss_view_params.shadow_size is 0. 2048²: a texel is ~1/1000 of the
 * bounding diameter, below a twentieth of the mean edge of the 23K dragon
 * (18.5 texels), so only vertices within about a texel of a shadow's
 * outline disagree with a ray. 16 MiB of 32-bit float depth. */
#define SSS_SHADOW_SIZE 2048

typedef enum sss_tonemap {
    SSS_TONEMAP_CLAMP = 0,   /* clamp(exposure · L, 0, 1): the measurement convention */
    SSS_TONEMAP_REINHARD = 1 /* x / (1 + x) after exposure: for viewing bright scenes */
} sss_tonemap;

/* The largest exposure and light irradiance the tools accept: with every
 * stored value at most SSS_VALUE_MAX (sss/format.h), q · E · exposure stays
 * below 1e30, far inside float (docs/robustness.md, "Values"). */
#define SSS_VIEW_GAIN_MAX 1e12

/* Everything a frame depends on. Directions need not be normalised. */
typedef struct sss_view_params {
    double light[3];      /* towards the light, world (= mesh) space */
    double light_rgb[3];  /* irradiance E per channel (default 1,1,1) */
    double view[3];       /* from the object's centre towards the eye */
    double distance;      /* eye distance in bounding radii (0: default 3.6: the bounding sphere fits a 35° view) */
    double pan[2];        /* target offset in bounding radii, screen x/y */
    double up[3];         /* the picture's up, world space (0,0,0: +y, or +z when looking along y); a scene camera's "up" */
    double fov_deg;       /* vertical field of view (0: default 35) */
    double exposure;      /* multiplies radiance before tone mapping (0: default 1) */
    int scatter;          /* draw the subsurface term (default on: set by sss_view_params_default) */
    int specular;         /* draw the surface reflection term */
    int wireframe;        /* polygon mode line */
    sss_tonemap tonemap;
    sss_eval_path path;
    float background[3];  /* clear colour, linear */
    int near_terms;         /* files with OWNT: add the near terms to q (default on; 0 leaves q as evaluated
                           * or uploaded, for tools that draw a full q computed elsewhere); ignored otherwise */
    int shadow_size;      /* the shadow map of the surface terms (surface_shadow) and, for files with OWNT
                           * and near_visibility SSS_NEAR_MAP, of the near terms: texels per side,
                           * 256 … 8192 (0: SSS_SHADOW_SIZE); finer agrees with the bake's rays at more
                           * vertices and costs more per light change (docs/viewer.md) */
    int near_visibility;  /* files with OWNT: SSS_NEAR_RAYS (default) or SSS_NEAR_MAP (docs/viewer.md) */
    int exit_normalised;  /* 1: the subsurface exit term F_t(η, n·ω_o) divided by c(η) = sss_exit_norm(η),
                           * so that the radiance integrates to the dipole's exitance (docs/physics.md §4);
                           * 0 (default): Jensen's F_t, as the paper */
    int interp;           /* how q at the light is formed from the direction samples, both paths:
                           * SSS_INTERP_TRIANGLE (0, default) or SSS_INTERP_NEAREST4, the paper's four
                           * nearest samples (Hao–Varshney 2004 §3.2, Fig. 3; sss/decode.h, docs/viewer.md) */
    int surface_shadow;   /* 1 (default): the surface terms (specular, diffuse) are 0 where the shadow map
                           * says the light is blocked (docs/viewer.md, "Direct surface light") */
    double diffuse;       /* ρ_d in [0, 1]: the share of the Fresnel-reflected light the surface reflects
                           * diffusely (Lambert) instead of in the specular lobe (default 0: all specular) */
    int single;           /* single scattering per pixel (docs/layers.md §8): 0 (default) when the file's
                           * effect set has single-scattering, 1 always, -1 never */
    int single_samples;   /* its N, segments along the view ray (0: the default, 32) */
    int single_march;     /* SSS_SINGLE_MARCH_SEGMENTS (0, default: the per-segment closed form) or
                           * SSS_SINGLE_MARCH_SEED (seed 002's Algorithm 1) */
    int sh_tables;        /* GPU path, SH codes: the frame's folded tables as SSS_SH_TABLES_UNIFORM (a
                           * uniform block, where they fit 16 KiB) or SSS_SH_TABLES_STORAGE (a storage
                           * buffer); the same q to the bit, only the time differs. 0 (default): storage
                           * on a GPU, uniform on a software GL (docs/viewer.md, "SH tables on the GPU") */
} sss_view_params;

#define SSS_SH_TABLES_UNIFORM 1
#define SSS_SH_TABLES_STORAGE 2

#define SSS_SINGLE_MARCH_SEGMENTS 0
#define SSS_SINGLE_MARCH_SEED 1

/* Fills the defaults: light and view (0, 0, 1), light_rgb (1, 1, 1),
 * distance 3.6, fov 35°, exposure 1, scatter and specular on, clamp tone
 * map, GPU path, near_terms on, SSS_NEAR_RAYS, black background, no pan,
 * no wireframe, shadow_size 0, triangle interpolation, surface_shadow on,
 * diffuse 0. Needs no context. */
void sss_view_params_default(sss_view_params *p);

/* The camera of p about a bounding sphere (centre, radius; the frame
 * sss_view_params is measured in is sss_mesh_bounding_sphere's): the eye, and
 * the picture's right, up and forward directions (world space). */
void sss_view_frame(const sss_view_params *p, const double centre[3], double radius, double eye[3], double right[3],
                    double up[3], double fwd[3]);

/* Applies the tone map t to one linear value x already multiplied by the
 * exposure: clamp to [0, 1], or x / (1 + x). Needs no context. */
float sss_tonemap_apply(sss_tonemap t, float x);

/* ---- the renderer -------------------------------------------------------- */

/* Frame timings in milliseconds (GPU timer queries for GPU work, wall
 * clock for CPU work); values are of the previous completed frame. */
typedef struct sss_frame_times {
    double scatter_ms; /* evaluation of q for all vertices (incl. upload on the CPU path) */
    double draw_ms;    /* the shading draw */
    double near_ms;     /* files with OWNT: the near-term passes, the rays or the shadow map render
                        * included when the light moved (GPU timer; 0 when none ran) */
} sss_frame_times;

/* Uploads geometry and scattering data of f (which must stay alive as long
 * as the renderer: the CPU path decodes from it) and builds the programs f
 * needs (only those of its storage form; the near-term passes and the
 * mesh's BVH only for a file with OWNT). Fails with a message if GL is
 * older than 4.3 or lacks something (SSS_ERR_UNSUPPORTED: a shader that does
 * not compile, a buffer above GL_MAX_SHADER_STORAGE_BLOCK_SIZE), or a buffer
 * cannot be allocated (SSS_ERR_NOMEM); *out is then NULL. */
sss_result sss_renderer_create(const sss_bake_file *f, sss_renderer **out, sss_error *err);
/* A file with the vector integrals Q (section QVEC, format 1.7) is drawn
 * from Q, interpolated and dotted with the light (Hao–Varshney 2004 §3.2),
 * on both paths; this one draws q's rows of the same file instead, to set
 * q against Q. sss_renderer_vector says which r draws (1: Q). */
sss_result sss_renderer_create_scalar(const sss_bake_file *f, sss_renderer **out, sss_error *err);
int sss_renderer_vector(const sss_renderer *r);
/* Deletes every GL object of r and frees it. NULL-safe. */
void sss_renderer_destroy(sss_renderer *r);

/* Reconstructs q for p->light on p->path into the per-vertex buffer; for a
 * file with OWNT and p->near_terms set, the full q: the stored rest plus the
 * near terms with the visibility p->near_visibility asks for (rays traced,
 * or the map re-rendered, when the light direction differs from the last
 * one they were made for). */
void sss_renderer_evaluate(sss_renderer *r, const sss_view_params *p);

/* Draws into the currently bound framebuffer, viewport width × height
 * pixels: clears it to p->background, then shades with depth test. The
 * default framebuffer gets p->tonemap and sRGB encoding; the renderer's own
 * float framebuffer (sss_renderer_bind_offscreen) gets linear radiance ×
 * exposure. Call after sss_renderer_evaluate (or sss_renderer_upload_q). */
void sss_renderer_draw(sss_renderer *r, const sss_view_params *p, int width, int height);

/* Reads the per-vertex q buffer back into out (nv × channels floats,
 * caller-owned): out[v * channels + c]. */
void sss_renderer_read_q(sss_renderer *r, float *out);

/* Every vertex's own visibility of the last near-term pass, one byte per
 * vertex (nv, caller-owned): 1 where the test (the bake's ray through the
 * BVH; or, with the map, that ray against the vertex's own triangles, then
 * the shadow map) found x_o lit from that pass's light. Vertices with
 * n_o·ω ≤ 0 are not tested (their g is 0) and read 0. Before any pass every
 * vertex reads 0; a file without OWNT has no near terms and every vertex
 * reads 1. For comparing the viewer's V with the bake's. */
void sss_renderer_read_near_visibility(sss_renderer *r, uint8_t *lit);

/* 1 when the file has OWNT, so the renderer built the near-term passes and
 * the mesh's BVH (the shadow map follows on the first pass that asks for
 * it). */
int sss_renderer_has_near_terms(const sss_renderer *r);

/* Timings of the last evaluate + draw (waits for the GPU timer queries). */
sss_frame_times sss_renderer_times(const sss_renderer *r);

/* Renders one frame into an internal float framebuffer of width × height
 * (each 1 … 16384, else SSS_ERR_ARG) and returns the tone-mapped linear RGB
 * image (3 floats per pixel, rows bottom-up as OpenGL returns them; values
 * in [0,1] for CLAMP) in *rgb, and, if hdr is non-NULL, the linear radiance
 * × exposure before tone mapping. Both malloc'ed, caller frees; NULL on
 * failure. Leaves the default framebuffer (0) bound. */
sss_result sss_renderer_render_image(sss_renderer *r, const sss_view_params *p, int width, int height, float **rgb,
                                     float **hdr, sss_error *err);

/* Replaces the per-vertex q buffer with q[v * channels + c] (nv × channels
 * floats, the layout sss_decode_all writes; copied, the caller keeps q):
 * values computed elsewhere (the exact evaluator, another interpolation) are
 * then drawn exactly as the viewer draws its own (sss-stat --error's image
 * error). For a file with OWNT the light is not known yet: the next
 * sss_renderer_draw adds the near terms for its p->light when its
 * p->near_terms is set (once; nothing when it is 0), so q here is the rest,
 * as the file's decoder returns it. */
void sss_renderer_upload_q(sss_renderer *r, const float *q);

/* Uploads the positions and normals of the file r was created with again,
 * after the caller changed them in place (same vertex and triangle counts):
 * a deforming object's pose (docs/deformable.md §4). The surface terms'
 * shadow map is made again on the next draw; the camera's centre and
 * radius stay those of the first shape. Files with OWNT are not supported
 * (their near-term BVH is built once). */
void sss_renderer_update_geometry(sss_renderer *r);

/* sss_renderer_render_image with the per-vertex q supplied (uploaded with
 * sss_renderer_upload_q) instead of evaluated from the file; for a file with
 * OWNT the near terms for p->light are added when p->near_terms is set.
 * SSS_ERR_ARG when q is NULL. */
sss_result sss_renderer_render_q_image(sss_renderer *r, const sss_view_params *p, const float *q, int width,
                                       int height, float **rgb, float **hdr, sss_error *err);

/* Creates (or resizes) the internal float framebuffer (RGBA32F colour,
 * 32-bit float depth; width and height 1 … 16384) and binds it, so that
 * sss_renderer_draw renders linear radiance × exposure into it. */
sss_result sss_renderer_bind_offscreen(sss_renderer *r, int width, int height, sss_error *err);

/* The GL name of the per-vertex q buffer (nv·channels floats, SSBO
 * binding 3 of the draw), for evaluators that write it on the GPU
 * (sss_fx_gpu: the scene's lights). Owned by r. */
unsigned sss_renderer_q_buffer(const sss_renderer *r);

/* Bytes per vertex of the scattering data as stored in the file (for the
 * overlay). Needs no context. */
double sss_renderer_bytes_per_vertex(const sss_renderer *r);
/* How the frame for p evaluates q, in a few words, for reports: "cpu"; on
 * the GPU path "rows" (float, lloyd8, or a reference form without SH part)
 * or where the coded pass reads the SH tables from, "uniform tables" or
 * "storage tables" (sss_view_params.sh_tables). Static. */
const char *sss_renderer_scheme(const sss_renderer *r, const sss_view_params *p);

/* Camera frame for p: eye position (world units) and unit right / up /
 * forward vectors in world space (for mapping mouse drags to rotations).
 * Needs no context. */
void sss_renderer_camera(const sss_renderer *r, const sss_view_params *p, double eye[3], double right[3],
                         double up[3], double fwd[3]);

/* One-line description of f's storage form for the overlay and --bench:
 * sss_quant_name, then for the compressed forms the SH order and code kind
 * and the reference fraction, e.g. "refs 3.0% + SH 3 linear8, 16-bit
 * weights". Always NUL-terminated (n > 0). Needs no context. */
void sss_storage_describe(const sss_bake_file *f, char *buf, size_t n);

/* ---- a scene's lights (format 1.2, docs/scenes.md "Viewer") ------------- */

/* `sss-view FILE.sss --scene S.json`: the scene's lights summed per vertex
 * from the parameterisation the file records for each, on the CPU. Needs no
 * context. */
typedef struct sss_scene_eval sss_scene_eval;

/* Matches every light of sc to the effect data of f: a static directional
 * light (or far static point light) to its QDIR entry by direction, a
 * moving directional light to the direction set, a point light to PSHL, an
 * environment to ENVT. A light f has no data for is an error naming it
 * (SSS_ERR_ARG: the file was baked for another scene). f and sc must
 * outlive the evaluator; destroy it with sss_scene_eval_destroy
 * (NULL-safe). */
sss_result sss_scene_eval_create(const sss_bake_file *f, const sss_scene *sc, sss_scene_eval **out, sss_error *err);
void sss_scene_eval_destroy(sss_scene_eval *e);

/* q for the frame into q[v * channels + c] (nv × channels floats,
 * caller-owned; light colours and intensities folded in: render with
 * light_rgb = 1). angle (radians) turns the moving lights about +z, so a
 * benchmark's frames differ. The reference of the GPU sum. For a file with
 * OWNT (a plain bake with near terms at run time, viewed with a scene) each
 * direction-set light's term is its full q: the stored rows plus its own
 * near terms, the visibility by the bake's ray traced on the CPU through
 * the BVH the GPU traces (operation for operation), as
 * sss_scene_eval_set_view asks; so the q of a scene is drawn without adding
 * near terms again (sss_scene_render_image). */
void sss_scene_eval_frame(sss_scene_eval *e, double angle, float *q);

/* The view settings the sums follow: p->near_terms (0: the rows alone, as
 * --no-own-term asks), and for the GPU sum p->near_visibility and
 * p->shadow_size (the CPU sum traces the bake's rays either way). Default:
 * near terms on, rays. */
void sss_scene_eval_set_view(sss_scene_eval *e, const sss_view_params *p);
const sss_view_params *sss_scene_eval_view(const sss_scene_eval *e);

/* One light's parameters for the frame at angle (the vertex-independent
 * part of sss_scene_eval_frame), so that another evaluator (the GPU path,
 * sss_fx_gpu) sums exactly the same terms in the same order. */
typedef struct sss_scene_light_frame {
    int kind;             /* 0 directional-exact, 1 direction-set, 2 point-shells, 3 environment-sh */
    double w[3];          /* weight of channel c < channels (colour × intensity; a grey file: the mean) */
    uint32_t exact;       /* kind 0: QDIR entry */
    double dir[3];        /* kind 1: direction towards the light this frame */
    double pos[3];        /* kind 2: position this frame (world units) */
    float env_L[3 * 64];  /* kind 3: the probe's SH this frame (rotated about +z when moving); w unused */
} sss_scene_light_frame;

/* Number of lights evaluated (lights of zero intensity and environments
 * after the first are dropped: the file's probe sums them), and light i's
 * parameters (i < that number) at angle. */
uint32_t sss_scene_eval_count(const sss_scene_eval *e);
void sss_scene_eval_light(const sss_scene_eval *e, uint32_t i, double angle, sss_scene_light_frame *out);

/* Which light kinds the sums take (sss_scene_eval_frame, sss_fx_gpu_frame):
 * bit k on takes the lights of sss_scene_light_frame kind k (0 directional-
 * exact, 1 direction-set, 2 point-shells, 3 environment-sh); a kind off
 * contributes nothing, as if the scene had none of it. Default
 * SSS_SCENE_KINDS_ALL. The viewer's panel switches them (docs/viewer.md). */
#define SSS_SCENE_KINDS_ALL 0xFu
void sss_scene_eval_set_kinds(sss_scene_eval *e, unsigned mask);
unsigned sss_scene_eval_kinds(const sss_scene_eval *e);
/* The kinds the scene's lights have (bit k: at least one light of kind k). */
unsigned sss_scene_eval_kinds_present(const sss_scene_eval *e);

/* Which paths the file needs, e.g. "directional-exact + environment-sh"
 * (owned by e). */
const char *sss_scene_eval_paths(const sss_scene_eval *e);

/* The scene's camera (if any; p unchanged otherwise) as view parameters:
 * direction from the target, distance in bounding radii, the target as a
 * pan off the object's centre, up and field of view, so that the eye sits
 * at the camera's position and looks at its target (docs/scenes.md). */
void sss_scene_camera_params(const sss_scene *sc, const sss_bake_file *f, sss_view_params *p);

/* The scene's lights summed on the GPU: the same terms as
 * sss_scene_eval_frame (which stays the fallback, `--cpu`, and the
 * reference), one compute dispatch per light in the scene's order, written
 * straight into the renderer's per-vertex q buffer:
 *   directional-exact  the light's QDIR row times its colour (format §5.11);
 *   direction-set      the renderer's own §3.2 compute pass, then times its colour;
 *   point-shells       Hao–Varshney 2004 §3.3: six shell rows weighted
 *                      (directions × distance shells, trilinear), over r²;
 *   environment-sh     Σ_i T_i L_i per vertex and channel (format §5.12),
 *                      L rotated about +z on the CPU when the environment moves.
 * Only the programs and buffers the file needs are built, from its effect
 * set (format §5.10). Needs the renderer's context (GL 4.3 with double
 * precision in shaders, core since 4.0). */
typedef struct sss_fx_gpu sss_fx_gpu;

/* Programs sss_fx_gpu_programs reports as built. */
enum {
    SSS_FXGPU_ROWS = 1u,  /* directional-exact and direction-set */
    SSS_FXGPU_SHELL = 2u, /* point-shells */
    SSS_FXGPU_ENV = 4u    /* environment-sh */
};

/* Builds what f needs for the lights of ev, drawing through r (f, ev and r
 * must outlive it; destroy it first, with sss_fx_gpu_destroy, NULL-safe).
 * Fails (the caller then sums on the CPU) when a program does not compile
 * or a buffer exceeds this GL's limits. */
sss_result sss_fx_gpu_create(const sss_bake_file *f, const sss_scene_eval *ev, sss_renderer *r, sss_fx_gpu **out,
                             sss_error *err);
void sss_fx_gpu_destroy(sss_fx_gpu *g);

/* Sums the lights at angle (radians: the moving lights turn about +z, as in
 * sss_scene_eval_frame) into the renderer's q buffer, ready to draw
 * (sss_renderer_draw; or sss_renderer_read_q). */
void sss_fx_gpu_frame(sss_fx_gpu *g, double angle);

/* The picture `sss-view --scene` draws for the frame at angle: the lights
 * summed on the GPU (g) or, with g NULL, on the CPU (ev), with the near
 * terms of each light as p asks (sss_scene_eval_set_view is called with p),
 * then drawn with p but without adding near terms again (the sum holds
 * them). As sss_renderer_render_image returns it. */
sss_result sss_scene_render_image(sss_renderer *r, sss_scene_eval *ev, sss_fx_gpu *g, const sss_view_params *p,
                                  double angle, int width, int height, float **rgb, float **hdr, sss_error *err);

/* SSS_FXGPU_* bits of the programs built. */
unsigned sss_fx_gpu_programs(const sss_fx_gpu *g);

/* The programs built, e.g. "rows + env" ("none" when no light needs one;
 * owned by g). */
const char *sss_fx_gpu_describe(const sss_fx_gpu *g);

/* ---- images ---------------------------------------------------------------
 * Input pixels are linear RGB floats, 3 per pixel, rows bottom-up (as
 * glReadPixels returns them). Every image is written atomically to a path
 * the output policy allows (sss/fileio.h: a new or regular file, a symbolic
 * link followed to one; never a directory or a device): the target holds
 * its old content or the complete image, never a partial one. A pixel that
 * is not a finite number is refused (SSS_ERR_ARG, naming the pixel) and
 * nothing is written. Failures name the path. Need no context. The _with
 * forms refuse also a path that is the same file as one of the inputs. */
struct sss_inputs;

/* 8-bit sRGB PNG of values clamped to [0, 1]. */
sss_result sss_write_png(const char *path, const float *rgb, int width, int height, sss_error *err);
sss_result sss_write_png_with(const char *path, const float *rgb, int width, int height, const struct sss_inputs *in,
                              sss_error *err);

/* 8-bit RGB PNG of bytes already encoded (3 per pixel, rows bottom-up), with
 * the sRGB chunk: a window's screenshot. */
sss_result sss_write_png_rgb8(const char *path, const unsigned char *px, int width, int height,
                              const struct sss_inputs *in, sss_error *err);

/* 32-bit float RGB OpenEXR (ZIP compression), through the
 * OpenEXR C API. Values are written as they are (no clamp, no curve). */
sss_result sss_write_exr(const char *path, const float *rgb, int width, int height, sss_error *err);
sss_result sss_write_exr_with(const char *path, const float *rgb, int width, int height, const struct sss_inputs *in,
                              sss_error *err);

/* Chooses PNG (from ldr) or EXR (from hdr, or ldr when hdr is NULL) by the
 * extension, case-insensitive; SSS_ERR_ARG for any other. */
sss_result sss_write_image(const char *path, const float *ldr, const float *hdr, int width, int height,
                           sss_error *err);
sss_result sss_write_image_with(const char *path, const float *ldr, const float *hdr, int width, int height,
                                const struct sss_inputs *in, sss_error *err);

/* sss_write_image_with without the last step: checks the path, encodes the
 * image into a temporary file and leaves it in a (sss/fileio.h) for the
 * caller to sss_atomic_commit or sss_atomic_abort, so that a tool writing
 * several images writes none when one fails. On failure nothing is left
 * and a needs no abort. */
struct sss_atomic;
sss_result sss_image_stage(struct sss_atomic *a, const char *path, const float *ldr, const float *hdr, int width,
                           int height, const struct sss_inputs *in, sss_error *err);

/* 1 when path ends in .png or .exr (any case): an image sss_write_image
 * can write. */
int sss_image_type_known(const char *path);

/* sRGB transfer function of a linear value, clamped to [0, 1] first. */
float sss_srgb_encode(float x);

/* ---- GL programs for overlays -------------------------------------------- */

/* Compiles the GLSL bodies vs and fs (vertex and fragment stage; the line
 * "#version 430 core" is put in front of each) and links them into a
 * program: its GL name, or 0 with err set (the driver's log on one line,
 * SSS_ERR_UNSUPPORTED). The shaders are deleted either way; the program is
 * the caller's (glDeleteProgram). */
unsigned sss_gl_program(const char *vs, const char *fs, sss_error *err);

#ifdef __cplusplus
}
#endif
#endif
