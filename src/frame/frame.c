/* springpend: the frame model: the trail ring buffer and the view extent
 * found by a physics pre-pass. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

#include "springpend/advice.h"
#include "springpend/common.h"
#include "springpend/frame.h"
#include "base/array.h"
#include "sim/sim_report.h"

int sp_trail_make(struct sp_trail *tr, int capacity)
{
    *tr = (struct sp_trail){0};
    if (capacity <= 0)
        return 0;
    tr->points = calloc((size_t)capacity, sizeof(*tr->points));
    if (!tr->points) {
        sp_log_error("out of memory for a trail of %d points", capacity);
        return SP_E_NOMEM;
    }
    tr->capacity = capacity;
    return 0;
}

void sp_trail_destroy(struct sp_trail *tr)
{
    free(tr->points);
    *tr = (struct sp_trail){0};
}

void sp_trail_push(struct sp_trail *tr, const struct sp_state *s)
{
    sp_trail_push_at(tr, s, 0);
}

void sp_trail_push_at(struct sp_trail *tr, const struct sp_state *s, double pivot_y)
{
    if (tr->capacity == 0)
        return;
    tr->points[tr->head] = (struct sp_trail_point){
        .x = (float)s->x,
        .y = (float)(s->y + pivot_y),
        .z = (float)s->z,
        .speed = (float)sqrt(s->vx * s->vx + s->vy * s->vy + s->vz * s->vz),
        .t = s->t,
    };
    tr->head = (tr->head + 1) % tr->capacity;
    if (tr->count < tr->capacity)
        tr->count++;
}

int sp_trail_follow(struct sp_trail *tr, struct sp_history *h, struct sp_sim *sim,
                    double t_target, int substeps)
{
    const double t0 = sim->s.t;
    int err = 0;
    if (substeps < 1 || t_target <= t0)
        substeps = 1;
    for (int i = 1; i <= substeps && !err; i++) {
        err = sp_history_follow(h, sim, i == substeps ? t_target : t0 + (t_target - t0) * i / substeps);
        if (!err)
            sp_trail_push_at(tr, &sim->s, sp_pivot_y(&sim->p, sim->s.t));
    }
    return err;
}

int sp_trail_substeps(double dt, double accel, double px_per_m)
{
    /* a h^2 / 8 * px_per_m <= 0.5  <=>  h <= 2 / sqrt(a px_per_m) */
    const double n = ceil(dt * sqrt(fmax(accel, 0) * fmax(px_per_m, 0)) / 2 - 1e-9);
    return !(n > 1) ? 1 : n > 64 ? 64 : (int)n;
}

const struct sp_trail_point *sp_trail_at(const struct sp_trail *tr, int i)
{
    int oldest = tr->count < tr->capacity ? 0 : tr->head;
    return &tr->points[(oldest + i) % tr->capacity];
}

static void widen(struct sp_range *g, double v)
{
    g->lo = fmin(g->lo, v);
    g->hi = fmax(g->hi, v);
}

void sp_look_of(const struct sp_scene *scene, struct sp_look *out)
{
    struct sp_scene defaults;
    if (!scene) {
        sp_scene_defaults(&defaults);
        scene = &defaults;
    }
    *out = (struct sp_look){.view = scene->view, .fps = scene->video.fps,
                            .speed = scene->video.speed,
                            .ensemble_count = scene->ensemble.count,
                            .timeline = scene->timeline,
                            .perspective = sp_scene_perspective(scene),
                            .spatial = scene->initial.azimuth_rate != 0};
    if (scene->view.hud) {
        struct sp_sim sim;
        sp_sim_init(&sim, scene);
        sp_advise_predict(&sim.p, &sim.s, sim.spatial, &out->predict);
    }
}

/* W: the power damping takes from the bob in state s (b |v_air|^2, the air
 * at rest in the lab; vz in 3-D); 0 without damping. */
static double damping_power(const struct sp_params *p, const struct sp_state *s)
{
    if (p->b_over_m <= 0)
        return 0;
    const double vy = s->vy + p->drive_amp * p->drive_omega * cos(p->drive_omega * s->t);
    return p->b_over_m * p->mass * (s->vx * s->vx + vy * vy + s->vz * s->vz);
}

/* Widens out's largest force (of the arrows in `vectors`, SP_VECTOR_*) and
 * acceleration with those of the bob in state s. N, m/s^2. */
static void extent_forces(const struct sp_params *p, const struct sp_state *s, unsigned vectors,
                          struct sp_view_extent *out)
{
    struct sp_forces fo;
    sp_state_forces(p, s, &fo);
    const double *each[] = {fo.gravity, fo.spring, fo.damping, fo.drive, fo.net};
    const unsigned bit[] = {SP_VECTOR_GRAVITY, SP_VECTOR_SPRING, SP_VECTOR_DAMPING,
                            SP_VECTOR_DRIVE, SP_VECTOR_NET};
    for (int i = 0; i < 5; i++)
        if (vectors & bit[i])
            out->max_force = fmax(out->max_force, hypot(each[i][0], each[i][1]));
    out->max_accel = fmax(out->max_accel, hypot(fo.accel[0], fo.accel[1]));
}

int sp_view_extent_measure(const struct sp_scene *scene, double t_end,
                           const volatile sig_atomic_t *cancel,
                           void (*progress)(void *ctx, double t), void *progress_ctx,
                           struct sp_view_extent *out)
{
    struct sp_sim sim;
    sp_sim_init(&sim, scene);
    sim.cancel = cancel;
    sim.progress = progress;
    sim.progress_ctx = progress_ctx;
    *out = (struct sp_view_extent){.t_end = t_end};
    out->r = out->theta = out->r_dot = out->theta_dot = out->energy = out->modes =
        (struct sp_range){INFINITY, -INFINITY};
    const unsigned vectors = scene->view.vectors;
    const int bars = (scene->view.panels & SP_PANEL_ENERGY_BARS) != 0;
    /* the charts of energy take gravity's zero at the lowest point too */
    const int low = (scene->view.panels & (SP_PANEL_ENERGY | SP_PANEL_ENERGY_BARS)) != 0;
    const double mg = sim.p.mass * sim.p.g;
    struct sp_range kin = {0, 0}, grav = {INFINITY, -INFINITY}, tot = {INFINITY, -INFINITY};
    struct sp_range ks = {INFINITY, -INFINITY}; /* J: kinetic and spring, for the chart */
    struct sp_range work = {0, 0};
    double loss = 0; /* J: lost to damping, trapezoid over the steps */
    out->y_low = INFINITY;
    out->azimuth = (struct sp_range){0, 0};
    double azimuth = 0; /* rad, continued from step to step */
    /* Sample every step: the camera must hold every position the bob takes. */
    for (;;) {
        const struct sp_state *s = &sim.s;
        double v = sqrt(s->vx * s->vx + s->vy * s->vy + s->vz * s->vz);
        const double yp = sp_pivot_y(&sim.p, s->t); /* the bob in the lab: y + yp */
        out->xmin = fmin(out->xmin, s->x);
        out->xmax = fmax(out->xmax, s->x);
        out->ymin = fmin(out->ymin, fmin(s->y + yp, yp));
        out->ymax = fmax(out->ymax, fmax(s->y + yp, yp));
        out->zmin = fmin(out->zmin, s->z);
        out->zmax = fmax(out->zmax, s->z);
        out->max_speed = fmax(out->max_speed, v);
        if (vectors)
            extent_forces(&sim.p, s, vectors, out);
        if (scene->view.panels) {
            struct sp_polar pol;
            struct sp_energy e;
            if (sim.spatial) {
                azimuth = sp_azimuth_unwrap(azimuth, sp_state_azimuth(&sim.p, s));
                widen(&out->azimuth, azimuth);
            }
            sp_state_polar_in(s, azimuth, &pol); /* the theta panel shows data's theta */
            sp_state_energy(&sim.p, s, &e);
            widen(&out->r, pol.r);
            widen(&out->theta, pol.theta);
            if (sim.spatial) /* the panel's samples may take the plane's other side */
                widen(&out->theta, -pol.theta);
            widen(&out->r_dot, pol.r_dot);
            widen(&out->theta_dot, pol.theta_dot);
            widen(&ks, e.kinetic);
            widen(&ks, e.spring);
            widen(&grav, e.gravity);
            widen(&tot, e.total);
            widen(&out->modes, e.bounce);
            widen(&out->modes, e.swing);
            if (low)
                out->y_low = fmin(out->y_low, s->y);
            if (bars) {
                widen(&kin, fmax(fmax(e.kinetic, e.spring), fmax(e.bounce, e.swing)));
                if (sim.p.drive_amp != 0)
                    widen(&work, sim.work + loss); /* the drive's work */
                widen(&work, loss);                /* the loss to damping */
            }
            out->horizontal = fmax(out->horizontal, fmax(fabs(s->x), fabs(s->z)));
        }
        if (s->t >= t_end)
            break;
        const double t0 = s->t, power = bars ? damping_power(&sim.p, s) : 0;
        int ret = sp_sim_advance(&sim, fmin(t_end, s->t + sim.dt));
        if (ret == SP_E_UNSTABLE)
            sp_sim_explain(&sim);
        if (ret)
            return ret;
        if (bars)
            loss += 0.5 * (s->t - t0) * (power + damping_power(&sim.p, s));
    }
    if (!low || !(out->y_low < INFINITY))
        out->y_low = 0;
    /* gravity from the lowest point: no bar below zero but the drive's work */
    const double shift = mg * out->y_low;
    if (bars)
        out->bars = (struct sp_range){fmin(0, work.lo), fmax(fmax(kin.hi, grav.hi - shift),
                                                             fmax(tot.hi - shift, work.hi))};
    if (scene->view.panels)
        out->energy = (struct sp_range){fmin(ks.lo, fmin(grav.lo, tot.lo) - shift),
                                        fmax(ks.hi, fmax(grav.hi, tot.hi) - shift)};
    if (out->max_speed <= 0)
        out->max_speed = 1;
    return 0;
}

/* ---- panel histories ---- */

int sp_history_make(struct sp_history *h, const struct sp_scene *scene)
{
    *h = (struct sp_history){0};
    h->measure = scene->view.hud && scene->initial.azimuth_rate != 0;
    h->active = scene->view.panels != 0 || scene->view.strobe > 0 || h->measure;
    h->poincare = (scene->view.panels & SP_PANEL_POINCARE) != 0;
    return 0;
}

void sp_history_destroy(struct sp_history *h)
{
    free(h->samples);
    free(h->crossings);
    *h = (struct sp_history){0};
}

/* Makes room for one more element; 0 or SP_E_NOMEM (logged). */
static int grow(void **items, int *cap, int used, size_t size, const char *what)
{
    size_t room = (size_t)*cap;
    if (sp_array_reserve(items, size, &room, (size_t)used + 1, 1024, INT_MAX)) {
        sp_log_error("out of memory for %d %s", used + 1, what);
        return SP_E_NOMEM;
    }
    *cap = (int)room;
    return 0;
}

/* The bob's acceleration relative to the pivot, m/s^2: the equations of
 * motion of sim.h, moving pivot and damping (against the air at rest)
 * included. */
static void accel_of(const struct sp_params *p, const struct sp_state *s, double a[2])
{
    const double rho = sqrt(s->x * s->x + s->y * s->y);
    const double f = p->k_over_m * (1 - (rho > 0 ? p->L0 / rho : 0));
    const double w = p->drive_omega * s->t;
    const double vp = p->drive_amp * p->drive_omega * cos(w);
    const double ap = -p->drive_amp * p->drive_omega * p->drive_omega * sin(w);
    a[0] = -f * s->x - p->b_over_m * s->vx;
    a[1] = -f * s->y - p->g - ap - p->b_over_m * (s->vy + vp);
}

/* Quintic Hermite interpolant on [0, 1] of a coordinate with values q,
 * derivatives dq and second derivatives ddq (per unit time) at both ends of
 * an interval of length h: value and time derivative at u. */
static void hermite5(const double q[2], const double dq[2], const double ddq[2], double h,
                     double u, double *val, double *der)
{
    const double u2 = u * u, u3 = u2 * u, u4 = u3 * u, u5 = u4 * u;
    const double h0 = 1 - 10 * u3 + 15 * u4 - 6 * u5, h5 = 1 - h0;
    const double h1 = u - 6 * u3 + 8 * u4 - 3 * u5, h4 = -4 * u3 + 7 * u4 - 3 * u5;
    const double h2 = 0.5 * (u2 - 3 * u3 + 3 * u4 - u5), h3 = 0.5 * (u3 - 2 * u4 + u5);
    const double d0 = -30 * u2 + 60 * u3 - 30 * u4;
    const double d1 = 1 - 18 * u2 + 32 * u3 - 15 * u4, d4 = -12 * u2 + 28 * u3 - 15 * u4;
    const double d2 = u - 4.5 * u2 + 6 * u3 - 2.5 * u4, d3 = 1.5 * u2 - 4 * u3 + 2.5 * u4;
    *val = h0 * q[0] + h5 * q[1] + h * (h1 * dq[0] + h4 * dq[1]) + h * h * (h2 * ddq[0] + h3 * ddq[1]);
    *der = (d0 * q[0] - d0 * q[1]) / h + d1 * dq[0] + d4 * dq[1] + h * (d2 * ddq[0] + d3 * ddq[1]);
}

/* Adds the crossing of x = 0 from x < 0 (below the pivot), if any, between
 * states a and b of the same motion. 0 or SP_E_NOMEM. */
static int find_crossing(struct sp_history *h, const struct sp_params *p,
                         const struct sp_state *a, const struct sp_state *b)
{
    double aa[2], ab[2], lo = 0, hi = 1, x, y, vx, vy;
    const double dt = b->t - a->t;
    int err;

    /* theta = 0 is x = 0 below the pivot; theta' > 0 there means x grows. */
    if (!(a->x < 0 && b->x >= 0) || (a->y >= 0 && b->y >= 0) || dt <= 0)
        return 0;
    accel_of(p, a, aa);
    accel_of(p, b, ab);
    const double qx[2] = {a->x, b->x}, vqx[2] = {a->vx, b->vx}, ax[2] = {aa[0], ab[0]};
    const double qy[2] = {a->y, b->y}, vqy[2] = {a->vy, b->vy}, ay[2] = {aa[1], ab[1]};
    for (int i = 0; i < 60; i++) { /* bisection: x(lo) < 0 <= x(hi) */
        const double mid = 0.5 * (lo + hi);
        hermite5(qx, vqx, ax, dt, mid, &x, &vx);
        if (x < 0)
            lo = mid;
        else
            hi = mid;
    }
    hermite5(qx, vqx, ax, dt, hi, &x, &vx);
    hermite5(qy, vqy, ay, dt, hi, &y, &vy);
    if (y >= 0 || vx <= 0)
        return 0;
    err = grow((void **)&h->crossings, &h->cap_crossings, h->n_crossings,
               sizeof(*h->crossings), "Poincare points");
    if (err)
        return err;
    /* At x = 0: r = |y| = -y, r' = (x vx + y vy) / r = -vy,
     * theta' = (x vy - y vx) / r^2 = vx / r. */
    h->crossings[h->n_crossings++] = (struct sp_crossing){a->t + hi * dt, -y, -vy, vx / -y};
    return 0;
}

/* Feeds the newest sample to h's precession meter (struct
 * sp_precession_meter); p: the run's parameters. */
static void meter_push(struct sp_history *h, const struct sp_params *p)
{
    struct sp_precession_meter *m = &h->meter;
    const struct sp_history_sample *s = h->samples;
    const int n = h->count - 1;
    if (n == 0) {
        struct sp_physics ph;
        sp_params_physics(p, &ph);
        *m = (struct sp_precession_meter){.window = ph.omega_p > 0 ? 2 * M_PI / ph.omega_p : 0};
        return;
    }
    if (!(m->window > 0))
        return;
    m->sum += 0.5 * ((double)s[n - 1].swing + s[n].swing) * ((double)s[n].t - s[n - 1].t);
    while (m->lo + 1 < n && (double)s[n].t - s[m->lo + 1].t >= m->window) {
        m->sum -= 0.5 * ((double)s[m->lo].swing + s[m->lo + 1].swing) *
                  ((double)s[m->lo + 1].t - s[m->lo].t);
        m->lo++;
    }
    const double span = (double)s[n].t - s[m->lo].t;
    if (span < m->window * (1 - 1e-6))
        return; /* the first window is not full yet */
    const double mean = m->sum / span, tc = s[n].t - 0.5 * span;
    while (m->mid + 1 < n && s[m->mid + 1].t <= tc)
        m->mid++;
    const struct sp_history_sample *a = &s[m->mid], *b = &s[m->mid + 1];
    const double u = b->t > a->t ? (tc - a->t) / ((double)b->t - a->t) : 0;
    const double az = a->azimuth + u * ((double)b->azimuth - a->azimuth);
    if (!m->started) {
        m->started = 1;
        m->low = m->high = mean;
        return;
    }
    if (!m->rising) {
        m->low = fmin(m->low, mean);
        m->high = fmax(m->high, mean);
        if (m->high - m->low > 0.1 * m->high && mean > m->low + 0.25 * (m->high - m->low))
            m->rising = 1, m->top = mean, m->top_az = az, m->top_t = tc;
        return;
    }
    if (mean > m->top) {
        m->top = mean, m->top_az = az, m->top_t = tc;
        return;
    }
    if (m->top - m->low > 0.1 * m->top && mean < m->top - 0.25 * (m->top - m->low)) {
        if (m->peaks++ == 0)
            m->first_az = m->top_az;
        m->last_az = m->top_az;
        m->last_t = m->top_t;
        m->rising = 0;
        m->high = m->top;
        m->low = mean;
    }
}

double sp_history_precession(const struct sp_history *h, int *peaks)
{
    const struct sp_precession_meter *m = &h->meter;
    if (peaks)
        *peaks = m->peaks;
    return m->peaks >= 2 ? (m->last_az - m->first_az) / (m->peaks - 1) : NAN;
}

/* Appends the sample of sim's state; 0 or SP_E_NOMEM. */
static int push_sample(struct sp_history *h, const struct sp_sim *sim)
{
    struct sp_polar pol;
    struct sp_energy e;
    if (h->crossings_only)
        return 0;
    int err = grow((void **)&h->samples, &h->capacity, h->count, sizeof(*h->samples),
                   "panel samples");
    if (err)
        return err;
    if (sim->spatial)
        h->azimuth = sp_azimuth_unwrap(h->azimuth, sp_state_azimuth(&sim->p, &sim->s));
    sp_state_polar_in(&sim->s, h->azimuth, &pol); /* as data writes theta */
    sp_state_energy(&sim->p, &sim->s, &e);
    h->samples[h->count++] = (struct sp_history_sample){
        (float)sim->s.t, (float)sim->s.x, (float)(sim->s.y + sp_pivot_y(&sim->p, sim->s.t)),
        (float)pol.r, (float)pol.theta, (float)pol.r_dot, (float)pol.theta_dot,
        (float)e.kinetic, (float)e.spring, (float)e.gravity, (float)e.bounce, (float)e.swing,
        (float)sim->s.z, (float)h->azimuth};
    if (h->measure && sim->spatial)
        meter_push(h, &sim->p);
    return 0;
}

int sp_history_follow(struct sp_history *h, struct sp_sim *sim, double t_target)
{
    int err = 0;

    if (!h->active)
        return sp_sim_advance(sim, t_target);
    /* A tenth of a radian of the fastest small oscillation per interval keeps
     * the crossings' interpolation error near 1e-10 of the amplitude, and
     * the charts smooth where frames are far apart for the motion. */
    if (h->max_step <= 0)
        h->max_step = 0.1 / sp_params_omega_max(&sim->p);
    const double t0 = sim->s.t;
    const int parts = (int)ceil((t_target - t0) / h->max_step - 1e-9);
    for (int i = 1; i <= parts && !err; i++) {
        const struct sp_state a = sim->s;
        const double pa = damping_power(&sim->p, &a);
        err = sp_sim_advance(sim, i == parts ? t_target : t0 + (t_target - t0) * i / parts);
        h->loss += 0.5 * (sim->s.t - a.t) * (pa + damping_power(&sim->p, &sim->s));
        if (!err && h->poincare)
            err = find_crossing(h, &sim->p, &a, &sim->s);
        if (!err && i < parts)
            err = push_sample(h, sim);
    }
    return err ? err : push_sample(h, sim);
}
