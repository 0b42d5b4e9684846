/* springpend: what a refused still of physical size would fit, found by
 * laying it out again (compose only). See figure.h's sp_figure_fit_advise. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/figure.h"
#include "springpend/scene.h"
#include "frame/compose.h"

/* --size's units: pt each, the step a suggested size is rounded up to (in
 * the unit) and the decimals it is written with. */
static const struct fit_unit {
    const char *name;
    double pt, step;
    int decimals;
} fit_units[] = {{"cm", 72 / 2.54, 0.1, 1}, {"mm", 72 / 25.4, 1, 0}, {"in", 72, 0.1, 1},
                 {"pt", 1, 1, 0}};

static const struct fit_unit *unit_of(const char *name)
{
    for (size_t i = 0; name && i < sizeof(fit_units) / sizeof(fit_units[0]); i++)
        if (!strcmp(name, fit_units[i].name))
            return &fit_units[i];
    return NULL;
}

/* The body text a look's figure has, pt: its view.font_size, else the
 * printed default (compose.c's PRINT_FONT_PT). */
#define FIT_FONT_DEFAULT 10.0
#define FIT_FONT_MIN 5.0  /* pt: the smallest font_size suggested */
#define FIT_PAGE_MAX 14400.0 /* pt: --size's largest side, 200 in */

/* A setting laid out: the page (pt), the body text (pt; 0 = the looks'),
 * the panels (SP_PANEL_* bits; ~0u = the looks'). */
struct trial {
    double w, h, font;
    unsigned panels;
};

/* 1 when a page (pt) is past 10:1, where compose.c's small_frame draws a
 * figure without its heads-up text, panels and colour bar. */
static int drops_panels(double w, double h)
{
    return fmax(w, h) > 10 * fmin(w, h);
}

/* 1 when t is past what a still takes: a side over 200 in or under 1 in,
 * a PNG over 7680x4320 px or too large to supersample; or on the other
 * side of 10:1 from the size refused, so that every trial is laid out as
 * that one was (with its panels, or, past 10:1, without them: there only
 * the title, caption and the pendulum are laid out, and a size that brought
 * the panels back would be another figure). */
static int beyond(const struct sp_figure_fit *fit, struct trial t)
{
    const double w = round(t.w * fit->pt_px), h = round(t.h * fit->pt_px);
    const double ss = fit->supersample > 1 ? fit->supersample : 1;
    return t.w > FIT_PAGE_MAX + 1e-6 || t.h > FIT_PAGE_MAX + 1e-6 || fmin(t.w, t.h) < 72 - 1e-6 ||
           drops_panels(t.w, t.h) != drops_panels(fit->page_w, fit->page_h) ||
           (fit->png && (w > 7680 || h > 4320 || w * h * ss * ss > 7680.0 * 4320 * 4));
}

/* 1 when fit's figure lays out at t (compose only, muted). */
static int fits(const struct sp_figure_fit *fit, const struct sp_frame *f, struct trial t)
{
    struct sp_look looks[SP_MAX_CELLS];
    const int n = fit->cells < 1 ? 1 : fit->cells > SP_MAX_CELLS ? SP_MAX_CELLS : fit->cells;
    const int ss = fit->supersample > 1 ? fit->supersample : 1;
    if (beyond(fit, t))
        return 0;
    for (int i = 0; i < n; i++) {
        looks[i] = fit->looks[i];
        if (t.font > 0)
            looks[i].view.font_size = t.font;
        if (t.panels != ~0u)
            looks[i].view.panels = t.panels;
    }
    const int w = (int)round(t.w * fit->pt_px), h = (int)round(t.h * fit->pt_px);
    return sp_compose_cells_fits(&(struct sp_compose_desc){.width = w * ss, .height = h * ss,
                                                           .extent = fit->extent,
                                                           .look = &looks[0], .supersample = ss},
                                 looks, n, f);
}

/* How a larger size is sought: the height alone at the given width (WIDTH
 * alone given), both sides at the given aspect (WIDTHxHEIGHT), or WIDTH
 * alone again (the height following the scene's aspect). */
enum grow { GROW_TALLER, GROW_BOTH, GROW_WIDTH };

/* The k-th size (k = 0: the first on the steps' grid not under the given
 * one) as grown: the page (pt) in *t, the steps of each side's unit in
 * n[0..2) (n[0] < 0: the width as given; n[1] < 0: none, WIDTH alone). */
static struct trial size_step(const struct sp_figure_fit *fit, const struct fit_unit *const u[2],
                              enum grow g, long k, long n[2])
{
    const double sw = u[0]->step * u[0]->pt, sh = u[1]->step * u[1]->pt;
    struct trial t = {fit->page_w, fit->page_h, 0, ~0u};
    n[0] = n[1] = -1;
    if (g == GROW_TALLER) {
        n[1] = (long)ceil(fit->page_h / sh - 1e-6) + k;
        t.h = (double)n[1] * sh;
        return t;
    }
    n[0] = (long)ceil(fit->page_w / sw - 1e-6) + k;
    t.w = (double)n[0] * sw;
    t.h = t.w * fit->page_h / fit->page_w;
    if (g == GROW_BOTH) {
        n[1] = lround(t.h / sh);
        t.h = (double)n[1] * sh;
    }
    return t;
}

/* The smallest k at which size_step's size fits, with k - 1 refused (the
 * given size, under k = 0, was): doubled until one fits, then halved. -1
 * when none fits up to beyond(). */
static long smallest_size(const struct sp_figure_fit *fit, const struct sp_frame *f,
                          const struct fit_unit *const u[2], enum grow g)
{
    long lo = -1, hi = 0, n[2];
    for (;;) {
        if (beyond(fit, size_step(fit, u, g, hi, n))) {
            long a = lo, b = hi; /* the last size within reach, a, tried last */
            while (b - a > 1) {
                const long m = a + (b - a) / 2;
                *(beyond(fit, size_step(fit, u, g, m, n)) ? &b : &a) = m;
            }
            if (a <= lo || !fits(fit, f, size_step(fit, u, g, a, n)))
                return -1;
            hi = a;
            break;
        }
        if (fits(fit, f, size_step(fit, u, g, hi, n)))
            break;
        lo = hi;
        hi = 2 * hi + 1;
    }
    while (hi - lo > 1) {
        const long m = lo + (hi - lo) / 2;
        *(fits(fit, f, size_step(fit, u, g, m, n)) ? &hi : &lo) = m;
    }
    return hi;
}

/* Appends "--size ..." for the smallest size that fits, and why, to buf;
 * 0 when none does. */
static int size_advice(const struct sp_figure_fit *fit, const struct sp_frame *f, char *buf,
                       size_t size)
{
    const int alone = !fit->unit[1] || !fit->unit[1][0];
    const struct fit_unit *u[2] = {unit_of(fit->unit[0]), unit_of(alone ? fit->unit[0] : fit->unit[1])};
    if (!u[0] || !u[1])
        return 0;
    enum grow g = alone ? GROW_TALLER : GROW_BOTH;
    long k = smallest_size(fit, f, u, g), n[2];
    if (k < 0 && alone)
        k = smallest_size(fit, f, u, g = GROW_WIDTH);
    if (k < 0)
        return 0;
    size_step(fit, u, g, k, n);
    char w[32], h[32] = "";
    if (n[0] < 0)
        snprintf(w, sizeof(w), "%.6g%s", fit->page_w / u[0]->pt, u[0]->name);
    else
        snprintf(w, sizeof(w), "%.*f%s", u[0]->decimals, (double)n[0] * u[0]->step, u[0]->name);
    if (n[1] >= 0)
        snprintf(h, sizeof(h), "x%.*f%s", u[1]->decimals, (double)n[1] * u[1]->step, u[1]->name);
    snprintf(buf, size, "--size %s%s (the smallest %s, to %g %s)", w, h,
             g == GROW_TALLER ? "height at that width"
             : g == GROW_BOTH ? "at that aspect" : "width, the height following the scene's aspect",
             u[g == GROW_TALLER]->step, u[g == GROW_TALLER]->name);
    return 1;
}

/* Appends "--set view.font_size=X" for the largest body text (0.5 pt
 * steps, down to FIT_FONT_MIN) that fits at the given size; 0 when none. */
static int font_advice(const struct sp_figure_fit *fit, const struct sp_frame *f, char *buf,
                       size_t size)
{
    const double now = fit->looks[0].view.font_size > 0 ? fit->looks[0].view.font_size
                                                        : FIT_FONT_DEFAULT;
    for (double pt = ceil(now * 2 - 1e-9) / 2 - 0.5; pt >= FIT_FONT_MIN; pt -= 0.5)
        if (fits(fit, f, (struct trial){fit->page_w, fit->page_h, pt, ~0u})) {
            snprintf(buf, size, "--set view.font_size=%g (the largest at this size, to 0.5 pt%s)",
                     pt, fit->looks[0].view.font_scale != 1 ? ", times font_scale" : "");
            return 1;
        }
    return 0;
}

/* The look's panels as view.panels names them, in its order: bits[i] of
 * name[i] ("phase" is two panels); returns how many. */
static int panel_keys(const struct sp_view *v, unsigned bits[SP_PANEL_COUNT],
                      char name[SP_PANEL_COUNT][32])
{
    int order[SP_PANEL_COUNT], n = 0;
    const int np = sp_scene_panel_order(v, order);
    for (int i = 0; i < np; i++) {
        char value[16], key[32];
        snprintf(value, sizeof(value), "%u", 1u << order[i]);
        sp_scene_canonical_display("view.panels", value, key, sizeof(key));
        int j = 0;
        while (j < n && strcmp(name[j], key))
            j++;
        if (j == n)
            snprintf(name[n++], sizeof(name[0]), "%s", key), bits[j] = 0;
        bits[j] |= 1u << order[i];
    }
    return n;
}

/* Appends "--set view.panels=..." for the longest list of the first
 * panels that fits at the given size, else the first panel that fits
 * alone; 0 when none. */
static int panels_advice(const struct sp_figure_fit *fit, const struct sp_frame *f, char *buf,
                         size_t size)
{
    unsigned bits[SP_PANEL_COUNT];
    char name[SP_PANEL_COUNT][32];
    const int n = panel_keys(&fit->looks[0].view, bits, name);
    for (int m = n - 1; m >= 0; m--) { /* m: the first m panels; 0: each alone */
        for (int one = 0; one < (m ? 1 : n); one++) {
            unsigned set = 0;
            char list[256] = "";
            for (int i = m ? 0 : one; i < (m ? m : one + 1); i++)
                set |= bits[i], snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s%s",
                                         list[0] ? "," : "", name[i]);
            if (!fits(fit, f, (struct trial){fit->page_w, fit->page_h, 0, set}))
                continue;
            if (m)
                snprintf(buf, size, "--set view.panels=%s (the first %d of its %d)", list, m, n);
            else
                snprintf(buf, size, "--set view.panels=%s (alone: no first %s fit)", list,
                         n > 1 ? "panels" : "panel");
            return 1;
        }
    }
    return 0;
}

void sp_figure_fit_advise(const struct sp_figure_fit *fit, const struct sp_frame *f)
{
    const struct trial given = {fit->page_w, fit->page_h, 0, ~0u};
    if (!(fit->pt_px > 0) || !fit->looks || beyond(fit, given) || fits(fit, f, given))
        return; /* not refused for its layout (too large a PNG to draw): nothing to say here */
    char said[3][400];
    const int has[3] = {size_advice(fit, f, said[0], sizeof(said[0])),
                        font_advice(fit, f, said[1], sizeof(said[1])),
                        panels_advice(fit, f, said[2], sizeof(said[2]))};
    char line[1400] = "";
    for (int i = 0; i < 3; i++)
        if (has[i])
            snprintf(line + strlen(line), sizeof(line) - strlen(line), "%s%s", line[0] ? "; " : "",
                     said[i]);
    if (line[0])
        sp_log_error("laid out again, each of these fits: %s", line);
    else
        sp_log_error("laid out again, no larger --size (to 200 in), view.font_size down to "
                     "%g pt or shorter view.panels list fits", FIT_FONT_MIN);
}
