/* springpend (internal): the teaching overlays drawn into a canvas: strip
 * charts (r, theta, energy, extension), phase portraits, the Poincare
 * section, the heads-up text and the speed colourbar. Axes come from the
 * pre-pass ranges (struct sp_view_extent), so they never jump.
 * Shared with: sweep (sweep_plot.c's colormaps). */
#ifndef SPRINGPEND_PANELS_H
#define SPRINGPEND_PANELS_H

#include "springpend/frame.h"
#include "canvas.h"
#include "layout.h"

/* s: what fades with time (a trail = all, a phase portrait) fades over its
 * newest 10 s and keeps its faintest colour after that, so that its older
 * part never changes and is drawn once. */
#define SP_FADE_S 10.0
/* s: a phase portrait's fade advances in steps this long (panels.c) */
#define SP_FADE_STEP (1.0 / 6.0)

/* Colours of a theme, straight RGBA. */
struct sp_palette {
    float background[4], panel[4], axis[4], grid[4], text[4], muted[4];
    float series[4][4]; /* total / the plotted quantity, kinetic, spring, gravity */
    float cursor[4], accent[4];
    float mount[4], wire_front[4], wire_back[4], pivot[4], bob[4];
    float vectors[SP_VECTOR_COUNT][4]; /* [view] vectors' arrows, by SP_VECTOR_* bit */
    float axis_hw;          /* px: half the width of axes and grid lines; 0 =
                               from the panels' unit */
    float tick;             /* px: a tick's length; 0 = 0.006 of the panels' unit */
    float cmap_lo, cmap_hi; /* the part of the colormap speeds 0..max use: the
                               end that would vanish into the background is left out */
};

/* The theme's palette with [view]'s background applied. */
void sp_palette_get(const struct sp_view *view, struct sp_palette *out);

/* Colour of a speed fraction t in [0, 1] in the scene's colormap. */
void sp_colormap(int colormap, float t, float rgb[3]);

/* Where the energy_bars panel puts its bars, px: bar i (0 = kinetic, then
 * spring, gravity, total, [start, drive work, damping loss,] bounce, swing)
 * is centred at x0 + (i + 0.5) slot_px; value v (J) reaches
 * zero_px - v px_per_J. */
struct sp_bars_scale {
    float zero_px, px_per_J, slot_px, x0;
    int n; /* bars; 0 = no panel */
    /* the energy chart (panel energy), on the same gravity zero: value v
     * (J) at chart_zero_px - v chart_px_per_J; chart 0 = no panel */
    float chart_zero_px, chart_px_per_J;
    int chart;
};

/* How the panels are drawn: [view]'s figure keys, resolved for the output. */
struct sp_panel_style {
    int fade;          /* 0: the phase curves' history at full strength */
    int cursor;        /* 1: the marks of now (time cursor, current state, latest
                          crossing) and their "now" / "latest" legend entries */
    int legend;        /* 1: legends; 0: none */
    int titles;        /* 1: each panel's title */
    int labels;        /* 0 = none, 'a' or 'A': (a), (b), ... in `order` */
    float marker_px;   /* px, a marker's diameter (Poincare points); 0 = the panel's own */
    const char *xlabel, *ylabel; /* [view]'s ("" = each axis's own; '|' lists) */
    const char *xlabel_where, *ylabel_where; /* where each was set ("FILE:LINE",
                          "--set view.xlabel" or ""), for the refusal of one
                          that cannot fit its panel */
    int ss;            /* drawn px per output px, for those messages (0 = 1) */
    float pt;          /* drawn px per pt at a printed size (--size 8.6cm), else 0:
                          there a panel that cannot hold its title, legend and a
                          plot is refused (panel_refused), nothing drawn over */
    float fig_w, fig_h; /* the figure's size, pt (printed sizes), for that message */
    int order[SP_PANEL_COUNT];   /* bit numbers in the order drawn and labelled */
    int n_order;
    int index;         /* set by sp_panels_draw: the panel's place in order */
};

/* Draws every panel the layout holds for frame f, in st's order. `unit` is
 * the frame's smaller side, px (line widths and dot sizes follow it). bars
 * (may be NULL) receives the energy bars' and the energy chart's scales
 * where those panels are drawn. */
void sp_panels_draw(struct sp_canvas *c, const struct sp_layout *lay, const struct sp_frame *f,
                    const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                    const struct sp_panel_style *st, struct sp_bars_scale *bars);

/* Heads-up text: writes the lines for params (time left out) wrapped to
 * max_width px into lines[0..max) and returns how many; line 0 is the time
 * line, filled in at draw time. differs (NULL or "" = none): side by side,
 * the keys in which this scene differs from the others ("stiffness = 5,
 * damping = 0.4"), listed first, in the accent colour. */
#define SP_HUD_MAX_LINES 32
#define SP_HUD_LINE_BYTES 200
/* pd: what may be stated (sp_advise_predict, as info): without a pendulum
 * frequency (g = 0) no omega_p, ratio or 2:1 check. */
int sp_hud_lines(const struct sp_font *font, const struct sp_params *p,
                 const struct sp_prediction *pd, const char *differs, float max_width,
                 char lines[][SP_HUD_LINE_BYTES], int max);
/* A line that is this byte alone is drawn with sp_hud_draw's `live` text, on
 * the dynamic layer (a 3-D scene's measured precession). */
#define SP_HUD_LIVE '\3'
/* Keeps the first of the n lines that fit max_height px (sp_hud_height),
 * the last one kept replaced by "… N more lines: a larger frame shows them"
 * (cut to max_width px); returns how many are kept (0: not even the time
 * line fits). */
int sp_hud_fit(const struct sp_font *font, float max_width, float max_height,
               char lines[][SP_HUD_LINE_BYTES], int n);
/* Height in px of n heads-up lines. */
float sp_hud_height(const struct sp_font *font, int n);
/* Draws the time and the lines in r; live (may be NULL): the text of the
 * SP_HUD_LIVE line at time t. */
void sp_hud_draw(struct sp_canvas *c, const struct sp_rect *r, double t,
                 char lines[][SP_HUD_LINE_BYTES], int n, const struct sp_params *p,
                 const struct sp_palette *pal, const char *live);

/* The colour bar's own name, drawn when [view] colorbar_label is "". */
#define SP_COLORBAR_NAME "|v| (m/s)"
/* Width in px the colourbar needs, and its drawing (speed 0 .. max_speed).
 * label: its name, n lines one after another, each NUL-terminated
 * (sp_font_wrap's); "" = SP_COLORBAR_NAME. The lines stack above the bar. */
float sp_colorbar_width(const struct sp_font *font, float unit, double max_speed, const char *label,
                        int n);
void sp_colorbar_draw(struct sp_canvas *c, const struct sp_rect *r, int colormap,
                      double max_speed, const struct sp_palette *pal, float unit, const char *label,
                      int n);
/* The bar with its ticks and tick labels alone, px. */
float sp_colorbar_bar_width(const struct sp_font *font, float unit, double max_speed);

/* True when omega_spring / omega_pendulum is within 3 % of 2. */
int sp_params_resonant(const struct sp_params *p, double *ratio);

#endif
