/* springpend: the render pipeline: scene -> sim -> frame model -> render ->
 * sink. Commands build a desc and call it; nothing here parses arguments.
 * Rendering (this thread) and encoding (a second thread) overlap through a
 * small bounded queue of frames, so memory stays flat however long the
 * video. */
#ifndef SPRINGPEND_PIPELINE_H
#define SPRINGPEND_PIPELINE_H

#include "springpend/render.h"
#include "springpend/scene.h"
#include "springpend/sim.h"

struct sp_outfile;
struct sp_pipeline_desc {
    const struct sp_scene *scene;
    const char *output;  /* target path ("-" = stdout for raw); the sink
                            kind follows its extension or `format` */
    const char *format;  /* "mp4", "webm", "gif", "png", "raw"; NULL = by
                            the output's extension */
    int still;           /* 1: one frame at still_at instead of the video */
    double still_at;     /* simulated s, used when still = 1 */
    int first, last;     /* video frames [first, last) only; last 0 = to the
                            end. The physics still runs from t = 0. */
    enum sp_gl gl; /* GL backend; 0 = default */
    int progress;        /* 1: say progress on stderr: the integration's
                            (sp_progress_*: redrawn on a terminal, else a line
                            after 10 s and once a minute), and on a terminal
                            the frames' bar */
    int verbose;         /* 1: print per-stage times on stderr at the end */
    int handle_signals;  /* 1: SIGINT/SIGTERM/SIGHUP finish the file so far (see
                            sp_pipeline_run, and signals.h's hold); 0 leaves
                            them to main's handler */
    int supersample;     /* draw at this many times the size, average down; 0/1 = off */
    double pt_px;        /* a still of physical size (--size 8.6cm): the scene's
                            video.width x height px are page_w x page_h pt at
                            pt_px px per pt (sp_look.pt_px); 0 = a video frame */
    double page_w, page_h; /* pt: an SVG or PDF still's page, when pt_px > 0 */
    const char *size_unit[2]; /* --size's units as given ("cm", ...), width's and
                            height's ("" = WIDTH alone): a still refused for its
                            layout then says what fits (sp_figure_fit_advise);
                            NULL = says nothing more */
    const struct sp_scene *recorded; /* the scene provenance records; NULL =
                                        scene. A still of physical size records
                                        its scene before --size set its px, so
                                        that the same command on it makes the
                                        same page */
    int piece;           /* 1: a video piece (MP4/WebM of --frames or --shard):
                            it records its --frames/--shard too
                            (sp_command_line_piece), so that its record
                            re-makes it; 0: outputs record the whole run's
                            command */
    int part;            /* 1: --frames or --shard: a part of the video; 0:
                            the whole (a PNG sequence then removes an earlier,
                            longer run's frames past its last) */
    /* A still's second output (--state): called with the bob's state once
     * the frame is drawn, it opens and writes *partner without committing
     * it; the image and it are then put in place together under their
     * folder's lock (sp_outfile_commit_pair), or both discarded. NULL =
     * none. */
    int (*write_partner)(void *ctx, const struct sp_state *st, struct sp_outfile *partner);
    void *partner_ctx;
    struct sp_outfile *partner;
    /* Side by side: the scenes drawn beside `scene`, each in its own cell
     * of the frame (up to SP_PIPELINE_MAX_SCENES in all), labelled with its
     * view.title or the keys in which the scenes differ, one camera scale
     * and the same chart axes in every cell. [video] size, fps and speed are
     * `scene`'s (the caller checks that they agree). The video runs to the
     * longest scene's end; a shorter one holds its last frame, marked as
     * ended. */
    const struct sp_scene *const *more;
    int n_more;
};

#define SP_PIPELINE_MAX_SCENES 4

/* Runs the whole pipeline. On any failure nothing is left at desc->output.
 * With handle_signals, a first SIGINT, SIGTERM or SIGHUP finishes the frame in
 * hand, flushes the encoder and keeps a playable file of the frames so far
 * at the target, then returns SP_E_INTERRUPTED (the signal: sp_signal_seen);
 * a second one removes the .part being written and exits the process at
 * once with status 128 + signal. PNGs carry provenance.h's text chunks. */
int sp_pipeline_run(const struct sp_pipeline_desc *desc);

/* Frames [*first, *last) of shard i (0-based) of n equal consecutive
 * ranges of n_frames frames. SP_E_INPUT (logged) unless 0 <= i < n <=
 * n_frames. */
int sp_pipeline_shard(int n_frames, int i, int n, int *first, int *last);

#endif
