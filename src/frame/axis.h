/* springpend (internal): one layout of a chart's axes and ticks, for a
 * still's panels (panels.c) and a sweep's figures (sweep_plot.c): round
 * ticks (1, 2, 5 x 10^k) whose labels fit along the axis, the labels'
 * text (a real minus sign; a small range around a large value labelled
 * from a round offset), and at a physical size the marks in pt:
 * matplotlib's print defaults (axes.linewidth 0.8 pt, xtick.major.size
 * 3.5 pt), tick labels SP_AXIS_LABEL_FRAC of the body text.
 * Shared with: sweep. */
#ifndef SPRINGPEND_AXIS_H
#define SPRINGPEND_AXIS_H

#include <stddef.h>

#define SP_AXIS_LINE_PT 0.8     /* axis lines and ticks, width at a physical size, pt */
#define SP_AXIS_TICK_PT 3.5     /* a tick's length at a physical size, pt */
#define SP_AXIS_LABEL_FRAC 0.85 /* tick labels' and axis names' size over the body text's */

struct sp_axis {
    double lo, hi;      /* data range shown */
    double step, first; /* tick spacing and first tick */
    int decimals;
    double offset;      /* subtracted from the ticks before labelling; 0 = none */
    int offset_decimals;
    int exponent;       /* labels in units of 10^exponent (a factor in the
                           axis's name: large values); 0 = none */
};

/* The tick labels' size, pt, for body text of body pt drawn at per_pt
 * drawing units (px) per pt: SP_AXIS_LABEL_FRAC of it, in whole drawing
 * units (as a font's sizes are; per_pt <= 0: not rounded). */
double sp_axis_label_pt(double body, double per_pt);

/* Sets a to [lo, hi] widened by pad of its span (an empty or tiny range
 * around its value first), no ticks yet. */
void sp_axis_range(struct sp_axis *a, double lo, double hi, double pad);

/* sp_axis_range, then the round step whose tick count is nearest
 * max_ticks (not above it by much). */
void sp_axis_make(struct sp_axis *a, double lo, double hi, int max_ticks, double pad);

/* Labels of more digits than these before the point, or after it, are
 * written in units of a power of ten named with the axis (×10⁷, ×10⁻¹⁰). */
#define SP_AXIS_MAX_DIGITS 6
#define SP_AXIS_MAX_DECIMALS 6

/* Sets a's step (with its first tick, decimals, offset and exponent: labels
 * of large values, over SP_AXIS_MAX_DIGITS digits, or tiny steps, over
 * SP_AXIS_MAX_DECIMALS decimals, in units of 10^N, N the largest label's
 * order, stated in the name): the finest
 * round step, 10 ticks at most, whose labels fit along an axis of `length`
 * units: side by side with a gap of one line height `line` (horizontal;
 * width(ctx, label) measures a label in the same units), or 1.3 line
 * heights apart (vertical: width is not called, may be NULL). */
void sp_axis_fit(struct sp_axis *a, double length, double line,
                 double (*width)(void *ctx, const char *label), void *ctx, int vertical);

/* "1.5" or "−0.25" (U+2212), decimals after the point. */
void sp_axis_number(char *buf, size_t size, double v, int decimals);

/* Tick v of a scale whose ticks are `step` apart, on its own (a colour
 * bar's, no axis name to hold a factor): as sp_axis_number with the
 * decimals step needs; beyond SP_AXIS_MAX_DIGITS digits "2.5×10⁶", and
 * for steps of more than SP_AXIS_MAX_DECIMALS decimals "2×10⁻¹⁶" (0 is
 * "0"). */
void sp_axis_number_step(char *buf, size_t size, double v, double step);

/* Rewrites, in place, each '-' that is a number's sign in text printf
 * wrote ("λ1 = -0.25", "%+d": "-1", "1e-05") as the minus sign U+2212,
 * within size bytes (what no longer fits is cut at a character's end); a
 * hyphen between words ("Kaplan-Yorke", "k-2") stays. */
void sp_axis_minus(char *buf, size_t size);

/* The label of tick v of a (its offset taken off). */
void sp_axis_label(const struct sp_axis *a, double v, char *buf, size_t size);

/* ---- the memo: a chart's axes are laid out again every frame from the
 * same range (the pre-pass's), so their fits and tick labels are kept,
 * each keyed by what produced it (range, length, line height and measure
 * for a fit; range, step, first tick, decimals and offset for labels).
 * What comes out of the memo is byte for byte what the plain calls give. */

#define SP_AXIS_LABEL_BYTES 48 /* a tick label, NUL included */
#define SP_AXIS_MAX_TICKS 16   /* sp_axis_fit gives at most 11 */

/* An axis's ticks: value, label and (when measured) width. */
struct sp_axis_ticks {
    int n;
    double v[SP_AXIS_MAX_TICKS]; /* first, first + step, ... (summed as the loops do) */
    char label[SP_AXIS_MAX_TICKS][SP_AXIS_LABEL_BYTES];
    double width[SP_AXIS_MAX_TICKS]; /* width(ctx, label); 0 when not measured */
};

/* One allocation with no pointers inside: released with free(). */
struct sp_axis_memo;

/* 0, or SP_E_NOMEM. */
int sp_axis_memo_make(struct sp_axis_memo **out);

/* sp_axis_fit through memo m (NULL: computed): the same fit for the same
 * range, length, line, measure (width, ctx) and direction. */
void sp_axis_fit_memo(struct sp_axis_memo *m, struct sp_axis *a, double length, double line,
                      double (*width)(void *ctx, const char *label), void *ctx, int vertical);

/* The ticks of a (fitted by sp_axis_fit: at most SP_AXIS_MAX_TICKS are
 * kept) from first to hi, labelled by sp_axis_label and, with width not
 * NULL, measured by it; from memo m, or (m NULL, or a miss) worked out
 * into *scratch and, with m, kept. The result lives until the next call
 * with m (or scratch). */
const struct sp_axis_ticks *sp_axis_ticks_of(struct sp_axis_memo *m, const struct sp_axis *a,
                                             double (*width)(void *ctx, const char *label),
                                             void *ctx, struct sp_axis_ticks *scratch);

/* The axis's name with its offset and power of ten: "r (m)" with offset
 * 1.004 is "r − 1.004 (m)", so that the ticks read as the difference;
 * "E (J)" with exponent 19 is "E (×10¹⁹ J)", "n" is "n (×10¹⁹)". A large
 * offset is written as a power of ten too ("1.0004×10⁶"). */
void sp_axis_name(const struct sp_axis *a, const char *name, char *buf, size_t size);

#endif
