/* springpend: a scene's [timeline], presentation keyed by simulated time:
 * captions that change, speed changes that ease, pauses with a note. Pure:
 * no fonts, no GL, no files. The scene parser (scene.c) reads the section
 * into cues; sp_timeline_plan turns them into the video's clock, which maps
 * every video time to one simulated time in closed form (no sums carried
 * from frame to frame, so no drift), and into the caption band's schedule.
 *
 * The clock. u runs in video seconds; the speed s (simulated s per video s)
 * starts at [video] speed. A cue `speed S` at simulated time T starts, at
 * the video time where the clock reaches T, an ease of E = SP_TIMELINE_EASE
 * video seconds from the speed at that moment, s0, to S:
 *     s(u) = s0 + (S - s0) * q((u - u_T) / E),  q(x) = 3x^2 - 2x^3 (0 <= x <= 1),
 * so the ease covers E * (s0 + S) / 2 simulated seconds; a later speed cue
 * inside an ease starts a new one from the speed reached. A cue `pause D` at
 * T holds the clock at T for D video seconds (an ease in progress resumes
 * after it). Simulated time is t(u) = the integral of s; the video is as
 * long as the clock takes to reach [video] duration, pauses included, and
 * has N = round(length * fps) frames, frame k at video time k / fps. A scene
 * without speed or pause cues keeps N = round(duration * fps / speed) and
 * t_k = k * speed / fps exactly. */
#ifndef SPRINGPEND_TIMELINE_H
#define SPRINGPEND_TIMELINE_H

#include <stddef.h>

struct sp_scene;

#define SP_TIMELINE_EASE 0.5   /* video s: a speed change eases over this */
#define SP_TIMELINE_FADE 0.25  /* video s: the caption band's text fades out,
                                  then the next one in, each over this */
#define SP_TIMELINE_MAX_CUES 1000

enum sp_cue_kind {
    SP_CUE_CAPTION, /* caption: TEXT  (text "" clears the caption) */
    SP_CUE_SPEED,   /* speed S        (value: simulated s per video s, > 0) */
    SP_CUE_PAUSE,   /* pause D[: NOTE] (value: video s held, > 0; text: the note or "") */
};

struct sp_cue {
    double t;              /* simulated s, 0 <= t <= [video] duration */
    enum sp_cue_kind kind;
    double value;          /* SPEED: the speed; PAUSE: video s held */
    const char *text;      /* CAPTION, PAUSE: UTF-8 in the timeline's pool, "" = none
                              (set by sp_timeline_plan) */
    size_t text_at;        /* where text starts in the pool */
    int line;              /* in the scene file, for messages */
};

/* One stretch of the clock: a hold, or the speed easing from s_a to s_b
 * (s_a == s_b: constant), entered at ease progress x0 (0..1). */
struct sp_clock_piece {
    double u0, t0;     /* video s and simulated s where it starts */
    double s_a, s_b;   /* simulated s per video s */
    double x0;         /* ease progress at u0 (0 for a constant speed) */
    int hold;          /* 1: a pause, t stays t0 */
};

/* The caption band's text in force from video time u on. */
struct sp_band_change {
    double u;          /* video s */
    const char *text;  /* "" = none */
    int note;          /* 1: a pause's note */
};

struct sp_timeline {
    char origin[256];          /* the scene file, for FILE:LINE messages */
    struct sp_cue *cues;       /* n_cues, in file order (= time order) */
    int n_cues, cap_cues;
    int cues_over;             /* lines past SP_TIMELINE_MAX_CUES (reported once) */
    char *pool;                /* the cues' texts, owned */
    size_t pool_used, pool_cap;
    double last_t;             /* the time on the last line read, s */
    int last_line;             /* that line, 0 = none yet */
    /* Derived by sp_timeline_plan: */
    struct sp_clock_piece *pieces; /* n_pieces, in video time order, owned */
    int n_pieces, cap_pieces;
    struct sp_band_change *band;   /* n_band, in video time order, owned */
    int n_band, cap_band;
    double length;             /* video s until the clock reaches the duration */
    int clocked;               /* 1: speed or pause cues (the clock is not k*speed/fps) */
    double speed_min, speed_max; /* simulated s per video s over the whole video */
};

/* What the timeline shows at one moment of the video. */
struct sp_moment {
    double t;            /* simulated s */
    double speed;        /* simulated s per video s now; 0 inside a pause */
    int easing;          /* 1: the speed is changing */
    const char *band;    /* the caption band's text, "" = none */
    float band_alpha;    /* its opacity, 0..1 */
    int band_note;       /* 1: the text is a pause's note */
};

/* Frees t's memory and sets *t to NULL. Safe on NULL. */
void sp_timeline_destroy(struct sp_timeline **t);

/* Reads one [timeline] line "TIME = VERB ..." of origin:line into tl
 * (created on first use), printing what is wrong as "ORIGIN:LINE: ..." to
 * stderr. Returns the number of problems reported (0 or 1), or SP_E_NOMEM. */
int sp_timeline_read(struct sp_timeline **tl, const char *origin, int line, const char *time,
                     const char *cue);

/* Checks the cues against the scene: every time within [video] duration.
 * Problems are printed as "ORIGIN:LINE: ..."; returns how many. */
int sp_timeline_check(const struct sp_timeline *tl, const struct sp_scene *s);

/* Builds the clock and the band's schedule of a checked timeline from
 * [video] speed and duration and [view] caption (the caption in force from
 * t = 0 until a caption cue). 0 or SP_E_NOMEM (logged). */
int sp_timeline_plan(struct sp_timeline *tl, const struct sp_scene *s);

/* The scene's video: frames, and the simulated time of frame k. Without a
 * clocked timeline these are sp_scene_frame_count and sp_scene_frame_time,
 * bit for bit. */
int sp_timeline_frames(const struct sp_scene *s);
double sp_timeline_length(const struct sp_scene *s); /* video s */

/* What frame k shows (k / fps video s into the video). */
void sp_timeline_frame(const struct sp_scene *s, int k, struct sp_moment *out);

/* What a still at simulated time t shows: the caption in force at t (a
 * pause's note when a pause is at t) at full opacity, the speed where the
 * video first reaches t (0 when a pause is at t). */
void sp_timeline_still(const struct sp_scene *s, double t, struct sp_moment *out);

/* The speed marker's text for m, e.g. "speed ×0.25" or "paused". */
void sp_timeline_marker(const struct sp_moment *m, char *buf, size_t size);

#endif
