/* springpend (internal): the draw list of one frame, composed on the CPU in
 * output pixels (y down from the top-left corner) and drawn by a backend:
 * GL (draw_gl.c: videos, PNG) or cairo (draw_cairo.c: SVG, PDF). Nothing
 * here knows GL or cairo.
 *
 * Geometry is a flat array of capsules (segment + half width + kind +
 * straight colour: lines, discs, lit balls, axis-aligned boxes), which the GL
 * backend uploads as they are. Items give the array its structure:
 *   SHAPES  independent capsules (markers, boxes, single strokes);
 *   PATH    a polyline: capsule i ends where capsule i+1 starts, a colour and
 *           width per segment (a vector backend strokes it as one path, or
 *           one per run of equal colour);
 *   TEXT    a run of UTF-8 text at a size, pen position and colour (laid
 *           out once on the CPU, text.h; GL draws its glyph quads);
 *   CLIP    the rectangle the shapes after it are clipped to (text is not
 *           clipped), or none;
 *   IMAGE   a raster of RGBA pixels stretched over a rectangle, each pixel a
 *           sharp-edged cell (a sweep's map); clipped like shapes.
 * Text comes in two forms: at one of the font's sizes with its pen on whole
 * pixels (sp_canvas_text: what both backends draw), or laid out at a size and
 * drawn at any scale, position and angle (sp_canvas_text_turned: a figure's
 * type in points, a y axis's name). Images and turned text are drawn by the
 * cairo backend only (SVG, PDF, and a sweep figure's PNG); the GL backend
 * refuses a list that has them rather than leave them out.
 * Every item carries a layer (static: the same every frame, e.g. panel
 * frames and axes; settled: a strip chart's past, which only grows;
 * dynamic: the motion) so that a backend may cache the static part and
 * append to the settled one. Both backends draw the accumulated layer, then
 * the shapes in list order, then the text over them. Allocation failures are remembered in `err` and reported once
 * by the caller.
 * Shared with: render (the draw list its backends draw), sweep (sweep_plot.c
 * composes its figures on it). */
#ifndef SPRINGPEND_CANVAS_H
#define SPRINGPEND_CANVAS_H

#include "text.h"

enum sp_shape_kind {
    SP_SHAPE_FLAT = 0,
    SP_SHAPE_BALL = 1,
    SP_SHAPE_BOX = 2,
    SP_SHAPE_SOFT = 3, /* an ellipse with its axes along the segment (half its
                          length) and across it (the half width), fading from
                          the colour at its centre to nothing at its edge as
                          (1 - d^2)^2, d the distance in radii: soft shadows
                          and pools of light */
};

/* One capsule; layout matches the attributes of shaders/shape.vert. */
struct sp_shape {
    float seg[4];   /* p0.xy, p1.xy: px */
    float style[2]; /* half width (px), kind (enum sp_shape_kind) */
    float color[4]; /* straight RGBA, 0..1 */
};

enum sp_align { SP_ALIGN_LEFT, SP_ALIGN_CENTER, SP_ALIGN_RIGHT };

enum sp_item_kind { SP_ITEM_SHAPES, SP_ITEM_PATH, SP_ITEM_TEXT, SP_ITEM_CLIP, SP_ITEM_IMAGE };

enum sp_layer {
    SP_LAYER_STATIC,  /* the same in every frame of a run */
    SP_LAYER_DYNAMIC, /* changes with the motion */
    SP_LAYER_ACCUM,   /* drawn once and kept: each frame's list holds only
                         what is new (a long exposure's settled trail), drawn
                         under everything else; a backend that draws one
                         frame just draws it first */
    SP_LAYER_SETTLED, /* drawn in list order like the others, but append-only:
                         each frame's item holds the last frame's shapes of
                         the same item first, unchanged, then what is new
                         (a strip chart's curve up to its newest complete
                         time bin), so a backend may draw only what is new.
                         Shapes only: text added while it is the layer goes
                         to the dynamic layer */
};

/* How shapes combine with what is under them. */
enum sp_blend {
    SP_BLEND_OVER, /* "over" */
    SP_BLEND_MAX,  /* a faded trail on a dark or transparent background: the
                      brighter of the two, so overlapping segments do not
                      stack into beads (GL_MAX; vector backends stroke the
                      trail as paths, which has the same effect) */
};

struct sp_item {
    enum sp_item_kind kind;
    enum sp_layer layer;
    enum sp_blend blend;
    int first, count; /* shapes (SHAPES, PATH) or glyph quads (TEXT); IMAGE:
                         first is the byte offset of its pixels in `pixels` */
    /* PATH only: lanes >= 2 interleaves that many polylines, shape k
     * belonging to lane (k - first) % lanes: the series of one chart drawn
     * point by point (each point's segments in lane order), so that the
     * chart's appended parts overlap as the whole does; a vector backend
     * strokes each lane as one path, lane 0 first. 0 or 1: one polyline. */
    int lanes;
    /* TEXT only: */
    int size;         /* enum sp_text_size */
    float x, y;       /* pen start and baseline, px (whole pixels unless turned) */
    float color[4];   /* straight RGBA */
    int text;         /* byte offset of the NUL-terminated UTF-8 in `strings` */
    float scale;      /* 0: drawn at its size's own px; > 0: turned text, the
                         size's layout drawn this many times as large (count 0:
                         it has no glyph quads) */
    float angle;      /* turned text: its baseline turned about the pen, rad,
                         clockwise on the y-down page (-pi/2 reads upward) */
    /* IMAGE only: */
    float rect[4];    /* x0, y0, x1, y1, px: where the pixels go */
    int iw, ih;       /* its pixels across and down (RGBA, straight, 4 bytes
                         each, rows top first) */
    /* CLIP only: */
    float clip[4];    /* x0, y0, x1, y1, px; x1 <= x0 = no clipping */
};

struct sp_axis_memo;

struct sp_canvas {
    struct sp_shape *shapes;
    int n_shapes, cap_shapes;
    struct sp_glyph_quad *quads;
    int n_quads, cap_quads;
    struct sp_item *items;
    int n_items, cap_items;
    char *strings;
    int n_strings, cap_strings; /* bytes */
    unsigned char *pixels;      /* the images' (IMAGE items) */
    int n_pixels, cap_pixels;   /* bytes */
    const struct sp_font *font;
    struct sp_axis_memo *axes; /* the panels' axis fits and tick labels (axis.h),
                                  kept from frame to frame by sp_canvas_reset;
                                  one allocation, freed by sp_canvas_free */
    enum sp_layer layer; /* given to the items added from now on */
    enum sp_blend blend;
    int in_path;         /* between sp_canvas_path_begin and _end */
    int err; /* 0, or SP_E_NOMEM once an append failed */
};

/* Empties the lists, keeping their memory; layer static, blend over. */
void sp_canvas_reset(struct sp_canvas *c);
/* Frees the lists. */
void sp_canvas_free(struct sp_canvas *c);

/* The layer and blending of what is added from now on. */
void sp_canvas_layer(struct sp_canvas *c, enum sp_layer layer);
void sp_canvas_blend(struct sp_canvas *c, enum sp_blend blend);

/* Lines between begin and end form one PATH item; each must start where the
 * previous one ended. Outside a path a line is an item of its own kind
 * (SHAPES). */
void sp_canvas_path_begin(struct sp_canvas *c);
void sp_canvas_path_end(struct sp_canvas *c);
/* Starts a SHAPES item that the shapes added next join, kept in the list
 * even when none are (a settled item is the same item in every frame). */
void sp_canvas_shapes_begin(struct sp_canvas *c);

/* Within a path: its shapes interleave n polylines (sp_item.lanes). */
void sp_canvas_path_lanes(struct sp_canvas *c, int n);

/* Clips the shapes added from now on to the rectangle (x0, y0, x1, y1) px;
 * NULL = no clipping. */
void sp_canvas_clip(struct sp_canvas *c, const float rect[4]);

/* A segment from a to b, half width hw px, round caps. */
void sp_canvas_line(struct sp_canvas *c, float ax, float ay, float bx, float by, float hw,
                    const float color[4]);
/* A disc, or a shaded ball when ball = 1. */
void sp_canvas_disc(struct sp_canvas *c, float x, float y, float radius, int ball,
                    const float color[4]);
/* A soft ellipse (SP_SHAPE_SOFT) centred at (x, y) with radii rx, ry px along
 * the axes. */
void sp_canvas_soft(struct sp_canvas *c, float x, float y, float rx, float ry,
                    const float color[4]);
/* A filled axis-aligned rectangle with crisp edges. */
void sp_canvas_rect(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                    const float color[4]);

/* Empties c of everything but its text (items, glyph quads, strings), in
 * order, keeping its clip: what a backend drawing a long list in pieces
 * (draw_cairo.h) has drawn is dropped, the text, drawn over all of it at
 * the end, stays. The layer and blending stay too. Not within a path. */
void sp_canvas_keep_text(struct sp_canvas *c);

/* Appends src's draw list to dst moved by (dx, dy) px, after a CLIP item
 * that ends any clipping: the cells of a side-by-side frame, each composed
 * on its own canvas, become one list. Text must come from the same font (its
 * glyph quads point into that font's atlas). Failures go to dst->err. */
void sp_canvas_append(struct sp_canvas *dst, const struct sp_canvas *src, float dx, float dy);

/* Text with its baseline at y, aligned on x; returns its width, px. */
int sp_canvas_text(struct sp_canvas *c, int size, float x, float y, enum sp_align align,
                   const float color[4], const char *utf8);

/* Turned text (cairo backend only): utf8 laid out at text size `size`,
 * drawn `scale` times as large (scale > 0) with its pen at (x, y) px, not
 * rounded, its baseline turned clockwise by angle rad about the pen. A
 * character no font has is refused (logged; c->err = SP_E_INPUT), never
 * drawn as a box. */
void sp_canvas_text_turned(struct sp_canvas *c, int size, float x, float y, float scale,
                           float angle, const float color[4], const char *utf8);

/* An image of w x h pixels (cairo backend only) stretched over the
 * rectangle (x0, y0)-(x1, y1) px, each pixel a sharp-edged cell: returns
 * its pixels for the caller to fill, straight RGBA, 4 bytes each, rows top
 * first, stride 4 w (valid until the next thing added); NULL when out of
 * memory (c->err) or w, h < 1. */
unsigned char *sp_canvas_image(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                               int w, int h);

#endif
