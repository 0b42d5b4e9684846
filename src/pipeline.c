/* springpend: the render pipeline. Owns the sim, trail, renderer and sink of
 * one run and drives them frame by frame. */
#include <math.h>
#include <stdio.h>
#include <time.h>

#include "springpend/common.h"
#include "springpend/frame.h"
#include "springpend/pipeline.h"
#include "springpend/provenance.h"
#include "springpend/render.h"
#include "springpend/sink.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static void show_progress(int done, int total, double t0)
{
    double el = now_s() - t0, fps = el > 0 ? done / el : 0;
    double eta = fps > 0 ? (total - done) / fps : 0;
    fprintf(stderr, "\rframe %d/%d  %.1f fps  ETA %.0f s ", done, total, fps, eta);
    if (done == total)
        fputc('\n', stderr);
}

/* Renders the frame model at the sim's current state and hands it to the sink. */
static int emit(struct sp_renderer *r, struct sp_sink *sink, const struct sp_sim *sim,
                const struct sp_trail *trail, const struct sp_history *hist,
                struct sp_provenance *prov)
{
    struct sp_image img;
    struct sp_frame f = {.state = sim->s, .params = &sim->p, .trail = trail, .history = hist};
    sp_provenance_set_time(prov, sim->s.t);
    int ret = sp_render_draw(r, &f, &img);
    return ret ? ret : sp_sink_write(sink, &img);
}

int sp_pipeline_run(const struct sp_pipeline_desc *desc)
{
    const struct sp_scene *sc = desc->scene;
    struct sp_renderer *r = NULL;
    struct sp_sink *sink = NULL;
    struct sp_trail trail = {0};
    struct sp_history hist = {0};
    struct sp_view_extent extent;
    struct sp_sim sim;
    struct sp_provenance prov;
    int n = sp_scene_frame_count(sc), ret;
    /* A still past the video's end still fits its camera to the whole motion. */
    double t_end = desc->still ? fmax(desc->still_at, sp_scene_frame_time(sc, n - 1))
                               : sp_scene_frame_time(sc, n - 1);

    ret = sp_view_extent_measure(sc, t_end, &extent);
    if (ret)
        goto done;
    ret = sp_trail_make(&trail, sc->view.trail == SP_TRAIL_ALL ? n + 1 : sc->view.trail);
    if (!ret)
        ret = sp_history_make(&hist, sc);
    if (ret)
        goto done;
    ret = sp_render_make(&r, &(struct sp_render_desc){
        .width = sc->video.width, .height = sc->video.height, .extent = extent,
        .scene = sc, .supersample = desc->supersample});
    if (ret || (ret = sp_provenance_init(&prov, sc, sp_render_renderer_name(r))) != 0)
        goto done;
    ret = sp_sink_open(&sink, &(struct sp_sink_desc){
        .path = desc->output, .width = sc->video.width,
        .height = sc->video.height, .fps = sc->video.fps,
        .text = prov.text, .n_text = SP_PROVENANCE_N_TEXT});
    if (ret)
        goto done;

    sp_sim_init(&sim, sc);
    double t0 = now_s();
    for (int k = 0; k < n; k++) {
        double t = sp_scene_frame_time(sc, k);
        if (desc->still && t > desc->still_at)
            break;
        ret = sp_interrupted() ? SP_E_INTERRUPTED : sp_history_follow(&hist, &sim, t);
        if (ret)
            goto done;
        sp_trail_push_at(&trail, &sim.s, sp_pivot_y(&sim.p, sim.s.t));
        if (desc->still)
            continue;
        ret = emit(r, sink, &sim, &trail, &hist, &prov);
        if (ret)
            goto done;
        if (desc->progress && (k % 10 == 9 || k == n - 1))
            show_progress(k + 1, n, t0);
    }
    if (desc->still) {
        if (sim.s.t < desc->still_at) {
            ret = sp_history_follow(&hist, &sim, desc->still_at);
            if (ret)
                goto done;
            sp_trail_push_at(&trail, &sim.s, sp_pivot_y(&sim.p, sim.s.t));
        }
        ret = emit(r, sink, &sim, &trail, &hist, &prov);
        if (ret)
            goto done;
    }
    ret = sp_interrupted() ? SP_E_INTERRUPTED : sp_sink_close(&sink);
    if (!ret && desc->state_out)
        *desc->state_out = sim.s;
done:
    if (ret == SP_E_INTERRUPTED)
        sp_log_error("interrupted; %s is not written", desc->output);
    sp_sink_abort(&sink);
    sp_render_destroy(&r);
    sp_trail_destroy(&trail);
    sp_history_destroy(&hist);
    return ret;
}
