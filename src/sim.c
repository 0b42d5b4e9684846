/* springpend: the integrator core. Cartesian RK4 with the right-hand side
 * inlined, exact landing on requested times, and a blow-up guard. */
#include <math.h>
#include <stdio.h>

#include "springpend/common.h"
#include "springpend/sim.h"

/* Relative energy drift (of sim->energy_scale) that an undamped run may show
 * before it is declared unstable. RK4 at a sane step drifts by ~1e-10. */
#define SP_ENERGY_DRIFT_LIMIT 1e-2
#define SP_RK4_STABILITY 2.8284271247461903 /* |h*omega| on the imaginary axis */

/* Acceleration of the bob, m/s^2. Regular everywhere: at the pivot the unit
 * vector is taken as zero (the force stays bounded, only its direction jumps). */
static inline void accel(const struct sp_params *p, double x, double y, double vx,
                         double vy, double *ax, double *ay)
{
    double rho = sqrt(x * x + y * y);
    double inv = rho > 0 ? p->L0 / rho : 0;
    *ax = -p->k_over_m * (x - inv * x) - p->b_over_m * vx;
    *ay = -p->k_over_m * (y - inv * y) - p->g - p->b_over_m * vy;
}

static inline void rk4_step(const struct sp_params *p, struct sp_state *s, double h)
{
    double x = s->x, y = s->y, vx = s->vx, vy = s->vy;
    double a1x, a1y, a2x, a2y, a3x, a3y, a4x, a4y;
    accel(p, x, y, vx, vy, &a1x, &a1y);
    double x2 = x + 0.5 * h * vx, y2 = y + 0.5 * h * vy;
    double vx2 = vx + 0.5 * h * a1x, vy2 = vy + 0.5 * h * a1y;
    accel(p, x2, y2, vx2, vy2, &a2x, &a2y);
    double x3 = x + 0.5 * h * vx2, y3 = y + 0.5 * h * vy2;
    double vx3 = vx + 0.5 * h * a2x, vy3 = vy + 0.5 * h * a2y;
    accel(p, x3, y3, vx3, vy3, &a3x, &a3y);
    double x4 = x + h * vx3, y4 = y + h * vy3;
    double vx4 = vx + h * a3x, vy4 = vy + h * a3y;
    accel(p, x4, y4, vx4, vy4, &a4x, &a4y);
    s->x = x + h / 6 * (vx + 2 * vx2 + 2 * vx3 + vx4);
    s->y = y + h / 6 * (vy + 2 * vy2 + 2 * vy3 + vy4);
    s->vx = vx + h / 6 * (a1x + 2 * a2x + 2 * a3x + a4x);
    s->vy = vy + h / 6 * (a1y + 2 * a2y + 2 * a3y + a4y);
}

void sp_state_polar(const struct sp_state *s, struct sp_polar *out)
{
    double r = sqrt(s->x * s->x + s->y * s->y);
    out->r = r;
    out->theta = atan2(s->x, -s->y);
    out->r_dot = r > 0 ? (s->x * s->vx + s->y * s->vy) / r : 0;
    out->theta_dot = r > 0 ? (s->x * s->vy - s->y * s->vx) / (r * r) : 0;
}

void sp_state_energy(const struct sp_params *p, const struct sp_state *s,
                     struct sp_energy *out)
{
    double rho = sqrt(s->x * s->x + s->y * s->y);
    out->kinetic = 0.5 * p->mass * (s->vx * s->vx + s->vy * s->vy);
    out->spring = 0.5 * p->stiffness * (rho - p->L0) * (rho - p->L0);
    out->gravity = p->mass * p->g * s->y;
    out->total = out->kinetic + out->spring + out->gravity;
}

double sp_params_omega_max(const struct sp_params *p)
{
    double ell = p->L0 + p->g / p->k_over_m;
    double w = sqrt(p->k_over_m);
    if (sqrt(p->g / ell) > w)
        w = sqrt(p->g / ell);
    if (p->b_over_m > w)
        w = p->b_over_m;
    return w;
}

void sp_sim_init(struct sp_sim *sim, const struct sp_scene *scene)
{
    const double r = scene->initial.length, th = scene->initial.angle;
    const double rd = scene->initial.length_rate, thd = scene->initial.angle_rate;
    struct sp_energy e;
    sim->scene = scene;
    sim->p = (struct sp_params){
        .k_over_m = scene->pendulum.stiffness / scene->pendulum.mass,
        .L0 = scene->pendulum.natural_length,
        .g = scene->pendulum.gravity,
        .b_over_m = scene->pendulum.damping / scene->pendulum.mass,
        .mass = scene->pendulum.mass,
        .stiffness = scene->pendulum.stiffness,
    };
    sim->s = (struct sp_state){
        .t = 0,
        .x = r * sin(th),
        .y = -r * cos(th),
        .vx = rd * sin(th) + r * thd * cos(th),
        .vy = -rd * cos(th) + r * thd * sin(th),
    };
    sim->dt = scene->integrator.dt;
    sim->steps = 0;
    sp_state_energy(&sim->p, &sim->s, &e);
    sim->energy0 = e.total;
    /* The energies the motion trades between, J: the start's own terms, and
     * what hanging at the equilibrium length ell = L0 + m g / k involves. */
    double ell = sim->p.L0 + sim->p.g / sim->p.k_over_m;
    sim->energy_scale = fabs(e.kinetic) + fabs(e.spring) + fabs(e.gravity) +
                        sim->p.mass * sim->p.g * ell +
                        0.5 * sim->p.stiffness * sim->p.L0 * sim->p.L0;
}

/* Prints what went wrong, when, and how to fix it. */
static int report_blowup(const struct sp_sim *sim, double energy, const char *what)
{
    double w = sp_params_omega_max(&sim->p);
    double limit = SP_RK4_STABILITY / w;
    /* suggest half the limit, rounded down to one significant digit */
    double safe = 0.5 * limit, mag = pow(10, floor(log10(safe)));
    safe = floor(safe / mag) * mag;
    sp_log_error("the simulation became unstable at t = %.6g s (%s): "
                 "x = %.6g m, y = %.6g m, vx = %.6g m/s, vy = %.6g m/s, "
                 "energy %.6g J vs %.6g J at t = 0",
                 sim->s.t, what, sim->s.x, sim->s.y, sim->s.vx, sim->s.vy, energy,
                 sim->energy0);
    if (sim->dt * w > SP_RK4_STABILITY)
        fprintf(stderr, "  dt = %g s is above RK4's stability limit %.3g s for "
                "omega_max = %.4g rad/s (k/m = %g 1/s^2); use integrator.dt <= %g\n",
                sim->dt, limit, w, sim->p.k_over_m, safe);
    else
        fprintf(stderr, "  dt = %g s is within RK4's stability limit %.3g s but too "
                "coarse for this motion; try integrator.dt = %g\n",
                sim->dt, limit, sim->dt / 10);
    return SP_E_UNSTABLE;
}

/* 0 if the state is finite and the energy plausible, else the report. */
static int check_state(const struct sp_sim *sim)
{
    const struct sp_state *s = &sim->s;
    if (!isfinite(s->x) || !isfinite(s->y) || !isfinite(s->vx) || !isfinite(s->vy))
        return report_blowup(sim, NAN, "the state is no longer finite");
    struct sp_energy e;
    sp_state_energy(&sim->p, s, &e);
    double drift = (e.total - sim->energy0) / sim->energy_scale;
    /* Damping only removes energy; without it energy is conserved. */
    if (drift > SP_ENERGY_DRIFT_LIMIT ||
        (sim->p.b_over_m == 0 && drift < -SP_ENERGY_DRIFT_LIMIT)) {
        char what[96];
        snprintf(what, sizeof(what), "energy drifted by %.3g%% of its scale %.3g J",
                 100 * drift, sim->energy_scale);
        return report_blowup(sim, e.total, what);
    }
    return 0;
}

int sp_sim_advance(struct sp_sim *sim, double t_target)
{
    struct sp_state *s = &sim->s;
    while (s->t < t_target) {
        double h = sim->dt, remaining = t_target - s->t;
        int last = remaining <= h * (1 + 1e-9);
        if (last)
            h = remaining;
        rk4_step(&sim->p, s, h);
        s->t = last ? t_target : s->t + h;
        sim->steps++;
        if (!isfinite(s->x + s->y + s->vx + s->vy) || (sim->steps & 3) == 0) {
            int ret = check_state(sim);
            if (ret)
                return ret;
        }
    }
    return check_state(sim);
}
