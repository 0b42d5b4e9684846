/* springpend (internal): which cells of a picture a long exposure's settled
 * trail has already crossed, and in which colours (trail = all, attack17
 * #10). A segment whose centre line crosses only cells that an earlier one
 * crossed in its colour adds nothing a reader can see (it lies within a
 * cell and a colour step of what is drawn) and is left out, so the list a
 * still or a figure draws is bounded by the picture, not by how long the
 * run is: the same curve traced a thousand times is drawn about once.
 * Decisions depend only on the segments before, in time order, so a video's
 * frame and a still at the same time leave out the same segments. */
#ifndef SPRINGPEND_COVER_H
#define SPRINGPEND_COVER_H

#include <stdint.h>

/* Colours: COVER_COLORS steps of a trail's colormap position, and one more
 * bit for a floor trace's one colour. */
#define SP_COVER_COLORS 15
#define SP_COVER_FLOOR SP_COVER_COLORS

struct sp_cover {
    uint16_t *bits; /* w * h cells, bit k: crossed in colour k; NULL: not made */
    int w, h;       /* cells */
    float cell;     /* px a cell's side: 0.5, or larger so that a large
                       drawing has at most 8.4e6 cells (cover.c) */
    int failed;     /* out of memory: every segment is drawn, as before */
};

/* 1 when the segment a -> b (px of a width x height drawing) crosses a cell
 * not yet crossed in colour `color` (0 .. SP_COVER_FLOOR), which it then
 * marks; 0 when it adds nothing. Parts outside the drawing count as
 * crossed. Made on first use; out of memory, every segment is new. */
int sp_cover_new(struct sp_cover *c, int width, int height, const float a[2], const float b[2],
                 int color);

/* The colour step of a colormap position in [0, 1]. */
int sp_cover_color(float position);

void sp_cover_destroy(struct sp_cover *c);

#endif
