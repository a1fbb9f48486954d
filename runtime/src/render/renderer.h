/* renderer.h: the renderer's parts (internal to sss_render; the API is
 * sss/render.h). One sss_renderer holds three subsystems, each with its own
 * state and file, plus the glue (renderer.c) that creates them and orders
 * their work in a frame:
 *   sss_gpu_mesh  the mesh as the GPU holds it (geometry, the per-vertex q
 *                 buffer) and its view frame, shared by every pass;
 *   sss_scatter   scatter.c: q for the light from the direction set's rows,
 *                 every storage form, GPU or CPU path (Hao–Varshney 2004
 *                 §3.2, §4);
 *   sss_draw      draw.c: camera, shading draw, tone map, the float
 *                 framebuffer and whole offscreen images;
 * and the passes over q of the effects the file carries (effects/effects.h:
 * the near terms of section OWNT), created from the pass table.
 */
#ifndef SSS_RENDERER_INTERNAL_H
#define SSS_RENDERER_INTERNAL_H

#include <epoxy/gl.h>
#include <math.h>
#include <stdint.h>

#include "sss/gpu.h"
#include "sss/render.h"
#include "sss/vec3.h"

/* The mesh on the GPU, created and owned by the renderer; passes read it. */
typedef struct sss_gpu_mesh {
    const sss_bake_file *f;
    uint32_t nv, nf, C;
    double centre[3], radius; /* sss_mesh_bounding_sphere */
    GLuint vao, vbo_pos, vbo_nrm, ebo;
    GLuint qbuf;              /* per-vertex q, nv·C floats */
} sss_gpu_mesh;

/* scatter.c: the direction set on the GPU, as libsss lays it out
 * (sss/gpu.h), and the CPU path's scratch. */
typedef struct sss_scatter {
    sss_gpu_layout layout;           /* the buffers and programs (borrows the mesh's file) */
    sss_gpu_frame frame;             /* this frame's rows, weights and folded tables */
    GLuint buf[SSS_GPU_BUFFERS];     /* the layout's buffers by SSS_GPU_BUF_*; q is the mesh's qbuf */
    GLuint levels, sh_tab;           /* the frame's folded tables (binding 4 of each pass) */
    GLuint prog[SSS_GPU_PASSES];     /* by SSS_GPU_PASS_*; 0 where the file has no such pass */
    GLuint prog_n4;                  /* the rows pass's 4-nearest variant (SSS_GPU_NEAREST4_DEFINE) */
    /* the coded pass by its SH tables' block: [0] uniform, [1] storage (sss_view_params.sh_tables),
     * compiled when a frame first asks; the layout's own is prog[SSS_GPU_PASS_CODED] */
    GLuint coded[2];
    GLint coded_count[2];            /* their u_count */
    int coded_failed[2];             /* that variant did not compile (said once on stderr) */
    int software;                    /* the GL renders in software (llvmpipe, softpipe, SwiftShader) */
    /* each program's uniform locations, looked up once at creation (by
     * SSS_GPU_PASS_*, then the 4-nearest variant); −1 where it has none */
    struct sss_scatter_uniforms { GLint w, light, channels, count; } uni[SSS_GPU_PASSES + 1];
    float *cpu_q;       /* CPU path scratch */
    double cpu_ms;      /* the CPU path's last evaluation and upload, wall clock */
} sss_scatter;

/* Checks that m->f's storage form can be drawn and builds its programs and
 * buffers; on failure s holds what was made (sss_scatter_destroy frees it). */
sss_result sss_scatter_create(sss_scatter *s, const sss_gpu_mesh *m, sss_error *err);
/* The same with q's rows even when the file holds Q (sss_renderer_create_scalar). */
sss_result sss_scatter_create_scalar(sss_scatter *s, const sss_gpu_mesh *m, sss_error *err);
void sss_scatter_destroy(sss_scatter *s);
/* q for the unit light l into m->qbuf: on the GPU, the compute passes as
 * p's interp and sh_tables say, under the GL_TIME_ELAPSED query `query`;
 * on the CPU, sss_decode_all_interp (interp: sss_interp) and an upload,
 * timed into s->cpu_ms. */
void sss_scatter_gpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3], const sss_view_params *p,
                     GLuint query);
/* 1: the coded pass reads its SH tables from a storage buffer for p
 * (sss_view_params.sh_tables; docs/viewer.md, "SH tables on the GPU"): as
 * p asks, or by default on a GPU, where the invocations' code-dependent
 * loads from a uniform block are serialised, but not on a software GL,
 * where a storage-buffer load is a loop over the lanes; always when the
 * tables do not fit a uniform block. 0 without SH tables. */
int sss_scatter_storage(const sss_scatter *s, const sss_view_params *p);
void sss_scatter_cpu(sss_scatter *s, const sss_gpu_mesh *m, const double l[3], int interp);

/* draw.c: the shading program and the float framebuffer. */
typedef struct sss_draw {
    GLuint prog_shade, prog_shade_ss; /* without and with single scattering (draw.c) */
    struct sss_shadow *shadow; /* the surface terms' shadow map, made on the first frame that asks for it */
    struct sss_single *single; /* single scattering's maps (effects/single.h), made on the first frame that asks */
    GLuint fbo, fbo_color, fbo_depth;
    int fbo_w, fbo_h;
    GLuint qtex; /* non-zero: q per pixel from this RGBA32F texture of the frame's size (splat_gpu.c) */
    /* 1: that q already holds its lights' irradiance, each light's E in its
     * own light-space map (htsm_gpu.c, docs/heterogeneous.md §9.1): not
     * scaled again by p's light_rgb */
    int q_lit;
    /* non-zero (with q_lit): the surface terms per pixel from this RGBA32F
     * texture of the frame's size, every light's each shadowed by its own
     * light-space map (htsm_gpu.c), instead of p's light's with the shadow
     * map */
    GLuint stex;
} sss_draw;

sss_result sss_draw_create(sss_draw *d, sss_error *err);
void sss_draw_destroy(sss_draw *d);
/* The shading draw of m's q into the bound framebuffer under `query`. */
void sss_draw_frame(sss_draw *d, const sss_gpu_mesh *m, const sss_view_params *p, int width, int height,
                    GLuint query);

/* The camera's matrix (column-major perspective × view) and eye for p in
 * the frame of m's bounding sphere: the draw's, and the splatting's camera
 * buffer (splat_gpu.c), which must cover the same pixels. */
void sss_draw_camera_mvp(const sss_gpu_mesh *m, const sss_view_params *p, int width, int height, double eye[3],
                         float mvp[16]);

/* Draws r's frame into its float framebuffer (width × height) and reads
 * it back as sss_renderer_render_image returns it, q as r holds it (per
 * vertex, or per pixel from draw.qtex). */
sss_result sss_draw_read_image(sss_renderer *r, const sss_view_params *p, int width, int height, float **rgb,
                               float **hdr, sss_error *err);

/* The capacity of the pass table (effects/table.c). */
#define SSS_EFFECTS_MAX 8

struct sss_renderer {
    sss_gpu_mesh mesh;
    sss_scatter scatter;
    sss_draw draw;
    void *pass[SSS_EFFECTS_MAX]; /* the passes over q the file has, by table row (effects/effects.h) */
    unsigned pass_on;            /* bit i: table row i was created */
    GLuint queries[3];  /* scatter, draw, near terms */
    int have_times;     /* bits of the queries that hold a result */
    int last_path;
    int near_pending;    /* q was uploaded: the next draw runs the passes over q (near terms) for its light */
};

#endif
