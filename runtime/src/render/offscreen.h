/* offscreen.h: a windowless OpenGL 4.5 core context through EGL on the
 * surfaceless platform (Mesa llvmpipe without a GPU, or a GPU driver's EGL
 * device), for scripts, tests and benchmarks. */
#ifndef SSS_OFFSCREEN_H
#define SSS_OFFSCREEN_H

#include "sss/result.h"

typedef struct sss_offscreen sss_offscreen;

/* Creates the context and makes it current on this thread. */
sss_result sss_offscreen_create(sss_offscreen **out, sss_error *err);
void sss_offscreen_destroy(sss_offscreen *o);

/* GL_RENDERER string of the current context (static storage). */
const char *sss_gl_renderer_name(void);

#endif
