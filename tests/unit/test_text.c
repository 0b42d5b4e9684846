/* springpend tests: the text layout module (text.c) on every script a
 * teacher would use: no missing glyph (.notdef) in the layout, distinct
 * characters draw distinct ink, Arabic letters take their joined forms,
 * mixed-direction lines are ordered right to left around left-to-right
 * numbers and units, marks sit on their bases, a font is chosen by its
 * fontconfig family, and what no font has, or a family that is not
 * installed, is refused. The PNG/SVG/PDF outputs are test_text.py's. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "frame/text.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

#define W 1200
#define H 80

static const struct {
    const char *name, *text;
} scripts[] = {
    {"Latin with diacritics", "Federpendel: Größe ß ł ő ø ñ Łódź Å"},
    {"Latin with combining marks", "x\xcc\x83 e\xcc\x81 a\xcc\x8a n\xcc\x83 \xce\xb8\xcc\x87"}, /* x̃ é å ñ θ̇ */
    {"Greek", "Ελατήριο εκκρεμές ωθ"},
    {"Cyrillic", "Пружинный маятник"},
    {"CJK", "弹簧摆 ばね振り子 용수철"},
    {"Arabic", "البندول الزنبركي"},
    {"Hebrew", "מטוטלת קפיץ"},
    {"Devanagari", "स्प्रिंग लोलक"},
    {"mixed direction", "البندول 2 m/s"},
};

/* Coverage image of utf8 laid out at the normal size. */
static uint8_t *ink_of(const struct sp_font *f, const char *utf8)
{
    static const float white[4] = {1, 1, 1, 1};
    uint8_t *img = calloc(W * H, 1);
    int n = sp_font_layout(f, SP_TEXT_NORMAL, utf8, 4, 50, white, NULL, 0);
    struct sp_glyph_quad *q = calloc((size_t)(n > 0 ? n : 1), sizeof(*q));
    if (img && q && n >= 0)
        sp_font_blit(f, q, sp_font_layout(f, SP_TEXT_NORMAL, utf8, 4, 50, white, q, n), img, W, H);
    free(q);
    return img;
}

static int ink_count(const uint8_t *img)
{
    int n = 0;
    for (int i = 0; i < W * H; i++)
        n += img[i] > 96;
    return n;
}

/* The next UTF-8 character of s (its bytes into out), or 0 at the end. */
static size_t next_char(const char *s, char out[8])
{
    const size_t n = sp_utf8_char(s);
    memcpy(out, s, n);
    out[n] = 0;
    return n;
}

static void test_script(const struct sp_font *f, const char *name, const char *text)
{
    struct sp_line l;
    int notdef = 0;
    sp_tap_ok(sp_font_check(f, name, text) == 0, "%s: every character is in an installed font", name);
    /* shaped first: the message's arguments are read before sp_tap_ok runs */
    const int shaped = sp_font_shape(f, SP_TEXT_NORMAL, text, &l) == 0;
    sp_tap_ok(shaped && l.n_glyphs > 0 && l.missing == 0,
              "%s: laid out (%d glyphs in %d runs, %d px)", name, l.n_glyphs, l.n_runs, l.width);
    for (int i = 0; i < l.n_glyphs; i++)
        notdef += l.glyphs[i].index == 0;
    sp_tap_ok(notdef == 0, "%s: no .notdef glyph in the layout (%d)", name, notdef);

    /* distinct characters (spaces and marks aside) draw distinct ink */
    char chars[64][8];
    uint8_t *ink[64];
    int n = 0, same = 0, blank = 0;
    for (const char *s = text; *s && n < 64;) {
        char c[8];
        s += next_char(s, c);
        const unsigned char u0 = (unsigned char)c[0];
        if (c[0] == ' ' || (u0 == 0xCC || u0 == 0xCD) || !strcmp(c, "\xe0\xa5\x8d") /* virama */)
            continue;
        int seen = 0;
        for (int k = 0; k < n; k++)
            seen |= !strcmp(chars[k], c);
        if (seen)
            continue;
        strcpy(chars[n], c);
        ink[n] = ink_of(f, c);
        blank += ink_count(ink[n]) == 0;
        n++;
    }
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++)
            if (!memcmp(ink[a], ink[b], W * H)) {
                sp_tap_diag("%s and %s draw the same", chars[a], chars[b]);
                same++;
            }
    sp_tap_ok(n > 1 && same == 0 && blank == 0, "%s: its %d distinct characters draw distinct ink", name, n);
    for (int k = 0; k < n; k++)
        free(ink[k]);
}

/* The glyph index that a character takes alone and inside a word. */
static unsigned glyph_alone(const struct sp_font *f, const char *c)
{
    struct sp_line l;
    return sp_font_shape(f, SP_TEXT_NORMAL, c, &l) == 0 && l.n_glyphs == 1 ? l.glyphs[0].index : 0;
}

static void test_arabic(const struct sp_font *f)
{
    /* "سلم": seen, lam, meem join on both sides: initial, medial, final forms */
    static const char *word = "سلم", *letters[] = {"س", "ل", "م"};
    struct sp_line l;
    int joined = 0;
    sp_font_shape(f, SP_TEXT_NORMAL, word, &l);
    for (int i = 0; i < l.n_glyphs; i++) { /* glyphs left to right: meem first */
        const unsigned alone = glyph_alone(f, letters[2 - i]);
        sp_font_shape(f, SP_TEXT_NORMAL, word, &l);
        joined += alone && l.glyphs[i].index != alone;
    }
    sp_tap_ok(l.n_glyphs == 3 && joined == 3, "Arabic: each letter of a word takes a joined form (%d of %d)",
              joined, l.n_glyphs);
    sp_tap_ok(l.n_runs == 1 && l.runs[0].rtl, "Arabic: the word is one right-to-left run");
    sp_tap_ok(l.n_glyphs == 3 && l.glyphs[0].cluster > l.glyphs[2].cluster,
              "Arabic: its first letter is drawn rightmost");

    /* "البندول 2 m/s": the Arabic word at the right, "2 m/s" left of it in
     * its own order (an RTL paragraph) */
    const char *mixed = "البندول 2 m/s";
    sp_font_shape(f, SP_TEXT_NORMAL, mixed, &l);
    const char *two = strchr(mixed, '2'), *m = strchr(mixed, 'm');
    int x_arabic = -1, x_two = -1, x_m = -1;
    for (int i = 0; i < l.n_glyphs; i++) {
        const char *at = mixed + l.glyphs[i].cluster;
        if (at == two)
            x_two = l.glyphs[i].x;
        else if (at == m)
            x_m = l.glyphs[i].x;
        else if (at == mixed)
            x_arabic = l.glyphs[i].x;
    }
    sp_tap_ok(x_m >= 0 && x_m < x_two && x_two < x_arabic,
              "mixed direction: \"m/s\" left of \"2\", left of the Arabic word (x %d < %d < %d)",
              x_m, x_two, x_arabic);

    /* its stretches: "2 m/s" (bytes 15..20, after seven two-byte letters
     * and a space) is one, of the runs "m/s", " ", "2"; the Arabic word
     * (with the space after it) is its own; and in "سرعة 2.5 m/s في" the
     * stretch "2.5 m/s" stops before the space that leads back to Arabic */
    int in = 0, alone = 0;
    for (int i = 0; i < l.n_runs; i++) {
        const struct sp_glyph_run *r = &l.runs[i];
        in += r->start >= 15 && r->span_start == 15 && r->span_end == 20;
        alone += r->start < 15 && r->span_start == r->start && r->span_end == r->end;
    }
    sp_tap_ok(l.n_runs == 4 && in == 3 && alone == 1,
              "mixed direction: \"2 m/s\" is one stretch of 3 runs, the Arabic its own (%d runs: "
              "%d, %d)", l.n_runs, in, alone);
    const char *longer = "سرعة 2.5 m/s في";
    sp_font_shape(f, SP_TEXT_NORMAL, longer, &l);
    const int a = (int)(strchr(longer, '2') - longer), b = (int)(strchr(longer, 's') - longer) + 1;
    in = 0;
    for (int i = 0; i < l.n_runs; i++)
        in += l.runs[i].span_start == a && l.runs[i].span_end == b;
    sp_tap_ok(in == 3, "mixed direction: \"2.5 m/s\" between Arabic words is one stretch of 3 runs (%d)",
              in);
    const char *plain = "Federpendel 2 m/s";
    sp_font_shape(f, SP_TEXT_NORMAL, plain, &l);
    sp_tap_ok(l.n_runs == 1 && l.runs[0].span_start == 0 && l.runs[0].span_end == (int)strlen(plain),
              "a left-to-right line is one run, its own stretch");
}

static void test_marks(const struct sp_font *f)
{
    struct sp_line l;
    const int wa = sp_font_width(f, SP_TEXT_NORMAL, "θ"), wb = sp_font_width(f, SP_TEXT_NORMAL, "θ̇");
    sp_tap_ok(wa > 0 && wa == wb, "a combining dot adds no width (%d, %d)", wa, wb);
    sp_font_shape(f, SP_TEXT_NORMAL, "θ̇", &l);
    sp_tap_ok(l.n_glyphs == 2 && l.glyphs[1].mark && l.glyphs[1].y < 0 && l.glyphs[1].x >= 0 &&
                  l.glyphs[1].x < wa,
              "the dot of θ̇ is a mark placed over the θ (x %d, y %d)", l.n_glyphs == 2 ? l.glyphs[1].x : -1,
              l.n_glyphs == 2 ? l.glyphs[1].y : 0);
}

static void test_refusals(const struct sp_font *f)
{
    static const struct {
        const char *text, *code;
    } missing[] = {
        {"test tube \xf0\x9f\xa7\xaa", "U+1F9EA"},
        {"x \xef\xbf\xbe", "U+FFFE"},
        {"x \xef\xbf\xbf", "U+FFFF"},
        {"x \xf4\x8f\xbf\xbf", "U+10FFFF"},
    };
    for (size_t i = 0; i < sizeof(missing) / sizeof(missing[0]); i++)
        sp_tap_ok(sp_font_check(f, "test", missing[i].text) == SP_E_INPUT,
                  "%s is in no installed font: refused", missing[i].code);
    sp_tap_ok(sp_font_check(f, "test", "𝜃 = 0") == 0, "a mathematical italic θ (U+1D703) is in a font");
    sp_tap_ok(sp_font_check(f, "test", "\xf0\x9f\x98\x80") == 0, "an emoji (U+1F600) is in a font");
    sp_tap_ok(sp_font_check(f, "test", "bad \xc3") == SP_E_INPUT, "malformed UTF-8 is refused");
    sp_tap_ok(sp_font_check(f, "test", "a\xe2\x80\x8d\xe2\x80\x8f") == 0,
              "invisible format characters need no glyph");
}

static void test_families(void)
{
    struct sp_font *f = NULL;
    struct sp_font_desc d = {.family = "Latin Modern Roman", .px = {12, 16, 22, 28}};
    int index;
    const unsigned char *data;
    size_t size;
    const int made = sp_font_make(&f, &d) == 0;
    const char *file = made ? sp_font_face_file(f, 0, &index, &data, &size) : NULL;
    sp_tap_ok(made && file && strstr(file, "lmroman"), "Latin Modern Roman is found (%s)",
              file ? file : "none");
    if (f) {
        struct sp_line a, b;
        sp_font_shape(f, SP_TEXT_NORMAL, "Federpendel θ 弹簧", &a);
        int faces = 0;
        for (int i = 0; i < a.n_runs; i++)
            faces += i == 0 || a.glyphs[a.runs[i].first].face != a.glyphs[a.runs[i - 1].first].face;
        sp_tap_ok(a.missing == 0 && faces >= 2, "Latin Modern falls back to other fonts for CJK (%d faces)", faces);
        (void)b;
    }
    sp_font_destroy(&f);
    d.family = "latin modern roman";
    sp_tap_ok(sp_font_make(&f, &d) == 0, "a family's name is matched without regard to case");
    sp_font_destroy(&f);
    d.family = "Latin Modren Roman";
    sp_tap_ok(sp_font_make(&f, &d) == SP_E_INPUT && !f, "an unknown family is refused");
    d.family = "DejaVu Serif";
    sp_tap_ok(sp_font_make(&f, &d) == 0, "DejaVu Serif is found");
    sp_font_destroy(&f);
}

/* 1 when two layouts are the same glyphs at the same places. */
static int same_line(const struct sp_line *a, const struct sp_line *b)
{
    if (a->width != b->width || a->missing != b->missing || a->n_glyphs != b->n_glyphs ||
        a->n_runs != b->n_runs)
        return 0;
    for (int i = 0; i < a->n_glyphs; i++) {
        const struct sp_glyph *x = &a->glyphs[i], *y = &b->glyphs[i];
        if (x->index != y->index || x->face != y->face || x->x != y->x || x->y != y->y ||
            x->cluster != y->cluster || x->mark != y->mark)
            return 0;
    }
    for (int i = 0; i < a->n_runs; i++) {
        const struct sp_glyph_run *x = &a->runs[i], *y = &b->runs[i];
        if (x->first != y->first || x->count != y->count || x->rtl != y->rtl || x->start != y->start ||
            x->end != y->end || x->span_start != y->span_start || x->span_end != y->span_end)
            return 0;
    }
    return 1;
}

/* The shape cache: a line joined from cached pieces (a clock's digits) is
 * the line HarfBuzz gives for the whole string, in four families and every
 * size, for clocks, readouts, kerning and ligature candidates next to
 * digits, marks on digits, other scripts' digits and mixed directions; an
 * unchanged string is never shaped again; a new clock reading after the
 * first few shapes nothing; text used every frame survives the eviction of
 * thousands of one-off strings. */
static void test_shape_cache(void)
{
    static const char *family[] = {NULL, "DejaVu Serif", "Latin Modern Roman", "Noto Sans"};
    static const char *fixed[] = {
        "speed \xc3\x97" "0.25", "\xe2\x88\x92" "12.3\xc2\xb0", "\xce\xb8 = 12\xc2\xb0",
        "E = 1.234 J", "10:00 11", "x1\xcc\x87" "2", "V1A T1 Y7 L1 11 17 74", "ff1fi fl2ffl", "AV1VA Yo7oY f1f 7ff L'1 '7' P4. r7, W0W",
        "(1) [2] {3} 1/2 \xe2\x82\x81" "2", "\xe5\xbc\xb9\xe7\xb0\xa7 12", "\xce\x95\xce\xbb 3 \xce\xbb",
        "\xd8\xa7\xd9\x84\xd8\xa8\xd9\x86\xd8\xaf\xd9\x88\xd9\x84 2 m/s", "\xd8\xa8" "2" "\xd8\xa8",
        "\xe0\xa5\xa7\xe0\xa5\xa8" "3 \xe0\xa4\x95" "4", "12ab", "1", "42", "3.", ".5", " 7 ",
        "\xd7\xa9\xd7\x9c\xd7\x95\xd7\x9d 12", "\xe2\x80\x8f" "12", "a\xe2\x80\x8d" "1",
    };
    int all_same = 1, composed_total = 0;
    char bad[160] = "";
    for (size_t k = 0; k < sizeof(family) / sizeof(family[0]); k++) {
        struct sp_font_desc d = {.family = family[k], .px = {11, 17, 23, 31}};
        struct sp_font *f = NULL, *w = NULL;
        if (sp_font_make(&f, &d)) {
            sp_tap_ok(0, "shape cache: the family %s", family[k] ? family[k] : "default");
            continue;
        }
        d.whole_lines = 1;
        sp_font_make(&w, &d);
        char s[64];
        for (int size = 0; size < SP_TEXT_SIZES; size++)
            for (int i = 0; i < 1200 + (int)(sizeof(fixed) / sizeof(fixed[0])); i++) {
                if (i < 1000)
                    snprintf(s, sizeof(s), "t = %.2f s", i * 0.37);
                else if (i < 1100)
                    snprintf(s, sizeof(s), "%+.3g m, %d Hz", (i - 1050) * 0.0123, i);
                else if (i < 1200)
                    snprintf(s, sizeof(s), "\xce\xb8 = %.1f\xc2\xb0 (%d)", (i - 1150) * 1.7, i);
                else
                    snprintf(s, sizeof(s), "%s", fixed[i - 1200]);
                struct sp_line a, b;
                if (sp_font_shape(f, size, s, &a) || sp_font_shape(w, size, s, &b) || !same_line(&a, &b)) {
                    if (all_same)
                        snprintf(bad, sizeof(bad), "%s, size %d: \"%s\"", family[k] ? family[k] : "default",
                                 size, s);
                    all_same = 0;
                }
            }
        int shaped, composed, whole_composed;
        sp_font_shape_stats(f, &shaped, &composed);
        sp_font_shape_stats(w, &whole_composed, &whole_composed);
        sp_tap_ok(composed > 1000 && whole_composed == 0,
                  "shape cache, %s: %d of %d lines joined from cached pieces (none when shaping whole)",
                  family[k] ? family[k] : "DejaVu Sans", composed, composed + shaped);
        composed_total += composed;
        sp_font_destroy(&f);
        sp_font_destroy(&w);
    }
    sp_tap_ok(all_same, "shape cache: every line joined from pieces equals the whole line shaped (%s)",
              bad[0] ? bad : "all");

    static const struct sp_font_desc fd = {.px = {12, 20, 22, 28}};
    struct sp_font *f = NULL;
    if (sp_font_make(&f, &fd))
        return;
    struct sp_line l;
    int before, after, composed;
    sp_font_shape(f, SP_TEXT_NORMAL, "Energy of the spring", &l);
    sp_font_shape(f, SP_TEXT_NORMAL, "t = 0.00 s", &l);
    sp_font_shape(f, SP_TEXT_NORMAL, "t = 1.23 s", &l);
    sp_font_shape(f, SP_TEXT_NORMAL, "t = 4.56 s", &l);
    sp_font_shape(f, SP_TEXT_NORMAL, "t = 7.89 s", &l);
    sp_font_shape_stats(f, &before, &composed);
    sp_font_shape(f, SP_TEXT_NORMAL, "Energy of the spring", &l);
    sp_font_shape_stats(f, &after, &composed);
    sp_tap_ok(after == before,
              "shape cache: an unchanged string is not shaped again");
    sp_font_shape(f, SP_TEXT_NORMAL, "t = 98.76 s", &l);
    sp_font_shape_stats(f, &after, &composed);
    sp_tap_ok(after == before && l.width > 0, "shape cache: a new clock reading is shaped by HarfBuzz %d times "
              "(0: its digits and words are cached)", after - before);
    /* 10 000 one-off readings, the static text drawn between them */
    for (int i = 0; i < 10000; i++) {
        char s[32];
        snprintf(s, sizeof(s), "x = %d.%03d m", i / 1000, i % 1000);
        sp_font_shape(f, SP_TEXT_SMALL, s, &l);
        if (i % 20 == 0)
            sp_font_shape(f, SP_TEXT_NORMAL, "Energy of the spring", &l);
    }
    sp_font_shape_stats(f, &before, &composed);
    sp_font_shape(f, SP_TEXT_NORMAL, "Energy of the spring", &l);
    sp_font_shape_stats(f, &after, &composed);
    sp_tap_ok(after == before && composed > 10000 - 40,
              "shape cache: after 10000 one-off strings the text in use is still cached (%d shaped again, "
              "%d joined from pieces)", after - before, composed);
    sp_font_destroy(&f);
}

/* A line's quads are worked out once (when its glyphs are rasterised) and
 * copied after: laid out again at another pen position, and again after
 * 5000 other lines pushed it out of the shape cache (so it is shaped and
 * placed anew), every script gives the same quads moved by the whole
 * pixels the pen moved, the same atlas rectangles and its own colour. */
static void test_layout_again(void)
{
    static const struct sp_font_desc fd = {.px = {12, 20, 22, 28}};
    static const float white[4] = {1, 1, 1, 1}, red[4] = {1, 0, 0, 0.5f};
    struct sp_font *f = NULL;
    if (sp_font_make(&f, &fd))
        return;
    for (size_t i = 0; i < sizeof(scripts) / sizeof(scripts[0]); i++) {
        const char *t = scripts[i].text;
        const int n = sp_font_layout(f, SP_TEXT_NORMAL, t, 0, 0, white, NULL, 0);
        struct sp_glyph_quad *a = calloc((size_t)n + 1, sizeof(*a)), *b = calloc((size_t)n + 1, sizeof(*b)),
                             *c = calloc((size_t)n + 1, sizeof(*c));
        const int na = sp_font_layout(f, SP_TEXT_NORMAL, t, 0, 0, white, a, n);
        const int nb = sp_font_layout(f, SP_TEXT_NORMAL, t, 37.4f, 61.6f, red, b, n);
        for (int k = 0; k < 5000; k++) {
            char s[32];
            snprintf(s, sizeof(s), "evict %d", k);
            sp_font_width(f, SP_TEXT_SMALL, s);
        }
        const int nc = sp_font_layout(f, SP_TEXT_NORMAL, t, 0, 0, white, c, n);
        int same = n > 0 && na == n && nb == n && nc == n;
        for (int k = 0; same && k < n; k++)
            same = a[k].rect[0] + 37 == b[k].rect[0] && a[k].rect[2] + 37 == b[k].rect[2] &&
                   a[k].rect[1] + 62 == b[k].rect[1] && a[k].rect[3] + 62 == b[k].rect[3] &&
                   !memcmp(a[k].uv, b[k].uv, sizeof(a[k].uv)) && !memcmp(b[k].color, red, sizeof(red)) &&
                   !memcmp(&a[k], &c[k], sizeof(a[k]));
        sp_tap_ok(same, "%s: its %d quads laid out again at another pen, and after the line left the "
                  "shape cache, are the first ones moved by the pen's whole pixels", scripts[i].name, n);
        free(a), free(b), free(c);
    }
    sp_font_destroy(&f);
}

int main(void)
{
    static const struct sp_font_desc fd = {.px = {12, 20, 22, 28}};
    struct sp_font *f = NULL;
    if (!sp_tap_ok(sp_font_make(&f, &fd) == 0, "the default font (DejaVu Sans, embedded)"))
        return sp_tap_done();
    for (size_t i = 0; i < sizeof(scripts) / sizeof(scripts[0]); i++)
        test_script(f, scripts[i].name, scripts[i].text);
    test_arabic(f);
    test_marks(f);
    test_refusals(f);
    int glyphs;
    double s;
    sp_font_raster_stats(f, &glyphs, &s);
    sp_tap_diag("%d glyphs rasterised in %.2f ms", glyphs, 1e3 * s);
    sp_font_destroy(&f);
    test_families();
    test_shape_cache();
    test_layout_again();
    return sp_tap_done();
}
