/* springpend (internal): several scenes side by side. See compose.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "compose.h"

struct sp_compose_cells {
    struct sp_composer *cell[SP_MAX_CELLS];
    float dx[SP_MAX_CELLS], dy[SP_MAX_CELLS]; /* px: each cell's top-left corner */
    int n;
    int ss;                                    /* supersampling factor */
    struct sp_canvas merged;                   /* the cells' lists joined (n > 1) */
    int scaled;                                /* the cells share one camera scale */
};

void sp_compose_cells_grid(int width, int height, int n, int *cols, int *rows)
{
    if (n == 4) {
        *cols = *rows = 2;
    } else if (width >= height) {
        *cols = n, *rows = 1;
    } else {
        *cols = 1, *rows = n;
    }
}

int sp_compose_cells_make(struct sp_compose_cells **out, const struct sp_compose_desc *desc,
                          const struct sp_look *looks, int n)
{
    struct sp_compose_cells *c = calloc(1, sizeof(*c));
    int cols, rows, err = 0;
    *out = NULL;
    if (!c) {
        sp_log_error("out of memory for the composer");
        return SP_E_NOMEM;
    }
    c->n = n < 1 ? 1 : n > SP_MAX_CELLS ? SP_MAX_CELLS : n;
    c->ss = desc->supersample > 1 ? desc->supersample : 1;
    sp_compose_cells_grid(desc->width, desc->height, c->n, &cols, &rows);
    for (int i = 0; i < c->n && !err; i++) {
        struct sp_compose_desc d = *desc;
        d.width = desc->width / cols;
        d.height = desc->height / rows;
        d.look = looks ? &looks[i] : desc->look;
        d.font = i ? sp_compose_font(c->cell[0]) : NULL; /* one atlas for the merged list */
        c->dx[i] = (float)(i % cols * d.width);
        c->dy[i] = (float)(i / cols * d.height);
        d.cell = 1;
        if (c->n == 1)
            d = *desc;
        err = sp_compose_make(&c->cell[i], &d);
    }
    if (err) {
        sp_compose_cells_destroy(&c);
        return err;
    }
    c->merged.font = sp_compose_font(c->cell[0]);
    *out = c;
    return 0;
}

int sp_compose_cells_frame(struct sp_compose_cells *c, const struct sp_frame *frames,
                           const struct sp_canvas **out)
{
    const struct sp_canvas *cv;
    if (!c->scaled && c->n > 1) { /* one metre, one length: the smallest scale */
        double scale = INFINITY, arrow = INFINITY; /* px per m; px: the longest arrow */
        for (int i = 0; i < c->n; i++) {
            int err = sp_compose_lay_out(c->cell[i], frames[i].params);
            if (err)
                return err;
            scale = fmin(scale, sp_compose_scale(c->cell[i]));
            arrow = fmin(arrow, sp_compose_arrow_px(c->cell[i]));
        }
        for (int i = 0; i < c->n; i++) {
            sp_compose_rescale(c->cell[i], scale);
            sp_compose_shrink_arrows(c->cell[i], arrow);
        }
    }
    c->scaled = 1;
    int err = sp_compose_frame(c->cell[0], &frames[0], &cv);
    if (err || c->n == 1) {
        *out = cv;
        return err;
    }
    sp_canvas_reset(&c->merged);
    sp_canvas_append(&c->merged, cv, c->dx[0], c->dy[0]);
    for (int i = 1; i < c->n && !err; i++) {
        err = sp_compose_frame(c->cell[i], &frames[i], &cv);
        if (!err)
            sp_canvas_append(&c->merged, cv, c->dx[i], c->dy[i]);
    }
    if (!err && c->merged.err) {
        sp_log_error("out of memory for %d shapes and %d glyphs", c->merged.n_shapes,
                     c->merged.n_quads);
        err = c->merged.err;
    }
    *out = &c->merged;
    return err;
}

int sp_compose_cells_fits(const struct sp_compose_desc *desc, const struct sp_look *looks, int n,
                          const struct sp_frame *frames)
{
    struct sp_compose_cells *c = NULL;
    const struct sp_canvas *cv;
    const int muted = sp_log_muted();
    sp_log_mute(1);
    int err = sp_compose_cells_make(&c, desc, looks, n);
    if (!err)
        err = sp_compose_cells_frame(c, frames, &cv);
    sp_compose_cells_destroy(&c);
    sp_log_mute(muted);
    return !err;
}

const struct sp_font *sp_compose_cells_font(const struct sp_compose_cells *c)
{
    return sp_compose_font(c->cell[0]);
}

const struct sp_palette *sp_compose_cells_palette(const struct sp_compose_cells *c)
{
    return sp_compose_palette(c->cell[0]);
}

void sp_compose_cells_overlay(const struct sp_compose_cells *c, char *buf, size_t size)
{
    size_t used = 0;
    if (size)
        buf[0] = 0;
    for (int i = 0; i < c->n && used < size; i++) {
        char prefix[16] = "";
        if (c->n > 1)
            snprintf(prefix, sizeof(prefix), "cell%d.", i + 1);
        sp_compose_overlay(c->cell[i], prefix, c->dx[i] / c->ss, c->dy[i] / c->ss, buf + used,
                           size - used);
        while (used < size && buf[used])
            used++;
    }
}

void sp_compose_cells_destroy(struct sp_compose_cells **cp)
{
    struct sp_compose_cells *c = *cp;
    if (!c)
        return;
    for (int i = c->n - 1; i >= 0; i--) /* the others borrow cell 0's font */
        sp_compose_destroy(&c->cell[i]);
    c->merged.font = NULL;
    sp_canvas_free(&c->merged);
    free(c);
    *cp = NULL;
}
