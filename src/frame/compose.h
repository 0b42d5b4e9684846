/* springpend (internal): composes a frame on the CPU into a draw list
 * (canvas.h): the trail, stroboscopic images, mount, spring and bob in a
 * camera fitted to the motion, and the panels, heads-up text and colourbar
 * the look (sp_look: [view] and a few scene numbers) asks for, placed by
 * layout.c. Includes no GL or cairo: any backend draws the result.
 * Shared with: render (render.c composes each frame). */
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
    const struct sp_font *font;   /* NULL: the composer makes its own when text is
                                     drawn; else it draws with this one, borrowed
                                     (side by side: one glyph atlas for all cells) */
    int cell;                     /* 1: one of several scenes side by side (a
                                     portrait cell gives the pendulum more height) */
};

/* Scenes side by side: at most this many cells in one frame. */
#define SP_MAX_CELLS 4

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
 * "key=value" lines (output pixels), each key after `prefix`: the camera
 * (camera.px_per_m, camera.origin_px: the pivot's rest position, moved by
 * (dx, dy), the cell's corner), each arrow scale (vectors.QUANTITY.px_per_unit
 * and .key) and the energy bars' axis. "" when the composer draws neither
 * vectors nor energy bars nor is a cell (prefix ""), or before the first
 * frame. */
void sp_compose_overlay(const struct sp_composer *c, const char *prefix, double dx, double dy,
                        char *buf, size_t size);

/* The camera's scale, px per m (after the first frame), and a new one: the
 * camera keeps its centre. Side by side, every cell takes the smallest, so
 * a metre is the same length in every cell. */
double sp_compose_scale(const struct sp_composer *c);
void sp_compose_rescale(struct sp_composer *c, double px_per_m);
/* The longest arrow, px (after the layout), and a shorter one: side by
 * side, every cell takes the shortest, so an arrow of one newton is the
 * same length in every cell. */
double sp_compose_arrow_px(const struct sp_composer *c);
void sp_compose_shrink_arrows(struct sp_composer *c, double px);
/* Lays the frame out and fits the camera for parameters p, as the first
 * frame does (once; a no-op after). */
int sp_compose_lay_out(struct sp_composer *c, const struct sp_params *p);

/* compose_cells.c: n scenes (1..SP_MAX_CELLS) side by side in one frame,
 * each in its cell of a grid (sp_compose_cells_grid) with its own look, all
 * with desc's extent (the union of the scenes': one camera scale and the
 * same chart axes in every cell) and one font. With n = 1 it is the one
 * composer of desc alone. */
struct sp_compose_cells;
void sp_compose_cells_grid(int width, int height, int n, int *cols, int *rows);
int sp_compose_cells_make(struct sp_compose_cells **out, const struct sp_compose_desc *desc,
                          const struct sp_look *looks, int n);
/* Composes frames[0..n) (cell by cell) into one draw list; as
 * sp_compose_frame. At the first frame every cell takes the smallest camera
 * scale. */
int sp_compose_cells_frame(struct sp_compose_cells *c, const struct sp_frame *frames,
                           const struct sp_canvas **out);
/* 1 when frames[0..n) lay out as sp_compose_cells_make and _frame would
 * compose them (a figure of physical size: its panels hold their texts,
 * its labels fit), 0 when either refuses. Composes into a draw list only:
 * nothing drawn or written, and the refusals' messages muted (a probe for
 * what would fit: render/figure_fit.c). */
int sp_compose_cells_fits(const struct sp_compose_desc *desc, const struct sp_look *looks, int n,
                          const struct sp_frame *frames);
const struct sp_font *sp_compose_cells_font(const struct sp_compose_cells *c);
const struct sp_palette *sp_compose_cells_palette(const struct sp_compose_cells *c);
/* Every cell's sp_compose_overlay, prefixed "cellN." when n > 1. */
void sp_compose_cells_overlay(const struct sp_compose_cells *c, char *buf, size_t size);
void sp_compose_cells_destroy(struct sp_compose_cells **c);

/* The font (NULL when no text is drawn) and the palette, owned by c. */
const struct sp_font *sp_compose_font(const struct sp_composer *c);
const struct sp_palette *sp_compose_palette(const struct sp_composer *c);

/* compose_ensemble.c: draws ensemble e's members (thin rods from their
 * pivots, discs in sp_ensemble_color, and their trails when kept) with the
 * front view px = (ox + scale x, oy - scale y), or through cam (not NULL:
 * the perspective of a 3-D scene; scale is then cam's px per m at its
 * target, the members' discs sized by 1/depth and drawn far to near);
 * unit is the frame's smaller side, px. */
struct sp_ensemble;
struct sp_camera;
void sp_compose_ensemble(struct sp_canvas *c, const struct sp_ensemble *e, double ox, double oy,
                         double scale, float unit, const struct sp_palette *pal,
                         const struct sp_camera *cam);

/* Frees everything and sets *c to NULL. Safe on NULL. */
void sp_compose_destroy(struct sp_composer **c);

#endif
