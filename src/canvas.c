/* springpend (internal): the per-frame draw list. See canvas.h. */
#include <stdlib.h>

#include "springpend/common.h"
#include "canvas.h"

void sp_canvas_reset(struct sp_canvas *c)
{
    c->n_shapes = 0;
    c->n_quads = 0;
    c->err = 0;
}

void sp_canvas_free(struct sp_canvas *c)
{
    free(c->shapes);
    free(c->quads);
    *c = (struct sp_canvas){0};
}

/* Makes room for n more items of `size` bytes in *items; 0 or SP_E_NOMEM. */
static int grow(void **items, int *cap, int used, int n, size_t size)
{
    int want = *cap ? *cap : 256;
    void *p;
    if (used + n <= *cap)
        return 0;
    while (want < used + n)
        want *= 2;
    p = realloc(*items, (size_t)want * size);
    if (!p)
        return SP_E_NOMEM;
    *items = p;
    *cap = want;
    return 0;
}

static void push(struct sp_canvas *c, float ax, float ay, float bx, float by, float hw,
                 float kind, const float color[4])
{
    if (c->err || grow((void **)&c->shapes, &c->cap_shapes, c->n_shapes, 1,
                       sizeof(*c->shapes))) {
        c->err = SP_E_NOMEM;
        return;
    }
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

void sp_canvas_rect(struct sp_canvas *c, float x0, float y0, float x1, float y1,
                    const float color[4])
{
    const float ym = 0.5f * (y0 + y1), hh = 0.5f * (y1 > y0 ? y1 - y0 : y0 - y1);
    push(c, x0, ym, x1, ym, hh, SP_SHAPE_BOX, color);
}

int sp_canvas_text(struct sp_canvas *c, int size, float x, float y, enum sp_align align,
                   const float color[4], const char *utf8)
{
    const int w = sp_font_width(c->font, size, utf8);
    int n;
    if (align == SP_ALIGN_CENTER)
        x -= 0.5f * (float)w;
    else if (align == SP_ALIGN_RIGHT)
        x -= (float)w;
    n = sp_font_layout(c->font, size, utf8, x, y, color, NULL, 0);
    if (c->err || grow((void **)&c->quads, &c->cap_quads, c->n_quads, n, sizeof(*c->quads))) {
        c->err = SP_E_NOMEM;
        return w;
    }
    c->n_quads += sp_font_layout(c->font, size, utf8, x, y, color, c->quads + c->n_quads, n);
    return w;
}
