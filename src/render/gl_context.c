/* springpend: picks the GL context backend and forwards to it. */
#include <dlfcn.h>
#include <stddef.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "gl_context.h"

/* Every backend's context starts with this. */
struct sp_gl_context {
    struct sp_gl_context_head head;
};

int sp_gl_context_make(struct sp_gl_context **out, int width, int height,
                       enum sp_gl which)
{
    *out = NULL;
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384) {
        sp_log_error("image size %dx%d: each side must be 1..16384 px",
                     width, height);
        return SP_E_INPUT;
    }
    const struct sp_gl_backend *b = which == SP_GL_EGL ? &sp_gl_backend_egl
                                                       : &sp_gl_backend_osmesa;
    /* The default falls back to EGL quietly where OSMesa is not installed
     * (Mesa >= 25.1 dropped it). */
    if (which == SP_GL_DEFAULT && b->load(1) != 0)
        b = &sp_gl_backend_egl;
    int err = b->load(0);
    return err ? err : b->make(out, width, height);
}

int sp_gl_context_bind(struct sp_gl_context *c)
{
    return c->head.backend->bind(c);
}

sp_gl_proc sp_gl_context_proc(struct sp_gl_context *c, const char *name)
{
    return c->head.backend->proc(c, name);
}

uint8_t *sp_gl_context_pixels(struct sp_gl_context *c, int *stride)
{
    sp_gl_offscreen_read(&c->head.fb, c->head.target);
    *stride = 4 * c->head.width;
    return c->head.target;
}

void sp_gl_context_target(struct sp_gl_context *c, uint8_t *pixels)
{
    c->head.target = pixels ? pixels : c->head.pixels;
}

int sp_gl_context_head_init(struct sp_gl_context_head *h, const struct sp_gl_backend *b,
                            int width, int height)
{
    *h = (struct sp_gl_context_head){.backend = b, .width = width, .height = height};
    if (!(h->pixels = malloc((size_t)width * (size_t)height * 4))) {
        sp_log_error("out of memory for a %dx%d GL colour buffer", width, height);
        return SP_E_NOMEM;
    }
    h->target = h->pixels;
    return 0;
}

void sp_gl_context_head_free(struct sp_gl_context_head *h, int current)
{
    sp_gl_offscreen_destroy(&h->fb, current);
    free(h->pixels);
    h->pixels = h->target = NULL;
}

struct sp_gl_offscreen *sp_gl_context_framebuffer(struct sp_gl_context *c)
{
    return &c->head.fb;
}

const char *sp_gl_context_backend(const struct sp_gl_context *c)
{
    return c->head.backend->name;
}

void sp_gl_context_destroy(struct sp_gl_context **c)
{
    if (!*c)
        return;
    (*c)->head.backend->destroy(*c);
    *c = NULL;
}

int sp_gl_load_library(const char *lib, const char *what, const char *hint,
                       const struct sp_gl_symbol *syms, int n, int quiet,
                       void **handle)
{
    void *h = dlopen(lib, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        if (!quiet)
            sp_log_error("cannot load %s: %s (%s)", what, dlerror(), hint);
        return SP_E_GL;
    }
    for (int i = 0; i < n; i++)
        if (!(*syms[i].slot = dlsym(h, syms[i].name))) {
            if (!quiet)
                sp_log_error("%s lacks %s", lib, syms[i].name);
            dlclose(h);
            return SP_E_GL;
        }
    *handle = h;
    return 0;
}
