/* springpend: ensembles. [ensemble] count = N pendulums whose scenes differ
 * only in one numeric physics key, spread evenly over `spread` (the key's
 * file units, total range) around the scene's own value, stepped together by
 * the batched integrator (batch.h: each member's states are sp_sim's to the
 * last bit for fixed-step methods). Keeps what the frames draw: the members'
 * positions, their short trails, and the ensemble's spread in phase space
 * against time; knows nothing of drawing. A 3-D scene (initial.azimuth_rate
 * != 0) gives 3-D members: positions, trails and spread take z and vz too. */
#ifndef SPRINGPEND_ENSEMBLE_H
#define SPRINGPEND_ENSEMBLE_H

#include <stdio.h>

#include "springpend/batch.h"
#include "springpend/frame.h"

/* Trail points each member keeps when [ensemble] trails = true: at most
 * this many frames back, and at most about 3000 / N, so that N trails cost
 * no more than about 3000 segments per frame. */
#define SP_ENSEMBLE_TRAIL 90

struct sp_ensemble {
    int n;                     /* members */
    char key[64];              /* "section.key" they differ in */
    double *value;             /* each member's key value, file units */
    struct sp_scene *scenes;   /* n, owned */
    struct sp_params *params;  /* n: each member's parameters (its pivot) */
    struct sp_batch *batch;    /* the members, at time t */
    double t;                  /* s */
    double omega;              /* rad/s: velocities enter the spread divided by it */
    double lambda;             /* 1/s: the central scene's largest Lyapunov exponent
                                  over the run (tangent equations, Benettin) */
    double log_spread0;        /* log10 m: the spread at t = 0 */
    struct sp_range log_spread; /* log10 m over the run: the spread panel's axis */
    float *spread_t, *spread_log; /* the spread so far: s, log10 m */
    int n_spread, cap_spread;
    int trail_cap;             /* points per member's trail, 0 = none */
    int trail_count, trail_head; /* the rings' fill and next slot (all members alike) */
    float *trail_xyz;          /* member i's ring: trail_xyz[3 * (i * trail_cap + j)] + 0, 1,
                                  2: x, y, z, m in the lab (z 0 planar) */
};

/* Builds the ensemble of scene (ensemble.count > 1, checked by the parser),
 * runs every member from 0 to t_end once (a pre-pass like
 * sp_view_extent_measure) widening *extent by their positions and speeds,
 * finding the spread's range and, with a second batch of one, the central
 * scene's Lyapunov exponent; then sets the members back to t = 0. A member
 * that blows up fails the whole run: SP_E_UNSTABLE (exit 3), naming it and
 * its key value; also SP_E_NOMEM. Logged. Once the caller's *cancel is set
 * (NULL = never), the pre-pass stops with SP_E_INTERRUPTED; progress (NULL
 * = none) hears the members' simulated time, s, with progress_ctx, as
 * sp_view_extent_measure's does. */
int sp_ensemble_make(struct sp_ensemble **out, const struct sp_scene *scene, double t_end,
                     const volatile sig_atomic_t *cancel,
                     void (*progress)(void *ctx, double t), void *progress_ctx,
                     struct sp_view_extent *extent);

/* Advances every member to t (>= the current time), pushing a trail point
 * and a spread sample. 0, SP_E_UNSTABLE or SP_E_NOMEM (logged). */
int sp_ensemble_advance(struct sp_ensemble *e, double t);

/* The spread at the current time: the root mean square distance of the
 * members from their mean in phase space (x, y, vx / omega, vy / omega, and
 * z, vz / omega in 3-D), m. */
double sp_ensemble_spread(const struct sp_ensemble *e);

/* Member i's position in the lab (pivot at rest at the origin), m; z is 0
 * for planar members. */
void sp_ensemble_position(const struct sp_ensemble *e, int i, double *x, double *y, double *z);

/* Member i's colour of n: hues around the wheel, distinct neighbours. */
void sp_ensemble_color(int i, int n, float rgb[3]);

/* Writes the members' states at times t_k = k * every (every > 0) or the
 * video's frame times as CSV rows "t,member,KEY,x,y,vx,vy" (positions and
 * velocities relative to the pivot, as data's columns; %.15g like data),
 * and ",z,vz,azimuth" for a 3-D scene (as data's, the azimuth continued from
 * each member's previous row).
 * 0, SP_E_UNSTABLE, SP_E_IO, SP_E_NOMEM or SP_E_INTERRUPTED (once the
 * caller's *cancel is set; NULL = never). */
int sp_ensemble_write_csv(FILE *fp, const struct sp_scene *scene, double every,
                          const volatile sig_atomic_t *cancel);

/* 1 when some member of scene's ensemble leaves the x-y plane (its
 * initial.azimuth_rate is not 0, the scene's or the key's), else 0. */
int sp_ensemble_spatial(const struct sp_scene *scene);

/* Frees e and sets *e to NULL; NULL is fine. */
void sp_ensemble_destroy(struct sp_ensemble **e);

#endif
