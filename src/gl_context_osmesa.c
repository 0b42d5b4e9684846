/* springpend: the OSMesa GL context backend (Mesa's llvmpipe, no display).
 * GL draws straight into a buffer we own; glFinish makes it readable, so no
 * FBO and no glReadPixels. */
#include <stdlib.h>

#include <GL/osmesa.h>

#include "springpend/common.h"
#include "gl_context.h"

struct sp_gl_context {
    OSMesaContext ctx;
    uint8_t *pixels; /* width * height * 4 bytes, RGBA8, owned */
    int width, height; /* px */
};

int sp_gl_context_make(struct sp_gl_context **out, int width, int height)
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
    struct sp_gl_context *c = NULL;
    int err = 0;

    *out = NULL;
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        sp_log_error("image size %dx%d: each side must be 1..16384 px",
                     width, height);
        return SP_E_INPUT;
    }
    c = calloc(1, sizeof(*c));
    if (c)
        c->pixels = malloc((size_t)width * height * 4);
    if (!c || !c->pixels) {
        sp_log_error("out of memory for a %dx%d GL colour buffer", width, height);
        err = SP_E_NOMEM;
        goto fail;
    }
    c->width = width;
    c->height = height;
    c->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!c->ctx) {
        sp_log_error("OSMesa could not create a GL 3.3 core context");
        err = SP_E_GL;
        goto fail;
    }
    if (!OSMesaMakeCurrent(c->ctx, c->pixels, GL_UNSIGNED_BYTE, width, height)) {
        sp_log_error("OSMesa could not bind a %dx%d RGBA buffer", width, height);
        err = SP_E_GL;
        goto fail;
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0); /* first row of pixels = top */
    *out = c;
    return 0;

fail:
    sp_gl_context_destroy(&c);
    return err;
}

int sp_gl_context_bind(struct sp_gl_context *c)
{
    if (OSMesaGetCurrentContext() == c->ctx)
        return 0;
    if (!OSMesaMakeCurrent(c->ctx, c->pixels, GL_UNSIGNED_BYTE, c->width,
                           c->height)) {
        sp_log_error("OSMesa could not make the context current");
        return SP_E_GL;
    }
    OSMesaPixelStore(OSMESA_Y_UP, 0);
    return 0;
}

sp_gl_proc sp_gl_context_proc(struct sp_gl_context *c, const char *name)
{
    (void)c;
    return (sp_gl_proc)OSMesaGetProcAddress(name);
}

uint8_t *sp_gl_context_pixels(struct sp_gl_context *c, int *stride)
{
    glFinish();
    *stride = 4 * c->width;
    return c->pixels;
}

void sp_gl_context_destroy(struct sp_gl_context **cp)
{
    struct sp_gl_context *c = *cp;

    if (!c)
        return;
    if (c->ctx) {
        if (OSMesaGetCurrentContext() == c->ctx)
            OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(c->ctx);
    }
    free(c->pixels);
    free(c);
    *cp = NULL;
}
