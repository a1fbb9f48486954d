/* gl_util.c: shader compilation and program linking shared by the renderer
 * and the overlay; failures become one-line errors (newlines of the driver
 * log folded to spaces). */
#include "gl_util.h"

GLuint sss_gl_compile(GLenum type, const char *prefix, const char *src, sss_error *err)
{
    GLuint s = glCreateShader(type);
    const char *parts[3] = {"#version 430 core\n", prefix, src};
    glShaderSource(s, 3, parts, NULL);
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

