/* springpend (internal): text.c's laid-out glyphs drawn with cairo, the one
 * place where shaped text meets cairo: the still figures' backend
 * (draw_cairo.c) and the sweep figures (sweep_plot.c) both draw through
 * it, so a title in any script comes out the same in every figure. Linked
 * into each cairo module.
 * Shared with: sweep (sweep_plot.c draws its text with it). */
#ifndef SPRINGPEND_CAIRO_TEXT_H
#define SPRINGPEND_CAIRO_TEXT_H

#include <cairo.h>

#include "frame/text.h"

/* The cairo faces of a font's fallback list, made on first use. */
struct sp_cairo_faces {
    const struct sp_font *font;
    cairo_font_face_t **face; /* [n], NULL until used */
    int n;                    /* grows with the font's faces: text.c adds fallback
                               * faces while text is laid out */
    int cap;                  /* room for */
};

/* Prepares faces for f, and cr's font options for text.c's unhinted
 * outlines. 0 or SP_E_NOMEM (logged). */
int sp_cairo_faces_make(struct sp_cairo_faces *faces, const struct sp_font *f, cairo_t *cr);

/* Gives the faces back (cairo keeps what a surface still uses). Safe on a
 * zeroed struct. */
void sp_cairo_faces_destroy(struct sp_cairo_faces *faces);

/* Draws utf8 laid out at text size `size` with its pen at (x, y) (the
 * baseline; user units, one per layout px) in cr's current source, run by
 * run (one face and direction each) with its text and clusters, so that a
 * PDF keeps it real: selectable, and extracted in logical order. 0, or
 * SP_E_NOMEM / SP_E_IO (logged). */
int sp_cairo_text_show(cairo_t *cr, struct sp_cairo_faces *faces, int size, double x, double y,
                       const char *utf8);

/* Names the font files the text was drawn from in a PDF's /Keywords,
 * "fonts: DejaVu Sans (embedded in springpend), NotoSansCJK-Regular.ttc": by file
 * name alone, so that a PDF's bytes do not depend on where the fonts are
 * installed (the environment record in a PNG keeps paths and hashes). */
void sp_cairo_pdf_fonts(cairo_surface_t *pdf, const struct sp_font *f);

/* That text, "fonts: NAME, NAME" (an SVG's <metadata id="springpend.fonts">),
 * into names (size bytes, cut to fit). */
void sp_cairo_font_names(const struct sp_font *f, char *names, size_t size);

#endif
