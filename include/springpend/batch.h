/* springpend: many trajectories at once. The same physics and steppers as
 * sim.h, laid out as a structure of arrays and stepped SP_BATCH_BLOCK
 * trajectories at a time, so that the compiler turns each step into vector
 * instructions (AVX2 where the CPU has it, chosen at run time; SSE2 or NEON
 * otherwise). Trajectories never interact: each one's result depends only
 * on its own scene, never on which others share its batch, so any split of
 * a grid over batches and threads gives the same numbers.
 *
 * Fixed-step methods (rk4, verlet, yoshida4) mirror sim.c's arithmetic
 * operation for operation: a batch of one gives sp_sim's states to the last
 * bit. Adaptive methods (dopri5 and dop853 both run as dop853 here) control
 * each trajectory's step on its own, in lockstep: every trajectory of a
 * block takes a stage at the same time, with its own h; one whose error is
 * too large shrinks its h and retries while the others move on; steps are
 * cut short to land exactly on each requested time (no dense output), so
 * the results agree with sp_sim within the tolerance, not bitwise.
 *
 * The tangent (variational) equations ride along when asked for:
 *   dq' = dv,  dv' = J dq - (b/m) dv,
 *   J = -(k/m) [(1 - L0/rho) I + L0 q q^T / rho^3],
 * integrated by the same method (for the splitting methods, the derivative
 * of the discrete map itself), from dq = (1, 0), dv = 0. */
#ifndef SPRINGPEND_BATCH_H
#define SPRINGPEND_BATCH_H

#include <signal.h>

#include "springpend/scene.h"

/* Trajectories stepped together: four AVX2 vectors of 4 doubles (measured
 * best: 8 and 32 were slower with the tangent, 4 much slower). */
#define SP_BATCH_BLOCK 16

/* Components of a trajectory's state, the index into u[] and out[]. */
enum sp_batch_comp {
    SP_BX, SP_BY,     /* position relative to the pivot, m */
    SP_BVX, SP_BVY,   /* velocity relative to the pivot, m/s */
    SP_BW,            /* work per mass done by damping and drive, J/kg */
    SP_BDX, SP_BDY,   /* tangent vector, position part */
    SP_BDVX, SP_BDVY, /* tangent vector, velocity part */
    SP_BATCH_NC,
};

struct sp_batch {
    int n;                 /* trajectories */
    int cap;               /* n rounded up to SP_BATCH_BLOCK (padding repeats the last) */
    enum sp_method method; /* rk4, verlet, yoshida4 or dop853 */
    int tangent;           /* 1: the tangent vector is integrated */
    int forced;            /* damping or drive in some trajectory: work is tracked */
    double dt;             /* fixed-step methods' step, s */
    double tol;            /* adaptive methods' relative tolerance */
    double t;              /* time of out[], s */
    long grid;             /* fixed step: u[] is the state at t = grid * dt */
    long steps;            /* steps taken per trajectory (fixed), summed (adaptive) */
    double *out[SP_BATCH_NC]; /* the state at t, per trajectory (cap entries) */
    unsigned char *dead;   /* 1: the trajectory blew up; its out[] is NaN */
    /* private */
    double *u[SP_BATCH_NC];   /* stepping state: the grid state (fixed) */
    double *cache[6];         /* splitting: ax, ay, a_pivot, jxx, jxy, jyy at u */
    double *km, *L0, *g, *bm, *amp, *om; /* 1/s^2, m, m/s^2, 1/s, m, rad/s */
    double *mass, *stiff;     /* kg, N/m */
    double *e0, *escale;      /* energy at t = 0, and the largest energy of the
                               * motion so far, J (as sim.c) */
    double *emin;             /* the least energy the scene can hold, J */
    double drift_limit;       /* as sim.c's: |drift| / escale that is a blow-up */
    double *atol_q, *atol_v;  /* adaptive: absolute tolerances, m and m/s */
    double *h;                /* adaptive: next step per trajectory, s */
    double *mem;
    const volatile sig_atomic_t *cancel; /* the caller's (a signal): once set,
                                          * sp_batch_advance stops; NULL = never */
    int fast;                 /* 1 (set before the first advance, where
                               * sp_batch_fast_supported): RK4 with the tangent,
                               * undamped and undriven, through the fast kernel:
                               * fused multiply-adds and 1/rho from vrsqrt14pd and
                               * two Newton steps instead of sqrt and a division.
                               * Within rounding of the exact kernel, not its bits
                               * (sp_sim's); other methods and forced scenes
                               * ignore it, so a caller refuses them. */
};

/* 1 when this CPU runs the fast kernel (x86-64 with AVX-512F and FMA). */
int sp_batch_fast_supported(void);

/* Makes a batch of n trajectories, one per scene (scenes[i] for
 * trajectory i), all with scenes[0]'s integrator (method, dt, tolerance).
 * force_forced = 1 tracks work (and takes the damped/driven code path) even
 * when no scene needs it, so that a trajectory's arithmetic does not depend
 * on its neighbours: a sweep passes whether any point of its grid is forced.
 * Returns 0, SP_E_NOMEM, or SP_E_INPUT for rkn1210 (not batched). */
int sp_batch_make(struct sp_batch **out, const struct sp_scene *const *scenes, int n,
                  int tangent, int force_forced);

/* Frees b and sets *b to NULL; NULL is fine. */
void sp_batch_destroy(struct sp_batch **b);

/* Integrates every trajectory to t_target (>= b->t); out[] then holds the
 * states at exactly t_target. A trajectory whose state stops being finite,
 * or whose energy less the work of damping and drive drifts by more than 1%
 * of its scale (sim.c's test), is marked dead and its out[] set to NaN; the
 * others go on. Returns 0, or SP_E_INTERRUPTED once *b->cancel is set
 * (checked every SP_BATCH_CHUNK fixed steps, every adaptive step): the
 * batch is then part-way and good only for sp_batch_destroy. A fixed-step
 * run is cut only at multiples of SP_BATCH_CHUNK steps on the grid, so one
 * long call gives the same bits as no cut at all. */
int sp_batch_advance(struct sp_batch *b, double t_target);

/* Fixed steps between two looks at the cancel flag: a multiple of the
 * energy check's interval (batch.c), so a cut adds no check. */
#define SP_BATCH_CHUNK 65536

/* Lyapunov bookkeeping: for each trajectory i, growth[i] = ln |delta| of its
 * tangent vector, which is then scaled back to length 1 (in the stepping
 * state and in out[]). Fixed-step methods: b->t must be on the grid
 * (a multiple of dt), as the stepping state is renormalised. */
void sp_batch_renormalise(struct sp_batch *b, double *growth);

/* Resets every tangent vector to dq = (1, 0), dv = 0 (after a transient). */
void sp_batch_reset_tangent(struct sp_batch *b);

/* Sets trajectory i's tangent vector to d = (dq_x, dq_y, dv_x, dv_y) (in the
 * stepping state and in out[]); as sp_batch_renormalise, fixed-step methods
 * need b->t on the grid. A dead trajectory stays NaN. */
void sp_batch_set_tangent(struct sp_batch *b, int i, const double d[4]);

#endif
