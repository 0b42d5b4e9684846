/* springpend tests: text stays legible at every output size. Composes
 * frames (on the CPU: compose.c, no GL) with every panel at sizes from
 * 320x180 to 7680x4320, at 4:3, 16:9 and 9:16, and checks the draw list's
 * text runs: none overlaps another, all lie inside the frame, none is
 * smaller than the legible minimum, every legend is there, and the tick
 * labels of a small range around a large value are short.
 * usage: test_legibility TESTS_SOURCE_DIR */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/frame.h"
#include "springpend/sim.h"
#include "frame/compose.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

struct box {
    float x0, y0, x1, y1;
    const char *text;
};

/* The boxes of c's text runs: pen to advance, cap height above the
 * baseline to a fifth of the em below it. */
static int boxes(const struct sp_canvas *c, const struct sp_font *f, struct box *out, int max)
{
    int n = 0;
    for (int i = 0; i < c->n_items && n < max; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind != SP_ITEM_TEXT)
            continue;
        const char *s = c->strings + it->text;
        const float w = (float)sp_font_width(f, it->size, s);
        out[n++] = (struct box){it->x, it->y - sp_font_cap(f, it->size), it->x + w,
                                it->y + 0.2f * sp_font_px(f, it->size), s};
    }
    return n;
}

/* Composes `scene` at t with the overrides (and `more`, n_more of them)
 * and checks its text; returns the problems found (diagnosed). `need`
 * lists texts that must appear. */
static int check(const char *src, const char *scene_file, double t, int w, int h,
                 const char *const *need, int n_need, int min_px, const char *const *more,
                 int n_more)
{
    char path[4096], size_w[32], size_h[32];
    const char *ov[8] = {size_w, size_h, "view.panels=all", "view.colorbar=true"};
    for (int i = 0; i < n_more && i < 4; i++)
        ov[4 + i] = more[i];
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_history hist = {0};
    struct sp_trail trail = {0};
    struct sp_view_extent e;
    struct sp_look look;
    struct sp_composer *comp = NULL;
    const struct sp_canvas *cv;
    static struct box b[4096];
    int bad = 0;

    snprintf(path, sizeof(path), "%s/../scenes/%s", src, scene_file);
    snprintf(size_w, sizeof(size_w), "video.width=%d", w);
    snprintf(size_h, sizeof(size_h), "video.height=%d", h);
    if (sp_scene_load(&sc, path, ov, 4 + (n_more < 4 ? n_more : 4)) ||
        sp_view_extent_measure(&sc, sc.video.duration, NULL, NULL, NULL, &e) ||
        sp_history_make(&hist, &sc) || sp_trail_make(&trail, 600))
        return 1;
    sp_sim_init(&sim, &sc);
    for (int k = 0; sp_scene_frame_time(&sc, k) <= t; k++) {
        if (sp_history_follow(&hist, &sim, sp_scene_frame_time(&sc, k)))
            return 1;
        sp_trail_push_at(&trail, &sim.s, 0);
    }
    sp_look_of(&sc, &look);
    if (sp_compose_make(&comp, &(struct sp_compose_desc){w, h, e, &look, 1, NULL, 0}) ||
        sp_compose_frame(comp, &(struct sp_frame){.state = sim.s, .params = &sim.p,
                                                   .trail = &trail, .history = &hist}, &cv))
        return 1;
    const struct sp_font *f = sp_compose_font(comp);
    const int n = boxes(cv, f, b, 4096);
    for (int s = 0; s < SP_TEXT_SIZES; s++)
        if (sp_font_px(f, s) < min_px)
            bad++, sp_tap_diag("%s %dx%d: text size %d is %d px", scene_file, w, h, s, sp_font_px(f, s));
    for (int i = 0; i < n; i++) {
        if (b[i].x0 < 0 || b[i].y0 < 0 || b[i].x1 > w || b[i].y1 > h)
            bad++, sp_tap_diag("%s %dx%d: '%s' leaves the frame", scene_file, w, h, b[i].text);
        for (int j = i + 1; j < n; j++)
            if (b[i].x0 < b[j].x1 - 0.5f && b[j].x0 < b[i].x1 - 0.5f &&
                b[i].y0 < b[j].y1 - 0.5f && b[j].y0 < b[i].y1 - 0.5f)
                bad++, sp_tap_diag("%s %dx%d: '%s' overlaps '%s'", scene_file, w, h, b[i].text,
                                   b[j].text);
    }
    for (int k = 0; k < n_need; k++) {
        int found = 0;
        for (int i = 0; i < n && !found; i++)
            found = strstr(b[i].text, need[k]) != NULL;
        if (!found)
            bad++, sp_tap_diag("%s %dx%d: no '%s'", scene_file, w, h, need[k]);
    }
    sp_compose_destroy(&comp);
    sp_history_destroy(&hist);
    sp_trail_destroy(&trail);
    return bad;
}

/* The largest whole font_size (px) a w x h frame of default.ini with
 * every panel and the colour bar takes (sp_compose_make refuses larger
 * ones); 0 when none. */
static int largest_font(const char *src, int w, int h)
{
    int lo = 0, hi = 200; /* [view] font_size's own limit */
    while (lo < hi) {
        const int mid = (lo + hi + 1) / 2;
        char path[4096], size_w[32], size_h[32], fs[32];
        const char *ov[] = {size_w, size_h, "view.panels=all", "view.colorbar=true", fs};
        struct sp_scene sc;
        struct sp_look look;
        struct sp_composer *comp = NULL;
        snprintf(path, sizeof(path), "%s/../scenes/default.ini", src);
        snprintf(size_w, sizeof(size_w), "video.width=%d", w);
        snprintf(size_h, sizeof(size_h), "video.height=%d", h);
        snprintf(fs, sizeof(fs), "view.font_size=%d", mid);
        if (sp_scene_load(&sc, path, ov, 5))
            return 0;
        sp_look_of(&sc, &look);
        const struct sp_view_extent e = {.xmin = -1, .xmax = 1, .ymin = -1, .ymax = 1, .max_speed = 1, .t_end = 10};
        const int taken = sp_compose_make(&comp, &(struct sp_compose_desc){w, h, e, &look, 1, NULL, 0}) == 0;
        sp_compose_destroy(&comp);
        if (taken)
            lo = mid;
        else
            hi = mid - 1;
    }
    return lo;
}

/* attack12 #19: the largest whole font_size (px) a w x h frame of
 * default.ini with every panel and the colour bar takes in `family` when
 * its time axis ends at t_end (sp_compose_make refuses larger ones), and,
 * composed there at t = t_end, the text runs drawn outside the panels'
 * clips (the HUD's time among them) that do not start inside a panel's
 * box (its title, its legend) kept off those boxes (the rectangles filled in the
 * panel colour) and inside the frame: the problems found (diagnosed), *px
 * the size. */
static int check_wide_time(const char *src, int w, int h, const char *family, double t_end, int *px)
{
    char path[4096], size_w[32], size_h[32], fs[32], font[96];
    const char *ov[] = {size_w, size_h, "view.panels=all", "view.colorbar=true", font, fs};
    const struct sp_view_extent e = {.xmin = -1, .xmax = 1, .ymin = -1, .ymax = 1, .max_speed = 1,
                                     .t_end = t_end};
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_look look;
    struct sp_composer *comp = NULL;
    const struct sp_canvas *cv;
    static struct box b[4096];
    static float clips[256][4];
    int lo = 0, hi = 200, bad = 0, n = 0, n_clips = 0, clipped = 0, times = 0;
    snprintf(path, sizeof(path), "%s/../scenes/default.ini", src);
    snprintf(size_w, sizeof(size_w), "video.width=%d", w);
    snprintf(size_h, sizeof(size_h), "video.height=%d", h);
    snprintf(font, sizeof(font), "view.font=%s", family);
    while (lo < hi) {
        const int mid = (lo + hi + 1) / 2;
        snprintf(fs, sizeof(fs), "view.font_size=%d", mid);
        if (sp_scene_load(&sc, path, ov, 6))
            return 1;
        sp_look_of(&sc, &look);
        const int taken = sp_compose_make(&comp, &(struct sp_compose_desc){w, h, e, &look, 1, NULL, 0}) == 0;
        sp_compose_destroy(&comp);
        if (taken)
            lo = mid;
        else
            hi = mid - 1;
    }
    *px = lo;
    snprintf(fs, sizeof(fs), "view.font_size=%d", lo);
    if (lo < 1 || sp_scene_load(&sc, path, ov, 6))
        return 1;
    sp_sim_init(&sim, &sc);
    sim.s.t = t_end; /* the HUD shows the state's time */
    sp_look_of(&sc, &look);
    if (sp_compose_make(&comp, &(struct sp_compose_desc){w, h, e, &look, 1, NULL, 0}) ||
        sp_compose_frame(comp, &(struct sp_frame){.state = sim.s, .params = &sim.p}, &cv))
        return 1;
    const struct sp_font *f = sp_compose_font(comp);
    for (int i = 0; i < cv->n_items && n < 4096; i++) {
        const struct sp_item *it = &cv->items[i];
        if (it->kind == SP_ITEM_CLIP) {
            clipped = it->clip[2] > it->clip[0];
            continue;
        }
        if (it->kind != SP_ITEM_TEXT || clipped)
            continue;
        const char *t = cv->strings + it->text;
        b[n++] = (struct box){it->x, it->y - sp_font_cap(f, it->size),
                              it->x + (float)sp_font_width(f, it->size, t),
                              it->y + 0.2f * sp_font_px(f, it->size), t};
        times += strncmp(t, "t = ", 4) == 0;
    }
    /* the panels' boxes: the boxes filled in the panel colour */
    const float *panel = sp_compose_palette(comp)->panel;
    for (int i = 0; i < cv->n_shapes && n_clips < 256; i++) {
        const struct sp_shape *sh = &cv->shapes[i];
        if ((int)sh->style[1] == SP_SHAPE_BOX && !memcmp(sh->color, panel, sizeof(sh->color)) &&
            sh->seg[2] - sh->seg[0] > 20 && sh->style[0] > 10) {
            const float box[4] = {sh->seg[0], sh->seg[1] - sh->style[0], sh->seg[2],
                                  sh->seg[1] + sh->style[0]};
            memcpy(clips[n_clips++], box, sizeof(box));
        }
    }
    if (times != 1 || n_clips < 4)
        bad++, sp_tap_diag("%s %dx%d: %d time runs, %d panel boxes drawn", family, w, h, times,
                           n_clips);
    for (int i = 0; i < n; i++) {
        if (b[i].x0 < 0 || b[i].y0 < 0 || b[i].x1 > w || b[i].y1 > h)
            bad++, sp_tap_diag("%s %dx%d: '%s' leaves the frame", family, w, h, b[i].text);
        int inside = 0; /* a panel's own title or legend: it starts in the box */
        for (int k = 0; k < n_clips && !inside; k++)
            inside = b[i].x0 >= clips[k][0] && b[i].x0 < clips[k][2] && b[i].y0 >= clips[k][1] &&
                     b[i].y0 < clips[k][3];
        for (int k = 0; k < n_clips && !inside; k++)
            if (b[i].x0 < clips[k][2] - 0.5f && clips[k][0] < b[i].x1 - 0.5f &&
                b[i].y0 < clips[k][3] - 0.5f && clips[k][1] < b[i].y1 - 0.5f) {
                bad++, sp_tap_diag("%s %dx%d, %d px: '%s' (x %.0f-%.0f, y %.0f-%.0f) runs into "
                                   "a panel's box (x %.0f-%.0f, y %.0f-%.0f)", family, w, h, lo,
                                   b[i].text, b[i].x0, b[i].x1, b[i].y0, b[i].y1, clips[k][0],
                                   clips[k][2], clips[k][1], clips[k][3]);
                break;
            }
    }
    sp_compose_destroy(&comp);
    return bad;
}

/* The text runs in a frame of `scene` at t = 5 s with every panel, the
 * colour bar and speed 4 asked for; -1 when it cannot be composed. */
static int count_texts(const char *src, const char *scene_file, int w, int h)
{
    char path[4096], size_w[32], size_h[32];
    const char *ov[] = {size_w, size_h, "view.panels=all", "view.colorbar=true", "video.speed=4",
                        "view.hud=true"};
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_view_extent e;
    struct sp_look look;
    struct sp_composer *comp = NULL;
    const struct sp_canvas *cv;
    int n = 0;
    snprintf(path, sizeof(path), "%s/../scenes/%s", src, scene_file);
    snprintf(size_w, sizeof(size_w), "video.width=%d", w);
    snprintf(size_h, sizeof(size_h), "video.height=%d", h);
    if (sp_scene_load(&sc, path, ov, 6) ||
        sp_view_extent_measure(&sc, sc.video.duration, NULL, NULL, NULL, &e))
        return -1;
    sp_sim_init(&sim, &sc);
    if (sp_sim_advance(&sim, 5))
        return -1;
    sp_look_of(&sc, &look);
    if (sp_compose_make(&comp, &(struct sp_compose_desc){w, h, e, &look, 1, NULL, 0}) ||
        sp_compose_frame(comp, &(struct sp_frame){.state = sim.s, .params = &sim.p}, &cv))
        return -1;
    for (int i = 0; i < cv->n_items; i++)
        n += cv->items[i].kind == SP_ITEM_TEXT;
    sp_compose_destroy(&comp);
    return n;
}

/* Side by side (attacker's pass 3, finding 8): two cells of default.ini
 * whose HUDs list eleven differing keys. Every text run drawn outside the
 * panels' clip rectangles (the HUD, the labels) must keep off them, stay in
 * the frame and off every other text; each cell keeps its "differs:"
 * heading; where lines are left out, the last says so ("more line"). */
static int check_cells(const char *src, int w, int h, int *cut)
{
    char path[4096], size_w[32], size_h[32];
    const char *ov[] = {size_w, size_h, "view.panels=all", "view.colorbar=true"};
    static const char differs[] = "natural_length = 0.5, stiffness = 2, mass = 0.5, gravity = "
                                  "9.81, damping = 0, length = 0.55, angle = 10, length_rate = "
                                  "0, angle_rate = 0, amplitude = 0, frequency = 0";
    struct sp_scene sc;
    struct sp_sim sim;
    struct sp_history hist = {0};
    struct sp_view_extent e;
    struct sp_look looks[2];
    struct sp_compose_cells *comp = NULL;
    const struct sp_canvas *cv;
    static struct box b[4096];
    static float clips[256][4];
    int bad = 0, n_clips = 0, headings = 0;

    snprintf(path, sizeof(path), "%s/../scenes/default.ini", src);
    snprintf(size_w, sizeof(size_w), "video.width=%d", w);
    snprintf(size_h, sizeof(size_h), "video.height=%d", h);
    if (sp_scene_load(&sc, path, ov, 4) ||
        sp_view_extent_measure(&sc, sc.video.duration, NULL, NULL, NULL, &e) ||
        sp_history_make(&hist, &sc))
        return 1;
    sp_sim_init(&sim, &sc);
    for (int k = 0; sp_scene_frame_time(&sc, k) <= 5; k++)
        if (sp_history_follow(&hist, &sim, sp_scene_frame_time(&sc, k)))
            return 1;
    for (int i = 0; i < 2; i++) {
        sp_look_of(&sc, &looks[i]);
        snprintf(looks[i].differs, sizeof(looks[i].differs), "%s", differs);
    }
    const struct sp_frame fr = {.state = sim.s, .params = &sim.p, .history = &hist};
    const struct sp_frame frames[2] = {fr, fr};
    if (sp_compose_cells_make(&comp, &(struct sp_compose_desc){w, h, e, NULL, 1, NULL, 0}, looks, 2) ||
        sp_compose_cells_frame(comp, frames, &cv))
        return 1;
    const struct sp_font *f = sp_compose_cells_font(comp);
    /* the text runs drawn with no clip (HUD, labels), and the clips (panels) */
    int n = 0, clipped = 0;
    for (int i = 0; i < cv->n_items && n < 4096; i++) {
        const struct sp_item *it = &cv->items[i];
        if (it->kind == SP_ITEM_CLIP) {
            clipped = it->clip[2] > it->clip[0];
            if (clipped && n_clips < 256)
                memcpy(clips[n_clips++], it->clip, sizeof(clips[0]));
            continue;
        }
        if (it->kind != SP_ITEM_TEXT || clipped)
            continue;
        const char *t = cv->strings + it->text;
        const float tw = (float)sp_font_width(f, it->size, t);
        b[n++] = (struct box){it->x, it->y - sp_font_cap(f, it->size), it->x + tw,
                              it->y + 0.2f * sp_font_px(f, it->size), t};
        headings += strncmp(t, "differs:", 8) == 0;
        *cut += strstr(t, " more") != NULL;
    }
    for (int i = 0; i < n; i++) {
        if (b[i].x0 < 0 || b[i].y0 < 0 || b[i].x1 > w || b[i].y1 > h)
            bad++, sp_tap_diag("side by side %dx%d: '%s' leaves the frame", w, h, b[i].text);
        for (int k = 0; k < n_clips; k++)
            if (b[i].x0 < clips[k][2] - 0.5f && clips[k][0] < b[i].x1 - 0.5f &&
                b[i].y0 < clips[k][3] - 0.5f && clips[k][1] < b[i].y1 - 0.5f) {
                bad++, sp_tap_diag("side by side %dx%d: '%s' (x %.0f-%.0f, y %.0f-%.0f) runs "
                                   "into a panel (x %.0f-%.0f, y %.0f-%.0f)", w, h, b[i].text,
                                   b[i].x0, b[i].x1, b[i].y0, b[i].y1, clips[k][0], clips[k][2],
                                   clips[k][1], clips[k][3]);
                break;
            }
        for (int j = i + 1; j < n; j++)
            if (b[i].x0 < b[j].x1 - 0.5f && b[j].x0 < b[i].x1 - 0.5f &&
                b[i].y0 < b[j].y1 - 0.5f && b[j].y0 < b[i].y1 - 0.5f)
                bad++, sp_tap_diag("side by side %dx%d: '%s' overlaps '%s'", w, h, b[i].text,
                                   b[j].text);
    }
    if (headings != 2)
        bad++, sp_tap_diag("side by side %dx%d: %d of 2 cells show the 'differs:' heading", w, h,
                           headings);
    sp_compose_cells_destroy(&comp);
    sp_history_destroy(&hist);
    return bad;
}

int main(int argc, char **argv)
{
    static const int sizes[][2] = {{320, 180}, {180, 320}, {320, 240}, {640, 360}, {854, 480}, {1024, 768}, {1280, 720},
                                   {1920, 1080}, {1080, 1920}, {720, 1280}, {1600, 1200},
                                   {3840, 2160}, {7680, 4320}};
    /* the legends' entries (short forms at least) and the current-state mark */
    static const char *const need[] = {"tot", "kin", "spr", "grav", "b", "sw", "now", "latest"};
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_SOURCE_DIR\n", argv[0]);
        return 2;
    }
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        const int w = sizes[i][0], h = sizes[i][1];
        int bad = check(argv[1], "resonance.ini", 20, w, h, need, 8, 11, NULL, 0);
        bad += check(argv[1], "pure_swing.ini", 5, w, h, need, 7, 11, NULL, 0);
        sp_tap_ok(bad == 0, "%dx%d, every panel: no text overlaps, all inside, at least 11 px, "
                  "every legend shown", w, h);
    }
    /* at the largest font size the size check lets through, with a speed
     * marker (attack11 #14, #18: at 640x240 and 24 px the colour bar's
     * labels overlapped and the energy legend ran over the panel below; at
     * 640x360 and 24 px "speed x2" was drawn over the time) */
    static const int big[][2] = {{320, 180}, {180, 320}, {480, 200}, {640, 240}, {640, 360},
                                 {854, 480}, {1280, 720}, {1080, 1920}};
    for (size_t i = 0; i < sizeof(big) / sizeof(big[0]); i++) {
        const int w = big[i][0], h = big[i][1], px = largest_font(argv[1], w, h);
        char fs[32];
        snprintf(fs, sizeof(fs), "view.font_size=%d", px);
        const char *const more[] = {fs, "video.speed=2"};
        int bad = px < 12 || check(argv[1], "resonance.ini", 20, w, h, need, 8, 0, more, 2);
        bad += px >= 12 && check(argv[1], "pure_swing.ini", 5, w, h, need, 7, 0, more, 2);
        sp_tap_ok(bad == 0, "%dx%d at the largest font size it takes (%d px), speed x2: no text "
                  "overlaps, all inside, every legend shown", w, h, px);
    }
    /* a monospace font's wider digits at the largest size taken, the time
     * at the end of a long video (attack12 #19: at 640x360 and 24 px "t =
     * 987654.32 s" in DejaVu Sans Mono ran under the first panel) */
    static const int wide[][2] = {{320, 180}, {640, 360}, {854, 480}, {1280, 720}, {1080, 1920}};
    static const char *const families[] = {"DejaVu Sans Mono", "DejaVu Sans"};
    for (size_t i = 0; i < sizeof(wide) / sizeof(wide[0]); i++)
        for (int k = 0; k < 2; k++) {
            int px = 0;
            const int bad = check_wide_time(argv[1], wide[i][0], wide[i][1], families[k], 987654.32, &px);
            sp_tap_ok(bad == 0, "%dx%d in %s at the largest font size it takes (%d px), t = "
                      "987654.32 s: the time and the other HUD text keep off the panels, inside "
                      "the frame", wide[i][0], wide[i][1], families[k], px);
        }
    /* below 320x180 (180x320 upright) the HUD, panels, colour bar and speed
     * marker are left out (attacker's pass 3, finding 8: at 160x90 the time
     * ran over "speed x4", the panels over the HUD): no text is drawn */
    static const int tiny[][2] = {{319, 180}, {320, 179}, {160, 90}, {90, 160}, {64, 36}, {16, 16}};
    for (size_t i = 0; i < sizeof(tiny) / sizeof(tiny[0]); i++) {
        const int texts = count_texts(argv[1], "default.ini", tiny[i][0], tiny[i][1]);
        sp_tap_ok(texts == 0, "%dx%d, under the least size for text: the HUD, panels, colour bar "
                  "and speed marker are left out (%d text runs drawn)", tiny[i][0], tiny[i][1],
                  texts);
    }
    static const int cells[][2] = {{640, 360}, {854, 480}, {1280, 720}, {1920, 1080},
                                   {1080, 1920}, {3840, 2160}};
    for (size_t i = 0; i < sizeof(cells) / sizeof(cells[0]); i++) {
        int cut = 0;
        const int bad = check_cells(argv[1], cells[i][0], cells[i][1], &cut);
        sp_tap_ok(bad == 0, "%dx%d, two scenes side by side differing in 11 keys: the HUD keeps "
                  "off the panels and other text, inside the frame, each cell keeps its "
                  "'differs:' heading%s", cells[i][0], cells[i][1],
                  cut ? " (lines left out are counted on the last line)" : "");
    }
    return sp_tap_done();
}
