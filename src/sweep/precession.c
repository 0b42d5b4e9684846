/* springpend: the swinging spring's precession per exchange over a sweep's
 * points (see analysis.h).
 *
 * Each point is sampled every d->sample seconds (a 32nd of the shortest
 * pendulum period on the grid, sp_sweep_check) over the measured span. At
 * each sample:
 *   - the swing plane's azimuth, sim.h's sp_state_azimuth (the major axis of
 *     M = h h^T + h' h'^T / omega_p^2, h = (x, z)), made continuous from
 *     sample to sample as data's azimuth column is from row to row;
 *   - the swing's size S = trace M = x^2 + z^2 + (vx^2 + vz^2) / omega_p^2
 *     (the horizontal ellipse's a^2 + b^2: slow, like the azimuth).
 * Both are averaged over the point's own pendulum period (a trailing window
 * of round(T_p / sample) samples) and kept every STRIDE samples. The swing's
 * maxima are those of the averaged S that rise above the least value
 * before them (since the previous maximum, or the start) and fall below
 * the least value after them by a third of S's range over the span each
 * (Billauer's peak detection with delta = (max - min) / 3): the exchanges.
 * The precession per exchange is the mean turn of the averaged azimuth
 * between successive maxima, (phi_last - phi_first) / (maxima - 1), in
 * degrees from +x towards +z; the exchange period the mean time between
 * them. Fewer than two maxima in the span: nan, 0 exchanges. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/sim.h"

#define STRIDE 4 /* samples between kept averages: a period holds 8 */
#define RAD2DEG 57.29577951308232

/* One point's running record. */
struct lane {
    struct sp_params p;
    double w2;       /* omega_p^2, 1/s^2 */
    int win;         /* samples per pendulum period */
    double phi;      /* the continuous azimuth of the last sample, rad */
    double *ring_s, *ring_phi; /* the last win samples */
    long seen;       /* samples so far */
    double *s, *a, *t; /* kept averages: S (m^2), azimuth (rad), window centre (s) */
    long kept;
};

/* The maxima of s[0..n) by Billauer's rule with the given delta; writes
 * their indices to idx (at most n) and returns how many. */
static long maxima(const double *s, long n, double delta, long *idx)
{
    long count = 0, at = 0;
    double lo = INFINITY, hi = -INFINITY;
    int rising = 0; /* 0: after a maximum (or at the start), waiting to rise by delta */
    for (long j = 0; j < n; j++) {
        if (!rising) {
            lo = fmin(lo, s[j]);
            if (s[j] > lo + delta)
                rising = 1, hi = s[j], at = j;
        } else if (s[j] > hi) {
            hi = s[j], at = j;
        } else if (s[j] < hi - delta) {
            idx[count++] = at;
            rising = 0, lo = s[j];
        }
    }
    return count;
}

/* The point's row from its kept averages. */
static void point_row(const struct lane *L, char *buf, size_t size)
{
    double lo = INFINITY, hi = -INFINITY;
    for (long j = 0; j < L->kept; j++)
        lo = fmin(lo, L->s[j]), hi = fmax(hi, L->s[j]);
    long *idx = L->kept ? malloc(sizeof(long) * (size_t)L->kept) : NULL;
    long m = idx && hi > lo ? maxima(L->s, L->kept, (hi - lo) / 3, idx) : 0;
    if (m >= 2) {
        const double turn = (L->a[idx[m - 1]] - L->a[idx[0]]) / (double)(m - 1);
        const double period = (L->t[idx[m - 1]] - L->t[idx[0]]) / (double)(m - 1);
        snprintf(buf, size, "%.9g,%ld,%.9g\n", turn * RAD2DEG + 0.0, m - 1, period);
    } else {
        snprintf(buf, size, "nan,0,nan\n");
    }
    free(idx);
}

int sp_precession_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                          const long *pts, const int *skip, int n, int forced, FILE *rows,
                          long *blown_up)
{
    const struct sp_scene *ptr[64] = {0};
    struct lane L[64];
    struct sp_batch *b = NULL;
    int ret = 0;
    if (n > 64)
        return SP_E_NOMEM; /* sweep.c's chunks hold 32 */
    memset(L, 0, sizeof(L));
    const double dt = d->sample;
    const long k0 = (long)ceil(d->transient / dt - 1e-9);
    const long k1 = (long)floor((d->transient + d->time) / dt + 1e-9);
    const long keep = (k1 - k0) / STRIDE + 2;
    for (int i = 0; i < n; i++) {
        struct sp_sim sim;
        struct sp_physics ph;
        ptr[i] = &scenes[i];
        sp_sim_init(&sim, &scenes[i]);
        L[i].p = sim.p;
        sp_params_physics(&sim.p, &ph);
        L[i].w2 = ph.omega_p * ph.omega_p;
        L[i].win = (int)fmax(1, lround(2 * M_PI / ph.omega_p / dt));
        L[i].ring_s = malloc(sizeof(double) * (size_t)L[i].win * 2);
        L[i].ring_phi = L[i].ring_s ? L[i].ring_s + L[i].win : NULL;
        L[i].s = malloc(sizeof(double) * (size_t)keep * 3);
        L[i].a = L[i].s ? L[i].s + keep : NULL;
        L[i].t = L[i].s ? L[i].s + 2 * keep : NULL;
        if (!L[i].ring_s || !L[i].s) {
            sp_log_error("out of memory for a precession sweep's samples (%ld a point)", keep);
            ret = SP_E_NOMEM;
            goto done;
        }
    }
    if ((ret = sp_batch_make(&b, ptr, n, 0, forced)))
        goto done;
    b->cancel = d->cancel; /* a long transient is one call */
    for (long k = k0; k <= k1; k++) {
        const double t = (double)k * dt;
        if (t > b->t && sp_batch_advance(b, t)) {
            ret = SP_E_INTERRUPTED;
            goto done;
        }
        for (int i = 0; i < n; i++) {
            struct lane *l = &L[i];
            if (b->dead[i])
                continue;
            const struct sp_state s = {
                .t = t, .x = b->out[SP_BX][i], .y = b->out[SP_BY][i], .vx = b->out[SP_BVX][i],
                .vy = b->out[SP_BVY][i], .z = b->out[SP_BZ][i], .vz = b->out[SP_BVZ][i]};
            l->phi = sp_azimuth_unwrap(l->phi, sp_state_azimuth(&l->p, &s));
            l->ring_s[l->seen % l->win] = s.x * s.x + s.z * s.z + (s.vx * s.vx + s.vz * s.vz) / l->w2;
            l->ring_phi[l->seen % l->win] = l->phi;
            l->seen++;
            if (l->seen < l->win || (k - k0) % STRIDE || l->kept >= keep)
                continue;
            double ss = 0, sa = 0;
            for (int j = 0; j < l->win; j++)
                ss += l->ring_s[j], sa += l->ring_phi[j];
            l->s[l->kept] = ss / l->win;
            l->a[l->kept] = sa / l->win;
            l->t[l->kept] = t - 0.5 * (l->win - 1) * dt;
            l->kept++;
        }
    }
    for (int i = 0; i < n; i++) {
        char head[160], row[96];
        if (skip[i])
            continue;
        if (b->dead[i]) {
            snprintf(row, sizeof(row), "nan,nan,nan\n");
            ++*blown_up;
        } else {
            point_row(&L[i], row, sizeof(row));
        }
        fprintf(rows, "%s%s", sp_sweep_format_point(head, sizeof(head), d, pts[i]), row);
    }
done:
    sp_batch_destroy(&b);
    for (int i = 0; i < n; i++)
        free(L[i].ring_s), free(L[i].s);
    return ret;
}
