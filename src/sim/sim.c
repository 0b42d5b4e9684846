/* springpend: the integrator core. Five methods share one right-hand side,
 * inlined into each stepper: fixed-step RK4, Stormer-Verlet and Yoshida's
 * 4th-order composition on a uniform grid, and the adaptive Dormand-Prince
 * pairs 5(4) and 8(5,3) with dense output. The blow-up guard checks after
 * every step (every 4th on RK4's cheap steps) that the state is finite and
 * that total energy, less the work done by damping and the moving pivot,
 * stays put. No allocation anywhere.
 * A second compile-time switch, `spatial`, adds z and vz (the swinging
 * spring in three dimensions) at u[5], u[6]; with it off every method does
 * exactly the planar arithmetic, bit for bit. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/sim.h"

/* For the functions taking `const int forced` (and `const int spatial`):
 * inlined always, so that each caller passing constants gets its own
 * specialised copy. */
#define SPECIALISED static inline __attribute__((always_inline))

static const struct sp_method_info methods[] = {
    [SP_METHOD_RKN1210] = {"rkn1210", 12, 1, 0, 17},
    [SP_METHOD_RK4] = {"rk4", 4, 0, 2.8284271247461903, 4},
    [SP_METHOD_VERLET] = {"verlet", 2, 0, 2.0, 1},
    /* |h omega| < 1.5734 for the triple jump, found from the trace of the
     * composed harmonic-oscillator map */
    [SP_METHOD_YOSHIDA4] = {"yoshida4", 4, 0, 1.5734, 3},
    [SP_METHOD_DOPRI5] = {"dopri5", 5, 1, 0, 6},
    [SP_METHOD_DOP853] = {"dop853", 8, 1, 0, 12},
};

const struct sp_method_info *sp_method_info(enum sp_method m)
{
    return &methods[m];
}

/* ---- the right-hand side ------------------------------------------------ */

/* The pivot's velocity and acceleration at t, m/s and m/s^2. */
static inline void pivot_motion(const struct sp_params *p, double t, double *v, double *a)
{
    double s = sin(p->drive_omega * t), c = cos(p->drive_omega * t);
    *v = p->drive_amp * p->drive_omega * c;
    *a = -p->drive_amp * p->drive_omega * p->drive_omega * s;
}

/* Acceleration of the bob at position (x, y) from the spring, gravity and
 * the pivot's acceleration a_pivot, m/s^2: everything that does not depend on
 * the velocity. Regular everywhere: at the pivot the unit vector is taken as
 * zero (the force stays bounded, only its direction jumps). */
static inline void accel_q(const struct sp_params *p, double x, double y, double a_pivot,
                           double *ax, double *ay)
{
    double rho = sqrt(x * x + y * y);
    double c = p->k_over_m * (1 - (rho > 0 ? p->L0 / rho : 0));
    *ax = -c * x;
    *ay = -c * y - p->g - a_pivot;
}

/* accel_q in three dimensions: (x, y, z) to (ax, ay, az). */
static inline void accel_q3(const struct sp_params *p, double x, double y, double z,
                            double a_pivot, double *ax, double *ay, double *az)
{
    double rho = sqrt(x * x + y * y + z * z);
    double c = p->k_over_m * (1 - (rho > 0 ? p->L0 / rho : 0));
    *ax = -c * x;
    *ay = -c * y - p->g - a_pivot;
    *az = -c * z;
}

/* d/dt of u = (x, y, vx, vy, w, z, vz), w the work per mass done by damping
 * and the drive (J/kg). `forced` and `spatial` are compile-time constants at
 * every call: forced = 0 skips damping, drive and w; spatial = 0 skips z and
 * vz (u[5], u[6] are then neither read nor written). */
SPECIALISED void rhs(const struct sp_params *p, double t, const double *u, double *d,
                       const int forced, const int spatial)
{
    double vp = 0, ap = 0;
    if (forced && p->drive_amp != 0)
        pivot_motion(p, t, &vp, &ap);
    if (spatial) {
        double a[7];
        accel_q3(p, u[0], u[1], u[5], ap, &a[0], &a[1], &a[5]);
        d[2] = a[0], d[3] = a[1], d[6] = a[5];
        d[5] = u[6];
        if (!forced)
            d[4] = 0;
    } else {
        accel_q(p, u[0], u[1], ap, &d[2], &d[3]);
    }
    d[0] = u[2];
    d[1] = u[3];
    if (forced) {
        d[2] -= p->b_over_m * u[2];
        d[3] -= p->b_over_m * (u[3] + vp);
        if (spatial) {
            d[6] -= p->b_over_m * u[6];
            d[4] = -p->b_over_m * (u[2] * u[2] + u[3] * (u[3] + vp) + u[6] * u[6]) - ap * u[3];
        } else {
            d[4] = -p->b_over_m * (u[2] * u[2] + u[3] * (u[3] + vp)) - ap * u[3];
        }
    }
}

/* Components a method updates: (x, y, vx, vy), w when forced, all seven in
 * space (w then stays 0 unforced). */
#define NC(forced, spatial) ((spatial) ? 7 : (forced) ? 5 : 4)
/* The physical components of the error norm: 4 in the plane, 6 in space. */
#define NPHYS(spatial) ((spatial) ? 6 : 4)

/* ---- fixed-step methods -------------------------------------------------- */

SPECIALISED void rk4_step(const struct sp_params *p, double t, double *u, double h,
                            const int forced, const int spatial)
{
    double k1[7], k2[7], k3[7], k4[7], v[7];
    const int n = NC(forced, spatial);
    rhs(p, t, u, k1, forced, spatial);
    for (int c = 0; c < n; c++)
        v[c] = u[c] + 0.5 * h * k1[c];
    rhs(p, t + 0.5 * h, v, k2, forced, spatial);
    for (int c = 0; c < n; c++)
        v[c] = u[c] + 0.5 * h * k2[c];
    rhs(p, t + 0.5 * h, v, k3, forced, spatial);
    for (int c = 0; c < n; c++)
        v[c] = u[c] + h * k3[c];
    rhs(p, t + h, v, k4, forced, spatial);
    for (int c = 0; c < n; c++)
        u[c] += h / 6 * (k1[c] + 2 * (k2[c] + k3[c]) + k4[c]);
}

/* The exact flow of the damping alone over h: the velocity relative to the
 * air decays by exp(-b h / m); its work is the change of kinetic energy. */
SPECIALISED void damp(const struct sp_params *p, double t, double *u, double h,
                      const int spatial)
{
    double vp = 0, ap, f = exp(-p->b_over_m * h);
    if (p->drive_amp != 0)
        pivot_motion(p, t, &vp, &ap);
    if (spatial) {
        double e = u[2] * u[2] + u[3] * u[3] + u[6] * u[6];
        u[2] *= f;
        u[3] = (u[3] + vp) * f - vp;
        u[6] *= f;
        u[4] += 0.5 * (u[2] * u[2] + u[3] * u[3] + u[6] * u[6] - e);
        return;
    }
    double e = u[2] * u[2] + u[3] * u[3];
    u[2] *= f;
    u[3] = (u[3] + vp) * f - vp;
    u[4] += 0.5 * (u[2] * u[2] + u[3] * u[3] - e);
}

/* A kick: v += h a(q, t) with a = (ax, ay, a_pivot, az) precomputed; the
 * drive's share of the work is -a_pivot * vy_mean * h. */
SPECIALISED void kick(double *u, double h, const double *a, const int forced,
                      const int spatial)
{
    double vy = u[3];
    u[2] += h * a[0];
    u[3] += h * a[1];
    if (spatial)
        u[6] += h * a[3];
    if (forced)
        u[4] -= a[2] * 0.5 * (vy + u[3]) * h;
}

/* Symmetric composition of Stormer-Verlet substeps with weights w[0..n-1]:
 * for each, damp(h/2) kick(h/2) drift(h) kick(h/2) damp(h/2). The force
 * depends on position and time only, so one evaluation per drift serves the
 * kick after it and the kick before the next drift. a[] carries the force at
 * the start of the step in and at its end out. Returns evaluations made. */
SPECIALISED int splitting_step(const struct sp_params *p, double t, double *u,
                                 double h, const double *w, int n, double *a,
                                 const int forced, const int spatial)
{
    for (int i = 0; i < n; i++) {
        double hi = w[i] * h;
        if (forced && p->b_over_m != 0)
            damp(p, t, u, 0.5 * hi, spatial);
        kick(u, 0.5 * hi, a, forced, spatial);
        u[0] += hi * u[2];
        u[1] += hi * u[3];
        if (spatial)
            u[5] += hi * u[6];
        t += hi;
        double vp;
        a[2] = 0;
        if (forced && p->drive_amp != 0)
            pivot_motion(p, t, &vp, &a[2]);
        if (spatial)
            accel_q3(p, u[0], u[1], u[5], a[2], &a[0], &a[1], &a[3]);
        else
            accel_q(p, u[0], u[1], a[2], &a[0], &a[1]);
        kick(u, 0.5 * hi, a, forced, spatial);
        if (forced && p->b_over_m != 0)
            damp(p, t, u, 0.5 * hi, spatial);
    }
    return n;
}

#define CBRT2 1.2599210498948731648
static const double verlet_w[] = {1};
static const double yoshida_w[] = {1 / (2 - CBRT2), -CBRT2 / (2 - CBRT2), 1 / (2 - CBRT2)};

/* One step of a fixed-step method from t over h, in place; a[] is the
 * force cache of the splitting methods (valid for u at t, in and out).
 * Returns the evaluations made. */
SPECIALISED int fixed_step(const struct sp_sim *sim, double t, double *u, double h,
                             double *a, const int forced, const int spatial)
{
    switch (sim->method) {
    case SP_METHOD_VERLET:
        return splitting_step(&sim->p, t, u, h, verlet_w, 1, a, forced, spatial);
    case SP_METHOD_YOSHIDA4:
        return splitting_step(&sim->p, t, u, h, yoshida_w, 3, a, forced, spatial);
    default:
        rk4_step(&sim->p, t, u, h, forced, spatial);
        return 4;
    }
}

/* The force cache for state u at time t: acceleration without the velocity
 * terms (ax, ay, then az at a[3] when spatial), and the pivot's acceleration
 * at a[2]. */
static void force_at(const struct sp_params *p, double t, const double *u, double *a,
                     int spatial)
{
    double vp;
    a[2] = 0;
    if (p->drive_amp != 0)
        pivot_motion(p, t, &vp, &a[2]);
    if (spatial)
        accel_q3(p, u[0], u[1], u[5], a[2], &a[0], &a[1], &a[3]);
    else
        accel_q(p, u[0], u[1], a[2], &a[0], &a[1]);
}

/* ---- adaptive methods ---------------------------------------------------- */

#include "sim_tableaus.h"

/* Two doubles in one SSE2/NEON register (GCC vector extension). */
typedef double v2d __attribute__((vector_size(16)));

static inline v2d load2(const double *p)
{
    v2d v;
    memcpy(&v, p, sizeof(v));
    return v;
}

static inline void store2(double *p, v2d v)
{
    memcpy(p, &v, sizeof(v));
}

/* v = u + h * sum_j a[j] k[j] over j < s. The loop unrolls fully, the zero
 * coefficients of the sparse tableaus fall away at compile time, and the
 * components go two by two: (x, y) and (vx, vy), then w when forced, then
 * (z, vz) when sp (spatial). */
#define STAGE_SUM(v, u, h, a, k, s, n, sp)                                    \
    do {                                                                      \
        v2d q_ = {0, 0}, p_ = {0, 0}, z_ = {0, 0};                            \
        double w_ = 0;                                                        \
        _Pragma("GCC unroll 16") for (int j_ = 0; j_ < (s); j_++)             \
            if ((a)[j_] != 0.0) {                                             \
                q_ += (a)[j_] * load2(&(k)[j_][0]);                           \
                p_ += (a)[j_] * load2(&(k)[j_][2]);                           \
                if ((n) >= 5)                                                 \
                    w_ += (a)[j_] * (k)[j_][4];                               \
                if (sp)                                                       \
                    z_ += (a)[j_] * load2(&(k)[j_][5]);                       \
            }                                                                 \
        store2(&(v)[0], load2(&(u)[0]) + (h) * q_);                           \
        store2(&(v)[2], load2(&(u)[2]) + (h) * p_);                           \
        if ((n) >= 5)                                                         \
            (v)[4] = (u)[4] + (h) * w_;                                       \
        if (sp)                                                               \
            store2(&(v)[5], load2(&(u)[5]) + (h) * z_);                       \
    } while (0)

/* 1 / (atol + tol * max(|u0|, |u1|)) per physical component: the weights of
 * Hairer's RMS error norm. */
static inline void err_weights(const struct sp_sim *sim, const double *u0, const double *u1,
                               double *w, const int spatial)
{
    for (int c = 0; c < 7; c++) {
        if (c == 4 || (c > 4 && !spatial))
            continue;
        double a = fabs(u0[c]), b = fabs(u1[c]);
        w[c] = 1 / (sim->atol[c] + sim->tol * (a > b ? a : b));
    }
}

/* Over the physical components: x, y, vx, vy, and z, vz when spatial. */
static inline double err_norm(const double *e, const double *w, const int spatial)
{
    double sum = 0;
    for (int c = 0; c < 7; c++) {
        if (c == 4 || (c > 4 && !spatial))
            continue;
        sum += (e[c] * w[c]) * (e[c] * w[c]);
    }
    return sqrt(sum / NPHYS(spatial));
}

/* Tries one Dormand-Prince 5(4) step of size h from (t1, y1) into u;
 * k[0] holds f(t1, y1). Returns the error norm (<= 1: acceptable). */
SPECIALISED double dopri5_try(struct sp_sim *sim, double h, double *u, const int forced,
                              const int spatial)
{
    const int n = NC(forced, spatial);
    double v[7], e[7];
    _Pragma("GCC unroll 6") for (int s = 1; s < 6; s++) {
        STAGE_SUM(v, sim->y1, h, dp5_a[s], sim->k, s, n, spatial);
        rhs(&sim->p, sim->t1 + dp5_c[s] * h, v, sim->k[s], forced, spatial);
    }
    STAGE_SUM(u, sim->y1, h, dp5_a[6], sim->k, 6, n, spatial);
    rhs(&sim->p, sim->t1 + h, u, sim->k[6], forced, spatial);
    STAGE_SUM(e, (double[7]){0}, h, dp5_e, sim->k, 7, 4, spatial);
    double w[7];
    err_weights(sim, sim->y1, u, w, spatial);
    return err_norm(e, w, spatial);
}

/* Tries one DOP853 step; as dopri5_try. */
SPECIALISED double dop853_try(struct sp_sim *sim, double h, double *u, const int forced,
                              const int spatial)
{
    const int n = NC(forced, spatial);
    double v[7], e5[7], e3[7];
    _Pragma("GCC unroll 12") for (int s = 1; s < 12; s++) {
        STAGE_SUM(v, sim->y1, h, d8_a[s], sim->k, s, n, spatial);
        rhs(&sim->p, sim->t1 + d8_c[s] * h, v, sim->k[s], forced, spatial);
    }
    STAGE_SUM(u, sim->y1, h, d8_a[12], sim->k, 12, n, spatial);
    rhs(&sim->p, sim->t1 + h, u, sim->k[12], forced, spatial);
    STAGE_SUM(e5, (double[7]){0}, 1.0, d8_e5, sim->k, 12, 4, spatial);
    STAGE_SUM(e3, (double[7]){0}, 1.0, d8_e3, sim->k, 12, 4, spatial);
    double w[7];
    err_weights(sim, sim->y1, u, w, spatial);
    double n5 = err_norm(e5, w, spatial), n3 = err_norm(e3, w, spatial);
    if (n5 == 0 && n3 == 0)
        return 0;
    return fabs(h) * n5 * n5 / sqrt(n5 * n5 + 0.01 * n3 * n3);
}

/* Tries one RKN12(10) step of size h from (t, y) into u (q'' = f(q): no
 * damping, no drive, so only positions enter the stages). g_s goes to
 * sim->k[s][0..1]. Returns the error norm. */
SPECIALISED double rkn_try(struct sp_sim *sim, double t, const double *y, double h,
                           double *u, const int spatial)
{
    double(*g)[7] = sim->k; /* spatial: g_z at g[s][2] */
    const v2d q0 = load2(&y[0]), v0 = load2(&y[2]);
    (void)t;
    if (spatial)
        accel_q3(&sim->p, y[0], y[1], y[5], 0, &g[0][0], &g[0][1], &g[0][2]);
    else
        accel_q(&sim->p, y[0], y[1], 0, &g[0][0], &g[0][1]);
    _Pragma("GCC unroll 17") for (int s = 1; s < 17; s++) {
        v2d acc = {0, 0}, q;
        double accz = 0;
        _Pragma("GCC unroll 16") for (int j = 0; j < s; j++)
            if (rkn_a[s][j] != 0.0) {
                acc += rkn_a[s][j] * load2(&g[j][0]);
                if (spatial)
                    accz += rkn_a[s][j] * g[j][2];
            }
        q = q0 + (rkn_c[s] * h) * v0 + (h * h) * acc;
        if (spatial)
            accel_q3(&sim->p, q[0], q[1], y[5] + (rkn_c[s] * h) * y[6] + (h * h) * accz, 0,
                     &g[s][0], &g[s][1], &g[s][2]);
        else
            accel_q(&sim->p, q[0], q[1], 0, &g[s][0], &g[s][1]);
    }
    v2d bq = {0, 0}, bv = {0, 0}, eq = {0, 0}, ev = {0, 0};
    double bqz = 0, bvz = 0, eqz = 0, evz = 0;
    _Pragma("GCC unroll 17") for (int j = 0; j < 17; j++) {
        v2d gj = load2(&g[j][0]);
        if (rkn_bhat[j] != 0.0)
            bq += rkn_bhat[j] * gj, bqz += rkn_bhat[j] * g[j][2];
        if (rkn_bphat[j] != 0.0)
            bv += rkn_bphat[j] * gj, bvz += rkn_bphat[j] * g[j][2];
        if (rkn_bhat[j] - rkn_b[j] != 0.0)
            eq += (rkn_bhat[j] - rkn_b[j]) * gj, eqz += (rkn_bhat[j] - rkn_b[j]) * g[j][2];
        if (rkn_bphat[j] - rkn_bp[j] != 0.0)
            ev += (rkn_bphat[j] - rkn_bp[j]) * gj, evz += (rkn_bphat[j] - rkn_bp[j]) * g[j][2];
    }
    store2(&u[0], q0 + h * v0 + (h * h) * bq);
    store2(&u[2], v0 + h * bv);
    u[4] = y[4];
    double e[7] = {h * h * eq[0], h * h * eq[1], h * ev[0], h * ev[1], 0, 0, 0}, w[7];
    if (spatial) {
        u[5] = y[5] + h * y[6] + (h * h) * bqz;
        u[6] = y[6] + h * bvz;
        e[5] = h * h * eqz, e[6] = h * evz;
    }
    err_weights(sim, y, u, w, spatial);
    return err_norm(e, w, spatial);
}

/* Fills sim->dense for the step [t0, t1]. */
SPECIALISED void dense_prepare(struct sp_sim *sim, const int forced, const int spatial)
{
    const int n = NC(forced, spatial);
    const double h = sim->t1 - sim->t0;
    if (sim->method == SP_METHOD_DOPRI5) {
        for (int j = 0; j < 4; j++)
            for (int c = 0; c < n; c++) {
                double acc = 0;
                for (int i = 0; i < 7; i++)
                    acc += dp5_p[i][j] * sim->k[i][c];
                sim->dense[j][c] = h * acc;
            }
    } else {
        double v[7];
        for (int s = 13; s < 16; s++) {
            STAGE_SUM(v, sim->y0, h, d8_a[s], sim->k, s, n, spatial);
            rhs(&sim->p, sim->t0 + d8_c[s] * h, v, sim->k[s], forced, spatial);
        }
        sim->evals += 3;
        for (int c = 0; c < n; c++) {
            double dy = sim->y1[c] - sim->y0[c];
            sim->dense[0][c] = dy;
            sim->dense[1][c] = h * sim->k[0][c] - dy;
            sim->dense[2][c] = 2 * dy - h * (sim->k[12][c] + sim->k[0][c]);
        }
        for (int i = 0; i < 4; i++)
            STAGE_SUM(sim->dense[3 + i], (double[7]){0}, h, d8_d[i], sim->k, 16, n, spatial);
    }
    sim->dense_ready = 1;
}

/* The interpolated state at t in [t0, t1] into u. */
SPECIALISED void dense_eval(struct sp_sim *sim, double t, double *u, const int forced,
                            const int spatial)
{
    const int n = NC(forced, spatial);
    if (!sim->dense_ready)
        dense_prepare(sim, forced, spatial);
    double x = (t - sim->t0) / (sim->t1 - sim->t0);
    for (int c = 0; c < n; c++) {
        if (sim->method == SP_METHOD_DOPRI5) {
            const double(*q)[7] = sim->dense;
            u[c] = sim->y0[c] + x * (q[0][c] + x * (q[1][c] + x * (q[2][c] + x * q[3][c])));
        } else {
            /* Hairer's contd8: alternating factors x and (1 - x) */
            double y = 0;
            for (int i = 6; i >= 0; i--) {
                y += sim->dense[i][c];
                y *= ((6 - i) % 2 == 0) ? x : 1 - x;
            }
            u[c] = sim->y0[c] + y;
        }
    }
}

/* ---- derived quantities -------------------------------------------------- */

/* sp_state_polar off the x-y plane: theta is the polar angle from the
 * downward vertical, H = hypot(x, z) the horizontal distance. */
static void polar_spatial(const struct sp_state *s, struct sp_polar *out)
{
    double H = hypot(s->x, s->z), r = sqrt(s->x * s->x + s->y * s->y + s->z * s->z);
    double H_dot = H > 0 ? (s->x * s->vx + s->z * s->vz) / H : 0;
    out->r = r;
    out->theta = atan2(H, -s->y);
    out->r_dot = r > 0 ? (s->x * s->vx + s->y * s->vy + s->z * s->vz) / r : 0;
    out->theta_dot = r > 0 ? (H * s->vy - s->y * H_dot) / (r * r) : 0;
}

void sp_state_polar(const struct sp_state *s, struct sp_polar *out)
{
    if (s->z != 0 || s->vz != 0) {
        polar_spatial(s, out);
        return;
    }
    double r = sqrt(s->x * s->x + s->y * s->y);
    out->r = r;
    out->theta = atan2(s->x, -s->y);
    out->r_dot = r > 0 ? (s->x * s->vx + s->y * s->vy) / r : 0;
    out->theta_dot = r > 0 ? (s->x * s->vy - s->y * s->vx) / (r * r) : 0;
}

void sp_state_polar_in(const struct sp_state *s, double azimuth, struct sp_polar *out)
{
    sp_state_polar(s, out);
    if (s->z == 0 && s->vz == 0) {
        if (azimuth == 0)
            return; /* atan2(x, -y) already */
        const double side = s->x < 0 ? -1 : 1; /* to the polar angle and its rate */
        out->theta *= side, out->theta_dot *= side;
    }
    /* the side of the swing plane: the horizontal position along its axis */
    const double sign = s->x * cos(azimuth) + s->z * sin(azimuth) < 0 ? -1 : 1;
    out->theta *= sign, out->theta_dot *= sign;
}

/* The equilibrium length l = L0 + m g / k, m: the one place it is
 * computed (sp_params_physics hands it out). */
static inline double equilibrium_length(const struct sp_params *p)
{
    return p->L0 + p->g / p->k_over_m;
}

void sp_state_energy(const struct sp_params *p, const struct sp_state *s,
                     struct sp_energy *out)
{
    struct sp_polar q;
    double ell = equilibrium_length(p);
    sp_state_polar(s, &q);
    if (s->z != 0 || s->vz != 0) {
        /* the swing is everything but the radial motion: the kinetic energy
         * across the spring, in the swing's plane and about the vertical */
        const double v2 = s->vx * s->vx + s->vy * s->vy + s->vz * s->vz;
        out->kinetic = 0.5 * p->mass * v2;
        out->spring = 0.5 * p->stiffness * (q.r - p->L0) * (q.r - p->L0);
        out->gravity = p->mass * p->g * s->y;
        out->total = out->kinetic + out->spring + out->gravity;
        out->bounce = 0.5 * p->mass * q.r_dot * q.r_dot +
                      0.5 * p->stiffness * (q.r - ell) * (q.r - ell);
        out->swing = 0.5 * p->mass * fmax(0, v2 - q.r_dot * q.r_dot) +
                     p->mass * p->g * (q.r + s->y);
        return;
    }
    out->kinetic = 0.5 * p->mass * (s->vx * s->vx + s->vy * s->vy);
    out->spring = 0.5 * p->stiffness * (q.r - p->L0) * (q.r - p->L0);
    out->gravity = p->mass * p->g * s->y;
    out->total = out->kinetic + out->spring + out->gravity;
    out->bounce = 0.5 * p->mass * q.r_dot * q.r_dot +
                  0.5 * p->stiffness * (q.r - ell) * (q.r - ell);
    /* r (1 - cos theta) = r + y, exact also near theta = 0 */
    out->swing = 0.5 * p->mass * q.r * q.r * q.theta_dot * q.theta_dot +
                 p->mass * p->g * (q.r + s->y);
}

void sp_state_forces(const struct sp_params *p, const struct sp_state *s,
                     struct sp_forces *out)
{
    double vp = 0, ap = 0;
    if (p->drive_amp != 0)
        pivot_motion(p, s->t, &vp, &ap);
    const double rho = sqrt(s->x * s->x + s->y * s->y + s->z * s->z);
    const double c = p->stiffness * (1 - (rho > 0 ? p->L0 / rho : 0));
    const double b = p->b_over_m * p->mass;
    *out = (struct sp_forces){
        .gravity = {0, -p->mass * p->g},
        .spring = {-c * s->x, -c * s->y},
        .damping = {-b * s->vx, -b * (s->vy + vp)},
        .drive = {0, -p->mass * ap},
    };
    for (int i = 0; i < 2; i++) {
        out->net[i] = out->gravity[i] + out->spring[i] + out->damping[i] + out->drive[i];
        out->accel[i] = out->net[i] / p->mass;
    }
}

double sp_state_angular_momentum_y(const struct sp_state *s)
{
    return s->z * s->vx - s->x * s->vz;
}

double sp_state_azimuth(const struct sp_params *p, const struct sp_state *s)
{
    const double w2 = p->g / equilibrium_length(p); /* omega_p^2, 1/s^2 */
    const double mxx = s->x * s->x + s->vx * s->vx / w2;
    const double mzz = s->z * s->z + s->vz * s->vz / w2;
    const double mxz = s->x * s->z + s->vx * s->vz / w2;
    if (!(w2 > 0) || (mxz == 0 && mxx == mzz))
        return 0;
    double a = 0.5 * atan2(2 * mxz, mxx - mzz);
    return a <= -M_PI / 2 ? a + M_PI : a;
}

double sp_azimuth_unwrap(double prev, double a)
{
    return a + M_PI * round((prev - a) / M_PI);
}

double sp_pivot_y(const struct sp_params *p, double t)
{
    return p->drive_amp * sin(p->drive_omega * t);
}

void sp_params_physics(const struct sp_params *p, struct sp_physics *out)
{
    out->ell = equilibrium_length(p);
    out->omega_s = sqrt(p->k_over_m);
    out->omega_p = sqrt(p->g / out->ell);
    out->ratio = out->omega_s / out->omega_p;
}

double sp_params_omega_max(const struct sp_params *p)
{
    struct sp_physics ph;
    sp_params_physics(p, &ph);
    double w = ph.omega_s;
    if (ph.omega_p > w)
        w = ph.omega_p;
    if (p->b_over_m > w)
        w = p->b_over_m;
    return w;
}

/* ---- set-up and the guard ------------------------------------------------ */

static void to_state(double t, const double *u, struct sp_state *s)
{
    *s = (struct sp_state){.t = t, .x = u[0], .y = u[1], .vx = u[2], .vy = u[3],
                           .z = u[5], .vz = u[6]};
}

/* Hairer's starting step for an adaptive method of the given order. */
static double initial_step(struct sp_sim *sim, int order)
{
    double d0 = 0, d1 = 0, d2 = 0, u[7] = {0}, f1[7];
    const double *y = sim->y1, *f0 = sim->k[0];
    const int sp = sim->spatial, nphys = NPHYS(sp);
    for (int c = 0; c < 7; c++) {
        if (c == 4 || (c > 4 && !sp))
            continue;
        double sc = sim->atol[c] + sim->tol * fabs(y[c]);
        d0 += (y[c] / sc) * (y[c] / sc);
        d1 += (f0[c] / sc) * (f0[c] / sc);
    }
    d0 = sqrt(d0 / nphys), d1 = sqrt(d1 / nphys);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    for (int c = 0; c < (sp ? 7 : 5); c++)
        u[c] = y[c] + h0 * f0[c];
    if (sp)
        rhs(&sim->p, sim->t1 + h0, u, f1, 1, 1);
    else
        rhs(&sim->p, sim->t1 + h0, u, f1, 1, 0);
    sim->evals++;
    for (int c = 0; c < 7; c++) {
        if (c == 4 || (c > 4 && !sp))
            continue;
        double sc = sim->atol[c] + sim->tol * fabs(y[c]);
        d2 += ((f1[c] - f0[c]) / sc) * ((f1[c] - f0[c]) / sc);
    }
    d2 = sqrt(d2 / nphys) / h0;
    double dm = fmax(d1, d2);
    double h1 = dm <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : pow(0.01 / dm, 1.0 / (order + 1));
    return fmin(100 * h0, h1);
}

/* The energy of the motion in a state of total energy `total` whose terms
 * add up to `size` in magnitude, J: total - energy_min, and never below the
 * rounding of its terms or of the scene's energy scales (a bob at rest has
 * none: hanging still at l, or at L0 without gravity). */
static double motion_energy(const struct sp_sim *sim, double total, double size)
{
    const double L0 = sim->p.L0;
    return fmax(total - sim->energy_min,
                1e-12 * (size + fabs(sim->energy_min) + sim->p.stiffness * L0 * L0));
}

void sp_sim_init(struct sp_sim *sim, const struct sp_scene *scene)
{
    const double r = scene->initial.length, th = scene->initial.angle;
    const double rd = scene->initial.length_rate, thd = scene->initial.angle_rate;
    const double phd = scene->initial.azimuth_rate;
    struct sp_energy e;
    memset(sim, 0, sizeof(*sim));
    sim->scene = scene;
    sim->p = (struct sp_params){
        .k_over_m = scene->pendulum.stiffness / scene->pendulum.mass,
        .L0 = scene->pendulum.natural_length,
        .g = scene->pendulum.gravity,
        .b_over_m = scene->pendulum.damping / scene->pendulum.mass,
        .mass = scene->pendulum.mass,
        .stiffness = scene->pendulum.stiffness,
        .drive_amp = scene->pivot.amplitude,
        .drive_omega = 2 * M_PI * scene->pivot.frequency,
    };
    if (sim->p.drive_omega == 0)
        sim->p.drive_amp = 0; /* a pivot displaced but at rest is no drive */
    sim->s = (struct sp_state){
        .t = 0,
        .x = r * sin(th),
        .y = -r * cos(th),
        .vx = rd * sin(th) + r * thd * cos(th),
        .vy = -rd * cos(th) + r * thd * sin(th),
        /* phi' = (x vz - z vx) / (x^2 + z^2) with z = 0 at the start */
        .vz = phd * r * sin(th),
    };
    sim->spatial = sim->s.vz != 0;
    sim->method = scene->integrator.method;
    sim->dt = scene->integrator.dt;
    sim->tol = scene->integrator.tolerance;
    sim->forced = sim->p.b_over_m != 0 || sim->p.drive_amp != 0;
    /* the scene refuses this pairing; a scene built in code gets dop853 */
    if (sim->forced && sim->method == SP_METHOD_RKN1210)
        sim->method = SP_METHOD_DOP853;
    sp_state_energy(&sim->p, &sim->s, &e);
    sim->energy0 = e.total;
    /* Drift is judged against the energy of the motion, what can move: the
     * energy above the least the scene can hold (hanging still at ell), not
     * offsets such as k L0^2 / 2 that cancel out of every difference. */
    double ell = equilibrium_length(&sim->p);
    const double mg = sim->p.mass * sim->p.g;
    sim->energy_min = -mg * sim->p.L0 - 0.5 * mg * mg / sim->p.stiffness;
    sim->energy_scale = motion_energy(sim, e.total, fabs(e.kinetic) + fabs(e.spring) +
                                      fabs(e.gravity));
    sim->drift_limit = SP_SIM_DRIFT_LIMIT;
    sim->y1[0] = sim->s.x, sim->y1[1] = sim->s.y;
    sim->y1[2] = sim->s.vx, sim->y1[3] = sim->s.vy;
    sim->y1[5] = sim->s.z, sim->y1[6] = sim->s.vz;
    memcpy(sim->y0, sim->y1, sizeof(sim->y0));
    force_at(&sim->p, 0, sim->y1, sim->force, sim->spatial);
    if (sp_method_info(sim->method)->adaptive) {
        /* absolute tolerances from the scene's length and speed scales */
        double len = fmax(fmax(ell, r), sim->p.L0);
        /* a speed from the energies the motion trades between */
        double energies = fabs(e.kinetic) + fabs(e.spring) + fabs(e.gravity) + mg * ell +
                          0.5 * sim->p.stiffness * sim->p.L0 * sim->p.L0;
        double speed = sqrt(2 * energies / sim->p.mass);
        sim->atol[0] = sim->atol[1] = sim->atol[5] = sim->tol * len;
        sim->atol[2] = sim->atol[3] = sim->atol[6] = sim->tol * speed;
        if (sim->spatial)
            rhs(&sim->p, 0, sim->y1, sim->k[0], 1, 1);
        else
            rhs(&sim->p, 0, sim->y1, sim->k[0], 1, 0);
        sim->evals = 1;
        sim->h = initial_step(sim, sp_method_info(sim->method)->order);
    }
}

/* Records what went wrong and when, for the caller to word. */
static int unstable(struct sp_sim *sim, const struct sp_state *s, double energy, const char *what)
{
    sim->failure.s = *s;
    sim->failure.energy = energy;
    snprintf(sim->failure.what, sizeof(sim->failure.what), "%s", what);
    sim->failure.pass_distance = sim->failure.pass_speed = NAN;
    return SP_E_UNSTABLE;
}

/* 0 if state u at time t is finite and its energy balance plausible, else
 * the report. */
static int check_state(struct sp_sim *sim, double t, const double *u)
{
    struct sp_state s;
    /* The caller's cancel flag (a signal) stops a long integration (a still
     * far in the future, the camera pre-pass); callers decide what to keep. */
    if (sim->cancel && *sim->cancel)
        return SP_E_INTERRUPTED;
    if (sim->progress)
        sim->progress(sim->progress_ctx, t);
    to_state(t, u, &s);
    if (!isfinite(u[0]) || !isfinite(u[1]) || !isfinite(u[2]) || !isfinite(u[3]) ||
        !isfinite(u[4]) || !isfinite(u[5]) || !isfinite(u[6]))
        return unstable(sim, &s, NAN, "the state is no longer finite");
    /* the three energies, as sp_state_energy has them, without the polar
     * form it needs for bounce and swing (this runs after every step) */
    const struct sp_params *p = &sim->p;
    double stretch, kin;
    if (sim->spatial) {
        stretch = sqrt(u[0] * u[0] + u[1] * u[1] + u[5] * u[5]) - p->L0;
        kin = 0.5 * p->mass * (u[2] * u[2] + u[3] * u[3] + u[6] * u[6]);
    } else {
        stretch = sqrt(u[0] * u[0] + u[1] * u[1]) - p->L0;
        kin = 0.5 * p->mass * (u[2] * u[2] + u[3] * u[3]);
    }
    double spring = 0.5 * p->stiffness * stretch * stretch, grav = p->mass * p->g * u[1];
    double total = kin + spring + grav, work = p->mass * u[4];
    /* the largest the motion has been: a drive may pump it up, damping drain
     * it, and what was integrated carries the error made at its peak */
    double scale = fmax(sim->energy_scale, motion_energy(sim, total, kin + spring + fabs(grav)));
    double drift = (total - sim->energy0 - work) / scale;
    if (!(fabs(drift) <= sim->drift_limit)) {
        char what[128];
        snprintf(what, sizeof(what), "energy, less the work of damping and drive, "
                 "drifted by %.3g%% of its scale %.3g J", 100 * drift, scale);
        sim->work = work;
        return unstable(sim, &s, total, what);
    }
    sim->energy_scale = scale;
    return 0;
}

/* ---- advancing ----------------------------------------------------------- */

/* After a failed check at time t_fail: replays the steps from the last
 * state that passed, (n_ok dt, u_ok), as advance_fixed took them, and records
 * in sim->failure the closest the bob came to the pivot on the chords of the
 * steps that took it past the pivot (its direction from the pivot turned by
 * more than 90 degrees within the step), and its speed there. Such a pass,
 * where the spring's push turns round within less than a step, is what a
 * fixed step cannot follow (sim_report.c words it). */
SPECIALISED void find_pass(struct sp_sim *sim, long n_ok, const double *u_ok, double t_fail,
                           const int forced, const int spatial)
{
    double u[7], a[4], dist = INFINITY, speed = NAN;
    long n = n_ok;
    memcpy(u, u_ok, sizeof(u));
    force_at(&sim->p, (double)n * sim->dt, u, a, spatial);
    for (double t = (double)n * sim->dt; t < t_fail;) {
        const double t_next = fmin((double)(n + 1) * sim->dt, t_fail);
        const double q0[3] = {u[0], u[1], u[5]};
        fixed_step(sim, t, u, t_next - t, a, forced, spatial);
        /* the point of the chord q0 -> q1 nearest the pivot (z is 0 in the
         * plane, and adds nothing) */
        const double dx = u[0] - q0[0], dy = u[1] - q0[1], dz = u[5] - q0[2];
        const double len2 = dx * dx + dy * dy + dz * dz;
        const double f = len2 > 0 ? fmin(1, fmax(0, -(q0[0] * dx + q0[1] * dy + q0[2] * dz) /
                                                         len2)) : 0;
        const double d = spatial ? sqrt((q0[0] + f * dx) * (q0[0] + f * dx) +
                                        (q0[1] + f * dy) * (q0[1] + f * dy) +
                                        (q0[2] + f * dz) * (q0[2] + f * dz))
                                 : hypot(q0[0] + f * dx, q0[1] + f * dy);
        if (q0[0] * u[0] + q0[1] * u[1] + q0[2] * u[5] < 0 && d < dist)
            dist = d, speed = sqrt(len2) / (t_next - t);
        t = t_next;
        n++;
    }
    sim->failure.pass_distance = isfinite(dist) ? dist : NAN;
    sim->failure.pass_speed = speed;
}

/* Fixed-step methods: walk the grid to the last point <= t_target, then one
 * short step from a copy to t_target. */
SPECIALISED int advance_fixed(struct sp_sim *sim, double t_target, const int forced,
                              const int spatial)
{
    double u[7], a[4], u_ok[7];
    long n = lround(sim->t1 / sim->dt), n_ok = n;
    const int check_every = sim->method == SP_METHOD_VERLET ? 8 : 4;
    memcpy(u, sim->y1, sizeof(u));
    memcpy(u_ok, u, sizeof(u));
    memcpy(a, sim->force, sizeof(a));
    while ((double)(n + 1) * sim->dt <= t_target) {
        sim->evals += fixed_step(sim, (double)n * sim->dt, u, sim->dt, a, forced, spatial);
        n++;
        sim->steps++;
        if (sim->steps % check_every == 0 || !isfinite(u[0] + u[1] + u[2] + u[3]) ||
            (spatial && !isfinite(u[5] + u[6]))) {
            int ret = check_state(sim, (double)n * sim->dt, u);
            if (ret) {
                to_state((double)n * sim->dt, u, &sim->s);
                if (ret == SP_E_UNSTABLE)
                    find_pass(sim, n_ok, u_ok, (double)n * sim->dt, forced, spatial);
                return ret;
            }
            n_ok = n;
            memcpy(u_ok, u, sizeof(u));
        }
    }
    sim->t1 = (double)n * sim->dt;
    memcpy(sim->y1, u, sizeof(u));
    memcpy(sim->force, a, sizeof(a));
    if (t_target > sim->t1)
        sim->evals += fixed_step(sim, sim->t1, u, t_target - sim->t1, a, forced, spatial);
    int ret = check_state(sim, t_target, u);
    to_state(t_target, u, &sim->s);
    sim->work = sim->p.mass * u[4];
    if (ret == SP_E_UNSTABLE)
        find_pass(sim, n_ok, u_ok, t_target, forced, spatial);
    return ret;
}

/* Accepts an adaptive step of h from (t1, y1) to u: the step window moves
 * on, the next step is h * fac (not grown right after a rejection), and the
 * new state is checked. Returns check_state's verdict. */
static int accept_step(struct sp_sim *sim, double h, double fac, const double u[7])
{
    if (sim->last_rejected)
        fac = fmin(fac, 1);
    sim->last_rejected = 0;
    sim->t0 = sim->t1;
    memcpy(sim->y0, sim->y1, sizeof(sim->y0));
    sim->t1 += h;
    memcpy(sim->y1, u, sizeof(sim->y1));
    sim->h = h * fac;
    sim->steps++;
    int ret = check_state(sim, sim->t1, sim->y1);
    if (ret)
        to_state(sim->t1, sim->y1, &sim->s);
    return ret;
}

/* err^(-1/(order+1)) for the step-size controller: for dop853 (-1/8) three
 * square roots, cheaper than pow. */
static inline double step_factor(double err, const int d853)
{
    return d853 ? 1 / sqrt(sqrt(sqrt(err))) : pow(err, -0.2);
}

/* The adaptive step fell below what double precision resolves at t1 (about
 * 1e-14 t): the tolerance cannot be met here. Records it with the state and
 * its (finite) energy; sim->s is that state. */
static int report_step_collapse(struct sp_sim *sim, double h)
{
    struct sp_energy e;
    char what[200];
    to_state(sim->t1, sim->y1, &sim->s);
    sp_state_energy(&sim->p, &sim->s, &e);
    snprintf(what, sizeof(what), "the step size fell to %.3g s, under the %.3g s that double "
             "precision resolves at this time: tolerance %g cannot be met here", h,
             1e-14 * fmax(1, fabs(sim->t1)), sim->tol);
    return unstable(sim, &sim->s, e.total, what);
}

/* Adaptive methods: accepted steps until t1 >= t_target, then dense output. */
SPECIALISED int advance_adaptive(struct sp_sim *sim, double t_target, const int forced,
                                 const int spatial)
{
    const int d853 = sim->method == SP_METHOD_DOP853;
    const int fsal = d853 ? 12 : 6;
    const double fac_min = d853 ? 0.333 : 0.2, fac_max = d853 ? 6 : 10;
    double u[7] = {0}; /* u[4] stays 0 when not forced, u[5..6] when planar */
    while (sim->t1 < t_target) {
        double h = sim->h, err;
        if (sim->steps > 0 || sim->rejected > 0)
            memcpy(sim->k[0], sim->k[fsal], sizeof(sim->k[0]));
        for (;;) {
            if (!(h > 1e-14 * fmax(1, fabs(sim->t1))))
                return report_step_collapse(sim, h);
            err = d853 ? dop853_try(sim, h, u, forced, spatial)
                       : dopri5_try(sim, h, u, forced, spatial);
            sim->evals += d853 ? 12 : 6;
            if (err <= 1)
                break;
            /* a NaN error also lands here: shrink and retry */
            h *= isfinite(err) ? fmax(fac_min, 0.9 * step_factor(err, d853)) : fac_min;
            sim->rejected++;
            sim->last_rejected = 1;
        }
        double fac = err == 0 ? fac_max : fmin(fac_max, fmax(fac_min, 0.9 * step_factor(err, d853)));
        sim->dense_ready = 0;
        int ret = accept_step(sim, h, fac, u);
        if (ret)
            return ret;
    }
    if (t_target == sim->t1)
        memcpy(u, sim->y1, sizeof(u));
    else
        dense_eval(sim, t_target, u, forced, spatial);
    int ret = check_state(sim, t_target, u);
    to_state(t_target, u, &sim->s);
    sim->work = sim->p.mass * u[4];
    return ret;
}

/* RKN12(10): accepted steps until t1 >= t_target; a time inside the last
 * step is reached by one extra step from its start (17 evaluations, and
 * the step sequence stays what the error control chose). */
SPECIALISED int advance_rkn(struct sp_sim *sim, double t_target, const int spatial)
{
    double u[7] = {0};
    while (sim->t1 < t_target) {
        double h = sim->h, err;
        for (;;) {
            if (!(h > 1e-14 * fmax(1, fabs(sim->t1))))
                return report_step_collapse(sim, h);
            err = rkn_try(sim, sim->t1, sim->y1, h, u, spatial);
            sim->evals += 17;
            if (err <= 1)
                break;
            h *= isfinite(err) ? fmax(0.2, 0.9 * pow(err, -1.0 / 11)) : 0.2;
            sim->rejected++;
            sim->last_rejected = 1;
        }
        double fac = err == 0 ? 5 : fmin(5, fmax(0.2, 0.9 * pow(err, -1.0 / 11)));
        int ret = accept_step(sim, h, fac, u);
        if (ret)
            return ret;
    }
    if (t_target == sim->t1) {
        memcpy(u, sim->y1, sizeof(u));
    } else {
        rkn_try(sim, sim->t0, sim->y0, t_target - sim->t0, u, spatial);
        sim->evals += 17;
    }
    int ret = check_state(sim, t_target, u);
    to_state(t_target, u, &sim->s);
    return ret;
}

/* The four specialisations of each stepper: forced or not, planar or not. */
#define SPECIALISE(call_, sim_, t_, ...)                                              \
    ((sim_)->spatial ? ((sim_)->forced ? call_(sim_, t_, ##__VA_ARGS__, 1, 1)          \
                                       : call_(sim_, t_, ##__VA_ARGS__, 0, 1))         \
                     : ((sim_)->forced ? call_(sim_, t_, ##__VA_ARGS__, 1, 0)          \
                                       : call_(sim_, t_, ##__VA_ARGS__, 0, 0)))

int sp_sim_advance(struct sp_sim *sim, double t_target)
{
    if (sim->method == SP_METHOD_RKN1210)
        return sim->spatial ? advance_rkn(sim, t_target, 1) : advance_rkn(sim, t_target, 0);
    if (sp_method_info(sim->method)->adaptive)
        return SPECIALISE(advance_adaptive, sim, t_target);
    return SPECIALISE(advance_fixed, sim, t_target);
}

/* A probe takes at most about this many steps: past them, what it took to
 * the time it reached is scaled to t_end, so that a drive far faster than
 * the pendulum or a step set by a huge stiffness keeps it to milliseconds
 * (attack19 #1: one probe took 20 s). */
#define PROBE_STEPS 20000

double sp_sim_estimate_steps(const struct sp_scene *scene, double t_end,
                             const volatile sig_atomic_t *cancel)
{
    struct sp_sim sim;
    if (!sp_method_info(scene->integrator.method)->adaptive)
        return t_end / scene->integrator.dt;
    sp_sim_init(&sim, scene);
    sim.cancel = cancel;
    /* 100 radians of the fastest motion: the pendulum's, the damping's or
     * the pivot's drive */
    const double w = fmax(sp_params_omega_max(&sim.p),
                          sim.p.drive_amp != 0 ? fabs(sim.p.drive_omega) : 0);
    const double t_probe = fmin(t_end, 100 / w);
    if (!(t_probe > 0))
        return 0;
    /* spans doubling up to t_probe from 2^-12 of it: each takes about as
     * many steps as all before it, so the bound is passed by at most twice */
    double t = 0;
    for (int k = 12; k >= 0; k--) {
        t = ldexp(t_probe, -k);
        if (sp_sim_advance(&sim, t))
            return 0;
        if (sim.steps + sim.rejected > PROBE_STEPS)
            break;
    }
    return (double)(sim.steps + sim.rejected) * (t_end / t);
}
