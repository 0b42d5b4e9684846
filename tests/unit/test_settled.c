/* springpend tests: the settled layer's contract (canvas.h). Composes
 * every frame of a video on the CPU (compose.c, no GL) and checks that each
 * frame's settled items hold the previous frame's, unchanged, first (the
 * same items with the same blending, lanes and clip, their shapes a byte
 * prefix), which is what lets the GL backend draw only what is new; that
 * the strip charts' curves (items with lanes >= 1) are thinned to at most
 * two points per pixel column however long the history grows, and the
 * phase curves (lanes 0) to at most 8000 segments; that every curve is
 * connected, interleaved series keep whole points and strip charts run
 * left to right; that the settled curve goes on, in the dynamic layer, to
 * the newest sample; and that a Poincare section's settled item holds
 * discs (every crossing but the latest). The GL side (same pixels with and without the cache) is
 * test_draw_cache.py's.
 * usage: test_settled TESTS_SOURCE_DIR */
#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/frame.h"
#include "springpend/sim.h"
#include "frame/compose.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

/* A copy of one frame's settled items: heads and shapes. */
struct settled {
    struct sp_item items[64];
    float clips[64][4];
    struct sp_shape *shapes[64];
    int n;
};

static void settled_free(struct settled *s)
{
    for (int i = 0; i < s->n; i++)
        free(s->shapes[i]);
    s->n = 0;
}

/* Copies c's settled items into s (each with the clip it is under). */
static void settled_take(const struct sp_canvas *c, struct settled *s)
{
    float clip[4] = {0, 0, 0, 0};
    settled_free(s);
    for (int i = 0; i < c->n_items && s->n < 64; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP)
            memcpy(clip, it->clip, sizeof(clip));
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        s->items[s->n] = *it;
        memcpy(s->clips[s->n], clip, sizeof(clip));
        s->shapes[s->n] = malloc((size_t)(it->count ? it->count : 1) * sizeof(struct sp_shape));
        assert(s->shapes[s->n]);
        memcpy(s->shapes[s->n], c->shapes + it->first, (size_t)it->count * sizeof(struct sp_shape));
        s->n++;
    }
}

struct result {
    int frames, not_prefix, odd_lanes, too_dense, tail_off, max_lanes, dots;
    int samples, max_points; /* history samples and points of the longest lane, at the end */
};

/* Renders `scene` with the overrides frame by frame through the composer. */
static int run(const char *src, const char *scene_file, const char *const *ov, int n_ov,
               struct result *res)
{
    char path[4096];
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_history hist = {0};
    struct sp_view_extent e;
    struct sp_look look;
    struct sp_composer *comp = NULL;
    const struct sp_canvas *cv;
    struct settled prev = {0}, now = {0};

    memset(res, 0, sizeof(*res));
    snprintf(path, sizeof(path), "%s/../scenes/%s", src, scene_file);
    if (sp_scene_load(&sc, path, ov, n_ov) ||
        sp_view_extent_measure(&sc, sc.video.duration, NULL, NULL, NULL, &e) ||
        sp_history_make(&hist, &sc))
        return 1;
    sp_sim_init(&sim, &sc);
    sp_look_of(&sc, &look);
    if (sp_compose_make(&comp, &(struct sp_compose_desc){sc.video.width, sc.video.height, e, &look, 1, NULL, 0}))
        return 1;
    const int n_frames = sp_scene_frame_count(&sc);
    for (int k = 0; k < n_frames; k++) {
        if (sp_history_follow(&hist, &sim, sp_scene_frame_time(&sc, k)) ||
            sp_compose_frame(comp, &(struct sp_frame){.state = sim.s, .params = &sim.p, .history = &hist},
                             &cv))
            return 1;
        settled_take(cv, &now);
        res->frames++;
        /* the previous frame's settled items, unchanged, at the head of this one's */
        if (prev.n && prev.n != now.n)
            res->not_prefix++;
        for (int i = 0; prev.n == now.n && i < now.n; i++) {
            const struct sp_item *a = &prev.items[i], *b = &now.items[i];
            if (a->blend != b->blend || a->lanes != b->lanes || a->count > b->count ||
                memcmp(prev.clips[i], now.clips[i], sizeof(now.clips[i])) ||
                memcmp(prev.shapes[i], now.shapes[i], (size_t)a->count * sizeof(struct sp_shape)))
                res->not_prefix++;
        }
        for (int i = 0; i < now.n; i++) {
            const struct sp_item *it = &now.items[i];
            if (it->kind == SP_ITEM_SHAPES) { /* the Poincare section's dots: discs */
                res->dots = it->count > res->dots ? it->count : res->dots;
                for (int s = 0; s < it->count; s++)
                    if (now.shapes[i][s].seg[0] != now.shapes[i][s].seg[2] ||
                        now.shapes[i][s].seg[1] != now.shapes[i][s].seg[3])
                        res->odd_lanes++;
                continue;
            }
            const int strip = it->lanes >= 1, lanes = it->lanes > 1 ? it->lanes : 1;
            res->max_lanes = lanes > res->max_lanes ? lanes : res->max_lanes;
            if (it->count % lanes)
                res->odd_lanes++;
            /* at most two points per pixel column of the clip (plus the first) */
            const float width = now.clips[i][2] - now.clips[i][0];
            if (it->count / lanes > (strip ? 2 * (int)ceilf(width) + 1 : 8001))
                res->too_dense++;
            if (strip && it->count / lanes > res->max_points)
                res->max_points = it->count / lanes;
            /* each segment starts where its lane's previous one ended; a
             * strip chart's run left to right */
            for (int s = lanes; s < it->count; s++) {
                const struct sp_shape *p = &now.shapes[i][s - lanes], *q = &now.shapes[i][s];
                if (q->seg[0] != p->seg[2] || q->seg[1] != p->seg[3] || (strip && q->seg[2] < q->seg[0]))
                    res->odd_lanes++;
            }
            /* the dynamic tail starts at the settled curve's end: a shape
             * of a dynamic item begins there */
            if (it->count) {
                const struct sp_shape *end = &now.shapes[i][it->count - 1];
                int found = 0;
                for (int j = 0; j < cv->n_items && !found; j++) {
                    const struct sp_item *d = &cv->items[j];
                    if (d->layer != SP_LAYER_DYNAMIC || (d->kind != SP_ITEM_SHAPES && d->kind != SP_ITEM_PATH))
                        continue;
                    for (int m = d->first; m < d->first + d->count && !found; m++)
                        found = cv->shapes[m].seg[0] == end->seg[2] && cv->shapes[m].seg[1] == end->seg[3];
                }
                if (!found)
                    res->tail_off++;
            }
        }
        struct settled t = prev;
        prev = now;
        now = t;
    }
    res->samples = hist.count;
    settled_free(&prev);
    settled_free(&now);
    sp_compose_destroy(&comp);
    sp_history_destroy(&hist);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_SOURCE_DIR\n", argv[0]);
        return 2;
    }
    static const struct {
        const char *scene;
        const char *ov[8];
        int n_ov;
    } cases[] = {
        /* 60 s at 30 fps: far more samples than the charts' pixel columns */
        {"default.ini", {"video.width=640", "video.height=360", "video.duration=60", "video.fps=30"}, 4},
        /* every panel: the modes chart's two interleaved series */
        {"resonance.ini", {"video.width=854", "video.height=480", "video.duration=20", "video.fps=24",
                           "view.panels=all"}, 5},
        /* phase portraits without fading, 120 s of chaos: all but the tail settled,
         * more samples than 8000 time bins */
        {"chaotic.ini", {"video.width=800", "video.height=800", "video.duration=120", "video.fps=10",
                         "view.panels=phase,poincare", "view.fade=false"}, 6},
        /* a driven pivot at 4K, slowed down */
        {"driven.ini", {"video.width=3840", "video.height=2160", "video.duration=6", "video.fps=60",
                        "video.speed=0.5", "view.panels=r,theta,energy,extension,modes"}, 5},
    };
    for (size_t c = 0; c < sizeof(cases) / sizeof(cases[0]); c++) {
        struct result r;
        const char *name = cases[c].scene;
        if (!sp_tap_ok(run(argv[1], name, cases[c].ov, cases[c].n_ov, &r) == 0, "%s: composed", name))
            continue;
        sp_tap_ok(r.not_prefix == 0, "%s: %d frames, each frame's settled curves begin with the "
                  "last frame's, unchanged (%d not)", name, r.frames, r.not_prefix);
        sp_tap_ok(r.too_dense == 0, "%s: at most two points per pixel column of a strip chart, 8000 "
                  "segments of a phase curve (%d samples, longest chart %d points; %d too dense)",
                  name, r.samples, r.max_points, r.too_dense);
        sp_tap_ok(r.odd_lanes == 0, "%s: every curve connected, interleaved series keep whole "
                  "points, strip charts run left to right (up to %d lanes; %d wrong)", name,
                  r.max_lanes, r.odd_lanes);
        sp_tap_ok(r.tail_off == 0, "%s: each settled curve goes on as a tail to the newest sample "
                  "(%d without)", name, r.tail_off);
        if (c == 0)
            sp_tap_ok(r.samples > 2 * r.max_points, "%s: the history outgrew the pixel columns "
                      "(%d samples, %d points drawn), so the thinning was exercised", name, r.samples,
                      r.max_points);
        if (c == 1)
            sp_tap_ok(r.max_lanes == 4, "%s: the energy chart interleaves its four series", name);
        if (c == 2)
            sp_tap_ok(r.dots > 20, "%s: the Poincare section's crossings but the latest are settled "
                      "discs (%d at the end)", name, r.dots);
    }
    return sp_tap_done();
}
