/* springpend benchmark: work-precision of the physics core, against GSL's
 * odeiv2 steppers when the build found libgsl (HAVE_GSL).
 *
 * usage: bench_physics OUTDIR [--quick]
 * Writes OUTDIR/bench_physics.csv and OUTDIR/bench_physics.png and prints
 * the tables. For each scene and each method over a sweep of dt (fixed-step)
 * or tolerance (adaptive), it measures the error against a reference, the
 * worst over every sampled time (the end, or each of a video's frames, where
 * interpolated frames can be worse than the step ends), the median wall time
 * of repeated runs, and the right-hand-side evaluations. The reference is
 * classical RK4 in long double (a separate implementation of the equations of
 * motion, 64-bit mantissa) at h <= 5e-5 s, checked against twice that step:
 * the difference, divided by 15 for a 4th-order method, estimates the
 * reference's own error and is printed. Besides best against best, it
 * compares method for method: dop853 against GSL's rk8pd at equal error, and
 * rk4 against GSL's rk4 at equal work (GSL's rk4 estimates its error by step
 * doubling, 12 evaluations a step, so its dt is 3 times springpend's).
 * Then: relative energy error over 1e5 s per method at its working step, and
 * the cost per step and per evaluation. Timings are figures to report, not
 * assertions; the benchmark fails only if it cannot run. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <fcntl.h>
#include <unistd.h>

#include "plot.h"
#include "springpend/png_io.h"
#include "springpend/sim.h"

#ifdef HAVE_GSL
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#endif

struct bench_scene {
    const char *name;
    struct sp_scene sc;
    double T;        /* horizon, s */
    int frames;      /* > 0: sample at this many frames over T (dense output
                        for springpend, stopping at each frame for GSL) */
    long double (*ref)[2]; /* the reference position at each sample, m */
    double ref_err;  /* estimated error of the reference, m */
};

struct row {
    const char *scene, *method, *family; /* family: springpend or gsl */
    double param;  /* dt (s) or tolerance */
    double error;  /* max over the samples of |position - reference|, m;
                    * INFINITY: unstable */
    double time;   /* s, the fastest of 7 batches */
    long evals;
};

static struct row rows[4096];
static int n_rows;
static int quick;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- the reference: long double RK4 ------------------------------------- */

static void ref_rhs(const struct sp_params *p, const long double *u, long double *d)
{
    long double rho = sqrtl(u[0] * u[0] + u[1] * u[1]);
    long double c = (long double)p->k_over_m * (1 - (long double)p->L0 / rho);
    d[0] = u[2], d[1] = u[3];
    d[2] = -c * u[0];
    d[3] = -c * u[1] - (long double)p->g;
}

static void ref_steps(const struct sp_sim *init, long double *u, long double h, long n);

/* The samples: frames at T k / frames, k = 1 .. frames, or the end alone. */
static int n_samples(const struct bench_scene *b)
{
    return b->frames > 0 ? b->frames : 1;
}

/* RK4 from the start to each sample in turn, n steps per sample interval;
 * positions into q. */
static void ref_run(const struct sp_sim *init, const struct bench_scene *b, long n,
                    long double (*q)[2])
{
    long double u[4];
    for (int c = 0; c < 4; c++)
        u[c] = (&init->s.x)[c];
    for (int k = 0; k < n_samples(b); k++) {
        ref_steps(init, u, (long double)b->T / n_samples(b) / n, n);
        q[k][0] = u[0], q[k][1] = u[1];
    }
}

static void ref_steps(const struct sp_sim *init, long double *u, long double h, long n)
{
    long double k[4][4], v[4];
    for (long i = 0; i < n; i++) {
        ref_rhs(&init->p, u, k[0]);
        for (int c = 0; c < 4; c++) v[c] = u[c] + h / 2 * k[0][c];
        ref_rhs(&init->p, v, k[1]);
        for (int c = 0; c < 4; c++) v[c] = u[c] + h / 2 * k[1][c];
        ref_rhs(&init->p, v, k[2]);
        for (int c = 0; c < 4; c++) v[c] = u[c] + h * k[2][c];
        ref_rhs(&init->p, v, k[3]);
        for (int c = 0; c < 4; c++)
            u[c] += h / 6 * (k[0][c] + 2 * k[1][c] + 2 * k[2][c] + k[3][c]);
    }
}

static void make_reference(struct bench_scene *b)
{
    struct sp_sim sim;
    const int ns = n_samples(b);
    long double (*coarse)[2] = malloc(ns * sizeof(*coarse));
    long n = 2 * (long)ceil(b->T / ns / 1e-4); /* even, h <= 5e-5 s */
    b->ref = malloc(ns * sizeof(*b->ref));
    if (!coarse || !b->ref)
        abort();
    sp_sim_init(&sim, &b->sc);
    ref_run(&sim, b, n, b->ref);
    ref_run(&sim, b, n / 2, coarse);
    b->ref_err = 0;
    for (int k = 0; k < ns; k++)
        b->ref_err = fmax(b->ref_err, (double)hypotl(b->ref[k][0] - coarse[k][0],
                                                     b->ref[k][1] - coarse[k][1]) / 15);
    free(coarse);
}

/* ---- timed runs ---------------------------------------------------------- */

struct run_ctx {
    const struct bench_scene *b;
    struct sp_scene sc;
#ifdef HAVE_GSL
    const gsl_odeiv2_step_type *gsl_type;
    double param;
    int adaptive;
    /* allocated once per sweep point, outside the timing, and reset per
     * run: GSL's allocation is not charged to it */
    gsl_odeiv2_system sys;
    gsl_odeiv2_driver *driver;
    gsl_odeiv2_step *step;
    struct sp_params params;
#endif
    double (*q)[2]; /* the position at each sample, m */
    long evals;
    int failed;
};

static void run_sp(struct run_ctx *c)
{
    struct sp_sim sim;
    int ret = 0;
    const int ns = n_samples(c->b);
    sp_sim_init(&sim, &c->sc);
    for (int k = 1; k <= ns && !ret; k++) {
        ret = sp_sim_advance(&sim, c->b->T * k / ns);
        c->q[k - 1][0] = sim.s.x, c->q[k - 1][1] = sim.s.y;
    }
    c->evals = sim.evals;
    c->failed = ret != 0;
}

#ifdef HAVE_GSL
static long gsl_evals;

static int gsl_rhs(double t, const double *u, double *d, void *params)
{
    const struct sp_params *p = params;
    double rho = sqrt(u[0] * u[0] + u[1] * u[1]);
    double c = p->k_over_m * (1 - p->L0 / rho);
    (void)t;
    d[0] = u[2], d[1] = u[3];
    d[2] = -c * u[0];
    d[3] = -c * u[1] - p->g;
    gsl_evals++;
    return GSL_SUCCESS;
}

/* GSL the way its manual shows: the driver with its standard error control
 * for rkf45 and rk8pd (eps_abs = eps_rel = tol), and step_apply with a fixed
 * h, shortened to land on each target, for rk4. */
static void run_gsl(struct run_ctx *c)
{
    struct sp_sim sim;
    sp_sim_init(&sim, &c->sc);
    c->params = sim.p;
    double u[4] = {sim.s.x, sim.s.y, sim.s.vx, sim.s.vy}, t = 0;
    int n = n_samples(c->b), ret = 0;
    gsl_evals = 0;
    if (c->adaptive) {
        gsl_odeiv2_driver_reset_hstart(c->driver, 1e-3);
        for (int k = 1; k <= n && !ret; k++) {
            ret = gsl_odeiv2_driver_apply(c->driver, &t, c->b->T * k / n, u);
            c->q[k - 1][0] = u[0], c->q[k - 1][1] = u[1];
        }
    } else {
        double err[4];
        gsl_odeiv2_step_reset(c->step);
        for (int k = 1; k <= n && !ret; k++) {
            double target = c->b->T * k / n;
            while (t < target && !ret) {
                double h = fmin(c->param, target - t);
                ret = gsl_odeiv2_step_apply(c->step, t, h, u, err, NULL, NULL, &c->sys);
                t = target - t <= c->param ? target : t + h;
            }
            c->q[k - 1][0] = u[0], c->q[k - 1][1] = u[1];
        }
    }
    c->evals = gsl_evals;
    c->failed = ret != 0 || !isfinite(u[0] + u[1]);
}
#endif

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The fastest of 7 batches of the time of one run, s; a batch repeats the
 * run until it lasts >= 4 ms (1 ms in quick mode). The minimum, not the
 * median: on a shared machine other work only ever adds time. */
static double time_run(void (*fn)(struct run_ctx *), struct run_ctx *c)
{
    double t0 = now(), batch[7], min_batch = quick ? 1e-3 : 4e-3;
    fn(c);
    double once = now() - t0;
    long reps = once >= min_batch ? 1 : (long)(min_batch / fmax(once, 1e-8)) + 1;
    for (int i = 0; i < 7; i++) {
        t0 = now();
        for (long r = 0; r < reps; r++)
            fn(c);
        batch[i] = (now() - t0) / reps;
    }
    qsort(batch, 7, sizeof(batch[0]), cmp_double);
    return batch[0];
}

static void record(const struct bench_scene *b, const char *method, const char *family,
                   double param, void (*fn)(struct run_ctx *), struct run_ctx *c)
{
    struct row *r = &rows[n_rows++];
    fn(c);
    *r = (struct row){b->name, method, family, param, INFINITY, NAN, c->evals};
    if (c->failed)
        return;
    r->error = 0;
    for (int k = 0; k < n_samples(b); k++)
        r->error = fmax(r->error, hypot(c->q[k][0] - (double)b->ref[k][0],
                                        c->q[k][1] - (double)b->ref[k][1]));
    r->time = time_run(fn, c);
}

static const double dts[] = {0.05, 0.02, 0.01, 0.005, 0.002, 0.001, 5e-4, 2e-4, 1e-4};
static const double tols[] = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9,
                              1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15};
#define N_DTS ((int)(sizeof(dts) / sizeof(dts[0])))
#define N_TOLS ((int)(sizeof(tols) / sizeof(tols[0])))

static void sweep(struct bench_scene *b)
{
    struct run_ctx c = {.b = b, .q = malloc(n_samples(b) * sizeof(*c.q))};
    if (!c.q)
        abort();
    for (int m = 0; m <= SP_METHOD_RKN1210; m++) {
        const struct sp_method_info *mi = sp_method_info((enum sp_method)m);
        int n = mi->adaptive ? N_TOLS : N_DTS;
        for (int i = 0; i < n; i++) {
            c.sc = b->sc;
            c.sc.integrator.method = (enum sp_method)m;
            if (mi->adaptive)
                c.sc.integrator.tolerance = tols[i];
            else
                c.sc.integrator.dt = dts[i];
            record(b, mi->name, "springpend", mi->adaptive ? tols[i] : dts[i], run_sp, &c);
        }
    }
#ifdef HAVE_GSL
    const struct { const char *name; const gsl_odeiv2_step_type **t; int adaptive; } g[] = {
        {"gsl-rk4", &gsl_odeiv2_step_rk4, 0},
        {"gsl-rkf45", &gsl_odeiv2_step_rkf45, 1},
        {"gsl-rk8pd", &gsl_odeiv2_step_rk8pd, 1},
    };
    for (int m = 0; m < 3; m++) {
        int n = g[m].adaptive ? N_TOLS : N_DTS;
        for (int i = 0; i < n; i++) {
            c.sc = b->sc;
            c.gsl_type = *g[m].t;
            c.adaptive = g[m].adaptive;
            /* rk4: 3 times springpend's dt, for equal evaluations */
            c.param = g[m].adaptive ? tols[i] : 3 * dts[i];
            c.sys = (gsl_odeiv2_system){gsl_rhs, NULL, 4, &c.params};
            c.driver = c.adaptive ? gsl_odeiv2_driver_alloc_y_new(&c.sys, c.gsl_type, 1e-3,
                                                                   c.param, c.param)
                                  : NULL;
            c.step = c.adaptive ? NULL : gsl_odeiv2_step_alloc(c.gsl_type, 4);
            record(b, g[m].name, "gsl", c.param, run_gsl, &c);
            if (c.driver)
                gsl_odeiv2_driver_free(c.driver);
            if (c.step)
                gsl_odeiv2_step_free(c.step);
        }
    }
#endif
    free(c.q);
}

/* ---- summaries ----------------------------------------------------------- */

/* The fastest row of `family` (NULL: any) on scene with error <= level. */
static const struct row *fastest(const char *scene, const char *family, double level)
{
    const struct row *best = NULL;
    for (int i = 0; i < n_rows; i++) {
        const struct row *r = &rows[i];
        if (strcmp(r->scene, scene) || (family && strcmp(r->family, family)) ||
            !(r->error <= level))
            continue;
        if (!best || r->time < best->time)
            best = r;
    }
    return best;
}

/* The fastest row of method `method` on scene with error <= level. */
static const struct row *fastest_method(const char *scene, const char *method, double level)
{
    const struct row *best = NULL;
    for (int i = 0; i < n_rows; i++) {
        const struct row *r = &rows[i];
        if (!strcmp(r->scene, scene) && !strcmp(r->method, method) && r->error <= level &&
            (!best || r->time < best->time))
            best = r;
    }
    return best;
}

/* "GSL time / springpend time" of the two rows, or "-". */
static const char *ratio_of(const struct row *s, const struct row *g, char *buf, size_t size)
{
    if (s && g)
        snprintf(buf, size, "%.2fx", g->time / s->time);
    else
        snprintf(buf, size, "-");
    return buf;
}

static void print_goals(const struct bench_scene *b)
{
    printf("\n%s: fastest run at or below each error level (worst position error over the "
           "samples, m); ratios are GSL time / springpend time\n", b->name);
    printf("  %-8s  %-26s  %-26s  %-10s  %s\n", "error <=", "springpend best", "GSL best",
           "best/best", "dop853/rk8pd");
    for (int e = -4; e >= -12; e--) {
        double level = pow(10, e);
        const struct row *s = fastest(b->name, "springpend", level);
        const struct row *g = fastest(b->name, "gsl", level);
        char sb[64] = "-", gb[64] = "-", r1[32], r2[32];
        if (s)
            snprintf(sb, sizeof(sb), "%s %g: %.3g ms", s->method, s->param, 1e3 * s->time);
        if (g)
            snprintf(gb, sizeof(gb), "%s %g: %.3g ms", g->method, g->param, 1e3 * g->time);
        printf("  1e%-6d  %-26s  %-26s  %-10s  %s\n", e, sb, gb,
               ratio_of(s, g, r1, sizeof(r1)),
               ratio_of(fastest_method(b->name, "dop853", level),
                        fastest_method(b->name, "gsl-rk8pd", level), r2, sizeof(r2)));
    }
    /* rk4 against GSL's rk4 at equal work: springpend at dt, GSL at 3 dt (not
     * where frames cut the steps: the evaluations differ there) */
    if (!b->frames)
        printf("  rk4 at equal work (same evaluations; GSL's dt is 3x, its step doubles):\n");
    for (int i = 0; i < n_rows && !b->frames; i++) {
        const struct row *r = &rows[i], *g = NULL;
        if (strcmp(r->scene, b->name) || strcmp(r->method, "rk4"))
            continue;
        for (int j = 0; j < n_rows; j++)
            if (!strcmp(rows[j].scene, b->name) && !strcmp(rows[j].method, "gsl-rk4") &&
                fabs(rows[j].param / (3 * r->param) - 1) < 1e-9)
                g = &rows[j];
        if (!g || isinf(r->error) || isinf(g->error))
            continue;
        printf("    dt %-7g %ld evals: springpend %.3g ms, error %.2e; GSL %.3g ms, error "
               "%.2e: time %.2fx, error %.1fx\n", r->param, r->evals, 1e3 * r->time,
               r->error, 1e3 * g->time, g->error, g->time / r->time, g->error / r->error);
    }
    /* the seed: RK4 at dt = 1e-3 */
    for (int i = 0; i < n_rows; i++) {
        const struct row *r = &rows[i];
        if (strcmp(r->scene, b->name) || strcmp(r->method, "rk4") || r->param != 1e-3)
            continue;
        const struct row *s = fastest(b->name, "springpend", r->error);
        if (s)
            printf("  seed RK4 dt=1e-3: error %.2e in %.3g ms; %s %g matches it in %.3g ms: "
                   "%.1fx faster\n", r->error, 1e3 * r->time, s->method, s->param,
                   1e3 * s->time, r->time / s->time);
    }
}

static void print_table(const struct bench_scene *b)
{
    printf("\n%s (T = %g s%s; reference error estimate %.1e m)\n", b->name, b->T,
           b->frames ? ", sampled at 60 fps" : "", b->ref_err);
    printf("  %-10s %-9s %-10s %-10s %-9s\n", "method", "dt/tol", "error m", "time ms",
           "evals");
    for (int i = 0; i < n_rows; i++) {
        const struct row *r = &rows[i];
        if (strcmp(r->scene, b->name))
            continue;
        if (isinf(r->error))
            printf("  %-10s %-9g unstable\n", r->method, r->param);
        else
            printf("  %-10s %-9g %-10.2e %-10.4g %-9ld\n", r->method, r->param, r->error,
                   1e3 * r->time, r->evals);
    }
}

/* ---- energy over long runs and step cost --------------------------------- */

static void energy_runs(FILE *csv)
{
    const double T = quick ? 1e4 : 1e5;
    const struct { enum sp_method m; double dt, tol; } w[] = {
        {SP_METHOD_RK4, 1e-3, 0}, {SP_METHOD_VERLET, 1e-3, 0},
        {SP_METHOD_YOSHIDA4, 1e-3, 0}, {SP_METHOD_DOPRI5, 0, 1e-9},
        {SP_METHOD_DOP853, 0, 1e-9}, {SP_METHOD_RKN1210, 0, 1e-9},
    };
    printf("\nenergy over %g s on the default scene, sampled every 100 s\n", T);
    printf("  %-9s %-8s %-13s %-13s %-13s %-9s %-9s %s\n", "method", "dt/tol",
           "max|dE/E| 1st", "max|dE/E| last", "|dE/E| at end", "ns/step", "ns/eval",
           "wall s");
    fprintf(csv, "\nenergy_method,dt_or_tol,T_s,max_rel_first_tenth,max_rel_last_tenth,"
                 "rel_at_end,ns_per_step,ns_per_eval\n");
    for (size_t i = 0; i < sizeof(w) / sizeof(w[0]); i++) {
        struct sp_scene sc;
        struct sp_sim sim;
        struct sp_energy e;
        double first = 0, last = 0, end = 0;
        sp_scene_defaults(&sc);
        sc.integrator.method = w[i].m;
        if (w[i].dt > 0)
            sc.integrator.dt = w[i].dt;
        else
            sc.integrator.tolerance = w[i].tol;
        sp_sim_init(&sim, &sc);
        double t0 = now();
        int n = (int)(T / 100);
        for (int k = 1; k <= n; k++) {
            if (sp_sim_advance(&sim, 100.0 * k))
                break;
            sp_state_energy(&sim.p, &sim.s, &e);
            end = fabs(e.total - sim.energy0) / fabs(sim.energy0);
            if (k <= n / 10)
                first = fmax(first, end);
            if (k > n - n / 10)
                last = fmax(last, end);
        }
        double wall = now() - t0;
        const char *name = sp_method_info(w[i].m)->name;
        double par = w[i].dt > 0 ? w[i].dt : w[i].tol;
        printf("  %-9s %-8g %-13.2e %-13.2e %-13.2e %-9.1f %-9.2f %.2f\n", name, par, first,
               last, end, 1e9 * wall / sim.steps, 1e9 * wall / sim.evals, wall);
        fprintf(csv, "%s,%g,%g,%.3e,%.3e,%.3e,%.2f,%.3f\n", name, par, T, first, last, end,
                1e9 * wall / sim.steps, 1e9 * wall / sim.evals);
    }
}

/* ---- output -------------------------------------------------------------- */

static const struct { const char *method; uint32_t rgb; int dash; } styles[] = {
    {"rk4", 0x1f77b4, 0},      {"verlet", 0xff7f0e, 0},    {"yoshida4", 0x2ca02c, 0},
    {"dopri5", 0xd62728, 0},   {"dop853", 0x9467bd, 0},    {"rkn1210", 0x000000, 0},
    {"gsl-rk4", 0x1f77b4, 1},
    {"gsl-rkf45", 0xd62728, 1}, {"gsl-rk8pd", 0x8c564b, 1},
};
#define N_STYLES ((int)(sizeof(styles) / sizeof(styles[0])))

static int write_plot(const char *path, struct bench_scene *bs, int nb)
{
    const int pw = 620, ph = 430, mx = 80, my = 60, cols = 2;
    const int rows_n = (nb + cols - 1) / cols;
    struct plot p;
    if (plot_make(&p, cols * (pw + mx + 30) + 260, rows_n * (ph + my + 50) + 20))
        return -1;
    for (int s = 0; s < nb; s++) {
        struct plot_panel pn = {.x0 = mx + (s % cols) * (pw + mx + 30),
                                .y0 = my + (s / cols) * (ph + my + 50), .w = pw, .h = ph,
                                .lx0 = 1e9, .lx1 = -1e9, .ly0 = 1e9, .ly1 = -1e9};
        for (int i = 0; i < n_rows; i++) {
            const struct row *r = &rows[i];
            if (strcmp(r->scene, bs[s].name) || !(r->error > 0) || isinf(r->error))
                continue;
            pn.lx0 = fmin(pn.lx0, floor(log10(r->time)));
            pn.lx1 = fmax(pn.lx1, ceil(log10(r->time)));
            pn.ly0 = fmin(pn.ly0, floor(log10(r->error)));
            pn.ly1 = fmax(pn.ly1, ceil(log10(r->error)));
        }
        if (pn.lx0 > pn.lx1)
            continue;
        pn.ly0 = fmax(pn.ly0, -16);
        pn.ly1 = fmin(pn.ly1, 2);
        char title[128];
        snprintf(title, sizeof(title), "%s: %g s%s", bs[s].name, bs[s].T,
                 bs[s].frames ? ", 600 frames" : "");
        plot_axes(&p, &pn, title, "wall time per run, s",
                  bs[s].frames ? "worst position error over the frames, m" : "final position error, m");
        for (int k = 0; k < N_STYLES; k++) {
            double x[64], y[64];
            int n = 0;
            for (int i = 0; i < n_rows && n < 64; i++) {
                const struct row *r = &rows[i];
                if (strcmp(r->scene, bs[s].name) || strcmp(r->method, styles[k].method) ||
                    isinf(r->error) || r->error < pow(10, pn.ly0) ||
                    r->error > pow(10, pn.ly1))
                    continue;
                x[n] = r->time, y[n] = r->error, n++;
            }
            plot_series(&p, &pn, x, y, n, styles[k].rgb, styles[k].dash);
        }
    }
    /* legend */
    int lx = cols * (pw + mx + 30) + 10, ly = my;
    for (int k = 0; k < N_STYLES; k++) {
        double x[2] = {1, 10}, y[2] = {1, 1};
        struct plot_panel pn = {.x0 = lx, .y0 = ly + 28 * k, .w = 40, .h = 1,
                                .lx0 = 0, .lx1 = 1, .ly0 = -1, .ly1 = 1};
        pn.y0 -= 0;
        plot_series(&p, &pn, x, y, 2, styles[k].rgb, styles[k].dash);
        plot_text(&p, lx + 50, ly + 28 * k - 10, 16, 0x000000, styles[k].method);
    }
    plot_text(&p, lx, ly + 28 * N_STYLES + 10, 13, 0x444444, "solid: springpend");
    plot_text(&p, lx, ly + 28 * N_STYLES + 28, 13, 0x444444, "dashed, x: GSL odeiv2");
    int ret = sp_png_write(path, &p.img, 6);
    plot_destroy(&p);
    return ret;
}

static void write_csv(FILE *fp)
{
    fprintf(fp, "scene,family,method,dt_or_tol,error_m,time_s,evals\n");
    for (int i = 0; i < n_rows; i++) {
        const struct row *r = &rows[i];
        fprintf(fp, "%s,%s,%s,%g,%.3e,%.4e,%ld\n", r->scene, r->family, r->method, r->param,
                r->error, r->time, r->evals);
    }
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 1 ? argv[1] : ".";
    char path[4096];
    quick = argc > 2 && !strcmp(argv[2], "--quick");
    struct bench_scene bs[4];
    /* 1: the original's default scene, 10 s */
    bs[0].name = "default";
    sp_scene_defaults(&bs[0].sc);
    bs[0].T = 10, bs[0].frames = 0;
    /* 2: exact 2:1 resonance, k L0 = 3 m g, started with a bounce and a
     * small swing: energy flows from one to the other */
    bs[1].name = "resonance-2to1";
    sp_scene_defaults(&bs[1].sc);
    bs[1].sc.pendulum.stiffness = 3 * 0.5 * 9.81 / 0.5;
    bs[1].sc.initial.length = 0.8;
    bs[1].sc.initial.angle = 2 * M_PI / 180;
    bs[1].T = 10, bs[1].frames = 0;
    /* 3: large amplitude, chaotic: theta0 = 1.5 rad, r0 = 1.2 m at l = 1 m;
     * errors grow like exp(0.36 t), so a short horizon */
    bs[2].name = "chaotic";
    sp_scene_defaults(&bs[2].sc);
    bs[2].sc.pendulum.mass = 1;
    bs[2].sc.pendulum.stiffness = 20;
    bs[2].sc.pendulum.natural_length = 1 - 9.81 / 20;
    bs[2].sc.initial.length = 1.2;
    bs[2].sc.initial.angle = 1.5;
    bs[2].T = 5, bs[2].frames = 0;
    /* 4: the default scene as a video needs it: 600 frames at 60 fps */
    bs[3] = bs[0];
    bs[3].name = "default-60fps";
    bs[3].frames = 600;
    const int nb = 4;

    /* the runs report their own blow-ups on stderr: keep the log readable */
    fflush(stderr);
    int saved = dup(2), devnull = open("/dev/null", O_WRONLY);
    for (int i = 0; i < nb; i++) {
        make_reference(&bs[i]);
        dup2(devnull, 2);
        sweep(&bs[i]);
        dup2(saved, 2);
    }
    close(devnull);
#ifndef HAVE_GSL
    printf("(built without libgsl: no GSL peers)\n");
#endif
    for (int i = 0; i < nb; i++)
        print_table(&bs[i]);
    for (int i = 0; i < nb; i++)
        print_goals(&bs[i]);

    snprintf(path, sizeof(path), "%s/bench_physics.csv", outdir);
    FILE *csv = fopen(path, "w");
    if (!csv) {
        perror(path);
        return 1;
    }
    write_csv(csv);
    energy_runs(csv);
    fclose(csv);
    printf("\nwrote %s\n", path);
    snprintf(path, sizeof(path), "%s/bench_physics.png", outdir);
    if (write_plot(path, bs, nb))
        return 1;
    printf("wrote %s\n", path);
    return 0;
}
