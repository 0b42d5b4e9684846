/* springpend: the data command. Parses argv, loads the scenes, checks what
 * the run would write (one scene with --poincare or an ensemble, the scene
 * column's names, the rows and the work) and hands the export
 * (data_export.h) a desc. */
#include <math.h>
#include <stdio.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "springpend/common.h"
#include "springpend/data_export.h"
#include "springpend/outfile.h"
#include "springpend/timeline.h"

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
    "rows follow in turn, after a first column scene (the file's name less its\n"
    "extension); z,vz,azimuth are written for all when one scene is spatial;\n"
    "--poincare and [ensemble] take one scene.\n"
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
    "  --fps N                shorthand for video.fps: the frame times sampled (not\n"
    "                         with --every or --poincare, which sample none)\n"
    "  --quality Q            low, medium, high or 4k: render's rates (the frame\n"
    "                         times; not with --every or --poincare)\n"
    "  -q, --quiet            no 'wrote' line\n"
    "  -h, --help             this text\n";

/* Refuses (SP_E_INPUT, said) scene i's column name (names[i], as shown;
 * raw: the file's own) beside the ones before it: a name that starts with
 * = + - @, a tab or a carriage return, which a spreadsheet would take for
 * a formula (CSV injection, OWASP's list: a leading tab or CR is stripped
 * before the formula is read; attack11 #24, attack12 #13; rows are not
 * rewritten behind a reader's back), or one that another scene gives
 * (their rows could not be told apart). 0 when neither. */
static int check_column(const struct sp_cli_options *o, const char *const *names,
                        const char *raw, int i)
{
    const char c = raw[0] == '\r' ? '\r' : names[i][0];
    if (c && strchr("=+-@\t\r", c)) {
        char sign[8];
        snprintf(sign, sizeof(sign), "'%c'", c);
        sp_log_error("%s: its scene column '%s' starts with %s, which a spreadsheet reads as "
                     "the start of a formula (a leading tab or carriage return is dropped "
                     "first); rename the file so that its name starts with none of = + - @, "
                     "a tab or a carriage return", o->scene_paths[i], names[i],
                     c == '\t' ? "a tab" : c == '\r' ? "a carriage return" : sign);
        return SP_E_INPUT;
    }
    for (int j = 0; j < i; j++)
        if (!strcmp(names[i], names[j])) {
            sp_log_error("%s and %s both give the scene column '%s' (a file's name less its "
                         "extension): rename one so that the rows can be told apart",
                         o->scene_paths[j], o->scene_paths[i], names[i]);
            return SP_E_INPUT;
        }
    return 0;
}

/* --fps and --quality pick the frame times, which --every and --poincare
 * do not sample: taken with them, they would change nothing (attack12
 * #18). 0, or SP_E_INPUT (said). */
static int check_rates(const struct sp_cli_options *o)
{
    const char *rate = o->fps_buf[0] ? "--fps" : o->quality_buf[0][0] ? "--quality" : NULL;
    const char *other = o->data.every > 0 ? "--every" : o->data.poincare ? "--poincare" : NULL;
    if (!rate || !other)
        return 0;
    sp_log_error("%s sets the frame times (video.fps), which %s replaces%s: the rows would be "
                 "the same whatever its value; give one of them", rate, other,
                 o->data.poincare ? " with the section's crossings" : "");
    return SP_E_INPUT;
}

/* data refuses a --set key it does not read (attack13 #5): it draws
 * nothing, and its rows are the physics at the frame times; with --every
 * or --poincare, which replace the frame times, not video.fps or speed
 * either, as it refuses --fps there; ensemble.trails is drawn, never
 * written (attack15 #13). */
static int check_set_read(const struct sp_cli_options *o)
{
    static const char *const read[] = {"pendulum", "initial", "pivot", "integrator",
                                       "ensemble.count", "ensemble.key", "ensemble.spread",
                                       "video.duration", "video.fps", "video.speed"};
    const int frame_times = !(o->data.every > 0) && !o->data.poincare;
    const size_t n = sizeof(read) / sizeof(read[0]) - (frame_times ? 0 : 2);
    return sp_cli_check_set_read(o, "data", read, n, 0,
                                 frame_times
                                     ? "the [pendulum], [initial], [pivot] and [integrator] keys, "
                                       "ensemble.count, key and spread, and video.duration, fps "
                                       "and speed (the frame times); it draws nothing"
                                     : "the [pendulum], [initial], [pivot] and [integrator] keys, "
                                       "ensemble.count, key and spread, and video.duration; with "
                                       "--every or --poincare, not the frame times' video.fps and "
                                       "speed; it draws nothing");
}

int sp_cmd_data(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    struct sp_cli_options o;
    static struct sp_scene scenes[SP_CLI_MAX_SCENES]; /* big: not on the stack */
    char out[4096];
    int ret = sp_cli_parse(&o, argc, argv, data_usage,
                           SP_CLI_TAKES_EVERY | SP_CLI_TAKES_POINCARE | SP_CLI_TAKES_SCENES);
    if (ret)
        return ret > 0 ? 0 : ret;
    if ((ret = check_rates(&o)) != 0)
        return ret;
    ret = check_set_read(&o);
    if (!ret)
        ret = sp_cli_load_scenes(&o, scenes);
    const struct sp_scene *const sc0 = &scenes[0];
    int spatial = 0;
    /* the scene column: each file's stem, shown as a message shows it (a
     * terminal escape in a file name must not reach whoever cats the CSV) */
    static char column[SP_CLI_MAX_SCENES][4 * sizeof(scenes[0].name)];
    const char *column_names[SP_CLI_MAX_SCENES];
    for (int i = 0; i < o.n_scenes; i++) {
        sp_text_shown(scenes[i].name, 1, column[i], sizeof(column[i]));
        column_names[i] = column[i];
        sp_timeline_destroy(&scenes[i].timeline); /* presentation: data ignores it */
        spatial |= scenes[i].initial.azimuth_rate != 0;
        if (!ret && o.n_scenes > 1 && (o.data.poincare || scenes[i].ensemble.count > 1)) {
            sp_log_error("%s: %s takes one scene", o.scene_paths[i],
                         o.data.poincare ? "--poincare" : "[ensemble]");
            ret = SP_E_INPUT;
        }
        if (!ret && o.n_scenes > 1)
            ret = check_column(&o, column_names, scenes[i].name, i);
    }
    if (!ret)
        ret = sp_cli_output_path(&o, sc0, ".csv", out, sizeof(out));
    if (ret)
        goto done;
    if (o.data.poincare && spatial) {
        sp_log_error("%s: --poincare writes the planar section theta = 0 with dtheta/dt > 0, "
                     "which a 3-D motion (initial.azimuth_rate = %g rad/s) does not have; set "
                     "initial.azimuth_rate = 0, or write the samples (z, vz, azimuth among them) "
                     "without --poincare", o.scene_paths[0], sc0->initial.azimuth_rate);
        ret = SP_E_INPUT;
        goto done;
    }
    if (o.data.every > 0 && o.data.poincare) {
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
        const double every = o.data.every;
        const double rows = o.data.poincare ? 0
                            : every > 0     ? floor(sc->video.duration / every * (1 + 1e-12)) + 1
                                            : sp_scene_frame_count(sc);
        const double members =
            !o.data.poincare && sc->ensemble.count > 1 ? sc->ensemble.count : 1;
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
                         o.data.every > 0 ? "--every " : "frame times every ",
                         o.data.every > 0 ? o.data.every : sc->video.speed / sc->video.fps,
                         sc->video.duration, rows, rows * ROW_BYTES / 1e9, MAX_ROWS);
            ret = SP_E_INPUT;
            goto done;
        }
        const double t_sc = o.data.every > 0 || o.data.poincare
                           ? sc->video.duration
                           : sp_scene_frame_time(sc, sp_scene_frame_count(sc) - 1);
        if ((ret = sp_cli_check_work(&o, sc, t_sc, 0, cancel)) != 0)
            goto done;
        t_end = fmax(t_end, t_sc);
    }
    const struct sp_data_desc desc = {
        .scenes = scenes, .n_scenes = o.n_scenes, .names = column_names,
        .overrides = o.overrides, .n_overrides = o.n_overrides, .every = o.data.every,
        .poincare = o.data.poincare, .output = out, .t_end = t_end, .quiet = o.quiet,
        .cancel = cancel};
    ret = sp_data_run(&desc);
done:
    for (int i = 0; i < o.n_scenes; i++)
        sp_scene_free(&scenes[i]);
    return ret;
}
