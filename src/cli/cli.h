/* springpend: command-line helpers shared by the commands (main.c, cli_*.c). */
#ifndef SPRINGPEND_CLI_H
#define SPRINGPEND_CLI_H

#include <signal.h>

#include "springpend/scene.h"

#define SP_CLI_MAX_OVERRIDES 64
#define SP_CLI_NUMBER_MAX 40 /* --size's and --fps's numbers: characters at most */

/* The options only render takes (SP_CLI_TAKES_VIDEO). */
struct sp_cli_video_options {
    const char *format;      /* --format, NULL = by the output's extension */
    const char *frames;      /* --frames A:B as given, NULL = all */
    const char *shard;       /* --shard I/N as given, NULL = all */
};

/* The options only still takes (SP_CLI_TAKES_STILL). */
struct sp_cli_still_options {
    double at;               /* --at, simulated s; < 0 = not given */
    int scale;               /* --scale: supersampling factor, 0 = not given */
    double paper_w, paper_h; /* --size with units: the figure's physical
                                size, pt; 0 = not given (paper_h 0 alone: the
                                height follows the scene's aspect) */
    char paper_unit[2][3];   /* --size's units as given ("cm", "in", "pt", "mm"),
                                width's and height's; "" = not given */
    double dpi;              /* --dpi (PNG with paper_w): dots per inch, 0 = not given */
    const char *state;       /* --state: JSON path, NULL = none */
};

/* The options only data takes (SP_CLI_TAKES_EVERY, SP_CLI_TAKES_POINCARE). */
struct sp_cli_data_options {
    double every;            /* --every, simulated s; < 0 = not given */
    int poincare;            /* --poincare */
};

/* The options only info takes (SP_CLI_TAKES_JSON). */
struct sp_cli_info_options {
    int json;                /* --json */
};

/* A scene command's command line: the options every scene command
 * understands, and each command's own, which sp_cli_parse fills only for
 * the command that takes them (another's are refused). */
struct sp_cli_options {
    const char *scene_path;  /* the positional SCENE argument (the first) */
    const char *scene_paths[4]; /* SP_CLI_TAKES_SCENES: every SCENE given, n_scenes of them */
    int n_scenes;
    const char *output;      /* -o, NULL = the command's default */
    const char *overrides[SP_CLI_MAX_OVERRIDES]; /* --set, --size, --fps */
    int n_overrides;
    char size_buf[2][64];    /* storage for the overrides --size makes */
    char fps_buf[64];        /* storage for the override --fps makes */
    char quality_buf[3][48]; /* storage for the overrides --quality makes */
    int quiet;               /* -q */
    int verbose;             /* --verbose */
    int gl;                  /* --gl: enum sp_gl */
    struct sp_cli_video_options video; /* render */
    struct sp_cli_still_options still; /* still */
    struct sp_cli_data_options data;   /* data */
    struct sp_cli_info_options info;   /* info */
};

/* What a scene command takes beyond the options every one does (-o,
 * --set, --fps, --quality, --gl, --verbose, -q, -h; --size WxH only
 * render and still, which draw frames): its
 * command line, as sp_cli_parse's `takes`. An option of another command is
 * refused, naming the command that takes it. */
enum sp_cli_takes {
    SP_CLI_TAKES_VIDEO = 1 << 0,    /* render: --format, --frames, --shard */
    SP_CLI_TAKES_STILL = 1 << 1,    /* still: --at, --state, --scale, --dpi and
                                       --size with a unit */
    SP_CLI_TAKES_EVERY = 1 << 2,    /* data: --every */
    SP_CLI_TAKES_POINCARE = 1 << 3, /* data: --poincare */
    SP_CLI_TAKES_JSON = 1 << 4,     /* info: --json */
    SP_CLI_TAKES_SCENES = 1 << 5,   /* up to SP_CLI_MAX_SCENES SCENE files
                                       (side by side); else one */
};
#define SP_CLI_MAX_SCENES 4

/* Parses argv for one scene command, which takes `takes` (SP_CLI_TAKES_*).
 * Prints a message and returns SP_E_INPUT on misuse; returns 1 when --help
 * was asked (usage already printed). */
int sp_cli_parse(struct sp_cli_options *o, int argc, char **argv,
                 const char *usage, unsigned takes);

/* Refuses (SP_E_INPUT, said) a --set key the command does not read: one
 * is read when it, or its section, is among read[0..n) ("pendulum",
 * "video.fps"), or when skip lists it and it is not (a still: every key but
 * video.crf and video.preset). --quality's own keys are not checked (they
 * are the option's, which the command's --help offers). takes: the keys
 * the command reads, in words, for the message. */
int sp_cli_check_set_read(const struct sp_cli_options *o, const char *command,
                          const char *const *read, size_t n, int skip, const char *takes);

/* Reads a figure's physical size, "WIDTH" or "WIDTHxHEIGHT", each a decimal
 * number and a unit (pt, in, cm, mm) from 1 in to 200 in, into *w_pt and
 * *h_pt (pt; *h_pt 0 when only the width is given). Refuses anything else
 * (sp_cli_refuse, naming opt). */
int sp_cli_paper_size(const char *opt, const char *arg, double *w_pt, double *h_pt);

/* The pixels of a PNG of w_pt x h_pt pt at dpi dots per inch, into *w and
 * *h (rounded). A PNG springpend draws is 16x16 to 7680x4320 px, as its
 * frames are; beyond that, SP_E_INPUT after "--size W x H in at DPI dpi:
 * WxH px; WHAT is 16x16 to 7680x4320 px: lower --dpi or the size". */
int sp_cli_png_pixels(double w_pt, double h_pt, double dpi, const char *what, int *w, int *h);

/* Turns --frames / --shard into frames [*first, *last) of a video of
 * n_frames (*last = 0: to the end). */
int sp_cli_frame_range(const struct sp_cli_options *o, int n_frames,
                       int *first, int *last);

struct option;

/* The option table render, still and data parse with (cli.c), and its
 * short options into *shortopts: to read a recorded command's words as the
 * command would (`scene FILE --command`). Its output options' values: 'o'
 * (-o, --output) and 'J' (--state). */
const struct option *sp_cli_options(const char **shortopts);

/* As sp_cli_options for sweep (cli_sweep.c); its output options' values:
 * 'o', 'C' (--csv) and 'G' (--merge, which reads shards and writes). */
const struct option *sp_cli_sweep_options(const char **shortopts);

/* An option with a value is given once: SP_E_INPUT after a message when
 * option c (getopt_long's value for one of opts; its value: optarg) was
 * given before, which would silently win otherwise. first[c] keeps each
 * option's first value (the caller zeroes first). The options in
 * `repeatable` (--set, --vary: they add up) and flags may repeat. */
int sp_cli_once(int c, const struct option *opts, const char *repeatable, const char *first[128]);

/* Logs "OPT ARG: WRONG; expected ALLOWED" (adding the decimal syntax when
 * WRONG says SP_DECIMAL_NOT) and returns SP_E_INPUT: the one shape of a bad
 * numeric option's message, ARG as the user typed it. */
int sp_cli_refuse(const char *opt, const char *arg, const char *wrong, const char *allowed);

/* Says why getopt_long refused `word` ('?'; opterr off) for 'springpend
 * command': a value given to an option that takes none ("--merge=1"), a
 * prefix of several options ("--s": --set, --shard or --size), or no such
 * option. Always logs one line. */
void sp_cli_bad_option(const char *word, const struct option *opts, const char *command);

/* Reads arg, option opt's value, whole as a decimal number within lo..hi
 * (sp_decimal_in's flags: SP_DECIMAL_INTEGER, SP_DECIMAL_ABOVE) into *v;
 * else refuses it (sp_cli_refuse) with `allowed`. */
int sp_cli_number(const char *opt, const char *arg, double lo, double hi, int flags,
                  const char *allowed, double *v);

/* sp_decimal_in on the n characters at s (a field of a composite value such
 * as A:B): NULL with *v stored, or what is wrong. */
const char *sp_cli_field(const char *s, size_t n, double lo, double hi, int flags, double *v);

/* Reads --shard's "I/N", integers with 1 <= I <= N <= limit, into *i and
 * *n; `of` names what is split in the message ("the video's frames"). */
int sp_cli_shard(const char *arg, long limit, const char *of, int *i, int *n);

/* Loads each of o->scene_paths with the overrides into scenes[0..n_scenes);
 * every file's problems are said. 0 or the first error. */
int sp_cli_load_scenes(const struct sp_cli_options *o, struct sp_scene *scenes);

/* Loads o->scene_path with the overrides into *scene. */
int sp_cli_load_scene(const struct sp_cli_options *o, struct sp_scene *scene);

/* Fills buf with o->output or "out/<scene name><ext>", and refuses an output
 * that is a scene file itself, or (ext ".csv") whose metadata sidecar
 * NAME.csv-metadata.json is. */
int sp_cli_output_path(const struct sp_cli_options *o, const struct sp_scene *scene,
                       const char *ext, char *buf, size_t size);

/* The one rule for work that may run for hours: refuses `steps` beyond
 * limit (SP_E_INPUT: "WHAT: about N steps in all; at most LIMIT are
 * allowed: ADVICE"), and beyond note says on stderr (unless quiet) that it
 * will take a while. Render, still, data and sweep use it. */
int sp_cli_work(double steps, double limit, double note, const char *what, const char *advice,
                int quiet);

/* Estimates the integration to t_end: the run, and with camera (render,
 * still) the camera's pre-pass and the trails; an ensemble's members (each
 * integrated twice) and its Lyapunov run. Refuses beyond 1e10 steps with
 * every part's count and what to change; says so on stderr beyond 3e8.
 * cancel (main's stop flag) stops an adaptive method's probe. */
int sp_cli_check_work(const struct sp_cli_options *o, const struct sp_scene *sc,
                      double t_end, int camera, const volatile sig_atomic_t *cancel);

/* The commands. Each parses argv (argv[0] is the command's name) into its
 * options and runs; cancel is main's stop flag (the signal's number once
 * one arrived), handed down to what runs long. 0 or SP_E_*. */
int sp_cmd_render(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_still(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_data(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_info(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_compare(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_sweep(int argc, char **argv, const volatile sig_atomic_t *cancel);
int sp_cmd_scene(int argc, char **argv, const volatile sig_atomic_t *cancel);

#endif
