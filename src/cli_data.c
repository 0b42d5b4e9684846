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
#include "springpend/outfile.h"
#include "springpend/sim.h"

static const char data_usage[] =
    "usage: springpend data SCENE [-o FILE.csv | -o -] [--every SECONDS] [options]\n"
    "\n"
    "Writes the motion as CSV, one row per sample: by default at the video's frame\n"
    "times (k * speed / fps, k = 0 .. frames-1); with --every at t = 0, every,\n"
    "2 every, ... up to video.duration inclusive. No rendering is done.\n"
    "Columns (SI units, angles in radians, positions relative to the pivot):\n"
    "  t,x,y,vx,vy,r,theta,r_dot,theta_dot,kinetic,spring,gravity,energy,\n"
    "  bounce,swing,work,pivot_y\n"
    "bounce + swing = energy - E_eq (E_eq: hanging still at l = L0 + m g / k);\n"
    "work: done on the bob by damping and the moving pivot since t = 0, so\n"
    "energy - work stays at its t = 0 value.\n"
    "Default output: out/<scene>.csv; '-o -' writes to stdout. A run that becomes\n"
    "unstable stops with exit status 3 and leaves no file (stdout keeps the rows\n"
    "before it, each of them checked).\n"
    "\n"
    "options:\n"
    "  -o, --output PATH      where to write (.csv, or - for stdout)\n"
    "  --every SECONDS        sampling interval in simulated seconds\n"
    "  --set SECTION.KEY=VAL  override a scene key (repeatable)\n"
    "  -q, --quiet            no 'wrote' line\n"
    "  -h, --help             this text\n";

static const char csv_header[] =
    "t,x,y,vx,vy,r,theta,r_dot,theta_dot,kinetic,spring,gravity,energy,"
    "bounce,swing,work,pivot_y\n";

/* One CSV row for the sim's current state. */
static int write_row(FILE *fp, const struct sp_sim *sim)
{
    const struct sp_state *s = &sim->s;
    struct sp_polar q;
    struct sp_energy e;
    sp_state_polar(s, &q);
    sp_state_energy(&sim->p, s, &e);
    return fprintf(fp,
                   "%.10g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,"
                   "%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g\n",
                   s->t, s->x, s->y, s->vx, s->vy, q.r, q.theta, q.r_dot, q.theta_dot,
                   e.kinetic, e.spring, e.gravity, e.total, e.bounce, e.swing, sim->work,
                   sp_pivot_y(&sim->p, s->t)) < 0 ? SP_E_IO : 0;
}

/* Writes every sample of the scene to fp. */
static int write_samples(FILE *fp, const struct sp_scene *sc, double every)
{
    struct sp_sim sim;
    long n;
    if (every > 0)
        n = (long)floor(sc->video.duration / every * (1 + 1e-12)) + 1;
    else
        n = sp_scene_frame_count(sc);
    if (fputs(csv_header, fp) < 0)
        return SP_E_IO;
    sp_sim_init(&sim, sc);
    for (long k = 0; k < n; k++) {
        double t = every > 0 ? k * every : sp_scene_frame_time(sc, (int)k);
        int ret = sp_interrupted() ? SP_E_INTERRUPTED : sp_sim_advance(&sim, t);
        if (!ret)
            ret = write_row(fp, &sim);
        if (ret)
            return ret;
    }
    return 0;
}

int sp_cmd_data(int argc, char **argv)
{
    struct sp_cli_options o;
    struct sp_scene scene;
    struct sp_outfile f = {.fd = -1, .slot = -1};
    struct sp_dirs dirs = {0};
    char out[4096];
    int ret = sp_cli_parse(&o, argc, argv, data_usage, SP_CLI_EVERY);
    if (ret)
        return ret > 0 ? 0 : ret;
    ret = sp_cli_load_scene(&o, &scene);
    if (!ret)
        ret = sp_cli_output_path(&o, &scene, ".csv", out, sizeof(out));
    if (ret)
        return ret;
    if (o.every > 0 && scene.video.duration / o.every > 1e8) {
        sp_log_error("--every %g: video.duration / every = %.3g rows; at most 1e8 are "
                     "allowed", o.every, scene.video.duration / o.every);
        return SP_E_INPUT;
    }
    double t_end = o.every > 0 ? scene.video.duration
                               : sp_scene_frame_time(&scene, sp_scene_frame_count(&scene) - 1);
    if ((ret = sp_cli_check_work(&o, &scene, t_end, 0)) != 0)
        return ret;
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
    ret = write_samples(fp, &scene, o.every);
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
    if (!ret)
        ret = sp_outfile_commit(&f);
    if (!ret && !o.quiet && !through)
        fprintf(stderr, "wrote %s\n", out);
done:
    if (ret) {
        sp_outfile_discard(&f);
        sp_dirs_remove_empty(&dirs);
    }
    sp_dirs_keep(&dirs);
    return ret;
}
