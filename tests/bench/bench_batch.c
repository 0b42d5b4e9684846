/* Benchmark of the batched integrator (meson test --benchmark sweep runs it
 * from bench_sweep.py): trajectory-steps per second of RK4 on chaotic.ini's
 * physics (m 1, k 39.24, L0 0.75, r0 1.2; angles 1..179 degrees), for the
 * state alone and with the tangent equations (renormalised every second,
 * as a Lyapunov sweep does), on one thread and on one per core; and the
 * same work through GSL odeiv2 (rk4 at the same fixed dt through
 * gsl_odeiv2_driver_apply_fixed_step, one trajectory at a time), with the
 * Lyapunov exponents each gets at three angles; where the CPU runs it,
 * the tangent runs again through the fast kernel (springpend_fast_*). springpend_*_1_cpu: per
 * second of the one thread's own CPU time (steadier on a shared machine).
 * With AZIMUTH_RATE (rad/s, not 0) every start also turns about the
 * vertical at that rate: 3-D trajectories (z, vz and a 6-D tangent), printed
 * as springpend3d_* (the batched and the GSL planar runs are skipped).
 * usage: bench_batch N T DT [AZIMUTH_RATE]   (prints key = value lines) */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/scene.h"
#ifdef HAVE_GSL
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#endif

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double angle_deg(int i, int n)
{
    return n > 1 ? 1 + 178.0 * i / (n - 1) : 90;
}

static double azimuth_rate; /* rad/s: bench_batch's fourth argument, 0 = planar */

static void scene_at(struct sp_scene *s, double deg, double dt)
{
    sp_scene_defaults(s);
    s->initial.azimuth_rate = azimuth_rate;
    s->pendulum.mass = 1, s->pendulum.stiffness = 39.24, s->pendulum.natural_length = 0.75;
    s->initial.length = 1.2, s->initial.angle = deg * M_PI / 180;
    s->integrator.method = SP_METHOD_RK4, s->integrator.dt = dt;
}

/* The grid's trajectories [first, first + n) of total, integrated over T in
 * chunks of 32 (as a sweep does). */
struct work {
    int first, n, total, tangent, fast;
    double T, dt;
    double *lambda;
};

static void *work_run(void *arg)
{
    struct work *w = arg;
    enum { CH = 32 };
    struct sp_scene sc[CH];
    const struct sp_scene *ptr[CH];
    double growth[CH];
    long m = lround(1.0 / w->dt), K = lround(w->T);
    for (int c0 = w->first; c0 < w->first + w->n; c0 += CH) {
        int n = w->first + w->n - c0 < CH ? w->first + w->n - c0 : CH;
        for (int i = 0; i < n; i++) {
            scene_at(&sc[i], angle_deg(c0 + i, w->total), w->dt);
            ptr[i] = &sc[i];
        }
        struct sp_batch *b;
        if (sp_batch_make(&b, ptr, n, w->tangent, 0))
            return NULL;
        b->fast = w->fast;
        double sum[CH] = {0};
        for (long k = 1; k <= K; k++) {
            sp_batch_advance(b, (double)(k * m) * w->dt);
            if (w->tangent) {
                sp_batch_renormalise(b, growth);
                for (int i = 0; i < n; i++)
                    sum[i] += growth[i];
            }
        }
        if (w->lambda)
            for (int i = 0; i < n; i++)
                w->lambda[c0 + i] = sum[i] / ((double)(K * m) * w->dt);
        sp_batch_destroy(&b);
    }
    return NULL;
}

static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double thread_cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Seconds for the whole grid on `threads` threads (equal contiguous parts);
 * *cpu: the process's CPU seconds meanwhile (all threads). One thread runs
 * in the caller's, and *cpu is then that thread's own CPU time (what other
 * processes on a shared machine take is not counted). */
static int use_fast; /* the tangent runs through the fast kernel (sp_batch.fast) */

static double batch_time(int total, double T, double dt, int tangent, int threads, double *lambda,
                         double *cpu)
{
    pthread_t tid[64];
    struct work w[64];
    double t0 = now(), c0 = cpu_now();
    if (threads == 1) {
        w[0] = (struct work){0, total, total, tangent, use_fast && tangent, T, dt, lambda};
        c0 = thread_cpu_now();
        work_run(&w[0]);
        *cpu = thread_cpu_now() - c0;
        return now() - t0;
    }
    for (int i = 0; i < threads; i++) {
        w[i] = (struct work){total * i / threads, total * (i + 1) / threads - total * i / threads,
                             total, tangent, use_fast && tangent, T, dt, lambda};
        pthread_create(&tid[i], NULL, work_run, &w[i]);
    }
    for (int i = 0; i < threads; i++)
        pthread_join(tid[i], NULL);
    *cpu = cpu_now() - c0;
    return now() - t0;
}

#ifdef HAVE_GSL
static int gsl_rhs(double t, const double *s, double *d, void *params)
{
    const double km = 39.24, L0 = 0.75, g = 9.81;
    const int tangent = *(const int *)params;
    (void)t;
    double x = s[0], y = s[1], rho = sqrt(x * x + y * y), c = km * (1 - L0 / rho);
    d[0] = s[2], d[1] = s[3], d[2] = -c * x, d[3] = -c * y - g;
    if (tangent) {
        double a = km * L0 / (rho * rho * rho);
        double jxx = -c - a * x * x, jxy = -a * x * y, jyy = -c - a * y * y;
        d[4] = s[6], d[5] = s[7];
        d[6] = jxx * s[4] + jxy * s[5], d[7] = jxy * s[4] + jyy * s[5];
    }
    return GSL_SUCCESS;
}

/* One trajectory through GSL's rk4 driver at fixed dt; returns lambda. */
static double gsl_one(double deg, double T, double dt, int tangent)
{
    gsl_odeiv2_system sys = {gsl_rhs, NULL, tangent ? 8 : 4, &tangent};
    gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, gsl_odeiv2_step_rk4, dt, 1e-6, 0);
    double th = deg * M_PI / 180, s[8] = {1.2 * sin(th), -1.2 * cos(th), 0, 0, 1, 0, 0, 0};
    double t = 0, sum = 0;
    long m = lround(1.0 / dt), K = lround(T);
    for (long k = 1; k <= K; k++) {
        gsl_odeiv2_driver_apply_fixed_step(d, &t, dt, (unsigned long)m, s);
        if (tangent) {
            double n = sqrt(s[4] * s[4] + s[5] * s[5] + s[6] * s[6] + s[7] * s[7]);
            sum += log(n);
            for (int i = 4; i < 8; i++)
                s[i] /= n;
        }
    }
    gsl_odeiv2_driver_free(d);
    return sum / ((double)(K * m) * dt);
}
#endif

int main(int argc, char **argv)
{
    if (argc != 4 && argc != 5) {
        fprintf(stderr, "usage: bench_batch N T DT [AZIMUTH_RATE]\n");
        return 2;
    }
    azimuth_rate = argc == 5 ? atof(argv[4]) : 0;
    const char *name = azimuth_rate != 0 ? "springpend3d" : "springpend";
    int n = atoi(argv[1]);
    double T = atof(argv[2]), dt = atof(argv[3]);
    int cores = (int)sysconf(_SC_NPROCESSORS_ONLN);
    if (cores > 64)
        cores = 64;
    double steps = (double)n * lround(T) * lround(1.0 / dt);
    double *lam = calloc((size_t)n, sizeof(double));
    for (int tangent = 0; tangent < 2; tangent++) {
        const char *what = tangent ? "tangent" : "state";
        double c1, cn;
        double t1 = batch_time(n, T, dt, tangent, 1, NULL, &c1);
        double tn = batch_time(n, T, dt, tangent, cores, tangent ? lam : NULL, &cn);
        printf("%s_%s_1 = %.4g\n", name, what, steps / t1);
        printf("%s_%s_1_cpu = %.4g\n", name, what, steps / c1);
        printf("%s_%s_%d = %.4g\n", name, what, cores, steps / tn);
        printf("%s_%s_cpu = %.4g\n", name, what, steps / cn);
    }
    int idx[3] = {0, n / 2, n - 1};
    for (int k = 0; k < 3; k++)
        printf("%s_lambda_%.1f = %.6f\n", name, angle_deg(idx[k], n), lam[idx[k]]);
    if (azimuth_rate != 0) { /* the fast kernel and GSL's runs are planar */
        free(lam);
        return 0;
    }
    if (sp_batch_fast_supported()) { /* the same through the fast kernel (sweep --fast) */
        double c1, cn, *lf = calloc((size_t)n, sizeof(double));
        use_fast = 1;
        double t1 = batch_time(n, T, dt, 1, 1, NULL, &c1);
        double tn = batch_time(n, T, dt, 1, cores, lf, &cn);
        use_fast = 0;
        printf("springpend_fast_1 = %.4g\nspringpend_fast_1_cpu = %.4g\n", steps / t1, steps / c1);
        printf("springpend_fast_%d = %.4g\nspringpend_fast_cpu = %.4g\n", cores, steps / tn, steps / cn);
        for (int k = 0; k < 3; k++)
            printf("springpend_fast_lambda_%.1f = %.6f\n", angle_deg(idx[k], n), lf[idx[k]]);
        free(lf);
    }
#ifdef HAVE_GSL
    /* a sample of the grid (GSL is slow): 16 trajectories, then the three */
    for (int tangent = 0; tangent < 2; tangent++) {
        int m = 16;
        double t0 = now(), c0 = cpu_now();
        for (int i = 0; i < m; i++)
            gsl_one(angle_deg(i * (n - 1) / (m - 1), n), T, dt, tangent);
        double gsteps = (double)m * lround(T) * lround(1.0 / dt);
        printf("gsl_%s_1 = %.4g\n", tangent ? "tangent" : "state", gsteps / (now() - t0));
        printf("gsl_%s_cpu = %.4g\n", tangent ? "tangent" : "state", gsteps / (cpu_now() - c0));
    }
    for (int k = 0; k < 3; k++)
        printf("gsl_lambda_%.1f = %.6f\n", angle_deg(idx[k], n), gsl_one(angle_deg(idx[k], n), T, dt, 1));
#endif
    printf("cores = %d\n", cores);
    free(lam);
    return 0;
}
