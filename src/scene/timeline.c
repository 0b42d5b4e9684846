/* springpend: the [timeline] section: its cues, the video's clock and the
 * caption band's schedule. See timeline.h for the rule. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/scene.h"
#include "springpend/timeline.h"
#include "base/decimal.h"
#include "base/array.h"
#include "base/ini_lines.h"
#include "base/utf8.h"

#define E SP_TIMELINE_EASE
#define H SP_TIMELINE_FADE
#define MAX_TIME 1e6   /* simulated s: [video] duration's own limit */
#define MAX_PAUSE 3600 /* video s */

#define VERBS "caption: TEXT (an empty TEXT clears the caption), speed S (simulated s per " \
              "video s, 0 < S <= 1e4) or pause D[: NOTE] (D video s, 0 < D <= 3600)"

void sp_timeline_destroy(struct sp_timeline **tp)
{
    struct sp_timeline *t = *tp;
    if (!t)
        return;
    free(t->cues);
    free(t->pool);
    free(t->pieces);
    free(t->band);
    free(t);
    *tp = NULL;
}

static void report(const char *origin, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Says a [timeline] line's error, but while the log is muted (sp_log_muted:
 * sweep --merge's look at a scene a shard's command names, whose text the
 * messages would quote: attack11 #7), as scene.c's report. */
static void report(const char *origin, int line, const char *fmt, ...)
{
    if (sp_log_muted())
        return;
    va_list ap;
    va_start(ap, fmt);
    char *msg = NULL;
    if (vasprintf(&msg, fmt, ap) < 0)
        msg = NULL;
    va_end(ap);
    sp_fprintf_line(stderr, "%s:%d: %s", origin, line, msg ? msg : fmt);
    free(msg);
}

/* Appends text (n bytes) to the pool; returns its offset, or -1. */
static long pool_add(struct sp_timeline *tl, const char *text, size_t n)
{
    if (SP_ARRAY_RESERVE(tl->pool, tl->pool_cap, tl->pool_used + n + 1, 1024))
        return -1;
    memcpy(tl->pool + tl->pool_used, text, n);
    tl->pool[tl->pool_used + n] = 0;
    tl->pool_used += n + 1;
    return (long)(tl->pool_used - n - 1);
}

/* The text of a caption or a pause note, after its ':' (at colon), into
 * *text and *tn (its bytes; surrounding double quotes taken off). 0, or 1
 * when it was refused (said): a comment sign where it would cut the text,
 * or more than a comment after a closing quote. */
static int cue_text(const char *origin, int line, enum sp_cue_kind kind, const char *cue,
                    const char *colon, const char **text, size_t *tn)
{
    const char *t = *text = colon + 1 + strspn(colon + 1, " \t");
    size_t at;
    const int first = t > colon + 1 && (*t == '#' || *t == ';'); /* the text starts with it */
    const enum sp_ini_text how = first ? SP_INI_TEXT_COMMENT : sp_ini_text(t, tn, &at);
    if (how == SP_INI_TEXT_COMMENT) {
        size_t whole, ignored;
        sp_ini_text(t, &whole, &ignored); /* the text as written, to quote it back */
        const char sign = first ? *t : t[at], blank = first ? t[-1] : t[at - 1];
        char *quoted = sp_ini_text_quoted(t, whole);
        report(origin, line, "[timeline] %s: %s%c' would start a comment here; to show it, "
               "write the text in double quotes (%.*s: %s)%s; a comment may follow the "
               "closing quote", kind == SP_CUE_CAPTION ? "caption" : "pause note",
               blank == '\t' ? "a tab then '" : "' ", sign, (int)(colon - cue), cue,
               quoted ? quoted : "\"TEXT\"", memchr(t, '\t', whole) ? ", a tab written as a space" : "");
        free(quoted);
        return 1;
    }
    if (how == SP_INI_TEXT_AFTER_QUOTE) {
        report(origin, line, "[timeline] %s: only a '#' or ';' comment may follow the "
               "closing quote, not '%.*s'", kind == SP_CUE_CAPTION ? "caption" : "pause note",
               (int)(*tn - at), t + at);
        return 1;
    }
    if (*tn >= 2 && t[0] == '"' && t[*tn - 1] == '"') /* quotes, as title's */
        *text += 1, *tn -= 2;
    const size_t bad = sp_utf8_not_text(*text, *tn); /* as [view] text's (attack11 #19) */
    if (bad < *tn) {
        const unsigned char *u = (const unsigned char *)*text + bad;
        const int c1 = bad + 1 < *tn && u[0] == 0xc2 && u[1] >= 0x80 && u[1] < 0xa0;
        report(origin, line, "[timeline] %s: %s 0x%02x at byte %zu is not text; allowed: "
               "UTF-8 text without control characters (C0 such as a tab, DEL or C1)",
               kind == SP_CUE_CAPTION ? "caption" : "pause note",
               c1 ? "the C1 control, bytes 0xc2" : "byte", c1 ? u[1] : *u, bad + 1);
        return 1;
    }
    return 0;
}

/* The number of a speed or pause cue (rest: what follows its verb; a
 * pause's ends at its note's colon, both at comment) into *value. 0, or 1
 * when it is missing or out of range (said). */
static int cue_number(const char *origin, int line, enum sp_cue_kind kind, const char *rest,
                      const char *colon, const char *comment, double *value)
{
    char num[64];
    const char *wrong;
    const char *end = colon && colon < comment && kind == SP_CUE_PAUSE ? colon : comment;
    const char *v = rest + strspn(rest, " \t");
    size_t n = end > v ? (size_t)(end - v) : 0;
    while (n && (v[n - 1] == ' ' || v[n - 1] == '\t'))
        n--;
    if (!n) {
        report(origin, line, "[timeline] %s needs a %s; write '%s'",
               kind == SP_CUE_SPEED ? "speed" : "pause",
               kind == SP_CUE_SPEED ? "speed (simulated s per video s)" : "duration in video seconds",
               kind == SP_CUE_SPEED ? "speed S, e.g. speed 0.25" : "pause D[: NOTE], e.g. pause 3: a note");
        return 1;
    }
    snprintf(num, sizeof(num), "%.*s", (int)(n < sizeof(num) ? n : sizeof(num) - 1), v);
    wrong = n >= sizeof(num) ? SP_DECIMAL_NOT
          : sp_decimal_in(num, 0, kind == SP_CUE_SPEED ? 1e4 : MAX_PAUSE, SP_DECIMAL_ABOVE, value);
    if (wrong) {
        report(origin, line, "[timeline] %s %.*s: %s; expected %s%s",
               kind == SP_CUE_SPEED ? "speed" : "pause", (int)n, v, wrong,
               kind == SP_CUE_SPEED ? "a speed S with 0 < S <= 1e4 simulated s per video s"
                                    : "a duration D with 0 < D <= 3600 video s",
               !strcmp(wrong, SP_DECIMAL_NOT) ? ", " SP_DECIMAL_ALLOWED : "");
        return 1;
    }
    return 0;
}

int sp_timeline_read(struct sp_timeline **tlp, const char *origin, int line, const char *time,
                     const char *cue)
{
    struct sp_timeline *tl = *tlp;
    double t = 0, value = 0;
    const char *wrong = sp_decimal_in(time, 0, MAX_TIME, 0, &t);
    if (wrong) {
        report(origin, line, "[timeline] time '%s' is %s; expected a simulated time in "
               "seconds, 0 <= time <= video.duration%s", time, wrong,
               !strcmp(wrong, SP_DECIMAL_NOT) ? ", " SP_DECIMAL_ALLOWED : "");
        return 1;
    }
    if (!tl) {
        tl = *tlp = calloc(1, sizeof(*tl));
        if (!tl)
            return SP_E_NOMEM;
        snprintf(tl->origin, sizeof(tl->origin), "%s", origin);
    }
    /* in time order, checked against the line before whatever else it holds */
    const double last_t = tl->last_t;
    const int last_line = tl->last_line;
    tl->last_t = t, tl->last_line = line;
    if (tl->n_cues >= SP_TIMELINE_MAX_CUES) { /* said once, at the first cue too many */
        if (tl->cues_over++ == 0)
            report(origin, line, "[timeline] has more than %d cues; at most %d are allowed",
                   SP_TIMELINE_MAX_CUES, SP_TIMELINE_MAX_CUES);
        return 1;
    }
    /* the verb: a word, then ':' (caption) or blanks and a number; the
     * line comes whole (scene.c's read_line), comments and all */
    size_t vn = strcspn(cue, ": \t#;");
    enum sp_cue_kind kind;
    if (vn == 7 && !strncmp(cue, "caption", 7))
        kind = SP_CUE_CAPTION;
    else if (vn == 5 && !strncmp(cue, "speed", 5))
        kind = SP_CUE_SPEED;
    else if (vn == 5 && !strncmp(cue, "pause", 5))
        kind = SP_CUE_PAUSE;
    else {
        report(origin, line, "[timeline] '%.*s' is not a cue; allowed: " VERBS, (int)vn, cue);
        return 1;
    }
    const char *rest = cue + vn, *text = "", *comment = rest + strlen(rest);
    size_t tn = 0;
    for (const char *p = rest; *p; p++) /* where a comment would start, unquoted */
        if ((*p == '#' || *p == ';') && p > cue && (p[-1] == ' ' || p[-1] == '\t')) {
            comment = p;
            break;
        }
    const char *colon = strchr(rest, ':');
    if (kind == SP_CUE_CAPTION && colon != rest) {
        report(origin, line, "[timeline] caption needs a ':' before its text; write "
               "'caption: TEXT' ('caption:' alone clears the caption)");
        return 1;
    }
    if (colon && colon < comment && kind != SP_CUE_SPEED && /* the caption or the note */
        cue_text(origin, line, kind, cue, colon, &text, &tn))
        return 1;
    if (kind != SP_CUE_CAPTION && cue_number(origin, line, kind, rest, colon, comment, &value))
        return 1;
    /* no byte limit: the caption band's check (compose.c) refuses, with
     * FILE:LINE, a text that cannot fit its lines */
    if (last_line && t < last_t) {
        report(origin, line, "[timeline] time %s comes before %.17g (line %d): times out of "
               "order; list the cues in the order of their times", time, last_t, last_line);
        return 1;
    }
    for (int i = tl->n_cues - 1; i >= 0 && tl->cues[i].t == t; i--)
        if (tl->cues[i].kind == kind && kind != SP_CUE_PAUSE) {
            report(origin, line, "[timeline] a second %s at %s s (the first on line %d); keep one",
                   kind == SP_CUE_CAPTION ? "caption" : "speed", time, tl->cues[i].line);
            return 1;
        }
    if (SP_ARRAY_RESERVE(tl->cues, tl->cap_cues, tl->n_cues + 1, 2))
        return SP_E_NOMEM;
    long at = pool_add(tl, text, tn);
    if (at < 0)
        return SP_E_NOMEM;
    tl->cues[tl->n_cues++] = (struct sp_cue){.t = t, .kind = kind, .value = value,
                                             .text_at = (size_t)at, .line = line};
    return 0;
}

/* ---- the clock ---- */

/* q(x) = 3x^2 - 2x^3 on [0, 1], and its integral from 0, R(x) = x^3 - x^4 / 2. */
static double ease_q(double x) { return x * x * (3 - 2 * x); }
static double ease_r(double x) { return x * x * x * (1 - 0.5 * x); }

/* Video s of p's ease that remain from its start (0 for a constant speed). */
static double ease_left(const struct sp_clock_piece *p)
{
    return p->s_a == p->s_b ? 0 : (1 - p->x0) * E;
}

/* Simulated s the piece covers in du video s from its start. */
static double piece_dt(const struct sp_clock_piece *p, double du)
{
    if (p->hold)
        return 0;
    const double de = ease_left(p);
    if (du <= de)
        return p->s_a * du + (p->s_b - p->s_a) * E * (ease_r(p->x0 + du / E) - ease_r(p->x0));
    return piece_dt(p, de) + p->s_b * (du - de);
}

/* The speed du video s into the piece. */
static double piece_speed(const struct sp_clock_piece *p, double du)
{
    if (p->hold)
        return 0;
    return du < ease_left(p) ? p->s_a + (p->s_b - p->s_a) * ease_q(p->x0 + du / E) : p->s_b;
}

/* The video s into the piece where it has covered dt simulated s (>= 0):
 * the steady part in closed form, the ease by bisection to the last bit. */
static double piece_du(const struct sp_clock_piece *p, double dt)
{
    const double de = ease_left(p);
    const double dt_ease = piece_dt(p, de);
    if (dt >= dt_ease)
        return de + (dt - dt_ease) / p->s_b;
    double lo = 0, hi = de;
    for (int i = 0; i < 200; i++) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi)
            break;
        if (piece_dt(p, mid) < dt)
            lo = mid;
        else
            hi = mid;
    }
    return hi;
}

static int push_piece(struct sp_timeline *tl, const struct sp_clock_piece *p)
{
    if (SP_ARRAY_RESERVE(tl->pieces, tl->cap_pieces, tl->n_pieces + 1, 2))
        return SP_E_NOMEM;
    tl->pieces[tl->n_pieces++] = *p;
    return 0;
}

static int push_band(struct sp_timeline *tl, double u, const char *text, int note)
{
    if (SP_ARRAY_RESERVE(tl->band, tl->cap_band, tl->n_band + 1, 2))
        return SP_E_NOMEM;
    tl->band[tl->n_band++] = (struct sp_band_change){u, text, note};
    return 0;
}

/* The clock from the speed and pause cues: pieces that start where the
 * previous one ends, the last one open. */
static int build_clock(struct sp_timeline *tl, double s0, double duration)
{
    struct sp_clock_piece open = {.s_a = s0, .s_b = s0};
    int ret = 0;
    tl->speed_min = tl->speed_max = s0;
    for (int i = 0; i < tl->n_cues && !ret; i++) {
        const struct sp_cue *c = &tl->cues[i];
        if (c->kind == SP_CUE_CAPTION)
            continue;
        tl->clocked = 1;
        const double du = piece_du(&open, c->t - open.t0), u = open.u0 + du;
        struct sp_clock_piece next;
        if (c->kind == SP_CUE_SPEED) {
            next = (struct sp_clock_piece){u, c->t, piece_speed(&open, du), c->value, 0, 0};
            tl->speed_min = fmin(tl->speed_min, c->value);
            tl->speed_max = fmax(tl->speed_max, c->value);
        } else {
            const int easing = du < ease_left(&open);
            next = (struct sp_clock_piece){u + c->value, c->t, easing ? open.s_a : open.s_b,
                                           open.s_b, easing ? open.x0 + du / E : 0, 0};
        }
        if (du > 0)
            ret = push_piece(tl, &open);
        if (!ret && c->kind == SP_CUE_PAUSE)
            ret = push_piece(tl, &(struct sp_clock_piece){.u0 = u, .t0 = c->t, .hold = 1});
        open = next;
    }
    if (!ret)
        ret = push_piece(tl, &open);
    tl->length = open.u0 + piece_du(&open, duration - open.t0);
    return ret;
}

/* The first video time at which the clock reaches simulated time t. */
static double first_u(const struct sp_timeline *tl, double t)
{
    int i = 0;
    for (; i + 1 < tl->n_pieces; i++) {
        const struct sp_clock_piece *p = &tl->pieces[i];
        if (p->hold ? p->t0 >= t : tl->pieces[i + 1].t0 >= t)
            break;
    }
    const struct sp_clock_piece *p = &tl->pieces[i];
    return p->hold ? p->u0 : p->u0 + piece_du(p, t - p->t0);
}

/* The caption band's schedule: each caption cue from where the clock
 * reaches it (after the pauses at the same time listed before it); a
 * pause's note from its start until it has time to give way to the
 * caption again before the pause ends. */
static int build_band(struct sp_timeline *tl, const char *caption)
{
    const char *in_force = caption;
    double held = 0, held_t = -1; /* video s of the pauses so far at time held_t */
    int ret = push_band(tl, 0, caption, 0);
    for (int i = 0; i < tl->n_cues && !ret; i++) {
        const struct sp_cue *c = &tl->cues[i];
        if (c->t != held_t)
            held = 0, held_t = c->t;
        const double u = first_u(tl, c->t) + held;
        if (c->kind == SP_CUE_CAPTION) {
            ret = push_band(tl, u, c->text, 0);
            in_force = c->text;
        } else if (c->kind == SP_CUE_PAUSE) {
            held += c->value;
            if (c->text[0] && !(ret = push_band(tl, u, c->text, 1)))
                ret = push_band(tl, u + c->value - fmin(2 * H, 0.5 * c->value), in_force, 0);
        }
    }
    return ret;
}

int sp_timeline_check(const struct sp_timeline *tl, const struct sp_scene *s)
{
    int errors = 0;
    for (int i = 0; i < tl->n_cues; i++) {
        const struct sp_cue *c = &tl->cues[i];
        if (c->t > s->video.duration) {
            report(tl->origin, c->line, "[timeline] time %.17g is beyond the end of the "
                   "video (video.duration = %g simulated s); allowed: 0 <= time <= %g",
                   c->t, s->video.duration, s->video.duration);
            errors++;
        }
    }
    return errors;
}

/* The frame times the clock makes, as the scene's own check counts
 * video.duration * video.fps / video.speed: at most SP_MAX_FRAMES (a slow
 * speed cue, 1e-7, made 3.9e8 s of video and a frame count past int's
 * range, printed negative by info: attack15 #2). Said at the slowest speed
 * cue's line (the first, if several); SP_E_INPUT. */
static int check_length(const struct sp_timeline *tl, const struct sp_scene *s)
{
    const double frames = tl->length * s->video.fps;
    if (!tl->clocked || frames <= SP_MAX_FRAMES)
        return 0;
    int line = tl->n_cues ? tl->cues[0].line : 0, longest = -1;
    double held = 0; /* video s the pauses hold */
    for (int i = tl->n_cues - 1; i >= 0; i--) {
        if (tl->cues[i].kind == SP_CUE_SPEED && tl->cues[i].value == tl->speed_min)
            line = tl->cues[i].line;
        if (tl->cues[i].kind == SP_CUE_PAUSE) {
            held += tl->cues[i].value;
            if (longest < 0 || tl->cues[i].value >= tl->cues[longest].value)
                longest = i;
        }
    }
    /* the advice that helps: the pauses where they hold most of it
     * (attack16 #5: "raise the slowest speed" for a video of pauses) */
    if (longest >= 0 && held >= 0.5 * tl->length) {
        report(tl->origin, tl->cues[longest].line, "[timeline] the speeds and pauses make the "
               "video %.4g s long at %g fps: %.3g frame times; at most %d are allowed (the "
               "pauses hold %.4g s of it; shorten them)", tl->length, s->video.fps, frames,
               SP_MAX_FRAMES, held);
        return SP_E_INPUT;
    }
    report(tl->origin, line, "[timeline] the speeds and pauses make the video %.4g s long at %g "
           "fps: %.3g frame times; at most %d are allowed (the slowest speed here is %g; raise it, "
           "or shorten video.duration)", tl->length, s->video.fps, frames, SP_MAX_FRAMES,
           tl->speed_min);
    return SP_E_INPUT;
}

int sp_timeline_plan(struct sp_timeline *tl, const struct sp_scene *s)
{
    for (int i = 0; i < tl->n_cues; i++)
        tl->cues[i].text = tl->pool + tl->cues[i].text_at; /* the pool no longer moves */
    free(tl->pieces); /* a second plan starts afresh */
    free(tl->band);
    tl->pieces = NULL, tl->band = NULL;
    tl->n_pieces = tl->n_band = tl->cap_pieces = tl->cap_band = 0;
    tl->clocked = 0;
    int ret = build_clock(tl, s->video.speed, s->video.duration);
    if (!ret)
        ret = build_band(tl, s->view.caption);
    if (ret) {
        sp_log_error("out of memory for the timeline");
        return ret;
    }
    return check_length(tl, s);
}

/* ---- what a frame shows ---- */

int sp_timeline_frames(const struct sp_scene *s)
{
    if (!s->timeline || !s->timeline->clocked)
        return sp_scene_frame_count(s);
    return (int)lround(s->timeline->length * s->video.fps);
}

double sp_timeline_length(const struct sp_scene *s)
{
    if (!s->timeline || !s->timeline->clocked)
        return s->video.duration / s->video.speed;
    return s->timeline->length;
}

/* The band at video time u: the text in force fades out (linearly in video
 * time, from its opacity then) over at most H, then the next fades in over
 * H; the shown opacity is q of that. */
static void band_at(const struct sp_timeline *tl, double u, struct sp_moment *m)
{
    const struct sp_band_change *shown = &tl->band[0], *target;
    int i = 1;
    while (i < tl->n_band && tl->band[i].u <= 0)
        shown = &tl->band[i++];
    target = shown;
    double a = shown->text[0] ? 1 : 0, last = 0;
    for (;; i++) {
        const double until = i < tl->n_band && tl->band[i].u <= u ? tl->band[i].u : u;
        double d = until - last;
        if (shown->note == target->note && !strcmp(shown->text, target->text)) {
            a = shown->text[0] ? fmin(1, a + d / H) : 0;
        } else if (a - d / H > 0) {
            a -= d / H;
        } else {
            d -= a * H;
            shown = target;
            a = shown->text[0] ? fmin(1, d / H) : 0;
        }
        last = until;
        if (!(i < tl->n_band && tl->band[i].u <= u))
            break;
        target = &tl->band[i];
    }
    m->band = shown->text;
    m->band_note = shown->note;
    m->band_alpha = (float)ease_q(a);
}

void sp_timeline_frame(const struct sp_scene *s, int k, struct sp_moment *m)
{
    const struct sp_timeline *tl = s->timeline;
    const double u = k / s->video.fps;
    *m = (struct sp_moment){.t = sp_scene_frame_time(s, k), .speed = s->video.speed,
                            .band = s->view.caption, .band_alpha = 1};
    if (!tl)
        return;
    if (tl->clocked) {
        int lo = 0, hi = tl->n_pieces - 1; /* the last piece starting at or before u */
        while (lo < hi) {
            const int mid = (lo + hi + 1) / 2;
            if (tl->pieces[mid].u0 <= u)
                lo = mid;
            else
                hi = mid - 1;
        }
        const struct sp_clock_piece *p = &tl->pieces[lo];
        const double du = u - p->u0;
        m->t = fmin(p->t0 + piece_dt(p, du), s->video.duration);
        m->speed = piece_speed(p, du);
        m->easing = !p->hold && du < ease_left(p);
    }
    band_at(tl, u, m);
}

void sp_timeline_still(const struct sp_scene *s, double t, struct sp_moment *m)
{
    const struct sp_timeline *tl = s->timeline;
    *m = (struct sp_moment){.t = t, .speed = s->video.speed, .band = s->view.caption,
                            .band_alpha = 1};
    if (!tl)
        return;
    if (tl->clocked && t <= s->video.duration) {
        const double u = first_u(tl, t);
        int i = 0; /* the last piece that moves and starts at or before u */
        for (int j = 1; j < tl->n_pieces && tl->pieces[j].u0 <= u; j++)
            if (!tl->pieces[j].hold)
                i = j;
        m->speed = piece_speed(&tl->pieces[i], u - tl->pieces[i].u0);
        m->easing = u - tl->pieces[i].u0 < ease_left(&tl->pieces[i]);
    } else if (tl->clocked) { /* past the video's end: the last speed holds */
        m->speed = tl->pieces[tl->n_pieces - 1].s_b;
    }
    for (int i = 0; i < tl->n_cues && tl->cues[i].t <= t; i++) {
        const struct sp_cue *c = &tl->cues[i];
        if (c->kind == SP_CUE_CAPTION)
            m->band = c->text, m->band_note = 0;
        if (c->kind == SP_CUE_PAUSE && c->t == t) {
            m->speed = 0, m->easing = 0;
            if (c->text[0])
                m->band = c->text, m->band_note = 1;
        }
    }
}

void sp_timeline_marker(const struct sp_moment *m, char *buf, size_t size)
{
    if (m->speed <= 0)
        snprintf(buf, size, "paused");
    else /* a real multiplication sign */
        snprintf(buf, size, "speed \xc3\x97%.3g", m->speed);
}
