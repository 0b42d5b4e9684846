/* springpend (internal): the draw cache's policy, without GL. See
 * draw_cache.h. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "base/array.h"
#include "draw_cache.h"

enum { TILE = SP_DRAW_TILE, DTILE = SP_DRAW_DTILE, MAX_FILLS = 200 };

/* A rectangle of base: x0, y0, x1, y1 px; v = 1: copied from base, v >= 2:
 * filled with fills[v - 2]. */
struct fill_rect {
    float r[4];
    int v;
};

struct box {
    float x0, y0, x1, y1; /* px; x1 < x0 = touches nothing */
    float clip[4];        /* the clip the item is drawn under (x1 <= x0 = none) */
};

struct sp_draw_cache {
    int on;                      /* 1 = cache the static layer */
    int width, height;           /* px */
    int base_valid;              /* base holds `key`'s static layer */
    int has_accum;               /* a long exposure exists (from the first frame
                                    with accumulated items on) */
    int kept;                    /* the target holds base + the last plan's
                                    dynamic items inside `damage` */
    unsigned char *key;          /* the static layer base was drawn from */
    size_t n_key, cap_key;       /* bytes */
    unsigned char *next;         /* this frame's, compared with key */
    size_t n_next, cap_next;     /* bytes */
    struct box *boxes;           /* per item of the list: what it may touch */
    int cap_boxes;
    struct sp_item *items;       /* the list's items, those the cache cannot
                                    order moved to the dynamic layer */
    int cap_items;
    struct sp_canvas lifted;     /* the plan's list, with `items` */
    struct fill_rect *rects;     /* where base differs from the background (no
                                    accumulated layer): copied, or filled */
    int n_rects, cap_rects;
    struct sp_draw_rect *patches; /* rects as the plan gives them */
    int cap_patches;
    float fills[MAX_FILLS][4];   /* the opaque colours of filled rectangles */
    int n_fills;
    unsigned char *tiles;        /* scratch: what base holds in TILE px squares */
    struct sp_draw_rect *damage; /* the rectangles of the target to restore */
    int n_damage, cap_damage;
    unsigned char *dtiles;       /* scratch: DTILE px squares touched */
    /* The settled layer as base holds it: per settled item in list order, a
     * struct settled_head and the shapes drawn. A frame whose settled items
     * start with these, unchanged, draws only the rest into base. */
    unsigned char *settled;
    size_t n_settled, cap_settled; /* bytes */
    int *settled_old;            /* per settled item, shapes base holds */
    int cap_settled_old;
    /* The last cached frame's dynamic items as the target holds them: per
     * dynamic item in list order, a struct dyn_head and its shapes or glyph
     * quads. An item of this frame equal to its counterpart there (same
     * place in the order, byte for byte) is left as it is: the target is
     * restored and the item redrawn only where something else changed. */
    unsigned char *dyn;
    size_t n_dyn, cap_dyn;       /* bytes */
    int n_dyn_items;
    unsigned char *same;         /* per item of the list, 1 = unchanged */
    int cap_same, any_same;
    struct sp_draw_cache_stats stats;
};

static void box_add(struct box *b, float x0, float y0, float x1, float y1)
{
    b->x0 = fminf(b->x0, x0), b->y0 = fminf(b->y0, y0);
    b->x1 = fmaxf(b->x1, x1), b->y1 = fmaxf(b->y1, y1);
}

static int box_meets(const struct box *a, const struct box *b)
{
    return a->x1 >= a->x0 && b->x1 >= b->x0 && a->x0 <= b->x1 && b->x0 <= a->x1 &&
           a->y0 <= b->y1 && b->y0 <= a->y1;
}

/* The box of a shape sh, or of a glyph quad q when sh is NULL, of an item
 * of `layer` under the clip cl (x1 <= x0 = none). */
static struct box prim_box_of(const struct sp_shape *sh, const struct sp_glyph_quad *q,
                              enum sp_layer layer, const float cl[4])
{
    struct box b = {INFINITY, INFINITY, -INFINITY, -INFINITY, {0, 0, 0, 0}};
    if (!sh) {
        const float *r = q->rect;
        box_add(&b, fminf(r[0], r[2]) - 1, fminf(r[1], r[3]) - 1, fmaxf(r[0], r[2]) + 1,
                fmaxf(r[1], r[3]) + 1);
        return b; /* text is never clipped */
    }
    const float e = sh->style[0] + 2; /* the quad reaches half width + 1 px */
    /* a box or soft ellipse (kinds 2 and 3, horizontal as sp_canvas_rect and
     * _soft make them) reaches 1 px beyond its ends */
    const float ex = sh->style[1] > 1.5f && sh->seg[1] == sh->seg[3] ? 2 : e;
    box_add(&b, fminf(sh->seg[0], sh->seg[2]) - ex, fminf(sh->seg[1], sh->seg[3]) - e,
            fmaxf(sh->seg[0], sh->seg[2]) + ex, fmaxf(sh->seg[1], sh->seg[3]) + e);
    if (layer != SP_LAYER_ACCUM && cl[2] > cl[0]) { /* the scissor's whole pixels */
        memcpy(b.clip, cl, sizeof(b.clip));
        b.x0 = fmaxf(b.x0, floorf(cl[0]) - 1), b.y0 = fmaxf(b.y0, floorf(cl[1]) - 1);
        b.x1 = fminf(b.x1, ceilf(cl[2]) + 1), b.y1 = fminf(b.y1, ceilf(cl[3]) + 1);
    }
    return b;
}

/* The box of primitive k (a shape, or a glyph quad when text) of item it,
 * cut by the clip cl (x1 <= x0 = none). */
static struct box prim_box(const struct sp_canvas *c, const struct sp_item *it, int k,
                           const float cl[4])
{
    return it->kind == SP_ITEM_TEXT ? prim_box_of(NULL, &c->quads[k], it->layer, cl)
                                    : prim_box_of(&c->shapes[k], NULL, it->layer, cl);
}

/* Fills d->boxes for the items of c: each the union of its primitives'.
 * 0 or SP_E_NOMEM. */
static int boxes_make(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    float cl[4] = {0, 0, 0, 0};
    if (SP_ARRAY_RESERVE(d->boxes, d->cap_boxes, c->n_items, 0))
        return SP_E_NOMEM;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        struct box *b = &d->boxes[i];
        *b = (struct box){INFINITY, INFINITY, -INFINITY, -INFINITY, {0, 0, 0, 0}};
        if (it->kind == SP_ITEM_CLIP) {
            memcpy(cl, it->clip, sizeof(cl));
            continue;
        }
        if (it->kind != SP_ITEM_TEXT && it->layer != SP_LAYER_ACCUM)
            memcpy(b->clip, cl, sizeof(cl));
        for (int k = it->first; k < it->first + it->count; k++) {
            const struct box p = prim_box(c, it, k, cl);
            if (p.x1 >= p.x0)
                box_add(b, p.x0, p.y0, p.x1, p.y1);
        }
    }
    return 0;
}

/* Whether items a and b touch a common pixel: their boxes meet, and so do
 * the boxes of some primitive of each (a coarse test, then a finer one). */
static int items_meet(const struct sp_draw_cache *d, const struct sp_canvas *c, int a, int b)
{
    const struct sp_item *ia = &c->items[a], *ib = &c->items[b];
    if (!box_meets(&d->boxes[a], &d->boxes[b]))
        return 0;
    for (int k = ia->first; k < ia->first + ia->count; k++) {
        const struct box pa = prim_box(c, ia, k, d->boxes[a].clip);
        if (!box_meets(&pa, &d->boxes[b]))
            continue;
        for (int m = ib->first; m < ib->first + ib->count; m++) {
            const struct box pb = prim_box(c, ib, m, d->boxes[b].clip);
            if (box_meets(&pa, &pb))
                return 1;
        }
    }
    return 0;
}

/* Whether drawing c's static layer, then its settled one, then its
 * dynamic one keeps every pixel of drawing the list in order (shapes in
 * list order, then text in list order): no dynamic item that the list draws
 * before a static one touches it; no settled item touches static text, a
 * static shape the list draws after it, a dynamic shape the list draws
 * before it, or another settled item (base gets each frame's new parts of
 * all settled items in turn). */
static int order_keeps(const struct sp_draw_cache *d, const struct sp_canvas *c)
{
    for (int a = 0; a < c->n_items; a++) {
        if (c->items[a].kind == SP_ITEM_CLIP || c->items[a].layer != SP_LAYER_SETTLED)
            continue;
        for (int k = 0; k < c->n_items; k++) {
            const struct sp_item *o = &c->items[k];
            if (k == a || o->kind == SP_ITEM_CLIP)
                continue;
            const int text = o->kind == SP_ITEM_TEXT;
            const int clash = o->layer == SP_LAYER_SETTLED ||
                              (o->layer == SP_LAYER_STATIC && (text || k > a)) ||
                              (o->layer == SP_LAYER_DYNAMIC && !text && k < a);
            if (clash && items_meet(d, c, a, k))
                return 0;
        }
    }
    for (int s = 0; s < c->n_items; s++) {
        const struct sp_item *st = &c->items[s];
        if (st->kind == SP_ITEM_CLIP || st->layer != SP_LAYER_STATIC)
            continue;
        for (int k = 0; k < c->n_items; k++) {
            const struct sp_item *dy = &c->items[k];
            if (dy->kind == SP_ITEM_CLIP || dy->layer != SP_LAYER_DYNAMIC)
                continue;
            const int text_d = dy->kind == SP_ITEM_TEXT, text_s = st->kind == SP_ITEM_TEXT;
            const int before = text_d == text_s ? k < s : text_s;
            if (before && items_meet(d, c, k, s))
                return 0;
        }
    }
    return 1;
}

/* Marks tiles x0..x1, y0..y1 (inclusive, clamped) with v. */
static void tiles_mark(struct sp_draw_cache *d, int tw, int th, int x0, int y0, int x1, int y1,
                       unsigned char v)
{
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= tw ? tw - 1 : x1, y1 = y1 >= th ? th - 1 : y1;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            d->tiles[y * tw + x] = v;
}

/* Sorts the tiles by what base holds there: the background (0), what
 * must be copied (1), or one opaque colour (2 + its index in d->fills):
 * the primitives of the static layer in list order, each marking the tiles
 * its box touches 1, except an opaque box (alpha 1, horizontal) that
 * covers whole tiles, which marks those with its colour (all it covers is
 * that colour, whatever was under it). Then the rectangles: runs of equal
 * tiles along each row, joined with the run above when it spans the same
 * columns with the same value. 0 or SP_E_NOMEM. */
static int rects_make(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    const int tw = (d->width + TILE - 1) / TILE, th = (d->height + TILE - 1) / TILE;
    if (!d->tiles && !(d->tiles = malloc((size_t)tw * (size_t)th)))
        return SP_E_NOMEM;
    memset(d->tiles, 0, (size_t)tw * (size_t)th);
    d->n_fills = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_STATIC)
            continue;
        for (int k = it->first; k < it->first + it->count; k++) {
            const struct box b = prim_box(c, it, k, d->boxes[i].clip);
            if (b.x1 < b.x0)
                continue;
            tiles_mark(d, tw, th, (int)floorf(b.x0 / TILE), (int)floorf(b.y0 / TILE),
                       (int)floorf(b.x1 / TILE), (int)floorf(b.y1 / TILE), 1);
            const struct sp_shape *sh = it->kind == SP_ITEM_TEXT ? NULL : &c->shapes[k];
            if (!sh || sh->style[1] < 1.5f || sh->style[1] > 2.5f || sh->color[3] < 1 ||
                sh->seg[1] != sh->seg[3] ||
                d->boxes[i].clip[2] > d->boxes[i].clip[0] || d->n_fills == MAX_FILLS)
                continue;
            /* pixels whose centres are half a pixel inside are fully covered */
            const float x0 = fminf(sh->seg[0], sh->seg[2]), x1 = fmaxf(sh->seg[0], sh->seg[2]);
            const float y0 = sh->seg[1] - sh->style[0], y1 = sh->seg[1] + sh->style[0];
            const int tx0 = (int)ceilf(x0 / TILE), ty0 = (int)ceilf(y0 / TILE);
            /* whole tiles inside the frame only (the last row and column may be cut) */
            const int tx1 = (int)fminf(floorf(x1 / TILE), (float)(d->width / TILE)) - 1;
            const int ty1 = (int)fminf(floorf(y1 / TILE), (float)(d->height / TILE)) - 1;
            if (tx1 < tx0 || ty1 < ty0)
                continue;
            int f = 0;
            while (f < d->n_fills && memcmp(d->fills[f], sh->color, sizeof(d->fills[f])))
                f++;
            if (f == d->n_fills)
                memcpy(d->fills[d->n_fills++], sh->color, sizeof(d->fills[f]));
            tiles_mark(d, tw, th, tx0, ty0, tx1, ty1, (unsigned char)(2 + f));
        }
    }
    /* base holds the settled layer too, which grows: all it may cover */
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const float *cl = d->boxes[i].clip;
        if (cl[2] > cl[0])
            tiles_mark(d, tw, th, (int)floorf((floorf(cl[0]) - 1) / TILE), (int)floorf((floorf(cl[1]) - 1) / TILE),
                       (int)floorf((ceilf(cl[2]) + 1) / TILE), (int)floorf((ceilf(cl[3]) + 1) / TILE), 1);
        else
            tiles_mark(d, tw, th, 0, 0, tw - 1, th - 1, 1);
    }
    d->n_rects = 0;
    int row_first = 0; /* the rectangles ending on the previous row start here */
    for (int y = 0; y < th; y++) {
        const int prev_first = row_first;
        int prev_end = d->n_rects;
        row_first = d->n_rects;
        for (int x = 0; x < tw;) {
            const unsigned char v = d->tiles[y * tw + x];
            if (!v) {
                x++;
                continue;
            }
            int e = x;
            while (e < tw && d->tiles[y * tw + e] == v)
                e++;
            const struct fill_rect r = {{(float)(x * TILE), (float)(y * TILE), (float)(e * TILE),
                                         (float)((y + 1) * TILE)}, v};
            int k = prev_first;
            while (k < prev_end && !(d->rects[k].r[0] == r.r[0] && d->rects[k].r[2] == r.r[2] &&
                                     d->rects[k].v == v))
                k++;
            if (k < prev_end) { /* the same columns as a run above: grow it down, and
                                   keep this row's rectangles together at the end */
                struct fill_rect t = d->rects[k];
                t.r[3] = r.r[3];
                memmove(d->rects + k, d->rects + k + 1, (size_t)(d->n_rects - k - 1) * sizeof(t));
                d->rects[d->n_rects - 1] = t;
                row_first--;
                prev_end--;
            } else {
                if (SP_ARRAY_RESERVE(d->rects, d->cap_rects, d->n_rects + 1, 16))
                    return SP_E_NOMEM;
                d->rects[d->n_rects++] = r;
            }
            x = e;
        }
    }
    return 0;
}

static int append(unsigned char **buf, size_t *n, size_t *cap, const void *data, size_t size)
{
    if (SP_ARRAY_RESERVE(*buf, *cap, *n + size, 4096))
        return SP_E_NOMEM;
    memcpy(*buf + *n, data, size);
    *n += size;
    return 0;
}

/* What the cache's pixels depend on: every static item (kind, blending,
 * clip) with its shapes or glyph quads, and the background. */
static int key_make(struct sp_draw_cache *d, const struct sp_canvas *c, const float bg[4])
{
    int err;
    d->n_next = 0;
    err = append(&d->next, &d->n_next, &d->cap_next, bg, 4 * sizeof(float));
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_STATIC)
            continue;
        const int head[3] = {it->kind, it->blend, it->count};
        err = append(&d->next, &d->n_next, &d->cap_next, head, sizeof(head));
        if (!err)
            err = append(&d->next, &d->n_next, &d->cap_next, d->boxes[i].clip, sizeof(d->boxes[i].clip));
        if (!err && it->kind == SP_ITEM_TEXT)
            err = append(&d->next, &d->n_next, &d->cap_next, c->quads + it->first,
                         (size_t)it->count * sizeof(*c->quads));
        else if (!err)
            err = append(&d->next, &d->n_next, &d->cap_next, c->shapes + it->first,
                         (size_t)it->count * sizeof(*c->shapes));
    }
    return err;
}

/* Whether the accumulated items of c touch no static or settled item. */
static int accum_apart(const struct sp_draw_cache *d, const struct sp_canvas *c)
{
    for (int a = 0; a < c->n_items; a++) {
        if (c->items[a].kind == SP_ITEM_CLIP || c->items[a].layer != SP_LAYER_ACCUM)
            continue;
        for (int s = 0; s < c->n_items; s++)
            if (c->items[s].kind != SP_ITEM_CLIP &&
                (c->items[s].layer == SP_LAYER_STATIC || c->items[s].layer == SP_LAYER_SETTLED) &&
                items_meet(d, c, a, s))
                return 0;
    }
    return 1;
}

/* Marks the DTILE px squares that shapes [from, to) of item i of c may touch
 * in d->dtiles (sized by dtiles_clear). */
static void dtiles_mark_box(struct sp_draw_cache *d, const struct box *b);

static void dtiles_mark(struct sp_draw_cache *d, const struct sp_canvas *c, int i, int from, int to)
{
    for (int k = from; k < to; k++) {
        const struct box b = prim_box(c, &c->items[i], k, d->boxes[i].clip);
        dtiles_mark_box(d, &b);
    }
}

/* Marks the DTILE px squares box b touches. */
static void dtiles_mark_box(struct sp_draw_cache *d, const struct box *b)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    if (b->x1 < b->x0)
        return;
    int x0 = (int)floorf(b->x0 / DTILE), y0 = (int)floorf(b->y0 / DTILE);
    int x1 = (int)floorf(b->x1 / DTILE), y1 = (int)floorf(b->y1 / DTILE);
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= tw ? tw - 1 : x1, y1 = y1 >= th ? th - 1 : y1;
    for (int y = y0; y <= y1; y++)
        memset(d->dtiles + (size_t)y * tw + x0, 1, x1 >= x0 ? (size_t)(x1 - x0 + 1) : 0);
}

/* Empties d->dtiles. 0 or SP_E_NOMEM. */
static int dtiles_clear(struct sp_draw_cache *d)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    if (!d->dtiles && !(d->dtiles = malloc((size_t)tw * (size_t)th)))
        return SP_E_NOMEM;
    memset(d->dtiles, 0, (size_t)tw * (size_t)th);
    return 0;
}

struct dyn_head {
    int kind, blend, count, lanes;
    float clip[4];
};

static size_t dyn_bytes(const struct sp_item *it)
{
    return (size_t)it->count * (it->kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad)
                                                           : sizeof(struct sp_shape));
}

static const void *dyn_data(const struct sp_canvas *c, const struct sp_item *it)
{
    return it->kind == SP_ITEM_TEXT ? (const void *)(c->quads + it->first)
                                    : (const void *)(c->shapes + it->first);
}

/* Records c's dynamic items as the target now holds them. 0 or SP_E_NOMEM. */
static int dyn_save(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    int err = 0;
    d->n_dyn = 0;
    d->n_dyn_items = 0;
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_DYNAMIC)
            continue;
        struct dyn_head h = {it->kind, (int)it->blend, it->count, it->lanes, {0, 0, 0, 0}};
        memcpy(h.clip, d->boxes[i].clip, sizeof(h.clip));
        err = append(&d->dyn, &d->n_dyn, &d->cap_dyn, &h, sizeof(h));
        if (!err)
            err = append(&d->dyn, &d->n_dyn, &d->cap_dyn, dyn_data(c, it), dyn_bytes(it));
        d->n_dyn_items++;
    }
    if (err)
        d->n_dyn = 0, d->n_dyn_items = -1; /* nothing known: all changed */
    return err;
}

/* Compares c's dynamic items with the record (d->same) and marks in
 * d->dtiles the squares of those that changed, in their last frame's form
 * and in this one's. 0 or SP_E_NOMEM. */
static int dyn_compare(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    if (SP_ARRAY_RESERVE(d->same, d->cap_same, c->n_items, 0))
        return SP_E_NOMEM;
    memset(d->same, 0, (size_t)c->n_items);
    d->any_same = 0;
    int n = 0;
    for (int i = 0; i < c->n_items; i++)
        n += c->items[i].kind != SP_ITEM_CLIP && c->items[i].layer == SP_LAYER_DYNAMIC;
    const int paired = n == d->n_dyn_items;
    size_t at = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_DYNAMIC)
            continue;
        if (paired) { /* this item against its counterpart */
            struct dyn_head h;
            memcpy(&h, d->dyn + at, sizeof(h));
            at += sizeof(h);
            const unsigned char *old = d->dyn + at;
            const size_t size = (size_t)h.count * (h.kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad)
                                                                           : sizeof(struct sp_shape));
            at += size;
            d->same[i] = h.kind == (int)it->kind && h.blend == (int)it->blend && h.count == it->count &&
                         h.lanes == it->lanes && !memcmp(h.clip, d->boxes[i].clip, sizeof(h.clip)) &&
                         !memcmp(old, dyn_data(c, it), size);
            d->any_same |= d->same[i];
            if (d->same[i]) {
                d->stats.unchanged++;
                continue;
            }
            for (int k = 0; k < h.count; k++) { /* where it was */
                const struct box b = h.kind == SP_ITEM_TEXT
                    ? prim_box_of(NULL, (const struct sp_glyph_quad *)old + k, SP_LAYER_DYNAMIC, h.clip)
                    : prim_box_of((const struct sp_shape *)old + k, NULL, SP_LAYER_DYNAMIC, h.clip);
                dtiles_mark_box(d, &b);
            }
        }
        dtiles_mark(d, c, i, it->first, it->first + it->count); /* where it is */
    }
    for (size_t b = 0; !paired && b < d->n_dyn;) { /* every old item, where it was */
        struct dyn_head h;
        memcpy(&h, d->dyn + b, sizeof(h));
        b += sizeof(h);
        for (int k = 0; k < h.count; k++) {
            const struct box x = h.kind == SP_ITEM_TEXT
                ? prim_box_of(NULL, (const struct sp_glyph_quad *)(d->dyn + b) + k, SP_LAYER_DYNAMIC, h.clip)
                : prim_box_of((const struct sp_shape *)(d->dyn + b) + k, NULL, SP_LAYER_DYNAMIC, h.clip);
            dtiles_mark_box(d, &x);
        }
        b += (size_t)h.count * (h.kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad) : sizeof(struct sp_shape));
    }
    return 0;
}

/* Sets d->damage to the marked squares, as runs along each row. 0 or
 * SP_E_NOMEM. */
static int damage_runs(struct sp_draw_cache *d)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    d->n_damage = 0;
    for (int y = 0; y < th; y++)
        for (int x = 0; x < tw;) {
            if (!d->dtiles[y * tw + x]) {
                x++;
                continue;
            }
            int e = x;
            while (e < tw && d->dtiles[y * tw + e])
                e++;
            if (SP_ARRAY_RESERVE(d->damage, d->cap_damage, d->n_damage + 1, 64))
                return SP_E_NOMEM;
            d->damage[d->n_damage++] = (struct sp_draw_rect){
                {(float)(x * DTILE), (float)(y * DTILE), fminf((float)(e * DTILE), (float)d->width),
                 fminf((float)((y + 1) * DTILE), (float)d->height)},
                {0, 0, 0, -1}};
            x = e;
        }
    return 0;
}

/* ---- the settled layer in base ---- */

struct settled_head {
    int blend, lanes, count;
    float clip[4];
};

/* Whether base holds a prefix of each of c's settled items (the same
 * items, blending, lanes and clips; their first shapes byte for byte), and
 * how many shapes of each (d->settled_old). 0 = no, 1 = yes, or
 * SP_E_NOMEM. */
static int settled_prefix(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    size_t at = 0;
    int j = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        struct settled_head h;
        if (at + sizeof(h) > d->n_settled)
            return 0;
        memcpy(&h, d->settled + at, sizeof(h));
        at += sizeof(h);
        if (h.blend != (int)it->blend || h.lanes != it->lanes || h.count > it->count ||
            memcmp(h.clip, d->boxes[i].clip, sizeof(h.clip)) ||
            memcmp(d->settled + at, c->shapes + it->first, (size_t)h.count * sizeof(*c->shapes)))
            return 0;
        at += (size_t)h.count * sizeof(*c->shapes);
        if (SP_ARRAY_RESERVE(d->settled_old, d->cap_settled_old, j + 1, 8))
            return SP_E_NOMEM;
        d->settled_old[j++] = h.count;
    }
    return at == d->n_settled;
}

/* Records c's settled items as base now holds them. 0 or SP_E_NOMEM. */
static int settled_save(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    int err = 0;
    d->n_settled = 0;
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        struct settled_head h = {(int)it->blend, it->lanes, it->count, {0, 0, 0, 0}};
        memcpy(h.clip, d->boxes[i].clip, sizeof(h.clip));
        err = append(&d->settled, &d->n_settled, &d->cap_settled, &h, sizeof(h));
        if (!err)
            err = append(&d->settled, &d->n_settled, &d->cap_settled, c->shapes + it->first,
                         (size_t)it->count * sizeof(*c->shapes));
    }
    if (err)
        d->n_settled = 0;
    return err;
}

/* Marks in d->dtiles the squares that what is new of c's settled items
 * (past d->settled_old) may touch. Returns the new shapes. */
static int settled_find_new(struct sp_draw_cache *d, const struct sp_canvas *c)
{
    int j = 0, n_new = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const int old = d->settled_old[j++];
        dtiles_mark(d, c, i, it->first + old, it->first + it->count);
        n_new += it->count - old;
    }
    return n_new;
}

/* Items whose order against others the cache cannot keep are drawn with
 * the dynamic layer instead, each frame (an unchanged one is left as the
 * last frame drew it; the others of their layer stay cached): a static
 * shape the list draws after a settled item it touches, static text
 * touching a settled item (text is drawn after every shape), a static item
 * that a dynamic one drawn before it touches, a settled item touching a
 * dynamic shape drawn before it or a settled item before it (at small sizes
 * panels, legends, labels and the pendulum crowd each other: such frames
 * were drawn uncached, their cost growing with the curves). Repeated until
 * nothing moves, since a moved item is dynamic for the others; order_keeps
 * then holds. Sets d->items to c's items with those layers changed and
 * *out to c with them. 0 or SP_E_NOMEM. */
static int lift_items(struct sp_draw_cache *d, const struct sp_canvas *c, struct sp_canvas *out)
{
    *out = *c;
    if (SP_ARRAY_RESERVE(d->items, d->cap_items, c->n_items, 0))
        return SP_E_NOMEM;
    if (c->n_items)
        memcpy(d->items, c->items, (size_t)c->n_items * sizeof(*d->items));
    out->items = d->items;
    for (int moved = 1; moved;) {
        moved = 0;
        for (int i = 0; i < c->n_items; i++) {
            struct sp_item *it = &d->items[i];
            const int st = it->layer == SP_LAYER_STATIC, text_i = it->kind == SP_ITEM_TEXT;
            if (it->kind == SP_ITEM_CLIP || !(st || it->layer == SP_LAYER_SETTLED))
                continue;
            for (int k = 0; k < c->n_items; k++) {
                const struct sp_item *o = &d->items[k];
                if (k == i || o->kind == SP_ITEM_CLIP)
                    continue;
                const int text_o = o->kind == SP_ITEM_TEXT;
                const int dyn = o->layer == SP_LAYER_DYNAMIC, set = o->layer == SP_LAYER_SETTLED;
                const int over = st ? (set && (text_i || k < i)) ||
                                          (dyn && (text_o == text_i ? k < i : text_i))
                                    : (dyn && !text_o && k < i) || (set && k < i);
                if (over && items_meet(d, out, k, i)) {
                    it->layer = SP_LAYER_DYNAMIC;
                    moved = 1;
                    break;
                }
            }
        }
    }
    return 0;
}

/* Sets d->patches to base's rectangles as the plan gives them (the last
 * tiles cut at the frame's edges). 0 or SP_E_NOMEM. */
static int patches_make(struct sp_draw_cache *d)
{
    if (SP_ARRAY_RESERVE(d->patches, d->cap_patches, d->n_rects ? d->n_rects : 1, 0))
        return SP_E_NOMEM;
    for (int k = 0; k < d->n_rects; k++) {
        const struct fill_rect *fr = &d->rects[k];
        struct sp_draw_rect *p = &d->patches[k];
        memcpy(p->rect, fr->r, sizeof(p->rect));
        p->rect[2] = fminf(p->rect[2], (float)d->width); /* the last tiles are cut */
        p->rect[3] = fminf(p->rect[3], (float)d->height);
        if (fr->v == 1)
            memcpy(p->fill, (const float[4]){0, 0, 0, -1}, sizeof(p->fill));
        else /* opaque: what the shape shader writes for it (premultiplied, alpha 1) */
            memcpy(p->fill, d->fills[fr->v - 2], sizeof(p->fill));
    }
    return 0;
}

int sp_draw_cache_make(struct sp_draw_cache **out, int width, int height)
{
    struct sp_draw_cache *d = calloc(1, sizeof(*d));
    *out = NULL;
    if (!d) {
        sp_log_error("out of memory for the GL backend");
        return SP_E_NOMEM;
    }
    d->on = 1;
    d->width = width;
    d->height = height;
    *out = d;
    return 0;
}

/* Base rebuilt from c (cached): records its static and settled layers and,
 * with no long exposure, its rectangles (p->rects). 0 or SP_E_NOMEM
 * (logged). */
static int plan_rebuild(struct sp_draw_cache *d, const struct sp_canvas *c, struct sp_draw_plan *p)
{
    int err;
    p->rebuild = 1;
    p->under = SP_DRAW_UNDER_REBUILT;
    if ((err = settled_save(d, c)) != 0) {
        sp_log_error("out of memory for the settled layer's record");
        return err;
    }
    unsigned char *swap = d->key;
    size_t cap = d->cap_key;
    d->key = d->next, d->n_key = d->n_next, d->cap_key = d->cap_next;
    d->next = swap, d->cap_next = cap, d->n_next = 0;
    d->base_valid = 1;
    d->stats.redrawn++;
    if (!d->has_accum) {
        if ((err = rects_make(d, c)) != 0 || (err = patches_make(d)) != 0) {
            sp_log_error("out of memory for the static cache's rectangles");
            return err;
        }
        p->rects = d->patches;
        p->n_rects = d->n_rects;
    }
    return 0;
}

/* Base kept (cached, its static layer and a prefix of its settled one as
 * c's): what is new of the settled layer, and what to restore under this
 * frame, with the target holding the last frame (kept) or not. 0 or
 * SP_E_NOMEM (logged). */
static int plan_keep(struct sp_draw_cache *d, const struct sp_canvas *c, int kept,
                     struct sp_draw_plan *p)
{
    int err;
    if ((err = dtiles_clear(d)) != 0 || (kept && (err = dyn_compare(d, c)) != 0)) {
        sp_log_error("out of memory for the damaged rectangles");
        return err;
    }
    if (kept && d->any_same)
        p->same = d->same;
    for (int i = 0; p->accum_in_base && i < c->n_items; i++) /* drawn into base too */
        if (c->items[i].kind != SP_ITEM_CLIP && c->items[i].layer == SP_LAYER_ACCUM)
            dtiles_mark(d, c, i, c->items[i].first, c->items[i].first + c->items[i].count);
    p->settled_old = d->settled_old;
    p->n_new = settled_find_new(d, c);
    if (p->n_new) {
        d->stats.appended++;
        if ((err = settled_save(d, c)) != 0) {
            sp_log_error("out of memory for the settled layer's record");
            return err;
        }
    }
    if (kept) { /* base where the last frame's dynamic items were */
        if ((err = damage_runs(d)) != 0) {
            sp_log_error("out of memory for the damaged rectangles");
            return err;
        }
        p->under = SP_DRAW_UNDER_RESTORE;
        p->damage = d->damage;
        p->n_damage = d->n_damage;
    } else {
        p->under = d->has_accum ? SP_DRAW_UNDER_BASE : SP_DRAW_UNDER_RECTS;
    }
    return 0;
}

int sp_draw_cache_plan(struct sp_draw_cache *d, const struct sp_canvas *c, const float bg[4],
                       struct sp_draw_plan *p)
{
    int err = 0;
    const int kept = d->kept; /* cleared until this frame is drawn */
    d->kept = 0;
    *p = (struct sp_draw_plan){.list = c};
    for (int i = 0; i < c->n_items && !p->accum; i++)
        p->accum = c->items[i].layer == SP_LAYER_ACCUM && c->items[i].kind != SP_ITEM_CLIP;
    if (d->on) {
        if ((err = boxes_make(d, c)) != 0 || (err = lift_items(d, c, &d->lifted)) != 0) {
            sp_log_error("out of memory for the static cache's bounds");
            return err;
        }
        c = p->list = &d->lifted;
        /* also with no static item: base is then the background (or the
         * long exposure), restored only where the last frame drew */
        p->cached = order_keeps(d, c);
    }
    if (p->accum) { /* the long exposure, and base unless they touch */
        d->has_accum = 1;
        if (d->base_valid && p->cached && accum_apart(d, c))
            p->accum_in_base = 1;
        else
            d->base_valid = 0;
    }
    if (!p->cached) {
        d->stats.uncached++;
        p->under = d->has_accum ? SP_DRAW_UNDER_ACCUM : SP_DRAW_UNDER_CLEAR;
        return 0;
    }
    if ((err = key_make(d, c, bg)) != 0) {
        sp_log_error("out of memory for the static cache's key");
        return err;
    }
    int prefix = 0; /* base holds the static layer and a prefix of the settled one */
    if (d->base_valid && d->n_next == d->n_key && !memcmp(d->next, d->key, d->n_key) &&
        (prefix = settled_prefix(d, c)) < 0) {
        sp_log_error("out of memory for the settled layer's record");
        return prefix;
    }
    err = prefix ? plan_keep(d, c, kept, p) : plan_rebuild(d, c, p);
    if (err)
        return err;
    d->stats.cached++;
    if ((err = dyn_save(d, c)) != 0) {
        sp_log_error("out of memory for the damaged rectangles");
        return err;
    }
    return 0;
}

void sp_draw_cache_drawn(struct sp_draw_cache *d, const struct sp_draw_plan *p)
{
    d->kept = p->cached;
}

const float *sp_draw_cache_clip(const struct sp_draw_cache *d, int i)
{
    return d->boxes[i].clip;
}

int sp_draw_cache_run(const struct sp_draw_cache *d, const struct sp_canvas *c, int i,
                      const struct sp_draw_rect *r, int *first, int *end)
{
    const struct sp_item *it = &c->items[i];
    const float *cl = d->boxes[i].clip;
    const struct box rb = {r->rect[0], r->rect[1], r->rect[2], r->rect[3], {0, 0, 0, 0}};
    if (*first < 0) {
        if (!box_meets(&d->boxes[i], &rb))
            return 0;
        *first = it->first;
    }
    for (int k = *first; k < it->first + it->count; k++) {
        const struct box b = prim_box(c, it, k, cl);
        if (!box_meets(&b, &rb))
            continue;
        int e = k + 1;
        while (e < it->first + it->count) {
            const struct box be = prim_box(c, it, e, cl);
            if (!box_meets(&be, &rb))
                break;
            e++;
        }
        *first = k, *end = e;
        return 1;
    }
    return 0;
}

void sp_draw_cache_set(struct sp_draw_cache *d, int on)
{
    d->on = on;
    d->base_valid = 0;
    d->kept = 0;
}

void sp_draw_cache_stats(const struct sp_draw_cache *d, struct sp_draw_cache_stats *out)
{
    *out = d->stats;
}

void sp_draw_cache_destroy(struct sp_draw_cache **d)
{
    if (!*d)
        return;
    free((*d)->key);
    free((*d)->next);
    free((*d)->boxes);
    free((*d)->items);
    free((*d)->rects);
    free((*d)->patches);
    free((*d)->tiles);
    free((*d)->damage);
    free((*d)->dtiles);
    free((*d)->settled);
    free((*d)->settled_old);
    free((*d)->dyn);
    free((*d)->same);
    free(*d);
    *d = NULL;
}
