/* springpend (internal): the draw list of one frame, in pixels (y down from
 * the top-left corner). Shapes are capsules for shaders/shape.vert (lines,
 * discs, lit balls, axis-aligned boxes); text becomes glyph quads. render.c
 * fills one, the panels and the heads-up text add to it, and render.c draws
 * the shapes, then the text. Allocation failures are remembered in `err`
 * and reported once by the renderer. */
#ifndef SPRINGPEND_CANVAS_H
#define SPRINGPEND_CANVAS_H

#include "text.h"

enum sp_shape_kind { SP_SHAPE_FLAT = 0, SP_SHAPE_BALL = 1, SP_SHAPE_BOX = 2 };

/* One capsule; layout matches the attributes of shaders/shape.vert. */
struct sp_shape {
    float seg[4];   /* p0.xy, p1.xy: px */
    float style[2]; /* half width (px), kind (enum sp_shape_kind) */
    float color[4]; /* straight RGBA, 0..1 */
};

enum sp_align { SP_ALIGN_LEFT, SP_ALIGN_CENTER, SP_ALIGN_RIGHT };

struct sp_canvas {
    struct sp_shape *shapes;
    int n_shapes, cap_shapes;
    struct sp_glyph_quad *quads;
    int n_quads, cap_quads;
    const struct sp_font *font;
    int err; /* 0, or SP_E_NOMEM once an append failed */
};

/* Empties the lists, keeping their memory. */
void sp_canvas_reset(struct sp_canvas *c);
/* Frees the lists. */
void sp_canvas_free(struct sp_canvas *c);

/* A segment from a to b, half width hw px, round caps. */
void sp_canvas_line(struct sp_canvas *c, float ax, float ay, float bx, float by, float hw,
                    const float color[4]);
/* A disc, or a shaded ball when ball = 1. */
void sp_canvas_disc(struct sp_canvas *c, float x, float y, float radius, int ball,
                    const float color[4]);
/* A filled axis-aligned rectangle with crisp edges. */
void sp_canvas_rect(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                    const float color[4]);

/* Text with its baseline at y, aligned on x; returns its width, px. */
int sp_canvas_text(struct sp_canvas *c, int size, float x, float y, enum sp_align align,
                   const float color[4], const char *utf8);

#endif
