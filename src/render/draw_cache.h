/* springpend (internal): the draw cache's policy, without GL. Each frame
 * sp_draw_cache_plan turns the canvas (canvas.h) and what the cache recorded
 * of the frames before into a plan: whether the frame can be drawn over the
 * cached base picture, whether base must be rebuilt, which items move to
 * the dynamic layer, what is new of the settled layer, the rectangles of
 * the target to restore from base, and which dynamic items are unchanged
 * since the last frame. draw_gl.c executes the plan with GL; nothing here
 * draws (Weston's renderer split: the core computes damage, the GL repaint
 * draws it).
 *
 * Base holds the accumulated picture (or the background), the static layer
 * over it, then the settled layer; the target keeps its pixels from frame to
 * frame. Drawing the static layer first (into base) and the dynamic layer
 * over it gives the very pixels of drawing the list in order (all shapes,
 * then all text) wherever no dynamic item drawn earlier than a static one
 * touches it: blending is per pixel, so only the order at each pixel
 * counts. That is checked from the items' bounding boxes (conservative:
 * every pixel a capsule's or glyph's quad may cover, cut by the clip the
 * item is under). Items whose order the cache cannot keep are lifted to the
 * dynamic layer (see sp_draw_cache_plan); a frame still failing the check
 * is drawn uncached. Base is rebuilt whenever its content would change: the
 * static items (geometry, colours, blending and clips, byte for byte) or the
 * background differ from those it was drawn from, its settled items are not
 * a prefix of this frame's, or new accumulated items touch static or
 * settled ones. */
#ifndef SPRINGPEND_DRAW_CACHE_H
#define SPRINGPEND_DRAW_CACHE_H

#include <stddef.h>

#include "frame/canvas.h"

enum { SP_DRAW_TILE = 32 };  /* px: the grain of base's rectangles */
enum { SP_DRAW_DTILE = 16 }; /* px: the grain of the damaged rectangles */

/* A rectangle drawn from base without blending: x0, y0, x1, y1 px (whole
 * pixels); fill an opaque premultiplied RGBA to write, or alpha < 0 to copy
 * base's pixels. Layout matches draw_gl.c's patch program. */
struct sp_draw_rect {
    float rect[4];
    float fill[4];
};

/* What lies under this frame's dynamic layer in the target, before it is
 * drawn. */
enum sp_draw_under {
    SP_DRAW_UNDER_CLEAR,   /* uncached: clear to the background; every layer drawn */
    SP_DRAW_UNDER_ACCUM,   /* uncached: the long exposure's picture; every layer drawn */
    SP_DRAW_UNDER_REBUILT, /* base was rebuilt in the target itself (plan.rebuild) */
    SP_DRAW_UNDER_RESTORE, /* the target holds the last frame: base copied over plan.damage */
    SP_DRAW_UNDER_BASE,    /* base copied over the whole frame (a long exposure) */
    SP_DRAW_UNDER_RECTS,   /* clear to the background, then base's rectangles */
};

struct sp_draw_plan {
    /* The list to draw: the canvas given, with the items the cache cannot
     * order lifted to the dynamic layer (the cache's own copy), or the
     * canvas itself with the cache off. */
    const struct sp_canvas *list;
    int cached;        /* draw the dynamic layer only, over base; 0 = every layer */
    int accum;         /* list has accumulated items: draw them into the long exposure */
    int accum_in_base; /* and into base, under nothing (they touch nothing cached) */
    /* Rebuild base: the long exposure (or the background), then the static
     * layer's shapes and text, then the settled layer, drawn into the target
     * and copied into base. With no long exposure, `rects` are base's
     * rectangles where it differs from the background (upload them for
     * SP_DRAW_UNDER_RECTS); NULL otherwise. */
    int rebuild;
    const struct sp_draw_rect *rects;
    int n_rects;
    /* Base kept (cached, not rebuilt): per settled item of list, in list
     * order, the shapes base holds already; n_new shapes past those are to
     * be drawn into base, each item under its clip (sp_draw_cache_clip). */
    const int *settled_old;
    int n_new;
    enum sp_draw_under under;
    const struct sp_draw_rect *damage; /* SP_DRAW_UNDER_RESTORE: base copied over these */
    int n_damage;
    /* NULL, or per item of list: 1 = a dynamic item as the target holds it
     * from the last frame; draw it only inside `damage` (sp_draw_cache_run),
     * and the others as usual. */
    const unsigned char *same;
};

struct sp_draw_cache_stats {
    /* frames drawn over base, times base was (re)built, frames drawn without
     * it, cached frames that drew only what was new of the settled layer
     * into base, and dynamic items left as the last frame drew them */
    long cached, redrawn, uncached, appended, unchanged;
};

struct sp_draw_cache;

/* A cache for a width x height px target, on. 0 or SP_E_NOMEM (logged). */
int sp_draw_cache_make(struct sp_draw_cache **out, int width, int height);

/* Plans frame c over background bg (straight RGBA) and records what the
 * plan makes of base and the target as if it were executed. The plan points
 * into the cache and into c; it holds until the next call. The target counts
 * as holding this frame only after sp_draw_cache_drawn. 0 or SP_E_NOMEM
 * (logged). */
int sp_draw_cache_plan(struct sp_draw_cache *k, const struct sp_canvas *c, const float bg[4],
                       struct sp_draw_plan *plan);

/* The plan was drawn: the target holds it (the next frame may restore only
 * the damage). */
void sp_draw_cache_drawn(struct sp_draw_cache *k, const struct sp_draw_plan *plan);

/* The clip item i of the last plan's list is drawn under (x1 <= x0 = none);
 * cached plans only. */
const float *sp_draw_cache_clip(const struct sp_draw_cache *k, int i);

/* For an unchanged item i of the last plan (plan.same[i]) and damage
 * rectangle r: the next run [*k, *e) of its primitives (shapes or glyph
 * quads), from *k on, whose boxes meet r (the others do not touch it).
 * Returns 1, or 0 when none is left. Start with *k = -1: that also checks
 * the item's own box against r. */
int sp_draw_cache_run(const struct sp_draw_cache *k, const struct sp_canvas *list, int i,
                      const struct sp_draw_rect *r, int *first, int *end);

/* Turns the cache on or off (off: every frame is drawn uncached); either way
 * base and the target are taken to hold nothing. */
void sp_draw_cache_set(struct sp_draw_cache *k, int on);

void sp_draw_cache_stats(const struct sp_draw_cache *k, struct sp_draw_cache_stats *out);

/* Frees the cache and sets *k to NULL. Safe on NULL. */
void sp_draw_cache_destroy(struct sp_draw_cache **k);

#endif
