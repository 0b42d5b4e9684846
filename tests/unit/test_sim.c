/* springpend tests: the physics core (sim.c). */
#include <math.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/sim.h"
#include "tap.h"

static struct sp_scene scene_with(double k, double m, double r0, double theta0_deg)
{
    struct sp_scene s;
    sp_scene_defaults(&s);
    s.pendulum.stiffness = k;
    s.pendulum.mass = m;
    s.initial.length = r0;
    s.initial.angle = theta0_deg * M_PI / 180;
    return s;
}

static double total_energy(const struct sp_sim *sim)
{
    struct sp_energy e;
    sp_state_energy(&sim->p, &sim->s, &e);
    return e.total;
}

/* Undamped default scene over 100 s: energy holds. */
static void test_energy(void)
{
    struct sp_scene sc;
    struct sp_sim sim;
    sp_scene_defaults(&sc);
    sp_sim_init(&sim, &sc);
    double worst = 0;
    for (int i = 1; i <= 1000; i++) {
        if (sp_sim_advance(&sim, i * 0.1))
            break;
        worst = fmax(worst, fabs(total_energy(&sim) - sim.energy0));
    }
    sp_tap_ok(sim.s.t == 100.0 && worst / fabs(sim.energy0) < 1e-9,
              "default scene, RK4 dt=1e-3, 100 s: |dE|/|E0| = %.2e < 1e-9", worst / fabs(sim.energy0));
}

/* Final position after t_end with step dt. */
static void run_to(const struct sp_scene *base, double dt, double t_end, double *x, double *y)
{
    struct sp_scene sc = *base;
    struct sp_sim sim;
    sc.integrator.dt = dt;
    sp_sim_init(&sim, &sc);
    sp_sim_advance(&sim, t_end);
    *x = sim.s.x;
    *y = sim.s.y;
}

/* RK4 is 4th order: halving dt divides the global error by ~16. */
static void test_order(void)
{
    struct sp_scene sc;
    sp_scene_defaults(&sc);
    double xr, yr, x1, y1, x2, y2;
    run_to(&sc, 1e-4, 3, &xr, &yr);
    run_to(&sc, 0.02, 3, &x1, &y1);
    run_to(&sc, 0.01, 3, &x2, &y2);
    double e1 = hypot(x1 - xr, y1 - yr), e2 = hypot(x2 - xr, y2 - yr);
    sp_tap_ok(e1 / e2 > 13 && e1 / e2 < 19,
              "RK4 error ratio for dt 0.02 -> 0.01 is %.2f (expected ~16; errors %.2e, %.2e)",
              e1 / e2, e1, e2);
}

/* Angular frequency from the mean spacing of upward zero crossings of
 * f(t) - mean, sampled every dt over t_end. */
static double measure_omega(const struct sp_scene *sc, int radial, double t_end)
{
    struct sp_sim sim;
    struct sp_polar p;
    double ell = sc->pendulum.natural_length +
                 sc->pendulum.mass * sc->pendulum.gravity / sc->pendulum.stiffness;
    double prev = 0, first = -1, last = -1, prev_t = 0;
    int crossings = 0;
    sp_sim_init(&sim, sc);
    while (sim.s.t < t_end) {
        sp_sim_advance(&sim, sim.s.t + 1e-3);
        sp_state_polar(&sim.s, &p);
        double f = radial ? p.r - ell : p.theta;
        if (prev < 0 && f >= 0) {
            double tc = prev_t + (sim.s.t - prev_t) * (-prev) / (f - prev);
            if (first < 0)
                first = tc;
            last = tc;
            crossings++;
        }
        prev = f;
        prev_t = sim.s.t;
    }
    return crossings > 1 ? 2 * M_PI * (crossings - 1) / (last - first) : 0;
}

static void test_small_oscillations(void)
{
    /* k/m = 100, l = 0.5 + 0.049 m: omega_s = 10, omega_p = 4.23 rad/s. */
    const double k = 50, m = 0.5, g = 9.81, L0 = 0.5, ell = L0 + m * g / k;
    struct sp_scene bounce = scene_with(k, m, ell - 0.01, 0);
    struct sp_scene swing = scene_with(k, m, ell, 0.5);
    double ws = measure_omega(&bounce, 1, 20), wp = measure_omega(&swing, 0, 40);
    sp_tap_ok(fabs(ws / sqrt(k / m) - 1) < 1e-3, "pure bounce: omega = %.5f, sqrt(k/m) = %.5f",
              ws, sqrt(k / m));
    sp_tap_ok(fabs(wp / sqrt(g / ell) - 1) < 2e-3,
              "small swing: omega = %.5f, sqrt(g/l) = %.5f with l = L0 + mg/k (sqrt(g/L0) = %.5f)",
              wp, sqrt(g / ell), sqrt(g / L0));
}

/* The polar equations from the Lagrangian (with + g cos(theta)) agree with
 * the Cartesian integration; the original page's - g cos(theta) does not. */
static void polar_rhs(double sign, const double *s, double *d)
{
    const double g = 9.81, km = 4, L0 = 0.5;
    d[0] = s[2];
    d[1] = s[3];
    d[2] = s[0] * s[3] * s[3] + sign * g * cos(s[1]) + km * (L0 - s[0]);
    d[3] = (-g * sin(s[1]) - 2 * s[2] * s[3]) / s[0];
}

static double polar_distance(double sign, const struct sp_sim *cart, double t_end)
{
    double s[4] = {0.55, 10 * M_PI / 180, 0, 0}, k[4][4], tmp[4], h = 1e-4;
    for (int n = 0; n < (int)lround(t_end / h); n++) {
        polar_rhs(sign, s, k[0]);
        for (int i = 0; i < 4; i++) tmp[i] = s[i] + h / 2 * k[0][i];
        polar_rhs(sign, tmp, k[1]);
        for (int i = 0; i < 4; i++) tmp[i] = s[i] + h / 2 * k[1][i];
        polar_rhs(sign, tmp, k[2]);
        for (int i = 0; i < 4; i++) tmp[i] = s[i] + h * k[2][i];
        polar_rhs(sign, tmp, k[3]);
        for (int i = 0; i < 4; i++) s[i] += h / 6 * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]);
    }
    return hypot(s[0] * sin(s[1]) - cart->s.x, -s[0] * cos(s[1]) - cart->s.y);
}

static void test_polar_agrees(void)
{
    struct sp_scene sc;
    struct sp_sim sim;
    sp_scene_defaults(&sc);
    sc.integrator.dt = 1e-4;
    sp_sim_init(&sim, &sc);
    sp_sim_advance(&sim, 5);
    double good = polar_distance(+1, &sim, 5), bad = polar_distance(-1, &sim, 5);
    sp_tap_ok(good < 1e-11, "polar form with +g cos(theta) matches Cartesian after 5 s: %.2e m", good);
    sp_tap_ok(bad > 0.1, "the original page's -g cos(theta) does not: %.2f m apart", bad);
}

static void test_exact_landing(void)
{
    struct sp_scene sc;
    struct sp_sim sim;
    sp_scene_defaults(&sc);
    sp_sim_init(&sim, &sc);
    int ok = 1;
    for (int k = 1; k <= 120; k++) {
        double t = sp_scene_frame_time(&sc, k);
        ok &= sp_sim_advance(&sim, t) == 0 && sim.s.t == t;
    }
    sp_tap_ok(ok && sim.steps >= 2000 && sim.steps <= 2000 + 120,
              "frames 1..120 at 60 fps are reached exactly (%ld steps)", sim.steps);
}

static void test_blowup(void)
{
    /* k/m = 1e7: RK4 at dt = 1e-3 has h*omega = 3.16 > 2.83 and grows. */
    struct sp_scene sc = scene_with(1e7, 1, 0.51, 5);
    struct sp_sim sim;
    sp_sim_init(&sim, &sc);
    fprintf(stderr, "# expected: an instability report follows\n");
    int ret = sp_sim_advance(&sim, 10);
    sp_tap_ok(ret == SP_E_UNSTABLE && sim.s.t < 10,
              "RK4 dt=1e-3 with k/m=1e7 is stopped as unstable (at t = %.3g s, finite: %d)",
              sim.s.t, isfinite(sim.s.x));
    /* At dt = 1e-4 (h omega = 0.32) RK4 loses |R|^2 - 1 ~ (h omega)^6 / 72 of
     * the bounce's energy per step, 14% in 1 s: the guard, which judges
     * drift against the energy of the motion, stops it. At 1e-5, 1e-6. */
    sc.integrator.dt = 1e-5;
    sp_sim_init(&sim, &sc);
    sp_tap_ok(sp_sim_advance(&sim, 1) == 0, "the same scene at dt=1e-5 runs clean");
}

static void test_damping(void)
{
    struct sp_scene sc;
    struct sp_sim sim;
    sp_scene_defaults(&sc);
    sc.pendulum.damping = 0.2;
    sp_sim_init(&sim, &sc);
    double prev = sim.energy0;
    int monotone = 1;
    for (int i = 1; i <= 200; i++) {
        sp_sim_advance(&sim, i * 0.1);
        double e = total_energy(&sim);
        monotone &= e <= prev + 1e-12;
        prev = e;
    }
    sp_tap_ok(monotone && prev < sim.energy0 - 1, "damped: energy falls monotonically (%.3f -> %.3f J)",
              sim.energy0, prev);
}

/* A scene with the given method; other keys default. */
static struct sp_scene scene_method(enum sp_method m, double dt, double tol)
{
    struct sp_scene s;
    sp_scene_defaults(&s);
    s.integrator.method = m;
    s.integrator.dt = dt;
    s.integrator.tolerance = tol;
    return s;
}

/* Error of the position at t_end against the reference (xr, yr), m. */
static double pos_error(const struct sp_scene *sc, double t_end, double xr, double yr,
                        long *evals)
{
    struct sp_sim sim;
    sp_sim_init(&sim, sc);
    if (sp_sim_advance(&sim, t_end))
        return INFINITY;
    if (evals)
        *evals = sim.evals;
    return hypot(sim.s.x - xr, sim.s.y - yr);
}

/* Each fixed-step method converges at its order. */
static void test_orders(void)
{
    struct sp_scene ref = scene_method(SP_METHOD_DOP853, 1e-3, 1e-14);
    struct sp_sim sim;
    sp_sim_init(&sim, &ref);
    sp_sim_advance(&sim, 3);
    const double xr = sim.s.x, yr = sim.s.y;
    const struct { enum sp_method m; double dt; double ratio; } cases[] = {
        {SP_METHOD_VERLET, 0.002, 4}, {SP_METHOD_YOSHIDA4, 0.01, 16}, {SP_METHOD_RK4, 0.02, 16},
    };
    for (size_t i = 0; i < sizeof(cases) / sizeof(cases[0]); i++) {
        struct sp_scene a = scene_method(cases[i].m, cases[i].dt, 0);
        struct sp_scene b = scene_method(cases[i].m, cases[i].dt / 2, 0);
        double e1 = pos_error(&a, 3, xr, yr, NULL), e2 = pos_error(&b, 3, xr, yr, NULL);
        double q = e1 / e2;
        sp_tap_ok(q > 0.8 * cases[i].ratio && q < 1.2 * cases[i].ratio,
                  "%s: error ratio for dt %g -> %g is %.2f (expected ~%g; errors %.2e, %.2e)",
                  sp_method_info(cases[i].m)->name, cases[i].dt, cases[i].dt / 2, q,
                  cases[i].ratio, e1, e2);
    }
}

/* Adaptive methods meet their tolerance at the end and, through dense
 * output, at every frame in between; dop853 needs far fewer evaluations. */
static void test_adaptive(void)
{
    const double T = 10;
    struct sp_scene ref = scene_method(SP_METHOD_RK4, 2e-5, 0);
    struct sp_sim r, a;
    const enum sp_method ms[] = {SP_METHOD_DOPRI5, SP_METHOD_DOP853, SP_METHOD_RKN1210};
    for (int i = 0; i < 3; i++) {
        struct sp_scene sc = scene_method(ms[i], 1e-3, 1e-10);
        double worst = 0;
        sp_sim_init(&r, &ref);
        sp_sim_advance(&r, 0);
        sp_sim_init(&a, &sc);
        int ok = 1;
        for (int k = 1; k <= 600; k++) {
            double t = k * T / 600;
            ok &= sp_sim_advance(&r, t) == 0 && sp_sim_advance(&a, t) == 0 && a.s.t == t;
            worst = fmax(worst, hypot(a.s.x - r.s.x, a.s.y - r.s.y));
        }
        sp_tap_ok(ok && worst < 1e-6,
                  "%s tol 1e-10: worst position error over 600 sampled frames in "
                  "10 s is %.2e m (< 1e-6; %ld evaluations, %ld steps, %ld rejected)",
                  sp_method_info(ms[i])->name, worst, a.evals, a.steps, a.rejected);
        if (ms[i] == SP_METHOD_DOP853)
            sp_tap_ok(a.evals * 20 < r.evals,
                      "dop853 used %ld evaluations, RK4 at dt=2e-5 %ld", a.evals, r.evals);
    }
    /* RKN12(10) to the end alone: fewer steps than dop853 at the same
     * tolerance, and at least as close to a dop853 run at 1e-15 */
    struct sp_scene tight = scene_method(SP_METHOD_DOP853, 1e-3, 1e-15);
    sp_sim_init(&r, &tight);
    sp_sim_advance(&r, T);
    long steps[2];
    double err[2];
    for (int i = 0; i < 2; i++) {
        struct sp_scene sc = scene_method(i ? SP_METHOD_RKN1210 : SP_METHOD_DOP853, 1e-3, 1e-12);
        sp_sim_init(&a, &sc);
        sp_sim_advance(&a, T);
        steps[i] = a.steps;
        err[i] = hypot(a.s.x - r.s.x, a.s.y - r.s.y);
    }
    sp_tap_ok(steps[1] * 2 < steps[0] && err[1] < 1e-10 && err[1] < 10 * err[0],
              "rkn1210 tol 1e-12, 10 s: %ld steps, error %.1e m (dop853: %ld steps, %.1e m)",
              steps[1], err[1], steps[0], err[0]);
}

/* Long runs: the symplectic methods' energy error stays bounded. */
static void test_symplectic_energy(void)
{
    struct sp_scene sc = scene_method(SP_METHOD_YOSHIDA4, 1e-3, 0);
    struct sp_sim sim;
    double first = 0, last = 0;
    sp_sim_init(&sim, &sc);
    for (int i = 1; i <= 2000; i++) {
        sp_sim_advance(&sim, i * 1.0);
        double d = fabs(total_energy(&sim) - sim.energy0) / fabs(sim.energy0);
        if (i <= 1000)
            first = fmax(first, d);
        else
            last = fmax(last, d);
    }
    sp_tap_ok(last < 1e-9 && last < 3 * first + 1e-15,
              "yoshida4 dt=1e-3 over 2000 s: max |dE/E| %.2e in the first half, %.2e in "
              "the second (no drift)", first, last);
}

/* With damping and a moving pivot, every method's energy balance holds:
 * E(t) - E(0) equals the work it tracked, and the methods agree on it. */
static void test_forced_balance(void)
{
    double works[5];
    int ok = 1;
    for (int m = 0; m < 5; m++) {
        struct sp_scene sc = scene_method((enum sp_method)m, 2e-4, 1e-11);
        struct sp_sim sim;
        sc.pendulum.damping = 0.05;
        sc.pivot.amplitude = 0.1;
        sc.pivot.frequency = 0.6;
        sp_sim_init(&sim, &sc);
        ok &= sp_sim_advance(&sim, 5) == 0;
        double bal = fabs(total_energy(&sim) - sim.energy0 - sim.work) / sim.energy_scale;
        works[m] = sim.work;
        sp_tap_ok(ok && bal < 1e-7 && fabs(sim.work) > 1e-2,
                  "%s, damped and driven, 5 s: work %.6f J, |E - E0 - W| / scale = %.1e",
                  sp_method_info((enum sp_method)m)->name, sim.work, bal);
    }
    double spread = 0;
    for (int m = 0; m < 5; m++)
        spread = fmax(spread, fabs(works[m] - works[SP_METHOD_DOP853]));
    sp_tap_ok(spread < 1e-5, "the five methods agree on the work to %.1e J", spread);
}

int main(void)
{
    test_energy();
    test_order();
    test_small_oscillations();
    test_polar_agrees();
    test_exact_landing();
    test_blowup();
    test_damping();
    test_orders();
    test_adaptive();
    test_symplectic_energy();
    test_forced_balance();
    return sp_tap_done();
}
