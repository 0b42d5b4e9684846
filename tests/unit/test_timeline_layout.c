/* springpend tests: a [timeline]'s layout is fixed for the whole video.
 * Composes (on the CPU: compose.c, no GL) every frame of a timeline with a
 * short caption, a three-line one, a pause note and speed changes, with all
 * panels and the heads-up text, and checks that the static layer (panel
 * rectangles, axes, ticks, labels, the title) is byte for byte the same in
 * every frame, and the same again in a fresh composer for a still at each
 * caption's time (where a layout sized for the caption in force would move
 * the panels); that the caption band's text stays inside one band and the
 * speed marker at one right edge; and that the band shows the caption in
 * force. Then that a scene without a timeline composes as before.
 * usage: test_timeline_layout TESTS_SOURCE_DIR */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/frame.h"
#include "springpend/sim.h"
#include "springpend/timeline.h"
#include "frame/compose.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

static const char scene_text[] =
    "[pendulum]\nnatural_length = 1\nstiffness = 29.43\nmass = 1\n"
    "[initial]\nlength = 1.4333\nangle = 1\n"
    "[video]\nwidth = 640\nheight = 360\nfps = 10\nduration = 12\n"
    "[view]\npanels = all\nhud = true\ntitle = Layout\ntrail = 2s\n"
    "[timeline]\n"
    "0 = caption: Short\n"
    "2 = speed 0.5\n"
    "3 = caption: A caption long enough to need two lines of the band at 640 by 360: "
    "the swing takes the energy of the bounce, and then the bounce takes it back again, "
    "over and over\n"
    "5 = pause 1.5: A note\n"
    "6 = speed 2\n"
    "8 = caption:\n"
    "10 = caption: Short again\n";

/* FNV-1a over bytes. */
static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    return h;
}

/* A hash of the static layer: its items, their shapes, glyph quads and text. */
static uint64_t static_hash(const struct sp_canvas *c)
{
    uint64_t h = 1469598103934665603ull;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->layer != SP_LAYER_STATIC)
            continue;
        h = fnv(h, &it->kind, sizeof(it->kind));
        if (it->kind == SP_ITEM_TEXT) {
            /* where each glyph goes and its colour; not its place in the
             * glyph cache, which depends on the order glyphs were first
             * needed in (text.c fills it on demand) */
            for (int k = 0; k < it->count; k++) {
                h = fnv(h, c->quads[it->first + k].rect, sizeof(c->quads->rect));
                h = fnv(h, c->quads[it->first + k].color, sizeof(c->quads->color));
            }
            h = fnv(h, c->strings + it->text, strlen(c->strings + it->text));
        } else if (it->kind == SP_ITEM_CLIP) {
            h = fnv(h, it->clip, sizeof(it->clip));
        } else {
            h = fnv(h, c->shapes + it->first, sizeof(*c->shapes) * (size_t)it->count);
        }
    }
    return h;
}

/* The dynamic text items below y_min (the caption band): their top and
 * bottom baselines, and whether `want` is among them ("" = none shown). */
struct band { float y0, y1; int n, has; float marker_x1; };

static struct band band_of(const struct sp_canvas *c, const struct sp_font *f, float y_min,
                           const char *want)
{
    struct band b = {1e9f, -1e9f, 0, 0, -1};
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind != SP_ITEM_TEXT || it->layer != SP_LAYER_DYNAMIC)
            continue;
        const char *s = c->strings + it->text;
        if (!strncmp(s, "speed ", 6) || !strcmp(s, "paused")) {
            b.marker_x1 = it->x + (float)sp_font_width(f, it->size, s);
            continue;
        }
        if (it->y < y_min || fabsf(it->x + 0.5f * (float)sp_font_width(f, it->size, s) - 320) > 1)
            continue; /* the band's lines are centred */
        b.y0 = fminf(b.y0, it->y), b.y1 = fmaxf(b.y1, it->y);
        b.n++;
        b.has |= want[0] && strstr(want, s) != NULL;
    }
    return b;
}

int main(int argc, char **argv)
{
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_history hist = {0};
    struct sp_trail trail = {0};
    struct sp_view_extent e;
    struct sp_look look;
    struct sp_composer *video = NULL;
    const struct sp_canvas *cv;
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_SOURCE_DIR\n", argv[0]);
        return 2;
    }
    if (!sp_tap_ok(sp_scene_parse(&sc, scene_text, "layout.ini", NULL, 0) == 0 && sc.timeline,
                   "the scene with a timeline parses"))
        return sp_tap_done();
    const int n = sp_timeline_frames(&sc);
    struct sp_moment m, last;
    sp_timeline_frame(&sc, n - 1, &last);
    if (sp_view_extent_measure(&sc, last.t, NULL, NULL, NULL, &e) ||
        sp_history_make(&hist, &sc) || sp_trail_make(&trail, 100000))
        return 1;
    sp_sim_init(&sim, &sc);
    sp_look_of(&sc, &look);
    if (sp_compose_make(&video, &(struct sp_compose_desc){640, 360, e, &look, 1, NULL, 0}))
        return 1;
    const struct sp_font *f = sp_compose_font(video);
    uint64_t first = 0;
    int moved = 0, stills = 0, stills_moved = 0, wrong_caption = 0;
    float band_y0 = 1e9f, band_y1 = -1e9f, marker_x1 = -1, y_min = 360 * 0.8f;
    double followed = -1;
    const char *captions[] = {"Short", "A caption long", "A note", "", "Short again"};
    const double caption_at[] = {0, 3, 5, 8, 10};
    for (int k = 0; k < n; k++) {
        sp_timeline_frame(&sc, k, &m);
        if (m.t != followed) {
            followed = m.t;
            if (sp_history_follow(&hist, &sim, m.t))
                return 1;
            sp_trail_push_at(&trail, &sim.s, 0);
        }
        const struct sp_frame fr = {.state = sim.s, .params = &sim.p, .trail = &trail,
                                    .history = &hist, .moment = &m};
        if (sp_compose_frame(video, &fr, &cv))
            return 1;
        const uint64_t h = static_hash(cv);
        if (!k)
            first = h;
        moved += h != first;
        const struct band b = band_of(cv, f, y_min, m.band);
        if (b.n) {
            band_y0 = fminf(band_y0, b.y0), band_y1 = fmaxf(band_y1, b.y1);
            wrong_caption += m.band_alpha > 0.99f && m.band[0] && !b.has;
        }
        if (marker_x1 < 0)
            marker_x1 = b.marker_x1;
        moved += b.marker_x1 != marker_x1;
        /* at each caption's time, a still in a fresh composer */
        for (int i = 0; i < 5; i++) {
            if (!(m.t >= caption_at[i] && m.t < caption_at[i] + 0.05) ||
                (i == 2 && m.t != caption_at[i])) /* a pause's note: at its time only */
                continue;
            struct sp_composer *one = NULL;
            struct sp_moment sm;
            const struct sp_canvas *sv;
            sp_timeline_still(&sc, m.t, &sm);
            const struct sp_frame sf = {.state = sim.s, .params = &sim.p, .trail = &trail,
                                        .history = &hist, .moment = &sm};
            if (sp_compose_make(&one, &(struct sp_compose_desc){640, 360, e, &look, 1, NULL, 0}) ||
                sp_compose_frame(one, &sf, &sv))
                return 1;
            stills++;
            stills_moved += static_hash(sv) != first;
            const struct band sb = band_of(sv, f, y_min, sm.band);
            if (!(sm.band[0] ? sb.has : !sb.n) || strncmp(sm.band, captions[i], strlen(captions[i])))
                sp_tap_diag("still at %g: the band shows '%s', expected '%s'", m.t, sm.band,
                            captions[i]), wrong_caption++;
            sp_compose_destroy(&one);
        }
    }
    sp_tap_ok(n > 100 && moved == 0, "%d frames: the static layer (panel rectangles, axes, "
              "labels, title) and the speed marker's right edge are the same in every frame "
              "(%d differ)", n, moved);
    sp_tap_ok(stills >= 5 && stills_moved == 0, "%d stills at the captions' times, each in a "
              "fresh composer, have the video's static layer (%d differ)", stills, stills_moved);
    sp_tap_ok(band_y0 >= y_min && band_y1 - band_y0 == sp_font_line(f, SP_TEXT_NORMAL),
              "the caption band's lines stay in one band, two lines tall for the longest "
              "caption (baselines %.0f .. %.0f px)", band_y0, band_y1);
    sp_tap_ok(wrong_caption == 0, "the band shows the caption in force (%d frames or stills "
              "wrong)", wrong_caption);
    sp_compose_destroy(&video);
    sp_history_destroy(&hist);
    sp_trail_destroy(&trail);
    sp_scene_free(&sc);
    sp_tap_ok(sc.timeline == NULL, "sp_scene_free releases the timeline");
    return sp_tap_done();
}
