/* springpend: a sweep's figure, composed straight from its CSV (see
 * sweep.h) on the draw list still figures use (canvas.h) and drawn by the
 * same cairo backend (draw_cairo.h) into PNG, SVG or PDF: a Lyapunov map
 * with a colour bar (two keys) or line (one key), an orbit diagram (dots),
 * a Poincare mosaic (dots coloured by orbit), a spectrum, a basin map. The
 * look is the scene's theme and colormap (panels.c's palette); text is laid
 * out by text.c (HarfBuzz, FriBidi, fontconfig: the [view] font, DejaVu
 * Sans by default, with fallbacks) at LAYOUT_PX and placed on the list as
 * turned text at its size in pt, a title wrapped to the page. One list
 * unit is one pt. Built as springpend-plot.so, loaded on first use, so that
 * cairo costs only the commands that draw. */
#include <errno.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/array.h"
#include "render/draw_cairo.h"
#include "frame/axis.h"
#include "frame/canvas.h"
#include "frame/panels.h"
#include "frame/text.h"
#include "springpend/common.h"
#include "springpend/outfile.h"
#include "springpend/png_io.h"
#include "springpend/provenance.h"
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
    double label_pt;   /* tick labels' size, pt (axis.h) */
    const char *title; /* NULL: the measure's own; "" = none */
    const struct sp_view *v; /* [view]'s figure keys: xlabel, ylabel, colorbar_label,
                                legend, marker_size, panel_titles, panel_labels */
    /* text (text.c): laid out once at LAYOUT_PX px per em and drawn scaled */
    struct sp_font *font;
    struct sp_canvas cv; /* the figure's draw list, pt (its font: font) */
    struct sp_draw_cairo *dc; /* the document it is drawn into, in pieces when long */
    float col[4];       /* the colour of what is added next (straight RGBA) */
    double lwidth;      /* the width of lines added next, pt */
    double pt;          /* the size text is drawn at now, pt */
    int err;            /* 0, or the first failure of the text or the drawing (logged) */
    char *title_lines;  /* the title wrapped (sp_font_wrap); NULL = none */
    int title_n;        /* its lines */
    double title_pt;    /* its size, pt */
    const volatile sig_atomic_t *cancel; /* the style's: once set, drawing stops */
    /* the default figure's layout, measured at the text's size (place) */
    char *sub_lines;    /* the subtitle wrapped to the page; NULL = none */
    int sub_n;          /* its lines */
    int quiet;          /* wrapping for the font size check: nothing said */
    int measuring;      /* text is measured into box, nothing drawn */
    int vector;         /* an SVG or PDF: dots at one spot merged (struct dot_grid) */
    double box[4];      /* what was measured: x0, y0, x1, y1, pt */
    struct {            /* a Poincare mosaic's key (key_layout) */
        double gx, gy, gw, gh; /* its gradient, pt */
        double lx;      /* the centre of its name */
        double row;     /* the height of its own row over the plot; 0: beside the title */
        char lo[64], hi[64];
        const char *name;
    } key;
} G = {.w = 900, .h = 600, .u = 1, .lw = 1, .tick = 5};
#define W G.w
#define H G.h
#define U(x) ((x) * G.u)
/* A length of the default figure (a margin, a gap, a bar's width), pt: as
 * at 14 pt text (view.font_size's default) and below, scaled with larger. */
#define D(x) fmax((x), U(x))
#define PNG_SCALE_DEFAULT 2 /* px per pt without a printed size */
/* A Lyapunov map's image, pixels a side at most: more than the plot's
 * 720 pt (1440 PNG px) can show, far less than cairo's limit (32767). */
#define MAP_MAX_PX 2048
/* Shapes the list holds at most before they are drawn and dropped
 * (flush_if_long): an orbit diagram's dots grow with --time, its memory
 * must not. 64 Ki shapes are 2.5 MiB. */
#define FLUSH_SHAPES 65536
/* Text is laid out at this em size (px of text.c's layout, each advance
 * rounded to a whole one: 1/200 em) and drawn scaled to its size in pt. */
#define LAYOUT_PX 200
#define LAYOUT SP_TEXT_NORMAL
/* A title line's height, times its size (the printed figure's spacing). */
#define TITLE_LEADING 1.25
/* A PNG's text is at least this many px tall (a still's floor, compose.c). */
#define SMALLEST_TEXT_PX 4
/* Where a colour bar stands right of the plot, pt: at a printed size
 * (draw_colorbar), and in the default figure (its callers: 30). */
#define BAR_GAP (G.print ? U(14) : D(30))

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

/* The colour (straight RGBA) and line width (pt) of what is added next. */
static void set_rgba(const float c[4])
{
    memcpy(G.col, c, sizeof(G.col));
}

static void set_rgba4(double r, double g, double b, double a)
{
    G.col[0] = (float)r, G.col[1] = (float)g, G.col[2] = (float)b, G.col[3] = (float)a;
}

static void set_line_width(double w)
{
    G.lwidth = w;
}

/* A line from a to b in the colour and width set. */
static void line(double ax, double ay, double bx, double by)
{
    if (G.measuring)
        return;
    sp_canvas_line(&G.cv, (float)ax, (float)ay, (float)bx, (float)by, (float)(0.5 * G.lwidth),
                   G.col);
}

/* A filled rectangle in the colour set. */
static void fill_rect(double x, double y, double w, double h)
{
    if (G.measuring)
        return;
    sp_canvas_rect(&G.cv, (float)x, (float)y, (float)(x + w), (float)(y + h), G.col);
}

/* A rectangle's outline in the colour and width set: one closed path. */
static void stroke_rect(double x, double y, double w, double h)
{
    if (G.measuring)
        return;
    sp_canvas_path_begin(&G.cv);
    line(x, y, x + w, y);
    line(x + w, y, x + w, y + h);
    line(x + w, y + h, x, y + h);
    line(x, y + h, x, y);
    sp_canvas_path_end(&G.cv);
}

/* A circle's outline, radius r pt, in the colour and width set: a closed
 * path of 24 chords (within 1% of r of the circle). */
static void stroke_ring(double x, double y, double r)
{
    sp_canvas_path_begin(&G.cv);
    for (int k = 0; k < 24; k++)
        line(x + r * cos(k * M_PI / 12), y + r * sin(k * M_PI / 12),
             x + r * cos((k + 1) * M_PI / 12), y + r * sin((k + 1) * M_PI / 12));
    sp_canvas_path_end(&G.cv);
}

/* A polyline added point by point between sp_canvas_path_begin and _end
 * (in the colour and width set): *pen says whether (last[0], last[1]) was
 * its previous point; a point that is not finite breaks it. */
static void poly_to(int *pen, double last[2], double x, double y)
{
    if (!isfinite(x) || !isfinite(y)) {
        if (*pen)
            sp_canvas_path_end(&G.cv), sp_canvas_path_begin(&G.cv);
        *pen = 0;
        return;
    }
    if (*pen)
        line(last[0], last[1], x, y);
    last[0] = x, last[1] = y, *pen = 1;
}

/* Once the list holds FLUSH_SHAPES shapes, draws all of it but its text
 * into the document and drops it (the text stays for the end, drawn over
 * everything as in one list). Outside a path. Failures go to G.err. */
static void flush_if_long(void)
{
    if (G.cv.n_shapes < FLUSH_SHAPES || G.err || G.cv.err)
        return;
    G.err = sp_draw_cairo_shapes(G.dc, &G.cv);
    sp_canvas_keep_text(&G.cv);
}

/* Clips what is added next to the plot rectangle (NULL: no clipping). */
static void clip_to(const struct frame *f)
{
    if (!f) {
        sp_canvas_clip(&G.cv, NULL);
        return;
    }
    const float r[4] = {(float)f->x0, (float)f->y0, (float)(f->x0 + f->w), (float)(f->y0 + f->h)};
    sp_canvas_clip(&G.cv, r);
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

/* fix_range for the range of a swept key: one --vary accepts (its steps
 * over 1e-9 of its values' size, sweep.c) is kept as it is, tiny ones too
 * (1e-300 to 2e-300); one of a single value is widened. */
static void fix_key_range(double *lo, double *hi)
{
    if (!(isfinite(*lo) && isfinite(*hi) && *hi - *lo > 1e-9 * fmax(fabs(*lo), fabs(*hi))))
        fix_range(lo, hi);
}

/* A swept key's range, low to high: a --vary written from high to low
 * (KEY=170:10:5) is drawn as any other, ascending, each point at its value
 * (the CSV keeps the order it was given). */
static void key_span(const struct sp_sweep_axis *a, double *lo, double *hi)
{
    *lo = fmin(a->from, a->to), *hi = fmax(a->from, a->to);
}

/* A map's range along a key: key_span and half a step beyond each end, the
 * cells centred on the grid values. */
static void key_cells(const struct sp_sweep_axis *a, double *lo, double *hi)
{
    const double step = a->count > 1 ? fabs(a->to - a->from) / (a->count - 1) : 1;
    key_span(a, lo, hi);
    *lo -= step / 2, *hi += step / 2;
}

/* The cell, of n in a map drawn ascending (left to right, bottom to top),
 * that holds index i of the key (of n too): the same, or mirrored for a key
 * given from high to low. */
static long key_cell(const struct sp_sweep_axis *a, long i, long n)
{
    return a->to < a->from ? n - 1 - i : i;
}

/* The size text is drawn at from now on, pt. */
static void font_pt(double pt)
{
    G.pt = pt;
}

/* The advance of s at the current size, pt. */
static double text_width(const char *s)
{
    return G.font ? sp_font_width(G.font, LAYOUT, s) * G.pt / LAYOUT_PX : 0;
}

/* Refuses [view] xlabel (which 0), ylabel (1) or colorbar_label (2) when
 * its text is wider than the room it has, pt (at the current size): what
 * `where` is that room ("the plot's width"). Said once, naming where the
 * key was set; G.err = SP_E_INPUT. Labels the figure names itself are not
 * checked (which < 0). */
static void label_room(int which, const char *text, double room, const char *where)
{
    static const char *const keys[3] = {"xlabel", "ylabel", "colorbar_label"};
    const double w = text_width(text);
    if (which < 0 || G.err || w <= room)
        return;
    const char *set = G.v->label_where[which];
    char at[600];
    if (!set[0])
        snprintf(at, sizeof(at), "[view] %s", keys[which]);
    else if (!strncmp(set, "--set ", 6))
        snprintf(at, sizeof(at), "%s", set);
    else
        snprintf(at, sizeof(at), "%s: [view] %s", set, keys[which]);
    sp_log_error("%s: \"%s\" cannot fit: it is %.0f pt wide at %.3g pt, and the figure has "
                 "%.0f pt for it (%s); allowed: at most %.0f pt; shorten it, use a smaller "
                 "font_size or font_scale, or a larger --size", at, text, w, G.pt, room, where,
                 room);
    G.err = SP_E_INPUT;
}

/* Adds s at the current size and colour, with the point (x, y) at
 * fraction ax of its advance across and fraction ay of its capital height
 * down (0: the top of a capital, 1: the baseline), its baseline turned
 * clockwise by angle rad about that point (-pi/2 reads upward). A
 * character no font has is refused, never drawn as a box. Failures go to
 * G.err. */
static void text_turned(double x, double y, const char *s, double ax, double ay, double angle)
{
    struct sp_line l;
    const double k = G.pt / LAYOUT_PX;
    if (G.err || !s[0] || (G.err = sp_font_shape(G.font, LAYOUT, s, &l)))
        return;
    if (l.missing) {
        if (!sp_font_check(G.font, "the figure's text", s))
            sp_log_error("the figure's text \"%s\" has a character no font draws", s);
        G.err = SP_E_INPUT;
        return;
    }
    /* the pen from the anchor, along the baseline and down across it */
    const double lx = -ax * k * l.width, ly = (1 - ay) * k * sp_font_cap(G.font, LAYOUT);
    const double c = cos(angle), sn = sin(angle);
    if (G.measuring) { /* its box: the advance, an em above the baseline, a quarter below */
        for (int i = 0; i < 4; i++) {
            const double bx = lx + (i & 1) * k * l.width, by = ly + (i & 2 ? 0.25 : -1) * G.pt;
            const double X = x + bx * c - by * sn, Y = y + bx * sn + by * c;
            G.box[0] = fmin(G.box[0], X), G.box[1] = fmin(G.box[1], Y);
            G.box[2] = fmax(G.box[2], X), G.box[3] = fmax(G.box[3], Y);
        }
        return;
    }
    sp_canvas_text_turned(&G.cv, LAYOUT, (float)(x + lx * c - ly * sn), (float)(y + lx * sn + ly * c),
                          (float)k, (float)angle, G.col, s);
}

/* text_turned, level. */
static void text_at(double x, double y, const char *s, double ax, double ay)
{
    text_turned(x, y, s, ax, ay, 0);
}

/* Measures what is added from now on instead of drawing it: its text's
 * box, pt, into G.box (measure_end). */
static void measure_begin(void)
{
    G.measuring = 1;
    G.box[0] = G.box[1] = INFINITY, G.box[2] = G.box[3] = -INFINITY;
}

/* Stops measuring: the box of the text added since measure_begin (x0, y0,
 * x1, y1; all 0 when none was). */
static void measure_end(double box[4])
{
    G.measuring = 0;
    for (int i = 0; i < 4; i++)
        box[i] = isfinite(G.box[i]) ? G.box[i] : 0;
}

/* text_width, as sp_axis_fit measures a label (ctx unused). */
static double label_width(void *ctx, const char *label)
{
    (void)ctx;
    return text_width(label);
}

/* The ticks of [lo, hi] along an axis `length` pt long, laid out as a
 * still's panels lay theirs out (axis.h): the finest round step whose
 * labels, at G.label_pt, fit side by side (horizontal) or a line apart
 * (vertical). */
static void ticks(struct sp_axis *a, double lo, double hi, double length, int vertical)
{
    const double pt = G.pt;
    font_pt(G.label_pt);
    *a = (struct sp_axis){.lo = lo, .hi = hi};
    sp_axis_fit(a, length, G.font ? sp_font_line(G.font, LAYOUT) * G.pt / LAYOUT_PX : G.pt,
                label_width, NULL, vertical);
    font_pt(pt);
}

/* The y ticks' (draw_axes's) labels' widest width, pt: f's y range along
 * its height. */
static double ylabels_width(const struct frame *f)
{
    char buf[64];
    struct sp_axis a;
    double wmax = 0;
    ticks(&a, f->ylo, f->yhi, f->h, 1);
    const double pt = G.pt;
    font_pt(G.label_pt);
    for (double v = a.first; v <= a.hi + 1e-9 * a.step; v += a.step) {
        sp_axis_label(&a, v, buf, sizeof(buf));
        wmax = fmax(wmax, text_width(buf));
    }
    font_pt(pt);
    return wmax;
}

/* The height the title's lines below its first take, pt. */
static double title_extra(void)
{
    return G.title_n > 1 ? (G.title_n - 1) * G.title_pt * TITLE_LEADING : 0;
}

/* The default figure's subtitle: its size, pt, and the height its lines
 * below its first take. */
#define SUB_PT U(12)
static double sub_extra(void)
{
    return G.sub_n > 1 ? (G.sub_n - 1) * SUB_PT * TITLE_LEADING : 0;
}

/* Where the default figure's title and subtitle start, pt: 80, or clear of
 * the panel label "(a)" left of them when the text is large. */
static double title_left(void)
{
    if (G.print || !G.v || !G.v->panel_labels)
        return 80;
    const double pt = G.pt;
    font_pt(U(17));
    const double x = fmax(80, 10 + text_width(G.v->panel_labels == 1 ? "(a)" : "(A)") + D(8));
    font_pt(pt);
    return x;
}

/* Where the default figure's x axis's name starts below the plot, pt:
 * under its tick labels (draw_axes). */
static double xname_drop(void)
{
    return G.print ? U(30) : fmax(D(30), G.tick + U(4) + G.label_pt * 1.2 + U(5));
}

/* The default figure's margins above and below its plot, pt: the title's
 * and subtitle's lines (and a Poincare mosaic's key in its own row); the
 * tick labels and the x axis's name. 56 and 60 at 14 pt text. */
static double default_top(void)
{
    return D(56) + title_extra() + sub_extra() + G.key.row;
}

static double default_bottom(void)
{
    return fmax(60, xname_drop() + G.label_pt * 1.25 + D(4));
}

/* The default figure's left margin, pt, for y tick labels ylw pt wide:
 * room for them and the y axis's name, 80 at least. */
static double default_left(double ylw)
{
    return fmax(80, U(4) + G.label_pt * 1.2 + U(6) + ylw + U(4) + G.tick);
}

/* Narrows f until each x tick label (centred on its tick, as draw_axes
 * draws it) ends U(2) short of what stands right of the plot: the next
 * drawing `gap` pt on (gap > 0: a colour bar, a legend), else the page's
 * edge, `right` pt on. A narrower plot may take other ticks: four tries. */
static void fit_x_labels(struct frame *f, double right, double gap)
{
    const double room = (gap > 0 ? gap : right) - U(2), pt = G.pt;
    for (int k = 0; k < 4; k++) {
        struct sp_axis a;
        char buf[64];
        double over = 0;
        ticks(&a, f->xlo, f->xhi, f->w, 0);
        font_pt(G.label_pt);
        for (double v = a.first; v <= a.hi + 1e-9 * a.step; v += a.step) {
            sp_axis_label(&a, v, buf, sizeof(buf));
            over = fmax(over, px(f, v) + 0.5 * text_width(buf) - (f->x0 + f->w + room));
        }
        font_pt(pt);
        if (over <= 0 || f->w - over < U(20))
            return;
        f->w -= over;
    }
}

/* The least plot the default figure's ticks and axis names need, pt: as
 * at a printed size, 12 x 7 times the body text's size. */
#define LEAST_W (12 * U(14))
#define LEAST_H (7 * U(14))

/* Says that the default figure's text is too large for its page: what
 * does not fit (`why`), and best > 0: the largest view.font_size that
 * fits (at the font_scale in force). Returns SP_E_INPUT. */
static int font_refused(const char *why, double best)
{
    const char *where = G.v->text_size_where[0] ? G.v->text_size_where : "[view] font_size";
    const double scale = G.v->font_scale > 0 ? G.v->font_scale : 1;
    char allowed[160];
    if (best > 0)
        snprintf(allowed, sizeof(allowed), "at most view.font_size %.1f%s for this figure", best,
                 scale != 1 ? " at this font_scale" : "");
    else
        snprintf(allowed, sizeof(allowed), "a smaller view.font_size for this figure");
    sp_log_error("%s: text of %.3g pt (font_size %g, font_scale %g) cannot fit the sweep's "
                 "%.0f x %.0f pt figure: %s; allowed: %s; use a smaller font_size or "
                 "font_scale, or a printed size (--size)", where, U(14), U(14) / scale, scale, W,
                 H, why, allowed);
    return SP_E_INPUT;
}

/* The plot's w x h pt against the need_w x need_h its text needs: said. */
static void plot_why(char *buf, size_t size, double w, double h, double need_w, double need_h)
{
    snprintf(buf, size, "the plot inside its margins would be %.0f x %.0f pt, and its ticks, axis "
             "names and legend need at least %.0f x %.0f pt", fmax(w, 0), fmax(h, 0), need_w,
             need_h);
}

/* Refuses (G.err) a default figure's plot f smaller than its text needs:
 * text so large that the margins leave too little (the data's own tick
 * labels, which the check before the sweep cannot know, make it so). */
static void plot_room(const struct frame *f)
{
    char why[256];
    if (G.err || (f->w >= LEAST_W && f->h >= LEAST_H))
        return;
    plot_why(why, sizeof(why), f->w, f->h, LEAST_W, LEAST_H);
    G.err = font_refused(why, 0);
}

/* Refuses (G.err) a legend w x h pt that the default figure's plot f
 * cannot hold with `in` pt around it. */
static void legend_room(const struct frame *f, double w, double h, double in)
{
    char why[256];
    if (G.print || G.err || (w + 2 * in <= f->w && h + 2 * in <= f->h))
        return;
    snprintf(why, sizeof(why), "its legend would be %.0f x %.0f pt in a plot of %.0f x %.0f pt",
             w + 2 * in, h + 2 * in, f->w, f->h);
    G.err = font_refused(why, 0);
}

/* Places the plot rectangle of f (its data range set) on the page: the
 * default figure's margins from its text (the title's and subtitle's
 * lines, the tick labels, the axes' names: default_top, _bottom, _left),
 * right = `right` pt (room for a colour bar or legend), its plot refused
 * when too small for its text (plot_room); at a printed size margins that
 * fit the labels, right = print_right pt. Either way narrower when the last x tick label would
 * reach past the page's edge, or the drawing `gap` pt right of the plot
 * (fit_x_labels). A title of several lines (title()) moves the plot down. */
static void place(struct frame *f, double right, double print_right, double gap)
{
    if (!G.print) { /* the margins from the text at its size: 80, 56, right, 60 at 14 pt */
        f->y0 = default_top();
        f->h = H - f->y0 - default_bottom();
        if (f->h < LEAST_H) {
            plot_room(f);
            f->h = fmax(f->h, U(20));
        }
        f->x0 = default_left(ylabels_width(f));
        f->w = fmax(W - f->x0 - right, U(20));
        fit_x_labels(f, right, gap);
        plot_room(f);
        return;
    }
    const double title = G.title_n ? G.title_n * G.title_pt * TITLE_LEADING
                         : G.v->panel_labels ? U(17) * TITLE_LEADING : 0;
    f->y0 = U(6) + title + U(6);
    f->h = H - f->y0 - (G.tick + U(4) + G.label_pt * 1.2 + U(5) + G.label_pt * 1.25 + U(4));
    f->h = fmax(f->h, U(20));
    /* the left margin depends on the y labels, which depend on the height */
    f->x0 = U(4) + G.label_pt * 1.2 + U(6) + ylabels_width(f) + U(4) + G.tick;
    f->w = fmax(W - f->x0 - print_right, U(20));
    fit_x_labels(f, print_right, gap);
}

/* Axes, ticks, grid and labels around the frame. */
static void draw_axes(const struct frame *f, const struct sp_palette *pal, const char *xlabel,
                      const char *ylabel)
{
    char buf[64];
    const int own_x = G.v->xlabel[0] ? 0 : -1, own_y = G.v->ylabel[0] ? 1 : -1;
    if (G.v->xlabel[0]) /* [view] xlabel, ylabel: the axes' own names */
        xlabel = G.v->xlabel;
    if (G.v->ylabel[0])
        ylabel = G.v->ylabel;
    struct sp_axis ax, ay;
    char xname[256], yname[256];
    ticks(&ax, f->xlo, f->xhi, f->w, 0);
    ticks(&ay, f->ylo, f->yhi, f->h, 1);
    sp_axis_name(&ax, xlabel, xname, sizeof(xname)); /* with an offset the ticks leave out */
    sp_axis_name(&ay, ylabel, yname, sizeof(yname));
    xlabel = xname, ylabel = yname;
    font_pt(G.label_pt);
    const double grid_lw = G.print ? 0.5 * G.lw : G.lw;
    for (double v = ax.first; v <= ax.hi + 1e-9 * ax.step; v += ax.step) {
        double x = px(f, v);
        set_rgba(pal->grid), set_line_width(grid_lw);
        line(x, f->y0, x, f->y0 + f->h);
        set_rgba(pal->axis), set_line_width(G.lw);
        line(x, f->y0 + f->h, x, f->y0 + f->h + G.tick);
        sp_axis_label(&ax, v, buf, sizeof(buf));
        set_rgba(pal->muted);
        text_at(x, f->y0 + f->h + G.tick + U(4), buf, 0.5, 0);
    }
    for (double v = ay.first; v <= ay.hi + 1e-9 * ay.step; v += ay.step) {
        double y = py(f, v);
        set_rgba(pal->grid), set_line_width(grid_lw);
        line(f->x0, y, f->x0 + f->w, y);
        set_rgba(pal->axis), set_line_width(G.lw);
        line(f->x0 - G.tick, y, f->x0, y);
        sp_axis_label(&ay, v, buf, sizeof(buf));
        set_rgba(pal->muted);
        text_at(f->x0 - G.tick - U(4), y, buf, 1, 0.5);
    }
    set_rgba(pal->axis), set_line_width(G.lw);
    stroke_rect(f->x0, f->y0, f->w, f->h);
    font_pt(G.label_pt); /* the names at the tick labels' size, as a still's (axis.h) */
    set_rgba(pal->text);
    /* each name within the plot's side: never off the page or past the
     * colour bar */
    label_room(own_x, xlabel, f->w, "the plot's width");
    label_room(own_y, ylabel, f->h, "the plot's height, along which it is turned");
    text_at(f->x0 + f->w / 2, f->y0 + f->h + xname_drop(), xlabel, 0.5, 0);
    /* the y axis's name clear of its widest tick label, reading upward */
    const double yoff = G.tick + U(4) + ylabels_width(f) + U(12);
    text_turned(f->x0 - (G.print ? yoff : fmax(58, yoff)), f->y0 + f->h / 2, ylabel, 0.5, 0.5,
                -M_PI / 2);
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
    if ((G.cancel && *G.cancel) || !fgets(line, sizeof(line), fp)) /* stopped: stop drawing */
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

/* "FILE:LINE: [view] title" (or "--set view.title") for messages. */
static void title_where(char *buf, size_t size)
{
    const char *where = G.v->title_where ? G.v->title_where : "";
    if (!strncmp(where, "--set ", 6))
        snprintf(buf, size, "%s", where);
    else
        snprintf(buf, size, "%s%s[view] title", where, where[0] ? ": " : "");
}

/* Wraps text, the title, into G.title_lines at G.title_pt to the page's
 * width less its margins, as a still wraps its title to the frame. A
 * title that takes more than half the page's height, or has a character
 * wider than a line, is refused (logged, naming where it was set when
 * it is [view] title: `what`). 0 or SP_E_INPUT / SP_E_NOMEM. */
static int wrap_title(const char *text, const char *what)
{
    const double k = G.title_pt / LAYOUT_PX, lead = G.title_pt * TITLE_LEADING;
    const double width = G.print ? W - 2 * U(4) : W - title_left() - 10; /* pt */
    const int max_lines = G.quiet ? 1000 : (int)fmax(1, floor(H / 2 / lead));
    free(G.title_lines);
    G.title_lines = NULL, G.title_n = 0;
    int err = G.quiet ? 0 : sp_font_check(G.font, what, text);
    if (G.quiet) /* fit_check: only its lines */
        return sp_font_wrap(G.font, LAYOUT, text, (float)(width / k), max_lines, &G.title_lines,
                            &G.title_n);
    if (!err)
        err = sp_font_wrap(G.font, LAYOUT, text, (float)(width / k), max_lines, &G.title_lines,
                           &G.title_n);
    const char *line = G.title_lines;
    for (int i = 0; !err && i < G.title_n; i++, line += strlen(line) + 1)
        if (sp_font_width(G.font, LAYOUT, line) * k > width) {
            sp_log_error("%s: \"%s\" is %.0f pt wide, wider than the figure's %.0f pt for "
                         "text; use a smaller font_size or font_scale, or a wider --size", what,
                         line, sp_font_width(G.font, LAYOUT, line) * k, width);
            err = SP_E_INPUT;
        }
    if (!err && G.title_n > max_lines) {
        sp_log_error("%s: the title cannot fit: it wraps to more than %d lines at %.0f pt "
                     "wide; allowed: at most half the figure's height (%.0f of %.0f pt); "
                     "shorten it, use a smaller font_size or font_scale, or a larger --size",
                     what, max_lines, width, H / 2, H);
        err = SP_E_INPUT;
    }
    if (err) {
        free(G.title_lines);
        G.title_lines = NULL, G.title_n = 0;
    }
    return err;
}

/* The default figure's subtitle: what was sampled, over what time, by
 * which method. */
static void subtitle_text(const struct sp_sweep_desc *d, char *buf, size_t size)
{
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
    char method[96];
    sp_sweep_method_text(d, method, sizeof(method));
    snprintf(buf, size, "%s%sover %g s%s, %s", sampled, energy, d->time, transient, method);
    sp_axis_minus(buf, size); /* a negative energy: −0.5 J */
}

/* The default figure's subtitle wrapped into G.sub_lines at SUB_PT to the
 * width its title has. 0 or SP_E_NOMEM. */
static int wrap_subtitle(const struct sp_sweep_desc *d)
{
    char buf[512];
    subtitle_text(d, buf, sizeof(buf));
    const double k = SUB_PT / LAYOUT_PX;
    return sp_font_wrap(G.font, LAYOUT, buf, (float)((W - title_left() - 10) / k), 1000,
                        &G.sub_lines, &G.sub_n);
}

/* Sets the figure's title before place(): [view] title when set, else the
 * measure's (the default figure's "SCENE: what", a printed figure's
 * short_what), none with title = "" or panel_titles = false; wrapped
 * (wrap_title), and the default figure's subtitle under it (wrap_subtitle).
 * Failures go to G.err. */
static void title(const struct sp_sweep_desc *d, const char *what, const char *short_what)
{
    char buf[512], where[512], name[256];
    free(G.title_lines), free(G.sub_lines);
    G.title_lines = G.sub_lines = NULL, G.title_n = G.sub_n = 0;
    if (G.err || (G.title && !G.title[0]) || (!G.title && !G.v->panel_titles))
        return;
    G.title_pt = U(17);
    /* the scene's name as messages show it: a file name may hold controls
     * and noncharacters, which no font draws (common.h) */
    sp_text_shown(d->scene, 0, name, sizeof(name));
    snprintf(buf, sizeof(buf), "%s: %s", name, what);
    title_where(where, sizeof(where));
    G.err = wrap_title(G.title ? G.title : G.print ? short_what : buf,
                       G.title ? where : "the figure's title");
    if (!G.err && !G.print)
        G.err = wrap_subtitle(d);
}

static void draw_title(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                       const struct frame *f)
{
    (void)d;
    if (G.v->panel_labels) { /* the figure is panel (a) */
        font_pt(U(17));
        set_rgba(pal->text);
        text_at(G.print ? U(4) : 10, G.print ? U(6) : D(10), G.v->panel_labels == 1 ? "(a)" : "(A)",
                0, 0);
    }
    /* the title's lines: a printed figure's centred over the plot (inside
     * the page), the default figure's from the plot's left edge, with the
     * subtitle's under them */
    font_pt(G.title_pt);
    set_rgba(pal->text);
    const char *line = G.title_lines;
    for (int i = 0; i < G.title_n; i++, line += strlen(line) + 1) {
        const double w = text_width(line);
        const double y = (G.print ? U(6) : D(10)) + i * G.title_pt * TITLE_LEADING;
        if (G.print)
            text_at(fmin(fmax(f->x0 + f->w / 2, U(4) + w / 2), W - U(4) - w / 2), y, line,
                    0.5, 0);
        else
            text_at(title_left(), y, line, 0, 0);
    }
    font_pt(SUB_PT);
    set_rgba(pal->muted);
    line = G.sub_lines;
    for (int i = 0; i < G.sub_n; i++, line += strlen(line) + 1)
        text_at(title_left(), D(34) + title_extra() + i * SUB_PT * TITLE_LEADING, line, 0, 0);
}

static void colormap_rgb(const struct sp_sweep_desc *d, double t, float rgb[3])
{
    sp_colormap(d->colormap, (float)t, rgb);
}

/* An image pixel (straight RGBA) from an opaque colour, 0..1. */
static void put_rgb(unsigned char *q, const float rgb[3])
{
    for (int k = 0; k < 3; k++)
        q[k] = (unsigned char)lrintf(fminf(fmaxf(rgb[k], 0), 1) * 255);
    q[3] = 255;
}

/* The colormap from t0 to t1 as an image of 128 cells over the rectangle
 * (x, y, w, h) pt: upward when vertical, else rightward. */
static void colormap_strip(const struct sp_sweep_desc *d, double x, double y, double w, double h,
                           int vertical, double t0, double t1)
{
    const int n = 128;
    unsigned char *p = sp_canvas_image(&G.cv, (float)x, (float)y, (float)(x + w), (float)(y + h),
                                       vertical ? 1 : n, vertical ? n : 1);
    for (int i = 0; p && i < n; i++) {
        float rgb[3];
        colormap_rgb(d, t0 + (t1 - t0) * (i + 0.5) / n, rgb);
        put_rgb(p + 4 * (vertical ? n - 1 - i : i), rgb);
    }
}

/* The room a colour bar (draw_colorbar) takes right of the plot at a
 * printed size, pt. */
static double colorbar_room(double lo, double hi)
{
    /* its ticks as for a bar as tall as the page: at least as many as the
     * bar will have, so labels at least as wide */
    struct frame f = {0, 0, 1, H, 0, 1, lo, hi};
    return U(14) + U(12) + G.tick + U(3) + ylabels_width(&f) + U(6) + G.label_pt * 1.2 + U(4);
}

/* The room right of the plot a default figure's colour bar (draw_colorbar)
 * takes, pt: 120, or its gap, width, ticks and their labels, or its own
 * name `label` centred above it, when wider. A [view] colorbar_label does
 * not widen it: one wider than the room is refused (draw_colorbar). */
static double bar_right(double lo, double hi, const char *label)
{
    struct frame f = {0, 0, 1, H, 0, 1, lo, hi}; /* ticks as for a bar as tall as the page */
    struct sp_axis a;
    char named[256];
    const double ylw = ylabels_width(&f), pt = G.pt;
    ticks(&a, lo, hi, H, 1);
    sp_axis_name(&a, label, named, sizeof(named));
    font_pt(G.label_pt);
    /* only text that is drawn is measured: a font shaped is a font the
     * figure records as drawn from (its provenance) */
    const double tw = G.v->colorbar_label[0] ? 0 : text_width(named);
    font_pt(pt);
    const double bar = D(30) + D(18) + G.tick + U(3) + ylw;
    return fmax(120, fmax(bar, fmax(D(30) + D(9) + tw / 2, D(6) + tw)) + D(4));
}

/* A colour bar from t0 to t1 of the colormap, ticks lo..hi. By default at
 * (x, y), h tall, its label above; at a printed size right of the plot f,
 * as tall, its label turned along it. */
static void draw_colorbar(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                          double x, double y, double h, double lo, double hi, const char *label,
                          const struct frame *pf, double t0, double t1)
{
    const double bw = G.print ? U(12) : D(18);
    if (G.print)
        x = pf->x0 + pf->w + BAR_GAP, y = pf->y0, h = pf->h;
    colormap_strip(d, x, y, bw, h, 1, t0, t1);
    set_rgba(pal->axis), set_line_width(G.lw);
    stroke_rect(x, y, bw, h);
    struct sp_axis a;
    char buf[64];
    ticks(&a, lo, hi, h, 1);
    font_pt(G.label_pt);
    for (double v = a.first; v <= a.hi + 1e-9 * a.step; v += a.step) {
        double yy = y + h - (v - lo) / (hi - lo) * h;
        set_rgba(pal->axis);
        line(x + bw, yy, x + bw + G.tick, yy);
        sp_axis_label(&a, v, buf, sizeof(buf));
        set_rgba(pal->muted);
        text_at(x + bw + G.tick + U(3), yy, buf, 0, 0.5);
    }
    font_pt(G.label_pt); /* an axis's name: as draw_axes's */
    set_rgba(pal->text);
    const int own = G.v->colorbar_label[0] ? 2 : -1;
    if (G.v->colorbar_label[0])
        label = G.v->colorbar_label;
    char named[256];
    sp_axis_name(&a, label, named, sizeof(named)); /* its ticks' offset or power of ten */
    label = named;
    if (!G.print) { /* centred above the bar, clear of the plot on its left, on the page */
        const double tw = text_width(label), left = pf->x0 + pf->w + D(6);
        const double cx = fmin(fmax(x + bw / 2, left + 0.5 * tw), W - D(4) - 0.5 * tw);
        label_room(own, label, W - D(4) - left, "right of the plot, above the bar");
        text_at(cx, y - D(10), label, 0.5, 1);
        return;
    }
    label_room(own, label, h, "the bar's height, along which it is turned");
    struct frame tf = {0, 0, 1, h, 0, 1, lo, hi}; /* the bar's own ticks */
    text_turned(x + bw + G.tick + U(3) + ylabels_width(&tf) + U(6) + U(7), y + h / 2, label, 0.5,
                0.5, -M_PI / 2);
}

/* Whether the segment a-b passes through the rectangle r (x0, y0, x1, y1):
 * Liang-Barsky clipping. */
static int crosses(const double a[2], const double b[2], const double r[4])
{
    double t0 = 0, t1 = 1;
    const double d[2] = {b[0] - a[0], b[1] - a[1]};
    for (int k = 0; k < 4; k++) {
        const int axis = k & 1, lower = k < 2; /* x0, y0, x1, y1 */
        const double p = lower ? -d[axis] : d[axis];
        const double q = lower ? a[axis] - r[k] : r[k] - a[axis];
        if (p == 0) {
            if (q < 0)
                return 0;
        } else if (p < 0) {
            t0 = fmax(t0, q / p);
        } else {
            t1 = fmin(t1, q / p);
        }
        if (t0 > t1)
            return 0;
    }
    return 1;
}

/* The curves of a line figure, for its legend to keep clear of: n points
 * on the page (pt), a point that is not finite breaking a curve. */
struct curves {
    double (*p)[2];
    long n, cap;
};

/* Adds (x, y) to c (NaN: a break); an allocation that fails is logged
 * and sets G.err (the figure is not written). */
static void curve_to(struct curves *c, double x, double y)
{
    if (SP_ARRAY_RESERVE(c->p, c->cap, c->n + 1, 256)) {
        if (!G.err)
            sp_log_error("out of memory for the figure's legend");
        G.err = G.err ? G.err : SP_E_NOMEM;
        return;
    }
    c->p[c->n][0] = x, c->p[c->n][1] = y, c->n++;
}

/* Whether c's point i is finite with neither neighbour finite: a lone
 * value (a sweep of one point, or one between blown-up ones) that no
 * segment of its curve draws. */
static int isolated(const struct curves *c, long i)
{
    const double *p = c->p[i];
    return isfinite(p[0] + p[1]) && (i == 0 || !isfinite(c->p[i - 1][0] + c->p[i - 1][1])) &&
           (i + 1 >= c->n || !isfinite(c->p[i + 1][0] + c->p[i + 1][1]));
}

/* Marks each isolated point of c from its index `from` on (the curve just
 * drawn) with a disc 4 line widths across (6.4 pt for a 1.6 pt line, about
 * matplotlib's 6 pt marker), in the colour set; outside a
 * path. */
static void mark_isolated(const struct curves *c, long from)
{
    if (G.measuring)
        return;
    for (long i = from; i < c->n; i++)
        if (isolated(c, i))
            sp_canvas_disc(&G.cv, (float)c->p[i][0], (float)c->p[i][1], (float)(2 * G.lwidth), 0,
                           G.col);
}

/* The box of draw_legend's n entries text[i], w x h pt. */
static void legend_size(const char *const *text, int n, double *w, double *h)
{
    font_pt(G.label_pt);
    *w = 0;
    for (int i = 0; i < n; i++)
        *w = fmax(*w, text_width(text[i]));
    *h = U(16) * (n - 1) + G.label_pt;
}

/* Draws the n legend entries text[i] in colour[i] at G.label_pt, each
 * U(16) below the last, inside the plot f where no curve of c passes: the
 * first free of its corners (top right, top left, bottom right, bottom
 * left), then the middles of its edges. When every place is crossed, the
 * least crossed, on a box of the background colour (as orbit_legend's) so
 * that it reads over the curves. */
static void draw_legend(const struct frame *f, const struct curves *c, const char *const *text,
                        const float *const *colour, int n, const struct sp_palette *pal)
{
    double w, h;
    legend_size(text, n, &w, &h);
    const double in = U(8), pad = U(3);
    legend_room(f, w, h, in);
    /* top-left corners (x: fraction of the free width, y: of the free height) */
    static const double place_at[][2] = {{1, 0}, {0, 0}, {1, 1}, {0, 1},
                                         {0.5, 0}, {0.5, 1}, {1, 0.5}, {0, 0.5}};
    int best = 0;
    long best_hits = LONG_MAX;
    for (int k = 0; k < (int)(sizeof(place_at) / sizeof(place_at[0])) && best_hits; k++) {
        const double x = f->x0 + in + place_at[k][0] * (f->w - 2 * in - w);
        const double y = f->y0 + in + place_at[k][1] * (f->h - 2 * in - h);
        const double r[4] = {x - pad, y - pad, x + w + pad, y + h + pad};
        long hits = 0;
        for (long i = 0; i < c->n; i++)
            hits += (i + 1 < c->n &&
                     isfinite(c->p[i][0] + c->p[i][1] + c->p[i + 1][0] + c->p[i + 1][1]) &&
                     crosses(c->p[i], c->p[i + 1], r)) ||
                    (isolated(c, i) && crosses(c->p[i], c->p[i], r)); /* its mark */
        if (hits < best_hits)
            best = k, best_hits = hits;
    }
    const double ax = place_at[best][0];
    const double x = f->x0 + in + ax * (f->w - 2 * in - w);
    const double y = f->y0 + in + place_at[best][1] * (f->h - 2 * in - h);
    if (best_hits) {
        set_rgba4(pal->background[0], pal->background[1], pal->background[2], 0.85);
        fill_rect(x - pad, y - pad, w + 2 * pad, h + 2 * pad);
    }
    for (int i = 0; i < n; i++) {
        set_rgba(colour[i]);
        text_at(x + ax * w, y + U(16) * i, text[i], ax, 0);
    }
}

/* The one-number measures, drawn as a line over one key or a map over two:
 * the title and its short form (at a printed size), the y axis's label, the
 * colour bar's, and the legend of a line's two series (the first value of a
 * row, then the second; NULL: the line shows the first alone). */
static const struct scalar_look {
    const char *title, *short_title, *label, *bar, *series[2];
} scalar_looks[SP_MEASURE_COUNT] = {
    [SP_MEASURE_LYAPUNOV] = {"largest Lyapunov exponent", "largest Lyapunov exponent",
                             "λ (1/s)", "λ (1/s)", {"λ over T", "λ over T/2"}},
    [SP_MEASURE_PRECESSION] = {"precession of the swing plane per exchange",
                               "precession per exchange", "Δφ (° per exchange)",
                               "° per exchange", {"precession per exchange", NULL}},
};

/* What the default figure's title says the figure of d shows. */
static const char *figure_what(const struct sp_sweep_desc *d)
{
    switch (d->measure) {
    case SP_MEASURE_LYAPUNOV:
    case SP_MEASURE_PRECESSION:
        return scalar_looks[d->measure].title;
    case SP_MEASURE_ORBIT:
        return d->driven ? "orbit diagram, once per drive period"
                         : "orbit diagram at the Poincaré crossings";
    case SP_MEASURE_POINCARE:
        return "Poincaré sections (θ = 0, θ̇ > 0), one colour per orbit";
    case SP_MEASURE_SPECTRUM:
        return sp_sweep_points(d) == 1 ? "Lyapunov spectrum: running values against T"
                                       : "Lyapunov spectrum";
    default:
        return "basins of attraction";
    }
}

/* draw_lyapunov's line over one key: lam (and half, where the look has a
 * second series) at the n points, the y axis from lo to hi, x labelled xl. */
static void scalar_line(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                        const double *lam, const double *half, double lo, double hi,
                        const char *xl)
{
    const struct scalar_look *look = &scalar_looks[d->measure];
    const struct sp_sweep_axis *ax = &d->axis[0];
    const long n = sp_sweep_points(d);
    struct frame f = {80, 56, W - 110, H - 116, 0, 1, lo, hi + 0.05 * (hi - lo)};
    key_span(ax, &f.xlo, &f.xhi);
    fix_key_range(&f.xlo, &f.xhi);
    title(d, figure_what(d), look->short_title);
    place(&f, fmax(30, U(18)), U(18), 0);
    draw_title(d, pal, &f);
    draw_axes(&f, pal, xl, look->label);
    clip_to(&f);
    struct curves cv = {0};
    for (int pass = look->series[1] ? 0 : 1; pass < 2; pass++) {
        const double *v = pass ? lam : half;
        double last[2];
        int pen = 0;
        const long from = cv.n;
        set_rgba(pass ? pal->series[1] : pal->muted), set_line_width(pass ? 1.6 : 1.0);
        sp_canvas_path_begin(&G.cv);
        for (long i = 0; i < n; i++) {
            const double x = px(&f, sp_sweep_axis_value(ax, (int)i)), y = py(&f, v[i]);
            poly_to(&pen, last, x, y);
            curve_to(&cv, x, y);
        }
        sp_canvas_path_end(&G.cv);
        mark_isolated(&cv, from);
        curve_to(&cv, NAN, NAN);
    }
    clip_to(NULL);
    const float *const colour[2] = {pal->series[1], pal->muted};
    if (!G.v->legend)
        draw_legend(&f, &cv, look->series, colour, look->series[1] ? 2 : 1, pal);
    free(cv.p);
}

static int draw_lyapunov(FILE *fp, const struct sp_sweep_desc *d,
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
        scalar_line(d, pal, lam, half, lo, hi, xl);
    } else {
        /* cells centred on the grid values */
        struct frame f = {80, 56, W - 200, H - 116, 0, 1, 0, 1};
        key_cells(ax, &f.xlo, &f.xhi), key_cells(ay, &f.ylo, &f.yhi);
        title(d, figure_what(d), look->short_title);
        place(&f, bar_right(lo, hi, look->bar), colorbar_room(lo, hi), BAR_GAP);
        draw_title(d, pal, &f);
        /* one image pixel per grid point up to MAP_MAX_PX a side (cairo
         * makes none wider than 32767); beyond, each pixel is the mean of
         * the finite values of its block of points */
        const int iw = ax->count < MAP_MAX_PX ? ax->count : MAP_MAX_PX;
        const int ih = ay->count < MAP_MAX_PX ? ay->count : MAP_MAX_PX;
        unsigned char *data = sp_canvas_image(&G.cv, (float)f.x0, (float)f.y0, (float)(f.x0 + f.w),
                                              (float)(f.y0 + f.h), iw, ih);
        if (!data) {
            sp_log_error("cannot make the map's %dx%d image", iw, ih);
            free(lam), free(half);
            return SP_E_NOMEM;
        }
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
                put_rgb(data + 4 * ((size_t)(ih - 1 - key_cell(ay, j, ih)) * (size_t)iw +
                                    (size_t)key_cell(ax, i, iw)), rgb);
            }
        key_label(yl, sizeof(yl), ay->key);
        draw_axes(&f, pal, xl, yl);
        draw_colorbar(d, pal, f.x0 + f.w + BAR_GAP, f.y0 + D(20), f.h - D(20), lo, hi, look->bar,
                      &f, 0, 1);
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

/* The lines of an orbit diagram's legend (orbit_legend), right-aligned at
 * x from y down, pt. */
static void orbit_legend_lines(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                               double x, double y)
{
    const char *q = d->peak == SP_PEAK_R ? "r" : "θ";
    char buf[160];
    font_pt(U(12));
    for (int br = 1; br >= -1; br -= 2) {
        if (d->cont != SP_CONTINUE_BOTH && br != (d->cont == SP_CONTINUE_DOWN ? -1 : 1))
            continue;
        const float *c = branch_colour(pal, br);
        snprintf(buf, sizeof(buf), "%s%s at t = k/f", !d->cont ? "" : br > 0 ? "up: " : "down: ",
                 q);
        set_rgba(c);
        text_at(x, y, buf, 1, 0);
        y += U(16);
        if (d->peak) {
            float light[4];
            peak_colour(pal, c, light);
            set_rgba(light);
            snprintf(buf, sizeof(buf), "○ largest %s%s%s over each period",
                     d->peak == SP_PEAK_R ? "" : "|", q, d->peak == SP_PEAK_R ? "" : "|");
            text_at(x, y, buf, 1, 0);
            y += U(16);
        }
    }
    if (d->cont) {
        set_rgba(pal->muted);
        text_at(x, y, "each value starts from the last one's state", 1, 0);
    }
}

/* An orbit diagram's legend's box, w x h pt (orbit_legend): 288 pt wide
 * at least in the default figure. */
static void orbit_legend_size(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                              double plot_w, double *w, double *h)
{
    const int lines = (d->cont == SP_CONTINUE_BOTH ? 2 : 1) * (d->peak ? 2 : 1) + (d->cont != 0);
    double box[4];
    measure_begin();
    orbit_legend_lines(d, pal, 0, 0);
    measure_end(box);
    font_pt(U(12));
    *w = G.print ? fmin(text_width("each value starts from the last one's state") + U(16),
                        plot_w - U(2))
                 : fmax(288, -box[0] + U(14));
    *h = U(16) * lines + U(10);
}

/* What an orbit diagram with --continue or --peak samples, in the corner. */
static void orbit_legend(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                         const struct frame *f)
{
    double bw, bh;
    orbit_legend_size(d, pal, f->w, &bw, &bh);
    legend_room(f, bw, bh, U(2));
    set_rgba4(pal->background[0], pal->background[1], pal->background[2], 0.85);
    fill_rect(f->x0 + f->w - bw - U(2), f->y0 + U(2), bw, bh);
    orbit_legend_lines(d, pal, f->x0 + f->w - U(8), f->y0 + U(8));
}

/* Which colour of a Poincare mosaic is which start: at a printed size a
 * colour bar right of the plot f over the first key's values (low to high,
 * the colours reversed with a falling range), else a small gradient from
 * FROM to TO at the top right. */
static void poincare_key(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                         const struct frame *pf, const char *xl)
{
    if (G.print) {
        double lo, hi;
        key_span(&d->axis[0], &lo, &hi);
        fix_key_range(&lo, &hi);
        const int falling = d->axis[0].to < d->axis[0].from; /* the first orbit's colour at FROM */
        draw_colorbar(d, pal, 0, 0, 0, lo, hi, xl, pf, falling ? 0.95 : 0.1, falling ? 0.1 : 0.95);
        return;
    }
    (void)pf, (void)xl;
    const double x0 = G.key.gx, y0 = G.key.gy, w = G.key.gw, h = G.key.gh;
    colormap_strip(d, x0, y0, w, h, 0, 0.1, 0.95);
    font_pt(U(11));
    set_rgba(pal->muted);
    text_at(x0 - D(5), y0 + h / 2, G.key.lo, 1, 0.5);
    text_at(x0 + w + D(5), y0 + h / 2, G.key.hi, 0, 0.5);
    if (G.v->colorbar_label[0]) /* over the gradient, inside the page */
        label_room(2, G.v->colorbar_label, 2 * (W - D(4) - (x0 + w / 2)),
                   "over the colour gradient at the top right");
    text_at(G.key.lx, y0 - D(4), G.key.name, 0.5, 1);
}

/* Lays out the default Poincare mosaic's key (poincare_key), the first key's
 * values FROM and TO either side of a gradient with the key's name xl (or
 * [view] colorbar_label) over it, after title(): at the top right beside
 * the title, or, where a line of the title or subtitle would reach it, in a
 * row of its own over the plot (G.key.row: its height). */
static void key_layout(const struct sp_sweep_desc *d, const char *xl)
{
    const double pt = G.pt;
    snprintf(G.key.lo, sizeof(G.key.lo), "%g", d->axis[0].from);
    sp_axis_minus(G.key.lo, sizeof(G.key.lo));
    snprintf(G.key.hi, sizeof(G.key.hi), "%g", d->axis[0].to);
    sp_axis_minus(G.key.hi, sizeof(G.key.hi));
    G.key.name = G.v->colorbar_label[0] ? G.v->colorbar_label : xl;
    font_pt(U(11));
    const double wl = text_width(G.key.lo), wr = text_width(G.key.hi), wn = text_width(G.key.name);
    G.key.gw = D(150), G.key.gh = D(10), G.key.row = 0;
    G.key.gx = W - fmax(100, D(5) + wr + D(10)) - G.key.gw;
    G.key.lx = fmax(fmin(G.key.gx + G.key.gw / 2, W - D(4) - wn / 2), D(4) + wn / 2);
    const double left = fmin(G.key.gx - D(5) - wl, G.key.lx - wn / 2) - D(10);
    G.key.gy = D(22); /* beside the title, unless a line of it reaches the key */
    const double bottom = G.key.gy + G.key.gh;
    int clash = 0;
    font_pt(G.title_pt);
    const char *line = G.title_lines;
    for (int i = 0; i < G.title_n; i++, line += strlen(line) + 1)
        clash |= D(10) + i * G.title_pt * TITLE_LEADING < bottom &&
                 title_left() + text_width(line) > left;
    font_pt(SUB_PT);
    line = G.sub_lines;
    for (int i = 0; i < G.sub_n; i++, line += strlen(line) + 1)
        clash |= D(34) + title_extra() + i * SUB_PT * TITLE_LEADING < bottom &&
                 title_left() + text_width(line) > left;
    if (clash) { /* under the subtitle: its name's line, the gradient, a gap */
        G.key.gy = D(50) + title_extra() + sub_extra() + U(11) + D(4);
        G.key.row = G.key.gy + G.key.gh + D(10) - (D(56) + title_extra() + sub_extra());
    }
    font_pt(pt);
}

/* An SVG or PDF keeps every shape it is given (cairo records the page until
 * it ends, and SVG writes an element a shape), so an orbit diagram's dots
 * would grow the file and the memory with --time. There the dots that fall
 * in one cell of a grid over the plot are drawn as one: at the last of them
 * (what is drawn later stays on top, as in the PNG), its colour, with the
 * opacity all of them make together, 1 - (1 - a)^k for k dots of opacity a
 * (dense spots read as dense, as in the PNG). A cell is DOT_CELL_PT a side,
 * a third of a pixel at an SVG's normal zoom and a dot at 300 dpi, larger
 * where the plot would need more than DOT_CELLS of them: the dots, their
 * memory and the file are bounded by the figure's size, not --time. A PNG
 * draws every dot (its memory is its pixels). */
#define DOT_CELL_PT 0.25
#define DOT_CELLS (1L << 22)

/* Each cell: how many dots fall in it (high 16 bits, at most 65535) and
 * how many of them the drawing pass has met (low 16 bits). */
struct dot_grid {
    uint32_t *c; /* NULL: every dot drawn (a PNG) */
    long nx, ny;
    double x0, y0, cell;
};

/* A grid over the plot f (nothing for a PNG). 0 or SP_E_NOMEM. */
static int dot_grid_new(struct dot_grid *g, const struct frame *f)
{
    *g = (struct dot_grid){.x0 = f->x0, .y0 = f->y0};
    if (!G.vector)
        return 0;
    g->cell = fmax(DOT_CELL_PT, sqrt(f->w * f->h / (double)DOT_CELLS));
    g->nx = (long)ceil(f->w / g->cell) + 1, g->ny = (long)ceil(f->h / g->cell) + 1;
    if (!(g->c = calloc((size_t)(g->nx * g->ny), sizeof(*g->c)))) {
        sp_log_error("out of memory for the figure's grid of dots");
        return SP_E_NOMEM;
    }
    return 0;
}

/* The cell of the point (x, y), pt (clamped to the grid). */
static uint32_t *dot_cell(const struct dot_grid *g, double x, double y)
{
    long i = (long)floor((x - g->x0) / g->cell), j = (long)floor((y - g->y0) / g->cell);
    i = i < 0 ? 0 : i >= g->nx ? g->nx - 1 : i;
    j = j < 0 ? 0 : j >= g->ny ? g->ny - 1 : j;
    return &g->c[j * g->nx + i];
}

/* Counts a dot at (x, y) into its cell (the first pass). */
static void dot_count(const struct dot_grid *g, double x, double y)
{
    if (!g->c || !isfinite(x) || !isfinite(y))
        return;
    uint32_t *c = dot_cell(g, x, y);
    if (*c >> 16 < 0xffff)
        *c += 1u << 16;
}

/* Whether the dot at (x, y) is drawn (the drawing pass): with no grid,
 * each one at opacity a; else the last one of its cell at the opacity its
 * cell's k dots make together (*a), the others not. */
static int dot_drawn(const struct dot_grid *g, double x, double y, double *a)
{
    if (!g->c)
        return 1;
    uint32_t *c = dot_cell(g, x, y);
    const uint32_t k = *c >> 16, seen = *c & 0xffff;
    if (seen >= k)
        return 0; /* drawn already (a cell of more than 65535) */
    *c += 1;
    if (seen + 1 < k)
        return 0;
    *a = *a >= 1 ? 1 : 1 - pow(1 - *a, (double)k);
    return 1;
}

/* The x and y of an orbit diagram's or a Poincare mosaic's dot of row r:
 * orbit: x = the key, y = theta (driven; r with --peak r) or r;
 * poincare: x = r, y = dr/dt. */
static void dot_xy(const struct sp_sweep_desc *d, const struct row *r, double *x, double *y)
{
    const int orbit = d->measure == SP_MEASURE_ORBIT;
    *x = orbit ? r->key[0] : r->v[1];
    *y = orbit ? (d->driven && d->peak != SP_PEAK_R ? r->v[1] : r->v[2]) : r->v[2];
}

/* The dots' pass over the rows from fp's first: with count, into the
 * grids (dots g, the peaks' rings ring); else drawn in the plot f at
 * radius pt and opacity alpha. 0 or SP_E_INPUT. */
static int dot_pass(FILE *fp, const char *name, struct sp_sweep_desc *d,
                    const struct sp_palette *pal, const struct frame *f,
                    const struct dot_grid *g, const struct dot_grid *ring, int count,
                    double radius, double alpha)
{
    const int orbit = d->measure == SP_MEASURE_ORBIT;
    const int ext = orbit && (d->cont || d->peak); /* t,theta,r,branch,peak */
    const long n = sp_sweep_points(d);
    struct row r;
    double x, y, a;
    if (to_rows(fp, name, d))
        return SP_E_INPUT;
    while (next_row(fp, d, ext ? 5 : 3, &r)) {
        dot_xy(d, &r, &x, &y);
        if (!isfinite(x) || !isfinite(y))
            continue;
        const int peak = ext && d->peak && isfinite(r.v[4]);
        if (count) {
            dot_count(g, px(f, x), py(f, y));
            if (peak)
                dot_count(ring, px(f, x), py(f, r.v[4]));
            continue;
        }
        if (ext) {
            const float *c = branch_colour(pal, (int)r.v[3]);
            if (peak && (a = 1, dot_drawn(ring, px(f, x), py(f, r.v[4]), &a))) {
                float light[4]; /* the period's peak: a light ring */
                peak_colour(pal, c, light);
                set_rgba(light), set_line_width(0.7);
                stroke_ring(px(f, x), py(f, r.v[4]), 1.8);
            }
            set_rgba4(c[0], c[1], c[2], a = alpha);
        } else if (orbit) {
            set_rgba4(pal->series[1][0], pal->series[1][1], pal->series[1][2], a = alpha);
        } else {
            float rgb[3];
            colormap_rgb(d, 0.1 + 0.85 * (n > 1 ? (double)r.point / (n - 1) : 0.5), rgb);
            set_rgba4(rgb[0], rgb[1], rgb[2], a = fmax(alpha, 0.5));
        }
        if (dot_drawn(g, px(f, x), py(f, y), &a)) {
            G.col[3] = (float)a;
            fill_rect(px(f, x) - radius, py(f, y) - radius, 2 * radius, 2 * radius);
        }
        flush_if_long();
    }
    return 0;
}

/* Orbit diagram and Poincare mosaic: a pass over the rows for the range,
 * one for the grid of an SVG or PDF (struct dot_grid), one for the dots. */
static int draw_dots(FILE *fp, const char *name, struct sp_sweep_desc *d,
                     const struct sp_palette *pal)
{
    const int orbit = d->measure == SP_MEASURE_ORBIT;
    const int ext = orbit && (d->cont || d->peak); /* t,theta,r,branch,peak */
    const int nv = ext ? 5 : 3;
    struct row r;
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY, x, y;
    long dots = 0;
    while (next_row(fp, d, nv, &r)) {
        dot_xy(d, &r, &x, &y);
        if (!isfinite(x) || !isfinite(y))
            continue;
        xlo = fmin(xlo, x), xhi = fmax(xhi, x), ylo = fmin(ylo, y), yhi = fmax(yhi, y);
        if (d->peak && isfinite(r.v[4]))
            ylo = fmin(ylo, r.v[4]), yhi = fmax(yhi, r.v[4]);
        dots++;
    }
    if (orbit)
        key_span(&d->axis[0], &xlo, &xhi);
    if (orbit) /* the key's range */
        fix_key_range(&xlo, &xhi);
    else
        fix_range(&xlo, &xhi);
    fix_range(&ylo, &yhi);
    double mx = orbit ? 0 : 0.04 * (xhi - xlo), my = 0.05 * (yhi - ylo);
    struct frame f = {80, 56, W - 110, H - 116, xlo - mx, xhi + mx, ylo - my, yhi + my};
    char xl[96];
    key_label(xl, sizeof(xl), d->axis[0].key);
    title(d, figure_what(d), orbit ? "orbit diagram" : "Poincaré sections");
    double klo, khi; /* the first key's values, low to high */
    key_span(&d->axis[0], &klo, &khi);
    G.key.row = 0;
    if (!orbit && !G.print)
        key_layout(d, xl);
    place(&f, fmax(30, U(18)), orbit ? U(18) : colorbar_room(klo, khi), orbit ? 0 : BAR_GAP);
    draw_title(d, pal, &f);
    draw_axes(&f, pal, orbit ? xl : "r (m)",
              orbit ? (d->driven && d->peak != SP_PEAK_R ? "θ (degrees)" : "r (m)")
                    : "ṙ (m/s)");
    /* dots fade with their number, so dense regions read as density */
    double radius = G.v->marker_size > 0 ? 0.5 * G.v->marker_size : ext ? 1.1 : orbit ? 0.7 : 0.9;
    double alpha = fmin(0.9, fmax(0.15, 3e4 / (double)(dots + 1)));
    struct dot_grid g, ring = {0};
    int ret = dot_grid_new(&g, &f);
    if (!ret && ext && d->peak)
        ret = dot_grid_new(&ring, &f);
    if (!ret && g.c)
        ret = dot_pass(fp, name, d, pal, &f, &g, &ring, 1, radius, alpha);
    clip_to(&f);
    if (!ret)
        ret = dot_pass(fp, name, d, pal, &f, &g, &ring, 0, radius, alpha);
    free(g.c), free(ring.c);
    if (ret)
        return ret;
    clip_to(NULL);
    if (ext && !G.v->legend) /* over the dots */
        orbit_legend(d, pal, &f);
    if (!orbit)
        poincare_key(d, pal, &f, xl);
    return 0;
}

/* ---- the Lyapunov spectrum ---- */

/* A spectrum CSV's rows: x (T for one point, else the point's index), the
 * four exponents and Kaplan-Yorke's dimension of each (y); lo..hi the range
 * of lambda (of lambda_1 alone for a map). */
struct spectrum {
    long m, cap_x, cap_y;
    double *x, (*y)[5];
    double lo, hi;
};

/* Reads fp's rows into *s (zeroed by the caller, who frees x and y): a map
 * keeps the last row (T = time) of each point. 0 or SP_E_NOMEM. */
static int read_spectrum(FILE *fp, const struct sp_sweep_desc *d, int conv, struct spectrum *s)
{
    struct row r;
    long last_point = -1;
    s->lo = INFINITY, s->hi = -INFINITY;
    if (SP_ARRAY_RESERVE(s->x, s->cap_x, 1, 64) || SP_ARRAY_RESERVE(s->y, s->cap_y, 1, 64))
        return SP_E_NOMEM;
    while (next_row(fp, d, 7, &r)) {
        if (!conv && r.point == last_point)
            s->m--; /* an earlier T of this point: replaced */
        last_point = r.point;
        if (SP_ARRAY_RESERVE(s->x, s->cap_x, s->m + 1, 64) ||
            SP_ARRAY_RESERVE(s->y, s->cap_y, s->m + 1, 64))
            return SP_E_NOMEM;
        s->x[s->m] = conv ? r.v[0] : (double)r.point;
        for (int j = 0; j < 4; j++) {
            s->y[s->m][j] = r.v[1 + j];
            if (isfinite(r.v[1 + j]) && (d->n_axes < 2 || j == 0))
                s->lo = fmin(s->lo, r.v[1 + j]), s->hi = fmax(s->hi, r.v[1 + j]);
        }
        s->y[s->m][4] = r.v[6]; /* Kaplan-Yorke */
        s->m++;
    }
    fix_range(&s->lo, &s->hi);
    return 0;
}

/* Two keys: a map of lambda_1 with the lyapunov map's look, x labelled xl.
 * 0 or SP_E_NOMEM. */
static int draw_spectrum_map(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                             const struct spectrum *s, const char *xl)
{
    const struct sp_sweep_axis *ax = &d->axis[0], *ay = &d->axis[1];
    const double lo = s->lo, hi = s->hi;
    struct frame f = {80, 56, W - 200, H - 116, 0, 1, 0, 1};
    key_cells(ax, &f.xlo, &f.xhi), key_cells(ay, &f.ylo, &f.yhi);
    char yl[96];
    title(d, figure_what(d), "Lyapunov spectrum");
    place(&f, bar_right(lo, hi, "λ1 (1/s)"), colorbar_room(lo, hi), BAR_GAP);
    draw_title(d, pal, &f);
    /* one image pixel per grid point; a point without a row is clear */
    unsigned char *img = sp_canvas_image(&G.cv, (float)f.x0, (float)f.y0, (float)(f.x0 + f.w),
                                         (float)(f.y0 + f.h), ax->count, ay->count);
    if (!img)
        return SP_E_NOMEM;
    memset(img, 0, 4 * (size_t)ax->count * (size_t)ay->count);
    for (long i = 0; i < s->m; i++) {
        int idx[SP_SWEEP_MAX_AXES];
        sp_sweep_point_index(d, (long)s->x[i], idx);
        float rgb[3] = {pal->muted[0] * 0.5f, pal->muted[1] * 0.5f, pal->muted[2] * 0.5f};
        if (isfinite(s->y[i][0]))
            colormap_rgb(d, (s->y[i][0] - lo) / (hi - lo), rgb);
        put_rgb(img + 4 * ((size_t)(ay->count - 1 - key_cell(ay, idx[1], ay->count)) *
                               (size_t)ax->count + (size_t)key_cell(ax, idx[0], ax->count)),
                rgb);
    }
    key_label(yl, sizeof(yl), ay->key);
    draw_axes(&f, pal, xl, yl);
    draw_colorbar(d, pal, f.x0 + f.w + BAR_GAP, f.y0 + D(20), f.h - D(20), lo, hi, "λ1 (1/s)",
                  &f, 0, 1);
    return 0;
}

/* One point: each lambda_j against T (log T axis), the convergence figure;
 * one key: the final four against it; two keys: a map of lambda_1 with the
 * lyapunov map's look. */
static int draw_spectrum(FILE *fp, const struct sp_sweep_desc *d,
                         const struct sp_palette *pal)
{
    const int conv = sp_sweep_points(d) == 1;
    struct spectrum s = {0};
    int ret = 0;
    char xl[96];
    if (read_spectrum(fp, d, conv, &s))
        goto nomem;
    key_label(xl, sizeof(xl), d->axis[0].key);
    if (d->n_axes == 2) {
        if (draw_spectrum_map(d, pal, &s, xl))
            goto nomem;
        goto done;
    }
    const long m = s.m;
    const double *x = s.x, (*y)[5] = (const double(*)[5])s.y, lo = s.lo, hi = s.hi;
    double pad = 0.06 * (hi - lo);
    struct frame f = {80, 56, W - 110, H - 116, 0, 1, lo - pad, hi + pad};
    if (conv) {
        f.xlo = log10(x[0] > 0 ? x[0] : 1);
        f.xhi = log10(m ? fmax(x[m - 1], x[0] * 10) : 10);
    } else {
        key_span(&d->axis[0], &f.xlo, &f.xhi);
    }
    fix_key_range(&f.xlo, &f.xhi);
    title(d, figure_what(d), "Lyapunov spectrum");
    place(&f, fmax(30, U(18)), U(18), 0);
    draw_title(d, pal, &f);
    draw_axes(&f, pal, conv ? "log10 T (s)" : xl, "λ (1/s)");
    /* zero, where lambda_2 and lambda_3 of a free orbit belong */
    set_rgba(pal->axis), set_line_width(0.8);
    line(f.x0, py(&f, 0), f.x0 + f.w, py(&f, 0));
    clip_to(&f);
    static const int colour[4] = {1, 2, 3, 0};
    struct curves cv = {0};
    for (int j = 0; j < 4; j++) {
        double last[2];
        int pen = 0;
        const long from = cv.n;
        set_rgba(pal->series[colour[j]]), set_line_width(1.6);
        sp_canvas_path_begin(&G.cv);
        for (long i = 0; i < m; i++) {
            double xv = conv ? log10(x[i]) : sp_sweep_axis_value(&d->axis[0], (int)x[i]);
            poly_to(&pen, last, px(&f, xv), py(&f, y[i][j]));
            curve_to(&cv, px(&f, xv), py(&f, y[i][j]));
        }
        sp_canvas_path_end(&G.cv);
        mark_isolated(&cv, from);
        curve_to(&cv, NAN, NAN);
    }
    clip_to(NULL);
    char entry[5][128];
    const char *texts[5];
    const float *colours[5];
    for (int j = 0; j < 4; j++) {
        if (conv && m)
            snprintf(entry[j], sizeof(entry[j]), "λ%d = %.4f 1/s", j + 1, y[m - 1][j]);
        else
            snprintf(entry[j], sizeof(entry[j]), "λ%d", j + 1);
        texts[j] = entry[j], colours[j] = pal->series[colour[j]];
    }
    if (conv && m)
        snprintf(entry[4], sizeof(entry[4]), "sum %.3g 1/s, Kaplan-Yorke dimension %.3f",
                 y[m - 1][0] + y[m - 1][1] + y[m - 1][2] + y[m - 1][3], y[m - 1][4]);
    texts[4] = entry[4], colours[4] = pal->muted;
    for (int j = 0; j < 5; j++)
        sp_axis_minus(entry[j], sizeof(entry[j]));
    if (!G.v->legend)
        draw_legend(&f, &cv, texts, colours, conv && m ? 5 : 4, pal);
    free(cv.p);
done:
    free(s.x), free(s.y);
    return ret;
nomem:
    free(s.x), free(s.y);
    sp_log_error("out of memory for a spectrum figure");
    return SP_E_NOMEM;
}

/* ---- basins of attraction ---- */

/* The basin legend's entropies at (lx, ly) pt: S_b and S_bb, their boxes,
 * what no whole box holds (or that there is none). Returns ly moved down
 * by the extra line when there is one. */
static double entropy_legend(const struct sp_basin_map *map, const struct sp_palette *pal,
                             double lx, double ly)
{
    char buf[200];
    set_rgba(pal->text);
    font_pt(U(12));
    const int cut_x = map->nx - map->box * map->boxes_x, cut_y = map->ny - map->box * map->boxes_y;
    if (isfinite(map->entropy))
        snprintf(buf, sizeof(buf), "S_b = %.3f, S_bb = %.3f", map->entropy, map->boundary_entropy);
    else
        snprintf(buf, sizeof(buf), "S_b, S_bb: none");
    text_at(lx, ly + U(8), buf, 0, 0);
    set_rgba(pal->muted);
    font_pt(U(10));
    if (isfinite(map->entropy))
        snprintf(buf, sizeof(buf), "basin entropies, nats, %dx%d boxes", map->box, map->box);
    else
        snprintf(buf, sizeof(buf), "the %dx%d grid has no %dx%d box", map->nx, map->ny, map->box,
                 map->box);
    text_at(lx, ly + U(26), buf, 0, 0);
    if (isfinite(map->entropy) && (cut_x || cut_y)) { /* what no whole box holds */
        char cols[48] = "", rows[48] = "";
        if (cut_x)
            snprintf(cols, sizeof(cols), "last %d column%s", cut_x, cut_x > 1 ? "s" : "");
        if (cut_y)
            snprintf(rows, sizeof(rows), "last %d row%s", cut_y, cut_y > 1 ? "s" : "");
        snprintf(buf, sizeof(buf), "(%s%s%s left out)", cols, cut_x && cut_y ? ", " : "", rows);
        ly += U(16);
        text_at(lx, ly + U(26), buf, 0, 0);
    }
    return ly;
}

/* The basins' legend at (lx, ly), pt: each attractor's colour, basin
 * fraction and state, the entropies, the blown-up starts. */
static void basins_legend(const struct sp_basin_map *map, const float (*rgb)[3],
                          const struct sp_palette *pal, double lx, double ly)
{
    char buf[200];
    long all = 0;
    for (int a = 0; a < map->n_attractors; a++)
        all += map->att[a].count;
    font_pt(U(11));
    for (int a = 0; a < map->n_attractors && !G.v->legend; a++, ly += U(30)) {
        set_rgba4(rgb[a][0], rgb[a][1], rgb[a][2], 1);
        fill_rect(lx, ly, U(14), U(14));
        set_rgba(pal->axis), set_line_width(0.6);
        stroke_rect(lx, ly, U(14), U(14));
        set_rgba(pal->text);
        snprintf(buf, sizeof(buf), "%.1f%%  %s", all ? 100.0 * map->att[a].count / all : 0.0,
                 map->att[a].label);
        sp_axis_minus(buf, sizeof(buf)); /* θ −12.3°, −1 turn */
        char *comma = map->att[a].period > 0 ? strstr(buf, ", θ") : NULL;
        if (comma) { /* the state on a second line */
            *comma = 0;
            text_at(lx + U(20), ly, buf, 0, 0);
            set_rgba(pal->muted);
            text_at(lx + U(20), ly + U(14), comma + 2, 0, 0);
        } else {
            text_at(lx + U(20), ly, buf, 0, 0);
        }
    }
    ly = entropy_legend(map, pal, lx, ly);
    if (map->blown_up) {
        snprintf(buf, sizeof(buf), "%ld blown up (black)", map->blown_up);
        text_at(lx, ly + U(42), buf, 0, 0);
    }
}

/* The room right of the plot the default basins figure's legend takes, pt
 * (300 at least), and refuses (G.err) a legend taller than the page has
 * under the plot's top. */
static double basins_right(const struct sp_basin_map *map, const float (*rgb)[3],
                           const struct sp_palette *pal)
{
    double box[4];
    measure_begin();
    basins_legend(map, rgb, pal, 0, 0);
    measure_end(box);
    const double top = default_top() + U(4);
    if (!G.err && top + box[3] > H - D(4)) {
        char why[200];
        snprintf(why, sizeof(why), "its basins' legend would be %.0f pt tall, and the page has "
                 "%.0f pt for it under the plot's top", box[3], H - D(4) - top);
        G.err = font_refused(why, 0);
    }
    return fmax(300, U(20) + box[2] + D(4));
}

/* The map, one colour per attractor (the colormap's spread for periodic
 * ones, grey for undecided), and the legend with each basin's fraction. */
static int draw_basins(FILE *fp, const struct sp_sweep_desc *d,
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
    char xl[96], yl[96];
    key_label(xl, sizeof(xl), ax->key);
    key_label(yl, sizeof(yl), ay->key);
    struct frame f = {80, 56, W - 380, H - 116, 0, 1, 0, 1};
    key_cells(ax, &f.xlo, &f.xhi), key_cells(ay, &f.ylo, &f.yhi);
    title(d, figure_what(d), "basins of attraction");
    const double right = G.print ? 0 : basins_right(&map, (const float(*)[3])rgb, pal);
    place(&f, right, U(300), U(20)); /* the legend U(20) right of the plot */
    draw_title(d, pal, &f);
    /* one image pixel per grid point, black where the orbit blew up */
    unsigned char *data = sp_canvas_image(&G.cv, (float)f.x0, (float)f.y0, (float)(f.x0 + f.w),
                                          (float)(f.y0 + f.h), ax->count, ay->count);
    if (!data) {
        sp_log_error("cannot make the basins' %dx%d image", ax->count, ay->count);
        sp_basins_free(&map);
        return SP_E_NOMEM;
    }
    memset(data, 0, 4 * (size_t)ax->count * (size_t)ay->count);
    for (long p = 0; p < (long)map.nx * map.ny; p++) {
        int idx[SP_SWEEP_MAX_AXES], a = map.label[p];
        sp_sweep_point_index(d, p, idx);
        static const float black[3] = {0, 0, 0};
        put_rgb(data + 4 * ((size_t)(ay->count - 1 - key_cell(ay, idx[1], ay->count)) *
                                (size_t)ax->count + (size_t)key_cell(ax, idx[0], ax->count)),
                a >= 0 ? rgb[a] : black);
    }
    draw_axes(&f, pal, xl, yl);
    basins_legend(&map, rgb, pal, f.x0 + f.w + U(20), f.y0 + U(4));
    sp_basins_free(&map);
    return 0;
}

/* The room right of the plot and the legend inside it, w x h pt, that the
 * default figure of d takes without its data (fit_plot): its colour bar
 * over 0..1, its legend's entries with zeros for their numbers. */
static void fit_extras(const struct sp_sweep_desc *d, const struct sp_palette *pal,
                       double *right, double *lw, double *lh)
{
    static const char *const spectrum[5] = {"λ1 = −0.0000 1/s", "λ2 = −0.0000 1/s",
                                            "λ3 = −0.0000 1/s", "λ4 = −0.0000 1/s",
                                            "sum −0.000 1/s, Kaplan-Yorke dimension 0.000"};
    static const char *const lambdas[4] = {"λ1", "λ2", "λ3", "λ4"};
    const int scalar = d->measure == SP_MEASURE_LYAPUNOV || d->measure == SP_MEASURE_PRECESSION;
    const int conv = sp_sweep_points(d) == 1;
    *right = fmax(30, U(18)), *lw = *lh = 0;
    if (d->n_axes > 1 && (scalar || d->measure == SP_MEASURE_SPECTRUM)) {
        *right = bar_right(0, 1, scalar ? scalar_looks[d->measure].bar : "λ1 (1/s)");
    } else if (d->measure == SP_MEASURE_BASINS) { /* its entropies' lines, undecided starts' */
        font_pt(U(12));
        double w = text_width("S_b = 0.000, S_bb = 0.000");
        font_pt(U(10));
        w = fmax(w, text_width("basin entropies, nats, 5x5 boxes"));
        font_pt(U(11));
        w = fmax(w, U(20) + text_width("100.0%  undecided (not periodic by the end)"));
        *right = fmax(300, U(20) + w + D(4));
    } else if (d->measure == SP_MEASURE_ORBIT && (d->cont || d->peak) && !G.v->legend) {
        orbit_legend_size(d, pal, W, lw, lh);
        *lw += 2 * U(2), *lh += 2 * U(2);
    } else if (scalar && !G.v->legend) {
        const struct scalar_look *look = &scalar_looks[d->measure];
        legend_size(look->series, look->series[1] ? 2 : 1, lw, lh);
        *lw += 2 * U(8), *lh += 2 * U(8);
    } else if (d->measure == SP_MEASURE_SPECTRUM && !G.v->legend) {
        legend_size(conv ? spectrum : lambdas, conv ? 5 : 4, lw, lh);
        *lw += 2 * U(8), *lh += 2 * U(8);
    }
}

/* The default figure's plot at the text's size G.u, got = w x h pt, and
 * what its text needs, need: the margins place() gives for d's title and
 * subtitle (without d: one line of each) and a Poincare mosaic's key, the
 * colour bar or legend of its measure (fit_extras), a map's y tick
 * labels, and for other figures, whose data it has not yet, labels as
 * over 0..1. G's title is left unset. */
static void fit_plot(const struct sp_sweep_desc *d, const struct sp_palette *pal, double got[2],
                     double need[2])
{
    double right = fmax(30, U(18)), lw = 0, lh = 0;
    G.label_pt = sp_axis_label_pt(U(14), 0);
    G.title_pt = U(17), G.quiet = 1, G.key.row = 0;
    if (d) {
        title(d, figure_what(d), "");
    } else {
        free(G.title_lines), free(G.sub_lines);
        G.title_lines = G.sub_lines = NULL, G.title_n = G.sub_n = 0;
        if (G.title && G.title[0])
            G.err = wrap_title(G.title, "");
    }
    if (d && d->measure == SP_MEASURE_POINCARE) {
        char xl[96];
        key_label(xl, sizeof(xl), d->axis[0].key);
        key_layout(d, xl);
    }
    if (d)
        fit_extras(d, pal, &right, &lw, &lh);
    /* the y tick labels: a map's of its second key, else as over 0..1 */
    struct frame f = {0, 0, 1, H - default_top() - default_bottom(), 0, 1, 0, 1};
    if (d && d->n_axes > 1 && d->measure != SP_MEASURE_ORBIT && d->measure != SP_MEASURE_POINCARE)
        key_cells(&d->axis[1], &f.ylo, &f.yhi);
    got[0] = W - default_left(f.h > 0 ? ylabels_width(&f) : 0) - right, got[1] = f.h;
    need[0] = fmax(LEAST_W, lw), need[1] = fmax(LEAST_H, lh);
    free(G.title_lines), free(G.sub_lines);
    G.title_lines = G.sub_lines = NULL, G.title_n = G.sub_n = 0;
    G.quiet = 0, G.key.row = 0;
}

/* Refuses, before the sweep runs, a default figure (of d; NULL: any) whose
 * text is too large for its plot (fit_plot), with the largest
 * view.font_size that fits. 0, or SP_E_INPUT (said) / SP_E_NOMEM. */
static int fit_check(const struct sp_sweep_desc *d, const struct sp_palette *pal)
{
    double got[2], need[2], lo = 0, hi = G.u;
    const double u = G.u, scale = G.v->font_scale > 0 ? G.v->font_scale : 1;
    char why[256];
    fit_plot(d, pal, got, need);
    if (G.err || (got[0] >= need[0] && got[1] >= need[1]))
        return G.err;
    plot_why(why, sizeof(why), got[0], got[1], need[0], need[1]);
    for (int i = 0; i < 40 && !G.err; i++) { /* the largest text that fits */
        G.u = 0.5 * (lo + hi);
        fit_plot(d, pal, got, need);
        *(got[0] >= need[0] && got[1] >= need[1] ? &lo : &hi) = G.u;
    }
    double best = floor(lo * 14 / scale * 10) / 10;
    for (int i = 0; i < 50 && best > 0.1 && !G.err; i++, best -= 0.1) { /* and says so */
        G.u = best * scale / 14;
        fit_plot(d, pal, got, need);
        if (got[0] >= need[0] && got[1] >= need[1])
            break;
    }
    G.u = u, G.label_pt = sp_axis_label_pt(U(14), 0), G.title_pt = U(17);
    return G.err ? G.err : font_refused(why, best);
}

/* Sets G up for a figure of the style, look being its scene with the
 * style's [view] copied in (kept by the caller until end()): the page, the
 * text's scale, the font ([view] font, with fontconfig's fallbacks), and
 * checks the [view] texts it draws: every character in some font, a title
 * that fits the page (wrap_title); with check (sp_sweep_plot_check, before
 * the sweep: its estimates' text is shaped, and a font shaped is recorded
 * as drawn from), a default figure's text that fits its page, d's
 * (fit_check). 0, or SP_E_INPUT (said), SP_E_NOMEM,
 * SP_E_IO. */
static int begin(const struct sp_plot_style *style, struct sp_scene *look,
                 const struct sp_sweep_desc *d, int check)
{
    const int print = style && style->page_w > 0;
    const double body = look->view.font_size > 0 ? look->view.font_size : print ? 10 : 14;
    const struct sp_view *v = &look->view;
    G.print = print;
    G.w = print ? style->page_w : 900, G.h = print ? style->page_h : 600;
    G.u = body / 14 * (v->font_scale > 0 ? v->font_scale : 1);
    G.lw = print ? SP_AXIS_LINE_PT : 1, G.tick = print ? SP_AXIS_TICK_PT : 5;
    G.label_pt = sp_axis_label_pt(U(14), 0); /* sp_sweep_plot rounds it for its output */
    G.title = style && style->title_set ? v->title : NULL;
    G.v = v;
    G.cancel = style ? style->cancel : NULL;
    G.err = 0, G.pt = U(12);
    sp_canvas_reset(&G.cv);
    G.cv.font = NULL;
    G.lwidth = G.lw;
    G.title_lines = G.sub_lines = NULL, G.title_n = G.sub_n = 0;
    G.key.row = 0, G.measuring = G.quiet = 0;
    struct sp_font_desc fd = {.family = v->font, .where = v->font_where};
    for (int i = 0; i < SP_TEXT_SIZES; i++)
        fd.px[i] = LAYOUT_PX;
    int err = sp_font_make(&G.font, &fd);
    G.cv.font = G.font;
    const char *const labels[][2] = {{"view.xlabel", v->xlabel}, {"view.ylabel", v->ylabel},
                                     {"view.colorbar_label", v->colorbar_label}};
    for (size_t i = 0; !err && i < sizeof(labels) / sizeof(labels[0]); i++) {
        if (i < 2 && strchr(labels[i][1], '|')) { /* the scene's, for a still's panels */
            sp_log_error("%s = '%s' names a still's panels ('|' between); a sweep figure has "
                         "one plot: give it one name with --set %s=NAME", labels[i][0],
                         labels[i][1], labels[i][0]);
            err = SP_E_INPUT;
        } else if (labels[i][1][0]) {
            err = sp_font_check(G.font, labels[i][0], labels[i][1]);
        }
    }
    if (!err) { /* before the grid: what no figure has room for (draw_axes and
                   draw_colorbar check each figure's own room as they draw) */
        const double left = print ? U(4) + G.label_pt * 1.2 + U(6) + U(4) + G.tick : 80;
        const double plot_w = W - left - (print ? U(18) : 30);
        const double plot_h = print ? H - 2 * U(6) - (G.tick + U(4) + G.label_pt * 1.2 + U(5) +
                                                        G.label_pt * 1.25 + U(4))
                                    : H - 116;
        /* a printed size whose plot has no room for its ticks and labels
         * (--size 1inx200in drew its text over itself): refused */
        const double least_w = 12 * U(14), least_h = 7 * U(14); /* an axis label, ticks */
        if (print && (plot_w < least_w || plot_h < least_h)) {
            sp_log_error("--size %.4gx%.4g in: the plot inside the figure's margins would be "
                         "%.0f x %.0f pt, and its ticks and axis labels need at least %.0f x "
                         "%.0f pt at view.font_size %g pt; allowed: a page at least %.2f in "
                         "wide and %.2f in tall, or a smaller view.font_size", W / 72, H / 72,
                         fmax(plot_w, 0), fmax(plot_h, 0), least_w, least_h, body,
                         (W - plot_w + least_w) / 72, (H - plot_h + least_h) / 72);
            return SP_E_INPUT;
        }
        /* a PNG's dots per inch that draw its text in smudges (--dpi 11:
         * 1 px tick labels): refused below the 4 px a still's text keeps */
        const double smallest = fmin(SP_AXIS_LABEL_FRAC * U(14), U(11)); /* pt: ticks, basins */
        if (print && style->dpi > 0 && smallest * style->dpi / 72 < SMALLEST_TEXT_PX) {
            sp_log_error("--dpi %g: at --size %.4gx%.4g in the figure's smallest text (%.3g pt, "
                         "at view.font_size %g pt) would be %.2g px tall; allowed: text of at "
                         "least %d px, as a still's: --dpi %.0f or more, or a larger "
                         "view.font_size", style->dpi, W / 72, H / 72, smallest, body,
                         smallest * style->dpi / 72, SMALLEST_TEXT_PX,
                         ceil(SMALLEST_TEXT_PX * 72 / smallest - 1e-9));
            return SP_E_INPUT;
        }
        font_pt(G.label_pt); /* the axes' names' size (draw_axes) */
        label_room(v->xlabel[0] ? 0 : -1, v->xlabel, plot_w, "the widest plot's width");
        label_room(v->ylabel[0] ? 1 : -1, v->ylabel, plot_h, "the tallest plot's height");
        label_room(v->colorbar_label[0] ? 2 : -1, v->colorbar_label, print ? plot_h : 2 * 171,
                   print ? "the tallest bar's height" : "the most any figure's colour bar has");
        font_pt(U(12));
        err = G.err;
    }
    if (!err && !print && check) { /* text the default figure's page cannot hold */
        struct sp_palette pal;
        sp_palette_get(v, &pal);
        err = fit_check(d, &pal);
    }
    if (!err && G.title && G.title[0]) {
        char where[512];
        title_where(where, sizeof(where));
        G.title_pt = U(17);
        err = wrap_title(G.title, where);
    }
    return err;
}

/* Gives back what begin() and title() took. */
static void end(void)
{
    free(G.title_lines), free(G.sub_lines);
    G.title_lines = G.sub_lines = NULL, G.title_n = G.sub_n = 0;
    sp_canvas_free(&G.cv);
    sp_font_destroy(&G.font);
    /* fontconfig keeps its configuration for the next figure; there is
     * none: give it back (a sanitizer build checks) */
    FcFini();
}

int sp_sweep_plot_check(const struct sp_plot_style *style)
{
    struct sp_scene look;
    sp_scene_defaults(&look);
    if (style && style->view)
        look.view = *style->view;
    const int err = begin(style, &look, style ? style->desc : NULL, 1);
    end();
    return err;
}

/* The figure's raster img into out as a PNG (png_io.h) carrying a still's
 * text chunks (provenance.h) but its time, which a sweep has none of: the
 * base scene (as a scene file, which `springpend scene` prints, and
 * canonical, with its hash), the environment, the font files drawn from;
 * and, at a printed size, its dpi (pHYs). RGB when every pixel is opaque.
 * 0 or an SP_E_* code (logged). */
static int write_png(const struct sp_image *img, struct sp_outfile *out,
                     const struct sp_plot_style *style, double dpi)
{
    struct sp_provenance prov = {0};
    struct sp_png_text text[SP_PROVENANCE_N_TEXT];
    int n = 0, opaque = 1, ret = 0;
    for (int y = 0; y < img->height && opaque; y++)
        for (int x = 0; x < img->width; x++)
            opaque &= img->pixels[(size_t)y * (size_t)img->stride + 4 * (size_t)x + 3] == 255;
    if (style && style->scene &&
        !(ret = sp_provenance_init(&prov, style->scene, sp_draw_cairo_version(), NULL))) {
        sp_font_files(G.font, prov.fonts, sizeof(prov.fonts));
        ret = sp_font_environment(G.font, prov.environment, sizeof(prov.environment));
        if (!ret) /* the figure's own: a merged one's is its shards' */
            ret = sp_provenance_set_command(&prov, style->command);
        for (int i = 0; i < SP_PROVENANCE_N_TEXT; i++)
            if (strcmp(prov.text[i].key, "springpend.time"))
                text[n++] = prov.text[i];
    }
    const struct sp_png_write_opts opts = {.level = 6, .text = text, .n_text = n,
                                           .opaque = opaque, .dpi = dpi};
    if (!ret)
        ret = sp_png_write_outfile(out, img, &opts);
    sp_provenance_free(&prov);
    return ret;
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
    if ((ret = begin(style, &look, &d, 0))) { /* the page, the text's scale and font (G) */
        end();
        return ret;
    }
    /* cairo writes front to back: a device or stdout is fine */
    if ((ret = sp_outfile_open(&out, path, SP_OUTFILE_STREAM))) {
        end();
        return ret;
    }
    const char *ext = strrchr(path, '.');
    const int png = !strcasecmp(ext, ".png");
    G.vector = !png;
    const double scale = !png ? 0 : G.print ? (style->dpi > 0 ? style->dpi : 300) / 72 : PNG_SCALE_DEFAULT;
    if (G.print) /* in whole px of the output, as a still's at the same size and dpi */
        G.label_pt = sp_axis_label_pt(U(14), png ? scale : SP_FIGURE_PX_PER_PT);
    struct sp_draw_cairo_desc dd = {
        .canvas = &G.cv, .font = G.font, .width = W, .height = H, .page_w = W, .page_h = H,
        .fd = out.fd, .path = path, .format = !strcasecmp(ext, ".svg") ? SP_FIGURE_SVG : SP_FIGURE_PDF,
        .scene_file = style ? style->scene_file : NULL, .command = style ? style->command : NULL,
        .cancel = style ? style->cancel : NULL};
    memcpy(dd.background, pal.background, sizeof(dd.background));
    struct sp_image img = {0};
    /* the figure's draw list, in pt, drawn through the still figures'
     * backend (in pieces when long: flush_if_long) */
    ret = sp_draw_cairo_begin(&G.dc, &dd, png ? (int)lround(W * scale) : 0,
                              png ? (int)lround(H * scale) : 0);
    if (!ret)
        ret = d.measure == SP_MEASURE_LYAPUNOV || d.measure == SP_MEASURE_PRECESSION
                  ? draw_lyapunov(csv, &d, &pal)
              : d.measure == SP_MEASURE_SPECTRUM ? draw_spectrum(csv, &d, &pal)
              : d.measure == SP_MEASURE_BASINS   ? draw_basins(csv, &d, &pal)
                                                 : draw_dots(csv, csv_name, &d, &pal);
    if (!ret && G.err)
        ret = G.err; /* the text's or the drawing's (logged) */
    else if (!ret && G.cv.err) {
        sp_log_error("out of memory for the figure %s's draw list", path);
        ret = G.cv.err;
    }
    const int drawn = sp_draw_cairo_end(&G.dc, ret ? NULL : &G.cv, png ? &img : NULL);
    if (!ret)
        ret = drawn;
    if (!ret && style && style->cancel && *style->cancel)
        ret = SP_E_INTERRUPTED; /* a figure cut short by a stop is not written */
    if (!ret && png)
        ret = write_png(&img, &out, style, G.print ? scale * 72 : 0);
    sp_image_free(&img);
    if (ret)
        sp_outfile_discard(&out);
    else
        *figure = out; /* the caller commits it after the CSV, or discards it */
    /* cairo keeps its font faces for the next figure; there is none: give
     * them back (a sanitizer build checks), and the font and list */
    sp_draw_cairo_done();
    end();
    return ret;
}
