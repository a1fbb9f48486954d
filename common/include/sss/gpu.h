/* sss/gpu.h: a .sss file's direction set laid out for a GPU, without GL.
 *
 * What an engine needs to evaluate q(x_v, ω) on its own GPU, with its own
 * GL or Vulkan code, exactly as sss-view does (Hao–Varshney 2004 §3.2, and
 * §4 for the compressed forms; docs/gpu_layout.md):
 *   - the static buffers (sss_gpu_layout.buffer): every byte to upload once,
 *     each with the binding index its shader declares;
 *   - the programs (sss_gpu_layout.pass): which embedded GLSL source
 *     (sss_gpu_glsl) and which #define lines to compile it with, and how
 *     many work groups to dispatch;
 *   - per frame (sss_gpu_frame_eval): the three direction rows and their
 *     weights for the light, and the light-dependent tables folded on the
 *     CPU (a few thousand products), with their bindings and the uniforms.
 * The passes write q into a buffer the engine owns (binding 3): nv·C
 * float32, element v·C + c, q in 1/sr per unit irradiance, the very floats
 * sss_decode_all returns for the same light (to the bit: the folded tables
 * are the C decoder's terms, and the shaders sum them in its order).
 *
 * Ownership: a layout borrows the file (the rows, the reference indices are
 * the file's own arrays); f must outlive it. What the layout builds (the
 * word-aligned SH codes, the coded-vertex records, the weight table) it
 * owns; sss_gpu_layout_free releases it. A frame owns its tables.
 * Thread safety: a layout is read-only once created; any number of threads
 * may read it and fill frames at once, each its own sss_gpu_frame.
 */
#ifndef SSS_GPU_H
#define SSS_GPU_H

#include <stdint.h>

#include "sss/decode.h" /* sss_interp */
#include "sss/format.h"
#include "sss/result.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The GLSL version line every program starts with; the #define lines of
 * sss_gpu_program.defines follow it, then the source. */
#define SSS_GPU_GLSL_VERSION "#version 430 core\n"
/* The line to add after sss_gpu_program.defines of the rows pass to get its
 * 4-nearest variant (frames of sss_gpu_frame_eval_interp with
 * SSS_INTERP_NEAREST4): four direction rows, the fourth bound at
 * SSS_GPU_ROW4_BINDING, and a vec4 u_w (docs/gpu_layout.md). */
#define SSS_GPU_NEAREST4_DEFINE "#define NEAREST4 1\n"
#define SSS_GPU_ROW4_BINDING 7u
/* Invocations per work group (local_size_x of both shaders). */
#define SSS_GPU_GROUP_SIZE 256u

/* The two passes, in the order they run. The compressed forms need a
 * memory barrier between them: the coded pass reads what the rows pass
 * wrote (binding 5). */
enum {
    SSS_GPU_PASS_ROWS = 0,  /* scatter.comp.glsl: three direction rows interpolated per value (float,
                               lloyd8; the references' rows of the reference form) */
    SSS_GPU_PASS_CODED = 1, /* scatter_coded.comp.glsl: every coded vertex (SH, reference form) */
    SSS_GPU_PASSES = 2
};

/* The buffers, by index into sss_gpu_layout.buffer. */
enum {
    SSS_GPU_BUF_ROWS = 0,    /* the direction rows, row j at j·stride; bound as three ranges (bindings 0–2) */
    SSS_GPU_BUF_Q,           /* the output q, nv·C float32; written by the GPU (binding 3) */
    SSS_GPU_BUF_REF_Q,       /* reference values of the frame, nref·4 float32 (a reference's C ≤ 3 values,
                                then padding); GPU scratch (binding 5) */
    SSS_GPU_BUF_REF_VERTEX,  /* nref uint32: the vertex of each reference (binding 6, rows pass) */
    SSS_GPU_BUF_SH_CODES,    /* SH codes, each coded vertex's on groups of four words of its own (binding 0,
                                coded pass) */
    SSS_GPU_BUF_CODED,       /* per coded vertex 4 uint32: its vertex, its reference triangle's three
                                references (binding 1, coded pass) */
    SSS_GPU_BUF_WEIGHTS,     /* per coded vertex 2 float32: its weights w0, w1 (binding 6, coded pass) */
    SSS_GPU_BUFFERS
};

/* Whether the engine uploads a buffer or the GPU writes it. */
enum { SSS_GPU_UPLOAD = 0, SSS_GPU_WRITTEN = 1 };

typedef struct sss_gpu_buffer {
    const char *name;     /* "rows", "q", "ref_q", "ref_vertex", "sh_codes", "coded", "weights" */
    uint32_t binding;     /* the std430 binding index the shaders declare it at */
    uint32_t passes;      /* bit p: pass p binds it (1u << SSS_GPU_PASS_*); 0: the file has no such buffer */
    uint32_t access;      /* SSS_GPU_UPLOAD or SSS_GPU_WRITTEN (data NULL) */
    uint64_t bytes;       /* size of the GPU buffer: nrows · stride */
    /* The bytes to upload: nrows rows of row_bytes each, back to back; the
     * GPU buffer holds row j at j·stride (the rows buffer: stride is
     * row_bytes rounded up to the row alignment; every other buffer is one
     * row, stride == row_bytes == bytes). Borrowed from the file or owned by
     * the layout; never freed by the caller. sss_gpu_buffer_pack writes the
     * padded image. */
    const void *data;
    uint64_t nrows, row_bytes, stride;
} sss_gpu_buffer;

typedef struct sss_gpu_program {
    const char *name;     /* "scatter" or "scatter_coded"; NULL: the pass does not run for this file */
    const char *source;   /* sss_gpu_glsl(name): the embedded GLSL, NUL-terminated, static */
    char defines[224];    /* "#define X v\n" lines, to put between SSS_GPU_GLSL_VERSION and source */
    uint32_t count;       /* u_count: invocations that do work (rows pass: row entries, nrow·C; coded
                             pass: coded vertices); 0: nothing to dispatch */
    uint32_t groups;      /* work groups to dispatch in x: ceil(count / SSS_GPU_GROUP_SIZE) */
} sss_gpu_program;

typedef struct sss_gpu_layout {
    const sss_bake_file *f;   /* borrowed */
    uint32_t nv, channels;    /* vertices, channels C (1 or 3) */
    sss_quant quant;
    uint32_t ndirs;           /* direction rows in SSS_GPU_BUF_ROWS (0: no rows pass) */
    uint64_t row_range;       /* bytes to bind per row range: row_bytes rounded up to 4 */
    uint32_t row_n;           /* entries per row / C: nv, or nref for the reference form */
    uint32_t ncoded;          /* coded vertices (SH: nv; reference form: nv − nref) */
    uint32_t sh_levels;       /* SH dequantisation levels: 256, 16, 1 (linear16: the step), or 0 without an SH part */
    /* 1: the rows are the vector integrals Q (section QVEC, format 1.7):
     * 3·nv·C float32 per direction, interpolated per component and dotted
     * with the light (uniform u_light), sss_decode_vector_range's floats;
     * the layout of a file with Q, unless made by sss_gpu_layout_create_scalar */
    int vector;
    sss_gpu_program pass[SSS_GPU_PASSES];
    sss_gpu_buffer buffer[SSS_GPU_BUFFERS];
    /* Per-frame block sizes (sss_gpu_frame), 0 when absent. */
    uint64_t levels_bytes;    /* 4·C·256 float32 (lloyd8, reference form): a table per blended row */
    uint64_t sh_bytes;        /* the folded SH tables' floats (sss_decode_fold_floats; SH, reference form with
                                 an SH part), rounded up to 16 bytes when sh_uniform */
    /* 1: the coded pass declares the frame's sh as a uniform block (std140,
     * uniform-buffer binding 4: bind it with GL_UNIFORM_BUFFER), since it
     * fits the 16 KiB every GL 4.3 and Vulkan allows; 0: a storage buffer
     * at binding 4 */
    int sh_uniform;
    void *owned_[3];          /* what the layout built; private */
} sss_gpu_layout;

/* One light's constants: what the engine uploads and sets per frame. */
typedef struct sss_gpu_frame {
    uint32_t row[4];          /* the direction rows of the light's triangle (sss_dirset_lookup); with
                                 SSS_INTERP_NEAREST4 its four nearest samples (sss_dirset_nearest4) */
    uint64_t row_offset[4];   /* byte offsets of those rows in SSS_GPU_BUF_ROWS (row[k] · stride): bind
                                 [row_offset[k], row_offset[k] + row_range) at binding k, rows pass (the
                                 fourth, 4-nearest frames only, at SSS_GPU_ROW4_BINDING) */
    float u_w[4];             /* uniform vec3 u_w: barycentric weights (float rows), u_w[3] = 0; 4-nearest
                                 frames: uniform vec4 u_w; all 0 for no light */
    uint32_t nrows;           /* direction rows the frame blends: 3, or 4 (SSS_INTERP_NEAREST4) */
    uint32_t u_count[SSS_GPU_PASSES]; /* uniform uint u_count of each pass (= pass[p].count) */
    uint32_t u_channels;      /* uniform uint u_channels (rows pass) */
    float u_light[3];         /* uniform vec3 u_light (rows pass of a vector layout): the unit light, as float */
    /* binding 4 of the rows pass: levels[(t·C + c)·256 + x] = w_t · level_c[x], t < 4 (the fourth
     * table 0 in triangle frames) (lloyd8 and the references' rows; NULL otherwise) */
    float *levels;
    uint64_t levels_bytes;
    /* binding 4 of the coded pass (a uniform buffer when the layout's sh_uniform, else a storage
     * buffer): sh[(c·ncoef + i)·L + x] = table_c,i[x] · y_i(ω) (sss_decode_fold_sh; NULL without an
     * SH part) */
    float *sh;
    uint64_t sh_bytes;
} sss_gpu_frame;

/* Lays f's direction set out for upload. row_alignment: the offset
 * alignment of a bound storage-buffer range, in bytes (GL:
 * GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT; Vulkan:
 * minStorageBufferOffsetAlignment); a power of two, 0 for 4; values below 4
 * count as 4. Every storage form is laid out; a scene bake without the
 * direction-set effect (fx.mask without SSS_FX_DIR_SET) gets a layout with
 * no pass and no buffer but q (its q comes from the effect evaluators,
 * sss/effects.h). Fails (one-line message, *layout zeroed) on an unknown
 * storage form or SH kind, an alignment that is not a power of two,
 * coded counts that disagree with the vertex count, nv·C above 2^32 − 1
 * (the shaders index with uint), or no memory. */
sss_result sss_gpu_layout_create(const sss_bake_file *f, uint32_t row_alignment, sss_gpu_layout *layout,
                                 sss_error *err);
/* The same, with q's rows even when f holds Q (to compare q against Q). */
sss_result sss_gpu_layout_create_scalar(const sss_bake_file *f, uint32_t row_alignment, sss_gpu_layout *layout,
                                        sss_error *err);
void sss_gpu_layout_free(sss_gpu_layout *layout);

/* Writes buffer b's GPU image, b->bytes bytes, into dst (padding zeroed). */
void sss_gpu_buffer_pack(const sss_gpu_buffer *b, void *dst);

/* Allocates frame's tables for layout (zeroed otherwise). */
sss_result sss_gpu_frame_init(const sss_gpu_layout *layout, sss_gpu_frame *frame, sss_error *err);
/* Fills frame for the light direction `light` (towards the light, any
 * length; normalised here as sss_decode_all does; a zero or non-finite one
 * gives zero weights and tables, so q = 0). */
void sss_gpu_frame_eval(const sss_gpu_layout *layout, const double light[3], sss_gpu_frame *frame);
/* sss_gpu_frame_eval with a choice of direction interpolation: the frame
 * then gives sss_decode_all_interp's floats for the same light and interp
 * (SSS_INTERP_NEAREST4: the rows pass compiled with
 * SSS_GPU_NEAREST4_DEFINE; the SH pass is the same for both). */
void sss_gpu_frame_eval_interp(const sss_gpu_layout *layout, const double light[3], sss_interp interp,
                               sss_gpu_frame *frame);
void sss_gpu_frame_free(sss_gpu_frame *frame);

/* The embedded GLSL of the evaluation (runtime/shaders/NAME.comp.glsl,
 * byte for byte): "scatter" or "scatter_coded"; NULL for another name. */
const char *sss_gpu_glsl(const char *name);

#ifdef __cplusplus
}
#endif
#endif
