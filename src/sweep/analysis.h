/* springpend (internal): the sweep measures of the analysis (issue 23), each
 * run on one chunk of grid points by sweep.c's workers and writing its rows
 * (sweep.h's CSV layout) to a stream in the grid's order:
 *   spectrum.c      all four Lyapunov exponents (Benettin, QR by modified
 *                   Gram-Schmidt), their running values and the Kaplan-Yorke
 *                   dimension;
 *   basins.c        which attractor of the stroboscopic map each start ends
 *                   on, and (from the CSV alone) the attractors, their basin
 *                   fractions and the basin entropies;
 *   continuation.c  orbit diagrams with continuation in the parameter and the
 *                   largest |theta| (or r) per drive period;
 *   precession.c    the swinging spring's turn of the swing plane per
 *                   exchange (3-D scenes).
 * Every point's numbers depend on its own start only (a continued branch on
 * the points before it on the branch), so threads and shards change nothing. */
#ifndef SPRINGPEND_ANALYSIS_H
#define SPRINGPEND_ANALYSIS_H

#include <stdio.h>

#include "springpend/scene.h"
#include "sweep.h"

/* The cubic Hermite interpolant of a position over a step of length h:
 * value at s in [0, 1] from the ends' positions and velocities. */
static inline double sp_hermite(double s, double h, double q0, double v0, double q1, double v1)
{
    double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * h * v0 + (-2 * s3 + 3 * s2) * q1 +
           (s3 - s2) * h * v1;
}

/* Writes "p,KEY1[,KEY2]," (grid point p and its axis values) into buf.
 * Returns buf. (sweep.c: every measure's rows start so.) */
char *sp_sweep_format_point(char *buf, size_t size, const struct sp_sweep_desc *d, long p);

/* The Lyapunov measures' renormalisation interval: about a second, and for
 * fixed steps a whole number m of them (dt, s), so that the tangent is
 * renormalised on the grid; T = K tau exactly (sp_sweep_check refuses a
 * --time that no whole K >= 2 makes, or too short to step). */
struct sp_lyap_grid {
    int fixed;  /* 1: rk4, verlet, yoshida4 */
    long m;     /* steps per tau (fixed), else 1 */
    double tau; /* s */
    long K;     /* intervals in T */
};
void sp_sweep_lyap_grid(double time, enum sp_method method, double dt, struct sp_lyap_grid *g);

/* sweep_rows.c: row (point p, branch b, its first value's field tf read as
 * t; mark: 0 a measured row, 1 the NaN row of a point that blew up, 2 the
 * row of an orbit's or poincare point without an event) in the sequence of
 * the shard's rows r (the rules: sweep.h's sp_sweep_rows_end). NULL, or
 * what is wrong. Called by sp_sweep_row_check before it takes the row as
 * the last (r->point). */
const char *sp_sweep_row_sequence(struct sp_sweep_rows *r, long p, int b, const char *tf,
                                  double t, int mark);

/* ---- spectrum.c ---------------------------------------------------------- */

/* The Lyapunov spectrum of scenes[0..n) (grid points pts[], skip[i]: not
 * written) over d->time after d->transient: four copies of each trajectory,
 * copy j carrying tangent vector j, stepped together in one batch (the
 * copies' states are bitwise equal; the error control of dop853 looks at the
 * state only, so they take the same steps); every tau the four tangent
 * vectors are re-orthonormalised by modified Gram-Schmidt, ln R_jj summed.
 * Rows at checkpoints T (about ten per decade of T, and T = d->time).
 * forced: the grid's (sweep.c). Returns 0, SP_E_NOMEM or SP_E_INTERRUPTED. */
#define SP_SPECTRUM_MAX_CHECKS 128 /* checkpoints per point: ten per decade of T/tau */

/* The renormalisation times T of a spectrum point's rows (the checkpoints
 * k tau: k = round(10^(i/10)) up to K, and K), in order, into T[0..max);
 * returns how many (sweep_rows.c: what a merge checks the rows against). */
int sp_spectrum_checkpoints(const struct sp_sweep_desc *d, double *T, int max);

int sp_spectrum_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                        const long *pts, const int *skip, int n, int forced, FILE *rows,
                        long *blown_up);

/* QR of the 4x4 matrix whose columns are v[0..3] by modified Gram-Schmidt
 * (Golub and Van Loan, Matrix Computations, 4th ed., Algorithm 5.2.6): v
 * becomes Q, r[j] = R_jj (> 0, or 0 when column j is dependent; then the
 * column is left as it is). */
void sp_spectrum_mgs(double v[4][4], double r[4]);

/* The Kaplan-Yorke (Lyapunov) dimension of exponents lam[0..n) in any order:
 * j + (lam_1 + ... + lam_j) / |lam_{j+1}| for the largest j whose partial sum
 * of the exponents in decreasing order is >= 0; n when the whole sum is
 * >= 0; 0 when the largest is < 0. */
double sp_spectrum_kaplan_yorke(const double *lam, int n);

/* ---- basins.c ------------------------------------------------------------ */

#define SP_BASINS_MAX_PERIOD 8 /* longest cycle of the stroboscopic map looked for */

/* Runs the stroboscopic map of each start (a driven scene) until its last
 * samples repeat with a period p <= SP_BASINS_MAX_PERIOD (in the cells of a
 * state-space grid), at most d->transient + d->time. Rows: period (0:
 * undecided), winding (whole turns per cycle), the cycle's representative
 * state (the sample of least theta: degrees, m, rad/s, m/s) and the time it
 * was settled (s). Returns 0, SP_E_NOMEM or SP_E_INTERRUPTED. */
int sp_basins_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                      const long *pts, const int *skip, int n, int forced, FILE *rows,
                      long *blown_up);

/* One attractor (or category) of a basin map. */
struct sp_attractor {
    int period;          /* of the stroboscopic map; 0: undecided */
    int winding;         /* whole turns per cycle (rotating when != 0) */
    double theta, r, theta_dot, r_dot; /* representative state: deg, m, rad/s, m/s */
    long count;          /* grid points that end on it */
    char label[96];      /* "period 2, theta 23.1 deg, 0.41 rad/s" */
};

#define SP_BASINS_MAX_ATTRACTORS 24 /* more are pooled into "other" */

/* What a basin map's CSV holds: its attractors, each point's attractor, the
 * basin fractions and the entropies. */
struct sp_basin_map {
    int n_attractors;    /* the last may be "other" */
    struct sp_attractor att[SP_BASINS_MAX_ATTRACTORS];
    int nx, ny;          /* the grid */
    int *label;          /* nx * ny attractor indices, -1 = no row (blown up) */
    double entropy;      /* S_b, nats; NaN: no box (a side under box points) */
    double boundary_entropy; /* S_bb, nats; NaN as S_b */
    int box;             /* boxes of box x box points for the entropies */
    int boxes_x, boxes_y; /* whole boxes along each key: box * boxes_x of the nx
                           * columns (box * boxes_y of the ny rows) are used, the
                           * rest left out */
    long blown_up;
};

/* Reads a basin map's rows (fp after the column names) for description d,
 * clusters the settled cycles into attractors (same period and winding,
 * representative states within 2% of their scale) and computes basin
 * fractions, S_b and S_bb (Daza et al., Sci. Rep. 6, 31416 (2016), whole
 * boxes of 5 x 5 points from the grid's first point; NaN for a grid under 5
 * on a side). Returns 0, SP_E_NOMEM or SP_E_INPUT. */
int sp_basins_read(FILE *fp, const struct sp_sweep_desc *d, struct sp_basin_map *map);

/* How map's entropies were taken, for a legend or a message: "boxes of 5x5
 * points", "...; the last 2 of 12 columns left out", or "none: the 40x4
 * grid has no box ..." when it has none. */
void sp_basins_box_text(const struct sp_basin_map *map, char *buf, size_t size);

void sp_basins_free(struct sp_basin_map *map);

/* ---- precession.c -------------------------------------------------------- */

/* The swinging spring's precession per exchange (3-D scenes): rows
 * precession (degrees per exchange), exchanges (maxima of the swing less
 * one), exchange_period (s), from samples every d->sample s over d->time
 * after d->transient (precession.c says how). Returns 0, SP_E_NOMEM or
 * SP_E_INTERRUPTED. */
int sp_precession_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                          const long *pts, const int *skip, int n, int forced, FILE *rows,
                          long *blown_up);

/* ---- continuation.c ------------------------------------------------------ */

/* Orbit diagram rows with the peak column, for points scenes[0..n) run each
 * from its own start (no continuation). */
int sp_orbit_peak_measure(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                          const long *pts, const int *skip, int n, int forced, FILE *rows,
                          long *blown_up);

/* A whole continued orbit diagram over the grid of d (one axis), written in
 * the grid's order (for each point, the up branch's rows, then the down
 * branch's). One thread: a branch is a sequence. Starts within 0.05 degrees
 * and 0.001 rad/s of hanging are moved to 0.05 degrees (the hanging state of
 * a vertically driven pendulum is invariant: without a seed an upward branch
 * would never leave it). Returns 0, SP_E_NOMEM, SP_E_IO or
 * SP_E_INTERRUPTED. */
int sp_orbit_continue(const struct sp_sweep_desc *d, const struct sp_scene *base, int forced,
                      FILE *fp, long *blown_up);

#endif
