/* springpend: the render pipeline. Owns the sim, trail, renderer and sink of
 * one run and drives them frame by frame. This thread advances the sim,
 * updates the frame model and renders each frame straight into a free slot
 * of a small bounded queue (no copy); an encoder thread takes the slots in
 * order and hands them to the sink. Both stages work at once; the slots
 * are allocated once, so memory does not grow with the video's length. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/clock.h"
#include "springpend/common.h"
#include "springpend/ensemble.h"
#include "springpend/figure.h"
#include "springpend/frame.h"
#include "springpend/outfile.h"
#include "springpend/pipeline.h"
#include "springpend/provenance.h"
#include "springpend/render.h"
#include "springpend/sink.h"
#include "springpend/timeline.h"
#include "base/command_line.h"
#include "base/signals.h"
#include "sim/sim_report.h"

#define QUEUE_SLOTS 4 /* frames in flight between render and encoder */

/* ---- the bounded queue ---- */

struct queue {
    pthread_mutex_t lock;
    pthread_cond_t changed;       /* a slot was filled or freed, or stop */
    struct sp_image slot[QUEUE_SLOTS]; /* owned pixels, allocated once */
    double slot_t[QUEUE_SLOTS];   /* simulated s each slot shows */
    int head, count;              /* filled slots: head .. head+count-1 */
    int closed;                   /* the producer is done */
    int cancel;                   /* the run failed: drop what is queued */
    int err;                      /* the consumer failed: stop producing */
    struct sp_sink *sink;         /* written by the consumer thread only */
    struct sp_provenance *prov;   /* the sink's text chunks: consumer only */
    double encode_s, idle_s;      /* consumer: time in the sink, waiting */
};

/* Encoder thread: writes filled slots in order until closed and empty. */
static void *consume(void *arg)
{
    struct queue *q = arg;
    pthread_mutex_lock(&q->lock);
    for (;;) {
        double t0 = sp_clock_s();
        while (!q->count && !q->closed)
            pthread_cond_wait(&q->changed, &q->lock);
        q->idle_s += sp_clock_s() - t0;
        if (!q->count || q->cancel)
            break;
        struct sp_image *img = &q->slot[q->head];
        sp_provenance_set_time(q->prov, q->slot_t[q->head]);
        pthread_mutex_unlock(&q->lock);
        t0 = sp_clock_s();
        int err = sp_sink_write(q->sink, img); /* logs its own failure */
        double dt = sp_clock_s() - t0;
        pthread_mutex_lock(&q->lock);
        q->encode_s += dt;
        q->head = (q->head + 1) % QUEUE_SLOTS;
        q->count--;
        if (err) {
            q->err = err;
            q->count = 0; /* drop the rest */
        }
        pthread_cond_broadcast(&q->changed);
        if (err)
            break;
    }
    pthread_mutex_unlock(&q->lock);
    return NULL;
}

/* Waits for the next free slot and returns it (the producer's to fill), or
 * NULL with *err set if the consumer failed. *wait_s grows by the wait. */
static struct sp_image *acquire(struct queue *q, int *err, double *wait_s)
{
    double t0 = sp_clock_s();
    pthread_mutex_lock(&q->lock);
    while (q->count == QUEUE_SLOTS && !q->err)
        pthread_cond_wait(&q->changed, &q->lock);
    *err = q->err;
    struct sp_image *slot = &q->slot[(q->head + q->count) % QUEUE_SLOTS];
    pthread_mutex_unlock(&q->lock);
    *wait_s += sp_clock_s() - t0;
    return *err ? NULL : slot;
}

/* Hands the slot acquire returned, showing simulated time t, s, to the
 * consumer. */
static void publish(struct queue *q, double t)
{
    pthread_mutex_lock(&q->lock);
    q->slot_t[(q->head + q->count) % QUEUE_SLOTS] = t;
    q->count++; /* only the producer adds, so the slot is still ours */
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
}

/* ---- progress and stage times ---- */

static void show_progress(int done, int total, double t0)
{
    double el = sp_clock_s() - t0, fps = el > 0 ? done / el : 0;
    double eta = fps > 0 ? (total - done) / fps : 0;
    char bar[31];
    int fill = total ? (int)(30L * done / total) : 30;
    memset(bar, '#', (size_t)fill);
    memset(bar + fill, '.', (size_t)(30 - fill));
    bar[30] = '\0';
    fprintf(stderr, "\r[%s] frame %d/%d  %.1f fps  ETA %.0f s ", bar, done,
            total, fps, eta);
    if (done == total)
        fputc('\n', stderr);
}

struct stage_times {
    double sim, render, wait;       /* s, this thread */
    double setup, finish, total;    /* s */
};

static void print_times(const struct stage_times *t, const struct queue *q,
                        const struct sp_render_stats *rs, int frames)
{
    double per = frames > 0 ? 1e3 / frames : 0;
    fprintf(stderr,
            "stage times for %d frames (s total, ms per frame):\n"
            "  setup (camera pre-pass, GL, encoder)  %7.3f\n"
            "  render thread: sim + frame model      %7.3f  %6.2f\n"
            "  render thread: compose draw list      %7.3f  %6.2f\n"
            "  render thread: GL draw + readback     %7.3f  %6.2f\n"
            "  render thread: waiting for a slot     %7.3f  %6.2f\n"
            "  encoder thread: convert + encode/write %6.3f  %6.2f\n"
            "  encoder thread: waiting for a frame   %7.3f  %6.2f\n"
            "  finish (flush, trailer, rename)       %7.3f\n"
            "  wall                                  %7.3f  (%.1f fps)\n",
            frames, t->setup, t->sim, t->sim * per, rs->compose_s, rs->compose_s * per,
            t->render - rs->compose_s, (t->render - rs->compose_s) * per,
            t->wait, t->wait * per, q->encode_s,
            q->encode_s * per, q->idle_s, q->idle_s * per, t->finish, t->total,
            t->total > 0 ? frames / t->total : 0);
    fprintf(stderr, "  text: %d glyphs rasterised in %.2f ms, %d of them (%.2f ms) by the first frame\n",
            rs->glyphs, 1e3 * rs->raster_s, rs->glyphs_first, 1e3 * rs->raster_first_s);
    fprintf(stderr, "  text: %d lines shaped by HarfBuzz, %d joined from cached pieces\n",
            rs->lines_shaped, rs->lines_composed);
    fprintf(stderr, "  static layer cached in %ld frames (drawn %ld time%s), uncached in %ld\n"
            "  settled chart curves appended to it in %ld frames\n"
            "  dynamic items left as the last frame drew them: %ld\n",
            rs->cached, rs->redrawn, rs->redrawn == 1 ? "" : "s", rs->uncached, rs->appended,
            rs->unchanged);
}

/* ---- the run ---- */

int sp_pipeline_shard(int n_frames, int i, int n, int *first, int *last)
{
    if (n < 1 || i < 0 || i >= n || n > n_frames) {
        sp_log_error("shard %d/%d: need 0 <= I < N <= %d (the video's frames)",
                     i, n, n_frames);
        return SP_E_INPUT;
    }
    *first = (int)((long)n_frames * i / n);
    *last = (int)((long)n_frames * (i + 1) / n);
    return 0;
}

/* One run: what sp_pipeline_run's steps share. */
struct run {
    const struct sp_pipeline_desc *desc;
    const struct sp_scene *sc;
    int n;                       /* the video's frames */
    int first, last;             /* frames [first, last) are written */
    int w, h;                    /* px */
    int figure;                  /* a still to .svg or .pdf: cairo, no GL */
    int substeps;                /* trail samples per frame */
    struct sp_view_extent extent;
    struct sp_sim sim;
    struct sp_trail trail;
    struct sp_history hist;
    struct sp_ensemble *ens;     /* NULL: one pendulum */
    struct sp_renderer *r;
    struct sp_provenance prov;
    struct sp_sink *sink;
    struct sp_image img;         /* a still's frame, the renderer's */
    struct queue q;              /* video: frames between render and encoder */
    pthread_t encoder;
    int encoder_running;
    int signals_held;            /* desc->handle_signals: signals.h's hold */
    struct sp_signals_saved saved_signals;
    int emitted;                 /* frames handed to the encoder */
    int stop_said;               /* 1: an interruption is said already */
    struct stage_times tm;
    double t_start;              /* s, monotonic */
    struct sp_moment moment;     /* what the frame being drawn shows (timeline.h) */
    double followed_t;           /* s: the last frame time followed; < 0 = none */
    double t_last;               /* s: side by side, the last frame time of this
                                    scene's own video (it holds that frame after) */
    /* side by side: the scenes beside the first, each with its own motion */
    struct cell {
        const struct sp_scene *sc;
        double t_last;           /* s: its own video's last frame time */
        int substeps;
        struct sp_sim sim;
        struct sp_trail trail;
        struct sp_history hist;
        double followed_t;       /* s; < 0 = none */
    } more[SP_PIPELINE_MAX_SCENES - 1];
    int n_more;
    int compose_refused;         /* 1: the PNG's frame was refused as composed
                                    (its title or caption cannot fit, ...) */
    struct sp_look looks[SP_PIPELINE_MAX_SCENES]; /* side by side: each cell's look */
    char labels[SP_PIPELINE_MAX_SCENES][SP_VIEW_TEXT_BYTES];
    char label_what[SP_PIPELINE_MAX_SCENES][320]; /* for messages about a label */
};

/* The fields of the frame that run's sim, trail and histories are at. */
#define FRAME_OF(run)                                                                    \
    .state = (run)->sim.s, .params = &(run)->sim.p, .trail = &(run)->trail,              \
    .history = &(run)->hist, .ensemble = (run)->ens, .moment = &(run)->moment,           \
    .work = (run)->sim.work, .energy0 = (run)->sim.energy0

/* The frames run shows at simulated time t, s: the first scene's, then, side
 * by side, each other's (a scene past its own end holds its last frame,
 * marked as ended). Returns frames. */
static struct sp_frame *frames_of(struct run *run, double t, struct sp_frame *frames)
{
    frames[0] = (struct sp_frame){FRAME_OF(run), .ended = run->n_more && t > run->t_last + 1e-9};
    for (int i = 0; i < run->n_more; i++) {
        struct cell *cl = &run->more[i];
        frames[i + 1] = (struct sp_frame){.state = cl->sim.s, .params = &cl->sim.p,
                                          .trail = &cl->trail, .history = &cl->hist,
                                          .work = cl->sim.work, .energy0 = cl->sim.energy0,
                                          .ended = t > cl->t_last + 1e-9};
    }
    return frames;
}

/* The signal that stops a render which holds the signals (signals.h): it
 * keeps the frames so far. 0 = none, or not held. */
static int stopped(const struct run *run)
{
    return run->signals_held ? sp_signal_seen() : 0;
}

/* The frame range, checked before anything is set up. */
static int run_check(const struct run *run)
{
    if (run->first < 0 || run->last > run->n || run->first >= run->last) {
        sp_log_error("frames %d:%d: the video has frames 0:%d; give A:B with "
                     "0 <= A < B <= %d", run->first, run->last, run->n, run->n);
        return SP_E_INPUT;
    }
    return 0;
}

/* Widens a (scene sa's extent) to hold b (scene sb's) too: one camera and one
 * set of chart axes for scenes side by side. The energy charts' and bars'
 * gravity zero goes to the lower of the two lowest points, their axes up by
 * what that adds to gravity's and the total's energy. */
static void extent_union(struct sp_view_extent *a, const struct sp_scene *sa,
                         const struct sp_view_extent *b, const struct sp_scene *sb)
{
    struct sp_range *ra[] = {&a->r, &a->theta, &a->r_dot, &a->theta_dot, &a->modes};
    const struct sp_range *rb[] = {&b->r, &b->theta, &b->r_dot, &b->theta_dot, &b->modes};
    for (int i = 0; i < 5; i++)
        *ra[i] = (struct sp_range){fmin(ra[i]->lo, rb[i]->lo), fmax(ra[i]->hi, rb[i]->hi)};
    a->xmin = fmin(a->xmin, b->xmin), a->xmax = fmax(a->xmax, b->xmax);
    a->ymin = fmin(a->ymin, b->ymin), a->ymax = fmax(a->ymax, b->ymax);
    a->zmin = fmin(a->zmin, b->zmin), a->zmax = fmax(a->zmax, b->zmax);
    a->max_speed = fmax(a->max_speed, b->max_speed);
    a->max_accel = fmax(a->max_accel, b->max_accel);
    a->max_force = fmax(a->max_force, b->max_force);
    a->t_end = fmax(a->t_end, b->t_end);
    const double low = fmin(a->y_low, b->y_low);
    const double wa = sa->pendulum.mass * sa->pendulum.gravity, wb = sb->pendulum.mass * sb->pendulum.gravity;
    a->bars = (struct sp_range){fmin(a->bars.lo, b->bars.lo),
                                fmax(a->bars.hi + wa * (a->y_low - low), b->bars.hi + wb * (b->y_low - low))};
    a->energy = (struct sp_range){fmin(a->energy.lo, b->energy.lo),
                                  fmax(a->energy.hi + wa * (a->y_low - low),
                                       b->energy.hi + wb * (b->y_low - low))};
    a->y_low = low;
}

/* A trail for scene sc in a video of n frames, frame_dt simulated s apart
 * (slow: how much a timeline's slowest speed stretches them), sampled
 * `substeps` times a frame, held to about 100 MB; *used gets the substeps
 * kept. 0 or SP_E_NOMEM. */
static int trail_setup(struct sp_trail *tr, int *used, const struct sp_scene *sc, int n,
                       int substeps, double frame_dt, double slow)
{
    const int trail_frames = sc->view.trail == SP_TRAIL_ALL ? n + 1
                           : sc->view.trail == SP_TRAIL_DURATION
                               ? (int)fmin(ceil(sc->view.trail_duration / frame_dt * slow) + 1, n + 1)
                           : slow > 1 ? (int)fmin(ceil((sc->view.trail - 1) * slow) + 1, n + 1)
                               : sc->view.trail;
    if ((double)trail_frames * substeps > 4e6) /* about 100 MB of trail at most */
        substeps = (int)fmax(1, 4e6 / fmax(trail_frames, 1));
    *used = substeps;
    return sp_trail_make(tr, trail_frames ? (trail_frames - 1) * substeps + 1 : 0);
}

/* Side by side: each cell's look, titled with its scene's view.title or,
 * without one, the keys in which the scenes differ ("stiffness = 5,
 * damping = 0.4"; [video] and [view] keys aside), else its name; those keys
 * go to its HUD too (look.differs). */
static void cell_looks(struct run *run)
{
    const struct sp_scene *all[SP_PIPELINE_MAX_SCENES] = {run->sc};
    char *text[SP_PIPELINE_MAX_SCENES] = {0};
    const int n = 1 + run->n_more;
    for (int i = 1; i < n; i++)
        all[i] = run->more[i - 1].sc;
    for (int i = 0; i < n; i++) {
        const int len = sp_scene_canonical(all[i], NULL, 0);
        text[i] = malloc((size_t)len + 1);
        if (text[i])
            sp_scene_canonical(all[i], text[i], (size_t)len + 1);
    }
    for (int i = 0; i < n; i++) {
        char *label = run->labels[i];
        size_t used = 0;
        label[0] = 0;
        /* Lines are matched by key, not by position: optional keys (the
         * [view] style keys, the camera) appear only when set, so the same
         * line number may hold different keys in two scenes. */
        for (const char *line = text[i]; line && *line;
             line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
            const size_t len = strcspn(line, "\n");
            const char *eq = memchr(line, '=', len);
            if (!eq)
                continue;
            const size_t klen = (size_t)(eq - line) + 1; /* "section.key=" */
            int differs = 0;
            for (int j = 0; j < n && !differs; j++) {
                const char *q = text[j];
                while (q && *q && !(strncmp(q, line, klen) == 0))
                    q = strchr(q, '\n') ? strchr(q, '\n') + 1 : NULL;
                differs = !q || !*q || strcspn(q, "\n") != len || strncmp(q, line, len);
            }
            if (!differs || !strncmp(line, "video.", 6) || !strncmp(line, "view.", 5))
                continue;
            char key[128], value[256], shown[256];
            if ((size_t)(eq - line) >= sizeof(key))
                continue;
            snprintf(key, sizeof(key), "%.*s", (int)(eq - line), line);
            snprintf(value, sizeof(value), "%.*s", (int)(len - (size_t)(eq + 1 - line)), eq + 1);
            sp_scene_canonical_display(key, value, shown, sizeof(shown));
            if (used < SP_VIEW_TEXT_BYTES)
                used += (size_t)snprintf(label + used, SP_VIEW_TEXT_BYTES - used, "%s%s = %s",
                                         used ? ", " : "", strchr(key, '.') + 1, shown);
        }
        sp_look_of(all[i], &run->looks[i]);
        snprintf(run->looks[i].differs, sizeof(run->looks[i].differs), "%s", label);
        if (!label[0])
            sp_text_shown(all[i]->name, 0, label, SP_VIEW_TEXT_BYTES); /* no control byte */
        if (!run->looks[i].view.title[0]) {
            run->looks[i].view.title = label; /* run->labels: lives as long as the looks */
            snprintf(run->label_what[i], sizeof(run->label_what[i]),
                     "%s: the side-by-side cell's automatic label (the keys its scene changes; "
                     "[view] title sets another)", all[i]->name);
            run->looks[i].title_what = run->label_what[i];
        }
    }
    for (int i = 0; i < n; i++)
        free(text[i]);
}

/* The camera pre-pass: run->extent, fitted to the whole motion of every
 * scene (the ensemble's members and the side-by-side cells too). 0, or
 * the first failure (said). */
static int measure_extent(struct run *run)
{
    const struct sp_pipeline_desc *desc = run->desc;
    const struct sp_scene *sc = run->sc;
    int ret;
    /* A still past the video's end still fits its camera to the whole
     * motion; a frame range fits the whole video's, so shards match. */
    struct sp_moment last;
    sp_timeline_frame(sc, run->n - 1, &last);
    double t_end = last.t;
    if (desc->still)
        t_end = fmax(desc->still_at, t_end);

    sp_progress_begin(desc->progress, "camera pre-pass", t_end);
    ret = sp_view_extent_measure(sc, t_end, sp_signal_flag(), sp_progress_sim, NULL, &run->extent);
    sp_progress_end();
    if (!ret && sc->ensemble.count > 1) { /* widens the extent by every member's motion */
        sp_progress_begin(desc->progress, "ensemble pre-pass", t_end);
        ret = sp_ensemble_make(&run->ens, sc, t_end, sp_signal_flag(), sp_progress_sim, NULL,
                               &run->extent);
        sp_progress_end();
    }
    for (int i = 0; !ret && i < run->n_more; i++) { /* one camera and one set of axes */
        struct sp_view_extent e;
        const struct sp_scene *o = run->more[i].sc;
        ret = sp_view_extent_measure(o, run->more[i].t_last, sp_signal_flag(), sp_progress_sim,
                                     NULL, &e);
        if (!ret)
            extent_union(&run->extent, sc, &e, o);
    }
    return ret;
}

/* Signals, the camera pre-pass, the sim, trail and histories; then, unless
 * a figure, the renderer, provenance and sink. */
static int run_setup(struct run *run)
{
    const struct sp_pipeline_desc *desc = run->desc;
    const struct sp_scene *sc = run->sc;
    const int n = run->n, w = run->w, h = run->h;
    int ret;
    if (desc->handle_signals) {
        /* From the start: a signal during setup stops before frame one. */
        sp_signals_hold(&run->saved_signals, sp_outfile_remove_parts);
        run->signals_held = 1;
    }
    if ((ret = measure_extent(run)) != 0)
        return ret;
    const struct sp_view_extent extent = run->extent;
    /* The trail is sampled between frames finely enough that its chords stay
     * within half a pixel: at most the top speed times the fastest angular
     * frequency of acceleration, at the largest scale the camera can have. */
    sp_sim_init(&run->sim, sc);
    run->sim.cancel = sp_signal_flag();
    run->sim.progress = sp_progress_sim;
    /* A timeline's speeds: the fastest sets the substeps, the slowest how
     * many frames the trail's simulated span can take. */
    const struct sp_timeline *tl = sc->timeline;
    const double frame_dt = sc->video.speed / sc->video.fps;
    const double dt_max = tl && tl->clocked ? tl->speed_max / sc->video.fps : frame_dt;
    const double slow = tl && tl->clocked ? sc->video.speed / tl->speed_min : 1;
    const int ss = desc->supersample > 1 ? desc->supersample : 1;
    const double px_per_m = /* the largest scale the camera can have */
        ss * fmin(w / fmax(extent.xmax - extent.xmin, 1e-9), h / fmax(extent.ymax - extent.ymin, 1e-9));
    int substeps = sp_trail_substeps(dt_max, extent.max_speed * sp_params_omega_max(&run->sim.p),
                                     px_per_m);
    /* a still past the video's end: its frames go on (still_past_end), a
     * trail = all holds them too, at most 4e6 */
    const double n_at = desc->still ? fmin(floor(desc->still_at / frame_dt) + 1, 4e6) : 0;
    ret = trail_setup(&run->trail, &run->substeps, sc, (int)fmax(n, n_at), substeps, frame_dt, slow);
    if (!ret)
        ret = sp_history_make(&run->hist, sc);
    for (int i = 0; !ret && i < run->n_more; i++) { /* the others, as the first */
        struct cell *cl = &run->more[i];
        sp_sim_init(&cl->sim, cl->sc);
        cl->sim.cancel = sp_signal_flag();
        cl->sim.progress = sp_progress_sim;
        ret = trail_setup(&cl->trail, &cl->substeps, cl->sc, n,
                          sp_trail_substeps(frame_dt, extent.max_speed * sp_params_omega_max(&cl->sim.p),
                                            px_per_m),
                          frame_dt, 1);
        if (!ret)
            ret = sp_history_make(&cl->hist, cl->sc);
    }
    sp_look_of(sc, &run->looks[0]);
    if (run->n_more)
        cell_looks(run);
    for (int i = 0; i <= run->n_more; i++) { /* a still of physical size: px per pt */
        run->looks[i].pt_px = desc->pt_px;
        run->looks[i].still = desc->still;
    }
    if (ret || run->figure)
        return ret;
    ret = sp_render_make(&run->r, &(struct sp_render_desc){
        .width = w, .height = h, .extent = extent, .gl = desc->gl,
        .look = &run->looks[0], .supersample = desc->supersample,
        .cells = 1 + run->n_more, .looks = run->looks});
    run->compose_refused = ret == SP_E_INPUT;
    if (ret || (ret = sp_provenance_init(&run->prov, desc->recorded ? desc->recorded : sc,
                                         sp_render_renderer_name(run->r),
                                         sp_render_gl_version(run->r))) != 0)
        return ret;
    if (desc->piece) { /* a video piece records the part it holds */
        char *piece = sp_command_line_piece();
        ret = piece ? sp_provenance_set_command(&run->prov, piece) : SP_E_NOMEM;
        if (!piece)
            sp_log_error("out of memory");
        free(piece);
    }
    for (int i = 0; !ret && i < run->n_more; i++) /* side by side: every scene */
        ret = sp_provenance_add_scene(&run->prov, run->more[i].sc);
    if (ret)
        return ret;
    return sp_sink_open(&run->sink, &(struct sp_sink_desc){
        .path = desc->output, .format = desc->format, .width = w,
        .height = h, .fps = sc->video.fps, .first_frame = run->first,
        .partner = desc->write_partner ? desc->partner : NULL,
        .whole = !desc->part && !desc->still,
        .alpha = sc->view.background == SP_BACKGROUND_TRANSPARENT,
        .png_level = sc->video.png_level, .dpi = desc->pt_px * 72,
        .crf = sc->video.crf, .preset = sp_scene_preset_name(sc),
        .text = run->prov.text,
        .n_text = SP_PROVENANCE_N_TEXT + run->n_more +
                  (run->n_more || sc->view.vectors || sc->view.panels & SP_PANEL_ENERGY_BARS ||
                   sp_scene_perspective(sc))});
}

/* The sim, trail, histories and ensemble to t_target, s; the sim's blow-up
 * is worded here (the ensemble words its own). A frame at the time the
 * last one showed (inside a pause) adds nothing. */
static int run_follow(struct run *run, double t_target)
{
    int ret = 0;
    for (int i = 0; !ret && i < run->n_more; i++) { /* each to its own end, then held */
        struct cell *cl = &run->more[i];
        const double t = fmin(t_target, cl->t_last);
        if (t == cl->followed_t)
            continue;
        cl->followed_t = t;
        ret = sp_trail_follow(&cl->trail, &cl->hist, &cl->sim, t, cl->substeps);
        if (ret == SP_E_UNSTABLE)
            sp_sim_explain(&cl->sim);
    }
    if (run->n_more)
        t_target = fmin(t_target, run->t_last);
    if (ret || t_target == run->followed_t)
        return ret;
    run->followed_t = t_target;
    ret = sp_trail_follow(&run->trail, &run->hist, &run->sim, t_target, run->substeps);
    if (ret == SP_E_UNSTABLE)
        sp_sim_explain(&run->sim);
    if (!ret && run->ens)
        ret = sp_ensemble_advance(run->ens, run->sim.s.t);
    return ret;
}

/* A still past the video's last frame (at t_last, speed simulated s per
 * video s): the frames go on at that speed, so the trail holds the frame
 * times before `at` as a longer video's would (attack15 #9: past the end it
 * held none and was not drawn). The sim jumps to a trail's length (and a
 * frame) before `at`; from there on each frame is followed. */
static int still_past_end(struct run *run, double at, double t_last, double speed)
{
    const double dt = speed / run->sc->video.fps;
    const double after = floor((at - t_last) / dt * (1 + 1e-12)); /* frames past the last */
    const double window = run->substeps > 0 ? run->trail.capacity / run->substeps + 2 : 2;
    int ret = 0;
    for (double k = fmax(1, after - window); !ret && k <= after; k++)
        ret = run_follow(run, t_last + k * dt);
    return ret;
}

/* A still: the sim to still_at, the trail holding the video's frame
 * positions before it (past its end, still_past_end's). The progress
 * line stays up (run_close ends it). */
static int run_still_follow(struct run *run)
{
    const struct sp_scene *sc = run->sc;
    const double at = run->desc->still_at;
    int ret, k;
    sp_progress_begin(run->desc->progress, "integrating", at);
    for (k = 0; k < run->n; k++) {
        sp_timeline_frame(sc, k, &run->moment);
        if (run->moment.t > at)
            break;
        ret = run_follow(run, run->moment.t);
        if (ret)
            return ret;
    }
    if (k == run->n && run->n > 0 && at > run->moment.t && !run->n_more &&
        (ret = still_past_end(run, at, run->moment.t, run->moment.speed)) != 0)
        return ret;
    sp_timeline_still(sc, at, &run->moment);
    return run_follow(run, at); /* nothing when it is there already */
}

/* A still to .svg or .pdf, composed and drawn with cairo; sp_figure_write
 * writes it whole, so run_finish does not follow. */
static int run_figure(struct run *run)
{
    struct sp_frame frames[SP_PIPELINE_MAX_SCENES];
    int ret = run_still_follow(run);
    if (!ret && run->desc->write_partner)
        ret = run->desc->write_partner(run->desc->partner_ctx, &run->sim.s, run->desc->partner);
    if (ret)
        return ret;
    /* provenance, as a PNG's (NULL: none) */
    char *ini = sp_scene_ini(run->desc->recorded ? run->desc->recorded : run->sc);
    char *command = sp_command_line_unnamed();
    ret = sp_figure_write(&(struct sp_figure_desc){
        .width = run->w, .height = run->h, .extent = run->extent, .look = &run->looks[0],
        .page_w = run->desc->pt_px > 0 ? run->desc->page_w : 0,
        .page_h = run->desc->pt_px > 0 ? run->desc->page_h : 0,
        .title = run->sc->name, .path = run->desc->output, .cells = 1 + run->n_more,
        .looks = run->looks, .scene_file = ini, .command = command,
        .cancel = sp_signal_flag(),
        .partner = run->desc->write_partner ? run->desc->partner : NULL},
        frames_of(run, run->desc->still_at, frames));
    free(ini);
    free(command);
    return ret;
}

/* A still PNG: one frame drawn and handed to the sink. */
static int run_still(struct run *run)
{
    int ret = run_still_follow(run);
    if (ret)
        return ret;
    sp_progress_end();
    sp_provenance_set_time(&run->prov, run->sim.s.t);
    /* A sink that takes only YUV (raw yuv420p) gets the renderer's planes. */
    if (sp_sink_image_format(run->sink) == SP_IMAGE_YUV420 &&
        ((ret = sp_image_alloc_yuv420(&run->q.slot[0], run->w, run->h)) != 0 ||
         (ret = sp_render_target(run->r, &run->q.slot[0])) != 0))
        return ret;
    struct sp_frame frames[SP_PIPELINE_MAX_SCENES];
    ret = sp_render_draw(run->r, frames_of(run, run->desc->still_at, frames), &run->img);
    sp_render_fonts(run->r, run->prov.fonts, sizeof(run->prov.fonts));
    sp_render_overlay(run->r, run->prov.overlay, sizeof(run->prov.overlay));
    if (!ret)
        ret = sp_render_font_environment(run->r, run->prov.environment,
                                         sizeof(run->prov.environment));
    if (!ret)
        ret = sp_sink_write(run->sink, &run->img);
    return ret;
}

/* The render stage: the frame the sim, trail and histories are at, drawn
 * into the queue's slot. */
static int render_frame(struct run *run, struct sp_image *slot)
{
    struct sp_renderer *r = run->r;
    int ret = sp_render_target(r, slot);
    struct sp_frame frames[SP_PIPELINE_MAX_SCENES];
    if (!ret)
        ret = sp_render_draw(r, frames_of(run, run->moment.t, frames), &run->img);
    return ret;
}

/* The video: an encoder thread, then frame by frame: advance the sim to t_k
 * -> update the frame model -> render into a free slot -> publish it to the
 * encoder. A first signal ends the loop with the frames so far (returns 0:
 * run_finish keeps them). */
static int run_video(struct run *run)
{
    const struct sp_scene *sc = run->sc;
    struct queue *q = &run->q;
    struct stage_times *tm = &run->tm;
    int ret;
    /* In the format the sink takes best: a video encoder's YUV planes come
     * out of the renderer's last pass, 1.5 bytes a pixel. */
    const int yuv = sp_sink_image_format(run->sink) == SP_IMAGE_YUV420;
    for (int i = 0; i < QUEUE_SLOTS; i++) {
        ret = yuv ? sp_image_alloc_yuv420(&q->slot[i], run->w, run->h)
                  : sp_image_alloc(&q->slot[i], run->w, run->h);
        if (ret)
            return ret;
    }
    q->sink = run->sink;
    q->prov = &run->prov;
    if (pthread_create(&run->encoder, NULL, consume, q) != 0) {
        sp_log_error("cannot start the encoder thread");
        return SP_E_NOMEM;
    }
    run->encoder_running = 1;
    tm->setup = sp_clock_s() - run->t_start;

    const double t0 = sp_clock_s();
    for (int k = 0; k < run->last && !stopped(run); k++) {
        double ts = sp_clock_s();
        sp_timeline_frame(sc, k, &run->moment);
        ret = run_follow(run, run->moment.t);
        if (ret == SP_E_INTERRUPTED && stopped(run))
            break; /* keep the frames so far, in run_finish */
        if (ret)
            return ret;
        tm->sim += sp_clock_s() - ts;
        if (k < run->first)
            continue; /* frames before the range only feed trail and histories */
        struct sp_image *slot = acquire(q, &ret, &tm->wait);
        if (!slot)
            return ret;
        ts = sp_clock_s();
        ret = render_frame(run, slot);
        if (ret)
            return ret;
        if (!run->emitted) { /* before the encoder thread reads them, and fixed after */
            sp_render_fonts(run->r, run->prov.fonts, sizeof(run->prov.fonts));
            sp_render_overlay(run->r, run->prov.overlay, sizeof(run->prov.overlay));
            if ((ret = sp_render_font_environment(run->r, run->prov.environment,
                                                  sizeof(run->prov.environment))) != 0)
                return ret;
        }
        tm->render += sp_clock_s() - ts;
        publish(q, run->sim.s.t);
        run->emitted++;
        if (run->desc->progress && isatty(2) && (run->emitted % 10 == 0 || k == run->last - 1))
            show_progress(run->emitted, run->last - run->first, t0);
    }
    return 0;
}

/* Drains the encoder, closes the sink (the file appears whole), says what a
 * signal kept and prints the stage times. */
static int run_finish(struct run *run)
{
    const struct sp_pipeline_desc *desc = run->desc;
    struct queue *q = &run->q;
    int ret;
    if (run->encoder_running) {
        pthread_mutex_lock(&q->lock);
        q->closed = 1;
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
        pthread_join(run->encoder, NULL);
        run->encoder_running = 0;
        ret = q->err;
        if (ret == SP_E_INTERRUPTED && run->emitted) /* a frame's FIFO waited for a reader */
            sp_log_error("interrupted by %s while an output waited: the frames written are "
                         "removed", sp_signal_name(sp_signal_seen())), run->stop_said = 1;
        if (ret)
            return ret;
    }
    const double t0 = sp_clock_s();
    if (stopped(run) && desc->progress && isatty(2))
        fputc('\n', stderr);
    if (stopped(run) && !run->emitted && !desc->still)
        return SP_E_INTERRUPTED; /* said by run_close, which aborts the sink */
    /* a still's --state: written now, put in place with the image */
    if (desc->write_partner &&
        (ret = desc->write_partner(desc->partner_ctx, &run->sim.s, desc->partner)) != 0)
        return ret; /* run_close aborts the sink */
    ret = sp_sink_close(&run->sink);
    if (ret == SP_E_INTERRUPTED) /* a frame's FIFO waited for a reader */
        sp_log_error("interrupted by %s while an output waited: the frames written are "
                     "removed", sp_signal_name(sp_signal_seen())), run->stop_said = 1;
    run->tm.finish = sp_clock_s() - t0;
    run->tm.total = sp_clock_s() - run->t_start;
    if (!ret && stopped(run)) {
        sp_log_error("interrupted by %s: kept the %d frame%s rendered so far "
                     "in %s", sp_signal_name(stopped(run)), run->emitted,
                     run->emitted == 1 ? "" : "s", desc->output);
        ret = SP_E_INTERRUPTED;
    }
    if (desc->verbose && !desc->still) {
        struct sp_render_stats rs;
        sp_render_stats(run->r, &rs);
        print_times(&run->tm, q, &rs, run->emitted);
    }
    return ret;
}

/* Whatever the outcome ret: says an interruption that kept nothing, stops
 * the encoder, aborts a sink still open (its .part goes), restores the
 * signals and frees everything. */
static void run_close(struct run *run, int ret)
{
    struct queue *q = &run->q;
    sp_progress_end();
    if (ret == SP_E_INTERRUPTED && !run->stop_said && sp_outfile_write_was_stopped()) {
        /* raw frames, a still or a figure through a FIFO whose reader did not read */
        sp_log_error("interrupted by %s while %s waited for its reader: what went through "
                     "it stops short", sp_signal_name(sp_signal_seen()), run->desc->output);
    } else if (ret == SP_E_INTERRUPTED && !run->stop_said && !run->emitted) {
        sp_log_error("interrupted by %s before the first frame: nothing written",
                     sp_signal_name(sp_signal_seen()));
    }
    if (run->encoder_running) {
        pthread_mutex_lock(&q->lock);
        q->closed = q->cancel = 1;
        pthread_cond_broadcast(&q->changed);
        pthread_mutex_unlock(&q->lock);
        pthread_join(run->encoder, NULL);
    }
    sp_sink_abort(&run->sink);
    if (run->r)
        sp_render_target(run->r, NULL); /* before the slots go */
    if (run->signals_held)
        sp_signals_release(&run->saved_signals);
    for (int i = 0; i < QUEUE_SLOTS; i++)
        sp_image_free(&q->slot[i]);
    sp_render_destroy(&run->r);
    sp_trail_destroy(&run->trail);
    sp_history_destroy(&run->hist);
    for (int i = 0; i < run->n_more; i++) {
        sp_trail_destroy(&run->more[i].trail);
        sp_history_destroy(&run->more[i].hist);
    }
    sp_ensemble_destroy(&run->ens);
    sp_provenance_free(&run->prov);
}

/* A still of physical size refused while composed (its panels cannot hold
 * their texts, a label cannot fit): says what would fit, laid out again
 * with the frame it refused (sp_figure_fit_advise). */
static void advise_fit(struct run *run)
{
    const struct sp_pipeline_desc *d = run->desc;
    struct sp_frame frames[SP_PIPELINE_MAX_SCENES];
    sp_progress_end();
    sp_figure_fit_advise(&(struct sp_figure_fit){
        .page_w = d->page_w, .page_h = d->page_h, .pt_px = d->pt_px,
        .supersample = run->figure ? 0 : d->supersample, .png = !run->figure,
        .unit = {d->size_unit[0], d->size_unit[1]}, .extent = run->extent,
        .looks = run->looks, .cells = 1 + run->n_more}, frames_of(run, d->still_at, frames));
}

/* check -> setup -> (figure | still | video) -> finish -> close. */
int sp_pipeline_run(const struct sp_pipeline_desc *desc)
{
    const struct sp_scene *sc = desc->scene;
    int n = sp_timeline_frames(sc);
    for (int i = 0; i < desc->n_more && i < SP_PIPELINE_MAX_SCENES - 1; i++)
        n = n > sp_timeline_frames(desc->more[i]) ? n : sp_timeline_frames(desc->more[i]);
    struct run run = {
        .desc = desc, .sc = sc, .n = n,
        .first = desc->still ? 0 : desc->first,
        .last = desc->still || !desc->last ? n : desc->last,
        .w = sc->video.width, .h = sc->video.height,
        .figure = desc->still && sp_figure_format(desc->output) != SP_FIGURE_NONE,
        .q = {.lock = PTHREAD_MUTEX_INITIALIZER, .changed = PTHREAD_COND_INITIALIZER},
        .t_start = sp_clock_s(), .followed_t = -1,
    };
    run.n_more = desc->n_more < SP_PIPELINE_MAX_SCENES - 1 ? desc->n_more : SP_PIPELINE_MAX_SCENES - 1;
    run.t_last = sp_scene_frame_time(sc, sp_timeline_frames(sc) - 1);
    for (int i = 0; i < run.n_more; i++)
        run.more[i] = (struct cell){.sc = desc->more[i], .followed_t = -1,
                                    .t_last = sp_scene_frame_time(desc->more[i],
                                                                  sp_timeline_frames(desc->more[i]) - 1)};
    int ret = run_check(&run);
    if (ret)
        return ret;
    ret = run_setup(&run);
    const int fit = desc->still && desc->pt_px > 0 && desc->size_unit[0];
    if (ret == SP_E_INPUT && run.compose_refused && fit && !run_still_follow(&run))
        advise_fit(&run); /* a PNG refused as composed, before the sim ran: at --at */
    if (!ret) {
        ret = run.figure ? run_figure(&run) : desc->still ? run_still(&run) : run_video(&run);
        if (ret == SP_E_INPUT && fit)
            advise_fit(&run);
    }
    if (!ret && !run.figure)
        ret = run_finish(&run);
    run_close(&run, ret);
    return ret;
}
