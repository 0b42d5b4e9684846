/* UTF-8 validation and decoding shared by the log, the scene checks and
 * text layout (utf8.h). */
#include <stddef.h>
#include <stdint.h>

#include <fribidi.h>
#include <hb.h>

#include "utf8.h"

size_t sp_utf8_char(const char *s)
{
    const unsigned char *u = (const unsigned char *)s;
    size_t n = u[0] < 0x80 ? 1 : u[0] >= 0xC2 && u[0] <= 0xDF ? 2 : u[0] >= 0xE0 && u[0] <= 0xEF ? 3
             : u[0] >= 0xF0 && u[0] <= 0xF4 ? 4 : 0;
    uint32_t cp = n == 1 ? u[0] : u[0] & (0x7Fu >> n);
    for (size_t i = 1; i < n; i++) {
        if ((u[i] & 0xC0) != 0x80)
            return 0;
        cp = cp << 6 | (u[i] & 0x3Fu);
    }
    if (!u[0] || (n == 3 && (cp < 0x800 || (cp >= 0xD800 && cp <= 0xDFFF))) ||
        (n == 4 && (cp < 0x10000 || cp > 0x10FFFF)))
        return 0;
    return n;
}

size_t sp_utf8_not_text(const char *s, size_t n)
{
    for (size_t i = 0; i < n;) {
        const unsigned char *u = (const unsigned char *)s + i;
        const size_t len = sp_utf8_char((const char *)u);
        if (!len || i + len > n || *u < 0x20 || *u == 0x7f ||
            (len == 2 && u[0] == 0xc2 && u[1] < 0xa0))
            return i;
        i += len;
    }
    return n;
}

uint32_t sp_utf8_decode(const char *s, size_t *len)
{
    const unsigned char *u = (const unsigned char *)s;
    const size_t n = sp_utf8_char(s);
    if (!n) {
        *len = 1;
        return 0xFFFD;
    }
    uint32_t cp = n == 1 ? u[0] : u[0] & (0x7Fu >> n);
    for (size_t i = 1; i < n; i++)
        cp = cp << 6 | (u[i] & 0x3Fu);
    *len = n;
    return cp;
}

int sp_utf8_is_bidi_control(uint32_t u)
{
    return u == 0x061c || u == 0x200e || u == 0x200f || (u >= 0x202a && u <= 0x202e) ||
           (u >= 0x2066 && u <= 0x2069);
}

/* Unicode's Default_Ignorable_Code_Point (DerivedCoreProperties.txt,
 * Unicode 15.1; unchanged since 9.0 but for U+1BCA0..): HarfBuzz keeps it
 * internal and FriBidi and the other linked libraries expose none, so the
 * ranges are here. Code points, first and last. */
static const uint32_t default_ignorable[][2] = {
    {0x00AD, 0x00AD},   {0x034F, 0x034F},   {0x061C, 0x061C},   {0x115F, 0x1160},
    {0x17B4, 0x17B5},   {0x180B, 0x180F},   {0x200B, 0x200F},   {0x202A, 0x202E},
    {0x2060, 0x206F},   {0x3164, 0x3164},   {0xFE00, 0xFE0F},   {0xFEFF, 0xFEFF},
    {0xFFA0, 0xFFA0},   {0xFFF0, 0xFFF8},   {0x1BCA0, 0x1BCA3}, {0x1D173, 0x1D17A},
    {0xE0000, 0xE0FFF},
};

/* 1 when u is in one of the n ranges (first, last) of table. */
static int in_table(uint32_t u, const uint32_t table[][2], size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (u >= table[i][0] && u <= table[i][1])
            return 1;
    return 0;
}

int sp_utf8_is_invisible(uint32_t u)
{
    if (in_table(u, default_ignorable, sizeof(default_ignorable) / sizeof(default_ignorable[0])))
        return 1;
    if (u == 0x2800) /* BRAILLE PATTERN BLANK (So): a blank letter, not ignorable */
        return 1;
    /* the Unicode Character Database's general category, as HarfBuzz (which
     * shapes the drawn text) has it; unassigned: nothing to draw */
    switch (hb_unicode_general_category(hb_unicode_funcs_get_default(), u)) {
    case HB_UNICODE_GENERAL_CATEGORY_FORMAT:
    case HB_UNICODE_GENERAL_CATEGORY_LINE_SEPARATOR:
    case HB_UNICODE_GENERAL_CATEGORY_PARAGRAPH_SEPARATOR:
    case HB_UNICODE_GENERAL_CATEGORY_UNASSIGNED:
        return 1;
    default:
        return 0;
    }
}

int sp_utf8_is_hidden(uint32_t u)
{
    return (u >= 0x80 && u < 0xa0) || (u & 0xfffe) == 0xfffe || (u >= 0xfdd0 && u <= 0xfdef) ||
           sp_utf8_is_invisible(u);
}

/* The character before p in text (from start): its code point in *u and
 * its start, or NULL at start or before a byte that is not UTF-8. */
static const char *before(const char *start, const char *p, uint32_t *u)
{
    for (const char *q = p - 1; q >= start && p - q <= 4; q--) {
        if (((unsigned char)*q & 0xC0) == 0x80)
            continue; /* a continuation byte: the character starts further back */
        size_t n;
        *u = sp_utf8_decode(q, &n);
        return sp_utf8_char(q) == (size_t)(p - q) ? q : NULL;
    }
    return NULL;
}

/* Unicode's Indic_Syllabic_Category (IndicSyllabicCategory.txt, Unicode
 * 15.0, as ICU 72 has it): the viramas (combining class 9) that are pure
 * killers, which form no conjunct (Myanmar's asat, Thai's phinthu), and the
 * independent vowels, which a virama does not join. HarfBuzz keeps these
 * internal, and ICU's data library (30 MB mapped at every start) broke the
 * runs under ulimit -v that test `compare` makes, so the ranges are here,
 * written by a ten-line C program over ICU's u_getIntPropertyValue
 * (UCHAR_INDIC_SYLLABIC_CATEGORY) and u_getCombiningClass. First, last. */
static const uint32_t pure_killer[][2] = {
    {0x0D3B, 0x0D3C}, {0x0E3A, 0x0E3A}, {0x0EBA, 0x0EBA}, {0x0F84, 0x0F84}, {0x103A, 0x103A},
    {0x1714, 0x1715}, {0x1734, 0x1734}, {0x1BAA, 0x1BAA}, {0x1BF2, 0x1BF3}, {0x2D7F, 0x2D7F},
    {0xA82C, 0xA82C}, {0xA953, 0xA953}, {0xABED, 0xABED}, {0x11070, 0x11070}, {0x1107F, 0x1107F},
    {0x11134, 0x11134}, {0x112EA, 0x112EA}, {0x1172B, 0x1172B}, {0x1193D, 0x1193D}, {0x11A34, 0x11A34},
    {0x11D44, 0x11D44}, {0x11F41, 0x11F41},
};
static const uint32_t vowel_independent[][2] = {
    {0x0904, 0x0914}, {0x0960, 0x0961}, {0x0972, 0x0977}, {0x0985, 0x098C}, {0x098F, 0x0990},
    {0x0993, 0x0994}, {0x09E0, 0x09E1}, {0x0A05, 0x0A0A}, {0x0A0F, 0x0A10}, {0x0A13, 0x0A14},
    {0x0A85, 0x0A8D}, {0x0A8F, 0x0A91}, {0x0A93, 0x0A94}, {0x0AE0, 0x0AE1}, {0x0B05, 0x0B0C},
    {0x0B0F, 0x0B10}, {0x0B13, 0x0B14}, {0x0B60, 0x0B61}, {0x0B85, 0x0B8A}, {0x0B8E, 0x0B90},
    {0x0B92, 0x0B94}, {0x0C05, 0x0C0C}, {0x0C0E, 0x0C10}, {0x0C12, 0x0C14}, {0x0C60, 0x0C61},
    {0x0C85, 0x0C8C}, {0x0C8E, 0x0C90}, {0x0C92, 0x0C94}, {0x0CE0, 0x0CE1}, {0x0D05, 0x0D0C},
    {0x0D0E, 0x0D10}, {0x0D12, 0x0D14}, {0x0D5F, 0x0D61}, {0x0D85, 0x0D96}, {0x1021, 0x102A},
    {0x1052, 0x1055}, {0x1700, 0x1702}, {0x1720, 0x1722}, {0x1740, 0x1742}, {0x1760, 0x1762},
    {0x17A3, 0x17B3}, {0x1A4D, 0x1A52}, {0x1B05, 0x1B12}, {0x1B83, 0x1B89}, {0x1BE4, 0x1BE5},
    {0xA800, 0xA801}, {0xA803, 0xA805}, {0xA882, 0xA891}, {0xA8FE, 0xA8FE}, {0xA984, 0xA988},
    {0xA98C, 0xA98E}, {0xAA00, 0xAA05}, {0xAAE0, 0xAAE1}, {0xABCE, 0xABCF}, {0xABD1, 0xABD1},
    {0x11005, 0x11012}, {0x11071, 0x11072}, {0x11083, 0x1108C}, {0x11103, 0x11106}, {0x11183, 0x11190},
    {0x11200, 0x11207}, {0x11240, 0x11240}, {0x11280, 0x11283}, {0x112B0, 0x112B9}, {0x11305, 0x1130C},
    {0x1130F, 0x11310}, {0x11313, 0x11314}, {0x11360, 0x11361}, {0x11400, 0x1140D}, {0x11481, 0x1148E},
    {0x11580, 0x1158D}, {0x115D8, 0x115DB}, {0x11600, 0x1160D}, {0x11680, 0x11689}, {0x11800, 0x11809},
    {0x11900, 0x11906}, {0x11909, 0x11909}, {0x119A0, 0x119A7}, {0x119AA, 0x119AD}, {0x11A00, 0x11A00},
    {0x11A50, 0x11A50}, {0x11C00, 0x11C08}, {0x11C0A, 0x11C0D}, {0x11D00, 0x11D06}, {0x11D08, 0x11D09},
    {0x11D0B, 0x11D0B}, {0x11D60, 0x11D65}, {0x11D67, 0x11D68}, {0x11D6A, 0x11D6B}, {0x11F04, 0x11F10},
};

/* 1 for a virama (RFC 5892's Canonical_Combining_Class Virama) that forms
 * conjuncts (not a pure killer: a joiner after Myanmar's asat or Thai's
 * phinthu draws nothing, attack11 #1, measured: identical pixels). */
static int virama(uint32_t u)
{
    return hb_unicode_combining_class(hb_unicode_funcs_get_default(), u) ==
               HB_UNICODE_COMBINING_CLASS_VIRAMA &&
           !in_table(u, pure_killer, sizeof(pure_killer) / sizeof(pure_killer[0]));
}

/* 1 when c is a consonant of the script of v (a virama): a letter of that
 * script but an independent vowel, which a virama does not join. */
static int consonant_of(uint32_t c, uint32_t v)
{
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    return hb_unicode_general_category(uf, c) == HB_UNICODE_GENERAL_CATEGORY_OTHER_LETTER &&
           hb_unicode_script(uf, c) == hb_unicode_script(uf, v) &&
           !in_table(c, vowel_independent, sizeof(vowel_independent) / sizeof(vowel_independent[0]));
}

/* The consonant of v's script that the virama v starting at p (in the text
 * from start) follows, nuktas between them (KA NUKTA VIRAMA), or 0: a
 * virama with nothing to kill (after a space, a vowel) forms nothing. */
static uint32_t virama_after_consonant(const char *start, const char *p, uint32_t v)
{
    uint32_t c = 0;
    do
        p = before(start, p, &c);
    while (p && hb_unicode_combining_class(hb_unicode_funcs_get_default(), c) ==
                    HB_UNICODE_COMBINING_CLASS_NUKTA);
    return p && consonant_of(c, v) ? c : 0;
}

/* The code point at p, or 0 at the end or at a byte that is not UTF-8;
 * *next: where the one after it starts. */
static uint32_t char_at(const char *p, const char **next)
{
    size_t n = 0;
    const uint32_t u = *p && sp_utf8_char(p) ? sp_utf8_decode(p, &n) : 0;
    *next = p + n;
    return u;
}

/* Sinhala's touching letters (bandi akuru): consonant, al-lakuna, ZWJ,
 * consonant drawn touching (KA+SSA, KA+VA, GA+DHA, NYA+CA, TTA+TTHA,
 * TA+THA, TA+VA, DA+DHA, DA+VA, NA+THA, NA+DA, NA+DHA, NA+VA); each
 * first << 16 | second. */
static const uint32_t sinhala_touching[] = {
    0x0D9A0DC2, 0x0D9A0DC0, 0x0D9C0DB0, 0x0DA40DA0, 0x0DA70DA8, 0x0DAD0DAE, 0x0DAD0DC0,
    0x0DAF0DB0, 0x0DAF0DC0, 0x0DB10DAE, 0x0DB10DAF, 0x0DB10DB0, 0x0DB10DC0,
};

/* The scripts whose virama forms a conjunct only before a few consonants,
 * elsewhere a visible virama that a joiner leaves as it is (attack12 #17):
 * whether the joiner j after consonant c and virama v, with the text after
 * it at next, changes what is drawn: 1 or 0, or -1 for the other scripts.
 * From the scripts' conjunct rules in The Unicode Standard's sections on
 * them (Tamil: KSSA and SRI are its conjuncts, other clusters keep the
 * pulli shown; Gurmukhi: subjoined HA, RA, VA and post-base YA; Sinhala:
 * the al-lakuna is shown unless a ZWJ asks for repaya (RA first), yansaya
 * (YA after), rakaransaya (RA after) or a touching letter, a ZWNJ asks for
 * nothing) as HarfBuzz's Indic shaper applies them: shaping every pair of
 * letters with and without the joiner (Noto Sans Tamil, Gurmukhi, Sinhala
 * and Noto Serif Sinhala, HarfBuzz 6) changes the glyphs in exactly these
 * (doc/notes/2026-11-27/fix15.md); tests/e2e/test_attack12_seen.py draws
 * them. Independent of the font, as file names and records must be. */
static int few_conjuncts(uint32_t c, uint32_t v, uint32_t j, const char *next)
{
    const char *after;
    const uint32_t d = char_at(next, &after), e = char_at(after, &after);
    switch (v) {
    case 0x0BCD: /* Tamil pulli: KA+SSA (KSSA); SA or SHA+RA+II (SRI) */
        return (c == 0x0B95 && d == 0x0BB7) || ((c == 0x0BB8 || c == 0x0BB6) && d == 0x0BB0 && e == 0x0BC0);
    case 0x0A4D: /* Gurmukhi virama: HA, RA, VA below, YA after, but with a
                  * nukta or yakash (and RA, VA, HA with udaat) on them, which
                  * have no such form; a ZWJ keeps sihari (the i sign, drawn
                  * first) with the next consonant or URA (not IRI or EK ONKAR) */
        if (d == 0x0A39 || d == 0x0A30 || d == 0x0A35 || d == 0x0A2F)
            return e != 0x0A3C && e != 0x0A75 && (e != 0x0A51 || d == 0x0A2F);
        return j == 0x200D && e == 0x0A3F && (d == 0x0A73 || (d < 0x0A72 && consonant_of(d, v)));
    case 0x0DCA: /* Sinhala al-lakuna: only a ZWJ joins; RA+ZWJ+RA draws as
                  * RA+RA but with a kombuva (the signs drawn first) after */
        if (j != 0x200D)
            return 0;
        if (c == 0x0DBB && d == 0x0DBB)
            return e >= 0x0DD9 && e <= 0x0DDE;
        if (c == 0x0DBB || d == 0x0DBA || d == 0x0DBB)
            return 1;
        for (size_t i = 0; i < sizeof(sinhala_touching) / sizeof(sinhala_touching[0]); i++)
            if (sinhala_touching[i] == (c << 16 | d))
                return 1;
        return 0;
    default:
        return -1;
    }
}

int sp_utf8_is_joiner(const char *start, const char *at)
{
    size_t n;
    uint32_t u = sp_utf8_decode(at, &n), b = 0;
    const char *p = before(start, at, &b);
    if (u != 0x200C && u != 0x200D)
        return 0;
    /* A.1, A.2: after a virama (Indic conjuncts) that follows a consonant of
     * its script (else the virama forms nothing, attack11 #1): a ZWJ asks for
     * the half form, whatever follows; a ZWNJ only keeps the virama shown
     * before a consonant of the script (the conjunct it breaks), before
     * anything else (a vowel letter, attack10 #14 and attack11 #1) it draws
     * nothing */
    const uint32_t c = p && virama(b) ? virama_after_consonant(start, p, b) : 0;
    if (c) {
        size_t m;
        const int few = few_conjuncts(c, b, u, at + n);
        if (few >= 0)
            return few;
        if (u == 0x200D)
            return 1;
        if (*(at + n) && sp_utf8_char(at + n) && consonant_of(sp_utf8_decode(at + n, &m), b))
            return 1;
    }
    if (u == 0x200D)
        return 0;
    /* A.1: (Joining_Type:{L,D})(Joining_Type:T)* ZWNJ (Joining_Type:T)*(Joining_Type:{R,D}),
     * each T shown as it is: a T that is shown escaped (U+034F, a variation
     * selector) leaves the joiner between a letter and a backslash, where it
     * changes nothing that is seen (attack10 #3) */
    while (p && fribidi_get_joining_type(b) == FRIBIDI_JOINING_TYPE_T) {
        if (sp_utf8_is_hidden(b))
            return 0;
        p = before(start, p, &b);
    }
    if (!p || (fribidi_get_joining_type(b) != FRIBIDI_JOINING_TYPE_L &&
               fribidi_get_joining_type(b) != FRIBIDI_JOINING_TYPE_D))
        return 0;
    for (const char *q = at + n; *q; q += n) {
        if (!sp_utf8_char(q))
            return 0;
        const uint32_t c = sp_utf8_decode(q, &n);
        const FriBidiJoiningType j = fribidi_get_joining_type(c);
        if (j != FRIBIDI_JOINING_TYPE_T)
            return j == FRIBIDI_JOINING_TYPE_R || j == FRIBIDI_JOINING_TYPE_D;
        if (sp_utf8_is_hidden(c))
            return 0;
    }
    return 0;
}

int sp_utf8_hidden_at(const char *start, const char *at)
{
    size_t n;
    const uint32_t u = sp_utf8_decode(at, &n);
    return n > 1 && sp_utf8_is_hidden(u) && !sp_utf8_is_joiner(start, at);
}

/* A Hangul jamo's or syllable's Hangul_Syllable_Type (Unicode's
 * HangulSyllableType.txt): 'L' a leading consonant, 'V' a vowel, 'T' a
 * trailing consonant, 'l' an LV syllable, 'x' an LVT syllable; 0 none. */
static int hangul_type(uint32_t u)
{
    if ((u >= 0x1100 && u <= 0x115F) || (u >= 0xA960 && u <= 0xA97C))
        return 'L';
    if ((u >= 0x1160 && u <= 0x11A7) || (u >= 0xD7B0 && u <= 0xD7C6))
        return 'V';
    if ((u >= 0x11A8 && u <= 0x11FF) || (u >= 0xD7CB && u <= 0xD7FB))
        return 'T';
    if (u >= 0xAC00 && u <= 0xD7A3)
        return (u - 0xAC00) % 28 ? 'x' : 'l';
    return 0;
}

/* 1 when UAX #29 keeps p and u (p's next character) in one Hangul
 * syllable: L x (L|V|LV|LVT), (LV|V) x (V|T), (LVT|T) x T (GB6-GB8). */
static int hangul_joined(uint32_t p, uint32_t u)
{
    const int a = hangul_type(p), b = hangul_type(u);
    if (!a || !b)
        return 0;
    if (a == 'L')
        return b != 'T';
    if (a == 'l' || a == 'V')
        return b == 'V' || b == 'T';
    return (a == 'x' || a == 'T') && b == 'T';
}

/* 1 when the regional indicator at `at` is the second of a flag: an odd
 * number of regional indicators stand right before it (GB12, GB13). */
static int second_of_flag(const char *start, const char *at)
{
    int odd = 0;
    uint32_t p = 0;
    for (const char *q = before(start, at, &p); q && p >= 0x1F1E6 && p <= 0x1F1FF;
         q = before(start, q, &p))
        odd = !odd;
    return odd;
}

int sp_utf8_breakable(const char *start, const char *at)
{
    if (at == start || !*at)
        return 1;
    if (((unsigned char)*at & 0xC0) == 0x80) {
        const char *q = at; /* inside a well-formed character? */
        while (q > start && at - q < 3 && ((unsigned char)*q & 0xC0) == 0x80)
            q--;
        if (sp_utf8_char(q) > (size_t)(at - q))
            return 0;
    }
    if (!sp_utf8_char(at))
        return 1; /* a byte that is not UTF-8: shown as \xHH, alone */
    size_t n;
    uint32_t u = sp_utf8_decode(at, &n), p = 0;
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    switch (hb_unicode_general_category(uf, u)) {
    case HB_UNICODE_GENERAL_CATEGORY_NON_SPACING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_SPACING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_ENCLOSING_MARK:
    case HB_UNICODE_GENERAL_CATEGORY_FORMAT:
        return 0;
    default:
        break;
    }
    if (u >= 0x1F3FB && u <= 0x1F3FF) /* an emoji's skin tone */
        return 0;
    if (!before(start, at, &p))
        return 1;
    if (p == 0x200C || p == 0x200D || virama(p) || hangul_joined(p, u))
        return 0;
    return !(u >= 0x1F1E6 && u <= 0x1F1FF && second_of_flag(start, at));
}
