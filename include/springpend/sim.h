/* springpend: the physics. Pure: no I/O but the blow-up message, no GL.
 * Cartesian state, pivot at the origin, y up (x = r sin(theta),
 * y = -r cos(theta)). Equations of motion from the Lagrangian
 *   T = m/2 (r'^2 + r^2 theta'^2),  U = k/2 (r - L0)^2 - m g r cos(theta):
 *   x'' = -(k/m)(1 - L0/rho) x - (b/m) x'
 *   y'' = -(k/m)(1 - L0/rho) y - g - (b/m) y'
 * which in polar form is r'' = r theta'^2 + g cos(theta) + (k/m)(L0 - r)
 * (note + g cos: the original page's - g cos breaks energy conservation). */
#ifndef SPRINGPEND_SIM_H
#define SPRINGPEND_SIM_H

#include "springpend/scene.h"

struct sp_state {
    double t;      /* simulated time, s */
    double x, y;   /* bob position, m */
    double vx, vy; /* bob velocity, m/s */
};

struct sp_params {
    double k_over_m;  /* 1/s^2 */
    double L0;        /* natural length, m */
    double g;         /* m/s^2 */
    double b_over_m;  /* 1/s */
    double mass;      /* kg */
    double stiffness; /* N/m */
};

struct sp_polar {
    double r;         /* m */
    double theta;     /* rad from the downward vertical, in (-pi, pi] */
    double r_dot;     /* m/s */
    double theta_dot; /* rad/s */
};

struct sp_energy {
    double kinetic; /* J */
    double spring;  /* J */
    double gravity; /* J, zero at the pivot's height */
    double total;   /* J */
};

struct sp_sim {
    struct sp_params p;
    struct sp_state s;
    double dt;           /* nominal step, s */
    double energy0;      /* total energy at t = 0, J */
    double energy_scale; /* J: the size against which drift is judged */
    long steps;          /* steps taken so far */
    const struct sp_scene *scene; /* for messages */
};

/* Sets up the initial state from the scene. */
void sp_sim_init(struct sp_sim *sim, const struct sp_scene *scene);

/* Integrates forward to exactly t_target (>= sim->s.t), shortening the last
 * step so it lands on t_target. Returns SP_E_UNSTABLE (after printing the
 * time, state, energy drift and a fix) if the state stops being finite or
 * the energy of an undamped run drifts beyond what any sane step allows. */
int sp_sim_advance(struct sp_sim *sim, double t_target);

void sp_state_polar(const struct sp_state *s, struct sp_polar *out);
void sp_state_energy(const struct sp_params *p, const struct sp_state *s,
                     struct sp_energy *out);

/* The fastest small-oscillation angular frequency of the scene, rad/s:
 * max(sqrt(k/m), sqrt(g/l)) with l = L0 + m g / k. */
double sp_params_omega_max(const struct sp_params *p);

#endif
