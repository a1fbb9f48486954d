/* gl_util.h: small OpenGL helpers shared by the renderer and the overlay. */
#ifndef SSS_GL_UTIL_H
#define SSS_GL_UTIL_H

#include <epoxy/gl.h>
#include "sss/result.h"

/* Compiles "#version 430 core\n" + prefix + src as a shader of `type`;
 * returns 0 and fills err on failure. */
GLuint sss_gl_compile(GLenum type, const char *prefix, const char *src, sss_error *err);

/* Links a (and b when non-zero) into a program and deletes the shaders;
 * returns 0 and fills err on failure. */
GLuint sss_gl_link(GLuint a, GLuint b, sss_error *err);

#endif
