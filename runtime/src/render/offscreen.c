/* offscreen.c: EGL surfaceless OpenGL context (sss_offscreen_*, sss/render.h). epoxy's
 * EGL header must come before anything else EGL: the Khronos headers clash. */
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <stdlib.h>
#include <string.h>

#include "sss/render.h"

struct sss_offscreen {
    EGLDisplay dpy;
    EGLContext ctx;
};

/* The first display that initialises: the surfaceless platform (no X, no
 * GPU needed), then each EGL device (NVIDIA's driver offers no surfaceless
 * display, or one that may not initialise), then the default display. */
static EGLDisplay open_display(void)
{
    const char *ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    EGLDisplay cand[6];
    int n = 0;
    if (ext && strstr(ext, "EGL_MESA_platform_surfaceless"))
        cand[n++] = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (ext && strstr(ext, "EGL_EXT_platform_device")) {
        EGLDeviceEXT dev[4];
        EGLint nd = 0;
        if (eglQueryDevicesEXT(4, dev, &nd))
            for (EGLint i = 0; i < nd && i < 4; i++) cand[n++] = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev[i], NULL);
    }
    cand[n++] = eglGetDisplay(EGL_DEFAULT_DISPLAY);
    for (int i = 0; i < n; i++) {
        EGLint major, minor;
        if (cand[i] != EGL_NO_DISPLAY && eglInitialize(cand[i], &major, &minor)) return cand[i];
    }
    return EGL_NO_DISPLAY;
}

sss_result sss_offscreen_create(sss_offscreen **out, sss_error *err)
{
    *out = NULL;
    sss_offscreen *o = calloc(1, sizeof *o);
    if (!o) return sss_fail(err, SSS_ERR_NOMEM, "offscreen: out of memory");
    o->dpy = open_display();
    if (o->dpy == EGL_NO_DISPLAY) {
        free(o);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "offscreen: no EGL display (install libegl-mesa0 and libgl1-mesa-dri)");
    }
    if (!eglBindAPI(EGL_OPENGL_API)) {
        eglTerminate(o->dpy);
        free(o);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "offscreen: EGL cannot bind desktop OpenGL");
    }
    static const EGLint cfg_attr[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    EGLConfig cfg = NULL;
    EGLint ncfg = 0;
    eglChooseConfig(o->dpy, cfg_attr, &cfg, 1, &ncfg); /* surfaceless contexts may not need one */
    static const EGLint ctx_attr[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                      EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    o->ctx = eglCreateContext(o->dpy, ncfg > 0 ? cfg : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attr);
    if (o->ctx == EGL_NO_CONTEXT || !eglMakeCurrent(o->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, o->ctx)) {
        if (o->ctx != EGL_NO_CONTEXT) eglDestroyContext(o->dpy, o->ctx);
        eglTerminate(o->dpy);
        free(o);
        return sss_fail(err, SSS_ERR_UNSUPPORTED, "offscreen: cannot create an OpenGL 4.5 core context through EGL");
    }
    *out = o;
    return SSS_OK;
}

void sss_offscreen_destroy(sss_offscreen *o)
{
    if (!o) return;
    eglMakeCurrent(o->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(o->dpy, o->ctx);
    eglTerminate(o->dpy);
    free(o);
}

const char *sss_gl_renderer_name(void)
{
    const char *s = (const char *)glGetString(GL_RENDERER);
    return s ? s : "unknown";
}
