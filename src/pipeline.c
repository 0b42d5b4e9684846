/* springpend: the render pipeline. Owns the sim, trail, renderer and sink of
 * one run and drives them frame by frame. This thread advances the sim,
 * updates the frame model and renders each frame straight into a free slot
 * of a small bounded queue (no copy); an encoder thread takes the slots in
 * order and hands them to the sink. Both stages work at once; the slots
 * are allocated once, so memory does not grow with the video's length. */
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/ensemble.h"
#include "springpend/figure.h"
#include "springpend/frame.h"
#include "springpend/outfile.h"
#include "springpend/pipeline.h"
#include "springpend/provenance.h"
#include "springpend/render.h"
#include "springpend/sink.h"

#define QUEUE_SLOTS 4 /* frames in flight between render and encoder */

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* ---- signals ---- */

static volatile sig_atomic_t signal_seen;  /* the first signal, 0 = none */
static volatile sig_atomic_t signal_count; /* signals received this run */

static void on_signal(int sig)
{
    if (signal_count++ == 0) {
        signal_seen = sig;
        sp_interrupt_note(sig); /* stops a long sp_sim_advance too */
        return;
    }
    /* Second signal: stop at once. Only async-signal-safe calls here. The
     * .part table stays valid through the sink's close (outfile.c). */
    static const char msg[] = "springpend: second signal: stopped at once, "
                              "partial file removed\n";
    sp_outfile_remove_parts();
    if (write(2, msg, sizeof(msg) - 1) < 0) {
        /* nothing more can be done */
    }
    _exit(128 + sig);
}

static const char *sig_name(int sig)
{
    return sig == SIGINT ? "SIGINT" : sig == SIGTERM ? "SIGTERM" : "SIGHUP";
}

int sp_pipeline_signal(void)
{
    return signal_seen;
}

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
        double t0 = now_s();
        while (!q->count && !q->closed)
            pthread_cond_wait(&q->changed, &q->lock);
        q->idle_s += now_s() - t0;
        if (!q->count || q->cancel)
            break;
        struct sp_image *img = &q->slot[q->head];
        sp_provenance_set_time(q->prov, q->slot_t[q->head]);
        pthread_mutex_unlock(&q->lock);
        t0 = now_s();
        int err = sp_sink_write(q->sink, img); /* logs its own failure */
        double dt = now_s() - t0;
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
    double t0 = now_s();
    pthread_mutex_lock(&q->lock);
    while (q->count == QUEUE_SLOTS && !q->err)
        pthread_cond_wait(&q->changed, &q->lock);
    *err = q->err;
    struct sp_image *slot = &q->slot[(q->head + q->count) % QUEUE_SLOTS];
    pthread_mutex_unlock(&q->lock);
    *wait_s += now_s() - t0;
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
    double el = now_s() - t0, fps = el > 0 ? done / el : 0;
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
    fprintf(stderr, "  static layer cached in %ld frames (drawn %ld time%s), uncached in %ld\n",
            rs->cached, rs->redrawn, rs->redrawn == 1 ? "" : "s", rs->uncached);
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

/* Installs (on = 1) or restores the SIGINT/SIGTERM/SIGHUP handlers. */
static void catch_signals(int on, struct sigaction old[3])
{
    static const int sigs[3] = {SIGINT, SIGTERM, SIGHUP};
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < 3; i++) {
        if (on)
            sigaction(sigs[i], &sa, &old[i]);
        else
            sigaction(sigs[i], &old[i], NULL);
    }
}

int sp_pipeline_run(const struct sp_pipeline_desc *desc)
{
    const struct sp_scene *sc = desc->scene;
    struct sp_renderer *r = NULL;
    struct sp_sink *sink = NULL;
    struct sp_trail trail = {0};
    struct sp_history hist = {0};
    struct sp_ensemble *ens = NULL;
    struct sp_view_extent extent;
    struct sp_sim sim;
    struct sp_provenance prov;
    struct sp_image img;
    struct queue q = {.lock = PTHREAD_MUTEX_INITIALIZER,
                      .changed = PTHREAD_COND_INITIALIZER};
    struct stage_times tm = {0};
    struct sigaction old_sig[3];
    pthread_t encoder;
    int encoder_running = 0, signals_caught = 0, emitted = 0, ret;
    int n = sp_scene_frame_count(sc);
    int first = desc->still ? 0 : desc->first;
    int last = desc->still || !desc->last ? n : desc->last;
    int w = sc->video.width, h = sc->video.height;
    /* a still to .svg or .pdf: composed and drawn with cairo, no GL */
    const int figure = desc->still && sp_figure_format(desc->output) != SP_FIGURE_NONE;
    double t_start = now_s(), t0;

    signal_seen = signal_count = 0;
    if (first < 0 || last > n || first >= last) {
        sp_log_error("frames %d:%d: the video has frames 0:%d; give A:B with "
                     "0 <= A < B <= %d", first, last, n, n);
        return SP_E_INPUT;
    }
    if (desc->handle_signals) {
        /* From the start: a signal during setup stops before frame one. */
        catch_signals(1, old_sig);
        signals_caught = 1;
    }
    /* A still past the video's end still fits its camera to the whole
     * motion; a frame range fits the whole video's, so shards match. */
    double t_end = sp_scene_frame_time(sc, n - 1);
    if (desc->still)
        t_end = fmax(desc->still_at, t_end);

    sp_progress_begin(desc->progress, "camera pre-pass", t_end);
    ret = sp_view_extent_measure(sc, t_end, &extent);
    sp_progress_end();
    if (!ret && sc->ensemble.count > 1) /* widens the extent by every member's motion */
        ret = sp_ensemble_make(&ens, sc, t_end, &extent);
    if (ret)
        goto done;
    /* The trail is sampled between frames finely enough that its chords stay
     * within half a pixel: at most the top speed times the fastest angular
     * frequency of acceleration, at the largest scale the camera can have. */
    sp_sim_init(&sim, sc);
    const double frame_dt = sc->video.speed / sc->video.fps;
    const int ss = desc->supersample > 1 ? desc->supersample : 1;
    int substeps = sp_trail_substeps(
        frame_dt, extent.max_speed * sp_params_omega_max(&sim.p),
        ss * fmin(w / fmax(extent.xmax - extent.xmin, 1e-9), h / fmax(extent.ymax - extent.ymin, 1e-9)));
    const int trail_frames = sc->view.trail == SP_TRAIL_ALL ? n + 1
                           : sc->view.trail == SP_TRAIL_DURATION
                               ? (int)fmin(ceil(sc->view.trail_duration / frame_dt) + 1, n + 1)
                               : sc->view.trail;
    if ((double)trail_frames * substeps > 4e6) /* about 100 MB of trail at most */
        substeps = (int)fmax(1, 4e6 / fmax(trail_frames, 1));
    ret = sp_trail_make(&trail, trail_frames ? (trail_frames - 1) * substeps + 1 : 0);
    if (!ret)
        ret = sp_history_make(&hist, sc);
    if (ret || figure)
        goto setup_done;
    ret = sp_render_make(&r, &(struct sp_render_desc){
        .width = w, .height = h, .extent = extent, .gl = desc->gl,
        .scene = sc, .supersample = desc->supersample});
    if (ret || (ret = sp_provenance_init(&prov, sc, sp_render_renderer_name(r))) != 0)
        goto done;
    ret = sp_sink_open(&sink, &(struct sp_sink_desc){
        .path = desc->output, .format = desc->format, .width = w,
        .height = h, .fps = sc->video.fps, .first_frame = first,
        .alpha = sc->view.background == SP_BACKGROUND_TRANSPARENT,
        .png_level = sc->video.png_level,
        .crf = sc->video.crf, .preset = sp_scene_preset_name(sc),
        .text = prov.text, .n_text = SP_PROVENANCE_N_TEXT});
    if (ret)
        goto done;
setup_done:
    if (ret)
        goto done;
    if (desc->still) {
        /* The trail holds the video's frame positions before still_at. */
        sp_progress_begin(desc->progress, "integrating", desc->still_at);
        for (int k = 0; k < n && sp_scene_frame_time(sc, k) <= desc->still_at; k++) {
            ret = sp_trail_follow(&trail, &hist, &sim, sp_scene_frame_time(sc, k), substeps);
            if (!ret && ens)
                ret = sp_ensemble_advance(ens, sim.s.t);
            if (ret)
                goto done;
        }
        if (sim.s.t < desc->still_at) {
            ret = sp_trail_follow(&trail, &hist, &sim, desc->still_at, substeps);
            if (!ret && ens)
                ret = sp_ensemble_advance(ens, sim.s.t);
            if (ret)
                goto done;
        }
        if (figure) {
            ret = sp_figure_write(&(struct sp_figure_desc){
                .width = w, .height = h, .extent = extent, .scene = sc, .path = desc->output},
                &(struct sp_frame){.state = sim.s, .params = &sim.p, .trail = &trail,
                                   .history = &hist, .ensemble = ens});
            if (!ret && desc->state_out)
                *desc->state_out = sim.s;
            goto done;
        }
        sp_progress_end();
        sp_provenance_set_time(&prov, sim.s.t);
        ret = sp_render_draw(r, &(struct sp_frame){.state = sim.s, .params = &sim.p,
                                                   .trail = &trail, .history = &hist,
                                                   .ensemble = ens}, &img);
        if (!ret)
            ret = sp_sink_write(sink, &img);
        if (ret)
            goto done;
        goto finish;
    }

    for (int i = 0; i < QUEUE_SLOTS; i++) {
        ret = sp_image_alloc(&q.slot[i], w, h);
        if (ret)
            goto done;
    }
    q.sink = sink;
    q.prov = &prov;
    if (pthread_create(&encoder, NULL, consume, &q) != 0) {
        sp_log_error("cannot start the encoder thread");
        ret = SP_E_NOMEM;
        goto done;
    }
    encoder_running = 1;
    tm.setup = now_s() - t_start;

    t0 = now_s();
    for (int k = 0; k < last && !signal_seen; k++) {
        /* advance sim to t_k -> update frame model -> render -> sink */
        double ts = now_s();
        ret = sp_trail_follow(&trail, &hist, &sim, sp_scene_frame_time(sc, k), substeps);
        if (!ret && ens)
            ret = sp_ensemble_advance(ens, sim.s.t);
        if (ret == SP_E_INTERRUPTED && signal_seen)
            break; /* keep the frames so far, below */
        if (ret)
            goto done;
        tm.sim += now_s() - ts;
        if (k < first)
            continue; /* frames before the range only feed trail and histories */
        struct sp_image *slot = acquire(&q, &ret, &tm.wait);
        if (!slot)
            goto done;
        ts = now_s();
        ret = sp_render_target(r, slot);
        if (!ret)
            ret = sp_render_draw(r, &(struct sp_frame){.state = sim.s, .params = &sim.p,
                                                       .trail = &trail, .history = &hist,
                                                   .ensemble = ens}, &img);
        if (ret)
            goto done;
        tm.render += now_s() - ts;
        publish(&q, sim.s.t);
        emitted++;
        if (desc->progress && (emitted % 10 == 0 || k == last - 1))
            show_progress(emitted, last - first, t0);
    }

finish:
    if (encoder_running) {
        pthread_mutex_lock(&q.lock);
        q.closed = 1;
        pthread_cond_broadcast(&q.changed);
        pthread_mutex_unlock(&q.lock);
        pthread_join(encoder, NULL);
        encoder_running = 0;
        ret = q.err;
        if (ret)
            goto done;
    }
    t0 = now_s();
    if (signal_seen && desc->progress)
        fputc('\n', stderr);
    if (signal_seen && !emitted && !desc->still) {
        ret = SP_E_INTERRUPTED; /* said at done */
        goto done; /* aborts the sink */
    }
    ret = sp_sink_close(&sink);
    if (!ret && desc->state_out)
        *desc->state_out = sim.s;
    tm.finish = now_s() - t0;
    tm.total = now_s() - t_start;
    if (!ret && signal_seen) {
        sp_log_error("interrupted by %s: kept the %d frame%s rendered so far "
                     "in %s", sig_name(signal_seen), emitted, emitted == 1 ? "" : "s",
                     desc->output);
        ret = SP_E_INTERRUPTED;
    }
    if (desc->verbose && !desc->still) {
        struct sp_render_stats rs;
        sp_render_stats(r, &rs);
        print_times(&tm, &q, &rs, emitted);
    }
done:
    sp_progress_end();
    if (ret == SP_E_INTERRUPTED && !emitted) {
        int sig = signal_seen ? signal_seen : sp_interrupted();
        sp_log_error("interrupted by %s before the first frame: nothing written",
                     sig_name(sig));
    }
    if (encoder_running) {
        pthread_mutex_lock(&q.lock);
        q.closed = q.cancel = 1;
        pthread_cond_broadcast(&q.changed);
        pthread_mutex_unlock(&q.lock);
        pthread_join(encoder, NULL);
    }
    sp_sink_abort(&sink);
    if (r)
        sp_render_target(r, NULL); /* before the slots go */
    if (signals_caught)
        catch_signals(0, old_sig);
    for (int i = 0; i < QUEUE_SLOTS; i++)
        sp_image_free(&q.slot[i]);
    sp_render_destroy(&r);
    sp_trail_destroy(&trail);
    sp_history_destroy(&hist);
    sp_ensemble_destroy(&ens);
    return ret;
}
