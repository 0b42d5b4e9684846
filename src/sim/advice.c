/* springpend: what `info` predicts. The safe step is a promise kept by
 * running: a dop853 probe finds the fastest rate the motion reaches, the
 * method's stability region turns it into a first guess, and the method
 * itself then runs the scene at that step (halved until it completes with a
 * tenth of the guard's drift). The exchange, decay and drive figures are
 * closed forms or the averaged equations (see advice.h). Pure: no I/O. */
#include <complex.h>
#include <math.h>

#include "springpend/advice.h"
#include "springpend/common.h"

/* The longest a probe or a check may run, in evaluations and in steps. */
#define PROBE_EVALS 400000
#define CHECK_STEPS 2000000
/* The drift a suggested step may show: a tenth of the guard's. */
#define SAFE_DRIFT (0.1 * SP_SIM_DRIFT_LIMIT)

/* ---- the step ------------------------------------------------------------ */

/* A close pass by the pivot: inside half the natural length, where the
 * compressed spring pushes outward with between k L0 / 2 and k L0 (a bounded
 * force; sp_advise_failed_at_pass uses the same region). Its tangential
 * "rate" sqrt(k/m (L0/r - 1)) is a saddle's, not an oscillation's, and its
 * rotation rate |v|/r lasts only the pass. What a fixed step must do there
 * is resolve the pass: the push turns round within r / |v|, so the step
 * follows it only with dt < r / |v|; a longer step does not blow up but
 * loses some energy at each pass. Where that is practical (the run in 2e6
 * steps of 1 / rate) the pass's rate counts in omega_max; where it is not
 * (r -> 0 sends it without bound), sp_advise_dt reports the pass instead
 * (sp_dt_advice.pass_*). */
static int in_pass(const struct sp_params *p, double rho)
{
    return rho < 0.5 * p->L0;
}

/* The fastest rate of state s, rad/s: the spring's tangential stiffness
 * k/m |1 - L0/r| (at most k/m outside a close pass) and the rotation |v|/r;
 * the radial rate sqrt(k/m) is the caller's. */
static double local_rate(const struct sp_params *p, const struct sp_state *s)
{
    const double rho = hypot(s->x, s->y);
    if (!(rho > 0))
        return 0;
    return fmax(sqrt(p->k_over_m * fabs(1 - p->L0 / rho)), hypot(s->vx, s->vy) / rho);
}

/* What a dop853 probe of the run saw, rad/s: the fastest rate outside close
 * passes and inside them; the close pass with the shortest r / |v|. */
struct probe {
    double w_out, w_pass;
    double pass_d, pass_v; /* m, m/s; NAN if none */
};

static void probe_note(const struct sp_params *p, const struct sp_state *s, struct probe *pr)
{
    const double rho = hypot(s->x, s->y), v = hypot(s->vx, s->vy);
    if (!in_pass(p, rho)) {
        pr->w_out = fmax(pr->w_out, local_rate(p, s));
        return;
    }
    pr->w_pass = fmax(pr->w_pass, local_rate(p, s));
    if (v > 0 && (isnan(pr->pass_d) || rho / v < pr->pass_d / pr->pass_v))
        pr->pass_d = rho, pr->pass_v = v;
}

/* Follows the scene's motion over [0, t_end] step by step with dop853 (a
 * bounded number of evaluations); *pr: what it saw. */
static void probe_run(const struct sp_scene *sc, double t_end,
                      const volatile sig_atomic_t *cancel, struct probe *pr)
{
    struct sp_scene probe = *sc;
    struct sp_sim sim;
    struct sp_physics ph;
    probe.integrator.method = SP_METHOD_DOP853;
    probe.integrator.tolerance = 1e-9;
    sp_sim_init(&sim, &probe);
    sim.cancel = cancel; /* a failure is not reported: it is data */
    sp_params_physics(&sim.p, &ph);
    *pr = (struct probe){.w_out = fmax(fmax(ph.omega_s, ph.omega_p), sim.p.drive_omega),
                         .pass_d = NAN, .pass_v = NAN};
    probe_note(&sim.p, &sim.s, pr);
    while (sim.s.t < t_end && sim.evals < PROBE_EVALS) {
        /* one accepted step at a time: to the step's end, or one step on */
        const double next = sim.t1 > sim.s.t ? sim.t1 : sim.s.t + sim.h;
        if (sp_sim_advance(&sim, fmin(next, t_end)))
            break; /* what was seen so far; the checks below decide */
        probe_note(&sim.p, &sim.s, pr);
    }
}

/* A fixed step that failed on a pass close by the pivot at speed (in_pass:
 * inside half the natural length, where the compressed spring pushes outward
 * with nearly k L0) and that push turns round within distance / speed, less
 * than a step. Not a blow-up: the motion stays bounded (scipy agrees), but a
 * fixed step loses energy on every pass it does not resolve. Only where the
 * step is well inside the method's stability limit for the spring, the drive
 * and the damping: an unstable step flings the bob past the pivot too. */
int sp_advise_failed_at_pass(const struct sp_sim *sim)
{
    const struct sp_method_info *mi = sp_method_info(sim->method);
    const double d = sim->failure.pass_distance, v = sim->failure.pass_speed;
    const double w = fmax(fmax(sqrt(sim->p.k_over_m), sim->p.drive_omega), sim->p.b_over_m);
    return !mi->adaptive && isfinite(sim->failure.energy) && w * sim->dt <= 0.5 * mi->stability &&
           in_pass(&sim->p, d) && v * sim->dt > d;
}

/* One step of method m over h of the damped oscillator x'' = -w^2 x - g x',
 * applied to u = (x, v) in place, as sim.c steps: RK4, or the symmetric
 * composition of damp(h/2) kick(h/2) drift(h) kick(h/2) damp(h/2) substeps
 * with the exact damping flow. */
static void linear_step(enum sp_method m, double h, double w, double g, double u[2])
{
    if (m == SP_METHOD_RK4) {
        double k[4][2], v[2] = {u[0], u[1]};
        for (int i = 0; i < 4; i++) {
            k[i][0] = v[1];
            k[i][1] = -w * w * v[0] - g * v[1];
            const double f = i < 2 ? 0.5 * h : h;
            v[0] = u[0] + f * k[i][0], v[1] = u[1] + f * k[i][1];
        }
        for (int c = 0; c < 2; c++)
            u[c] += h / 6 * (k[0][c] + 2 * (k[1][c] + k[2][c]) + k[3][c]);
        return;
    }
    static const double cbrt2 = 1.2599210498948731648;
    const double yw[3] = {1 / (2 - cbrt2), -cbrt2 / (2 - cbrt2), 1 / (2 - cbrt2)};
    const double vw[1] = {1};
    const double *wt = m == SP_METHOD_VERLET ? vw : yw;
    for (int i = 0; i < (m == SP_METHOD_VERLET ? 1 : 3); i++) {
        const double hi = wt[i] * h, d = exp(-g * hi / 2);
        u[1] *= d;
        u[1] -= 0.5 * hi * w * w * u[0];
        u[0] += hi * u[1];
        u[1] -= 0.5 * hi * w * w * u[0];
        u[1] *= d;
    }
}

/* The spectral radius of method m's step over h for the damped oscillator. */
static double step_radius(enum sp_method m, double h, double w, double g)
{
    double a[2] = {1, 0}, b[2] = {0, 1};
    linear_step(m, h, w, g, a);
    linear_step(m, h, w, g, b);
    const double tr = a[0] + b[1], det = a[0] * b[1] - b[0] * a[1], disc = tr * tr / 4 - det;
    return disc >= 0 ? fabs(tr / 2) + sqrt(disc) : sqrt(fabs(det));
}

/* The largest h (s) before which method m's step for the oscillator of
 * angular frequency w damped at g (1/s) first stops being stable: scanned in
 * steps of 1% from 1e-4 / max(w, g) to 8 / w (40 / g undamped by a spring),
 * then bisected; INFINITY where it stays stable. RK4: 2.83 / w undamped,
 * 2.785 / g on the negative real axis; Verlet 2 / w whatever the damping. */
static double method_limit(enum sp_method m, double w, double g)
{
    if (!(w > 0 || g > 0))
        return INFINITY; /* nothing moves: no limit */
    const double top = w > 0 ? 8 / w : 40 / g;
    double lo = 0, hi = 0;
    for (double h = 1e-4 / fmax(w, g); h <= top; h *= 1.01) {
        hi = h;
        if (step_radius(m, hi, w, g) > 1 + 1e-9)
            break;
        lo = hi;
    }
    if (lo == hi)
        return INFINITY;
    for (int i = 0; i < 60; i++) {
        const double mid = 0.5 * (lo + hi);
        if (step_radius(m, mid, w, g) > 1 + 1e-9)
            hi = mid;
        else
            lo = mid;
    }
    return lo;
}

/* x rounded down to one significant digit. */
static double round_down(double x)
{
    const double mag = pow(10, floor(log10(x)));
    return floor(x / mag * (1 + 1e-12)) * mag;
}

/* Runs sc's method at dt over [0, t] with the given drift limit, quietly.
 * 0, SP_E_UNSTABLE (*fail_t: where; *at_pass: sp_advise_failed_at_pass) or
 * SP_E_INTERRUPTED. */
static int run_fixed(const struct sp_scene *sc, double dt, double t, double drift_limit,
                     const volatile sig_atomic_t *cancel, double *fail_t, int *at_pass)
{
    struct sp_scene s = *sc;
    struct sp_sim sim;
    s.integrator.dt = dt;
    sp_sim_init(&sim, &s);
    sim.cancel = cancel; /* a failure is not reported: it is data */
    sim.drift_limit = drift_limit;
    const int ret = sp_sim_advance(&sim, t);
    *fail_t = sim.s.t;
    *at_pass = ret == SP_E_UNSTABLE && sp_advise_failed_at_pass(&sim);
    return ret;
}

int sp_advise_dt(const struct sp_scene *sc, double t_end, const volatile sig_atomic_t *cancel,
                 struct sp_dt_advice *out)
{
    const enum sp_method m = sc->integrator.method;
    const double gamma = sc->pendulum.damping / sc->pendulum.mass;
    double fail_t = 0;
    int ret, at_pass;
    *out = (struct sp_dt_advice){.safe = NAN, .scene_fail_t = NAN, .pass_distance = NAN,
                                 .pass_speed = NAN};
    if (sp_method_info(m)->adaptive)
        return SP_E_INPUT;
    struct probe pr;
    probe_run(sc, t_end, cancel, &pr);
    /* the fastest rate, and the damping alone (a slow swing, strongly damped);
     * a close pass's rate counts where steps of 1 / rate cover the run in
     * CHECK_STEPS; otherwise resolving it is impractical: it is left out,
     * reported, and the runs below find what the passes cost */
    out->omega_max = fmax(pr.w_out, pr.w_pass);
    if (pr.w_pass > pr.w_out && t_end * pr.w_pass > CHECK_STEPS) {
        out->omega_max = pr.w_out;
        out->pass_distance = pr.pass_d;
        out->pass_speed = pr.pass_v;
    }
    out->limit = fmin(method_limit(m, out->omega_max, gamma), method_limit(m, 0, gamma));

    /* the scene's own step, with the guard every command uses */
    out->scene_checked = fmin(t_end, CHECK_STEPS * sc->integrator.dt);
    ret = run_fixed(sc, sc->integrator.dt, out->scene_checked, SP_SIM_DRIFT_LIMIT, cancel,
                    &fail_t, &out->scene_fail_pass);
    if (ret == SP_E_INTERRUPTED)
        return ret;
    out->scene_ok = ret == 0;
    if (ret)
        out->scene_fail_t = fail_t;

    /* half the limit, then halved until the run keeps a tenth of the guard */
    double dt = round_down(0.5 * out->limit);
    for (int i = 0; i < 40 && dt > 0; i++, dt = round_down(0.5 * dt)) {
        const double t = fmin(t_end, CHECK_STEPS * dt);
        ret = run_fixed(sc, dt, t, SAFE_DRIFT, cancel, &fail_t, &at_pass);
        if (ret == SP_E_INTERRUPTED)
            return ret;
        out->pass_bound |= at_pass;
        if (!ret) {
            out->safe = dt;
            out->checked = t;
            break;
        }
    }
    return 0;
}

/* The most evaluations sp_advise_adaptive spends: about a second. */
#define ADAPTIVE_EVALS 20000000

int sp_advise_adaptive(const struct sp_scene *sc, double t_end,
                       const volatile sig_atomic_t *cancel, double *checked)
{
    struct sp_scene s = *sc;
    struct sp_sim sim;
    s.integrator.method = SP_METHOD_DOP853;
    s.integrator.tolerance = fmin(sc->integrator.tolerance, 1e-9);
    sp_sim_init(&sim, &s);
    sim.cancel = cancel; /* a failure is not reported: it is data */
    sim.drift_limit = SAFE_DRIFT;
    *checked = 0;
    for (int i = 1; i <= 100 && sim.evals < ADAPTIVE_EVALS; i++) {
        const int ret = sp_sim_advance(&sim, t_end * i / 100);
        if (ret)
            return ret;
        *checked = sim.s.t;
    }
    return 0;
}

/* ---- the exchange near 2:1 ----------------------------------------------- */

/* d/dt of (A, B) at time t for Lynch's averaged equations (advice.h). */
static void lynch_rhs(double kA, double kB, double d, double t, const double complex *y,
                      double complex *f)
{
    const double complex ph = cexp(I * d * t);
    f[0] = I * kA * y[1] * conj(y[0]) * ph;
    f[1] = I * kB * y[0] * y[0] * conj(ph);
}

typedef void lynch_fn(double kA, double kB, double d, double t, const double complex *y,
                      double complex *f);

/* One RK4 step of h from t for the n (at most 3) amplitudes y of f. */
static void lynch_step(lynch_fn *f, int n, double kA, double kB, double d, double t,
                       double complex *y, double h)
{
    double complex k1[3], k2[3], k3[3], k4[3], v[3];
    f(kA, kB, d, t, y, k1);
    for (int c = 0; c < n; c++)
        v[c] = y[c] + 0.5 * h * k1[c];
    f(kA, kB, d, t + 0.5 * h, v, k2);
    for (int c = 0; c < n; c++)
        v[c] = y[c] + 0.5 * h * k2[c];
    f(kA, kB, d, t + 0.5 * h, v, k3);
    for (int c = 0; c < n; c++)
        v[c] = y[c] + h * k3[c];
    f(kA, kB, d, t + h, v, k4);
    for (int c = 0; c < n; c++)
        y[c] += h / 6 * (k1[c] + 2 * (k2[c] + k3[c]) + k4[c]);
}

int sp_advise_exchange(const struct sp_params *p, const struct sp_state *s0,
                       struct sp_exchange *out)
{
    struct sp_physics ph;
    struct sp_polar q;
    *out = (struct sp_exchange){.time = NAN, .swing_share = NAN, .epsilon = NAN};
    sp_params_physics(p, &ph);
    if (!(ph.omega_p > 0) || fabs(ph.ratio / 2 - 1) > 0.1)
        return SP_E_INPUT;
    sp_state_polar(s0, &q);
    const double wp = ph.omega_p, ws = ph.omega_s, l = ph.ell;
    const double kA = 0.75 * wp / l, kB = kA * wp * wp / (ws * ws), d = ws - 2 * wp;
    /* x = l theta = Re(A e^{i wp t}): A = x - i x'/wp; likewise B for r - l */
    double complex y[2] = {l * q.theta - I * l * q.theta_dot / wp,
                           (q.r - l) - I * q.r_dot / ws};
    out->rate = kA * cabs(y[1]);
    out->epsilon = fmax(cabs(y[0]), cabs(y[1])) / l;
    if (cabs(y[0]) == 0 || cabs(y[1]) == 0)
        return 0; /* nothing to exchange from, or the swing starts at its peak */
    /* RK4 at a fiftieth of the fastest slow rate; the first local maximum
     * of |A|^2 after t = 0, refined by a parabola through three steps */
    const double amax = sqrt(cabs(y[0]) * cabs(y[0]) + ph.ratio * ph.ratio * cabs(y[1]) * cabs(y[1]));
    const double h = 0.02 / (kA * amax + fabs(d));
    double f0 = NAN, f1 = cabs(y[0]) * cabs(y[0]), t = 0;
    for (long n = 0; n < 2000000; n++) {
        lynch_step(lynch_rhs, 2, kA, kB, d, t, y, h);
        t += h;
        const double f2 = cabs(y[0]) * cabs(y[0]);
        if (n > 0 && f1 > f0 && f1 >= f2) {
            const double den = f0 - 2 * f1 + f2;
            const double off = den != 0 ? 0.5 * (f0 - f2) / den : 0;
            const double eb = ws * ws * cabs(y[1]) * cabs(y[1]);
            out->time = t - h + off * h;
            out->swing_share = wp * wp * f1 / (wp * wp * f1 + eb);
            return 0;
        }
        f0 = f1;
        f1 = f2;
    }
    return 0;
}

/* ---- the swinging spring's precession ----------------------------------- */

/* d/dt of (A_x, A_z, B) at time t (advice.h, sp_precession). */
static void lynch3_rhs(double kA, double kB, double d, double t, const double complex *y,
                       double complex *f)
{
    const double complex ph = cexp(I * d * t);
    f[0] = I * kA * y[2] * conj(y[0]) * ph;
    f[1] = I * kA * y[2] * conj(y[1]) * ph;
    f[2] = I * kB * (y[0] * y[0] + y[1] * y[1]) * conj(ph);
}

/* The azimuth of the averaged swing A, rad in (-pi/2, pi/2] (0: none). */
static double averaged_azimuth(const double complex y[3])
{
    const double mxx = creal(y[0]) * creal(y[0]) + cimag(y[0]) * cimag(y[0]);
    const double mzz = creal(y[1]) * creal(y[1]) + cimag(y[1]) * cimag(y[1]);
    const double mxz = creal(y[0]) * creal(y[1]) + cimag(y[0]) * cimag(y[1]);
    return mxz == 0 && mxx == mzz ? 0 : 0.5 * atan2(2 * mxz, mxx - mzz);
}

/* The accuracy doc/physics.md states for the prediction holds where it was measured:
 * amplitudes up to this fraction of l. */
#define PRECESSION_EPS_MAX 0.065
#define PRECESSION_DETUNING_MAX 0.01 /* |omega_s / (2 omega_p) - 1| */
#define PRECESSION_MAXIMA 5 /* swing maxima followed */

/* The start's amplitude about the hanging equilibrium (0, -l, 0) as a
 * fraction of l: max(|A|, |B|) / l with the swing's |A| = l sqrt(th^2 +
 * (v_t / (r w_p))^2), th the angle from the downward vertical in [0, pi]
 * (not the horizontal offset: a bob near the top has almost none) and v_t
 * the velocity across the spring, and the bounce's |B| = sqrt((r - l)^2 +
 * (r' / w_s)^2). For a planar start this is sp_exchange's epsilon. r: m,
 * r_dot: m/s. */
static double start_amplitude(const struct sp_state *s, double r, double r_dot, double wp,
                              double ws, double l)
{
    const double th = atan2(hypot(s->x, s->z), -s->y);
    const double v2 = s->vx * s->vx + s->vy * s->vy + s->vz * s->vz;
    const double vt = sqrt(fmax(v2 - r_dot * r_dot, 0));
    const double swing = r > 0 ? l * hypot(th, vt / (r * wp)) : INFINITY;
    return fmax(swing, hypot(r - l, r_dot / ws)) / l;
}

int sp_advise_precession(const struct sp_params *p, const struct sp_state *s0,
                         struct sp_precession *out)
{
    struct sp_physics ph;
    *out = (struct sp_precession){.angle = NAN, .period = NAN, .first_peak = NAN,
                                  .epsilon = NAN, .swing_share = NAN};
    sp_params_physics(p, &ph);
    if (!(ph.omega_p > 0)) {
        out->why = "without gravity there is no swing to precess";
        return SP_E_INPUT;
    }
    if (fabs(ph.ratio / 2 - 1) > 0.1) {
        out->why = "omega_s / omega_p is further than 10% from 2: no resonant exchange";
        return SP_E_INPUT;
    }
    const double wp = ph.omega_p, ws = ph.omega_s, l = ph.ell;
    const double kA = 0.75 * wp / l, kB = kA * wp * wp / (ws * ws), d = ws - 2 * wp;
    /* h = Re(A e^{i wp t}): A = h - i h'/wp; r - l = Re(B e^{i ws t}) */
    const double r = sqrt(s0->x * s0->x + s0->y * s0->y + s0->z * s0->z);
    const double r_dot = r > 0 ? (s0->x * s0->vx + s0->y * s0->vy + s0->z * s0->vz) / r : 0;
    double complex y[3] = {s0->x - I * s0->vx / wp, s0->z - I * s0->vz / wp,
                           (r - l) - I * r_dot / ws};
    const double a0 = sqrt(cabs(y[0]) * cabs(y[0]) + cabs(y[1]) * cabs(y[1]));
    out->epsilon = start_amplitude(s0, r, r_dot, wp, ws, l);
    if (a0 == 0 || cabs(y[2]) == 0) {
        out->why = "it needs both a bounce (r0 != l or a length_rate) and a swing";
        return 0;
    }
    /* RK4 at a fiftieth of the fastest slow rate, as sp_advise_exchange */
    const double amax = sqrt(a0 * a0 + ph.ratio * ph.ratio * cabs(y[2]) * cabs(y[2]));
    const double h = 0.02 / (kA * amax + fabs(d));
    double f0 = NAN, f1 = a0 * a0, t = 0, az = averaged_azimuth(y), az_prev = az;
    double t_max[PRECESSION_MAXIMA], az_max[PRECESSION_MAXIMA];
    int n_max = 0;
    for (long n = 0; n < 4000000 && n_max < PRECESSION_MAXIMA; n++) {
        lynch_step(lynch3_rhs, 3, kA, kB, d, t, y, h);
        t += h;
        const double f2 = cabs(y[0]) * cabs(y[0]) + cabs(y[1]) * cabs(y[1]);
        const double az_now = sp_azimuth_unwrap(az, averaged_azimuth(y));
        if (n > 0 && f1 > f0 && f1 >= f2) {
            /* the maximum at the step before, refined by a parabola */
            const double den = f0 - 2 * f1 + f2;
            const double off = den != 0 ? 0.5 * (f0 - f2) / den : 0;
            t_max[n_max] = t - h + off * h;
            if (n_max == 0) {
                const double eb = ws * ws * cabs(y[2]) * cabs(y[2]);
                out->swing_share = wp * wp * f1 / (wp * wp * f1 + eb);
            }
            az_max[n_max++] = az + off * (off > 0 ? az_now - az : az - az_prev);
        }
        az_prev = az, az = az_now;
        f0 = f1;
        f1 = f2;
    }
    out->exchanges = n_max;
    if (n_max < 2) {
        out->why = "the averaged motion shows no repeated exchange";
        return 0;
    }
    out->first_peak = t_max[0];
    out->period = (t_max[n_max - 1] - t_max[0]) / (n_max - 1);
    out->angle = (az_max[n_max - 1] - az_max[0]) / (n_max - 1);
    if (p->b_over_m != 0 || p->drive_amp != 0)
        out->why = "damping or a driven pivot is outside the conservative averaged theory";
    else if (out->epsilon > PRECESSION_EPS_MAX)
        out->why = "the amplitude is too large for the averaged (small-amplitude) theory";
    else if (fabs(ph.ratio / 2 - 1) > PRECESSION_DETUNING_MAX)
        out->why = "omega_s / omega_p is further than 1% from 2, beyond where the prediction "
                   "was measured";
    else
        out->applies = 1;
    return 0;
}

/* ---- what info and the HUD state ----------------------------------------- */

int sp_advise_predict(const struct sp_params *p, const struct sp_state *s0, int spatial,
                      struct sp_prediction *out)
{
    *out = (struct sp_prediction){.spatial = spatial, .amplitude = NAN};
    sp_params_physics(p, &out->ph);
    out->swings = out->ph.omega_p > 0;
    out->near21 = sp_advise_exchange(p, s0, &out->ex) == 0;
    out->amplitude = out->ex.epsilon;
    if (spatial) {
        out->prec_ok = sp_advise_precession(p, s0, &out->prec) == 0;
        if (out->prec_ok) {
            /* the exchange of the 3-D motion is the three-wave one's: its first
             * swing peak, not the planar projection's */
            out->amplitude = out->prec.epsilon;
            out->ex.time = out->prec.first_peak;
            out->ex.swing_share = out->prec.swing_share;
        }
        out->brief = !out->swings ? "none: no swing without gravity"
                     : !out->prec_ok ? "none: not near a 2:1 exchange"
                     : isnan(out->prec.angle) ? "none: no repeated exchange to predict it by"
                                              : "";
    }
    /* the averaged equations expand in small amplitudes: far beyond, their
     * numbers would be stated for a motion they do not describe */
    if (out->near21 && out->amplitude > SP_ADVISE_AMPLITUDE_MAX) {
        out->ex.time = out->ex.swing_share = NAN;
        out->ex_beyond = 1;
        if (spatial && out->prec_ok) {
            out->prec_ok = 0;
            out->prec.applies = 0;
            out->prec.angle = NAN;
            out->prec.why = "the start's amplitude about the hanging equilibrium is beyond the "
                            "averaged theory's small amplitudes";
            out->brief = "not predicted: the start is too large for the theory";
        }
    }
    return 0;
}

/* ---- damping ------------------------------------------------------------- */

void sp_advise_decay(double omega, double gamma, struct sp_decay *out)
{
    *out = (struct sp_decay){.q = gamma > 0 ? omega / gamma : INFINITY,
                             .energy_time = gamma > 0 ? 1 / gamma : INFINITY};
    if (!(gamma > 0))
        return;
    const double zeta = gamma / (2 * omega);
    if (fabs(zeta - 1) <= 0.01)
        out->regime = 0;
    else if (zeta < 1)
        out->regime = -1;
    else {
        out->regime = 1;
        /* the slow root gamma/2 - sqrt(gamma^2/4 - omega^2), without the
         * cancellation; no restoring force: the velocity decays at gamma */
        const double slow = omega > 0 ? omega * omega / (gamma / 2 +
                                                          sqrt(gamma * gamma / 4 - omega * omega))
                                      : gamma;
        out->energy_time = 1 / (2 * slow);
    }
}

/* ---- the driven pivot ---------------------------------------------------- */

/* One drive period of x'' + gam x' + wp2 (1 + Re(E e^{i W t})) x = 0 from
 * y = (x, x') at t = 0, in place (RK4, 2000 steps). */
static void mathieu_period(double wp2, double complex E, double W, double gam, double y[2])
{
    const int n = 2000;
    const double h = 2 * M_PI / W / n;
#define MATHIEU_F(t, a, b, fa, fb) \
    (fa = (b), fb = -gam * (b) - wp2 * (1 + creal(E * cexp(I * W * (t)))) * (a))
    for (int i = 0; i < n; i++) {
        const double t = i * h;
        double k1a, k1b, k2a, k2b, k3a, k3b, k4a, k4b;
        MATHIEU_F(t, y[0], y[1], k1a, k1b);
        MATHIEU_F(t + h / 2, y[0] + h / 2 * k1a, y[1] + h / 2 * k1b, k2a, k2b);
        MATHIEU_F(t + h / 2, y[0] + h / 2 * k2a, y[1] + h / 2 * k2b, k3a, k3b);
        MATHIEU_F(t + h, y[0] + h * k3a, y[1] + h * k3b, k4a, k4b);
        y[0] += h / 6 * (k1a + 2 * (k2a + k3a) + k4a);
        y[1] += h / 6 * (k1b + 2 * (k2b + k3b) + k4b);
    }
#undef MATHIEU_F
}

int sp_advise_drive(const struct sp_params *p, const struct sp_state *s0,
                    struct sp_drive_advice *out)
{
    struct sp_physics ph;
    if (p->drive_amp == 0 || p->drive_omega == 0)
        return SP_E_INPUT;
    sp_params_physics(p, &ph);
    const double W = p->drive_omega, A = p->drive_amp, gam = p->b_over_m;
    const double wp = ph.omega_p, ws = ph.omega_s;
    /* the forced bounce: z'' + gam z' + ws^2 z = a_p + gam v_p */
    const double complex Z = (I * A * W * W + A * gam * W) / (ws * ws - W * W + I * gam * W);
    *out = (struct sp_drive_advice){.bounce_amp = cabs(Z), .seed_share = NAN,
                                    .time_10x = NAN, .growth = -gam / 2};
    if (!(wp > 0))
        return 0;
    /* x'' + wp^2 (1 + Re(E e^{i W t})) x = 0; x = Re(a e^{i W t / 2}) gives
     * a' = i dl a + c conj(a) - gam/2 a */
    const double complex E = ws * ws * p->L0 / (p->g * ph.ell) * Z;
    const double nu = W / 2, dl = (wp * wp - nu * nu) / (2 * nu);
    const double complex c = I * wp * wp * E / (4 * nu);
    out->h = cabs(E);
    out->detuning = dl;
    out->tongue = cabs(c);
    /* Floquet: the map over one drive period of the linear swing, exact where
     * the averaging above is only first order in h (it puts a start at rest
     * wholly in the decaying mode; the true share is of order h / 4) */
    const double T = 2 * M_PI / W;
    double M[2][2];
    for (int j = 0; j < 2; j++) {
        double y[2] = {j == 0, j == 1};
        mathieu_period(wp * wp, E, W, gam, y);
        M[0][j] = y[0], M[1][j] = y[1];
    }
    const double tr = M[0][0] + M[1][1], det = M[0][0] * M[1][1] - M[0][1] * M[1][0];
    const double disc = tr * tr / 4 - det;
    if (!(disc > 0)) { /* a complex pair: the swing turns, at most at the damping's rate */
        out->growth = log(sqrt(fabs(det))) / T;
        return 0;
    }
    const double mu[2] = {tr / 2 + copysign(sqrt(disc), tr), 0};
    double m2 = det / mu[0]; /* the other root, without cancellation */
    out->growth = log(fmax(fabs(mu[0]), fabs(m2))) / T;
    if (!(out->growth > 0))
        return 0;
    const double big = fabs(mu[0]) >= fabs(m2) ? mu[0] : m2, small = big == mu[0] ? m2 : mu[0];
    /* eigenvectors v (growing) and u (the other); the start = a v + b u */
    double v[2] = {M[0][1], big - M[0][0]}, u[2] = {M[0][1], small - M[0][0]};
    if (hypot(big - M[1][1], M[1][0]) > hypot(v[0], v[1]))
        v[0] = big - M[1][1], v[1] = M[1][0];
    if (hypot(small - M[1][1], M[1][0]) > hypot(u[0], u[1]))
        u[0] = small - M[1][1], u[1] = M[1][0];
    const double x0 = s0->x, v0 = s0->vx, dd = v[0] * u[1] - v[1] * u[0];
    const double size = hypot(x0, v0 / nu);
    if (!(size > 0) || dd == 0)
        return 0;
    const double a = (x0 * u[1] - v0 * u[0]) / dd;
    out->seed_share = fabs(a) * hypot(v[0], v[1] / nu) / size;
    if (out->seed_share > 0)
        out->time_10x = log(10 / out->seed_share) / out->growth;
    return 0;
}
