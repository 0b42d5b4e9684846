/* springpend (internal): frame layout. See layout.h. */
#include <math.h>

#include "layout.h"

static int is_square(int bit)
{
    return ((1u << bit) & (SP_PANEL_PHASE_R | SP_PANEL_PHASE_THETA | SP_PANEL_POINCARE |
                           SP_PANEL_TOP)) != 0;
}

/* Stacks n cells of the given kind in area: one column, or two when a
 * column would be thinner than min_h. */
/* The panels in the order they are placed: d's order, else bit order. */
struct order {
    int bit[SP_PANEL_COUNT], n;
};

static void order_of(const struct sp_layout_desc *d, struct order *o)
{
    unsigned left = d->panels & ((1u << SP_PANEL_COUNT) - 1);
    o->n = 0;
    for (int i = 0; i < d->n_order; i++)
        if (d->order[i] >= 0 && d->order[i] < SP_PANEL_COUNT && (left >> d->order[i] & 1))
            o->bit[o->n++] = d->order[i], left &= ~(1u << d->order[i]);
    for (int b = 0; b < SP_PANEL_COUNT; b++)
        if (left >> b & 1)
            o->bit[o->n++] = b;
}

static void stack(struct sp_layout *o, const struct order *ord, int square, struct sp_rect area,
                  float min_h)
{
    int n = 0, i = 0;
    for (int k = 0; k < ord->n; k++)
        n += is_square(ord->bit[k]) == square;
    if (!n)
        return;
    const float w = area.x1 - area.x0, h = area.y1 - area.y0, g = o->gap;
    int cols = (h - (n - 1) * g) / n < min_h && n > 1 ? 2 : 1;
    if (square) /* side by side when the area is wider than tall */
        cols = w > h ? n : 1;
    const int rows = (n + cols - 1) / cols;
    const float cw = (w - (cols - 1) * g) / cols, ch = (h - (rows - 1) * g) / rows;
    for (int k = 0; k < ord->n; k++) {
        const int b = ord->bit[k];
        if (is_square(b) != square)
            continue;
        const int r = i / cols, c = i % cols;
        /* an odd last cell of a two-column stack takes the whole row */
        const int span = !square && cols == 2 && i == n - 1 && n % 2 ? 2 : 1;
        o->panel[b] = (struct sp_rect){area.x0 + c * (cw + g), area.y0 + r * (ch + g),
                                       area.x0 + c * (cw + g) + span * cw + (span - 1) * g,
                                       area.y0 + r * (ch + g) + ch};
        i++;
    }
}

/* Tiles area with the n panels of `bits` without a pendulum: the grid of
 * cols x rows whose cells are nearest (in log aspect) to each panel's
 * preferred shape, wide for strip charts, square for the others. */
static void tile(struct sp_layout *o, const struct order *ord, struct sp_rect area)
{
    const float w = area.x1 - area.x0, h = area.y1 - area.y0, g = o->gap;
    int n = ord->n, best_cols = 1;
    double best = 1e300;
    for (int cols = 1; cols <= n; cols++) {
        const int rows = (n + cols - 1) / cols;
        const double aspect = (w - (cols - 1) * g) / cols / ((h - (rows - 1) * g) / rows);
        double miss = (double)(rows * cols - n); /* empty cells */
        for (int k = 0; k < n; k++)
            miss += fabs(log(aspect / (is_square(ord->bit[k]) ? 1.0 : 2.4)));
        if (miss < best)
            best = miss, best_cols = cols;
    }
    const int cols = best_cols, rows = (n + cols - 1) / cols;
    const float ch = (h - (rows - 1) * g) / rows;
    for (int i = 0; i < n; i++) {
        const int b = ord->bit[i];
        const int r = i / cols, c = i % cols;
        /* the last row's cells share its whole width */
        const int in_row = r == rows - 1 ? n - r * cols : cols;
        const float rw = (w - (in_row - 1) * g) / in_row;
        o->panel[b] = (struct sp_rect){area.x0 + c * (rw + g), area.y0 + r * (ch + g),
                                       area.x0 + c * (rw + g) + rw, area.y0 + r * (ch + g) + ch};
    }
}

void sp_layout_compute(const struct sp_layout_desc *d, struct sp_layout *o)
{
    const float W = (float)d->width, H = (float)d->height;
    const float unit = fminf(W, H), g = roundf(0.015f * unit);
    const float top = d->title_height > 0 ? d->title_height + g : 0;
    const float bottom = d->caption_height > 0 ? d->caption_height + g : 0;
    const float Y0 = top, Hb = fmaxf(H - top - bottom, 1);
    int ns = 0, nq = 0;
    struct sp_rect view = {0, Y0, W, Y0 + Hb}, rest = {0}, strips, squares;
    struct order ord;
    order_of(d, &ord);

    *o = (struct sp_layout){.gap = g};
    if (top > 0)
        o->title = (struct sp_rect){g, g, W - g, g + d->title_height};
    if (bottom > 0)
        o->caption = (struct sp_rect){g, H - g - d->caption_height, W - g, H - g};
    for (int b = 0; b < SP_PANEL_COUNT; b++)
        if ((d->panels >> b) & 1)
            is_square(b) ? nq++ : ns++;
    if (d->no_pendulum) {
        struct sp_rect area = {g, Y0 + g, W - g, Y0 + Hb - g};
        if (d->hud_height > 0) {
            o->hud = (struct sp_rect){g, area.y0, W - g, area.y0 + d->hud_height};
            area.y0 = o->hud.y1 + g;
        }
        if (ns + nq)
            tile(o, &ord, area);
        return;
    }
    if (ns + nq) {
        if (W >= 1.15f * Hb || d->view_left) { /* landscape: the view at the left */
            const float vw = roundf(fmaxf(0.34f * W, fminf(0.8f * Hb, 0.45f * W)));
            view = (struct sp_rect){0, Y0, vw, Y0 + Hb};
            rest = (struct sp_rect){vw, Y0 + g, W - g, Y0 + Hb - g};
        } else { /* portrait or square: the view on top */
            const float share = d->view_share > 0 ? d->view_share : W >= Hb ? 0.45f : 0.36f;
            const float vh = roundf(share * Hb);
            view = (struct sp_rect){0, Y0, W, Y0 + vh};
            rest = (struct sp_rect){g, Y0 + vh, W - g, Y0 + Hb - g};
        }
        const float rw = rest.x1 - rest.x0, rh = rest.y1 - rest.y0;
        strips = squares = rest;
        if (ns && nq) {
            if (rw >= rh) { /* squares in a column at the right */
                const float side = fminf((rh - (nq - 1) * g) / nq, 0.45f * rw);
                squares.x0 = rest.x1 - side;
                strips.x1 = squares.x0 - g;
            } else { /* squares in a row at the bottom */
                const float side = fminf((rw - (nq - 1) * g) / nq, 0.45f * rh);
                squares.y0 = rest.y1 - side;
                strips.y1 = squares.y0 - g;
            }
        }
        stack(o, &ord, 0, strips, 0.16f * unit);
        stack(o, &ord, 1, squares, 0);
    }
    /* Heads-up text along the top of the view, the colourbar at its right. */
    o->camera = view;
    if (d->hud_height > 0) {
        o->hud = (struct sp_rect){view.x0 + g, view.y0 + g, view.x1 - g, view.y0 + g + d->hud_height};
        o->camera.y0 = o->hud.y1;
    }
    if (d->colorbar_width > 0) {
        o->colorbar = (struct sp_rect){view.x1 - g - d->colorbar_width, o->camera.y0 + g,
                                       view.x1 - g, view.y1 - g};
        o->camera.x1 = o->colorbar.x0 - g;
    }
}

int sp_rect_overlap(const struct sp_rect *a, const struct sp_rect *b)
{
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1;
}

int sp_rect_valid(const struct sp_rect *a)
{
    return a->x1 > a->x0 && a->y1 > a->y0;
}
