/* gl_fixture.h: the cmocka group setup of the renderer tests — one EGL
 * offscreen context for the whole group (Mesa llvmpipe in CI). Setup fails
 * the group, rather than skipping it, when no GL 4.3 context exists: these
 * tests are the viewer's, and CI has GL. Include once per test program. */
#ifndef SSS_TEST_GL_FIXTURE_H
#define SSS_TEST_GL_FIXTURE_H

#include <stdio.h>
#include "sss/render.h"

static sss_offscreen *gl_ctx;

static int gl_setup(void **state)
{
    (void)state;
    sss_error err = {{0}};
    if (sss_offscreen_create(&gl_ctx, &err) != SSS_OK) {
        fprintf(stderr, "no offscreen GL context: %s\n", err.msg);
        return -1;
    }
    return 0;
}

static int gl_teardown(void **state)
{
    (void)state;
    sss_offscreen_destroy(gl_ctx);
    return 0;
}

#endif
