/* springpend (internal): composes a frame on the CPU into a draw list
 * (canvas.h): the trail, stroboscopic images, mount, spring and bob in a
 * camera fitted to the motion, and the panels, heads-up text and colourbar
 * the look (sp_look: [view] and a few scene numbers) asks for, placed by
 * layout.c. Includes no GL or cairo: any backend draws the result. */
#ifndef SPRINGPEND_COMPOSE_H
#define SPRINGPEND_COMPOSE_H

#include "springpend/frame.h"
#include "canvas.h"
#include "panels.h"

struct sp_compose_desc {
    int width, height;            /* px of the drawing (supersampled size) */
    struct sp_view_extent extent; /* world rectangle to fit, speed and panel ranges */
    const struct sp_look *look;   /* what is drawn and how; NULL = the default scene's */
    int supersample;              /* the drawing is this many times the output
                                     (0 or 1 = not): text floors scale with it */
};

struct sp_composer;

/* Builds the palette and, when text is drawn, the font (FreeType). 0,
 * SP_E_NOMEM or SP_E_IO (logged). */
int sp_compose_make(struct sp_composer **out, const struct sp_compose_desc *desc);

/* Composes f into the composer's own draw list and points *out at it (valid
 * until the next call or destroy). The layout is fixed at the first frame.
 * 0 or SP_E_NOMEM (logged). */
int sp_compose_frame(struct sp_composer *c, const struct sp_frame *f,
                     const struct sp_canvas **out);

/* What a test or tool needs to measure the overlays in the output image, as
 * "key=value" lines (output pixels): the camera (camera.px_per_m,
 * camera.origin_px: the pivot's rest position), each arrow scale
 * (vectors.QUANTITY.px_per_unit and .key) and the energy bars' axis. "" when
 * neither vectors nor energy bars are drawn, or before the first frame. */
void sp_compose_overlay(const struct sp_composer *c, char *buf, size_t size);

/* The font (NULL when no text is drawn) and the palette, owned by c. */
const struct sp_font *sp_compose_font(const struct sp_composer *c);
const struct sp_palette *sp_compose_palette(const struct sp_composer *c);

/* compose_ensemble.c: draws ensemble e's members (thin rods from their
 * pivots, discs in sp_ensemble_color, and their trails when kept) with the
 * camera px = (ox + scale x, oy - scale y); unit is the frame's smaller
 * side, px. */
struct sp_ensemble;
void sp_compose_ensemble(struct sp_canvas *c, const struct sp_ensemble *e, double ox, double oy,
                         double scale, float unit, const struct sp_palette *pal);

/* Frees everything and sets *c to NULL. Safe on NULL. */
void sp_compose_destroy(struct sp_composer **c);

#endif
