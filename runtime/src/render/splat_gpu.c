/* splat_gpu.c: Chen et al. 2012 §4's multiresolution splatting on the GPU
 * (sss/splat_gpu.h; docs/deformable.md §9). The 2012 paper splats with a
 * geometry shader per selected sample; here each stage is a compute pass
 * (splat.comp.glsl) and the splat is turned into a gather: a pixel of
 * camera level k projects its surface point into the light plane and
 * walks the irradiance quadtree's selected samples within the reach of
 * level k (the light plane's distance bounds the 3D one, so nothing in
 * range is missed), descending only where the selection's cut lies below.
 * Every pixel writes its own B^k, so no atomics or binning are needed.
 * The tables (R̄ of Eq. 14, R_d) come from sss/splat.h and sss/dipole.h.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gl_util.h"
#include "renderer.h"
#include "shaders.h"
#include "sss/clock.h"
#include "sss/dipole.h"
#include "sss/hatweights.h"
#include "sss/splat.h"
#include "sss/splat_gpu.h"
#include "sss/vec3.h"

/* R̄ sampled at log2 T = 0, 1/8, … 13 (T = 1 … 8192 texels across R_P) */
#define RB_N 105
#define RB_LO 0.0
#define RB_STEP 0.125
/* P̄'s samples (splat.c's grid): Eq. 14's R̄ is found on this grid */
#define PBAR_N 257
/* R_d per channel at sqrt(r / R_cut) uniform: dense near the peak at 0 */
#define RD_N 2048
/* light levels of the adaptive selection (the paper's three) */
#define LIGHT_LEVELS 3
/* splat.comp.glsl's CHUNK */
#define SPLAT_CHUNK 16
/* Eq. 17's λ_z (and λ_m) */
#define LAMBDA_Z 8.0
/* R_P(f) samples per channel of a spatially varying material, f = 0 … 1 */
#define RP_N 33
/* the materials R̄ and R_cut are taken over (their largest), f = 0, 1/4, … 1 */
#define FIELD_LEVELS 5

enum { P_LIGHT0, P_LIGHTMIP, P_SELECT, P_CAM0, P_CAMMIP, P_GATHER, P_UP, P_N };
enum { T_BUF, T_L0, T_L1, T_L2, T_ACC, T_N };

struct sss_splat_gpu {
    sss_renderer *r;
    sss_splat_options o;
    uint32_t C;
    double mpu, eta;
    double RP_mm[3], Rcut_mm[3];
    float rbar[RB_N];
    GLuint prog_light, prog_cam, prog[P_N];
    GLuint tab;                              /* R̄ then R_d per channel */
    GLuint lfbo, ltex[3];                    /* light raster: a, b, depth */
    GLuint cfbo, ctex[3];                    /* camera raster */
    int cw, ch;
    GLuint la, lb, sel, ca, cb, bk, qtex;
    uint32_t loff[LIGHT_LEVELS], coff[3], cdim[3][2];
    uint32_t ltot;                           /* texels of the light levels */
    /* A spatially varying material (sss_splat_gpu_set_field): f per vertex
     * as vertex attribute 2 of the splat's own VAO, f per texel and pixel
     * in mf; R_P(f) per channel; the inside material (f = 1). */
    int field;
    GLuint vao, fvbo, mf, ltexf, ctexf;
    sss_material inside;
    double RPmin_mm[3], RPmax_mm[3];
    double t0, t_ms[T_N];
};

void sss_splat_options_default(sss_splat_options *o)
{
    memset(o, 0, sizeof *o);
    o->light_size = 512;
    o->levels = 3;
    o->adaptive = 1;
    o->alpha = SSS_SPLAT_ALPHA;
    o->z0 = 0.03;
    o->eps = SSS_SPLAT_EPS;
    o->cut_eps = 1e-3;
}

static GLuint raster_program(int light, sss_error *err)
{
    GLuint vs = sss_gl_compile(GL_VERTEX_SHADER, "", sss_glsl_splat_raster_vert, err);
    const char *parts[3] = {light ? "#define LIGHT 1\n" : "#define LIGHT 0\n", sss_glsl_fresnel,
                            sss_glsl_splat_raster_frag};
    GLuint fs = vs ? sss_gl_compile_parts(GL_FRAGMENT_SHADER, parts, 3, err) : 0;
    if (vs && !fs) glDeleteShader(vs);
    return fs ? sss_gl_link(vs, fs, err) : 0;
}

static GLuint pass_program(int pass, sss_error *err)
{
    char def[32];
    snprintf(def, sizeof def, "#define PASS %d\n", pass + 1);
    GLuint cs = sss_gl_compile(GL_COMPUTE_SHADER, def, sss_glsl_splat_comp, err);
    return cs ? sss_gl_link(cs, 0, err) : 0;
}

/* R̄ at T from the table, as the gather interpolates it (splat.comp.glsl). */
static double rbar_at(const sss_splat_gpu *s, double T)
{
    double x = (log2(T > 1e-30 ? T : 1e-30) - RB_LO) / RB_STEP;
    if (x < 0) x = 0;
    if (x > RB_N - 1) x = RB_N - 1;
    int i = (int)x;
    if (i > RB_N - 2) i = RB_N - 2;
    return s->rbar[i] + (x - i) * (s->rbar[i + 1] - s->rbar[i]);
}

/* The blend at f of the file's material (f = 0) and the field's inside
 * (f = 1), as sss_material_blend makes it; its dipoles. */
static sss_result dipoles_at(const sss_splat_gpu *s, double fv, sss_dipole *dip, sss_error *err)
{
    const sss_material *base = &s->r->mesh.f->material;
    sss_material m = *base;
    if (s->field) sss_material_blend(base, &s->inside, fv, &m);
    for (uint32_t c = 0; c < s->C; c++)
        if (sss_dipole_init(&dip[c], m.sigma_a[c], m.sigmap_s[c], base->eta) != SSS_OK)
            return sss_fail(err, SSS_ERR_ARG, "splatting: channel %u of the material at f = %g makes no dipole", c, fv);
    return SSS_OK;
}

/* R̄ (Eqs. 14–16), R_P, R_cut and the tables the gather reads (TAB): R̄,
 * R_d per channel, and with a field R_P(f) per channel. With a field, R̄
 * and R_cut are the largest over the blends at f = 0, 1/4, … 1 and R_P
 * the range of R_P(f): the level ranges and reaches err on the long side. */
static sss_result build_tables(sss_splat_gpu *s, sss_error *err)
{
    const sss_bake_file *f = s->r->mesh.f;
    const int nf = s->field ? FIELD_LEVELS : 1;
    sss_dipole dip[3];
    for (uint32_t c = 0; c < 3; c++) {
        s->Rcut_mm[c] = 0;
        s->RPmin_mm[c] = INFINITY;
        s->RPmax_mm[c] = 0;
    }
    for (int lv = 0; lv < nf; lv++) {
        const double fv = nf > 1 ? (double)lv / (nf - 1) : 0.0;
        sss_result res = dipoles_at(s, fv, dip, err);
        if (res != SSS_OK) return res;
        /* P̄ and R̄ (Eqs. 14–16); R̄ made non-increasing in T, as Eq. 13's
         * ranges need (splat.c's level ranges take the same maximum) */
        sss_splat_profile prof;
        res = sss_splat_profile_dipole(dip, s->C, PBAR_N, &prof, err);
        if (res != SSS_OK) return res;
        for (int i = 0; i < RB_N; i++) {
            const float rb = (float)sss_splat_min_radius(&prof, exp2(RB_LO + i * RB_STEP), s->o.eps);
            if (lv == 0 || rb > s->rbar[i]) s->rbar[i] = rb;
        }
        for (uint32_t c = 0; c < s->C; c++) {
            s->RPmin_mm[c] = fmin(s->RPmin_mm[c], prof.R_P[c]);
            s->RPmax_mm[c] = fmax(s->RPmax_mm[c], prof.R_P[c]);
        }
        sss_splat_profile_free(&prof);
        /* the last level's reach: the bake's neighbourhood radius per channel,
         * so that the splat sums what the object-space path sums (the paper's
         * R_P holds 95 % of R_d's energy and would drop the rest) */
        double rc[3];
        sss_cutoff_radius_mm(&f->mesh, s->mpu, dip, s->C, s->o.cut_eps, rc);
        for (uint32_t c = 0; c < s->C; c++) s->Rcut_mm[c] = fmax(s->Rcut_mm[c], rc[c]);
    }
    for (int i = 1; i < RB_N; i++)
        if (s->rbar[i] > s->rbar[i - 1]) s->rbar[i] = s->rbar[i - 1];
    for (uint32_t c = 0; c < s->C; c++) {
        s->RP_mm[c] = s->RPmax_mm[c];
        if (s->Rcut_mm[c] < s->RP_mm[c]) s->Rcut_mm[c] = s->RP_mm[c];
    }
    /* R_d per channel for a homogeneous object (dip holds its dipoles from
     * the loop's one pass); a field's is evaluated per pair */
    const size_t ntab = RB_N + 3 * RD_N + 3 * RP_N;
    float *tab = calloc(ntab, sizeof *tab);
    if (!tab) return sss_fail(err, SSS_ERR_NOMEM, "splatting: out of memory");
    memcpy(tab, s->rbar, sizeof s->rbar);
    if (!s->field)
        for (uint32_t c = 0; c < s->C; c++)
            for (int i = 0; i < RD_N; i++) {
                const double u = (double)i / (RD_N - 1);
                tab[RB_N + c * RD_N + i] = (float)sss_rd(&dip[c], u * u * s->Rcut_mm[c]);
            }
    for (int i = 0; s->field && i < RP_N; i++) {
        sss_splat_profile prof;
        sss_result res = dipoles_at(s, (double)i / (RP_N - 1), dip, err);
        if (res == SSS_OK) res = sss_splat_profile_dipole(dip, s->C, 2, &prof, err);
        if (res != SSS_OK) {
            free(tab);
            return res;
        }
        for (uint32_t c = 0; c < s->C; c++) tab[RB_N + s->C * RD_N + c * RP_N + i] = (float)prof.R_P[c];
        sss_splat_profile_free(&prof);
    }
    if (s->tab) glDeleteBuffers(1, &s->tab);
    s->tab = sss_gl_ssbo((GLsizeiptr)ntab * sizeof *tab, tab, GL_STATIC_DRAW);
    free(tab);
    return SSS_OK;
}

/* A raster's targets, w × h: position and normal (RGBA32F, attachments 0
 * and 1), depth, and f of a spatially varying material (R32F, attachment
 * 2: splat_raster.frag.glsl's o_c), for the irradiance and the camera
 * buffers alike; 1 when the framebuffer is complete. */
static int raster_targets(int w, int h, GLuint tex[3], GLuint *texf, GLuint *fbo)
{
    glGenTextures(3, tex);
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glTexStorage2D(GL_TEXTURE_2D, 1, i < 2 ? GL_RGBA32F : GL_DEPTH_COMPONENT32F, w, h);
    }
    glGenTextures(1, texf);
    glBindTexture(GL_TEXTURE_2D, *texf);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_R32F, w, h);
    glBindTexture(GL_TEXTURE_2D, 0);
    glGenFramebuffers(1, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, *fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex[0], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D, tex[1], 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT2, GL_TEXTURE_2D, *texf, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, tex[2], 0);
    const GLenum bufs[3] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    glDrawBuffers(3, bufs);
    const int ok = glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return ok;
}

sss_result sss_splat_gpu_create(sss_renderer *r, const sss_splat_options *opt, sss_splat_gpu **out, sss_error *err)
{
    *out = NULL;
    sss_splat_options o;
    sss_splat_options_default(&o);
    if (opt) {
        if (opt->light_size) o.light_size = opt->light_size;
        if (opt->levels) o.levels = opt->levels;
        o.adaptive = opt->adaptive;
        if (opt->alpha > 0) o.alpha = opt->alpha;
        if (opt->z0 > 0) o.z0 = opt->z0;
        if (opt->eps > 0) o.eps = opt->eps;
        if (opt->cut_eps > 0) o.cut_eps = opt->cut_eps;
    }
    if (o.light_size < 64 || o.light_size > 4096 || (o.light_size & (o.light_size - 1)))
        return sss_fail(err, SSS_ERR_ARG, "splatting: irradiance buffer of %d texels (a power of two, 64 to 4096)",
                        o.light_size);
    if (o.levels < 1 || o.levels > 3)
        return sss_fail(err, SSS_ERR_ARG, "splatting: %d levels (1 to 3)", o.levels);
    if (!(o.alpha < 1e6) || !(o.z0 < 1e6) || !(o.eps < 1) || !(o.cut_eps < 1))
        return sss_fail(err, SSS_ERR_ARG, "splatting: alpha %g, z0 %g, eps %g or the cut's eps %g out of range",
                        o.alpha, o.z0, o.eps, o.cut_eps);
    const sss_bake_file *f = r->mesh.f;
    sss_splat_gpu *s = calloc(1, sizeof *s);
    if (!s) return sss_fail(err, SSS_ERR_NOMEM, "splatting: out of memory");
    s->r = r;
    s->o = o;
    s->C = r->mesh.C;
    s->mpu = f->mm_per_unit;
    s->eta = f->material.eta;
    sss_result res = build_tables(s, err);
    if (res != SSS_OK) {
        free(s);
        return res;
    }
    s->prog_light = raster_program(1, err);
    s->prog_cam = s->prog_light ? raster_program(0, err) : 0;
    int ok = s->prog_cam != 0;
    for (int i = 0; ok && i < P_N; i++) ok = (s->prog[i] = pass_program(i, err)) != 0;
    if (!ok) {
        sss_splat_gpu_destroy(s);
        return SSS_ERR_UNSUPPORTED;
    }
    /* the irradiance buffer: its raster and its levels */
    const GLsizei N = o.light_size;
    ok = raster_targets(N, N, s->ltex, &s->ltexf, &s->lfbo);
    if (!ok) {
        sss_splat_gpu_destroy(s);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "splatting: a %dx%d float irradiance buffer is not supported", N, N);
    }
    uint32_t tot = 0;
    for (int j = 0; j < LIGHT_LEVELS; j++) {
        s->loff[j] = tot;
        tot += (uint32_t)(N >> j) * (uint32_t)(N >> j);
    }
    s->ltot = tot;
    s->la = sss_gl_ssbo((GLsizeiptr)tot * 16, NULL, GL_DYNAMIC_COPY);
    s->lb = sss_gl_ssbo((GLsizeiptr)tot * 16, NULL, GL_DYNAMIC_COPY);
    s->sel = sss_gl_ssbo((GLsizeiptr)tot * 4, NULL, GL_DYNAMIC_COPY);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    *out = s;
    return SSS_OK;
}

static void camera_free(sss_splat_gpu *s)
{
    if (!s->cfbo) return;
    glDeleteFramebuffers(1, &s->cfbo);
    glDeleteTextures(3, s->ctex);
    GLuint b[4] = {s->ca, s->cb, s->bk, s->mf};
    glDeleteBuffers(4, b);
    glDeleteTextures(1, &s->qtex);
    glDeleteTextures(1, &s->ctexf);
    s->mf = s->ctexf = 0;
    s->cfbo = 0;
}

void sss_splat_gpu_destroy(sss_splat_gpu *s)
{
    if (!s) return;
    camera_free(s);
    if (s->prog_light) glDeleteProgram(s->prog_light);
    if (s->prog_cam) glDeleteProgram(s->prog_cam);
    for (int i = 0; i < P_N; i++)
        if (s->prog[i]) glDeleteProgram(s->prog[i]);
    GLuint b[4] = {s->tab, s->la, s->lb, s->sel};
    glDeleteBuffers(4, b);
    if (s->lfbo) glDeleteFramebuffers(1, &s->lfbo);
    if (s->ltex[0]) glDeleteTextures(3, s->ltex);
    if (s->ltexf) glDeleteTextures(1, &s->ltexf);
    if (s->fvbo) glDeleteBuffers(1, &s->fvbo);
    if (s->vao) glDeleteVertexArrays(1, &s->vao);
    free(s);
}

sss_splat_times sss_splat_gpu_times(const sss_splat_gpu *s)
{
    sss_splat_times t = {s->t_ms[T_BUF], {s->t_ms[T_L0], s->t_ms[T_L1], s->t_ms[T_L2]}, s->t_ms[T_ACC]};
    return t;
}

/* The camera raster and the splatting buffer's levels for a w × h frame. */
static sss_result camera_ensure(sss_splat_gpu *s, int w, int h, sss_error *err)
{
    if (s->cfbo && s->cw == w && s->ch == h) return SSS_OK;
    camera_free(s);
    glGenTextures(1, &s->qtex);
    glBindTexture(GL_TEXTURE_2D, s->qtex);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, w, h);
    glBindTexture(GL_TEXTURE_2D, 0);
    const int ok = raster_targets(w, h, s->ctex, &s->ctexf, &s->cfbo);
    s->cw = w;
    s->ch = h;
    if (!ok) {
        camera_free(s);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "splatting: a %dx%d float splatting buffer is not supported", w, h);
    }
    uint32_t tot = 0, cw = (uint32_t)w, chh = (uint32_t)h;
    for (int k = 0; k < 3; k++) {
        s->coff[k] = tot;
        s->cdim[k][0] = cw;
        s->cdim[k][1] = chh;
        tot += cw * chh;
        cw = (cw + 1) / 2;
        chh = (chh + 1) / 2;
    }
    s->ca = sss_gl_ssbo((GLsizeiptr)tot * 16, NULL, GL_DYNAMIC_COPY);
    s->cb = sss_gl_ssbo((GLsizeiptr)tot * 16, NULL, GL_DYNAMIC_COPY);
    s->bk = sss_gl_ssbo((GLsizeiptr)tot * 16, NULL, GL_DYNAMIC_COPY);
    s->mf = sss_gl_ssbo((GLsizeiptr)(s->ltot + tot) * 4, NULL, GL_DYNAMIC_COPY); /* f: light, then camera levels */
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    return SSS_OK;
}

/* Stage times: the wall clock between two glFinish, not GL_TIME_ELAPSED:
 * llvmpipe runs a compute dispatch on the CPU when it is issued, outside
 * its timer queries (which read 0 for it and garbage across a framebuffer
 * switch), and glFinish makes the wall clock measure completed work on a
 * GPU too. */
static void t_begin(sss_splat_gpu *s)
{
    glFinish();
    s->t0 = sss_now();
}
static void t_end(sss_splat_gpu *s, int stage)
{
    glFinish();
    s->t_ms[stage] += 1e3 * (sss_now() - s->t0);
}

static void barrier(void)
{
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT);
}

/* One compute pass over a w × h grid of level offset off (the other
 * level's offset and size off2, w2 × h2). */
static GLuint pass_use(const sss_splat_gpu *s, int pass, uint32_t w, uint32_t h, uint32_t off, uint32_t off2,
                       uint32_t w2, uint32_t h2)
{
    GLuint p = s->prog[pass];
    glUseProgram(p);
    glUniform2ui(glGetUniformLocation(p, "u_size"), w, h);
    glUniform1ui(glGetUniformLocation(p, "u_off"), off);
    glUniform1ui(glGetUniformLocation(p, "u_off2"), off2);
    glUniform2ui(glGetUniformLocation(p, "u_size2"), w2, h2);
    glUniform1i(glGetUniformLocation(p, "u_field"), s->field);
    glUniform1ui(glGetUniformLocation(p, "u_cfo"), s->ltot);
    return p;
}
static void dispatch(uint32_t w, uint32_t h)
{
    glDispatchCompute((w + 7) / 8, (h + 7) / 8, 1);
    barrier();
}

static void raster(GLuint prog, GLuint fbo, int w, int h, const sss_gpu_mesh *m, GLuint vao)
{
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, w, h);
    glClearColor(0, 0, 0, 0);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glUseProgram(prog);
    glBindVertexArray(vao ? vao : m->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * m->nf), GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
}

static void set3(GLuint p, const char *name, const double v[3])
{
    glUniform3f(glGetUniformLocation(p, name), (float)v[0], (float)v[1], (float)v[2]);
}

/* The field's materials and R_P(f) table for the gather and the upsampling. */
static void field_uniforms(const sss_splat_gpu *s, GLuint pr)
{
    if (!s->field) return;
    const sss_material *b = &s->r->mesh.f->material, *in = &s->inside;
    set3(pr, "u_sa0", b->sigma_a);
    set3(pr, "u_ss0", b->sigmap_s);
    set3(pr, "u_sa1", in->sigma_a);
    set3(pr, "u_ss1", in->sigmap_s);
    sss_dipole d;
    sss_dipole_init(&d, b->sigma_a[0], b->sigmap_s[0], b->eta); /* A depends on η alone */
    glUniform1f(glGetUniformLocation(pr, "u_A"), (float)d.A);
    glUniform1ui(glGetUniformLocation(pr, "u_rpo"), RB_N + s->C * RD_N);
    glUniform1i(glGetUniformLocation(pr, "u_nrp"), RP_N);
}

sss_result sss_splat_gpu_set_field(sss_splat_gpu *s, const sss_material *inside, const float *f, sss_error *err)
{
    const sss_gpu_mesh *m = &s->r->mesh;
    if (!f) {
        s->field = 0;
        return build_tables(s, err);
    }
    if (!inside) return sss_fail(err, SSS_ERR_ARG, "splatting: a field without its inside material");
    for (uint32_t v = 0; v < m->nv; v++)
        if (!(f[v] >= 0.0f && f[v] <= 1.0f))
            return sss_fail(err, SSS_ERR_ARG, "splatting: f of vertex %u is %g, outside [0, 1]", v, (double)f[v]);
    s->field = 1;
    s->inside = *inside;
    sss_result res = build_tables(s, err);
    if (res != SSS_OK) {
        s->field = 0;
        (void)build_tables(s, NULL);
        return res;
    }
    /* the splat's own VAO: the renderer's positions, normals and triangles
     * (which a new pose updates in place) and f as attribute 2 */
    if (!s->vao) {
        glGenVertexArrays(1, &s->vao);
        glGenBuffers(1, &s->fvbo);
        glBindVertexArray(s->vao);
        glBindBuffer(GL_ARRAY_BUFFER, m->vbo_pos);
        glEnableVertexAttribArray(0);
        glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
        glBindBuffer(GL_ARRAY_BUFFER, m->vbo_nrm);
        glEnableVertexAttribArray(1);
        glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 0, NULL);
        glBindBuffer(GL_ARRAY_BUFFER, s->fvbo);
        glEnableVertexAttribArray(2);
        glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, 0, NULL);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m->ebo);
        glBindVertexArray(0);
    }
    glBindBuffer(GL_ARRAY_BUFFER, s->fvbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)m->nv * sizeof *f, f, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return SSS_OK;
}

sss_result sss_splat_gpu_render_image(sss_splat_gpu *s, const sss_view_params *p, const double (*dirs)[3],
                                      const double (*w)[3], uint32_t nl, int width, int height, float **rgb,
                                      float **hdr, sss_error *err)
{
    *rgb = NULL;
    if (hdr) *hdr = NULL;
    if (width < 1 || height < 1 || width > 16384 || height > 16384)
        return sss_fail(err, SSS_ERR_ARG, "image size %dx%d out of range [1, 16384]", width, height);
    sss_result res = camera_ensure(s, width, height, err);
    if (res != SSS_OK) return res;
    memset(s->t_ms, 0, sizeof s->t_ms);
    sss_renderer *r = s->r;
    const sss_gpu_mesh *m = &r->mesh;
    const uint32_t C = s->C, K = (uint32_t)s->o.levels, J = s->o.adaptive ? LIGHT_LEVELS : 1;
    const uint32_t N0 = (uint32_t)s->o.light_size;
    /* the pose's own bounds: the light frame must hold this shape, not the first */
    double c[3];
    const double Rl = 1.001 * sss_mesh_bounding_sphere(&m->f->mesh, c);
    double RPw[3] = {0, 0, 0}, RPmm[3] = {0, 0, 0}, Rcut[3] = {0, 0, 0}, RPsel[3] = {0, 0, 0};
    for (uint32_t k = 0; k < C; k++) {
        RPmm[k] = s->RP_mm[k];
        RPw[k] = s->RP_mm[k] / s->mpu;
        Rcut[k] = s->Rcut_mm[k];
        /* Eq. 11's M with a field: the shortest R_P of any blend, so that a
         * coarse texel stands for its children only where every material
         * allows it (the homogeneous R_P otherwise) */
        RPsel[k] = (s->field ? s->RPmin_mm[k] : s->RP_mm[k]) / s->mpu;
    }

    /* the splatting buffer, once for all lights */
    double eye[3], right[3], up[3], fwd[3];
    float mvp[16];
    sss_draw_camera_mvp(m, p, width, height, eye, mvp);
    sss_renderer_camera(r, p, eye, right, up, fwd);
    glUseProgram(s->prog_cam);
    glUniformMatrix4fv(glGetUniformLocation(s->prog_cam, "u_mvp"), 1, GL_FALSE, mvp);
    set3(s->prog_cam, "u_eye", eye);
    set3(s->prog_cam, "u_fwd", fwd);
    glBindFramebuffer(GL_FRAMEBUFFER, s->cfbo);
    t_begin(s);
    raster(s->prog_cam, s->cfbo, width, height, m, s->field ? s->vao : 0);
    t_end(s, T_BUF);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    barrier();
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, s->la);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, s->lb);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, s->sel);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, s->ca);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, s->cb);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, s->bk);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, s->tab);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, s->mf);
    t_begin(s);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, s->ctex[0]);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, s->ctex[1]);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, s->ctexf);
    pass_use(s, P_CAM0, s->cdim[0][0], s->cdim[0][1], s->coff[0], 0, 0, 0);
    dispatch(s->cdim[0][0], s->cdim[0][1]);
    for (uint32_t k = 0; k + 1 < K; k++) {
        pass_use(s, P_CAMMIP, s->cdim[k + 1][0], s->cdim[k + 1][1], s->coff[k + 1], s->coff[k], s->cdim[k][0],
                 s->cdim[k][1]);
        dispatch(s->cdim[k + 1][0], s->cdim[k + 1][1]);
    }
    t_end(s, T_BUF);

    /* T(x_i) = T^k R_P / (2 tan(fov/2) z(x_i)) (Eq. 14's note), T^k the level's rows */
    const double tanh2 = 2.0 * tan(0.5 * (p->fov_deg > 0 ? p->fov_deg : 35.0) * SSS_PI / 180.0);
    const double zfar = sqrt(sss_dot3((double[3]){eye[0] - c[0], eye[1] - c[1], eye[2] - c[2]},
                                      (double[3]){eye[0] - c[0], eye[1] - c[1], eye[2] - c[2]})) + Rl;
    double tk[4] = {0, 0, 0, 0}, reach[3] = {0, 0, 0};
    for (uint32_t k = 0; k < K; k++) tk[k] = s->cdim[k][1] / tanh2;
    for (uint32_t k = 0; k < K; k++)
        for (uint32_t ch = 0; ch < C; ch++) {
            /* the farthest sample projects smallest, so its R̄ is the largest */
            const double hi = k == K - 1 ? Rcut[ch] : RPmm[ch] * rbar_at(s, tk[k + 1] * RPw[ch] / zfar);
            if (hi / s->mpu > reach[k]) reach[k] = hi / s->mpu;
            /* a field's pairs take R_P anywhere in [R_P,min, R_P,max]: the largest reach over it */
            for (int j = 0; s->field && k < K - 1 && j <= 8; j++) {
                const double rp = s->RPmin_mm[ch] + j / 8.0 * (s->RPmax_mm[ch] - s->RPmin_mm[ch]);
                const double h2 = rp * rbar_at(s, tk[k + 1] * rp / s->mpu / zfar);
                if (h2 / s->mpu > reach[k]) reach[k] = h2 / s->mpu;
            }
        }

    uint32_t done = 0; /* lights splatted: the first overwrites the q image */
    for (uint32_t l = 0; l < nl; l++) {
        double L[3];
        if (!sss_light_unit(dirs[l], L)) continue; /* a zero or non-finite direction lights nothing */
        /* the light frame: u, v span the plane across the beam */
        double a[3] = {1, 0, 0}, u[3], v[3];
        if (fabs(L[0]) > 0.9) a[0] = 0, a[1] = 1;
        sss_cross3(a, L, u);
        sss_normalize3(u);
        sss_cross3(L, u, v);
        /* orthographic: x = u·(p − c)/R_l, y = v·(p − c)/R_l, z = −L·(p − c)/R_l (nearer the light = smaller) */
        float M[16] = {0};
        for (int k = 0; k < 3; k++) {
            M[k * 4 + 0] = (float)(u[k] / Rl);
            M[k * 4 + 1] = (float)(v[k] / Rl);
            M[k * 4 + 2] = (float)(-L[k] / Rl);
        }
        M[12] = (float)(-sss_dot3(u, c) / Rl);
        M[13] = (float)(-sss_dot3(v, c) / Rl);
        M[14] = (float)(sss_dot3(L, c) / Rl);
        M[15] = 1.0f;
        const double texel_mm = 2.0 * Rl / N0 * s->mpu;
        glUseProgram(s->prog_light);
        glUniformMatrix4fv(glGetUniformLocation(s->prog_light, "u_mvp"), 1, GL_FALSE, M);
        set3(s->prog_light, "u_light", L);
        set3(s->prog_light, "u_centre", c);
        glUniform1f(glGetUniformLocation(s->prog_light, "u_eta"), (float)s->eta);
        glUniform1f(glGetUniformLocation(s->prog_light, "u_texel_mm2"), (float)(texel_mm * texel_mm));
        glBindFramebuffer(GL_FRAMEBUFFER, s->lfbo);
        t_begin(s);
        raster(s->prog_light, s->lfbo, (int)N0, (int)N0, m, s->field ? s->vao : 0);
        t_end(s, T_BUF);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        barrier();

        t_begin(s);
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, s->ltex[0]);
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, s->ltex[1]);
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D, s->ltexf);
        glActiveTexture(GL_TEXTURE0);
        pass_use(s, P_LIGHT0, N0, N0, s->loff[0], 0, 0, 0);
        dispatch(N0, N0);
        for (uint32_t j = 0; j + 1 < J; j++) {
            pass_use(s, P_LIGHTMIP, N0 >> (j + 1), N0 >> (j + 1), s->loff[j + 1], s->loff[j], N0 >> j, N0 >> j);
            dispatch(N0 >> (j + 1), N0 >> (j + 1));
        }
        /* Eq. 10 on every level: z0 and R_w = 2 R (the bounding sphere's diameter) in world units */
        for (uint32_t j = 0; j < J; j++) {
            GLuint pr = pass_use(s, P_SELECT, N0 >> j, N0 >> j, s->loff[j], 0, 0, 0);
            glUniform1i(glGetUniformLocation(pr, "u_J"), (GLint)J);
            glUniform1uiv(glGetUniformLocation(pr, "u_loff"), LIGHT_LEVELS, s->loff);
            glUniform1ui(glGetUniformLocation(pr, "u_N0"), N0);
            glUniform1f(glGetUniformLocation(pr, "u_z0"), (float)(s->o.z0 * Rl));
            glUniform1f(glGetUniformLocation(pr, "u_alpha_Rw"), (float)(s->o.alpha * 2.0 * Rl));
            set3(pr, "u_RPw", RPsel);
            glUniform1ui(glGetUniformLocation(pr, "u_C"), C);
            glUniform1i(glGetUniformLocation(pr, "u_j"), (GLint)j);
            dispatch(N0 >> j, N0 >> j);
        }
        t_end(s, T_BUF);

        for (uint32_t k = 0; k < K; k++) {
            t_begin(s);
            GLuint pr = pass_use(s, P_GATHER, s->cdim[k][0], s->cdim[k][1], s->coff[k], 0, 0, 0);
            glUniform1i(glGetUniformLocation(pr, "u_J"), (GLint)J);
            glUniform1uiv(glGetUniformLocation(pr, "u_loff"), LIGHT_LEVELS, s->loff);
            glUniform1ui(glGetUniformLocation(pr, "u_N0"), N0);
            glUniform1i(glGetUniformLocation(pr, "u_k"), (GLint)k);
            glUniform1i(glGetUniformLocation(pr, "u_K"), (GLint)K);
            set3(pr, "u_c", c);
            set3(pr, "u_u", u);
            set3(pr, "u_v", v);
            glUniform1f(glGetUniformLocation(pr, "u_Rl"), (float)Rl);
            /* a texel's diagonal more: a sample's position is its texel's, not the square's corner */
            glUniform1f(glGetUniformLocation(pr, "u_window"), (float)(reach[k] + 2.0 * Rl / (N0 >> (J - 1)) * 1.5));
            set3(pr, "u_eye", eye);
            set3(pr, "u_fwd", fwd);
            glUniform1f(glGetUniformLocation(pr, "u_tk0"), (float)tk[k]);
            glUniform1f(glGetUniformLocation(pr, "u_tk1"), (float)tk[k + 1]);
            set3(pr, "u_RPw", RPw);
            set3(pr, "u_RPmm", RPmm);
            set3(pr, "u_Rcut", Rcut);
            glUniform1f(glGetUniformLocation(pr, "u_mpu"), (float)s->mpu);
            glUniform1ui(glGetUniformLocation(pr, "u_C"), C);
            glUniform1i(glGetUniformLocation(pr, "u_nrbar"), RB_N);
            glUniform1f(glGetUniformLocation(pr, "u_rb0"), (float)RB_LO);
            glUniform1f(glGetUniformLocation(pr, "u_rbs"), (float)RB_STEP);
            glUniform1i(glGetUniformLocation(pr, "u_nrd"), RD_N);
            field_uniforms(s, pr);
            /* the reach's width in coarse texels, walked in shares (splat.comp.glsl, CHUNK) */
            const double win = reach[k] + 2.0 * Rl / (N0 >> (J - 1)) * 1.5;
            const int nc = (int)ceil((2.0 * win / (2.0 * Rl / (N0 >> (J - 1))) + 2.0) / SPLAT_CHUNK);
            for (int cy = 0; cy < nc; cy++)
                for (int cx = 0; cx < nc; cx++) {
                    glUniform2i(glGetUniformLocation(pr, "u_chunk"), cx, cy);
                    glUniform1i(glGetUniformLocation(pr, "u_accum"), cx + cy > 0);
                    dispatch(s->cdim[k][0], s->cdim[k][1]);
                }
            t_end(s, T_L0 + (int)k);
        }

        t_begin(s);
        glBindImageTexture(0, s->qtex, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
        for (uint32_t k = K > 1 ? K - 1 : 1; k-- > 0;) {
            const uint32_t kc = k + 1 < K ? k + 1 : k;
            GLuint pr = pass_use(s, P_UP, s->cdim[k][0], s->cdim[k][1], s->coff[k], s->coff[kc], s->cdim[kc][0],
                                 s->cdim[kc][1]);
            glUniform1i(glGetUniformLocation(pr, "u_k"), (GLint)k);
            glUniform1i(glGetUniformLocation(pr, "u_K"), (GLint)K);
            glUniform1f(glGetUniformLocation(pr, "u_lambda_Rw"), (float)(LAMBDA_Z / (2.0 * Rl)));
            double wl[3] = {w[l][0], w[l][1], w[l][2]};
            set3(pr, "u_w", wl);
            glUniform1i(glGetUniformLocation(pr, "u_first"), done == 0);
            glUniform1ui(glGetUniformLocation(pr, "u_C"), C);
            glUniform1f(glGetUniformLocation(pr, "u_mpu"), (float)s->mpu);
            field_uniforms(s, pr);
            dispatch(s->cdim[k][0], s->cdim[k][1]);
        }
        t_end(s, T_ACC);
        done++;
    }
    if (done == 0) { /* no light: q is 0 everywhere */
        const float zero[4] = {0, 0, 0, 0};
        glClearTexImage(s->qtex, 0, GL_RGBA, GL_FLOAT, zero);
    }
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE2);
    glBindTexture(GL_TEXTURE_2D, 0);
    glActiveTexture(GL_TEXTURE0);
    for (GLuint b = 0; b < 8; b++) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
    glUseProgram(0);

    r->draw.qtex = s->qtex;
    res = sss_draw_read_image(r, p, width, height, rgb, hdr, err);
    r->draw.qtex = 0;
    return res;
}
