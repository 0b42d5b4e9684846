/* springpend: the sweep command. Options, the output files (.part, then
 * renamed), shards and their merge, the progress bar; the grid's work is
 * sweep.c's, the figure sweep_plot.c's. */
#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/clock.h"
#include "base/module.h"
#include "base/signal_name.h"
#include "cli.h"
#include "base/decimal.h"
#include "base/digest.h"
#include <jansson.h>
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/infile.h"
#include "springpend/outfile.h"
#include "springpend/sim.h"
#include "springpend/timeline.h"
#include "base/command_line.h"
#include "sweep/sweep.h"
#include "sweep/sweep_format.h"
#include "sweep/sweep_merge.h"

static const char sweep_usage[] =
    "usage: springpend sweep SCENE --vary KEY=FROM:TO:COUNT [--vary KEY=FROM:TO:COUNT]\n"
    "                        --measure lyapunov|spectrum|orbit|poincare|basins|precession\n"
    "                        --time T\n"
    "                        [--transient T0] -o FIGURE.png|.svg|.pdf|- [--csv FILE.csv]\n"
    "                        [--format csv|json] [options]\n"
    "       springpend sweep SCENE ... --shard I/N --csv PART.csv\n"
    "       springpend sweep --merge PART.csv... -o FIGURE [--csv WHOLE.csv]\n"
    "\n"
    "Integrates the scene over a grid of one or two numeric keys of [pendulum],\n"
    "[initial] or [pivot] (file units: degrees for angles), COUNT values from FROM\n"
    "to TO each, on all cores, and draws what --measure asks for:\n"
    "  lyapunov  the largest Lyapunov exponent (1/s; Benettin: tangent equations,\n"
    "            renormalised every second) over T after the transient: a line over\n"
    "            one key, a coloured map over two. The CSV also has the value at T/2.\n"
    "  orbit     orbit diagram over one key: after the transient, theta (degrees) once\n"
    "            per drive period when the pivot moves (stroboscopic, at t = k/f),\n"
    "            else r at each Poincare crossing (theta = 0, dtheta/dt > 0).\n"
    "            Over pivot.frequency: FROM > 0 and TO > 0.\n"
    "  spectrum  all four Lyapunov exponents (1/s; Benettin: four tangent vectors,\n"
    "            re-orthonormalised every second by modified Gram-Schmidt), their\n"
    "            sum and the Kaplan-Yorke dimension; the CSV holds the running values\n"
    "            at about ten T per decade. One point: the convergence figure (each\n"
    "            lambda against T); one key: the four against it; two: a map of lambda1.\n"
    "  basins    damped, driven scenes, two keys: which attractor of the stroboscopic\n"
    "            map (t = k/f) each start ends on. A start is settled once its\n"
    "            samples repeat with a period p <= 8 (and counted rotating when it\n"
    "            turns over); undecided when not by T0 + T (chaos, or slow). The\n"
    "            settled cycles are clustered into attractors; the figure's legend\n"
    "            and stderr give each one's period, state and basin fraction, and the\n"
    "            basin entropy S_b and boundary basin entropy S_bb (whole 5x5 boxes,\n"
    "            the remainder left out and said; none under 5 points a side).\n"
    "  precession  3-D scenes (initial.azimuth_rate != 0): the swinging spring's turn\n"
    "            of the swing plane per exchange (degrees), as data's azimuth column\n"
    "            has it, between successive maxima of the swing (each averaged over a\n"
    "            pendulum period); the CSV also has the exchanges counted and their\n"
    "            period. A line over one key, a coloured map over two.\n"
    "  poincare  Poincare mosaic: (r, r_dot) at every crossing of every grid point's\n"
    "            orbit, coloured by orbit, all at one energy: each point's\n"
    "            initial.angle_rate is derived from --energy E (J; default the\n"
    "            scene's own), so vary initial.length, initial.angle or\n"
    "            initial.length_rate. Points that cannot reach E are skipped.\n"
    "orbit and poincare: a point without a crossing or sample in the span (or\n"
    "without the energy) has one CSV row of its own: t = T0 + T, the values nan.\n"
    "3-D scenes (initial.azimuth_rate != 0, or varied) take lyapunov (a 6-D tangent)\n"
    "and precession; the other measures are of the planar motion. A sweep draws\n"
    "no panel: [view] panels and vectors are not checked against the 3-D motion.\n"
    "The scene's [integrator] is used (rk4, verlet, yoshida4 at its dt; dopri5 and\n"
    "dop853 as dop853 at its tolerance, landing on every sample time; the\n"
    "figure's subtitle says which).\n"
    "FROM > TO is taken: the CSV in that order, the figure's axis ascending.\n"
    "A point whose integration blows up is NaN in the CSV and the figure, and\n"
    "counted; the sweep goes on (every point blown up: nothing written, exit 3).\n"
    "orbit and poincare bound their rows (CSV lines) before they run, from each\n"
    "start's energy (else one every two steps): past 1e8 refused; a run whose rows\n"
    "pass 1e8 stops and writes nothing (exit 2).\n"
    "Ctrl-C stops and writes nothing (exit 130).\n"
    "The scene's [timeline] (captions, speed changes, pauses) is presentation for\n"
    "render and still: sweep ignores it.\n"
    "\n"
    "options:\n"
    "  --vary KEY=FROM:TO:COUNT  a key to vary (one or two)\n"
    "  --measure NAME            lyapunov, spectrum, orbit, poincare, basins or precession\n"
    "  --time T                  simulated seconds measured, after the transient\n"
    "  --transient T0            simulated seconds integrated first (default 0)\n"
    "  --energy E                poincare: the orbits' energy, J\n"
    "  --continue up|down|both   orbit, driven: each value of the key starts from the\n"
    "                            previous value's final state (up: in increasing\n"
    "                            values, FROM:TO either way; down; both: two\n"
    "                            branches, two colours), so hysteresis shows; a\n"
    "                            [pendulum] or [pivot] key, not [initial]; a start\n"
    "                            within 0.05 deg of hanging is seeded at 0.05 deg.\n"
    "                            One sequence: no --shard.\n"
    "  --peak theta|r            orbit, driven: beside theta at t = k/f (stroboscopic),\n"
    "                            the largest |theta| (or r) over each drive period,\n"
    "                            drawn as light dots\n"
    "  -o, --output FIGURE       .png, .svg or .pdf; '-': no figure, the numbers on\n"
    "                            stdout (CSV, or --format)\n"
    "  --format csv|json         also print the numbers on stdout: the CSV, or JSON\n"
    "                            (a spectrum's final exponents; a basin map's\n"
    "                            attractors, fractions and entropies)\n"
    "  --csv FILE                also write the rows (a regular file), and beside it\n"
    "                            FILE-metadata.json (W3C CSV on the Web: the sweep,\n"
    "                            the columns' units, the scene, overrides, command)\n"
    "  --shard I/N               compute the I-th of N equal parts of the grid into\n"
    "                            --csv only; join them with --merge\n"
    "  --merge                   the arguments are shard CSVs: draw (and --csv) the whole\n"
    "  --threads N               worker threads (default: one per CPU it may use)\n"
    "  --fast                    lyapunov with rk4, undamped and undriven: the batch's fast\n"
    "                            kernel (fused multiply-adds, 1/rho without the divider;\n"
    "                            AVX-512F): about 1.4x the exact kernel's steps per second,\n"
    "                            within rounding of it but not its bits (the CSV header\n"
    "                            says kernel=fast; shards of both kinds do not merge)\n"
    "  --set SECTION.KEY=VAL     override a scene key (repeatable): [pendulum], [initial],\n"
    "                            [pivot] and [integrator] keys, and the figure's view.theme,\n"
    "                            colormap, background, font, font_size, font_scale, title\n"
    "                            (\"\" = none), xlabel, ylabel, colorbar_label, legend,\n"
    "                            marker_size, palette, panel_titles and panel_labels; any\n"
    "                            other key is refused\n"
    "  --size W[xH]              the figure's printed size: 8.6cm, 3.4in, 246pt, 86mm, or\n"
    "                            8.6cmx6cm (the height 2/3 of the width when left out);\n"
    "                            text then in points (view.font_size, 10 by default)\n"
    "  --dpi N                   a PNG figure's dots per inch at --size (default 300)\n"
    "  -q, --quiet               no progress bar, no 'wrote' line\n"
    "  -h, --help                this text\n";

struct sweep_opts {
    const char *scene, *output, *csv, *shard;
    int format; /* 0: no numbers on stdout, 1: CSV, 2: JSON */
    const char *overrides[SP_CLI_MAX_OVERRIDES];
    int n_overrides, quiet, merge, threads, energy_given;
    const char **parts;
    int n_parts;
    struct sp_plot_style style; /* --size, --dpi; the scene's [view] once loaded */
    const volatile sig_atomic_t *cancel; /* main's stop flag */
};

/* --vary KEY=FROM:TO:COUNT: FROM and TO any decimal numbers here (sp_sweep_check
 * holds them to the key's range), COUNT an integer. */
static int parse_vary(const char *arg, struct sp_sweep_desc *d)
{
    static const char *const field[] = {"FROM", "TO", "COUNT"};
    static const char allowed[] = "KEY=FROM:TO:COUNT, FROM and TO in the key's file units, "
                                  "COUNT an integer from 1 to 100000, e.g. --vary "
                                  "initial.angle=10:170:256";
    struct sp_sweep_axis *a = &d->axis[d->n_axes];
    const char *eq = strchr(arg, '='), *p = eq ? eq + 1 : NULL;
    double v[3];
    char wrong[64];
    if (d->n_axes == SP_SWEEP_MAX_AXES) {
        sp_log_error("--vary %s: at most %d keys can be varied", arg, SP_SWEEP_MAX_AXES);
        return SP_E_INPUT;
    }
    if (!eq || eq == arg || eq - arg >= (long)sizeof(a->key))
        return sp_cli_refuse("--vary", arg, "not KEY=FROM:TO:COUNT", allowed);
    for (int i = 0; i < 3; i++, p++) {
        const size_t n = strcspn(p, ":");
        const char *bad;
        if ((i == 2) != !p[n])
            return sp_cli_refuse("--vary", arg, "not KEY=FROM:TO:COUNT", allowed);
        if ((bad = sp_cli_field(p, n, i < 2 ? -DBL_MAX : 1, i < 2 ? DBL_MAX : 100000,
                                i < 2 ? 0 : SP_DECIMAL_INTEGER, &v[i]))) {
            snprintf(wrong, sizeof(wrong), "%s %s", field[i], bad);
            return sp_cli_refuse("--vary", arg, wrong, allowed);
        }
        p += n;
    }
    a->from = v[0], a->to = v[1], a->count = (int)v[2];
    snprintf(a->key, sizeof(a->key), "%.*s", (int)(eq - arg), arg);
    d->n_axes++;
    return 0;
}

static const char short_options[] = ":o:qh"; /* ":": a missing value is ':' */
static const struct option longopts[] = {
    {"output", required_argument, 0, 'o'}, {"set", required_argument, 0, 's'},
    {"vary", required_argument, 0, 'V'},   {"measure", required_argument, 0, 'M'},
    {"time", required_argument, 0, 'T'},   {"transient", required_argument, 0, 'R'},
    {"energy", required_argument, 0, 'E'}, {"csv", required_argument, 0, 'C'},
    {"shard", required_argument, 0, 'D'},  {"merge", no_argument, 0, 'G'},
    {"threads", required_argument, 0, 'N'}, {"quiet", no_argument, 0, 'q'},
    {"continue", required_argument, 0, 'K'}, {"peak", required_argument, 0, 'P'},
    {"size", required_argument, 0, 'S'},   {"dpi", required_argument, 0, 'I'},
    {"format", required_argument, 0, 'F'}, {"fast", no_argument, 0, 'X'},
    {"help", no_argument, 0, 'h'},         {0, 0, 0, 0},
};

const struct option *sp_cli_sweep_options(const char **shortopts)
{
    *shortopts = short_options;
    return longopts;
}

/* --measure NAME into d. */
static int parse_measure(const char *arg, struct sp_sweep_desc *d)
{
    if (!strcmp(arg, "lyapunov"))
        d->measure = SP_MEASURE_LYAPUNOV;
    else if (!strcmp(arg, "orbit"))
        d->measure = SP_MEASURE_ORBIT;
    else if (!strcmp(arg, "poincare"))
        d->measure = SP_MEASURE_POINCARE;
    else if (!strcmp(arg, "spectrum"))
        d->measure = SP_MEASURE_SPECTRUM;
    else if (!strcmp(arg, "basins"))
        d->measure = SP_MEASURE_BASINS;
    else if (!strcmp(arg, "precession"))
        d->measure = SP_MEASURE_PRECESSION;
    else {
        sp_log_error("--measure %s: use lyapunov, spectrum, orbit, poincare, basins or "
                     "precession", arg);
        return SP_E_INPUT;
    }
    return 0;
}

/* Takes option c, which getopt_long just read (its value: optarg), into *o
 * and *d. 0, 1 after --help (usage printed), or SP_E_INPUT after a
 * message. */
static int take_option(int c, char **argv, struct sweep_opts *o, struct sp_sweep_desc *d,
                       int *have_measure)
{
    int ret = 0;
    double v;
    switch (c) {
    case 'o': o->output = optarg; break;
    case 'C': o->csv = optarg; break;
    case 'D': o->shard = optarg; break;
    case 'G': o->merge = 1; break;
    case 'X': d->fast = 1; break;
    case 'q': o->quiet = 1; break;
    case 'h': fputs(sweep_usage, stdout); return 1;
    case 's':
        if (o->n_overrides == SP_CLI_MAX_OVERRIDES) {
            sp_log_error("too many --set; at most %d", SP_CLI_MAX_OVERRIDES);
            return SP_E_INPUT;
        }
        o->overrides[o->n_overrides++] = optarg;
        break;
    case 'V': ret = parse_vary(optarg, d); break;
    case 'M':
        *have_measure = 1;
        ret = parse_measure(optarg, d);
        break;
    case 'K':
        d->cont = !strcmp(optarg, "up")     ? SP_CONTINUE_UP
                  : !strcmp(optarg, "down") ? SP_CONTINUE_DOWN
                  : !strcmp(optarg, "both") ? SP_CONTINUE_BOTH
                                            : SP_CONTINUE_NONE;
        if (!d->cont)
            return sp_cli_refuse("--continue", optarg, "not a direction", "up, down or both");
        break;
    case 'P':
        d->peak = !strcmp(optarg, "theta") ? SP_PEAK_THETA
                  : !strcmp(optarg, "r")   ? SP_PEAK_R
                                           : 0;
        if (!d->peak)
            return sp_cli_refuse("--peak", optarg, "not a sampled quantity",
                                 "theta (the largest |theta| per drive period) or r");
        break;
    case 'F':
        o->format = !strcmp(optarg, "csv") ? 1 : !strcmp(optarg, "json") ? 2 : 0;
        if (!o->format)
            return sp_cli_refuse("--format", optarg, "not a format", "csv or json");
        break;
    case 'T':
        ret = sp_cli_number("--time", optarg, 0, 1e7, SP_DECIMAL_ABOVE,
                            "simulated seconds measured, 0 < T <= 1e7", &d->time);
        break;
    case 'R':
        ret = sp_cli_number("--transient", optarg, 0, DBL_MAX, 0,
                            "simulated seconds integrated first, T0 >= 0", &d->transient);
        break;
    case 'E':
        ret = sp_cli_number("--energy", optarg, -DBL_MAX, DBL_MAX, 0,
                            "the orbits' energy in J", &d->energy);
        o->energy_given = 1;
        break;
    case 'S':
        ret = sp_cli_paper_size("--size", optarg, &o->style.page_w, &o->style.page_h);
        if (!ret && !o->style.page_h) /* the default figure's 3:2 */
            o->style.page_h = o->style.page_w * 2 / 3;
        break;
    case 'I':
        ret = sp_cli_number("--dpi", optarg, 10, 2400, SP_DECIMAL_ABOVE,
                            "the PNG's dots per inch, 10 < dpi <= 2400, with --size, e.g. "
                            "--size 8.6cm --dpi 300", &o->style.dpi);
        break;
    case 'N':
        ret = sp_cli_number("--threads", optarg, 1, 1024, SP_DECIMAL_INTEGER,
                            "worker threads, an integer from 1 to 1024", &v);
        o->threads = (int)v;
        break;
    case ':':
        sp_log_error("option '%s' needs a value; see 'springpend sweep --help'", argv[optind - 1]);
        return SP_E_INPUT;
    default:
        sp_cli_bad_option(argv[optind - 1], longopts, "sweep");
        return SP_E_INPUT;
    }
    return ret;
}

/* --size and --dpi: a printed figure, -o FIGURE (a PNG for --dpi), and a
 * PNG of as many pixels as a still may have. */
static int check_size(const struct sweep_opts *o)
{
    if (o->style.dpi && !(o->style.page_w && o->output && strcmp(o->output, "-") &&
                          !strcasecmp(strrchr(o->output, '.') ? strrchr(o->output, '.') : "",
                                      ".png"))) {
        sp_log_error("--dpi sets a PNG figure's dots per inch at a printed size: give --size "
                     "8.6cm (or another) and -o FIGURE.png");
        return SP_E_INPUT;
    }
    if (o->style.page_w && !(o->output && strcmp(o->output, "-"))) {
        sp_log_error("--size is the figure's printed size: give -o FIGURE.png|.svg|.pdf");
        return SP_E_INPUT;
    }
    int png_w, png_h; /* a PNG of printed size: as many pixels as a still may have */
    if (o->style.page_w && o->output && strlen(o->output) > 4 &&
        !strcasecmp(o->output + strlen(o->output) - 4, ".png") &&
        sp_cli_png_pixels(o->style.page_w, o->style.page_h, o->style.dpi ? o->style.dpi : 300,
                          "a PNG figure", &png_w, &png_h))
        return SP_E_INPUT;
    return 0;
}

/* What follows the options: the shards' CSVs (--merge) or one SCENE, and
 * what each needs. */
static int take_operands(int argc, char **argv, struct sweep_opts *o,
                         const struct sp_sweep_desc *d, int have_measure, const char *first[128])
{
    if (o->merge) {
        /* the sweep itself comes from the shards: an option that describes
         * it would do nothing, yet land in the figure's record */
        static const char sweep_options[] = "MTRE";
        char unused[256] = "";
        size_t used = 0;
        for (const char *c = sweep_options; *c; c++)
            for (const struct option *p = longopts; first[(int)*c] && p->name; p++)
                if (p->val == *c && used < sizeof(unused))
                    used += (size_t)snprintf(unused + used, sizeof(unused) - used, "%s--%s %s",
                                             used ? ", " : "", p->name, first[(int)*c]);
        if (used) {
            sp_log_error("--merge takes the sweep from its shards: %s %s not used; drop %s",
                         unused, strchr(unused, ',') ? "are" : "is",
                         strchr(unused, ',') ? "them" : "it");
            return SP_E_INPUT;
        }
        o->parts = (const char **)argv + optind;
        o->n_parts = argc - optind;
        if (!o->n_parts || !(o->output || o->format) || o->shard || d->n_axes ||
            o->n_overrides || d->cont || d->peak || d->fast) {
            sp_log_error("--merge takes shard CSVs and -o FIGURE or -o - (and --csv "
                         "WHOLE.csv, --format); see 'springpend sweep --help'");
            return SP_E_INPUT;
        }
        return 0;
    }
    if (optind != argc - 1) {
        sp_log_error(optind >= argc ? "missing SCENE file; see 'springpend sweep --help'"
                                    : "expected one SCENE file; see 'springpend sweep --help'");
        return SP_E_INPUT;
    }
    o->scene = argv[optind];
    if (!d->n_axes || !have_measure || d->time < 0) {
        sp_log_error("sweep needs --vary KEY=FROM:TO:COUNT, --measure and --time; see "
                     "'springpend sweep --help'");
        return SP_E_INPUT;
    }
    if (o->shard ? (!o->csv || o->output || o->format) : !(o->output || o->format)) {
        sp_log_error(o->shard ? "--shard writes its part of the rows to --csv PART.csv only "
                                "(no -o, no --format; --merge draws the figure)"
                              : "sweep needs -o FIGURE.png|.svg|.pdf, or -o - (the numbers "
                                "on stdout)");
        return SP_E_INPUT;
    }
    if (o->shard && d->cont) {
        sp_log_error("--shard %s: a continued orbit diagram is one sequence (each value "
                     "starts from the one before), so it cannot be cut into shards; run it "
                     "whole (it uses one thread per branch)", o->shard);
        return SP_E_INPUT;
    }
    return 0;
}

/* Parses argv into *o and *d. 0, 1 after --help (usage printed), or
 * SP_E_INPUT after a message. */
static int parse_args(int argc, char **argv, struct sweep_opts *o, struct sp_sweep_desc *d)
{
    int c, ret = 0, have_measure = 0;
    const char *first[128] = {0};
    memset(o, 0, sizeof(*o));
    d->time = -1;
    optind = 0; /* getopt_long starts afresh (a merge parses its shard's command too) */
    opterr = 0;
    /* as the command records them (command_line.h) */
    while (!ret && (c = sp_command_line_getopt(argc, argv, short_options, longopts)) != -1)
        if (!(ret = sp_cli_once(c, longopts, "sV", first)))
            ret = take_option(c, argv, o, d, &have_measure);
    if (ret || (ret = check_size(o)))
        return ret;
    if (o->output && !strcmp(o->output, "-")) { /* the numbers, no figure */
        o->output = NULL;
        if (!o->format)
            o->format = 1;
    }
    return take_operands(argc, argv, o, d, have_measure, first);
}

/* The figure's path must end in .png, .svg or .pdf and be writable. */
static int check_outputs(const struct sweep_opts *o)
{
    if (o->output) {
        const char *dot = strrchr(o->output, '.');
        if (!dot || (strcasecmp(dot, ".png") && strcasecmp(dot, ".svg") && strcasecmp(dot, ".pdf"))) {
            sp_log_error("-o %s: the figure must be .png, .svg or .pdf", o->output);
            return SP_E_INPUT;
        }
        if (sp_outfile_check_writable(o->output, "-o"))
            return SP_E_INPUT;
    }
    if (o->csv && sp_outfile_is_stream(o->csv)) { /* outfile's message says CSV may be */
        sp_log_error("--csv %s: a sweep's rows are read back (for the figure and --merge), "
                     "so --csv must name a regular file", o->csv);
        return SP_E_INPUT;
    }
    if (o->csv && (sp_outfile_check_writable(o->csv, "--csv") ||
                   sp_outfile_check_name(o->csv, SP_CSV_METADATA_SUFFIX, "--csv", "metadata")))
        return SP_E_INPUT;
    char csv_meta[4096]; /* --csv's metadata, written beside it */
    if (o->csv && o->output &&
        (sp_outfile_same_output(o->csv, o->output) ||
         (snprintf(csv_meta, sizeof(csv_meta), "%s" SP_CSV_METADATA_SUFFIX, o->csv) <
              (int)sizeof(csv_meta) && sp_outfile_same_output(csv_meta, o->output)))) {
        sp_log_error("--csv %s and -o %s name one file (the CSV or its metadata); give each "
                     "its own", o->csv, o->output);
        return SP_E_INPUT;
    }
    /* the scene or a shard being read (its CSV and its metadata, which the
     * merge reads too: attack11 #12) must not be replaced by what it makes */
    const char *outs[2][2] = {{"-o", o->output}, {"--csv", o->csv}};
    for (int i = 0; i < 2; i++)
        for (int k = -1; outs[i][1] && k < (o->merge ? 2 * o->n_parts : 0); k++) {
            char part_meta[4096], meta[4096]; /* a shard's metadata; --csv's, beside it */
            const char *in = k < 0 ? o->scene : o->parts[k / 2];
            if (k >= 0 && k % 2 &&
                snprintf(part_meta, sizeof(part_meta), "%s" SP_CSV_METADATA_SUFFIX, in) <
                    (int)sizeof(part_meta))
                in = part_meta;
            else if (k >= 0 && k % 2)
                continue; /* longer than a path: no such file */
            if (in && sp_outfile_same_file(outs[i][1], in)) {
                sp_log_error("%s %s would overwrite an input%s%s%s; choose another path",
                             outs[i][0], outs[i][1], in == part_meta ? " (the metadata of " : "",
                             in == part_meta ? o->parts[k / 2] : "", in == part_meta ? ")" : "");
                return SP_E_INPUT;
            }
            if (in && i == 1 &&
                snprintf(meta, sizeof(meta), "%s" SP_CSV_METADATA_SUFFIX, o->csv) <
                    (int)sizeof(meta) && sp_outfile_same_file(meta, in)) {
                sp_log_error("--csv %s: its metadata %s would overwrite the input %s; choose "
                             "another path", o->csv, meta, in);
                return SP_E_INPUT;
            }
        }
    return 0;
}

/* A sweep's work, in trajectory-steps: beyond SWEEP_MAX_STEPS it is
 * refused (about 2 hours of the batched integrator on 2 cores, at about 150
 * million a second), beyond SWEEP_NOTE_STEPS (about 2 minutes) it says so. */
#define SWEEP_MAX_STEPS 1e12
#define SWEEP_NOTE_STEPS 1.5e10

/* An orbit diagram's or a Poincare mosaic's rows, one a sample: beyond
 * SWEEP_MAX_ROWS (about 6 GB of CSV, which without --csv waits in unlinked
 * temporary files) refused, beyond SWEEP_NOTE_ROWS (data's limit, about
 * 0.6 GB here) said; a row is about SWEEP_ROW_BYTES (attack13 #20). */
#define SWEEP_MAX_ROWS 1e8
#define SWEEP_NOTE_ROWS 1e7
#define SWEEP_ROW_BYTES 60
#define SWEEP_ROWS_SUMMED 1000000 /* points whose bounds are summed (each takes a
                                   * scene check, about 4 us) */

/* The rows points [first, last) of d write at most: a driven orbit one per
 * drive period at the grid's fastest drive (each branch of --continue
 * both); crossings of theta = 0 (orbit undriven, poincare) what each
 * point's energy allows (sp_sweep_point_rows_max), summed. Over
 * SWEEP_ROWS_SUMMED points every point takes the bound of one every two
 * steps. *by_steps: the points bounded by steps only, *loose their rows. */
static double max_rows(const struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                       long last, long *by_steps, double *loose)
{
    double rows = 0, rate = 0;
    *by_steps = 0, *loose = 0;
    if (d->measure == SP_MEASURE_ORBIT && d->driven) {
        for (int corner = 0; corner < (1 << d->n_axes); corner++) {
            struct sp_scene s = *base;
            for (int a = 0; a < d->n_axes; a++) /* checked: the ends are valid */
                sp_scene_set_number(&s, d->axis[a].key,
                                    (corner >> a) & 1 ? d->axis[a].to : d->axis[a].from, "--vary");
            rate = fmax(rate, s.pivot.frequency);
        }
        return (double)(last - first) * ceil(d->time * rate + 1) *
               (d->cont == SP_CONTINUE_BOTH ? 2 : 1);
    }
    if (last - first > SWEEP_ROWS_SUMMED) {
        *by_steps = last - first;
        return *loose = (double)(last - first) * (floor(d->time / d->dt / 2) + 2);
    }
    for (long p = first; p < last; p++) {
        struct sp_scene s;
        int steps = 0;
        if (sp_sweep_point_scene(d, base, p, &s))
            continue; /* the energy is out of its reach: no rows */
        const double most = sp_sweep_point_rows_max(d, &s, &steps);
        rows += most, *by_steps += steps, *loose += steps ? most : 0;
    }
    return rows;
}

/* Holds an orbit diagram's or a Poincare mosaic's rows (max_rows) to the
 * limits: refused past SWEEP_MAX_ROWS, said past SWEEP_NOTE_ROWS; the run
 * itself stops at SWEEP_MAX_ROWS (d->max_rows) should it get there. Rows
 * bounded only by the steps (a start whose energy reaches the pivot, a
 * drive, 3-D) can be thousands of times what they come to, so past the
 * limit through them the run is not refused but told it may be stopped. */
static int estimate_rows(struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                         long last, int quiet, double *bound)
{
    if (d->measure != SP_MEASURE_ORBIT && d->measure != SP_MEASURE_POINCARE)
        return 0;
    const char *cap = getenv("SPRINGPEND_SWEEP_ROW_CAP"); /* tests: a lower cap */
    d->max_rows = cap && atof(cap) > 0 ? atof(cap) : SWEEP_MAX_ROWS;
    long by_steps;
    double loose;
    const long points = last - first;
    const double rows = max_rows(d, base, first, last, &by_steps, &loose),
                 gb = rows * SWEEP_ROW_BYTES / 1e9;
    *bound = rows;
    char how[160];
    if (d->measure == SP_MEASURE_ORBIT && d->driven)
        snprintf(how, sizeof(how), "one a drive period");
    else if (!by_steps)
        snprintf(how, sizeof(how), "crossings of θ = 0 as often as each start's energy "
                 "allows");
    else
        snprintf(how, sizeof(how), "crossings of θ = 0, for %ld point%s at most one every "
                 "two steps of %g s", by_steps, by_steps == 1 ? "" : "s", d->dt);
    if (rows - loose > SWEEP_MAX_ROWS) {
        sp_log_error("--measure %s over %ld points for --time %g: at most %.2g rows (%s), about "
                     "%.3g GB of CSV; at most %.0e rows; allowed: fewer points (--vary's COUNT) "
                     "or a shorter --time", d->measure == SP_MEASURE_ORBIT ? "orbit" : "poincare",
                     points, d->time, rows, how, gb, SWEEP_MAX_ROWS);
        return SP_E_INPUT;
    }
    if (rows > SWEEP_NOTE_ROWS && !quiet)
        sp_fprintf_line(stderr, "springpend: at most %.2g rows (%s), %.3g GB of CSV (in --csv, "
                        "or in temporary files under /tmp until the figure is drawn)%s", rows,
                        how, gb, rows > SWEEP_MAX_ROWS ? "; past 1e+08 rows the run stops, "
                        "nothing written" : "");
    return 0;
}

/* Grid points whose adaptive step is probed for a sweep's estimate: every
 * point of a grid this small, else a sub-grid of this many spanning the
 * run's points, their corners among them (a probe is a DOP853 run over 100
 * radians of the fastest motion: about 300 steps, 0.1 ms). */
#define SWEEP_PROBES 256

/* What the probes found: the mean and the most trajectory-steps a point
 * (each at least floor_steps; a point that blows up in its probe none),
 * the costliest point, how many were probed; the base scene's cost (< 0
 * until probed). */
struct probe {
    double mean, most, floor_steps, span, base_cost;
    long costliest;
    int n;
};

/* A scene's trajectory-steps over the span with DOP853 (its probe, sim.h),
 * at least floor_steps; 0 when the probe blows up. */
static double probe_cost(const struct sp_scene *scene, const struct probe *pr)
{
    struct sp_scene s = *scene;
    s.integrator.method = SP_METHOD_DOP853;
    const double steps = sp_sim_estimate_steps(&s, pr->span);
    return steps > 0 ? fmax(steps, pr->floor_steps) : 0;
}

/* Probes grid point p (its own scene: a varied stiffness, mass, length,
 * drive or start sets its step) with DOP853 over the span. A point that
 * cannot have poincare's energy writes nothing but is integrated as the
 * base scene (sweep.c: company in its batch; 0 returned); one whose
 * probe blows up stops there and counts as none. */
static int probe_point(const struct sp_sweep_desc *d, const struct sp_scene *base, long p,
                       struct probe *pr)
{
    struct sp_scene s;
    pr->n++;
    if (sp_sweep_point_scene(d, base, p, &s)) {
        if (pr->base_cost < 0)
            pr->base_cost = probe_cost(base, pr);
        pr->mean += pr->base_cost;
        return 0;
    }
    const double cost = probe_cost(&s, pr);
    pr->mean += cost;
    if (cost > pr->most)
        pr->most = cost, pr->costliest = p;
    return 1;
}

/* The j-th of n indices spread evenly over [lo, hi], both ends among them. */
static int spread(int lo, int hi, int n, int j)
{
    return n <= 1 ? lo : lo + (int)((long)(hi - lo) * j / (n - 1));
}

/* Probes the adaptive step over points [first, last) of d's grid: every
 * point when they are at most SWEEP_PROBES, else a sub-grid of the box of
 * axis indices they fill (a shard of a map fills whole rows but its first
 * and last), its corners among the probes. pr->mean: the points' mean. A
 * poincare point that cannot have the energy costs the base scene's steps
 * when its batch of SP_SWEEP_CHUNK integrates someone, else none. */
static void probe_grid(const struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                       long last, struct probe *pr)
{
    int i0[SP_SWEEP_MAX_AXES], i1[SP_SWEEP_MAX_AXES];
    sp_sweep_point_index(d, first, i0);
    sp_sweep_point_index(d, last - 1, i1);
    const int c0 = d->axis[0].count;
    int lo[2] = {i0[0], i0[1]}, hi[2] = {i1[0], i1[1]};
    if (lo[1] != hi[1])
        lo[0] = 0, hi[0] = c0 - 1;
    const long span0 = hi[0] - lo[0] + 1, span1 = hi[1] - lo[1] + 1;
    const int n0 = (int)fmin(span0, fmax(16, SWEEP_PROBES / span1)),
              n1 = (int)fmin(span1, fmax(1, SWEEP_PROBES / n0));
    int reached = 0;
    if (last - first <= SWEEP_PROBES) {
        for (long c = first; c < last; c += SP_SWEEP_CHUNK) { /* the run's batches */
            int in_chunk = 0, company = 0;
            for (long p = c; p < last && p < c + SP_SWEEP_CHUNK; p++)
                probe_point(d, base, p, pr) ? in_chunk++ : company++;
            if (!in_chunk) /* a batch of skipped points only is not integrated */
                pr->mean -= company * pr->base_cost;
            reached += in_chunk;
        }
    } else {
        for (int j1 = 0; j1 < n1; j1++)
            for (int j0 = 0; j0 < n0; j0++) {
                const long p = spread(lo[0], hi[0], n0, j0) +
                               (long)c0 * spread(lo[1], hi[1], n1, j1);
                if (p >= first && p < last)
                    reached += probe_point(d, base, p, pr);
            }
        if (!pr->n) /* a shard of two rows' ends the sub-grid missed */
            reached += probe_point(d, base, first, pr) + probe_point(d, base, last - 1, pr);
    }
    /* none reachable: every batch skipped (the run is refused at once) */
    pr->mean = reached ? pr->mean / pr->n : 0;
}

/* ", the costliest probed about N (KEY = V[, KEY2 = V2])" when the probed
 * points differ by more than a tenth, else "". */
static void costliest_text(const struct sp_sweep_desc *d, const struct probe *pr, char *buf,
                           size_t size)
{
    buf[0] = 0;
    if (pr->costliest < 0 || !(pr->most > 1.1 * pr->mean))
        return;
    int idx[SP_SWEEP_MAX_AXES];
    sp_sweep_point_index(d, pr->costliest, idx);
    int n = snprintf(buf, size, ", the costliest probed about %.3g (", pr->most);
    for (int a = 0; a < d->n_axes && n > 0 && (size_t)n < size; a++)
        n += snprintf(buf + n, size - n, "%s%s = %.6g", a ? ", " : "", d->axis[a].key,
                      sp_sweep_axis_value(&d->axis[a], idx[a]));
    if (n > 0 && (size_t)n < size)
        snprintf(buf + n, size - n, ")");
}

/* What a point costs given its trajectory's steps: spectrum steps four
 * copies (each with its tangent), basins lands on SP_BASINS_SAMPLES times a
 * drive period (one more step each), precession on 32 samples a period,
 * and a continued orbit diagram runs each of its branches (*extra says
 * which). */
static double point_cost(const struct sp_sweep_desc *d, const struct sp_scene *base,
                         double span, double steps, const char **extra)
{
    *extra = "";
    if (d->measure == SP_MEASURE_SPECTRUM) {
        *extra = ", four copies with tangents";
        return 4 * steps;
    }
    if (d->measure == SP_MEASURE_BASINS) {
        double f = base->pivot.frequency; /* the fastest drive on the grid */
        for (int a = 0; a < d->n_axes; a++)
            if (!strcmp(d->axis[a].key, "pivot.frequency"))
                f = fmax(d->axis[a].from, d->axis[a].to);
        *extra = ", landing on 8 samples a drive period";
        return steps + SP_BASINS_SAMPLES * f * span;
    }
    if (d->measure == SP_MEASURE_PRECESSION) {
        *extra = ", landing on 32 samples a pendulum period";
        return fmax(steps, span / d->sample); /* lands on every sample */
    }
    if (d->cont == SP_CONTINUE_BOTH) {
        *extra = ", both branches";
        return 2 * steps;
    }
    return steps;
}

/* Estimates points * (trajectory-steps a point) for this run (a shard's
 * points only) and holds it to the limits (sp_cli_work). A point integrates
 * the transient and the span; fixed steps at integrator.dt, dop853 at its
 * tolerance (probed on the grid's own points, probe_grid: a varied key can
 * set the step; the mean counted, the costliest named) and, for events, at
 * least one step per dt; then what it costs beyond one trajectory
 * (point_cost). */
static int check_work(struct sp_sweep_desc *d, const struct sp_scene *base, long first,
                      long last, int quiet, double *rows)
{
    const long points = last - first;
    const int lyap = d->measure == SP_MEASURE_LYAPUNOV || d->measure == SP_MEASURE_SPECTRUM;
    const int adaptive = strcmp(d->method, "rk4") && strcmp(d->method, "verlet") &&
                         strcmp(d->method, "yoshida4");
    const double span = d->transient + d->time;
    struct probe pr = {.span = span, .floor_steps = lyap ? 0 : span / d->dt, .costliest = -1,
                       .base_cost = -1};
    if (adaptive)
        probe_grid(d, base, first, last, &pr);
    else
        pr.mean = pr.most = span / d->dt;
    const char *extra;
    const double per_point = point_cost(d, base, span, pr.mean, &extra);
    /* the step's own size sets the cost, unless the events' dt does */
    const int by_tolerance = adaptive && pr.mean > pr.floor_steps;
    pr.most = point_cost(d, base, span, pr.most, &extra);
    pr.mean = per_point;
    char what[512], method[96], costliest[192], advice[320];
    costliest_text(d, &pr, costliest, sizeof(costliest));
    sp_sweep_method_text(d, method, sizeof(method));
    snprintf(what, sizeof(what), "sweeping %ld points over %g s each (%s%s: about %.3g steps a "
             "point%s)", points, span, method, extra, per_point, costliest);
    /* a continued sweep cannot be cut into shards (--continue refuses --shard) */
    snprintf(advice, sizeof(advice), "fewer points (--vary's COUNT), a shorter --time or "
             "--transient, %s%s", d->cont != SP_CONTINUE_NONE ? "or " : "",
             by_tolerance ? "a larger integrator.tolerance" : "a larger integrator.dt");
    if (d->cont == SP_CONTINUE_NONE)
        snprintf(advice + strlen(advice), sizeof(advice) - strlen(advice),
                 ", or split the grid over machines with --shard I/N");
    const int ret = sp_cli_work((double)points * per_point, SWEEP_MAX_STEPS, SWEEP_NOTE_STEPS,
                                what, advice, quiet);
    return ret ? ret : estimate_rows(d, base, first, last, quiet, rows);
}

struct progress {
    double t0, last;
};

static void show_progress(void *user, long done, long total)
{
    struct progress *p = user;
    double now = sp_clock_s();
    if (done < total && now - p->last < 0.1)
        return;
    p->last = now;
    double el = now - p->t0, rate = el > 0 ? done / el : 0;
    char bar[31];
    int fill = total ? (int)(30 * done / total) : 30;
    memset(bar, '#', (size_t)fill);
    memset(bar + fill, '.', (size_t)(30 - fill));
    bar[30] = 0;
    fprintf(stderr, "\r[%s] point %ld/%ld  %.0f points/s  ETA %.0f s ", bar, done, total, rate,
            rate > 0 ? (total - done) / rate : 0);
    if (done == total)
        fputc('\n', stderr);
}

/* The rows as the figure reads them (sweep.h: the description line, the
 * column names, the rows), in an anonymous temporary file. */
static int open_rows(FILE **fp)
{
    *fp = tmpfile();
    if (!*fp) {
        sp_log_error("cannot create a temporary file for the sweep's rows: %s", strerror(errno));
        return SP_E_IO;
    }
    return 0;
}

/* The figure from the rows (through the module: cairo is loaded only here). */
static int draw(FILE *rows, const char *rows_name, const char *figure,
                const struct sp_plot_style *style, struct sp_dirs *made, struct sp_outfile *out)
{
    int (*plot)(FILE *, const char *, const char *, const struct sp_plot_style *,
                struct sp_outfile *);
    *(void **)&plot = sp_module_symbol("springpend-plot.so", "sweep figures", "sp_sweep_plot");
    if (!plot)
        return SP_E_IO;
    int ret = sp_outfile_is_stream(figure) ? 0 : sp_dirs_make(figure, made);
    return ret ? ret : plot(rows, rows_name, figure, style, out);
}

/* The figure's texts checked before the sweep runs (sp_sweep_plot_check,
 * through the module). */
static int check_figure(const struct sp_plot_style *style)
{
    int (*check)(const struct sp_plot_style *);
    *(void **)&check = sp_module_symbol("springpend-plot.so", "sweep figures",
                                        "sp_sweep_plot_check");
    return check ? check(style) : SP_E_IO;
}

/* The [view] keys a sweep's figure uses; the sections its grid does. */
static const char *const figure_keys[] = {"theme", "colormap", "background", "font",
                                          "font_size", "font_scale", "title", "xlabel",
                                          "ylabel", "colorbar_label", "legend", "marker_size",
                                          "palette", "panel_titles", "panel_labels"};
static const char *const grid_sections[] = {"pendulum", "initial", "pivot", "integrator"};

/* Refuses a --set key that a sweep would not use (a video's or a still's:
 * [video], [ensemble], the panels, trail, HUD...). */
static int check_used(const struct sweep_opts *o)
{
    for (int i = 0; i < o->n_overrides; i++) {
        const char *s = o->overrides[i], *dot = strchr(s, '.');
        const size_t n = strcspn(s, "="), sec = dot && (size_t)(dot - s) < n ? (size_t)(dot - s) : n;
        int used = 0;
        for (size_t k = 0; k < sizeof(grid_sections) / sizeof(grid_sections[0]); k++)
            used |= strlen(grid_sections[k]) == sec && !strncmp(s, grid_sections[k], sec);
        for (size_t k = 0; sec == 4 && !strncmp(s, "view", 4) &&
                           k < sizeof(figure_keys) / sizeof(figure_keys[0]); k++)
            used |= strlen(figure_keys[k]) == n - 5 && !strncmp(s + 5, figure_keys[k], n - 5);
        if (used && (!strncmp(s, "view.xlabel=", 12) || !strncmp(s, "view.ylabel=", 12)) &&
            strchr(s, '|')) { /* a still's names per panel; the figure has one plot */
            sp_log_error("--set %s: a sweep figure has one plot, so one name; '|' separates "
                         "the names of a still's panels", s);
            return SP_E_INPUT;
        }
        if (!used) {
            sp_log_error("--set %.*s: sweep does not use %.*s; it takes the [pendulum], "
                         "[initial], [pivot] and [integrator] keys, and view.theme, colormap, "
                         "background, font, font_size, font_scale, title, xlabel, ylabel, "
                         "colorbar_label, legend, marker_size, palette, panel_titles and "
                         "panel_labels for its figure",
                         (int)n, s, (int)n, s);
            return SP_E_INPUT;
        }
    }
    return 0;
}

/* What the CSV's metadata records beside the rows (csv_metadata.h). */
struct provenance {
    const struct sp_sweep_desc *d;
    const struct sp_scene *scene;      /* the base scene, overrides applied */
    const char *const *overrides;
    int n_overrides;
    const char *shard;                 /* "I/N", NULL = the whole grid */
    int merged;                        /* 1: a merge's figure, which records */
    const char *command;               /* its shards' command (merged_command; NULL:
                                          none); else this run's own is recorded */
};

/* The description line's words without "# springpend sweep " (the
 * metadata's dc:description), from the rows (rewound) into buf. */
static int description_words(FILE *rows, char *buf, size_t size)
{
    static const char prefix[] = "# springpend sweep ";
    rewind(rows);
    if (!fgets(buf, (int)size, rows) || strncmp(buf, prefix, strlen(prefix)))
        return SP_E_IO;
    buf[strcspn(buf, "\n")] = 0;
    memmove(buf, buf + strlen(prefix), strlen(buf + strlen(prefix)) + 1);
    return 0;
}

/* --csv: the rows without the description line (plain CSV: the column
 * names, then the rows), and beside it CSV.csv-metadata.json (the columns'
 * units, the sweep's description, the scene, the overrides, the command,
 * a shard's rows and SHA-256), both as .parts, the metadata renamed into
 * place first. Folders made go in *made. */
static int write_csv(FILE *rows, const char *csv, const struct provenance *pv,
                     struct sp_dirs *made, const volatile sig_atomic_t *cancel)
{
    static char buf[1 << 16];
    char description[1024];
    struct sp_outfile f, meta = {.fd = -1, .slot = -1};
    struct sha256_ctx sha;
    char hex[65];
    long lines = 0;
    int ret = description_words(rows, description, sizeof(description));
    if (!ret)
        ret = sp_dirs_make(csv, made);
    if (!ret)
        ret = sp_outfile_open(&f, csv, 0);
    if (ret)
        return ret;
    sha256_init(&sha);
    size_t got;
    while (!ret && (got = fread(buf, 1, sizeof(buf), rows)) > 0) {
        sha256_update(&sha, got, (const uint8_t *)buf);
        for (const char *q = buf; (q = memchr(q, '\n', (size_t)(buf + got - q))); q++)
            lines++;
        for (size_t done = 0; !ret && done < got;) {
            ssize_t w = write(f.fd, buf + done, got - done);
            if (w < 0 && errno == EINTR && !*cancel)
                continue;
            if (w <= 0) {
                sp_log_error("cannot write %s: %s", f.path, strerror(errno));
                ret = SP_E_IO;
            }
            done += w > 0 ? (size_t)w : 0;
        }
        if (!ret && *cancel)
            ret = SP_E_INTERRUPTED;
    }
    if (!ret && ferror(rows)) {
        sp_log_error("cannot read the sweep's rows back: %s", strerror(errno));
        ret = SP_E_IO;
    }
    sp_digest_hex(&sha, hex);
    struct sp_csv_column columns[SP_SWEEP_MAX_AXES + 16];
    struct sp_csv_meta m = {
        .title = "springpend sweep: one row per grid point and sample", .description = description,
        .scene = pv->scene, .overrides = pv->overrides, .n_overrides = pv->n_overrides,
        .columns = columns, .n_columns = sp_sweep_column_info(pv->d, columns, 18),
        .shard = pv->shard, .rows = lines - 1, .sha256 = hex};
    if (!ret)
        ret = sp_csv_metadata_write(&meta, csv, &m);
    if (!ret) /* the metadata first: when the CSV appears, it is there */
        ret = sp_outfile_commit_pair(&meta, &f, cancel);
    sp_outfile_discard(&f);
    return ret;
}

/* Flushes the rows, draws, prints, writes --csv and its metadata, and
 * only then puts the figure in place: a run that fails (a full disk under
 * the CSV) leaves no figure. On failure removes the folders made
 * (made[0]: the CSV's, made[1]: the figure's) that are left empty. Closes
 * fp. */
static int finish(FILE *fp, const struct sweep_opts *o, int ret, const struct provenance *pv,
                  struct sp_dirs made[2])
{
    const char *name = "the sweep's rows";
    struct sp_outfile figure = {.fd = -1, .slot = -1};
    if (!ret && fflush(fp) != 0) {
        sp_log_error("cannot write %s: %s", name, strerror(errno));
        ret = SP_E_IO;
    }
    if (!ret && o->output) {
        struct sp_plot_style style = o->style; /* with the scene, as the CSV's dc:source */
        char *ini = pv->scene ? sp_scene_ini(pv->scene) : NULL;
        /* a merged figure records the command of the sweep its shards
         * came from with the merge's figure options (merged_command): the
         * whole run's bytes */
        char *command = pv->merged ? (pv->command ? strdup(pv->command) : NULL)
                                   : sp_command_line_unnamed();
        style.scene_file = ini, style.command = command, style.scene = pv->scene;
        style.cancel = o->cancel; /* a signal stops the drawing */
        ret = draw(fp, o->csv ? o->csv : name, o->output, &style, &made[1], &figure);
        free(ini);
        free(command);
    }
    if (!ret && !o->quiet)
        sp_sweep_print_legend(fp, stderr); /* a basin map's attractors */
    if (!ret && o->format) {
        ret = sp_sweep_print(fp, name, o->format == 2, stdout);
        if (!ret && (fflush(stdout) != 0 || ferror(stdout))) {
            sp_log_error("cannot write the numbers to stdout: %s", strerror(errno));
            ret = SP_E_IO;
        }
    }
    if (!ret && *o->cancel) /* while drawing or merging: nothing written */
        ret = SP_E_INTERRUPTED;
    if (!ret && o->csv)
        ret = write_csv(fp, o->csv, pv, &made[0], o->cancel);
    if (!ret && figure.target)
        ret = sp_outfile_commit(&figure);
    sp_outfile_discard(&figure);
    fclose(fp);
    if (ret) {
        sp_dirs_remove_empty(&made[1]);
        sp_dirs_remove_empty(&made[0]);
    }
    sp_dirs_keep(&made[0]);
    sp_dirs_keep(&made[1]);
    return ret;
}

/* The figure's look into o->style: the scene's [view] (a sweep's or the
 * merged shards'), its title in force when the scene or a --set gives one;
 * checked (fonts, sizes) when a figure is asked for. 0 or SP_E_*. */
static int figure_look(struct sweep_opts *o, const struct sp_scene *scene,
                       const char *const *overrides, int n_overrides,
                       const struct sp_sweep_desc *d)
{
    o->style.view = &scene->view;
    o->style.desc = d; /* its figure's measure and keys: the text's room checked */
    o->style.title_set = scene->view.title[0] != 0;
    for (int i = 0; i < n_overrides; i++)
        o->style.title_set |= !strncmp(overrides[i], "view.title=", 11);
    return o->output ? check_figure(&o->style) : 0;
}

/* The scene's total energy at t = 0, J, as a sweep without --energy
 * takes it (sp_sweep_check). */
static double scene_energy(const struct sp_scene *s)
{
    struct sp_sim sim;
    sp_sim_init(&sim, s);
    return sim.energy0;
}

/* 1 when the E a poincare shard's command means (--energy, or the scene's
 * own without it: m->scene, the shard's dc:source) is the E the shard
 * holds, to 1e-12 of it (dc:source's angles in degrees round-trip to the
 * last bit at most). */
static int same_energy(const struct sweep_opts *o, const struct sp_sweep_desc *c,
                       const struct sp_sweep_merge *m)
{
    const double e = o->energy_given ? c->energy : scene_energy(&m->scene), h = m->d.energy;
    return e == h || fabs(e - h) <= 1e-12 * fmax(fabs(e), fabs(h));
}

/* The first difference between what a shard's command says (o, c: its
 * parse) and what the merge checked of the shards (m), as "what the
 * command says" and "what the shard holds", into said and held; 0 when
 * they agree. */
static int command_differs(const struct sweep_opts *o, const struct sp_sweep_desc *c,
                           const struct sp_sweep_merge *m, char *said, char *held, size_t size)
{
    const struct sp_sweep_desc *d = &m->d;
    int si = 0, sn = 0;
    if (o->merge || !o->shard) {
        snprintf(said, size, "%s", o->merge ? "--merge" : "no --shard");
        snprintf(held, size, "shard %d of %d", m->command_shard, m->n);
    } else if (sp_cli_shard(o->shard, sp_sweep_points(d), "the grid's points", &si, &sn) ||
               si != m->command_shard || sn != m->n) {
        snprintf(said, size, "--shard %s", o->shard);
        snprintf(held, size, "shard %d of %d (schema:position)", m->command_shard, m->n);
    } else if (c->measure != d->measure) {
        snprintf(said, size, "--measure %s", sp_sweep_measure_name(c->measure));
        snprintf(held, size, "measure %s", sp_sweep_measure_name(d->measure));
    } else if (c->n_axes != d->n_axes) {
        snprintf(said, size, "%d --vary", c->n_axes);
        snprintf(held, size, "%d keys varied", d->n_axes);
    } else if (c->time != d->time) {
        snprintf(said, size, "--time %.17g", c->time);
        snprintf(held, size, "T = %.17g s", d->time);
    } else if (c->transient != d->transient) {
        snprintf(said, size, "--transient %.17g", c->transient);
        snprintf(held, size, "T0 = %.17g s", d->transient);
    } else if (o->energy_given && d->measure != SP_MEASURE_POINCARE) {
        snprintf(said, size, "--energy %.17g", c->energy);
        snprintf(held, size, "measure %s, which takes no energy",
                 sp_sweep_measure_name(d->measure));
    } else if (d->measure == SP_MEASURE_POINCARE && !same_energy(o, c, m)) {
        if (o->energy_given)
            snprintf(said, size, "--energy %.17g", c->energy);
        else /* the sweep then takes the scene's own (attack9 #1) */
            snprintf(said, size, "no --energy (the scene's own E = %.17g J)",
                     scene_energy(&m->scene));
        snprintf(held, size, "E = %.17g J", d->energy);
    } else if (c->cont != d->cont || c->peak != d->peak || c->fast != d->fast) {
        snprintf(said, size, "--continue/--peak/--fast as %d/%d/%d", c->cont, c->peak, c->fast);
        snprintf(held, size, "continue/peak/kernel as %d/%d/%d", d->cont, d->peak, d->fast);
    } else if (o->n_overrides != m->n_overrides) {
        snprintf(said, size, "%d --set", o->n_overrides);
        snprintf(held, size, "%d overrides (prov:used)", m->n_overrides);
    } else {
        for (int a = 0; a < c->n_axes; a++)
            if (strcmp(c->axis[a].key, d->axis[a].key) || c->axis[a].from != d->axis[a].from ||
                c->axis[a].to != d->axis[a].to || c->axis[a].count != d->axis[a].count) {
                snprintf(said, size, "--vary %s=%.17g:%.17g:%d", c->axis[a].key,
                         c->axis[a].from, c->axis[a].to, c->axis[a].count);
                snprintf(held, size, "%s from %.17g to %.17g in %d values", d->axis[a].key,
                         d->axis[a].from, d->axis[a].to, d->axis[a].count);
                return 1;
            }
        for (int i = 0; i < o->n_overrides; i++)
            if (strcmp(o->overrides[i], m->overrides[i])) {
                snprintf(said, size, "--set %s", o->overrides[i]);
                snprintf(held, size, "the override %s (prov:used)", m->overrides[i]);
                return 1;
            }
        return 0;
    }
    return 1;
}

/* Whether the scene file a shard's command names (o->scene, its --set
 * applied as the sweep applied them) is another scene than the shard holds
 * (m->scene, from dc:source): both written as dc:source writes a scene
 * (sp_scene_ini). A file that cannot be opened here (the shard ran in
 * another folder or machine) or is no regular file is not checked: 0. 1
 * when it differs or does not load (the loader's messages muted: they
 * would quote the file), with said naming the file;
 * SP_E_NOMEM when out of memory. */
static int scene_differs(const struct sweep_opts *o, const struct sp_sweep_merge *m,
                         char *said, size_t size)
{
    /* a look, never a wait, and nothing but an ordinary file opened
     * (sp_infile_peek): a FIFO would block the merge for ever (attack9 #2),
     * a device's open runs its driver (a watchdog, a serial port: attack10
     * #5), /proc/kmsg takes the kernel's log and blocks (attack10 #11) */
    char *text = NULL;
    size_t bytes = 0;
    const int peeked = o->scene && strcmp(o->scene, "-")
                           ? sp_infile_peek(o->scene, 1u << 20, &text, &bytes) : 0;
    if (peeked <= 0)
        return peeked; /* not here, or no ordinary file: not checked */
    struct sp_scene named;
    sp_scene_defaults(&named);
    int differs = 1;
    /* the parser's messages would quote what the file holds (its first
     * section and keys), which the shard's author chose: muted, said below
     * without them */
    sp_log_mute(1);
    const int loaded = sp_scene_load_text(&named, o->scene, text, bytes, o->overrides,
                                          o->n_overrides) == 0;
    free(text);
    sp_log_mute(0);
    if (loaded) {
        sp_timeline_destroy(&named.timeline); /* as the sweep ignored it */
        char *a = sp_scene_ini(&named), *b = sp_scene_ini(&m->scene);
        if (!a || !b) {
            free(a), free(b);
            sp_scene_free(&named);
            sp_log_error("out of memory");
            return SP_E_NOMEM;
        }
        differs = strcmp(a, b) != 0;
        free(a), free(b);
    }
    sp_scene_free(&named);
    snprintf(said, size, loaded ? "the scene %s, whose scene is not the one the shard holds "
             "(dc:source)" : "%s, which is no scene springpend reads (with the command's --set; "
             "what it holds is not said)", o->scene);
    return differs;
}

/* The command a merged figure records, into *record (malloc'd; NULL:
 * none): the first shard's prov:wasGeneratedBy, parsed as a sweep's
 * command, with the merge's own figure options (--size, --dpi, --format)
 * after it, less what outputs omit (--shard, --csv). So the merge of a
 * sweep's shards drawn with --size 3in records what the one-piece run
 * with --size 3in does. A line springpend never writes is no command (the
 * figure records none, and the merge says so); a command that says
 * another sweep than the shard holds (another grid, measure, T or --set,
 * or a scene file, readable here, that holds another scene than dc:source)
 * is refused, naming the difference. 0 or SP_E_INPUT / SP_E_NOMEM. */
static int merged_command(const struct sp_sweep_merge *m, char **record)
{
    static const char help[] = "merge the shards as 'springpend sweep ... --shard I/N --csv "
                               "FILE' wrote them";
    struct sp_command_line *r = sp_command_line_read(m->command);
    *record = NULL;
    if (!r) {
        if (m->command)
            sp_log_note("%s" SP_CSV_METADATA_SUFFIX ": prov:wasGeneratedBy is not a command "
                        "line springpend writes; the figure records no command",
                        m->command_path);
        return 0;
    }
    int argc, ret;
    char **argv = sp_command_line_words(r, &argc);
    struct sweep_opts o;
    struct sp_sweep_desc c = {0};
    char said[320], held[320];
    if (strcmp(argv[0], "sweep")) {
        sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": prov:wasGeneratedBy is a command of "
                     "'springpend %.40s', not of a sweep's shard; %s", m->command_path, argv[0],
                     help);
        ret = SP_E_INPUT;
    } else {
        /* read as springpend read the shard's words when it ran them:
         * options after the scene too, whatever POSIXLY_CORRECT says here
         * (glibc's getopt reads it afresh at optind = 0) */
        const char *posix = getenv("POSIXLY_CORRECT");
        char *kept = posix ? strdup(posix) : NULL;
        if (posix && !kept) {
            sp_log_error("out of memory");
            sp_command_line_free(r);
            return SP_E_NOMEM;
        }
        unsetenv("POSIXLY_CORRECT");
        sp_command_line_parse_into(r);
        ret = parse_args(argc, argv, &o, &c);
        sp_command_line_parse_into(NULL);
        if (kept)
            setenv("POSIXLY_CORRECT", kept, 1), free(kept);
        if (ret) {
            sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": prov:wasGeneratedBy is not a sweep "
                         "shard's command springpend runs%s; %s", m->command_path,
                         ret > 0 ? " (it asks for --help)" : " (above)", help);
            ret = SP_E_INPUT;
        } else if (command_differs(&o, &c, m, said, held, sizeof(said))) {
            sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": prov:wasGeneratedBy says %s, but the "
                         "shard holds %s: it is not the command that made the shard; %s",
                         m->command_path, said, held, help);
            ret = SP_E_INPUT;
        } else if ((ret = scene_differs(&o, m, said, sizeof(said)))) {
            if (ret > 0)
                sp_log_error("%s" SP_CSV_METADATA_SUFFIX ": prov:wasGeneratedBy names %s: it "
                             "is not the command that made the shard; %s", m->command_path, said,
                             help);
            ret = ret > 0 ? SP_E_INPUT : ret;
        } else if (!(*record = sp_command_line_merged(r, "merge"))) {
            sp_log_error("out of memory");
            ret = SP_E_NOMEM;
        } else if ((ret = sp_command_line_check(*record))) {
            free(*record);
            *record = NULL;
        }
    }
    sp_command_line_free(r);
    return ret;
}

/* sweep --merge: the shards' rows (sweep_merge.h), drawn and written as a
 * sweep's own. */
static int merge(const struct sweep_opts *opts)
{
    struct sp_sweep_merge m;
    struct sweep_opts look = *opts, *o = &look; /* the figure's look: the shards' scene's */
    const struct sp_sweep_merge_desc desc = {.parts = o->parts, .n_parts = o->n_parts,
                                             .cancel = o->cancel};
    int ret = sp_sweep_merge_open(&m, &desc);
    FILE *out = NULL;
    char *record = NULL;
    struct sp_dirs made[2] = {{0}, {0}};
    if (!ret) /* checked whatever is written; recorded by a figure */
        ret = merged_command(&m, &record);
    if (!ret) /* as sweep_scene sets it for the one-piece run (its --set applied in m.scene) */
        ret = figure_look(o, &m.scene, m.overrides, m.n_overrides, &m.d);
    if (!ret)
        ret = open_rows(&out);
    if (!ret) {
        sp_sweep_merge_write(&m, out);
        const struct provenance whole = {.d = &m.d, .scene = &m.scene,
                                         .overrides = m.overrides,
                                         .n_overrides = m.n_overrides, .merged = 1,
                                         .command = record};
        ret = finish(out, o, 0, &whole, made);
    }
    if (ret == SP_E_INTERRUPTED) /* from any step: reading the shards too (attack10 #13) */
        sp_log_error("interrupted by %s: nothing written",
                     sp_signal_name(o->cancel ? (int)*o->cancel : 0));
    sp_sweep_merge_close(&m);
    free(record);
    if (!ret && !o->quiet)
        sp_fprintf_line(stderr, "wrote %s%s%s from %d shards", o->output ? o->output : "stdout",
                o->csv ? " and " : "", o->csv ? o->csv : "", m.n);
    return ret;
}

/* Refuses a --set of a key the grid varies: the grid's values would
 * replace it at every point, unseen. */
static int check_set_varied(const struct sweep_opts *o, const struct sp_sweep_desc *d)
{
    for (int i = 0; i < o->n_overrides; i++) {
        const char *s = o->overrides[i];
        const size_t n = strcspn(s, "=");
        for (int a = 0; a < d->n_axes; a++)
            if (strlen(d->axis[a].key) == n && !strncmp(s, d->axis[a].key, n)) {
                sp_log_error("--set %s and --vary %s=%.9g:%.9g:%d: the grid varies %s, so the "
                             "--set value would be replaced at every point; give one of them "
                             "(a fixed value: --set; a range: --vary)", s, d->axis[a].key,
                             d->axis[a].from, d->axis[a].to, d->axis[a].count, d->axis[a].key);
                return SP_E_INPUT;
            }
    }
    return 0;
}

/* A Poincare mosaic none of whose points can have the sweep's energy is
 * refused, named by where the energy came from (--energy, or the scene's
 * own when none was given), with the least energy the grid's starts need
 * (a grid of at most SWEEP_LEAST_SUMMED points). */
#define SWEEP_LEAST_SUMMED 100000
static int refuse_energy(const struct sweep_opts *o, const struct sp_sweep_desc *d,
                         const struct sp_scene *scene, long first, long last)
{
    /* each point's least energy takes a scene check (about 7 us) */
    const double least = last - first <= SWEEP_LEAST_SUMMED
                             ? sp_sweep_least_energy(d, scene, first, last) : NAN,
                 own = scene_energy(scene);
    char need[96] = "", give[96] = "a larger --energy E";
    if (isfinite(least)) {
        snprintf(need, sizeof(need), " (its starts need at least %g J, with θ̇ = 0)", least);
        snprintf(give, sizeof(give), "--energy E with E >= %g", least);
    }
    if (o->energy_given)
        sp_log_error("--energy %g: no point of the grid can have this energy%s; nothing "
                     "written; allowed: %s%s, or a grid (--vary) whose starts need less",
                     d->energy, need, give, own >= least ? " (or no --energy: the scene's own)"
                     : "");
    else
        sp_log_error("no --energy given, so every orbit takes the scene's own energy, %g J, "
                     "and no point of the grid can have it%s; nothing written; allowed: %s, or "
                     "a grid (--vary) whose starts need less", d->energy, need, give);
    return SP_E_INPUT;
}

/* Runs the sweep of the scene sp_cmd_sweep loaded (it frees the scene). */
static int sweep_scene(struct sweep_opts *o, struct sp_sweep_desc *d, struct sp_scene *scene)
{
    int ret;
    if ((ret = check_set_varied(o, d)) || (ret = sp_sweep_check(d, scene, o->energy_given)) ||
        (ret = figure_look(o, scene, o->overrides, o->n_overrides, d)))
        return ret;
    long total = sp_sweep_points(d), first = 0, last = total;
    int si = 0, sn = 0;
    if (o->shard) {
        if (sp_cli_shard(o->shard, total, "the grid's points", &si, &sn))
            return SP_E_INPUT;
        first = total * (si - 1) / sn;
        last = total * si / sn;
    }
    double rows = -1; /* orbit and poincare: the most rows */
    if ((ret = check_work(d, scene, first, last, o->quiet, &rows)))
        return ret;
    FILE *fp;
    struct sp_dirs made[2] = {{0}, {0}};
    if ((ret = open_rows(&fp)))
        return ret;
    static char buf[1 << 16];
    setvbuf(fp, buf, _IOFBF, sizeof(buf));
    ret = sp_sweep_write_header(fp, d, NULL);
    long blown = 0, unreachable = 0;
    struct progress prog = {.t0 = sp_clock_s()};
    double t0 = sp_clock_s();
    if (!ret)
        ret = sp_sweep_run(d, scene, first, last, o->threads, fp, &blown, &unreachable,
                           !o->quiet && isatty(2) ? show_progress : NULL, &prog);
    if (!ret && !o->shard && unreachable == last - first) { /* an empty figure */
        ret = refuse_energy(o, d, scene, first, last);
    }
    if (!ret && !o->shard && blown > 0 && blown + unreachable == last - first) {
        /* nothing to draw: an empty figure is no result (data exits 3 too) */
        char how[96];
        if (d->tolerance > 0)
            snprintf(how, sizeof(how), "a smaller integrator.tolerance (here %g)", d->tolerance);
        else
            snprintf(how, sizeof(how), "a smaller integrator.dt (here %g s), an adaptive "
                     "integrator.method (dop853)", d->dt);
        sp_log_error("every point of the grid blew up (%ld of %ld%s): nothing written; "
                     "allowed: a grid where some point stays finite: %s, or other values",
                     blown, last - first, unreachable ? ", the rest skipped" : "", how);
        ret = SP_E_UNSTABLE;
    }
    char shard[32];
    snprintf(shard, sizeof(shard), "%d/%d", si, sn);
    const struct provenance pv = {.d = d, .scene = scene, .overrides = o->overrides,
                                  .n_overrides = o->n_overrides, .shard = o->shard ? shard : NULL};
    ret = finish(fp, o, ret, &pv, made);
    if (ret == SP_E_INTERRUPTED) /* named, as merge's (attack11 #9) */
        sp_log_error("interrupted by %s: nothing written (a figure of part of a grid would "
                     "not say which part)", sp_signal_name(o->cancel ? (int)*o->cancel : 0));
    if (ret)
        return ret;
    if (blown)
        sp_log_error("%ld of %ld points blew up (NaN in the %s); the rest are drawn", blown,
                     last - first, o->output ? "figure" : "CSV");
    if (unreachable) /* only poincare skips points (sp_sweep_check refuses the rest) */
        sp_log_error("%ld of %ld points cannot have energy %g J (skipped)", unreachable,
                     last - first, d->energy);
    if (!o->quiet)
        sp_fprintf_line(stderr, "wrote %s%s%s: %ld points in %.2f s%s%.0f%s",
                o->output ? o->output : o->csv ? "" : "stdout", o->output && o->csv ? " and " : "",
                o->csv ? o->csv : "", last - first, sp_clock_s() - t0,
                rows >= 0 ? " (rows estimated: at most " : "", rows >= 0 ? rows : 0.0,
                rows >= 0 ? ")" : "");
    return 0;
}

int sp_cmd_sweep(int argc, char **argv, const volatile sig_atomic_t *cancel)
{
    struct sweep_opts o;
    struct sp_sweep_desc d = {0};
    struct sp_scene scene;
    int ret = parse_args(argc, argv, &o, &d);
    if (ret)
        return ret > 0 ? 0 : ret;
    o.cancel = cancel;
    if ((ret = check_outputs(&o)))
        return ret;
    if (o.merge)
        return merge(&o);
    sp_scene_defaults(&scene);
    if ((ret = check_used(&o)) || (ret = sp_scene_load(&scene, o.scene, o.overrides, o.n_overrides)))
        return ret;
    sp_timeline_destroy(&scene.timeline); /* the [timeline] is presentation: sweeps ignore it */
    d.cancel = cancel; /* a signal stops the run */
    ret = sweep_scene(&o, &d, &scene);
    sp_scene_free(&scene);
    return ret;
}
