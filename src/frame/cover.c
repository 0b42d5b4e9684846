/* springpend: a long exposure's covered cells (cover.h). */
#include <math.h>
#include <stdlib.h>

#include "cover.h"

/* Cells of half a pixel up to this many, else larger cells, at most
 * MAX_CELLS of them (16.8 MB: a 4K drawing in whole pixels; a poster's
 * drawing of 30000 px a side in cells of 10 px: attack20 #3, where the map
 * had grown to 2.3 GB). */
#define FINE_CELLS 4.2e6
#define MAX_CELLS 8.4e6

static int cover_make(struct sp_cover *c, int width, int height)
{
    const double area = (double)width * height;
    c->cell = area * 4 <= FINE_CELLS ? 0.5f : (float)fmax(1.0, sqrt(area / MAX_CELLS));
    c->w = (int)ceilf(width / c->cell);
    c->h = (int)ceilf(height / c->cell);
    c->bits = c->w > 0 && c->h > 0 ? calloc((size_t)c->w * (size_t)c->h, sizeof(*c->bits)) : NULL;
    c->failed = !c->bits;
    return !c->failed;
}

int sp_cover_new(struct sp_cover *c, int width, int height, const float a[2], const float b[2],
                 int color)
{
    if (c->failed || (!c->bits && !cover_make(c, width, height)))
        return 1;
    const uint16_t bit = (uint16_t)(1u << color);
    const float dx = b[0] - a[0], dy = b[1] - a[1];
    /* samples half a cell apart along the centre line: every cell it crosses */
    const float len = sqrtf(dx * dx + dy * dy);
    const int n = len < 1e6f ? (int)ceilf(2 * len / c->cell) + 1 : 1 << 21;
    int added = 0;
    for (int k = 0; k <= n; k++) {
        const float x = (a[0] + dx * k / n) / c->cell, y = (a[1] + dy * k / n) / c->cell;
        if (!(x >= 0 && y >= 0 && x < c->w && y < c->h))
            continue; /* outside the drawing: nothing to show */
        uint16_t *cell = &c->bits[(size_t)(int)y * (size_t)c->w + (size_t)(int)x];
        added |= !(*cell & bit);
        *cell |= bit;
    }
    return added;
}

int sp_cover_color(float position)
{
    const int k = (int)(position * SP_COVER_COLORS);
    return k < 0 ? 0 : k >= SP_COVER_COLORS ? SP_COVER_COLORS - 1 : k;
}

void sp_cover_destroy(struct sp_cover *c)
{
    free(c->bits);
    *c = (struct sp_cover){0};
}
