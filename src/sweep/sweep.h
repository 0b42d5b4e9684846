/* springpend (internal): sweeps. A grid over one or two numeric scene keys,
 * every point integrated by the batched integrator (batch.h) on all cores,
 * one measurement per point, streamed as CSV in the grid's order. The CSV
 * carries its own description (a first "# springpend sweep" line), so the
 * figure is drawn from the CSV alone: a whole run and the merge of its
 * shards give the same CSV bytes and the same figure.
 *
 * CSV layout: line 1 the description, line 2 the column names, then rows.
 *   lyapunov: point,KEY[,KEY2],lyapunov,lyapunov_half   (1/s; the value at T/2)
 *   orbit:    point,KEY,t,theta,r                       (s, degrees, m)
 *   poincare: point,KEY[,KEY2],t,r,r_dot,theta_dot      (s, m, m/s, rad/s)
 *   orbit with --continue or --peak (spectrum.h's neighbour continuation.c):
 *             point,KEY,t,theta,r,branch,peak               (branch: 0 none,
 *             1 up, -1 down; peak: the largest |theta| (degrees) or r (m)
 *             over the drive period that ends at the sample)
 *   spectrum: point,KEY[,KEY2],T,lambda1,lambda2,lambda3,lambda4,sum,kaplan_yorke
 *             (running values at checkpoints T; the last row of a point is
 *             at T = time; 1/s, the dimension unitless)
 *   basins:   point,KEY,KEY2,period,winding,theta,r,theta_dot,r_dot,settled
 *             (basins.h)
 *   precession: point,KEY[,KEY2],precession,exchanges,exchange_period
 *             (degrees per exchange, 1, s; analysis.h; 3-D scenes)
 * orbit and poincare: a point without a sample or crossing in the span (or,
 * poincare, a start that cannot have the energy) writes one row of its own,
 * t = T0 + T and the values nan, so that every point has rows (a merge
 * tells a point dropped: sweep_rows.c).
 * lyapunov and precession sweep 3-D scenes (initial.azimuth_rate != 0);
 * the other measures are of the planar motion and refuse them.
 * A shard's CSV has a "# shard I/N" line after the description and ends
 * with "# end rows=N sha256=HEX", the SHA-256 of every byte before that
 * line, so that --merge can refuse a copy cut short or edited.
 * Shared with: cli. */
#ifndef SPRINGPEND_SWEEP_H
#define SPRINGPEND_SWEEP_H

#include <signal.h>
#include <stdio.h>

#include "springpend/csv_metadata.h"
#include "springpend/scene.h"

struct sp_sweep_desc;

enum sp_measure {
    SP_MEASURE_LYAPUNOV,
    SP_MEASURE_ORBIT,
    SP_MEASURE_POINCARE,
    SP_MEASURE_SPECTRUM,
    SP_MEASURE_BASINS,
    SP_MEASURE_PRECESSION,
    SP_MEASURE_COUNT,
};

/* Orbit diagrams' continuation (--continue): each parameter value starts
 * from the previous value's final state, upward, downward, or both. */
enum sp_continue { SP_CONTINUE_NONE, SP_CONTINUE_UP, SP_CONTINUE_DOWN, SP_CONTINUE_BOTH };
enum { SP_PEAK_THETA = 1, SP_PEAK_R = 2 };

/* The measure's name ("lyapunov", ...) and its CSV columns after the keys. */
const char *sp_sweep_measure_name(enum sp_measure m);
const char *sp_sweep_columns(const struct sp_sweep_desc *d);

#define SP_SWEEP_MAX_AXES 2
#define SP_SWEEP_MAX_POINTS 50000000L /* a map's figure holds 16 bytes per point */

struct sp_sweep_axis {
    char key[48];  /* "section.key" */
    double from, to; /* file units (degrees for angles) */
    int count;     /* grid points along the axis, >= 1 */
};

/* basins: stroboscopic samples per drive period (each one a time the
 * integration lands on; cli_sweep.c's estimate counts them) */
#define SP_BASINS_SAMPLES 8

/* What a sweep computes; the figure is drawn from this and the rows. */
struct sp_sweep_desc {
    char scene[64];              /* the scene's name, for titles */
    enum sp_measure measure;
    struct sp_sweep_axis axis[SP_SWEEP_MAX_AXES];
    int n_axes;
    double time;                 /* measured span T, s */
    double transient;            /* s integrated before measuring */
    double energy;               /* poincare: the energy every orbit has, J */
    int driven;                  /* orbit: 1 stroboscopic (drive period), 0 Poincare crossings */
    char method[16];             /* the integrator's name */
    double dt;                   /* its step, s (fixed-step methods) */
    double tolerance;            /* dopri5 and dop853 (run as DOP853): integrator.tolerance
                                  * (header word tolerance=, written when > 0; 0 in a
                                  * sweep of a fixed-step method or an older CSV) */
    int theme, colormap;         /* the scene's look, for the figure */
    enum sp_continue cont;       /* orbit: continuation (header word continue=) */
    int peak;                    /* orbit: 0, or SP_PEAK_THETA / SP_PEAK_R: also the
                                  * largest |theta| (or r) over each drive period */
    int fast;                    /* lyapunov, rk4, undamped and undriven: 1 = the batch's
                                  * fast kernel (sweep --fast; header word kernel=fast) */
    double sample;               /* precession: the sampling interval, s, a 32nd of the
                                  * grid's shortest pendulum period (sp_sweep_check;
                                  * not in the header) */
    const volatile sig_atomic_t *cancel; /* the caller's stop flag (not in the
                                  * header): once set, a run stops with
                                  * SP_E_INTERRUPTED; NULL = never */
    double max_rows;             /* orbit and poincare: a run whose rows pass it
                                  * stops, SP_E_INPUT after a message (not in the
                                  * header); 0 = no limit */
};

/* 1 once d's caller asked the sweep to stop (*d->cancel set). */
static inline int sp_sweep_cancelled(const struct sp_sweep_desc *d)
{
    return d->cancel && *d->cancel;
}

/* Point p's index along each axis (the first axis varies fastest). */
void sp_sweep_point_index(const struct sp_sweep_desc *d, long p, int idx[SP_SWEEP_MAX_AXES]);

/* The value of axis a at index i, in file units. */
double sp_sweep_axis_value(const struct sp_sweep_axis *a, int i);

/* How d's points were integrated, for a figure or a message: "rk4 at dt =
 * 0.001 s", "DOP853 at tolerance 1e-06" (dopri5: "... (dopri5 runs as DOP853)"). */
void sp_sweep_method_text(const struct sp_sweep_desc *d, char *buf, size_t size);

/* Grid points in all. */
long sp_sweep_points(const struct sp_sweep_desc *d);

/* Every column of the sweep's CSV (point, the keys, then the measure's),
 * with what it is and its unit, into out (at most max); returns how many.
 * The names point into static storage: one sweep at a time. */
int sp_sweep_column_info(const struct sp_sweep_desc *d, struct sp_csv_column *out, int max);

/* Writes the description line ("# springpend sweep ...\n"), `between` (a
 * shard's "# shard I/N\n" line, or NULL) and the column names. Returns 0 or
 * SP_E_IO. */
int sp_sweep_write_header(FILE *fp, const struct sp_sweep_desc *d, const char *between);

/* Parses a description line back (the line without its newline). Returns 0
 * or SP_E_INPUT (no message; the caller names the file). */
int sp_sweep_parse_header(const char *line, struct sp_sweep_desc *d);

/* What a shard's rows must be, checked row by row (sp_sweep_row_check). */
struct sp_sweep_rows {
    const struct sp_sweep_desc *d;
    long first, last; /* the shard's points [first, last) */
    long rows;        /* rows checked so far */
    long point;       /* the last row's point, -1 before the first */
    double t;         /* orbit, poincare: the last row's time, s */
    int blown;        /* the last row was a blown-up point's NaN row */
    /* the rows of a point as a sequence (sweep_rows.c) */
    const struct sp_scene *base; /* the sweep's scene (the shards' dc:source, --set
                                  * applied): a driven orbit's drive frequency when it
                                  * is not varied; NULL: that rule is not checked */
    int branch;       /* orbit --continue/--peak: the last row's branch column */
    long seq;         /* rows of the current point and branch so far */
    double k;         /* driven orbit: the last row's drive period k (t = k/f) */
    int group_blown;  /* the current point and branch is one NaN row */
};

/* Checks one row (with its newline) as the sweep writes it: as many
 * fields as the columns (sp_sweep_columns), the point an integer in
 * [first, last), one row per point in order (lyapunov, basins) or the
 * points' rows in order; the key values the grid's own (as written,
 * %.10g); the measured values finite decimal numbers or "nan" (no inf, hex
 * or blanks). Lyapunov, orbit and poincare rows (sweep.c's own) also: a
 * point that blew up is one row of nan only, an event's time lies in the
 * measured span (within a step) and a point's times ascend. Returns NULL,
 * or what is wrong (for "FILE:LINE: WHAT"). */
const char *sp_sweep_row_check(struct sp_sweep_rows *r, const char *line);

/* After a shard's last row (sweep_rows.c): the last point's rows whole and
 * every point after it one that writes no row. Returns NULL, or what is
 * wrong. The row rules of every measure, beyond each row's own form:
 *   lyapunov, basins, precession: one row per point, every point;
 *   spectrum: every point, its rows at exactly the renormalisation times T
 *     of the checkpoints, in order, the last at T = time (or one row at
 *     T = time of NaN: it blew up);
 *   orbit of a driven scene (with --peak and --continue too, per branch):
 *     rows at exactly t = k/f for every whole k with T0 <= k/f up to the
 *     last step's end (sp_sweep_strobe_range), in order, each once;
 *   orbit of an undriven scene, poincare: each point's times strictly
 *     ascending in the measured span;
 *   or, for a point (branch) of the last two, one NaN row (it blew up) or
 *     one row t = T0 + T and NaN (no sample or crossing; poincare: nor the
 *     energy). Every point of the shard is there. */
const char *sp_sweep_rows_end(struct sp_sweep_rows *r);

/* A driven orbit's samples at drive frequency f (Hz): the first and last k
 * of t = k/f that the steps of d->dt over [0, T0 + T] sample (none when
 * *k1 < *k0), and whether some are skipped (*gaps: a drive period no
 * longer than a step, which samples once a step). */
void sp_sweep_strobe_range(const struct sp_sweep_desc *d, double f, double *k0, double *k1,
                           int *gaps);

/* A running sweep's report to its caller (progress bar), from the calling
 * thread: points done of total. */
typedef void (*sp_sweep_progress_fn)(void *user, long done, long total);

/* Runs points [first, last) of the grid of d over `base` (a scene with the
 * run's integrator) on `threads` threads (0: one per core) and writes their
 * rows to fp in the grid's order (no header). *blown_up counts points whose
 * integration blew up (NaN rows; the run goes on), *unreachable the
 * poincare points whose energy cannot be met (skipped). Returns 0,
 * SP_E_IO, SP_E_NOMEM or SP_E_INTERRUPTED (a signal; rows written so far
 * are incomplete). The grid's scenes must have been checked already
 * (sp_sweep_check). */
int sp_sweep_run(const struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                 long last, int threads, FILE *fp, long *blown_up, long *unreachable,
                 sp_sweep_progress_fn progress, void *user);

/* Checks that every key can be varied and both ends of every axis give a
 * valid scene, and that the measure can be taken on the grid (3-D points:
 * lyapunov and precession only; precession: some 3-D point, gravity);
 * fills d's derived fields (driven, energy if < 0: the base scene's,
 * method, dt, theme, sample). Messages name `origin`. */
int sp_sweep_check(struct sp_sweep_desc *d, const struct sp_scene *base, int energy_given);

/* The scene of grid point p: base with the axes' values set (and, for
 * poincare, the angle rate that gives the sweep's energy). Returns 0, or 1
 * when the energy cannot be reached from that start. */
int sp_sweep_point_scene(const struct sp_sweep_desc *d, const struct sp_scene *base, long p,
                         struct sp_scene *out);

/* The most rows grid point s (its scene, from sp_sweep_point_scene) of an
 * orbit diagram of an undriven scene or a Poincare mosaic can write: its
 * crossings of theta = 0 over d->time, bounded from its energy (see
 * sweep.c), else by one every two steps of d->dt (*by_steps = 1). */
double sp_sweep_point_rows_max(const struct sp_sweep_desc *d, const struct sp_scene *s,
                               int *by_steps);

/* How a sweep's figure looks (sweep_plot.c): its printed size and the
 * scene's [view]. Zero means the default: 900 x 600 pt, the CSV's theme and
 * colormap, DejaVu Sans, the measure's own title. */
struct sp_plot_style {
    double page_w, page_h;      /* pt: a printed size (sweep --size 8.6cm); 0 = none */
    double dpi;                 /* a PNG's at a printed size; 0 = 300 (without one:
                                   2 px per pt) */
    const struct sp_view *view; /* theme, colormap, background, font, font_size (pt),
                                   font_scale, title; NULL = the CSV's look */
    int title_set;              /* 1: view->title is the title ("" = none) */
    const char *scene_file;     /* provenance: the sweep's base scene as a scene
                                   file (PDF /Subject, SVG <metadata>); NULL = none */
    const struct sp_scene *scene; /* provenance: that scene, for a PNG's text
                                   chunks as a still's (provenance.h); NULL = none */
    const char *command;        /* provenance: the command without its -o; NULL = none */
    const volatile sig_atomic_t *cancel; /* the caller's stop flag: once set, drawing
                                   stops and nothing is written
                                   (SP_E_INTERRUPTED); NULL = never */
    const struct sp_sweep_desc *desc; /* sp_sweep_plot_check: the sweep the figure is
                                   of (its measure, keys, title and legend); NULL =
                                   any. sp_sweep_plot takes the CSV's */
};

/* Draws the figure for the CSV in fp (rewound and read to the end) into
 * path (.png, .svg or .pdf), written whole into *figure's .part and left
 * there: the caller commits it once everything else the run writes (the
 * CSV and its metadata) is in place, or discards it (outfile.h), so that
 * a run that fails leaves no figure. On failure *figure is closed. Lives in
 * sweep_plot.c (cairo); the executable reaches it through the module that
 * module.h loads (springpend-plot.so), so that cairo costs only the
 * commands that draw.
 * Returns 0, SP_E_INPUT (not a sweep CSV; a text the figure cannot draw or
 * fit, as sp_sweep_plot_check) or SP_E_IO. */
int sp_sweep_plot(FILE *csv, const char *csv_name, const char *path,
                  const struct sp_plot_style *style, struct sp_outfile *figure);

/* Checks, before a sweep runs, that its figure can draw the style's texts:
 * the [view] font exists, every character of the title, xlabel, ylabel and
 * colorbar_label is in some installed font, the title wraps to at
 * most half the page's height, and the plot inside the margins its text
 * takes at view.font_size is large enough for it (the default figure's
 * of style->desc; a printed size's). 0, or SP_E_INPUT having said what is wrong
 * and where it was set; SP_E_NOMEM / SP_E_IO. In the plot module too. */
int sp_sweep_plot_check(const struct sp_plot_style *style);

#endif
