/* springpend: the data export (data_export.h): samples the motion at the
 * frame times (or every `every` simulated seconds), or the Poincare
 * section's crossings, and writes CSV and its metadata. It integrates and
 * formats numbers, nothing else: no GL, no rendering. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/data_export.h"
#include "springpend/ensemble.h"
#include "springpend/frame.h"
#include "springpend/outfile.h"
#include "springpend/sim.h"
#include "base/signal_name.h"
#include "sim/sim_report.h"

/* The columns, as the header line names them (the metadata file's too). */
static const struct sp_csv_column sample_columns[] = {
    {"t", "simulated time", "s"},
    {"x", "the bob's horizontal position from the pivot", "m"},
    {"y", "the bob's height above the pivot (negative below)", "m"},
    {"vx", "horizontal velocity", "m/s"},
    {"vy", "vertical velocity", "m/s"},
    {"r", "spring length", "m"},
    {"theta", "angle from the downward vertical", "rad"},
    {"r_dot", "rate of change of r", "m/s"},
    {"theta_dot", "rate of change of theta", "rad/s"},
    {"kinetic", "kinetic energy", "J"},
    {"spring", "spring energy", "J"},
    {"gravity", "gravitational energy (zero at the pivot's height)", "J"},
    {"energy", "total energy", "J"},
    {"bounce", "bounce mode's energy above hanging still", "J"},
    {"swing", "swing mode's energy", "J"},
    {"work", "work done on the bob by damping and the moving pivot since t = 0", "J"},
    {"pivot_y", "the pivot's height in the lab", "m"},
};
static const struct sp_csv_column crossing_columns[] = {
    {"t", "simulated time of the crossing (theta = 0, theta_dot > 0)", "s"},
    {"r", "spring length", "m"},
    {"r_dot", "rate of change of r", "m/s"},
    {"theta_dot", "rate of change of theta", "rad/s"},
};
/* A spatial scene's columns after the sample columns (sim.h: spatial). */
static const struct sp_csv_column spatial_columns[] = {
    {"z", "the bob's position off the x-y plane", "m"},
    {"vz", "velocity along z", "m/s"},
    {"azimuth", "the swing plane's angle about the vertical, from +x, continuous from row to "
                "row", "degrees"},
};
#define N_OF(a) ((int)(sizeof(a) / sizeof((a)[0])))

/* The columns' names, comma-separated (comma first: after others). */
static int write_names(FILE *fp, const struct sp_csv_column *c, int n, int comma_first)
{
    for (int i = 0; i < n; i++)
        if (fprintf(fp, "%s%s", i || comma_first ? "," : "", c[i].name) < 0)
            return SP_E_IO;
    return 0;
}

/* One CSV row for the sim's current state; a spatial run's row goes on with
 * z, vz and the azimuth, degrees, continued from *azimuth (rad, updated). */
/* A CSV field as RFC 4180 writes it: quoted, with '"' doubled, when it holds
 * a comma, a quote or a line break; as it is otherwise. */
static int write_field(FILE *fp, const char *s)
{
    if (!s[strcspn(s, ",\"\r\n")])
        return fputs(s, fp) < 0 ? SP_E_IO : 0;
    if (fputc('"', fp) == EOF)
        return SP_E_IO;
    for (; *s; s++)
        if ((*s == '"' && fputc('"', fp) == EOF) || fputc(*s, fp) == EOF)
            return SP_E_IO;
    return fputc('"', fp) == EOF ? SP_E_IO : 0;
}

static int write_row(FILE *fp, const struct sp_sim *sim, double *azimuth, const char *name,
                     int spatial)
{
    const struct sp_state *s = &sim->s;
    struct sp_polar q;
    struct sp_energy e;
    if (sim->spatial) /* theta is signed by the side of this row's swing plane */
        *azimuth = sp_azimuth_unwrap(*azimuth, sp_state_azimuth(&sim->p, s));
    sp_state_polar_in(s, *azimuth, &q);
    sp_state_energy(&sim->p, s, &e);
    if (name && (write_field(fp, name) || fputc(',', fp) == EOF))
        return SP_E_IO;
    if (fprintf(fp,
                "%.10g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,"
                "%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g",
                s->t, s->x, s->y, s->vx, s->vy, q.r, q.theta, q.r_dot, q.theta_dot,
                e.kinetic, e.spring, e.gravity, e.total, e.bounce, e.swing, sim->work,
                sp_pivot_y(&sim->p, s->t)) < 0)
        return SP_E_IO;
    if (sim->spatial || spatial) {
        if (fprintf(fp, ",%.15g,%.15g,%.15g", s->z, s->vz, *azimuth * 180 / M_PI) < 0)
            return SP_E_IO;
    }
    return fputc('\n', fp) == EOF ? SP_E_IO : 0;
}

/* Writes the Poincare section's crossings over [0, video.duration] to fp as
 * they are found (the panel's code: sp_history_follow with samples off). */
static int write_crossings(FILE *fp, const struct sp_scene *sc,
                           const volatile sig_atomic_t *cancel)
{
    struct sp_sim sim;
    struct sp_history h = {.active = 1, .poincare = 1, .crossings_only = 1};
    int ret = write_names(fp, crossing_columns, N_OF(crossing_columns), 0) ||
              fputc('\n', fp) == EOF ? SP_E_IO : 0;
    sp_sim_init(&sim, sc);
    sim.cancel = cancel;
    sim.progress = sp_progress_sim;
    /* in pieces of about 1000 interpolation intervals, memory stays flat */
    const double piece = 1000 * 0.1 / sp_params_omega_max(&sim.p);
    for (double t = 0; !ret && t < sc->video.duration;) {
        t = fmin(sc->video.duration, t + piece);
        ret = cancel && *cancel ? SP_E_INTERRUPTED : sp_history_follow(&h, &sim, t);
        for (int i = 0; i < h.n_crossings && !ret; i++)
            if (fprintf(fp, "%.15g,%.15g,%.15g,%.15g\n", h.crossings[i].t, h.crossings[i].r,
                        h.crossings[i].r_dot, h.crossings[i].theta_dot) < 0)
                ret = SP_E_IO;
        h.n_crossings = 0;
    }
    if (ret == SP_E_UNSTABLE)
        sp_sim_explain(&sim);
    sp_history_destroy(&h);
    return ret;
}

/* Writes every sample of the scene to fp, or its crossings. Several scenes
 * (name not NULL): each row starts with the name, the header (first scene
 * only: header = 1) with "scene", and every row has the spatial columns
 * when spatial = 1. */
static int write_samples(FILE *fp, const struct sp_scene *sc, double every, int poincare,
                         const char *name, int header, int spatial,
                         const volatile sig_atomic_t *cancel)
{
    struct sp_sim sim;
    long n;
    if (poincare)
        return write_crossings(fp, sc, cancel);
    if (sc->ensemble.count > 1)
        return sp_ensemble_write_csv(fp, sc, every, cancel);
    if (every > 0)
        n = (long)floor(sc->video.duration / every * (1 + 1e-12)) + 1;
    else
        n = sp_scene_frame_count(sc);
    sp_sim_init(&sim, sc);
    double azimuth = 0;
    if (header && ((name && fputs("scene,", fp) < 0) ||
                   write_names(fp, sample_columns, N_OF(sample_columns), 0) ||
                   ((sim.spatial || spatial) &&
                    write_names(fp, spatial_columns, N_OF(spatial_columns), 1)) ||
                   fputc('\n', fp) == EOF))
        return SP_E_IO;
    sim.cancel = cancel;
    sim.progress = sp_progress_sim;
    for (long k = 0; k < n; k++) {
        double t = every > 0 ? k * every : sp_scene_frame_time(sc, (int)k);
        int ret = cancel && *cancel ? SP_E_INTERRUPTED : sp_sim_advance(&sim, t);
        if (ret == SP_E_UNSTABLE)
            sp_sim_explain(&sim);
        if (!ret)
            ret = write_row(fp, &sim, &azimuth, name, spatial);
        if (ret)
            return ret;
    }
    return 0;
}

/* NAME.csv-metadata.json's .part for the CSV at out (none for a stream):
 * the columns the rows have (an ensemble's: t, member, its key, x, y, vx,
 * vy), the scene and the command. sc: the several (1 .. 4) scenes, side
 * by side, each recorded in dc:source. */
static int write_metadata(struct sp_outfile *meta, const char *out,
                          const struct sp_data_desc *o, const struct sp_scene *sc, int several,
                          int spatial)
{
    const char *key_unit = sp_scene_key_unit(sc->ensemble.key);
    const struct sp_csv_column ensemble_columns[] = {
        sample_columns[0],
        {"member", "the member's index, 0 .. ensemble.count - 1", "1"},
        {sc->ensemble.key, "the member's value of ensemble.key (file units)",
         key_unit ? key_unit : "1"},
        sample_columns[1], sample_columns[2], sample_columns[3], sample_columns[4],
    };
    struct sp_csv_column all[1 + N_OF(sample_columns) + N_OF(spatial_columns)];
    struct sp_csv_meta m = {.scene = sc, .overrides = o->overrides,
                            .n_overrides = o->n_overrides,
                            .more = sc + 1, .n_more = several - 1}; /* side by side: all */
    if (o->poincare) {
        m.title = "springpend data --poincare: the Poincare section's crossings";
        m.columns = crossing_columns, m.n_columns = N_OF(crossing_columns);
    } else if (sc->ensemble.count > 1) {
        m.title = "springpend data: the ensemble's members, one row per member and time";
        for (int i = 0; i < N_OF(ensemble_columns); i++)
            all[m.n_columns++] = ensemble_columns[i];
        for (int i = 0; sp_ensemble_spatial(sc) && i < N_OF(spatial_columns); i++) /* 3-D */
            all[m.n_columns++] = spatial_columns[i];
        m.columns = all;
    } else {
        struct sp_sim sim; /* spatial or not, as write_samples will find */
        sp_sim_init(&sim, sc);
        if (several > 1) /* side by side: each scene's rows in turn */
            all[m.n_columns++] = (struct sp_csv_column){
                "scene", "the scene file's name without .ini (the scene's rows follow in turn)", "1"};
        for (int i = 0; i < N_OF(sample_columns); i++)
            all[m.n_columns++] = sample_columns[i];
        for (int i = 0; (sim.spatial || spatial) && i < N_OF(spatial_columns); i++)
            all[m.n_columns++] = spatial_columns[i];
        m.title = several > 1 ? "springpend data: several scenes' motions, each scene's rows in turn "
                            "(the scene described is the first)"
                          : "springpend data: the motion, one row per sample";
        m.columns = all;
    }
    return sp_csv_metadata_write(meta, out, &m);
}

int sp_data_run(const struct sp_data_desc *d)
{
    struct sp_outfile f = {.fd = -1, .slot = -1};
    struct sp_dirs dirs = {0};
    const char *out = d->output;
    int ret = 0, spatial = 0;
    for (int i = 0; i < d->n_scenes; i++)
        spatial |= d->scenes[i].initial.azimuth_rate != 0;
    int to_stdout = !strcmp(out, "-");
    const char *what = to_stdout ? "stdout" : out;
    if (!to_stdout && !sp_outfile_is_stream(out))
        ret = sp_dirs_make(out, &dirs);
    if (!ret)
        ret = sp_outfile_open(&f, out, SP_OUTFILE_STREAM);
    if (ret)
        goto done;
    FILE *fp = sp_outfile_fdopen(&f); /* f.fd is fp's now */
    if (!fp) {
        sp_log_error("%s: %s", what, strerror(errno));
        ret = SP_E_NOMEM;
        goto done;
    }
    static char buf[1 << 16];
    setvbuf(fp, buf, _IOFBF, sizeof(buf));
    sp_progress_begin(!d->quiet && !(to_stdout && (isatty(1) || sp_stderr_is_stdout())), "data",
                      d->t_end);
    for (int i = 0; !ret && i < d->n_scenes; i++)
        ret = write_samples(fp, &d->scenes[i], d->every, d->poincare,
                            d->n_scenes > 1 ? d->names[i] : NULL, i == 0,
                            spatial && d->n_scenes > 1, d->cancel);
    sp_progress_end();
    int write_errno = errno;
    if (fclose(fp) != 0 && !ret)
        ret = SP_E_IO, write_errno = errno;
    if (ret == SP_E_IO && sp_outfile_write_was_stopped()) /* a reader that did not read */
        ret = SP_E_INTERRUPTED;
    if (ret == SP_E_IO)
        sp_log_error("cannot write the CSV to %s: %s", what, write_errno == EPIPE
                     ? "the reader closed the pipe" : strerror(write_errno));
    int through = f.through;
    struct sp_outfile meta = {.fd = -1, .slot = -1};
    if (!ret)
        ret = write_metadata(&meta, out, d, d->scenes, d->n_scenes, spatial);
    if (!ret) /* the metadata first: when the CSV appears, it is there */
        ret = sp_outfile_commit_pair(&meta, &f, d->cancel);
    if (ret == SP_E_INTERRUPTED && !through) /* once, from either step (attack10 #17) */
        sp_log_error("interrupted by %s: %s not written",
                     sp_signal_name(d->cancel ? (int)*d->cancel : 0), out);
    else if (ret == SP_E_INTERRUPTED && sp_outfile_write_was_stopped())
        sp_log_error("interrupted by %s while %s waited for its reader: the CSV stops short",
                     sp_signal_name(d->cancel ? (int)*d->cancel : 0), what);
    if (!ret && !d->quiet && !through)
        sp_fprintf_line(stderr, "wrote %s", out);
done:
    if (ret) {
        sp_outfile_discard(&f);
        sp_dirs_remove_empty(&dirs);
    }
    sp_dirs_keep(&dirs);
    return ret;
}
