/* springpend (internal): text. A font (DejaVu Sans, embedded at build time)
 * rasterized once by FreeType into a glyph atlas at a few pixel sizes; strings
 * are laid out into textured quads at whole pixels, so the same string always
 * gives the same pixels. Pure CPU work shared by the backends: GL draws the
 * quads from the atlas (draw_gl.c), cairo the glyphs' outlines at the same
 * pen positions (draw_cairo.c, via sp_font_glyphs). */
#ifndef SPRINGPEND_TEXT_H
#define SPRINGPEND_TEXT_H

#include <stddef.h>
#include <stdint.h>

enum sp_text_size { SP_TEXT_SMALL, SP_TEXT_NORMAL, SP_TEXT_LARGE, SP_TEXT_TITLE, SP_TEXT_SIZES };

/* One glyph on screen; layout matches the attributes of shaders/text.vert. */
struct sp_glyph_quad {
    float rect[4];  /* x0, y0, x1, y1: px, y down from the top-left corner */
    float uv[4];    /* the atlas rectangle, texels */
    float color[4]; /* straight RGBA, 0..1 */
};

struct sp_font;

/* The byte length (1..4) of the well-formed UTF-8 character at s, or 0 when
 * s is at its NUL or at a malformed, overlong or surrogate sequence (text
 * that cairo would refuse whole). */
size_t sp_utf8_char(const char *s);

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

/* One glyph of a laid-out string for an outline renderer: the font's glyph
 * index and where its origin goes, px (the same place sp_font_layout puts
 * its bitmap), and how many bytes of the UTF-8 string it stands for. */
struct sp_glyph_pos {
    unsigned index;
    float x, y;
    int bytes;
};

/* Lays out utf8 as sp_font_layout does, one entry per code point, into
 * out[0..max); returns how many it needs. */
int sp_font_glyphs(const struct sp_font *f, int size, const char *utf8, float x,
                   float baseline, struct sp_glyph_pos *out, int max);

/* The em size of a text size, px (what FreeType was asked for). */
int sp_font_px(const struct sp_font *f, int size);

/* The R8 atlas: *w x *h bytes, row 0 first. Owned by f. */
const uint8_t *sp_font_atlas(const struct sp_font *f, int *w, int *h);

/* Draws quads into an 8-bit coverage image (w x h, stride w) on the CPU by
 * copying atlas texels, the way the GL pass samples them (nearest). For tests. */
void sp_font_blit(const struct sp_font *f, const struct sp_glyph_quad *q, int n,
                  uint8_t *img, int w, int h);

#endif
