/* springpend: the EGL GL context backend. No window and no surface: a
 * hardware EGL device where one exists (EGL_EXT_platform_device, e.g. an
 * NVIDIA GPU), else Mesa's surfaceless platform (EGL_MESA_platform_surfaceless:
 * a GPU render node, or llvmpipe). GL draws into a framebuffer object whose
 * pixels are read back into our buffer (gl_offscreen.h). libEGL is dlopened
 * on first use. */
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include "springpend/common.h"
#include "gl_context.h"

#define EGL_LIBRARY "libEGL.so.1"
/* EGL entry points loaded by dlsym. */
#define EGL_FUNCS(X)                                                         \
    X(PFNEGLGETPROCADDRESSPROC, GetProcAddress)                              \
    X(PFNEGLQUERYSTRINGPROC, QueryString)                                    \
    X(PFNEGLINITIALIZEPROC, Initialize)                                      \
    X(PFNEGLTERMINATEPROC, Terminate)                                        \
    X(PFNEGLBINDAPIPROC, BindAPI)                                            \
    X(PFNEGLCHOOSECONFIGPROC, ChooseConfig)                                  \
    X(PFNEGLCREATECONTEXTPROC, CreateContext)                                \
    X(PFNEGLDESTROYCONTEXTPROC, DestroyContext)                              \
    X(PFNEGLMAKECURRENTPROC, MakeCurrent)                                    \
    X(PFNEGLGETCURRENTCONTEXTPROC, GetCurrentContext)                        \
    X(PFNEGLGETERRORPROC, GetError)

static struct {
#define X(type, name) type name;
    EGL_FUNCS(X)
#undef X
    void *lib; /* dlopen handle, kept for the process's life */
} egl;

struct sp_gl_context {
    struct sp_gl_context_head head; /* first, see gl_context.h */
    EGLDisplay dpy;
    EGLContext ctx;
};

static int egl_load(int quiet)
{
    static const struct sp_gl_symbol syms[] = {
#define X(type, name) {"egl" #name, (void **)&egl.name},
        EGL_FUNCS(X)
#undef X
    };
    if (egl.lib)
        return 0;
    return sp_gl_load_library(EGL_LIBRARY, "EGL", "install libegl1 and libegl-mesa0",
                              syms, (int)(sizeof(syms) / sizeof(syms[0])), quiet, &egl.lib);
}

static int has_word(const char *list, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = list; p && (p = strstr(p, word)) != NULL; p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return 1;
    return 0;
}

/* A display on a hardware EGL device if there is one, else on Mesa's
 * surfaceless platform; EGL_NO_DISPLAY if neither is offered. */
static EGLDisplay open_display(void)
{
    const char *client = egl.QueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display = (PFNEGLGETPLATFORMDISPLAYEXTPROC)
        egl.GetProcAddress("eglGetPlatformDisplayEXT");
    if (!get_display)
        return EGL_NO_DISPLAY;
    PFNEGLQUERYDEVICESEXTPROC query_devices = (PFNEGLQUERYDEVICESEXTPROC)
        egl.GetProcAddress("eglQueryDevicesEXT");
    PFNEGLQUERYDEVICESTRINGEXTPROC device_string = (PFNEGLQUERYDEVICESTRINGEXTPROC)
        egl.GetProcAddress("eglQueryDeviceStringEXT");
    if (has_word(client, "EGL_EXT_platform_device") && query_devices &&
        device_string) {
        EGLDeviceEXT devices[16];
        EGLint n = 0;
        if (query_devices(16, devices, &n))
            for (EGLint i = 0; i < n; i++) {
                const char *ext = device_string(devices[i], EGL_EXTENSIONS);
                if (has_word(ext, "EGL_MESA_device_software"))
                    continue; /* llvmpipe: surfaceless gives the same */
                EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
                if (d != EGL_NO_DISPLAY)
                    return d;
            }
    }
    if (has_word(client, "EGL_MESA_platform_surfaceless"))
        return get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    return EGL_NO_DISPLAY;
}

static void egl_destroy(struct sp_gl_context *c)
{
    const int current = c->ctx != EGL_NO_CONTEXT && egl.GetCurrentContext() == c->ctx;
    sp_gl_context_head_free(&c->head, current);
    if (current)
        egl.MakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (c->ctx != EGL_NO_CONTEXT)
        egl.DestroyContext(c->dpy, c->ctx);
    /* eglTerminate is left out: the display is shared by every context of
     * the process and terminating it would pull it from under the others. */
    free(c);
}

static void *egl_getproc(const char *name)
{
    return (void *)egl.GetProcAddress(name);
}

static int egl_make(struct sp_gl_context **out, int width, int height)
{
    static const EGLint config_attribs[] = {
        EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
        EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,
        EGL_NONE,
    };
    static const EGLint context_attribs[] = {
        EGL_CONTEXT_MAJOR_VERSION, 3,
        EGL_CONTEXT_MINOR_VERSION, 3,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_NONE,
    };
    struct sp_gl_context *c = calloc(1, sizeof(*c));
    EGLConfig config = NULL;
    EGLint n_configs = 0;
    int err = SP_E_GL;

    if (!c) {
        sp_log_error("out of memory for a GL context");
        return SP_E_NOMEM;
    }
    c->ctx = EGL_NO_CONTEXT;
    if ((err = sp_gl_context_head_init(&c->head, &sp_gl_backend_egl, width, height)) != 0)
        goto fail;
    err = SP_E_GL;
    c->dpy = open_display();
    if (c->dpy == EGL_NO_DISPLAY || !egl.Initialize(c->dpy, NULL, NULL)) {
        sp_log_error("EGL: no surfaceless display (needs Mesa's "
                     "EGL_MESA_platform_surfaceless or an EGL device); "
                     "error 0x%x", egl.GetError());
        goto fail;
    }
    if (!egl.BindAPI(EGL_OPENGL_API)) {
        sp_log_error("EGL: this display has no desktop OpenGL");
        goto fail;
    }
    /* Without a surface the config only picks the context's kind. */
    if (!egl.ChooseConfig(c->dpy, config_attribs, &config, 1, &n_configs) ||
        n_configs < 1)
        config = NULL; /* EGL_KHR_no_config_context */
    c->ctx = egl.CreateContext(c->dpy, config, EGL_NO_CONTEXT, context_attribs);
    if (c->ctx == EGL_NO_CONTEXT) {
        sp_log_error("EGL could not create a GL 3.3 core context (0x%x)",
                     egl.GetError());
        goto fail;
    }
    if (!egl.MakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx)) {
        sp_log_error("EGL could not make a context current without a "
                     "surface (0x%x)", egl.GetError());
        goto fail;
    }
    err = sp_gl_offscreen_make(&c->head.fb, egl_getproc, "EGL", width, height);
    if (err)
        goto fail;
    *out = c;
    return 0;

fail:
    egl_destroy(c);
    return err;
}

static int egl_bind(struct sp_gl_context *c)
{
    if (egl.GetCurrentContext() == c->ctx)
        return 0;
    if (!egl.MakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx)) {
        sp_log_error("EGL could not make the context current (0x%x)",
                     egl.GetError());
        return SP_E_GL;
    }
    sp_gl_offscreen_bind(&c->head.fb);
    return 0;
}

static sp_gl_proc egl_proc(struct sp_gl_context *c, const char *name)
{
    (void)c;
    return (sp_gl_proc)egl.GetProcAddress(name);
}

const struct sp_gl_backend sp_gl_backend_egl = {
    .name = "egl",
    .load = egl_load,
    .make = egl_make,
    .bind = egl_bind,
    .proc = egl_proc,
    .destroy = egl_destroy,
};
