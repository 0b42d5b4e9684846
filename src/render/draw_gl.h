/* springpend (internal): the GL backend of the draw list (canvas.h). Every
 * capsule is an instance of one program (shaders/shape.*), glyphs quads of a
 * second (shaders/text.*) sampling the font's atlas; a frame is a few
 * instanced draws: one per run of shapes with the same blending (usually the
 * trail, then everything else), then all text. What to draw of each frame
 * over the cached layers is draw_cache.c's plan; this file only executes
 * it. */
#ifndef SPRINGPEND_DRAW_GL_H
#define SPRINGPEND_DRAW_GL_H

#include "frame/canvas.h"
#include "draw_cache.h"
#include "gl_api.h"

struct sp_draw_gl;

/* Builds the programs and buffers for a width x height px target, and
 * uploads font's atlas (font may be NULL: no text). The context of gl must be
 * current. 0, SP_E_GL or SP_E_NOMEM (logged). */
int sp_draw_gl_make(struct sp_draw_gl **out, const struct sp_gl_api *gl,
                    const struct sp_font *font, int width, int height);

/* Clears to bg (straight RGBA) and draws c; the result is premultiplied.
 * 0 or SP_E_GL (logged); SP_E_INPUT (said, nothing drawn) for a list with
 * images or turned text, which only the cairo backend draws. */
int sp_draw_gl_list(struct sp_draw_gl *d, const struct sp_canvas *c, const float bg[4]);

/* Turns the static cache on (the default) or off. With it on, the static
 * layer of a frame is drawn once into a texture (over the accumulated
 * layer) and copied under the dynamic layer of each frame whose static
 * layer is the same, byte for byte; the settled layer is kept in that
 * texture too, each frame drawing only what it appends; the pixels are those of the list drawn
 * in order (frames where that cannot be shown from the items' bounds are
 * drawn uncached). Off: every frame draws every item. */
void sp_draw_gl_cache(struct sp_draw_gl *d, int on);

/* What the cache did so far (draw_cache.h). */
void sp_draw_gl_stats(const struct sp_draw_gl *d, struct sp_draw_cache_stats *out);

/* Frees the CPU side and sets *d to NULL (GL objects die with the context).
 * Safe on NULL. */
void sp_draw_gl_destroy(struct sp_draw_gl **d);

#endif
