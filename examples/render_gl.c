/* render_gl.c: a .sss drawn with plain OpenGL 4.3, linking libsss only (no
 * viewer): the GPU layout (sss/gpu.h, docs/gpu_layout.md) uploaded as is,
 * its embedded GLSL compiled with the layout's #defines, q evaluated for a
 * light, read back and compared with sss_decode_all (exit 1 unless every
 * float is identical), then the mesh drawn with q as its radiance.
 *   render_gl FILE.sss OUT.ppm [LX LY LZ [EXPOSURE]]
 * Context: EGL surfaceless (Mesa llvmpipe needs no display or GPU). */
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/decode.h"
#include "sss/gpu.h"

#define W 512
#define H 512

static GLuint compile(GLenum type, const char *defines, const char *src)
{
    const char *parts[3] = {SSS_GPU_GLSL_VERSION, defines, src};
    GLuint s = glCreateShader(type);
    glShaderSource(s, 3, parts, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "render_gl: shader: %s\n", log);
        exit(1);
    }
    return s;
}

static GLuint link(GLuint a, GLuint b)
{
    GLuint p = glCreateProgram();
    glAttachShader(p, a);
    if (b) glAttachShader(p, b);
    glLinkProgram(p);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) fprintf(stderr, "render_gl: program link failed\n"), exit(1);
    return p;
}

/* The draw: positions scaled into the unit cube, seen along −z; q (binding 3) per vertex. */
static const char *vs = "layout(location = 0) in vec3 a_pos;\n"
                        "layout(std430, binding = 3) readonly buffer Q { float q[]; };\n"
                        "uniform vec4 u_fit; uniform uint u_channels; out vec3 v_q;\n"
                        "void main() { uint v = uint(gl_VertexID);\n"
                        "  v_q = u_channels == 3u ? vec3(q[3u * v], q[3u * v + 1u], q[3u * v + 2u]) : vec3(q[v]);\n"
                        "  vec3 p = (a_pos - u_fit.xyz) * u_fit.w; gl_Position = vec4(p.xy, -p.z, 1.0); }\n";
/* radiance ≈ q · exposure (unit irradiance), then sRGB-like 1/2.2 */
static const char *fs = "in vec3 v_q; uniform float u_exposure; out vec4 o;\n"
                        "void main() { o = vec4(pow(clamp(v_q * u_exposure, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0); }\n";

int main(int argc, char **argv)
{
    if (argc != 3 && argc != 6 && argc != 7)
        return fprintf(stderr, "usage: render_gl FILE.sss OUT.ppm [LX LY LZ [EXPOSURE]]\n"), 2;
    const double light[3] = {argc > 3 ? atof(argv[3]) : 0.3, argc > 3 ? atof(argv[4]) : 0.5,
                             argc > 3 ? atof(argv[5]) : 0.8};
    const float exposure = argc > 6 ? (float)atof(argv[6]) : 4.0f;
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) return fprintf(stderr, "render_gl: %s\n", err.msg), 1;

    /* Mesa's surfaceless platform, else the default display (NVIDIA's
     * driver gives its first GPU there, with no window system) */
    EGLDisplay dpy = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, NULL, NULL)) dpy = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLContext ctx = EGL_NO_CONTEXT;
    if (dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL) && eglBindAPI(EGL_OPENGL_API))
        ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attr);
    if (ctx == EGL_NO_CONTEXT || !eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
        return fprintf(stderr, "render_gl: no OpenGL 4.3 context through EGL\n"), 1;

    /* 1. the layout: static buffers once, packed to the GL's range alignment */
    GLint align = 4;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    sss_gpu_layout L;
    sss_gpu_frame fr;
    if (sss_gpu_layout_create(&f, (uint32_t)align, &L, &err) != SSS_OK || sss_gpu_frame_init(&L, &fr, &err) != SSS_OK)
        return fprintf(stderr, "render_gl: %s: %s\n", argv[1], err.msg), 1;
    if (!L.pass[SSS_GPU_PASS_ROWS].name && !L.pass[SSS_GPU_PASS_CODED].name)
        return fprintf(stderr, "render_gl: %s: no direction set (its q comes from sss/effects.h)\n", argv[1]), 1;
    GLuint buf[SSS_GPU_BUFFERS] = {0}, tab[SSS_GPU_PASSES] = {0}, prog[SSS_GPU_PASSES] = {0};
    for (int k = 0; k < SSS_GPU_BUFFERS; k++) {
        const sss_gpu_buffer *b = &L.buffer[k];
        if (!b->bytes && k != SSS_GPU_BUF_Q) continue;
        void *img = b->data ? malloc(b->bytes) : NULL;
        if (img) sss_gpu_buffer_pack(b, img);
        glGenBuffers(1, &buf[k]);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[k]);
        glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)(b->bytes ? b->bytes : 4), img, GL_STATIC_DRAW);
        free(img);
    }
    for (int p = 0; p < SSS_GPU_PASSES; p++)
        if (L.pass[p].name) prog[p] = link(compile(GL_COMPUTE_SHADER, L.pass[p].defines, L.pass[p].source), 0);

    /* 2. the frame: the light's constants, then the passes in order */
    sss_gpu_frame_eval(&L, light, &fr);
    const void *blk[SSS_GPU_PASSES] = {fr.levels, fr.sh};
    const uint64_t blk_bytes[SSS_GPU_PASSES] = {fr.levels_bytes, fr.sh_bytes};
    for (int p = 0; p < SSS_GPU_PASSES; p++) {
        if (!prog[p] || !fr.u_count[p]) continue;
        glUseProgram(prog[p]);
        for (int k = 0; k < SSS_GPU_BUFFERS; k++) {
            if (!(L.buffer[k].passes >> p & 1)) continue;
            if (k == SSS_GPU_BUF_ROWS) /* the light's three direction rows, as ranges */
                for (int t = 0; t < 3; t++)
                    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, (GLuint)t, buf[k], (GLintptr)fr.row_offset[t],
                                      (GLsizeiptr)L.row_range);
            else glBindBufferBase(GL_SHADER_STORAGE_BUFFER, L.buffer[k].binding, buf[k]);
        }
        if (blk[p]) { /* the folded tables at binding 4: the coded pass's as a uniform block if sh_uniform */
            const GLenum target = p == SSS_GPU_PASS_CODED && L.sh_uniform ? GL_UNIFORM_BUFFER : GL_SHADER_STORAGE_BUFFER;
            glGenBuffers(1, &tab[p]);
            glBindBuffer(target, tab[p]);
            glBufferData(target, (GLsizeiptr)blk_bytes[p], blk[p], GL_DYNAMIC_DRAW);
            glBindBufferBase(target, 4, tab[p]);
        }
        glUniform3f(glGetUniformLocation(prog[p], "u_w"), fr.u_w[0], fr.u_w[1], fr.u_w[2]);
        glUniform1ui(glGetUniformLocation(prog[p], "u_channels"), fr.u_channels);
        glUniform1ui(glGetUniformLocation(prog[p], "u_count"), fr.u_count[p]);
        glDispatchCompute(L.pass[p].groups, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    }

    /* 3. q read back against the C decoder, float for float */
    const size_t n = (size_t)f.mesh.nv * f.channels;
    float *gpu = malloc(n * sizeof *gpu + 4), *cpu = malloc(n * sizeof *cpu + 4);
    if (!gpu || !cpu) return fprintf(stderr, "render_gl: out of memory\n"), 1;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[SSS_GPU_BUF_Q]);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)(n * sizeof *gpu), gpu);
    sss_decode_all(&f, light, cpu);
    double max_abs = 0.0;
    for (size_t i = 0; i < n; i++) max_abs = fmax(max_abs, fabs((double)gpu[i] - cpu[i]));
    const int same = memcmp(gpu, cpu, n * sizeof *gpu) == 0;
    printf("render_gl: %s: %s%s%s, %u vertices x %u channels, max |GPU - sss_decode_all| = %g (%s)\n", argv[1],
           sss_quant_name(f.quant), L.sh_levels ? " SH " : "", L.sh_levels ? sss_shq_name(f.sh.kind) : "", f.mesh.nv,
           f.channels, max_abs, same ? "bit-identical" : "DIFFERENT");

    /* 4. the picture: the mesh with q as its radiance, into OUT.ppm */
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < 3 * (size_t)f.mesh.nv; i++)
        lo[i % 3] = fminf(lo[i % 3], f.mesh.pos[i]), hi[i % 3] = fmaxf(hi[i % 3], f.mesh.pos[i]);
    const float ext = fmaxf(fmaxf(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    GLuint vao, vbo[2], fbo, rb[2];
    GLuint draw = link(compile(GL_VERTEX_SHADER, "", vs), compile(GL_FRAGMENT_SHADER, "", fs));
    glGenVertexArrays(1, &vao);
    glBindVertexArray(vao);
    glGenBuffers(2, vbo);
    glBindBuffer(GL_ARRAY_BUFFER, vbo[0]);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)f.mesh.nv * 12, f.mesh.pos, GL_STATIC_DRAW);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glEnableVertexAttribArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, vbo[1]);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)f.mesh.nf * 12, f.mesh.tri, GL_STATIC_DRAW);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, W, H);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, W, H);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, rb[1]);
    glViewport(0, 0, W, H);
    glClearColor(0.1f, 0.1f, 0.12f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glUseProgram(draw);
    glUniform4f(glGetUniformLocation(draw, "u_fit"), (lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2,
                1.8f / ext);
    glUniform1ui(glGetUniformLocation(draw, "u_channels"), f.channels);
    glUniform1f(glGetUniformLocation(draw, "u_exposure"), exposure);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, buf[SSS_GPU_BUF_Q]);
    glDrawElements(GL_TRIANGLES, (GLsizei)(3 * f.mesh.nf), GL_UNSIGNED_INT, NULL);
    unsigned char *px = malloc((size_t)W * H * 4);
    glReadPixels(0, 0, W, H, GL_RGBA, GL_UNSIGNED_BYTE, px);
    FILE *out = fopen(argv[2], "wb");
    int ok = out && fprintf(out, "P6\n%d %d\n255\n", W, H) > 0;
    for (int y = H - 1; ok && y >= 0; y--) /* GL's rows go bottom up */
        for (int x = 0; ok && x < W; x++) ok = fwrite(px + 4 * ((size_t)y * W + x), 3, 1, out) == 1;
    if (out && fclose(out) != 0) ok = 0;
    if (!ok) fprintf(stderr, "render_gl: %s: cannot write the image\n", argv[2]), remove(argv[2]);

    free(px), free(gpu), free(cpu);
    sss_gpu_frame_free(&fr);
    sss_gpu_layout_free(&L);
    sss_file_free(&f);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, ctx);
    eglTerminate(dpy);
    return same && ok ? 0 : 1;
}
