/* springpend (internal): the cairo backend of the draw list (canvas.h),
 * writing SVG or PDF. It lives in springpend-cairo.so (loaded on first use,
 * module.h). Shapes become real vector paths (a polyline is one path, or
 * one per run of equal colour when its colour changes along it), text runs
 * glyphs of the embedded DejaVu Sans at the pen positions text.c's layout
 * gives, so the picture matches the GL one. cairo's SVG surface writes the
 * glyphs as outlines; its PDF surface embeds the font and keeps the text
 * selectable. One user unit is one output pixel (SVG: px; PDF: pt).
 * Shared with: frame (figure.c, which belongs in render/). */
#ifndef SPRINGPEND_DRAW_CAIRO_H
#define SPRINGPEND_DRAW_CAIRO_H

#include "springpend/figure.h"
#include "frame/canvas.h"

struct sp_draw_cairo_desc {
    const struct sp_canvas *canvas;
    const struct sp_font *font; /* NULL when the list has no text */
    float background[4];        /* straight RGBA; alpha 0 = transparent */
    int width, height;          /* px (SVG) or pt (PDF) */
    double page_w, page_h;      /* pt: the page when not width x height (a figure
                                   of physical size), the list scaled to fit; 0 = none */
    int fd;                     /* where the document goes (open for writing;
                                   the caller closes and renames it) */
    const char *path;           /* the target's name, for messages */
    enum sp_figure_format format; /* SVG or PDF */
    const char *title;          /* document title (PDF metadata); NULL = none */
    const char *scene_file;     /* provenance (cairo_fd.h): PDF /Subject, SVG
                                   <metadata>; NULL = none */
    const char *command;        /* provenance: the command without its -o; NULL = none */
    const volatile sig_atomic_t *cancel; /* once set, drawing stops (the caller
                                   then writes nothing); NULL = never */
};

/* Writes the list. 0, or SP_E_IO / SP_E_NOMEM with cairo's reason logged. */
int sp_draw_cairo_write(const struct sp_draw_cairo_desc *d);

#endif
