/* springpend tests: figure layouts: without the pendulum a lone panel
 * fills the frame and several tile it; title and caption bands cover
 * nothing; every rectangle stays inside the frame at 4:3, 16:9, 9:16 and
 * square sizes from 320x240 to 7680x4320. */
#include <stdio.h>

#include "frame/layout.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

static const unsigned ALL = (1u << SP_PANEL_COUNT) - 1;

/* Checks every shown rectangle of l: inside w x h, no overlaps; returns
 * the number of problems (diagnosed). */
static int check(const struct sp_layout *l, unsigned panels, int w, int h, const char *what)
{
    struct sp_rect all[SP_PANEL_COUNT + 4];
    int n = 0, bad = 0;
    for (int b = 0; b < SP_PANEL_COUNT; b++) {
        if ((int)((panels >> b) & 1) != sp_rect_valid(&l->panel[b]))
            bad++, sp_tap_diag("%s %dx%d: panel %d shown wrongly", what, w, h, b);
        if ((panels >> b) & 1)
            all[n++] = l->panel[b];
    }
    if (sp_rect_valid(&l->camera))
        all[n++] = l->camera;
    if (sp_rect_valid(&l->hud))
        all[n++] = l->hud;
    if (sp_rect_valid(&l->title))
        all[n++] = l->title;
    if (sp_rect_valid(&l->caption))
        all[n++] = l->caption;
    for (int a = 0; a < n; a++) {
        const struct sp_rect *r = &all[a];
        if (r->x0 < 0 || r->y0 < 0 || r->x1 > w || r->y1 > h)
            bad++, sp_tap_diag("%s %dx%d: rect %d outside the frame", what, w, h, a);
        for (int c = a + 1; c < n; c++)
            if (sp_rect_overlap(r, &all[c]))
                bad++, sp_tap_diag("%s %dx%d: rects %d and %d overlap", what, w, h, a, c);
    }
    return bad;
}

int main(void)
{
    static const int sizes[][2] = {{320, 240}, {640, 360}, {854, 480}, {1024, 768},
                                   {1920, 1080}, {1080, 1920}, {1200, 1200}, {7680, 4320}};
    struct sp_layout l;
    int bad = 0;

    /* a lone panel fills the frame */
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        const int w = sizes[i][0], h = sizes[i][1];
        sp_layout_compute(&(struct sp_layout_desc){.width = w, .height = h,
                                                   .panels = SP_PANEL_POINCARE,
                                                   .no_pendulum = 1}, &l);
        const struct sp_rect *p = &l.panel[6];
        const float share = (p->x1 - p->x0) * (p->y1 - p->y0) / ((float)w * h);
        if (share < 0.9f || sp_rect_valid(&l.camera))
            bad++, sp_tap_diag("%dx%d: the lone panel covers %.2f of the frame", w, h, share);
        bad += check(&l, SP_PANEL_POINCARE, w, h, "lone");
    }
    sp_tap_ok(bad == 0, "without the pendulum a lone panel covers at least 90%% of the frame");

    /* several tile, in a grid near each kind's shape */
    bad = 0;
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        const int w = sizes[i][0], h = sizes[i][1];
        float area = 0;
        sp_layout_compute(&(struct sp_layout_desc){.width = w, .height = h, .panels = ALL,
                                                   .no_pendulum = 1}, &l);
        bad += check(&l, ALL, w, h, "tiled");
        for (int b = 0; b < SP_PANEL_COUNT; b++)
            area += (l.panel[b].x1 - l.panel[b].x0) * (l.panel[b].y1 - l.panel[b].y0);
        if (area < 0.75f * w * h)
            bad++, sp_tap_diag("%dx%d: 8 tiles cover only %.2f of the frame", w, h, area / w / h);
    }
    sp_tap_ok(bad == 0, "without the pendulum 8 panels tile at least 75%% of the frame, no overlap");

    sp_layout_compute(&(struct sp_layout_desc){.width = 1920, .height = 1080,
                                               .panels = SP_PANEL_PHASE_R | SP_PANEL_POINCARE,
                                               .no_pendulum = 1}, &l);
    sp_tap_ok(l.panel[4].x1 <= l.panel[6].x0 && l.panel[4].y0 == l.panel[6].y0,
              "two square panels at 16:9 sit side by side");

    /* title, caption and heads-up text never cover the panels or the view */
    bad = 0;
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++)
        for (int pend = 0; pend < 2; pend++) {
            const int w = sizes[i][0], h = sizes[i][1];
            sp_layout_compute(&(struct sp_layout_desc){
                .width = w, .height = h, .panels = ALL, .no_pendulum = !pend,
                .hud_height = 0.08f * h, .title_height = 0.04f * h, .caption_height = 0.05f * h}, &l);
            bad += check(&l, ALL, w, h, pend ? "titled" : "titled, no pendulum");
            if (!sp_rect_valid(&l.title) || !sp_rect_valid(&l.caption) || l.title.y0 < 0 ||
                l.caption.y1 > h || (pend && l.camera.y0 < l.title.y1))
                bad++, sp_tap_diag("%dx%d: title or caption misplaced", w, h);
        }
    sp_tap_ok(bad == 0, "title and caption bands cover nothing, with and without the pendulum");
    return sp_tap_done();
}
