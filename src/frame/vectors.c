/* springpend (internal): arrows from the bob. See vectors.h. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vectors.h"

static const char *const NAMES[SP_VECTOR_COUNT] = {"velocity", "acceleration", "gravity", "spring",
                                                   "damping", "drive", "net"};
static const char *const UNITS[SP_VQ_COUNT] = {"N", "m/s", "m/s²"};
static const char *const QUANTITY[SP_VQ_COUNT] = {"force", "velocity", "acceleration"};

/* The quantity vector bit i shows. */
static enum sp_vector_quantity quantity_of(int i)
{
    return i == 0 ? SP_VQ_VELOCITY : i == 1 ? SP_VQ_ACCELERATION : SP_VQ_FORCE;
}

/* The largest of 1, 2, 5 x 10^k at most x (x > 0). */
static double nice_below(double x)
{
    const double p10 = pow(10, floor(log10(x)));
    return x >= 5 * p10 ? 5 * p10 : x >= 2 * p10 ? 2 * p10 : p10;
}

void sp_vectors_setup(struct sp_vectors *v, const struct sp_look *look,
                      const struct sp_view_extent *e, const struct sp_params *p, float unit,
                      float max_px)
{
    const double max[SP_VQ_COUNT] = {e->max_force, e->max_speed, e->max_accel};
    *v = (struct sp_vectors){.bits = look->view.vectors, .driven = p->drive_amp != 0,
                             .damped = p->b_over_m > 0, .unit = unit};
    for (int q = 0; q < SP_VQ_COUNT; q++) {
        /* the largest value takes SP_VECTOR_MAX_LENGTH; the key shows a round
         * value at most half of it */
        const double m = max[q] > 0 && isfinite(max[q]) ? max[q] : 1;
        v->px_per[q] = max_px / m;
        v->key[q] = nice_below(0.5 * m);
    }
}

/* An arrow from a along d (px) of length len px: a shaft and two barbs
 * whose round caps end exactly at the tip, so the tip is where the colour
 * reaches farthest. */
static void arrow(struct sp_canvas *c, float ax, float ay, float dx, float dy, float len, float hw,
                  const float color[4])
{
    if (len < 0.5f)
        return;
    const float ux = dx / len, uy = dy / len;
    const float px = ax + ux * (len - hw), py = ay + uy * (len - hw);
    const float head = fminf(4.5f * hw, 0.45f * len), wing = 0.5f * head;
    sp_canvas_line(c, ax, ay, px, py, hw, color);
    if (len < 3 * hw)
        return;
    sp_canvas_line(c, px, py, px - ux * head - uy * wing, py - uy * head + ux * wing, hw, color);
    sp_canvas_line(c, px, py, px - ux * head + uy * wing, py - uy * head - ux * wing, hw, color);
}

static float half_width(float unit)
{
    return fmaxf(1.0f, 0.0026f * unit);
}

void sp_vectors_draw(struct sp_canvas *c, const struct sp_vectors *v, const struct sp_frame *f,
                     const float bob[2], const struct sp_palette *pal)
{
    struct sp_forces fo;
    sp_state_forces(f->params, &f->state, &fo);
    const double vel[2] = {f->state.vx, f->state.vy};
    const double *each[SP_VECTOR_COUNT] = {vel, fo.accel, fo.gravity, fo.spring, fo.damping,
                                           fo.drive, fo.net};
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    /* net last, on top of the forces it sums */
    for (int i = 0; i < SP_VECTOR_COUNT; i++) {
        if (!(v->bits & 1u << i))
            continue;
        const double s = v->px_per[quantity_of(i)];
        const float dx = (float)(s * each[i][0]), dy = (float)(-s * each[i][1]); /* y down */
        arrow(c, bob[0], bob[1], dx, dy, sqrtf(dx * dx + dy * dy), half_width(v->unit),
              pal->vectors[i]);
    }
}

/* The legend's rows: text, arrow length (px; 0 = none) and colour; their
 * count. */
struct legend {
    char text[SP_VECTOR_COUNT + SP_VQ_COUNT + 1][96];
    float len[SP_VECTOR_COUNT + SP_VQ_COUNT + 1];
    const float *color[SP_VECTOR_COUNT + SP_VQ_COUNT + 1];
    int n;
    float line, cap, pad, lmax, w, h; /* px: its box is w x h */
};

static void legend_rows(const struct sp_font *f, const struct sp_vectors *v,
                        const struct sp_palette *pal, struct legend *g)
{
    static const float none_color[4] = {0};
    g->line = (float)sp_font_line(f, SP_TEXT_SMALL), g->cap = (float)sp_font_cap(f, SP_TEXT_SMALL);
    g->pad = roundf(0.5f * g->line);
    const float swatch = 2.2f * g->line;
    int n = 0;
    for (int i = 0; i < SP_VECTOR_COUNT; i++) {
        if (!(v->bits & 1u << i))
            continue;
        /* damping and the drive asked for in a scene without them: said, not drawn */
        const int none = (i == 4 && !v->damped) || (i == 5 && !v->driven);
        snprintf(g->text[n], sizeof(g->text[n]), "%s%s", NAMES[i],
                 i == 4 && none ? ": none (b = 0)" : i == 5 && none ? ": none (fixed pivot)"
                 : i == 5 ? " (inertial, −m a_pivot)" : "");
        g->len[n] = none ? 0 : swatch;
        g->color[n++] = !pal ? none_color : none ? pal->muted : pal->vectors[i];
    }
    for (int q = 0; q < SP_VQ_COUNT; q++) {
        int used = 0;
        for (int i = 0; i < SP_VECTOR_COUNT; i++)
            used |= (v->bits & 1u << i) && quantity_of(i) == (enum sp_vector_quantity)q;
        if (!used)
            continue;
        snprintf(g->text[n], sizeof(g->text[n]), "%g %s", v->key[q], UNITS[q]);
        g->len[n] = (float)(v->key[q] * v->px_per[q]), g->color[n++] = pal ? pal->muted : none_color;
    }
    if (v->driven) /* the frame the arrows are drawn in */
        snprintf(g->text[n], sizeof(g->text[n]), "in the pivot's frame"), g->len[n] = 0,
                                                 g->color[n++] = pal ? pal->muted : none_color;
    g->n = n;
    g->w = 0, g->lmax = swatch;
    for (int i = 0; i < n; i++)
        g->lmax = fmaxf(g->lmax, g->len[i]);
    for (int i = 0; i < n; i++)
        g->w = fmaxf(g->w, (g->len[i] > 0 ? g->lmax + g->pad : 0) +
                               sp_font_width(f, SP_TEXT_SMALL, g->text[i]));
    /* the box with its padding, and the gap to the view's corner */
    g->w += 3 * g->pad;
    g->h = n * g->line + 3 * g->pad - (g->line - g->cap) * 0.5f;
}

void sp_vectors_legend_size(const struct sp_font *f, const struct sp_vectors *v, float *w,
                            float *h)
{
    struct legend g;
    legend_rows(f, v, NULL, &g);
    *w = g.w, *h = g.h;
}

void sp_vectors_legend(struct sp_canvas *c, const struct sp_vectors *v, const struct sp_rect *r,
                       const struct sp_palette *pal)
{
    const struct sp_font *f = c->font;
    if (!f || !v->bits)
        return;
    struct legend g;
    legend_rows(f, v, pal, &g);
    const float pad = g.pad, hw = half_width(v->unit);
    const float x0 = r->x0 + pad, y0 = r->y0 + pad;
    float bg[4];
    memcpy(bg, pal->panel, sizeof(bg));
    bg[3] *= 0.85f;
    sp_canvas_layer(c, SP_LAYER_STATIC);
    sp_canvas_rect(c, x0, y0, x0 + g.w - pad, y0 + g.h - pad, bg);
    for (int i = 0; i < g.n; i++) {
        const float base = y0 + pad + i * g.line + g.cap, mid = base - 0.5f * g.cap;
        arrow(c, x0 + pad, mid, g.len[i], 0, g.len[i], hw, g.color[i]);
        sp_canvas_text(c, SP_TEXT_SMALL, x0 + pad + (g.len[i] > 0 ? g.lmax + pad : 0), base,
                       SP_ALIGN_LEFT, g.len[i] > 0 ? pal->text : g.color[i], g.text[i]);
    }
}

void sp_vectors_describe(const struct sp_vectors *v, int ss, const char *prefix, char *buf,
                         size_t size, size_t *used)
{
    for (int q = 0; q < SP_VQ_COUNT && v->bits; q++)
        if (*used < size)
            *used += (size_t)snprintf(buf + *used, size - *used,
                                      "%svectors.%s.px_per_unit=%.9g\n%svectors.%s.key=%g %s\n",
                                      prefix, QUANTITY[q], v->px_per[q] / ss, prefix, QUANTITY[q],
                                      v->key[q], UNITS[q]);
}
