/* springpend (internal): text. A font (DejaVu Sans, embedded at build time)
 * rasterized once by FreeType into a glyph atlas at a few pixel sizes; strings
 * are laid out into textured quads at whole pixels, so the same string always
 * gives the same pixels. The GL pass draws the quads in one instanced call. */
#ifndef SPRINGPEND_TEXT_H
#define SPRINGPEND_TEXT_H

#include <stdint.h>

#include "gl_api.h"

enum sp_text_size { SP_TEXT_SMALL, SP_TEXT_NORMAL, SP_TEXT_LARGE, SP_TEXT_SIZES };

/* One glyph on screen; layout matches the attributes of shaders/text.vert. */
struct sp_glyph_quad {
    float rect[4];  /* x0, y0, x1, y1: px, y down from the top-left corner */
    float uv[4];    /* the atlas rectangle, texels */
    float color[4]; /* straight RGBA, 0..1 */
};

struct sp_font;

/* Builds the atlas for the pixel sizes px[SP_TEXT_SIZES] (em height, px, each
 * 4..400). 0, SP_E_INPUT (bad size) or SP_E_NOMEM / SP_E_IO (FreeType's
 * message logged). */
int sp_font_make(struct sp_font **out, const int px[SP_TEXT_SIZES]);

/* Frees the font and sets *f to NULL. Safe on NULL. */
void sp_font_destroy(struct sp_font **f);

/* 1 when the embedded font has a glyph for code point cp (else a box is drawn). */
int sp_font_has(const struct sp_font *f, uint32_t cp);

/* Advance width of a UTF-8 string, px. */
int sp_font_width(const struct sp_font *f, int size, const char *utf8);

/* Height of a capital letter above the baseline, and the line spacing, px. */
int sp_font_cap(const struct sp_font *f, int size);
int sp_font_line(const struct sp_font *f, int size);

/* Lays out utf8 with its pen starting at (x, baseline) (rounded to whole px)
 * into out[0..max). Returns how many quads the string needs (which may exceed
 * max: then only max were written). */
int sp_font_layout(const struct sp_font *f, int size, const char *utf8, float x,
                   float baseline, const float color[4], struct sp_glyph_quad *out,
                   int max);

/* The R8 atlas: *w x *h bytes, row 0 first. Owned by f. */
const uint8_t *sp_font_atlas(const struct sp_font *f, int *w, int *h);

/* Draws quads into an 8-bit coverage image (w x h, stride w) on the CPU by
 * copying atlas texels, the way the GL pass samples them (nearest). For tests. */
void sp_font_blit(const struct sp_font *f, const struct sp_glyph_quad *q, int n,
                  uint8_t *img, int w, int h);

/* The GL pass: program, atlas texture and instance buffer. */
struct sp_text_pass;

/* Uploads f's atlas; the context of gl must be current. 0, SP_E_GL, SP_E_NOMEM. */
int sp_text_pass_make(struct sp_text_pass **out, const struct sp_gl_api *gl,
                      const struct sp_font *f, int width, int height);

/* Draws n quads with premultiplied "over" blending (set by the caller).
 * Leaves its program, VAO and buffer bound. 0 or SP_E_NOMEM. */
int sp_text_pass_draw(struct sp_text_pass *p, const struct sp_glyph_quad *q, int n);

/* Frees the pass's CPU memory and sets *p to NULL (its GL objects die with
 * the context). Safe on NULL. */
void sp_text_pass_destroy(struct sp_text_pass **p);

#endif
