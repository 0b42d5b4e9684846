/* springpend (internal): the draw list drawn with cairo into SVG or PDF.
 * See draw_cairo.h. Built into springpend-cairo.so. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cairo.h>
#include <cairo-ft.h>
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <ft2build.h>
#include FT_FREETYPE_H

#include "springpend/common.h"
#include "cairo_fd.h"
#include "draw_cairo.h"
#include "signals.h"
#include "text.h"

static void ft_face_done(void *face)
{
    FT_Done_Face(face);
}

/* Face i of the font as a cairo face, made on first use into faces[i]: its
 * own FT_Face (which cairo sizes as it likes), freed when cairo lets go of
 * the face. NULL when it cannot be made (logged). */
static cairo_font_face_t *face_of(const struct sp_font *f, int i, cairo_font_face_t **faces)
{
    static FT_Library lib; /* for the process: cairo's caches may outlive a document */
    static const cairo_user_data_key_t key;
    const unsigned char *data;
    size_t size;
    int index;
    FT_Face face;
    if (faces[i])
        return faces[i];
    const char *file = sp_font_face_file(f, i, &index, &data, &size);
    if ((!lib && FT_Init_FreeType(&lib)) ||
        (file ? FT_New_Face(lib, file, index, &face)
              : FT_New_Memory_Face(lib, data, (FT_Long)size, index, &face))) {
        sp_log_error("FreeType cannot open the font %s", file ? file : "DejaVu Sans (embedded)");
        return NULL;
    }
    cairo_font_face_t *cf = cairo_ft_font_face_create_for_ft_face(face, FT_LOAD_NO_HINTING);
    if (cairo_font_face_status(cf) ||
        cairo_font_face_set_user_data(cf, &key, face, ft_face_done)) {
        sp_log_error("cairo cannot use the font %s: %s", file ? file : "DejaVu Sans (embedded)",
                     cairo_status_to_string(cairo_font_face_status(cf)));
        cairo_font_face_destroy(cf);
        FT_Done_Face(face);
        return NULL;
    }
    return faces[i] = cf;
}

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

/* A text item as the glyphs text.c laid out, run by run (one face and
 * direction each) with their text and clusters, so that a PDF keeps it
 * real: selectable, and extracted in logical order. */
static int text(cairo_t *cr, const struct sp_font *f, const struct sp_item *it, const char *utf8,
                cairo_font_face_t **faces)
{
    struct sp_line l;
    int err = sp_font_shape(f, it->size, utf8, &l);
    cairo_glyph_t *g = malloc((size_t)(l.n_glyphs + 1) * sizeof(*g));
    cairo_text_cluster_t *cl = malloc((size_t)(l.n_glyphs + 1) * sizeof(*cl));
    if (!err && (!g || !cl)) {
        sp_log_error("out of memory for a text run");
        err = SP_E_NOMEM;
    }
    cairo_set_font_size(cr, sp_font_px(f, it->size));
    source(cr, it->color);
    /* runs in the text's order, so that a PDF holds the text as written
     * (pdftotext -raw returns it whole; the layout itself is visual) */
    for (int r = 0, from = -1; r < l.n_runs && !err; r++) {
        const struct sp_glyph_run *run = NULL;
        for (int k = 0; k < l.n_runs; k++)
            if (l.runs[k].start > from && (!run || l.runs[k].start < run->start))
                run = &l.runs[k];
        from = run->start;
        const struct sp_glyph *rg = l.glyphs + run->first;
        cairo_font_face_t *face = face_of(f, rg[0].face, faces);
        int n_cl = 0;
        if (!face) {
            err = SP_E_IO;
            break;
        }
        /* glyphs in the text's order (a right-to-left run's from its
         * right end: cairo 1.16 checks backward clusters' UTF-8 from the
         * wrong end), each cluster its glyphs and the text up to the next */
        for (int k = 0; k < run->count; k++) {
            const struct sp_glyph *gk = &rg[run->rtl ? run->count - 1 - k : k];
            g[k] = (cairo_glyph_t){gk->index, it->x + gk->x, it->y + gk->y};
            if (k && gk->cluster == (gk + (run->rtl ? 1 : -1))->cluster) {
                cl[n_cl - 1].num_glyphs++;
                continue;
            }
            int end = run->end; /* where this cluster's text stops */
            for (int j = k + 1; j < run->count; j++) {
                const struct sp_glyph *gj = &rg[run->rtl ? run->count - 1 - j : j];
                if (gj->cluster != gk->cluster) {
                    end = gj->cluster;
                    break;
                }
            }
            cl[n_cl++] = (cairo_text_cluster_t){end - gk->cluster, 1};
        }
        cairo_set_font_face(cr, face);
        cairo_show_text_glyphs(cr, utf8 + run->start, run->end - run->start, g, run->count, cl,
                               n_cl, 0);
    }
    free(g), free(cl);
    return err;
}

int sp_draw_cairo_write(const struct sp_draw_cairo_desc *d)
{
    const struct sp_canvas *c = d->canvas;
    cairo_surface_t *surface;
    cairo_font_options_t *fo;
    cairo_status_t st;
    cairo_t *cr;
    int err = 0;

    char *svg_meta = d->format == SP_FIGURE_SVG ? sp_cairo_svg_metadata(d->scene_file, d->command) : NULL;
    struct sp_cairo_fd sink = {.fd = d->fd, .svg_metadata = svg_meta}; /* every write checked */
    const int paper = d->page_w > 0 && d->page_h > 0;
    const double pw = paper ? d->page_w : d->width, ph = paper ? d->page_h : d->height;
    if (d->format == SP_FIGURE_PDF)
        surface = cairo_pdf_surface_create_for_stream(sp_cairo_fd_write, &sink, pw, ph);
    else
        surface = cairo_svg_surface_create_for_stream(sp_cairo_fd_write, &sink, pw, ph);
    st = cairo_surface_status(surface);
    if (st) {
        sp_log_error("%s: cannot create: %s", d->path, cairo_status_to_string(st));
        cairo_surface_destroy(surface);
        free(svg_meta);
        return SP_E_IO;
    }
    if (d->format == SP_FIGURE_PDF) {
        cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_CREATOR, "springpend " SP_VERSION);
        if (sp_cairo_pdf_date(surface)) {
            cairo_surface_destroy(surface);
            return SP_E_INPUT;
        }
        sp_cairo_pdf_scene(surface, d->scene_file, d->command);
        size_t n = 0, len = d->title ? strlen(d->title) : 0;
        while (n < len && sp_utf8_char(d->title + n))
            n += sp_utf8_char(d->title + n);
        if (d->title && n == len) /* a file name that is not UTF-8 gets no title */
            cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_TITLE, d->title);
    } else {
        cairo_svg_surface_set_document_unit(surface, paper ? CAIRO_SVG_UNIT_PT : CAIRO_SVG_UNIT_PX);
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
    /* the accumulated layer first, then the rest in order */
    for (int pass = 0; pass < 2 && !err; pass++) {
        for (int i = 0; i < c->n_items && !err && !sp_signal_seen(); i++) { /* Ctrl-C: stop */
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
    /* text over everything, as the GL backend draws it */
    if (d->font && c->n_strings) {
        cairo_font_face_t **faces = calloc((size_t)sp_font_faces(d->font), sizeof(*faces));
        if (!faces) {
            sp_log_error("out of memory for the fonts");
            err = SP_E_NOMEM;
        }
        fo = cairo_font_options_create();
        cairo_font_options_set_hint_style(fo, CAIRO_HINT_STYLE_NONE);
        cairo_font_options_set_hint_metrics(fo, CAIRO_HINT_METRICS_OFF);
        cairo_set_font_options(cr, fo);
        cairo_font_options_destroy(fo);
        for (int i = 0; i < c->n_items && !err; i++)
            if (c->items[i].kind == SP_ITEM_TEXT)
                err = text(cr, d->font, &c->items[i], c->strings + c->items[i].text, faces);
        for (int i = 0; faces && i < sp_font_faces(d->font); i++)
            cairo_font_face_destroy(faces[i]); /* cairo keeps what it still uses */
        free(faces);
        if (d->format == SP_FIGURE_PDF) { /* provenance: the font files drawn from */
            char files[2048] = "fonts: ";
            sp_font_files(d->font, files + strlen(files), sizeof(files) - strlen(files));
            cairo_pdf_surface_set_metadata(surface, CAIRO_PDF_METADATA_KEYWORDS, files);
        }
    }
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
