/* springpend tests: the joiner rule in the scripts whose virama forms a
 * conjunct only before a few consonants (attack12 #17: Tamil, Gurmukhi,
 * Sinhala), against HarfBuzz's shaping with the fonts that draw them. For
 * each consonant, virama, joiner (ZWNJ, ZWJ), letter of the script and
 * then nothing or each vowel sign, the text is shaped with and without the
 * joiner (default ignorables removed, so only what the joiner changes
 * counts); sp_utf8_is_joiner must keep it raw exactly when the glyphs or
 * their positions differ. A joiner followed directly by a mark, a space,
 * a Latin letter or nothing: never raw where it changes nothing (the
 * finding's class); where it does change glyphs (malformed text, a mark
 * with no base and its dotted circle) escaped is allowed, it shows the
 * joiner. Fonts missing: the script's checks are skipped.
 * usage: test_joiner_shaping */
#include <stdio.h>
#include <string.h>

#include <hb.h>

#include "base/utf8.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

static hb_font_t *font;

/* Appends c to s as UTF-8; returns the end. */
static char *put(char *s, uint32_t c)
{
    if (c < 0x80)
        *s++ = (char)c;
    else if (c < 0x800)
        *s++ = (char)(0xC0 | c >> 6), *s++ = (char)(0x80 | (c & 0x3F));
    else
        *s++ = (char)(0xE0 | c >> 12), *s++ = (char)(0x80 | (c >> 6 & 0x3F)),
        *s++ = (char)(0x80 | (c & 0x3F));
    *s = 0;
    return s;
}

/* The glyphs of cps (n of them) and their advances and offsets in g, p. */
static unsigned shape(const uint32_t *cps, int n, hb_codepoint_t *g, hb_position_t *p)
{
    hb_buffer_t *b = hb_buffer_create();
    hb_buffer_add_utf32(b, cps, n, 0, n);
    hb_buffer_guess_segment_properties(b);
    hb_buffer_set_flags(b, HB_BUFFER_FLAG_REMOVE_DEFAULT_IGNORABLES);
    hb_shape(font, b, NULL, 0);
    unsigned len;
    const hb_glyph_info_t *gi = hb_buffer_get_glyph_infos(b, &len);
    const hb_glyph_position_t *gp = hb_buffer_get_glyph_positions(b, &len);
    len = len > 16 ? 16 : len;
    for (unsigned i = 0; i < len; i++) {
        g[i] = gi[i].codepoint;
        p[3 * i] = gp[i].x_advance, p[3 * i + 1] = gp[i].x_offset, p[3 * i + 2] = gp[i].y_offset;
    }
    hb_buffer_destroy(b);
    return len;
}

/* Whether the joiner at cps[2] changes the shaped glyphs of cps (n). */
static int drawn(const uint32_t *cps, int n)
{
    uint32_t bare[8];
    hb_codepoint_t g1[16], g2[16];
    hb_position_t p1[48], p2[48];
    for (int i = 0, k = 0; i < n; i++)
        if (i != 2)
            bare[k++] = cps[i];
    const unsigned l1 = shape(cps, n, g1, p1), l2 = shape(bare, n - 1, g2, p2);
    return l1 != l2 || memcmp(g1, g2, l1 * sizeof *g1) || memcmp(p1, p2, 3 * l1 * sizeof *p1);
}

/* sp_utf8_is_joiner on cps[2] of cps (n). */
static int raw(const uint32_t *cps, int n)
{
    char text[64], *at = text, *end = text;
    for (int i = 0; i < n; i++) {
        if (i == 2)
            at = end;
        end = put(end, cps[i]);
    }
    return sp_utf8_is_joiner(text, at);
}

struct script {
    const char *name, *font;
    uint32_t first, last, virama; /* the block, its virama */
    uint32_t c0, c1;              /* its consonants */
};

static void check(const struct script *s)
{
    hb_blob_t *blob = hb_blob_create_from_file_or_fail(s->font);
    if (!blob) {
        printf("ok %d # SKIP %s: %s missing\n", ++sp_tap_count, s->name, s->font);
        printf("ok %d # SKIP %s: %s missing\n", ++sp_tap_count, s->name, s->font);
        return;
    }
    hb_face_t *face = hb_face_create(blob, 0);
    font = hb_font_create(face);
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    uint32_t letters[128], signs[64];
    int nl = 0, ns = 0;
    for (uint32_t c = s->first; c <= s->last; c++) {
        hb_codepoint_t g;
        const hb_unicode_general_category_t gc = hb_unicode_general_category(uf, c);
        if (c == s->virama || !hb_font_get_nominal_glyph(font, c, &g))
            continue;
        if (gc == HB_UNICODE_GENERAL_CATEGORY_OTHER_LETTER)
            letters[nl++] = c;
        else if (gc == HB_UNICODE_GENERAL_CATEGORY_SPACING_MARK ||
                 gc == HB_UNICODE_GENERAL_CATEGORY_NON_SPACING_MARK)
            signs[ns++] = c;
    }
    int pairs = 0, wrong = 0, joined = 0, tails = 0, hidden = 0;
    for (uint32_t c = s->c0; c <= s->c1; c++) {
        hb_codepoint_t g;
        if (!hb_font_get_nominal_glyph(font, c, &g) ||
            hb_unicode_general_category(uf, c) != HB_UNICODE_GENERAL_CATEGORY_OTHER_LETTER)
            continue;
        for (int j = 0; j < 2; j++) {
            const uint32_t joiner = j ? 0x200D : 0x200C;
            /* consonant virama joiner letter [sign] */
            for (int l = 0; l < nl; l++)
                for (int k = -1; k < ns; k++) {
                    const uint32_t cps[5] = {c, s->virama, joiner, letters[l], k < 0 ? 0 : signs[k]};
                    const int n = k < 0 ? 4 : 5, want = drawn(cps, n), got = raw(cps, n);
                    pairs++;
                    joined += want;
                    if (want != got && wrong++ < 6)
                        sp_tap_diag("%s: U+%04X U+%04X U+%04X U+%04X U+%04X: the joiner %s, %s", s->name,
                                    cps[0], cps[1], cps[2], cps[3], cps[4],
                                    want ? "draws" : "draws nothing", got ? "raw" : "escaped");
                }
            /* consonant virama joiner [a sign, a space, a Latin letter] */
            for (int k = -3; k < ns; k++) {
                const uint32_t t = k == -3 ? 0 : k == -2 ? ' ' : k == -1 ? 'a' : signs[k];
                const uint32_t cps[4] = {c, s->virama, joiner, t};
                const int n = t ? 4 : 3;
                tails++;
                if (raw(cps, n) && !drawn(cps, n) && hidden++ < 6)
                    sp_tap_diag("%s: U+%04X U+%04X U+%04X U+%04X: raw, draws nothing", s->name, cps[0],
                                cps[1], cps[2], cps[3]);
            }
        }
    }
    sp_tap_ok(pairs > 1000 && joined > 10 && wrong == 0,
              "%s (%s): of %d consonant, virama, joiner, letter (and vowel sign) texts the joiner "
              "changes the glyphs of %d; raw exactly there (%d wrong)",
              s->name, s->font, pairs, joined, wrong);
    sp_tap_ok(tails > 100 && hidden == 0,
              "%s: of %d joiners after consonant and virama before a sign, a space, a Latin letter "
              "or the end, none is raw where it changes nothing (%d are)",
              s->name, tails, hidden);
    hb_font_destroy(font);
    hb_face_destroy(face);
    hb_blob_destroy(blob);
}

int main(void)
{
#define NOTO "/usr/share/fonts/truetype/noto/"
    static const struct script scripts[] = {
        {"Tamil", NOTO "NotoSansTamil-Regular.ttf", 0x0B80, 0x0BFF, 0x0BCD, 0x0B95, 0x0BB9},
        {"Tamil", NOTO "NotoSerifTamil-Regular.ttf", 0x0B80, 0x0BFF, 0x0BCD, 0x0B95, 0x0BB9},
        {"Gurmukhi", NOTO "NotoSansGurmukhi-Regular.ttf", 0x0A00, 0x0A7F, 0x0A4D, 0x0A15, 0x0A5E},
        {"Sinhala", NOTO "NotoSansSinhala-Regular.ttf", 0x0D80, 0x0DFF, 0x0DCA, 0x0D9A, 0x0DC6},
        {"Sinhala", NOTO "NotoSerifSinhala-Regular.ttf", 0x0D80, 0x0DFF, 0x0DCA, 0x0D9A, 0x0DC6},
    };
    for (size_t i = 0; i < sizeof(scripts) / sizeof(scripts[0]); i++)
        check(&scripts[i]);
    return sp_tap_done();
}
