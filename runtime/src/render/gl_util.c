/* gl_util.c: shader compilation and program linking shared by the renderer
 * and the overlay; failures become one-line errors (newlines of the driver
 * log folded to spaces). */
#include "gl_util.h"
#include "sss/render.h"

GLuint sss_gl_compile(GLenum type, const char *prefix, const char *src, sss_error *err)
{
    const char *parts[2] = {prefix, src};
    return sss_gl_compile_parts(type, parts, 2, err);
}

GLuint sss_gl_compile_parts(GLenum type, const char *const *parts, int n, sss_error *err)
{
    GLuint s = glCreateShader(type);
    const char *all[8] = {"#version 430 core\n"};
    if (n > 7) n = 7;
    for (int i = 0; i < n; i++) all[i + 1] = parts[i];
    glShaderSource(s, n + 1, all, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        for (char *c = log; *c; c++)
            if (*c == '\n') *c = ' ';
        sss_fail(err, SSS_ERR_UNSUPPORTED, "shader compilation failed: %s", log);
        glDeleteShader(s);
        return 0;
    }
    return s;
}

GLuint sss_gl_link(GLuint a, GLuint b, sss_error *err)
{
    GLuint p = glCreateProgram();
    glAttachShader(p, a);
    if (b) glAttachShader(p, b);
    glLinkProgram(p);
    glDeleteShader(a);
    if (b) glDeleteShader(b);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[1024] = "";
        glGetProgramInfoLog(p, sizeof log, NULL, log);
        for (char *c = log; *c; c++)
            if (*c == '\n') *c = ' ';
        sss_fail(err, SSS_ERR_UNSUPPORTED, "shader link failed: %s", log);
        glDeleteProgram(p);
        return 0;
    }
    return p;
}

unsigned sss_gl_program(const char *vs, const char *fs, sss_error *err)
{
    GLuint v = sss_gl_compile(GL_VERTEX_SHADER, "", vs, err);
    GLuint f = v ? sss_gl_compile(GL_FRAGMENT_SHADER, "", fs, err) : 0;
    if (!f) {
        if (v) glDeleteShader(v);
        return 0;
    }
    return sss_gl_link(v, f, err);
}

GLuint sss_gl_ssbo(GLsizeiptr n, const void *data, GLenum usage)
{
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, n >= 4 ? n : 4, n >= 4 ? data : NULL, usage);
    if (n > 0 && n < 4 && data) glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, n, data);
    return b;
}

GLsizeiptr sss_gl_row_stride(GLsizeiptr row_bytes)
{
    GLint align = 16;
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
    if (align < 4) align = 4;
    return (row_bytes + align - 1) / align * align;
}

GLuint sss_gl_rows(const void *src, size_t nrows, GLsizeiptr row_bytes, GLsizeiptr stride)
{
    GLuint b = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, stride * (GLsizeiptr)(nrows ? nrows : 1), NULL, GL_STATIC_DRAW);
    for (size_t j = 0; j < nrows && row_bytes > 0; j++)
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, stride * (GLsizeiptr)j, row_bytes,
                        (const char *)src + (size_t)row_bytes * j);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    return b;
}
