/* springpend (internal): the draw list drawn with cairo into SVG or PDF.
 * See draw_cairo.h. Built into springpend-cairo.so. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>
#include <cairo-pdf.h>
#include <cairo-svg.h>

#include "springpend/common.h"
#include "cairo_fd.h"
#include "cairo_text.h"
#include "draw_cairo.h"
#include "frame/text.h"

static void source(cairo_t *cr, const float c[4])
{
    cairo_set_source_rgba(cr, c[0], c[1], c[2], c[3]);
}

/* A lit ball like shaders/shape.frag's: light from the upper left, a
 * highlight, a darker rim. */
static void ball(cairo_t *cr, const struct sp_shape *s)
{
    const double x = s->seg[0], y = s->seg[1], r = s->style[0];
    const float *c = s->color;
    cairo_pattern_t *g = cairo_pattern_create_radial(x - 0.35 * r, y - 0.4 * r, 0, x, y, r);
    static const double stops[][2] = {{0, 1.0}, {0.45, 0.95}, {0.85, 0.62}, {1, 0.38}};
    for (int i = 0; i < 4; i++) {
        const double hi = i == 0 ? 0.45 : 0;
        cairo_pattern_add_color_stop_rgba(g, stops[i][0], fmin(1, c[0] * stops[i][1] + hi),
                                          fmin(1, c[1] * stops[i][1] + hi),
                                          fmin(1, c[2] * stops[i][1] + hi), c[3]);
    }
    cairo_set_source(cr, g);
    cairo_arc(cr, x, y, r, 0, 2 * M_PI);
    cairo_fill(cr);
    cairo_pattern_destroy(g);
}

/* A soft ellipse like shaders/shape.frag's: (1 - d^2)^2 sampled as a
 * radial gradient in the ellipse's own coordinates. */
static void soft(cairo_t *cr, const struct sp_shape *s)
{
    const float *p = s->seg, *c = s->color;
    const double rx = 0.5 * hypot(p[2] - p[0], p[3] - p[1]), ry = s->style[0];
    if (!(rx > 0 && ry > 0))
        return;
    cairo_save(cr);
    cairo_translate(cr, 0.5 * (p[0] + p[2]), 0.5 * (p[1] + p[3]));
    cairo_rotate(cr, atan2(p[3] - p[1], p[2] - p[0]));
    cairo_scale(cr, rx, ry);
    cairo_pattern_t *g = cairo_pattern_create_radial(0, 0, 0, 0, 0, 1);
    for (int i = 0; i <= 8; i++) {
        const double d = i / 8.0, f = (1 - d * d) * (1 - d * d);
        cairo_pattern_add_color_stop_rgba(g, d, c[0], c[1], c[2], c[3] * f);
    }
    cairo_set_source(cr, g);
    cairo_arc(cr, 0, 0, 1, 0, 2 * M_PI);
    cairo_fill(cr);
    cairo_pattern_destroy(g);
    cairo_restore(cr);
}

static void shape(cairo_t *cr, const struct sp_shape *s)
{
    const float *p = s->seg, hw = s->style[0];
    const int kind = (int)lroundf(s->style[1]);
    if (kind == SP_SHAPE_BALL)
        return ball(cr, s);
    if (kind == SP_SHAPE_SOFT)
        return soft(cr, s);
    source(cr, s->color);
    if (kind == SP_SHAPE_BOX) {
        cairo_rectangle(cr, fmin(p[0], p[2]), p[1] - hw, fabs(p[2] - p[0]), 2 * hw);
        cairo_fill(cr);
    } else if (p[0] == p[2] && p[1] == p[3]) {
        cairo_arc(cr, p[0], p[1], hw, 0, 2 * M_PI);
        cairo_fill(cr);
    } else {
        cairo_move_to(cr, p[0], p[1]);
        cairo_line_to(cr, p[2], p[3]);
        cairo_set_line_width(cr, 2 * hw);
        cairo_stroke(cr);
    }
}

static int similar(const struct sp_shape *a, const struct sp_shape *b)
{
    for (int k = 0; k < 4; k++)
        if (fabsf(a->color[k] - b->color[k]) > 6.0f / 255)
            return 0;
    return fabsf(a->style[0] - b->style[0]) <= 0.15f;
}

/* A polyline: one path per run of segments of about the same colour and
 * width (all of it when it has one colour). Runs meet with butt caps, so a
 * translucent curve shows no beads where they join. */
static void path(cairo_t *cr, const struct sp_shape *s, int n)
{
    int runs = 0;
    for (int i = 0; i < n; runs++) {
        int j = i + 1;
        while (j < n && similar(&s[i], &s[j]))
            j++;
        i = j;
    }
    cairo_set_line_cap(cr, runs > 1 ? CAIRO_LINE_CAP_BUTT : CAIRO_LINE_CAP_ROUND);
    for (int i = 0; i < n;) {
        int j = i + 1;
        double w = s[i].style[0];
        while (j < n && similar(&s[i], &s[j]))
            w += s[j++].style[0];
        source(cr, s[(i + j) / 2].color);
        cairo_move_to(cr, s[i].seg[0], s[i].seg[1]);
        for (int k = i; k < j; k++)
            cairo_line_to(cr, s[k].seg[2], s[k].seg[3]);
        cairo_set_line_width(cr, 2 * w / (j - i));
        cairo_stroke(cr);
        i = j;
    }
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
}

/* n shapes interleaving `lanes` polylines (sp_item.lanes): each stroked as
 * one path, lane 0 first. 0 or SP_E_NOMEM. */
static int lanes(cairo_t *cr, const struct sp_shape *s, int n, int lanes)
{
    const int per = (n + lanes - 1) / lanes;
    struct sp_shape *lane = malloc((size_t)(per ? per : 1) * sizeof(*lane));
    if (!lane) {
        sp_log_error("out of memory for a chart's curves");
        return SP_E_NOMEM;
    }
    for (int l = 0; l < lanes; l++) {
        int m = 0;
        for (int k = l; k < n; k += lanes)
            lane[m++] = s[k];
        if (m)
            path(cr, lane, m);
    }
    free(lane);
    return 0;
}

/* The SVG or PDF surface of d, pw x ph (pt or px), writing to sink, with its
 * metadata (creator, date, scene and title; the SVG's unit). NULL when it
 * cannot be made (logged; *err set). */
static cairo_surface_t *surface_make(const struct sp_draw_cairo_desc *d, struct sp_cairo_fd *sink,
                                     double pw, double ph, int paper, int *err)
{
    cairo_surface_t *surface;
    if (d->format == SP_FIGURE_PDF)
        surface = cairo_pdf_surface_create_for_stream(sp_cairo_fd_write, sink, pw, ph);
    else
        surface = cairo_svg_surface_create_for_stream(sp_cairo_fd_write, sink, pw, ph);
    const cairo_status_t st = cairo_surface_status(surface);
    if (st) {
        sp_log_error("%s: cannot create: %s", d->path, cairo_status_to_string(st));
        cairo_surface_destroy(surface);
        *err = SP_E_IO;
        return NULL;
    }
    if (d->format == SP_FIGURE_PDF) {
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "springpend " SP_VERSION);
        if (sp_cairo_pdf_date(surface)) {
            cairo_surface_destroy(surface);
            *err = SP_E_INPUT;
            return NULL;
        }
        sp_cairo_pdf_scene(surface, d->scene_file, d->command);
        /* the title as messages show it: a file name may hold bytes that
         * are not UTF-8, controls and noncharacters, which cairo refuses */
        char *title = d->title ? malloc(4 * strlen(d->title) + 1) : NULL;
        if (title) {
            sp_text_shown(d->title, 0, title, 4 * strlen(d->title) + 1);
            cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, title);
        }
        free(title);
    } else {
        cairo_svg_surface_set_document_unit(surface, paper ? CAIRO_SVG_UNIT_PT : CAIRO_SVG_UNIT_PX);
    }
    return surface;
}

/* Draws c's shapes: the accumulated layer first, then the rest in list
 * order, under their clips; stops when *cancel is set. 0 or SP_E_NOMEM. */
static int shapes_draw(cairo_t *cr, const struct sp_canvas *c, const volatile sig_atomic_t *cancel)
{
    int err = 0;
    for (int pass = 0; pass < 2 && !err; pass++) {
        for (int i = 0; i < c->n_items && !err && !(cancel && *cancel); i++) { /* stop */
            const struct sp_item *it = &c->items[i];
            if ((it->layer == SP_LAYER_ACCUM) != (pass == 0))
                continue;
            if (it->kind == SP_ITEM_CLIP) {
                cairo_reset_clip(cr);
                if (it->clip[2] > it->clip[0]) {
                    cairo_rectangle(cr, it->clip[0], it->clip[1], it->clip[2] - it->clip[0],
                                    it->clip[3] - it->clip[1]);
                    cairo_clip(cr);
                }
            } else if (it->kind == SP_ITEM_PATH && it->lanes > 1) {
                if ((err = lanes(cr, c->shapes + it->first, it->count, it->lanes)) != 0)
                    break;
            } else if (it->kind == SP_ITEM_PATH)
                path(cr, c->shapes + it->first, it->count);
            else if (it->kind == SP_ITEM_SHAPES)
                for (int k = 0; k < it->count; k++)
                    shape(cr, &c->shapes[it->first + k]);
        }
    }
    cairo_reset_clip(cr);
    return err;
}

/* Draws c's text over everything, as the GL backend draws it, in d's font;
 * a PDF records the font files drawn from. 0 or negative SP_E_... */
static int text_draw(cairo_t *cr, cairo_surface_t *surface, const struct sp_canvas *c,
                     const struct sp_draw_cairo_desc *d)
{
    struct sp_cairo_faces faces = {0};
    int err = sp_cairo_faces_make(&faces, d->font, cr);
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind != SP_ITEM_TEXT)
            continue;
        source(cr, it->color);
        err = sp_cairo_text_show(cr, &faces, it->size, it->x, it->y, c->strings + it->text);
    }
    sp_cairo_faces_destroy(&faces);
    if (d->format == SP_FIGURE_PDF) /* provenance: the font files drawn from */
        sp_cairo_pdf_fonts(surface, d->font);
    return err;
}

int sp_draw_cairo_write(const struct sp_draw_cairo_desc *d)
{
    const struct sp_canvas *c = d->canvas;
    cairo_surface_t *surface;
    cairo_status_t st;
    cairo_t *cr;
    int err = 0;

    char *svg_meta = d->format == SP_FIGURE_SVG ? sp_cairo_svg_metadata(d->scene_file, d->command) : NULL;
    struct sp_cairo_fd sink = {.fd = d->fd, .svg_metadata = svg_meta}; /* every write checked */
    const int paper = d->page_w > 0 && d->page_h > 0;
    const double pw = paper ? d->page_w : d->width, ph = paper ? d->page_h : d->height;
    if (!(surface = surface_make(d, &sink, pw, ph, paper, &err))) {
        free(svg_meta);
        return err;
    }
    cr = cairo_create(surface);
    if (paper) /* the list's px onto the page's pt */
        cairo_scale(cr, pw / d->width, ph / d->height);
    cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    if (d->background[3] > 0) {
        source(cr, d->background);
        cairo_paint(cr);
    }
    err = shapes_draw(cr, c, d->cancel);
    if (!err && d->font && c->n_strings) /* text over everything */
        err = text_draw(cr, surface, c, d);
    st = cairo_status(cr);
    cairo_destroy(cr);
    cairo_surface_finish(surface);
    if (!st)
        st = cairo_surface_status(surface);
    cairo_surface_destroy(surface);
    free(svg_meta);
    if (sink.err && !err) {
        sp_log_error("%s: cannot write: %s", d->path, strerror(sink.err));
        err = SP_E_IO;
    } else if (st && !err) {
        sp_log_error("%s: cairo failed: %s", d->path, cairo_status_to_string(st));
        err = st == CAIRO_STATUS_NO_MEMORY ? SP_E_NOMEM : SP_E_IO;
    }
    return err;
}
