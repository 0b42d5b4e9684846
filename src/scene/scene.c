/* springpend: scene files. inih splits lines into sections and key = value
 * pairs; this file owns the key table, the defaults, the validation and the
 * FILE:LINE messages. Pure: nothing but stderr is touched. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <poll.h>
#include <stdarg.h>
#include <ini.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/scene.h"
#include "springpend/timeline.h"
#include "base/array.h"
#include "base/decimal.h"
#include "base/places.h"
#include "base/ini_lines.h"
#include "base/utf8.h"

#define SP_MAX_PIXELS (7680L * 4320L)
#define SP_MAX_RATE2 1e24  /* k/m and b/m, 1/s^2 and 1/s: omega up to 1e12 rad/s */
#define SP_MAX_STRETCH 1e9 /* m g / k, m: beyond it nothing is on screen */
#define SP_ENSEMBLE_MAX 10000 /* [ensemble] count */
#define SP_FONT_SIZE_MIN_PT 4.0 /* [view] font_size, pt: below it text is unreadable */

enum key_kind { KEY_REAL, KEY_INT, KEY_DEGREES, KEY_METHOD,
                KEY_BOOL,    /* true/false, stored as int */
                KEY_CHOICE,  /* one of the names in `unit` (", "-separated), int index */
                KEY_PANELS,  /* a list of panel names, unsigned SP_PANEL_* bits */
                KEY_COLOR,   /* #rrggbb, "theme" or "transparent", int */
                KEY_TRAIL,   /* frames, "5s" (SP_TRAIL_DURATION) or "all" (SP_TRAIL_ALL), int */
                KEY_TEXT,    /* UTF-8 text: char[SP_VIEW_TEXT_BYTES], or for title and
                                caption a heap string (long_text_slot) */
                KEY_CAMERA }; /* auto, front or "AZIMUTH ELEVATION [DISTANCE]":
                                 view.camera (int) and its three numbers */

/* One scene key: where it lives in struct sp_scene and what it accepts.
 * Accepted: lo < v (lo_open) or lo <= v, and v <= hi. */
struct key_info {
    const char *section, *name;
    enum key_kind kind;
    size_t offset;
    double def;      /* default, in file units (degrees for angles) */
    double lo, hi;   /* accepted range, file units */
    int lo_open;     /* 1: lo itself is not allowed */
    const char *unit;
};

/* Keys added after PNG provenance hashed the canonical text: left out of
 * sp_scene_canonical at their default, so that scenes without them keep
 * their hash and their PNGs' bytes. */
#define QUIET_KEY(k) ((k)->offset == offsetof(struct sp_scene, view.vectors) || \
                      (k)->offset == offsetof(struct sp_scene, view.camera) || \
                      (k)->offset == offsetof(struct sp_scene, view.panel_background) || \
                      ((k)->offset >= offsetof(struct sp_scene, view.cursor) && \
                       (k)->offset <= offsetof(struct sp_scene, view.colorbar_label)))

/* [video] preset's choices: auto, then scene.h's SP_VIDEO_PRESETS. */
#define PRESET_LISTED(name) ", " name
#define PRESET_NAMES "auto" SP_VIDEO_PRESETS(PRESET_LISTED)

#define F(field) offsetof(struct sp_scene, field)
static const struct key_info keys[] = {
    {"pendulum", "natural_length", KEY_REAL, F(pendulum.natural_length), 0.50, 0, 1e4, 1, "m"},
    {"pendulum", "stiffness", KEY_REAL, F(pendulum.stiffness), 2.00, 0, 1e12, 1, "N/m"},
    {"pendulum", "mass", KEY_REAL, F(pendulum.mass), 0.50, 0, 1e6, 1, "kg"},
    {"pendulum", "gravity", KEY_REAL, F(pendulum.gravity), 9.81, 0, 1e3, 0, "m/s^2"},
    {"pendulum", "damping", KEY_REAL, F(pendulum.damping), 0, 0, 1e9, 0, "N*s/m"},
    {"initial", "length", KEY_REAL, F(initial.length), 0.55, 0, 1e4, 1, "m"},
    {"initial", "angle", KEY_DEGREES, F(initial.angle), 10, -360, 360, 0, "degrees"},
    {"initial", "length_rate", KEY_REAL, F(initial.length_rate), 0, -1e6, 1e6, 0, "m/s"},
    {"initial", "angle_rate", KEY_REAL, F(initial.angle_rate), 0, -1e6, 1e6, 0, "rad/s"},
    {"initial", "azimuth_rate", KEY_REAL, F(initial.azimuth_rate), 0, -1e6, 1e6, 0, "rad/s"},
    {"integrator", "method", KEY_METHOD, F(integrator.method), 0, 0, 0, 0,
     "rk4, verlet, yoshida4, dopri5, dop853, rkn1210"},
    {"integrator", "dt", KEY_REAL, F(integrator.dt), 0.001, 0, 1, 1, "s"},
    {"integrator", "tolerance", KEY_REAL, F(integrator.tolerance), 1e-9, 1e-15, 1e-2, 0, "(relative)"},
    {"pivot", "amplitude", KEY_REAL, F(pivot.amplitude), 0, 0, 1e4, 0, "m"},
    {"pivot", "frequency", KEY_REAL, F(pivot.frequency), 0, 0, 1e6, 0, "Hz"},
    {"video", "width", KEY_INT, F(video.width), 1280, 16, 7680, 0, "px"},
    {"video", "height", KEY_INT, F(video.height), 720, 16, 4320, 0, "px"},
    {"video", "fps", KEY_REAL, F(video.fps), 60, 0, 1000, 1, "frames/s"},
    {"video", "duration", KEY_REAL, F(video.duration), 10, 0, 1e6, 1, "simulated s"},
    {"video", "speed", KEY_REAL, F(video.speed), 1, 0, 1e4, 1, "simulated s per video s"},
    {"video", "crf", KEY_INT, F(video.crf), 0, 0, 63, 0, "(quality, lower is better; 0 = the format's default: 23 H.264, 32 VP9)"},
    {"video", "preset", KEY_CHOICE, F(video.preset), 0, 0, 0, 0, PRESET_NAMES},
    {"video", "png_level", KEY_INT, F(video.png_level), 1, 1, 9, 0, "(PNG compression, 1 fastest, 9 smallest)"},
    {"view", "trail", KEY_TRAIL, F(view.trail), 600, 0, 1e6, 0, "frames"},
    {"view", "panels", KEY_PANELS, F(view.panels), 0, 0, 0, 0,
     "none, all, r, theta, energy, extension, phase, poincare, modes, spread, azimuth, top, "
     "energy_bars"},
    {"view", "vectors", KEY_PANELS, F(view.vectors), 0, 0, 0, 0,
     "none, forces, velocity, acceleration, gravity, spring, damping, drive, net"},
    {"view", "hud", KEY_BOOL, F(view.hud), 0, 0, 0, 0, "true, false"},
    {"view", "theme", KEY_CHOICE, F(view.theme), 0, 0, 0, 0, "dark, light"},
    {"view", "panel_background", KEY_CHOICE, F(view.panel_background), 0, 0, 0, 0, "theme, none"},
    {"view", "background", KEY_COLOR, F(view.background), SP_BACKGROUND_THEME, 0, 0, 0,
     "#rrggbb, theme, transparent"},
    {"view", "colormap", KEY_CHOICE, F(view.colormap), 0, 0, 0, 0,
     "inferno, viridis, magma, cividis, gray"},
    {"view", "colorbar", KEY_BOOL, F(view.colorbar), 0, 0, 0, 0, "true, false"},
    {"view", "strobe", KEY_REAL, F(view.strobe), 0, 0, 1e6, 0, "s"},
    {"view", "pendulum", KEY_BOOL, F(view.pendulum), 1, 0, 0, 0, "true, false"},
    {"view", "fade", KEY_BOOL, F(view.fade), 1, 0, 0, 0, "true, false"},
    {"view", "font_scale", KEY_REAL, F(view.font_scale), 1, 0.25, 4, 0, "(text size factor)"},
    {"view", "font_size", KEY_REAL, F(view.font_size), 0, 0, 200, 0,
     "pt (body text; 0 = from the frame's size, else 4 to 200)"},
    {"view", "font", KEY_TEXT, F(view.font), 0, 0, 0, 0,
     "a font family that fontconfig knows (fc-list : family), or a list \"A, B, serif\" "
     "tried in order; empty = DejaVu Sans"},
    {"view", "title", KEY_TEXT, F(view.title), 0, 0, 0, 0, "text"},
    {"view", "caption", KEY_TEXT, F(view.caption), 0, 0, 0, 0, "text"},
    {"view", "cursor", KEY_CHOICE, F(view.cursor), 0, 0, 0, 0, "auto, true, false"},
    {"view", "legend", KEY_CHOICE, F(view.legend), 0, 0, 0, 0, "auto, none"},
    {"view", "panel_titles", KEY_BOOL, F(view.panel_titles), 1, 0, 0, 0, "true, false"},
    {"view", "panel_labels", KEY_CHOICE, F(view.panel_labels), 0, 0, 0, 0, "none, a, A"},
    {"view", "marker_size", KEY_REAL, F(view.marker_size), 0, 0, 100, 0,
     "pt (a marker's diameter; 0 = each figure's own)"},
    {"view", "palette", KEY_CHOICE, F(view.palette), 0, 0, 0, 0, "theme, okabe_ito"},
    {"view", "xlabel", KEY_TEXT, F(view.xlabel), 0, 0, 0, 0,
     "text (empty = the axis's own name; one per plot, phase being two, '|' between)"},
    {"view", "ylabel", KEY_TEXT, F(view.ylabel), 0, 0, 0, 0,
     "text (empty = the axis's own name; one per plot, phase being two, '|' between)"},
    {"view", "colorbar_label", KEY_TEXT, F(view.colorbar_label), 0, 0, 0, 0,
     "text (empty = the colour bar's own name)"},
    {"view", "camera", KEY_CAMERA, F(view.camera), 0, 0, 0, 0,
     "auto, front, AZIMUTH ELEVATION [DISTANCE] (degrees, degrees, m)"},
    {"ensemble", "count", KEY_INT, F(ensemble.count), 0, 0, SP_ENSEMBLE_MAX, 0,
     "pendulums (0 or 1 = no ensemble)"},
    {"ensemble", "key", KEY_TEXT, F(ensemble.key), 0, 0, 0, 0,
     "a numeric key of [pendulum], [initial] or [pivot]"},
    {"ensemble", "spread", KEY_REAL, F(ensemble.spread), 1e-6, 0, 1e12, 1, "(the key's units, total range)"},
    {"ensemble", "trails", KEY_BOOL, F(ensemble.trails), 0, 0, 0, 0, "true, false"},
};
#undef F
#define N_KEYS ((int)(sizeof(keys) / sizeof(keys[0])))
_Static_assert(N_KEYS <= SP_SCENE_MAX_KEYS, "struct sp_scene's key_lines holds every key");

/* The text keys with no byte limit, view.title and view.caption: the index
 * of struct sp_scene's texts that holds k's text, or -1 for the others
 * (char arrays of SP_VIEW_TEXT_BYTES). */
static int long_text_slot(const struct key_info *k)
{
    return k->offset == offsetof(struct sp_scene, view.title)     ? 0
           : k->offset == offsetof(struct sp_scene, view.caption) ? 1 : -1;
}

/* A text key's value in s. */
static const char *text_of(const struct sp_scene *s, const struct key_info *k)
{
    const char *p = (const char *)s + k->offset;
    return long_text_slot(k) >= 0 ? *(const char *const *)p : p;
}

static const char *const method_names[] = {"rk4",    "verlet", "yoshida4",
                                           "dopri5", "dop853", "rkn1210"};
#define N_METHODS ((int)(sizeof(method_names) / sizeof(method_names[0])))

/* Encoder speed presets (x264's names; VP9 maps them to cpu-used); auto is
 * the format's default (superfast for H.264). */
#define PRESET_ITEM(name) name,
static const char *const preset_names[] = {"auto", SP_VIDEO_PRESETS(PRESET_ITEM)};
#define N_PRESETS ((int)(sizeof(preset_names) / sizeof(preset_names[0])))

const char *sp_scene_preset_name(const struct sp_scene *s)
{
    return s->video.preset > 0 && s->video.preset < N_PRESETS
               ? preset_names[s->video.preset] : NULL;
}

/* A text line (view.title, view.caption, view.font, a [timeline] cue) is
 * read by read_line, not by inih, so that nothing of the text is cut
 * silently: inih would end the value at ' #' or ' ;' (an inline comment)
 * and its line buffer is short. Text in double quotes is taken whole,
 * quotes removed, and may be followed by a comment; text without quotes
 * that holds ' #' or ' ;' is refused (was it a comment or text?). The line
 * is read from the scene's text in memory, whatever its length: title and
 * caption have no byte limit (the frame is theirs: the composer refuses
 * text that cannot fit), view.font holds SP_VIEW_TEXT_BYTES - 1, the same
 * for a scene line as for --set. Other lines longer than
 * TEXT_LINE_BYTES are refused. */
#define TEXT_LINE_BYTES (SP_VIEW_TEXT_BYTES + 256)
#define TEXT_MARK "\x02" /* the value inih sees for a text key: take text_value */

/* Parser state shared by the inih reader and handler. */
struct parse_ctx {
    struct sp_scene *scene;
    const char *origin;   /* file name for messages */
    const char *cursor;   /* next unread byte of the text */
    int line;             /* number of the line inih is looking at */
    int line_has_content; /* the line is neither blank, a comment nor a section */
    int line_handled;     /* inih called the handler for it */
    int key_line[N_KEYS]; /* where each key was set, 0 = not set */
    const char *key_set[N_KEYS]; /* the --set argument that gave a key its value, or NULL */
    int errors;
    char *text_value;     /* a text key's or cue's whole value (read_line), heap */
    size_t text_room;     /* bytes text_value holds */
    int in_timeline;      /* read_line is in the [timeline] section */
};

static void report(struct parse_ctx *c, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#define MAX_REPORTS 20 /* messages printed before the rest are only counted */

static void vreport(struct parse_ctx *c, int line, const char *fmt, va_list ap)
{
    if (++c->errors > MAX_REPORTS || sp_log_muted()) { /* muted: counted, not said */
        if (c->errors == MAX_REPORTS + 1 && !sp_log_muted())
            sp_fputs_line(c->origin, stderr), fputs(": too many errors; not showing more\n", stderr);
        return;
    }
    /* the origin may be a --set argument: its control bytes and newlines are
     * shown, not sent */
    char *msg = NULL;
    int n = vasprintf(&msg, fmt, ap);
    if (line > 0)
        sp_fputs_line(c->origin, stderr), fprintf(stderr, ":%d: ", line);
    else
        sp_fputs_line(c->origin, stderr), fputs(": ", stderr);
    sp_fputs_line(n >= 0 ? msg : fmt, stderr);
    fputc('\n', stderr);
    free(msg);
}

static void report(struct parse_ctx *c, int line, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vreport(c, line, fmt, ap);
    va_end(ap);
}

static const struct key_info *find_key(const char *section, const char *name);

/* A check of several keys refuses what section.name holds: the message
 * names where its value came from, "--set section.name=VALUE" or the scene
 * file's FILE:LINE (FILE alone when the key holds its default). */
static void report_key(struct parse_ctx *c, const char *section, const char *name,
                       const char *fmt, ...) __attribute__((format(printf, 4, 5)));

static void report_key(struct parse_ctx *c, const char *section, const char *name,
                       const char *fmt, ...)
{
    const int idx = (int)(find_key(section, name) - keys);
    const char *saved = c->origin;
    char origin[320];
    va_list ap;
    if (c->key_set[idx]) {
        snprintf(origin, sizeof(origin), "--set %s", c->key_set[idx]);
        c->origin = origin;
    }
    va_start(ap, fmt);
    vreport(c, c->key_set[idx] ? 0 : c->key_line[idx], fmt, ap);
    va_end(ap);
    c->origin = saved;
}

static const struct key_info *numeric_key(const char *key);
static void check_ensemble(struct parse_ctx *c);
static void check_view_3d(struct parse_ctx *c);

static const struct key_info *find_key(const char *section, const char *name)
{
    for (int i = 0; i < N_KEYS; i++)
        if (!strcmp(keys[i].section, section) && !strcmp(keys[i].name, name))
            return &keys[i];
    return NULL;
}

static int section_known(const char *section)
{
    if (!strcmp(section, "timeline")) /* cues, not keys: timeline.c */
        return 1;
    for (int i = 0; i < N_KEYS; i++)
        if (!strcmp(keys[i].section, section))
            return 1;
    return 0;
}

/* Levenshtein distance, capped: small helper for "did you mean". */
static int edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > 63 || lb > 63)
        return 99;
    int row[64];
    for (size_t j = 0; j <= lb; j++)
        row[j] = (int)j;
    for (size_t i = 1; i <= la; i++) {
        int diag = row[0];
        row[0] = (int)i;
        for (size_t j = 1; j <= lb; j++) {
            int up = row[j];
            int cost = a[i - 1] != b[j - 1];
            int best = diag + cost;
            if (row[j] + 1 < best)
                best = row[j] + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

/* Writes the keys of `section` as "a, b, c" into buf. */
static void list_keys(const char *section, char *buf, size_t size)
{
    buf[0] = 0;
    for (int i = 0; i < N_KEYS; i++) {
        if (strcmp(keys[i].section, section))
            continue;
        size_t used = strlen(buf);
        snprintf(buf + used, size - used, "%s%s", used ? ", " : "", keys[i].name);
    }
}

static void report_unknown(struct parse_ctx *c, int line, const char *section,
                           const char *name)
{
    char list[256];
    const char *best = NULL;
    int best_d = 3;
    if (!section_known(section)) {
        for (int i = 0; i < N_KEYS; i++) {
            int d = edit_distance(section, keys[i].section);
            if (d < best_d)
                best_d = d, best = keys[i].section;
        }
        if (best)
            report(c, line, "unknown section [%s]; did you mean [%s]? "
                   "(sections: pendulum, initial, integrator, pivot, video, view, ensemble, "
                   "timeline)", section, best);
        else
            report(c, line, "unknown section [%s] (sections: pendulum, initial, "
                   "integrator, pivot, video, view, ensemble, timeline)", section);
        return;
    }
    for (int i = 0; i < N_KEYS; i++) {
        if (strcmp(keys[i].section, section))
            continue;
        int d = edit_distance(name, keys[i].name);
        if (d < best_d)
            best_d = d, best = keys[i].name;
    }
    list_keys(section, list, sizeof(list));
    if (best)
        report(c, line, "unknown key '%s' in [%s]; did you mean '%s'? (keys: %s)",
               name, section, best, list);
    else
        report(c, line, "unknown key '%s' in [%s] (keys: %s)", name, section, list);
}

static void describe_range(const struct key_info *k, char *buf, size_t size)
{
    if (k->kind == KEY_TRAIL)
        snprintf(buf, size, "frames as an integer from %.0f to %.0f, a duration D such as 5s "
                 "(0 < D <= %g simulated s, a decimal number then s), or all", k->lo, k->hi,
                 k->hi);
    else if (k->kind == KEY_INT)
        snprintf(buf, size, "an integer from %.0f to %.0f %s", k->lo, k->hi, k->unit);
    else
        snprintf(buf, size, "a number with %g %s %s <= %g %s", k->lo,
                 k->lo_open ? "<" : "<=", k->name, k->hi, k->unit);
}

#define COLOUR_MARK '\x01' /* stands for the '#' of a colour value, see protect_colour */

/* Index of `word` in the ", "-separated list, or -1. */
static int choice_index(const char *list, const char *word, size_t len)
{
    for (int i = 0; *list; i++) {
        size_t n = strcspn(list, ",");
        if (n == len && !strncmp(list, word, len))
            return i;
        list += n;
        list += strspn(list, ", ");
    }
    return -1;
}

/* Records where [view] xlabel, ylabel or colorbar_label got its value
 * (view.label_where, as view.camera_where); other keys: nothing. */
static void label_set_where(struct parse_ctx *c, int line, const struct key_info *k)
{
    static const size_t at[3] = {offsetof(struct sp_scene, view.xlabel),
                                 offsetof(struct sp_scene, view.ylabel),
                                 offsetof(struct sp_scene, view.colorbar_label)};
    for (int i = 0; i < 3; i++) {
        if (k->offset != at[i])
            continue;
        char *w = c->scene->view.label_where[i];
        if (line > 0)
            snprintf(w, SP_VIEW_TEXT_BYTES, "%s:%d", c->origin, line);
        else
            snprintf(w, SP_VIEW_TEXT_BYTES, "--set %s.%s", k->section, k->name);
    }
}

/* [view] camera: auto, front, or azimuth and elevation (degrees) and
 * optionally the distance (m), separated by blanks (a comma is refused: it
 * reads as a list, and an empty entry between two would be lost). Returns 1. */
static int set_camera(struct parse_ctx *c, int line, const struct key_info *k,
                      const char *value)
{
    static const char *const what[] = {"azimuth", "elevation", "distance"};
    struct sp_view *v = &c->scene->view;
    double num[3] = {0, 0, 0};
    int n = 0;
    if (!strcmp(value, "auto") || !strcmp(value, "front")) {
        v->camera = value[0] == 'a' ? SP_CAMERA_AUTO : SP_CAMERA_FRONT;
        return 1;
    }
    if (strchr(value, ',')) {
        report(c, line, "%s.%s = '%s': numbers are separated by blanks, not commas; allowed: "
               "%s, e.g. camera = 35 25 or camera = 35 25 3", k->section, k->name, value,
               k->unit);
        return 1;
    }
    for (const char *w = value + strspn(value, " \t"); *w; w += strspn(w, " \t")) {
        const size_t len = strcspn(w, " \t");
        char word[64];
        if (n == 3 || len >= sizeof(word)) {
            n = 4;
            break;
        }
        snprintf(word, sizeof(word), "%.*s", (int)len, w);
        if (sp_decimal_read(word, &num[n]) != SP_DECIMAL_OK) {
            report(c, line, "%s.%s: the %s '%s' is not a finite decimal number; allowed: %s",
                   k->section, k->name, what[n], word, k->unit);
            return 1;
        }
        n++;
        w += len;
    }
    if (n < 2 || n > 3) {
        report(c, line, "%s.%s = '%s' is not allowed; allowed: %s", k->section, k->name, value,
               k->unit);
        return 1;
    }
    if (!(fabs(num[0]) <= 360) || !(fabs(num[1]) < 90) || (n == 3 && !(num[2] > 0 && num[2] <= 1e4))) {
        report(c, line, "%s.%s = '%s' is out of range; allowed: azimuth -360 ... 360 degrees, "
               "elevation strictly between -90 and 90 degrees, distance 0 < D <= 1e4 m (or "
               "left out: fitted to the motion)", k->section, k->name, value);
        return 1;
    }
    v->camera = SP_CAMERA_SET;
    if (line > 0)
        snprintf(v->camera_where, sizeof(v->camera_where), "%s:%d", c->origin, line);
    else
        snprintf(v->camera_where, sizeof(v->camera_where), "--set %s.%s", k->section, k->name);
    v->camera_azimuth = num[0] * (M_PI / 180.0);
    v->camera_elevation = num[1] * (M_PI / 180.0);
    v->camera_distance = n == 3 ? num[2] : 0;
    return 1;
}

/* A list of panels or vectors (k: view.panels or view.vectors) into the
 * bits at p, and the panels' order as named. Returns 1 (stored or
 * reported). */
static int set_list(struct parse_ctx *c, int line, const struct key_info *k,
                    const char *value, char *p)
{
    static const unsigned panel_bits[] = {
        0, SP_PANEL_ALL, SP_PANEL_R, SP_PANEL_THETA, SP_PANEL_ENERGY,
        SP_PANEL_EXTENSION, SP_PANEL_PHASE_R | SP_PANEL_PHASE_THETA, SP_PANEL_POINCARE,
        SP_PANEL_MODES, SP_PANEL_SPREAD, SP_PANEL_AZIMUTH, SP_PANEL_TOP,
        SP_PANEL_ENERGY_BARS};
    static const unsigned vector_bits[] = {
        0, SP_VECTOR_FORCES, SP_VECTOR_VELOCITY, SP_VECTOR_ACCELERATION, SP_VECTOR_GRAVITY,
        SP_VECTOR_SPRING, SP_VECTOR_DAMPING, SP_VECTOR_DRIVE, SP_VECTOR_NET};
    const int vectors = k->offset == offsetof(struct sp_scene, view.vectors);
    unsigned bits = 0;
    signed char order[SP_PANEL_COUNT];
    int i, n_order = 0;
    for (const char *w = value; *w;) {
        size_t n = strcspn(w, ", ");
        i = choice_index(k->unit, w, n);
        if (i < 0 || (i == 0 && (w != value || w[n]))) {
            if (vectors)
                report(c, line, "%s.%s: '%.*s' is not a vector; give a comma-separated "
                       "list of: velocity, acceleration, gravity, spring, damping, drive, "
                       "net, forces (every force: gravity, spring, damping, drive, net), "
                       "or none alone", k->section, k->name, (int)n, w);
            else
                report(c, line, "%s.%s: '%.*s' is not a panel; give a comma-separated "
                       "list of: r, theta, energy, extension, phase, poincare, modes, spread, "
                       "azimuth, top, energy_bars (or all, or none alone)", k->section, k->name, (int)n, w);
            return 1;
        }
        const unsigned add = vectors ? vector_bits[i] : panel_bits[i];
        for (int b = 0; !vectors && b < SP_PANEL_COUNT; b++) /* the order named */
            if ((add >> b & 1) && !(bits >> b & 1))
                order[n_order++] = (signed char)b;
        bits |= add;
        w += n;
        const size_t sep = strspn(w, ", ");
        const char *comma = memchr(w, ',', sep);
        if (comma && (memchr(comma + 1, ',', sep - (size_t)(comma + 1 - w)) || !w[sep])) {
            report(c, line, "%s.%s = '%s' has an empty entry; give a comma-separated "
                   "list of %s names, one between each two commas", k->section,
                   k->name, value, vectors ? "vector" : "panel");
            return 1;
        }
        w += sep;
    }
    *(unsigned *)p = bits;
    if (!vectors) {
        memset(c->scene->view.panel_order, -1, sizeof(c->scene->view.panel_order));
        memcpy(c->scene->view.panel_order, order, (size_t)n_order);
    }
    return 1;
}

/* view.trail: all, a duration ("5s") or frames; one message lists all
 * three. Returns 1 (stored or reported). */
static int set_trail(struct parse_ctx *c, int line, const struct key_info *k,
                     const char *value, char *p)
{
    const size_t n = strlen(value);
    const int secs = n > 0 && value[n - 1] == 's';
    char num[64], range[192];
    const char *wrong = NULL;
    double d = 0;
    if (!strcmp(value, "all")) {
        *(int *)p = SP_TRAIL_ALL;
        return 1;
    }
    snprintf(num, sizeof(num), "%.*s", (int)(n - (size_t)secs), value);
    const enum sp_decimal_read read =
        n - (size_t)secs < sizeof(num) ? sp_decimal_read(num, &d) : SP_DECIMAL_NOT_DECIMAL;
    if (read == SP_DECIMAL_NOT_DECIMAL)
        wrong = "is not a number of frames, a duration or all";
    else if (read == SP_DECIMAL_NOT_FINITE)
        wrong = "is not finite";
    else if (!secs && d != floor(d))
        wrong = "is not an integer";
    else if (secs ? !(d > 0 && d <= k->hi) : !(d >= k->lo && d <= k->hi))
        wrong = "is out of range";
    if (wrong) {
        describe_range(k, range, sizeof(range));
        report(c, line, read == SP_DECIMAL_NOT_DECIMAL ? "%s.%s = '%s' %s; allowed: %s"
               : "%s.%s = %s %s; allowed: %s", k->section, k->name, value, wrong, range);
    } else if (secs) {
        *(int *)p = SP_TRAIL_DURATION;
        c->scene->view.trail_duration = d;
    } else {
        *(int *)p = (int)d;
    }
    return 1;
}

/* A text key: optional quotes taken off, UTF-8 without control
 * characters; a title or caption on the scene's heap with where it was
 * set, the rest in place (the font with where, for fontconfig's
 * refusal). Returns 1 (stored or reported). */
static int set_text(struct parse_ctx *c, int line, const struct key_info *k,
                    const char *value, char *p)
{
    size_t n = strlen(value);
    if (n >= 2 && value[0] == '"' && value[n - 1] == '"') /* optional quotes */
        value++, n -= 2;
    const int slot = long_text_slot(k);
    if (slot < 0 && n >= SP_VIEW_TEXT_BYTES) {
        report(c, line, "%s.%s is %zu bytes long; at most %d are allowed", k->section,
               k->name, n, SP_VIEW_TEXT_BYTES - 1);
        return 1;
    }
    const size_t i = sp_utf8_not_text(value, n); /* --set bypasses the file's text check */
    if (i < n) {
        const unsigned char *u = (const unsigned char *)value + i;
        const int c1 = i + 1 < n && u[0] == 0xc2 && u[1] >= 0x80 && u[1] < 0xa0; /* U+0080..9F */
        report(c, line, "%s.%s: %s 0x%02x at byte %zu is not text; allowed: "
               "UTF-8 text without control characters (C0, DEL or C1)", k->section,
               k->name, c1 ? "the C1 control, bytes 0xc2" : "byte", c1 ? u[1] : *u, i + 1);
        return 1;
    }
    if (slot >= 0) { /* the scene's own heap copy, after where it was set; the
                        one it replaces is freed */
        char *where = NULL, *copy = NULL;
        const int wn = line > 0 ? asprintf(&where, "%s:%d", c->origin, line)
                                : asprintf(&where, "--set %s.%s", k->section, k->name);
        if (n && wn >= 0 && (copy = malloc((size_t)wn + 1 + n + 1))) {
            memcpy(copy, where, (size_t)wn + 1);
            memcpy(copy + wn + 1, value, n);
            copy[wn + 1 + n] = 0;
        }
        free(wn >= 0 ? where : NULL);
        if (n && !copy) {
            report(c, line, "%s.%s: out of memory for %zu bytes of text", k->section,
                   k->name, n);
            return 1;
        }
        free(c->scene->texts[slot]);
        c->scene->texts[slot] = copy;
        const char **text = (const char **)p, **at = slot ? &c->scene->view.caption_where
                                                           : &c->scene->view.title_where;
        *text = copy ? copy + wn + 1 : "";
        *at = copy ? copy : "";
        return 1;
    }
    memcpy(p, value, n);
    p[n] = 0;
    if (p == c->scene->view.font) { /* for fontconfig's refusal, after parsing */
        struct sp_view *v = &c->scene->view;
        if (line > 0)
            snprintf(v->font_where, sizeof(v->font_where), "%s:%d", c->origin, line);
        else
            snprintf(v->font_where, sizeof(v->font_where), "--set %s.%s", k->section,
                     k->name);
    }
    label_set_where(c, line, k);
    return 1;
}

/* The word-valued kinds and the trail. Returns 1 when it consumed the value
 * (stored or reported), 0 for kinds it does not read. */
static int set_word(struct parse_ctx *c, int line, const struct key_info *k,
                    const char *value, char *p)
{
    int i;
    switch (k->kind) {
    case KEY_BOOL:
        i = choice_index("false, true, no, yes, off, on, 0, 1", value, strlen(value));
        if (i < 0)
            break;
        *(int *)p = i & 1;
        return 1;
    case KEY_CHOICE:
        i = choice_index(k->unit, value, strlen(value));
        if (i < 0)
            break;
        *(int *)p = i;
        return 1;
    case KEY_PANELS:
        return set_list(c, line, k, value, p);
    case KEY_COLOR:
        if (!strcmp(value, "theme") || !strcmp(value, "transparent")) {
            *(int *)p = value[1] == 'h' ? SP_BACKGROUND_THEME : SP_BACKGROUND_TRANSPARENT;
            return 1;
        }
        if ((value[0] == '#' || value[0] == COLOUR_MARK) && strlen(value) == 7 && strspn(value + 1, "0123456789abcdefABCDEF") == 6) {
            *(int *)p = (int)strtol(value + 1, NULL, 16);
            return 1;
        }
        break;
    case KEY_TRAIL:
        return set_trail(c, line, k, value, p);
    case KEY_TEXT:
        return set_text(c, line, k, value, p);
    case KEY_CAMERA:
        return set_camera(c, line, k, value);
    default:
        return 0;
    }
    report(c, line, "%s.%s = '%s%s' is not allowed; allowed: %s", k->section, k->name,
           value[0] == COLOUR_MARK ? "#" : "", value + (value[0] == COLOUR_MARK), k->unit);
    return 1;
}

/* Parses and stores one value. `where` prefixes messages ("FILE:LINE" is
 * produced by report(); overrides pass line 0 and their own origin). */
static void set_value(struct parse_ctx *c, int line, const struct key_info *k,
                      const char *value)
{
    char range[192];
    char *p = (char *)c->scene + k->offset;
    describe_range(k, range, sizeof(range));
    if (k->kind == KEY_METHOD) {
        for (int i = 0; i < N_METHODS; i++)
            if (!strcmp(value, method_names[i])) {
                *(enum sp_method *)p = (enum sp_method)i;
                return;
            }
        report(c, line, "%s.%s = '%s' is not a method; allowed: %s", k->section,
               k->name, value, k->unit);
        return;
    }
    if (k->kind >= KEY_BOOL && set_word(c, line, k, value, p))
        return;
    double v = 0;
    const enum sp_decimal_read read = sp_decimal_read(value, &v);
    if (read == SP_DECIMAL_NOT_DECIMAL) {
        report(c, line, "%s.%s = '%s' is not a decimal number; expected %s, "
               SP_DECIMAL_ALLOWED, k->section, k->name, value, range);
        return;
    }
    if (read == SP_DECIMAL_NOT_FINITE) {
        report(c, line, "%s.%s = %s is not finite; expected %s", k->section,
               k->name, value, range);
        return;
    }
    if (k->kind == KEY_INT && v != floor(v)) {
        report(c, line, "%s.%s = %s is not an integer; expected %s", k->section,
               k->name, value, range);
        return;
    }
    if (v < k->lo || (k->lo_open && v == k->lo) || v > k->hi) {
        report(c, line, "%s.%s = %s is out of range; expected %s", k->section,
               k->name, value, range);
        return;
    }
    if (p == (char *)&c->scene->view.font_size && v > 0 && v < SP_FONT_SIZE_MIN_PT) {
        /* drawn at the renderer's 4 px floor, unreadable, and not said */
        report(c, line, "%s.%s = %s pt is too small to read; expected 0 (from the frame's "
               "size) or %g <= font_size <= %g pt", k->section, k->name, value,
               SP_FONT_SIZE_MIN_PT, k->hi);
        return;
    }
    if (p == (char *)&c->scene->view.font_size || p == (char *)&c->scene->view.font_scale) {
        struct sp_view *view = &c->scene->view;
        if (line > 0)
            snprintf(view->text_size_where, sizeof(view->text_size_where), "%s:%d", c->origin, line);
        else
            snprintf(view->text_size_where, sizeof(view->text_size_where), "--set %s.%s",
                     k->section, k->name);
    }
    if (k->kind == KEY_INT)
        *(int *)p = (int)v;
    else if (k->kind == KEY_DEGREES)
        *(double *)p = v * (M_PI / 180.0);
    else
        *(double *)p = v;
}

static int handle_pair(void *user, const char *section, const char *name,
                       const char *value)
{
    struct parse_ctx *c = user;
    c->line_handled = 1;
    if (!strcmp(section, "timeline")) {
        if (!strcmp(value, TEXT_MARK))
            value = c->text_value; /* read whole by read_line */
        const int n = sp_timeline_read(&c->scene->timeline, c->origin, c->line, name, value);
        if (n < 0)
            report(c, c->line, "out of memory for the timeline");
        c->errors += n < 0 ? 1 : n;
        return 1;
    }
    const struct key_info *k = find_key(section, name);
    if (!k) {
        if (section[0] && !section_known(section))
            return 1; /* reported once, at its [header] */
        if (!section[0])
            report(c, c->line, "'%s' comes before any [section]; put it under "
                   "[pendulum], [initial], [integrator], [pivot], [video], [view] or [ensemble]", name);
        else
            report_unknown(c, c->line, section, name);
        return 1;
    }
    int idx = (int)(k - keys);
    if (c->key_line[idx]) {
        report(c, c->line, "%s.%s is set twice (first on line %d); keep one",
               section, name, c->key_line[idx]);
        return 1;
    }
    c->key_line[idx] = c->line;
    if (k->kind == KEY_TEXT && !strcmp(value, TEXT_MARK))
        value = c->text_value; /* read whole by read_line */
    set_value(c, c->line, k, value);
    return 1;
}

/* A line inih read but did not hand to us was malformed. */
static void check_previous_line(struct parse_ctx *c)
{
    if (c->line > 0 && c->line_has_content && !c->line_handled)
        report(c, c->line, "expected 'key = value', '[section]' or a '#' comment");
}

/* Classifies a line: returns 1 when inih should hand it to the handler. */
static int line_has_content(struct parse_ctx *c, const char *s)
{
    while (*s == ' ' || *s == '\t' || *s == '\r' || *s == '\n')
        s++;
    if (!*s || *s == '#' || *s == ';')
        return 0;
    if (*s == '[') {
        const char *close = strchr(s, ']');
        if (!close) {
            report(c, c->line, "section header without ']'");
            return 0;
        }
        char name[256]; /* whole: the line holds at most 198 bytes (inih cuts at 49) */
        size_t n = (size_t)(close - s - 1);
        if (n >= sizeof(name))
            n = sizeof(name) - 1;
        memcpy(name, s + 1, n);
        name[n] = 0;
        if (!section_known(name))
            report_unknown(c, c->line, name, "");
        return 0;
    }
    return 1;
}

/* A value "#rrggbb" would read as an inline comment to inih: a '#' that
 * starts a value and is followed by a letter or digit becomes COLOUR_MARK,
 * which set_word reads back as '#'. */
static void protect_colour(char *line)
{
    char *eq = strchr(line, '='), *v;
    if (!eq)
        return;
    v = eq + 1 + strspn(eq + 1, " \t");
    if (v[0] == '#' && isalnum((unsigned char)v[1]))
        v[0] = COLOUR_MARK;
}

/* The [view] text key that `line` sets ("  title = ..."), or NULL. Its
 * value starts at *value. Any section: handle_pair says when the key is not
 * in its section. */
static const struct key_info *text_key_line(const char *line, const char **value)
{
    line += strspn(line, " \t");
    for (int i = 0; i < N_KEYS; i++) {
        const size_t n = strlen(keys[i].name);
        if (keys[i].kind != KEY_TEXT || strcmp(keys[i].section, "view") ||
            strncmp(line, keys[i].name, n))
            continue;
        const char *q = line + n + strspn(line + n, " \t");
        if (*q != '=' && *q != ':')
            continue;
        *value = q + 1 + strspn(q + 1, " \t");
        return &keys[i];
    }
    return NULL;
}

/* Keeps the n bytes at value in c->text_value, NUL-terminated, growing it.
 * Returns 0, or -1 when it reported that memory ran out. */
static int keep_text(struct parse_ctx *c, const char *value, size_t n)
{
    if (SP_ARRAY_RESERVE(c->text_value, c->text_room, n + 1, 0)) {
        report(c, c->line, "out of memory for a text of %zu bytes", n);
        return -1;
    }
    memcpy(c->text_value, value, n);
    c->text_value[n] = 0;
    return 0;
}

/* Keeps the text of a text line whose value starts at `value` (and runs to
 * the line's end) in c->text_value. Returns 0, or -1 when it reported the
 * value. */
static int text_value(struct parse_ctx *c, const struct key_info *k, const char *value)
{
    size_t n, at;
    switch (sp_ini_text(value, &n, &at)) {
    case SP_INI_TEXT_AFTER_QUOTE:
        report(c, c->line, "%s.%s: only a '#' or ';' comment may follow the closing "
               "quote, not '%.*s'", k->section, k->name, (int)(n - at), value + at);
        return -1;
    case SP_INI_TEXT_COMMENT: {
        char *quoted = sp_ini_text_quoted(value, n);
        report(c, c->line, "%s.%s: %s%c' would start a comment here; to show it, "
               "write the text in double quotes (%s = %s)%s; a comment may follow the "
               "closing quote", k->section, k->name,
               value[at - 1] == '\t' ? "a tab then '" : "' ", value[at], k->name,
               quoted ? quoted : "\"TEXT\"", memchr(value, '\t', n) ? ", a tab written as a space" : "");
        free(quoted);
        return -1;
    }
    default:
        break;
    }
    return keep_text(c, value, n);
}

/* inih's fgets-like reader over the in-memory text. It counts lines, and
 * turns lines inih must not see (too long, NUL bytes) into comments after
 * reporting them. A text key's value it keeps whole in c->text_value and
 * hands inih "name = TEXT_MARK" in its place: such a line is read from the
 * text itself, so it may be of any length. */
static char *read_line(char *str, int num, void *stream)
{
    struct parse_ctx *c = stream;
    struct sp_ini_lines l = {c->cursor, c->line};
    const char *start = c->cursor, *value;
    const struct key_info *text;
    char raw[TEXT_LINE_BYTES];
    size_t len;
    check_previous_line(c);
    if (!sp_ini_lines_next(&l, raw, (int)sizeof(raw), &len))
        return NULL;
    c->cursor = l.cursor, c->line = l.line;
    c->line_handled = 0;
    /* the whole line: raw, or the text itself when raw could not hold it
     * (what follows is read only up to the line's CR or LF) */
    const char *whole = len ? start : raw;
    const char *q = whole + strspn(whole, " \t");
    if (!len && *q == '[') /* which section: inih does not say while reading */
        c->in_timeline = !strncmp(q, "[timeline]", 10);
    if (c->in_timeline && *q && *q != '#' && *q != ';' && q[strcspn(q, "=:\r\n")] &&
        strchr("=:", q[strcspn(q, "=:\r\n")])) {
        /* a cue: its value whole, comments and quotes are timeline.c's to read
         * by the text rule (sp_ini_text) */
        const size_t k = strcspn(q, "=:");
        c->line_has_content = 1;
        if (q[k] == ':') { /* inih's other separator: "0:30 = caption: x" read as 0 */
            report(c, c->line, "[timeline] the line starts '%.*s:', but a cue is TIME = VERB, "
                   "with TIME a decimal number of simulated seconds (30, not 0:30); allowed: "
                   "e.g. '30 = caption: half a minute'", (int)(k < 20 ? k : 20), q);
            c->line_handled = 1;
            snprintf(str, (size_t)num, "#\n");
            return str;
        }
        if (k > 64) { /* a time that long was cut at 64 bytes: another time */
            report(c, c->line, "[timeline] time '%.20s...' is %zu bytes long; at most 64 "
                   "are allowed", q, k);
            c->line_handled = 1;
            snprintf(str, (size_t)num, "#\n");
            return str;
        }
        value = q + k + 1 + strspn(q + k + 1, " \t");
        if (keep_text(c, value, strcspn(value, "\r\n")))
            c->line_handled = 1, snprintf(str, (size_t)num, "#\n"); /* reported */
        else
            snprintf(str, (size_t)num, "%.*s= " TEXT_MARK "\n", (int)k, q);
        return str;
    }
    if ((text = text_key_line(whole, &value))) {
        c->line_has_content = 1;
        if (!text_value(c, text, value))
            snprintf(str, (size_t)num, "%s = " TEXT_MARK "\n", text->name);
        else
            c->line_handled = 1, snprintf(str, (size_t)num, "#\n"); /* reported */
        return str;
    }
    if (!len && strlen(raw) + 1 > (size_t)num)
        len = strlen(raw);
    if (len) {
        if (*q != '#' && *q != ';') /* long comments are fine */
            report(c, c->line, "line is %zu bytes long; at most %d are allowed "
                   "for a key = value line", len, num - 2);
        c->line_has_content = 0;
        snprintf(str, (size_t)num, "#\n");
        return str;
    }
    memcpy(str, raw, strlen(raw) + 1);
    protect_colour(str);
    c->line_has_content = line_has_content(c, str);
    return str;
}

void sp_scene_defaults(struct sp_scene *s)
{
    memset(s, 0, sizeof(*s));
    snprintf(s->name, sizeof(s->name), "scene");
    for (int i = 0; i < N_KEYS; i++) {
        char *p = (char *)s + keys[i].offset;
        switch (keys[i].kind) {
        case KEY_REAL: *(double *)p = keys[i].def; break;
        case KEY_DEGREES: *(double *)p = keys[i].def * (M_PI / 180.0); break;
        case KEY_INT: *(int *)p = (int)keys[i].def; break;
        case KEY_METHOD: *(enum sp_method *)p = (enum sp_method)(int)keys[i].def; break;
        case KEY_PANELS: *(unsigned *)p = (unsigned)keys[i].def; break;
        case KEY_TEXT:
            if (long_text_slot(&keys[i]) >= 0)
                *(const char **)p = ""; /* texts[] are NULL; _where below */
            else
                *p = 0;
            break;
        default: *(int *)p = (int)keys[i].def; break; /* bool, choice, colour, trail */
        }
    }
    snprintf(s->ensemble.key, sizeof(s->ensemble.key), "initial.angle");
    s->view.title_where = s->view.caption_where = "";
    memset(s->view.panel_order, -1, sizeof(s->view.panel_order));
}

int sp_scene_panel_order(const struct sp_view *view, int order[SP_PANEL_COUNT])
{
    unsigned left = view->panels & ((1u << SP_PANEL_COUNT) - 1);
    int n = 0;
    for (int i = 0; i < SP_PANEL_COUNT && view->panel_order[i] >= 0; i++) {
        const int b = view->panel_order[i];
        if (b < SP_PANEL_COUNT && (left >> b & 1))
            order[n++] = b, left &= ~(1u << b);
    }
    for (int b = 0; b < SP_PANEL_COUNT; b++)
        if (left >> b & 1)
            order[n++] = b;
    return n;
}

void sp_scene_key_where(const struct sp_scene *s, const char *key, const char *path, char *buf,
                        size_t size)
{
    const char *dot = strchr(key, '.');
    char section[64];
    snprintf(section, sizeof(section), "%.*s", dot ? (int)(dot - key) : 0, key);
    const struct key_info *k = dot ? find_key(section, dot + 1) : NULL;
    const int line = k ? s->key_lines[k - keys] : 0;
    if (line < 0)
        snprintf(buf, size, "--set %s", key);
    else if (line > 0)
        snprintf(buf, size, "%s:%d", path, line);
    else
        snprintf(buf, size, "%s", path);
}

const char *sp_scene_plot_name(int bit)
{
    static const char *const names[SP_PANEL_COUNT] = {
        "r", "theta", "energy", "extension", "phase r", "phase theta", "poincare", "modes",
        "spread", "azimuth", "top", "energy_bars"};
    return bit >= 0 && bit < SP_PANEL_COUNT ? names[bit] : "?";
}

void sp_scene_label_part(const char *label, int i, char *buf, size_t size)
{
    const char *at = label;
    if (strchr(label, '|'))
        for (int k = 0; k < i && at; k++)
            at = strchr(at, '|') ? strchr(at, '|') + 1 : NULL;
    buf[0] = 0;
    if (!at)
        return;
    size_t n = strcspn(at, "|");
    while (n && at[0] == ' ')
        at++, n--;
    while (n && at[n - 1] == ' ')
        n--;
    if (n > size - 1) /* as snprintf's "%.*s" cuts it, without parsing a format every frame */
        n = size - 1;
    memcpy(buf, at, n);
    buf[n] = 0;
}

static void apply_override(struct parse_ctx *c, const char *arg)
{
    char section[64], name[64];
    const char *dot = strchr(arg, '.'), *eq = strchr(arg, '=');
    if (!dot || !eq || dot > eq || (size_t)(dot - arg) >= sizeof(section) ||
        (size_t)(eq - dot - 1) >= sizeof(name)) {
        fputs("--set ", stderr), sp_fputs_line(arg, stderr);
        fputs(": expected section.key=value, e.g. --set video.fps=30\n", stderr);
        c->errors++;
        return;
    }
    memcpy(section, arg, (size_t)(dot - arg));
    section[dot - arg] = 0;
    memcpy(name, dot + 1, (size_t)(eq - dot - 1));
    name[eq - dot - 1] = 0;
    char origin[256];
    snprintf(origin, sizeof(origin), "--set %s", arg);
    const char *saved = c->origin;
    c->origin = origin;
    const struct key_info *k = find_key(section, name);
    if (!strcmp(section, "timeline"))
        report(c, 0, "the [timeline] is read from the scene file only; write the cue there "
               "as '%s = %s'", name, eq + 1);
    else if (!k)
        report_unknown(c, 0, section, name);
    else
    {
        set_value(c, 0, k, eq + 1);
        c->key_set[k - keys] = arg; /* lives as long as the parse */
    }
    c->origin = saved;
}

/* A scene is UTF-8 text without control characters but tab, CR and LF, and
 * not empty. Reports the first offending byte; returns 1 when text is fine. */
static int check_text(struct parse_ctx *c, const char *text)
{
    const unsigned char *p = (const unsigned char *)text, *line_start = p;
    int line = 1, blank = 1;
    while (*p) {
        int n = (int)sp_utf8_char((const char *)p);
        const int c1 = n == 2 && p[0] == 0xc2 && p[1] < 0xa0; /* U+0080..U+009F */
        if (!n || (*p < 0x20 && *p != '\t' && *p != '\r' && *p != '\n') || *p == 0x7f || c1) {
            report(c, line, "%s 0x%02x at column %d is not text; a scene is a UTF-8 "
                   "text file of 'key = value' lines, without control characters (C0, DEL "
                   "or C1)", c1 ? "the C1 control, bytes 0xc2" : "byte", c1 ? p[1] : *p,
                   (int)(p - line_start) + 1);
            return 0;
        }
        blank &= *p == ' ' || *p == '\t' || *p == '\r' || *p == '\n';
        if (*p == '\n' || (*p == '\r' && p[1] != '\n'))
            line++, line_start = p + 1;
        p += n;
    }
    if (blank) {
        char scenes[PATH_MAX];
        sp_scenes_dir(scenes, sizeof(scenes)); /* the installed or the source's scenes/ */
        report(c, 0, "the scene is empty; set at least one key (e.g. '[pendulum]' then "
               "'mass = 1'), or start from %s/default.ini", scenes);
        return 0;
    }
    return 1;
}

/* What the third dimension and the perspective camera do not draw: arrows
 * (drawn in the front view's plane) and the Poincare section (theta = 0 with dtheta/dt > 0 is
 * a section of the planar motion only: in 3-D the polar angle is >= 0 and
 * the state has two more dimensions). */
static int view_drawn = 1; /* sp_scene_view_drawn */

void sp_scene_view_drawn(int drawn)
{
    view_drawn = drawn;
}

static void check_view_3d(struct parse_ctx *c)
{
    if (!view_drawn) /* sweep, data, info, scene: no panel, no arrow (attack13 #4) */
        return;
    const struct sp_scene *s = c->scene;
    const int cam_line = c->key_line[find_key("view", "camera") - keys];
    const int rate_line = c->key_line[find_key("initial", "azimuth_rate") - keys];
    const char *why = s->view.camera == SP_CAMERA_SET ? "view.camera sets a perspective"
                      : "a 3-D scene (initial.azimuth_rate != 0) is drawn in perspective";
    if (sp_scene_perspective(s) && s->view.vectors)
        report(c, c->key_line[find_key("view", "vectors") - keys] ? c->key_line[find_key("view", "vectors") - keys]
               : cam_line ? cam_line : rate_line,
               "view.vectors draws its arrows in the front view's plane, but %s; set "
               "view.camera = front to draw them (the x-y projection), or view.vectors = none",
               why);
    if (s->initial.azimuth_rate != 0 && s->view.panels & SP_PANEL_POINCARE)
        report(c, c->key_line[find_key("view", "panels") - keys] ? c->key_line[find_key("view", "panels") - keys]
               : rate_line,
               "the poincare panel is the planar section theta = 0 with dtheta/dt > 0, which a "
               "3-D motion (initial.azimuth_rate = %g rad/s) does not have; leave poincare out "
               "of view.panels (azimuth and top show the third dimension) or set "
               "initial.azimuth_rate = 0", s->initial.azimuth_rate);
}

/* Checks that need several keys at once. */
static void validate_whole(struct parse_ctx *c)
{
    struct sp_scene *s = c->scene;
    long pixels = (long)s->video.width * s->video.height;
    /* each check names where the key it asks to change came from (report_key:
     * --set or FILE:LINE), not the scene file whatever the origin */
    if (pixels > SP_MAX_PIXELS)
        report_key(c, "video", "width", "video size %dx%d is too large; at most %ld pixels (8K, 7680x4320)",
               s->video.width, s->video.height, SP_MAX_PIXELS);
    double frames = s->video.duration * s->video.fps / s->video.speed;
    if (!(frames >= 0.5))
        report_key(c, "video", "duration", "video.duration * video.fps / video.speed = %g frames; at least "
               "1 frame is needed (raise video.duration or lower video.speed)", frames);
    else if (frames > SP_MAX_FRAMES)
        report_key(c, "video", "duration", "video.duration * video.fps / video.speed = %.3g frame times; at "
               "most %d are allowed", frames, SP_MAX_FRAMES);
    /* Quantities the simulation derives must be finite: k/m and b/m set
     * the time scales, m g / k the static stretch. Printed by their inputs,
     * which are finite. */
    const double k = s->pendulum.stiffness, m = s->pendulum.mass, b = s->pendulum.damping;
    const double g = s->pendulum.gravity;
    if (!(k / m <= SP_MAX_RATE2) || !(b / m <= SP_MAX_RATE2))
        report_key(c, "pendulum", "mass", "pendulum.mass = %g kg is too small for stiffness = %g N/m and damping "
               "= %g N*s/m: k/m and b/m must be at most %g (mass >= %g kg)", m, k, b,
               SP_MAX_RATE2, fmax(k, b) / SP_MAX_RATE2);
    else if (!(m * g / k <= SP_MAX_STRETCH))
        report_key(c, "pendulum", "stiffness", "pendulum.stiffness = %g N/m is too weak for mass = %g kg and gravity = "
               "%g m/s^2: the static stretch m g / k must be at most %g m (stiffness >= %g "
               "N/m)", k, m, g, SP_MAX_STRETCH, m * g / SP_MAX_STRETCH);
    if (s->integrator.method == SP_METHOD_RKN1210 &&
        (s->pendulum.damping > 0 || (s->pivot.amplitude > 0 && s->pivot.frequency > 0)))
        report_key(c, "integrator", "method", "integrator.method = rkn1210 needs a force that depends on the "
               "position only: set pendulum.damping = 0 and pivot.amplitude = 0, or use "
               "integrator.method = dop853");
    /* on the vertical: within 1e-9 degrees of a multiple of 180 (sin(pi) is
     * 1.2e-16, not 0, so the test is on the degrees the file gave) */
    const double from_vertical = fmod(fabs(s->initial.angle * 180 / M_PI), 180);
    if (s->initial.azimuth_rate != 0 && !(from_vertical > 1e-9 && from_vertical < 180 - 1e-9))
        report_key(c, "initial", "azimuth_rate", "initial.azimuth_rate = %g rad/s turns the bob about the vertical, but "
               "initial.angle = %g degrees starts it on the vertical, where there is nothing "
               "to turn; give initial.angle a swing (not 0 or 180 degrees) or set "
               "azimuth_rate = 0", s->initial.azimuth_rate, s->initial.angle * 180 / M_PI);
    check_view_3d(c);
    double steps = s->video.duration / s->integrator.dt;
    if (s->integrator.method <= SP_METHOD_YOSHIDA4 && steps > 1e10)
        report_key(c, "integrator", "dt", "video.duration / integrator.dt = %.3g steps; at most 1e10 are "
               "allowed (raise integrator.dt)", steps);
    if (s->ensemble.count > 1)
        check_ensemble(c);
    /* a label per plot: as many as the plots, or one for all */
    int order[SP_PANEL_COUNT];
    const int n_plots = sp_scene_panel_order(&s->view, order);
    for (int axis = 0; axis < 2; axis++) {
        const char *label = axis ? s->view.ylabel : s->view.xlabel, *key = axis ? "ylabel" : "xlabel";
        int parts = 1;
        for (const char *b = strchr(label, '|'); b; b = strchr(b + 1, '|'))
            parts++;
        if (parts > 1 && parts != n_plots) {
            char plots[256] = "";
            for (int i = 0; i < n_plots; i++)
                snprintf(plots + strlen(plots), sizeof(plots) - strlen(plots), "%s%s",
                         i ? ", " : "", sp_scene_plot_name(order[i]));
            report_key(c, "view", key, "view.%s = '%s' has %d entries for %d plot%s (%s); give "
                       "one name for every plot, or one per plot in the order view.panels lists "
                       "them ('phase' is two plots, r's and theta's), '|' between", key, label,
                       parts, n_plots, n_plots == 1 ? "" : "s", n_plots ? plots : "none");
        }
    }
}

/* [ensemble]: the key is a numeric physics key (as sweep's --vary), the
 * integrator is batched, and both ends of the spread are scenes the parser
 * accepts (their messages prefixed with the spread's or key's line). */
static void check_ensemble(struct parse_ctx *c)
{
    const struct sp_scene *s = c->scene;
    const char *key = s->ensemble.key;
    const int key_line = c->key_line[find_key("ensemble", "key") - keys];
    const int spread_line = c->key_line[find_key("ensemble", "spread") - keys];
    const int count_line = c->key_line[find_key("ensemble", "count") - keys];
    if ((strncmp(key, "pendulum.", 9) && strncmp(key, "initial.", 8) && strncmp(key, "pivot.", 6)) ||
        !numeric_key(key) || numeric_key(key)->kind == KEY_INT) {
        report(c, key_line, "ensemble.key = '%s' cannot be varied; give a numeric key of "
               "[pendulum], [initial] or [pivot], e.g. initial.angle", key);
        return;
    }
    if (s->integrator.method == SP_METHOD_RKN1210) {
        report(c, count_line, "[ensemble] needs a batched integrator; set integrator.method "
               "to rk4, verlet, yoshida4, dopri5 or dop853");
        return;
    }
    for (int end = -1; end <= 1; end += 2) {
        struct sp_scene e = *s;
        char origin[700];
        const double v = sp_scene_get_number(s, key) + 0.5 * end * s->ensemble.spread;
        const int line = spread_line ? spread_line : key_line;
        if (line)
            snprintf(origin, sizeof(origin), "%s:%d: ensemble.spread = %g around %s = %g",
                     c->origin, line, s->ensemble.spread, key, sp_scene_get_number(s, key));
        else
            snprintf(origin, sizeof(origin), "%s: ensemble.spread = %g around %s = %g",
                     c->origin, s->ensemble.spread, key, sp_scene_get_number(s, key));
        e.ensemble.count = 0; /* no recursion */
        if (sp_scene_set_number(&e, key, v, origin)) {
            c->errors++;
            return;
        }
    }
}

int sp_scene_parse(struct sp_scene *s, const char *text, const char *origin,
                   const char *const *overrides, int n_overrides)
{
    if (!strncmp(text, "\xef\xbb\xbf", 3))
        text += 3; /* a UTF-8 byte order mark, as some editors write */
    struct parse_ctx c = {.scene = s, .origin = origin, .cursor = text};
    char name[sizeof(s->name)];
    snprintf(name, sizeof(name), "%s", s->name);
    sp_scene_defaults(s);
    snprintf(s->name, sizeof(s->name), "%s", name);

    if (!check_text(&c, text))
        return SP_E_INPUT;
    ini_allow_multiline = false;
    ini_allow_inline_comments = true;
    ini_inline_comment_prefixes = "#;";
    int rc = ini_parse_stream(read_line, &c, handle_pair, &c);
    if (rc == -2) {
        report(&c, 0, "out of memory while parsing");
        free(c.text_value);
        sp_scene_free(s);
        return SP_E_NOMEM;
    }
    for (int i = 0; i < n_overrides; i++)
        apply_override(&c, overrides[i]);
    for (int i = 0; i < N_KEYS; i++) /* for the commands' own checks */
        s->key_lines[i] = c.key_set[i] ? -1 : c.key_line[i];
    if (!c.errors)
        validate_whole(&c);
    /* once, here: sp_scene_set_number's copies (sweeps, ensembles) share it */
    if (s->timeline)
        c.errors += sp_timeline_check(s->timeline, s);
    if (!c.errors && s->timeline && sp_timeline_plan(s->timeline, s))
        c.errors++;
    free(c.text_value);
    if (c.errors)
        sp_scene_free(s);
    return c.errors ? SP_E_INPUT : 0;
}

/* How long a FIFO scene waits for its writer before giving up. */
#define SCENE_FIFO_WAIT_MS 5000

/* 1 when path is a bare name ("default", "chaotic.ini": no folder) of a
 * shipped scene, whose path goes to out: a hint for a scene not found. */
static int shipped_scene(const char *path, char *out, size_t size)
{
    char dir[PATH_MAX];
    size_t len = strlen(path);
    if (!len || len > 200 || strchr(path, '/') || path[0] == '.')
        return 0;
    sp_scenes_dir(dir, sizeof(dir));
    const int ini = len > 4 && !strcmp(path + len - 4, ".ini");
    if ((size_t)snprintf(out, size, "%s/%s%s", dir, path, ini ? "" : ".ini") >= size)
        return 0;
    return access(out, R_OK) == 0;
}

/* Reads the whole scene at path into *text (NUL-terminated, caller frees).
 * A regular file is read by its size; a pipe, FIFO or device as a stream
 * (`<(cat x)`, `/dev/stdin`), at most 1 MiB, after waiting at most
 * SCENE_FIFO_WAIT_MS for a writer; a folder is refused. Logs; SP_E_INPUT, or
 * SP_E_INTERRUPTED without a word when a stop signal cuts the wait or a read. */
static int read_scene(const char *path, char **text, size_t *size)
{
    const size_t max = 1u << 20;
    struct stat st;
    int ret = SP_E_INPUT;
    *text = NULL;
    *size = 0;
    /* O_NONBLOCK: opening a FIFO must not wait for a writer forever. */
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        char shipped[PATH_MAX + 64];
        const int err = errno;
        if (err == ENOENT && shipped_scene(path, shipped, sizeof(shipped)))
            sp_fprintf_line(stderr, "%s: cannot open scene: %s; the shipped scene of that "
                            "name is %s", path, strerror(err), shipped);
        else
            sp_fprintf_line(stderr, "%s: cannot open scene: %s", path, strerror(err));
        return SP_E_INPUT;
    }
    if (fstat(fd, &st) != 0 || S_ISDIR(st.st_mode)) {
        sp_fprintf_line(stderr, "%s: %s; give a scene file (.ini)", path,
                S_ISDIR(st.st_mode) ? "is a folder" : strerror(errno));
        goto done;
    }
    if (S_ISREG(st.st_mode) && (size_t)st.st_size > max) {
        sp_fprintf_line(stderr, "%s: scene file is %lld bytes; at most 1 MiB is allowed", path,
                (long long)st.st_size);
        goto done;
    }
    if (S_ISFIFO(st.st_mode)) {
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        int n;
        /* EINTR here is a stop signal: every handler springpend installs
         * (signals.c) stands for one, so give up at once. */
        n = poll(&pfd, 1, SCENE_FIFO_WAIT_MS);
        if (n < 0) {
            if (errno == EINTR)
                ret = SP_E_INTERRUPTED;
            else
                sp_fprintf_line(stderr, "%s: cannot wait for the FIFO's writer: %s", path,
                        strerror(errno));
            goto done;
        }
        if (n == 0) {
            sp_fprintf_line(stderr, "%s: a FIFO with nothing written to it after %d s; start its "
                    "writer first, or give a scene file", path, SCENE_FIFO_WAIT_MS / 1000);
            goto done;
        }
    }
    fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
    size_t cap = 0; /* bytes at *text: what was read, one more and the NUL fit */
    for (;;) {
        if (*size > max) {
            sp_fprintf_line(stderr, "%s: the scene is more than 1 MiB; at most 1 MiB is "
                    "allowed", path);
            goto done;
        }
        if (sp_array_reserve((void **)text, 1, &cap, *size + 2,
                             S_ISREG(st.st_mode) ? (size_t)st.st_size + 1 : 4096, max + 2)) {
            ret = SP_E_NOMEM;
            goto done;
        }
        ssize_t got = read(fd, *text + *size, cap - 1 - *size);
        if (got < 0 && errno == EINTR) { /* a stop signal, as above */
            ret = SP_E_INTERRUPTED;
            goto done;
        }
        if (got < 0) {
            sp_fprintf_line(stderr, "%s: cannot read scene: %s", path, strerror(errno));
            goto done;
        }
        if (got == 0)
            break;
        *size += (size_t)got;
    }
    (*text)[*size] = 0;
    ret = 0;
done:
    close(fd);
    if (ret) {
        free(*text);
        *text = NULL;
    }
    return ret;
}

int sp_scene_load(struct sp_scene *s, const char *path,
                  const char *const *overrides, int n_overrides)
{
    char *text;
    size_t size;
    s->timeline = NULL; /* sp_scene_free is safe after any outcome */
    s->texts[0] = s->texts[1] = NULL;
    int ret = read_scene(path, &text, &size);
    if (ret)
        return ret;
    ret = sp_scene_load_text(s, path, text, size, overrides, n_overrides);
    free(text);
    return ret;
}

int sp_scene_load_text(struct sp_scene *s, const char *path, const char *text, size_t size,
                       const char *const *overrides, int n_overrides)
{
    s->timeline = NULL; /* sp_scene_free is safe after any outcome */
    s->texts[0] = s->texts[1] = NULL;
    if (memchr(text, 0, size)) {
        if (!sp_log_muted()) /* one rule for every message the parser gives */
            sp_fprintf_line(stderr, "%s: contains NUL bytes; a scene is a text file of "
                            "'key = value' lines", path);
        return SP_E_INPUT;
    }
    /* The scene's name is the file's stem: its name less the last
     * extension ("chaotic.v2.ini" is chaotic.v2, not chaotic, which
     * chaotic.v3.ini's outputs would share: attack11 #25). */
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *ext = strrchr(base, '.');
    snprintf(s->name, sizeof(s->name), "%.*s",
             (int)(ext ? (size_t)(ext - base) : strlen(base)), base); /* ".ini": "scene" */
    if (!s->name[0])
        snprintf(s->name, sizeof(s->name), "scene");
    return sp_scene_parse(s, text, path, overrides, n_overrides);
}

void sp_scene_free(struct sp_scene *s)
{
    sp_timeline_destroy(&s->timeline);
    for (int i = 0; i < 2; i++) {
        free(s->texts[i]);
        s->texts[i] = NULL;
    }
    s->view.title = s->view.caption = s->view.title_where = s->view.caption_where = "";
}

int sp_scene_perspective(const struct sp_scene *s)
{
    return s->view.camera == SP_CAMERA_SET ||
           (s->view.camera == SP_CAMERA_AUTO && s->initial.azimuth_rate != 0);
}

int sp_scene_frame_count(const struct sp_scene *s)
{
    return (int)lround(s->video.duration * s->video.fps / s->video.speed);
}

double sp_scene_frame_time(const struct sp_scene *s, int k)
{
    return k * s->video.speed / s->video.fps;
}

int sp_scene_canonical(const struct sp_scene *s, char *buf, size_t size)
{
    size_t used = 0;
    for (int i = 0; i < N_KEYS; i++) {
        const struct key_info *k = &keys[i];
        const char *p = (const char *)s + k->offset;
        char *at = used < size ? buf + used : NULL;
        size_t room = used < size ? size - used : 0;
        int n;
        switch (k->kind) {
        case KEY_REAL:
        case KEY_DEGREES:
            n = QUIET_KEY(k) && *(const double *)p == k->def
                    ? 0 : snprintf(at, room, "%s.%s=%.17g\n", k->section, k->name, *(const double *)p);
            break;
        case KEY_METHOD:
            n = snprintf(at, room, "%s.%s=%s\n", k->section, k->name,
                         method_names[*(const enum sp_method *)p]);
            break;
        case KEY_PANELS:
            n = QUIET_KEY(k) && !*(const unsigned *)p
                    ? 0 : snprintf(at, room, "%s.%s=%#x\n", k->section, k->name, *(const unsigned *)p);
            if (k->offset == offsetof(struct sp_scene, view.panels)) {
                /* the order, when it is not the bits' own */
                int order[SP_PANEL_COUNT], sorted = 1;
                const int np = sp_scene_panel_order(&s->view, order);
                for (int j = 1; j < np; j++)
                    sorted &= order[j] > order[j - 1];
                for (int j = 0; !sorted && j < np; j++) {
                    const int m = snprintf(used + n < size ? buf + used + n : NULL,
                                           used + n < size ? size - used - n : 0, "%s%d%s",
                                           j ? "" : "view.panel_order=", order[j],
                                           j + 1 < np ? "," : "\n");
                    n += m;
                }
            }
            break;
        case KEY_TEXT:
            n = QUIET_KEY(k) && !*text_of(s, k)
                    ? 0 : snprintf(at, room, "%s.%s=%s\n", k->section, k->name, text_of(s, k));
            break;
        case KEY_CAMERA:
            if (s->view.camera == SP_CAMERA_SET)
                n = snprintf(at, room, "%s.%s=%.17g %.17g %.17g\n", k->section, k->name,
                             s->view.camera_azimuth, s->view.camera_elevation,
                             s->view.camera_distance);
            else
                n = s->view.camera == SP_CAMERA_AUTO ? 0
                    : snprintf(at, room, "%s.%s=front\n", k->section, k->name);
            break;
        case KEY_TRAIL:
            if (*(const int *)p == SP_TRAIL_DURATION)
                n = snprintf(at, room, "%s.%s=%.17gs\n", k->section, k->name, s->view.trail_duration);
            else
                n = snprintf(at, room, "%s.%s=%d\n", k->section, k->name, *(const int *)p);
            break;
        default: /* KEY_INT, KEY_BOOL, KEY_CHOICE, KEY_COLOR: an int */
            n = QUIET_KEY(k) && *(const int *)p == (int)k->def
                    ? 0 : snprintf(at, room, "%s.%s=%d\n", k->section, k->name, *(const int *)p);
            break;
        }
        used += (size_t)n;
    }
    /* the timeline: what the video shows changes with it */
    for (int i = 0; s->timeline && i < s->timeline->n_cues; i++) {
        static const char *const verbs[] = {"caption", "speed", "pause"};
        const struct sp_cue *cue = &s->timeline->cues[i];
        char *at = used < size ? buf + used : NULL;
        size_t room = used < size ? size - used : 0;
        used += (size_t)snprintf(at, room, "timeline.%d=%.17g %s %.17g %s\n", i, cue->t,
                                 verbs[cue->kind], cue->value, cue->text);
    }
    return (int)used;
}

/* The shortest decimal text (at most 17 digits) that sp_decimal_read reads
 * back, times scale, as exactly v (scale 1: v itself; pi/180: an angle in
 * radians written in degrees). Such a text exists for every value the
 * parser stored; the neighbours of v / scale are tried for the angles. */
static int reads_as(const char *text, double scale, double v)
{
    double back;
    return sp_decimal_read(text, &back) == SP_DECIMAL_OK &&
           (scale == 1 ? back : back * scale) == v;
}

static void exact_number(double v, double scale, char *buf, size_t size)
{
    const double x = v / scale;
    double down = x, up = x;
    for (int step = 0; step < 32; step++) {
        for (int side = 0; side < (step ? 2 : 1); side++)
            for (int digits = 1; digits <= 17; digits++) {
                const double c = side ? up : down;
                snprintf(buf, size, "%.*g", digits, c);
                if (!reads_as(buf, scale, v))
                    continue;
                /* without an exponent where that is as short to read */
                const int e = c ? (int)floor(log10(fabs(c))) : 0;
                char plain[64];
                if (strchr(buf, 'e') && e > -5 && e < 16 &&
                    snprintf(plain, sizeof(plain), "%.*f", digits - 1 - e > 0 ? digits - 1 - e : 0,
                             c) < (int)sizeof(plain) &&
                    reads_as(plain, scale, v))
                    snprintf(buf, size, "%s", plain);
                return;
            }
        down = nextafter(down, -INFINITY);
        up = nextafter(up, INFINITY);
    }
    snprintf(buf, size, "%.17g", x); /* not reached for parsed values */
}

int sp_scene_write_ini(const struct sp_scene *s, char *buf, size_t size)
{
    size_t used = 0;
    const char *section = "";
#define EMIT(...)                                                                        \
    used += (size_t)snprintf(used < size ? buf + used : NULL, used < size ? size - used : 0, \
                             __VA_ARGS__)
    for (int i = 0; i < N_KEYS; i++) {
        const struct key_info *k = &keys[i];
        const char *p = (const char *)s + k->offset;
        char value[SP_VIEW_TEXT_BYTES + 64], canon[SP_VIEW_TEXT_BYTES + 64];
        if (strcmp(section, k->section))
            EMIT("%s[%s]\n", i ? "\n" : "", section = k->section);
        switch (k->kind) {
        case KEY_REAL:
            exact_number(*(const double *)p, 1, value, sizeof(value));
            break;
        case KEY_DEGREES:
            exact_number(*(const double *)p, M_PI / 180.0, value, sizeof(value));
            break;
        case KEY_INT:
            snprintf(value, sizeof(value), "%d", *(const int *)p);
            break;
        case KEY_METHOD:
            snprintf(value, sizeof(value), "%s", method_names[*(const enum sp_method *)p]);
            break;
        case KEY_TEXT: /* in quotes, taken whole: a ' #' inside stays text; any length */
            EMIT("%s = \"%s\"\n", k->name, text_of(s, k));
            continue;
        case KEY_CAMERA:
            if (s->view.camera == SP_CAMERA_SET) {
                char a[32], e[32], d[32] = "";
                exact_number(s->view.camera_azimuth, M_PI / 180.0, a, sizeof(a));
                exact_number(s->view.camera_elevation, M_PI / 180.0, e, sizeof(e));
                if (s->view.camera_distance > 0)
                    exact_number(s->view.camera_distance, 1, d, sizeof(d));
                snprintf(value, sizeof(value), "%s %s%s%s", a, e, d[0] ? " " : "", d);
            } else {
                snprintf(value, sizeof(value), "%s", s->view.camera ? "front" : "auto");
            }
            break;
        case KEY_TRAIL:
            if (*(const int *)p == SP_TRAIL_DURATION) {
                exact_number(s->view.trail_duration, 1, value, sizeof(value) - 1);
                strcat(value, "s");
                break;
            }
            /* fall through */
        default: /* the words: as the display of the canonical value */
            if (k->offset == offsetof(struct sp_scene, view.panels) && s->view.panels) {
                /* in the order listed: each panel's name, as the display gives it */
                int order[SP_PANEL_COUNT], len = 0;
                const int np = sp_scene_panel_order(&s->view, order);
                value[0] = 0;
                for (int j = 0; j < np; j++) {
                    char one[32], name[64];
                    if (order[j] == 5 && (s->view.panels & SP_PANEL_PHASE_R))
                        continue; /* theta's phase portrait goes with r's: "phase" */
                    snprintf(one, sizeof(one), "%#x", 1u << order[j]);
                    sp_scene_canonical_display("view.panels", one, name, sizeof(name));
                    len += snprintf(value + len, sizeof(value) - (size_t)len, "%s%s",
                                    len ? ", " : "", name);
                }
                break;
            }
            snprintf(canon, sizeof(canon), k->kind == KEY_PANELS ? "%#x" : "%d",
                     *(const int *)p);
            char key[64];
            snprintf(key, sizeof(key), "%s.%s", k->section, k->name);
            sp_scene_canonical_display(key, canon, value, sizeof(value));
            break;
        }
        EMIT("%s = %s\n", k->name, value);
    }
    for (int i = 0; s->timeline && i < s->timeline->n_cues; i++) {
        const struct sp_cue *cue = &s->timeline->cues[i];
        const char *text = s->timeline->pool ? s->timeline->pool + cue->text_at : "";
        char t[32], v[32];
        exact_number(cue->t, 1, t, sizeof(t));
        exact_number(cue->value, 1, v, sizeof(v));
        if (!i)
            EMIT("\n[timeline]\n");
        if (cue->kind == SP_CUE_CAPTION)
            EMIT("%s = caption: \"%s\"\n", t, text);
        else if (cue->kind == SP_CUE_SPEED)
            EMIT("%s = speed %s\n", t, v);
        else
            EMIT("%s = pause %s: \"%s\"\n", t, v, text);
    }
#undef EMIT
    return (int)used;
}

char *sp_scene_ini(const struct sp_scene *s)
{
    const int n = sp_scene_write_ini(s, NULL, 0);
    char *text = malloc((size_t)n + 1);
    if (text)
        sp_scene_write_ini(s, text, (size_t)n + 1);
    return text;
}

void sp_scene_print_keys(void)
{
    static struct sp_scene def; /* big: not on the stack */
    const char *section = "";
    sp_scene_defaults(&def);
    for (int i = 0; i < N_KEYS; i++) {
        const struct key_info *k = &keys[i];
        char range[192];
        if (strcmp(section, k->section))
            printf("  [%s]\n", section = k->section);
        if (k->kind == KEY_TEXT && strcmp(k->unit, "text"))
            snprintf(range, sizeof(range), "%s", k->unit);
        else if (k->kind == KEY_TEXT)
            snprintf(range, sizeof(range), "UTF-8 text of any length that fits the frame, wrapped");
        else if (k->kind >= KEY_BOOL && k->kind != KEY_TRAIL)
            snprintf(range, sizeof(range), "%s: %s", k->kind == KEY_PANELS ? "list of" : "one of", k->unit);
        else if (k->kind == KEY_METHOD)
            snprintf(range, sizeof(range), "one of: %s", k->unit);
        else
            describe_range(k, range, sizeof(range));
        if (k->kind == KEY_METHOD)
            printf("    %-15s default %-8s %s\n", k->name, method_names[(int)k->def], range);
        else if (k->kind == KEY_TEXT)
            printf("    %-15s default %-8s %s\n", k->name,
                   *text_of(&def, k) ? text_of(&def, k) : "\"\"", range);
        else if (k->kind >= KEY_BOOL && k->kind != KEY_TRAIL)
            printf("    %-15s default %-8.*s %s\n", k->name,
                   k->kind == KEY_BOOL ? 5 : (int)strcspn(k->unit, ","),
                   k->kind == KEY_BOOL ? (k->def ? "true" : "false")
                   : k->kind == KEY_COLOR ? "theme" : k->unit, range);
        else
            printf("    %-15s default %-8g %s\n", k->name, k->def, range);
    }
    /* cues, not keys: indented past a key's column, so no reader takes them for keys */
    printf("  [timeline] cues keyed by simulated time, in order (see 'springpend render --help'):\n"
           "      TIME = caption: TEXT    the caption from TIME on ('caption:' alone clears it)\n"
           "      TIME = speed S          ease to S simulated s per video s (0 < S <= 1e4)\n"
           "      TIME = pause D[: NOTE]  hold TIME for D s of video (0 < D <= 3600), NOTE shown\n");
}

void sp_scene_canonical_display(const char *key, const char *value, char *buf, size_t size)
{
    static const char *const panel_names[] = {"r", "theta", "energy", "extension", "phase",
                                              "poincare", "modes", "spread", "azimuth", "top",
                                              "energy_bars"};
    static const unsigned panel_bits[] = {SP_PANEL_R, SP_PANEL_THETA, SP_PANEL_ENERGY,
                                          SP_PANEL_EXTENSION,
                                          SP_PANEL_PHASE_R | SP_PANEL_PHASE_THETA,
                                          SP_PANEL_POINCARE, SP_PANEL_MODES, SP_PANEL_SPREAD,
                                          SP_PANEL_AZIMUTH, SP_PANEL_TOP, SP_PANEL_ENERGY_BARS};
    static const char *const vector_names[] = {"velocity", "acceleration", "gravity", "spring",
                                               "damping", "drive", "net"};
    char section[64];
    const char *dot = strchr(key, '.');
    const struct key_info *k = NULL;
    char *end;
    double v = strtod(value, &end);
    snprintf(buf, size, "%s", value);
    if (dot && (size_t)(dot - key) < sizeof(section)) {
        snprintf(section, sizeof(section), "%.*s", (int)(dot - key), key);
        k = find_key(section, dot + 1);
    }
    double cam[3];
    if (k && k->kind == KEY_CAMERA && sscanf(value, "%lf %lf %lf", &cam[0], &cam[1], &cam[2]) == 3) {
        int n = snprintf(buf, size, "%.10g %.10g", cam[0] * (180.0 / M_PI), cam[1] * (180.0 / M_PI));
        if (cam[2] > 0 && n >= 0 && (size_t)n < size)
            snprintf(buf + n, size - (size_t)n, " %.10g", cam[2]);
        return;
    }
    if (!k || end == value || *end)
        return;
    switch (k->kind) {
    case KEY_REAL: snprintf(buf, size, "%.10g", v); break;
    case KEY_DEGREES: snprintf(buf, size, "%.10g", v * (180.0 / M_PI)); break;
    case KEY_BOOL: snprintf(buf, size, "%s", v != 0 ? "true" : "false"); break;
    case KEY_CHOICE: {
        const char *w = k->unit;
        for (int i = 0; i < (int)v && *w; i++)
            w += strcspn(w, ","), w += strspn(w, ", ");
        if (*w)
            snprintf(buf, size, "%.*s", (int)strcspn(w, ","), w);
        break;
    }
    case KEY_COLOR:
        if ((int)v == SP_BACKGROUND_THEME)
            snprintf(buf, size, "theme");
        else if ((int)v == SP_BACKGROUND_TRANSPARENT)
            snprintf(buf, size, "transparent");
        else
            snprintf(buf, size, "#%06x", (unsigned)v);
        break;
    case KEY_TRAIL:
        if ((int)v == SP_TRAIL_ALL)
            snprintf(buf, size, "all");
        break;
    case KEY_PANELS: {
        unsigned bits = (unsigned)strtoul(value, NULL, 0);
        size_t used = 0;
        const int vectors = k->offset == offsetof(struct sp_scene, view.vectors);
        buf[0] = 0;
        for (int i = 0; vectors && i < SP_VECTOR_COUNT; i++)
            if (bits & 1u << i && used < size)
                used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? ", " : "",
                                         vector_names[i]);
        for (int i = 0; !vectors && i < (int)(sizeof(panel_bits) / sizeof(panel_bits[0])); i++)
            if (bits & panel_bits[i] && used < size)
                used += (size_t)snprintf(buf + used, size - used, "%s%s", used ? ", " : "",
                                         panel_names[i]);
        if (!bits)
            snprintf(buf, size, "none");
        break;
    }
    default: break;
    }
}

/* ---- numeric keys by name (sweeps) ---- */

static const struct key_info *numeric_key(const char *key)
{
    char section[32];
    const char *dot = strchr(key, '.');
    if (!dot || dot - key >= (long)sizeof(section))
        return NULL;
    snprintf(section, sizeof(section), "%.*s", (int)(dot - key), key);
    const struct key_info *k = find_key(section, dot + 1);
    return k && (k->kind == KEY_REAL || k->kind == KEY_DEGREES || k->kind == KEY_INT) ? k : NULL;
}

const char *sp_scene_key_unit(const char *key)
{
    const struct key_info *k = numeric_key(key);
    return k ? k->unit : NULL;
}

double sp_scene_get_number(const struct sp_scene *s, const char *key)
{
    const struct key_info *k = numeric_key(key);
    const char *p = (const char *)s;
    if (!k)
        return NAN;
    if (k->kind == KEY_INT)
        return *(const int *)(p + k->offset);
    return *(const double *)(p + k->offset) * (k->kind == KEY_DEGREES ? 180.0 / M_PI : 1.0);
}

int sp_scene_check_value(const char *key, const char *value, const char *origin)
{
    const struct key_info *k = numeric_key(key);
    struct sp_scene s;
    struct parse_ctx c = {.scene = &s, .origin = origin};
    if (!k) {
        sp_log_error("%s: '%s' is not a numeric scene key; see 'springpend keys'", origin, key);
        return SP_E_INPUT;
    }
    sp_scene_defaults(&s);
    set_value(&c, 0, k, value);
    return c.errors ? SP_E_INPUT : 0;
}

int sp_scene_set_number(struct sp_scene *s, const char *key, double value, const char *origin)
{
    const struct key_info *k = numeric_key(key);
    struct parse_ctx c = {.scene = s, .origin = origin};
    char text[64];
    if (!k) {
        sp_log_error("%s: '%s' is not a numeric scene key; see 'springpend keys'", origin, key);
        return SP_E_INPUT;
    }
    snprintf(text, sizeof(text), "%.17g", value);
    set_value(&c, 0, k, text);
    if (!c.errors)
        validate_whole(&c);
    return c.errors ? SP_E_INPUT : 0;
}
