/* springpend (internal): the draw list drawn with cairo into SVG or PDF.
 * See draw_cairo.h. Built into springpend-cairo.so. */
#include <errno.h>
#include <stdint.h>
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
#include "springpend/outfile.h"

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

/* Segment j continues run i: about the same colour and width, starting
 * where segment j - 1 ends (a long exposure's trail leaves out repeats,
 * cover.h, so its polyline has gaps). */
static int continues(const struct sp_shape *s, int i, int j)
{
    return similar(&s[i], &s[j]) && s[j].seg[0] == s[j - 1].seg[2] &&
           s[j].seg[1] == s[j - 1].seg[3];
}

/* A polyline: one path per run of joined segments of about the same colour
 * and width (all of it when it has one colour and no gap). Runs meet with
 * butt caps, so a translucent curve shows no beads where they join. */
static void path(cairo_t *cr, const struct sp_shape *s, int n, const float *max_over)
{
    int runs = 0;
    for (int i = 0; i < n; runs++) {
        int j = i + 1;
        while (j < n && continues(s, i, j))
            j++;
        i = j;
    }
    cairo_set_line_cap(cr, runs > 1 && !max_over ? CAIRO_LINE_CAP_BUTT : CAIRO_LINE_CAP_ROUND);
    for (int i = 0; i < n;) {
        int j = i + 1;
        double w = s[i].style[0];
        while (j < n && continues(s, i, j))
            w += s[j++].style[0];
        if (max_over) { /* GL_MAX's colour over the background, opaque */
            const float *c = s[(i + j) / 2].color;
            source(cr, (const float[4]){fmaxf(c[0] * c[3], max_over[0]), fmaxf(c[1] * c[3], max_over[1]),
                                        fmaxf(c[2] * c[3], max_over[2]), 1});
        } else {
            source(cr, s[(i + j) / 2].color);
        }
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
            path(cr, lane, m, NULL);
    }
    free(lane);
    return 0;
}

/* An IMAGE item: its pixels premultiplied into a cairo image (RGB24 when
 * every one is opaque, so that a PDF holds no soft mask), stretched over
 * its rectangle with sharp cells. 0 or SP_E_NOMEM (logged). */
static int image(cairo_t *cr, const struct sp_canvas *c, const struct sp_item *it)
{
    const unsigned char *p = c->pixels + it->first;
    const size_t n = (size_t)it->iw * (size_t)it->ih;
    int opaque = 1;
    for (size_t k = 0; k < n && opaque; k++)
        opaque = p[4 * k + 3] == 255;
    cairo_surface_t *img = cairo_image_surface_create(opaque ? CAIRO_FORMAT_RGB24 : CAIRO_FORMAT_ARGB32,
                                                      it->iw, it->ih);
    if (cairo_surface_status(img)) {
        sp_log_error("cannot make an image of %dx%d pixels: %s", it->iw, it->ih,
                     cairo_status_to_string(cairo_surface_status(img)));
        cairo_surface_destroy(img);
        return SP_E_NOMEM;
    }
    cairo_surface_flush(img);
    unsigned char *data = cairo_image_surface_get_data(img);
    const int stride = cairo_image_surface_get_stride(img);
    for (int j = 0; j < it->ih; j++)
        for (int i = 0; i < it->iw; i++) {
            const unsigned char *q = p + 4 * ((size_t)j * (size_t)it->iw + (size_t)i);
            const uint32_t a = q[3];
            uint32_t v = a << 24;
            for (int k = 0; k < 3; k++)
                v |= ((q[k] * a + 127) / 255) << (16 - 8 * k);
            ((uint32_t *)(data + (size_t)j * (size_t)stride))[i] = v;
        }
    cairo_surface_mark_dirty(img);
    cairo_save(cr);
    cairo_translate(cr, it->rect[0], it->rect[1]);
    cairo_scale(cr, (it->rect[2] - it->rect[0]) / it->iw, (it->rect[3] - it->rect[1]) / it->ih);
    cairo_set_source_surface(cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);
    return 0;
}

/* A document being drawn (draw_cairo.h). */
struct sp_draw_cairo {
    struct sp_draw_cairo_desc d;
    cairo_surface_t *surface;
    cairo_t *cr;
    struct sp_cairo_fd sink;
    char *svg_meta;
    int px_w, px_h; /* a raster's size; 0: a document */
    int err;        /* the first failure (logged) */
};

/* The items of c but its text, on cr (user space: the list's px): the
 * accumulated layer first, then the rest in order; the clip ends with
 * them. 0, or SP_E_NOMEM (logged). */
static int draw_shapes(cairo_t *cr, const struct sp_canvas *c, const float background[4],
                       const volatile sig_atomic_t *cancel)
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
            } else if (it->kind == SP_ITEM_IMAGE) {
                err = image(cr, c, it);
            } else if (it->kind == SP_ITEM_PATH && it->lanes > 1) {
                err = lanes(cr, c->shapes + it->first, it->count, it->lanes);
            } else if (it->kind == SP_ITEM_PATH) {
                /* A long exposure's settled trail (max-blended, over an
                 * opaque background): each run opaque in the colour GL's
                 * GL_MAX gives it there, so laps over the same place do not
                 * stack into a brighter, banded band as translucent strokes
                 * would, and the figure looks as the PNG does. */
                const int max = it->layer == SP_LAYER_ACCUM && it->blend == SP_BLEND_MAX &&
                                background[3] >= 1;
                path(cr, c->shapes + it->first, it->count, max ? background : NULL);
            } else if (it->kind == SP_ITEM_SHAPES) {
                for (int k = 0; k < it->count; k++)
                    shape(cr, &c->shapes[it->first + k]);
            }
        }
    }
    cairo_reset_clip(cr);
    return err;
}

/* The text of c over everything, as the GL backend draws it; a PDF (pdf
 * not NULL) is told the font files drawn from. 0, or SP_E_NOMEM / SP_E_IO. */
static int draw_text(cairo_t *cr, const struct sp_canvas *c, const struct sp_font *font,
                     cairo_surface_t *pdf)
{
    int err = 0;
    if (!font || !c->n_strings)
        return 0;
    struct sp_cairo_faces faces = {0};
    err = sp_cairo_faces_make(&faces, font, cr);
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind != SP_ITEM_TEXT)
            continue;
        source(cr, it->color);
        if (it->scale > 0) { /* turned text: the size's layout, scaled and turned */
            cairo_save(cr);
            cairo_translate(cr, it->x, it->y);
            cairo_rotate(cr, it->angle);
            cairo_scale(cr, it->scale, it->scale);
            err = sp_cairo_text_show(cr, &faces, it->size, 0, 0, c->strings + it->text);
            cairo_restore(cr);
        } else {
            err = sp_cairo_text_show(cr, &faces, it->size, it->x, it->y, c->strings + it->text);
        }
    }
    sp_cairo_faces_destroy(&faces);
    if (pdf) /* provenance: the font files drawn from */
        sp_cairo_pdf_fonts(pdf, font);
    return err;
}

/* The first failure of cr or the document, logged; 0 when none. */
static int cairo_err(struct sp_draw_cairo *dc, cairo_status_t st)
{
    if (dc->err || !st)
        return dc->err;
    if (dc->sink.err && sp_outfile_write_was_stopped())
        return dc->err = SP_E_INTERRUPTED; /* a FIFO's reader did not read: the caller says it */
    if (dc->sink.err)
        sp_log_error("%s: cannot write: %s", dc->d.path, strerror(dc->sink.err));
    else
        sp_log_error("%s: cairo failed: %s", dc->d.path, cairo_status_to_string(st));
    return dc->err = dc->sink.err ? SP_E_IO : st == CAIRO_STATUS_NO_MEMORY ? SP_E_NOMEM : SP_E_IO;
}

int sp_draw_cairo_begin(struct sp_draw_cairo **out, const struct sp_draw_cairo_desc *d, int px_w,
                        int px_h)
{
    struct sp_draw_cairo *dc = calloc(1, sizeof(*dc));
    *out = NULL;
    if (!dc) {
        sp_log_error("%s: out of memory", d->path);
        return SP_E_NOMEM;
    }
    dc->d = *d;
    dc->px_w = px_w > 0 ? px_w : 0, dc->px_h = px_w > 0 ? px_h : 0;
    const int paper = d->page_w > 0 && d->page_h > 0;
    const double pw = paper ? d->page_w : d->width, ph = paper ? d->page_h : d->height;
    if (dc->px_w) {
        dc->surface = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, px_w, px_h);
    } else {
        dc->svg_meta = d->format == SP_FIGURE_SVG ? sp_cairo_svg_metadata(d->scene_file, d->command, NULL)
                                                  : NULL;
        dc->sink = (struct sp_cairo_fd){.fd = d->fd, .svg_metadata = dc->svg_meta}; /* every write checked */
        if (d->format == SP_FIGURE_PDF)
            dc->surface = cairo_pdf_surface_create_for_stream(sp_cairo_fd_write, &dc->sink, pw, ph);
        else
            dc->surface = cairo_svg_surface_create_for_stream(sp_cairo_fd_write, &dc->sink, pw, ph);
    }
    cairo_status_t st = cairo_surface_status(dc->surface);
    if (st) {
        if (dc->px_w)
            sp_log_error("%s: cannot make a %dx%d px image: %s", d->path, px_w, px_h,
                         cairo_status_to_string(st));
        else
            sp_log_error("%s: cannot create: %s", d->path, cairo_status_to_string(st));
        const int err = dc->px_w && st == CAIRO_STATUS_NO_MEMORY ? SP_E_NOMEM : SP_E_IO;
        cairo_surface_destroy(dc->surface);
        free(dc->svg_meta);
        free(dc);
        return err;
    }
    if (!dc->px_w && d->format == SP_FIGURE_PDF) {
        cairo_pdf_surface_set_metadata(dc->surface, CAIRO_PDF_METADATA_CREATOR, "springpend " SP_VERSION);
        if (sp_cairo_pdf_date(dc->surface)) {
            cairo_surface_destroy(dc->surface);
            free(dc);
            return SP_E_INPUT;
        }
        sp_cairo_pdf_scene(dc->surface, d->scene_file, d->command);
        /* the title as messages show it: a file name may hold bytes that
         * are not UTF-8, controls and noncharacters, which cairo refuses */
        char *title = d->title ? malloc(4 * strlen(d->title) + 1) : NULL;
        if (title) {
            sp_text_shown(d->title, 0, title, 4 * strlen(d->title) + 1);
            cairo_pdf_surface_set_metadata(dc->surface, CAIRO_PDF_METADATA_TITLE, title);
        }
        free(title);
    } else if (!dc->px_w) {
        cairo_svg_surface_set_document_unit(dc->surface, paper ? CAIRO_SVG_UNIT_PT : CAIRO_SVG_UNIT_PX);
    }
    dc->cr = cairo_create(dc->surface);
    if (dc->px_w) /* the list's px onto the raster's */
        cairo_scale(dc->cr, px_w / d->width, px_h / d->height);
    else if (paper) /* the list's px onto the page's pt */
        cairo_scale(dc->cr, pw / d->width, ph / d->height);
    cairo_set_line_cap(dc->cr, CAIRO_LINE_CAP_ROUND);
    cairo_set_line_join(dc->cr, CAIRO_LINE_JOIN_ROUND);
    if (d->background[3] > 0) {
        source(dc->cr, d->background);
        cairo_paint(dc->cr);
    }
    *out = dc;
    return 0;
}

int sp_draw_cairo_shapes(struct sp_draw_cairo *dc, const struct sp_canvas *c)
{
    if (!dc->err)
        dc->err = draw_shapes(dc->cr, c, dc->d.background, dc->d.cancel);
    return cairo_err(dc, cairo_status(dc->cr));
}

int sp_draw_cairo_end(struct sp_draw_cairo **dcp, const struct sp_canvas *c, struct sp_image *out)
{
    struct sp_draw_cairo *dc = *dcp;
    if (out)
        *out = (struct sp_image){0};
    if (!dc)
        return 0;
    *dcp = NULL;
    if (c && !dc->err)
        dc->err = draw_shapes(dc->cr, c, dc->d.background, dc->d.cancel);
    if (c && !dc->err)
        dc->err = draw_text(dc->cr, c, dc->d.font,
                            !dc->px_w && dc->d.format == SP_FIGURE_PDF ? dc->surface : NULL);
    if (c)
        cairo_err(dc, cairo_status(dc->cr));
    cairo_destroy(dc->cr);
    if (c && !dc->err && dc->px_w && out) {
        cairo_surface_flush(dc->surface);
        if (!(dc->err = sp_image_alloc(out, dc->px_w, dc->px_h))) {
            const unsigned char *data = cairo_image_surface_get_data(dc->surface);
            const int stride = cairo_image_surface_get_stride(dc->surface);
            for (int y = 0; y < dc->px_h; y++)
                for (int x = 0; x < dc->px_w; x++) { /* premultiplied native ARGB to straight RGBA */
                    const uint32_t p = ((const uint32_t *)(data + (size_t)y * (size_t)stride))[x];
                    const unsigned a = p >> 24;
                    uint8_t *q = out->pixels + (size_t)y * (size_t)out->stride + 4 * (size_t)x;
                    for (int k = 0; k < 3; k++) {
                        const unsigned v = (p >> (16 - 8 * k)) & 255;
                        q[k] = (uint8_t)(a ? (v * 255 + a / 2) / a : 0);
                    }
                    q[3] = (uint8_t)a;
                }
        }
    }
    if (c && !dc->err && dc->svg_meta) { /* provenance: the font files drawn from */
        char fonts[2048] = "";
        if (dc->d.font && c->n_strings)
            sp_cairo_font_names(dc->d.font, fonts, sizeof(fonts));
        char *meta = sp_cairo_svg_metadata(dc->d.scene_file, dc->d.command, fonts);
        if (meta) /* else the record without them rather than none */
            free(dc->svg_meta), dc->svg_meta = meta, dc->sink.svg_metadata = meta;
    }
    cairo_surface_finish(dc->surface); /* a document's last bytes */
    if (c)
        cairo_err(dc, cairo_surface_status(dc->surface));
    if (c && !dc->err && dc->sink.err)
        cairo_err(dc, CAIRO_STATUS_WRITE_ERROR);
    cairo_surface_destroy(dc->surface);
    free(dc->svg_meta);
    const int err = c ? dc->err : 0;
    free(dc);
    return err;
}

int sp_draw_cairo_raster(const struct sp_draw_cairo_desc *d, int px_w, int px_h,
                         struct sp_image *out)
{
    struct sp_draw_cairo *dc;
    int err = sp_draw_cairo_begin(&dc, d, px_w, px_h);
    *out = (struct sp_image){0};
    err = err ? err : sp_draw_cairo_end(&dc, d->canvas, out);
    if (err)
        sp_image_free(out);
    return err;
}

int sp_draw_cairo_write(const struct sp_draw_cairo_desc *d)
{
    struct sp_draw_cairo *dc;
    int err = sp_draw_cairo_begin(&dc, d, 0, 0);
    return err ? err : sp_draw_cairo_end(&dc, d->canvas, NULL);
}

const char *sp_draw_cairo_version(void)
{
    return "cairo " CAIRO_VERSION_STRING;
}

void sp_draw_cairo_done(void)
{
    cairo_debug_reset_static_data();
}
