/* springpend: the render pipeline: scene -> sim -> frame model -> render ->
 * sink. Commands build a desc and call it; nothing here parses arguments. */
#ifndef SPRINGPEND_PIPELINE_H
#define SPRINGPEND_PIPELINE_H

#include "springpend/scene.h"
#include "springpend/sim.h"

struct sp_pipeline_desc {
    const struct sp_scene *scene;
    const char *output;  /* target path; the sink kind follows its extension */
    int still;           /* 1: one frame at still_at instead of the video */
    double still_at;     /* simulated s, used when still = 1 */
    int progress;        /* 1: draw a progress line on stderr */
    int supersample;     /* draw at this many times the size, average down; 0/1 = off */
    struct sp_state *state_out; /* not NULL: receives the bob's state in the
                                   last frame drawn */
};

/* Runs the whole pipeline. PNGs carry provenance.h's text chunks. On any
 * failure nothing is left at desc->output. */
int sp_pipeline_run(const struct sp_pipeline_desc *desc);

#endif
