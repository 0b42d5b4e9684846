/* springpend: the OSMesa GL context backend (Mesa's llvmpipe, no display).
 * GL draws straight into a buffer we own; glFinish makes it readable, so no
 * FBO and no glReadPixels. libOSMesa (which pulls in LLVM) is dlopened on
 * first use, so processes that never render start fast. */
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
    X(void, PixelStore, (GLint, GLint))                                     \
    X(OSMESAproc, GetProcAddress, (const char *))                           \
    X(void, DestroyContext, (OSMesaContext))

static struct {
#define X(ret, name, args) ret (*name) args;
    OSMESA_FUNCS(X)
#undef X
    void (*Finish)(void);
    void *lib; /* dlopen handle, kept for the process's life */
} os;

struct sp_gl_context {
    const struct sp_gl_backend *backend; /* first, see gl_context.c */
    OSMesaContext ctx;
    uint8_t *pixels; /* width * height * 4 bytes, RGBA8, owned */
    uint8_t *target; /* where GL draws: pixels or the caller's buffer */
    int width, height; /* px */
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
    int err = sp_gl_load_library(OSMESA_LIBRARY, "OSMesa", "install libosmesa6, or use --gl egl",
                                 syms, (int)(sizeof(syms) / sizeof(syms[0])), quiet, &os.lib);
    if (!err)
        os.Finish = (void (*)(void))os.GetProcAddress("glFinish");
    return err;
}

static void osmesa_destroy(struct sp_gl_context *c)
{
    if (c->ctx) {
        if (os.GetCurrentContext() == c->ctx)
            os.MakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        os.DestroyContext(c->ctx);
    }
    free(c->pixels);
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
    int err = 0;

    if (c) {
        c->backend = &sp_gl_backend_osmesa;
        c->pixels = malloc((size_t)width * height * 4);
    }
    if (!c || !c->pixels) {
        sp_log_error("out of memory for a %dx%d GL colour buffer", width, height);
        err = SP_E_NOMEM;
        goto fail;
    }
    c->width = width;
    c->height = height;
    c->target = c->pixels;
    c->ctx = os.CreateContextAttribs(attribs, NULL);
    if (!c->ctx) {
        sp_log_error("OSMesa could not create a GL 3.3 core context");
        err = SP_E_GL;
        goto fail;
    }
    if (!os.MakeCurrent(c->ctx, c->pixels, GL_UNSIGNED_BYTE, width, height)) {
        sp_log_error("OSMesa could not bind a %dx%d RGBA buffer", width, height);
        err = SP_E_GL;
        goto fail;
    }
    os.PixelStore(OSMESA_Y_UP, 0); /* first row of pixels = top */
    *out = c;
    return 0;

fail:
    if (c)
        osmesa_destroy(c);
    return err;
}

static int osmesa_bind(struct sp_gl_context *c)
{
    if (os.GetCurrentContext() == c->ctx)
        return 0;
    if (!os.MakeCurrent(c->ctx, c->target, GL_UNSIGNED_BYTE, c->width,
                        c->height)) {
        sp_log_error("OSMesa could not make the context current");
        return SP_E_GL;
    }
    os.PixelStore(OSMESA_Y_UP, 0);
    return 0;
}

static sp_gl_proc osmesa_proc(struct sp_gl_context *c, const char *name)
{
    (void)c;
    return (sp_gl_proc)os.GetProcAddress(name);
}

static uint8_t *osmesa_pixels(struct sp_gl_context *c, int *stride)
{
    os.Finish();
    *stride = 4 * c->width;
    return c->target;
}

/* OSMesa draws straight into whatever buffer is bound: rebinding is the
 * whole switch (the context must be current, as it is while rendering). */
static void osmesa_target(struct sp_gl_context *c, uint8_t *pixels)
{
    uint8_t *want = pixels ? pixels : c->pixels;
    if (want == c->target)
        return;
    c->target = want;
    os.MakeCurrent(c->ctx, c->target, GL_UNSIGNED_BYTE, c->width, c->height);
    os.PixelStore(OSMESA_Y_UP, 0);
}

const struct sp_gl_backend sp_gl_backend_osmesa = {
    .name = "osmesa",
    .load = osmesa_load,
    .make = osmesa_make,
    .bind = osmesa_bind,
    .proc = osmesa_proc,
    .pixels = osmesa_pixels,
    .target = osmesa_target,
    .destroy = osmesa_destroy,
};
