/* springpend: the Lyapunov spectrum of sweep points (see analysis.h).
 *
 * Benettin, Galgani, Giorgilli and Strelcyn, Meccanica 15 (1980) 9-30: four
 * tangent vectors ride along with the trajectory; every tau they are
 * re-orthonormalised (QR by modified Gram-Schmidt), and lambda_j is the
 * running mean of ln R_jj / tau. The first column is only ever normalised,
 * so lambda_1 is, to the last bit, what --measure lyapunov reports.
 *
 * The batch (batch.h) integrates one tangent vector per trajectory; a point
 * is four lanes of one batch, copies of one scene with tangent vectors e_1 ..
 * e_4. The copies do the same arithmetic on the same state, so their states
 * stay bitwise equal and each lane's tangent is exactly the linearised flow
 * applied to its own vector. The cost per point is four trajectories with a
 * tangent, the state counted four times: measured 4.0x the largest exponent
 * alone (doc/sweeps.md, "The Lyapunov spectrum"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis.h"
#include "springpend/batch.h"
#include "springpend/common.h"

#define COPIES 4
#define MAX_CHECKS SP_SPECTRUM_MAX_CHECKS

void sp_spectrum_mgs(double v[4][4], double r[4])
{
    for (int j = 0; j < 4; j++) {
        for (int k = 0; k < j; k++) { /* modified: against the updated column */
            double dot = 0;
            for (int c = 0; c < 4; c++)
                dot += v[k][c] * v[j][c];
            for (int c = 0; c < 4; c++)
                v[j][c] -= dot * v[k][c];
        }
        /* the norm as sp_batch_renormalise takes it, so that lambda_1 is
         * the largest exponent's measure to the bit */
        double nrm = sqrt(v[j][0] * v[j][0] + v[j][1] * v[j][1] + v[j][2] * v[j][2] +
                          v[j][3] * v[j][3]);
        r[j] = nrm;
        if (nrm > 0)
            for (int c = 0; c < 4; c++)
                v[j][c] /= nrm;
    }
}

static int by_value_desc(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x < y) - (x > y);
}

double sp_spectrum_kaplan_yorke(const double *lam, int n)
{
    double s[16], sum = 0;
    if (n < 1 || n > 16)
        return NAN;
    memcpy(s, lam, sizeof(double) * (size_t)n);
    for (int i = 0; i < n; i++)
        if (!isfinite(s[i]))
            return NAN;
    qsort(s, (size_t)n, sizeof(double), by_value_desc);
    if (s[0] < 0)
        return 0;
    for (int j = 0; j < n; j++) {
        if (sum + s[j] < 0)
            return j + sum / fabs(s[j]);
        sum += s[j];
    }
    return n;
}

/* Whether step k of K is a checkpoint: k = round(10^(i/10)) for some i, or
 * the last. *next: the smallest such value not yet passed (start at 1). */
static int checkpoint(long k, long K, long *next, int *i)
{
    while (*next < k)
        *next = lround(pow(10, ++*i / 10.0));
    return k == *next || k == K;
}

int sp_spectrum_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                        const long *pts, const int *skip, int n, int forced, FILE *rows,
                        long *blown_up)
{
    const struct sp_scene **ptr = malloc(sizeof(*ptr) * (size_t)(COPIES * n));
    double(*sum)[COPIES] = calloc((size_t)n, sizeof(*sum));
    double(*run)[MAX_CHECKS][COPIES + 1] = calloc((size_t)n, sizeof(*run));
    struct sp_batch *b = NULL;
    int ret = ptr && sum && run ? 0 : SP_E_NOMEM;
    if (!ret) {
        for (int i = 0; i < COPIES * n; i++)
            ptr[i] = &scenes[i / COPIES];
        ret = sp_batch_make(&b, ptr, COPIES * n, 1, forced);
    }
    if (ret) {
        if (ret == SP_E_NOMEM)
            sp_log_error("out of memory for a spectrum of %d points", n);
        free(ptr), free(sum), free(run);
        return ret;
    }
    /* tau as --measure lyapunov: about a second, on the grid for fixed steps */
    struct sp_lyap_grid g;
    sp_sweep_lyap_grid(d->time, b->method, b->dt, &g);
    const int fixed = g.fixed;
    const long m = g.m, K = g.K;
    const double tau = g.tau;
    long k0 = (long)ceil(d->transient / tau - 1e-9);
#define TAU_TIME(k) (fixed ? (double)((k) * m) * b->dt : (double)(k) * tau)
    b->cancel = d->cancel; /* a long transient is one call */
    if (k0 > 0 && sp_batch_advance(b, TAU_TIME(k0)))
        ret = SP_E_INTERRUPTED;
    for (int i = 0; i < COPIES * n; i++) {
        double e[4] = {0};
        e[i % COPIES] = 1;
        sp_batch_set_tangent(b, i, e);
    }
    long next = 1;
    int dec = 0, nc = 0;
    for (long k = 1; k <= K && !ret; k++) {
        if (sp_sweep_cancelled(d) || sp_batch_advance(b, TAU_TIME(k0 + k))) {
            ret = SP_E_INTERRUPTED;
            break;
        }
        for (int i = 0; i < n; i++) {
            double v[4][4], r[4];
            for (int j = 0; j < COPIES; j++)
                for (int c = 0; c < 4; c++)
                    v[j][c] = b->out[SP_BDX + c][COPIES * i + j];
            sp_spectrum_mgs(v, r);
            for (int j = 0; j < COPIES; j++) {
                sum[i][j] += log(r[j]);
                sp_batch_set_tangent(b, COPIES * i + j, v[j]);
            }
        }
        if (checkpoint(k, K, &next, &dec) && nc < MAX_CHECKS) {
            for (int i = 0; i < n; i++) {
                run[i][nc][0] = (double)k * tau;
                for (int j = 0; j < COPIES; j++)
                    run[i][nc][j + 1] = sum[i][j] / ((double)k * tau);
            }
            nc++;
        }
    }
#undef TAU_TIME
    for (int i = 0; i < n && !ret; i++) {
        if (skip[i])
            continue;
        int dead = 0;
        for (int j = 0; j < COPIES; j++)
            dead |= b->dead[COPIES * i + j];
        for (int c = 0; c < nc && !dead; c++)
            for (int j = 1; j <= COPIES; j++)
                dead |= !isfinite(run[i][c][j]);
        char head[160];
        sp_sweep_format_point(head, sizeof(head), d, pts[i]);
        if (dead) { /* one row says so */
            (*blown_up)++;
            fprintf(rows, "%s%.10g,nan,nan,nan,nan,nan,nan\n", head, d->time);
            continue;
        }
        for (int c = 0; c < nc; c++) {
            const double *l = &run[i][c][1];
            fprintf(rows, "%s%.10g,%.9g,%.9g,%.9g,%.9g,%.9g,%.6f\n", head, run[i][c][0], l[0] + 0.0,
                    l[1] + 0.0, l[2] + 0.0, l[3] + 0.0, l[0] + l[1] + l[2] + l[3] + 0.0,
                    sp_spectrum_kaplan_yorke(l, 4)); /* + 0.0: never "-0" (sweep.c) */
        }
    }
    sp_batch_destroy(&b);
    free(ptr), free(sum), free(run);
    return ret;
}
