/* springpend: one layout of a chart's axes and ticks (see axis.h). */
#include <ctype.h>
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
    if (a->exponent) {
        sp_axis_number(buf, size, d / pow(10, a->exponent), a->decimals);
        return;
    }
    if (a->decimals > SP_AXIS_MAX_DECIMALS) {
        /* a tiny range of sp_axis_make's (sp_axis_fit gives it an
         * exponent): as many significant digits as tell the ticks apart,
         * in e notation; fixed decimals would print every tick as
         * 0.000...0 */
        const double mag = fmax(fabs(a->lo - a->offset), fabs(a->hi - a->offset));
        const int digits = (int)(floor(log10(mag)) - floor(log10(a->step))) + 1;
        snprintf(buf, size, "%s%.*g", d < 0 ? "\xe2\x88\x92" : "",
                 d == 0 ? 1 : digits < 1 ? 1 : digits > 17 ? 17 : digits, fabs(d));
        return;
    }
    sp_axis_number(buf, size, d, a->decimals);
}

/* Decimals that tell ticks `step` apart. */
static int step_decimals(double step)
{
    return step >= 1 ? 0 : (int)ceil(-log10(step) - 1e-9);
}

/* Sets a's step, first tick, decimals, offset and exponent for step
 * `step`. Small ranges around a large value (more than 4 significant
 * digits needed, the span under 2% of the value) are labelled from a round
 * offset; labels of more than SP_AXIS_MAX_DIGITS digits before the point,
 * or more than SP_AXIS_MAX_DECIMALS after it, in units of 10^N, N the
 * order of the largest. */
static void axis_step(struct sp_axis *a, double step)
{
    const double span = a->hi - a->lo, mag = fmax(fabs(a->lo), fabs(a->hi));
    a->step = step;
    a->first = ceil(a->lo / step - 1e-9) * step;
    a->decimals = step_decimals(step);
    a->offset = 0;
    a->exponent = 0;
    if (mag > 0 && floor(log10(mag)) + 1 + a->decimals > 4 && span < 0.02 * mag) {
        const double q = pow(10, ceil(log10(span)));
        a->offset = floor(a->lo / q) * q; /* below the range: positive labels */
        a->offset_decimals = q >= 1 ? 0 : (int)lround(-log10(q));
    }
    const double lm = fmax(fabs(a->lo - a->offset), fabs(a->hi - a->offset));
    if (lm >= pow(10, SP_AXIS_MAX_DIGITS) || a->decimals > SP_AXIS_MAX_DECIMALS) {
        a->exponent = (int)floor(log10(lm));
        a->decimals = step_decimals(step / pow(10, a->exponent));
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

/* "×10¹⁹", "×10⁻³" (superscript digits and minus). */
static void power_of_ten(char *buf, size_t size, int e)
{
    static const char *const sup[10] = {"\u2070", "\u00b9", "\u00b2", "\u00b3", "\u2074",
                                        "\u2075", "\u2076", "\u2077", "\u2078", "\u2079"};
    char digits[16];
    const int n = snprintf(digits, sizeof(digits), "%d", e < 0 ? -e : e);
    size_t used = (size_t)snprintf(buf, size, "\u00d710%s", e < 0 ? "\u207b" : "");
    for (int i = 0; i < n && used < size; i++)
        used += (size_t)snprintf(buf + used, size - used, "%s", sup[digits[i] - '0']);
}

void sp_axis_number_step(char *buf, size_t size, double v, double step)
{
    const int tiny = step_decimals(step) > SP_AXIS_MAX_DECIMALS;
    if (tiny && v == 0) {
        snprintf(buf, size, "0");
        return;
    }
    if (!(fabs(v) >= pow(10, SP_AXIS_MAX_DIGITS)) && !tiny) {
        sp_axis_number(buf, size, v, step_decimals(step));
        return;
    }
    const int e = (int)floor(log10(fabs(v)));
    char mant[40], pow10[24];
    sp_axis_number(mant, sizeof(mant), v / pow(10, e), step_decimals(step / pow(10, e)));
    power_of_ten(pow10, sizeof(pow10), e);
    snprintf(buf, size, "%s%s", mant, pow10);
}

void sp_axis_minus(char *buf, size_t size)
{
    size_t n = strlen(buf);
    for (size_t i = 0; i < n; i++) {
        const unsigned char *u = (const unsigned char *)buf;
        const int digit_next = isdigit(u[i + 1]) || (u[i + 1] == '.' && isdigit(u[i + 2]));
        const int after_word = i > 0 && isalnum(u[i - 1]) &&
                               !(u[i - 1] == 'e' && i > 1 && isdigit(u[i - 2]));
        if (buf[i] != '-' || !digit_next || after_word)
            continue;
        /* "-" -> "\xe2\x88\x92": two more bytes, the tail moved (cut to size) */
        size_t tail = n - i - 1;
        if (i + 3 + tail > size - 1) {
            tail = i + 3 > size - 1 ? 0 : size - 1 - (i + 3);
            while (tail && ((unsigned char)buf[i + 1 + tail] & 0xc0) == 0x80)
                tail--; /* not inside a character */
        }
        if (i + 3 > size - 1) {
            buf[i] = 0;
            return;
        }
        memmove(buf + i + 3, buf + i + 1, tail);
        memcpy(buf + i, "\xe2\x88\x92", 3);
        n = i + 3 + tail;
        buf[n] = 0;
        i += 2;
    }
}

/* The offset's magnitude as the name writes it: "1.004", or beyond
 * SP_AXIS_MAX_DIGITS digits "1.0004×10⁶" (its digits down to its
 * rounding, 10^-offset_decimals or the span's order). */
static void offset_text(const struct sp_axis *a, char *buf, size_t size)
{
    const double v = fabs(a->offset);
    if (v < pow(10, SP_AXIS_MAX_DIGITS)) {
        sp_axis_number(buf, size, v, a->offset_decimals);
        return;
    }
    const int e = (int)floor(log10(v));
    const int q = (int)ceil(log10(a->hi - a->lo)); /* the offset is a multiple of 10^q */
    int decimals = e - q;
    decimals = decimals < 0 ? 0 : decimals > 16 ? 16 : decimals;
    char mant[40], pow10[24];
    snprintf(mant, sizeof(mant), "%.*f", decimals, v / pow(10, e));
    if (decimals) { /* no trailing zeros: 1.0004, not 1.000400 */
        char *end = mant + strlen(mant);
        while (end[-1] == '0')
            *--end = 0;
        if (end[-1] == '.')
            end[-1] = 0;
    }
    power_of_ten(pow10, sizeof(pow10), e);
    snprintf(buf, size, "%s%s", mant, pow10);
}

void sp_axis_name(const struct sp_axis *a, const char *name, char *buf, size_t size)
{
    char off[64], pow10[24];
    const char *unit = strstr(name, " (");
    if (a->exponent) {
        power_of_ten(pow10, sizeof(pow10), a->exponent);
        const int stem = unit ? (int)(unit - name) : (int)strlen(name);
        if (a->offset != 0)
            offset_text(a, off, sizeof(off));
        /* the unit's inside: "(J)" -> "J" */
        const char *u = unit ? unit + 2 : "";
        const int ulen = unit ? (int)strcspn(u, ")") : 0;
        snprintf(buf, size, "%.*s%s%s%s (%s%s%.*s)%s", stem, name, a->offset == 0 ? "" : " ",
                 a->offset == 0 ? "" : a->offset > 0 ? "\xe2\x88\x92 " : "+ ",
                 a->offset == 0 ? "" : off, pow10, ulen ? " " : "", ulen, u,
                 unit && u[ulen] == ')' ? u + ulen + 1 : "");
        return;
    }
    if (a->offset == 0) { /* snprintf's "%s", without parsing a format every frame */
        size_t n = strlen(name);
        if (n > size - 1)
            n = size - 1;
        memcpy(buf, name, n);
        buf[n] = 0;
        return;
    }
    offset_text(a, off, sizeof(off));
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
    k.a.exponent = a->exponent;
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
