/* draw.c: the view of a frame (renderer.h): view parameters and camera,
 * the shading draw
 *     L = E · q · F_t(η, n·ω_o)  [+ E · L⁽¹⁾]  +  V · (specular + diffuse surface terms)
 * per colour channel (Hao–Varshney 2004 §3.1's outgoing radiance; §3.2's
 * direct on-surface light including shadow, V from the shadow map of
 * shadow.c tested per fragment: docs/viewer.md, "Direct surface light";
 * L⁽¹⁾ single scattering per pixel: effects/single.h, docs/layers.md §8), exposure
 * and tone mapping, the float framebuffer, and whole offscreen images.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "renderer.h"
#include "shaders.h"
#include "shadow.h"
#include "effects/single.h"
#include "sss/dipole.h"
#include "sss/vec3.h"

/* single scattering's two maps (effects/single.h): texture units 2 and 3,
 * clear of the shadow map's 0 and of unit 1 */
#define SINGLE_UNIT 2

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
    p->near_terms = 1;
    p->near_visibility = SSS_NEAR_RAYS;
    p->surface_shadow = 1;
}

float sss_tonemap_apply(sss_tonemap t, float x)
{
    if (t == SSS_TONEMAP_REINHARD) return x / (1.0f + x);
    return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x;
}

/* The shading program, with single scattering (single.glsl, defines
 * SSS_SINGLE) or without it: a frame without the term runs a program that
 * does not hold it, which llvmpipe would otherwise step through masked
 * (8 times the draw's cost measured on the blob), and whose image is the
 * old one by construction. */
static GLuint shade_program(const char *defines, sss_error *err)
{
    GLuint vs = sss_gl_compile(GL_VERTEX_SHADER, "", sss_glsl_shade_vert, err);
    const char *parts[6] = {defines,         sss_glsl_shadow_map, sss_glsl_fresnel,
                            sss_glsl_single, sss_glsl_surface,    sss_glsl_shade_frag};
    GLuint fs = vs ? sss_gl_compile_parts(GL_FRAGMENT_SHADER, parts, 6, err) : 0;
    GLuint pr = fs ? sss_gl_link(vs, fs, err) : 0;
    if (vs && !fs) glDeleteShader(vs);
    return pr;
}

sss_result sss_draw_create(sss_draw *d, sss_error *err)
{
    d->prog_shade = shade_program("", err);
    d->prog_shade_ss = d->prog_shade ? shade_program("#define SSS_SINGLE 1\n", err) : 0;
    if (!d->prog_shade_ss) {
        if (d->prog_shade) glDeleteProgram(d->prog_shade);
        d->prog_shade = 0;
        return SSS_ERR_UNSUPPORTED;
    }
    return SSS_OK;
}

void sss_draw_destroy(sss_draw *d)
{
    if (d->prog_shade) glDeleteProgram(d->prog_shade);
    if (d->prog_shade_ss) glDeleteProgram(d->prog_shade_ss);
    sss_shadow_destroy(d->shadow);
    sss_single_destroy(d->single);
    if (d->fbo) {
        glDeleteFramebuffers(1, &d->fbo);
        glDeleteRenderbuffers(1, &d->fbo_color);
        glDeleteRenderbuffers(1, &d->fbo_depth);
    }
}

/* render.h */
void sss_view_frame(const sss_view_params *p, const double centre[3], double radius, double eye[3], double right[3],
                    double up[3], double fwd[3])
{
    double v[3] = {p->view[0], p->view[1], p->view[2]};
    sss_normalize3(v);
    if (!(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] > 0.5)) v[0] = 0, v[1] = 0, v[2] = 1;
    double dist = (p->distance > 0 ? p->distance : 3.6) * radius;
    /* up: the given one (a scene camera's), else +y; +z when looking along it */
    double wup[3] = {p->up[0], p->up[1], p->up[2]};
    if (!(sss_normalize3(wup) > 0) || fabs(sss_dot3(wup, v)) > 0.999) wup[0] = 0, wup[1] = 1, wup[2] = 0;
    if (fabs(sss_dot3(wup, v)) > 0.999) wup[1] = 0, wup[2] = 1;
    for (int k = 0; k < 3; k++) fwd[k] = -v[k];
    sss_cross3(fwd, wup, right);
    sss_normalize3(right);
    sss_cross3(right, fwd, up);
    double target[3];
    for (int k = 0; k < 3; k++) {
        target[k] = centre[k] + (p->pan[0] * right[k] + p->pan[1] * up[k]) * radius;
        eye[k] = target[k] + v[k] * dist;
    }
}

/* The camera frame of p about m's bounding sphere (sss_renderer_camera). */
static void camera(const sss_gpu_mesh *m, const sss_view_params *p, double eye[3], double right[3], double up[3],
                   double fwd[3])
{
    sss_view_frame(p, m->centre, m->radius, eye, right, up, fwd);
}

void sss_renderer_camera(const sss_renderer *r, const sss_view_params *p, double eye[3], double right[3],
                         double up[3], double fwd[3])
{
    camera(&r->mesh, p, eye, right, up, fwd);
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

/* renderer.h */
void sss_draw_camera_mvp(const sss_gpu_mesh *m, const sss_view_params *p, int width, int height, double eye[3],
                         float mvp[16])
{
    double right[3], up[3], fwd[3];
    camera(m, p, eye, right, up, fwd);
    /* column-major view and perspective matrices */
    double V[16] = {right[0], up[0], -fwd[0], 0, right[1], up[1], -fwd[1], 0, right[2], up[2], -fwd[2], 0, 0, 0, 0, 1};
    V[12] = -(right[0] * eye[0] + right[1] * eye[1] + right[2] * eye[2]);
    V[13] = -(up[0] * eye[0] + up[1] * eye[1] + up[2] * eye[2]);
    V[14] = fwd[0] * eye[0] + fwd[1] * eye[1] + fwd[2] * eye[2];
    double dist = (p->distance > 0 ? p->distance : 3.6) * m->radius;
    double zn = fmax(dist - 1.5 * m->radius, 1e-3 * m->radius), zf = dist + 1.5 * m->radius;
    double fy = 1.0 / tan(0.5 * (p->fov_deg > 0 ? p->fov_deg : 35.0) * SSS_PI / 180.0);
    double aspect = height > 0 ? (double)width / height : 1.0;
    double P[16] = {0};
    P[0] = fy / aspect;
    P[5] = fy;
    P[10] = (zf + zn) / (zn - zf);
    P[11] = -1;
    P[14] = 2 * zf * zn / (zn - zf);
    mat4_mul(P, V, mvp);
}

void sss_draw_frame(sss_draw *d, const sss_gpu_mesh *m, const sss_view_params *p, int width, int height,
                    GLuint query)
{
    double eye[3];
    float mvp[16];
    sss_draw_camera_mvp(m, p, width, height, eye, mvp);
    double l[3] = {p->light[0], p->light[1], p->light[2]};
    sss_normalize3(l);
    const float lf[3] = {(float)l[0], (float)l[1], (float)l[2]};
    const double rho_d = p->diffuse > 0 ? (p->diffuse < 1 ? p->diffuse : 1.0) : 0.0;
    /* the surface terms' shadow: the map for this light, rendered (outside
     * the draw's timer: llvmpipe's timer spans no framebuffer switch) only
     * when the light direction or the size changes */
    /* the run-time path's surface terms come per pixel, each light's tested
     * against its own light-space map (htsm_gpu.c): no shadow map here */
    const int simage = d->qtex && d->q_lit && d->stex;
    const int shadowed = !simage && p->surface_shadow && (p->specular || rho_d > 0) &&
                         lf[0] * lf[0] + lf[1] * lf[1] + lf[2] * lf[2] > 0.5f &&
                         sss_shadow_ensure(&d->shadow, m->vao, m->nf, m->centre, m->radius, p->shadow_size);
    if (shadowed) sss_shadow_update(d->shadow, lf, 0);
    /* single scattering's maps, before the draw and outside its timer as the shadow map */
    const int single = sss_single_wanted(m->f, p) && lf[0] * lf[0] + lf[1] * lf[1] + lf[2] * lf[2] > 0.5f &&
                       sss_single_ensure(&d->single, m);
    if (single) sss_single_prepare(d->single, m, mvp, lf, width, height);

    glViewport(0, 0, width, height);
    glClearColor(p->background[0], p->background[1], p->background[2], 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glBeginQuery(GL_TIME_ELAPSED, query);
    const GLuint pr = single ? d->prog_shade_ss : d->prog_shade;
    glUseProgram(pr);
    glUniformMatrix4fv(glGetUniformLocation(pr, "u_mvp"), 1, GL_FALSE, mvp);
    glUniform1ui(glGetUniformLocation(pr, "u_channels"), m->C);
    glUniform3f(glGetUniformLocation(pr, "u_eye"), (float)eye[0], (float)eye[1], (float)eye[2]);
    glUniform3f(glGetUniformLocation(pr, "u_light"), (float)l[0], (float)l[1], (float)l[2]);
    glUniform3f(glGetUniformLocation(pr, "u_light_rgb"), (float)p->light_rgb[0], (float)p->light_rgb[1],
                (float)p->light_rgb[2]);
    glUniform1f(glGetUniformLocation(pr, "u_eta"), (float)m->f->material.eta);
    /* the exit term F_t/π, or F_t/(π c) normalised (sss/dipole.h) */
    glUniform1f(glGetUniformLocation(pr, "u_exit_scale"),
                (float)(p->exit_normalised ? 1.0 / sss_exit_norm(m->f->material.eta) : 1.0));
    glUniform1f(glGetUniformLocation(pr, "u_exposure"), (float)(p->exposure > 0 ? p->exposure : 1.0));
    glUniform1i(glGetUniformLocation(pr, "u_scatter"), p->scatter);
    glUniform1i(glGetUniformLocation(pr, "u_specular"), p->specular);
    glUniform1f(glGetUniformLocation(pr, "u_diffuse"), (float)rho_d);
    glUniform1i(glGetUniformLocation(pr, "u_surface_shadow"), shadowed);
    if (shadowed) sss_shadow_bind(d->shadow, pr, 0);
    if (single) {
        sss_single_bind(d->single, pr, m, p, mvp, SINGLE_UNIT);
    } else { /* no layer depths for the vertex shader to pass on */
        glUniform1i(glGetUniformLocation(pr, "u_ss_nd"), 0);
    }
    GLint fb = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &fb);
    int offscreen = fb != 0 && (GLuint)fb == d->fbo;
    glUniform1i(glGetUniformLocation(pr, "u_tonemap"), offscreen ? -1 : (int)p->tonemap);
    glUniform1i(glGetUniformLocation(pr, "u_srgb"), offscreen ? 0 : 1);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, m->qbuf);
    glBindVertexArray(m->vao);
    glUniform1i(glGetUniformLocation(pr, "u_flat"), 0);
    /* q per pixel (the splatting, splat_gpu.c) instead of per vertex */
    glUniform1i(glGetUniformLocation(pr, "u_qimage"), d->qtex != 0);
    glUniform1i(glGetUniformLocation(pr, "u_q_lit"), d->qtex != 0 && d->q_lit);
    glUniform1i(glGetUniformLocation(pr, "u_simage"), simage);
    if (d->qtex) {
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, d->qtex);
        if (simage) {
            glActiveTexture(GL_TEXTURE4);
            glBindTexture(GL_TEXTURE_2D, d->stex);
        }
        glActiveTexture(GL_TEXTURE0);
    }
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
    if (p->wireframe) {
        glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
        glEnable(GL_POLYGON_OFFSET_LINE);
        glPolygonOffset(-1.0f, -1.0f);
        glUniform1i(glGetUniformLocation(pr, "u_flat"), 1);
        glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
        glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
        glDisable(GL_POLYGON_OFFSET_LINE);
    }
    glBindVertexArray(0);
    if (shadowed) glBindTexture(GL_TEXTURE_2D, 0);
    if (single) sss_single_unbind(SINGLE_UNIT);
    glEndQuery(GL_TIME_ELAPSED);
}

sss_result sss_renderer_bind_offscreen(sss_renderer *r, int width, int height, sss_error *err)
{
    sss_draw *d = &r->draw;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return sss_fail(err, SSS_ERR_ARG, "image size %dx%d out of range [1, 16384]", width, height);
    if (!d->fbo || d->fbo_w != width || d->fbo_h != height) {
        if (d->fbo) {
            glDeleteFramebuffers(1, &d->fbo);
            glDeleteRenderbuffers(1, &d->fbo_color);
            glDeleteRenderbuffers(1, &d->fbo_depth);
        }
        glGenFramebuffers(1, &d->fbo);
        glGenRenderbuffers(1, &d->fbo_color);
        glGenRenderbuffers(1, &d->fbo_depth);
        glBindRenderbuffer(GL_RENDERBUFFER, d->fbo_color);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA32F, width, height);
        glBindRenderbuffer(GL_RENDERBUFFER, d->fbo_depth);
        glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width, height);
        glBindFramebuffer(GL_FRAMEBUFFER, d->fbo);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, d->fbo_color);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, d->fbo_depth);
        if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            glBindFramebuffer(GL_FRAMEBUFFER, 0);
            return sss_fail(err, SSS_ERR_UNSUPPORTED, "float framebuffer %dx%d is not supported", width, height);
        }
        d->fbo_w = width;
        d->fbo_h = height;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, d->fbo);
    return SSS_OK;
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
    sss_result res = sss_renderer_bind_offscreen(r, width, height, err);
    if (res != SSS_OK) return res;
    if (q) sss_renderer_upload_q(r, q);
    else sss_renderer_evaluate(r, p);
    return sss_draw_read_image(r, p, width, height, rgb, hdr, err);
}

/* renderer.h */
sss_result sss_draw_read_image(sss_renderer *r, const sss_view_params *p, int width, int height, float **rgb,
                               float **hdr, sss_error *err)
{
    *rgb = NULL;
    if (hdr) *hdr = NULL;
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
    glBindFramebuffer(GL_FRAMEBUFFER, r->draw.fbo);
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
