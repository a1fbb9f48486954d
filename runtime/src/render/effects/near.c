/* near.c: the run-time near terms of files with section OWNT (format 1.3;
 * sss/nearterms.h, docs/viewer.md).
 *
 * The rows of such a file hold q minus the largest entries of the §3.1 sum
 * (Hao–Varshney 2004), the vertex's own w̃(o,o) g_o(ω_j) V(x_o, ω_j) and
 * those of its `near_rings` mesh rings: the entries that jump where x_o or a
 * neighbour enters a cast shadow, and that §3.2's interpolation between
 * direction samples would smear. After q is evaluated (either path) or
 * uploaded, two more compute passes add them back for the actual light: the
 * first finds every vertex's own visibility V(x_i, ω) and its transfer
 * g_i V_i; the second adds each vertex's row Σ_i w̃(o, i) g_i V_i, in
 * sss_near_sum's order. V is, by default, the bake's own ray traced on the
 * GPU through a BVH of the mesh built here once (common/src/bvh.c): a vertex that gets
 * V wrong is off by about half of its q, so only the bake's rule itself
 * keeps the image error at the bake's. On request (near_visibility = 1) V
 * comes from a shadow map instead (shadow.c, the paper's own test, §3.1,
 * plus the bake's ray against the vertex's own triangles), created on first
 * use and re-rendered only when the light direction changes. Pass 1 depends
 * on the light direction alone, so it runs only when that (or the
 * visibility asked for) changes. A file without OWNT gets none of it: no
 * weights, no BVH, no map, no programs, no passes.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/bvh.h"
#include "effects.h"
#include "gl_util.h"
#include "shaders.h"
#include "shadow.h"
#include "sss/nearterms.h"

/* Receivers per slice of pass 2's interleaved rows (near_build): a warp of
 * 32 invocations on NVIDIA, half a wave on AMD's 64. */
#define NEAR_SLICE 32u
/* Entries per upload of those rows (near_build): 16 MiB of indices and
 * 16·C MiB of weights at a time. */
#define NEAR_PIECE (1u << 22)

typedef struct sss_near_pass {
    sss_shadow *shadow; /* created on the first pass that asks for the map */
    GLuint prog_vis, prog_ray, prog_near; /* pass 1 (map or rays): V and g V per vertex; pass 2: the rows' sums into q */
    GLuint bvh_node, bvh_tri; /* the mesh's BVH (sss/bvh.h) for prog_ray */
    uint32_t bvh_ntri;
    int vis_valid, vis_map, vis_size; /* what pass 1 last computed: map or rays, map size, */
    float vis_dir[3];                 /* and light: lit and gv hold it */
    GLuint lit, gv;     /* V (uint) and g V (float) per vertex */
    GLuint fan;         /* incident triangles per vertex: offsets (nv + 1), then triangle indices */
    GLuint fan_sin;     /* per vertex: sin of the largest angle between n_o and its triangles' normals */
    /* sss_weights: rows of (vertex, w̃ per channel), in chunks of
     * consecutive receivers [first, first + count) whose entries fit one
     * storage buffer each (near_build); one chunk unless the rows are larger
     * than the GL's block limit */
    uint32_t nchunk;
    GLuint *near_start, *near_idx, *near_w; /* per chunk: per receiver (first entry, stride, count, 0), vertices,
                                             * weights, interleaved in slices (near_build) */
    uint32_t *chunk_first, *chunk_count;
    float delta;        /* the rays' offset δ, sss_mesh_ray_offset (sss/mesh.h) */
} sss_near_pass;

/* The near terms' resources: their rows and weights from the file's
 * geometry and material (sss_near_build: the file stores no bytes for
 * them), the mesh's BVH for the rays, each vertex's incident triangles for
 * the map, the per-vertex V and g V buffers and the programs. The shadow
 * map itself waits for a pass that asks for it. */
/* The longest of the rows of receivers v … v + w − 1. */
static uint64_t longest_row(const sss_weights *nr, uint32_t v, uint32_t w)
{
    uint64_t L = 0;
    for (uint32_t j = v; j < v + w; j++) L = nr->start[j + 1] - nr->start[j] > L ? nr->start[j + 1] - nr->start[j] : L;
    return L;
}

static sss_result near_build(sss_near_pass *r, const sss_effect_ctx *c, sss_error *err)
{
    const sss_gpu_mesh *m = c->mesh;
    const sss_bake_file *f = m->f;
    const uint32_t nv = m->nv, nf = m->nf, C = m->C;
    sss_weights nr;
    sss_result res = sss_near_build_file(f, &nr, err);
    if (res != SSS_OK) return res;
    /* The rows go to the GPU in chunks of consecutive receivers whose
     * entries (4 bytes of index, 4·C of weights each) fit the GL's storage
     * block limit (OpenGL 4.3 guarantees 2^27 bytes; llvmpipe gives no
     * more): the material's radius holds hundreds of entries per row on a
     * fine mesh (docs/accuracy.md, "Near terms sized by the material").
     * SSS_NEAR_BLOCK_BYTES lowers the limit (tests exercise the chunks on
     * small meshes). Pass 2 runs once per chunk; every receiver's sum is the
     * same float sum in the same order whatever the chunks.
     *
     * Within a chunk the rows are interleaved in slices of up to
     * NEAR_SLICE consecutive receivers: entry k of the slice's receiver j
     * at slice base + k·width + j, the slice padded to its longest row.
     * Pass 2 runs a receiver per invocation, so at each step of the rows'
     * walk the invocations of a slice read neighbouring entries, one cache
     * line for 32 of them, where rows one after another had each read its
     * own line (docs/viewer.md, "Cost per frame"). Each row is still
     * summed in its own order, to the bit as before. A slice narrower than
     * NEAR_SLICE only where a small block limit asks for it. */
    uint64_t limit = c->max_block > 0 ? (uint64_t)c->max_block : UINT64_MAX;
    const char *env = getenv("SSS_NEAR_BLOCK_BYTES");
    if (env && *env) {
        char *end;
        const unsigned long long v = strtoull(env, &end, 10);
        if (*end == 0 && v > 0 && v < limit) limit = v;
    }
    const uint64_t per_entry = (uint64_t)C * sizeof(float) > sizeof(uint32_t) ? (uint64_t)C * sizeof(float) : sizeof(uint32_t);
    const uint64_t cap = limit / per_entry < UINT32_MAX ? limit / per_entry : UINT32_MAX; /* entries per chunk */
    r->chunk_first = malloc(((size_t)nv + 1) * sizeof *r->chunk_first);
    r->chunk_count = malloc(((size_t)nv + 1) * sizeof *r->chunk_count);
    uint64_t *chunk_entries = malloc(((size_t)nv + 1) * sizeof *chunk_entries);
    uint32_t *slice_w = malloc(((size_t)nv + 1) * sizeof *slice_w); /* each slice's width, in receiver order */
    uint32_t *slice_len = malloc(((size_t)nv + 1) * sizeof *slice_len); /* and its longest row */
    if (!r->chunk_first || !r->chunk_count || !chunk_entries || !slice_w || !slice_len) {
        free(chunk_entries), free(slice_w), free(slice_len);
        sss_weights_free(&nr);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the near terms of %u vertices", nv);
    }
#define ROW(v) (nr.start[(v) + 1] - nr.start[v])
    uint32_t nslice = 0;
    for (uint32_t v0 = 0; v0 < nv;) {
        uint64_t padded = 0;
        uint32_t v = v0;
        while (v < nv) {
            uint32_t w = nv - v < NEAR_SLICE ? nv - v : NEAR_SLICE;
            /* narrower where a slice would exceed a quarter of a chunk: so
             * that a chunk holds several, and goes up in several pieces,
             * even under a small block limit */
            while (w > 1 && (uint64_t)w * longest_row(&nr, v, w) > cap / 4) w--;
            const uint64_t L = longest_row(&nr, v, w);
            if (L > cap) {
                free(chunk_entries), free(slice_w), free(slice_len);
                sss_weights_free(&nr);
                return sss_fail(err, SSS_ERR_UNSUPPORTED,
                                "renderer: vertex %u's near terms (%llu entries) exceed this GL's storage block of "
                                "%.1f MiB (bake with a smaller --near-fraction, --near-radius or fewer --rings)",
                                v, (unsigned long long)L, (double)limit / 1048576.0);
            }
            if (padded + (uint64_t)w * L > cap) break; /* the next chunk's first slice (padded > 0 here) */
            slice_w[nslice] = w;
            slice_len[nslice++] = (uint32_t)L; /* L ≤ cap < 2^32 */
            padded += (uint64_t)w * L;
            v += w;
        }
        r->chunk_first[r->nchunk] = v0;
        r->chunk_count[r->nchunk] = v - v0;
        chunk_entries[r->nchunk] = padded;
        r->nchunk++;
        v0 = v;
    }
    r->near_start = calloc((size_t)r->nchunk + 1, sizeof *r->near_start);
    r->near_idx = calloc((size_t)r->nchunk + 1, sizeof *r->near_idx);
    r->near_w = calloc((size_t)r->nchunk + 1, sizeof *r->near_w);
    /* The interleaved image goes up in pieces of about NEAR_PIECE entries
     * (whole slices), so that loading holds a piece beside the rows, not a
     * second copy of them (2.3 GB of weights for the 437K dragon); at most
     * a quarter of a chunk, so that a small block limit (the tests') also
     * sends several pieces. */
    uint64_t piece = cap / 4 < NEAR_PIECE ? (cap / 4 > 0 ? cap / 4 : 1) : NEAR_PIECE;
    for (uint32_t k = 0; k < nslice; k++)
        piece = (uint64_t)slice_w[k] * slice_len[k] > piece ? (uint64_t)slice_w[k] * slice_len[k] : piece;
    uint32_t *row = NULL, *idx = NULL;
    float *wt = NULL;
    if (r->near_start && r->near_idx && r->near_w) {
        row = malloc((size_t)nv * 4 * sizeof *row + 1);
        idx = calloc((size_t)piece + 1, sizeof *idx);
        wt = calloc((size_t)piece * C + 1, sizeof *wt);
    }
    if (!row || !idx || !wt) {
        free(row), free(idx), free(wt), free(chunk_entries), free(slice_w), free(slice_len);
        sss_weights_free(&nr);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the near terms of %u vertices", nv);
    }
    for (uint32_t k = 0, sl = 0; k < r->nchunk; k++) {
        const uint32_t v0 = r->chunk_first[k], n = r->chunk_count[k];
        const uint64_t ne = chunk_entries[k]; /* every row holds its vertex: ne ≥ n ≥ 1 */
        r->near_idx[k] = sss_gl_ssbo((GLsizeiptr)(ne * sizeof(uint32_t)), NULL, GL_STATIC_DRAW);
        r->near_w[k] = sss_gl_ssbo((GLsizeiptr)(ne * C * sizeof(float)), NULL, GL_STATIC_DRAW);
        /* per receiver: its first entry, the stride between its entries (its slice's width), its count */
        uint64_t base = 0, p0 = 0; /* the next slice's first entry; the piece's */
        for (uint32_t v = v0; v <= v0 + n; sl++) {
            const int last = v == v0 + n;
            const uint64_t size = last ? 0 : (uint64_t)slice_w[sl] * slice_len[sl];
            if (last || base + size - p0 > piece) { /* the piece [p0, base) up; the padding stays 0 */
                glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->near_idx[k]);
                glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(p0 * sizeof *idx),
                                (GLsizeiptr)((base - p0) * sizeof *idx), idx);
                glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->near_w[k]);
                glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(p0 * C * sizeof *wt),
                                (GLsizeiptr)((base - p0) * C * sizeof *wt), wt);
                memset(idx, 0, (size_t)(base - p0) * sizeof *idx);
                memset(wt, 0, (size_t)(base - p0) * C * sizeof *wt);
                p0 = base;
                if (last) break;
            }
            const uint32_t w = slice_w[sl];
            for (uint32_t j = 0; j < w; j++) {
                const uint64_t e0 = nr.start[v + j], len = ROW(v + j);
                uint32_t *rc = &row[4 * (size_t)(v + j - v0)];
                rc[0] = (uint32_t)(base + j), rc[1] = w, rc[2] = (uint32_t)len, rc[3] = 0; /* below cap: 32 bits */
                for (uint64_t e = 0; e < len; e++) {
                    const uint64_t a = base - p0 + e * w + j;
                    idx[a] = nr.idx[e0 + e];
                    memcpy(&wt[a * C], &nr.w[(e0 + e) * C], C * sizeof(float));
                }
            }
            base += size;
            v += w;
        }
        r->near_start[k] = sss_gl_ssbo((GLsizeiptr)((size_t)n * 4 * sizeof(uint32_t)), row, GL_STATIC_DRAW);
    }
#undef ROW
    free(row), free(idx), free(wt), free(chunk_entries), free(slice_w), free(slice_len);
    sss_weights_free(&nr);
    r->gv = sss_gl_ssbo((GLsizeiptr)nv * sizeof(float), NULL, GL_DYNAMIC_COPY);
    r->lit = sss_gl_ssbo((GLsizeiptr)nv * sizeof(uint32_t), NULL, GL_DYNAMIC_COPY);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    /* each vertex's incident triangles, for pass 1's exact test of the
     * bake's ray against them (shadow.c: the map cannot resolve them) */
    const uint64_t nfan = (uint64_t)nv + 1 + 3 * (uint64_t)nf;
    if (nfan > UINT32_MAX) return sss_fail(err, SSS_ERR_UNSUPPORTED, "renderer: mesh too large for the near terms");
    uint32_t *fan = calloc(nfan, sizeof *fan);
    if (!fan) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the vertices' triangle fans");
    for (size_t k = 0; k < 3 * (size_t)nf; k++) fan[f->mesh.tri[k] + 1]++;
    fan[0] = nv + 1;
    for (uint32_t v = 0; v < nv; v++) fan[v + 1] += fan[v];
    for (size_t k = 0; k < 3 * (size_t)nf; k++) fan[fan[f->mesh.tri[k]]++] = (uint32_t)(k / 3);
    for (uint32_t v = nv; v > 0; v--) fan[v] = fan[v - 1]; /* the fill advanced each start to its end */
    fan[0] = nv + 1;
    r->fan = sss_gl_ssbo((GLsizeiptr)(nfan * sizeof *fan), fan, GL_STATIC_DRAW);
    /* The ray cannot hit a triangle of the fan while ω is above every
     * triangle's plane, which holds when n_o·ω > sin α, α the largest angle
     * between n_o and a triangle's normal: the pass then skips the fan
     * (most vertices, most lights). sin α = 1 (never skip) where a triangle
     * faces away from n_o or is degenerate. */
    float *fs = malloc((size_t)nv * sizeof *fs + 1);
    if (!fs) {
        free(fan);
        return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory for the vertices' triangle fans");
    }
    for (uint32_t v = 0; v < nv; v++) {
        const float *n = &f->mesh.nrm[3 * (size_t)v];
        double cmin = 1.0;
        for (uint32_t k = fan[v]; k < fan[v + 1]; k++) {
            const uint32_t *t = &f->mesh.tri[3 * (size_t)fan[k]];
            double e1[3], e2[3], fnrm[3];
            for (int i = 0; i < 3; i++) {
                e1[i] = (double)f->mesh.pos[3 * (size_t)t[1] + i] - f->mesh.pos[3 * (size_t)t[0] + i];
                e2[i] = (double)f->mesh.pos[3 * (size_t)t[2] + i] - f->mesh.pos[3 * (size_t)t[0] + i];
            }
            sss_cross3(e1, e2, fnrm);
            const double len = sqrt(fnrm[0] * fnrm[0] + fnrm[1] * fnrm[1] + fnrm[2] * fnrm[2]);
            const double c = len > 0 ? (n[0] * fnrm[0] + n[1] * fnrm[1] + n[2] * fnrm[2]) / len : -1.0;
            if (c < cmin) cmin = c;
        }
        /* a margin of 1e-3 for the float arithmetic of the pass */
        fs[v] = cmin > 0.0 ? (float)fmin(1.0, sqrt(fmax(0.0, 1.0 - cmin * cmin)) + 1e-3) : 1.0f;
    }
    r->fan_sin = sss_gl_ssbo((GLsizeiptr)nv * sizeof *fs, fs, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    free(fs);
    free(fan);
    /* the bake's own offset, so that the origins are the bake's floats */
    r->delta = sss_mesh_ray_offset(&f->mesh);
    char pre[48];
    snprintf(pre, sizeof pre, "#define CHANNELS %u\n", C);
    const char *vis_parts[3] = {"", sss_glsl_shadow_map, sss_glsl_near_vis_comp};
    GLuint cs = sss_gl_compile_parts(GL_COMPUTE_SHADER, vis_parts, 3, err);
    if (!cs || !(r->prog_vis = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
    cs = sss_gl_compile(GL_COMPUTE_SHADER, pre, sss_glsl_near_sum_comp, err);
    if (!cs || !(r->prog_near = sss_gl_link(cs, 0, err))) return SSS_ERR_UNSUPPORTED;
    /* The BVH for the rays. Where its buffers exceed this GL's storage block
     * (above ~2.8M triangles at 48 bytes each in llvmpipe's 128 MiB), the
     * renderer keeps working with the shadow map alone (prog_ray stays 0). */
    sss_bvh bvh;
    res = sss_bvh_build(f->mesh.pos, nv, f->mesh.tri, nf, &bvh, err);
    if (res != SSS_OK) return res;
    const uint64_t node_bytes = (uint64_t)bvh.nnode * sizeof *bvh.node;
    const uint64_t tri_bytes = (uint64_t)bvh.ntri * 12 * sizeof(float);
    const GLint64 max_block = c->max_block;
    if (max_block <= 0 || (node_bytes <= (uint64_t)max_block && tri_bytes <= (uint64_t)max_block)) {
        r->bvh_node = sss_gl_ssbo((GLsizeiptr)node_bytes, bvh.node, GL_STATIC_DRAW);
        r->bvh_tri = sss_gl_ssbo((GLsizeiptr)tri_bytes, bvh.tri, GL_STATIC_DRAW);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        r->bvh_ntri = bvh.ntri;
        snprintf(pre, sizeof pre, "#define RAYS 1\n#define SSS_BVH_STACK %d\n", SSS_BVH_STACK);
        vis_parts[0] = pre;
        cs = sss_gl_compile_parts(GL_COMPUTE_SHADER, vis_parts, 3, err);
        if (!cs || !(r->prog_ray = sss_gl_link(cs, 0, err))) {
            sss_bvh_free(&bvh);
            return SSS_ERR_UNSUPPORTED;
        }
    }
    sss_bvh_free(&bvh);
    return SSS_OK;
}

int sss_pass_near_present(const sss_bake_file *f) { return f->near_terms != 0; }

void sss_pass_near_destroy(void *state)
{
    sss_near_pass *r = state;
    if (!r) return;
    GLuint bufs[6] = {r->lit, r->gv, r->fan, r->fan_sin, r->bvh_node, r->bvh_tri};
    glDeleteBuffers(6, bufs);
    for (uint32_t k = 0; k < r->nchunk; k++) {
        GLuint cb[3] = {r->near_start ? r->near_start[k] : 0, r->near_idx ? r->near_idx[k] : 0,
                        r->near_w ? r->near_w[k] : 0};
        glDeleteBuffers(3, cb);
    }
    free(r->near_start);
    free(r->near_idx);
    free(r->near_w);
    free(r->chunk_first);
    free(r->chunk_count);
    if (r->prog_vis) glDeleteProgram(r->prog_vis);
    if (r->prog_ray) glDeleteProgram(r->prog_ray);
    if (r->prog_near) glDeleteProgram(r->prog_near);
    sss_shadow_destroy(r->shadow);
    free(r);
}

sss_result sss_pass_near_create(const sss_effect_ctx *c, void **state, sss_error *err)
{
    *state = NULL;
    sss_near_pass *r = calloc(1, sizeof *r);
    if (!r) return sss_fail(err, SSS_ERR_NOMEM, "renderer: out of memory");
    sss_result res = near_build(r, c, err);
    if (res != SSS_OK) {
        sss_pass_near_destroy(r);
        return res;
    }
    *state = r;
    return SSS_OK;
}

/* The shadow map of the size asked for (clamped to 256 … 8192), created or
 * replaced here on first use; 0 when none can be had (the old one is kept
 * when a new size fails). */
static int near_map(sss_near_pass *r, const sss_gpu_mesh *m, int size)
{
    return sss_shadow_ensure(&r->shadow, m->vao, m->nf, m->centre, m->radius, size);
}

/* Adds the near terms for unit light l to q (binding 3) and records every
 * vertex's V, on the GPU whichever path evaluated q: by the bake's ray
 * through the BVH, or from the shadow map when p asks for it (or when
 * there is no BVH, or no map can be had: the other one then). 1 when it
 * ran (under the timer query), 0 when there is no light or no test. */
GLuint sss_pass_near_frame(void *state, const sss_effect_frame *fr)
{
    sss_near_pass *r = state;
    const sss_gpu_mesh *m = &fr->r->mesh;
    const double *l = fr->light;
    const sss_view_params *p = fr->p;
    const GLuint query = fr->query;
    if (!p->near_terms) return 0; /* the view asks for q as evaluated or uploaded */
    const float lf[3] = {(float)l[0], (float)l[1], (float)l[2]};
    if (!(lf[0] * lf[0] + lf[1] * lf[1] + lf[2] * lf[2] > 0.5f)) return 0; /* zero or NaN light: no light */
    int map = p->near_visibility == SSS_NEAR_MAP || !r->prog_ray;
    if (map && !near_map(r, m, p->shadow_size)) map = 0;
    if (!map && !r->prog_ray) return 0;
    const int size = map ? sss_shadow_size(r->shadow) : 0;
    /* lit and gv depend on the light direction and the test alone */
    const int fresh = !(r->vis_valid && r->vis_map == map && r->vis_size == size && r->vis_dir[0] == lf[0] &&
                        r->vis_dir[1] == lf[1] && r->vis_dir[2] == lf[2]);
    if (map) sss_shadow_update(r->shadow, lf, query); /* begins the timer query */
    else glBeginQuery(GL_TIME_ELAPSED, query);
    if (fresh) {
        /* pass 1: V and g V per vertex */
        GLuint pr = map ? r->prog_vis : r->prog_ray;
        glUseProgram(pr);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m->vbo_pos);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m->vbo_nrm);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r->gv);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->lit);
        if (map) {
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, m->ebo);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, r->fan);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, r->fan_sin);
            sss_shadow_bind(r->shadow, pr, 0);
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
        glUniform1f(glGetUniformLocation(pr, "u_eta"), (float)m->f->material.eta);
        glUniform1ui(glGetUniformLocation(pr, "u_count"), m->nv);
        glDispatchCompute((m->nv + 63) / 64, 1, 1);
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
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, r->gv);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m->qbuf);
    for (uint32_t k = 0; k < r->nchunk; k++) { /* disjoint receivers: no barrier between chunks */
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, r->near_start[k]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, r->near_idx[k]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, r->near_w[k]);
        glUniform1ui(glGetUniformLocation(pr, "u_first"), r->chunk_first[k]);
        glUniform1ui(glGetUniformLocation(pr, "u_count"), r->chunk_count[k]);
        glDispatchCompute((r->chunk_count[k] + 255) / 256, 1, 1);
    }
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    glEndQuery(GL_TIME_ELAPSED);
    return 1;
}

const char *sss_pass_near_describe(const void *state)
{
    const sss_near_pass *r = state;
    return r->prog_ray ? "near terms: rays (shadow map on request)" : "near terms: shadow map";
}

void sss_near_read_visibility(const void *state, uint32_t nv, uint8_t *lit)
{
    const sss_near_pass *r = state;
    uint32_t *u = malloc((size_t)nv * sizeof *u + 1);
    if (!u) {
        memset(lit, 0, nv);
        return;
    }
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, r->lit);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)nv * sizeof *u, u);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    for (uint32_t v = 0; v < nv; v++) lit[v] = u[v] != 0;
    free(u);
}
