/* springpend: option parsing shared by the scene commands. */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli.h"
#include "base/command_line.h"
#include "base/decimal.h"
#include "springpend/common.h"
#include "springpend/csv_metadata.h"
#include "springpend/outfile.h"
#include "springpend/pipeline.h"
#include "springpend/sim.h"
#include "springpend/timeline.h"

#define STRING(x) #x
#define QUOTE(x) STRING(x)

static int add_override(struct sp_cli_options *o, const char *s)
{
    if (o->n_overrides >= SP_CLI_MAX_OVERRIDES) {
        sp_log_error("too many overrides; at most %d are allowed", SP_CLI_MAX_OVERRIDES);
        return SP_E_INPUT;
    }
    o->overrides[o->n_overrides++] = s;
    return 0;
}

int sp_cli_once(int c, const struct option *opts, const char *repeatable, const char *first[128])
{
    if (c <= 0 || c >= 128 || strchr(repeatable, c))
        return 0;
    for (const struct option *p = opts; p->name; p++)
        if (p->val == c && p->has_arg == required_argument) {
            if (first[c]) {
                sp_log_error("--%s given twice (%s, then %s); give it once", p->name, first[c],
                             optarg);
                return SP_E_INPUT;
            }
            first[c] = optarg;
            return 0;
        }
    return 0;
}

int sp_cli_refuse(const char *opt, const char *arg, const char *wrong, const char *allowed)
{
    sp_log_error("%s %s: %s; expected %s%s", opt, arg, wrong, allowed,
                 strstr(wrong, SP_DECIMAL_NOT) ? ", " SP_DECIMAL_ALLOWED : "");
    return SP_E_INPUT;
}

int sp_cli_number(const char *opt, const char *arg, double lo, double hi, int flags,
                  const char *allowed, double *v)
{
    const char *wrong = sp_decimal_in(arg, lo, hi, flags, v);
    return wrong ? sp_cli_refuse(opt, arg, wrong, allowed) : 0;
}

const char *sp_cli_field(const char *s, size_t n, double lo, double hi, int flags, double *v)
{
    char num[128];
    if (n >= sizeof(num))
        return SP_DECIMAL_NOT;
    snprintf(num, sizeof(num), "%.*s", (int)n, s);
    return sp_decimal_in(num, lo, hi, flags, v);
}

int sp_cli_shard(const char *arg, long limit, const char *of, int *i, int *n)
{
    char allowed[192], wrong[64];
    const char *slash = strchr(arg, '/'), *bad;
    double vi, vn;
    snprintf(allowed, sizeof(allowed), "I/N, integers with 1 <= I <= N <= %ld (%s), e.g. "
             "--shard 2/4", limit, of);
    if (!slash || strchr(slash + 1, '/'))
        return sp_cli_refuse("--shard", arg, "not I/N", allowed);
    /* N first: I's range is 1..N */
    if ((bad = sp_cli_field(slash + 1, strlen(slash + 1), 1, (double)limit, SP_DECIMAL_INTEGER,
                            &vn))) {
        snprintf(wrong, sizeof(wrong), "N %s", bad);
        return sp_cli_refuse("--shard", arg, wrong, allowed);
    }
    if ((bad = sp_cli_field(arg, (size_t)(slash - arg), 1, vn, SP_DECIMAL_INTEGER, &vi))) {
        snprintf(wrong, sizeof(wrong), "I %s", bad);
        return sp_cli_refuse("--shard", arg, wrong, allowed);
    }
    *i = (int)vi, *n = (int)vn;
    return 0;
}

#define TOO_LONG "too long (at most " QUOTE(SP_CLI_NUMBER_MAX) " characters a number)"

/* The units a figure's physical size may be given in, pt each. */
static const struct { const char *name; double pt; } paper_units[] = {
    {"pt", 1}, {"in", 72}, {"cm", 72 / 2.54}, {"mm", 72 / 25.4},
};

/* 1 when arg gives a physical size: a unit after its first number. */
static int paper_given(const char *arg)
{
    const size_t n = strcspn(arg, "x"), all = strlen(arg);
    for (size_t u = 0; u < sizeof(paper_units) / sizeof(paper_units[0]); u++)
        if ((n >= 2 && !strncmp(arg + n - 2, paper_units[u].name, 2)) ||
            (all >= 2 && !strcmp(arg + all - 2, paper_units[u].name)))
            return 1;
    return 0;
}

int sp_cli_png_pixels(double w_pt, double h_pt, double dpi, const char *what, int *w, int *h)
{
    const double pw = round(w_pt * dpi / 72), ph = round(h_pt * dpi / 72);
    if (!(pw >= 16 && ph >= 16 && pw <= 7680 && ph <= 4320)) {
        sp_log_error("--size %.4g x %.4g in at %g dpi: %.0fx%.0f px; %s is 16x16 to "
                     "7680x4320 px: %s --dpi or the size", w_pt / 72, h_pt / 72, dpi, pw, ph,
                     what, pw > 7680 || ph > 4320 ? "lower" : "raise");
        return SP_E_INPUT;
    }
    *w = (int)pw, *h = (int)ph;
    return 0;
}

int sp_cli_paper_size(const char *opt, const char *arg, double *w_pt, double *h_pt)
{
    static const char allowed[] =
        "WIDTH or WIDTHxHEIGHT, each a number and a unit (pt, in, cm, mm), from 1 in to "
        "200 in, e.g. --size 8.6cm or --size 3.4inx2.5in";
    const char *x = strchr(arg, 'x');
    double side[2] = {0, 0};
    char wrong[96];
    if (x && (strchr(x + 1, 'x') || !x[1]))
        return sp_cli_refuse(opt, arg, "not WIDTH or WIDTHxHEIGHT", allowed);
    for (int k = 0; k < (x ? 2 : 1); k++) {
        const char *s = k ? x + 1 : arg;
        const size_t n = k || !x ? strlen(s) : (size_t)(x - arg);
        size_t u = 0, nu = sizeof(paper_units) / sizeof(paper_units[0]);
        while (u < nu && !(n >= 2 && !strncmp(s + n - 2, paper_units[u].name, 2)))
            u++;
        if (u == nu) {
            snprintf(wrong, sizeof(wrong), "%s has no unit", k ? "HEIGHT" : "WIDTH");
            return sp_cli_refuse(opt, arg, wrong, allowed);
        }
        const char *bad = sp_cli_field(s, n - 2, 72 / paper_units[u].pt,
                                       14400 / paper_units[u].pt, 0, &side[k]);
        if (bad) {
            snprintf(wrong, sizeof(wrong), "%s %s", k ? "HEIGHT" : "WIDTH", bad);
            return sp_cli_refuse(opt, arg, wrong, allowed);
        }
        side[k] *= paper_units[u].pt;
    }
    *w_pt = side[0], *h_pt = side[1];
    return 0;
}

/* --size WxH: each side read as the scene reads video.width and height,
 * messages naming --size; then the two overrides. A size with units is a
 * figure's physical size instead (sp_cli_paper_size). */
static int add_size(struct sp_cli_options *o, const char *arg)
{
    static const char *const key[2] = {"video.width", "video.height"};
    static const char allowed[] = "WIDTHxHEIGHT in pixels, e.g. --size 1920x1080, or a "
                                  "figure's physical size, e.g. --size 8.6cm";
    char origin[96], side[2][SP_CLI_NUMBER_MAX + 1];
    const char *x = strchr(arg, 'x');
    const size_t w = x ? (size_t)(x - arg) : 0;
    if (paper_given(arg)) { /* the units, for a refusal's sizes that fit (print_fit.c) */
        const size_t n = x ? (size_t)(x - arg) : strlen(arg);
        memset(o->still.paper_unit, 0, sizeof(o->still.paper_unit));
        if (n >= 2)
            memcpy(o->still.paper_unit[0], arg + n - 2, 2);
        if (x && strlen(x + 1) >= 2)
            memcpy(o->still.paper_unit[1], arg + strlen(arg) - 2, 2);
        return sp_cli_paper_size("--size", arg, &o->still.paper_w, &o->still.paper_h);
    }
    if (!x || strchr(x + 1, 'x'))
        return sp_cli_refuse("--size", arg, "not WIDTHxHEIGHT", allowed);
    if (w >= sizeof(side[0]) || strlen(x + 1) >= sizeof(side[1]))
        return sp_cli_refuse("--size", arg, TOO_LONG, allowed);
    snprintf(side[0], sizeof(side[0]), "%.*s", (int)w, arg);
    snprintf(side[1], sizeof(side[1]), "%s", x + 1);
    snprintf(origin, sizeof(origin), "--size %s", arg);
    for (int k = 0; k < 2; k++) {
        if (sp_scene_check_value(key[k], side[k], origin))
            return SP_E_INPUT;
        snprintf(o->size_buf[k], sizeof(o->size_buf[k]), "%s=%.*s", key[k], SP_CLI_NUMBER_MAX,
                 side[k]);
        if (add_override(o, o->size_buf[k]))
            return SP_E_INPUT;
    }
    o->still.paper_w = o->still.paper_h = 0; /* a later --size wins, whatever its form */
    return 0;
}

/* The options one scene command owns (struct sp_cli_takes): given to
 * another, each is refused as "OPT is for 'springpend OWNER'". */
static const struct owned_option {
    int ch;            /* getopt_long's value for it */
    unsigned needs;    /* SP_CLI_TAKES_*: the command must take this */
    const char *name;  /* as the message names it; NULL: as it was typed */
    const char *owner; /* the command that takes it */
} owned[] = {
    /* a still, data or info would take these and do nothing */
    {'f', SP_CLI_TAKES_VIDEO, "--format", "render"},
    {'R', SP_CLI_TAKES_VIDEO, "--frames", "render"},
    {'D', SP_CLI_TAKES_VIDEO, "--shard", "render"},
    {'j', SP_CLI_TAKES_JSON, NULL, "info"},
    {'P', SP_CLI_TAKES_POINCARE, NULL, "data"},
    {'J', SP_CLI_TAKES_STILL, "--state", "still"},
    {'a', SP_CLI_TAKES_STILL, "--at", "still"},
    {'X', SP_CLI_TAKES_STILL, "--scale", "still"},
    {'d', SP_CLI_TAKES_STILL, "--dpi", "still"},
    {'e', SP_CLI_TAKES_EVERY, "--every", "data"},
    /* a frame's size: data and info draw no frame */
    {'S', SP_CLI_TAKES_VIDEO | SP_CLI_TAKES_STILL, "--size", "render' and 'springpend still"},
    {'G', SP_CLI_TAKES_VIDEO | SP_CLI_TAKES_STILL, "--gl", "render' and 'springpend still"},
    {'v', SP_CLI_TAKES_VIDEO, "--verbose", "render"}, /* the stages' times */
    /* info prints; it writes no file and has nothing to quiet */
    {'o', SP_CLI_TAKES_VIDEO | SP_CLI_TAKES_STILL | SP_CLI_TAKES_EVERY, "-o/--output",
     "render', 'springpend still' and 'springpend data"},
    {'q', SP_CLI_TAKES_VIDEO | SP_CLI_TAKES_STILL | SP_CLI_TAKES_EVERY, "-q/--quiet",
     "render', 'springpend still' and 'springpend data"},
};

/* SP_E_INPUT after a message when option c (just read by getopt_long)
 * belongs to a command other than argv[0], which takes `takes`; else 0. */
static int refuse_owned(int c, unsigned takes, char **argv)
{
    for (size_t i = 0; i < sizeof(owned) / sizeof(owned[0]); i++)
        if (owned[i].ch == c && !(takes & owned[i].needs)) {
            sp_log_error("%s is for 'springpend %s'; see 'springpend %s --help'",
                         owned[i].name ? owned[i].name : argv[optind - 1], owned[i].owner,
                         argv[0]);
            return SP_E_INPUT;
        }
    return 0;
}

static const char short_options[] = ":o:qhv";
static const struct option longopts[] = {
    {"output", required_argument, 0, 'o'}, {"set", required_argument, 0, 's'},
    {"size", required_argument, 0, 'S'},   {"fps", required_argument, 0, 'F'},
    {"at", required_argument, 0, 'a'},     {"quiet", no_argument, 0, 'q'},
    {"help", no_argument, 0, 'h'},         {"every", required_argument, 0, 'e'},
    {"verbose", no_argument, 0, 'v'},      {"format", required_argument, 0, 'f'},
    {"frames", required_argument, 0, 'R'}, {"shard", required_argument, 0, 'D'},
    {"gl", required_argument, 0, 'G'},     {"quality", required_argument, 0, 'Q'},
    {"scale", required_argument, 0, 'X'},  {"dpi", required_argument, 0, 'd'},
    {"state", required_argument, 0, 'J'},
    {"json", no_argument, 0, 'j'},         {"poincare", no_argument, 0, 'P'},
    {0, 0, 0, 0},
};

const struct option *sp_cli_options(const char **shortopts)
{
    *shortopts = short_options;
    return longopts;
}

/* Takes option c, which getopt_long just read (its value: optarg), into
 * *o; --quality's name into *quality. 0, 1 after --help (usage printed),
 * or SP_E_INPUT after a message. */
static int take_option(struct sp_cli_options *o, int c, int argc, char **argv,
                       const char *usage, const char **quality)
{
    char origin[96];
    double v;
    switch (c) {
    case 'v': o->verbose = 1; return 0;
    case 'f': o->video.format = optarg; return 0;
    case 'R': o->video.frames = optarg; return 0;
    case 'D': o->video.shard = optarg; return 0;
    case 'Q': *quality = optarg; return 0;
    case 'G':
        if (!strcmp(optarg, "osmesa"))
            o->gl = SP_GL_OSMESA;
        else if (!strcmp(optarg, "egl"))
            o->gl = SP_GL_EGL;
        else {
            sp_log_error("--gl %s: use osmesa or egl", optarg);
            return SP_E_INPUT;
        }
        return 0;
    case 'o': o->output = optarg; return 0;
    case 's':
        if (!strchr(optarg, '=')) {
            sp_log_error("--set %s: expected SECTION.KEY=VALUE with '=' in one argument, "
                         "e.g. --set %s=%s", optarg, optarg,
                         optind < argc ? argv[optind] : "VALUE");
            return SP_E_INPUT;
        }
        return add_override(o, optarg);
    case 'q': o->quiet = 1, sp_log_quiet(1); return 0;
    case 'j': o->info.json = 1; return 0;
    case 'P': o->data.poincare = 1; return 0;
    case 'h': fputs(usage, stdout); return 1;
    case 'S': return add_size(o, optarg);
    case 'F':
        /* checked here, so that a message names --fps, not the override */
        snprintf(origin, sizeof(origin), "--fps %s", optarg);
        if (strlen(optarg) > SP_CLI_NUMBER_MAX)
            return sp_cli_refuse("--fps", optarg, TOO_LONG, "frames per second (video.fps)");
        if (sp_scene_check_value("video.fps", optarg, origin))
            return SP_E_INPUT;
        snprintf(o->fps_buf, sizeof(o->fps_buf), "video.fps=%s", optarg);
        return add_override(o, o->fps_buf);
    case 'J': o->still.state = optarg; return 0;
    case 'a':
        return sp_cli_number("--at", optarg, 0, 1e9, 0,
                             "a simulated time in seconds, 0 <= t <= 1e9", &o->still.at);
    case 'X': {
        int ret = sp_cli_number("--scale", optarg, 1, 4, SP_DECIMAL_INTEGER,
                                "a supersampling factor, an integer from 1 to 4", &v);
        o->still.scale = (int)v;
        return ret;
    }
    case 'd':
        return sp_cli_number("--dpi", optarg, 10, 2400, SP_DECIMAL_ABOVE,
                             "the PNG's dots per inch, 10 < dpi <= 2400, with --size in "
                             "units, e.g. --size 8.6cm --dpi 300", &o->still.dpi);
    case 'e':
        return sp_cli_number("--every", optarg, 0, 1e9, SP_DECIMAL_ABOVE,
                             "a sampling interval in simulated seconds, 0 < every <= 1e9",
                             &o->data.every);
    case ':':
        sp_log_error("option '%s' needs a value; see 'springpend %s --help'", argv[optind - 1],
                     argv[0]);
        return SP_E_INPUT;
    default:
        sp_cli_bad_option(argv[optind - 1], longopts, argv[0]);
        return SP_E_INPUT;
    }
}

void sp_cli_bad_option(const char *word, const struct option *opts, const char *command)
{
    if (word[0] == '-' && word[1] == '-' && word[2] && word[2] != '=') {
        const char *name = word + 2;
        const size_t len = strcspn(name, "=");
        char list[512] = "";
        int exact = -1, last = -1, n = 0;
        for (int i = 0; opts[i].name; i++) {
            if (strncmp(opts[i].name, name, len))
                continue;
            if (strlen(opts[i].name) == len)
                exact = i;
            last = i, n++;
        }
        const int one = exact >= 0 ? exact : n == 1 ? last : -1;
        if (one >= 0 && name[len] == '=' && opts[one].has_arg == no_argument) {
            sp_log_error("--%s takes no value ('%s'); see 'springpend %s --help'",
                         opts[one].name, word, command);
            return;
        }
        if (one < 0 && n > 1) {
            for (int i = 0, k = 0; opts[i].name; i++)
                if (!strncmp(opts[i].name, name, len))
                    snprintf(list + strlen(list), sizeof(list) - strlen(list), "%s--%s",
                             !k++ ? "" : k == n ? " or " : ", ", opts[i].name);
            sp_log_error("option '--%.*s' is ambiguous: %s; see 'springpend %s --help'",
                         (int)len, name, list, command);
            return;
        }
    }
    sp_log_error("unknown option '%s'; see 'springpend %s --help'", word, command);
}

/* 1 when --set text s names entry e: a section ("pendulum") or a key
 * ("video.fps"). */
static int set_names(const char *s, const char *e)
{
    const size_t key = strcspn(s, "="), n = strlen(e);
    return strchr(e, '.') ? key == n && !strncmp(s, e, n)
                          : key > n && s[n] == '.' && !strncmp(s, e, n);
}

int sp_cli_check_set_read(const struct sp_cli_options *o, const char *command,
                          const char *const *read, size_t n, int skip, const char *takes)
{
    for (int i = 0; i < o->n_overrides; i++) {
        const char *s = o->overrides[i];
        int named = 0, quality = 0;
        for (size_t k = 0; k < sizeof(o->quality_buf) / sizeof(o->quality_buf[0]); k++)
            quality |= s == o->quality_buf[k];
        for (size_t k = 0; k < n && !named; k++)
            named = set_names(s, read[k]);
        if (quality || named != skip || !strchr(s, '=') || s == o->fps_buf)
            continue; /* the parser names a key it does not know */
        sp_log_error("--set %.*s: %s does not read %.*s; it takes %s", (int)strcspn(s, "="), s,
                     command, (int)strcspn(s, "="), s, takes);
        return SP_E_INPUT;
    }
    return 0;
}

/* --quality NAME: like the tools people know, its size and fps put first
 * among the overrides, so that --set, --size and --fps still win. */
static int add_quality(struct sp_cli_options *o, const char *quality)
{
    static const struct { const char *name; int w, h, fps; } qualities[] = {
        {"low", 854, 480, 15}, {"medium", 1280, 720, 30},
        {"high", 1920, 1080, 60}, {"4k", 3840, 2160, 60},
    };
    size_t i = 0, n = sizeof(qualities) / sizeof(qualities[0]);
    while (i < n && strcmp(quality, qualities[i].name))
        i++;
    if (i == n) {
        sp_log_error("--quality %s: use low (854x480@15), medium (1280x720@30), "
                     "high (1920x1080@60) or 4k (3840x2160@60)", quality);
        return SP_E_INPUT;
    }
    if (o->n_overrides + 3 > SP_CLI_MAX_OVERRIDES) {
        sp_log_error("too many overrides; at most %d are allowed", SP_CLI_MAX_OVERRIDES);
        return SP_E_INPUT;
    }
    /* First, so that --set, --size and --fps override it. */
    memmove(o->overrides + 3, o->overrides, o->n_overrides * sizeof(o->overrides[0]));
    o->n_overrides += 3;
    snprintf(o->quality_buf[0], sizeof(o->quality_buf[0]), "video.width=%d", qualities[i].w);
    snprintf(o->quality_buf[1], sizeof(o->quality_buf[1]), "video.height=%d", qualities[i].h);
    snprintf(o->quality_buf[2], sizeof(o->quality_buf[2]), "video.fps=%d", qualities[i].fps);
    for (int k = 0; k < 3; k++)
        o->overrides[k] = o->quality_buf[k];
    return 0;
}

/* The SCENE arguments after the options: one, or up to SP_CLI_MAX_SCENES
 * when the command takes SP_CLI_TAKES_SCENES. */
static int take_scenes(struct sp_cli_options *o, int argc, char **argv, unsigned takes)
{
    const int most = takes & SP_CLI_TAKES_SCENES ? SP_CLI_MAX_SCENES : 1;
    if (optind >= argc || argc - optind > most) {
        if (most > 1 && optind < argc)
            sp_log_error("%d SCENE files: at most %d are shown side by side; see "
                         "'springpend %s --help'", argc - optind, most, argv[0]);
        else
            sp_log_error(optind >= argc ? "missing SCENE file; see 'springpend %s --help'"
                                        : "expected one SCENE file; see 'springpend %s --help'",
                         argv[0]);
        return SP_E_INPUT;
    }
    o->scene_path = argv[optind];
    o->n_scenes = argc - optind;
    for (int i = 0; i < o->n_scenes; i++)
        o->scene_paths[i] = argv[optind + i];
    return 0;
}

int sp_cli_parse(struct sp_cli_options *o, int argc, char **argv, const char *usage,
                 unsigned takes)
{
    const char *quality = NULL, *first[128] = {0};
    int c, ret = 0;
    memset(o, 0, sizeof(*o));
    o->still.at = -1;
    o->data.every = -1;
    optind = 1;
    opterr = 0;
    /* ':' first: an option missing its value returns ':', not '?'; parsed
     * as the outputs record the command (command_line.h) */
    while ((c = sp_command_line_getopt(argc, argv, short_options, longopts)) != -1)
        if ((ret = refuse_owned(c, takes, argv)) ||
            (ret = sp_cli_once(c, longopts, "sSF", first)) ||
            (ret = take_option(o, c, argc, argv, usage, &quality)))
            return ret;
    if (quality && (ret = add_quality(o, quality)))
        return ret;
    if (o->still.paper_w && !(takes & SP_CLI_TAKES_STILL)) {
        sp_log_error("--size with a unit is a figure's physical size, for 'springpend still' "
                     "and 'springpend sweep'; a %s's size is WIDTHxHEIGHT in pixels",
                     !strcmp(argv[0], "render") ? "video" : "scene");
        return SP_E_INPUT;
    }
    if (o->still.dpi && !o->still.paper_w) {
        sp_log_error("--dpi sets a PNG figure's dots per inch at a physical size: give --size "
                     "with a unit too, e.g. --size 8.6cm --dpi 300");
        return SP_E_INPUT;
    }
    return take_scenes(o, argc, argv, takes);
}

int sp_cli_frame_range(const struct sp_cli_options *o, int n_frames,
                       int *first, int *last)
{
    *first = *last = 0;
    if (o->video.frames && o->video.shard) {
        sp_log_error("--frames and --shard cannot be combined; give one");
        return SP_E_INPUT;
    }
    if (o->video.frames) {
        /* "A:B", "A:" (to the end) or ":B"; frames count from 0, B excluded */
        const char *s = o->video.frames, *colon = strchr(s, ':'), *bad = NULL;
        double a = 0, b = n_frames;
        char allowed[192], wrong[64];
        snprintf(allowed, sizeof(allowed), "A:B, A: or :B, integers with 0 <= A < B <= %d (the "
                 "video's frames are 0..%d; B is not included)", n_frames, n_frames - 1);
        if (!colon || strchr(colon + 1, ':') || (colon == s && !colon[1]))
            return sp_cli_refuse("--frames", s, "not A:B", allowed);
        if (colon > s && (bad = sp_cli_field(s, (size_t)(colon - s), 0, n_frames - 1,
                                             SP_DECIMAL_INTEGER, &a)))
            snprintf(wrong, sizeof(wrong), "A %s", bad);
        else if (colon[1] && (bad = sp_cli_field(colon + 1, strlen(colon + 1), 1, n_frames,
                                                 SP_DECIMAL_INTEGER, &b)))
            snprintf(wrong, sizeof(wrong), "B %s", bad);
        else if (a >= b)
            snprintf(wrong, sizeof(wrong), "%s", bad = "A not below B");
        if (bad)
            return sp_cli_refuse("--frames", s, wrong, allowed);
        *first = (int)a;
        *last = (int)b;
    }
    if (o->video.shard) {
        int i, n;
        if (sp_cli_shard(o->video.shard, n_frames, "the video's frames", &i, &n))
            return SP_E_INPUT;
        return sp_pipeline_shard(n_frames, i - 1, n, first, last);
    }
    return 0;
}

int sp_cli_load_scenes(const struct sp_cli_options *o, struct sp_scene *scenes)
{
    int ret = 0;
    for (int i = 0; i < o->n_scenes; i++) {
        sp_scene_defaults(&scenes[i]);
        int err = sp_scene_load(&scenes[i], o->scene_paths[i], o->overrides, o->n_overrides);
        ret = ret ? ret : err;
    }
    return ret;
}

int sp_cli_load_scene(const struct sp_cli_options *o, struct sp_scene *scene)
{
    sp_scene_defaults(scene);
    return sp_scene_load(scene, o->scene_path, o->overrides, o->n_overrides);
}

int sp_cli_output_path(const struct sp_cli_options *o, const struct sp_scene *scene,
                       const char *ext, char *buf, size_t size)
{
    if (o->output)
        snprintf(buf, size, "%s", o->output);
    else
        snprintf(buf, size, "out/%s%s", scene->name, ext);
    /* a CSV's metadata is written beside it (NAME.csv-metadata.json): it
     * must not replace a scene either */
    char meta[4096];
    const int csv = !strcmp(ext, ".csv") && !sp_outfile_is_stream(buf) &&
                    snprintf(meta, sizeof(meta), "%s" SP_CSV_METADATA_SUFFIX, buf) <
                        (int)sizeof(meta);
    for (int i = -1; i < o->n_scenes; i++) {
        const char *in = i < 0 ? o->scene_path : o->scene_paths[i];
        if (in && sp_outfile_same_file(buf, in)) {
            sp_log_error("output %s is the scene file itself; choose another -o", buf);
            return SP_E_INPUT;
        }
        if (in && csv && sp_outfile_same_file(meta, in)) {
            sp_log_error("output %s: its metadata %s would overwrite the scene file %s; choose "
                         "another -o", buf, meta, in);
            return SP_E_INPUT;
        }
    }
    int err = sp_outfile_check_writable(buf, "output");
    /* the metadata's own name must fit the folder too (attack19 #5) */
    return err ? err : csv ? sp_outfile_check_name(buf, SP_CSV_METADATA_SUFFIX, "output",
                                                   "metadata") : 0;
}

/* Past this many steps a run is refused: hours of integration. The same
 * limit scene.c puts on fixed-step videos. */
#define SP_MAX_STEPS 1e10
/* Past this many a run says how long it will be. */
#define SP_NOTE_STEPS 3e8

int sp_cli_work(double steps, double limit, double note, const char *what, const char *advice,
                int quiet)
{
    if (!(steps <= limit)) {
        sp_log_error("%s: about %.2g steps in all; at most %.0e are allowed: %s", what, steps,
                     limit, advice);
        return SP_E_INPUT;
    }
    if (steps > note && !quiet)
        sp_fprintf_line(stderr, "springpend: %s: about %.2g steps in all; this will take a while%s",
                what, steps, isatty(2) ? "" : " (progress is shown on a terminal)");
    return 0;
}

int sp_cli_check_work(const struct sp_cli_options *o, const struct sp_scene *sc,
                      double t_end, int camera)
{
    const struct sp_method_info *mi = sp_method_info(sc->integrator.method);
    const double steps = sp_sim_estimate_steps(sc, t_end);
    const int members = sc->ensemble.count > 1 ? sc->ensemble.count : 0;
    const double frames = sp_timeline_frames(sc); /* a [timeline]'s own count, as render makes */
    /* the camera's pre-pass integrates the run once more, sampling every
     * integrator.dt (adaptive methods too) */
    const double pre = camera ? steps + (mi->adaptive ? t_end / sc->integrator.dt : 0) : 0;
    /* an ensemble: every member twice (its own pre-pass for the camera and
     * the spread, then the run; the pre-pass of an adaptive batch samples
     * 200 times a fastest period), and the central scene's Lyapunov run */
    struct sp_sim sim;
    sp_sim_init(&sim, sc);
    const double member_pre = mi->adaptive ? t_end * sp_params_omega_max(&sim.p) / 0.03 : 0;
    const double ens = members ? members * (2 * steps + member_pre) + steps : 0;
    /* trails: up to 64 samples a frame for the pendulum's, a point a frame
     * for each member's */
    const double trail = camera ? (sc->view.trail ? 64 * frames : 0) +
                                  (members && sc->ensemble.trails ? members * frames : 0) : 0;
    char what[512], advice[512];
    snprintf(what, sizeof(what), "integrating to t = %g s with %s (%.3g steps per simulated "
             "second at %s): the run %.2g steps, the camera's pre-pass %.2g, %d ensemble "
             "members %.2g, trail samples %.2g", t_end, mi->name, steps / t_end,
             mi->adaptive ? "this tolerance" : "this dt", steps, pre, members, ens, trail);
    if (ens > steps + pre && ens > trail)
        snprintf(advice, sizeof(advice), "lower ensemble.count, or integrate less far");
    else if (pre > 2 * steps)
        snprintf(advice, sizeof(advice), "raise integrator.dt, which %s uses only to sample "
                 "the camera's pre-pass", mi->name);
    else if (trail > steps + pre)
        snprintf(advice, sizeof(advice), "shorten view.trail or the video");
    else
        snprintf(advice, sizeof(advice), "%s, lower pendulum.stiffness / pendulum.mass, or "
                 "integrate less far", mi->adaptive ? "raise integrator.tolerance"
                                                    : "raise integrator.dt");
    return sp_cli_work(steps + pre + ens + trail, SP_MAX_STEPS, SP_NOTE_STEPS, what, advice,
                       o->quiet);
}