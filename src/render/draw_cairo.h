/* springpend (internal): the cairo backend of the draw list (canvas.h),
 * writing SVG or PDF. It lives in springpend-cairo.so (loaded on first use,
 * module.h). Shapes become real vector paths (a polyline is one path, or
 * one per run of equal colour when its colour changes along it), text runs
 * glyphs of the embedded DejaVu Sans at the pen positions text.c's layout
 * gives, so the picture matches the GL one. cairo's SVG surface writes the
 * glyphs as outlines; its PDF surface embeds the font and keeps the text
 * selectable. One user unit is one output pixel (SVG: px; PDF: pt), or the
 * list is scaled onto a page of physical size. sp_draw_cairo_raster draws
 * the same list into pixels (a sweep figure's PNG; still PNGs are GL's).
 * Also linked into springpend-plot.so: sweep figures draw through it.
 * Shared with: frame (figure.c, which belongs in render/), sweep (sweep_plot.c). */
#ifndef SPRINGPEND_DRAW_CAIRO_H
#define SPRINGPEND_DRAW_CAIRO_H

#include "springpend/figure.h"
#include "springpend/image.h"
#include "frame/canvas.h"

struct sp_draw_cairo_desc {
    const struct sp_canvas *canvas;
    const struct sp_font *font; /* NULL when the list has no text */
    float background[4];        /* straight RGBA; alpha 0 = transparent */
    double width, height;       /* px (SVG) or pt (PDF); the list's size */
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

/* Draws the list (canvas, font, background, cancel; path for messages)
 * scaled from width x height onto a px_w x px_h raster: *out gets it as
 * straight RGBA (image.h; the caller frees it), for a PNG. 0, or SP_E_NOMEM /
 * SP_E_IO (logged; *out then empty). */
int sp_draw_cairo_raster(const struct sp_draw_cairo_desc *d, int px_w, int px_h,
                         struct sp_image *out);

/* The same in pieces, for a list too long to hold whole (a sweep's
 * million dots): begin opens the document of d (d->canvas unused), a raster
 * of px_w x px_h when px_w > 0, and paints the background; shapes draws
 * every item of c but its text, in order (the caller may then empty c of
 * them, sp_canvas_keep_text, and go on adding); end draws the rest of c
 * but its text, then its text over all of it (the text of every piece:
 * kept to the end, as in one list) and finishes the document, or the raster into *out (out != NULL, freed
 * by the caller). end with c = NULL abandons the document (nothing more is
 * said; what was written is the caller's to discard). Each returns 0 or
 * the first failure, logged once: SP_E_IO, SP_E_NOMEM; SP_E_INPUT from
 * begin for a bad SOURCE_DATE_EPOCH. */
struct sp_draw_cairo;
int sp_draw_cairo_begin(struct sp_draw_cairo **out, const struct sp_draw_cairo_desc *d, int px_w,
                        int px_h);
int sp_draw_cairo_shapes(struct sp_draw_cairo *dc, const struct sp_canvas *c);
int sp_draw_cairo_end(struct sp_draw_cairo **dc, const struct sp_canvas *c, struct sp_image *out);

/* "cairo 1.16.0": the renderer, for provenance. */
const char *sp_draw_cairo_version(void);

/* Gives back the fonts and caches cairo keeps for the next document, when
 * there will be none (a sanitizer build checks for leaks). */
void sp_draw_cairo_done(void);

#endif
