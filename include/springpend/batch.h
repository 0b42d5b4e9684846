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
 * of the discrete map itself), from dq = (1, 0), dv = 0.
 *
 * Three dimensions (sim.h: the spherical pendulum, a scene with
 * initial.azimuth_rate != 0): when any trajectory of a batch leaves the x-y
 * plane, the whole batch integrates z and vz too (and, with the tangent,
 * the 3 x 3 Jacobian on a 6-D tangent vector that starts at dq = (1, 0, 0),
 * dv = 0), each trajectory with sp_sim's 3-D arithmetic. A planar
 * trajectory in such a batch keeps z = vz = 0 exactly, and every number it
 * computes equals the planar path's (adding z^2 = +0 changes no value), so
 * its results still do not depend on its neighbours; its tangent stays in
 * the plane (the out-of-plane perturbations of a planar motion are not
 * followed: its lambda is the planar one). */
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
    SP_BZ, SP_BVZ,    /* 3-D: out of the starting plane (sim.h's z), m and m/s */
    SP_BDZ, SP_BDVZ,  /* 3-D: the tangent vector's z parts */
    SP_BATCH_NC,
};

struct sp_batch {
    int n;                 /* trajectories */
    int cap;               /* n rounded up to SP_BATCH_BLOCK (padding repeats the last) */
    enum sp_method method; /* rk4, verlet, yoshida4 or dop853 */
    int tangent;           /* 1: the tangent vector is integrated */
    int forced;            /* damping or drive in some trajectory: work is tracked */
    int spatial;           /* 1: some trajectory leaves the x-y plane: z, vz (and
                            * dz, dvz) are integrated for all */
    double dt;             /* fixed-step methods' step, s */
    double tol;            /* adaptive methods' relative tolerance */
    double t;              /* time of out[], s */
    long grid;             /* fixed step: u[] is the state at t = grid * dt */
    long steps;            /* steps taken per trajectory (fixed), summed (adaptive) */
    double *out[SP_BATCH_NC]; /* the state at t, per trajectory (cap entries) */
    unsigned char *dead;   /* 1: the trajectory blew up; its out[] is NaN */
    /* private */
    double *u[SP_BATCH_NC];   /* stepping state: the grid state (fixed) */
    double *cache[10];        /* splitting: ax, ay, a_pivot, jxx, jxy, jyy at u;
                               * 3-D also az, jxz, jyz, jzz */
    double *km, *L0, *g, *bm, *amp, *om; /* 1/s^2, m, m/s^2, 1/s, m, rad/s */
    double *mass, *stiff;     /* kg, N/m */
    double *e0, *escale;      /* energy at t = 0, and the largest energy of the
                               * motion so far, J (as sim.c) */
    double *emin;             /* the least energy the scene can hold, J */
    double drift_limit;       /* as sim.c's: |drift| / escale that is a blow-up */
    double *atol_q, *atol_v;  /* adaptive: absolute tolerances, m and m/s */
    double *h;                /* adaptive: next step per trajectory, s */
    double *nphys;            /* adaptive: the error norm's components, 4 (planar
                               * trajectory) or 6 (3-D), as sim.c's NPHYS */
    double *mem;
    const volatile sig_atomic_t *cancel; /* the caller's (a signal): once set,
                                          * sp_batch_advance stops; NULL = never */
    int fast;                 /* 1 (set before the first advance, where
                               * sp_batch_fast_supported): RK4 with the tangent,
                               * undamped and undriven, through the fast kernel:
                               * fused multiply-adds and 1/rho from vrsqrt14pd and
                               * two Newton steps instead of sqrt and a division.
                               * Within rounding of the exact kernel, not its bits
                               * (sp_sim's); other methods, forced scenes and
                               * 3-D batches ignore it, so a caller refuses
                               * them. */
};

/* 1 when this CPU runs the fast kernel (x86-64 with AVX-512F and FMA). */
int sp_batch_fast_supported(void);

/* Makes a batch of n trajectories, one per scene (scenes[i] for
 * trajectory i), all with scenes[0]'s integrator (method, dt, tolerance).
 * force_forced = 1 tracks work (and takes the damped/driven code path) even
 * when no scene needs it, so that a trajectory's arithmetic does not depend
 * on its neighbours: a sweep passes whether any point of its grid is forced.
 * The batch is 3-D (b->spatial) when any scene is (see above).
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
 * tangent vector (4 or, in a 3-D batch, 6 components), which is then scaled
 * back to length 1 (in the stepping
 * state and in out[]). Fixed-step methods: b->t must be on the grid
 * (a multiple of dt), as the stepping state is renormalised. */
void sp_batch_renormalise(struct sp_batch *b, double *growth);

/* Resets every tangent vector to dq = (1, 0), dv = 0 (dq = (1, 0, 0) in 3-D;
 * after a transient). */
void sp_batch_reset_tangent(struct sp_batch *b);

/* Sets trajectory i's tangent vector to d = (dq_x, dq_y, dv_x, dv_y) (in the
 * stepping state and in out[]); as sp_batch_renormalise, fixed-step methods
 * need b->t on the grid. A dead trajectory stays NaN. Planar batches only
 * (the Lyapunov spectrum's four vectors; a 3-D batch's dz, dvz stay). */
void sp_batch_set_tangent(struct sp_batch *b, int i, const double d[4]);

#endif
