/* springpend: a sweep's figure, drawn with cairo straight from its CSV (see
 * sweep.h): a Lyapunov map with a colour bar (two keys) or line (one key),
 * an orbit diagram (dots), a Poincare mosaic (dots coloured by orbit). The
 * look is the scene's theme and colormap (panels.c's palette), text in
 * DejaVu Sans. Built as springpend-plot.so, loaded on first use, so that
 * cairo costs only the commands that draw.
 * To do: move onto the figures' backend-neutral draw list when it lands. */
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <errno.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cairo_fd.h"
#include "panels.h"
#include "signals.h"
#include "springpend/common.h"
#include "springpend/outfile.h"
#include "analysis.h"
#include "sweep.h"

/* The figure being drawn (the module draws one at a time): its page and
 * the scale of its text. By default 900 x 600 pt with 12 pt ticks, 14 pt
 * labels and a 17 pt title (u = 1); at a printed size (sweep --size 8.6cm)
 * the page is that size and u sets the labels in [view] font_size (10 pt
 * by default: 8.6 pt ticks, 12 pt title, matplotlib's proportions), with
 * 0.8 pt axes and 3.5 pt ticks, and the margins follow the labels. */
static struct {
    double w, h;       /* page, pt */
    double u;          /* text and the offsets around it: times the default's */
    int print;         /* a printed size: margins measured, short titles */
    double lw, tick;   /* axes line width and tick length, pt */
    const char *title; /* NULL: the measure's own; "" = none */
    const struct sp_view *v; /* [view]'s figure keys: xlabel, ylabel, colorbar_label,
                                legend, marker_size, panel_titles, panel_labels */
} G = {900, 600, 1, 0, 1, 5, NULL, NULL};
#define W G.w
#define H G.h
#define U(x) ((x) * G.u)
#define PNG_SCALE_DEFAULT 2 /* px per pt without a printed size */
/* A Lyapunov map's image, pixels a side at most: more than the plot's
 * 720 pt (1440 PNG px) can show, far less than cairo's limit (32767). */
#define MAP_MAX_PX 2048

/* The plot area and the data range it shows. */
struct frame {
    double x0, y0, w, h;       /* plot rectangle, pt (y0 top) */
    double xlo, xhi, ylo, yhi; /* data range */
};

static double px(const struct frame *f, double x)
{
    return f->x0 + (x - f->xlo) / (f->xhi - f->xlo) * f->w;
}

static double py(const struct frame *f, double y)
{
    return f->y0 + f->h - (y - f->ylo) / (f->yhi - f->ylo) * f->h;
}

static void set_rgba(cairo_t *cr, const float c[4])
{
    cairo_set_source_rgba(cr, c[0], c[1], c[2], c[3]);
}

/* Round tick spacing (1, 2, 5 x 10^k) for about n ticks over [lo, hi]. */
static double tick_step(double lo, double hi, int n)
{
    double raw = (hi - lo) / n, mag = pow(10, floor(log10(raw))), r = raw / mag;
    return (r < 1.5 ? 1 : r < 3.5 ? 2 : r < 7.5 ? 5 : 10) * mag;
}

/* Widens a range that is empty or not finite. */
static void fix_range(double *lo, double *hi)
{
    if (!isfinite(*lo) || !isfinite(*hi))
        *lo = 0, *hi = 1;
    if (*hi - *lo < 1e-12 * fmax(1, fabs(*lo))) {
        double d = fmax(fabs(*lo) * 0.05, 1e-3);
        *lo -= d, *hi += d;
    }
}

static void text_at(cairo_t *cr, double x, double y, const char *s, double ax, double ay)
{
    cairo_text_extents_t e;
    cairo_text_extents(cr, s, &e);
    cairo_move_to(cr, x - ax * e.width - e.x_bearing, y - ay * e.height - e.y_bearing);
    cairo_show_text(cr, s);
}

static void fmt_tick(char *buf, size_t size, double v, double step)
{
    int dec = step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
    if (fabs(v) < step * 1e-6)
        v = 0;
    snprintf(buf, size, "%.*f", dec, v);
}

/* The y ticks' step (draw_axes's) and their labels' widest width, pt. */
static double ylabels_width(cairo_t *cr, const struct frame *f)
{
    char buf[64];
    cairo_text_extents_t e;
    double sy = tick_step(f->ylo, f->yhi, G.print ? (int)fmax(2, f->h / U(45)) : 6), wmax = 0;
    cairo_save(cr);
    cairo_set_font_size(cr, U(12));
    for (double v = ceil(f->ylo / sy - 1e-9) * sy; v <= f->yhi + 1e-9 * sy; v += sy) {
        fmt_tick(buf, sizeof(buf), v, sy);
        cairo_text_extents(cr, buf, &e);
        wmax = fmax(wmax, e.width);
    }
    cairo_restore(cr);
    return wmax;
}

/* Places the plot rectangle of f (its data range set) on the page: the
 * default figure's fixed margins, right = `right` pt (room for a colour
 * bar or legend); at a printed size margins that fit the labels, right =
 * print_right pt. */
static void place(cairo_t *cr, struct frame *f, double right, double print_right)
{
    if (!G.print) {
        f->x0 = 80, f->y0 = 56, f->w = W - 80 - right, f->h = H - 116;
        return;
    }
    const int none = (G.title && !G.title[0]) || (!G.title && !G.v->panel_titles);
    const double title = none && !G.v->panel_labels ? 0 : U(17) * 1.25;
    f->y0 = U(6) + title + U(6);
    f->h = H - f->y0 - (G.tick + U(4) + U(12) * 1.2 + U(5) + U(14) * 1.25 + U(4));
    f->h = fmax(f->h, U(20));
    /* the left margin depends on the y labels, which depend on the height */
    f->x0 = U(4) + U(14) * 1.2 + U(6) + ylabels_width(cr, f) + U(4) + G.tick;
    f->w = fmax(W - f->x0 - print_right, U(20));
}

/* Axes, ticks, grid and labels around the frame. */
static void draw_axes(cairo_t *cr, const struct frame *f, const struct sp_palette *pal,
                      const char *xlabel, const char *ylabel)
{
    char buf[64];
    if (G.v->xlabel[0]) /* [view] xlabel, ylabel: the axes' own names */
        xlabel = G.v->xlabel;
    if (G.v->ylabel[0])
        ylabel = G.v->ylabel;
    cairo_set_font_size(cr, U(12));
    double sx = tick_step(f->xlo, f->xhi, G.print ? (int)fmax(2, f->w / U(55)) : 8);
    double sy = tick_step(f->ylo, f->yhi, G.print ? (int)fmax(2, f->h / U(45)) : 6);
    cairo_set_line_width(cr, G.print ? 0.5 * G.lw : G.lw);
    for (double v = ceil(f->xlo / sx - 1e-9) * sx; v <= f->xhi + 1e-9 * sx; v += sx) {
        double x = px(f, v);
        set_rgba(cr, pal->grid);
        cairo_move_to(cr, x, f->y0), cairo_line_to(cr, x, f->y0 + f->h), cairo_stroke(cr);
        set_rgba(cr, pal->axis);
        cairo_set_line_width(cr, G.lw);
        cairo_move_to(cr, x, f->y0 + f->h), cairo_line_to(cr, x, f->y0 + f->h + G.tick);
        cairo_stroke(cr);
        cairo_set_line_width(cr, G.print ? 0.5 * G.lw : G.lw);
        fmt_tick(buf, sizeof(buf), v, sx);
        set_rgba(cr, pal->muted);
        text_at(cr, x, f->y0 + f->h + G.tick + U(4), buf, 0.5, 0);
    }
    for (double v = ceil(f->ylo / sy - 1e-9) * sy; v <= f->yhi + 1e-9 * sy; v += sy) {
        double y = py(f, v);
        set_rgba(cr, pal->grid);
        cairo_move_to(cr, f->x0, y), cairo_line_to(cr, f->x0 + f->w, y), cairo_stroke(cr);
        set_rgba(cr, pal->axis);
        cairo_set_line_width(cr, G.lw);
        cairo_move_to(cr, f->x0 - G.tick, y), cairo_line_to(cr, f->x0, y), cairo_stroke(cr);
        cairo_set_line_width(cr, G.print ? 0.5 * G.lw : G.lw);
        fmt_tick(buf, sizeof(buf), v, sy);
        set_rgba(cr, pal->muted);
        text_at(cr, f->x0 - G.tick - U(4), y, buf, 1, 0.5);
    }
    set_rgba(cr, pal->axis);
    cairo_set_line_width(cr, G.lw);
    cairo_rectangle(cr, f->x0, f->y0, f->w, f->h);
    cairo_stroke(cr);
    cairo_set_font_size(cr, U(14));
    set_rgba(cr, pal->text);
    text_at(cr, f->x0 + f->w / 2, f->y0 + f->h + U(30), xlabel, 0.5, 0);
    cairo_save(cr);
    /* the y axis's name clear of its widest tick label */
    cairo_translate(cr, f->x0 - (G.print ? G.tick + U(4) + ylabels_width(cr, f) + U(12) : 58),
                    f->y0 + f->h / 2);
    cairo_rotate(cr, -M_PI / 2);
    text_at(cr, 0, 0, ylabel, 0.5, 0.5);
    cairo_restore(cr);
}

/* "initial.angle (degrees)" */
static void key_label(char *buf, size_t size, const char *key)
{
    const char *unit = sp_scene_key_unit(key);
    if (unit && unit[0] != '(')
        snprintf(buf, size, "%s (%s)", key, unit);
    else
        snprintf(buf, size, "%s", key);
}

/* ---- reading rows ---- */

/* One row: the point, its axis values, and up to eight numbers. */
struct row {
    long point;
    double key[SP_SWEEP_MAX_AXES];
    double v[8];
};

static int next_row(FILE *fp, const struct sp_sweep_desc *d, int nv, struct row *r)
{
    char line[512], *p, *end;
    if (sp_signal_seen() || !fgets(line, sizeof(line), fp)) /* Ctrl-C: stop drawing */
        return 0;
    r->point = strtol(line, &p, 10);
    for (int a = 0; a < d->n_axes; a++) {
        r->key[a] = strtod(p + 1, &end);
        p = end;
    }
    for (int i = 0; i < nv; i++) {
        r->v[i] = strtod(p + 1, &end);
        p = end;
    }
    return 1;
}

/* Rewinds to the first row. Returns 0 or SP_E_INPUT. */
static int to_rows(FILE *fp, const char *name, struct sp_sweep_desc *d)
{
    char line[1024];
    rewind(fp);
    if (!fgets(line, sizeof(line), fp) || (line[strcspn(line, "\n")] = 0, 0) ||
        sp_sweep_parse_header(line, d) || !fgets(line, sizeof(line), fp)) {
        sp_log_error("%s:1: not a sweep CSV", name);
        return SP_E_INPUT;
    }
    return 0;
}

/* ---- the figures ---- */

static void draw_title(cairo_t *cr, const struct sp_sweep_desc *d, const struct sp_palette *pal,
                       const char *what, const char *short_what, const struct frame *f)
{
    char buf[256];
    if (G.v->panel_labels) { /* the figure is panel (a) */
        cairo_set_font_size(cr, U(17));
        set_rgba(cr, pal->text);
        text_at(cr, G.print ? U(4) : 10, G.print ? U(6) : 10, G.v->panel_labels == 1 ? "(a)" : "(A)",
                0, 0);
    }
    if ((G.title && !G.title[0]) || (!G.title && !G.v->panel_titles))
        return; /* [view] title = "" or panel_titles = false: none */
    if (G.print || G.title) { /* one line: [view] title, or the measure's short name */
        cairo_set_font_size(cr, U(17));
        set_rgba(cr, pal->text);
        if (G.print)
            text_at(cr, f->x0 + f->w / 2, U(6), G.title ? G.title : short_what, 0.5, 0);
        else
            text_at(cr, 80, 10, G.title, 0, 0);
        if (G.print)
            return;
    }
    cairo_set_font_size(cr, 17);
    set_rgba(cr, pal->text);
    snprintf(buf, sizeof(buf), "%s: %s", d->scene, what);
    if (!G.title)
        text_at(cr, 80, 10, buf, 0, 0);
    cairo_set_font_size(cr, 12);
    set_rgba(cr, pal->muted);
    char energy[48] = "", transient[48] = "";
    if (d->measure == SP_MEASURE_POINCARE)
        snprintf(energy, sizeof(energy), "energy %.6g J, ", d->energy);
    if (d->transient > 0)
        snprintf(transient, sizeof(transient), " after a %g s transient", d->transient);
    char sampled[128] = "";
    if (d->measure == SP_MEASURE_ORBIT && d->driven)
        snprintf(sampled, sizeof(sampled), "%s at t = k/f (stroboscopic)%s; ",
                 d->peak == SP_PEAK_R ? "r" : "θ",
                 d->peak == SP_PEAK_R ? " and the largest r per period"
                 : d->peak            ? " and the largest |θ| per period" : "");
    else if (d->measure == SP_MEASURE_SPECTRUM)
        snprintf(sampled, sizeof(sampled), "Benettin, QR (modified Gram-Schmidt) every τ ≈ 1 s; ");
    else if (d->measure == SP_MEASURE_BASINS)
        snprintf(sampled, sizeof(sampled), "stroboscopic map (t = k/f) settled by recurrence; ");
    snprintf(buf, sizeof(buf), "%s%sover %g s%s, %s at dt = %g s", sampled, energy, d->time,
             transient, d->method, d->dt);
    text_at(cr, 80, 34, buf, 0, 0);
}

static void colormap_rgb(const struct sp_sweep_desc *d, double t, float rgb[3])
{
    sp_colormap(d->colormap, (float)t, rgb);
}

/* The room a colour bar (draw_colorbar) takes right of the plot at a
 * printed size, pt. */
static double colorbar_room(cairo_t *cr, double lo, double hi)
{
    struct frame f = {0, 0, 1, 1, 0, 1, lo, hi};
    return U(14) + U(12) + G.tick + U(3) + ylabels_width(cr, &f) + U(6) + U(14) * 1.2 + U(4);
}

/* A colour bar from t0 to t1 of the colormap, ticks lo..hi. By default at
 * (x, y), h tall, its label above; at a printed size right of the plot f,
 * as tall, its label turned along it. */
static void draw_colorbar(cairo_t *cr, const struct sp_sweep_desc *d, const struct sp_palette *pal,
                          double x, double y, double h, double lo, double hi, const char *label,
                          const struct frame *pf, double t0, double t1)
{
    const int n = 128;
    const double bw = G.print ? U(12) : 18;
    if (G.print)
        x = pf->x0 + pf->w + U(14), y = pf->y0, h = pf->h;
    for (int i = 0; i < n; i++) {
        float rgb[3];
        colormap_rgb(d, t0 + (t1 - t0) * (i + 0.5) / n, rgb);
        cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
        cairo_rectangle(cr, x, y + h - (i + 1) * h / n, bw, h / n + 0.5);
        cairo_fill(cr);
    }
    set_rgba(cr, pal->axis);
    cairo_set_line_width(cr, G.lw);
    cairo_rectangle(cr, x, y, bw, h);
    cairo_stroke(cr);
    double step = tick_step(lo, hi, G.print ? (int)fmax(2, h / U(45)) : 6);
    char buf[64];
    cairo_set_font_size(cr, U(12));
    for (double v = ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step) {
        double yy = y + h - (v - lo) / (hi - lo) * h;
        set_rgba(cr, pal->axis);
        cairo_move_to(cr, x + bw, yy), cairo_line_to(cr, x + bw + G.tick, yy), cairo_stroke(cr);
        fmt_tick(buf, sizeof(buf), v, step);
        set_rgba(cr, pal->muted);
        text_at(cr, x + bw + G.tick + U(3), yy, buf, 0, 0.5);
    }
    cairo_set_font_size(cr, U(14));
    set_rgba(cr, pal->text);
    if (G.v->colorbar_label[0])
        label = G.v->colorbar_label;
    if (!G.print) {
        text_at(cr, x + 9, y - 10, label, 0.5, 1);
        return;
    }
    struct frame tf = {0, 0, 1, 1, 0, 1, lo, hi};
    cairo_save(cr);
    cairo_translate(cr, x + bw + G.tick + U(3) + ylabels_width(cr, &tf) + U(6) + U(7), y + h / 2);
    cairo_rotate(cr, -M_PI / 2);
    text_at(cr, 0, 0, label, 0.5, 0.5);
    cairo_restore(cr);
}

/* The one-number measures, drawn as a line over one key or a map over two:
 * the title, the y axis's (or colour bar's) label, and the legend of a
 * line's two series (the first value of a row, then the second; NULL: the
 * line shows the first alone). */
static const struct scalar_look {
    const char *title, *label, *series[2];
} scalar_looks[SP_MEASURE_COUNT] = {
    [SP_MEASURE_LYAPUNOV] = {"largest Lyapunov exponent", "λ (1/s)", {"λ over T", "λ over T/2"}},
    [SP_MEASURE_PRECESSION] = {"precession of the swing plane per exchange",
                               "Δφ (° per exchange)", {"precession per exchange", NULL}},
};

static int draw_lyapunov(cairo_t *cr, FILE *fp, const struct sp_sweep_desc *d,
                         const struct sp_palette *pal)
{
    const struct scalar_look *look = &scalar_looks[d->measure];
    const struct sp_sweep_axis *ax = &d->axis[0], *ay = &d->axis[1];
    long n = sp_sweep_points(d);
    double *lam = malloc(sizeof(double) * (size_t)n), *half = malloc(sizeof(double) * (size_t)n);
    struct row r;
    if (!lam || !half) {
        free(lam), free(half);
        sp_log_error("out of memory for a figure of %ld points", n);
        return SP_E_NOMEM;
    }
    for (long i = 0; i < n; i++)
        lam[i] = half[i] = NAN;
    double lo = INFINITY, hi = -INFINITY;
    while (next_row(fp, d, 2, &r))
        if (r.point >= 0 && r.point < n) {
            lam[r.point] = r.v[0], half[r.point] = r.v[1];
            for (int k = 0; k < (d->n_axes == 1 && look->series[1] ? 2 : 1); k++) /* a line: both */
                if (isfinite(r.v[k]))
                    lo = fmin(lo, r.v[k]), hi = fmax(hi, r.v[k]);
        }
    if (lo > 0)
        lo = 0;
    fix_range(&lo, &hi);
    char xl[96], yl[96];
    key_label(xl, sizeof(xl), ax->key);
    if (d->n_axes == 1) {
        struct frame f = {80, 56, W - 110, H - 116, ax->from, ax->to, lo, hi + 0.05 * (hi - lo)};
        fix_range(&f.xlo, &f.xhi);
        place(cr, &f, 30, U(18));
        draw_title(cr, d, pal, look->title, look->title, &f);
        draw_axes(cr, &f, pal, xl, look->label);
        cairo_save(cr);
        cairo_rectangle(cr, f.x0, f.y0, f.w, f.h);
        cairo_clip(cr);
        for (int pass = look->series[1] ? 0 : 1; pass < 2; pass++) {
            const double *v = pass ? lam : half;
            set_rgba(cr, pass ? pal->series[1] : pal->muted);
            cairo_set_line_width(cr, pass ? 1.6 : 1.0);
            int pen = 0;
            for (long i = 0; i < n; i++) {
                double x = px(&f, sp_sweep_axis_value(ax, (int)i));
                if (!isfinite(v[i])) {
                    pen = 0;
                    continue;
                }
                if (pen)
                    cairo_line_to(cr, x, py(&f, v[i]));
                else
                    cairo_move_to(cr, x, py(&f, v[i]));
                pen = 1;
            }
            cairo_stroke(cr);
        }
        cairo_restore(cr);
        cairo_set_font_size(cr, U(12));
        set_rgba(cr, pal->series[1]);
        if (!G.v->legend)
            text_at(cr, f.x0 + f.w - U(8), f.y0 + U(8), look->series[0], 1, 0);
        set_rgba(cr, pal->muted);
        if (!G.v->legend && look->series[1])
            text_at(cr, f.x0 + f.w - U(8), f.y0 + U(24), look->series[1], 1, 0);
    } else {
        /* cells centred on the grid values */
        double dx = ax->count > 1 ? (ax->to - ax->from) / (ax->count - 1) : 1;
        double dy = ay->count > 1 ? (ay->to - ay->from) / (ay->count - 1) : 1;
        struct frame f = {80, 56, W - 200, H - 116, ax->from - dx / 2, ax->to + dx / 2,
                          ay->from - dy / 2, ay->to + dy / 2};
        place(cr, &f, 120, colorbar_room(cr, lo, hi));
        draw_title(cr, d, pal, look->title, look->title, &f);
        /* one image pixel per grid point up to MAP_MAX_PX a side (cairo
         * makes none wider than 32767); beyond, each pixel is the mean of
         * the finite values of its block of points */
        const int iw = ax->count < MAP_MAX_PX ? ax->count : MAP_MAX_PX;
        const int ih = ay->count < MAP_MAX_PX ? ay->count : MAP_MAX_PX;
        cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, iw, ih);
        if (cairo_surface_status(img)) {
            sp_log_error("cannot make the map's %dx%d image: %s", iw, ih,
                         cairo_status_to_string(cairo_surface_status(img)));
            cairo_surface_destroy(img);
            free(lam), free(half);
            return SP_E_NOMEM;
        }
        unsigned char *data = cairo_image_surface_get_data(img);
        int stride = cairo_image_surface_get_stride(img);
        cairo_surface_flush(img);
        for (int j = 0; j < ih; j++)
            for (int i = 0; i < iw; i++) {
                const long x0 = (long)i * ax->count / iw, x1 = (long)(i + 1) * ax->count / iw;
                const long y0 = (long)j * ay->count / ih, y1 = (long)(j + 1) * ay->count / ih;
                double sum = 0;
                long got = 0;
                for (long y = y0; y < y1; y++)
                    for (long x = x0; x < x1; x++)
                        if (isfinite(lam[y * ax->count + x]))
                            sum += lam[y * ax->count + x], got++;
                float rgb[3] = {pal->muted[0] * 0.5f, pal->muted[1] * 0.5f, pal->muted[2] * 0.5f};
                if (got)
                    colormap_rgb(d, (sum / (double)got - lo) / (hi - lo), rgb);
                uint32_t *px32 = (uint32_t *)(data + (size_t)(ih - 1 - j) * (size_t)stride) + i;
                *px32 = (uint32_t)lrintf(rgb[0] * 255) << 16 |
                        (uint32_t)lrintf(rgb[1] * 255) << 8 | (uint32_t)lrintf(rgb[2] * 255);
            }
        cairo_surface_mark_dirty(img);
        cairo_save(cr);
        cairo_translate(cr, f.x0, f.y0);
        cairo_scale(cr, f.w / iw, f.h / ih);
        cairo_set_source_surface(cr, img, 0, 0);
        cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
        cairo_paint(cr);
        cairo_restore(cr);
        cairo_surface_destroy(img);
        key_label(yl, sizeof(yl), ay->key);
        draw_axes(cr, &f, pal, xl, yl);
        draw_colorbar(cr, d, pal, f.x0 + f.w + 30, f.y0 + 20, f.h - 20, lo, hi, look->label, &f, 0, 1);
    }
    free(lam), free(half);
    return 0;
}

/* A continued branch's colour: up, down, or none (not continued). */
static const float *branch_colour(const struct sp_palette *pal, int branch)
{
    return branch < 0 ? pal->series[3] : pal->series[1];
}

/* A branch's colour halfway to the background: the peaks' rings, opaque so
 * that many in one place do not darken into the branch's own colour. */
static void peak_colour(const struct sp_palette *pal, const float *c, float out[4])
{
    for (int i = 0; i < 3; i++)
        out[i] = 0.5f * (c[i] + pal->background[i]);
    out[3] = 1;
}

/* What an orbit diagram with --continue or --peak samples, in the corner. */
static void orbit_legend(cairo_t *cr, const struct sp_sweep_desc *d, const struct sp_palette *pal,
                         const struct frame *f)
{
    const char *q = d->peak == SP_PEAK_R ? "r" : "θ";
    char buf[160];
    double y = f->y0 + U(8);
    int lines = (d->cont == SP_CONTINUE_BOTH ? 2 : 1) * (d->peak ? 2 : 1) + (d->cont != 0);
    cairo_set_font_size(cr, U(12));
    cairo_text_extents_t e;
    cairo_text_extents(cr, "each value starts from the last one's state", &e);
    const double bw = G.print ? fmin(e.width + U(16), f->w - U(2)) : 288;
    cairo_set_source_rgba(cr, pal->background[0], pal->background[1], pal->background[2], 0.85);
    cairo_rectangle(cr, f->x0 + f->w - bw - U(2), f->y0 + U(2), bw, U(16) * lines + U(10));
    cairo_fill(cr);
    for (int br = 1; br >= -1; br -= 2) {
        if (d->cont != SP_CONTINUE_BOTH && br != (d->cont == SP_CONTINUE_DOWN ? -1 : 1))
            continue;
        const float *c = branch_colour(pal, br);
        snprintf(buf, sizeof(buf), "%s%s at t = k/f", !d->cont ? "" : br > 0 ? "up: " : "down: ",
                 q);
        set_rgba(cr, c);
        text_at(cr, f->x0 + f->w - U(8), y, buf, 1, 0);
        y += U(16);
        if (d->peak) {
            float light[4];
            peak_colour(pal, c, light);
            set_rgba(cr, light);
            snprintf(buf, sizeof(buf), "○ largest %s%s%s over each period",
                     d->peak == SP_PEAK_R ? "" : "|", q, d->peak == SP_PEAK_R ? "" : "|");
            text_at(cr, f->x0 + f->w - U(8), y, buf, 1, 0);
            y += U(16);
        }
    }
    if (d->cont) {
        set_rgba(cr, pal->muted);
        text_at(cr, f->x0 + f->w - U(8), y, "each value starts from the last one's state", 1, 0);
    }
}

/* Orbit diagram and Poincare mosaic: two passes over the rows, for the range
 * and for the dots. */
static int draw_dots(cairo_t *cr, FILE *fp, const char *name, struct sp_sweep_desc *d,
                     const struct sp_palette *pal)
{
    const int orbit = d->measure == SP_MEASURE_ORBIT;
    const int ext = orbit && (d->cont || d->peak); /* t,theta,r,branch,peak */
    const int nv = ext ? 5 : 3;
    struct row r;
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    long n = sp_sweep_points(d), dots = 0;
    /* orbit: x = the key, y = theta (driven; r with --peak r) or r; poincare:
     * x = r, y = dr/dt */
#define XV (orbit ? r.key[0] : r.v[1])
#define YV (orbit ? (d->driven && d->peak != SP_PEAK_R ? r.v[1] : r.v[2]) : r.v[2])
    while (next_row(fp, d, nv, &r)) {
        if (!isfinite(XV) || !isfinite(YV))
            continue;
        xlo = fmin(xlo, XV), xhi = fmax(xhi, XV), ylo = fmin(ylo, YV), yhi = fmax(yhi, YV);
        if (d->peak && isfinite(r.v[4]))
            ylo = fmin(ylo, r.v[4]), yhi = fmax(yhi, r.v[4]);
        dots++;
    }
    if (orbit)
        xlo = d->axis[0].from, xhi = d->axis[0].to;
    fix_range(&xlo, &xhi);
    fix_range(&ylo, &yhi);
    double mx = orbit ? 0 : 0.04 * (xhi - xlo), my = 0.05 * (yhi - ylo);
    struct frame f = {80, 56, W - 110, H - 116, xlo - mx, xhi + mx, ylo - my, yhi + my};
    char xl[96];
    key_label(xl, sizeof(xl), d->axis[0].key);
    place(cr, &f, 30, orbit ? U(18) : colorbar_room(cr, d->axis[0].from, d->axis[0].to));
    draw_title(cr, d, pal, orbit ? (d->driven ? "orbit diagram, once per drive period"
                                               : "orbit diagram at the Poincaré crossings")
                                 : "Poincaré sections (θ = 0, θ̇ > 0), one colour per orbit",
               orbit ? "orbit diagram" : "Poincaré sections", &f);
    draw_axes(cr, &f, pal, orbit ? xl : "r (m)",
              orbit ? (d->driven && d->peak != SP_PEAK_R ? "θ (degrees)" : "r (m)")
                    : "ṙ (m/s)");
    if (to_rows(fp, name, d))
        return SP_E_INPUT;
    cairo_save(cr);
    cairo_rectangle(cr, f.x0, f.y0, f.w, f.h);
    cairo_clip(cr);
    /* dots fade with their number, so dense regions read as density */
    double radius = G.v->marker_size > 0 ? 0.5 * G.v->marker_size : ext ? 1.1 : orbit ? 0.7 : 0.9;
    double alpha = fmin(0.9, fmax(0.15, 3e4 / (double)(dots + 1)));
    while (next_row(fp, d, nv, &r)) {
        if (!isfinite(XV) || !isfinite(YV))
            continue;
        if (ext) {
            const float *c = branch_colour(pal, (int)r.v[3]);
            if (d->peak && isfinite(r.v[4])) { /* the period's peak: a light ring */
                float light[4];
                peak_colour(pal, c, light);
                set_rgba(cr, light);
                cairo_set_line_width(cr, 0.7);
                cairo_new_sub_path(cr);
                cairo_arc(cr, px(&f, XV), py(&f, r.v[4]), 1.8, 0, 2 * M_PI);
                cairo_stroke(cr);
            }
            cairo_set_source_rgba(cr, c[0], c[1], c[2], alpha);
        } else if (orbit) {
            cairo_set_source_rgba(cr, pal->series[1][0], pal->series[1][1], pal->series[1][2],
                                  alpha);
        } else {
            float rgb[3];
            colormap_rgb(d, 0.1 + 0.85 * (n > 1 ? (double)r.point / (n - 1) : 0.5), rgb);
            cairo_set_source_rgba(cr, rgb[0], rgb[1], rgb[2], fmax(alpha, 0.5));
        }
        cairo_rectangle(cr, px(&f, XV) - radius, py(&f, YV) - radius, 2 * radius, 2 * radius);
        cairo_fill(cr);
    }
#undef XV
#undef YV
    cairo_restore(cr);
    if (ext && !G.v->legend) /* over the dots */
        orbit_legend(cr, d, pal, &f);
    if (!orbit && G.print) { /* which colour is which start: a colour bar */
        double lo = d->axis[0].from, hi = d->axis[0].to;
        fix_range(&lo, &hi);
        draw_colorbar(cr, d, pal, 0, 0, 0, lo, hi, xl, &f, 0.1, 0.95);
    } else if (!orbit) {
        /* which colour is which start: a small gradient over the first key */
        const double x0 = W - 250, y0 = 22, w = 150;
        for (int i = 0; i < 64; i++) {
            float rgb[3];
            colormap_rgb(d, 0.1 + 0.85 * (i + 0.5) / 64, rgb);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            cairo_rectangle(cr, x0 + i * w / 64, y0, w / 64 + 0.3, 10);
            cairo_fill(cr);
        }
        char buf[64];
        cairo_set_font_size(cr, 11);
        set_rgba(cr, pal->muted);
        snprintf(buf, sizeof(buf), "%g", d->axis[0].from);
        text_at(cr, x0 - 5, y0 + 5, buf, 1, 0.5);
        snprintf(buf, sizeof(buf), "%g", d->axis[0].to);
        text_at(cr, x0 + w + 5, y0 + 5, buf, 0, 0.5);
        text_at(cr, x0 + w / 2, y0 - 4, G.v->colorbar_label[0] ? G.v->colorbar_label : xl, 0.5, 1);
    }
    return 0;
}

/* ---- the Lyapunov spectrum ---- */

/* One point: each lambda_j against T (log T axis), the convergence figure;
 * one key: the final four against it; two keys: a map of lambda_1 with the
 * lyapunov map's look. */
static int draw_spectrum(cairo_t *cr, FILE *fp, const struct sp_sweep_desc *d,
                         const struct sp_palette *pal)
{
    const long n = sp_sweep_points(d);
    const int conv = n == 1;
    struct row r;
    long cap = 64, m = 0;
    double *x = malloc(sizeof(double) * (size_t)cap), (*y)[5] = malloc(sizeof(*y) * (size_t)cap);
    double lo = INFINITY, hi = -INFINITY;
    int ret = 0;
    if (!x || !y)
        goto nomem;
    long last_point = -1;
    /* a map: the last row of each point (T = time) */
    while (next_row(fp, d, 7, &r)) {
        if (!conv && r.point == last_point)
            m--; /* an earlier T of this point: replaced */
        last_point = r.point;
        if (m == cap) {
            cap *= 2;
            double *nx = realloc(x, sizeof(double) * (size_t)cap);
            double(*ny)[5] = realloc(y, sizeof(*y) * (size_t)cap);
            if (nx)
                x = nx;
            if (ny)
                y = ny;
            if (!nx || !ny)
                goto nomem;
        }
        x[m] = conv ? r.v[0] : (double)r.point;
        for (int j = 0; j < 4; j++) {
            y[m][j] = r.v[1 + j];
            if (isfinite(r.v[1 + j]) && (d->n_axes < 2 || j == 0))
                lo = fmin(lo, r.v[1 + j]), hi = fmax(hi, r.v[1 + j]);
        }
        y[m][4] = r.v[6]; /* Kaplan-Yorke */
        m++;
    }
    fix_range(&lo, &hi);
    char xl[96], yl[96], buf[160];
    key_label(xl, sizeof(xl), d->axis[0].key);
    if (d->n_axes == 2) {
        /* a map of lambda_1 */
        const struct sp_sweep_axis *ax = &d->axis[0], *ay = &d->axis[1];
        double dx = ax->count > 1 ? (ax->to - ax->from) / (ax->count - 1) : 1;
        double dy = ay->count > 1 ? (ay->to - ay->from) / (ay->count - 1) : 1;
        struct frame f = {80, 56, W - 200, H - 116, ax->from - dx / 2, ax->to + dx / 2,
                          ay->from - dy / 2, ay->to + dy / 2};
        place(cr, &f, 120, colorbar_room(cr, lo, hi));
        draw_title(cr, d, pal, "Lyapunov spectrum", "Lyapunov spectrum", &f);
        for (long i = 0; i < m; i++) {
            int idx[SP_SWEEP_MAX_AXES];
            sp_sweep_point_index(d, (long)x[i], idx);
            float rgb[3] = {pal->muted[0] * 0.5f, pal->muted[1] * 0.5f, pal->muted[2] * 0.5f};
            if (isfinite(y[i][0]))
                colormap_rgb(d, (y[i][0] - lo) / (hi - lo), rgb);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            double cx = px(&f, sp_sweep_axis_value(ax, idx[0]) - dx / 2);
            double cy = py(&f, sp_sweep_axis_value(ay, idx[1]) + dy / 2);
            cairo_rectangle(cr, cx, cy, f.w / ax->count + 0.3, f.h / ay->count + 0.3);
            cairo_fill(cr);
        }
        key_label(yl, sizeof(yl), ay->key);
        draw_axes(cr, &f, pal, xl, yl);
        draw_colorbar(cr, d, pal, f.x0 + f.w + 30, f.y0 + 20, f.h - 20, lo, hi, "λ1 (1/s)", &f, 0, 1);
        goto done;
    }
    double pad = 0.06 * (hi - lo);
    struct frame f = {80, 56, W - 110, H - 116, 0, 1, lo - pad, hi + pad};
    if (conv) {
        f.xlo = log10(x[0] > 0 ? x[0] : 1);
        f.xhi = log10(m ? fmax(x[m - 1], x[0] * 10) : 10);
    } else {
        f.xlo = d->axis[0].from, f.xhi = d->axis[0].to;
    }
    fix_range(&f.xlo, &f.xhi);
    place(cr, &f, 30, U(18));
    draw_title(cr, d, pal, conv ? "Lyapunov spectrum: running values against T"
                                : "Lyapunov spectrum", "Lyapunov spectrum", &f);
    draw_axes(cr, &f, pal, conv ? "log10 T (s)" : xl, "λ (1/s)");
    /* zero, where lambda_2 and lambda_3 of a free orbit belong */
    set_rgba(cr, pal->axis);
    cairo_set_line_width(cr, 0.8);
    cairo_move_to(cr, f.x0, py(&f, 0)), cairo_line_to(cr, f.x0 + f.w, py(&f, 0));
    cairo_stroke(cr);
    cairo_save(cr);
    cairo_rectangle(cr, f.x0, f.y0, f.w, f.h);
    cairo_clip(cr);
    static const int colour[4] = {1, 2, 3, 0};
    for (int j = 0; j < 4; j++) {
        set_rgba(cr, pal->series[colour[j]]);
        cairo_set_line_width(cr, 1.6);
        int pen = 0;
        for (long i = 0; i < m; i++) {
            double xv = conv ? log10(x[i]) : sp_sweep_axis_value(&d->axis[0], (int)x[i]);
            if (!isfinite(y[i][j])) {
                pen = 0;
                continue;
            }
            if (pen)
                cairo_line_to(cr, px(&f, xv), py(&f, y[i][j]));
            else
                cairo_move_to(cr, px(&f, xv), py(&f, y[i][j]));
            pen = 1;
        }
        cairo_stroke(cr);
    }
    cairo_restore(cr);
    cairo_set_font_size(cr, U(12));
    for (int j = 0; j < 4 && !G.v->legend; j++) {
        set_rgba(cr, pal->series[colour[j]]);
        if (conv && m)
            snprintf(buf, sizeof(buf), "λ%d = %.4f 1/s", j + 1, y[m - 1][j]);
        else
            snprintf(buf, sizeof(buf), "λ%d", j + 1);
        text_at(cr, f.x0 + f.w - U(8), f.y0 + U(8 + 16 * j), buf, 1, 0);
    }
    if (conv && m && !G.v->legend) {
        set_rgba(cr, pal->muted);
        snprintf(buf, sizeof(buf), "sum %.3g 1/s, Kaplan-Yorke dimension %.3f",
                 y[m - 1][0] + y[m - 1][1] + y[m - 1][2] + y[m - 1][3], y[m - 1][4]);
        text_at(cr, f.x0 + f.w - U(8), f.y0 + U(8 + 16 * 4), buf, 1, 0);
    }
done:
    free(x), free(y);
    return ret;
nomem:
    free(x), free(y);
    sp_log_error("out of memory for a spectrum figure");
    return SP_E_NOMEM;
}

/* ---- basins of attraction ---- */

/* The map, one colour per attractor (the colormap's spread for periodic
 * ones, grey for undecided), and the legend with each basin's fraction. */
static int draw_basins(cairo_t *cr, FILE *fp, const struct sp_sweep_desc *d,
                       const struct sp_palette *pal)
{
    struct sp_basin_map map;
    int ret = sp_basins_read(fp, d, &map);
    if (ret)
        return ret;
    const struct sp_sweep_axis *ax = &d->axis[0], *ay = &d->axis[1];
    /* Okabe and Ito's colour-blind-safe set, then lighter and darker turns */
    static const unsigned okabe_ito[] = {0xE69F00, 0x56B4E9, 0x009E73, 0xF0E442,
                                         0x0072B2, 0xD55E00, 0xCC79A7, 0x882255};
    float rgb[SP_BASINS_MAX_ATTRACTORS][3];
    for (int a = 0, k = 0; a < map.n_attractors; a++, k++) {
        if (map.att[a].period > 0) {
            unsigned c = okabe_ito[k % 8];
            float shade = k < 8 ? 1.0f : k < 16 ? 0.6f : 1.3f;
            for (int i = 0; i < 3; i++)
                rgb[a][i] = fminf(1, shade * (float)((c >> (16 - 8 * i)) & 255) / 255);
        } else {
            float g = map.att[a].period == 0 ? 0.55f : 0.8f;
            rgb[a][0] = rgb[a][1] = rgb[a][2] = g;
        }
    }
    char xl[96], yl[96], buf[200];
    key_label(xl, sizeof(xl), ax->key);
    key_label(yl, sizeof(yl), ay->key);
    double dx = ax->count > 1 ? (ax->to - ax->from) / (ax->count - 1) : 1;
    double dy = ay->count > 1 ? (ay->to - ay->from) / (ay->count - 1) : 1;
    struct frame f = {80, 56, W - 380, H - 116, ax->from - dx / 2, ax->to + dx / 2,
                      ay->from - dy / 2, ay->to + dy / 2};
    place(cr, &f, 300, U(300));
    draw_title(cr, d, pal, "basins of attraction", "basins of attraction", &f);
    cairo_surface_t *img = cairo_image_surface_create(CAIRO_FORMAT_RGB24, ax->count, ay->count);
    unsigned char *data = cairo_image_surface_get_data(img);
    int stride = cairo_image_surface_get_stride(img);
    cairo_surface_flush(img);
    for (long p = 0; p < (long)map.nx * map.ny; p++) {
        int idx[SP_SWEEP_MAX_AXES], a = map.label[p];
        sp_sweep_point_index(d, p, idx);
        float black[3] = {0, 0, 0};
        const float *c = a >= 0 ? rgb[a] : black;
        uint32_t *px32 = (uint32_t *)(data + (size_t)(ay->count - 1 - idx[1]) * stride) + idx[0];
        *px32 = (uint32_t)lrintf(c[0] * 255) << 16 | (uint32_t)lrintf(c[1] * 255) << 8 |
                (uint32_t)lrintf(c[2] * 255);
    }
    cairo_surface_mark_dirty(img);
    cairo_save(cr);
    cairo_translate(cr, f.x0, f.y0);
    cairo_scale(cr, f.w / ax->count, f.h / ay->count);
    cairo_set_source_surface(cr, img, 0, 0);
    cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
    cairo_paint(cr);
    cairo_restore(cr);
    cairo_surface_destroy(img);
    draw_axes(cr, &f, pal, xl, yl);
    /* the legend */
    long all = 0;
    for (int a = 0; a < map.n_attractors; a++)
        all += map.att[a].count;
    double lx = f.x0 + f.w + U(20), ly = f.y0 + U(4);
    cairo_set_font_size(cr, U(11));
    for (int a = 0; a < map.n_attractors && !G.v->legend; a++, ly += U(30)) {
        cairo_set_source_rgb(cr, rgb[a][0], rgb[a][1], rgb[a][2]);
        cairo_rectangle(cr, lx, ly, U(14), U(14));
        cairo_fill(cr);
        set_rgba(cr, pal->axis);
        cairo_set_line_width(cr, 0.6);
        cairo_rectangle(cr, lx, ly, U(14), U(14));
        cairo_stroke(cr);
        set_rgba(cr, pal->text);
        snprintf(buf, sizeof(buf), "%.1f%%  %s", all ? 100.0 * map.att[a].count / all : 0.0,
                 map.att[a].label);
        char *comma = map.att[a].period > 0 ? strstr(buf, ", θ") : NULL;
        if (comma) { /* the state on a second line */
            *comma = 0;
            text_at(cr, lx + U(20), ly, buf, 0, 0);
            set_rgba(cr, pal->muted);
            text_at(cr, lx + U(20), ly + U(14), comma + 2, 0, 0);
        } else {
            text_at(cr, lx + U(20), ly, buf, 0, 0);
        }
    }
    set_rgba(cr, pal->text);
    cairo_set_font_size(cr, U(12));
    snprintf(buf, sizeof(buf), "S_b = %.3f, S_bb = %.3f", map.entropy, map.boundary_entropy);
    text_at(cr, lx, ly + U(8), buf, 0, 0);
    set_rgba(cr, pal->muted);
    cairo_set_font_size(cr, U(10));
    snprintf(buf, sizeof(buf), "basin entropies, nats, %dx%d boxes", map.box, map.box);
    text_at(cr, lx, ly + U(26), buf, 0, 0);
    if (map.blown_up) {
        snprintf(buf, sizeof(buf), "%ld blown up (black)", map.blown_up);
        text_at(cr, lx, ly + U(42), buf, 0, 0);
    }
    sp_basins_free(&map);
    return 0;
}

int sp_sweep_plot(FILE *csv, const char *csv_name, const char *path,
                  const struct sp_plot_style *style, struct sp_outfile *figure)
{
    struct sp_sweep_desc d;
    struct sp_scene look;
    struct sp_palette pal;
    struct sp_outfile out;
    *figure = (struct sp_outfile){.fd = -1, .slot = -1};
    int ret = to_rows(csv, csv_name, &d);
    if (ret)
        return ret;
    sp_scene_defaults(&look);
    if (style && style->view) {
        look.view = *style->view;
        d.theme = look.view.theme, d.colormap = look.view.colormap;
    }
    look.view.theme = d.theme;
    sp_palette_get(&look.view, &pal);
    /* the page and the text's scale (G) */
    const int print = style && style->page_w > 0;
    const double body = look.view.font_size > 0 ? look.view.font_size : print ? 10 : 14;
    G.print = print;
    G.w = print ? style->page_w : 900, G.h = print ? style->page_h : 600;
    G.u = body / 14 * (look.view.font_scale > 0 ? look.view.font_scale : 1);
    G.lw = print ? 0.8 : 1, G.tick = print ? 3.5 : 5;
    G.title = style && style->title_set ? look.view.title : NULL;
    G.v = &look.view;
    const double png_scale = print ? (style->dpi > 0 ? style->dpi : 300) / 72 : PNG_SCALE_DEFAULT;
    /* cairo writes front to back: a device or stdout is fine */
    if ((ret = sp_outfile_open(&out, path, SP_OUTFILE_STREAM)))
        return ret;
    const char *ext = strrchr(path, '.');
    char *svg_meta = !strcasecmp(ext, ".svg") && style ? sp_cairo_svg_metadata(style->scene_file, style->command) : NULL;
    struct sp_cairo_fd sink = {.fd = out.fd, .svg_metadata = svg_meta}; /* every write checked */
    cairo_surface_t *s;
    if (!strcasecmp(ext, ".svg"))
        s = cairo_svg_surface_create_for_stream(sp_cairo_fd_write, &sink, W, H);
    else if (!strcasecmp(ext, ".pdf"))
        s = cairo_pdf_surface_create_for_stream(sp_cairo_fd_write, &sink, W, H);
    else
        s = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, (int)lround(W * png_scale),
                                       (int)lround(H * png_scale));
    if (!strcasecmp(ext, ".pdf") && (ret = sp_cairo_pdf_date(s))) { /* bytes that repeat */
        cairo_surface_destroy(s);
        sp_outfile_discard(&out);
        free(svg_meta);
        return ret;
    }
    if (!strcasecmp(ext, ".pdf") && style)
        sp_cairo_pdf_scene(s, style->scene_file, style->command);
    cairo_t *cr = cairo_create(s);
    if (cairo_status(cr)) { /* the surface's error, too: nothing to draw on */
        sp_log_error("cannot make the figure %s: %s", path, cairo_status_to_string(cairo_status(cr)));
        cairo_destroy(cr);
        cairo_surface_destroy(s);
        sp_outfile_discard(&out);
        free(svg_meta);
        return SP_E_IO;
    }
    if (!strcasecmp(ext, ".png"))
        cairo_scale(cr, lround(W * png_scale) / W, lround(H * png_scale) / H);
    cairo_select_font_face(cr, look.view.font[0] ? look.view.font : "DejaVu Sans",
                           CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    if (pal.background[3] > 0) { /* view.background = transparent: none */
        set_rgba(cr, pal.background);
        cairo_paint(cr);
    }
    if (d.measure == SP_MEASURE_LYAPUNOV || d.measure == SP_MEASURE_PRECESSION)
        ret = draw_lyapunov(cr, csv, &d, &pal);
    else if (d.measure == SP_MEASURE_SPECTRUM)
        ret = draw_spectrum(cr, csv, &d, &pal);
    else if (d.measure == SP_MEASURE_BASINS)
        ret = draw_basins(cr, csv, &d, &pal);
    else
        ret = draw_dots(cr, csv, csv_name, &d, &pal);
    cairo_status_t st = cairo_status(cr);
    cairo_destroy(cr);
    if (!ret && !st && !strcasecmp(ext, ".png"))
        st = cairo_surface_write_to_png_stream(s, sp_cairo_fd_write, &sink);
    cairo_surface_finish(s);
    if (!st)
        st = cairo_surface_status(s);
    if (!st && sink.err)
        st = CAIRO_STATUS_WRITE_ERROR;
    cairo_surface_destroy(s);
    free(svg_meta);
    /* cairo keeps its font faces and fontconfig its configuration for the
     * next figure; there is none: give them back (a sanitizer build checks) */
    cairo_debug_reset_static_data();
    FcFini();
    if (!ret && sp_signal_seen())
        ret = SP_E_INTERRUPTED; /* a figure cut short by a signal is not written */
    if (!ret && st) {
        sp_log_error("cannot write %s: %s", path,
                     sink.err ? strerror(sink.err) : cairo_status_to_string(st));
        ret = SP_E_IO;
    }
    if (ret)
        sp_outfile_discard(&out);
    else
        *figure = out; /* the caller commits it after the CSV, or discards it */
    return ret;
}
