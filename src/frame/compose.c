/* springpend (internal): frame composition on the CPU. See compose.h. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/timeline.h"
#include "axis.h"
#include "camera.h"
#include "compose.h"
#include "cover.h"
#include "layout.h"
#include "vectors.h"

enum {
    COIL_TURNS = 12,
    COIL_STEPS = 16,                      /* polyline segments per turn */
    COIL_SEGS = COIL_TURNS * COIL_STEPS,
    HATCHES = 7,
    MAX_STROBE = 400,                     /* stroboscopic images at most */
    CAPTION_LINES = 4,                    /* a timeline's caption band holds this many lines */
    ALL_FADE = (int)SP_FADE_S,            /* s: trail = all fades in its newest 10 s */
};

/* Sizes as fractions of the image's smaller side. */
#define BOB_RADIUS 0.022f
#define PIVOT_RADIUS 0.0065f
#define WIRE_RADIUS 0.0021f  /* half the spring wire's thickness */
#define COIL_RADIUS 0.016f   /* half the coil's width */
#define COIL_TILT 0.35f      /* helix seen from this much above: loop depth */
#define LEAD_TOP 0.012f
#define LEAD_BOTTOM 0.008f   /* beyond the bob's radius */
#define TRAIL_RADIUS 0.0022f
#define MOUNT_HALF 0.035f
#define MARGIN 0.06f         /* around the extent, besides the bob's radius */
/* A figure of physical size (sp_look.pt_px): matplotlib's print defaults,
 * pt. Body text PRINT_FONT_PT unless [view] font_size says otherwise; the
 * panels' markers follow the length whose TEXT_NORMAL fraction is that
 * size; their axis lines, ticks and tick labels are axis.h's, as a sweep
 * figure's. */
#define PRINT_FONT_PT 10.0f
#define PRINT_FONT_FRAC 0.0175f /* text_sizes' frac[SP_TEXT_NORMAL] */
/* The colour bar's label wraps to at most this share of the pendulum's
 * view's width (or the bar's own width, when wider). */
#define COLORBAR_SHARE 0.25f

struct sp_composer {
    struct sp_canvas canvas;  /* this frame's draw list */
    struct sp_font *font;     /* NULL when no text is drawn */
    int font_borrowed;        /* font is sp_compose_desc's, not ours to free */
    struct sp_look look;      /* a copy: what is drawn and how */
    struct sp_view_extent extent;
    struct sp_palette pal;
    struct sp_layout layout;
    int laid_out;             /* layout and camera fitted (at the first frame) */
    char hud[SP_HUD_MAX_LINES][SP_HUD_LINE_BYTES];
    int hud_lines;
    int live_short;           /* 1: the measured precession's long form does not fit */
    int width, height;        /* px */
    float unit;               /* the smaller side, px */
    float ink;                /* what the panels' and colourbar's text, lines and
                                 ticks follow, px: the unit, or for a figure of
                                 physical size (look.pt_px) a fixed length in pt */
    double scale;             /* px per m */
    double ox, oy;            /* px of the world origin (the pivot) */
    double max_speed;         /* m/s, the top of the trail's colormap */
    int premix_trail;         /* light opaque background: trail mixed with it, opaque */
    char *title, *caption;    /* wrapped: lines one after another, each NUL-terminated; owned */
    int title_lines, caption_lines;
    char *cbar;               /* [view] colorbar_label wrapped to the bar's column
                                 (wrap_colorbar_label); NULL = one line as set */
    int cbar_lines;
    const char *wrapped;      /* with a timeline: the text `caption` holds */
    int band_lines;           /* with a timeline: lines of its longest text */
    char speed[32];           /* "speed ×0.25" when [video] speed != 1, else "";
                                 with a clocked timeline, the widest it shows */
    int marker_rows;          /* HUD lines kept blank under the time for the
                                 speed marker (marker_room); 0: beside the time */
    /* trail = all: the part older than ALL_FADE is drawn once (SP_LAYER_ACCUM) */
    double accum_t;           /* s: the last trail point accumulated; < 0 = none */
    struct sp_trail_point accum_p; /* the last one drawn (the dynamic part starts there) */
    struct sp_cover cover;    /* the cells it has crossed: a repeat is left out */
    struct sp_vectors vectors;    /* [view] vectors' scales (set with the layout) */
    double room;                  /* <= 1: the camera's margin (and the arrows) as a
                                     share of their size in a large view */
    double arrow_px;              /* px: the longest arrow (0 without vectors) */
    struct sp_rect motion;        /* px: the rect the motion is centred in */
    struct sp_rect legend;        /* px: the vectors' legend's box */
    struct sp_bars_scale bars;    /* the energy bars' axis (set by each frame) */
    int ss;                       /* the drawing is this many times the output */
    int cell;                     /* one of several scenes side by side */
    struct sp_camera cam;         /* look.perspective: the camera the pendulum is
                                     drawn through (scale, ox, oy unused) */
    double floor_t;               /* s: the floor trace's last accumulated point
                                     (trail = all); < 0 = none */
    float floor_a[2];             /* px: that point */
};

/* The longest arrow, px: SP_VECTOR_MAX_LENGTH of the frame's smaller side,
 * but at most a quarter of the view's smaller side, so that a small view
 * (320x180 beside panels and the heads-up text) keeps most of its room for
 * the motion: its whole room went to the arrows, and the pendulum shrank to
 * a dot (0.19 px per m). */
static float arrow_room(const struct sp_composer *r, const struct sp_rect *v)
{
    if (!r->look.view.vectors)
        return 0;
    return fminf(SP_VECTOR_MAX_LENGTH * r->unit, 0.25f * fminf(v->x1 - v->x0, v->y1 - v->y0));
}

/* Fits the extent plus a margin into rectangle v, equal scale on both axes;
 * the motion is centred in v (r->motion). The margin follows the frame's
 * smaller side, with room for the longest arrow where arrows are drawn; in
 * a view so small that it would take over half of the view's smaller side
 * (a cell side by side, a tiny frame), it and the arrows shrink to that
 * (r->room < 1), so the motion keeps half. */
static void fit_camera(struct sp_composer *r, const struct sp_rect *v)
{
    r->motion = *v;
    const struct sp_view_extent *e = &r->extent;
    /* arrows from the bob need their longest length around the motion */
    double margin = (BOB_RADIUS + MARGIN) * r->unit + arrow_room(r, v);
    const double cap = 0.25 * fmin(v->x1 - v->x0, v->y1 - v->y0);
    r->room = margin > cap && cap > 0 ? cap / margin : 1;
    margin *= r->room;
    if (r->look.perspective) {
        sp_camera_fit(&r->cam, v->x0, v->y0, v->x1, v->y1, (float)margin);
        r->scale = sp_camera_scale(&r->cam);
        return;
    }
    const double ew = fmax(e->xmax - e->xmin, 1e-6);
    const double eh = fmax(e->ymax - e->ymin, 1e-6);
    const double aw = fmax(v->x1 - v->x0 - 2 * margin, 1.0);
    const double ah = fmax(v->y1 - v->y0 - 2 * margin, 1.0);

    sp_compose_rescale(r, fmin(aw / ew, ah / eh));
}

void sp_compose_rescale(struct sp_composer *r, double px_per_m)
{
    const struct sp_view_extent *e = &r->extent;
    const struct sp_rect *v = &r->motion;
    if (r->look.perspective) { /* about the rectangle's centre */
        const double f = px_per_m / sp_camera_scale(&r->cam);
        const double mx = 0.5 * (v->x0 + v->x1), my = 0.5 * (v->y0 + v->y1);
        r->cam.focal *= f;
        r->cam.centre[0] = mx + f * (r->cam.centre[0] - mx);
        r->cam.centre[1] = my + f * (r->cam.centre[1] - my);
        r->scale = px_per_m;
        return;
    }
    r->scale = px_per_m;
    r->ox = 0.5 * (v->x0 + v->x1) - r->scale * 0.5 * (e->xmin + e->xmax);
    r->oy = 0.5 * (v->y0 + v->y1) + r->scale * 0.5 * (e->ymin + e->ymax);
}

double sp_compose_scale(const struct sp_composer *c) { return c->scale; }
double sp_compose_arrow_px(const struct sp_composer *c) { return c->arrow_px; }

void sp_compose_shrink_arrows(struct sp_composer *c, double px)
{
    for (int q = 0; q < SP_VQ_COUNT && px < c->arrow_px; q++)
        c->vectors.px_per[q] *= px / c->arrow_px;
    c->arrow_px = fmin(c->arrow_px, px);
}

/* Text sizes follow the frame's smaller side, with a floor for small
 * frames, or [view] font_size (pt, one px each: see doc/teaching.md) for the
 * body text with the others in the same proportions; times [view]
 * font_scale. A figure of physical size (print = 1, ss px per pt) has
 * matplotlib's proportions instead: ticks and legends 0.85, titles 1.2 of
 * the body text. */
static void text_sizes(float unit, double font_size, double scale, float ss, int print,
                       int px[SP_TEXT_SIZES])
{
    static const float frac[SP_TEXT_SIZES] = {0.0150f, 0.0175f, 0.0230f, 0.0300f};
    static const float print_frac[SP_TEXT_SIZES] = {(float)SP_AXIS_LABEL_FRAC, 1, 1.2f, 1.2f};
    /* at least 11 px: a 480p GIF's tick labels read on a projector */
    static const float floor_px[SP_TEXT_SIZES] = {11, 12, 14, 17};
    for (int s = 0; s < SP_TEXT_SIZES; s++) {
        const float base = print ? (float)font_size * ss * print_frac[s]
                           : font_size > 0
                               ? (float)font_size * ss * frac[s] / frac[SP_TEXT_NORMAL]
                               : fmaxf(ss * floor_px[s], roundf(frac[s] * unit));
        px[s] = (int)fminf(400, fmaxf(4, roundf((float)scale * base)));
    }
}

/* Refuses body text too large for the frame when the HUD, panels, colour
 * bar or vectors' legend are drawn: they are laid out around the plots and
 * the pendulum, and past this they cover them. Allowed: at most 1/15 of the frame's smaller side (video), or
 * 1/8 of it (a figure of physical size), and never less than the body text
 * a default frame has (12 px: text_sizes' floor; 24 pt in a figure). A
 * 24 px floor let 640x240 take 24 px text, where the colour bar's labels
 * overlapped and a legend ran over the panel below (attack11 #14).
 * 0 or SP_E_INPUT (said). */
static int check_text_size(const struct sp_composer *r, const int px[SP_TEXT_SIZES], float ss)
{
    const int print = r->look.pt_px > 0;
    const struct sp_view *view = &r->look.view;
    if (!(view->hud || view->panels || view->colorbar || view->vectors))
        return 0; /* a title or caption alone: wrap_texts fits it to the frame */
    const float side = fminf((float)r->width, (float)r->height);
    const float most = print ? fmaxf(side / 8, 24 * ss) : fmaxf(side / 15, 12 * ss);
    if (px[SP_TEXT_NORMAL] <= most)
        return 0;
    const struct sp_view *v = &r->look.view;
    const char *where = v->text_size_where[0] ? v->text_size_where : "[view] font_size";
    const float unit = ss; /* drawn px per output px, or per pt in print */
    sp_log_error("%s: text of %.0f %s (font_size %g, font_scale %g) cannot fit a %.0fx%.0f %s "
                 "frame: the HUD, legends and labels would cover the plots and the pendulum; "
                 "allowed: at most %.0f %s here; use a smaller font_size or font_scale, or a "
                 "larger frame", where, px[SP_TEXT_NORMAL] / unit, print ? "pt" : "px",
                 v->font_size, v->font_scale, r->width / unit, r->height / unit,
                 print ? "pt" : "px", floorf(most / unit), print ? "pt" : "px");
    return SP_E_INPUT;
}

/* Line i of wrapped text. */
static const char *line_of(const char *wrapped, int i)
{
    while (i-- > 0)
        wrapped += strlen(wrapped) + 1;
    return wrapped;
}

/* "WHERE: [view] KEY" for a text's messages (without WHERE when it is "":
 * the default, or side by side's cell label). */
static void text_label(char *buf, size_t size, const char *where, const char *key)
{
    if (!strncmp(where, "--set ", 6)) /* "--set view.title" says it all */
        snprintf(buf, size, "%s", where);
    else
        snprintf(buf, size, "%s%s[view] %s", where, where[0] ? ": " : "", key);
}

/* How wrap_texts states a length of drawn px: in pt for a figure of
 * physical size (as its layout's refusals and notes are), else in px. */
static double text_len(const struct sp_composer *r, double px)
{
    return r->look.pt_px > 0 ? round(10 * px / (r->ss * r->look.pt_px)) / 10 : round(px);
}

static const char *text_unit(const struct sp_composer *r)
{
    return r->look.pt_px > 0 ? "pt" : "px";
}

/* Wraps the title and caption to the frame's width and checks that every
 * character has a font and that the bands leave the picture at least half
 * the frame: there is no other limit on their length. Each refusal names
 * where the text was set (FILE:LINE or --set) and the limit. 0, SP_E_INPUT
 * (said) or SP_E_NOMEM. */
static int wrap_texts(struct sp_composer *r)
{
    const struct sp_font *f = r->font;
    const float width = r->width - 2 * roundf(0.015f * r->unit); /* layout.c's bands */
    const struct sp_view *v = &r->look.view;
    char title[4200], caption[4200];
    if (r->look.title_what) /* what the title is when no [view] title set it */
        snprintf(title, sizeof(title), "%s", r->look.title_what);
    else
        text_label(title, sizeof(title), v->title_where, "title");
    text_label(caption, sizeof(caption), v->caption_where, "caption");
    int err = 0;
    if (v->title[0] && !(err = sp_font_check(f, title, v->title)))
        err = sp_font_wrap(f, SP_TEXT_TITLE, v->title, width, r->height / 2 / (sp_font_line(f, SP_TEXT_TITLE) > 0 ? sp_font_line(f, SP_TEXT_TITLE) : 1),
                   &r->title, &r->title_lines);
    if (!err && v->caption[0] && !(err = sp_font_check(f, caption, v->caption)))
        err = sp_font_wrap(f, SP_TEXT_NORMAL, v->caption, width, r->height / 2 / (sp_font_line(f, SP_TEXT_NORMAL) > 0 ? sp_font_line(f, SP_TEXT_NORMAL) : 1),
                   &r->caption, &r->caption_lines);
    if (err)
        return err;
    for (int i = 0; i < r->title_lines; i++)
        if (sp_font_width(f, SP_TEXT_TITLE, line_of(r->title, i)) > width) {
            sp_log_error("%s: \"%s\" is %g %s wide, wider than the frame's %g %s for "
                         "text; use a smaller font_size or font_scale, or a wider frame", title,
                         line_of(r->title, i),
                         text_len(r, sp_font_width(f, SP_TEXT_TITLE, line_of(r->title, i))),
                         text_unit(r), text_len(r, width), text_unit(r));
            return SP_E_INPUT;
        }
    for (int i = 0; i < r->caption_lines; i++)
        if (sp_font_width(f, SP_TEXT_NORMAL, line_of(r->caption, i)) > width) {
            sp_log_error("%s: \"%s\" is %g %s wide, wider than the frame's %g %s "
                         "for text; use a smaller font_size or font_scale, or a wider frame", caption,
                         line_of(r->caption, i),
                         text_len(r, sp_font_width(f, SP_TEXT_NORMAL, line_of(r->caption, i))),
                         text_unit(r), text_len(r, width), text_unit(r));
            return SP_E_INPUT;
        }
    const int text_h = r->title_lines * sp_font_line(f, SP_TEXT_TITLE) +
                       r->caption_lines * sp_font_line(f, SP_TEXT_NORMAL);
    if (text_h > r->height / 2) {
        /* both named when both are set: either may be the one to shorten */
        const char *u = text_unit(r);
        sp_log_error("%s%s%s: the title and caption cannot fit: they wrap to %d + %d lines at %g %s wide, "
                     "%g %s of the frame's %g; allowed: at most half the height (%g %s); "
                     "shorten them, use a smaller font_size or font_scale, or a larger frame",
                     v->title[0] ? title : "", v->title[0] && v->caption[0] ? " and " : "",
                     v->caption[0] ? caption : "", r->title_lines, r->caption_lines,
                     text_len(r, width), u, text_len(r, text_h), u, text_len(r, r->height),
                     text_len(r, r->height / 2), u);
        return SP_E_INPUT;
    }
    return 0;
}

/* The caption band's width, px. */
static float band_width(const struct sp_composer *r)
{
    return r->width - 2 * roundf(0.015f * r->unit);
}

/* With a timeline: every text the caption band will show (the opening
 * caption, the cues' captions and notes) must fit in CAPTION_LINES lines
 * of the band's width; the band is as tall as the longest needs. Reports
 * each that does not as FILE:LINE and returns SP_E_INPUT. */
static int check_band(struct sp_composer *r)
{
    const struct sp_timeline *tl = r->look.timeline;
    const float w = band_width(r);
    int bad = 0;
    for (int i = -1; i < tl->n_cues; i++) {
        const char *text = i < 0 ? r->look.view.caption : tl->cues[i].text;
        if (i >= 0 && tl->cues[i].kind == SP_CUE_SPEED)
            continue;
        char *lines;
        int n, wide = 0;
        if (sp_font_wrap(r->font, SP_TEXT_NORMAL, text, w, CAPTION_LINES, &lines, &n))
            return SP_E_NOMEM;
        free(lines);
        /* a word wider than the band (wrap would break it between characters) */
        for (const char *t = text; *t && !wide; t += strspn(t, " ")) {
            const size_t len = strcspn(t, " ");
            char *word = strndup(t, len);
            if (!word)
                return SP_E_NOMEM;
            wide = sp_font_width(r->font, SP_TEXT_NORMAL, word) > w;
            free(word);
            t += len;
        }
        if (n <= CAPTION_LINES && !wide) {
            r->band_lines = n > r->band_lines ? n : r->band_lines;
            continue;
        }
        char where[4200];
        if (i < 0)
            text_label(where, sizeof(where), r->look.view.caption_where, "caption");
        else
            snprintf(where, sizeof(where), "%s:%d: [timeline] %s", tl->origin, tl->cues[i].line,
                     tl->cues[i].kind == SP_CUE_CAPTION ? "caption" : "pause note");
        /* a FILE:LINE message, as the scene's others */
        sp_fprintf_line(stderr, "%s is too long for a %dx%d frame: %s; allowed: what fits in %d lines "
                "of %.0f px at this size (shorten it, or lower view.font_scale = %g)", where,
                     r->width, r->height, wide ? "a word is wider than the frame"
                     : "it needs more lines", CAPTION_LINES, w, r->look.view.font_scale);
        bad = 1;
    }
    return bad ? SP_E_INPUT : 0;
}

/* The least frame (or side-by-side cell), output px, in which the heads-up
 * text, the panels, the colour bar and the speed marker are laid out
 * without overlapping: SP_TEXT_MIN_LONG on the longer side and
 * SP_TEXT_MIN_SHORT on the shorter (test legibility: 320x180 and 180x320
 * hold every panel; at 160x90 the time ran over the speed marker and the
 * panels over the HUD). */
#define SP_TEXT_MIN_LONG 320
#define SP_TEXT_MIN_SHORT 180

/* Below that size (a video frame; a figure of physical size is exempt)
 * those are left out, and said once on stderr (a note: not with -q) with
 * the size they need. ss:
 * drawn px per output px. */
static void small_frame(struct sp_composer *r, float ss)
{
    const float w = (float)r->width / ss, h = (float)r->height / ss;
    struct sp_view *v = &r->look.view;
    /* a figure of physical size (w, h in pt) keeps them down to an inch a
     * side at no more than 10:1 (an 8.6 cm column figure is 244 x 137 pt) */
    if (r->look.pt_px > 0 ? fminf(w, h) >= 72 && fmaxf(w, h) <= 10 * fminf(w, h)
                          : fmaxf(w, h) >= SP_TEXT_MIN_LONG && fminf(w, h) >= SP_TEXT_MIN_SHORT)
        return;
    if (!(v->hud || v->panels || v->colorbar || r->speed[0]))
        return;
    const char *what[4] = {v->hud ? "heads-up text" : NULL, v->panels ? "panels" : NULL,
                           v->colorbar ? "colour bar" : NULL, r->speed[0] ? "speed marker" : NULL};
    char list[128] = "";
    for (int i = 0, n = 0; i < 4; i++)
        if (what[i])
            snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s%s", n++ ? ", " : "",
                     what[i]);
    if (r->look.pt_px > 0)
        sp_log_note("note: at %.0fx%.0f pt the %s would overlap: drawn without them (they "
                    "need at least 72 pt a side and at most 10:1; view.hud = false, "
                    "view.panels = none, view.colorbar = false and video.speed = 1 say so)", w,
                    h, list);
    else
        sp_log_note("note: at %.0fx%.0f%s the %s would overlap: drawn without them (they need "
                    "at least %dx%d, or %dx%d upright; view.hud = false, view.panels = none, "
                    "view.colorbar = false and video.speed = 1 say so)", w, h,
                    r->cell ? " a cell" : "", list, SP_TEXT_MIN_LONG, SP_TEXT_MIN_SHORT,
                    SP_TEXT_MIN_SHORT, SP_TEXT_MIN_LONG);
    v->hud = 0;
    v->panels = 0;
    v->colorbar = 0;
    r->speed[0] = 0;
}

static int check_hud_time(const struct sp_composer *r);

int sp_compose_make(struct sp_composer **out, const struct sp_compose_desc *desc)
{
    struct sp_composer *r = calloc(1, sizeof(*r));
    int err;

    *out = NULL;
    if (!r) {
        sp_log_error("out of memory for the composer");
        return SP_E_NOMEM;
    }
    if (desc->look)
        r->look = *desc->look;
    else
        sp_look_of(NULL, &r->look);
    r->width = desc->width;
    r->cell = desc->cell;
    r->height = desc->height;
    r->ss = desc->supersample > 1 ? desc->supersample : 1;
    r->accum_t = -1;
    r->floor_t = -1;
    r->unit = (float)(r->width < r->height ? r->width : r->height);
    /* ss: drawn px per output px; and per pt at a physical size */
    float ss = desc->supersample > 1 ? (float)desc->supersample : 1;
    if (r->look.pt_px > 0) {
        ss *= (float)r->look.pt_px;
        if (!(r->look.view.font_size > 0))
            r->look.view.font_size = PRINT_FONT_PT;
    }
    r->ink = r->look.pt_px > 0 ? ss * PRINT_FONT_PT / PRINT_FONT_FRAC : r->unit;
    r->extent = desc->extent;
    r->max_speed = desc->extent.max_speed > 0 ? desc->extent.max_speed : 1.0;
    if (!r->look.view.pendulum)
        r->look.perspective = 0;
    if (r->look.perspective &&
        (err = sp_camera_aim(&r->cam, &r->look.view,
                             (const double[3]){r->extent.xmin, r->extent.ymin, r->extent.zmin},
                             (const double[3]){r->extent.xmax, r->extent.ymax, r->extent.zmax}))) {
        free(r);
        return err;
    }
    sp_palette_get(&r->look.view, &r->pal);
    if (r->look.pt_px > 0)
        r->pal.axis_hw = 0.5f * (float)SP_AXIS_LINE_PT * ss, r->pal.tick = (float)SP_AXIS_TICK_PT * ss;
    r->premix_trail = r->pal.background[3] > 0 &&
                      0.3f * r->pal.background[0] + 0.6f * r->pal.background[1] +
                              0.1f * r->pal.background[2] > 0.35f;
    const struct sp_timeline *tl = r->look.timeline;
    if (tl && tl->clocked) /* the marker shows throughout: "paused", "speed ×0.25" */
        snprintf(r->speed, sizeof(r->speed), "paused");
    else if (r->look.speed != 1) /* a real multiplication sign */
        snprintf(r->speed, sizeof(r->speed), "speed \xc3\x97%g", r->look.speed);
    if (!r->look.view.pendulum || r->look.ensemble_count > 1)
        r->look.view.colorbar = 0; /* no speed-coloured trail to explain */
    if (r->look.ensemble_count > 1)
        r->look.view.vectors = 0; /* the members are drawn, not the one bob */
    small_frame(r, ss);
    if (r->look.view.panels || r->look.view.hud || r->look.view.colorbar || r->look.view.vectors ||
        r->look.view.title[0] || r->look.view.caption[0] || r->speed[0] || r->look.view.font[0] || tl) {
        struct sp_font_desc fd = {.family = r->look.view.font, .where = r->look.view.font_where};
        text_sizes(r->unit, r->look.view.font_size, r->look.view.font_scale, ss,
                   r->look.pt_px > 0, fd.px);
        if ((err = check_text_size(r, fd.px, ss)) != 0) {
            sp_compose_destroy(&r);
            return err;
        }
        r->font_borrowed = desc->font != NULL;
        err = desc->font ? (r->font = (struct sp_font *)desc->font, 0) : sp_font_make(&r->font, &fd);
        if (!err)
            err = wrap_texts(r);
        if (!err && tl)
            err = check_band(r);
        if (!err)
            err = check_hud_time(r);
        if (err) {
            sp_compose_destroy(&r);
            return err;
        }
        r->canvas.font = r->font;
    }
    *out = r;
    return 0;
}

/* Puts the vectors' legend (w x h px) in the first corner of the view, of
 * top-left, bottom-left, top-right and bottom-right, that the motion's box
 * (with the bob and the arrows' room around it) leaves free; top-left when
 * none does. It was always top-left, over the pendulum hanging there. */
static int legend_corner(struct sp_composer *r, float w, float h)
{
    const struct sp_rect *c = &r->layout.camera;
    const struct sp_view_extent *e = &r->extent;
    const double m = ((BOB_RADIUS + MARGIN) * r->unit + arrow_room(r, &r->motion)) * r->room;
    const struct sp_rect box = {(float)(r->ox + r->scale * e->xmin - m),
                                (float)(r->oy - r->scale * e->ymax - m),
                                (float)(r->ox + r->scale * e->xmax + m),
                                (float)(r->oy - r->scale * e->ymin + m)};
    const struct sp_rect corner[4] = {{c->x0, c->y0, c->x0 + w, c->y0 + h},
                                      {c->x0, c->y1 - h, c->x0 + w, c->y1},
                                      {c->x1 - w, c->y0, c->x1, c->y0 + h},
                                      {c->x1 - w, c->y1 - h, c->x1, c->y1}};
    r->legend = corner[0];
    for (int i = 0; i < 4 && !r->look.perspective; i++) /* perspective: no ox, oy */
        if (!sp_rect_overlap(&corner[i], &box)) {
            r->legend = corner[i];
            return 0;
        }
    return 1;
}

/* No corner of the view is free of the motion (legend_corner returned 1):
 * the motion is fitted again beside the legend (w x h px, at the view's
 * top left), below it or to its right, whichever draws it larger, so the
 * legend never covers the pendulum. */
static void legend_room(struct sp_composer *r, const struct sp_params *p, float w, float h)
{
    const struct sp_rect *cam = &r->layout.camera;
    const float g = r->layout.gap;
    const struct sp_rect side[2] = {{cam->x0, cam->y0 + h + g, cam->x1, cam->y1},
                                    {cam->x0 + w + g, cam->y0, cam->x1, cam->y1}};
    double best = 0;
    int pick = -1;
    for (int i = 0; i < 2; i++) {
        if (!sp_rect_valid(&side[i]))
            continue;
        fit_camera(r, &side[i]);
        if (r->scale > best)
            best = r->scale, pick = i;
    }
    if (pick < 0) {
        fit_camera(r, cam);
        return;
    }
    fit_camera(r, &side[pick]);
    r->arrow_px = arrow_room(r, &side[pick]) * r->room;
    sp_vectors_setup(&r->vectors, &r->look, &r->extent, p, r->unit, (float)r->arrow_px);
    sp_vectors_legend_size(r->font, &r->vectors, &w, &h); /* its keys may round anew */
    r->legend = (struct sp_rect){cam->x0, cam->y0, cam->x0 + w, cam->y0 + h};
}

/* deg (degrees) as the HUD prints an angle: one decimal, or two significant
 * digits where that would print 0.0 (a tiny turn is a number, not "0.0"):
 * "0.0012°", and past SP_AXIS_MAX_DECIMALS decimals "3.7×10⁻⁸°", as the
 * axes write numbers; with a real minus sign. */
static void hud_degrees(char *buf, size_t size, double deg)
{
    const char *sign = deg < 0 ? "\u2212" : "";
    if (deg == 0 || fabs(deg) >= 0.05) {
        snprintf(buf, size, "%s%.1f°", sign, fabs(deg));
        return;
    }
    /* two significant digits: a step one decade below the leading digit's,
     * taken after rounding (0.0099996 is 0.010, not 0.0100) */
    double step = pow(10, floor(log10(fabs(deg))) - 1);
    if (round(fabs(deg) / step) >= 100)
        step *= 10;
    char num[48];
    sp_axis_number_step(num, sizeof(num), round(fabs(deg) / step) * step, step);
    snprintf(buf, size, "%s%s°", sign, num);
}

/* A 3-D scene's heads-up lines, appended after the others: the precession
 * per exchange that the averaged theory predicts, by info's rules
 * (sp_look.predict: "not predicted" and why where info says so), and the
 * one measured from the run so far (an SP_HUD_LIVE line, filled per frame
 * by hud_measured). Long forms, short ones where those do not fit the
 * width; left out where neither does. */
static void hud_precession(struct sp_composer *r, const struct sp_font *f, float width)
{
    const struct sp_prediction *pd = &r->look.predict;
    char line[SP_HUD_LINE_BYTES], deg[64];
    if (pd->brief && pd->brief[0]) {
        snprintf(line, sizeof(line), "precession per exchange, theory: %s", pd->brief);
        if (sp_font_width(f, SP_TEXT_NORMAL, line) > width)
            snprintf(line, sizeof(line), "precession, theory: %s",
                     strncmp(pd->brief, "none", 4) ? "not predicted" : "none");
    } else {
        hud_degrees(deg, sizeof(deg), pd->prec.angle * (180 / M_PI));
        snprintf(line, sizeof(line), "precession per exchange, theory ≈ %s  (averaged, %s)", deg,
                 pd->prec.applies ? "±4%" : "outside its range: rough");
        if (sp_font_width(f, SP_TEXT_NORMAL, line) > width)
            snprintf(line, sizeof(line), "theory ≈ %s/exchange%s", deg,
                     pd->prec.applies ? "" : " (rough)");
    }
    if (sp_font_width(f, SP_TEXT_NORMAL, line) <= width && r->hud_lines < SP_HUD_MAX_LINES)
        snprintf(r->hud[r->hud_lines++], SP_HUD_LINE_BYTES, "%s", line);
    if (pd->brief && pd->brief[0])
        return; /* no slow exchange (or none the theory describes): none to measure */
    /* the measured line: as wide as its widest form, or left out */
    r->live_short = sp_font_width(f, SP_TEXT_NORMAL, "measured so far ≈ −000.0°/exchange (mean of 00)") > width;
    if (r->hud_lines < SP_HUD_MAX_LINES &&
        sp_font_width(f, SP_TEXT_NORMAL, "measured ≈ −000.0°/exchange") <= width)
        snprintf(r->hud[r->hud_lines++], SP_HUD_LINE_BYTES, "%c", SP_HUD_LIVE);
}

/* The measured line's text at frame f (hud_precession). */
static void hud_measured(const struct sp_composer *r, const struct sp_frame *f, char *buf,
                         size_t size)
{
    int peaks = 0;
    const double a = f->history ? sp_history_precession(f->history, &peaks) : NAN;
    char deg[64];
    if (isnan(a)) {
        snprintf(buf, size, r->live_short ? "measured: needs 2 swing peaks (%d)"
                                          : "measured so far: needs 2 swing peaks (%d seen)",
                 peaks);
        return;
    }
    hud_degrees(deg, sizeof(deg), a * (180 / M_PI));
    if (r->live_short)
        snprintf(buf, size, "measured ≈ %s/exchange", deg);
    else
        snprintf(buf, size, "measured so far ≈ %s/exchange (mean of %d)", deg, peaks - 1);
}

/* The colour bar's label as drawn: its wrapped lines, or as set ("" =
 * the bar's own name). */
static const char *colorbar_label(const struct sp_composer *r)
{
    return r->cbar ? r->cbar : r->look.view.colorbar_label;
}

/* Refuses [view] colorbar_label: "WHERE: [view] colorbar_label: the
 * colour bar's label cannot fit: <why, printf-style>; shorten it, ...".
 * Returns SP_E_INPUT. */
static int colorbar_refused(const struct sp_composer *r, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static int colorbar_refused(const struct sp_composer *r, const char *fmt, ...)
{
    char where[600], why[800];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, sizeof(why), fmt, ap);
    va_end(ap);
    text_label(where, sizeof(where), r->look.view.label_where[2], "colorbar_label");
    sp_log_error("%s: the colour bar's label cannot fit: %s; shorten it, use a smaller "
                 "font_size or font_scale, or a larger frame", where, why);
    return SP_E_INPUT;
}

/* Wraps [view] colorbar_label to the colour bar's column, so that a long
 * label never takes the pendulum's room: the column is as wide as the bar
 * with its tick labels, or its own name (SP_COLORBAR_NAME), or
 * COLORBAR_SHARE of the pendulum's view (px, before the bar), whichever is
 * widest; a label that fits on one line is drawn as it was set. A line
 * still wider (a character alone) is refused where check is set, naming
 * where the label was set. 0, SP_E_INPUT (said) or SP_E_NOMEM. */
static int wrap_colorbar_label(struct sp_composer *r, const struct sp_rect *view, int check)
{
    const struct sp_font *f = r->font;
    const char *label = r->look.view.colorbar_label;
    free(r->cbar);
    r->cbar = NULL, r->cbar_lines = 1;
    if (!label[0])
        return 0;
    const float room = fmaxf(fmaxf(sp_colorbar_bar_width(f, r->ink, r->max_speed),
                                   (float)sp_font_width(f, SP_TEXT_SMALL, SP_COLORBAR_NAME)),
                             floorf(COLORBAR_SHARE * (view->x1 - view->x0)));
    if ((float)sp_font_width(f, SP_TEXT_SMALL, label) <= room)
        return 0;
    const int line = sp_font_line(f, SP_TEXT_SMALL) > 0 ? sp_font_line(f, SP_TEXT_SMALL) : 1;
    if (sp_font_wrap(f, SP_TEXT_SMALL, label, room, r->height / line + 1, &r->cbar, &r->cbar_lines))
        return SP_E_NOMEM;
    const char *l = r->cbar;
    for (int i = 0; i < r->cbar_lines; i++, l += strlen(l) + 1) {
        const int w = sp_font_width(f, SP_TEXT_SMALL, l);
        if (w <= room)
            continue;
        if (!check) /* a trial layout (lay_out): the last one says it */
            return 0;
        return colorbar_refused(r, "\"%s\" is %d px wide, wider than the bar's column of "
                                "%.0f px (at most %.0f%% of the pendulum's view, so that the "
                                "pendulum keeps its room); allowed: lines of at most %.0f px", l,
                                w / r->ss, room / r->ss, 100 * COLORBAR_SHARE, room / r->ss);
    }
    return 0;
}

/* After the layout: the colour bar's label may take at most half of the
 * bar's column's height (the bar keeps the rest). 0 or SP_E_INPUT (said,
 * naming where the label was set). */
static int check_colorbar_label(const struct sp_composer *r)
{
    const struct sp_rect *c = &r->layout.colorbar;
    const float h = c->y1 - c->y0, need = (float)(r->cbar_lines * sp_font_line(r->font, SP_TEXT_SMALL));
    if (r->cbar_lines <= 1 || need <= 0.5f * h)
        return 0;
    return colorbar_refused(r, "it wraps to %d lines at %.0f px wide, %.0f px of the bar's "
                            "%.0f px tall column; allowed: at most half of it (%.0f px)",
                            r->cbar_lines, (c->x1 - c->x0) / r->ss, need / r->ss, h / r->ss,
                            0.5f * h / r->ss);
}

/* The widest "t = 12.34 s" the video shows (its time axis' end, each
 * digit as wide as the font's widest), px of the large text. */
static float widest_time(const struct sp_composer *r, const struct sp_font *f)
{
    char t[64], digit[2] = "0", widest = '0';
    int dw = 0;
    for (char d = '0'; d <= '9'; d++) {
        digit[0] = d;
        const int w = sp_font_width(f, SP_TEXT_LARGE, digit);
        if (w > dw)
            dw = w, widest = d;
    }
    snprintf(t, sizeof(t), "t = %.2f s", fmax(r->extent.t_end, 0));
    for (char *c = t; *c; c++)
        if (*c >= '0' && *c <= '9')
            *c = widest;
    return (float)sp_font_width(f, SP_TEXT_LARGE, t);
}

/* The widest speed marker the video shows, px: [video] speed's, or a
 * clocked timeline's "paused" and speeds from its least to its most (3
 * digits, as sp_timeline_marker writes them). */
static float widest_marker(const struct sp_composer *r, const struct sp_font *f)
{
    const struct sp_timeline *tl = r->look.timeline;
    float w = (float)sp_font_width(f, SP_TEXT_LARGE, r->speed);
    if (!tl || !tl->clocked)
        return w;
    char m[32];
    const double lo = fmax(tl->speed_min, 1e-9), hi = fmax(tl->speed_max, lo);
    for (double d = pow(10, floor(log10(lo))); d <= hi * 10; d *= 10)
        for (int k = 0; k < 3; k++) { /* the range's ends, and 8.88 at each power of ten */
            const double v = k == 0 ? lo : k == 1 ? hi : fmin(fmax(8.88 * d, lo), hi);
            sp_timeline_marker(&(struct sp_moment){.speed = v}, m, sizeof(m));
            w = fmaxf(w, (float)sp_font_width(f, SP_TEXT_LARGE, m));
        }
    return w;
}

/* Where the heads-up time and the speed marker do not fit one line of w px
 * (large text at 640x360, attack11 #18: "speed ×2" was drawn over
 * "t = 12345.67 s"), the marker gets a line of its own under the time:
 * blank HUD lines after the time's (lines[0]), as many as a line of large
 * text needs. Sets r->marker_rows. */
static void marker_room(struct sp_composer *r, const struct sp_font *f, float w)
{
    r->marker_rows = 0;
    if (!r->speed[0] || widest_time(r, f) + sp_font_line(f, SP_TEXT_LARGE) + widest_marker(r, f) <= w)
        return;
    const float line_l = (float)sp_font_line(f, SP_TEXT_LARGE), cap_l = (float)sp_font_cap(f, SP_TEXT_LARGE);
    const int k = (int)ceilf((0.5f * (line_l + cap_l) + 0.25f * line_l) /
                             (float)sp_font_line(f, SP_TEXT_NORMAL));
    if (r->hud_lines < 1 || r->hud_lines + k > SP_HUD_MAX_LINES)
        return;
    memmove(r->hud[1 + k], r->hud[1], (size_t)(r->hud_lines - 1) * sizeof(r->hud[0]));
    for (int i = 1; i <= k; i++)
        r->hud[i][0] = 0;
    r->hud_lines += k;
    r->marker_rows = k;
}

/* The layout's description for view (see lay_out), before the heads-up
 * text and the colour bar are placed: their sizes come from it. */
static void layout_desc(const struct sp_composer *r, int view, struct sp_layout_desc *d)
{
    const struct sp_font *f = r->font;
    *d = (struct sp_layout_desc){.width = r->width, .height = r->height,
                                 .panels = r->look.view.panels,
                                 .no_pendulum = !r->look.view.pendulum,
                                 .view_share = view == 1 ? 0.58f : 0, .view_left = view == 2};
    d->n_order = sp_scene_panel_order(&r->look.view, d->order);
    if (r->title_lines)
        d->title_height = (float)(r->title_lines * sp_font_line(f, SP_TEXT_TITLE));
    if (r->look.timeline && r->band_lines)
        d->caption_height = (float)(r->band_lines * sp_font_line(f, SP_TEXT_NORMAL));
    else if (r->caption_lines)
        d->caption_height = (float)(r->caption_lines * sp_font_line(f, SP_TEXT_NORMAL));
}

/* The heads-up column's width, px, in layout l of d: the view's, less a
 * gap each side (the whole frame's without a pendulum). */
static float hud_width(const struct sp_composer *r, const struct sp_layout_desc *d,
                       const struct sp_layout *l)
{
    const struct sp_rect *v = d->no_pendulum ? &(struct sp_rect){0, 0, (float)r->width, 0} : &l->camera;
    return v->x1 - v->x0 - 2 * l->gap;
}

/* The room the heads-up time has before it would reach what is right of
 * the pendulum's view, px: the HUD's column and the gap on its right (the
 * time may end in the gap, as it was drawn before the check; it never
 * reaches the panel's box: attack14 #1). */
static float time_room(const struct sp_composer *r, const struct sp_layout_desc *d,
                       const struct sp_layout *l)
{
    return hud_width(r, d, l) + l->gap;
}

/* 1 when the frame takes its own layout (view 0), not one of the two a
 * cell side by side tries at the first frame (lay_out). */
static int own_layout(const struct sp_composer *r)
{
    return !r->cell || !r->look.view.pendulum || !r->look.view.panels ||
           r->width >= 1.15f * r->height;
}

/* Refuses a text size at which the heads-up time's widest value (the time
 * axis' end, each digit the font's widest: widest_time) is wider than the
 * heads-up column w px: it ran under the first panel (attack12 #19: "t =
 * 987654.32 s" in DejaVu Sans Mono at 640x360, 24 px; check_text_size's
 * side/15 fits the default font's digits, not a wider family's). Says the
 * largest body text (whole px, or pt in print) whose time fits the same
 * column, measured with the same family: fonts made at smaller sizes. A
 * title or caption makes the column grow as text shrinks, so the size said
 * is then one that fits, perhaps not the largest. 0 or SP_E_INPUT (said). */
static int check_time_fits(const struct sp_composer *r, float w)
{
    const struct sp_view *v = &r->look.view;
    const float need = widest_time(r, r->font);
    if (need <= w)
        return 0;
    const int print = r->look.pt_px > 0;
    const float ss = r->ss * (print ? (float)r->look.pt_px : 1);
    const double scale = v->font_scale > 0 ? v->font_scale : 1;
    int cur[SP_TEXT_SIZES];
    text_sizes(r->unit, v->font_size, v->font_scale, ss, print, cur);
    /* from the size at which the time's width scales to w, up while it fits
     * (hinting rounds widths), else down: body text of m output px (pt) */
    int best = 0;
    const float guess = floorf((float)cur[SP_TEXT_NORMAL] / ss * w / need);
    const int below = (int)ceilf((float)cur[SP_TEXT_NORMAL] / ss) - 1; /* under the refused size */
    for (int m = (int)fminf(fmaxf(guess, 1), (float)below), step = 0; m >= 1 && m <= below && step < 40;
         step++) {
        struct sp_font_desc fd = {.family = v->font, .where = v->font_where};
        text_sizes(r->unit, m / scale, scale, ss, print, fd.px);
        struct sp_font *f = NULL;
        if (sp_font_make(&f, &fd))
            break;
        const int fits = widest_time(r, f) <= w;
        sp_font_destroy(&f);
        if (fits) {
            best = m;
            m++; /* and the next one up, while smaller than the refused size */
        } else if (best) {
            break;
        } else {
            m--;
        }
    }
    char t[64];
    snprintf(t, sizeof(t), "t = %.2f s", fmax(r->extent.t_end, 0));
    /* where the size was set, else where the font was (the default size) */
    const char *where = v->text_size_where[0] ? v->text_size_where
                        : v->font_where[0]                  ? v->font_where
                                                            : "[view] font_size";
    const char *unit = print ? "pt" : "px";
    char allowed[96];
    if (best)
        snprintf(allowed, sizeof(allowed), "at most %d %s with this font at this size", best, unit);
    else
        snprintf(allowed, sizeof(allowed), "no text size with this font at this size");
    sp_log_error("%s: text of %.0f %s (font_size %g, font_scale %g) in view.font '%s' cannot fit a "
                 "%.0fx%.0f %s frame: the heads-up time (\"%s\", every digit as wide as the "
                 "widest) needs %.0f %s and the heads-up column beside the panels is %.0f %s, so "
                 "it would run under them; allowed: %s; use a smaller font_size or font_scale, a "
                 "narrower font, or a larger frame",
                 where, cur[SP_TEXT_NORMAL] / ss, unit, v->font_size, v->font_scale,
                 v->font[0] ? v->font : SP_FONT_DEFAULT, r->width / ss, r->height / ss, unit, t,
                 need / ss, unit, w / ss, unit, allowed);
    return SP_E_INPUT;
}

/* check_time_fits before anything is drawn, in the frame's own layout (a
 * cell side by side that chooses its layout at the first frame is checked
 * there, by lay_out). 0 or SP_E_INPUT (said). */
static int check_hud_time(const struct sp_composer *r)
{
    if (!r->look.view.hud || !own_layout(r))
        return 0;
    struct sp_layout_desc d;
    struct sp_layout l;
    layout_desc(r, 0, &d);
    sp_layout_compute(&d, &l);
    return check_time_fits(r, time_room(r, &d, &l));
}

/* Places the view, panels, heads-up text and colourbar (once: the
 * parameters do not change during a run). SP_E_INPUT (logged, where check)
 * when the vectors' legend does not fit the pendulum's view: it was drawn
 * over the colour bar and cut off. view: see lay_out. */
static int lay_out_as(struct sp_composer *r, const struct sp_params *p, int view, int check)
{
    const struct sp_font *f = r->font;
    struct sp_layout_desc d;
    layout_desc(r, view, &d);
    /* The view's width decides the HUD's wrapping: lay out once without it. */
    sp_layout_compute(&d, &r->layout);
    if (r->look.view.hud) {
        const struct sp_rect *v = d.no_pendulum ? &(struct sp_rect){0, 0, (float)r->width, 0}
                                                : &r->layout.camera;
        const float w = hud_width(r, &d, &r->layout);
        r->hud_lines = sp_hud_lines(f, p, &r->look.predict, r->look.differs, w, r->hud,
                                    SP_HUD_MAX_LINES);
        const int refused = check ? check_time_fits(r, time_room(r, &d, &r->layout)) : 0;
        if (refused)
            return refused;
        if (r->look.spatial)
            hud_precession(r, f, w);
        marker_room(r, f, w);
        /* at most 0.65 of the view's height (the pendulum keeps the rest), or
         * of the frame's between the bands without a pendulum: lines beyond
         * are left out from the end, and the last kept says how many */
        const float room = d.no_pendulum ? (float)r->height - d.title_height - d.caption_height
                                         : v->y1 - v->y0;
        r->hud_lines = sp_hud_fit(f, w, 0.65f * room - r->layout.gap, r->hud, r->hud_lines);
        if (r->hud_lines <= r->marker_rows + 1) /* its line cut (or "… N more"): beside the time */
            r->marker_rows = 0;
        d.hud_height = r->hud_lines ? sp_hud_height(f, r->hud_lines) : 0;
    } else if (r->speed[0] && !d.title_height) { /* a line for the speed marker alone */
        d.hud_height = (float)sp_font_line(f, SP_TEXT_LARGE);
    }
    if (r->look.view.colorbar) {
        int err = wrap_colorbar_label(r, &r->layout.camera, check);
        if (err)
            return err;
        d.colorbar_width = sp_colorbar_width(r->font, r->ink, r->max_speed, colorbar_label(r),
                                             r->cbar_lines);
    }
    sp_layout_compute(&d, &r->layout);
    if (r->look.view.colorbar && check) {
        int err = check_colorbar_label(r);
        if (err)
            return err;
    }
    const struct sp_rect *cam = &r->layout.camera;
    fit_camera(r, cam);
    r->arrow_px = arrow_room(r, cam) * r->room;
    sp_vectors_setup(&r->vectors, &r->look, &r->extent, p, r->unit, (float)r->arrow_px);
    r->laid_out = 1;
    if (r->look.view.vectors && r->look.view.pendulum && r->font) {
        float w, h;
        sp_vectors_legend_size(r->font, &r->vectors, &w, &h);
        if (legend_corner(r, w, h))
            legend_room(r, p, w, h);
        if (check && (w > cam->x1 - cam->x0 || h > cam->y1 - cam->y0)) {
            sp_log_error("[view] vectors: the arrows' legend needs %.0fx%.0f px, and the "
                         "pendulum's view is %.0fx%.0f px of the %dx%d frame (beside the "
                         "panels, heads-up text and colour bar); use a larger frame (--size), "
                         "fewer panels or vectors, or view.hud = false",
                         w / r->ss, h / r->ss, (cam->x1 - cam->x0) / r->ss,
                         (cam->y1 - cam->y0) / r->ss, r->width / r->ss, r->height / r->ss);
            return SP_E_INPUT;
        }
    }
    return 0;
}

/* Lays the frame out for parameters p (view: 0 the frame's own layout).
 * A cell of scenes side by side (portrait or square) tries the view on top
 * with a larger share (1) and the view at the left with the panels beside
 * it (2), and keeps the one where the motion is drawn larger: a tall, narrow
 * motion gets the left. */
static int lay_out(struct sp_composer *r, const struct sp_params *p)
{
    if (own_layout(r))
        return lay_out_as(r, p, 0, 1);
    lay_out_as(r, p, 2, 0);
    const double left = r->scale;
    lay_out_as(r, p, 1, 0);
    return left > r->scale ? lay_out_as(r, p, 2, 1) : lay_out_as(r, p, 1, 1);
}

/* ---- geometry, all in px ---- */

static void to_px(const struct sp_composer *r, double x, double y, float p[2])
{
    p[0] = (float)(r->ox + r->scale * x);
    p[1] = (float)(r->oy - r->scale * y);
}

/* The world point (x, y, z) m, lab, in px: through the camera in
 * perspective (z counts), else the front view's (z is left out). Returns px
 * per m there (0: behind the eye). */
static double world_px(const struct sp_composer *r, double x, double y, double z, float p[2])
{
    if (!r->look.perspective) {
        to_px(r, x, y, p);
        return r->scale;
    }
    return sp_camera_project(&r->cam, (const double[3]){x, y, z}, p);
}

/* The trail's segment from a to point q (a, q in px): colour by speed, alpha
 * and width by age (1 = newest, 0 = oldest shown). */
static void trail_segment(struct sp_composer *r, const float a[2], const float b[2], float speed,
                          float age)
{
    const struct sp_look *lk = &r->look;
    const float w = TRAIL_RADIUS * r->unit;
    const float floor_alpha = lk->view.trail == SP_TRAIL_ALL ? 0.3f : 0.03f;
    const float fade = lk->view.fade ? 1.0f : 0.0f;
    const float *bg = r->pal.background;
    float alpha = 1 - fade * (1 - floor_alpha) * (1 - powf(age, 1.4f)), color[4] = {0, 0, 0, 1};
    sp_colormap(lk->view.colormap, r->pal.cmap_lo + (r->pal.cmap_hi - r->pal.cmap_lo) *
                fminf(speed / (float)r->max_speed, 1.0f), color);
    if (r->premix_trail) {
        for (int k = 0; k < 3; k++)
            color[k] = bg[k] + alpha * (color[k] - bg[k]);
        alpha = 1;
    }
    color[3] = alpha;
    sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], w * (1 - fade * 0.45f * (1 - age)), color);
}

/* Index of the first trail point later than t (points are in time order). */
static int trail_after(const struct sp_trail *tr, double t)
{
    int lo = 0, hi = tr->count;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (sp_trail_at(tr, mid)->t <= t)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The simulated s a trail fades over: the window of [view] trail (frames
 * or a duration), or for trail = all its newest ALL_FADE s. */
static double trail_span(const struct sp_look *lk)
{
    return lk->view.trail == SP_TRAIL_ALL ? ALL_FADE
           : lk->view.trail == SP_TRAIL_DURATION ? lk->view.trail_duration
           : (lk->view.trail - 1) * lk->speed / lk->fps;
}

/* Trail segments, oldest first, over the scene's trail window (a number of
 * frames, a duration, or the whole run), fading and thinning with age in
 * simulated time, so a trail looks the same at any fps. Points closer than
 * a pixel to the last drawn one add nothing and are skipped. A trail over
 * the whole run (trail = all) fades over its newest ALL_FADE s only; what is
 * older no longer changes and goes to the accumulated layer, each segment
 * once, so a long exposure costs the same per frame however long it is. */
static void put_trail(struct sp_composer *r, const struct sp_trail *tr)
{
    const struct sp_look *lk = &r->look;
    const int all = lk->view.trail == SP_TRAIL_ALL;
    const double now = sp_trail_at(tr, tr->count - 1)->t;
    const double span = trail_span(lk);
    const double start = now - span;
    const struct sp_trail_point *p;
    float a[2], b[2];
    int i;

    sp_canvas_blend(&r->canvas, r->premix_trail ? SP_BLEND_OVER : SP_BLEND_MAX);
    if (all) {
        if (r->accum_t < 0) {
            r->accum_p = *sp_trail_at(tr, 0);
            r->accum_t = r->accum_p.t;
        }
        world_px(r, r->accum_p.x, r->accum_p.y, r->accum_p.z, a);
        i = trail_after(tr, r->accum_t);
        sp_canvas_layer(&r->canvas, SP_LAYER_ACCUM);
        sp_canvas_path_begin(&r->canvas);
        for (; i < tr->count && sp_trail_at(tr, i)->t <= start; i++) {
            const struct sp_trail_point *q = sp_trail_at(tr, i);
            r->accum_t = q->t;
            world_px(r, q->x, q->y, q->z, b);
            if (fabsf(b[0] - a[0]) + fabsf(b[1] - a[1]) < 1.0f)
                continue;
            const float speed = 0.5f * (r->accum_p.speed + q->speed);
            if (sp_cover_new(&r->cover, r->width, r->height, a, b,
                             sp_cover_color(speed / (float)r->max_speed)))
                trail_segment(r, a, b, speed, 0);
            a[0] = b[0], a[1] = b[1];
            r->accum_p = *q;
        }
        sp_canvas_path_end(&r->canvas);
        sp_canvas_layer(&r->canvas, SP_LAYER_DYNAMIC);
        p = &r->accum_p;
    } else {
        i = 0;
        while (i < tr->count - 1 && sp_trail_at(tr, i)->t < start - 1e-9 * (1 + fabs(start)))
            i++; /* the ring may hold a little more than the window */
        p = sp_trail_at(tr, i++);
        world_px(r, p->x, p->y, p->z, a);
    }
    sp_canvas_path_begin(&r->canvas);
    for (; i < tr->count; i++) {
        const struct sp_trail_point *q = sp_trail_at(tr, i);
        world_px(r, q->x, q->y, q->z, b);
        if (i < tr->count - 1 && fabsf(b[0] - a[0]) + fabsf(b[1] - a[1]) < 1.0f)
            continue;
        trail_segment(r, a, b, 0.5f * (p->speed + q->speed),
                      span > 0 ? (float)fmin(fmax((q->t - start) / span, 0), 1) : 1);
        a[0] = b[0], a[1] = b[1];
        p = q;
    }
    sp_canvas_path_end(&r->canvas);
    sp_canvas_blend(&r->canvas, SP_BLEND_OVER);
}

/* Ceiling: a bar just above the pivot with hatch strokes above it. */
static void put_mount(struct sp_composer *r, const float pv[2])
{
    const float u = r->unit, half = MOUNT_HALF * u, wr = WIRE_RADIUS * u;
    const float y = pv[1] - PIVOT_RADIUS * u - wr;
    const float hatch = 0.012f * u;

    sp_canvas_line(&r->canvas, pv[0] - half, y, pv[0] + half, y, 1.2f * wr, r->pal.mount);
    for (int i = 0; i < HATCHES; i++) {
        const float x = pv[0] - half + hatch + (2 * half - hatch) * i / (HATCHES - 1);
        sp_canvas_line(&r->canvas, x - hatch, y - wr - hatch, x, y - wr, 0.55f * wr, r->pal.mount);
    }
}

/* The spring from pivot pv to bob bb: straight leads, then COIL_TURNS turns of
 * a helix seen slightly from the side, its pitch stretching with the length.
 * Segments behind the axis are written first (darker), so the front ones
 * cover them. */
static void put_spring(struct sp_composer *r, const float pv[2], const float bb[2])
{
    const float u = r->unit, wr = WIRE_RADIUS * u, rad = COIL_RADIUS * u;
    const float dx = bb[0] - pv[0], dy = bb[1] - pv[1];
    const float len = sqrtf(dx * dx + dy * dy);
    const float ax = len > 1e-3f ? dx / len : 0, ay = len > 1e-3f ? dy / len : 1;
    float lead0 = LEAD_TOP * u, lead1 = (BOB_RADIUS + LEAD_BOTTOM) * u;
    float c0[2], c1[2], coil;

    if (lead0 + lead1 > 0.3f * len) { /* short spring: shrink the leads */
        const float f = 0.3f * len / (lead0 + lead1);
        lead0 *= f;
        lead1 *= f;
    }
    coil = len - lead0 - lead1;
    c0[0] = pv[0] + ax * lead0;
    c0[1] = pv[1] + ay * lead0;
    c1[0] = bb[0] - ax * lead1;
    c1[1] = bb[1] - ay * lead1;
    sp_canvas_line(&r->canvas, pv[0], pv[1], c0[0], c0[1], wr, r->pal.wire_front);
    sp_canvas_line(&r->canvas, c1[0], c1[1], bb[0], bb[1], wr, r->pal.wire_front);

    for (int front = 0; front <= 1; front++) {
        float a[2] = {c0[0], c0[1]}, b[2];
        for (int i = 1; i <= COIL_SEGS; i++) {
            const float t = (float)i / COIL_SEGS;
            const float phase = 6.28318531f * COIL_TURNS * t;
            /* Ease the radius in and out over the first and last half turn. */
            const float ends = fminf(t, 1.0f - t) * 2.0f * COIL_TURNS;
            const float env = ends >= 1.0f ? 1.0f : ends * ends * (3 - 2 * ends);
            const float side = env * rad * sinf(phase);
            const float along = coil * t + env * rad * COIL_TILT * cosf(phase);
            const float mid = cosf(phase - 3.14159265f / COIL_STEPS); /* mid-segment */

            b[0] = c0[0] + ax * along - ay * side;
            b[1] = c0[1] + ay * along + ax * side;
            if ((mid > 0) == front)
                sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], wr,
                               front ? r->pal.wire_front : r->pal.wire_back);
            a[0] = b[0];
            a[1] = b[1];
        }
    }
}

/* ---- the pendulum in perspective (look.perspective) ---- */

/* A soft ellipse on the floor: the circle of radius rad m about (x, z) at
 * the floor's height, its axes taken from the images of its points along the
 * camera's horizontal right and forward (the camera has no roll). */
static void floor_soft(struct sp_composer *r, double x, double z, double rad, const float color[4])
{
    const struct sp_camera *c = &r->cam;
    const double fl = hypot(c->forward[0], c->forward[2]);
    const double f[2] = {c->forward[0] / fl, c->forward[2] / fl};
    float o[2], a[2], b[2], e[2], g[2];
    if (!world_px(r, x, c->floor_y, z, o) ||
        !world_px(r, x - rad * c->right[0], c->floor_y, z - rad * c->right[2], a) ||
        !world_px(r, x + rad * c->right[0], c->floor_y, z + rad * c->right[2], b) ||
        !world_px(r, x - rad * f[0], c->floor_y, z - rad * f[1], e) ||
        !world_px(r, x + rad * f[0], c->floor_y, z + rad * f[1], g))
        return;
    sp_canvas_soft(&r->canvas, o[0], o[1], 0.5f * fabsf(b[0] - a[0]),
                   fmaxf(0.5f * fabsf(e[1] - g[1]), 0.5f), color);
}

/* The floor under the motion (static): a faint pool of light and a grid of
 * grid_step lines, which the shadow falls on. */
static void put_floor(struct sp_composer *r)
{
    const struct sp_camera *c = &r->cam;
    const int n = (int)lround(c->grid_half / c->grid_step);
    float glow[4], line[4], a[2], b[2];
    memcpy(glow, r->pal.text, sizeof(glow));
    glow[3] = r->premix_trail ? 0.05f : 0.07f;
    memcpy(line, r->pal.grid, sizeof(line));
    line[3] = fminf(1, 2.2f * line[3]);
    sp_canvas_layer(&r->canvas, SP_LAYER_STATIC);
    floor_soft(r, c->target[0], c->target[2], 1.5 * c->grid_half, glow);
    for (int axis = 0; axis < 2; axis++)
        for (int i = -n; i <= n; i++) {
            const double u = i * c->grid_step, h = c->grid_half;
            const double x0 = c->target[0] + (axis ? u : -h), z0 = c->target[2] + (axis ? -h : u);
            const double x1 = c->target[0] + (axis ? u : h), z1 = c->target[2] + (axis ? h : u);
            if (world_px(r, x0, c->floor_y, z0, a) && world_px(r, x1, c->floor_y, z1, b))
                sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], 0.6f * WIRE_RADIUS * r->unit,
                               line);
        }
    sp_canvas_layer(&r->canvas, SP_LAYER_DYNAMIC);
}

/* One segment of the floor trace at strength alpha: the text colour mixed
 * with the background, opaque (so the joints of a path show no beads): on a
 * dark background the brighter of it and the floor wins (SP_BLEND_MAX, set
 * by the caller), on a light one it is drawn over. */
static void floor_segment(struct sp_composer *r, const float a[2], const float b[2], float alpha)
{
    float color[4];
    for (int k = 0; k < 3; k++)
        color[k] = r->pal.background[k] + alpha * (r->pal.text[k] - r->pal.background[k]);
    color[3] = r->pal.background[3] > 0 ? 1 : alpha; /* transparent: the text colour faded */
    if (r->pal.background[3] <= 0)
        memcpy(color, r->pal.text, 3 * sizeof(float));
    sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], 0.5f * TRAIL_RADIUS * r->unit, color);
}

/* The trail's shadow: the bob's path straight below it on the floor (the
 * top view in the picture, where the swing's plane and its turns show), a
 * faint line over the trail's window, fading with age. trail = all keeps
 * the whole run: what is older than ALL_FADE s is drawn once, faint, into
 * the accumulated layer (a star of the swing's planes). */
static void put_floor_trace(struct sp_composer *r, const struct sp_trail *tr)
{
    const struct sp_look *lk = &r->look;
    const int all = lk->view.trail == SP_TRAIL_ALL;
    const double now = sp_trail_at(tr, tr->count - 1)->t;
    const double span = trail_span(lk);
    const double fy = r->cam.floor_y, start = now - span;
    const float floor_alpha = 0.2f;
    float a[2], b[2];
    int i;
    sp_canvas_blend(&r->canvas, r->premix_trail ? SP_BLEND_OVER : SP_BLEND_MAX);
    if (all) {
        if (r->floor_t < 0 &&
            world_px(r, sp_trail_at(tr, 0)->x, fy, sp_trail_at(tr, 0)->z, r->floor_a))
            r->floor_t = sp_trail_at(tr, 0)->t;
        if (r->floor_t < 0)
            return;
        a[0] = r->floor_a[0], a[1] = r->floor_a[1];
        sp_canvas_layer(&r->canvas, SP_LAYER_ACCUM);
        sp_canvas_path_begin(&r->canvas);
        for (i = trail_after(tr, r->floor_t); i < tr->count && sp_trail_at(tr, i)->t <= start; i++) {
            const struct sp_trail_point *q = sp_trail_at(tr, i);
            r->floor_t = q->t;
            if (!world_px(r, q->x, fy, q->z, b) || fabsf(b[0] - a[0]) + fabsf(b[1] - a[1]) < 1.0f)
                continue;
            if (sp_cover_new(&r->cover, r->width, r->height, a, b, SP_COVER_FLOOR))
                floor_segment(r, a, b, floor_alpha);
            a[0] = b[0], a[1] = b[1];
        }
        sp_canvas_path_end(&r->canvas);
        sp_canvas_layer(&r->canvas, SP_LAYER_DYNAMIC);
        r->floor_a[0] = a[0], r->floor_a[1] = a[1];
    } else {
        i = trail_after(tr, start - 1e-9 * (1 + fabs(start)));
        if (i >= tr->count - 1 || !world_px(r, sp_trail_at(tr, i)->x, fy, sp_trail_at(tr, i)->z, a)) {
            sp_canvas_blend(&r->canvas, SP_BLEND_OVER);
            return;
        }
        i++;
    }
    sp_canvas_path_begin(&r->canvas);
    for (; i < tr->count; i++) {
        const struct sp_trail_point *q = sp_trail_at(tr, i);
        if (!world_px(r, q->x, fy, q->z, b) ||
            (i < tr->count - 1 && fabsf(b[0] - a[0]) + fabsf(b[1] - a[1]) < 1.0f))
            continue;
        const float age = span > 0 ? (float)fmin(fmax((q->t - start) / span, 0), 1) : 1;
        floor_segment(r, a, b, floor_alpha + (0.45f - floor_alpha) * (lk->view.fade ? age : 1));
        a[0] = b[0], a[1] = b[1];
    }
    sp_canvas_path_end(&r->canvas);
    sp_canvas_blend(&r->canvas, SP_BLEND_OVER);
}

/* The bob's shadow straight below it on the floor, soft: wider and fainter
 * the higher the bob is above the floor. */
static void put_shadow(struct sp_composer *r, const double bob[3], double bob_m)
{
    const struct sp_camera *c = &r->cam;
    const double height = fmax(c->box_hi[1] - c->floor_y, 1e-6);
    const double above = fmax(bob[1] - c->floor_y, 0) / height;
    const float dark[4] = {0, 0, 0, (float)((r->premix_trail ? 0.4 : 0.85) / (1 + 2 * above))};
    floor_soft(r, bob[0], bob[2], bob_m * (1.6 + 2.5 * above), dark);
}

/* The spring from pv to bb (m, lab) as a helix of COIL_TURNS turns about the
 * line between them, its radius and wire the 2-D spring's at the target's
 * depth, and nearer ones larger: its far half first, darker, then its near
 * half. */
static void put_spring3(struct sp_composer *r, const double pv[3], const double bb[3])
{
    const struct sp_camera *c = &r->cam;
    const double m = r->scale; /* px per m at the target */
    double ax[3] = {bb[0] - pv[0], bb[1] - pv[1], bb[2] - pv[2]};
    const double len = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
    if (len < 1e-9)
        return;
    for (int k = 0; k < 3; k++)
        ax[k] /= len;
    /* e1 across both the axis and the line of sight, e2 = axis x e1 towards the eye or away */
    const double *fw = c->forward;
    double e1[3] = {fw[1] * ax[2] - fw[2] * ax[1], fw[2] * ax[0] - fw[0] * ax[2],
                    fw[0] * ax[1] - fw[1] * ax[0]};
    double n1 = sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
    if (n1 < 1e-9) /* seen along the axis */
        e1[0] = c->right[0], e1[1] = c->right[1], e1[2] = c->right[2], n1 = 1;
    for (int k = 0; k < 3; k++)
        e1[k] /= n1;
    const double e2[3] = {ax[1] * e1[2] - ax[2] * e1[1], ax[2] * e1[0] - ax[0] * e1[2],
                          ax[0] * e1[1] - ax[1] * e1[0]};
    const double rad = COIL_RADIUS * r->unit / m, wr = WIRE_RADIUS * r->unit;
    double lead0 = LEAD_TOP * r->unit / m, lead1 = (BOB_RADIUS + LEAD_BOTTOM) * r->unit / m;
    if (lead0 + lead1 > 0.3 * len) {
        const double f = 0.3 * len / (lead0 + lead1);
        lead0 *= f, lead1 *= f;
    }
    const double coil = len - lead0 - lead1;
    float a[2], b[2];
    double s;
    /* the leads */
    for (int end = 0; end < 2; end++) {
        const double t0 = end ? lead0 + coil : 0, t1 = end ? len : lead0;
        s = world_px(r, pv[0] + ax[0] * t0, pv[1] + ax[1] * t0, pv[2] + ax[2] * t0, a);
        if (s && world_px(r, pv[0] + ax[0] * t1, pv[1] + ax[1] * t1, pv[2] + ax[2] * t1, b))
            sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], wr * (float)(s / m), r->pal.wire_front);
    }
    for (int front = 0; front <= 1; front++) {
        double p[3];
        for (int k = 0; k < 3; k++)
            p[k] = pv[k] + ax[k] * lead0;
        s = world_px(r, p[0], p[1], p[2], a);
        for (int i = 1; i <= COIL_SEGS; i++) {
            const double t = (double)i / COIL_SEGS, phase = 2 * M_PI * COIL_TURNS * t;
            const double ends = fmin(t, 1 - t) * 2 * COIL_TURNS;
            const double env = ends >= 1 ? 1 : ends * ends * (3 - 2 * ends);
            const double along = lead0 + coil * t;
            const double mid = cos(phase - M_PI / COIL_STEPS); /* e2 . (to the eye) at mid-segment */
            for (int k = 0; k < 3; k++)
                p[k] = pv[k] + ax[k] * along + env * rad * (sin(phase) * e1[k] + cos(phase) * e2[k]);
            const double sb = world_px(r, p[0], p[1], p[2], b);
            /* near: the wire's offset points back towards the eye */
            const int near = (mid * -(e2[0] * fw[0] + e2[1] * fw[1] + e2[2] * fw[2])) > 0;
            if (s && sb && near == front)
                sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], wr * (float)(0.5 * (s + sb) / m),
                               front ? r->pal.wire_front : r->pal.wire_back);
            a[0] = b[0], a[1] = b[1], s = sb;
        }
    }
}

/* The bob every view.strobe seconds back from now, fading with age. */
static void put_strobe(struct sp_composer *r, const struct sp_history *h)
{
    const double dt = r->look.view.strobe;
    float p[2], color[4];
    if (!h || h->count < 2 || dt <= 0)
        return;
    const double now = h->samples[h->count - 1].t;
    const int n = (int)fmin(floor(now / dt + 1e-9), MAX_STROBE);
    int j = h->count - 1;
    for (int k = n; k >= 1; k--) { /* oldest first, so newer ones cover them */
        const double t = now - k * dt;
        const float age = 1.0f - (float)k / (float)(n + 1);
        /* the sample nearest to t (samples are in time order) */
        int lo = 0, hi = h->count - 1;
        while (hi - lo > 1) {
            j = (lo + hi) / 2;
            if (h->samples[j].t <= t)
                lo = j;
            else
                hi = j;
        }
        j = t - h->samples[lo].t <= h->samples[hi].t - t ? lo : hi;
        const double px_m = world_px(r, h->samples[j].x, h->samples[j].y, h->samples[j].z, p);
        memcpy(color, r->pal.bob, sizeof(color));
        color[3] = 0.12f + 0.5f * age;
        sp_canvas_disc(&r->canvas, p[0], p[1], 0.8f * BOB_RADIUS * r->unit * (float)(px_m / r->scale),
                       0, color);
    }
}

/* With a timeline: the caption band's text now (dynamic), centred in the
 * band, faded by the moment's opacity; a pause's note in the accent colour. */
static void put_band(struct sp_composer *r, const struct sp_moment *m)
{
    const struct sp_layout *l = &r->layout;
    const struct sp_font *f = r->font;
    const char *text = m ? m->band : r->look.view.caption;
    const float alpha = m ? m->band_alpha : 1;
    float color[4];
    if (!text[0] || alpha <= 0 || !sp_rect_valid(&l->caption))
        return;
    if (text != r->wrapped) { /* wrapped again only when the text changes */
        free(r->caption);
        if (sp_font_wrap(f, SP_TEXT_NORMAL, text, band_width(r), CAPTION_LINES, &r->caption, &r->caption_lines)) {
            r->canvas.err = SP_E_NOMEM;
            r->wrapped = NULL;
            return;
        }
        r->wrapped = text;
    }
    memcpy(color, m && m->band_note ? r->pal.accent : r->pal.muted, sizeof(color));
    color[3] *= alpha;
    const int line = sp_font_line(f, SP_TEXT_NORMAL);
    const float y0 = l->caption.y0 + (float)((r->band_lines - r->caption_lines) * line / 2);
    sp_canvas_layer(&r->canvas, SP_LAYER_DYNAMIC);
    for (int i = 0; i < r->caption_lines; i++)
        sp_canvas_text(&r->canvas, SP_TEXT_NORMAL, 0.5f * (l->caption.x0 + l->caption.x1),
                       y0 + i * line + sp_font_cap(f, SP_TEXT_NORMAL), SP_ALIGN_CENTER, color,
                       line_of(r->caption, i));
}

/* Title, caption and the speed marker (static: the same in every frame;
 * with a timeline the caption band and a clocked marker are the moment's,
 * dynamic). */
static void put_texts(struct sp_composer *r, const struct sp_moment *m)
{
    const struct sp_layout *l = &r->layout;
    const struct sp_font *f = r->font;
    struct sp_canvas *cv = &r->canvas;
    const struct sp_timeline *tl = r->look.timeline;
    char marker[32];
    const char *speed = r->speed;
    sp_canvas_layer(cv, SP_LAYER_STATIC);
    for (int i = 0; i < r->title_lines; i++)
        sp_canvas_text(cv, SP_TEXT_TITLE, 0.5f * (l->title.x0 + l->title.x1),
                       l->title.y0 + i * sp_font_line(f, SP_TEXT_TITLE) + sp_font_cap(f, SP_TEXT_TITLE) +
                       0.5f * (sp_font_line(f, SP_TEXT_TITLE) - sp_font_cap(f, SP_TEXT_TITLE)) -
                       0.15f * sp_font_cap(f, SP_TEXT_TITLE),
                       SP_ALIGN_CENTER, r->pal.text, line_of(r->title, i));
    for (int i = 0; !tl && i < r->caption_lines; i++)
        sp_canvas_text(cv, SP_TEXT_NORMAL, 0.5f * (l->caption.x0 + l->caption.x1),
                       l->caption.y0 + i * sp_font_line(f, SP_TEXT_NORMAL) + sp_font_cap(f, SP_TEXT_NORMAL),
                       SP_ALIGN_CENTER, r->pal.muted, line_of(r->caption, i));
    if (tl)
        put_band(r, m);
    if (tl && tl->clocked) {
        sp_timeline_marker(m ? m : &(struct sp_moment){.speed = r->look.speed}, marker,
                           sizeof(marker));
        speed = marker;
        sp_canvas_layer(cv, SP_LAYER_DYNAMIC);
    }
    /* at the right of the heads-up time line, else of the title */
    if (speed[0] && sp_rect_valid(&l->hud)) /* on its own line (marker_room) a large line down */
        sp_canvas_text(cv, SP_TEXT_LARGE, l->hud.x1,
                       l->hud.y0 + sp_font_cap(f, SP_TEXT_LARGE) +
                           (r->marker_rows ? sp_font_line(f, SP_TEXT_LARGE) : 0),
                       SP_ALIGN_RIGHT, r->pal.accent, speed);
    else if (speed[0])
        sp_canvas_text(cv, SP_TEXT_LARGE, l->title.x1, l->title.y0 + sp_font_cap(f, SP_TEXT_TITLE),
                       SP_ALIGN_RIGHT, r->pal.accent, speed);
    sp_canvas_layer(cv, SP_LAYER_STATIC);
}

int sp_compose_lay_out(struct sp_composer *c, const struct sp_params *p)
{
    return c->laid_out ? 0 : lay_out(c, p);
}

/* Draws frame f's panels in their layout, in [view]'s figure style. */
static void put_panels(struct sp_composer *r, const struct sp_frame *f)
{
    const struct sp_view *v = &r->look.view;
    struct sp_panel_style st = {
        .fade = v->fade, .legend = v->legend == 0, .titles = v->panel_titles,
        .cursor = v->cursor == SP_CURSOR_SHOWN || (v->cursor == SP_CURSOR_AUTO && !r->look.still),
        .labels = v->panel_labels == 1 ? 'a' : v->panel_labels == 2 ? 'A' : 0,
        /* pt: one px each, or look.pt_px at a printed size, times the supersampling */
        .marker_px = (float)(v->marker_size * r->ss * (r->look.pt_px > 0 ? r->look.pt_px : 1)),
        .xlabel = v->xlabel, .ylabel = v->ylabel, .xlabel_where = v->label_where[0],
        .ylabel_where = v->label_where[1], .ss = r->ss,
        .pt = r->look.pt_px > 0 ? (float)(r->ss * r->look.pt_px) : 0};
    if (st.pt > 0)
        st.fig_w = (float)r->width / st.pt, st.fig_h = (float)r->height / st.pt;
    st.n_order = sp_scene_panel_order(v, st.order);
    sp_panels_draw(&r->canvas, &r->layout, f, &r->extent, &r->pal, r->ink, &st, &r->bars);
}

int sp_compose_frame(struct sp_composer *r, const struct sp_frame *f,
                     const struct sp_canvas **out)
{
    struct sp_canvas *cv = &r->canvas;
    float pv[2], bb[2];

    if (!r->laid_out) {
        int err = lay_out(r, f->params);
        if (err)
            return err;
    }
    sp_canvas_reset(cv);
    const double yp = sp_pivot_y(f->params, f->state.t); /* a driven pivot moves */
    to_px(r, 0, yp, pv);
    to_px(r, f->state.x, f->state.y + yp, bb);
    sp_canvas_layer(cv, SP_LAYER_DYNAMIC);
    if (r->look.view.pendulum && f->ensemble) { /* the members instead of the one bob */
        double piv_px = r->scale;
        if (r->look.perspective) { /* a 3-D ensemble (or a camera set): on the floor */
            put_floor(r);
            piv_px = world_px(r, 0, yp, 0, pv);
        }
        put_mount(r, pv);
        sp_compose_ensemble(cv, f->ensemble, r->ox, r->oy, r->scale, r->unit, &r->pal,
                            r->look.perspective ? &r->cam : NULL);
        sp_canvas_disc(cv, pv[0], pv[1], PIVOT_RADIUS * r->unit * (float)(piv_px / r->scale), 0,
                       r->pal.pivot);
    } else if (r->look.view.pendulum && r->look.perspective) {
        const double piv[3] = {0, yp, 0}, bob[3] = {f->state.x, f->state.y + yp, f->state.z};
        put_floor(r);
        const double bob_px = world_px(r, bob[0], bob[1], bob[2], bb);
        const double piv_px = world_px(r, piv[0], piv[1], piv[2], pv);
        if (f->trail && f->trail->count > 1)
            put_floor_trace(r, f->trail);
        put_shadow(r, bob, BOB_RADIUS * r->unit / r->scale);
        if (f->trail && f->trail->count > 1)
            put_trail(r, f->trail);
        put_strobe(r, f->history);
        put_mount(r, pv);
        put_spring3(r, piv, bob);
        sp_canvas_disc(cv, pv[0], pv[1], PIVOT_RADIUS * r->unit * (float)(piv_px / r->scale), 0,
                       r->pal.pivot);
        if (bob_px > 0)
            sp_canvas_disc(cv, bb[0], bb[1], BOB_RADIUS * r->unit * (float)(bob_px / r->scale), 1,
                           r->pal.bob);
    } else if (r->look.view.pendulum) {
        if (f->trail && f->trail->count > 1)
            put_trail(r, f->trail);
        put_strobe(r, f->history);
        put_mount(r, pv);
        put_spring(r, pv, bb);
        sp_canvas_disc(cv, pv[0], pv[1], PIVOT_RADIUS * r->unit, 0, r->pal.pivot);
        sp_canvas_disc(cv, bb[0], bb[1], BOB_RADIUS * r->unit, 1, r->pal.bob);
        if (r->look.view.vectors)
            sp_vectors_draw(cv, &r->vectors, f, bb, &r->pal);
    }
    if (r->look.view.panels)
        put_panels(r, f);
    if (r->look.view.hud && r->hud_lines) {
        char live[SP_HUD_LINE_BYTES] = "";
        if (r->look.spatial)
            hud_measured(r, f, live, sizeof(live));
        sp_hud_draw(cv, &r->layout.hud, f->state.t, r->hud, r->hud_lines, f->params, &r->pal,
                    live);
    }
    put_texts(r, f->moment);
    if (r->look.view.vectors && r->look.view.pendulum)
        sp_vectors_legend(cv, &r->vectors, &r->legend, &r->pal);
    if (f->ended && r->font) { /* side by side: a shorter video holds its last frame */
        const struct sp_rect *cam = &r->layout.camera;
        char note[64];
        snprintf(note, sizeof(note), "ended at t = %.3g s", f->state.t);
        sp_canvas_layer(cv, SP_LAYER_DYNAMIC);
        sp_canvas_text(cv, SP_TEXT_LARGE, cam->x1 - r->layout.gap,
                       cam->y0 + r->layout.gap + sp_font_cap(r->font, SP_TEXT_LARGE), SP_ALIGN_RIGHT,
                       r->pal.accent, note);
    }
    if (r->look.view.colorbar) {
        sp_canvas_layer(cv, SP_LAYER_STATIC);
        sp_colorbar_draw(cv, &r->layout.colorbar, r->look.view.colormap, r->max_speed,
                         &r->pal, r->ink, colorbar_label(r), r->cbar_lines);
    }
    if (cv->err) {
        if (cv->err == SP_E_NOMEM) /* others were said where they happened */
            sp_log_error("out of memory for %d shapes and %d glyphs", cv->n_shapes, cv->n_quads);
        return cv->err;
    }
    *out = cv;
    return 0;
}

void sp_compose_overlay(const struct sp_composer *c, const char *prefix, double dx, double dy,
                        char *buf, size_t size)
{
    size_t used = 0;
    if (size)
        buf[0] = 0;
    if (!c->laid_out || !(c->look.view.vectors || c->look.view.panels & SP_PANEL_ENERGY_BARS ||
                          prefix[0] || c->look.perspective))
        return;
    if (c->look.perspective) { /* the pinhole of camera.h, in output px */
        const struct sp_camera *m = &c->cam;
        float o[2];
        sp_camera_project(m, (const double[3]){0, 0, 0}, o);
        used = (size_t)snprintf(buf, size, "%scamera.px_per_m=%.9g\n%scamera.origin_px=%.9g,%.9g\n"
                                "%scamera.focal_px=%.9g\n%scamera.centre_px=%.9g,%.9g\n"
                                "%scamera.target_m=%.9g,%.9g,%.9g\n%scamera.distance_m=%.9g\n"
                                "%scamera.floor_y_m=%.9g\n",
                                prefix, c->scale / c->ss, prefix, o[0] / c->ss + dx, o[1] / c->ss + dy,
                                prefix, m->focal / c->ss, prefix, m->centre[0] / c->ss + dx,
                                m->centre[1] / c->ss + dy, prefix, m->target[0], m->target[1],
                                m->target[2], prefix, m->distance, prefix, m->floor_y);
    } else {
        used = (size_t)snprintf(buf, size, "%scamera.px_per_m=%.9g\n%scamera.origin_px=%.9g,%.9g\n",
                                prefix, c->scale / c->ss, prefix, c->ox / c->ss + dx,
                                c->oy / c->ss + dy);
    }
    sp_vectors_describe(&c->vectors, c->ss, prefix, buf, size, &used);
    if (c->look.view.vectors && c->look.view.pendulum && used < size)
        used += (size_t)snprintf(buf + used, size - used, "%svectors.legend_px=%.9g,%.9g,%.9g,%.9g\n",
                                 prefix, c->legend.x0 / c->ss + dx, c->legend.y0 / c->ss + dy,
                                 c->legend.x1 / c->ss + dx, c->legend.y1 / c->ss + dy);
    const struct sp_bars_scale *b = &c->bars;
    if (b->n && used < size)
        snprintf(buf + used, size - used, "%senergy_bars.zero_px=%.9g\n%senergy_bars.px_per_J=%.9g\n"
                 "%senergy_bars.slot_px=%.9g\n%senergy_bars.x0_px=%.9g\n%senergy_bars.count=%d\n"
                 "%senergy_bars.gravity_zero_y_m=%.9g\n", prefix, b->zero_px / c->ss + dy, prefix,
                 b->px_per_J / c->ss, prefix, b->slot_px / c->ss, prefix, b->x0 / c->ss + dx, prefix,
                 b->n, prefix, c->extent.y_low);
    while (used < size && buf[used])
        used++;
    if (b->chart && used < size)
        snprintf(buf + used, size - used, "%senergy.zero_px=%.9g\n%senergy.px_per_J=%.9g\n"
                 "%senergy.gravity_zero_y_m=%.9g\n", prefix, b->chart_zero_px / c->ss + dy,
                 prefix, b->chart_px_per_J / c->ss, prefix, c->extent.y_low);
}

const struct sp_font *sp_compose_font(const struct sp_composer *c) { return c->font; }
const struct sp_palette *sp_compose_palette(const struct sp_composer *c) { return &c->pal; }

void sp_compose_destroy(struct sp_composer **cp)
{
    struct sp_composer *c = *cp;
    if (!c)
        return;
    if (!c->font_borrowed)
        sp_font_destroy(&c->font);
    free(c->title);
    free(c->caption);
    free(c->cbar);
    sp_cover_destroy(&c->cover);
    sp_canvas_free(&c->canvas);
    free(c);
    *cp = NULL;
}
