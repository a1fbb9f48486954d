/* renderer.h: OpenGL 4.3+ core renderer for baked translucent meshes.
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
 * sss/ownterm.h) store q without its near terms, the vertex's own entry of
 * the §3.1 sum and those of its K mesh rings; the renderer adds
 * Σ_i w̃(o, i) · F_t(η, n_i·ω) max(0, n_i·ω) · V(x_i, ω) back for the actual
 * light ω in two more compute passes, with every vertex's own visibility V
 * from the bake's own ray, traced on the GPU through a BVH of the mesh
 * (bvh.h), or on request from a shadow map along ω (shadow.h; the paper's
 * visibility test, §3.1). Files without OWNT build nothing of it and run no
 * extra pass.
 *
 * All functions need a current GL context (window or EGL offscreen) with
 * GL ≥ 4.3 core; the renderer never creates or destroys contexts.
 */
#ifndef SSS_RENDERER_H
#define SSS_RENDERER_H

#include <stddef.h>
#include <stdint.h>
#include "sss/format.h"

typedef struct sss_renderer sss_renderer;

typedef enum sss_eval_path {
    SSS_EVAL_GPU = 0, /* compute shader (default) */
    SSS_EVAL_CPU = 1  /* sss_decode_all (OpenMP + SIMD), then upload */
} sss_eval_path;

/* Where the near terms' V(x_i, ω) comes from (sss_view_params.near_visibility). */
enum {
    SSS_NEAR_RAYS = 0, /* the bake's ray (precompute/src/visibility.c), traced on the GPU: V as baked (default) */
    SSS_NEAR_MAP = 1   /* a shadow map of shadow_size² texels: wrong within about a texel of a shadow's outline */
};

typedef enum sss_tonemap {
    SSS_TONEMAP_CLAMP = 0,   /* clamp(exposure · L, 0, 1): the measurement convention */
    SSS_TONEMAP_REINHARD = 1 /* x / (1 + x) after exposure: for viewing bright scenes */
} sss_tonemap;

/* Everything a frame depends on. Directions need not be normalised. */
typedef struct sss_view_params {
    double light[3];      /* towards the light, world (= mesh) space */
    double light_rgb[3];  /* irradiance E per channel (default 1,1,1) */
    double view[3];       /* from the object's centre towards the eye */
    double distance;      /* eye distance in bounding radii (0: default 3.6: the bounding sphere fits a 35° view) */
    double pan[2];        /* target offset in bounding radii, screen x/y */
    double fov_deg;       /* vertical field of view (0: default 35) */
    double exposure;      /* multiplies radiance before tone mapping (0: default 1) */
    int scatter;          /* draw the subsurface term (default on: set by sss_view_params_default) */
    int specular;         /* draw the surface reflection term */
    int wireframe;        /* polygon mode line */
    sss_tonemap tonemap;
    sss_eval_path path;
    float background[3];  /* clear colour, linear */
    int own_term;         /* files with OWNT: add the near terms to q (default on; 0 leaves q as evaluated
                           * or uploaded, for tools that draw a full q computed elsewhere); ignored otherwise */
    int shadow_size;      /* files with OWNT and near_visibility SSS_NEAR_MAP: shadow map texels per side,
                           * 256 … 8192 (0: SSS_SHADOW_SIZE); finer agrees with the bake's rays at more
                           * vertices and costs more per light change (docs/viewer.md) */
    int near_visibility;  /* files with OWNT: SSS_NEAR_RAYS (default) or SSS_NEAR_MAP (docs/viewer.md) */
} sss_view_params;

/* Fills defaults: light (0,0,1)... see renderer.c. */
void sss_view_params_default(sss_view_params *p);

/* Frame timings in milliseconds (GPU timer queries for GPU work, wall
 * clock for CPU work); values are of the previous completed frame. */
typedef struct sss_frame_times {
    double scatter_ms; /* evaluation of q for all vertices (incl. upload on the CPU path) */
    double draw_ms;    /* the shading draw */
    double own_ms;     /* files with OWNT: the near-term passes, the rays or the shadow map render
                        * included when the light moved (GPU timer; 0 when none ran) */
} sss_frame_times;

/* The frame sss_view_params is measured in: the centre of m's bounding box
 * into centre, and returns the bounding radius about it (1 when m has no
 * extent). */
double sss_view_bounds(const sss_mesh *m, double centre[3]);

/* Uploads geometry and scattering data of f (which must stay alive as long
 * as the renderer: the CPU path decodes from it). Fails with a message if GL
 * is too old or a buffer cannot be allocated. */
sss_result sss_renderer_create(const sss_bake_file *f, sss_renderer **out, sss_error *err);
void sss_renderer_destroy(sss_renderer *r);

/* Reconstructs q for p->light on p->path into the per-vertex buffer; for a
 * file with OWNT and p->own_term set, the full q: the stored rest plus the
 * near terms with the visibility p->near_visibility asks for (rays traced,
 * or the map re-rendered, when the light direction differs from the last
 * one they were made for). */
void sss_renderer_evaluate(sss_renderer *r, const sss_view_params *p);

/* Draws into the currently bound framebuffer, viewport width × height.
 * Call after sss_renderer_evaluate. */
void sss_renderer_draw(sss_renderer *r, const sss_view_params *p, int width, int height);

/* Reads the per-vertex q buffer back: out[v * channels + c]. */
void sss_renderer_read_q(sss_renderer *r, float *out);

/* Every vertex's own visibility of the last near-term pass, one byte per
 * vertex (nv): 1 where the test (the bake's ray through the BVH; or, with
 * the map, that ray against the vertex's own triangles, then the shadow
 * map) found x_o lit from that pass's light. Vertices with n_o·ω ≤ 0 are
 * not tested (their g is 0) and read 0. Before any pass every vertex reads
 * 0; a file without OWNT has no near terms and every vertex reads 1. For
 * comparing the viewer's V with the bake's. */
void sss_renderer_read_own_visibility(sss_renderer *r, uint8_t *lit);

/* 1 when the file has OWNT, so the renderer built the near-term passes and
 * the mesh's BVH (runtime/src/bvh.h; the shadow map, runtime/src/shadow.h,
 * follows on the first pass that asks for it). */
int sss_renderer_has_own_term(const sss_renderer *r);

/* Timings of the last evaluate + draw. */
sss_frame_times sss_renderer_times(const sss_renderer *r);

/* Renders one frame into an internal float framebuffer of width × height
 * and returns the tone-mapped linear RGB image (3 floats per pixel, rows
 * bottom-up as OpenGL returns them; values in [0,1] for CLAMP) in *rgb, and,
 * if hdr is non-NULL, the linear radiance × exposure before tone mapping.
 * Both malloc'ed, caller frees. */
sss_result sss_renderer_render_image(sss_renderer *r, const sss_view_params *p, int width, int height, float **rgb,
                                     float **hdr, sss_error *err);

/* Replaces the per-vertex q buffer with q[v * channels + c] (nv × channels
 * floats, the layout sss_decode_all writes): values computed elsewhere (the
 * exact evaluator, another interpolation) are then drawn exactly as the
 * viewer draws its own (sss-stat --error's image error, issue 5). For a
 * file with OWNT the light is not known yet: the next sss_renderer_draw adds
 * the near terms for its p->light when its p->own_term is set (once; nothing
 * when it is 0), so q here is the rest, as the file's decoder returns it. */
void sss_renderer_upload_q(sss_renderer *r, const float *q);

/* sss_renderer_render_image with the per-vertex q supplied (uploaded with
 * sss_renderer_upload_q) instead of evaluated from the file; for a file with
 * OWNT the near terms for p->light are added when p->own_term is set. */
sss_result sss_renderer_render_q_image(sss_renderer *r, const sss_view_params *p, const float *q, int width,
                                       int height, float **rgb, float **hdr, sss_error *err);

/* Creates (or resizes) the internal float framebuffer and binds it, so that
 * sss_renderer_draw renders linear radiance × exposure into it. */
sss_result sss_renderer_bind_offscreen(sss_renderer *r, int width, int height, sss_error *err);

/* The GL name of the per-vertex q buffer (nv·channels floats, SSBO
 * binding 3 of the draw), for evaluators that write it on the GPU
 * (fx_gpu.c: the scene's lights). */
unsigned sss_renderer_q_buffer(const sss_renderer *r);

/* Bytes per vertex of the scattering data as stored in the file (for the overlay). */
double sss_renderer_bytes_per_vertex(const sss_renderer *r);

/* One-line description of f's storage form for the overlay and --bench:
 * sss_quant_name, then for the compressed forms the SH order and code kind
 * and the reference fraction, e.g. "refs 3.0% + SH 3 linear8, 16-bit
 * weights". Always NUL-terminated (n > 0). */
void sss_storage_describe(const sss_bake_file *f, char *buf, size_t n);

#endif

#ifndef SSS_RENDERER_CAMERA
#define SSS_RENDERER_CAMERA
/* Camera frame for p: eye position and unit right / up / forward vectors in
 * world space (for mapping mouse drags to rotations). */
void sss_renderer_camera(const sss_renderer *r, const sss_view_params *p, double eye[3], double right[3],
                         double up[3], double fwd[3]);
/* Applies the tone map of p to one linear value already multiplied by the exposure. */
float sss_tonemap_apply(sss_tonemap t, float x);
#endif
