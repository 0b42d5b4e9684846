/* springpend: basins of attraction of a damped, driven scene (see analysis.h).
 *
 * Each start runs on its own (a lane of a batch) and is sampled 8 times per
 * drive period, at t = j / (8 f), so that theta can be unwrapped and whole
 * turns counted; once per period (t = k / f) its state is a sample of the
 * stroboscopic map. After the transient, a start is settled at the first
 * period k at which, for some p <= SP_BASINS_MAX_PERIOD, each of its last
 * p + 2 samples is within the recurrence tolerance of the sample p periods
 * before it, the contraction of those gaps since the window before puts
 * the distance left below the tolerance, and those samples differ from the
 * ones 16 periods or more before (a multiple of p) by under 0.02 tolerances
 * a period, so a swing still drifting away is not settled (repeats): the
 * smallest such p, reduced to a divisor q whose q-shifted
 * samples are within 3 tolerances (the cycle's least period), is its period;
 * a cycle within 10 tolerances of a q-cycle is held until told apart
 * (near_shorter). Tolerance: 1e-3 rad in
 * theta, 1e-3 of the equilibrium length in r, the same times the drive's
 * angular frequency in the rates. A start not settled by transient + time is
 * undecided (chaotic, or still on its way). Its row holds the cycle's sample
 * of least theta, which names the cycle whatever phase the start met it in.
 *
 * Which cycles are the same attractor is decided from the rows alone
 * (sp_basins_read), so the whole run and any merge of shards agree: cycles of
 * equal turns per drive period (winding / period) whose representatives
 * lie within 2 degrees, 1% of r, 0.1 rad/s and 2% of r per second are one
 * attractor (of the least period among them, and its winding: a cycle
 * settled while still closing in on a shorter one is that one), in order of
 * first appearance over the grid. This is the clustering of final states;
 * unlike Attractors.jl's AttractorsViaRecurrences (Datseris and Wagemakers,
 * Chaos 32, 023104 (2022)), which finds recurrences in the cells of a
 * state-space grid shared by all starts, each start here is judged alone, so
 * a chaotic attractor is reported as "undecided" rather than found.
 *
 * Basin entropy (Daza, Wagemakers, Georgeot, Guery-Odelin and Sanjuan, Sci.
 * Rep. 6, 31416 (2016)): the map is cut into boxes of 5 x 5 points from its
 * first point (the last nx % 5 columns and ny % 5 rows, which make no whole
 * box, are left out, as in Attractors.jl's basin_entropy; a grid under 5 on
 * a side has no entropies); box i with outcome fractions p_ij has S_i =
 * -sum_j p_ij ln p_ij; S_b is the mean of S_i over all boxes, S_bb over the
 * boxes with more than one outcome (on a boundary). Undecided counts as an
 * outcome; blown-up points are left out. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "springpend/batch.h"
#include "springpend/common.h"

#define RAD2DEG 57.29577951308232
#define SUB SP_BASINS_SAMPLES          /* samples per drive period */
#define RING 32 /* stroboscopic samples kept per start (>= 3 * max period + 4, and > the
                 * longest lag + its period + 1: 21 + 7 + 1 at p = 7) */
#define MAXL 64                        /* lanes: a chunk (sweep.c's CHUNK) */
#define BOX 5                          /* points per side of an entropy box */

struct lane {
    double ring[RING][4];  /* theta (rad, wrapped), r, theta_dot, r_dot */
    double unwrapped[RING]; /* theta, unwrapped, rad */
    long k;                /* samples taken */
    double last_theta;     /* the sub-sample before, rad */
    double turns;          /* unwrapped theta, rad */
    int period, winding, decided;
    double rep[4], settled;
    int held;              /* 1: a cycle close to a shorter one is held below */
    int held_period, held_winding;
    double held_rep[4], held_settled;
};

static double wrap(double a)
{
    return a - 2 * M_PI * floor(a / (2 * M_PI) + 0.5);
}

static void polar(const struct sp_batch *b, int i, double s[4])
{
    double x = b->out[SP_BX][i], y = b->out[SP_BY][i];
    double vx = b->out[SP_BVX][i], vy = b->out[SP_BVY][i];
    double r = hypot(x, y);
    s[0] = atan2(x, -y);
    s[1] = r;
    s[2] = (x * vy - y * vx) / (r * r);
    s[3] = (x * vx + y * vy) / r;
}

/* The largest distance, in units of the tolerance, between each of the
 * `count` samples that end `back` samples ago and the sample p before it. */
static double gap(const struct lane *L, int p, int back, int count, const double tol[4])
{
    double worst = 0;
    for (int q = back; q < back + count; q++) {
        const double *a = L->ring[(L->k - 1 - q) % RING], *c = L->ring[(L->k - 1 - q - p) % RING];
        worst = fmax(worst, fabs(wrap(a[0] - c[0])) / tol[0]);
        for (int i = 1; i < 4; i++)
            worst = fmax(worst, fabs(a[i] - c[i]) / tol[i]);
    }
    return worst;
}

/* Whether the last samples repeat with period p, converged (see the top):
 * the gaps over the last p + 2 samples (g) and over the p + 2 before them
 * (g1) give the contraction per p periods, rho = g / g1, and the distance
 * left to the cycle, about g rho / (1 - rho); it must be below the
 * tolerance. Not contracting (rho >= 1) is settled only at 1e-3 of it (the
 * rounding floor of a cycle reached). And the same p + 2 samples against
 * those `lag` periods before (the least multiple of p from SP_BASINS_LAG)
 * must differ by under SP_BASINS_DRIFT tolerances a period: a start whose
 * swing still grows under a fading transient contracts between two windows
 * while it drifts away (attack19 #3), a start closing in on its cycle, even
 * spiralling, does not drift. */
#define SP_BASINS_LAG 16
#define SP_BASINS_DRIFT 0.02
static int repeats(const struct lane *L, int p, const double tol[4])
{
    const int lag = p * ((SP_BASINS_LAG + p - 1) / p);
    if (L->k < 3 * p + 4 || L->k < lag + p + 2)
        return 0;
    double g = gap(L, p, 0, p + 2, tol);
    if (!(g < 1))
        return 0;
    double g1 = gap(L, p, p + 2, p + 2, tol), rho = g1 > 0 ? g / g1 : 1;
    if (!(rho < 1 ? g * rho / (1 - rho) < 1 : g < 1e-3))
        return 0;
    return gap(L, lag, 0, p + 2, tol) < SP_BASINS_DRIFT * lag;
}

/* The least period that a settled cycle of period p also has, within three
 * tolerances (a cycle that differs from a shorter one by less is that one:
 * a hanging state approached with alternating sides settles as period 2
 * first). */
static int least_period(const struct lane *L, int p, const double tol[4])
{
    for (int q = 1; q < p; q++)
        if (p % q == 0 && gap(L, q, 0, p, tol) < 3)
            return q;
    return p;
}

/* Whether a settled cycle of period p lies within SP_BASINS_NEAR tolerances
 * of a shorter one (period q dividing p) without being it: a start still
 * shedding a slow, beating transient around a period-q cycle (successive
 * samples alternating by a few tolerances, attack15 #8) passes the p test
 * first. Such a cycle is held, not settled: the start runs on until the
 * q-cycle settles, or the p-cycle moves further from it, or the run ends
 * (then the held cycle is its outcome). */
#define SP_BASINS_NEAR 10
static int near_shorter(const struct lane *L, int p, const double tol[4])
{
    for (int q = 1; q < p; q++)
        if (p % q == 0 && gap(L, q, 0, p, tol) < SP_BASINS_NEAR)
            return 1;
    return 0;
}

/* Settles lane L as a cycle of period p (already its least) at time t: its
 * winding and its sample of least theta; a cycle near a shorter one is held
 * (near_shorter) unless `hold` is 0. */
static void settle(struct lane *L, int p, double t, int hold)
{
    int winding = (int)lround((L->turns - L->unwrapped[(L->k - 1 - p) % RING]) / (2 * M_PI));
    int best = 0; /* the cycle's sample of least theta */
    for (int q = 1; q < p; q++)
        if (L->ring[(L->k - 1 - q) % RING][0] < L->ring[(L->k - 1 - best) % RING][0])
            best = q;
    if (hold) {
        if (!L->held) {
            L->held = 1, L->held_period = p, L->held_winding = winding, L->held_settled = t;
            memcpy(L->held_rep, L->ring[(L->k - 1 - best) % RING], sizeof(L->held_rep));
        }
        return;
    }
    L->decided = 1, L->period = p, L->winding = winding, L->settled = t;
    memcpy(L->rep, L->ring[(L->k - 1 - best) % RING], sizeof(L->rep));
}

/* Runs the lanes idx[0..m) of one drive frequency f (scenes[idx[i]]) in a
 * batch of their own and settles each. */
static int run_group(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                     const int *idx, int m, int forced, struct lane *lanes, long *blown_up,
                     const int *skip)
{
    const struct sp_scene *ptr[MAXL];
    struct sp_batch *b;
    for (int i = 0; i < m; i++)
        ptr[i] = &scenes[idx[i]];
    int ret = sp_batch_make(&b, ptr, m, 0, forced);
    if (ret)
        return ret;
    const double f = ptr[0]->pivot.frequency, t_max = d->transient + d->time;
    const double w = 2 * M_PI * f;
    double tol[MAXL][4];
    for (int i = 0; i < m; i++) { /* each start's own equilibrium length */
        const struct sp_scene *sc = ptr[i];
        double ell = sc->pendulum.natural_length +
                     sc->pendulum.mass * sc->pendulum.gravity / sc->pendulum.stiffness;
        tol[i][0] = 1e-3, tol[i][1] = 1e-3 * ell, tol[i][2] = 1e-3 * w;
        tol[i][3] = 1e-3 * ell * w;
    }
    for (int i = 0; i < m; i++) {
        double s[4];
        polar(b, i, s);
        lanes[i].last_theta = s[0];
    }
    for (long j = 1;; j++) {
        double t = (double)j / (SUB * f);
        if (t > t_max * (1 + 1e-12))
            break;
        if (j % 256 == 0 && sp_sweep_cancelled(d)) {
            ret = SP_E_INTERRUPTED;
            break;
        }
        sp_batch_advance(b, t);
        int open = 0;
        for (int i = 0; i < m; i++) {
            struct lane *L = &lanes[i];
            if (L->decided || b->dead[i])
                continue;
            double s[4];
            polar(b, i, s);
            L->turns += wrap(s[0] - L->last_theta);
            L->last_theta = s[0];
            if (j % SUB == 0) {
                memcpy(L->ring[L->k % RING], s, sizeof(s));
                L->unwrapped[L->k % RING] = L->turns;
                L->k++;
                if (t >= d->transient * (1 - 1e-12))
                    for (int p = 1; p <= SP_BASINS_MAX_PERIOD && !L->decided; p++)
                        if (repeats(L, p, tol[i])) {
                            int q = least_period(L, p, tol[i]);
                            settle(L, q, t, near_shorter(L, q, tol[i]));
                            break;
                        }
            }
            open |= !L->decided;
        }
        if (!open)
            break;
    }
    for (int i = 0; i < m; i++) {
        struct lane *L = &lanes[i];
        if (b->dead[i]) {
            L->decided = -1;
            if (!skip[idx[i]])
                (*blown_up)++;
        } else if (!L->decided && L->held) { /* never told apart: the held cycle */
            L->decided = 1, L->period = L->held_period, L->winding = L->held_winding;
            L->settled = L->held_settled;
            memcpy(L->rep, L->held_rep, sizeof(L->rep));
        } else if (!L->decided) { /* undecided: its last sample */
            memcpy(L->rep, L->ring[(L->k + RING - 1) % RING], sizeof(L->rep));
            L->settled = t_max;
        }
    }
    sp_batch_destroy(&b);
    return ret;
}

int sp_basins_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                      const long *pts, const int *skip, int n, int forced, FILE *rows,
                      long *blown_up)
{
    struct lane *lanes = calloc((size_t)n, sizeof(*lanes));
    int idx[MAXL], done[MAXL] = {0}, ret = 0;
    if (!lanes || n > MAXL) {
        free(lanes);
        sp_log_error("out of memory for a basin map");
        return SP_E_NOMEM;
    }
    /* one batch per drive frequency: the sample times are the drive's */
    for (int i = 0; i < n && !ret; i++) {
        if (done[i])
            continue;
        int m = 0;
        for (int k = i; k < n; k++)
            if (!done[k] && scenes[k].pivot.frequency == scenes[i].pivot.frequency)
                idx[m++] = k, done[k] = 1;
        struct lane group[MAXL];
        memset(group, 0, sizeof(struct lane) * (size_t)m);
        ret = run_group(d, scenes, idx, m, forced, group, blown_up, skip);
        for (int k = 0; k < m; k++)
            lanes[idx[k]] = group[k];
    }
    for (int i = 0; i < n && !ret; i++) {
        if (skip[i])
            continue;
        const struct lane *L = &lanes[i];
        char head[160];
        sp_sweep_format_point(head, sizeof(head), d, pts[i]);
        if (L->decided < 0)
            fprintf(rows, "%snan,nan,nan,nan,nan,nan,nan\n", head);
        else
            fprintf(rows, "%s%d,%d,%.6f,%.7g,%.6g,%.6g,%.6g\n", head, L->period, L->winding,
                    L->rep[0] * RAD2DEG, L->rep[1] + 0.0, L->rep[2] + 0.0, L->rep[3] + 0.0,
                    L->settled); /* + 0.0: never "-0" (sweep.c) */
    }
    free(lanes);
    return ret;
}

/* ---- the attractors, from the rows --------------------------------------- */

static int same(const struct sp_attractor *a, int period, int winding, const double s[4])
{
    /* the same turns per drive period: a p-cycle of winding w is the
     * cycle of period p / n and winding w / n traced n times */
    if ((a->period == 0) != (period == 0) ||
        (long)a->winding * period != (long)winding * a->period)
        return 0;
    if (period == 0)
        return 1; /* one "undecided" */
    double dth = fmod(fabs(a->theta - s[0]), 360);
    return fmin(dth, 360 - dth) < 2 && fabs(a->r - s[1]) < 0.01 * fabs(a->r) &&
           fabs(a->theta_dot - s[2]) < 0.1 && fabs(a->r_dot - s[3]) < 0.02 * fabs(a->r) + 1e-3;
}

static void label(struct sp_attractor *a)
{
    if (a->period == 0)
        snprintf(a->label, sizeof(a->label), "undecided (not periodic by the end)");
    else if (a->period < 0)
        snprintf(a->label, sizeof(a->label), "other attractors");
    else if (a->winding)
        snprintf(a->label, sizeof(a->label), "rotating, period %d, %+d turn%s, θ %.1f°, θ̇ %.2f rad/s",
                 a->period, a->winding, abs(a->winding) == 1 ? "" : "s", a->theta, a->theta_dot);
    else
        snprintf(a->label, sizeof(a->label), "period %d, θ %.1f°, θ̇ %.2f rad/s", a->period,
                 a->theta, a->theta_dot);
}

static int by_count(const void *x, const void *y)
{
    const struct sp_attractor *a = x, *b = y;
    /* undecided and other last; else the larger basin first */
    int ka = a->period <= 0, kb = b->period <= 0;
    if (ka != kb)
        return ka - kb;
    return (a->count < b->count) - (a->count > b->count);
}

int sp_basins_read(FILE *fp, const struct sp_sweep_desc *d, struct sp_basin_map *map)
{
    char line[512];
    memset(map, 0, sizeof(*map));
    map->nx = d->axis[0].count, map->ny = d->axis[1].count;
    map->box = BOX;
    long n = (long)map->nx * map->ny;
    map->label = malloc(sizeof(int) * (size_t)n);
    if (!map->label) {
        sp_log_error("out of memory for a basin map of %ld points", n);
        return SP_E_NOMEM;
    }
    for (long p = 0; p < n; p++)
        map->label[p] = -1;
    while (fgets(line, sizeof(line), fp)) {
        char *p = line, *end;
        long point = strtol(p, &end, 10);
        double v[9];
        int k = 0;
        for (p = end; k < 9 && *p == ','; k++, p = end)
            v[k] = strtod(p + 1, &end);
        if (k < 9 || point < 0 || point >= n)
            continue;
        if (!isfinite(v[2])) {
            map->blown_up++;
            continue;
        }
        int period = (int)v[2], winding = (int)v[3], a;
        for (a = 0; a < map->n_attractors; a++)
            if (same(&map->att[a], period, winding, v + 4))
                break;
        if (a == map->n_attractors) {
            if (a == SP_BASINS_MAX_ATTRACTORS - 1) { /* the last slot pools the rest */
                for (a = 0; a < map->n_attractors && map->att[a].period >= 0; a++)
                    ;
                if (a == map->n_attractors)
                    map->att[map->n_attractors++] = (struct sp_attractor){.period = -1};
            } else {
                map->att[map->n_attractors++] = (struct sp_attractor){
                    .period = period, .winding = winding, .theta = v[4], .r = v[5],
                    .theta_dot = v[6], .r_dot = v[7]};
            }
        }
        if (period > 0 && period < map->att[a].period) { /* the cleaner cycle names it */
            struct sp_attractor *t = &map->att[a];
            t->period = period, t->winding = winding, t->theta = v[4], t->r = v[5];
            t->theta_dot = v[6];
            t->r_dot = v[7];
        }
        map->att[a].count++;
        map->label[point] = a;
    }
    /* order: the larger basins first, undecided and other last */
    int order[SP_BASINS_MAX_ATTRACTORS], inv[SP_BASINS_MAX_ATTRACTORS];
    struct sp_attractor sorted[SP_BASINS_MAX_ATTRACTORS];
    for (int a = 0; a < map->n_attractors; a++)
        sorted[a] = map->att[a], sorted[a].label[0] = (char)a; /* remember the old index */
    qsort(sorted, (size_t)map->n_attractors, sizeof(sorted[0]), by_count);
    for (int a = 0; a < map->n_attractors; a++) {
        order[a] = (unsigned char)sorted[a].label[0];
        inv[order[a]] = a;
        map->att[a] = sorted[a];
        label(&map->att[a]);
    }
    for (long p = 0; p < n; p++)
        if (map->label[p] >= 0)
            map->label[p] = inv[map->label[p]];
    /* the entropies over boxes of BOX x BOX points (Daza et al.; as
     * Attractors.jl's basin_entropy): whole boxes from the grid's first
     * point, the last nx % BOX columns and ny % BOX rows left out; a grid
     * under BOX on a side has no box, and no entropies (NaN) */
    int bx = map->nx / BOX, by = map->ny / BOX, boundary = 0, boxes = 0;
    double total = 0;
    for (int j = 0; j < by; j++)
        for (int i = 0; i < bx; i++) {
            long cnt[SP_BASINS_MAX_ATTRACTORS] = {0}, all = 0;
            for (int y = j * BOX; y < (j + 1) * BOX; y++)
                for (int x = i * BOX; x < (i + 1) * BOX; x++) {
                    int a = map->label[(long)y * map->nx + x];
                    if (a >= 0)
                        cnt[a]++, all++;
                }
            if (!all)
                continue;
            double s = 0;
            int kinds = 0;
            for (int a = 0; a < map->n_attractors; a++)
                if (cnt[a])
                    s -= (double)cnt[a] / all * log((double)cnt[a] / all), kinds++;
            total += s;
            boxes++;
            if (kinds > 1)
                boundary++;
        }
    map->boxes_x = bx, map->boxes_y = by;
    map->entropy = boxes ? total / boxes : NAN;
    map->boundary_entropy = !boxes ? NAN : boundary ? total / boundary : 0;
    return 0;
}

void sp_basins_box_text(const struct sp_basin_map *map, char *buf, size_t size)
{
    if (map->boxes_x == 0 || map->boxes_y == 0) {
        snprintf(buf, size, "none: the %dx%d grid has no box of %dx%d points (--vary COUNT "
                 "%d or more on each key)", map->nx, map->ny, map->box, map->box, map->box);
        return;
    }
    const int lx = map->nx - map->box * map->boxes_x, ly = map->ny - map->box * map->boxes_y;
    char cols[64] = "", rows[64] = "";
    if (lx) /* the first key's values are the map's columns */
        snprintf(cols, sizeof(cols), "the last %d of %d columns", lx, map->nx);
    if (ly)
        snprintf(rows, sizeof(rows), "the last %d of %d rows", ly, map->ny);
    snprintf(buf, size, "boxes of %dx%d points%s%s%s%s%s", map->box, map->box,
             lx || ly ? "; " : "", cols, lx && ly ? " and " : "", rows, lx || ly ? " left out" : "");
}

void sp_basins_free(struct sp_basin_map *map)
{
    free(map->label);
    map->label = NULL;
}
