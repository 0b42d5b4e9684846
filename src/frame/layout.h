/* springpend (internal): where things go in the frame. A title band at the
 * top and a caption band at the bottom when asked; between them the pendulum
 * view and the panels side by side (landscape) or one above the other
 * (portrait), the strip charts stacked where they can be wide, the phase and
 * Poincare plots square; heads-up text at the top of the view, the colourbar
 * at its right. Without the pendulum the panels tile the whole area: a lone
 * panel fills it, several take the grid whose cells come nearest to each
 * kind's preferred shape (strip charts wide, the others square; a cell is not
 * forced to that shape, since a phase portrait's axes have different units).
 * Pure arithmetic on pixel rectangles, so it can be tested alone. */
#ifndef SPRINGPEND_LAYOUT_H
#define SPRINGPEND_LAYOUT_H

#include "springpend/scene.h"

struct sp_rect {
    float x0, y0, x1, y1; /* px, y down from the top-left corner; x0 < x1, y0 < y1 */
};

struct sp_layout_desc {
    int width, height;  /* px */
    unsigned panels;    /* SP_PANEL_* bits */
    int order[SP_PANEL_COUNT]; /* their bit numbers in the order placed (reading
                                  order: rows, left to right); n_order = 0: bit order */
    int n_order;
    float hud_height;   /* px of heads-up text, 0 = none */
    float colorbar_width; /* px of the colourbar with its labels, 0 = none */
    int no_pendulum;    /* 1: no pendulum view: the panels take its room */
    float title_height; /* px of the title band, 0 = none */
    float caption_height; /* px of the caption band, 0 = none */
    float view_share;   /* the view on top (portrait or square): its share of the
                           height below the title, 0 = the default (0.45 square,
                           0.36 portrait); a cell of scenes side by side takes more */
    int view_left;      /* 1: the view at the left and the panels at its right,
                           whatever the frame's shape (a cell side by side) */
};

struct sp_layout {
    struct sp_rect camera;   /* the pendulum fits in here (empty without it) */
    struct sp_rect hud;      /* heads-up text (empty when not asked) */
    struct sp_rect colorbar; /* the colourbar and its labels (empty when not asked) */
    struct sp_rect title;    /* the title band (empty when not asked) */
    struct sp_rect caption;  /* the caption band (empty when not asked) */
    struct sp_rect panel[SP_PANEL_COUNT]; /* indexed by bit number; empty when not shown */
    float gap;               /* px between neighbours */
};

/* Places everything without overlap, every rectangle inside the frame. */
void sp_layout_compute(const struct sp_layout_desc *d, struct sp_layout *out);

/* 1 when a and b share interior pixels. */
int sp_rect_overlap(const struct sp_rect *a, const struct sp_rect *b);

/* 1 when the rectangle has positive width and height. */
int sp_rect_valid(const struct sp_rect *a);

#endif
