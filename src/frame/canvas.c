/* springpend (internal): the per-frame draw list. See canvas.h. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "base/array.h"
#include "canvas.h"

void sp_canvas_reset(struct sp_canvas *c)
{
    c->n_shapes = c->n_quads = c->n_items = c->n_strings = c->n_pixels = 0;
    c->layer = SP_LAYER_STATIC;
    c->blend = SP_BLEND_OVER;
    c->in_path = 0;
    c->err = 0;
}

void sp_canvas_free(struct sp_canvas *c)
{
    free(c->shapes);
    free(c->quads);
    free(c->items);
    free(c->strings);
    free(c->pixels);
    free(c->axes);
    *c = (struct sp_canvas){0};
}

void sp_canvas_layer(struct sp_canvas *c, enum sp_layer layer) { c->layer = layer; }
void sp_canvas_blend(struct sp_canvas *c, enum sp_blend blend) { c->blend = blend; }

/* Makes room for n more items of `size` bytes in *items; 0 or SP_E_NOMEM
 * (remembered in c->err). */
static int grow(struct sp_canvas *c, void **items, int *cap, int used, int n, size_t size)
{
    if (c->err)
        return c->err;
    size_t room = (size_t)*cap;
    if (sp_array_reserve(items, size, &room, (size_t)used + (size_t)n, 256, INT_MAX))
        return c->err = SP_E_NOMEM;
    *cap = (int)room;
    return 0;
}

/* A new item of `kind` starting at `first`; NULL when out of memory. */
static struct sp_item *new_item(struct sp_canvas *c, enum sp_item_kind kind, int first)
{
    if (grow(c, (void **)&c->items, &c->cap_items, c->n_items, 1, sizeof(*c->items)))
        return NULL;
    struct sp_item *it = &c->items[c->n_items++];
    *it = (struct sp_item){.kind = kind, .layer = c->layer, .blend = c->blend, .first = first};
    if (kind == SP_ITEM_TEXT && it->layer == SP_LAYER_SETTLED) /* shapes only (canvas.h) */
        it->layer = SP_LAYER_DYNAMIC;
    return it;
}

void sp_canvas_clip(struct sp_canvas *c, const float rect[4])
{
    struct sp_item *it = new_item(c, SP_ITEM_CLIP, c->n_shapes);
    if (it)
        memcpy(it->clip, rect ? rect : (const float[4]){0, 0, 0, 0}, sizeof(it->clip));
}

void sp_canvas_path_begin(struct sp_canvas *c)
{
    c->in_path = 1;
    new_item(c, SP_ITEM_PATH, c->n_shapes);
}

void sp_canvas_shapes_begin(struct sp_canvas *c)
{
    new_item(c, SP_ITEM_SHAPES, c->n_shapes);
}

void sp_canvas_path_lanes(struct sp_canvas *c, int n)
{
    if (c->in_path && c->n_items && c->items[c->n_items - 1].kind == SP_ITEM_PATH)
        c->items[c->n_items - 1].lanes = n;
}

void sp_canvas_path_end(struct sp_canvas *c)
{
    c->in_path = 0;
    if (c->n_items && c->items[c->n_items - 1].kind == SP_ITEM_PATH &&
        c->items[c->n_items - 1].count == 0 && c->items[c->n_items - 1].layer != SP_LAYER_SETTLED)
        c->n_items--; /* an empty path (a settled one stays: it is the same item
                         in every frame, however long) */
}

static void push(struct sp_canvas *c, float ax, float ay, float bx, float by, float hw,
                 float kind, const float color[4])
{
    struct sp_item *last = c->n_items ? &c->items[c->n_items - 1] : NULL;
    if (grow(c, (void **)&c->shapes, &c->cap_shapes, c->n_shapes, 1, sizeof(*c->shapes)))
        return;
    if (!c->in_path && (!last || last->kind != SP_ITEM_SHAPES || last->layer != c->layer ||
                        last->blend != c->blend || last->first + last->count != c->n_shapes))
        last = new_item(c, SP_ITEM_SHAPES, c->n_shapes);
    if (!last)
        return;
    last->count++;
    c->shapes[c->n_shapes++] = (struct sp_shape){
        {ax, ay, bx, by}, {hw, kind}, {color[0], color[1], color[2], color[3]}};
}

void sp_canvas_line(struct sp_canvas *c, float ax, float ay, float bx, float by, float hw,
                    const float color[4])
{
    push(c, ax, ay, bx, by, hw, SP_SHAPE_FLAT, color);
}

void sp_canvas_disc(struct sp_canvas *c, float x, float y, float radius, int ball,
                    const float color[4])
{
    push(c, x, y, x, y, radius, ball ? SP_SHAPE_BALL : SP_SHAPE_FLAT, color);
}

void sp_canvas_soft(struct sp_canvas *c, float x, float y, float rx, float ry,
                    const float color[4])
{
    push(c, x - rx, y, x + rx, y, ry, SP_SHAPE_SOFT, color);
}

void sp_canvas_rect(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                    const float color[4])
{
    const float ym = 0.5f * (y0 + y1), hh = 0.5f * (y1 > y0 ? y1 - y0 : y0 - y1);
    push(c, x0, ym, x1, ym, hh, SP_SHAPE_BOX, color);
}

/* Shapes utf8 at size, refusing a character no font has (logged,
 * c->err). 0 or an SP_E_* code. */
static int shape_text(struct sp_canvas *c, int size, const char *utf8, struct sp_line *line)
{
    int err = sp_font_shape(c->font, size, utf8, line);
    if (err) /* logged */
        return c->err = err;
    if (line->missing) { /* never a silent box */
        if (sp_font_check(c->font, "text", utf8) == 0)
            sp_log_error("text \"%s\" has a character no font draws", utf8);
        return c->err = SP_E_INPUT;
    }
    return 0;
}

int sp_canvas_text(struct sp_canvas *c, int size, float x, float y, enum sp_align align,
                   const float color[4], const char *utf8)
{
    const int len = (int)strlen(utf8) + 1;
    struct sp_line line;
    struct sp_item *it;
    int err = shape_text(c, size, utf8, &line);
    if (err == SP_E_INPUT)
        return line.width;
    if (err)
        return 0;
    const int w = line.width;
    if (align == SP_ALIGN_CENTER)
        x -= 0.5f * (float)w;
    else if (align == SP_ALIGN_RIGHT)
        x -= (float)w;
    /* at most a quad per glyph */
    if (grow(c, (void **)&c->quads, &c->cap_quads, c->n_quads, line.n_glyphs, sizeof(*c->quads)) ||
        grow(c, (void **)&c->strings, &c->cap_strings, c->n_strings, len, 1) ||
        !(it = new_item(c, SP_ITEM_TEXT, c->n_quads)))
        return w;
    it->count = sp_font_layout(c->font, size, utf8, x, y, color, c->quads + c->n_quads, line.n_glyphs);
    if (it->count < 0) { /* logged */
        c->err = it->count;
        it->count = 0;
        return w;
    }
    it->size = size;
    it->x = roundf(x);
    it->y = roundf(y);
    memcpy(it->color, color, sizeof(it->color));
    it->text = c->n_strings;
    memcpy(c->strings + c->n_strings, utf8, (size_t)len);
    c->n_strings += len;
    c->n_quads += it->count;
    return w;
}

void sp_canvas_text_turned(struct sp_canvas *c, int size, float x, float y, float scale,
                           float angle, const float color[4], const char *utf8)
{
    const int len = (int)strlen(utf8) + 1;
    struct sp_line line;
    struct sp_item *it;
    if (c->err || !utf8[0] || !(scale > 0) || shape_text(c, size, utf8, &line) ||
        grow(c, (void **)&c->strings, &c->cap_strings, c->n_strings, len, 1) ||
        !(it = new_item(c, SP_ITEM_TEXT, c->n_quads)))
        return;
    it->size = size;
    it->x = x, it->y = y;
    it->scale = scale, it->angle = angle;
    memcpy(it->color, color, sizeof(it->color));
    it->text = c->n_strings;
    memcpy(c->strings + c->n_strings, utf8, (size_t)len);
    c->n_strings += len;
}

unsigned char *sp_canvas_image(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                               int w, int h)
{
    struct sp_item *it;
    if (w < 1 || h < 1 || (size_t)w * (size_t)h > (size_t)(INT_MAX - c->n_pixels) / 4) {
        if (!c->err && w >= 1 && h >= 1) {
            sp_log_error("an image of %dx%d pixels is too large for the draw list", w, h);
            c->err = SP_E_NOMEM;
        }
        return NULL;
    }
    const int bytes = 4 * w * h;
    if (grow(c, (void **)&c->pixels, &c->cap_pixels, c->n_pixels, bytes, 1) ||
        !(it = new_item(c, SP_ITEM_IMAGE, c->n_pixels)))
        return NULL;
    it->rect[0] = x0, it->rect[1] = y0, it->rect[2] = x1, it->rect[3] = y1;
    it->iw = w, it->ih = h;
    c->n_pixels += bytes;
    return c->pixels + it->first;
}

void sp_canvas_keep_text(struct sp_canvas *c)
{
    const struct sp_item *clip = NULL;
    int n = 0;
    for (int i = 0; i < c->n_items; i++)
        if (c->items[i].kind == SP_ITEM_CLIP)
            clip = &c->items[i];
    struct sp_item last_clip = clip ? *clip : (struct sp_item){.kind = SP_ITEM_SHAPES};
    for (int i = 0; i < c->n_items; i++)
        if (c->items[i].kind == SP_ITEM_TEXT)
            c->items[n++] = c->items[i];
    c->n_items = n;
    c->n_shapes = c->n_pixels = 0;
    if (clip) { /* after the text, which it does not clip: the shapes to come */
        struct sp_item *it = new_item(c, SP_ITEM_CLIP, 0);
        if (it)
            *it = last_clip, it->first = 0;
    }
}

void sp_canvas_append(struct sp_canvas *dst, const struct sp_canvas *src, float dx, float dy)
{
    const int s0 = dst->n_shapes, q0 = dst->n_quads, t0 = dst->n_strings, p0 = dst->n_pixels;
    if (src->err)
        dst->err = src->err;
    sp_canvas_clip(dst, NULL);
    if (grow(dst, (void **)&dst->shapes, &dst->cap_shapes, s0, src->n_shapes, sizeof(*dst->shapes)) ||
        grow(dst, (void **)&dst->quads, &dst->cap_quads, q0, src->n_quads, sizeof(*dst->quads)) ||
        grow(dst, (void **)&dst->strings, &dst->cap_strings, t0, src->n_strings, 1) ||
        grow(dst, (void **)&dst->pixels, &dst->cap_pixels, p0, src->n_pixels, 1) ||
        grow(dst, (void **)&dst->items, &dst->cap_items, dst->n_items, src->n_items, sizeof(*dst->items)))
        return;
    for (int i = 0; i < src->n_shapes; i++) {
        struct sp_shape *sh = &dst->shapes[s0 + i];
        *sh = src->shapes[i];
        sh->seg[0] += dx, sh->seg[1] += dy, sh->seg[2] += dx, sh->seg[3] += dy;
    }
    for (int i = 0; i < src->n_quads; i++) {
        struct sp_glyph_quad *q = &dst->quads[q0 + i];
        *q = src->quads[i];
        q->rect[0] += dx, q->rect[1] += dy, q->rect[2] += dx, q->rect[3] += dy;
    }
    if (src->n_strings) /* (none: both may be NULL) */
        memcpy(dst->strings + t0, src->strings, (size_t)src->n_strings);
    if (src->n_pixels)
        memcpy(dst->pixels + p0, src->pixels, (size_t)src->n_pixels);
    for (int i = 0; i < src->n_items; i++) {
        struct sp_item *it = &dst->items[dst->n_items++];
        *it = src->items[i];
        if (it->kind == SP_ITEM_TEXT) {
            it->first += q0;
            it->text += t0;
            it->x += dx, it->y += dy;
        } else if (it->kind == SP_ITEM_CLIP) {
            if (it->clip[2] > it->clip[0])
                it->clip[0] += dx, it->clip[1] += dy, it->clip[2] += dx, it->clip[3] += dy;
        } else if (it->kind == SP_ITEM_IMAGE) {
            it->first += p0;
            it->rect[0] += dx, it->rect[1] += dy, it->rect[2] += dx, it->rect[3] += dy;
        } else {
            it->first += s0;
        }
    }
    dst->n_shapes += src->n_shapes;
    dst->n_quads += src->n_quads;
    dst->n_strings += src->n_strings;
    dst->n_pixels += src->n_pixels;
}
