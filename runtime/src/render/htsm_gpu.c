/* htsm_gpu.c: seed 000's heterogeneous translucent shadow maps on the GPU
 * (sss/htsm_gpu.h; docs/heterogeneous.md §9). Two draws per frame, both
 * rasterising the mesh: along the light into the map's three images (MRT,
 * then glGenerateMipmap: the 2 × 2 means sss_htsm_map_mips computes), and
 * from the camera into q and x_o per pixel (htsm.frag.glsl, sss_htsm_q's
 * sum, and the light's surface terms shadowed by the same map). The
 * field's 3D texture is uploaded once with every level computed on the CPU
 * (sss_htsm_volume_build), so that the pass and its oracle read the same
 * numbers.
 */
#include "sss/htsm_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "renderer.h"
#include "shaders.h"
#include "shadow.h"
#include "sss/clock.h"

struct sss_htsm_gpu {
    sss_renderer *r;
    GLuint prog_map, prog_q;
    uint32_t size, levels;   /* the map */
    GLuint map_fbo, map_tex[3], map_depth;
    float lookup[16];
    double light[4], ref_w; /* the last map's light and depth of reference (sss_htsm_map's) */
    sss_htsm_volume vol;
    int vol_on;
    GLuint vol_tex;
    GLuint q_fbo, q_tex[3], q_depth; /* q, x_o, the surface terms */
    int w, h;
};

static GLuint program(const char *vs_src, const char *const *fs_parts, int nparts, sss_error *err)
{
    GLuint vs = sss_gl_compile(GL_VERTEX_SHADER, "", vs_src, err);
    GLuint fs = vs ? sss_gl_compile_parts(GL_FRAGMENT_SHADER, fs_parts, nparts, err) : 0;
    GLuint p = fs ? sss_gl_link(vs, fs, err) : 0;
    if (vs && !fs) glDeleteShader(vs);
    return p;
}

static void q_free(sss_htsm_gpu *g)
{
    if (g->q_fbo) glDeleteFramebuffers(1, &g->q_fbo);
    if (g->q_tex[0]) glDeleteTextures(3, g->q_tex);
    if (g->q_depth) glDeleteRenderbuffers(1, &g->q_depth);
    g->q_fbo = g->q_tex[0] = g->q_tex[1] = g->q_tex[2] = g->q_depth = 0;
    g->w = g->h = 0;
}

void sss_htsm_gpu_destroy(sss_htsm_gpu *g)
{
    if (!g) return;
    if (g->prog_map) glDeleteProgram(g->prog_map);
    if (g->prog_q) glDeleteProgram(g->prog_q);
    if (g->map_fbo) glDeleteFramebuffers(1, &g->map_fbo);
    if (g->map_tex[0]) glDeleteTextures(3, g->map_tex);
    if (g->map_depth) glDeleteRenderbuffers(1, &g->map_depth);
    if (g->vol_tex) glDeleteTextures(1, &g->vol_tex);
    q_free(g);
    sss_htsm_volume_free(&g->vol);
    free(g);
}

void sss_htsm_view_default(sss_htsm_view *v, const sss_bake_file *f, const sss_hetero *h)
{
    memset(v, 0, sizeof *v);
    /* the best error for the time of those measured (docs/heterogeneous.md §9.4) */
    v->n = 13;
    v->steps = 4;
    v->mat.base = f->material;
    v->mat.inside = h && h->field.kind != SSS_FIELD_NONE ? h->inside : f->material;
    v->mat.inside.eta = f->material.eta; /* one surface, one index (docs/heterogeneous.md §3) */
    v->mat.strength = 1.0;
    v->mat.mm_per_unit = f->mm_per_unit;
}

uint32_t sss_htsm_view_lights(sss_htsm_view *v, sss_view_params *p, const sss_scene *sc, const sss_mesh *m,
                              uint32_t *skipped)
{
    uint32_t n = 0;
    *skipped = 0;
    v->nmore = 0;
    v->no_p_light = 1;
    for (uint32_t l = 0; l < sc->nlights; l++) {
        const sss_scene_light *L = &sc->lights[l];
        if (L->intensity == 0.0) continue;
        const int point = L->kind == SSS_LIGHT_POINT;
        if ((!point && L->kind != SSS_LIGHT_DIRECTIONAL) || (point && !sss_htsm_point_drawn(m, L->position, NULL)) ||
            n == SSS_HTSM_MAX_LIGHTS) {
            (*skipped)++;
            continue;
        }
        n++;
        double *d = v->more_light[v->nmore], *e = v->more_rgb[v->nmore];
        if (!point && v->no_p_light) {
            d = p->light, e = p->light_rgb;
            v->no_p_light = 0;
        } else {
            v->more_point[v->nmore++] = point;
        }
        for (int k = 0; k < 3; k++) d[k] = point ? L->position[k] : L->direction[k], e[k] = L->intensity * L->colour[k];
    }
    /* p's light is not drawn: nothing of it in p for other readers */
    if (v->no_p_light) p->light_rgb[0] = p->light_rgb[1] = p->light_rgb[2] = 0.0;
    return n;
}

/* The mesh's bounding box, mesh units. */
static void mesh_box(const sss_mesh *m, double lo[3], double hi[3])
{
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t v = 0; v < m->nv; v++)
        for (int a = 0; a < 3; a++) {
            lo[a] = fmin(lo[a], m->pos[3 * (size_t)v + (size_t)a]);
            hi[a] = fmax(hi[a], m->pos[3 * (size_t)v + (size_t)a]);
        }
}

static sss_result make_map(sss_htsm_gpu *g, sss_error *err)
{
    glGenTextures(3, g->map_tex);
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, g->map_tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, (GLsizei)g->levels, GL_RGBA32F, (GLsizei)g->size, (GLsizei)g->size);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &g->map_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, g->map_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, (GLsizei)g->size, (GLsizei)g->size);
    GLint prev = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
    glGenFramebuffers(1, &g->map_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->map_fbo);
    for (int i = 0; i < 3; i++)
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, g->map_tex[i], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->map_depth);
    const GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev);
    if (st != GL_FRAMEBUFFER_COMPLETE)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "the light-space map's framebuffer is incomplete (0x%x)", st);
    return SSS_OK;
}

static sss_result upload_volume(sss_htsm_gpu *g)
{
    glGenTextures(1, &g->vol_tex);
    glBindTexture(GL_TEXTURE_3D, g->vol_tex);
    const GLsizei n0 = (GLsizei)g->vol.n[0];
    glTexStorage3D(GL_TEXTURE_3D, (GLsizei)g->vol.levels, GL_R32F, n0, n0, n0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (uint32_t l = 0; l < g->vol.levels; l++) {
        const GLsizei n = (GLsizei)g->vol.n[l];
        glTexSubImage3D(GL_TEXTURE_3D, (GLint)l, 0, 0, 0, n, n, n, GL_RED, GL_FLOAT, g->vol.f[l]);
    }
    glBindTexture(GL_TEXTURE_3D, 0);
    return SSS_OK;
}

sss_result sss_htsm_gpu_create(sss_renderer *r, const sss_hetero *h, uint32_t map_size, uint32_t vol_log2,
                               sss_htsm_gpu **out, sss_error *err)
{
    *out = NULL;
    if (!map_size) map_size = 256;
    if (!vol_log2) vol_log2 = 6;
    if (map_size < 16 || map_size > 4096 || (map_size & (map_size - 1)))
        return sss_fail(err, SSS_ERR_ARG, "light-space map size %u is not a power of two in [16, 4096]", map_size);
    sss_htsm_gpu *g = calloc(1, sizeof *g);
    if (!g) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    g->r = r;
    g->size = map_size;
    for (uint32_t s = map_size; s >= 1; s >>= 1) g->levels++;
    const char *map_parts[2] = {sss_glsl_fresnel, sss_glsl_htsm_map_frag};
    const char *q_parts[3] = {sss_glsl_fresnel, sss_glsl_surface, sss_glsl_htsm_frag};
    g->prog_map = program(sss_glsl_htsm_map_vert, map_parts, 2, err);
    /* the camera pass takes the map's vertex stage for the normal the surface terms need */
    g->prog_q = g->prog_map ? program(sss_glsl_htsm_map_vert, q_parts, 3, err) : 0;
    sss_result res = g->prog_q ? make_map(g, err) : SSS_ERR_UNSUPPORTED;
    if (res == SSS_OK && h && h->field.kind != SSS_FIELD_NONE) {
        double lo[3], hi[3];
        mesh_box(&r->mesh.f->mesh, lo, hi);
        res = sss_htsm_volume_build(h, lo, hi, vol_log2, &g->vol, err);
        if (res == SSS_OK) res = upload_volume(g);
        g->vol_on = res == SSS_OK;
    }
    if (res != SSS_OK) {
        sss_htsm_gpu_destroy(g);
        return res;
    }
    *out = g;
    return SSS_OK;
}

const sss_htsm_volume *sss_htsm_gpu_volume(const sss_htsm_gpu *g) { return g->vol_on ? &g->vol : NULL; }

static sss_result q_ensure(sss_htsm_gpu *g, int w, int h, sss_error *err)
{
    if (g->q_fbo && g->w == w && g->h == h) return SSS_OK;
    q_free(g);
    glGenTextures(3, g->q_tex);
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, g->q_tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, h);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenRenderbuffers(1, &g->q_depth);
    glBindRenderbuffer(GL_RENDERBUFFER, g->q_depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, w, h);
    GLint prev = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
    glGenFramebuffers(1, &g->q_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->q_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, g->q_tex[0], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, g->q_tex[1], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, g->q_tex[2], 0);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, g->q_depth);
    const GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev);
    g->w = w;
    g->h = h;
    if (st != GL_FRAMEBUFFER_COMPLETE)
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "the per-pixel q framebuffer is incomplete (0x%x)", st);
    return SSS_OK;
}

static void uni_f(GLuint p, const char *name, float v) { glUniform1f(glGetUniformLocation(p, name), v); }
static void uni_i(GLuint p, const char *name, int v) { glUniform1i(glGetUniformLocation(p, name), v); }
static void uni_v3(GLuint p, const char *name, const double v[3])
{
    glUniform3f(glGetUniformLocation(p, name), (float)v[0], (float)v[1], (float)v[2]);
}

/* The estimator's uniforms: the pattern for this map, the materials, the
 * field's texture (unit 2) and the map's two images (units 0, 1). */
static sss_result set_estimator(const sss_htsm_gpu *g, const sss_htsm_view *v, sss_error *err)
{
    const GLuint p = g->prog_q;
    const sss_gpu_mesh *m = &g->r->mesh;
    sss_htsm_map geo;
    memset(&geo, 0, sizeof geo);
    geo.size = g->size;
    geo.ref_w = g->ref_w;
    memcpy(geo.lookup, g->lookup, sizeof geo.lookup);
    const double texel = sss_htsm_texel_mm(&geo, v->mat.mm_per_unit);
    /* 13 samples reach 8 r0 = the bounding sphere's diameter: every lit point of a back-lit
     * object (docs/heterogeneous.md §9.4 measures the choice) */
    const double r0 = v->r0_mm > 0 ? v->r0_mm : m->radius * v->mat.mm_per_unit / 4.0;
    sss_htsm_pattern pat;
    sss_result res = sss_htsm_pattern_make(v->n, r0, texel, g->levels, &pat, err);
    if (res != SSS_OK) return res;
    if (v->steps < 1 || v->steps > SSS_HTSM_MAX_STEPS)
        return sss_fail(err, SSS_ERR_ARG, "march of %u steps: 1 to %d", v->steps, SSS_HTSM_MAX_STEPS);
    float off[2 * SSS_HTSM_MAX_SAMPLES], rho[SSS_HTSM_MAX_SAMPLES];
    GLint ml[SSS_HTSM_MAX_SAMPLES], vl[SSS_HTSM_MAX_SAMPLES];
    for (uint32_t i = 0; i < pat.n; i++) {
        off[2 * i] = (float)pat.off[i][0];
        off[2 * i + 1] = (float)pat.off[i][1];
        rho[i] = (float)pat.rho[i];
        ml[i] = (GLint)pat.map_level[i];
        vl[i] = (GLint)pat.vol_level[i];
    }
    glUniformMatrix4fv(glGetUniformLocation(p, "u_ht_lookup"), 1, GL_FALSE, g->lookup);
    glUniform4f(glGetUniformLocation(p, "u_ht_light"), (float)g->light[0], (float)g->light[1], (float)g->light[2],
                (float)g->light[3]);
    uni_f(p, "u_ht_wref", (float)g->ref_w);
    uni_f(p, "u_ht_span", (float)(texel * g->size));
    uni_f(p, "u_ht_texel", (float)(texel / v->mat.mm_per_unit));
    uni_f(p, "u_ht_mm", (float)v->mat.mm_per_unit);
    uni_i(p, "u_ht_size", (int)g->size);
    uni_i(p, "u_ht_n", (int)pat.n);
    uni_i(p, "u_ht_steps", (int)v->steps);
    glUniform2fv(glGetUniformLocation(p, "u_ht_off"), (GLsizei)pat.n, off);
    glUniform1fv(glGetUniformLocation(p, "u_ht_rho"), (GLsizei)pat.n, rho);
    glUniform1iv(glGetUniformLocation(p, "u_ht_mlev"), (GLsizei)pat.n, ml);
    glUniform1iv(glGetUniformLocation(p, "u_ht_vlev"), (GLsizei)pat.n, vl);
    uni_v3(p, "u_ht_base_sa", v->mat.base.sigma_a);
    uni_v3(p, "u_ht_base_ss", v->mat.base.sigmap_s);
    uni_v3(p, "u_ht_in_sa", v->mat.inside.sigma_a);
    uni_v3(p, "u_ht_in_ss", v->mat.inside.sigmap_s);
    const double F = sss_fdr(v->mat.base.eta);
    uni_f(p, "u_ht_A", (float)((1.0 + F) / (1.0 - F)));
    uni_f(p, "u_ht_strength", (float)v->mat.strength);
    uni_i(p, "u_ht_vol_on", g->vol_on);
    uni_i(p, "u_ht_vol_n", g->vol_on ? (int)g->vol.n[0] : 2);
    uni_i(p, "u_ht_vol_levels", g->vol_on ? (int)g->vol.levels : 1);
    uni_v3(p, "u_ht_vol_lo", g->vol.lo);
    uni_v3(p, "u_ht_vol_h", g->vol.h);
    const char *names[3] = {"u_ht_pos", "u_ht_irr", "u_ht_vol"};
    const GLuint tex[3] = {g->map_tex[0], g->map_tex[2], g->vol_tex};
    for (int i = 0; i < 3; i++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)i);
        glBindTexture(i < 2 ? GL_TEXTURE_2D : GL_TEXTURE_3D, tex[i]);
        uni_i(p, names[i], i);
    }
    glActiveTexture(GL_TEXTURE0);
    return SSS_OK;
}

/* The surface terms' uniforms (docs/heterogeneous.md §9.1): the light's
 * E0 or I, the view's lobes and whether they are shadowed, by the map with
 * shadow.h's constants. */
static void set_surface(const sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, const double rgb[3],
                        const double eye[3])
{
    const GLuint pr = g->prog_q;
    const double rho_d = p->diffuse > 0 ? (p->diffuse < 1 ? p->diffuse : 1.0) : 0.0; /* as draw.c's */
    uni_v3(pr, "u_ht_rgb", rgb);
    uni_v3(pr, "u_ht_eye", eye);
    uni_f(pr, "u_ht_eta", (float)v->mat.base.eta);
    uni_i(pr, "u_ht_specular", p->specular);
    uni_f(pr, "u_ht_diffuse", (float)rho_d);
    uni_i(pr, "u_ht_shadow", p->surface_shadow);
    uni_f(pr, "u_ht_k_n", (float)SSS_SHADOW_NORMAL_OFFSET);
    uni_f(pr, "u_ht_k_c", (float)SSS_SHADOW_BIAS_CONST);
    uni_f(pr, "u_ht_k_s", (float)SSS_SHADOW_BIAS_SLOPE);
    uni_f(pr, "u_ht_tan_max", (float)SSS_SHADOW_TAN_MAX);
}

static void unbind_units(void)
{
    for (int i = 0; i < 3; i++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)i);
        glBindTexture(i < 2 ? GL_TEXTURE_2D : GL_TEXTURE_3D, 0);
    }
    glActiveTexture(GL_TEXTURE0);
}

/* One light's two draws (§9.1): its map from the light, then q, x_o and
 * its surface terms from the camera, which the first light's pass clears
 * and each later one adds to: q and the surface terms blended one-to-one,
 * the depth buffer already the nearest surface's, so only that surface's
 * fragments pass (GL_LEQUAL) and x_o is written again with the same
 * values. point 0: light is the direction towards a directional light,
 * orthographic map; 1: a point light's position, perspective map. */
static sss_result light_pass(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, const double light[3],
                             int point, const double rgb[3], const float mvp[16], const double eye[3], int width,
                             int height, int add, sss_error *err)
{
    const sss_gpu_mesh *m = &g->r->mesh;
    const double R = m->radius * (1.0 + SSS_HTSM_MAP_MARGIN); /* sss_htsm_point_drawn's sphere */
    float clip[16];
    if (point) {
        if (!sss_shadow_frame_point(m->centre, R, light, clip, g->lookup, &g->ref_w))
            return sss_fail(err, SSS_ERR_ARG, "the point light at (%g, %g, %g) lies within the object's bounding "
                            "sphere (radius %g): no light-space map from there sees the object whole",
                            light[0], light[1], light[2], R);
        memcpy(g->light, light, 3 * sizeof *light);
        g->light[3] = 1.0;
    } else {
        double l[3] = {light[0], light[1], light[2]};
        sss_normalize3(l);
        const float lf[3] = {(float)l[0], (float)l[1], (float)l[2]};
        if (!sss_shadow_frame(m->centre, R, lf, clip, g->lookup))
            return sss_fail(err, SSS_ERR_ARG, "the light has no direction");
        memcpy(g->light, l, sizeof l);
        g->light[3] = 0.0;
        g->ref_w = 1.0;
    }
    /* 1. the map along the light: every surface, the nearest to the light */
    glBindFramebuffer(GL_FRAMEBUFFER, g->map_fbo);
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, bufs);
    glViewport(0, 0, (GLsizei)g->size, (GLsizei)g->size);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
    glUseProgram(g->prog_map);
    glUniformMatrix4fv(glGetUniformLocation(g->prog_map, "u_mat"), 1, GL_FALSE, clip);
    glUniform4f(glGetUniformLocation(g->prog_map, "u_light"), (float)g->light[0], (float)g->light[1],
                (float)g->light[2], (float)g->light[3]);
    uni_v3(g->prog_map, "u_light_rgb", rgb);
    uni_f(g->prog_map, "u_eta", (float)v->mat.base.eta);
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, g->map_tex[i]);
        glGenerateMipmap(GL_TEXTURE_2D);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    /* 2. q, x_o and the surface terms per pixel from the camera */
    glBindFramebuffer(GL_FRAMEBUFFER, g->q_fbo);
    glDrawBuffers(3, bufs);
    glViewport(0, 0, width, height);
    if (add) {
        glDepthFunc(GL_LEQUAL);
        for (GLuint i = 0; i < 3; i += 2) {
            glEnablei(GL_BLEND, i);
            glBlendEquationi(i, GL_FUNC_ADD);
            glBlendFunci(i, GL_ONE, GL_ONE);
        }
    } else {
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    }
    glUseProgram(g->prog_q);
    glUniformMatrix4fv(glGetUniformLocation(g->prog_q, "u_mat"), 1, GL_FALSE, mvp);
    sss_result res = set_estimator(g, v, err);
    set_surface(g, v, p, rgb, eye);
    if (res == SSS_OK) glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
    unbind_units();
    glDisable(GL_BLEND);
    glDepthFunc(GL_LESS);
    return res;
}

sss_result sss_htsm_gpu_frame(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, int width,
                              int height, double *ms, sss_error *err)
{
    const sss_gpu_mesh *m = &g->r->mesh;
    const uint32_t nlights = (v->no_p_light ? 0u : 1u) + v->nmore;
    if (nlights < 1 || nlights > SSS_HTSM_MAX_LIGHTS)
        return sss_fail(err, SSS_ERR_ARG, "%u lights: the run-time path draws 1 to %d", nlights, SSS_HTSM_MAX_LIGHTS);
    sss_result res = q_ensure(g, width, height, err);
    if (res != SSS_OK) return res;
    GLint prev = 0, vp[4];
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev);
    glGetIntegerv(GL_VIEWPORT, vp);
    double eye[3];
    float mvp[16];
    sss_draw_camera_mvp(m, p, width, height, eye, mvp);
    glFinish();
    const double t0 = sss_now();
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glBindVertexArray(m->vao);
    if (!v->no_p_light) res = light_pass(g, v, p, p->light, 0, p->light_rgb, mvp, eye, width, height, 0, err);
    for (uint32_t k = 0; res == SSS_OK && k < v->nmore; k++)
        res = light_pass(g, v, p, v->more_light[k], v->more_point[k], v->more_rgb[k], mvp, eye, width, height,
                         k > 0 || !v->no_p_light, err);
    glBindVertexArray(0);
    glUseProgram(0);
    glFinish();
    if (ms) *ms = 1e3 * (sss_now() - t0);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev);
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    return res;
}

sss_result sss_htsm_gpu_render_image(sss_htsm_gpu *g, const sss_htsm_view *v, const sss_view_params *p, int width,
                                     int height, float **rgb, float **hdr, sss_error *err)
{
    *rgb = NULL;
    if (hdr) *hdr = NULL;
    sss_result res = sss_htsm_gpu_frame(g, v, p, width, height, NULL, err);
    if (res != SSS_OK) return res;
    sss_htsm_gpu_attach(g, 1);
    res = sss_draw_read_image(g->r, p, width, height, rgb, hdr, err);
    sss_htsm_gpu_attach(g, 0);
    return res;
}

sss_result sss_htsm_gpu_attach(sss_htsm_gpu *g, int on)
{
    g->r->draw.qtex = on ? g->q_tex[0] : 0;
    g->r->draw.q_lit = on != 0;
    g->r->draw.stex = on ? g->q_tex[2] : 0;
    return SSS_OK;
}

/* The last frame's image i (q_tex: 0 q, 1 x_o, 2 the surface terms), RGBA
 * floats of the frame's size, into a new array (caller frees). */
static sss_result frame_image(const sss_htsm_gpu *g, int i, float **out, sss_error *err)
{
    *out = NULL;
    if (!g->q_fbo) return sss_fail(err, SSS_ERR_ARG, "no frame drawn yet");
    *out = malloc((size_t)g->w * g->h * 4 * sizeof **out);
    if (!*out) return sss_fail(err, SSS_ERR_NOMEM, "out of memory");
    glBindTexture(GL_TEXTURE_2D, g->q_tex[i]);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, *out);
    glBindTexture(GL_TEXTURE_2D, 0);
    return SSS_OK;
}

sss_result sss_htsm_gpu_read(const sss_htsm_gpu *g, sss_htsm_map *map, float **q, float **x, sss_error *err)
{
    *q = *x = NULL;
    sss_result res = sss_htsm_map_init(map, g->size, err);
    if (res != SSS_OK) return res;
    memcpy(map->lookup, g->lookup, sizeof map->lookup);
    memcpy(map->light, g->light, sizeof map->light);
    map->ref_w = g->ref_w;
    float *dst[3] = {map->pos[0], map->nrm[0], map->irr[0]};
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, g->map_tex[i]);
        glGetTexImage(GL_TEXTURE_2D, 0, GL_RGBA, GL_FLOAT, dst[i]);
    }
    glBindTexture(GL_TEXTURE_2D, 0);
    sss_htsm_map_mips(map);
    sss_result r = frame_image(g, 0, q, err);
    if (r == SSS_OK) r = frame_image(g, 1, x, err);
    if (r != SSS_OK) {
        free(*q);
        *q = NULL;
        sss_htsm_map_free(map);
    }
    return r;
}

sss_result sss_htsm_gpu_read_surface(const sss_htsm_gpu *g, float **s, sss_error *err)
{
    return frame_image(g, 2, s, err);
}
