/* single.c: single scattering per pixel (single.h, docs/layers.md §8).
 *
 * The shader (single.glsl) marches the refracted view ray below each pixel
 * and, at every sample M, needs the point K where the light entered. The
 * CPU oracle (sss_ss_mesh_point) casts a ray through the mesh; here a
 * light-space map stands in for the cast: drawn along the light with the
 * shadow map's orthographic projection (shadow.h, sss_shadow_frame), each
 * texel keeps the position and the triangle of the surface nearest the
 * light. K is then where the ray from M back along the refracted light
 * crosses that surface's tangent plane (single.glsl, ss_cast). The map is
 * redrawn only when the light turns.
 *
 * Where the view ray leaves the object: the nearest back faces as the
 * camera sees them (front faces culled; position and triangle per pixel,
 * as the light map), redrawn every frame; a sample is outside when it lies
 * beyond the plane of the back face's triangle in its pixel. A depth comparison
 * alone is not enough: across one pixel an oblique back face spans more
 * depth than a thin part is thick (docs/layers.md §8).
 */
#include "single.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "shaders.h"
#include "shadow.h"
#include "sss/format.h"

struct sss_single {
    GLuint prog_map;                 /* single_map.*.glsl: position and triangle per texel, for both maps */
    GLint map_mat;
    GLuint fbo_map, tex_pos, rb_depth;
    float dir[3];
    int valid;
    float clip[16], lookup[16];
    GLuint fbo_back, tex_bpos, rb_back;
    int back_w, back_h;
    GLuint ld_buf;   /* per-vertex layer depths (fill_layer_depths) */
    uint32_t nd;     /* layers per vertex */
};

int sss_single_wanted(const sss_bake_file *f, const sss_view_params *p)
{
    if (p->single > 0) return 1;
    if (p->single < 0) return 0;
    return (f->fx.mask & SSS_FX_SINGLE) != 0;
}

/* The layers' depths per vertex (nv × n, section LDEP's layout): the file's
 * own when its depths vary (docs/layers.md §3), else LAYR's constants. */
static void fill_layer_depths(const sss_bake_file *f, float *out)
{
    const uint32_t n = f->layers.n;
    if (f->layer_depth) {
        memcpy(out, f->layer_depth, (size_t)f->mesh.nv * n * sizeof *out);
        return;
    }
    for (uint32_t v = 0; v < f->mesh.nv; v++)
        for (uint32_t k = 0; k < n; k++) out[(size_t)v * n + k] = (float)f->layers.layer[k].depth;
}

void sss_single_destroy(sss_single *s)
{
    if (!s) return;
    if (s->prog_map) glDeleteProgram(s->prog_map);
    if (s->fbo_map) glDeleteFramebuffers(1, &s->fbo_map);
    if (s->tex_pos) glDeleteTextures(1, &s->tex_pos);
    if (s->rb_depth) glDeleteRenderbuffers(1, &s->rb_depth);
    if (s->fbo_back) glDeleteFramebuffers(1, &s->fbo_back);
    if (s->tex_bpos) glDeleteTextures(1, &s->tex_bpos);
    if (s->rb_back) glDeleteRenderbuffers(1, &s->rb_back);
    if (s->ld_buf) glDeleteBuffers(1, &s->ld_buf);
    free(s);
}

static GLuint program(const char *vsrc, const char *fsrc)
{
    sss_error err = {{0}};
    GLuint vs = sss_gl_compile(GL_VERTEX_SHADER, "", vsrc, &err);
    GLuint fs = vs ? sss_gl_compile(GL_FRAGMENT_SHADER, "", fsrc, &err) : 0;
    GLuint p = fs ? sss_gl_link(vs, fs, &err) : 0;
    if (vs && !fs) glDeleteShader(vs);
    return p;
}

static void texture(GLuint *t, GLenum fmt, int w, int h)
{
    glGenTextures(1, t);
    glBindTexture(GL_TEXTURE_2D, *t);
    glTexStorage2D(GL_TEXTURE_2D, 1, fmt, w, h);
    /* read with texelFetch */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D, 0);
}

/* A framebuffer of one RGBA32F texture (per texel the nearest surface's
 * position and its triangle + 1, exact to 2^24; 0: none) with a depth
 * buffer, w × h: the light map and the camera's back faces. */
static int surface_target(GLuint *fbo, GLuint *pos, GLuint *depth, int w, int h)
{
    GLint prev_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev_fb);
    texture(pos, GL_RGBA32F, w, h);
    glGenRenderbuffers(1, depth);
    glBindRenderbuffer(GL_RENDERBUFFER, *depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *pos, 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, *depth);
    const GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev_fb);
    return st == GL_FRAMEBUFFER_COMPLETE;
}

int sss_single_ensure(sss_single **out, const sss_gpu_mesh *m)
{
    if (*out) return 1;
    /* the maps name a triangle as a float (its index + 1): exact below 2^24 */
    if (m->nf >= (1u << 24) - 1u) return 0;
    sss_single *s = calloc(1, sizeof *s);
    if (!s) return 0;
    s->prog_map = program(sss_glsl_single_map_vert, sss_glsl_single_map_frag);
    if (!s->prog_map) {
        sss_single_destroy(s);
        return 0;
    }
    s->map_mat = glGetUniformLocation(s->prog_map, "u_mat");
    if (!surface_target(&s->fbo_map, &s->tex_pos, &s->rb_depth, SSS_SINGLE_MAP_SIZE,
                        SSS_SINGLE_MAP_SIZE)) {
        sss_single_destroy(s);
        return 0;
    }
    const sss_bake_file *f = m->f;
    s->nd = f->layers.n;
    if (s->nd) {
        float *ld = malloc((size_t)m->nv * s->nd * sizeof *ld);
        if (!ld) {
            sss_single_destroy(s);
            return 0;
        }
        fill_layer_depths(f, ld);
        glGenBuffers(1, &s->ld_buf);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, s->ld_buf);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)((size_t)m->nv * s->nd * sizeof *ld), ld, GL_STATIC_DRAW);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
        free(ld);
    }
    *out = s;
    return 1;
}

/* The camera's back faces at width × height. */
static int back_target(sss_single *s, int width, int height)
{
    if (s->fbo_back && s->back_w == width && s->back_h == height) return 1;
    if (s->fbo_back) glDeleteFramebuffers(1, &s->fbo_back);
    if (s->tex_bpos) glDeleteTextures(1, &s->tex_bpos);
    if (s->rb_back) glDeleteRenderbuffers(1, &s->rb_back);
    s->back_w = width;
    s->back_h = height;
    return surface_target(&s->fbo_back, &s->tex_bpos, &s->rb_back, width, height);
}

void sss_single_prepare(sss_single *s, const sss_gpu_mesh *m, const float mvp[16], const float l[3], int width,
                        int height)
{
    GLint prev_draw = 0, prev_read = 0, vp[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev_draw);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
    glGetIntegerv(GL_VIEWPORT, vp);
    const GLboolean depth_on = glIsEnabled(GL_DEPTH_TEST), cull_on = glIsEnabled(GL_CULL_FACE);
    GLint cull = GL_BACK;
    glGetIntegerv(GL_CULL_FACE_MODE, &cull);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glBindVertexArray(m->vao);
    if (!(s->valid && !memcmp(s->dir, l, sizeof s->dir)) &&
        sss_shadow_frame(m->centre, m->radius * (1.0 + SSS_SHADOW_MARGIN), l, s->clip, s->lookup)) {
        /* every surface, front or back facing: the nearest to the light */
        glBindFramebuffer(GL_FRAMEBUFFER, s->fbo_map);
        glViewport(0, 0, SSS_SINGLE_MAP_SIZE, SSS_SINGLE_MAP_SIZE);
        glClearColor(0, 0, 0, 0);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glDisable(GL_CULL_FACE);
        glUseProgram(s->prog_map);
        glUniformMatrix4fv(s->map_mat, 1, GL_FALSE, s->clip);
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
        memcpy(s->dir, l, sizeof s->dir);
        s->valid = 1;
    }
    if (back_target(s, width, height)) {
        /* the nearest back face: the first place a ray from the eye leaves the object */
        glBindFramebuffer(GL_FRAMEBUFFER, s->fbo_back);
        glViewport(0, 0, width, height);
        glClearColor(0, 0, 0, 0);
        glClearDepth(1.0);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glEnable(GL_CULL_FACE);
        glCullFace(GL_FRONT);
        glUseProgram(s->prog_map);
        glUniformMatrix4fv(s->map_mat, 1, GL_FALSE, mvp);
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
    }
    glBindVertexArray(0);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev_draw);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    glCullFace((GLenum)cull);
    if (!cull_on) glDisable(GL_CULL_FACE);
    if (!depth_on) glDisable(GL_DEPTH_TEST);
}

void sss_single_bind(const sss_single *s, GLuint pr, const sss_gpu_mesh *m, const sss_view_params *p,
                     const float mvp[16], int unit)
{
    const sss_bake_file *f = m->f;
    const sss_material *mat = &f->material;
    /* the stack: the file's layers over the material (a half-space, HG of
     * its g), as sss_ss_mesh_point builds it */
    float ss[3 * (SSS_MAX_LAYERS + 1)], st[3 * (SSS_MAX_LAYERS + 1)], g[SSS_MAX_LAYERS + 1];
    const uint32_t nl = (f->layers.n <= SSS_MAX_LAYERS ? f->layers.n : SSS_MAX_LAYERS) + 1;
    double st_min = INFINITY;
    for (uint32_t k = 0; k < nl; k++) {
        for (int c = 0; c < 3; c++) {
            const int cc = f->channels == 3 ? c : 0;
            double sigma_s, sigma_t;
            if (k + 1 < nl) {
                sigma_s = f->layers.layer[k].sigma_s[cc];
                sigma_t = f->layers.layer[k].sigma_t[cc];
            } else {
                sigma_s = sss_material_sigma_s(mat, cc);
                sigma_t = mat->sigma_a[cc] + sigma_s;
            }
            ss[3 * k + c] = (float)sigma_s;
            st[3 * k + c] = (float)sigma_t;
            if (sigma_t > 0.0) st_min = fmin(st_min, sigma_t);
        }
        g[k] = (float)(k + 1 < nl ? f->layers.layer[k].g : mat->g);
    }
    const int n = p->single_samples > 0 ? p->single_samples : SSS_SINGLE_SAMPLES_DEFAULT;
    glUniform1i(glGetUniformLocation(pr, "u_ss_n"), n);
    glUniform1i(glGetUniformLocation(pr, "u_ss_seed"), p->single_march == SSS_SINGLE_MARCH_SEED);
    glUniform1i(glGetUniformLocation(pr, "u_ss_schlick"), f->layers.n && f->layers.phase == SSS_PHASE_SCHLICK);
    glUniform1i(glGetUniformLocation(pr, "u_ss_nl"), (GLint)nl);
    glUniform3fv(glGetUniformLocation(pr, "u_ss_sigma_s"), (GLsizei)nl, ss);
    glUniform3fv(glGetUniformLocation(pr, "u_ss_sigma_t"), (GLsizei)nl, st);
    glUniform1fv(glGetUniformLocation(pr, "u_ss_g"), (GLsizei)nl, g);
    glUniform1f(glGetUniformLocation(pr, "u_ss_mm"), (float)f->mm_per_unit);
    glUniform1f(glGetUniformLocation(pr, "u_ss_eta"), (float)mat->eta);
    /* the oracle's tau_max (sss_ss_mesh_opts, e^{-16}) with one end for all channels */
    glUniform1f(glGetUniformLocation(pr, "u_ss_smax_cap"), (float)(isfinite(st_min) ? 16.0 / st_min : 0.0));
    glUniformMatrix4fv(glGetUniformLocation(pr, "u_ss_light"), 1, GL_FALSE, s->lookup);
    glUniform1i(glGetUniformLocation(pr, "u_ss_size"), SSS_SINGLE_MAP_SIZE);
    glUniformMatrix4fv(glGetUniformLocation(pr, "u_ss_mvp"), 1, GL_FALSE, mvp);
    glUniform1i(glGetUniformLocation(pr, "u_ss_nd"), (GLint)s->nd);
    const GLuint tex[2] = {s->tex_pos, s->tex_bpos};
    const char *names[2] = {"u_ss_kpos", "u_ss_bpos"};
    for (int i = 0; i < 2; i++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)(unit + i));
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glUniform1i(glGetUniformLocation(pr, names[i]), unit + i);
    }
    glActiveTexture(GL_TEXTURE0);
    if (s->ld_buf) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s->ld_buf);
    /* the mesh, for the triangles the maps name */
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, m->vbo_pos);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, m->vbo_nrm);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, m->ebo);
}

void sss_single_unbind(int unit)
{
    for (int i = 0; i < 2; i++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)(unit + i));
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glActiveTexture(GL_TEXTURE0);
}
