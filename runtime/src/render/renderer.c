/* renderer.c: OpenGL renderer for baked translucent meshes (renderer.h).
 *
 * GPU storage of the scattering data: one buffer holding every direction's
 * row (nv·channels values, float32 or packed bytes), each row padded to the
 * SSBO offset alignment so that the three rows a frame needs can be bound
 * with glBindBufferRange. A bound range is one row (a few MB), far below
 * GL_MAX_SHADER_STORAGE_BLOCK_SIZE (128 MiB on llvmpipe), while the whole
 * table (1 GB for the 437K dragon in RGB float) only needs to fit in memory.
 *
 * Compressed forms (format 1.1, Hao–Varshney 2004 §4) stay compressed on
 * the GPU: the SH codes (§4.1, each vertex's codes word-aligned), and for
 * the reference form the reference rows (laid out like a lloyd8 file's, one
 * entry per reference) plus each coded vertex's triangle and weight codes
 * (§4.2–4.3). Two passes: the references' values, then every coded vertex
 * (blend of three of them plus its SH-coded delta).
 * Per frame the CPU does only the light-dependent, vertex-independent work:
 * it folds the direction weights into the 256-level tables and the SH basis
 * values y_i(light) into the SH tables (a few thousand products), exactly as
 * the C decoder (common/src/decode.c) does, so the GPU's per-vertex sums use
 * the very same float terms and give the C decoder's result to the bit.
 *
 * Near terms (format 1.3, section OWNT; sss/ownterm.h): the rows of such a
 * file hold q minus the largest entries of the §3.1 sum, the vertex's own
 * w̃(o,o) g_o(ω_j) V(x_o, ω_j) and those of its `own_rings` mesh rings: the
 * entries that jump where x_o or a neighbour enters a cast shadow, and that
 * §3.2's interpolation between direction samples would smear. After q is
 * evaluated (either path) or uploaded, two more compute passes add them
 * back for the actual light: the first finds every vertex's own visibility
 * V(x_i, ω) and its transfer g_i V_i; the second adds each vertex's row
 * Σ_i w̃(o, i) g_i V_i, in sss_near_sum's order. V is, by default, the
 * bake's own ray traced on the GPU through a BVH of the mesh built here
 * once (bvh.c): a vertex that gets V wrong is off by about half of its q,
 * so only the bake's rule itself keeps the image error at the bake's. On
 * request (near_visibility = 1) V comes from a shadow map instead (shadow.c,
 * the paper's own test, §3.1, plus the bake's ray against the vertex's own
 * triangles), created on first use and re-rendered only when the light
 * direction changes. Pass 1 depends on the light direction alone, so it
 * runs only when that (or the visibility asked for) changes. A file without
 * OWNT gets none of it: no weights, no BVH, no map, no programs, no passes.
 */
#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "sss/render.h"
#include "bvh.h"
#include "gl_util.h"
#include "shaders.h"
#include "shadow.h"
#include "sss/decode.h"
#include "sss/ownterm.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

struct sss_renderer {
    const sss_bake_file *f;
    uint32_t nv, nf, C;
    double centre[3], radius;
    GLuint vao, vbo_pos, vbo_nrm, ebo;
    GLuint rows;        /* all direction rows, padded (float, lloyd8, or the references' rows) */
    GLsizeiptr row_bytes, row_stride;
    uint32_t row_n;     /* entries per row / channels: nv, or nref for the reference form */
    GLuint levels;      /* lloyd8 / reference rows: the three level tables times the weights, per frame */
    float *fold_l;      /* CPU copy of those, 3·C·256 */
    const float *lvl;   /* the file's level tables (f->levels or f->ref.levels), C·256 */
    GLuint qbuf;        /* per-vertex q, nv·C floats */
    GLuint prog_cs, prog_shade;
    /* compressed forms */
    GLuint prog_coded;  /* second pass: coded vertices */
    uint32_t ncoded, sh_levels;
    GLuint sh_codes;    /* SH codes, each coded vertex's starting on a new word */
    GLuint sh_tab;      /* SH tables times y_i(light), per frame */
    float *fold_sh;     /* CPU copy of those, C·ncoef·levels */
    GLuint ref_q;       /* reference values of the frame, nref·C */
    GLuint ref_vertex, ref_tri, coded_rec, wtab;
    GLuint queries[3];  /* scatter, draw, near terms */
    int have_times;
    float *cpu_q;       /* CPU path scratch */
    sss_frame_times times;
    double cpu_scatter_ms;
    int last_path;
    GLuint fbo, fbo_color, fbo_depth;
    int fbo_w, fbo_h;
    /* near terms (files with OWNT only) */
    sss_shadow *shadow; /* created on the first pass that asks for the map */
    GLuint prog_vis, prog_ray, prog_near; /* pass 1 (map or rays): V and g V per vertex; pass 2: the rows' sums into q */
    GLuint bvh_node, bvh_tri; /* the mesh's BVH (bvh.h) for prog_ray */
    uint32_t bvh_ntri;
    int vis_valid, vis_map, vis_size; /* what pass 1 last computed: map or rays, map size, */
    float vis_dir[3];                 /* and light: lit and gv hold it */
    GLuint lit, gv;     /* V (uint) and g V (float) per vertex */
    GLuint fan;         /* incident triangles per vertex: offsets (nv + 1), then triangle indices */
    GLuint fan_sin;     /* per vertex: sin of the largest angle between n_o and its triangles' normals */
    GLuint near_start, near_idx, near_w; /* sss_near: rows of (vertex, w̃ per channel) */
    float delta;        /* the bake's ray offset, 1e-5 of the bounding-box diagonal (visibility.c) */
    int own_pending;    /* q was uploaded: the next draw adds the near terms for its light */
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return 1e3 * (double)ts.tv_sec + 1e-6 * (double)ts.tv_nsec;
}

void sss_view_params_default(sss_view_params *p)
{
    memset(p, 0, sizeof *p);
    p->light[2] = 1.0;
    p->light_rgb[0] = p->light_rgb[1] = p->light_rgb[2] = 1.0;
    p->view[2] = 1.0;
    p->distance = 3.6;
    p->fov_deg = 35.0;
    p->exposure = 1.0;
    p->scatter = 1;
    p->specular = 1;
    p->tonemap = SSS_TONEMAP_CLAMP;
    p->path = SSS_EVAL_GPU;
    p->own_term = 1;
    p->near_visibility = SSS_NEAR_RAYS;
}

float sss_tonemap_apply(sss_tonemap t, float x)
{
    if (t == SSS_TONEMAP_REINHARD) return x / (1.0f + x);
    return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
}

double sss_view_bounds(const sss_mesh *m, double centre[3])
{
    double lo[3], hi[3];
    sss_mesh_bounds(m, lo, hi);
    for (int k = 0; k < 3; k++) centre[k] = 0.5 * (lo[k] + hi[k]);
    double r2 = 0;
    for (uint32_t v = 0; v < m->nv; v++) {
        double d2 = 0;
        for (int k = 0; k < 3; k++) {
            double d = m->pos[3 * (size_t)v + k] - centre[k];
            d2 += d * d;
        }
        if (d2 > r2) r2 = d2;
    }
    return r2 > 0 ? sqrt(r2) : 1.0;
}

static void normalize3(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int k = 0; k < 3; k++) v[k] /= l;
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

/* The near terms' resources (files with OWNT): their rows and weights from
 * the file's geometry and material (sss_near_build: the file stores no
 * bytes for them), the mesh's BVH for the rays, each vertex's incident
 * triangles for the map, the per-vertex V and g V buffers and the programs.
 * The shadow map itself waits for a pass that asks for it. */
static sss_result own_create(sss_renderer *r, sss_error *err)
{
    const sss_bake_file *f = r->f;
    sss_near nr;
    sss_result res = sss_near_build(&f->mesh, &f->material, f->mm_per_unit, r->C, f->own_rings, &nr, err);
    if (res != SSS_OK) return res;
    const uint64_t nent = nr.start[r->nv];
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    if (max_block > 0 && nent * r->C * sizeof(float) > (uint64_t)max_block) {
        sss_near_free(&nr);
        return sss_fail(err, SSS_ERR_UNSUPPORTED,
                        "renderer: the near terms of %u rings need a %.1f MiB storage buffer, above this GL's limit "
                        "of %.1f MiB (bake with fewer --rings)",
                        f->own_rings, (double)(nent * r->C * sizeof(float)) / 1048576.0,
                        (double)max_block / 1048576.0);
    }
    r->near_start = sss_gl_ssbo((GLsizeiptr)(((size_t)r->nv + 1) * sizeof(uint32_t)), nr.start, GL_STATIC_DRAW);
    r->near_idx = sss_gl_ssbo((GLsizeiptr)(nent * sizeof(uint32_t)), nr.idx, GL_STATIC_DRAW);
    r->near_w = sss_gl_ssbo((GLsizeiptr)(nent * r->C * sizeof(float)), nr.w, GL_STATIC_DRAW);
    sss_near_free(&nr);
    r->gv = sss_gl_ssbo((GLsizeiptr)r->nv * sizeof(float), NULL, GL_DYNAMIC_COPY);
    r->lit = sss_gl_ssbo((GLsizeiptr)r->nv * sizeof(uint32_t), NULL, GL_DYNAMIC_COPY);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    /* each vertex's incident triangles, for pass 1's exact test of the
     * bake's ray against them (shadow.c: the map cannot resolve them) */
    const uint64_t nfan = (uint64_t)r->nv + 1 + 3 * (uint64_t)r->nf;
    if (nfan > UINT32_MAX) return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: mesh too large for the near terms");
    uint32_t *fan = calloc(nfan, sizeof *fan);
    if (!fan) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the vertices' triangle fans");
    for (size_t k = 0; k < 3 * (size_t)r->nf; k++) fan[f->mesh.tri[k] + 1]++;
    fan[0] = r->nv + 1;
    for (uint32_t v = 0; v < r->nv; v++) fan[v + 1] += fan[v];
    for (size_t k = 0; k < 3 * (size_t)r->nf; k++) fan[fan[f->mesh.tri[k]]++] = (uint32_t)(k / 3);
    for (uint32_t v = r->nv; v > 0; v--) fan[v] = fan[v - 1]; /* the fill advanced each start to its end */
    fan[0] = r->nv + 1;
    r->fan = sss_gl_ssbo((GLsizeiptr)(nfan * sizeof *fan), fan, GL_STATIC_DRAW);
    /* The ray cannot hit a triangle of the fan while ω is above every
     * triangle's plane, which holds when n_o·ω > sin α, α the largest angle
     * between n_o and a triangle's normal: the pass then skips the fan
     * (most vertices, most lights). sin α = 1 (never skip) where a triangle
     * faces away from n_o or is degenerate. */
    float *fs = malloc((size_t)r->nv * sizeof *fs + 1);
    if (!fs) {
        free(fan);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the vertices' triangle fans");
    }
    for (uint32_t v = 0; v < r->nv; v++) {
        const float *n = &f->mesh.nrm[3 * (size_t)v];
        double cmin = 1.0;
        for (uint32_t k = fan[v]; k < fan[v + 1]; k++) {
            const uint32_t *t = &f->mesh.tri[3 * (size_t)fan[k]];
            double e1[3], e2[3], fnrm[3];
            for (int i = 0; i < 3; i++) {
                e1[i] = (double)f->mesh.pos[3 * (size_t)t[1] + i] - f->mesh.pos[3 * (size_t)t[0] + i];
                e2[i] = (double)f->mesh.pos[3 * (size_t)t[2] + i] - f->mesh.pos[3 * (size_t)t[0] + i];
            }
            cross3(e1, e2, fnrm);
            const double len = sqrt(fnrm[0] * fnrm[0] + fnrm[1] * fnrm[1] + fnrm[2] * fnrm[2]);
            const double c = len > 0 ? (n[0] * fnrm[0] + n[1] * fnrm[1] + n[2] * fnrm[2]) / len : -1.0;
            if (c < cmin) cmin = c;
        }
        /* a margin of 1e-3 for the float arithmetic of the pass */
        fs[v] = cmin > 0.0 ? (float)fmin(1.0, sqrt(fmax(0.0, 1.0 - cmin * cmin)) + 1e-3) : 1.0f;
    }
    r->fan_sin = sss_gl_ssbo((GLsizeiptr)r->nv * sizeof *fs, fs, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    free(fs);
    free(fan);
    double lo[3], hi[3];
    /* as visibility.c computes it, so that the origins are the bake's floats */
    r->delta = (float)(1e-5 * sss_mesh_bounds(&f->mesh, lo, hi));
    char pre[48];
    snprintf(pre, sizeof pre, "#define CHANNELS %u\n", r->C);
    GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, "", sss_glsl_own_vis_cs, err);
    if (!cs || !(r->prog_vis = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
    cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_own_near_cs, err);
    if (!cs || !(r->prog_near = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
    /* The BVH for the rays. Where its buffers exceed this GL's storage block
     * (above ~2.8M triangles at 48 bytes each in llvmpipe's 128 MiB), the
     * renderer keeps working with the shadow map alone (prog_ray stays 0). */
    sss_bvh bvh;
    res = sss_bvh_build(f->mesh.pos, r->nv, f->mesh.tri, r->nf, &bvh, err);
    if (res != SSS_OK) return res;
    const uint64_t node_bytes = (uint64_t)bvh.nnode * sizeof *bvh.node;
    const uint64_t tri_bytes = (uint64_t)bvh.ntri * 12 * sizeof(float);
    if (max_block <= 0 || (node_bytes <= (uint64_t)max_block && tri_bytes <= (uint64_t)max_block)) {
        r->bvh_node = sss_gl_ssbo((GLsizeiptr)node_bytes, bvh.node, GL_STATIC_DRAW);
        r->bvh_tri = sss_gl_ssbo((GLsizeiptr)tri_bytes, bvh.tri, GL_STATIC_DRAW);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        r->bvh_ntri = bvh.ntri;
        snprintf(pre, sizeof pre, "#define RAYS 1\n#define SSS_BVH_STACK %d\n", SSS_BVH_STACK);
        cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_own_vis_cs, err);
        if (!cs || !(r->prog_ray = sss_gl_link(cs, 0, err))) {
            sss_bvh_free(&bvh);
            return SSS_ERR_UNSUPPORTED;
        }
    }
    sss_bvh_free(&bvh);
    return SSS_OK;
}

sss_result sss_renderer_create(const sss_bake_file *f, sss_renderer **out, sss_error *err)
{
    *out = NULL;
    if (epoxy_gl_version() < 43)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "OpenGL 4.3 or newer is needed (this context has %d.%d)",
                        epoxy_gl_version() / 10, epoxy_gl_version() % 10);
    sss_renderer *r = calloc(1, sizeof *r);
    if (!r) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    r->f = f;
    r->nv = f->mesh.nv;
    r->nf = f->mesh.nf;
    r->C = f->channels;
    r->cpu_q = malloc((size_t)r->nv * r->C * sizeof(float));
    if (!r->cpu_q) { free(r); return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory"); }

    r->radius = sss_view_bounds(&f->mesh, r->centre);

    const sss_quant qt = f->quant;
    const int l8 = qt == SSS_QUANT_LLOYD8, refs = qt == SSS_QUANT_REFS, sh = qt == SSS_QUANT_SH;
    if (qt != SSS_QUANT_FLOAT && !l8 && !refs && !sh) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: storage form %d is not supported", (int)qt);
    }
    const sss_shcode *shc = &f->sh;
    r->sh_levels = shc->ncoef ? sss_shq_levels(shc->kind) : 0;
    if ((sh || refs) && shc->ncoef && !r->sh_levels) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: SH code kind %u is not supported", shc->kind);
    }
    /* SH-only codes every vertex, in vertex order; the reference form codes
     * the others (the reader has checked both). */
    r->ncoded = sh || refs ? shc->ncoded : 0;
    if ((sh && r->ncoded != r->nv) || (refs && (uint64_t)r->ncoded + f->ref.nref != r->nv)) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_CORRUPT, "renderer: %u coded vertices do not match %u vertices", r->ncoded, r->nv);
    }

    /* Programs: the row interpolation (float, lloyd8, and pass 1 of the
     * reference form), the coded-vertex pass (compressed forms), shading. */
    int ok = 1;
    /* A scene bake without the direction-set effect (format 1.2,
     * docs/scenes.md) has no rows to interpolate: only the shading program
     * is built, and the per-vertex values come from the effect evaluation
     * (sss_renderer_upload_q, runtime/src/scene_view.c). */
    const int no_set = f->fx.mask && !(f->fx.mask & SSS_FX_DIR_SET);
    if (!sh && !no_set) {
        GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, refs ? "#define LLOYD8 1\n#define REFS 1\n" : l8 ? "#define LLOYD8 1\n" : "",
                                   sss_glsl_scatter_cs, err);
        ok = cs && (r->prog_cs = sss_gl_link(cs, 0, err)) != 0;
    }
    if (ok && (sh || refs)) {
        char pre[192];
        snprintf(pre, sizeof pre, "#define CHANNELS %u\n#define NCOEF %u\n#define SH_LEVELS %u\n%s%s", r->C, shc->ncoef,
                 r->sh_levels ? r->sh_levels : 256u, shc->kind == SSS_SHQ_LLOYD4 ? "#define SH_NIBBLE 1\n" : "",
                 refs ? "#define REFS 1\n" : "");
        GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_coded_cs, err);
        ok = cs && (r->prog_coded = sss_gl_link(cs, 0, err)) != 0;
    }
    GLuint vs = ok ? sss_gl_compile(GL_VERTEX_SHADER, "", sss_glsl_shade_vs, err) : 0;
    GLuint fs = vs ? sss_gl_compile(GL_FRAGMENT_SHADER, "", sss_glsl_shade_fs, err) : 0;
    r->prog_shade = fs ? sss_gl_link(vs, fs, err) : 0;
    if (!r->prog_shade) {
        if (vs && !fs) glDeleteShader(vs);
        sss_renderer_destroy(r);
        return SSS_ERR_UNSUPPORTED;
    }

    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    glGenBuffers(1, &r->vbo_pos);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo_pos);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)r->nv * 3 * sizeof(float), f->mesh.pos, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    glGenBuffers(1, &r->vbo_nrm);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo_nrm);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)r->nv * 3 * sizeof(float), f->mesh.nrm, GL_STATIC_DRAW);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(1);
    glGenBuffers(1, &r->ebo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)r->nf * 3 * sizeof(uint32_t), f->mesh.tri, GL_STATIC_DRAW);
    glBindVertexArray(0);

    /* Buffers bound whole must fit one storage block. */
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    const uint32_t per_word = shc->kind == SSS_SHQ_LLOYD4 ? 8 : 4, ncv = r->C * shc->ncoef;
    const uint32_t vwords = shc->ncoef ? (ncv + per_word - 1) / per_word : 0;
    const uint64_t code_bytes = (uint64_t)r->ncoded * vwords * 4;
    const uint64_t whole[3] = {(uint64_t)r->nv * r->C * sizeof(float), code_bytes,
                               (uint64_t)r->ncoded * 3 * sizeof(uint32_t)};
    for (int k = 0; k < 3; k++)
        if (max_block > 0 && whole[k] > (uint64_t)max_block) {
            sss_renderer_destroy(r);
            return sss_fail(err, SSS_ERR_UNSUPPORTED,
                            "renderer: a %.1f MiB storage buffer is needed, above this GL's limit of %.1f MiB",
                            (double)whole[k] / 1048576.0, (double)max_block / 1048576.0);
        }

    /* Direction rows, each padded to the SSBO offset alignment: the
     * vertices' rows (float, lloyd8) or the references' (§4.2). */
    if (!sh && !no_set) {
        r->row_n = refs ? f->ref.nref : r->nv;
        r->row_bytes = (GLsizeiptr)r->row_n * r->C * (l8 || refs ? 1 : 4);
        r->row_stride = sss_gl_row_stride(r->row_bytes);
        const void *src = refs ? (const void *)f->ref.idx : l8 ? (const void *)f->qidx : (const void *)f->q;
        r->rows = sss_gl_rows(src, f->dirs.n, r->row_bytes, r->row_stride);
    }
    if (l8 || refs) {
        r->lvl = refs ? f->ref.levels : f->levels;
        r->fold_l = malloc((size_t)3 * r->C * 256 * sizeof(float));
        r->levels = sss_gl_ssbo((GLsizeiptr)3 * r->C * 256 * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    }
    if (shc->ncoef && (sh || refs)) {
        /* The codes as stored, but each vertex's C·ncoef codes starting on
         * a word of their own (at most 3 bytes of padding per vertex): an
         * invocation then loads its vertex's few words once, at fixed
         * offsets, instead of one word per code. */
        uint32_t *words = calloc((size_t)r->ncoded * vwords + 1, sizeof *words);
        if (words) {
            const uint32_t bits = 32 / per_word;
            for (size_t k = 0; k < r->ncoded; k++)
                for (uint32_t b = 0; b < ncv; b++)
                    words[k * vwords + b / per_word] |= sss_shq_code(shc->code, shc->kind, (uint64_t)k * ncv + b)
                                                        << (b % per_word * bits);
            r->sh_codes = sss_gl_ssbo((GLsizeiptr)code_bytes, words, GL_STATIC_DRAW);
            free(words);
        }
        size_t ntab = (size_t)r->C * shc->ncoef * r->sh_levels;
        r->fold_sh = malloc(ntab * sizeof(float));
        r->sh_tab = sss_gl_ssbo((GLsizeiptr)(ntab * sizeof(float)), NULL, GL_DYNAMIC_DRAW);
    }
    if (refs) {
        const sss_refcode *rf = &f->ref;
        r->ref_q = sss_gl_ssbo((GLsizeiptr)rf->nref * r->C * sizeof(float), NULL, GL_DYNAMIC_COPY);
        r->ref_vertex = sss_gl_ssbo((GLsizeiptr)rf->nref * sizeof(uint32_t), rf->ref_vertex, GL_STATIC_DRAW);
        r->ref_tri = sss_gl_ssbo((GLsizeiptr)rf->nrt * 3 * sizeof(uint32_t), rf->ref_tri, GL_STATIC_DRAW);
        /* one record per coded vertex: its vertex, its reference triangle,
         * its two weight codes packed in one word (≤ 16 bits each) */
        uint32_t *rec = malloc(((size_t)r->ncoded * 3 + 1) * sizeof *rec);
        /* every weight a code can stand for, as coded_weights in the C
         * decoder computes it (in double): at most 65536 values, and the
         * GPU then needs no double division */
        const uint32_t nw = rf->wbits == 16 ? 65536u : 256u;
        double *wt = malloc(nw * sizeof *wt);
        if (rec && wt) {
            for (size_t k = 0; k < r->ncoded; k++) {
                rec[3 * k] = rf->coded_vertex[k];
                rec[3 * k + 1] = rf->vtri[k];
                rec[3 * k + 2] = (uint32_t)rf->w[2 * k] | (uint32_t)rf->w[2 * k + 1] << 16;
            }
            const double span = (double)rf->w_hi - rf->w_lo, wmax = rf->wbits == 16 ? 65535.0 : 255.0;
            for (uint32_t x = 0; x < nw; x++) wt[x] = rf->w_lo + span * ((double)x / wmax);
            r->coded_rec = sss_gl_ssbo((GLsizeiptr)r->ncoded * 3 * sizeof(uint32_t), rec, GL_STATIC_DRAW);
            r->wtab = sss_gl_ssbo((GLsizeiptr)nw * sizeof(double), wt, GL_STATIC_DRAW);
        }
        free(rec);
        free(wt);
    }
    if ((r->lvl && !r->fold_l) || (r->sh_tab && (!r->fold_sh || !r->sh_codes)) || (refs && !r->wtab)) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    }
    glGenBuffers(1, &r->qbuf);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->qbuf);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)r->nv * r->C * sizeof(float), NULL, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glGenQueries(3, r->queries);
    if (f->own_term) {
        sss_result res = own_create(r, err);
        if (res != SSS_OK) {
            sss_renderer_destroy(r);
            return res;
        }
    }
    if (glGetError() == GL_OUT_OF_MEMORY) {
        sss_renderer_destroy(r);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: the GPU is out of memory for %u directions x %u vertices",
                        f->dirs.n, f->mesh.nv);
    }
    *out = r;
    return SSS_OK;
}

void sss_renderer_destroy(sss_renderer *r)
{
    if (!r) return;
    GLuint bufs[22] = {r->vbo_pos, r->vbo_nrm,  r->ebo,     r->rows,    r->levels,    r->qbuf, r->sh_codes,
                       r->sh_tab,  r->ref_q,    r->ref_vertex, r->ref_tri, r->coded_rec, r->wtab, r->lit,
                       r->gv,      r->fan,      r->near_start, r->near_idx, r->near_w, r->fan_sin,
                       r->bvh_node, r->bvh_tri};
    glDeleteBuffers(22, bufs);
    if (r->vao) glDeleteVertexArrays(1, &r->vao);
    if (r->prog_cs) glDeleteProgram(r->prog_cs);
    if (r->prog_coded) glDeleteProgram(r->prog_coded);
    if (r->prog_shade) glDeleteProgram(r->prog_shade);
    if (r->prog_vis) glDeleteProgram(r->prog_vis);
    if (r->prog_ray) glDeleteProgram(r->prog_ray);
    if (r->prog_near) glDeleteProgram(r->prog_near);
    sss_shadow_destroy(r->shadow);
    if (r->queries[0]) glDeleteQueries(3, r->queries);
    if (r->fbo) {
        glDeleteFramebuffers(1, &r->fbo);
        glDeleteRenderbuffers(1, &r->fbo_color);
        glDeleteRenderbuffers(1, &r->fbo_depth);
    }
    free(r->cpu_q);
    free(r->fold_l);
    free(r->fold_sh);
    free(r);
}

void sss_renderer_camera(const sss_renderer *r, const sss_view_params *p, double eye[3], double right[3],
                         double up[3], double fwd[3])
{
    double v[3] = {p->view[0], p->view[1], p->view[2]};
    normalize3(v);
    if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.5)) v[0] = 0, v[1] = 0, v[2] = 1;
    double dist = (p->distance > 0 ? p->distance : 3.6) * r->radius;
    /* up: +y unless looking along it, then +z */
    double wup[3] = {0, 1, 0};
    if (fabs(v[1]) > 0.999) wup[1] = 0, wup[2] = 1;
    for (int k = 0; k < 3; k++) fwd[k] = -v[k];
    cross3(fwd, wup, right);
    normalize3(right);
    cross3(right, fwd, up);
    double target[3];
    for (int k = 0; k < 3; k++) {
        target[k] = r->centre[k] + (p->pan[0] * right[k] + p->pan[1] * up[k]) * r->radius;
        eye[k] = target[k] + v[k] * dist;
    }
}

/* The shadow map of the size asked for (clamped to 256 … 8192), created or
 * replaced here on first use; 0 when none can be had (the old one is kept
 * when a new size fails). */
static int own_map(sss_renderer *r, int size)
{
    size = size > 0 ? (size < 256 ? 256 : size > 8192 ? 8192 : size) : SSS_SHADOW_SIZE;
    if (!r->shadow || size != sss_shadow_size(r->shadow)) {
        sss_shadow *ns = NULL;
        sss_error e = {{0}};
        if (sss_shadow_create(r->vao, r->nf, r->centre, r->radius, size, &ns, &e) == SSS_OK) {
            sss_shadow_destroy(r->shadow);
            r->shadow = ns;
        }
    }
    return r->shadow != NULL;
}

/* Adds the near terms for unit light l to q (binding 3) and records every
 * vertex's V, on the GPU whichever path evaluated q: by the bake's ray
 * through the BVH, or from the shadow map when p asks for it (or when
 * there is no BVH, or no map can be had: the other one then). */
static void own_pass(sss_renderer *r, const double l[3], const sss_view_params *p)
{
    const float lf[3] = {(float)l[0], (float)l[1], (float)l[2]};
    if (!(lf[0] * lf[0] + lf[1] * lf[1] + lf[2] * lf[2] > 0.5f)) return; /* zero or NaN light: no light */
    int map = p->near_visibility == SSS_NEAR_MAP || !r->prog_ray;
    if (map && !own_map(r, p->shadow_size)) map = 0;
    if (!map && !r->prog_ray) return;
    const int size = map ? sss_shadow_size(r->shadow) : 0;
    /* lit and gv depend on the light direction and the test alone */
    const int fresh = !(r->vis_valid && r->vis_map == map && r->vis_size == size && r->vis_dir[0] == lf[0] &&
                        r->vis_dir[1] == lf[1] && r->vis_dir[2] == lf[2]);
    if (map) sss_shadow_update(r->shadow, lf, r->queries[2]); /* begins the timer query */
    else glBeginQuery(GL_TIME_ELAPSED, r->queries[2]);
    if (fresh) {
        /* pass 1: V and g V per vertex */
        GLuint pr = map ? r->prog_vis : r->prog_ray;
        glUseProgram(pr);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, r->vbo_pos);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, r->vbo_nrm);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r->gv);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->lit);
        if (map) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, r->ebo);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, r->fan);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->fan_sin);
            glActiveTexture(GL_TEXTURE0);
            glBindTexture(GL_TEXTURE_2D, sss_shadow_texture(r->shadow));
            glUniform1i(glGetUniformLocation(pr, "u_depth"), 0);
            glUniformMatrix4fv(glGetUniformLocation(pr, "u_shadow"), 1, GL_FALSE, sss_shadow_matrix(r->shadow));
            glUniform1i(glGetUniformLocation(pr, "u_size"), sss_shadow_size(r->shadow));
            glUniform1f(glGetUniformLocation(pr, "u_offset"),
                        (float)(SSS_SHADOW_NORMAL_OFFSET * sss_shadow_texel(r->shadow)));
            glUniform1f(glGetUniformLocation(pr, "u_bias_c"), (float)SSS_SHADOW_BIAS_CONST);
            glUniform1f(glGetUniformLocation(pr, "u_bias_s"), (float)SSS_SHADOW_BIAS_SLOPE);
            glUniform1f(glGetUniformLocation(pr, "u_tan_max"), (float)SSS_SHADOW_TAN_MAX);
        } else {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, r->bvh_node);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, r->bvh_tri);
            /* the unit light in double too: the bake's facing test, n·ω > 0,
             * is evaluated in double (transfer.c, bake.c) */
            glUniform3d(glGetUniformLocation(pr, "u_light_d"), l[0], l[1], l[2]);
            glUniform1ui(glGetUniformLocation(pr, "u_ntri"), r->bvh_ntri);
        }
        glUniform1f(glGetUniformLocation(pr, "u_delta"), r->delta);
        glUniform3f(glGetUniformLocation(pr, "u_light"), lf[0], lf[1], lf[2]);
        glUniform1f(glGetUniformLocation(pr, "u_eta"), (float)r->f->material.eta);
        glUniform1ui(glGetUniformLocation(pr, "u_count"), r->nv);
        glDispatchCompute((r->nv + 63) / 64, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        if (map) glBindTexture(GL_TEXTURE_2D, 0);
        r->vis_valid = 1;
        r->vis_map = map;
        r->vis_size = size;
        memcpy(r->vis_dir, lf, sizeof lf);
    }
    /* pass 2: q[o] += Σ_i w̃(o, i) g_i V_i over o's row */
    GLuint pr = r->prog_near;
    glUseProgram(pr);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, r->near_start);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, r->near_idx);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r->gv);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->qbuf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->near_w);
    glUniform1ui(glGetUniformLocation(pr, "u_count"), r->nv);
    glDispatchCompute((r->nv + 255) / 256, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glEndQuery(GL_TIME_ELAPSED);
    r->have_times |= 4;
}

void sss_renderer_evaluate(sss_renderer *r, const sss_view_params *p)
{
    const sss_bake_file *f = r->f;
    double l[3] = {p->light[0], p->light[1], p->light[2]};
    normalize3(l);
    r->last_path = p->path;
    r->own_pending = 0;
    r->have_times &= ~4; /* own_ms: only when this frame runs the passes */
    if (p->path == SSS_EVAL_CPU) {
        double t0 = now_ms();
        sss_decode_all(f, l, r->cpu_q);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->qbuf);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->nv * r->C * sizeof(float), r->cpu_q);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        r->cpu_scatter_ms = now_ms() - t0;
        if (r->prog_near && p->own_term) own_pass(r, l, p);
        return;
    }
    uint32_t idx[3] = {0, 0, 0};
    double w[3] = {0.0, 0.0, 0.0};
    if (r->rows && sss_dirset_lookup(&f->dirs, l, idx, w) < 0 && f->dirs.ntri > 0) {
        idx[0] = idx[1] = idx[2] = 0;
        w[0] = w[1] = w[2] = 0.0; /* zero or NaN light: no scattering */
    }
    /* Light-dependent tables, folded on the CPU in double and rounded once,
     * term for term what the C decoder forms (see the top of this file). */
    if (r->fold_l) {
        /* T_t[c][x] = w_t · level_c[x]: the §3.2 interpolation of 8-bit rows
         * becomes three table loads per value */
        const size_t n = (size_t)r->C * 256;
        for (size_t t = 0; t < 3; t++)
            for (size_t x = 0; x < n; x++) r->fold_l[t * n + x] = (float)(w[t] * r->lvl[x]);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->levels);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(3 * n * sizeof(float)), r->fold_l);
    }
    if (r->fold_sh) {
        /* T_c,i[x] = table_c,i[x] · y_i(ω): q̃ = Σ_i c_i y_i(ω) (§4.1) becomes
         * one table load per coefficient */
        const size_t n = (size_t)r->C * f->sh.ncoef * r->sh_levels;
        sss_decode_fold_sh(f, l, r->fold_sh);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->sh_tab);
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(n * sizeof(float)), r->fold_sh);
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glBeginQuery(GL_TIME_ELAPSED, r->queries[0]);
    GLuint count = r->row_n * r->C;
    if (r->prog_cs && count > 0) {
        /* rows of the vertices (float, lloyd8), or pass 1 of the reference
         * form: the references' values, also scattered to their vertices */
        glUseProgram(r->prog_cs);
        for (int k = 0; k < 3; k++)
            glBindBufferRange(GL_SHADER_STORAGE_BUFFER, (GLuint)k, r->rows, r->row_stride * (GLintptr)idx[k],
                              (r->row_bytes + 3) / 4 * 4);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->qbuf);
        if (r->levels) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->levels);
        if (r->ref_q) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, r->ref_q);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, r->ref_vertex);
        }
        glUniform3f(glGetUniformLocation(r->prog_cs, "u_w"), (float)w[0], (float)w[1], (float)w[2]);
        glUniform1ui(glGetUniformLocation(r->prog_cs, "u_count"), count);
        glUniform1ui(glGetUniformLocation(r->prog_cs, "u_channels"), r->C);
        glDispatchCompute((count + 255) / 256, 1, 1);
    }
    count = r->ncoded;
    if (r->prog_coded && count > 0) {
        /* pass 2 reads the reference values pass 1 has just written */
        if (r->prog_cs) glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        glUseProgram(r->prog_coded);
        if (r->sh_codes) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, r->sh_codes);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->sh_tab);
        }
        if (r->coded_rec) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, r->coded_rec);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r->ref_tri);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, r->ref_q);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, r->wtab);
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->qbuf);
        glUniform1ui(glGetUniformLocation(r->prog_coded, "u_count"), count);
        glDispatchCompute((count + 255) / 256, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glEndQuery(GL_TIME_ELAPSED);
    r->have_times |= 1;
    if (r->prog_near && p->own_term) own_pass(r, l, p);
}

static void mat4_mul(const double a[16], const double b[16], float out[16])
{
    for (int c = 0; c < 4; c++)
        for (int rr = 0; rr < 4; rr++) {
            double s = 0;
            for (int k = 0; k < 4; k++) s += a[k * 4 + rr] * b[c * 4 + k];
            out[c * 4 + rr] = (float)s;
        }
}

void sss_renderer_draw(sss_renderer *r, const sss_view_params *p, int width, int height)
{
    double eye[3], right[3], up[3], fwd[3];
    sss_renderer_camera(r, p, eye, right, up, fwd);
    /* column-major view and perspective matrices */
    double V[16] = {right[0], up[0], -fwd[0], 0, right[1], up[1], -fwd[1], 0, right[2], up[2], -fwd[2], 0, 0, 0, 0, 1};
    V[12] = -(right[0] * eye[0] + right[1] * eye[1] + right[2] * eye[2]);
    V[13] = -(up[0] * eye[0] + up[1] * eye[1] + up[2] * eye[2]);
    V[14] = fwd[0] * eye[0] + fwd[1] * eye[1] + fwd[2] * eye[2];
    double dist = (p->distance > 0 ? p->distance : 3.6) * r->radius;
    double zn = fmax(dist - 1.5 * r->radius, 1e-3 * r->radius), zf = dist + 1.5 * r->radius;
    double fy = 1.0 / tan(0.5 * (p->fov_deg > 0 ? p->fov_deg : 35.0) * M_PI / 180.0);
    double aspect = height > 0 ? (double)width / height : 1.0;
    double P[16] = {0};
    P[0] = fy / aspect;
    P[5] = fy;
    P[10] = (zf + zn) / (zn - zf);
    P[11] = -1;
    P[14] = 2 * zf * zn / (zn - zf);
    float mvp[16];
    mat4_mul(P, V, mvp);
    double l[3] = {p->light[0], p->light[1], p->light[2]};
    normalize3(l);
    if (r->own_pending) {
        /* uploaded q: its near terms for this frame's light, once */
        if (p->own_term) own_pass(r, l, p);
        r->own_pending = 0;
    }

    glViewport(0, 0, width, height);
    glClearColor(p->background[0], p->background[1], p->background[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glBeginQuery(GL_TIME_ELAPSED, r->queries[1]);
    glUseProgram(r->prog_shade);
    GLuint pr = r->prog_shade;
    glUniformMatrix4fv(glGetUniformLocation(pr, "u_mvp"), 1, GL_FALSE, mvp);
    glUniform1ui(glGetUniformLocation(pr, "u_channels"), r->C);
    glUniform3f(glGetUniformLocation(pr, "u_eye"), (float)eye[0], (float)eye[1], (float)eye[2]);
    glUniform3f(glGetUniformLocation(pr, "u_light"), (float)l[0], (float)l[1], (float)l[2]);
    glUniform3f(glGetUniformLocation(pr, "u_light_rgb"), (float)p->light_rgb[0], (float)p->light_rgb[1],
                (float)p->light_rgb[2]);
    glUniform1f(glGetUniformLocation(pr, "u_eta"), (float)r->f->material.eta);
    glUniform1f(glGetUniformLocation(pr, "u_exposure"), (float)(p->exposure > 0 ? p->exposure : 1.0));
    glUniform1i(glGetUniformLocation(pr, "u_scatter"), p->scatter);
    glUniform1i(glGetUniformLocation(pr, "u_specular"), p->specular);
    GLint fb = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);
    int offscreen = fb != 0 && (GLuint)fb == r->fbo;
    glUniform1i(glGetUniformLocation(pr, "u_tonemap"), offscreen ? -1 : (int)p->tonemap);
    glUniform1i(glGetUniformLocation(pr, "u_srgb"), offscreen ? 0 : 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->qbuf);
    glBindVertexArray(r->vao);
    glUniform1i(glGetUniformLocation(pr, "u_flat"), 0);
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * r->nf), GL_UNSIGNED_INT, NULL);
    if (p->wireframe) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_POLYGON_OFFSET_LINE);
        glPolygonOffset(-1.0f, -1.0f);
        glUniform1i(glGetUniformLocation(pr, "u_flat"), 1);
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * r->nf), GL_UNSIGNED_INT, NULL);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDisable(GL_POLYGON_OFFSET_LINE);
    }
    glBindVertexArray(0);
    glEndQuery(GL_TIME_ELAPSED);
    r->have_times |= 2;
}

void sss_renderer_read_q(sss_renderer *r, float *out)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->qbuf);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->nv * r->C * sizeof(float), out);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
}

void sss_renderer_read_own_visibility(sss_renderer *r, uint8_t *lit)
{
    if (!r->lit) {
        memset(lit, 1, r->nv); /* no own term: nothing was tested */
        return;
    }
    uint32_t *u = malloc((size_t)r->nv * sizeof *u + 1);
    if (!u) {
        memset(lit, 0, r->nv);
        return;
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->lit);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->nv * sizeof *u, u);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    for (uint32_t v = 0; v < r->nv; v++) lit[v] = u[v] != 0;
    free(u);
}

int sss_renderer_has_own_term(const sss_renderer *r) { return r->prog_near != 0; }

sss_frame_times sss_renderer_times(const sss_renderer *r)
{
    sss_frame_times t = {0, 0, 0};
    GLuint64 ns = 0;
    if (r->last_path == SSS_EVAL_CPU) t.scatter_ms = r->cpu_scatter_ms;
    else if (r->have_times & 1) {
        glGetQueryObjectui64v(r->queries[0], GL_QUERY_RESULT, &ns);
        t.scatter_ms = 1e-6 * (double)ns;
    }
    if (r->have_times & 2) {
        glGetQueryObjectui64v(r->queries[1], GL_QUERY_RESULT, &ns);
        t.draw_ms = 1e-6 * (double)ns;
    }
    if (r->have_times & 4) {
        glGetQueryObjectui64v(r->queries[2], GL_QUERY_RESULT, &ns);
        t.own_ms = 1e-6 * (double)ns;
    }
    return t;
}

unsigned sss_renderer_q_buffer(const sss_renderer *r) { return r->qbuf; }

double sss_renderer_bytes_per_vertex(const sss_renderer *r) { return sss_file_integral_bytes_per_vertex(r->f); }

void sss_storage_describe(const sss_bake_file *f, char *buf, size_t n)
{
    if (!n) return;
    const char *q = sss_quant_name(f->quant);
    const sss_shcode *s = &f->sh;
    if (f->quant == SSS_QUANT_SH) {
        snprintf(buf, n, "%s: SH %u %s", q, s->order, sss_shq_name(s->kind));
    } else if (f->quant == SSS_QUANT_REFS) {
        double pct = f->mesh.nv ? 100.0 * f->ref.nref / f->mesh.nv : 0.0;
        if (s->ncoef)
            snprintf(buf, n, "%s %.1f%% + SH %u %s, %u-bit weights", q, pct, s->order, sss_shq_name(s->kind),
                     f->ref.wbits);
        else
            snprintf(buf, n, "%s %.1f%%, %u-bit weights", q, pct, f->ref.wbits);
    } else {
        snprintf(buf, n, "%s", q);
    }
}

sss_result sss_renderer_bind_offscreen(sss_renderer *r, int width, int height, sss_error *err)
{
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return sss_fail(err, SSS_ERR_ARG, "image size %dx%d out of range [1, 16384]", width, height);
    if (!r->fbo || r->fbo_w != width || r->fbo_h != height) {
        if (r->fbo) {
            glDeleteFramebuffers(1, &r->fbo);
            glDeleteRenderbuffers(1, &r->fbo_color);
            glDeleteRenderbuffers(1, &r->fbo_depth);
        }
        glGenFramebuffers(1, &r->fbo);
        glGenRenderbuffers(1, &r->fbo_color);
        glGenRenderbuffers(1, &r->fbo_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, r->fbo_color);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA32F, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, r->fbo_depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, r->fbo_color);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, r->fbo_depth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            return sss_fail(err, SSS_ERR_UNSUPPORTED, "float framebuffer %dx%d is not supported", width, height);
        }
        r->fbo_w = width;
        r->fbo_h = height;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    return SSS_OK;
}

void sss_renderer_upload_q(sss_renderer *r, const float *q)
{
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->qbuf);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)r->nv * r->C * sizeof(float), q);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    /* the light is not known here: the next draw adds the near terms */
    r->own_pending = r->prog_near != 0;
    r->have_times &= ~4;
}

static sss_result render_image(sss_renderer *r, const sss_view_params *p, const float *q, int width, int height,
                               float **rgb, float **hdr, sss_error *err);

sss_result sss_renderer_render_image(sss_renderer *r, const sss_view_params *p, int width, int height, float **rgb,
                                     float **hdr, sss_error *err)
{
    return render_image(r, p, NULL, width, height, rgb, hdr, err);
}

sss_result sss_renderer_render_q_image(sss_renderer *r, const sss_view_params *p, const float *q, int width,
                                       int height, float **rgb, float **hdr, sss_error *err)
{
    if (!q) return sss_fail(err, SSS_ERR_ARG, "render: no per-vertex values given");
    return render_image(r, p, q, width, height, rgb, hdr, err);
}

/* One offscreen frame: q from the renderer's own evaluation (q NULL) or
 * supplied per vertex. */
static sss_result render_image(sss_renderer *r, const sss_view_params *p, const float *q, int width, int height,
                               float **rgb, float **hdr, sss_error *err)
{
    *rgb = NULL;
    if (hdr) *hdr = NULL;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return sss_fail(err, SSS_ERR_ARG, "image size %dx%d out of range [1, 16384]", width, height);
    sss_result res = sss_renderer_bind_offscreen(r, width, height, err);
    if (res != SSS_OK) return res;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    size_t n = (size_t)width * height;
    float *px = malloc(n * 4 * sizeof(float));
    float *out = malloc(n * 3 * sizeof(float));
    float *h = hdr ? malloc(n * 3 * sizeof(float)) : NULL;
    if (!px || !out || (hdr && !h)) {
        free(px); free(out); free(h);
        return sss_fail(err, SSS_ERR_NOMEM, "out of memory for a %dx%d image", width, height);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, r->fbo);
    if (q) sss_renderer_upload_q(r, q);
    else sss_renderer_evaluate(r, p);
    sss_renderer_draw(r, p, width, height);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, px);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            float x = px[4 * i + c]; /* exposure · L, linear */
            if (h) h[3 * i + c] = x;
            out[3 * i + c] = sss_tonemap_apply(p->tonemap, x);
        }
    free(px);
    *rgb = out;
    if (hdr) *hdr = h;
    return SSS_OK;
}
