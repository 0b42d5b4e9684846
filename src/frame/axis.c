/* springpend: one layout of a chart's axes and ticks (see axis.h). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "axis.h"

static const double MULT[] = {1, 2, 5};

double sp_axis_label_pt(double body, double per_pt)
{
    const double pt = SP_AXIS_LABEL_FRAC * body;
    return per_pt > 0 ? round(pt * per_pt) / per_pt : pt;
}

void sp_axis_range(struct sp_axis *a, double lo, double hi, double pad)
{
    double span = hi - lo, mag = fmax(fabs(lo), fabs(hi));
    if (!(span > 1e-9 * (mag + 1e-30)) || !isfinite(span)) {
        const double half = mag > 0 ? 0.1 * mag : 1;
        lo -= half;
        hi += half;
        span = hi - lo;
    }
    *a = (struct sp_axis){.lo = lo - pad * span, .hi = hi + pad * span};
}

void sp_axis_make(struct sp_axis *a, double lo, double hi, int max_ticks, double pad)
{
    sp_axis_range(a, lo, hi, pad);
    const double span = a->hi - a->lo;
    if (max_ticks < 2)
        max_ticks = 2;
    /* the round step whose tick count is nearest to max_ticks, not above it by much */
    const double raw = span / max_ticks, p10 = pow(10, floor(log10(raw)));
    double best = 1e300;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 3; i++) {
            const double step = MULT[i] * p10 * (k ? 10 : 1), count = span / step;
            const double miss = fabs(log(count / max_ticks)) + (count > 1.4 * max_ticks ? 10 : 0);
            if (miss < best)
                best = miss, a->step = step;
        }
    a->first = ceil(a->lo / a->step - 1e-9) * a->step;
    a->decimals = a->step >= 1 ? 0 : (int)ceil(-log10(a->step) - 1e-9);
}

void sp_axis_number(char *buf, size_t size, double v, int decimals)
{
    if (fabs(v) < 1e-12)
        v = 0;
    snprintf(buf, size, "%s%.*f", v < 0 ? "\xe2\x88\x92" : "", decimals, fabs(v));
}

void sp_axis_label(const struct sp_axis *a, double v, char *buf, size_t size)
{
    double d = v - a->offset;
    if (fabs(d) < 1e-9 * a->step)
        d = 0;
    if (a->decimals > 6) {
        /* a tiny range (an azimuth of 1e-298 degrees): as many significant
         * digits as tell the ticks apart, in e notation; fixed decimals
         * would print every tick as 0.000...0 */
        const double mag = fmax(fabs(a->lo - a->offset), fabs(a->hi - a->offset));
        const int digits = (int)(floor(log10(mag)) - floor(log10(a->step))) + 1;
        snprintf(buf, size, "%s%.*g", d < 0 ? "\xe2\x88\x92" : "",
                 d == 0 ? 1 : digits < 1 ? 1 : digits > 17 ? 17 : digits, fabs(d));
        return;
    }
    sp_axis_number(buf, size, d, a->decimals);
}

/* Sets a's step, first tick, decimals and offset for step `step`. Small
 * ranges around a large value (more than 4 significant digits needed, the
 * span under 2% of the value) are labelled from a round offset. */
static void axis_step(struct sp_axis *a, double step)
{
    const double span = a->hi - a->lo, mag = fmax(fabs(a->lo), fabs(a->hi));
    a->step = step;
    a->first = ceil(a->lo / step - 1e-9) * step;
    a->decimals = step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
    a->offset = 0;
    if (mag > 0 && floor(log10(mag)) + 1 + a->decimals > 4 && span < 0.02 * mag) {
        const double q = pow(10, ceil(log10(span)));
        a->offset = floor(a->lo / q) * q; /* below the range: positive labels */
        a->offset_decimals = q >= 1 ? 0 : (int)lround(-log10(q));
    }
}

void sp_axis_fit(struct sp_axis *a, double length, double line,
                 double (*width)(void *ctx, const char *label), void *ctx, int vertical)
{
    const double span = a->hi - a->lo;
    double p10 = pow(10, floor(log10(span / 60)));
    char buf[48];
    for (int k = 0; k < 12; k++, p10 *= 10)
        for (int i = 0; i < 3; i++) {
            const double step = MULT[i] * p10;
            float need = 1.3f * (float)line;
            if (span / step > 10) /* at most 10 ticks: more is clutter, not information */
                continue;
            axis_step(a, step);
            if (!vertical) {
                float widest = 0;
                for (double v = a->first; v <= a->hi + 1e-9 * step; v += step) {
                    sp_axis_label(a, v, buf, sizeof(buf));
                    widest = fmaxf(widest, (float)width(ctx, buf));
                }
                need = widest + (float)line;
            }
            if (step / span * length >= need)
                return;
        }
}

void sp_axis_name(const struct sp_axis *a, const char *name, char *buf, size_t size)
{
    char off[40];
    const char *unit = strstr(name, " (");
    if (a->offset == 0) { /* snprintf's "%s", without parsing a format every frame */
        size_t n = strlen(name);
        if (n > size - 1)
            n = size - 1;
        memcpy(buf, name, n);
        buf[n] = 0;
        return;
    }
    sp_axis_number(off, sizeof(off), fabs(a->offset), a->offset_decimals);
    snprintf(buf, size, "%.*s %s %s%s", unit ? (int)(unit - name) : (int)strlen(name), name,
             a->offset > 0 ? "\xe2\x88\x92" : "+", off, unit ? unit : "");
}

/* ---- the memo ---- */

enum { MEMO_FITS = 32, MEMO_TICKS = 32 }; /* a frame's panels have at most 16 axes */

/* Keys are compared as bytes (memcmp): built from zeroed memory, so the
 * padding compares too, and -0 and 0, which round differently, differ. */
struct fit_key {
    double lo, hi, length, line;
    double (*width)(void *ctx, const char *label);
    void *ctx;
    int vertical;
};

struct ticks_key {
    struct sp_axis a;
    double (*width)(void *ctx, const char *label);
    void *ctx;
};

struct sp_axis_memo {
    struct {
        struct fit_key key;
        struct sp_axis out;
    } fit[MEMO_FITS];
    struct {
        struct ticks_key key;
        struct sp_axis_ticks t;
    } ticks[MEMO_TICKS];
    int n_fit, n_ticks;       /* entries in use */
    int next_fit, next_ticks; /* the entry replaced when full (oldest first) */
};

int sp_axis_memo_make(struct sp_axis_memo **out)
{
    *out = calloc(1, sizeof(**out));
    return *out ? 0 : SP_E_NOMEM;
}

/* The slot for a new entry of a table of `cap` with *n used. */
static int memo_slot(int *n, int *next, int cap)
{
    if (*n < cap)
        return (*n)++;
    const int i = *next;
    *next = (i + 1) % cap;
    return i;
}

void sp_axis_fit_memo(struct sp_axis_memo *m, struct sp_axis *a, double length, double line,
                      double (*width)(void *ctx, const char *label), void *ctx, int vertical)
{
    if (!m) {
        sp_axis_fit(a, length, line, width, ctx, vertical);
        return;
    }
    struct fit_key k;
    memset(&k, 0, sizeof(k));
    k.lo = a->lo, k.hi = a->hi, k.length = length, k.line = line;
    k.width = width, k.ctx = ctx, k.vertical = vertical;
    for (int i = 0; i < m->n_fit; i++)
        if (!memcmp(&m->fit[i].key, &k, sizeof(k))) {
            *a = m->fit[i].out;
            return;
        }
    sp_axis_fit(a, length, line, width, ctx, vertical);
    const int i = memo_slot(&m->n_fit, &m->next_fit, MEMO_FITS);
    m->fit[i].key = k;
    m->fit[i].out = *a;
}

/* Fills t with a's ticks, labels and widths. */
static void ticks_make(struct sp_axis_ticks *t, const struct sp_axis *a,
                       double (*width)(void *ctx, const char *label), void *ctx)
{
    t->n = 0;
    for (double v = a->first; v <= a->hi + 1e-9 * a->step && t->n < SP_AXIS_MAX_TICKS;
         v += a->step, t->n++) {
        t->v[t->n] = v;
        sp_axis_label(a, v, t->label[t->n], SP_AXIS_LABEL_BYTES);
        t->width[t->n] = width ? width(ctx, t->label[t->n]) : 0;
    }
}

const struct sp_axis_ticks *sp_axis_ticks_of(struct sp_axis_memo *m, const struct sp_axis *a,
                                             double (*width)(void *ctx, const char *label),
                                             void *ctx, struct sp_axis_ticks *scratch)
{
    struct ticks_key k;
    memset(&k, 0, sizeof(k));
    /* field by field: the struct's own padding stays zero */
    k.a.lo = a->lo, k.a.hi = a->hi, k.a.step = a->step, k.a.first = a->first;
    k.a.decimals = a->decimals, k.a.offset = a->offset, k.a.offset_decimals = a->offset_decimals;
    k.width = width, k.ctx = ctx;
    if (m) {
        for (int i = 0; i < m->n_ticks; i++)
            if (!memcmp(&m->ticks[i].key, &k, sizeof(k)))
                return &m->ticks[i].t;
        const int i = memo_slot(&m->n_ticks, &m->next_ticks, MEMO_TICKS);
        m->ticks[i].key = k;
        scratch = &m->ticks[i].t;
    }
    ticks_make(scratch, a, width, ctx);
    return scratch;
}
