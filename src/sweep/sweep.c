/* springpend: sweeps (see sweep.h). The grid is cut into chunks of CHUNK
 * points; workers (one per core) take chunks in order, integrate each as one
 * batch and format its rows; the calling thread writes the chunks in grid
 * order as they complete. At most WINDOW chunks per worker are held, and a
 * chunk's long rows wait in a temporary file (struct chunk_out), so memory
 * stays flat whatever the grid's size and the measured span. Every point's numbers depend
 * on its own scene only, so the thread count, the chunking and the shards
 * never change a byte. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "base/cpu_count.h"
#include "base/decimal.h"
#include "springpend/batch.h"
#include "springpend/common.h"
#include "springpend/sim.h"
#include "analysis.h"
#include "base/array.h"
#include "sweep.h"
#include "frame/text.h"

#define CHUNK 32  /* points per batch */
#define WINDOW 4  /* chunks held per worker, finished or not */
#define RAD2DEG 57.29577951308232

static const char *const measure_names[] = {"lyapunov", "orbit", "poincare", "spectrum",
                                            "basins", "precession"};
static const char *const continue_names[] = {"none", "up", "down", "both"};
static const char *const method_names[] = {"rk4", "verlet", "yoshida4", "dopri5", "dop853",
                                           "rkn1210"};

/* ---- the grid and its description ---------------------------------------- */

void sp_sweep_method_text(const struct sp_sweep_desc *d, char *buf, size_t size)
{
    const int dopri5 = !strcmp(d->method, "dopri5");
    if (dopri5 || !strcmp(d->method, "dop853")) {
        char tol[48] = " at its tolerance"; /* an older CSV: not recorded */
        if (d->tolerance > 0)
            snprintf(tol, sizeof(tol), " at tolerance %g", d->tolerance);
        snprintf(buf, size, "DOP853%s%s", tol, dopri5 ? " (dopri5 runs as DOP853)" : "");
    } else {
        snprintf(buf, size, "%s at dt = %g s", d->method, d->dt);
    }
}

long sp_sweep_points(const struct sp_sweep_desc *d)
{
    long n = 1;
    for (int a = 0; a < d->n_axes; a++)
        n *= d->axis[a].count;
    return n;
}

void sp_sweep_point_index(const struct sp_sweep_desc *d, long p, int idx[SP_SWEEP_MAX_AXES])
{
    for (int a = 0; a < SP_SWEEP_MAX_AXES; a++) {
        int n = a < d->n_axes ? d->axis[a].count : 1;
        idx[a] = (int)(p % n);
        p /= n;
    }
}

double sp_sweep_axis_value(const struct sp_sweep_axis *a, int i)
{
    if (a->count <= 1)
        return a->from;
    if (i == a->count - 1)
        return a->to;
    return a->from + (a->to - a->from) * i / (a->count - 1);
}

const char *sp_sweep_measure_name(enum sp_measure m)
{
    return (int)m >= 0 && m < SP_MEASURE_COUNT ? measure_names[m] : "?";
}

const char *sp_sweep_columns(const struct sp_sweep_desc *d)
{
    static const char *const columns[] = {
        "lyapunov,lyapunov_half", "t,theta,r", "t,r,r_dot,theta_dot",
        "T,lambda1,lambda2,lambda3,lambda4,sum,kaplan_yorke",
        "period,winding,theta,r,theta_dot,r_dot,settled",
        "precession,exchanges,exchange_period"};
    if (d->measure == SP_MEASURE_ORBIT && (d->cont || d->peak))
        return "t,theta,r,branch,peak";
    return columns[d->measure];
}

int sp_sweep_column_info(const struct sp_sweep_desc *d, struct sp_csv_column *out, int max)
{
    static const struct sp_csv_column known[] = {
        {"lyapunov", "largest Lyapunov exponent over the measured span T", "1/s"},
        {"lyapunov_half", "largest Lyapunov exponent over T/2", "1/s"},
        {"t", "simulated time of the sample", "s"},
        {"theta", "angle from the downward vertical", "degrees"},
        {"r", "spring length", "m"},
        {"r_dot", "rate of change of r", "m/s"},
        {"theta_dot", "rate of change of theta", "rad/s"},
        {"branch", "continuation branch: 0 none, 1 up, -1 down", "1"},
        {"T", "span the running values are taken over", "s"},
        {"lambda1", "largest Lyapunov exponent", "1/s"},
        {"lambda2", "second Lyapunov exponent", "1/s"},
        {"lambda3", "third Lyapunov exponent", "1/s"},
        {"lambda4", "fourth Lyapunov exponent", "1/s"},
        {"sum", "sum of the four exponents", "1/s"},
        {"kaplan_yorke", "Kaplan-Yorke dimension", "1"},
        {"period", "period of the settled cycle in drive periods (0: undecided)", "1"},
        {"winding", "whole turns per cycle (rotating when not 0)", "1"},
        {"settled", "simulated time the start was settled at", "s"},
        {"precession", "the swing plane's mean turn about the vertical per exchange, from +x "
                       "towards +z (between successive maxima of the swing)", "degrees"},
        {"exchanges", "exchanges measured (maxima of the swing less one)", "1"},
        {"exchange_period", "mean time between successive maxima of the swing", "s"},
    };
    static char names[SP_SWEEP_MAX_AXES + 16][24];
    const struct sp_csv_column peak = {
        "peak", d->peak == SP_PEAK_R ? "largest r over the drive period that ends at the sample"
                                     : "largest |theta| over the drive period that ends at the "
                                       "sample", d->peak == SP_PEAK_R ? "m" : "degrees"};
    int n = 0;
    if (n < max)
        out[n++] = (struct sp_csv_column){"point", "grid point (the first key varies fastest)", "1"};
    for (int a = 0; a < d->n_axes && n < max; a++) {
        const char *unit = sp_scene_key_unit(d->axis[a].key);
        out[n++] = (struct sp_csv_column){d->axis[a].key, "the varied scene key (file units)",
                                          unit ? unit : "1"};
    }
    for (const char *c = sp_sweep_columns(d); *c && n < max && n < (int)(sizeof(names) /
                                                                          sizeof(names[0]));) {
        const size_t len = strcspn(c, ",");
        snprintf(names[n], sizeof(names[n]), "%.*s", (int)len, c);
        out[n] = (struct sp_csv_column){names[n], "?", "1"};
        if (!strcmp(names[n], "peak"))
            out[n] = peak;
        for (size_t i = 0; i < sizeof(known) / sizeof(known[0]); i++)
            if (!strcmp(known[i].name, names[n]))
                out[n] = known[i];
        n++;
        c += len + (c[len] == ',');
    }
    return n;
}

int sp_sweep_write_header(FILE *fp, const struct sp_sweep_desc *d, const char *between)
{
    fprintf(fp, "# springpend sweep scene=%s measure=%s time=%.17g transient=%.17g "
            "energy=%.17g driven=%d method=%s dt=%.17g theme=%d colormap=%d",
            d->scene, measure_names[d->measure], d->time, d->transient, d->energy, d->driven,
            d->method, d->dt, d->theme, d->colormap);
    if (d->tolerance > 0) /* adaptive: what decided the steps (older sweeps' bytes stay) */
        fprintf(fp, " tolerance=%.17g", d->tolerance);
    if (d->cont) /* only when asked for: older sweeps' bytes stay as they were */
        fprintf(fp, " continue=%s", continue_names[d->cont]);
    if (d->peak)
        fprintf(fp, " peak=%s", d->peak == SP_PEAK_R ? "r" : "theta");
    if (d->fast)
        fprintf(fp, " kernel=fast");
    for (int a = 0; a < d->n_axes; a++)
        fprintf(fp, " vary=%s=%.17g:%.17g:%d", d->axis[a].key, d->axis[a].from,
                d->axis[a].to, d->axis[a].count);
    fprintf(fp, "\n%spoint", between ? between : "");
    for (int a = 0; a < d->n_axes; a++)
        fprintf(fp, ",%s", d->axis[a].key);
    return fprintf(fp, ",%s\n", sp_sweep_columns(d)) < 0 ? SP_E_IO : 0;
}

int sp_sweep_parse_header(const char *line, struct sp_sweep_desc *d)
{
    const char *prefix = "# springpend sweep ";
    memset(d, 0, sizeof(*d));
    d->measure = -1;
    if (strncmp(line, prefix, strlen(prefix)))
        return SP_E_INPUT;
    char buf[1024];
    snprintf(buf, sizeof(buf), "%s", line + strlen(prefix));
    int seen = 0;
    for (char *save = NULL, *w = strtok_r(buf, " \n", &save); w; w = strtok_r(NULL, " \n", &save)) {
        char *eq = strchr(w, '=');
        if (!eq)
            return SP_E_INPUT;
        *eq = 0;
        const char *v = eq + 1;
        if (!strcmp(w, "scene"))
            snprintf(d->scene, sizeof(d->scene), "%s", v);
        else if (!strcmp(w, "measure")) {
            for (int i = 0; i < SP_MEASURE_COUNT; i++)
                if (!strcmp(v, measure_names[i]))
                    d->measure = (enum sp_measure)i;
        } else if (!strcmp(w, "continue")) {
            d->cont = SP_CONTINUE_NONE;
            for (int i = 1; i < 4; i++)
                if (!strcmp(v, continue_names[i]))
                    d->cont = (enum sp_continue)i;
            if (!d->cont)
                return SP_E_INPUT;
        } else if (!strcmp(w, "peak")) {
            if (strcmp(v, "theta") && strcmp(v, "r"))
                return SP_E_INPUT;
            d->peak = !strcmp(v, "r") ? SP_PEAK_R : SP_PEAK_THETA;
        } else if (!strcmp(w, "kernel")) {
            if (strcmp(v, "fast"))
                return SP_E_INPUT;
            d->fast = 1;
        } else if (!strcmp(w, "time"))
            d->time = strtod(v, NULL);
        else if (!strcmp(w, "transient"))
            d->transient = strtod(v, NULL);
        else if (!strcmp(w, "energy"))
            d->energy = strtod(v, NULL);
        else if (!strcmp(w, "driven"))
            d->driven = atoi(v);
        else if (!strcmp(w, "method"))
            snprintf(d->method, sizeof(d->method), "%s", v);
        else if (!strcmp(w, "dt"))
            d->dt = strtod(v, NULL);
        else if (!strcmp(w, "tolerance")) {
            d->tolerance = strtod(v, NULL);
            if (!(d->tolerance > 0 && d->tolerance < 1))
                return SP_E_INPUT;
        }
        else if (!strcmp(w, "theme"))
            d->theme = atoi(v);
        else if (!strcmp(w, "colormap"))
            d->colormap = atoi(v);
        else if (!strcmp(w, "vary") && d->n_axes < SP_SWEEP_MAX_AXES) {
            struct sp_sweep_axis *a = &d->axis[d->n_axes];
            const char *eq2 = strchr(v, '=');
            if (!eq2 || eq2 - v >= (long)sizeof(a->key) ||
                sscanf(eq2 + 1, "%lf:%lf:%d", &a->from, &a->to, &a->count) != 3 || a->count < 1)
                return SP_E_INPUT;
            snprintf(a->key, sizeof(a->key), "%.*s", (int)(eq2 - v), v);
            d->n_axes++;
        } else
            return SP_E_INPUT;
        seen++;
    }
    return seen && (int)d->measure >= 0 && d->n_axes > 0 ? 0 : SP_E_INPUT;
}

/* ---- rows read back ------------------------------------------------------- */

/* 1 when value field (read as v) is exactly what one of the row writers'
 * formats prints for v (%.6f, %.6g, %.7g, %.9g, %.10g: sweep.c, basins.c,
 * spectrum.c, precession.c, continuation.c), so an edit in another form
 * ("+0.5", ".5", "5.0", "1e-00", "05") is refused even with the SHA-256
 * recomputed; never "-0", which the writers avoid. */
static int printf_form(const char *f, double v)
{
    static const char *const forms[] = {"%.6f", "%.6g", "%.7g", "%.9g", "%.10g"};
    char buf[64];
    if (!strcmp(f, "-0"))
        return 0;
    for (size_t i = 0; i < sizeof(forms) / sizeof(*forms); i++) {
        snprintf(buf, sizeof(buf), forms[i], v);
        if (!strcmp(buf, f))
            return 1;
    }
    return 0;
}

/* What kind of row an orbit's or poincare row is: 0 measured, 1 the NaN
 * row of a point that blew up, 2 the row of a point without an event (one
 * row of its own: t = T0 + T, tf, and the values NaN, the branch column
 * kept), -1 neither (NaN in some values only). Other measures: 0. */
static int row_mark(const struct sp_sweep_desc *d, const char *tf, int first_nan, int nan,
                    int nv)
{
    const int ext = d->measure == SP_MEASURE_ORBIT && (d->cont || d->peak);
    char end[32];
    if (d->measure != SP_MEASURE_ORBIT && d->measure != SP_MEASURE_POINCARE)
        return 0;
    if (first_nan || !nan)
        return first_nan;
    snprintf(end, sizeof(end), "%.10g", d->transient + d->time);
    return !strcmp(tf, end) && nan == nv - 1 - ext ? 2 : -1;
}

const char *sp_sweep_row_check(struct sp_sweep_rows *r, const char *line)
{
    const struct sp_sweep_desc *d = r->d;
    const char *columns = sp_sweep_columns(d);
    int nv = 1;
    for (const char *c = columns; *c; c++)
        nv += *c == ',';
    /* the measures whose rows sweep.c writes itself: a blown-up point is one
     * row of nan only, an event's time lies in the measured span and a
     * point's times ascend; the analysis measures (analysis.h) write nan in
     * some columns of a row, and several branches of a point */
    const int plain = d->measure == SP_MEASURE_LYAPUNOV || d->measure == SP_MEASURE_POINCARE ||
                      (d->measure == SP_MEASURE_ORBIT && !d->cont && !d->peak);
    const int one_per_point = d->measure == SP_MEASURE_LYAPUNOV ||
                              d->measure == SP_MEASURE_BASINS ||
                              d->measure == SP_MEASURE_PRECESSION;
    const int n = 1 + d->n_axes + nv;
    char field[64], want[32], tf[64] = "";
    double t = 0, v, branch = 0;
    int first_nan = 0;
    int nan = 0, idx[SP_SWEEP_MAX_AXES];
    long point = -1;
    const char *p = line;
    for (int i = 0; i < n; i++) {
        const size_t len = strcspn(p, ",\n");
        if (p[len] != (i + 1 < n ? ',' : '\n') || len >= sizeof(field))
            return i + 1 < n ? "too few numbers or one too long" : "not a whole row";
        memcpy(field, p, len);
        field[len] = 0;
        p += len + 1;
        if (i == d->n_axes + 1) /* the first value: a time (T for spectrum) */
            memcpy(tf, field, len + 1), first_nan = !strcmp(field, "nan");
        if (i == d->n_axes + 4 && (d->cont || d->peak)) /* orbit's branch column */
            branch = !strcmp(field, "nan") ? 2 : strtod(field, NULL);
        if (i == 0) { /* the point, as "%ld" */
            point = strtol(field, NULL, 10);
            snprintf(want, sizeof(want), "%ld", point);
            if (strcmp(field, want))
                return "the point is not an integer";
            if (point < r->first || point >= r->last)
                return "the point is not one of this shard's";
            sp_sweep_point_index(d, point, idx);
        } else if (i <= d->n_axes) { /* the grid's value, as sp_sweep_format_point writes it */
            snprintf(want, sizeof(want), "%.10g",
                     sp_sweep_axis_value(&d->axis[i - 1], idx[i - 1]));
            if (strcmp(field, want))
                return "a key's value is not the grid's value for this point";
        } else if (!strcmp(field, "nan")) {
            nan++;
        } else if (sp_decimal_read(field, &v) != SP_DECIMAL_OK) {
            return "a value is not a finite decimal number (nan, inf and hex are not written)";
        } else if (!printf_form(field, v)) {
            return "a value in a form springpend does not write (printf's %.6f, or %g at 6, "
                   "7, 9 or 10 digits: no '+', no bare '.', no leading or trailing zeros, no "
                   "-0, no e-00)";
        } else if (d->measure == SP_MEASURE_PRECESSION && i == d->n_axes + 2 &&
                   !(v >= 0 && v == floor(v))) {
            return "the number of exchanges is not a count (a whole number, 0 or more)";
        } else if (d->measure == SP_MEASURE_PRECESSION && i == d->n_axes + 3 && !(v > 0)) {
            return "the exchange period is not a positive time";
        } else if (i == d->n_axes + 1) {
            t = v; /* the first value: a time for orbit and poincare */
        }
    }
    if (*p)
        return "more than a row";
    const int mark = row_mark(d, tf, first_nan, nan, nv);
    if (mark < 0)
        return "a row is all numbers, all nan (a point that blew up) or, for a point "
               "without an event, the span's end T0 + T and nan";
    if (one_per_point && point != r->first + r->rows)
        return "not the next point's row (one row per point, in order)";
    if (point < r->point)
        return "a point's rows after a later point's";
    if (branch != floor(branch) || fabs(branch) > 1)
        return "the branch is not 1, -1 or 0";
    /* the point's rows in sequence (sweep_rows.c); a spectrum's NaN row has T */
    const char *wrong = sp_sweep_row_sequence(r, point, (int)branch, tf, t,
                                              d->measure == SP_MEASURE_SPECTRUM ? nan > 0 : mark);
    if (wrong)
        return wrong;
    if (plain && nan && nan != nv && mark != 2)
        return "a row is either all numbers or all nan (a point that blew up)";
    if (plain && d->measure != SP_MEASURE_LYAPUNOV) {
        const double slack = d->dt > 0 ? d->dt : 0;
        if (point == r->point && (nan || r->blown))
            return "a point that blew up has one row";
        if (point == r->point && !(t > r->t))
            return "a point's times do not strictly ascend (allowed: one row per event, each "
                   "later than the last)";
        if (!nan && !(t >= d->transient - slack && t <= d->transient + d->time + slack))
            return "a time outside the measured span";
        r->t = t;
    }
    r->point = point;
    r->blown = nan > 0;
    r->rows++;
    return NULL;
}

/* ---- the scenes of the grid ---------------------------------------------- */

/* The scene's total energy at t = 0, J. */
static double scene_energy(const struct sp_scene *s)
{
    struct sp_sim sim;
    sp_sim_init(&sim, s);
    return sim.energy0;
}

/* Poincare sweeps at one energy E: dtheta/dt at t = 0 from
 * E = m/2 (r'^2 + r^2 theta'^2) + k/2 (r - L0)^2 - m g r cos(theta), with the
 * sign of the base scene's rate (+ when 0). Returns 1 when E is too low. */
static int set_energy(struct sp_scene *s, double energy, double sign)
{
    double m = s->pendulum.mass, r = s->initial.length, rd = s->initial.length_rate;
    double u = 0.5 * s->pendulum.stiffness * (r - s->pendulum.natural_length) *
                   (r - s->pendulum.natural_length) -
               m * s->pendulum.gravity * r * cos(s->initial.angle);
    double kin = energy - u - 0.5 * m * rd * rd;
    if (!(kin >= 0))
        return 1;
    s->initial.angle_rate = sign * sqrt(2 * kin / m) / r;
    return 0;
}

int sp_sweep_point_scene(const struct sp_sweep_desc *d, const struct sp_scene *base, long p,
                         struct sp_scene *out)
{
    int idx[SP_SWEEP_MAX_AXES];
    *out = *base;
    sp_sweep_point_index(d, p, idx);
    for (int a = 0; a < d->n_axes; a++)
        if (sp_scene_set_number(out, d->axis[a].key, sp_sweep_axis_value(&d->axis[a], idx[a]),
                                "--vary"))
            return -1; /* checked before: not reached */
    if (d->measure == SP_MEASURE_POINCARE)
        return set_energy(out, d->energy, base->initial.angle_rate < 0 ? -1 : 1);
    return 0;
}

/* The most rows grid point s of an event sweep (orbit undriven, poincare:
 * upward crossings of theta = 0, checked once a step dt after the
 * transient) can write over d->time. A crossing needs x < 0 at one check
 * and x >= 0 at the next, so there is at most one every two steps: that
 * bound (*by_steps = 1) is all there is when a drive can pump energy in, in
 * 3-D, or when the energy lets the bob reach the pivot. Else, with damping
 * b >= 0, the energy never exceeds E (the start's, plus 2% for the
 * integration's drift), and V = k/2 (r - L0)^2 - m g r cos(theta) >=
 * W(r) = k/2 (r - L0)^2 - m g r keeps r in [r1, r2] where W = E, and
 * m/2 r^2 theta'^2 <= E - W(r) bounds |theta'| by
 * w1^2 = 2/m (B^2 / (4 |A|) - k/2), A = E - k L0^2 / 2 < 0, B = k L0 + m g.
 * Between two crossings theta either turns 2 pi (taking >= 2 pi / w1) or
 * has two zeros; theta'' + (2 r'/r + b/m) theta' + (g/r)(sin theta/theta)
 * theta = 0 is, with theta = u exp(-1/2 int a), u'' + Q u = 0 with
 * Q = (g/r)(sin theta/theta - cos theta) - (b/2m)^2 - theta'^2 +
 * (k/m)(1 - L0/r) <= 1.07 g / r1 + (k/m)(1 - L0/r2) = w2^2, so (Sturm)
 * zeros are >= pi / w2 apart. Hence at most 1 + T max(w1, w2) / (2 pi). */
double sp_sweep_point_rows_max(const struct sp_sweep_desc *d, const struct sp_scene *s,
                               int *by_steps)
{
    const double steps = floor(d->time / d->dt / 2) + 2;
    struct sp_sim sim;
    sp_sim_init(&sim, s);
    const struct sp_params *p = &sim.p;
    const double m = p->mass, k = p->stiffness, L0 = p->L0, g = p->g;
    *by_steps = 1;
    if (sim.spatial || p->drive_amp != 0 || !(p->b_over_m >= 0) || !(k > 0) || !(m > 0) ||
        !(g >= 0))
        return steps;
    const double E = sim.energy0 + 0.02 * (fabs(sim.energy0) + m * g * (L0 + m * g / k));
    const double A = E - 0.5 * k * L0 * L0, B = k * L0 + m * g, disc = B * B + 2 * k * A;
    if (!(A < 0) || !(disc >= 0))
        return steps; /* the bob may reach the pivot: theta' unbounded */
    const double r1 = (B - sqrt(disc)) / k, r2 = (B + sqrt(disc)) / k;
    const double w1 = sqrt(fmax(0, 2 / m * (B * B / (4 * -A) - k / 2)));
    const double w2 = sqrt(fmax(0, 1.07 * g / r1 + k / m * (1 - L0 / r2)));
    const double rows = 1 + ceil(d->time * fmax(w1, w2) / (2 * M_PI));
    if (!(r1 > 0) || !(rows < steps))
        return steps;
    *by_steps = 0;
    return rows;
}

/* The scene's name as the CSV header's one word and the figure's title:
 * whole UTF-8 characters only (cairo refuses the rest), a space, '=' or
 * control byte (which would split the header) or a malformed byte as '_'. */
static void header_name(char *dst, size_t size, const char *name)
{
    size_t at = 0, n;
    for (; *name; name += n ? n : 1) {
        n = sp_utf8_char(name);
        if (at + (n ? n : 1) >= size)
            break;
        if (n > 1)
            memcpy(dst + at, name, n), at += n;
        else
            dst[at++] = n && (unsigned char)*name > ' ' && *name != '=' && *name != 0x7F
                        ? *name : '_';
    }
    dst[at] = 0;
}

static int grid_forced(const struct sp_sweep_desc *d, const struct sp_scene *base);

/* The scene at a corner of the grid (bit a of corner: axis a's end). */
static struct sp_scene corner_scene(const struct sp_sweep_desc *d, const struct sp_scene *base,
                                    int corner)
{
    struct sp_scene s = *base;
    for (int a = 0; a < d->n_axes; a++)
        sp_scene_set_number(&s, d->axis[a].key,
                            (corner >> a) & 1 ? d->axis[a].to : d->axis[a].from, "--vary");
    return s;
}

/* The largest |initial.azimuth_rate| on the grid, rad/s: 0 when every point
 * is planar (the rate is linear along its axis, so its ends decide). */
static double grid_azimuth_rate(const struct sp_sweep_desc *d, const struct sp_scene *base)
{
    double most = 0;
    for (int corner = 0; corner < (1 << d->n_axes); corner++)
        most = fmax(most, fabs(corner_scene(d, base, corner).initial.azimuth_rate));
    return most;
}

/* The 3-D checks: which measures take 3-D points, and precession's needs
 * and sampling interval (d->sample). */
static int check_spatial(struct sp_sweep_desc *d, const struct sp_scene *base)
{
    const double rate = grid_azimuth_rate(d, base);
    const enum sp_measure m = d->measure;
    if (rate != 0 && m != SP_MEASURE_LYAPUNOV && m != SP_MEASURE_PRECESSION) {
        sp_log_error("--measure %s: the grid leaves the x-y plane (initial.azimuth_rate up to "
                     "%g rad/s), and %s is of the planar motion (theta in the plane); 3-D "
                     "points take --measure lyapunov or precession, or set "
                     "initial.azimuth_rate = 0 (--set initial.azimuth_rate=0)",
                     measure_names[m], rate, measure_names[m]);
        return SP_E_INPUT;
    }
    if (rate != 0 && d->fast) {
        sp_log_error("--fast: the fast kernel steps planar pendulums only, and the grid leaves "
                     "the x-y plane (initial.azimuth_rate up to %g rad/s); leave --fast out "
                     "(the exact kernel integrates 3-D points)", rate);
        return SP_E_INPUT;
    }
    if (m != SP_MEASURE_PRECESSION)
        return 0;
    if (rate == 0) {
        sp_log_error("--measure precession: every point of the grid swings in the x-y plane "
                     "(initial.azimuth_rate = 0), whose swing plane never turns; give the "
                     "scene an initial.azimuth_rate (rad/s, e.g. --set "
                     "initial.azimuth_rate=1) or vary it (--vary "
                     "initial.azimuth_rate=0.2:2:10)");
        return SP_E_INPUT;
    }
    d->sample = INFINITY;
    for (int corner = 0; corner < (1 << d->n_axes); corner++) {
        const struct sp_scene s = corner_scene(d, base, corner);
        if (!(s.pendulum.gravity > 0)) {
            sp_log_error("--measure precession: pendulum.gravity = %g m/s^2 on the grid; the "
                         "swing's period, over which its plane is measured, needs gravity > 0",
                         s.pendulum.gravity);
            return SP_E_INPUT;
        }
        struct sp_sim sim;
        struct sp_physics ph;
        sp_sim_init(&sim, &s);
        sp_params_physics(&sim.p, &ph);
        /* l / g = L0 / g + m / k is monotonic in every key: the corners
         * hold the shortest period */
        d->sample = fmin(d->sample, 2 * M_PI / ph.omega_p / 32);
    }
    return 0;
}

/* Checks --vary's axis a: a physics key with a number, given once, its
 * ends valid for base, its values apart. 0, or SP_E_INPUT (said). */
static int check_axis(const struct sp_sweep_desc *d, const struct sp_scene *base, int a)
{
    const char *k = d->axis[a].key;
    if (strncmp(k, "pendulum.", 9) && strncmp(k, "initial.", 8) && strncmp(k, "pivot.", 6)) {
        sp_log_error("--vary %s: only the physics can be varied: keys of [pendulum], "
                     "[initial] and [pivot] (see 'springpend keys')", k);
        return SP_E_INPUT;
    }
    if (!sp_scene_key_unit(k)) {
        sp_log_error("--vary %s: no such numeric key; see 'springpend keys'", k);
        return SP_E_INPUT;
    }
    if (d->measure == SP_MEASURE_POINCARE && !strcmp(k, "initial.angle_rate")) {
        sp_log_error("--vary initial.angle_rate: a poincare sweep derives it from the "
                     "energy (--energy); vary initial.length, initial.angle or "
                     "initial.length_rate instead");
        return SP_E_INPUT;
    }
    for (int b = 0; b < a; b++)
        if (!strcmp(k, d->axis[b].key)) {
            sp_log_error("--vary %s is given twice", k);
            return SP_E_INPUT;
        }
    for (int end = 0; end < 2; end++) {
        struct sp_scene s = *base;
        char origin[192]; /* as sp_log_error's messages, the option and the end named */
        snprintf(origin, sizeof(origin), "springpend: --vary %s=%.9g:%.9g:%d (%s %.9g)", k,
                 d->axis[a].from, d->axis[a].to, d->axis[a].count, end ? "TO" : "FROM",
                 end ? d->axis[a].to : d->axis[a].from);
        if (sp_scene_set_number(&s, k, end ? d->axis[a].to : d->axis[a].from, origin))
            return SP_E_INPUT;
    }
    /* distinct points, far enough apart for the figure's axis to tell
     * them apart (a span of a few ulps hung the tick loop) */
    const struct sp_sweep_axis *x = &d->axis[a];
    const double step = fabs(x->to - x->from) / (x->count > 1 ? x->count - 1 : 1);
    if (x->count == 1 && x->from != x->to) {
        sp_log_error("--vary %s=%.9g:%.9g:1: one value cannot run from %.9g to %.9g; "
                     "allowed: COUNT 2 or more for a range, or FROM = TO for one value "
                     "(--vary %s=%.9g:%.9g:1)", k, x->from, x->to, x->from, x->to, k,
                     x->from, x->from);
        return SP_E_INPUT;
    }
    /* relative to the values' size, as the axis code labels any range
     * whose span is over 1e-9 of its magnitude (axis.c), tiny ones too;
     * a step of DBL_MIN or less is no longer a number's full precision */
    if (x->count > 1 && !(step > 1e-9 * fmax(fabs(x->from), fabs(x->to)) && step > DBL_MIN)) {
        sp_log_error("--vary %s=%.17g:%.17g:%d: the %d values are %s; allowed: FROM and TO "
                     "apart by more than 1e-9 of the larger of |FROM| and |TO| for each "
                     "step, and by more than %g (or COUNT 1)", k,
                     x->from, x->to, x->count, x->count,
                     x->from == x->to ? "all the same" : "too close to tell apart", DBL_MIN);
        return SP_E_INPUT;
    }
    return 0;
}

/* A basins map: two axes, and a damped, driven scene at both corners of
 * the grid. 0, or SP_E_INPUT (said). */
static int check_basins(const struct sp_sweep_desc *d, const struct sp_scene *base)
{
    if (d->n_axes != 2) {
        sp_log_error("--measure basins draws a map over two keys (two starting keys, or "
                     "one and a parameter): give two --vary");
        return SP_E_INPUT;
    }
    for (int end = 0; end < 2; end++) {
        struct sp_scene s = *base;
        for (int a = 0; a < d->n_axes; a++)
            sp_scene_set_number(&s, d->axis[a].key, end ? d->axis[a].to : d->axis[a].from,
                                "--vary");
        if (!(s.pivot.frequency > 0 && s.pivot.amplitude > 0 && s.pendulum.damping > 0)) {
            sp_log_error("--measure basins needs a damped, driven scene over the whole "
                         "grid: pivot.frequency > 0, pivot.amplitude > 0 and "
                         "pendulum.damping > 0 (here %g Hz, %g m, %g N*s/m)",
                         s.pivot.frequency, s.pivot.amplitude, s.pendulum.damping);
            return SP_E_INPUT;
        }
    }
    return 0;
}

/* --time for the lyapunov and spectrum measures: a whole number (2 or
 * more) of the fixed steps' renormalisations, or renormalisations the
 * adaptive steps resolve. 0, or SP_E_INPUT (said). */
static int check_renormalisation(const struct sp_sweep_desc *d, const struct sp_scene *base)
{
    struct sp_lyap_grid g;
    sp_sweep_lyap_grid(d->time, base->integrator.method, base->integrator.dt, &g);
    const double x = d->time / g.tau;
    if (g.fixed && (g.K < 2 || fabs(x - (double)g.K) > 1e-9 * x)) {
        const double lo = fmax(2, floor(x)) * g.tau, hi = fmax(2, ceil(x)) * g.tau;
        char alt[64] = "";
        if (hi != lo)
            snprintf(alt, sizeof(alt), " or %.10g", hi);
        sp_log_error("--time %g: %s renormalises the tangent every tau = %.10g s (%ld steps "
                     "of integrator.dt = %g s) and measures a whole number of them, at "
                     "least 2; use --time %.10g%s",
                     d->time, measure_names[d->measure], g.tau, g.m,
                     base->integrator.dt, lo, alt);
        return SP_E_INPUT;
    }
    /* dop853 lands on every renormalisation: a step below about 1e-14
     * of the time collapses (batch.c), so keep tau well above that */
    const double floor_s = 1e-9 * fmax(1, d->transient + d->time);
    if (!g.fixed && !(g.tau > floor_s)) {
        sp_log_error("--time %g: too short to measure: %s renormalises every T/%ld = %g s, "
                     "below what the adaptive steps resolve after %g s (%g s); use --time "
                     "%g or more", d->time, measure_names[d->measure], g.K, g.tau,
                     d->transient + d->time, floor_s, 2 * floor_s * 1.000001);
        return SP_E_INPUT;
    }
    return 0;
}

/* On the vertical as the scene check has it (scene.c): within 1e-9 degrees
 * of a multiple of 180. */
static int on_vertical(double degrees)
{
    const double v = fmod(fabs(degrees), 180);
    return !(v > 1e-9 && v < 180 - 1e-9);
}

/* A grid point inside the range that the scene check refuses though both
 * ends pass (check_axis): a 3-D start on the vertical, where the azimuth
 * rate has nothing to turn (initial.angle=-5:5:3 has 0 in the middle;
 * attack13 #27). The point's angle depends on its angle axis alone and its
 * rate on its rate axis alone, so one look along each finds it. 0, or
 * SP_E_INPUT (said). */
static int check_vertical_points(const struct sp_sweep_desc *d, const struct sp_scene *base)
{
    int ia = -1, ir = -1, idx[SP_SWEEP_MAX_AXES] = {0};
    for (int a = 0; a < d->n_axes; a++) {
        ia = !strcmp(d->axis[a].key, "initial.angle") ? a : ia;
        ir = !strcmp(d->axis[a].key, "initial.azimuth_rate") ? a : ir;
    }
    double angle = base->initial.angle * 180 / M_PI, rate = base->initial.azimuth_rate;
    int found = 0;
    for (int i = 0; ia >= 0 && i < d->axis[ia].count && !found; i++)
        if (on_vertical(sp_sweep_axis_value(&d->axis[ia], i)))
            found = 1, idx[ia] = i, angle = sp_sweep_axis_value(&d->axis[ia], i);
    if (ia >= 0 ? !found : !on_vertical(angle))
        return 0;
    found = 0;
    for (int j = 0; ir >= 0 && j < d->axis[ir].count && !found; j++)
        if (sp_sweep_axis_value(&d->axis[ir], j) != 0)
            found = 1, idx[ir] = j, rate = sp_sweep_axis_value(&d->axis[ir], j);
    if (ir >= 0 ? !found : rate == 0)
        return 0;
    const int a = ia >= 0 ? ia : ir; /* the axis that brings it in */
    const struct sp_sweep_axis *x = &d->axis[a];
    sp_log_error("--vary %s=%.9g:%.9g:%d: point %ld has initial.angle = %g degrees, on the "
                 "vertical, with initial.azimuth_rate = %g rad/s, which has nothing to turn "
                 "there (the scene check refuses such a start); allowed: a grid whose "
                 "initial.angle values miss 0 and 180 degrees (e.g. an even COUNT over a range "
                 "symmetric about 0), or initial.azimuth_rate = 0 there", x->key, x->from,
                 x->to, x->count, (long)idx[0] + (d->n_axes > 1 ? (long)idx[1] * d->axis[0].count : 0),
                 angle + 0.0, rate);
    return SP_E_INPUT;
}

int sp_sweep_check(struct sp_sweep_desc *d, const struct sp_scene *base, int energy_given)
{
    header_name(d->scene, sizeof(d->scene), base->name);
    snprintf(d->method, sizeof(d->method), "%s", method_names[base->integrator.method]);
    d->dt = base->integrator.dt;
    d->tolerance = base->integrator.method == SP_METHOD_DOPRI5 ||
                           base->integrator.method == SP_METHOD_DOP853
                       ? base->integrator.tolerance
                       : 0;
    d->theme = base->view.theme;
    d->colormap = base->view.colormap;
    if (base->integrator.method == SP_METHOD_RKN1210) {
        sp_log_error("integrator.method = rkn1210 cannot sweep; use rk4, yoshida4, verlet or "
                     "dop853 (--set integrator.method=dop853)");
        return SP_E_INPUT;
    }
    int varies_frequency = 0;
    for (int a = 0; a < d->n_axes; a++) {
        if (check_axis(d, base, a))
            return SP_E_INPUT;
        varies_frequency |= !strcmp(d->axis[a].key, "pivot.frequency");
    }
    if (check_vertical_points(d, base))
        return SP_E_INPUT;
    if (sp_sweep_points(d) > SP_SWEEP_MAX_POINTS) {
        sp_log_error("--vary: %ld grid points; at most %ld (the figure keeps two numbers "
                     "per point); split the range over several sweeps", sp_sweep_points(d),
                     (long)SP_SWEEP_MAX_POINTS);
        return SP_E_INPUT;
    }
    if (d->measure == SP_MEASURE_ORBIT && d->n_axes != 1) {
        sp_log_error("--measure orbit draws one diagram over one key: give one --vary");
        return SP_E_INPUT;
    }
    d->driven = base->pivot.frequency > 0 || varies_frequency;
    if ((d->cont || d->peak) && (d->measure != SP_MEASURE_ORBIT || !d->driven)) {
        sp_log_error("--continue and --peak belong to orbit diagrams of a driven scene "
                     "(--measure orbit, pivot.frequency > 0)");
        return SP_E_INPUT;
    }
    /* continuation carries each value's final state to the next: a key of
     * [initial] would be overwritten by it (attack13 #3) */
    if (d->cont && !strncmp(d->axis[0].key, "initial.", 8)) {
        sp_log_error("--continue %s: continuation follows a parameter; %s is the start, which "
                     "each value takes from the last one's final state; allowed: vary a "
                     "[pendulum] or [pivot] key (pivot.amplitude, pivot.frequency, "
                     "pendulum.stiffness, ...)", continue_names[d->cont], d->axis[0].key);
        return SP_E_INPUT;
    }
    /* an orbit diagram of a driven scene samples at t = k/f: a point of 0 Hz
     * has no such time (attack13 #13; basins refuses it too) */
    if (d->measure == SP_MEASURE_ORBIT && varies_frequency) {
        const struct sp_sweep_axis *x = &d->axis[0];
        if (!(x->from > 0 && x->to > 0)) {
            sp_log_error("--vary pivot.frequency=%g:%g:%d: an orbit diagram over the drive's "
                         "frequency samples theta at t = k/f, and %g Hz has no drive period; "
                         "allowed: FROM > 0 and TO > 0", x->from, x->to, x->count,
                         x->from > 0 ? x->to : x->from);
            return SP_E_INPUT;
        }
    }
    if (d->measure == SP_MEASURE_BASINS && check_basins(d, base))
        return SP_E_INPUT;
    if (d->fast && (d->measure != SP_MEASURE_LYAPUNOV ||
                    base->integrator.method != SP_METHOD_RK4 || grid_forced(d, base))) {
        sp_log_error("--fast: the fast kernel steps the lyapunov measure of undamped, undriven "
                     "scenes with integrator.method = rk4 (here --measure %s, method %s%s); "
                     "leave --fast out", measure_names[d->measure],
                     method_names[base->integrator.method],
                     grid_forced(d, base) ? ", damping or a moving pivot in the grid" : "");
        return SP_E_INPUT;
    }
    if (d->fast && !sp_batch_fast_supported()) {
        sp_log_error("--fast: the fast kernel needs AVX-512F and FMA, which this CPU lacks; "
                     "leave --fast out");
        return SP_E_INPUT;
    }
    if (check_spatial(d, base))
        return SP_E_INPUT;
    if (energy_given && d->measure != SP_MEASURE_POINCARE) {
        sp_log_error("--energy %g: only --measure poincare puts every orbit at one energy; "
                     "--measure %s starts each point from its scene's own state, so --energy "
                     "would be ignored; leave it out", d->energy, measure_names[d->measure]);
        return SP_E_INPUT;
    }
    if (d->measure == SP_MEASURE_POINCARE && !energy_given)
        d->energy = scene_energy(base);
    if (!(d->time > 0) || !(d->transient >= 0)) {
        sp_log_error("--time must be > 0 and --transient >= 0 (simulated seconds)");
        return SP_E_INPUT;
    }
    if ((d->measure == SP_MEASURE_LYAPUNOV || d->measure == SP_MEASURE_SPECTRUM) &&
        check_renormalisation(d, base))
        return SP_E_INPUT;
    return 0;
}

void sp_sweep_lyap_grid(double time, enum sp_method method, double dt, struct sp_lyap_grid *g)
{
    g->fixed = method == SP_METHOD_RK4 || method == SP_METHOD_VERLET ||
               method == SP_METHOD_YOSHIDA4;
    if (g->fixed) {
        g->m = lround(fmax(1.0, 1.0 / dt));
        g->tau = (double)g->m * dt;
        g->K = lround(time / g->tau);
    } else { /* no grid: T in whole intervals of at most a second, at least 2 */
        g->m = 1;
        g->K = (long)fmax(2, ceil(time - 1e-9));
        g->tau = time / (double)g->K;
    }
}

/* ---- rows into memory ----------------------------------------------------- */

struct sbuf {
    char *s;
    size_t len, cap;
    int failed;
};

__attribute__((format(printf, 2, 3))) static void sb_printf(struct sbuf *b, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        size_t room = b->cap - b->len;
        va_start(ap, fmt);
        int n = b->s ? vsnprintf(b->s + b->len, room, fmt, ap) : -1;
        va_end(ap);
        if (n >= 0 && (size_t)n < room) {
            b->len += (size_t)n;
            return;
        }
        /* n < 0: vsnprintf failed, or b->s is NULL: grow and retry */
        const size_t need = n >= 0 ? b->len + (size_t)n + 1 : 2 * b->cap + 1;
        if (SP_ARRAY_RESERVE(b->s, b->cap, need, 4096)) {
            b->failed = 1;
            return;
        }
    }
}

char *sp_sweep_format_point(char *buf, size_t size, const struct sp_sweep_desc *d, long p)
{
    int idx[SP_SWEEP_MAX_AXES];
    size_t at = 0;
    sp_sweep_point_index(d, p, idx);
    at += (size_t)snprintf(buf, size, "%ld", p);
    for (int a = 0; a < d->n_axes && at < size; a++)
        at += (size_t)snprintf(buf + at, size - at, ",%.10g",
                               sp_sweep_axis_value(&d->axis[a], idx[a]));
    if (at + 1 < size)
        buf[at++] = ',', buf[at] = 0;
    return buf;
}

/* "p,v1[,v2]," the start of point p's rows. */
static void row_start(struct sbuf *b, const struct sp_sweep_desc *d, long p)
{
    char buf[160];
    sb_printf(b, "%s", sp_sweep_format_point(buf, sizeof(buf), d, p));
}

/* ---- measurements on one chunk ------------------------------------------- */

/* A chunk's rows: lane i's rows (point first + i) are its spilled blocks,
 * in order, then lane[i]. An orbit's rows grow with --time; a lane holding
 * more than SPILL_BYTES moves them to the chunk's temporary file, so the
 * memory a chunk holds stays under 2 * CHUNK * SPILL_BYTES (the lanes'
 * buffers; and 24 bytes of index per block spilled) whatever the span. Lyapunov
 * rows are one per point, all in lane[0]. */
#define SPILL_BYTES 16384

struct spill_block {
    int lane;        /* -1: dropped (the orbit blew up) */
    size_t len;      /* bytes */
    long offset;     /* in the chunk's spill file */
};

struct chunk_out {
    struct sbuf lane[CHUNK];
    int n_lanes;
    FILE *spill;                 /* the blocks' temporary file, or NULL */
    struct spill_block *blocks;
    long n_blocks, cap_blocks;
    int spill_failed;            /* errno of a failed spill, else 0 */
    long blown_up, unreachable;
    atomic_long *made;           /* the rows every chunk of the run has made */
};

/* Counts a row of an event sweep; 1 (after a message, once a run) when the
 * run's rows pass d->max_rows: the estimate (cli_sweep.c) bounds them, so
 * this is the backstop that keeps a run from filling the disk if it is
 * ever wrong. */
static int row_made(const struct sp_sweep_desc *d, struct chunk_out *out)
{
    const long made = out->made ? atomic_fetch_add(out->made, 1) + 1 : 0;
    if (!(d->max_rows > 0) || made <= d->max_rows)
        return 0;
    if (made == (long)d->max_rows + 1)
        sp_log_error("the sweep's rows passed the limit of %.0f; stopped, "
                     "nothing written; allowed: fewer points (--vary's COUNT) or a shorter "
                     "--time", floor(d->max_rows));
    return 1;
}

/* Moves lane i's rows to the spill file. */
static void spill_lane(struct chunk_out *o, int i)
{
    struct sbuf *b = &o->lane[i];
    if (o->spill_failed || b->failed || !b->len)
        return;
    if (!o->spill && !(o->spill = tmpfile())) {
        o->spill_failed = errno ? errno : EIO;
        return;
    }
    if (SP_ARRAY_RESERVE(o->blocks, o->cap_blocks, o->n_blocks + 1, 64)) {
        b->failed = 1;
        return;
    }
    long at = ftell(o->spill);
    if (at < 0 || fwrite(b->s, 1, b->len, o->spill) != b->len) {
        o->spill_failed = errno ? errno : EIO;
        return;
    }
    o->blocks[o->n_blocks++] = (struct spill_block){.lane = i, .len = b->len, .offset = at};
    b->len = 0;
}

/* Writes the chunk's rows to fp in lane order. Returns 0 or SP_E_IO. */
static int write_chunk(struct chunk_out *o, FILE *fp)
{
    static char buf[SPILL_BYTES];
    if (o->spill && fflush(o->spill) != 0) {
        sp_log_error("cannot write a temporary file of the sweep's rows: %s", strerror(errno));
        return SP_E_IO;
    }
    for (int i = 0; i < o->n_lanes; i++) {
        for (long k = 0; k < o->n_blocks; k++) {
            const struct spill_block *bl = &o->blocks[k];
            for (size_t done = 0, n; bl->lane == i && done < bl->len; done += n) {
                n = bl->len - done < sizeof(buf) ? bl->len - done : sizeof(buf);
                if (pread(fileno(o->spill), buf, n, bl->offset + (long)done) != (ssize_t)n) {
                    sp_log_error("cannot read a temporary file of the sweep's rows: %s",
                                 strerror(errno ? errno : EIO));
                    return SP_E_IO;
                }
                if (fwrite(buf, 1, n, fp) != n)
                    goto fail;
            }
        }
        if (o->lane[i].len && fwrite(o->lane[i].s, 1, o->lane[i].len, fp) != o->lane[i].len)
            goto fail;
    }
    return 0;
fail:
    sp_log_error("cannot write the sweep's rows: %s", strerror(errno));
    return SP_E_IO;
}

static void chunk_out_free(struct chunk_out *o)
{
    for (int i = 0; i < CHUNK; i++)
        free(o->lane[i].s);
    if (o->spill)
        fclose(o->spill);
    free(o->blocks);
    memset(o, 0, sizeof(*o));
}

/* Benettin: renormalise the tangent every tau (about a second, on the grid
 * for fixed steps); lambda = sum of ln growth / T, and the same at T/2. */
static int measure_lyapunov(const struct sp_sweep_desc *d, struct sp_batch *b, const long *pts,
                            const int *skip, int n, struct chunk_out *out)
{
    struct sp_lyap_grid g;
    sp_sweep_lyap_grid(d->time, b->method, b->dt, &g);
    const int fixed = g.fixed;
    const long m = g.m, K = g.K;
    const double tau = g.tau;
    long k0 = (long)ceil(d->transient / tau - 1e-9);
    double growth[CHUNK], sum[CHUNK] = {0}, half[CHUNK] = {0};
#define TAU_TIME(k) (fixed ? (double)((k) * m) * b->dt : (double)(k) * tau)
    b->cancel = d->cancel; /* a long transient is one call */
    if (k0 > 0 && sp_batch_advance(b, TAU_TIME(k0)))
        return SP_E_INTERRUPTED;
    sp_batch_reset_tangent(b);
    for (long k = 1; k <= K; k++) {
        if (sp_sweep_cancelled(d) || sp_batch_advance(b, TAU_TIME(k0 + k)))
            return SP_E_INTERRUPTED;
        sp_batch_renormalise(b, growth);
        for (int i = 0; i < n; i++) {
            sum[i] += growth[i];
            if (k == K / 2)
                half[i] = sum[i] / (k * tau);
        }
    }
#undef TAU_TIME
    for (int i = 0; i < n; i++) {
        if (skip[i])
            continue;
        double lam = sum[i] / (K * tau);
        if (b->dead[i] || !isfinite(lam))
            lam = half[i] = NAN, out->blown_up++;
        row_start(&out->lane[0], d, pts[i]);
        sb_printf(&out->lane[0], "%.9g,%.9g\n", lam + 0.0, half[i] + 0.0); /* never "-0" */
    }
    return 0;
}

/* Events along each trajectory, checked every step dt after the transient:
 * the drive's period (stroboscopic, orbit with a moving pivot) or
 * theta = 0 with dtheta/dt > 0 (Poincare crossings: x goes from < 0 to
 * >= 0 below the pivot). Positions at an event come from the cubic Hermite
 * interpolant of the step (error ~ dt^4), velocities by linear
 * interpolation (~ dt^2). */
static int measure_events(const struct sp_sweep_desc *d, struct sp_batch *b,
                          const struct sp_scene *scenes, const long *pts, const int *skip, int n,
                          struct chunk_out *out)
{
    const double dt = d->dt, t_end = d->transient + d->time;
    const int strobe = d->measure == SP_MEASURE_ORBIT && d->driven;
    struct sbuf *rows = out->lane;
    double prev[4][CHUNK], last_k[CHUNK] = {0}; /* strobe: the last k sampled (k >= 1) */
    long made[CHUNK] = {0};                       /* each lane's rows */
    int ret = 0;
    for (long step = 0;; step++) {
        double t0 = (double)step * dt, t1 = (double)(step + 1) * dt;
        if (t0 >= t_end || ret)
            break;
        if (step % 1024 == 0 && sp_sweep_cancelled(d)) {
            ret = SP_E_INTERRUPTED;
            break;
        }
        for (int i = 0; i < n; i++)
            if (rows[i].len > SPILL_BYTES)
                spill_lane(out, i);
        for (int c = 0; c < 4; c++)
            memcpy(prev[c], b->out[c], sizeof(double) * (size_t)n);
        sp_batch_advance(b, t1);
        if (t1 < d->transient)
            continue;
        for (int i = 0; i < n; i++) {
            if (skip[i] || b->dead[i])
                continue;
            const double x0 = prev[0][i], y0 = prev[1][i], vx0 = prev[2][i], vy0 = prev[3][i];
            const double x1 = b->out[SP_BX][i], y1 = b->out[SP_BY][i];
            const double vx1 = b->out[SP_BVX][i], vy1 = b->out[SP_BVY][i];
            double s;
            if (strobe) {
                double f = scenes[i].pivot.frequency;
                if (!(f > 0))
                    continue;
                double k = floor(t1 * f * (1 + 1e-15)), te = k / f;
                /* k/f just past t1 (within the 1e-15) is this step's; the
                 * next step would take it again: once only, so a point's
                 * times strictly ascend (sp_sweep_rows_end) */
                if (!(te > t0 && te <= t1 * (1 + 1e-15) && te >= d->transient) ||
                    k <= last_k[i])
                    continue;
                last_k[i] = k;
                s = fmin(1, (te - t0) / dt);
                double x = sp_hermite(s, dt, x0, vx0, x1, vx1), y = sp_hermite(s, dt, y0, vy0, y1, vy1);
                row_start(&rows[i], d, pts[i]);
                sb_printf(&rows[i], "%.10g,%.9g,%.9g\n", te, atan2(x, -y) * RAD2DEG + 0.0,
                          hypot(x, y)); /* + 0.0: never "-0" */
                made[i]++;
                ret = row_made(d, out) ? SP_E_INPUT : ret;
                continue;
            }
            if (!(x0 < 0 && x1 >= 0 && y0 < 0 && y1 < 0))
                continue;
            s = x0 / (x0 - x1);
            for (int it = 0; it < 4; it++) { /* Newton on the Hermite x(s) */
                double hs = 1e-7, fx = sp_hermite(s, dt, x0, vx0, x1, vx1);
                double dfx = (sp_hermite(s + hs, dt, x0, vx0, x1, vx1) - fx) / hs;
                if (dfx != 0)
                    s = fmin(1, fmax(0, s - fx / dfx));
            }
            double x = sp_hermite(s, dt, x0, vx0, x1, vx1), y = sp_hermite(s, dt, y0, vy0, y1, vy1);
            double vx = vx0 + s * (vx1 - vx0), vy = vy0 + s * (vy1 - vy0);
            double r = hypot(x, y), rd = (x * vx + y * vy) / r, thd = (x * vy - y * vx) / (r * r);
            row_start(&rows[i], d, pts[i]);
            if (d->measure == SP_MEASURE_ORBIT)
                sb_printf(&rows[i], "%.10g,%.9g,%.9g\n", t0 + s * dt, 0.0, r);
            else
                sb_printf(&rows[i], "%.10g,%.9g,%.9g,%.9g\n", t0 + s * dt, r, rd + 0.0,
                          thd + 0.0); /* + 0.0: never "-0" */
            made[i]++;
            ret = row_made(d, out) ? SP_E_INPUT : ret;
        }
    }
    for (int i = 0; i < n; i++) {
        if (!skip[i] && b->dead[i]) {
            /* the points of a blown-up orbit are dropped; one NaN row says so */
            out->blown_up++;
            rows[i].len = 0;
            for (long k = 0; k < out->n_blocks; k++)
                if (out->blocks[k].lane == i)
                    out->blocks[k].lane = -1;
            row_start(&rows[i], d, pts[i]);
            sb_printf(&rows[i], d->measure == SP_MEASURE_ORBIT ? "nan,nan,nan\n" : "nan,nan,nan,nan\n");
        } else if (skip[i] || !made[i]) {
            /* no event in the span (or, poincare, a start that cannot have
             * the energy): one row says so, so that every point has rows
             * and a merge can tell a point dropped (sweep_rows.c) */
            row_start(&rows[i], d, pts[i]);
            sb_printf(&rows[i], "%.10g,%s\n", t_end,
                      d->measure == SP_MEASURE_ORBIT ? "nan,nan" : "nan,nan,nan");
        }
    }
    return ret;
}

/* The analysis measures (analysis.h) write their rows to a stream; here they
 * become the chunk's text. */
static int analysis_chunk(const struct sp_sweep_desc *d, const struct sp_scene *scenes,
                          const long *pts, const int *skip, int n, int forced,
                          struct chunk_out *out)
{
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp) {
        sp_log_error("out of memory for a sweep's rows");
        return SP_E_NOMEM;
    }
    int (*const fn)(const struct sp_sweep_desc *, const struct sp_scene *, const long *,
                    const int *, int, int, FILE *, long *) =
        d->measure == SP_MEASURE_SPECTRUM     ? sp_spectrum_measure
        : d->measure == SP_MEASURE_BASINS     ? sp_basins_measure
        : d->measure == SP_MEASURE_PRECESSION ? sp_precession_measure
                                              : sp_orbit_peak_measure;
    int ret = fn(d, scenes, pts, skip, n, forced, fp, &out->blown_up);
    if (fclose(fp) != 0 && !ret) {
        sp_log_error("out of memory for a sweep's rows");
        ret = SP_E_NOMEM;
    }
    out->n_lanes = 1;
    if (!ret)
        out->lane[0] = (struct sbuf){.s = text, .len = len, .cap = len + 1};
    else
        free(text);
    return ret;
}

static int run_chunk(const struct sp_sweep_desc *d, const struct sp_scene *base, int forced,
                     long first, int n, struct chunk_out *out)
{
    struct sp_scene scenes[CHUNK];
    const struct sp_scene *ptr[CHUNK];
    long pts[CHUNK];
    int skip[CHUNK];
    for (int i = 0; i < n; i++) {
        pts[i] = first + i;
        skip[i] = sp_sweep_point_scene(d, base, pts[i], &scenes[i]) != 0;
        if (skip[i]) {
            out->unreachable++;
            scenes[i] = *base; /* integrated for company, not written */
        }
        ptr[i] = &scenes[i];
    }
    if (d->measure == SP_MEASURE_SPECTRUM || d->measure == SP_MEASURE_BASINS ||
        d->measure == SP_MEASURE_PRECESSION || (d->measure == SP_MEASURE_ORBIT && d->peak))
        return analysis_chunk(d, scenes, pts, skip, n, forced, out);
    struct sp_batch *b;
    int ret = sp_batch_make(&b, ptr, n, d->measure == SP_MEASURE_LYAPUNOV, forced);
    if (ret)
        return ret;
    b->fast = d->fast; /* sp_sweep_check held it to what the kernel does */
    out->n_lanes = d->measure == SP_MEASURE_LYAPUNOV ? 1 : n;
    if (d->measure == SP_MEASURE_LYAPUNOV)
        ret = measure_lyapunov(d, b, pts, skip, n, out);
    else
        ret = measure_events(d, b, scenes, pts, skip, n, out);
    sp_batch_destroy(&b);
    for (int i = 0; i < n; i++)
        if (!ret && out->lane[i].failed) {
            sp_log_error("out of memory for a sweep's rows");
            ret = SP_E_NOMEM;
        }
    if (!ret && out->spill_failed) {
        sp_log_error("cannot write a temporary file of the sweep's rows: %s",
                     strerror(out->spill_failed));
        ret = SP_E_IO;
    }
    return ret;
}

/* ---- threads -------------------------------------------------------------- */

struct slot {
    int done;
    int ret;
    struct chunk_out out;
};

struct run {
    const struct sp_sweep_desc *d;
    const struct sp_scene *base;
    int forced;
    long first, last, n_chunks;
    int window;
    pthread_mutex_t lock;
    pthread_cond_t changed;
    long next, written;
    int stop, ret;                /* ret: the first failed chunk's */
    struct slot *slots;
    atomic_long made;             /* rows made (event sweeps) */
};

static void *worker(void *arg)
{
    struct run *r = arg;
    for (;;) {
        pthread_mutex_lock(&r->lock);
        while (!r->stop && r->next < r->n_chunks && r->next >= r->written + r->window)
            pthread_cond_wait(&r->changed, &r->lock);
        if (r->stop || r->next >= r->n_chunks) {
            pthread_mutex_unlock(&r->lock);
            return NULL;
        }
        long c = r->next++;
        pthread_mutex_unlock(&r->lock);
        struct chunk_out out;
        memset(&out, 0, sizeof(out));
        out.made = &r->made;
        long p0 = r->first + c * CHUNK;
        int n = (int)(r->last - p0 < CHUNK ? r->last - p0 : CHUNK);
        int ret = run_chunk(r->d, r->base, r->forced, p0, n, &out);
        pthread_mutex_lock(&r->lock);
        struct slot *s = &r->slots[c % r->window];
        s->out = out, s->ret = ret, s->done = 1;
        if (ret)
            r->stop = 1, r->ret = r->ret ? r->ret : ret;
        pthread_cond_broadcast(&r->changed);
        pthread_mutex_unlock(&r->lock);
    }
}

/* Whether any point of the grid has damping or a moving pivot (then every
 * batch takes the forced path, so no point's arithmetic depends on its
 * neighbours). Both ends of each axis suffice: the keys act monotonically. */
static int grid_forced(const struct sp_sweep_desc *d, const struct sp_scene *base)
{
    for (int corner = 0; corner < (1 << d->n_axes); corner++) {
        const struct sp_scene s = corner_scene(d, base, corner);
        struct sp_sim sim;
        sp_sim_init(&sim, &s);
        if (sim.forced)
            return 1;
    }
    return 0;
}

int sp_sweep_run(const struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                 long last, int threads, FILE *fp, long *blown_up, long *unreachable,
                 sp_sweep_progress_fn progress, void *user)
{
    struct run r = {.d = d, .base = base, .first = first, .last = last};
    atomic_init(&r.made, 0);
    int ret = 0;
    *blown_up = *unreachable = 0;
    if (threads <= 0)
        threads = sp_cpu_count(); /* those this process may use */
    r.forced = grid_forced(d, base);
    if (d->measure == SP_MEASURE_ORBIT && d->cont) { /* one sequence: no chunks */
        ret = sp_orbit_continue(d, base, r.forced, fp, blown_up);
        if (!ret && progress)
            progress(user, last - first, last - first);
        return ret;
    }
    r.n_chunks = (last - first + CHUNK - 1) / CHUNK;
    if (threads > r.n_chunks)
        threads = r.n_chunks > 0 ? (int)r.n_chunks : 1;
    r.window = WINDOW * threads;
    r.slots = calloc((size_t)r.window, sizeof(*r.slots));
    pthread_t *tid = calloc((size_t)threads, sizeof(*tid));
    if (!r.slots || !tid) {
        free(r.slots), free(tid);
        sp_log_error("out of memory for a sweep");
        return SP_E_NOMEM;
    }
    pthread_mutex_init(&r.lock, NULL);
    pthread_cond_init(&r.changed, NULL);
    int started = 0;
    for (; started < threads; started++)
        if (pthread_create(&tid[started], NULL, worker, &r))
            break;
    if (!started) {
        sp_log_error("cannot start a sweep thread");
        ret = SP_E_NOMEM;
    }
    for (long c = 0; !ret && c < r.n_chunks; c++) {
        struct slot *s = &r.slots[c % r.window];
        pthread_mutex_lock(&r.lock);
        while (!s->done && !r.stop && !sp_sweep_cancelled(d)) {
            struct timespec until;
            clock_gettime(CLOCK_REALTIME, &until);
            until.tv_nsec += 200000000;
            if (until.tv_nsec >= 1000000000)
                until.tv_sec++, until.tv_nsec -= 1000000000;
            pthread_cond_timedwait(&r.changed, &r.lock, &until);
        }
        const int failed = r.ret; /* a later chunk's, which said why */
        pthread_mutex_unlock(&r.lock);
        if (!s->done) {
            ret = sp_sweep_cancelled(d) ? SP_E_INTERRUPTED : failed ? failed : SP_E_NOMEM;
            break;
        }
        ret = s->ret;
        if (!ret)
            ret = write_chunk(&s->out, fp);
        *blown_up += s->out.blown_up;
        *unreachable += s->out.unreachable;
        chunk_out_free(&s->out);
        pthread_mutex_lock(&r.lock);
        memset(s, 0, sizeof(*s));
        r.written++;
        if (ret)
            r.stop = 1;
        pthread_cond_broadcast(&r.changed);
        pthread_mutex_unlock(&r.lock);
        if (progress) {
            long done = first + (c + 1) * CHUNK < last ? (c + 1) * CHUNK : last - first;
            progress(user, done, last - first);
        }
    }
    pthread_mutex_lock(&r.lock);
    r.stop = 1;
    pthread_cond_broadcast(&r.changed);
    pthread_mutex_unlock(&r.lock);
    for (int i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
    for (int i = 0; i < r.window; i++)
        chunk_out_free(&r.slots[i].out);
    if (!ret && sp_sweep_cancelled(d))
        ret = SP_E_INTERRUPTED;
    pthread_mutex_destroy(&r.lock);
    pthread_cond_destroy(&r.changed);
    free(r.slots);
    free(tid);
    return ret;
}
