/* springpend tests: the teaching overlays' pure parts: text rasterization
 * (text.c), the frame layout (layout.c), the Poincare crossings (frame.c)
 * and the axis memo (axis.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/frame.h"
#include "springpend/scene.h"
#include "springpend/sim.h"
#include "frame/axis.h"
#include "frame/layout.h"
#include "frame/panels.h"
#include "frame/text.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

#define TW 480
#define TH 64
static const char SAMPLE[] = "θ = 0, θ̇ > 0   ωₛ/ωₚ ≈ 2   r₀ = 1.5 m   g = 9.81 m/s²   ṙ Poincaré";

/* Lays SAMPLE out with a fresh font and returns its coverage image. */
static uint8_t *render_sample(int *ink)
{
    static const struct sp_font_desc fd = {.px = {12, 16, 22, 28}};
    static const float white[4] = {1, 1, 1, 1};
    struct sp_font *f = NULL;
    struct sp_glyph_quad q[256];
    uint8_t *img = calloc(TW * TH, 1);
    if (!img || sp_font_make(&f, &fd)) {
        free(img);
        return NULL;
    }
    const int n = sp_font_layout(f, SP_TEXT_NORMAL, SAMPLE, 4, 40, white, q, 256);
    sp_font_blit(f, q, n < 256 ? n : 256, img, TW, TH);
    *ink = 0;
    for (int i = 0; i < TW * TH; i++)
        *ink += img[i] > 128;
    sp_font_destroy(&f);
    return img;
}

static void test_text(void)
{
    static const struct sp_font_desc fd = {.px = {12, 16, 22, 28}};
    static const uint32_t needed[] = {0x03B8, 0x03C9, 0x2080, 0x00B2, 0x1E59, 0x0307,
                                      0x209B, 0x209A, 0x2248, 0x00E9, 0x2212, 0x2113};
    struct sp_font *f = NULL;
    int ink1 = 0, ink2 = 0, missing = 0;

    if (!sp_tap_ok(sp_font_make(&f, &fd) == 0, "font made from the embedded DejaVu Sans"))
        return;
    for (size_t i = 0; i < sizeof(needed) / sizeof(needed[0]); i++)
        if (!sp_font_has(f, needed[i])) {
            sp_tap_diag("no glyph for U+%04X", needed[i]);
            missing++;
        }
    sp_tap_ok(missing == 0, "the font has every Greek, sub/superscript and math glyph used");
    sp_tap_ok(sp_font_has(f, 0x4E2D), "a CJK character comes from a fallback font");
    sp_tap_ok(!sp_font_has(f, 0xFFFE) && !sp_font_has(f, 0x10FFFF), "noncharacters are in no font");
    const int wa = sp_font_width(f, SP_TEXT_NORMAL, "θ"), wb = sp_font_width(f, SP_TEXT_NORMAL, "θ̇");
    sp_tap_ok(wa > 0 && wa == wb, "a combining dot adds no width (%d, %d)", wa, wb);
    sp_tap_ok(sp_font_width(f, SP_TEXT_LARGE, "mmm") > sp_font_width(f, SP_TEXT_SMALL, "mmm"),
              "larger sizes are wider");
    sp_font_destroy(&f);
    sp_tap_ok(f == NULL, "destroy sets the font to NULL");

    uint8_t *a = render_sample(&ink1), *b = render_sample(&ink2);
    sp_tap_ok(a && b && ink1 > 400, "the sample string leaves ink (%d pixels)", ink1);
    sp_tap_ok(a && b && memcmp(a, b, TW * TH) == 0,
              "two fonts built apart render the string to the same glyph pixels");
    free(a);
    free(b);
}

static void test_layout(void)
{
    static const int sizes[][2] = {{1920, 1080}, {1280, 960}, {1080, 1920}, {640, 360},
                                   {3840, 2160}, {1000, 1000}};
    static const unsigned sets[] = {
        (1u << SP_PANEL_COUNT) - 1, SP_PANEL_R, SP_PANEL_POINCARE,
        SP_PANEL_R | SP_PANEL_THETA | SP_PANEL_ENERGY | SP_PANEL_EXTENSION,
        SP_PANEL_PHASE_R | SP_PANEL_PHASE_THETA | SP_PANEL_POINCARE,
        SP_PANEL_ENERGY | SP_PANEL_POINCARE};
    for (size_t i = 0; i < sizeof(sizes) / sizeof(sizes[0]); i++) {
        const int W = sizes[i][0], H = sizes[i][1];
        int bad = 0;
        for (size_t s = 0; s < sizeof(sets) / sizeof(sets[0]); s++) {
            for (int extras = 0; extras < 2; extras++) {
                struct sp_layout l;
                struct sp_rect all[SP_PANEL_COUNT + 3];
                int n = 0;
                sp_layout_compute(&(struct sp_layout_desc){.width = W, .height = H, .panels = sets[s],
                                                           .hud_height = extras ? 0.08f * H : 0,
                                                           .colorbar_width = extras ? 0.06f * W : 0}, &l);
                all[n++] = l.camera;
                if (extras) {
                    all[n++] = l.hud;
                    all[n++] = l.colorbar;
                }
                for (int b = 0; b < SP_PANEL_COUNT; b++) {
                    const int want = (sets[s] >> b) & 1;
                    if (want != sp_rect_valid(&l.panel[b]))
                        bad++, sp_tap_diag("%dx%d set %zu: panel %d shown %d", W, H, s, b, !want);
                    if (want)
                        all[n++] = l.panel[b];
                }
                for (int a = 0; a < n; a++) {
                    const struct sp_rect *r = &all[a];
                    const float min_side = a == 0 ? 0.25f * (W < H ? W : H) : 0.05f * (W < H ? W : H);
                    if (!sp_rect_valid(r) || r->x0 < 0 || r->y0 < 0 || r->x1 > W || r->y1 > H ||
                        r->x1 - r->x0 < min_side || r->y1 - r->y0 < min_side) {
                        bad++;
                        sp_tap_diag("%dx%d set %zu: rect %d (%.0f %.0f %.0f %.0f) outside the "
                                    "frame or too small", W, H, s, a, r->x0, r->y0, r->x1, r->y1);
                    }
                    for (int c = a + 1; c < n; c++)
                        if (sp_rect_overlap(r, &all[c])) {
                            bad++;
                            sp_tap_diag("%dx%d set %zu: rects %d and %d overlap", W, H, s, a, c);
                        }
                }
            }
        }
        sp_tap_ok(bad == 0, "layout at %dx%d: every panel inside the frame, none overlapping",
                  W, H);
    }
}

/* Runs scene text for `seconds` with the Poincare panel, sampling at 60 Hz. */
static int run_history(const char *text, double seconds, struct sp_scene *sc,
                       struct sp_history *h, struct sp_sim *sim)
{
    sp_scene_defaults(sc);
    if (sp_scene_parse(sc, text, "test.ini", NULL, 0) || sp_history_make(h, sc))
        return 1;
    sp_sim_init(sim, sc);
    for (int k = 0; k <= (int)(seconds * 60); k++)
        if (sp_history_follow(h, sim, k / 60.0))
            return 1;
    return 0;
}

static void test_poincare(void)
{
    struct sp_scene sc;
    struct sp_history h;
    struct sp_sim sim;

    /* Pure bounce: theta stays 0, it is never crossed with dtheta/dt > 0. */
    int err = run_history("[pendulum]\nnatural_length = 1\nstiffness = 20\nmass = 1\n"
                          "[initial]\nlength = 1.79\nangle = 0\n[view]\npanels = poincare\n",
                          20, &sc, &h, &sim);
    sp_tap_ok(!err && h.count > 1000 && h.n_crossings == 0,
              "pure bounce: no Poincare points in 20 s (%d)", h.n_crossings);
    sp_history_destroy(&h);

    /* Small swing of a stiff spring from rest at the equilibrium length: the
     * bob passes theta = 0 once per swing period 2 pi sqrt(l/g), at r = l
     * (to the centrifugal stretch, ~ l theta0^2 omega_p^2/omega_s^2) with r' ~ 0. */
    const double k = 5000, m = 1, L0 = 1, g = 9.81;
    const double ell = L0 + m * g / k, period = 2 * M_PI * sqrt(ell / g);
    char text[512];
    snprintf(text, sizeof(text), "[pendulum]\nnatural_length = %g\nstiffness = %g\nmass = %g\n"
             "[initial]\nlength = %.10f\nangle = 2\n[integrator]\ndt = 0.0002\n"
             "[view]\npanels = poincare\n", L0, k, m, ell);
    err = run_history(text, 30, &sc, &h, &sim);
    const int expected = (int)floor((30 - 0.75 * period) / period) + 1;
    double worst_r = 0, worst_rd = 0, worst_gap = 0;
    for (int i = 0; i < h.n_crossings; i++) {
        worst_r = fmax(worst_r, fabs(h.crossings[i].r - ell));
        worst_rd = fmax(worst_rd, fabs(h.crossings[i].r_dot));
        if (i)
            worst_gap = fmax(worst_gap, fabs(h.crossings[i].t - h.crossings[i - 1].t - period));
    }
    sp_tap_ok(!err && h.n_crossings == expected, "small swing: %d crossings in 30 s, one per "
              "period %.4f s (%d)", expected, period, h.n_crossings);
    sp_tap_ok(h.n_crossings > 0 && worst_r < 2e-4 && worst_rd < 2e-3,
              "small swing: every point at r = l = %.5f m, r' = 0 (worst %.2g m, %.2g m/s)",
              ell, worst_r, worst_rd);
    sp_tap_ok(h.n_crossings > 1 && worst_gap < 2e-3 * period,
              "small swing: crossings one period apart (worst %.2g s off)", worst_gap);

    /* Exactness: at each crossing time the motion itself (integrated there
     * directly) has x = 0 and the same r, r'. Frames are 1/60 s apart, so a
     * nearest-sample answer would be off by up to ~1e-2 s. */
    double worst_x = 0, worst_dr = 0;
    for (int i = 0; i < h.n_crossings && i < 6; i++) {
        struct sp_sim ref;
        struct sp_polar pol;
        sp_sim_init(&ref, &sc);
        for (int j = 1; j * (1 / 60.0) < h.crossings[i].t; j++) /* the same stops as the run */
            sp_sim_advance(&ref, j / 60.0);
        sp_sim_advance(&ref, h.crossings[i].t);
        sp_state_polar(&ref.s, &pol);
        worst_x = fmax(worst_x, fabs(ref.s.x));
        worst_dr = fmax(worst_dr, fabs(pol.r_dot - h.crossings[i].r_dot));
    }
    sp_tap_ok(worst_x < 1e-7 && worst_dr < 1e-5, "crossings located exactly: |x| <= %.2g m, "
              "r' off by %.2g m/s at the interpolated times", worst_x, worst_dr);
    sp_history_destroy(&h);

    /* Panels not asked for cost nothing. */
    err = run_history("[view]\npanels = none\n", 2, &sc, &h, &sim);
    sp_tap_ok(!err && !h.active && h.samples == NULL && h.count == 0,
              "without panels no history is kept");
}

/* The colour maps against matplotlib 3.6's own values (colormaps[NAME](t),
 * printed with Debian's python3-matplotlib), and gray's black to white. */
static void test_colormaps(void)
{
    static const struct {
        int map;
        const char *name;
        float t, rgb[3];
    } want[] = {
        {SP_COLORMAP_MAGMA, "magma", 0, {0.001462f, 0.000466f, 0.013866f}},
        {SP_COLORMAP_MAGMA, "magma", 0.25f, {0.316654f, 0.071690f, 0.485380f}},
        {SP_COLORMAP_MAGMA, "magma", 0.5f, {0.716387f, 0.214982f, 0.475290f}},
        {SP_COLORMAP_MAGMA, "magma", 1, {0.987053f, 0.991438f, 0.749504f}},
        {SP_COLORMAP_CIVIDIS, "cividis", 0, {0.0f, 0.135112f, 0.304751f}},
        {SP_COLORMAP_CIVIDIS, "cividis", 0.25f, {0.263738f, 0.307831f, 0.422789f}},
        {SP_COLORMAP_CIVIDIS, "cividis", 0.5f, {0.488697f, 0.485318f, 0.471008f}},
        {SP_COLORMAP_CIVIDIS, "cividis", 1, {0.995737f, 0.909344f, 0.217772f}},
        {SP_COLORMAP_GRAY, "gray", 0, {0, 0, 0}},
        {SP_COLORMAP_GRAY, "gray", 0.5f, {0.5f, 0.5f, 0.5f}},
        {SP_COLORMAP_GRAY, "gray", 1, {1, 1, 1}},
    };
    for (size_t i = 0; i < sizeof(want) / sizeof(want[0]); i++) {
        float rgb[3];
        sp_colormap(want[i].map, want[i].t, rgb);
        float off = 0;
        for (int k = 0; k < 3; k++)
            off = fmaxf(off, fabsf(rgb[k] - want[i].rgb[k]));
        /* 8-bit entries, and matplotlib picks entry floor(256 t) where we
         * interpolate: within 1.5 levels */
        sp_tap_ok(off <= 1.5f / 255, "%s(%g) = (%.4f, %.4f, %.4f), matplotlib's within %.4f",
                  want[i].name, want[i].t, rgb[0], rgb[1], rgb[2], off);
    }
}

/* A made-up label measure: 7 units a byte, +3 per '.', counting its calls. */
static int measure_calls;
static double measure(void *ctx, const char *label)
{
    (void)ctx;
    measure_calls++;
    double w = 0;
    for (const char *s = label; *s; s++)
        w += *s == '.' ? 10 : 7;
    return w;
}

/* The memo gives what the plain calls give (fits, ticks, labels, widths),
 * and a fit or a tick list asked again at once is not worked out again:
 * 200 ranges of every size (tiny spans, offsets, negative), three times
 * (each pass finds its entries replaced by the 200 after them, in a
 * 32-entry memo). */
static void test_axis_memo(void)
{
    struct sp_axis_memo *m = NULL;
    if (!sp_tap_ok(sp_axis_memo_make(&m) == 0, "axis memo made"))
        return;
    int bad = 0, again_calls = 0, ticks_max = 0, hits = 0;
    for (int pass = 0; pass < 3; pass++) {
        srand(7);
        for (int i = 0; i < 200; i++) {
            const double mag = pow(10, rand() % 25 - 12), lo = (rand() % 2001 - 1000) * mag / 100;
            const double span = mag * pow(10, -(rand() % 8)) * (1 + rand() % 9);
            const double length = 40 + rand() % 600, line = 8 + rand() % 12;
            const int vertical = rand() % 2;
            struct sp_axis plain, memo;
            sp_axis_range(&plain, lo, lo + span, 0.06);
            memo = plain;
            sp_axis_fit(&plain, length, line, measure, NULL, vertical);
            const int before = measure_calls;
            sp_axis_fit_memo(m, &memo, length, line, measure, NULL, vertical);
            struct sp_axis_ticks scratch;
            const struct sp_axis_ticks *t = sp_axis_ticks_of(m, &memo, measure, NULL, &scratch);
            if (measure_calls == before) /* a hit: the first pass had none */
                hits++;
            struct sp_axis again = plain;
            sp_axis_range(&again, lo, lo + span, 0.06);
            const int before_again = measure_calls;
            sp_axis_fit_memo(m, &again, length, line, measure, NULL, vertical);
            const struct sp_axis_ticks *t2 = sp_axis_ticks_of(m, &again, measure, NULL, &scratch);
            again_calls += measure_calls - before_again;
            bad += t2 != t;
            bad += memcmp(&plain.step, &memo.step, sizeof(double)) || plain.first != memo.first ||
                   plain.decimals != memo.decimals || plain.offset != memo.offset ||
                   plain.offset_decimals != memo.offset_decimals;
            int k = 0;
            char buf[SP_AXIS_LABEL_BYTES];
            for (double v = plain.first; v <= plain.hi + 1e-9 * plain.step; v += plain.step, k++) {
                sp_axis_label(&plain, v, buf, sizeof(buf));
                bad += k >= t->n || t->v[k] != v || strcmp(t->label[k], buf) ||
                       t->width[k] != measure(NULL, buf);
            }
            bad += k != t->n;
            ticks_max = t->n > ticks_max ? t->n : ticks_max;
        }
    }
    sp_tap_ok(bad == 0, "axis memo: 600 fits and tick lists as the plain calls give them (%d differ)",
              bad);
    sp_tap_ok(ticks_max <= 11, "a fitted axis has at most 11 ticks (%d)", ticks_max);
    sp_tap_ok(again_calls == 0, "axis memo: a fit and ticks asked again measure nothing (%d calls)",
              again_calls);
    sp_tap_ok(hits == 0, "axis memo: 200 ranges later, a range's entries were replaced (%d hits)",
              hits);
    free(m);
}

/* The axis's name with its power of ten (and offset), and minus signs in
 * printf's text: the strings, written out by hand. */
static void test_axis_names(void)
{
    struct sp_axis a;
    char buf[128];
    sp_axis_range(&a, 0, 5e19, 0);
    sp_axis_fit(&a, 300, 12, measure, NULL, 1);
    sp_axis_name(&a, "E (J)", buf, sizeof(buf));
    sp_tap_ok(a.exponent == 19 && !strcmp(buf, "E (\u00d710\u00b9\u2079 J)"),
              "0..5e19 J: exponent %d, name '%s'", a.exponent, buf);
    sp_axis_label(&a, 3e19, buf, sizeof(buf));
    sp_tap_ok(a.step == 5e18 && !strcmp(buf, "3.0"), "3e19 in units of 1e19, ticks 0.5 apart: '%s'",
              buf);
    sp_axis_name(&a, "n", buf, sizeof(buf));
    sp_tap_ok(!strcmp(buf, "n (\u00d710\u00b9\u2079)"), "a name without a unit: '%s'", buf);
    sp_axis_range(&a, -2e-10, 0, 0);
    sp_axis_fit(&a, 300, 12, measure, NULL, 1);
    sp_axis_name(&a, "x (m)", buf, sizeof(buf));
    sp_tap_ok(a.exponent == -10 && !strcmp(buf, "x (\u00d710\u207b\u00b9\u2070 m)"),
              "-2e-10..0 m: exponent %d, name '%s'", a.exponent, buf);
    sp_axis_label(&a, -1.5e-10, buf, sizeof(buf));
    sp_tap_ok(!strcmp(buf, "\u22121.5"), "-1.5e-10 in units of 1e-10: '%s'", buf);
    sp_axis_range(&a, 12345678.0, 12345678.5, 0); /* a small range around a large value */
    sp_axis_fit(&a, 300, 12, measure, NULL, 1);
    sp_axis_name(&a, "r (m)", buf, sizeof(buf));
    sp_tap_ok(a.exponent == 0 && a.offset == 12345678 &&
              !strcmp(buf, "r \u2212 1.2345678\u00d710\u2077 (m)"),
              "12345678..12345678.5 m: offset %.17g written '%s'", a.offset, buf);
    sp_axis_range(&a, 0, 999999, 0);
    sp_axis_fit(&a, 300, 12, measure, NULL, 1);
    sp_axis_name(&a, "m (kg)", buf, sizeof(buf));
    sp_tap_ok(a.exponent == 0 && !strcmp(buf, "m (kg)"), "0..999999: no power of ten ('%s')", buf);
    char m[96] = "λ3 = -0.0754 1/s, sum -8e-10, Kaplan-Yorke, k-2, +1, -1 turn";
    sp_axis_minus(m, sizeof(m));
    sp_tap_ok(!strcmp(m, "λ3 = \u22120.0754 1/s, sum \u22128e\u221210, Kaplan-Yorke, k-2, +1, "
                         "\u22121 turn"), "minus signs: '%s'", m);
    char cut[8] = "a -1 -2";
    sp_axis_minus(cut, sizeof(cut));
    sp_tap_ok(!strcmp(cut, "a \u22121 "), "minus signs within 8 bytes: '%s'", cut);
}

int main(void)
{
    test_text();
    test_layout();
    test_poincare();
    test_colormaps();
    test_axis_memo();
    test_axis_names();
    return sp_tap_done();
}
