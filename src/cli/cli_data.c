/* springpend: the data command. Samples the motion at the frame times (or
 * every --every simulated seconds) and writes CSV. It integrates and
 * formats numbers, nothing else: no GL, no rendering. */
#include <math.h>
#include <stdio.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/ensemble.h"
#include "springpend/frame.h"
#include "springpend/outfile.h"
#include "springpend/sim.h"
#include "springpend/timeline.h"
#include "sim/sim_report.h"

/* The most rows one run writes, and the size of a typical row, bytes. */
#define MAX_ROWS 1e7
#define ROW_BYTES 260

static const char data_usage[] =
    "usage: springpend data SCENE [SCENE ...] [-o FILE.csv | -o -]\n"
    "                            [--every SECONDS | --poincare]\n"
    "                            [options]\n"
    "\n"
    "Writes the motion as CSV, one row per sample: by default at the video's frame\n"
    "times (k * speed / fps, k = 0 .. frames-1); with --every at t = 0, every,\n"
    "2 every, ... up to video.duration inclusive. No rendering is done.\n"
    "The scene's [timeline] is presentation (captions, slow motion, pauses in the\n"
    "video): data ignores it, so its frame times are those of [video] speed.\n"
    "Columns (SI units, angles in radians, positions relative to the pivot):\n"
    "  t,x,y,vx,vy,r,theta,r_dot,theta_dot,kinetic,spring,gravity,energy,\n"
    "  bounce,swing,work,pivot_y\n"
    "A scene that leaves the x-y plane (initial.azimuth_rate != 0) adds z,vz,azimuth:\n"
    "  z, vz: the horizontal axis out of the starting plane (x-y-z right-handed);\n"
    "  azimuth: the swing plane's angle about the vertical in degrees, from +x\n"
    "  towards +z: the major axis of the horizontal ellipse the swing traces in one\n"
    "  pendulum period (sim.h, sp_state_azimuth), made continuous from row to row\n"
    "  (a turn of over 90 degrees between two rows is read as the nearer one).\n"
    "  theta is then signed by the side of that plane the bob is on: positive\n"
    "  towards the azimuth (the planar convention, where azimuth is 0 and theta\n"
    "  = atan2(x, -y)), in (-pi, pi]; theta_dot is its rate.\n"
    "bounce + swing = energy - E_eq (E_eq: hanging still at l = L0 + m g / k);\n"
    "work: done on the bob by damping and the moving pivot since t = 0, so\n"
    "energy - work stays at its t = 0 value.\n"
    "Driven pivot (pivot.amplitude > 0): positions, velocities and energies are in\n"
    "the pivot's frame (gravity measured from the pivot's current height; the\n"
    "pivot's acceleration does work, counted in work); pivot_y is the pivot's\n"
    "height in the lab. Damping acts on the bob's velocity relative to the air,\n"
    "at rest in the lab. initial.length_rate and angle_rate are relative to the\n"
    "pivot, so the bob starts with the pivot's velocity added.\n"
    "With --poincare: one row per crossing of the Poincare section (theta = 0\n"
    "going forward, theta_dot > 0) over video.duration, located on a quintic\n"
    "Hermite interpolant as the Poincare panel does: t,r,r_dot,theta_dot.\n"
    "A scene with [ensemble] count = N > 1 writes its N members instead, N rows\n"
    "per time: t,member,KEY,x,y,vx,vy (KEY: ensemble.key's value, file units,\n"
    "17 digits; each member is the single run with --set KEY=that value;\n"
    "z,vz,azimuth follow for a 3-D scene; --poincare still writes the scene's own\n"
    "crossings).\n"
    "With 2 to 4 SCENE files (the scenes 'render' shows side by side), each scene's\n"
    "rows follow in turn, after a first column scene (the file's name without .ini);\n"
    "z,vz,azimuth are written for all when one scene is spatial; --poincare and\n"
    "[ensemble] take one scene.\n"
    "At most 1e7 rows (about 2.6 GB) are written; the video's frame limit does not\n"
    "apply. Default output: out/<scene>.csv, with out/<scene>.csv-metadata.json\n"
    "beside it (W3C CSV on the Web: each column's unit, the scene as a scene file,\n"
    "the command line, the version); '-o -' writes the CSV alone to stdout. A run that\n"
    "becomes unstable stops with exit status 3 and leaves no file (stdout keeps the\n"
    "rows before it, each of them checked against the blow-up guard).\n"
    "\n"
    "options:\n"
    "  -o, --output PATH      where to write (.csv, or - for stdout)\n"
    "  --every SECONDS        sampling interval in simulated seconds\n"
    "  --poincare             the Poincare section's crossings instead of samples\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable)\n"
    "  -q, --quiet            no 'wrote' line\n"
    "  -h, --help             this text\n";

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
        ret = *cancel ? SP_E_INTERRUPTED : sp_history_follow(&h, &sim, t);
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
        int ret = *cancel ? SP_E_INTERRUPTED : sp_sim_advance(&sim, t);
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
                          const struct sp_cli_options *o, const struct sp_scene *sc, int several,
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

int sp_cmd_data(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    struct sp_cli_options o;
    static struct sp_scene scenes[SP_CLI_MAX_SCENES]; /* big: not on the stack */
    struct sp_outfile f = {.fd = -1, .slot = -1};
    struct sp_dirs dirs = {0};
    char out[4096];
    int ret = sp_cli_parse(&o, argc, argv, data_usage, SP_CLI_EVERY | SP_CLI_POINCARE | SP_CLI_SCENES);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = sp_cli_load_scenes(&o, scenes);
    const struct sp_scene *const sc0 = &scenes[0];
    int spatial = 0;
    /* the scene column: each file's stem, shown as a message shows it (a
     * terminal escape in a file name must not reach whoever cats the CSV) */
    static char column[SP_CLI_MAX_SCENES][4 * sizeof(scenes[0].name)];
    for (int i = 0; i < o.n_scenes; i++) {
        sp_text_shown(scenes[i].name, 1, column[i], sizeof(column[i]));
        sp_timeline_destroy(&scenes[i].timeline); /* presentation: data ignores it */
        spatial |= scenes[i].initial.azimuth_rate != 0;
        if (!ret && o.n_scenes > 1 && (o.poincare || scenes[i].ensemble.count > 1)) {
            sp_log_error("%s: %s takes one scene", o.scene_paths[i],
                         o.poincare ? "--poincare" : "[ensemble]");
            ret = SP_E_INPUT;
        }
        for (int j = 0; !ret && j < i; j++)
            if (!strcmp(column[i], column[j])) {
                sp_log_error("%s and %s both give the scene column '%s' (a file's name "
                             "without .ini): rename one so that the rows can be told apart",
                             o.scene_paths[j], o.scene_paths[i], column[i]);
                ret = SP_E_INPUT;
            }
    }
    if (!ret)
        ret = sp_cli_output_path(&o, sc0, ".csv", out, sizeof(out));
    if (ret)
        goto done;
    if (o.poincare && spatial) {
        sp_log_error("%s: --poincare writes the planar section theta = 0 with dtheta/dt > 0, "
                     "which a 3-D motion (initial.azimuth_rate = %g rad/s) does not have; set "
                     "initial.azimuth_rate = 0, or write the samples (z, vz, azimuth among them) "
                     "without --poincare", o.scene_paths[0], sc0->initial.azimuth_rate);
        ret = SP_E_INPUT;
        goto done;
    }
    if (o.every > 0 && o.poincare) {
        sp_log_error("--every and --poincare cannot be combined: the crossings fall where "
                     "they fall");
        ret = SP_E_INPUT;
        goto done;
    }
    /* the limit is on what data writes, rows, not on video frames: each scene's */
    double t_end = 0;
    for (int i = 0; i < o.n_scenes; i++) {
        const struct sp_scene *sc = &scenes[i];
        /* the limit is on what data writes, rows, not on video frames */
        const double rows = o.poincare ? 0
                            : o.every > 0 ? floor(sc->video.duration / o.every * (1 + 1e-12)) + 1
                                          : sp_scene_frame_count(sc);
        const double members = !o.poincare && sc->ensemble.count > 1 ? sc->ensemble.count : 1;
        if (rows * members > MAX_ROWS && members > 1) {
            sp_log_error("%.0f times of %d ensemble members: %.0f rows; at most %.0f are written "
                         "(raise --every, lower video.duration or ensemble.count)", rows,
                         sc->ensemble.count, rows * members, MAX_ROWS);
            ret = SP_E_INPUT;
            goto done;
        }
        if (rows > MAX_ROWS) {
            sp_log_error("%s%g over video.duration = %g s: %.0f rows, about %.3g GB of CSV; at "
                         "most %.0f rows are written (raise --every or lower video.duration)",
                         o.every > 0 ? "--every " : "frame times every ",
                         o.every > 0 ? o.every : sc->video.speed / sc->video.fps,
                         sc->video.duration, rows, rows * ROW_BYTES / 1e9, MAX_ROWS);
            ret = SP_E_INPUT;
            goto done;
        }
        const double t_sc = o.every > 0 || o.poincare
                           ? sc->video.duration
                           : sp_scene_frame_time(sc, sp_scene_frame_count(sc) - 1);
        if ((ret = sp_cli_check_work(&o, sc, t_sc, 0)) != 0)
            goto done;
        t_end = fmax(t_end, t_sc);
    }
    int to_stdout = !strcmp(out, "-");
    const char *what = to_stdout ? "stdout" : out;
    if (!to_stdout && !sp_outfile_is_stream(out))
        ret = sp_dirs_make(out, &dirs);
    if (!ret)
        ret = sp_outfile_open(&f, out, SP_OUTFILE_STREAM);
    if (ret)
        goto done;
    FILE *fp = fdopen(f.fd, "w");
    if (!fp) {
        sp_log_error("%s: %s", what, strerror(errno));
        ret = SP_E_NOMEM;
        goto done;
    }
    f.fd = -1; /* fp owns it */
    static char buf[1 << 16];
    setvbuf(fp, buf, _IOFBF, sizeof(buf));
    sp_progress_begin(!o.quiet && !(to_stdout && isatty(1)), "data", t_end);
    for (int i = 0; !ret && i < o.n_scenes; i++)
        ret = write_samples(fp, &scenes[i], o.every, o.poincare,
                            o.n_scenes > 1 ? column[i] : NULL, i == 0, spatial && o.n_scenes > 1,
                            cancel);
    sp_progress_end();
    int write_errno = errno;
    if (fclose(fp) != 0 && !ret)
        ret = SP_E_IO, write_errno = errno;
    if (ret == SP_E_IO)
        sp_log_error("cannot write the CSV to %s: %s", what, write_errno == EPIPE
                     ? "the reader closed the pipe" : strerror(write_errno));
    if (ret == SP_E_INTERRUPTED && !f.through)
        sp_log_error("interrupted: %s not written", out);
    int through = f.through;
    struct sp_outfile meta = {.fd = -1, .slot = -1};
    if (!ret)
        ret = write_metadata(&meta, out, &o, scenes, o.n_scenes, spatial);
    if (!ret) /* the metadata first: when the CSV appears, it is there */
        ret = sp_outfile_commit(&meta);
    if (!ret)
        ret = sp_outfile_commit(&f);
    if (!ret && !o.quiet && !through)
        sp_fprintf_line(stderr, "wrote %s", out);
done:
    if (ret) {
        sp_outfile_discard(&f);
        sp_dirs_remove_empty(&dirs);
    }
    sp_dirs_keep(&dirs);
    for (int i = 0; i < o.n_scenes; i++)
        sp_scene_free(&scenes[i]);
    return ret;
}
