/* springpend (internal): a headless GL context behind one small API, so that
 * render.c knows no window system. Backends: gl_context_osmesa.c (OSMesa,
 * llvmpipe). Another (EGL) implements the same five functions. */
#ifndef SPRINGPEND_GL_CONTEXT_H
#define SPRINGPEND_GL_CONTEXT_H

#include <stdint.h>

struct sp_gl_context;

/* A GL entry point as the backend returns it; cast to the PFNGL...PROC type. */
typedef void (*sp_gl_proc)(void);

/* Creates a GL >= 3.3 core context drawing into a width x height RGBA8 colour
 * buffer (no depth, no stencil, no MSAA) that the context owns, and makes it
 * current on the calling thread. GL's framebuffer row height-1 (NDC y = +1)
 * is the buffer's first row. Returns 0, SP_E_INPUT for a bad size, SP_E_NOMEM
 * or SP_E_GL (logged). */
int sp_gl_context_make(struct sp_gl_context **out, int width, int height);

/* Makes c current on the calling thread if it is not already. 0 or SP_E_GL. */
int sp_gl_context_bind(struct sp_gl_context *c);

/* The address of a GL function of c, or NULL if the backend lacks it. */
sp_gl_proc sp_gl_context_proc(struct sp_gl_context *c, const char *name);

/* Waits for every GL command issued on c (c must be current) and returns its
 * colour buffer: RGBA8, straight alpha, top row first, *stride bytes between
 * rows. Owned by c, valid until the next GL command on c or destroy. */
uint8_t *sp_gl_context_pixels(struct sp_gl_context *c, int *stride);

/* Frees the context and its buffer and sets *c to NULL. Safe on NULL. */
void sp_gl_context_destroy(struct sp_gl_context **c);

#endif
