/* springpend (internal): charts, phase portraits, Poincare section, HUD and
 * colourbar. See panels.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/ensemble.h"
#include "axis.h"
#include "colormap_data.h"
#include "panels.h"

#define RAD2DEG 57.29577951308232

static const struct sp_palette DARK = {
    .background = {0x12 / 255.f, 0x16 / 255.f, 0x1c / 255.f, 1},
    .panel = {0x1a / 255.f, 0x20 / 255.f, 0x29 / 255.f, 1},
    .axis = {0.50f, 0.55f, 0.62f, 1}, .grid = {1, 1, 1, 0.07f},
    .text = {0.90f, 0.92f, 0.94f, 1}, .muted = {0.62f, 0.66f, 0.72f, 1},
    .series = {{0.95f, 0.95f, 0.95f, 1}, {0.35f, 0.70f, 1.00f, 1},
               {0.40f, 0.85f, 0.50f, 1}, {1.00f, 0.65f, 0.25f, 1}},
    .cursor = {0.93f, 0.33f, 0.16f, 0.8f}, .accent = {0.40f, 0.90f, 0.50f, 1},
    .mount = {0.56f, 0.60f, 0.66f, 1}, .wire_front = {0.80f, 0.82f, 0.85f, 1},
    .wire_back = {0.47f, 0.50f, 0.55f, 1}, .pivot = {0.86f, 0.88f, 0.91f, 1},
    .bob = {0.93f, 0.33f, 0.16f, 1}, .cmap_lo = 0.18f, .cmap_hi = 1.0f,
    /* velocity, acceleration, gravity, spring, damping, drive, net */
    .vectors = {{0.25f, 0.85f, 0.95f, 1}, {1.00f, 0.80f, 0.15f, 1}, {0.40f, 0.55f, 1.00f, 1},
                {0.35f, 0.90f, 0.40f, 1}, {0.80f, 0.50f, 1.00f, 1}, {1.00f, 0.40f, 0.75f, 1},
                {1.00f, 1.00f, 1.00f, 1}},
};

static const struct sp_palette LIGHT = {
    .background = {0.97f, 0.97f, 0.955f, 1}, .panel = {1, 1, 1, 1},
    .axis = {0.35f, 0.38f, 0.42f, 1}, .grid = {0, 0, 0, 0.08f},
    .text = {0.10f, 0.12f, 0.15f, 1}, .muted = {0.36f, 0.39f, 0.44f, 1},
    .series = {{0.10f, 0.10f, 0.10f, 1}, {0.10f, 0.45f, 0.80f, 1},
               {0.15f, 0.58f, 0.25f, 1}, {0.85f, 0.45f, 0.05f, 1}},
    .cursor = {0.85f, 0.25f, 0.10f, 0.8f}, .accent = {0.05f, 0.55f, 0.20f, 1},
    .mount = {0.40f, 0.43f, 0.48f, 1}, .wire_front = {0.30f, 0.33f, 0.37f, 1},
    .wire_back = {0.62f, 0.65f, 0.69f, 1}, .pivot = {0.25f, 0.27f, 0.30f, 1},
    .bob = {0.88f, 0.30f, 0.12f, 1}, .cmap_lo = 0.0f, .cmap_hi = 0.82f,
    .vectors = {{0.00f, 0.55f, 0.70f, 1}, {0.80f, 0.50f, 0.00f, 1}, {0.15f, 0.30f, 0.90f, 1},
                {0.10f, 0.55f, 0.15f, 1}, {0.50f, 0.20f, 0.75f, 1}, {0.85f, 0.10f, 0.50f, 1},
                {0.00f, 0.00f, 0.00f, 1}},
};

void sp_palette_get(const struct sp_view *view, struct sp_palette *out)
{
    const int bg = view->background;
    *out = view->theme == SP_THEME_LIGHT ? LIGHT : DARK;
    if (view->panel_background)
        out->panel[3] = 0; /* panel_background = none */
    if (view->palette) { /* Okabe and Ito's colour-blind-safe set: the total in
                            the text's colour, then blue (sky blue on dark),
                            bluish green, vermillion */
        static const unsigned okabe_ito[2][3] = {{0x56B4E9, 0x009E73, 0xD55E00},
                                                 {0x0072B2, 0x009E73, 0xD55E00}};
        const int light = view->theme == SP_THEME_LIGHT;
        for (int k = 0; k < 3; k++)
            for (int i = 0; i < 3; i++)
                out->series[k + 1][i] = (float)((okabe_ito[light][k] >> (16 - 8 * i)) & 255) / 255.f;
        memcpy(out->series[0], out->text, sizeof(out->series[0]));
    }
    if (bg == SP_BACKGROUND_TRANSPARENT) {
        out->background[3] = 0;
    } else if (bg >= 0) {
        out->background[0] = (float)((bg >> 16) & 255) / 255.f;
        out->background[1] = (float)((bg >> 8) & 255) / 255.f;
        out->background[2] = (float)(bg & 255) / 255.f;
        /* a light background hides the colormap's light end, a dark one its dark end */
        const int light = 0.3f * out->background[0] + 0.6f * out->background[1] +
                          0.1f * out->background[2] > 0.5f;
        out->cmap_lo = light ? 0.0f : 0.18f;
        out->cmap_hi = light ? 0.82f : 1.0f;
    }
}

/* Polynomial fits of matplotlib's colormaps by Matt Zucker (CC0). */
static const float COLORMAPS[2][7][3] = {
    { /* inferno */
        {0.0002189404f, 0.0016510046f, -0.0194808984f}, {0.1065134195f, 0.5639564368f, 3.9327123889f},
        {11.6024930825f, -3.9728539657f, -15.9423941063f}, {-41.7039961314f, 17.4363988821f, 44.3541451987f},
        {77.1629356994f, -33.4023589421f, -81.8073092574f}, {-71.3194282450f, 32.6260642640f, 73.2095198580f},
        {25.1311262248f, -12.2426689524f, -23.0703250029f},
    },
    { /* viridis */
        {0.2777273272f, 0.0054073445f, 0.3340998053f}, {0.1050930431f, 1.4046135299f, 1.3845901626f},
        {-0.3308618287f, 0.2148475595f, 0.0950951630f}, {-4.6342304990f, -5.7991009734f, -19.3324409563f},
        {6.2282699363f, 14.1799333668f, 56.6905526007f}, {4.7763849977f, -13.7451453777f, -65.3530326334f},
        {-5.4354558559f, 4.6458526122f, 26.3124352496f},
    },
};

void sp_colormap(int colormap, float t, float rgb[3])
{
    const float(*c)[3] = COLORMAPS[colormap == SP_COLORMAP_VIRIDIS];
    t = fminf(fmaxf(t, 0.0f), 1.0f);
    if (colormap == SP_COLORMAP_GRAY) { /* black to white */
        rgb[0] = rgb[1] = rgb[2] = t;
        return;
    }
    if (colormap == SP_COLORMAP_MAGMA || colormap == SP_COLORMAP_CIVIDIS) {
        /* matplotlib's 256 entries, linearly between them */
        const unsigned char(*lut)[3] = colormap == SP_COLORMAP_MAGMA ? CMAP_MAGMA : CMAP_CIVIDIS;
        const float x = t * 255;
        const int i = x >= 255 ? 254 : (int)x;
        for (int k = 0; k < 3; k++)
            rgb[k] = (lut[i][k] + (x - (float)i) * (float)(lut[i + 1][k] - lut[i][k])) / 255.f;
        return;
    }
    for (int k = 0; k < 3; k++) {
        float v = c[6][k];
        for (int i = 5; i >= 0; i--)
            v = v * t + c[i][k];
        rgb[k] = fminf(fmaxf(v, 0.0f), 1.0f);
    }
}

/* ---- axes: axis.h ---- */

/* A tick label's width in small type, px (sp_axis_fit's measure; ctx: the
 * font). */
static double small_width(void *ctx, const char *label)
{
    return sp_font_width(ctx, SP_TEXT_SMALL, label);
}

/* c's axis memo, made at its first use (NULL, with c->err set, when there
 * is no memory for it: then nothing is kept). */
static struct sp_axis_memo *axis_memo(struct sp_canvas *c)
{
    if (!c->axes && !c->err && sp_axis_memo_make(&c->axes))
        c->err = SP_E_NOMEM;
    return c->axes;
}

/* sp_axis_fit for an axis `length` px long whose labels are c's font's
 * small type, through c's memo. */
static void axis_fit(struct sp_canvas *c, struct sp_axis *a, float length, int vertical)
{
    sp_axis_fit_memo(axis_memo(c), a, length, sp_font_line(c->font, SP_TEXT_SMALL), small_width,
                     (void *)c->font, vertical);
}

/* a's ticks, labelled and measured in c's font's small type, from c's memo
 * (or *scratch). */
static const struct sp_axis_ticks *axis_ticks(struct sp_canvas *c, const struct sp_axis *a,
                                              struct sp_axis_ticks *scratch)
{
    return sp_axis_ticks_of(axis_memo(c), a, small_width, (void *)c->font, scratch);
}

struct plot {
    struct sp_rect area; /* the data rectangle, px */
    struct sp_axis x, y;
    float title_end;     /* px: where the title ends in its row */
    float label_base;    /* px: the baseline of the x labels' row, 0 = none */
};

static float px_x(const struct plot *p, double v)
{
    return (float)(p->area.x0 + (v - p->x.lo) / (p->x.hi - p->x.lo) * (p->area.x1 - p->area.x0));
}

static float px_y(const struct plot *p, double v)
{
    return (float)(p->area.y1 - (v - p->y.lo) / (p->y.hi - p->y.lo) * (p->area.y1 - p->area.y0));
}

/* One legend entry: a text in `color`, after a dot of that colour when
 * `dot` (a mark such as the current state), or of `dot_color` when set.
 * The label may have a short form: "long|short". */
struct legend_item {
    const char *label;
    const float *color;
    int dot;
    const float *dot_color;
};

/* buf = the first n bytes of s (all of s when shorter), cut to size - 1
 * bytes and NUL-terminated: what snprintf(buf, size, "%.*s", n, s) writes,
 * without parsing a format each time (the panels cut their labels' forms
 * for every frame; snprintf was most of what measuring them cost). */
static void part_copy(char *buf, size_t size, const char *s, size_t n)
{
    n = strnlen(s, n);
    if (n > size - 1)
        n = size - 1;
    memcpy(buf, s, n);
    buf[n] = 0;
}

/* The long (shrt = 0) or short form of a "long|short" label. */
static const char *label_form(const char *label, int shrt, char *buf, size_t size)
{
    const char *bar = strchr(label, '|');
    part_copy(buf, size, bar && shrt ? bar + 1 : label,
              bar && !shrt ? (size_t)(bar - label) : strlen(label));
    return buf;
}

static float legend_width(const struct sp_font *f, const struct legend_item *it, int n, int shrt)
{
    const float line = (float)sp_font_line(f, SP_TEXT_SMALL);
    char buf[64];
    float w = 0;
    for (int i = 0; i < n; i++)
        w += (it[i].dot ? line : 0) + (i ? 0.7f * line : 0) +
             sp_font_width(f, SP_TEXT_SMALL, label_form(it[i].label, shrt, buf, sizeof(buf)));
    return w;
}

/* Draws the legend with its first entry starting at x, baseline y,
 * wrapping at x1 onto rows starting at x_wrap; returns the rows used. With
 * c = NULL it only counts them. */
static int legend_draw(struct sp_canvas *c, const struct sp_font *f, float x, float y, float x_wrap,
                       float x1, const struct legend_item *it, int n, int shrt)
{
    const float line = (float)sp_font_line(f, SP_TEXT_SMALL), cap = (float)sp_font_cap(f, SP_TEXT_SMALL);
    char label[64];
    int rows = 1;
    for (int i = 0; i < n; i++) {
        label_form(it[i].label, shrt, label, sizeof(label));
        const float w = (it[i].dot ? line : 0) + sp_font_width(f, SP_TEXT_SMALL, label);
        if (x + w > x1 && i > 0) {
            x = x_wrap;
            y += line;
            rows++;
        }
        if (!c) {
            x += w + 0.7f * line;
            continue;
        }
        if (it[i].dot) {
            sp_canvas_disc(c, x + 0.35f * line, y - 0.5f * cap, 0.28f * line, 0,
                           it[i].dot_color ? it[i].dot_color : it[i].color);
            x += line;
        }
        x += sp_canvas_text(c, SP_TEXT_SMALL, x, y, SP_ALIGN_LEFT, it[i].color, label) + 0.7f * line;
    }
    return rows;
}

/* Where frame_plot puts the legend of a panel r titled `title` with y name
 * ylabel: on the title row (judged with the long title and the plain y
 * name; returns 0) or on rows of its own (returns how many; *own = 1), with
 * long labels when they fit one row, else short ones wrapped (*shrt = 1). */
static int legend_rows(const struct sp_font *f, const struct sp_rect *r, const char *title,
                       const char *ylabel, const struct legend_item *leg, int n_leg, int *own,
                       int *shrt)
{
    const float pad = roundf(0.5f * sp_font_line(f, SP_TEXT_SMALL));
    const char *bar0 = strchr(title, '|');
    char full0[96];
    part_copy(full0, sizeof(full0), title, bar0 ? (size_t)(bar0 - title) : strlen(title));
    const float row_free = r->x1 - r->x0 - 4 * pad - sp_font_width(f, SP_TEXT_SMALL, ylabel) -
                           sp_font_width(f, SP_TEXT_NORMAL, full0);
    *own = n_leg && legend_width(f, leg, n_leg, 0) > row_free;
    *shrt = *own && legend_width(f, leg, n_leg, 0) > r->x1 - r->x0 - 2 * pad;
    return *own ? legend_draw(NULL, f, r->x0 + pad, 0, r->x0 + pad, r->x1 - pad, leg, n_leg, *shrt)
                : 0;
}

/* Refuses [view] xlabel (axis 0) or ylabel (1) as drawn in a panel: text,
 * width px wide, where the panel has room px for it (said, naming where
 * the key was set; the canvas's err set to SP_E_INPUT, so the frame fails
 * and nothing is written). */
static void label_refused(struct sp_canvas *c, const struct sp_panel_style *st, int axis,
                          const char *text, int width, float room)
{
    const char *where = axis ? st->ylabel_where : st->xlabel_where;
    const char *key = axis ? "ylabel" : "xlabel";
    /* drawn px per output px, or per pt at a printed size: said in its unit */
    const float ss = st->pt > 0 ? st->pt : st->ss > 0 ? (float)st->ss : 1;
    const char *unit = st->pt > 0 ? "pt" : "px";
    char at[600];
    if (!where || !where[0])
        snprintf(at, sizeof(at), "[view] %s", key);
    else if (!strncmp(where, "--set ", 6))
        snprintf(at, sizeof(at), "%s", where);
    else
        snprintf(at, sizeof(at), "%s: [view] %s", where, key);
    if (!c->err)
        sp_log_error("%s: the %s axis's name \"%s\" cannot fit the %s panel: it is %.0f %s "
                     "wide, and the panel has %.0f %s for it%s; allowed: at most %.0f %s; shorten "
                     "it, use a smaller font_size or font_scale, fewer panels or a larger frame",
                     at, axis ? "y" : "x", text, sp_scene_plot_name(st->order[st->index]),
                     width / ss, unit, fmaxf(room, 0) / ss, unit,
                     axis ? " beside the panel's title" : "", fmaxf(room, 0) / ss, unit);
    c->err = SP_E_INPUT;
}

/* At a printed size (st->pt > 0) the figure's text is in pt, not a share of
 * the frame, and the small-frame rule (compose.c small_frame) does not apply:
 * a panel may then be too small for its own texts, and was drawn with its
 * legend over the curves, its plot turned inside out over the title, or its
 * title over the next panel (attack13 #19: resonance.ini's eight panels at
 * 8.6 cm, 1 in square). Refuses (said once, naming the panel, what it needs
 * and what it has; the canvas's err set to SP_E_INPUT, so the still fails
 * and nothing is written) a panel r whose title row and legend rows (p's
 * top, leg_rows) leave its plot, with the x labels dropped, under 1 pt, or
 * whose title (title_w px, the form drawn) or widest legend entry (leg_w
 * px), both starting pad px in, would cross the panel's right edge. */
static void panel_refused(struct sp_canvas *c, const struct sp_rect *r, const struct sp_panel_style *st,
                          const struct plot *p, float tick, const struct legend_item *leg,
                          int n_leg, int shrt, int leg_rows)
{
    if (!(st->pt > 0)) /* a pixel size: small_frame's rule */
        return;
    const struct sp_font *f = c->font;
    const float pad = roundf(0.5f * sp_font_line(f, SP_TEXT_SMALL)), min_plot = st->pt; /* 1 pt */
    /* the plot's top, and its bottom with the x labels dropped, as frame_plot lays them out */
    const float top = p->area.y0, bottom = r->y1 - pad - tick, title_w = p->title_end - r->x0 - pad;
    float leg_w = 0; /* the widest entry, in the form drawn */
    for (int i = 0; i < n_leg; i++)
        leg_w = fmaxf(leg_w, legend_width(f, &leg[i], 1, shrt));
    const float room_w = r->x1 - r->x0 - pad, plot = bottom - top; /* from x0 + pad to the box's edge */
    if (c->err || (plot >= min_plot && title_w <= room_w && leg_w <= room_w))
        return;
    const float pt = st->pt;
    const float body = (float)sp_font_px(c->font, SP_TEXT_NORMAL) / pt;
    char what[256], rows[64] = "";
    if (leg_rows)
        snprintf(rows, sizeof(rows), " and its legend's %d row%s", leg_rows, leg_rows > 1 ? "s" : "");
    /* the three parts of the height, each as printed, add up to it as printed */
    const float h_said = roundf((r->y1 - r->y0) / pt * 10) / 10,
                t_said = roundf((top - r->y0) / pt * 10) / 10,
                b_said = roundf((r->y1 - bottom) / pt * 10) / 10;
    if (plot < min_plot)
        snprintf(what, sizeof(what), "of its %.1f pt height its title row%s take%s %.1f pt and "
                 "the padding and ticks under the plot %.1f pt, leaving %.1f pt for the plot "
                 "(at least %.0f pt)", h_said, rows, leg_rows ? "" : "s", t_said, b_said,
                 roundf((h_said - t_said - b_said) * 10) / 10 + 0.0f, min_plot / pt);
    else
        snprintf(what, sizeof(what), "its %s is %.0f pt wide, and the panel has %.0f pt for it",
                 title_w > room_w ? "title" : "widest legend entry",
                 (title_w > room_w ? title_w : leg_w) / pt, room_w / pt);
    sp_log_error("at %.0fx%.0f pt with %d panel%s and text of %.0f pt, the %s panel (%.0fx%.0f pt) "
                 "cannot hold its texts: %s, so they would be drawn over its curves or the next "
                 "panel; use fewer panels (view.panels), a smaller view.font_size or font_scale, "
                 "or a larger --size",
                 st->fig_w, st->fig_h, st->n_order, st->n_order == 1 ? "" : "s", body,
                 sp_scene_plot_name(st->order[st->index]), (r->x1 - r->x0) / pt,
                 (r->y1 - r->y0) / pt, what);
    c->err = SP_E_INPUT;
}

/* [view]'s figure keys applied to a panel's texts: the axes' own names
 * (xlabel, ylabel: "a|b|c", the panel's part; the x axis keeps none when
 * *xlabel is NULL, a bar chart's categories), no title without `titles`,
 * and the panel's label "(a) " before the title's long and short forms.
 * xl_own, yl_own and titled (SP_VIEW_TEXT_BYTES each) hold the texts the
 * pointers may be set to. */
static void style_labels(const struct sp_panel_style *st, const char **title, const char **xlabel,
                         const char **ylabel, char *xl_own, char *yl_own, char *titled)
{
    sp_scene_label_part(st->xlabel, st->index, xl_own, SP_VIEW_TEXT_BYTES);
    sp_scene_label_part(st->ylabel, st->index, yl_own, SP_VIEW_TEXT_BYTES);
    if (*xlabel && xl_own[0])
        *xlabel = xl_own;
    if (yl_own[0])
        *ylabel = yl_own;
    if (!st->titles)
        *title = "";
    if (st->labels) { /* "(a) long|(a) short" */
        const char *tb = strchr(*title, '|');
        const char mark[] = {'(', (char)(st->labels + st->index), ')', 0};
        if (tb)
            snprintf(titled, SP_VIEW_TEXT_BYTES, "%s %.*s|%s %s", mark, (int)(tb - *title), *title,
                     mark, tb + 1);
        else
            snprintf(titled, SP_VIEW_TEXT_BYTES, "%s%s%s", mark, (*title)[0] ? " " : "", *title);
        *title = titled;
    }
}

/* What frame_plot measured for the axes' marks: px sizes (padding, a line
 * and a cap of small type, a cap of body type, the axis lines' half width,
 * the tick length, the x labels' drop below the axis, the frame's unit),
 * what shows (x and y tick labels, the x axis's name on its own row below,
 * category names instead of x ticks, the y axis's name), the x name's
 * width, whether the axes' names are [view]'s own (refused when they do not
 * fit), the names, and the title's short form beside the y name. */
struct axes_marks {
    float pad, line_s, cap_s, cap_n, hw, tick, drop, unit;
    int label_x, label_y, xl_below, categories, name_fits, xl_w, own_x, own_y;
    const char *xlabel, *ylabel, *short_title;
};

/* Draws a laid out panel's grid, ticks, tick labels, axes' names and axis
 * lines (the static layer), refusing [view]'s axis names that do not fit
 * (label_refused), then starts its data: the dynamic layer, clipped to the
 * plot (with room for a marker on the edge). */
static void axes_draw(struct sp_canvas *c, const struct sp_rect *r, const struct plot *p,
                      const struct sp_panel_style *st, const struct sp_palette *pal,
                      const struct axes_marks *m)
{
    const struct sp_font *f = c->font;
    /* grid, ticks and labels */
    const float base = p->area.y1 + m->drop + m->cap_s + 0.25f * m->pad;
    const float xl_x0 = m->xl_below ? p->area.x1 + 2 * m->pad : p->area.x1 - m->xl_w;
    if (m->label_x && m->own_x && !m->categories) { /* [view] xlabel inside the panel, or refused */
        const float mid = 0.5f * (p->area.x0 + p->area.x1);
        const float room = m->xl_below ? 2 * fminf(mid - r->x0 - m->pad, r->x1 - m->pad - mid)
                                       : p->area.x1 - r->x0 - m->pad;
        if ((float)m->xl_w > room)
            label_refused(c, st, 0, m->xlabel, m->xl_w, room);
    }
    if (m->label_x)
        sp_canvas_text(c, SP_TEXT_SMALL, m->xl_below ? 0.5f * (p->area.x0 + p->area.x1) : p->area.x1,
                       m->xl_below ? base + m->line_s : base,
                       m->xl_below ? SP_ALIGN_CENTER : SP_ALIGN_RIGHT, pal->muted, m->xlabel);
    struct sp_axis_ticks scratch;
    const struct sp_axis_ticks *t = axis_ticks(c, &p->x, &scratch);
    for (int i = 0; !m->categories && i < t->n; i++) {
        const double v = t->v[i];
        const char *buf = t->label[i];
        const float x = px_x(p, v);
        const float w = (float)(int)t->width[i];
        sp_canvas_rect(c, x - m->hw, p->area.y0, x + m->hw, p->area.y1, pal->grid);
        sp_canvas_rect(c, x - m->hw, p->area.y1, x + m->hw, p->area.y1 + m->tick, pal->axis);
        if (m->label_x && x + 0.5f * w < fminf(xl_x0 - m->pad, r->x1) &&
            x - 0.5f * w >= r->x0 + m->pad)
            sp_canvas_text(c, SP_TEXT_SMALL, x, base, SP_ALIGN_CENTER, pal->muted, buf);
    }
    t = axis_ticks(c, &p->y, &scratch);
    for (int i = 0; i < t->n; i++) {
        const char *buf = t->label[i];
        const float y = px_y(p, t->v[i]);
        sp_canvas_rect(c, p->area.x0, y - m->hw, p->area.x1, y + m->hw, pal->grid);
        sp_canvas_rect(c, p->area.x0 - m->tick, y - m->hw, p->area.x0, y + m->hw, pal->axis);
        if (m->label_y)
            sp_canvas_text(c, SP_TEXT_SMALL, p->area.x0 - m->tick - 0.4f * m->pad,
                           y + 0.5f * m->cap_s, SP_ALIGN_RIGHT, pal->muted, buf);
    }
    /* the y axis's name and unit at the right end of the title row; [view]
     * ylabel there, or refused (never dropped as the panel's own may be) */
    if (!m->name_fits && m->own_y)
        label_refused(c, st, 1, m->ylabel, sp_font_width(f, SP_TEXT_SMALL, m->ylabel),
                      r->x1 - r->x0 - 3 * m->pad - sp_font_width(f, SP_TEXT_SMALL, m->short_title));
    if (m->name_fits)
        sp_canvas_text(c, SP_TEXT_SMALL, r->x1 - m->pad, r->y0 + m->pad + m->cap_n, SP_ALIGN_RIGHT,
                       pal->muted, m->ylabel);
    /* axes lines: left and bottom */
    sp_canvas_rect(c, p->area.x0 - m->hw, p->area.y0, p->area.x0 + m->hw, p->area.y1 + m->hw,
                   pal->axis);
    sp_canvas_rect(c, p->area.x0 - m->hw, p->area.y1 - m->hw, p->area.x1, p->area.y1 + m->hw,
                   pal->axis);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC); /* the data from here, inside the axes (with
                                             room for a marker on the edge) */
    const float mg = 0.006f * m->unit;
    if (p->area.x1 > p->area.x0 + 1 && p->area.y1 > p->area.y0 + 1) /* not a collapsed plot */
        sp_canvas_clip(c, (const float[4]){p->area.x0 - mg, p->area.y0 - mg, p->area.x1 + mg,
                                           p->area.y1 + mg});
}

/* Lays out a panel in r: background, title, axes with ticks and labels;
 * fills p->area. ylabel/xlabel name the axes with their units. The legend
 * goes in the title row when it fits between the title and the y axis's
 * name, else on a row of its own below (the plot gives up the room), so it
 * never disappears. */
static void frame_plot(struct sp_canvas *c, const struct sp_rect *r, struct plot *p,
                       const struct sp_panel_style *st,
                       const char *title, const char *xlabel, const char *ylabel,
                       struct sp_range xr, struct sp_range yr, double xpad,
                       const struct sp_palette *pal, float unit,
                       const struct legend_item *leg, int n_leg, enum sp_layer leg_layer)
{
    /* [view]'s figure keys: the axes' names, the title, the panel's label */
    char xl_own[SP_VIEW_TEXT_BYTES], yl_own[SP_VIEW_TEXT_BYTES], titled[SP_VIEW_TEXT_BYTES];
    if (!st->legend)
        n_leg = 0;
    style_labels(st, &title, &xlabel, &ylabel, xl_own, yl_own, titled);
    const struct sp_font *f = c->font;
    const float pad = roundf(0.5f * sp_font_line(f, SP_TEXT_SMALL));
    const float line_s = (float)sp_font_line(f, SP_TEXT_SMALL), cap_s = (float)sp_font_cap(f, SP_TEXT_SMALL);
    const float cap_n = (float)sp_font_cap(f, SP_TEXT_NORMAL);
    const float hw = pal->axis_hw > 0 ? pal->axis_hw : fmaxf(0.5f, 0.0009f * unit);
    const float tick = roundf(pal->tick > 0 ? pal->tick : 0.006f * unit);
    int tw = 0;

    sp_canvas_layer(c, SP_LAYER_STATIC);
    sp_canvas_rect(c, r->x0, r->y0, r->x1, r->y1, pal->panel);
    int leg_row, shrt;
    const int leg_rows = legend_rows(f, r, title, ylabel, leg, n_leg, &leg_row, &shrt);
    p->area.y0 = r->y0 + 2.2f * pad + cap_n + 0.5f * cap_s + leg_rows * line_s;
    /* A wide plot names its x axis at the right end of the tick row; a
     * narrow one on its own row below, so that it can keep its ticks. No
     * xlabel: categories (bars) name themselves in the tick row. */
    const int categories = !xlabel;
    int xl_below = !categories && r->x1 - r->x0 < 1.6f * (r->y1 - r->y0);
    /* x labels clear of the lowest y label (half a cap above the axis' end) */
    const float drop = fmaxf(tick, 0.6f * cap_s);
    /* A panel too small for its labels keeps at least two lines of plot:
     * the x axis's name moves to the tick row, then the x labels go, then
     * the y labels (never drawn over one another). */
    if (xl_below && r->y1 - pad - 2 * line_s - drop - p->area.y0 < 2 * line_s)
        xl_below = 0;
    const int label_x = r->y1 - pad - line_s - drop - p->area.y0 >= 2 * line_s;
    p->area.y1 = r->y1 - pad - line_s * (label_x ? (xl_below ? 2 : 1) : 0) - (label_x ? drop : tick);
    const int label_y = p->area.y1 - p->area.y0 >= 1.3f * line_s;
    sp_axis_range(&p->y, yr.lo, yr.hi, 0.06);
    axis_fit(c, &p->y, p->area.y1 - p->area.y0, 1);
    char yname[128], xname[128];
    sp_axis_name(&p->y, ylabel, yname, sizeof(yname));
    ylabel = yname;
    /* the title at the left of its row, the y axis's name at the right; when
     * both do not fit, the title's short form ("long|short") in small type */
    const char *bar = strchr(title, '|');
    char full[96];
    part_copy(full, sizeof(full), title, bar ? (size_t)(bar - title) : strlen(title));
    const int fits = sp_font_width(f, SP_TEXT_NORMAL, full) + sp_font_width(f, SP_TEXT_SMALL, ylabel) +
                     3 * pad <= r->x1 - r->x0;
    /* in a very narrow panel the y name gives way to the short title */
    const int name_fits = fits || sp_font_width(f, SP_TEXT_SMALL, bar ? bar + 1 : full) +
                                  sp_font_width(f, SP_TEXT_SMALL, ylabel) + 3 * pad <= r->x1 - r->x0;
    /* a labelled figure keeps every panel's title in body type, (a) as (c):
     * the short form there when the long one does not fit */
    const int body = fits || (st->labels && bar &&
                              sp_font_width(f, SP_TEXT_NORMAL, bar + 1) +
                              sp_font_width(f, SP_TEXT_SMALL, ylabel) + 3 * pad <= r->x1 - r->x0);
    p->title_end = r->x0 + pad +
        sp_canvas_text(c, body ? SP_TEXT_NORMAL : SP_TEXT_SMALL, r->x0 + pad, r->y0 + pad + cap_n,
                       SP_ALIGN_LEFT, pal->text, fits || !bar ? full : bar + 1);
    panel_refused(c, r, st, p, tick, leg, n_leg, shrt, leg_rows); /* at a printed size */
    const float leg_x = leg_row ? r->x0 + pad : p->title_end + pad;
    const float leg_y = r->y0 + pad + cap_n + (leg_row ? line_s : 0);
    /* dynamic when it counts what is shown, or when it reaches down to the
     * data (tiny panels), which must stay under it: a backend keeping the
     * static layer under the data could not keep it so */
    const int rows = n_leg ? legend_draw(NULL, f, leg_x, leg_y, r->x0 + pad, r->x1 - pad, leg, n_leg, shrt) : 0;
    const float leg_bottom = leg_y + (float)(rows - 1) * line_s + (line_s - cap_s);
    const int flat = !(p->area.y1 > p->area.y0 + 1); /* no clip: the data may reach anywhere */
    sp_canvas_layer(c, !flat && leg_bottom + 4 < p->area.y0 - 0.006f * unit ? leg_layer
                                                                        : SP_LAYER_DYNAMIC);
    if (n_leg)
        legend_draw(c, f, leg_x, leg_y, r->x0 + pad, r->x1 - pad, leg, n_leg, shrt);
    sp_canvas_layer(c, SP_LAYER_STATIC);
    struct sp_axis_ticks scratch;
    const struct sp_axis_ticks *yt = label_y ? axis_ticks(c, &p->y, &scratch) : NULL;
    for (int i = 0; yt && i < yt->n; i++) {
        const int w = (int)yt->width[i];
        tw = w > tw ? w : tw;
    }
    p->area.x0 = r->x0 + pad + tw + tick + 0.5f * pad;
    p->area.x1 = r->x1 - pad - 0.5f * sp_font_width(f, SP_TEXT_SMALL, "00");
    xlabel = categories ? "" : xlabel;
    int xl_w = sp_font_width(f, SP_TEXT_SMALL, xlabel);
    sp_axis_range(&p->x, xr.lo, xr.hi, xpad);
    axis_fit(c, &p->x, p->area.x1 - p->area.x0 - (xl_below ? 0 : xl_w + pad), 0);
    sp_axis_name(&p->x, xlabel, xname, sizeof(xname));
    xlabel = xname;
    xl_w = sp_font_width(f, SP_TEXT_SMALL, xlabel);
    p->label_base = label_x ? p->area.y1 + drop + cap_s + 0.25f * pad : 0;

    const struct axes_marks am = {pad,      line_s,     cap_s,     cap_n,    hw,
                                  tick,     drop,       unit,      label_x,  label_y,
                                  xl_below, categories, name_fits, xl_w,     xl_own[0] != 0,
                                  yl_own[0] != 0,       xlabel,    ylabel,   bar ? bar + 1 : full};
    axes_draw(c, r, p, st, pal, &am);
}

/* What a strip chart or phase plot shows along an axis. The energies run
 * total, kinetic, spring, gravity (palette series 0..3), then the modes. */
enum quantity {
    Q_R,          /* m */
    Q_THETA,      /* degrees */
    Q_EXTENSION,  /* m: r - L0 */
    Q_R_DOT,      /* m/s */
    Q_THETA_DOT,  /* rad/s (as data's and sweep's CSVs) */
    Q_ENERGY,     /* J: kinetic + spring + gravity */
    Q_KINETIC,    /* J */
    Q_SPRING,     /* J */
    Q_GRAVITY,    /* J */
    Q_BOUNCE,     /* J */
    Q_SWING,      /* J */
    Q_AZIMUTH,    /* degrees: the swing plane's (3-D) */
    Q_X,          /* m */
    Q_Z,          /* m */
};

/* Sample s's value of quantity which. */
static double quantity(const struct sp_history_sample *s, enum quantity which,
                       const struct sp_params *p)
{
    const double L0 = p->L0;
    switch (which) {
    case Q_R: return s->r;
    case Q_THETA: return s->theta * RAD2DEG;
    case Q_EXTENSION: return s->r - L0;
    case Q_R_DOT: return s->r_dot;
    case Q_THETA_DOT: return s->theta_dot;
    case Q_ENERGY: return (double)s->kinetic + s->spring + s->gravity;
    case Q_KINETIC: return s->kinetic;
    case Q_SPRING: return s->spring;
    case Q_GRAVITY: return s->gravity;
    case Q_BOUNCE: return s->bounce;
    case Q_AZIMUTH: return s->azimuth * RAD2DEG;
    case Q_X: return s->x;
    case Q_Z: return s->z;
    default: return s->swing;
    }
}

/* The n samples thinned by fixed time bins, floor((t - t0) / bin): among
 * samples 1 .. n-2, sample i is a point of the curve when sample i+1 lies
 * in another bin (the last of its bin; with bin not positive, every one).
 * Returns the first point after sample i, or n when none is left. The bins
 * only grow with t, so this is a binary search for where the bin changes:
 * a frame's curve costs its points (bounded by the bins), not the length
 * of the history, which grows with the video. */
static int next_point(const struct sp_history_sample *s, int i, int n, double t0, double bin)
{
    if (!(bin > 0))
        return i + 1 < n - 1 ? i + 1 : n;
    if (i + 1 >= n)
        return n;
    /* the first j > i+1 in another bin than sample i+1: j - 1 ends that bin */
    const double b = floor((s[i + 1].t - t0) / bin);
    int lo = i + 2, hi = n;
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (floor((s[mid].t - t0) / bin) != b)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo < n ? lo - 1 : n;
}

/* The point after sample i (next_point, bins from t = 0), else the newest
 * sample n-1, else n once that was i. */
static int point_or_newest(const struct sp_history_sample *s, int i, int n, double bin)
{
    if (i + 1 >= n)
        return n;
    const int k = next_point(s, i, n, 0, bin);
    return k < n ? k : n - 1;
}

/* A phase curve: the polyline of (x(t), y(t)) over the samples, thinned
 * by fixed time bins (8000 over the run: a curve may wind over itself many
 * times) so that its past never changes, as a strip chart's (strip_curves),
 * and points within a pixel of the last one drawn dropped (a choice that
 * depends on the points before only, so it never changes either).
 * With fade_to, each segment fades into that colour by the age of its newer
 * end, over the newest SP_FADE_S seconds (the trail's rule), to 6%; what is
 * older keeps that colour. The age is counted from the last whole step of
 * SP_FADE_STEP, so that the faded part stays the same between steps (a
 * backend may leave it as it is). What can no longer change (all of it but the
 * tail without fading, what is older than SP_FADE_S with it) is settled;
 * the rest is redrawn each frame. */
static void phase_curve(struct sp_canvas *c, const struct plot *p, const struct sp_history *h,
                        double t_end, enum quantity xq, enum quantity yq, const struct sp_params *pp,
                        float hw, const float color[4], const float *fade_to)
{
    const double bin = t_end / 8000;
    const struct sp_history_sample *s = h->samples;
    /* the fade advances in steps of SP_FADE_STEP: between steps the faded
     * part is the same, byte for byte, and what is newer than the last
     * step is at full strength */
    const double now = fade_to ? floor(s[h->count - 1].t / SP_FADE_STEP) * SP_FADE_STEP
                               : s[h->count - 1].t;
    float ax = px_x(p, quantity(&s[0], xq, pp)), ay = px_y(p, quantity(&s[0], yq, pp));
    float col[4] = {color[0], color[1], color[2], color[3]}, floor_col[4];
    for (int k = 0; k < 4; k++)
        floor_col[k] = fade_to ? fade_to[k] + 0.06f * (color[k] - fade_to[k]) : color[k];
    floor_col[3] = color[3];
    sp_canvas_layer(c, SP_LAYER_SETTLED);
    sp_canvas_path_begin(c);
    int part = 0; /* 0: settled, 1: fading (until the next step), 2: newest */
    const int n = h->count;
    for (int i = n > 1 ? point_or_newest(s, 0, n, bin) : n; i < n; i = point_or_newest(s, i, n, bin)) {
        const int last = i + 1 == n;
        const float bx = px_x(p, quantity(&s[i], xq, pp)), by = px_y(p, quantity(&s[i], yq, pp));
        if (!last && (bx - ax) * (bx - ax) + (by - ay) * (by - ay) < 1)
            continue; /* within a pixel of the last point: a slow curl would pile
                         hundreds of segments onto a few pixels */
        const double age = now - s[i].t;
        const int want = !fade_to ? (last ? 2 : 0) : age >= SP_FADE_S ? 0 : age >= 0 && !last ? 1 : 2;
        while (part < want) { /* the next part, as an item of its own */
            sp_canvas_path_end(c);
            sp_canvas_layer(c, SP_LAYER_DYNAMIC);
            sp_canvas_path_begin(c);
            part++;
        }
        if (part != 1) {
            sp_canvas_line(c, ax, ay, bx, by, hw, part == 0 ? floor_col : color);
        } else { /* mixed with the opaque panel colour: no beads at the joints */
            const float a = 0.06f + 0.94f * powf((float)fmax(0.0, 1.0 - age / SP_FADE_S), 1.5f);
            for (int k = 0; k < 3; k++)
                col[k] = fade_to[k] + a * (color[k] - fade_to[k]);
            sp_canvas_line(c, ax, ay, bx, by, hw, col);
        }
        ax = bx, ay = by;
    }
    sp_canvas_path_end(c);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
}

static struct sp_range range_of(struct sp_range r, double scale, double shift)
{
    return (struct sp_range){r.lo * scale + shift, r.hi * scale + shift};
}

/* The series of a strip chart, drawn over time. What is drawn of the past
 * must not change as the history grows, so that a backend may keep it
 * (SP_LAYER_SETTLED): the x axis spans the whole run, and the samples are
 * thinned by fixed time bins of the axis (two per pixel column) instead of
 * a stride that grows with their count. A sample is a point of the curve
 * when it is the first, or the last of its bin, which is known once the
 * next sample exists; the points so far form the settled curve, one PATH
 * item whose segments interleave the series point by point, in the order
 * given (the last on top). The tail from the last point to the newest
 * sample is redrawn each frame (dynamic). Each series has its colour, half
 * width (px) and a shift (in its unit) subtracted from every value. */
static void strip_curves(struct sp_canvas *c, const struct plot *p, const struct sp_history *h,
                         const struct sp_params *pp, const enum quantity *qs, int n,
                         const float *const *colors, const float *hws, const double *shifts)
{
    int max_segs = 2 * (int)(p->area.x1 - p->area.x0);
    if (max_segs < 2) /* a plot squeezed to under a pixel (tiny frames) */
        max_segs = 2;
    const double bin = (p->x.hi - p->x.lo) / max_segs;
    const struct sp_history_sample *s = h->samples;
    float ax = px_x(p, s[0].t), ay[4];
    for (int k = 0; k < n; k++)
        ay[k] = px_y(p, quantity(&s[0], qs[k], pp) - shifts[k]);
    sp_canvas_layer(c, SP_LAYER_SETTLED);
    sp_canvas_path_begin(c);
    sp_canvas_path_lanes(c, n);
    for (int i = next_point(s, 0, h->count, p->x.lo, bin); i < h->count;
         i = next_point(s, i, h->count, p->x.lo, bin)) {
        const float bx = px_x(p, s[i].t);
        for (int k = 0; k < n; k++) {
            const float by = px_y(p, quantity(&s[i], qs[k], pp) - shifts[k]);
            sp_canvas_line(c, ax, ay[k], bx, by, hws[k], colors[k]);
            ay[k] = by;
        }
        ax = bx;
    }
    sp_canvas_path_end(c);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    if (h->count < 2)
        return;
    const struct sp_history_sample *last = &s[h->count - 1];
    const float bx = px_x(p, last->t);
    for (int k = 0; k < n; k++)
        sp_canvas_line(c, ax, ay[k], bx, px_y(p, quantity(last, qs[k], pp) - shifts[k]), hws[k],
                       colors[k]);
}

/* The legend's note of gravity's zero at y_low (m), one convention for the
 * energy chart and the energy bars: long and short forms. */
static void gravity_zero_note(char *buf, size_t size, double y_low)
{
    snprintf(buf, size, "gravity 0 at the lowest point, y = %s%.3g m|0 at y = %s%.3g m",
             y_low < 0 ? "−" : "", fabs(y_low), y_low < 0 ? "−" : "", fabs(y_low));
}

static void strip_chart(struct sp_canvas *c, const struct sp_rect *r, int bit,
                        const struct sp_frame *f, const struct sp_view_extent *e,
                        const struct sp_palette *pal, float unit, const struct sp_panel_style *st,
                        struct sp_bars_scale *scale)
{
    static const char *const titles[] = {"Spring length r|r", "Angle θ|θ", "Energy|E",
                                         "Spring extension r − L₀|Extension", "", "", "",
                                         "Energy of bounce and swing|Modes", "",
                                         "Azimuth of the swing plane|Azimuth"};
    static const char *const ylabels[] = {"r (m)", "θ (°)", "E (J)", "r − L₀ (m)", "", "", "",
                                          "E (J)", "", "azimuth (°)"};
    const struct sp_params *L0 = f->params;
    const struct sp_range yr = bit == 0 ? e->r : bit == 1 ? range_of(e->theta, RAD2DEG, 0)
                             : bit == 2 ? e->energy : bit == 3 ? range_of(e->r, 1, -L0->L0)
                             : bit == 9 ? range_of(e->azimuth, RAD2DEG, 0)
                             : e->modes;
    const struct sp_history *h = f->history;
    const float hw = fmaxf(0.6f, 0.0013f * unit);
    struct plot p;

    char zero_note[96];
    gravity_zero_note(zero_note, sizeof(zero_note), e->y_low);
    const struct legend_item energy[] = {{"total|tot", pal->series[0], 0, NULL},
                                         {"kinetic|kin", pal->series[1], 0, NULL},
                                         {"spring|spr", pal->series[2], 0, NULL},
                                         {"gravity|grav", pal->series[3], 0, NULL},
                                         {zero_note, pal->muted, 0, NULL}};
    /* J: gravity's energy at y_low, gravity's (and the total's) zero, as the bars' */
    const double zero = L0->mass * L0->g * e->y_low;
    /* the zero's note where it costs the plot no row of legend (a small panel
     * keeps its plot's height instead) */
    int own, shrt;
    const int n_energy = c->font && legend_rows(c->font, r, titles[bit], ylabels[bit], energy, 5, &own,
                                                &shrt) <=
                                        legend_rows(c->font, r, titles[bit], ylabels[bit], energy, 4,
                                                    &own, &shrt)
                             ? 5 : 4;
    const struct legend_item modes[] = {{"bounce|bnc", pal->series[1], 0, NULL},
                                        {"swing|swg", pal->series[2], 0, NULL}};
    frame_plot(c, r, &p, st, titles[bit], "t (s)", ylabels[bit], (struct sp_range){0, e->t_end},
               yr, 0, pal, unit, bit == 2 ? energy : modes, bit == 2 ? n_energy : bit == 7 ? 2 : 0,
               SP_LAYER_STATIC);
    if (bit == 2 && scale) {
        scale->chart = 1;
        scale->chart_zero_px = px_y(&p, 0);
        scale->chart_px_per_J = (float)((p.area.y1 - p.area.y0) / (p.y.hi - p.y.lo));
    }
    if ((bit == 1 || bit == 3) && p.y.lo < 0 && p.y.hi > 0) { /* the zero line */
        sp_canvas_layer(c, SP_LAYER_STATIC);
        sp_canvas_rect(c, p.area.x0, px_y(&p, 0) - hw * 0.6f, p.area.x1, px_y(&p, 0) + hw * 0.6f, pal->axis);
        sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    }
    if (!h || h->count == 0)
        return;
    /* the series (the energies' split first, the total on top), then the
     * cursor at the newest time, then the dots on it */
    enum quantity qs[4];
    const float *colors[4];
    float hws[4];
    double shifts[4] = {0};
    int n = 0;
    if (bit == 2) {
        for (int k = 3; k >= 0; k--, n++) {
            qs[n] = Q_ENERGY + k, colors[n] = pal->series[k], hws[n] = k ? hw : 1.4f * hw;
            shifts[n] = qs[n] == Q_ENERGY || qs[n] == Q_GRAVITY ? zero : 0;
        }
    } else if (bit == 7) {
        for (int k = 0; k < 2; k++, n++)
            qs[n] = Q_BOUNCE + k, colors[n] = pal->series[k + 1], hws[n] = 1.2f * hw;
    } else {
        qs[0] = bit == 0 ? Q_R : bit == 1 ? Q_THETA : bit == 9 ? Q_AZIMUTH : Q_EXTENSION;
        colors[0] = pal->series[1], hws[0] = hw, n = 1;
    }
    strip_curves(c, &p, h, L0, qs, n, colors, hws, shifts);
    const struct sp_history_sample *last = &h->samples[h->count - 1];
    const float now = px_x(&p, last->t);
    if (!st->cursor)
        return;
    sp_canvas_rect(c, now - hw * 0.8f, p.area.y0, now + hw * 0.8f, p.area.y1, pal->cursor);
    if (bit != 2)
        for (int k = 0; k < n; k++)
            sp_canvas_disc(c, now, px_y(&p, quantity(last, qs[k], L0)), 2.2f * hw, 0, colors[k]);
}

static void phase_plot(struct sp_canvas *c, const struct sp_rect *r, int theta,
                       const struct sp_frame *f, const struct sp_view_extent *e,
                       const struct sp_palette *pal, float unit, const struct sp_panel_style *st)
{
    const int fade = st->fade, n_now = st->cursor;
    const struct sp_history *h = f->history;
    const float hw = fmaxf(0.6f, 0.0012f * unit);
    struct plot p;
    const struct legend_item now[] = {{"now", pal->muted, 1, pal->cursor}};
    if (theta)
        frame_plot(c, r, &p, st, "Phase portrait θ, θ̇|θ, θ̇", "θ (°)", "θ̇ (rad/s)",
                   range_of(e->theta, RAD2DEG, 0), e->theta_dot, 0.06, pal, unit, now, n_now,
                   SP_LAYER_STATIC);
    else
        frame_plot(c, r, &p, st, "Phase portrait r, ṙ|r, ṙ", "r (m)", "ṙ (m/s)", e->r, e->r_dot, 0.06, pal,
                   unit, now, n_now, SP_LAYER_STATIC);
    if (!h || h->count == 0)
        return;
    const enum quantity xq = theta ? Q_THETA : Q_R, yq = theta ? Q_THETA_DOT : Q_R_DOT;
    phase_curve(c, &p, h, e->t_end, xq, yq, f->params, hw, pal->series[1], fade ? pal->panel : NULL);
    const struct sp_history_sample *s = &h->samples[h->count - 1];
    if (st->cursor)
        sp_canvas_disc(c, px_x(&p, quantity(s, xq, f->params)), px_y(&p, quantity(s, yq, f->params)),
                       st->marker_px > 0 ? 0.5f * st->marker_px : 2.6f * hw, 0, pal->cursor);
}

/* The top view: the bob's path in the horizontal (x, z) plane, x to the
 * right and z up the panel (so seen from below the pivot), both over the
 * largest |x|, |z|, fading like a phase portrait: the swing's plane turns
 * in it. */
static void top_plot(struct sp_canvas *c, const struct sp_rect *r, const struct sp_frame *f,
                     const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                     const struct sp_panel_style *st)
{
    const struct sp_history *h = f->history;
    const float hw = fmaxf(0.6f, 0.0012f * unit);
    const double span = e->horizontal > 0 ? e->horizontal : 1;
    const struct sp_range both = {-span, span};
    const struct legend_item now[] = {{"now", pal->muted, 1, pal->cursor}};
    struct plot p;
    frame_plot(c, r, &p, st, "Top view x, z|Top", "x (m)", "z (m)", both, both, 0.06, pal, unit,
               now, st->cursor, SP_LAYER_STATIC);
    if (!h || h->count == 0)
        return;
    phase_curve(c, &p, h, e->t_end, Q_X, Q_Z, f->params, hw, pal->series[1],
                st->fade ? pal->panel : NULL);
    const struct sp_history_sample *s = &h->samples[h->count - 1];
    if (st->cursor)
        sp_canvas_disc(c, px_x(&p, s->x), px_y(&p, s->z),
                       st->marker_px > 0 ? 0.5f * st->marker_px : 2.6f * hw, 0, pal->cursor);
}

static void poincare_plot(struct sp_canvas *c, const struct sp_rect *r, const struct sp_frame *f,
                          const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                          const struct sp_panel_style *st)
{
    const struct sp_history *h = f->history;
    const float dot = st->marker_px > 0 ? 0.5f * st->marker_px : fmaxf(1.8f, 0.0035f * unit);
    char count[64];
    struct plot p;
    const int n = h ? h->n_crossings : 0;
    snprintf(count, sizeof(count), "%d crossing%s|%d", n, n == 1 ? "" : "s", n);
    const struct legend_item leg[] = {{count, pal->muted, 1, pal->series[2]},
                                      {"latest", pal->muted, 1, pal->cursor}};
    frame_plot(c, r, &p, st, "Poincaré θ = 0, θ̇ > 0|Poincaré", "r (m)", "ṙ (m/s)", e->r, e->r_dot, 0.06, pal,
               unit, leg, n && st->cursor ? 2 : 1, SP_LAYER_DYNAMIC);
    if (!h)
        return;
    /* every crossing but the latest never changes again: settled */
    sp_canvas_layer(c, SP_LAYER_SETTLED);
    sp_canvas_shapes_begin(c);
    for (int i = 0; i + 1 < h->n_crossings; i++)
        sp_canvas_disc(c, px_x(&p, h->crossings[i].r), px_y(&p, h->crossings[i].r_dot), dot, 0,
                       pal->series[2]);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    if (n && !st->cursor) /* the latest as the others */
        sp_canvas_disc(c, px_x(&p, h->crossings[n - 1].r), px_y(&p, h->crossings[n - 1].r_dot),
                       dot, 0, pal->series[2]);
    else if (n)
        sp_canvas_disc(c, px_x(&p, h->crossings[n - 1].r), px_y(&p, h->crossings[n - 1].r_dot),
                       1.8f * dot, 0, pal->cursor);
}

/* [ensemble]: log10 of the members' spread in phase space against time, and
 * the line of slope lambda / ln 10 from the spread at t = 0 (what growth at
 * the central scene's Lyapunov exponent would give). */
static void spread_plot(struct sp_canvas *c, const struct sp_rect *r, const struct sp_frame *f,
                        const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                        const struct sp_panel_style *st)
{
    const struct sp_ensemble *en = f->ensemble;
    const float hw = fmaxf(0.6f, 0.0013f * unit);
    char slope[64];
    struct plot p;
    const struct sp_range yr = en ? (struct sp_range){en->log_spread.lo - 0.3, en->log_spread.hi + 0.3}
                                  : (struct sp_range){-1, 1};
    snprintf(slope, sizeof(slope), "Lyapunov slope %.3g/s|%.3g/s", en ? en->lambda : 0, en ? en->lambda : 0);
    const struct legend_item leg[] = {{"spread|spr", pal->series[1], 0, NULL},
                                      {slope, pal->accent, 0, NULL}};
    frame_plot(c, r, &p, st, "Ensemble spread in phase space|Spread", "t (s)", "log₁₀ spread (m)",
               (struct sp_range){0, e->t_end}, yr, 0, pal, unit, leg, en ? 2 : 0, SP_LAYER_STATIC);
    if (!en || en->n_spread == 0)
        return;
    /* the line lambda: log10 d(t) = log10 d(0) + lambda t / ln 10, to the axes' top */
    const double t_top = en->lambda > 0 ? fmin(e->t_end, (yr.hi - en->log_spread0) * M_LN10 / en->lambda)
                                        : e->t_end;
    sp_canvas_line(c, px_x(&p, 0), px_y(&p, en->log_spread0), px_x(&p, t_top),
                   px_y(&p, en->log_spread0 + en->lambda * t_top / M_LN10), 0.8f * hw, pal->accent);
    const int n = en->n_spread, max_segs = (int)fmaxf(2, 2 * (p.area.x1 - p.area.x0));
    const int stride = n > max_segs ? (n + max_segs - 1) / max_segs : 1;
    float ax = px_x(&p, en->spread_t[0]), ay = px_y(&p, en->spread_log[0]);
    sp_canvas_path_begin(c);
    for (int i = stride; i < n + stride - 1; i += stride) {
        const int j = i < n ? i : n - 1;
        const float bx = px_x(&p, en->spread_t[j]), by = px_y(&p, en->spread_log[j]);
        sp_canvas_line(c, ax, ay, bx, by, 1.2f * hw, pal->series[1]);
        ax = bx, ay = by;
    }
    sp_canvas_path_end(c);
    sp_canvas_disc(c, ax, ay, 2.2f * hw, 0, pal->series[1]);
}

/* The energy now as bars on the run's one fixed axis (e->bars): kinetic,
 * spring and gravity, gravity's zero at the lowest point of the run (so no
 * bar but the drive's work goes below zero), the total; with damping or a
 * drive the energy at the start, the drive's work and the loss to damping,
 * so that total = start + work - loss; then the bounce and swing split. */
static void energy_bars(struct sp_canvas *c, const struct sp_rect *r, const struct sp_frame *f,
                        const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                        const struct sp_panel_style *st, struct sp_bars_scale *out)
{
    const struct sp_params *pp = f->params;
    const double zero = pp->mass * pp->g * e->y_low; /* J: gravity's energy at y_low */
    const int damped = pp->b_over_m > 0, driven = pp->drive_amp != 0;
    const double loss = f->history ? f->history->loss : 0;
    struct sp_energy en;
    sp_state_energy(pp, &f->state, &en);
    struct bar {
        const char *label;
        double value; /* J */
        const float *color;
    } bars[9];
    int n = 0;
    bars[n++] = (struct bar){"kinetic|kin", en.kinetic, pal->series[1]};
    bars[n++] = (struct bar){"spring|spr", en.spring, pal->series[2]};
    bars[n++] = (struct bar){"gravity|grav", en.gravity - zero, pal->series[3]};
    bars[n++] = (struct bar){"total|tot", en.total - zero, pal->series[0]};
    if (damped || driven)
        bars[n++] = (struct bar){"start|E₀", f->energy0 - zero, pal->muted};
    if (driven)
        bars[n++] = (struct bar){"drive work|drive", f->work + loss, pal->vectors[5]};
    if (damped)
        bars[n++] = (struct bar){"damping loss|loss", loss, pal->vectors[4]};
    bars[n++] = (struct bar){"bounce|bnc", en.bounce, pal->vectors[0]};
    bars[n++] = (struct bar){"swing|swg", en.swing, pal->vectors[1]};
    char zero_note[96];
    gravity_zero_note(zero_note, sizeof(zero_note), e->y_low);
    const struct legend_item leg[] = {{zero_note, pal->muted, 0, NULL},
                                      {"total = start + work − loss|= E₀ + W − loss", pal->muted, 0, NULL}};
    struct plot p;
    frame_plot(c, r, &p, st, "Energy bars|Energy", NULL, "E (J)", (struct sp_range){0, 1}, e->bars, 0,
               pal, unit, leg, damped || driven ? 2 : 1, SP_LAYER_STATIC);
    const float slot = (p.area.x1 - p.area.x0) / (float)n, half = 0.32f * slot;
    const float y0 = px_y(&p, 0);
    const struct sp_font *font = c->font;
    /* the labels: long forms when every one fits its slot, else short ones */
    int shrt = 0;
    char buf[64];
    for (int i = 0; i < n; i++)
        shrt |= sp_font_width(font, SP_TEXT_SMALL, label_form(bars[i].label, 0, buf, sizeof(buf))) >
                0.96f * slot;
    sp_canvas_clip(c, NULL);
    sp_canvas_layer(c, SP_LAYER_STATIC);
    for (int i = 0; p.label_base > 0 && i < n; i++) /* a label wider than its slot is left out */
        if (sp_font_width(font, SP_TEXT_SMALL, label_form(bars[i].label, shrt, buf, sizeof(buf))) <= slot)
            sp_canvas_text(c, SP_TEXT_SMALL, p.area.x0 + (i + 0.5f) * slot, p.label_base,
                           SP_ALIGN_CENTER, pal->muted, buf);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    for (int i = 0; i < n; i++) {
        const float x = p.area.x0 + (i + 0.5f) * slot, y = px_y(&p, bars[i].value);
        if (fabsf(y - y0) >= 0.5f)
            sp_canvas_rect(c, x - half, fminf(y, y0), x + half, fmaxf(y, y0), bars[i].color);
    }
    /* the zero line over the bars */
    const float hw = fmaxf(0.5f, 0.0009f * unit);
    sp_canvas_rect(c, p.area.x0, y0 - hw, p.area.x1, y0 + hw, pal->axis);
    if (out) {
        out->zero_px = y0, out->px_per_J = (float)((p.area.y1 - p.area.y0) / (p.y.hi - p.y.lo));
        out->slot_px = slot, out->x0 = p.area.x0, out->n = n;
    }
}

void sp_panels_draw(struct sp_canvas *c, const struct sp_layout *lay, const struct sp_frame *f,
                    const struct sp_view_extent *e, const struct sp_palette *pal, float unit,
                    const struct sp_panel_style *style, struct sp_bars_scale *bars)
{
    struct sp_panel_style one = *style;
    const struct sp_panel_style *st = &one;
    for (int i = 0; i < style->n_order; i++) {
        const int b = style->order[i];
        const struct sp_rect *r = &lay->panel[b];
        one.index = i;
        if (!sp_rect_valid(r))
            continue;
        if (b == 11)
            energy_bars(c, r, f, e, pal, unit, st, bars);
        else if (b == 8)
            spread_plot(c, r, f, e, pal, unit, st);
        else if (b == 10)
            top_plot(c, r, f, e, pal, unit, st);
        else if (b <= 3 || b == 7 || b == 9)
            strip_chart(c, r, b, f, e, pal, unit, st, bars);
        else if (b <= 5)
            phase_plot(c, r, b == 5, f, e, pal, unit, st);
        else
            poincare_plot(c, r, f, e, pal, unit, st);
        sp_canvas_clip(c, NULL);
    }
}

/* ---- heads-up text ---- */

int sp_params_resonant(const struct sp_params *p, double *ratio)
{
    struct sp_physics ph;
    sp_params_physics(p, &ph);
    *ratio = ph.ratio;
    return fabs(*ratio - 2) <= 0.03 * 2;
}

/* Cuts text (UTF-8, in place) at a character boundary and ends it with
 * "…" until it is at most max_width px wide; "" when not even "…" fits. */
static void cut_to_width(const struct sp_font *font, float max_width, char *text, size_t size)
{
    size_t len = strlen(text);
    if (sp_font_width(font, SP_TEXT_NORMAL, text) <= max_width)
        return;
    char buf[SP_HUD_LINE_BYTES];
    while (len > 0) {
        do
            len--;
        while (len > 0 && (text[len] & 0xc0) == 0x80);
        if (len + 4 > size || len + 4 > sizeof(buf))
            continue; /* no room for the ellipsis yet */
        memcpy(buf, text, len);
        memcpy(buf + len, "…", 4); /* 3 bytes and the NUL */
        if (sp_font_width(font, SP_TEXT_NORMAL, buf) <= max_width) {
            memcpy(text, buf, len + 4);
            return;
        }
    }
    text[0] = 0;
}

/* Appends `item` to the lines, starting a new line when it would not fit. */
static void add_item(const struct sp_font *font, float max_width, char lines[][SP_HUD_LINE_BYTES],
                     int *n, int max, const char *item, int new_line)
{
    /* "long|short": the short form when the long one is wider than a line;
     * neither when both are (a tiny frame), unless the item is "!..." (a
     * side-by-side difference: cut with "…" rather than left out) */
    char form[SP_HUD_LINE_BYTES];
    const int cut = item[0] == '!';
    item += cut;
    const char *bar = strchr(item, '|');
    part_copy(form, sizeof(form), item, bar ? (size_t)(bar - item) : strlen(item));
    if (bar && sp_font_width(font, SP_TEXT_NORMAL, form) > max_width)
        snprintf(form, sizeof(form), "%s", bar + 1);
    if (cut)
        cut_to_width(font, max_width, form, sizeof(form));
    if (!form[0] || sp_font_width(font, SP_TEXT_NORMAL, form) > max_width)
        return;
    item = form;
    char *l = lines[*n - 1];
    char joined[2 * SP_HUD_LINE_BYTES];
    snprintf(joined, sizeof(joined), "%s%s%s", l, !*l ? "" : strcmp(l, "differs:") ? "    " : " ",
             item);
    if (!new_line && (!*l || sp_font_width(font, SP_TEXT_NORMAL, joined) <= max_width)) {
        snprintf(l, SP_HUD_LINE_BYTES, "%.*s", SP_HUD_LINE_BYTES - 1, joined);
        return;
    }
    if (*n < max)
        snprintf(lines[(*n)++], SP_HUD_LINE_BYTES, "%s", item);
}

/* The resonance check's words, short when the long ones do not fit. */
static const char *resonance_note(const struct sp_font *f, int resonant, float max_width)
{
    const char *note = resonant ? "≈ 2:1 resonance ✓" : "(2:1 resonance needs kL₀ = 3mg)";
    if (sp_font_width(f, SP_TEXT_NORMAL, note) > max_width)
        note = resonant ? "≈ 2:1 ✓" : "(not 2:1)";
    return note;
}

/* Lines that start with this byte are drawn in the accent colour (it is not drawn). */
#define HUD_ACCENT '\2'

/* The ratio's line starts with this byte (not drawn): the resonance check
 * follows it, or has a line of its own ("\1") after it. */
#define HUD_RATIO '\4'
/* The line that says how many lines were left out (sp_hud_fit) starts with
 * this byte (not drawn; in the muted colour, cut to the width). */
#define HUD_MORE '\5'

int sp_hud_lines(const struct sp_font *font, const struct sp_params *p,
                 const struct sp_prediction *pd, const char *differs, float max_width,
                 char lines[][SP_HUD_LINE_BYTES], int max)
{
    struct sp_physics ph;
    sp_params_physics(p, &ph);
    const double ell = ph.ell, ws = ph.omega_s, wp = ph.omega_p;
    char item[SP_HUD_LINE_BYTES];
    double ratio;
    int n = 2;
    lines[0][0] = lines[1][0] = 0;
    if (differs && *differs) { /* "differs: a = 1, b = 2", wrapped at its commas */
        const char *s = differs;
        add_item(font, max_width, lines, &n, max, "!differs:", 0); /* the heading, kept */
        while (*s) {
            const size_t len = strcspn(s, ",");
            snprintf(item, sizeof(item), "!%.*s%s", (int)len, s, s[len] ? "," : "");
            add_item(font, max_width, lines, &n, max, item, 0);
            s += len + (s[len] != 0);
            s += strspn(s, " ");
        }
        for (int i = 1; i < n; i++) { /* the accent's mark */
            memmove(lines[i] + 1, lines[i], SP_HUD_LINE_BYTES - 2);
            lines[i][0] = HUD_ACCENT;
            lines[i][SP_HUD_LINE_BYTES - 1] = 0;
        }
        if (n < max)
            lines[n++][0] = 0;
    }
    snprintf(item, sizeof(item), "m = %.3g kg", p->mass);
    add_item(font, max_width, lines, &n, max, item, 0);
    snprintf(item, sizeof(item), "k = %.4g N/m", p->stiffness);
    add_item(font, max_width, lines, &n, max, item, 0);
    snprintf(item, sizeof(item), "L₀ = %.3g m", p->L0);
    add_item(font, max_width, lines, &n, max, item, 0);
    snprintf(item, sizeof(item), "g = %.3g m/s²", p->g);
    add_item(font, max_width, lines, &n, max, item, 0);
    if (p->b_over_m > 0) {
        snprintf(item, sizeof(item), "b = %.3g N·s/m", p->b_over_m * p->mass);
        add_item(font, max_width, lines, &n, max, item, 0);
    }
    snprintf(item, sizeof(item), "ωₛ = √(k/m) = %.3f rad/s|ωₛ = %.3f rad/s", ws, ws);
    add_item(font, max_width, lines, &n, max, item, 1);
    if (pd->swings)
        snprintf(item, sizeof(item), "ωₚ = √(g/ℓ) = %.3f rad/s|ωₚ = %.3f rad/s", wp, wp);
    else /* as info: without gravity no pendulum period, ratio or 2:1 exists */
        snprintf(item, sizeof(item), "ωₚ: none (g = 0: no swing back)|ωₚ: none (g = 0)");
    add_item(font, max_width, lines, &n, max, item, 0);
    snprintf(item, sizeof(item), "ℓ = L₀ + mg/k = %.3f m|ℓ = %.3f m", ell, ell);
    add_item(font, max_width, lines, &n, max, item, 0);
    if (p->drive_amp > 0 && p->drive_omega > 0) {
        snprintf(item, sizeof(item), "pivot: %.3g m at %.4g Hz", p->drive_amp, p->drive_omega / (2 * M_PI));
        add_item(font, max_width, lines, &n, max, item, 1);
        if (pd->swings) {
            snprintf(item, sizeof(item), "Ω/ωₚ = %.3f", p->drive_omega / wp);
            add_item(font, max_width, lines, &n, max, item, 0);
        }
    }
    if (!pd->swings)
        return n;
    const int res = sp_params_resonant(p, &ratio);
    snprintf(item, sizeof(item), "ωₛ/ωₚ = %.3f", ratio);
    const int before = n;
    add_item(font, max_width, lines, &n, max, item, 1);
    if (n == before)
        return n; /* no room for the ratio: nor for its check */
    memmove(lines[n - 1] + 1, lines[n - 1], SP_HUD_LINE_BYTES - 2);
    lines[n - 1][0] = HUD_RATIO;
    lines[n - 1][SP_HUD_LINE_BYTES - 1] = 0;
    /* the resonance note after the ratio, or on a line of its own ("\1") */
    snprintf(item, sizeof(item), "%s    %s", lines[n - 1] + 1, resonance_note(font, res, max_width));
    if (sp_font_width(font, SP_TEXT_NORMAL, item) > max_width && n < max)
        snprintf(lines[n++], SP_HUD_LINE_BYTES, "\1");
    return n;
}

int sp_hud_fit(const struct sp_font *font, float max_width, float max_height,
               char lines[][SP_HUD_LINE_BYTES], int n)
{
    int keep = n;
    while (keep > 1 && sp_hud_height(font, keep) > max_height)
        keep--;
    if (keep == n)
        return n;
    if (keep < 2)
        return sp_hud_height(font, 1) <= max_height ? 1 : 0;
    /* the last line kept says how many are left out */
    int left = n - keep + 1;
    for (int i = keep - 1; i < n; i++)
        left -= !strcmp(lines[i], "\1"); /* the check's own line is part of the ratio's */
    char more[SP_HUD_LINE_BYTES - 1]; /* and the mark's byte */
    snprintf(more, sizeof(more), "… %d more line%s: a larger frame shows them", left,
             left == 1 ? "" : "s");
    if (sp_font_width(font, SP_TEXT_NORMAL, more) > max_width)
        snprintf(more, sizeof(more), "… %d more", left);
    cut_to_width(font, max_width, more, sizeof(more));
    snprintf(lines[keep - 1], SP_HUD_LINE_BYTES, "%c%s", HUD_MORE, more);
    return keep;
}

float sp_hud_height(const struct sp_font *font, int n)
{
    return (float)sp_font_line(font, SP_TEXT_LARGE) + (float)(n - 1) * sp_font_line(font, SP_TEXT_NORMAL);
}

void sp_hud_draw(struct sp_canvas *c, const struct sp_rect *r, double t,
                 char lines[][SP_HUD_LINE_BYTES], int n, const struct sp_params *p,
                 const struct sp_palette *pal, const char *live)
{
    const struct sp_font *f = c->font;
    char buf[64];
    double ratio;
    float y = r->y0 + sp_font_cap(f, SP_TEXT_LARGE);
    snprintf(buf, sizeof(buf), "t = %.2f s", t);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    sp_canvas_text(c, SP_TEXT_LARGE, r->x0, y, SP_ALIGN_LEFT, pal->text, buf);
    sp_canvas_layer(c, SP_LAYER_STATIC); /* the parameters do not change in a run */
    y += 0.5f * (sp_font_line(f, SP_TEXT_LARGE) - sp_font_cap(f, SP_TEXT_LARGE)) +
         0.5f * (sp_font_line(f, SP_TEXT_NORMAL) - sp_font_cap(f, SP_TEXT_NORMAL));
    const int res = sp_params_resonant(p, &ratio);
    const char *note = resonance_note(f, res, r->x1 - r->x0);
    for (int i = 1; i < n; i++) {
        const float base = y + sp_font_cap(f, SP_TEXT_NORMAL);
        y += sp_font_line(f, SP_TEXT_NORMAL);
        if (!lines[i][0])
            continue;
        if (!strcmp(lines[i], "\1")) {
            sp_canvas_text(c, SP_TEXT_NORMAL, r->x0, base, SP_ALIGN_LEFT, res ? pal->accent : pal->muted, note);
            continue;
        }
        if (lines[i][0] == SP_HUD_LIVE) { /* changes every frame */
            sp_canvas_layer(c, SP_LAYER_DYNAMIC);
            sp_canvas_text(c, SP_TEXT_NORMAL, r->x0, base, SP_ALIGN_LEFT, pal->text, live ? live : "");
            sp_canvas_layer(c, SP_LAYER_STATIC);
            continue;
        }
        if (lines[i][0] == HUD_MORE) {
            sp_canvas_text(c, SP_TEXT_NORMAL, r->x0, base, SP_ALIGN_LEFT, pal->muted, lines[i] + 1);
            continue;
        }
        if (lines[i][0] == HUD_ACCENT) {
            sp_canvas_text(c, SP_TEXT_NORMAL, r->x0, base, SP_ALIGN_LEFT, pal->accent, lines[i] + 1);
            continue;
        }
        const int ratio_line = lines[i][0] == HUD_RATIO;
        const char *text = lines[i] + ratio_line;
        const float w = (float)sp_canvas_text(c, SP_TEXT_NORMAL, r->x0, base, SP_ALIGN_LEFT,
                                              ratio_line ? pal->text : pal->muted, text);
        if (ratio_line && !(i + 1 < n && !strcmp(lines[i + 1], "\1")))
            sp_canvas_text(c, SP_TEXT_NORMAL, r->x0 + w + sp_font_line(f, SP_TEXT_NORMAL), base,
                           SP_ALIGN_LEFT, res ? pal->accent : pal->muted, note);
    }
}

/* ---- colourbar ---- */

/* The widest of the n lines one after another in label ("" = the bar's
 * own name), px. */
static int colorbar_label_width(const struct sp_font *font, const char *label, int n)
{
    int w = 0;
    if (!label[0])
        return sp_font_width(font, SP_TEXT_SMALL, SP_COLORBAR_NAME);
    for (int i = 0; i < n; i++, label += strlen(label) + 1) {
        const int lw = sp_font_width(font, SP_TEXT_SMALL, label);
        w = lw > w ? lw : w;
    }
    return w;
}

float sp_colorbar_bar_width(const struct sp_font *font, float unit, double max_speed)
{
    char buf[32];
    if (max_speed >= 0.01 && max_speed < pow(10, SP_AXIS_MAX_DIGITS)) /* the top label, 2 decimals */
        sp_axis_number(buf, sizeof(buf), max_speed, 2);
    else /* "9.99×10⁶", "0.00123", "1.00×10⁻¹⁵": as many decimals as ticks 1% apart need */
        sp_axis_number_step(buf, sizeof(buf), max_speed, 0.01 * max_speed);
    return roundf(0.018f * unit) + roundf(0.006f * unit) +
           (float)sp_font_width(font, SP_TEXT_SMALL, buf) + 4;
}

float sp_colorbar_width(const struct sp_font *font, float unit, double max_speed, const char *label,
                        int n)
{
    return fmaxf(sp_colorbar_bar_width(font, unit, max_speed),
                 (float)colorbar_label_width(font, label, n));
}

void sp_colorbar_draw(struct sp_canvas *c, const struct sp_rect *r, int colormap,
                      double max_speed, const struct sp_palette *pal, float unit, const char *label,
                      int n)
{
    const struct sp_font *f = c->font;
    const float bw = roundf(0.018f * unit), tick = roundf(0.006f * unit);
    const float cap = (float)sp_font_cap(f, SP_TEXT_SMALL), line = (float)sp_font_line(f, SP_TEXT_SMALL);
    if (!label[0])
        label = SP_COLORBAR_NAME, n = 1;
    float y0 = r->y0 + 1.6f * cap + (float)(n - 1) * line, h = fminf(r->y1 - y0 - cap, 0.4f * unit);
    const float x0 = r->x1 - bw - tick - (sp_colorbar_width(f, unit, max_speed, label, n) - bw - tick);
    enum { STEPS = 64 };
    struct sp_axis a;
    char buf[32];
    float rgb[4] = {0, 0, 0, 1};
    sp_axis_make(&a, 0, max_speed, (int)(h / (4.0f * line)), 0);
    /* a top tick at or near the bar's top (a round top speed) would touch
     * the name's last line: the bar moves down until the tick label's top
     * clears the name's descenders (line - cap below its baseline) */
    const double top = floor(max_speed * (1 + 1e-9) / a.step) * a.step;
    const float clear = r->y0 + (float)n * line + 0.5f * cap - (float)(y0 + h * (1 - top / max_speed));
    if (clear > 0) {
        y0 += clear;
        h = fminf(h, r->y1 - y0 - cap);
        sp_axis_make(&a, 0, max_speed, (int)(h / (4.0f * line)), 0);
    }
    for (int i = 0; i < n; i++, label += strlen(label) + 1)
        sp_canvas_text(c, SP_TEXT_SMALL, x0, r->y0 + cap + (float)i * line, SP_ALIGN_LEFT,
                       pal->muted, label);
    for (int i = 0; i < STEPS; i++) { /* fast at the top, like the trail's speed range */
        sp_colormap(colormap, pal->cmap_lo + (pal->cmap_hi - pal->cmap_lo) * (1.0f - (i + 0.5f) / STEPS), rgb);
        sp_canvas_rect(c, x0, y0 + h * i / STEPS, x0 + bw, y0 + h * (i + 1) / STEPS + 0.5f, rgb);
    }
    /* a bar too short for a label at every tick labels every k-th, counted
     * down from the top one, a line apart (at 640x240 and 24 px "4", "2"
     * and "0" were drawn over each other: attack11 #14) */
    const double gap = h * a.step / max_speed;
    const int k = gap >= line ? 1 : (int)ceil(line / fmax(gap, 1e-6));
    int n_ticks = 0;
    for (double v = a.step; v <= max_speed * (1 + 1e-9); v += a.step)
        n_ticks++; /* the ticks above 0, as the loop below steps */
    int i = 0;
    for (double v = 0; v <= max_speed * (1 + 1e-9); v += a.step, i++) {
        const float y = (float)(y0 + h * (1 - v / max_speed));
        sp_canvas_rect(c, x0 + bw, y - 0.5f, x0 + bw + tick, y + 0.5f, pal->axis);
        if ((n_ticks - i) % k)
            continue;
        sp_axis_number_step(buf, sizeof(buf), v, a.step);
        sp_canvas_text(c, SP_TEXT_SMALL, x0 + bw + tick + 3, y + 0.5f * cap, SP_ALIGN_LEFT, pal->muted, buf);
    }
}
