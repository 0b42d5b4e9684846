/* springpend tests: the draw cache's plan (render/draw_cache.c) without GL.
 * Canvases are built item by item and each frame's plan is checked against
 * the plan worked out by hand from the rules in draw_cache.h: base's
 * rectangles (32 px tiles, opaque boxes filled), the damage (16 px tiles
 * of the dynamic items where they were and are), unchanged items, the
 * settled layer's growth and its rebuild when its past changes, the
 * accumulated layer into base or not, and the items lifted to the dynamic
 * layer. tests/e2e/test_draw_cache.py checks the pixels of the GL path. */
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "frame/canvas.h"
#include "render/draw_cache.h"
#include "tap.h"

#define W 320
#define H 180

static const float BG[4] = {0, 0, 0, 1};
static const float RED[4] = {1, 0, 0, 1};
static const float GREEN[4] = {0, 1, 0, 1};
static const float GREY[4] = {0.5f, 0.5f, 0.5f, 0.5f};

/* Appends a TEXT item of one glyph quad covering rect (no font needed:
 * the plan reads only the quads' rectangles). */
static void text_quad(struct sp_canvas *c, enum sp_layer layer, float x0, float y0, float x1,
                      float y1)
{
    c->quads = realloc(c->quads, (size_t)(c->n_quads + 1) * sizeof(*c->quads));
    c->items = realloc(c->items, (size_t)(c->n_items + 1) * sizeof(*c->items));
    if (!c->quads || !c->items)
        abort();
    c->cap_quads = c->n_quads + 1, c->cap_items = c->n_items + 1;
    c->quads[c->n_quads] = (struct sp_glyph_quad){{x0, y0, x1, y1}, {0, 0, 1, 1}, {1, 1, 1, 1}};
    c->items[c->n_items++] = (struct sp_item){
        .kind = SP_ITEM_TEXT, .layer = layer, .first = c->n_quads++, .count = 1};
}

static int rect_is(const struct sp_draw_rect *r, float x0, float y0, float x1, float y1,
                   const float fill[4])
{
    const float copy[4] = {0, 0, 0, -1};
    return r->rect[0] == x0 && r->rect[1] == y0 && r->rect[2] == x1 && r->rect[3] == y1 &&
           !memcmp(r->fill, fill ? fill : copy, sizeof(r->fill));
}

static void diag_rects(const char *what, const struct sp_draw_rect *r, int n)
{
    for (int i = 0; i < n; i++)
        sp_tap_diag("%s %d: %g %g %g %g fill alpha %g", what, i, r[i].rect[0], r[i].rect[1],
                    r[i].rect[2], r[i].rect[3], r[i].fill[3]);
}

/* The frame of the first checks: an opaque static box from (32, 32) to
 * (128, 96) px, a dynamic line that never moves, and a dynamic disc of
 * radius 5 at (x, 100). */
static void frame_box_disc(struct sp_canvas *c, float x)
{
    sp_canvas_reset(c);
    sp_canvas_rect(c, 32, 32, 128, 96, RED);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    sp_canvas_line(c, 260, 20, 300, 20, 1, GREEN);
    sp_canvas_shapes_begin(c); /* the disc as an item of its own */
    sp_canvas_disc(c, x, 100, 5, 0, GREEN);
}

static void check_base_and_damage(void)
{
    struct sp_draw_cache *k = NULL;
    struct sp_canvas c = {0};
    struct sp_draw_plan p;
    int planned;
    sp_tap_ok(sp_draw_cache_make(&k, W, H) == 0, "cache made");

    frame_box_disc(&c, 200);
    sp_tap_ok(sp_draw_cache_plan(k, &c, BG, &p) == 0, "frame 1 planned");
    sp_tap_ok(p.cached && p.rebuild && p.under == SP_DRAW_UNDER_REBUILT && !p.same && !p.n_new,
              "frame 1: base is built, in the target (cached %d rebuild %d under %d)", p.cached,
              p.rebuild, (int)p.under);
    /* the box's bounds (30, 30)-(130, 98) touch tiles 0..4 x 0..3; it fully
     * covers tiles 1..3 x 1..2, filled with red; runs joined down the rows */
    const int rects_ok = p.n_rects == 5 && rect_is(&p.rects[0], 0, 0, 160, 32, NULL) &&
                         rect_is(&p.rects[1], 0, 32, 32, 96, NULL) &&
                         rect_is(&p.rects[2], 32, 32, 128, 96, RED) &&
                         rect_is(&p.rects[3], 128, 32, 160, 96, NULL) &&
                         rect_is(&p.rects[4], 0, 96, 160, 128, NULL);
    if (!sp_tap_ok(rects_ok, "frame 1: base's 5 rectangles, the box's inside filled red"))
        diag_rects("rect", p.rects, p.n_rects);
    sp_draw_cache_drawn(k, &p);

    frame_box_disc(&c, 240);
    sp_tap_ok(sp_draw_cache_plan(k, &c, BG, &p) == 0, "frame 2 planned");
    sp_tap_ok(p.cached && !p.rebuild && p.under == SP_DRAW_UNDER_RESTORE && !p.n_new,
              "frame 2: base kept, the damage restored (rebuild %d under %d)", p.rebuild,
              (int)p.under);
    /* the disc's bounds were (193, 93)-(207, 107): 16 px tiles 12 x 5..6;
     * now (233, 93)-(247, 107): tiles 14..15 x 5..6 */
    const int damage_ok = p.n_damage == 4 && rect_is(&p.damage[0], 192, 80, 208, 96, NULL) &&
                          rect_is(&p.damage[1], 224, 80, 256, 96, NULL) &&
                          rect_is(&p.damage[2], 192, 96, 208, 112, NULL) &&
                          rect_is(&p.damage[3], 224, 96, 256, 112, NULL);
    if (!sp_tap_ok(damage_ok, "frame 2: the damage is the disc's old and new 16 px tiles"))
        diag_rects("damage", p.damage, p.n_damage);
    /* items: 0 the box, 1 the line, 2 the disc */
    sp_tap_ok(p.same && p.same[1] && !p.same[2],
              "frame 2: the line is left as frame 1 drew it, the disc redrawn");
    int first = -1, end = 0, runs = 0;
    for (int r = 0; r < p.n_damage; r++)
        for (first = -1; sp_draw_cache_run(k, p.list, 1, &p.damage[r], &first, &end); first = end)
            runs++;
    sp_tap_ok(runs == 0, "frame 2: the unchanged line meets no damage, so is not redrawn (%d runs)",
              runs);
    struct sp_draw_cache_stats st;
    sp_draw_cache_stats(k, &st);
    sp_tap_ok(st.cached == 2 && st.redrawn == 1 && st.unchanged == 1 && st.uncached == 0,
              "stats: 2 cached, 1 rebuilt, 1 unchanged item (%ld %ld %ld)", st.cached, st.redrawn,
              st.unchanged);

    /* not drawn: the target is not known to hold frame 2 */
    frame_box_disc(&c, 250);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.cached && !p.rebuild &&
                  p.under == SP_DRAW_UNDER_RECTS && !p.same,
              "a frame after one not drawn: background and base's rectangles (under %d)",
              (int)p.under);
    sp_draw_cache_drawn(k, &p);

    /* the static layer changes: base is rebuilt */
    frame_box_disc(&c, 250);
    c.shapes[0].color[1] = 0.5f;
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.rebuild && p.n_rects == 5 &&
                  p.rects[2].fill[1] == 0.5f,
              "a static box of another colour: base rebuilt, filled with it");
    sp_draw_cache_drawn(k, &p);
    frame_box_disc(&c, 250);
    c.shapes[0].color[1] = 0.5f;
    const float bg2[4] = {0, 0, 0.1f, 1};
    planned = sp_draw_cache_plan(k, &c, bg2, &p) == 0;
    sp_tap_ok(planned && p.rebuild,
              "another background: base rebuilt");

    /* the cache off: every layer drawn, the list as given */
    sp_draw_cache_set(k, 0);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && !p.cached && p.list == &c &&
                  p.under == SP_DRAW_UNDER_CLEAR,
              "cache off: uncached, cleared, the canvas as given");
    sp_draw_cache_set(k, 1);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.cached && p.rebuild,
              "cache on again: base rebuilt");
    sp_draw_cache_destroy(&k);
    sp_canvas_free(&c);
    sp_tap_ok(!k, "cache destroyed");
}

/* A chart: a settled path of n segments along y = 140 from x = 10, 10 px
 * each, clipped to (0, 120)-(320, 160), and a dynamic cursor. */
static void frame_chart(struct sp_canvas *c, int n, float first_y)
{
    static const float clip[4] = {0, 120, 320, 160};
    sp_canvas_reset(c);
    sp_canvas_clip(c, clip);
    sp_canvas_layer(c, SP_LAYER_SETTLED);
    sp_canvas_path_begin(c);
    for (int i = 0; i < n; i++)
        sp_canvas_line(c, 10 + 10 * i, i ? 140 : first_y, 20 + 10 * i, 140, 1, GREY);
    sp_canvas_path_end(c);
    sp_canvas_layer(c, SP_LAYER_DYNAMIC);
    sp_canvas_clip(c, NULL);
    sp_canvas_disc(c, 10 + 10 * n, 60, 3, 0, RED);
}

static void check_settled(void)
{
    struct sp_draw_cache *k = NULL;
    struct sp_canvas c = {0};
    struct sp_draw_plan p;
    int planned;
    sp_draw_cache_make(&k, W, H);
    frame_chart(&c, 3, 140);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.rebuild, "chart: base built");
    /* base holds the settled layer too: all its clip may cover, tiles
     * floor(-1/32) .. floor(321/32) x floor(119/32) .. floor(161/32) */
    const int chart_rects = p.n_rects == 1 && rect_is(&p.rects[0], 0, 96, 320, 180, NULL);
    if (!sp_tap_ok(chart_rects, "chart: base's one rectangle, the clip's tiles"))
        diag_rects("rect", p.rects, p.n_rects);
    sp_draw_cache_drawn(k, &p);

    frame_chart(&c, 5, 140);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.cached && !p.rebuild && p.n_new == 2 &&
                  p.settled_old && p.settled_old[0] == 3,
              "chart grown by 2 segments: base keeps 3, 2 appended (n_new %d)", p.n_new);
    /* new segments (40..60, 140) hw 1: bounds (37, 137)-(63, 143), 16 px
     * tiles 2..3 x 8; the cursor from (40, 60) to (60, 60), r 3: bounds
     * (35, 55)-(45, 65) and (55, 55)-(65, 65), tiles 2..4 x 3..4 */
    const int grow_ok = p.n_damage == 3 && rect_is(&p.damage[0], 32, 48, 80, 64, NULL) &&
                        rect_is(&p.damage[1], 32, 64, 80, 80, NULL) &&
                        rect_is(&p.damage[2], 32, 128, 64, 144, NULL);
    if (!sp_tap_ok(grow_ok, "chart grown: the damage is the cursor's tiles and the new segments'"))
        diag_rects("damage", p.damage, p.n_damage);
    const float *cl = sp_draw_cache_clip(k, 1);
    sp_tap_ok(cl[0] == 0 && cl[1] == 120 && cl[2] == 320 && cl[3] == 160,
              "the settled path is drawn under its clip");
    sp_draw_cache_drawn(k, &p);

    frame_chart(&c, 5, 140);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && !p.rebuild && p.n_new == 0,
              "chart unchanged: nothing appended");
    sp_draw_cache_drawn(k, &p);
    frame_chart(&c, 6, 130);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.rebuild,
              "chart whose first segment changed: base rebuilt, not appended to");
    struct sp_draw_cache_stats st;
    sp_draw_cache_stats(k, &st);
    sp_tap_ok(st.appended == 1 && st.redrawn == 2, "stats: 1 append, 2 rebuilds (%ld %ld)",
              st.appended, st.redrawn);
    sp_draw_cache_destroy(&k);
    sp_canvas_free(&c);
}

static void check_lift(void)
{
    struct sp_draw_cache *k = NULL;
    struct sp_canvas c = {0};
    struct sp_draw_plan p;
    int planned;
    sp_draw_cache_make(&k, W, H);
    /* 0: dynamic disc at (50, 50); 1: static line over it (drawn after it:
     * lifted); 2: static line far away (stays); 3: static text that the
     * settled path 4 crosses, and 5: static text after it over it (text is
     * drawn after every shape: both lifted); 6: a static box under a
     * dynamic disc drawn after it (stays); 7: that disc */
    sp_canvas_layer(&c, SP_LAYER_DYNAMIC);
    sp_canvas_disc(&c, 50, 50, 5, 0, RED);
    sp_canvas_layer(&c, SP_LAYER_STATIC);
    sp_canvas_line(&c, 40, 50, 60, 50, 1, GREEN);
    sp_canvas_shapes_begin(&c);
    sp_canvas_line(&c, 200, 20, 220, 20, 1, GREEN);
    text_quad(&c, SP_LAYER_STATIC, 130, 145, 140, 155);
    sp_canvas_layer(&c, SP_LAYER_SETTLED);
    sp_canvas_path_begin(&c);
    sp_canvas_line(&c, 100, 150, 150, 150, 1, GREY);
    sp_canvas_path_end(&c);
    text_quad(&c, SP_LAYER_STATIC, 110, 145, 120, 155);
    sp_canvas_layer(&c, SP_LAYER_STATIC);
    sp_canvas_rect(&c, 250, 100, 290, 140, GREEN);
    sp_canvas_layer(&c, SP_LAYER_DYNAMIC);
    sp_canvas_shapes_begin(&c);
    sp_canvas_disc(&c, 270, 120, 4, 0, RED);
    sp_tap_ok(c.n_items == 8, "lift canvas: 8 items (%d)", c.n_items);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.cached && p.list != &c,
              "lift: cached, the plan's own list");
    const struct sp_item *it = p.list->items;
    sp_tap_ok(it[1].layer == SP_LAYER_DYNAMIC, "a static line drawn after a dynamic disc it touches is lifted");
    sp_tap_ok(it[2].layer == SP_LAYER_STATIC, "a static line touching nothing stays static");
    sp_tap_ok(it[4].layer == SP_LAYER_SETTLED, "the settled path stays settled");
    sp_tap_ok(it[3].layer == SP_LAYER_DYNAMIC && it[5].layer == SP_LAYER_DYNAMIC,
              "static text over a settled path, before or after it in the list, is lifted");
    sp_tap_ok(it[6].layer == SP_LAYER_STATIC, "a static box under a dynamic disc drawn after it stays");
    sp_tap_ok(c.items[1].layer == SP_LAYER_STATIC && c.items[3].layer == SP_LAYER_STATIC &&
                  c.items[5].layer == SP_LAYER_STATIC,
              "the canvas given is unchanged");
    /* base holds only the static line far away, the box and the settled
     * path's whole frame (no clip): every tile is copied */
    sp_tap_ok(p.n_rects == 1 && rect_is(&p.rects[0], 0, 0, 320, 180, NULL),
              "an unclipped settled item: base copied everywhere (%d rects)", p.n_rects);
    sp_draw_cache_destroy(&k);
    sp_canvas_free(&c);
}

/* A static box at (0, 0)-(64, 64) and a new accumulated segment at y. */
static void frame_accum(struct sp_canvas *c, float y)
{
    sp_canvas_reset(c);
    sp_canvas_rect(c, 0, 0, 64, 64, RED);
    sp_canvas_layer(c, SP_LAYER_ACCUM);
    sp_canvas_line(c, 200, y, 210, y, 1, GREEN);
}

static void check_accum(void)
{
    struct sp_draw_cache *k = NULL;
    struct sp_canvas c = {0};
    struct sp_draw_plan p;
    int planned;
    sp_draw_cache_make(&k, W, H);
    frame_accum(&c, 90);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.accum && !p.accum_in_base && p.rebuild &&
                  !p.rects,
              "long exposure, frame 1: base built over it, no rectangles (a picture under all)");
    sp_draw_cache_drawn(k, &p);
    frame_accum(&c, 100); /* bounds (197, 97)-(213, 103): tiles 12..13 x 6 */
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.accum && p.accum_in_base && !p.rebuild &&
                  p.under == SP_DRAW_UNDER_RESTORE && p.n_damage == 1 &&
                  rect_is(&p.damage[0], 192, 96, 224, 112, NULL),
              "new segments apart from the box: drawn into base too, restored there (%d)",
              p.n_damage);
    sp_draw_cache_drawn(k, &p);
    frame_accum(&c, 30);
    c.shapes[1].seg[0] = 20; /* reaches into the box */
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && p.accum && !p.accum_in_base && p.rebuild,
              "new segments touching the box: base rebuilt over the long exposure");
    sp_draw_cache_set(k, 0);
    frame_accum(&c, 120);
    planned = sp_draw_cache_plan(k, &c, BG, &p) == 0;
    sp_tap_ok(planned && !p.cached && p.under == SP_DRAW_UNDER_ACCUM,
              "cache off with a long exposure: the picture under every layer");
    sp_draw_cache_destroy(&k);
    sp_canvas_free(&c);
}

int main(void)
{
    check_base_and_damage();
    check_settled();
    check_lift();
    check_accum();
    return sp_tap_done();
}
