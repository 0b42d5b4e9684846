/* springpend: the OSMesa GL context backend (Mesa's llvmpipe, no display).
 * GL draws into a framebuffer object read back into our buffer
 * (gl_offscreen.h), as with EGL: OSMesa's own buffer (1x1, never drawn)
 * is rendered with another orientation than framebuffer objects, which
 * rounds some pixels differently from the static cache's textures.
 * libOSMesa (which pulls in LLVM) is dlopened on first use, so processes
 * that never render start fast. */
#include <stdlib.h>

#include <GL/osmesa.h>

#include "springpend/common.h"
#include "gl_context.h"

#define OSMESA_LIBRARY "libOSMesa.so.8"

/* The OSMesa entry points we call, loaded by osmesa_load. */
#define OSMESA_FUNCS(X)                                                     \
    X(OSMesaContext, CreateContextAttribs, (const int *, OSMesaContext))    \
    X(GLboolean, MakeCurrent, (OSMesaContext, void *, GLenum, GLsizei, GLsizei)) \
    X(OSMesaContext, GetCurrentContext, (void))                             \
    X(OSMESAproc, GetProcAddress, (const char *))                           \
    X(void, DestroyContext, (OSMesaContext))

static struct {
#define X(ret, name, args) ret (*name) args;
    OSMESA_FUNCS(X)
#undef X
    void *lib; /* dlopen handle, kept for the process's life */
} os;

struct sp_gl_context {
    struct sp_gl_context_head head; /* first, see gl_context.h */
    OSMesaContext ctx;
    uint8_t window[4]; /* OSMesa's own buffer: 1x1, only to be current */
};

static int osmesa_load(int quiet)
{
    static const struct sp_gl_symbol syms[] = {
#define X(ret, name, args) {"OSMesa" #name, (void **)&os.name},
        OSMESA_FUNCS(X)
#undef X
    };
    if (os.lib)
        return 0;
    return sp_gl_load_library(OSMESA_LIBRARY, "OSMesa", "install libosmesa6, or use --gl egl",
                              syms, (int)(sizeof(syms) / sizeof(syms[0])), quiet, &os.lib);
}

static void *osmesa_getproc(const char *name)
{
    return (void *)os.GetProcAddress(name);
}

static void osmesa_destroy(struct sp_gl_context *c)
{
    const int current = c->ctx && os.GetCurrentContext() == c->ctx;
    sp_gl_context_head_free(&c->head, current);
    if (current)
        os.MakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    if (c->ctx)
        os.DestroyContext(c->ctx);
    free(c);
}

static int osmesa_make(struct sp_gl_context **out, int width, int height)
{
    static const int attribs[] = {
        OSMESA_FORMAT, OSMESA_RGBA,
        OSMESA_DEPTH_BITS, 0,
        OSMESA_STENCIL_BITS, 0,
        OSMESA_ACCUM_BITS, 0,
        OSMESA_PROFILE, OSMESA_CORE_PROFILE,
        OSMESA_CONTEXT_MAJOR_VERSION, 3,
        OSMESA_CONTEXT_MINOR_VERSION, 3,
        0,
    };
    struct sp_gl_context *c = calloc(1, sizeof(*c));
    int err = SP_E_NOMEM;

    if (!c) {
        sp_log_error("out of memory for a GL context");
        return err;
    }
    if ((err = sp_gl_context_head_init(&c->head, &sp_gl_backend_osmesa, width, height)) != 0)
        goto fail;
    c->ctx = os.CreateContextAttribs(attribs, NULL);
    if (!c->ctx) {
        sp_log_error("OSMesa could not create a GL 3.3 core context");
        err = SP_E_GL;
        goto fail;
    }
    if (!os.MakeCurrent(c->ctx, c->window, GL_UNSIGNED_BYTE, 1, 1)) {
        sp_log_error("OSMesa could not make its context current");
        err = SP_E_GL;
        goto fail;
    }
    err = sp_gl_offscreen_make(&c->head.fb, osmesa_getproc, "OSMesa", width, height);
    if (err)
        goto fail;
    *out = c;
    return 0;

fail:
    osmesa_destroy(c);
    return err;
}

static int osmesa_bind(struct sp_gl_context *c)
{
    if (os.GetCurrentContext() == c->ctx)
        return 0;
    if (!os.MakeCurrent(c->ctx, c->window, GL_UNSIGNED_BYTE, 1, 1)) {
        sp_log_error("OSMesa could not make the context current");
        return SP_E_GL;
    }
    sp_gl_offscreen_bind(&c->head.fb);
    return 0;
}

static sp_gl_proc osmesa_proc(struct sp_gl_context *c, const char *name)
{
    (void)c;
    return (sp_gl_proc)os.GetProcAddress(name);
}

const struct sp_gl_backend sp_gl_backend_osmesa = {
    .name = "osmesa",
    .load = osmesa_load,
    .make = osmesa_make,
    .bind = osmesa_bind,
    .proc = osmesa_proc,
    .destroy = osmesa_destroy,
};
