/* shadow.c: depth-only shadow map from a directional light (shadow.h).
 *
 * The own-term pass with near_visibility = SSS_NEAR_MAP (effects/near.c,
 * GLSL near_vis.comp.glsl without RAYS; the default traces the ray itself,
 * bvh.c) asks whether vertex
 * x_o sees the light, and must answer as the bake does: an Embree ray from
 * x_o + δ n_o, δ = sss_mesh_ray_offset (1e-5 of the box diagonal), towards
 * ω, beyond t = δ, blocked by any hit of the mesh
 * (precompute/src/kernels/visibility.c). It answers in two
 * parts.
 *
 * Around x_o, exactly: the bake's ray against the triangles around x_o
 * (Möller–Trumbore, in the pass). They lie within a fraction of a texel of
 * the vertex, where no map can tell them from the vertex's own surface, and
 * at grazing light a ray clips them often: on the 23K dragon, half of the
 * vertices the map alone called lit against the ray were blocked by their
 * own triangles, the ray hitting them less than one texel away.
 *
 * Far field, the map (Hao–Varshney 2004 §3.1's depth comparison):
 *  - it keeps the nearest surface to the light at each texel, front or back
 *    facing (no culling): "any hit" along the line through the texel centre;
 *  - a lit vertex's own surface is in the map, sampled at the texel centre
 *    up to 0.71 t away, where a plane tilted by θ lies up to 0.71 t tan θ
 *    nearer the light: the map's self-shadowing. Lifting the tested point by
 *    k_n t along n_o puts it k_n t / cos θ in front of its plane along ω,
 *    and the slope-scaled bias adds k_s t tan θ; the two cover 0.71 t tan θ
 *    when k_n + k_s sin θ > 0.71 sin θ, i.e. always for k_n = k_s = 0.5
 *    (below the tan θ clamp, θ < 84°, where g is small anyway);
 *  - both are kept small because the lift moves the tested point sideways
 *    by k_n t sin θ in the map, which at grazing light carries it across an
 *    occluder's outline, and the bias hides occluders that close in depth.
 *    Measured on the dragon (12 random lights, front-facing vertices), with
 *    the exact test around x_o and k_c = 0.05, k_s = 0.5: k_n = 1.5 agrees on
 *    99.30 %, 1.0 on 99.46 %, 0.5 on 99.66 %, 0.25 on 99.55 %, 0 on 97.91 %
 *    (the map shadowing lit vertices: the bias alone is too small; k_c = 0.2,
 *    k_s = 1.5 bring it to 99.59 %). Larger k_s or tan_max change < 0.02 %.
 *    Without the exact test around x_o the best was 99.20 % (k_n = 0.75).
 *  - vertices with n_o·ω ≤ 0 are not tested: the own term's g is 0 there.
 *
 * What is left is sampling: vertices within about a texel of an occluder's
 * outline as the light sees it, a band that at grazing light covers 1/cos θ
 * texels of the receiving surface (so most disagreements are at small
 * n_o·ω, where g is small too). test_render_near_terms measures it.
 */
#include "shadow.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "shaders.h"

struct sss_shadow {
    GLuint vao;
    uint32_t nf;
    double centre[3], radius; /* R' = R (1 + margin) */
    int size;
    GLuint tex, fbo, prog;
    GLint loc_mat;
    int valid;
    float dir[3];    /* direction the map holds */
    float clip[16];  /* world → clip, for the rasteriser */
    float lookup[16];/* world → (s, t, z) in [0, 1]³ */
};

sss_result sss_shadow_create(GLuint vao, uint32_t nf, const double centre[3], double radius, int size,
                             sss_shadow **out, sss_error *err)
{
    *out = NULL;
    GLint max_tex = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
    if (max_tex > 0 && size > max_tex) size = max_tex;
    if (size < 1) return sss_fail(err, SSS_ERR_ARG, "shadow map: size %d", size);
    sss_shadow *s = calloc(1, sizeof *s);
    if (!s) return sss_fail(err, SSS_ERR_NOMEM, "shadow map: out of memory");
    s->vao = vao;
    s->nf = nf;
    memcpy(s->centre, centre, sizeof s->centre);
    s->radius = (radius > 0 ? radius : 1.0) * (1.0 + SSS_SHADOW_MARGIN);
    s->size = size;
    GLuint vs = sss_gl_compile(GL_VERTEX_SHADER, "", sss_glsl_shadow_vert, err);
    GLuint fs = vs ? sss_gl_compile(GL_FRAGMENT_SHADER, "", sss_glsl_shadow_frag, err) : 0;
    s->prog = fs ? sss_gl_link(vs, fs, err) : 0;
    if (!s->prog) {
        if (vs && !fs) glDeleteShader(vs);
        free(s);
        return SSS_ERR_UNSUPPORTED;
    }
    s->loc_mat = glGetUniformLocation(s->prog, "u_mat");

    GLint prev_fb = 0;
    glGetIntegerv(GL_FRAMEBUFFER_BINDING, &prev_fb);
    glGenTextures(1, &s->tex);
    glBindTexture(GL_TEXTURE_2D, s->tex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT32F, size, size);
    /* read with texelFetch: nearest, no comparison mode, no filtering */
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, &s->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, s->tex, 0);
    glDrawBuffer(GL_NONE);
    glReadBuffer(GL_NONE);
    GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, (GLuint)prev_fb);
    if (st != GL_FRAMEBUFFER_COMPLETE || glGetError() == GL_OUT_OF_MEMORY) {
        sss_shadow_destroy(s);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "shadow map: a %dx%d depth framebuffer is not supported", size,
                        size);
    }
    *out = s;
    return SSS_OK;
}

void sss_shadow_destroy(sss_shadow *s)
{
    if (!s) return;
    if (s->fbo) glDeleteFramebuffers(1, &s->fbo);
    if (s->tex) glDeleteTextures(1, &s->tex);
    if (s->prog) glDeleteProgram(s->prog);
    free(s);
}

void sss_shadow_invalidate(sss_shadow *s) { s->valid = 0; }

/* (u, v, ω): u along the world axis least aligned with ω, made orthogonal. */
static void light_frame(const double w[3], double u[3], double v[3])
{
    const double ax = fabs(w[0]), ay = fabs(w[1]), az = fabs(w[2]);
    double a[3] = {0, 0, 0};
    a[ax <= ay && ax <= az ? 0 : ay <= az ? 1 : 2] = 1.0;
    const double d = a[0] * w[0] + a[1] * w[1] + a[2] * w[2];
    double l = 0;
    for (int k = 0; k < 3; k++) u[k] = a[k] - d * w[k], l += u[k] * u[k];
    l = sqrt(l);
    for (int k = 0; k < 3; k++) u[k] /= l;
    v[0] = w[1] * u[2] - w[2] * u[1];
    v[1] = w[2] * u[0] - w[0] * u[2];
    v[2] = w[0] * u[1] - w[1] * u[0];
}

int sss_shadow_frame(const double c[3], double R, const float l[3], float clip[16], float lookup[16])
{
    double w[3] = {l[0], l[1], l[2]}, u[3], v[3];
    const double n = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (!(n > 0.5)) return 0;
    for (int k = 0; k < 3; k++) w[k] /= n;
    light_frame(w, u, v);
    /* rows of the clip matrix: x = u·(p − c)/R', y = v·(p − c)/R',
     * z = −ω·(p − c)/R' (nearer the light → smaller depth), w = 1 */
    const double *rows[3] = {u, v, w};
    const double sign[3] = {1.0, 1.0, -1.0};
    memset(clip, 0, 16 * sizeof *clip);
    memset(lookup, 0, 16 * sizeof *lookup);
    for (int r = 0; r < 3; r++) {
        double off = 0;
        for (int k = 0; k < 3; k++) {
            const double m = sign[r] * rows[r][k] / R;
            clip[k * 4 + r] = (float)m;
            lookup[k * 4 + r] = (float)(0.5 * m);
            off -= m * c[k];
        }
        clip[12 + r] = (float)off;
        lookup[12 + r] = (float)(0.5 * off + 0.5);
    }
    clip[15] = 1.0f;
    lookup[15] = 1.0f;
    return 1;
}

int sss_shadow_frame_point(const double c[3], double R, const double P[3], float clip[16], float lookup[16],
                           double *ref_w)
{
    double e[3] = {c[0] - P[0], c[1] - P[1], c[2] - P[2]}, w[3], u[3], v[3];
    const double D = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    if (!(R > 0.0) || !(D > R) || !isfinite(D)) return 0;
    for (int k = 0; k < 3; k++) e[k] /= D, w[k] = -e[k];
    light_frame(w, u, v);
    /* the cone from P tangent to the sphere: half-angle θ, tan θ = R / sqrt(D² − R²);
     * depth z = e·(p − P) = e·(p − c) + D in [D − R, D + R]. Each row is
     * written about c (u·(p − P) = u·(p − c), since u ⊥ e), so that a far
     * light's large |P| does not cancel in float. */
    const double t = R / sqrt(D * D - R * R), n = D - R, f = D + R;
    const double A = (f + n) / (f - n), B = -2.0 * f * n / (f - n);
    double rows[4][4]; /* x, y, z and w of the clip matrix: a · p + b */
    for (int k = 0; k < 3; k++) rows[0][k] = u[k] / t, rows[1][k] = v[k] / t, rows[3][k] = e[k], rows[2][k] = A * e[k];
    rows[0][3] = -(u[0] * c[0] + u[1] * c[1] + u[2] * c[2]) / t;
    rows[1][3] = -(v[0] * c[0] + v[1] * c[1] + v[2] * c[2]) / t;
    rows[3][3] = D - (e[0] * c[0] + e[1] * c[1] + e[2] * c[2]);
    rows[2][3] = A * rows[3][3] + B;
    for (int r = 0; r < 4; r++)
        for (int k = 0; k < 4; k++) {
            clip[k * 4 + r] = (float)rows[r][k];
            /* (s, t, depth) = ½ (clip / w) + ½: ½ clip + ½ w before the division */
            lookup[k * 4 + r] = (float)(r < 3 ? 0.5 * rows[r][k] + 0.5 * rows[3][k] : rows[3][k]);
        }
    *ref_w = D;
    return 1;
}

int sss_shadow_update(sss_shadow *s, const float l[3], GLuint query)
{
    if (s->valid && s->dir[0] == l[0] && s->dir[1] == l[1] && s->dir[2] == l[2]) {
        if (query) glBeginQuery(GL_TIME_ELAPSED, query);
        return 0;
    }
    if (!sss_shadow_frame(s->centre, s->radius, l, s->clip, s->lookup)) { /* no direction: the caller adds nothing */
        if (query) glBeginQuery(GL_TIME_ELAPSED, query);
        return 0;
    }

    GLint prev_draw = 0, prev_read = 0, vp[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &prev_draw);
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
    glGetIntegerv(GL_VIEWPORT, vp);
    const GLboolean depth_on = glIsEnabled(GL_DEPTH_TEST);
    GLint depth_func = GL_LESS;
    glGetIntegerv(GL_DEPTH_FUNC, &depth_func);
    GLboolean depth_mask = GL_TRUE;
    glGetBooleanv(GL_DEPTH_WRITEMASK, &depth_mask);

    glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    glViewport(0, 0, s->size, s->size);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClearDepth(1.0);
    glClear(GL_DEPTH_BUFFER_BIT);
    /* after the bind and the clear: Mesa 22's llvmpipe returns its clock's
     * absolute value for a timer query that spans either */
    if (query) glBeginQuery(GL_TIME_ELAPSED, query);
    glUseProgram(s->prog);
    glUniformMatrix4fv(s->loc_mat, 1, GL_FALSE, s->clip);
    glBindVertexArray(s->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * s->nf), GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);

    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)prev_draw);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
    glViewport(vp[0], vp[1], vp[2], vp[3]);
    if (!depth_on) glDisable(GL_DEPTH_TEST);
    glDepthFunc((GLenum)depth_func);
    glDepthMask(depth_mask);
    /* no barrier: rendering into the texture and then sampling it is
     * ordered by GL itself (barriers are for shader image/buffer writes) */
    memcpy(s->dir, l, sizeof s->dir);
    s->valid = 1;
    return 1;
}

GLuint sss_shadow_texture(const sss_shadow *s) { return s->tex; }

void sss_shadow_bind(const sss_shadow *s, GLuint pr, int unit)
{
    glActiveTexture(GL_TEXTURE0 + (GLenum)unit);
    glBindTexture(GL_TEXTURE_2D, s->tex);
    glUniform1i(glGetUniformLocation(pr, "u_depth"), unit);
    glUniformMatrix4fv(glGetUniformLocation(pr, "u_shadow"), 1, GL_FALSE, s->lookup);
    glUniform1i(glGetUniformLocation(pr, "u_size"), s->size);
    glUniform1f(glGetUniformLocation(pr, "u_offset"), (float)(SSS_SHADOW_NORMAL_OFFSET * sss_shadow_texel(s)));
    glUniform1f(glGetUniformLocation(pr, "u_bias_c"), (float)SSS_SHADOW_BIAS_CONST);
    glUniform1f(glGetUniformLocation(pr, "u_bias_s"), (float)SSS_SHADOW_BIAS_SLOPE);
    glUniform1f(glGetUniformLocation(pr, "u_tan_max"), (float)SSS_SHADOW_TAN_MAX);
}

int sss_shadow_ensure(sss_shadow **s, GLuint vao, uint32_t nf, const double centre[3], double radius, int size)
{
    size = size > 0 ? (size < 256 ? 256 : size > 8192 ? 8192 : size) : SSS_SHADOW_SIZE;
    if (!*s || size != (*s)->size) {
        sss_shadow *ns = NULL;
        sss_error e = {{0}};
        if (sss_shadow_create(vao, nf, centre, radius, size, &ns, &e) == SSS_OK) {
            sss_shadow_destroy(*s);
            *s = ns;
        }
    }
    return *s != NULL;
}
const float *sss_shadow_matrix(const sss_shadow *s) { return s->lookup; }
int sss_shadow_size(const sss_shadow *s) { return s->size; }
double sss_shadow_texel(const sss_shadow *s) { return 2.0 * s->radius / s->size; }
