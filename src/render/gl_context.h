/* springpend (internal): a headless GL context behind one small API, so that
 * render.c knows no window system. Backends, one file each, fill a struct
 * sp_gl_backend: gl_context_osmesa.c (OSMesa, llvmpipe) and
 * gl_context_egl.c (EGL on Mesa's surfaceless platform: llvmpipe, or a GPU
 * where one exists). gl_context.c picks one. Both draw into the same kind
 * of framebuffer object (gl_offscreen.h). Each backend dlopens its
 * library on first use, so a process that never renders does not load GL. */
#ifndef SPRINGPEND_GL_CONTEXT_H
#define SPRINGPEND_GL_CONTEXT_H

#include <stdint.h>

#include "springpend/render.h"
#include "gl_offscreen.h"

/* A GL entry point as the backend returns it; cast to the PFNGL...PROC type. */
typedef void (*sp_gl_proc)(void);

struct sp_gl_context;

/* What a backend implements; the contracts are those of the sp_gl_context_*
 * functions below. Every struct sp_gl_context a backend makes starts with
 * a struct sp_gl_context_head. */
struct sp_gl_backend {
    const char *name; /* "osmesa", "egl" */
    /* Loads the library; 0, or SP_E_GL (logged unless quiet). */
    int (*load)(int quiet);
    int (*make)(struct sp_gl_context **out, int width, int height);
    int (*bind)(struct sp_gl_context *c);
    sp_gl_proc (*proc)(struct sp_gl_context *c, const char *name);
    void (*destroy)(struct sp_gl_context *c);
};

/* The start of every backend's context: the backend, and the framebuffer
 * both backends draw into (gl_offscreen.h) with where its pixels are read
 * back to (sp_gl_context_pixels, sp_gl_context_target). */
struct sp_gl_context_head {
    const struct sp_gl_backend *backend;
    struct sp_gl_offscreen fb; /* made by the backend once its context is current */
    uint8_t *pixels;           /* width * height * 4 bytes, RGBA8, owned */
    uint8_t *target;           /* where readback goes: pixels or the caller's */
    int width, height;         /* px */
};

/* For backends: sets h up for backend b (pixels allocated, target =
 * pixels; fb still to be made). 0 or SP_E_NOMEM (logged). */
int sp_gl_context_head_init(struct sp_gl_context_head *h, const struct sp_gl_backend *b,
                            int width, int height);
/* For backends: frees what the head owns; current: whether the backend's
 * context is current (the framebuffer's GL objects are deleted then). */
void sp_gl_context_head_free(struct sp_gl_context_head *h, int current);

/* For backends: one library symbol and the function pointer it fills. */
struct sp_gl_symbol {
    const char *name;
    void **slot; /* address of the backend's function pointer */
};

/* dlopens lib and resolves every symbol; *handle is set only when all are
 * found. On failure (logged unless quiet: "cannot load WHAT: reason (HINT)"
 * or "LIB lacks NAME") the library is closed and SP_E_GL returned. */
int sp_gl_load_library(const char *lib, const char *what, const char *hint,
                       const struct sp_gl_symbol *syms, int n, int quiet,
                       void **handle);

extern const struct sp_gl_backend sp_gl_backend_osmesa;
extern const struct sp_gl_backend sp_gl_backend_egl;

/* Creates a GL >= 3.3 core context drawing into a width x height RGBA8 colour
 * buffer (no depth, no stencil, no MSAA) that the context owns, and makes it
 * current on the calling thread. GL's framebuffer row height-1 (NDC y = +1)
 * is the buffer's first row. `which` = SP_GL_DEFAULT tries OSMesa, then EGL.
 * Returns 0, SP_E_INPUT for a bad size, SP_E_NOMEM or SP_E_GL (logged). */
int sp_gl_context_make(struct sp_gl_context **out, int width, int height,
                       enum sp_gl which);

/* Makes c current on the calling thread if it is not already. 0 or SP_E_GL. */
int sp_gl_context_bind(struct sp_gl_context *c);

/* The address of a GL function of c, or NULL if the backend lacks it. */
sp_gl_proc sp_gl_context_proc(struct sp_gl_context *c, const char *name);

/* Waits for every GL command issued on c (c must be current) and returns its
 * colour buffer: RGBA8, straight alpha, top row first, *stride bytes between
 * rows. Owned by c, valid until the next GL command on c or destroy. */
uint8_t *sp_gl_context_pixels(struct sp_gl_context *c, int *stride);

/* Makes the next frames land in `pixels` (width * height * 4 bytes, stride
 * 4 * width, owned by the caller and alive while it is the target) instead
 * of c's own buffer; NULL goes back to c's own. sp_gl_context_pixels then
 * returns it. Saves a copy per frame where frames go into a queue. */
void sp_gl_context_target(struct sp_gl_context *c, uint8_t *pixels);

/* The framebuffer c draws into (its texture is what yuv_gl.h samples). */
struct sp_gl_offscreen *sp_gl_context_framebuffer(struct sp_gl_context *c);

/* The backend that made c ("osmesa", "egl"). */
const char *sp_gl_context_backend(const struct sp_gl_context *c);

/* Frees the context and its buffer and sets *c to NULL. Safe on NULL. */
void sp_gl_context_destroy(struct sp_gl_context **c);

#endif
