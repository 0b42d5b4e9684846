/* springpend: a shard's rows as a sequence (sweep.h: sp_sweep_row_check
 * checks each row's form, this what rows each point has). A forger who
 * edits rows and recomputes the SHA-256 and the row count (a checksum, not
 * a signature) can still swap, copy over or drop rows; each measure's rows
 * follow a rule that such an edit breaks:
 *   lyapunov, basins, precession  one row per point, every point;
 *   spectrum   the checkpoints' renormalisation times T, in order, the same
 *              for every point (or one NaN row at T = time);
 *   orbit, driven   t = k/f for every k the steps sample, per branch;
 *   orbit, undriven; poincare   times strictly ascending.
 * Every point (and branch) has rows: one that blew up one row of NaN, an
 * orbit's or Poincare mosaic's point without a sample or crossing in the
 * span (or, poincare, without the energy) one row of its own, t = T0 + T
 * and NaN (sweep.c, continuation.c), so a point dropped is told. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "analysis.h"
#include "sweep.h"

enum rule { ONE_ROW, SPECTRUM, STROBE, EVENTS };

static enum rule rule_of(const struct sp_sweep_desc *d)
{
    switch (d->measure) {
    case SP_MEASURE_SPECTRUM:
        return SPECTRUM;
    case SP_MEASURE_ORBIT:
        return d->driven ? STROBE : EVENTS;
    case SP_MEASURE_POINCARE:
        return EVENTS;
    default:
        return ONE_ROW;
    }
}

/* The branches of a point's rows, in order (the branch column of --continue
 * and --peak; 0 without one). Returns how many. */
static int branches(const struct sp_sweep_desc *d, int out[2])
{
    out[0] = d->cont == SP_CONTINUE_DOWN ? -1 : d->cont ? 1 : 0;
    out[1] = -1;
    return d->cont == SP_CONTINUE_BOTH ? 2 : 1;
}

/* Where branch b stands among the point's branches; -1: not one of them. */
static int branch_index(const struct sp_sweep_desc *d, int b)
{
    int list[2];
    const int n = branches(d, list);
    for (int i = 0; i < n; i++)
        if (list[i] == b)
            return i;
    return -1;
}

int sp_spectrum_checkpoints(const struct sp_sweep_desc *d, double *T, int max)
{
    const int fixed = !strcmp(d->method, "rk4") || !strcmp(d->method, "verlet") ||
                      !strcmp(d->method, "yoshida4");
    struct sp_lyap_grid g;
    sp_sweep_lyap_grid(d->time, fixed ? SP_METHOD_RK4 : SP_METHOD_DOP853, d->dt, &g);
    int n = 0;
    long prev = 0;
    for (int i = 0; n < max; i++) { /* as spectrum.c's checkpoint() walks them */
        const long v = lround(pow(10, i / 10.0));
        if (v >= g.K)
            break;
        if (v > prev)
            T[n++] = (double)v * g.tau, prev = v;
    }
    if (n < max)
        T[n++] = (double)g.K * g.tau;
    return n;
}

void sp_sweep_strobe_range(const struct sp_sweep_desc *d, double f, double *k0, double *k1,
                           int *gaps)
{
    const double dt = d->dt, t_end = d->transient + d->time;
    /* the steps run while step dt < t_end (sweep.c's measure_events): S of them */
    double S = fmax(1, ceil(t_end / dt));
    while (S * dt < t_end)
        S++;
    while (S > 1 && (S - 1) * dt >= t_end)
        S--;
    double first = fmax(1, ceil(d->transient * f));
    while (first / f < d->transient)
        first++;
    while (first > 1 && (first - 1) / f >= d->transient)
        first--;
    *k0 = first;
    *k1 = floor(S * dt * f * (1 + 1e-15));
    *gaps = !(f * dt < 1);
}

/* The drive frequency of point p (Hz), or 0 when it is not known here. */
static double point_frequency(const struct sp_sweep_rows *r, long p)
{
    struct sp_scene s;
    if (!r->base || sp_sweep_point_scene(r->d, r->base, p, &s) < 0)
        return 0;
    return s.pivot.frequency;
}

static char said[320];

/* The current group (point r->point, branch r->branch) ends here: whole? */
static const char *group_done(const struct sp_sweep_rows *r)
{
    const enum rule rule = rule_of(r->d);
    if (r->group_blown)
        return NULL;
    if (rule == SPECTRUM) {
        double T[SP_SPECTRUM_MAX_CHECKS];
        const int n = sp_spectrum_checkpoints(r->d, T, SP_SPECTRUM_MAX_CHECKS);
        if (r->seq == n)
            return NULL;
        snprintf(said, sizeof(said), "point %ld's rows end at its row %ld, before T = %.10g "
                 "(allowed: one row per renormalisation time T, %d of them, the last at "
                 "T = --time)", r->point, r->seq, T[n - 1], n);
        return said;
    }
    if (rule == STROBE) {
        const double f = point_frequency(r, r->point);
        double k0, k1;
        int gaps;
        if (!(f > 0))
            return NULL;
        sp_sweep_strobe_range(r->d, f, &k0, &k1, &gaps);
        if (k1 < k0 || r->k == k1)
            return NULL;
        snprintf(said, sizeof(said), "point %ld's rows end at t = %.10g, before t = %.10g "
                 "(allowed: a row at every drive period t = k/f sampled, k from %.0f to %.0f, "
                 "f = %.10g Hz)", r->point, r->k / f, k1 / f, k0, k1, f);
        return said;
    }
    return NULL;
}

/* Every group from just after (p0, branch index i0) up to before (p1, i1)
 * wrote nothing: may it have? */
static const char *groups_missing(const struct sp_sweep_rows *r, long p0, int i0, long p1,
                                  int i1)
{
    int list[2];
    const int nb = branches(r->d, list);
    for (long p = p0; p <= p1 && p < r->last; p++) {
        if (p < r->first)
            continue;
        for (int i = p == p0 ? i0 + 1 : 0; i < (p == p1 ? i1 : nb); i++) {
            if (nb > 1 || list[0])
                snprintf(said, sizeof(said), "point %ld's rows of branch %d are missing "
                         "(allowed: every point of the shard, each of its branches, in order)",
                         p, list[i]);
            else
                snprintf(said, sizeof(said), "point %ld's rows are missing (allowed: every "
                         "point of the shard, in order)", p);
            return said;
        }
    }
    return NULL;
}

/* The first row of point p, branch b: the groups before it whole or empty. */
static const char *group_start(struct sp_sweep_rows *r, long p, int b)
{
    const int bi = branch_index(r->d, b);
    if (bi < 0) {
        snprintf(said, sizeof(said), "branch %d is not one of this sweep's (allowed: %s)", b,
                 r->d->cont == SP_CONTINUE_BOTH ? "1 then -1" : r->d->cont ? "only its one"
                                                                          : "0");
        return said;
    }
    const char *wrong = r->point >= 0 ? group_done(r) : NULL;
    const int at = r->point >= 0 ? branch_index(r->d, r->branch) : -1;
    if (!wrong && p == r->point && bi <= at)
        wrong = "a point's branches out of order (allowed: branch 1, then -1)";
    if (!wrong)
        wrong = groups_missing(r, r->point >= 0 ? r->point : r->first, r->point >= 0 ? at : -1,
                               p, bi);
    r->seq = 0;
    r->k = 0;
    r->group_blown = 0;
    return wrong;
}

/* A driven orbit's row that says point p has no sample: right only when
 * the span holds no drive period of its frequency. */
static const char *no_sample(const struct sp_sweep_rows *r, long p)
{
    const double f = point_frequency(r, p);
    double k0, k1;
    int gaps;
    if (!(f > 0))
        return NULL; /* not known here: not checked */
    sp_sweep_strobe_range(r->d, f, &k0, &k1, &gaps);
    if (k1 < k0)
        return NULL;
    snprintf(said, sizeof(said), "point %ld's row says it has no sample, but the span holds "
             "t = k/f for k from %.0f to %.0f (f = %.10g Hz; allowed: a row at each)", p, k0,
             k1, f);
    return said;
}

/* One row (point p, branch b; its time field tf, read as t; mark: 0 a
 * measured row, 1 the NaN row of a point that blew up, 2 the row of a
 * point without an event) in its group's sequence. */
static const char *in_sequence(struct sp_sweep_rows *r, long p, const char *tf, double t,
                               int mark)
{
    const enum rule rule = rule_of(r->d);
    const int blown = mark == 1;
    char want[48];
    if (r->group_blown || (mark && r->seq > 0))
        return "a point that blew up, or has no event, has that one row and no other "
               "(allowed: its measured rows, or that one row)";
    r->group_blown = mark;
    if (rule == STROBE && mark == 2 && no_sample(r, p))
        return said;
    if (rule == SPECTRUM) {
        double T[SP_SPECTRUM_MAX_CHECKS];
        const int n = sp_spectrum_checkpoints(r->d, T, SP_SPECTRUM_MAX_CHECKS);
        snprintf(want, sizeof(want), "%.10g", blown ? r->d->time : r->seq < n ? T[r->seq] : -1.0);
        if (r->seq >= n || strcmp(tf, want)) {
            snprintf(said, sizeof(said), "T = %s is not point %ld's next renormalisation time "
                     "(allowed: one row per checkpoint T, in order: here %s)", tf, p,
                     r->seq < n ? want : "none, the point's rows ended at T = --time");
            return said;
        }
    } else if (rule == STROBE && !mark) {
        const double f = point_frequency(r, p);
        double k0, k1;
        int gaps;
        if (f > 0) {
            sp_sweep_strobe_range(r->d, f, &k0, &k1, &gaps);
            const double k = round(t * f), next = r->seq ? r->k + 1 : k0;
            snprintf(want, sizeof(want), "%.10g", k / f);
            if (strcmp(tf, want) || k < k0 || k > k1 || k <= r->k || (!gaps && k != next)) {
                snprintf(said, sizeof(said), "t = %s is not point %ld's next drive period "
                         "(allowed: t = k/f at f = %.10g Hz for every k from %.0f to %.0f, in "
                         "order: here k = %.0f, t = %.10g)", tf, p, f, k0, k1, next, next / f);
                return said;
            }
            r->k = k;
        }
    } else if (rule == EVENTS && !mark && r->seq > 0 && !(t > r->t)) {
        return "a point's times do not strictly ascend (allowed: one row per crossing, each "
               "later than the last)";
    }
    r->seq++;
    return NULL;
}

/* sweep.c's sp_sweep_row_check, once a row's form holds. */
const char *sp_sweep_row_sequence(struct sp_sweep_rows *r, long p, int b, const char *tf,
                                  double t, int mark)
{
    const char *wrong = NULL;
    if (p != r->point || b != r->branch || r->point < 0)
        wrong = group_start(r, p, b);
    if (!wrong)
        wrong = in_sequence(r, p, tf, t, mark);
    r->branch = b;
    return wrong;
}

const char *sp_sweep_rows_end(struct sp_sweep_rows *r)
{
    int list[2];
    const int nb = branches(r->d, list);
    const char *wrong = r->point >= 0 ? group_done(r) : NULL;
    if (!wrong)
        wrong = groups_missing(r, r->point >= 0 ? r->point : r->first,
                               r->point >= 0 ? branch_index(r->d, r->branch) : -1, r->last, nb);
    return wrong;
}
