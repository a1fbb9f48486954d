/* gl_util.h: small OpenGL helpers of the renderer (the overlay gets
 * sss_gl_program, sss/render.h). */
#ifndef SSS_GL_UTIL_H
#define SSS_GL_UTIL_H

#include <epoxy/gl.h>
#include "sss/result.h"

/* Compiles "#version 430 core\n" + prefix + src as a shader of `type`;
 * returns 0 and fills err on failure. */
GLuint sss_gl_compile(GLenum type, const char *prefix, const char *src, sss_error *err);

/* The same for "#version 430 core\n" + parts[0] + … + parts[n - 1] (n ≤ 7):
 * a program composed of shared pieces and its own text. */
GLuint sss_gl_compile_parts(GLenum type, const char *const *parts, int n, sss_error *err);

/* Links a (and b when non-zero) into a program and deletes the shaders;
 * returns 0 and fills err on failure. */
GLuint sss_gl_link(GLuint a, GLuint b, sss_error *err);

/* A shader storage buffer of n bytes holding data (NULL: undefined),
 * left bound to GL_SHADER_STORAGE_BUFFER. At least 4 bytes, so that
 * binding it is valid even when it is empty. */
GLuint sss_gl_ssbo(GLsizeiptr n, const void *data, GLenum usage);

/* row_bytes rounded up to GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT (at
 * least 4), so that each row of a table can be bound with glBindBufferRange. */
GLsizeiptr sss_gl_row_stride(GLsizeiptr row_bytes);

/* A static storage buffer of nrows rows of row_bytes from src, row j at
 * j·stride (stride from sss_gl_row_stride); leaves nothing bound. */
GLuint sss_gl_rows(const void *src, size_t nrows, GLsizeiptr row_bytes, GLsizeiptr stride);

#endif
