/* springpend: orbit diagrams of a driven scene with the peak of each drive
 * period beside the stroboscopic sample, and with continuation in the
 * parameter (see analysis.h).
 *
 * Samples: theta at t = k/f as --measure orbit takes it (the cubic Hermite
 * interpolant of the step, so the column equals the plain diagram's), and
 * the largest |theta| (or r) over the period that ends there, from the state
 * at every step of dt and at the sample itself (error ~ theta'' dt^2 / 8).
 *
 * Continuation: a branch walks the grid's values in order (up: increasing,
 * down: decreasing, whichever way the range was given); each value starts
 * from the relative state (position and velocity relative to the pivot) that
 * the previous value's run had at its last whole drive period, so the drive's
 * phase (0 at t = 0) matches. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "base/array.h"
#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/sim.h"

#define RAD2DEG 57.29577951308232
#define SEED_ANGLE (0.05 / RAD2DEG) /* rad: the seed away from hanging */
#define SEED_RATE 1e-3              /* rad/s */

struct sample {
    double t, theta, r, peak; /* s, degrees, m, degrees or m */
};

struct samples {
    struct sample *s;
    long n, cap;
    int dead;
};

static int push(struct samples *v, struct sample s)
{
    if (SP_ARRAY_RESERVE(v->s, v->cap, v->n + 1, 64))
        return SP_E_NOMEM;
    v->s[v->n++] = s;
    return 0;
}

/* Steps every lane of b (scenes[i]'s drive) from 0 to transient + time by
 * dt, appending each lane's samples after the transient to out[i]. */
static int sample_lanes(const struct sp_sweep_desc *d, struct sp_batch *b,
                        const struct sp_scene *const *scenes, int n, struct samples *out)
{
    const double dt = d->dt, t_end = d->transient + d->time;
    const int by_r = d->peak == SP_PEAK_R;
    double prev[4][64], peak[64], last_k[64] = {0}; /* the last k sampled (k >= 1) */
    if (n > 64)
        return SP_E_INPUT; /* not reached: chunks are smaller */
    for (int i = 0; i < n; i++) {
        double x = b->out[SP_BX][i], y = b->out[SP_BY][i];
        peak[i] = by_r ? hypot(x, y) : fabs(atan2(x, -y)) * RAD2DEG;
    }
    for (long step = 0;; step++) {
        double t0 = (double)step * dt, t1 = (double)(step + 1) * dt;
        if (t0 >= t_end)
            break;
        if (step % 1024 == 0 && sp_sweep_cancelled(d))
            return SP_E_INTERRUPTED;
        for (int c = 0; c < 4; c++)
            memcpy(prev[c], b->out[c], sizeof(double) * (size_t)n);
        sp_batch_advance(b, t1);
        for (int i = 0; i < n; i++) {
            if (b->dead[i])
                continue;
            const double x0 = prev[0][i], y0 = prev[1][i], vx0 = prev[2][i], vy0 = prev[3][i];
            const double x1 = b->out[SP_BX][i], y1 = b->out[SP_BY][i];
            const double vx1 = b->out[SP_BVX][i], vy1 = b->out[SP_BVY][i];
            const double f = scenes[i]->pivot.frequency;
            double k = floor(t1 * f * (1 + 1e-15)), te = k / f;
            if (te > t0 && te <= t1 * (1 + 1e-15) && k > last_k[i]) { /* as measure_events */
                last_k[i] = k;
                double s = fmin(1, (te - t0) / dt);
                double x = sp_hermite(s, dt, x0, vx0, x1, vx1);
                double y = sp_hermite(s, dt, y0, vy0, y1, vy1);
                double th = atan2(x, -y) * RAD2DEG, r = hypot(x, y);
                double at = by_r ? r : fabs(th);
                if (te >= d->transient &&
                    push(&out[i], (struct sample){te, th, r, fmax(peak[i], at)}))
                    return SP_E_NOMEM;
                peak[i] = at; /* the next period starts here */
            }
            double at = by_r ? hypot(x1, y1) : fabs(atan2(x1, -y1)) * RAD2DEG;
            peak[i] = fmax(peak[i], at);
        }
    }
    for (int i = 0; i < n; i++)
        out[i].dead = b->dead[i];
    return 0;
}

/* One point's rows: its samples, or one NaN row when it blew up. */
static void write_rows(FILE *fp, const struct sp_sweep_desc *d, long p, int branch,
                       const struct samples *v, long *blown_up)
{
    char head[160];
    sp_sweep_format_point(head, sizeof(head), d, p);
    if (v->dead) {
        (*blown_up)++;
        fprintf(fp, "%snan,nan,nan,%d,nan\n", head, branch);
        return;
    }
    if (!v->n) /* no drive period in the span: one row says so (sweep_rows.c) */
        fprintf(fp, "%s%.10g,nan,nan,%d,nan\n", head, d->transient + d->time, branch);
    for (long j = 0; j < v->n; j++)
        fprintf(fp, "%s%.10g,%.9g,%.9g,%d,%.9g\n", head, v->s[j].t, v->s[j].theta + 0.0,
                v->s[j].r, branch, v->s[j].peak + 0.0); /* + 0.0: never "-0" (sweep.c) */
}

int sp_orbit_peak_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                          const long *pts, const int *skip, int n, int forced, FILE *rows,
                          long *blown_up)
{
    const struct sp_scene *ptr[64] = {0};
    struct samples v[64];
    struct sp_batch *b;
    memset(v, 0, sizeof(v));
    for (int i = 0; i < n; i++)
        ptr[i] = &scenes[i];
    int ret = sp_batch_make(&b, ptr, n, 0, forced);
    if (!ret)
        ret = sample_lanes(d, b, ptr, n, v);
    sp_batch_destroy(&b);
    for (int i = 0; i < n; i++) {
        if (!ret && !skip[i])
            write_rows(rows, d, pts[i], 0, &v[i], blown_up);
        free(v[i].s);
    }
    if (ret == SP_E_NOMEM)
        sp_log_error("out of memory for an orbit diagram's samples");
    return ret;
}

/* The relative state of lane i at b->t as scene's initial keys (SI units,
 * scene.h), with the seed away from hanging. */
static void carry_state(const struct sp_batch *b, int i, struct sp_scene *next)
{
    double x = b->out[SP_BX][i], y = b->out[SP_BY][i];
    double vx = b->out[SP_BVX][i], vy = b->out[SP_BVY][i];
    double r = hypot(x, y), th = atan2(x, -y);
    double rd = (x * vx + y * vy) / r, thd = (x * vy - y * vx) / (r * r);
    if (fabs(th) < SEED_ANGLE && fabs(thd) < SEED_RATE)
        th = SEED_ANGLE;
    next->initial.length = r;
    next->initial.angle = th;
    next->initial.length_rate = rd;
    next->initial.angle_rate = thd;
}

int sp_orbit_continue(const struct sp_sweep_desc *d, const struct sp_scene *base, int forced,
                      FILE *fp, long *blown_up)
{
    const long N = d->axis[0].count;
    const int up = d->cont == SP_CONTINUE_UP || d->cont == SP_CONTINUE_BOTH;
    const int down = d->cont == SP_CONTINUE_DOWN || d->cont == SP_CONTINUE_BOTH;
    /* runs[0][p]: the up branch at point p, runs[1][p] the down branch's */
    struct samples *runs[2] = {calloc((size_t)N, sizeof(struct samples)),
                               calloc((size_t)N, sizeof(struct samples))};
    int ret = runs[0] && runs[1] ? 0 : SP_E_NOMEM;
    for (int br = 0; br < 2 && !ret; br++) {
        if (!(br ? down : up))
            continue;
        struct sp_scene carried = *base;
        int have = 0;
        for (long j = 0; j < N && !ret; j++) {
            /* up: in increasing values of the key, whichever way --vary
             * gave its range (FROM > TO lists them from the top) */
            long p = (br != 0) != (d->axis[0].to < d->axis[0].from) ? N - 1 - j : j;
            struct sp_scene sc;
            const struct sp_scene *ptr = &sc;
            struct sp_batch *b;
            sp_sweep_point_scene(d, base, p, &sc);
            if (have)
                sc.initial = carried.initial;
            if ((ret = sp_batch_make(&b, &ptr, 1, 0, forced)))
                break;
            ret = sample_lanes(d, b, &ptr, 1, &runs[br][p]);
            /* on to the next whole drive period: the drive's phase is 0 there */
            double f = sc.pivot.frequency, t_c = ceil(b->t * f - 1e-9) / f;
            if (!ret && t_c > b->t)
                sp_batch_advance(b, t_c);
            have = !ret && !b->dead[0];
            if (have)
                carry_state(b, 0, &carried);
            sp_batch_destroy(&b);
        }
    }
    for (long q = 0; q < N; q++) {
        long dead = 0; /* the point's branches that blew up: the point counts once */
        for (int br = 0; br < 2; br++) {
            if (!ret && (br ? down : up))
                write_rows(fp, d, q, br ? -1 : 1, &runs[br][q], &dead);
            if (runs[br])
                free(runs[br][q].s);
        }
        *blown_up += dead > 0;
    }
    free(runs[0]), free(runs[1]);
    if (ret == SP_E_NOMEM)
        sp_log_error("out of memory for a continued orbit diagram");
    return ret;
}
