/* springpend: the physics. Pure: no I/O, no process-wide state, no GL; a
 * caller hands it a cancel flag and a progress callback, and words its
 * failures (sp_sim_failure; sim_report.h's sp_sim_explain).
 * Cartesian state relative to the pivot, y up (x = r sin(theta),
 * y = -r cos(theta)). Equations of motion from the Lagrangian
 *   T = m/2 (r'^2 + r^2 theta'^2),  U = k/2 (r - L0)^2 - m g r cos(theta):
 *   x'' = -(k/m)(1 - L0/rho) x - (b/m) x'
 *   y'' = -(k/m)(1 - L0/rho) y - g - a_p(t) - (b/m)(y' + v_p(t))
 * which in polar form is r'' = r theta'^2 + g cos(theta) + (k/m)(L0 - r)
 * (note + g cos: the original page's - g cos breaks energy conservation).
 * The pivot moves vertically, y_p(t) = A sin(Omega t) (A = 0: fixed); the
 * state is kept in the pivot's frame, where the pivot's acceleration a_p acts
 * as a time-dependent gravity. Damping acts on the bob's velocity relative
 * to the air, which is at rest in the lab: v + v_p(t) y-hat.
 * In three dimensions (the spherical elastic pendulum, "the swinging
 * spring") z is the horizontal axis out of the starting plane and
 *   z'' = -(k/m)(1 - L0/rho) z - (b/m) z',  rho = |(x, y, z)|;
 * a scene whose motion stays in the x-y plane (initial.azimuth_rate = 0)
 * integrates x and y alone, with the planar run's arithmetic. */
#ifndef SPRINGPEND_SIM_H
#define SPRINGPEND_SIM_H

#include <signal.h>

#include "springpend/scene.h"

struct sp_state {
    double t;      /* simulated time, s */
    double x, y;   /* bob position relative to the pivot, m */
    double vx, vy; /* bob velocity relative to the pivot, m/s */
    double z, vz;  /* out of the starting plane (horizontal, x-y-z right-handed
                    * with y up), m and m/s; 0 in a planar run */
};

struct sp_params {
    double k_over_m;    /* 1/s^2 */
    double L0;          /* natural length, m */
    double g;           /* m/s^2 */
    double b_over_m;    /* 1/s */
    double mass;        /* kg */
    double stiffness;   /* N/m */
    double drive_amp;   /* pivot amplitude A, m (0: fixed pivot) */
    double drive_omega; /* pivot angular frequency Omega, rad/s */
};

struct sp_polar {
    double r;         /* m */
    double theta;     /* rad from the downward vertical, in (-pi, pi] */
    double r_dot;     /* m/s */
    double theta_dot; /* rad/s */
};

/* Energies in the pivot's frame. bounce + swing = total - E_eq, where E_eq
 * is the energy of the bob hanging still at the equilibrium length
 * l = L0 + m g / k: the split the original text speaks of. */
struct sp_energy {
    double kinetic; /* J */
    double spring;  /* J */
    double gravity; /* J, zero at the pivot's height */
    double total;   /* J */
    double bounce;  /* J: m r'^2 / 2 + k (r - l)^2 / 2, radial */
    double swing;   /* J: m r^2 theta'^2 / 2 + m g r (1 - cos theta), angular */
};

/* What a method is: for `info`, the blow-up message and the benchmark. */
struct sp_method_info {
    const char *name;  /* as in the scene file */
    int order;         /* global order of accuracy */
    int adaptive;      /* 1: error-controlled steps, dense output */
    double stability;  /* largest |dt*omega| on the imaginary axis (fixed dt) */
    int evals;         /* right-hand-side evaluations per step */
};

const struct sp_method_info *sp_method_info(enum sp_method m);

/* Why sp_sim_advance returned SP_E_UNSTABLE, for the caller to word. */
struct sp_sim_failure {
    struct sp_state s; /* the last state checked */
    double energy;     /* J: its total energy; NAN when not finite */
    char what[256];    /* what failed: "the state is no longer finite", ... */
    double pass_distance; /* m: fixed-step methods, the closest the bob came
                          * to the pivot on a step that took it past the pivot
                          * (its direction turned by over 90 degrees; the chord
                          * between step ends) since the last check it passed;
                          * NAN if none or otherwise */
    double pass_speed;   /* m/s: the bob's speed along that chord */
};

/* The integrator. Fixed-step methods walk the grid t_n = n dt and reach a
 * requested time between grid points with one extra short step from the
 * last grid state, so the grid (and a symplectic method's energy behaviour)
 * does not depend on when it is sampled. Adaptive methods take their own
 * steps and interpolate (dense output). Fields below `private` are the
 * stepper's own. */
struct sp_sim {
    struct sp_params p;
    struct sp_state s;   /* the state at the last requested time */
    enum sp_method method;
    double dt;           /* fixed step, s (adaptive: the scene's dt, unused) */
    double tol;          /* adaptive methods' tolerance, relative */
    double energy0;      /* total energy at t = 0, J */
    double energy_min;   /* J: the least energy the scene can hold, hanging
                          * still at l = L0 + m g / k: -m g L0 - (m g)^2 / 2k */
    double energy_scale; /* J: the energy of the motion, total - energy_min,
                          * the largest it has been so far (at least at t = 0):
                          * drift is judged against it */
    double drift_limit;  /* largest |total - energy0 - work| / energy_scale a
                          * run may show (SP_SIM_DRIFT_LIMIT unless set) */
    const volatile sig_atomic_t *cancel; /* the caller's: not NULL, once *cancel
                          * is nonzero sp_sim_advance stops with
                          * SP_E_INTERRUPTED (sp_sim_init: NULL) */
    void (*progress)(void *ctx, double t); /* the caller's: not NULL, called
                          * with the simulated time, s, after each checked
                          * step; must be cheap (sp_sim_init: NULL) */
    void *progress_ctx;  /* progress's first argument */
    struct sp_sim_failure failure; /* set when sp_sim_advance returns
                          * SP_E_UNSTABLE */
    double work;         /* J: work done on the bob by damping and the moving
                          * pivot up to s.t; total - energy0 - work is drift */
    long steps;          /* steps taken so far (accepted, on adaptive) */
    long rejected;       /* adaptive: steps rejected by error control */
    long evals;          /* right-hand-side evaluations so far */
    const struct sp_scene *scene; /* for messages */
    /* private */
    int forced;          /* damping or a moving pivot: track the work */
    int spatial;         /* 1: the motion leaves the x-y plane, z and vz are
                          * integrated (initial.azimuth_rate != 0) */
    double y0[7], y1[7]; /* state (x, y, vx, vy, work/m, z, vz) at t0 and t1 */
    double t0, t1;       /* the current step (adaptive); t1: grid point (fixed) */
    double force[4];     /* splitting methods: ax, ay, a_pivot, az at (t1, y1) */
    double h;            /* adaptive: next step size, s */
    double atol[7];      /* adaptive: absolute tolerance per component */
    int dense_ready;     /* adaptive: dense[] is filled for [t0, t1] */
    int last_rejected;
    double k[17][7];     /* stage derivatives of the current step */
    double dense[7][7];  /* dense output coefficients */
};

/* The blow-up guard's default: energy drift, less the work of damping and
 * drive, as a fraction of the motion's energy. Sane steps drift by ~1e-10. */
#define SP_SIM_DRIFT_LIMIT 1e-2

/* Sets up the initial state from the scene. */
void sp_sim_init(struct sp_sim *sim, const struct sp_scene *scene);

/* Integrates forward so that afterwards sim->s is the state at exactly
 * t_target (>= sim->s.t). Returns SP_E_UNSTABLE, with sim->failure saying
 * what and where (nothing is printed: sp_sim_explain words it), if the state
 * stops being finite or the energy, less the work of damping and drive,
 * drifts by more than drift_limit of the motion's energy (energy_scale);
 * sim->s is then the last state checked. SP_E_INTERRUPTED once *sim->cancel
 * is set. A state returned with 0 always passed the check. */
int sp_sim_advance(struct sp_sim *sim, double t_target);

/* The steps an integration of scene from 0 to t_end takes: t_end / dt for
 * a fixed-step method; for an adaptive one, the steps of a probe over the
 * first 100 radians of the fastest motion (the pendulum's, the damping's,
 * the drive's), at most about 2e4 steps, scaled to t_end. An estimate
 * within a factor of a few (the motion may change its pace); 0 when the
 * probe itself fails (the real run then reports why) or cancel (may be
 * NULL) is set while it runs. */
double sp_sim_estimate_steps(const struct sp_scene *scene, double t_end,
                             const volatile sig_atomic_t *cancel);

/* r, theta and their rates. A state off the x-y plane (z or vz nonzero) has
 * theta as the polar angle from the downward vertical, in [0, pi] (for
 * what is shown and written, see sp_state_polar_in). */
void sp_state_polar(const struct sp_state *s, struct sp_polar *out);

/* The angle springpend shows and writes (data's theta, a still's --state,
 * the theta panel): from the downward vertical, signed by the side of the
 * swing plane the bob is on: positive towards the horizontal direction
 * (cos azimuth, sin azimuth) in (x, z), azimuth in rad (data's azimuth
 * column, sp_state_azimuth made continuous), in (-pi, pi]; theta_dot the
 * rate of that angle. One convention for planar and 3-D scenes: in the x-y
 * plane (azimuth 0) it is atan2(x, -y), and a 3-D run whose swing plane has
 * barely turned (azimuth_rate 1e-10) gives the planar run's angle, sign
 * and all (the polar angle, never negative, gave +0.0132 where the planar
 * run gave -0.0132). r and r_dot are sp_state_polar's. */
void sp_state_polar_in(const struct sp_state *s, double azimuth, struct sp_polar *out);
void sp_state_energy(const struct sp_params *p, const struct sp_state *s,
                     struct sp_energy *out);

/* The forces on the bob, N, and its acceleration, m/s^2, as x, y pairs (y
 * up), in the pivot's frame: with a driven pivot that frame accelerates,
 * and `drive` is its inertial force -m a_pivot; damping acts on the bob's
 * velocity relative to the air, at rest in the lab. net is the sum of the
 * four and equals mass times accel, the acceleration relative to the pivot
 * (what the integrator integrates). In three dimensions these are the x-y
 * components (the plane the view shows). */
struct sp_forces {
    double gravity[2], spring[2], damping[2], drive[2]; /* N */
    double net[2];                                      /* N */
    double accel[2];                                    /* m/s^2 */
};
void sp_state_forces(const struct sp_params *p, const struct sp_state *s,
                     struct sp_forces *out);

/* The vertical component of the angular momentum about the pivot per mass,
 * m^2/s: z vx - x vz (y up). Conserved without damping: gravity, the spring
 * and the vertical drive exert no torque about the vertical. */
double sp_state_angular_momentum_y(const struct sp_state *s);

/* The azimuth of the swing's plane, rad in (-pi/2, pi/2], measured about
 * the vertical from +x towards +z: the major axis of the horizontal ellipse
 * that the swing traces in one pendulum period, taken from the tensor
 *   M = h h^T + h' h'^T / omega_p^2,   h = (x, z), omega_p = sqrt(g / l),
 * which for a small isotropic swing h = a cos(wt) e1 + b sin(wt) e2 is
 * a^2 e1 e1^T + b^2 e2 e2^T at every instant (the ellipse's slow variable):
 * azimuth = atan2(2 M_xz, M_xx - M_zz) / 2. 0 when the swing has no
 * preferred direction (a circle or no swing at all). */
double sp_state_azimuth(const struct sp_params *p, const struct sp_state *s);

/* An azimuth a (rad, defined modulo pi) moved by a multiple of pi to lie
 * within pi/2 of prev: a continuous azimuth from samples of
 * sp_state_azimuth. */
double sp_azimuth_unwrap(double prev, double a);

/* The pivot's height at time t, m (0 for a fixed pivot). */
double sp_pivot_y(const struct sp_params *p, double t);

/* What a scene's parameters imply for small oscillations. */
struct sp_physics {
    double ell;     /* m: equilibrium length L0 + m g / k */
    double omega_s; /* rad/s: the bounce, sqrt(k/m) */
    double omega_p; /* rad/s: the swing, sqrt(g/l) (0 without gravity) */
    double ratio;   /* omega_s / omega_p (infinite without gravity); 2:1 at 2 */
};

void sp_params_physics(const struct sp_params *p, struct sp_physics *out);

/* The fastest small-oscillation angular frequency of the scene, rad/s:
 * max(sqrt(k/m), sqrt(g/l), b/m) with l = L0 + m g / k. */
double sp_params_omega_max(const struct sp_params *p);

#endif
