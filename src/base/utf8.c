/* UTF-8 validation and decoding shared by the log, the scene checks and
 * text layout (utf8.h). */
#include <stddef.h>
#include <stdint.h>

#include <fribidi.h>
#include <hb.h>
#include <unicode/uchar.h>

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

int sp_utf8_is_invisible(uint32_t u)
{
    for (size_t i = 0; i < sizeof(default_ignorable) / sizeof(default_ignorable[0]); i++)
        if (u >= default_ignorable[i][0] && u <= default_ignorable[i][1])
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

/* 1 for a virama (RFC 5892's Canonical_Combining_Class Virama) that forms
 * conjuncts (Indic_Syllabic_Category Virama or Invisible_Stacker): a pure
 * killer (Myanmar's asat, Thai's phinthu) forms none, so a joiner after it
 * draws nothing (attack11 #1, measured: identical pixels). */
static int virama(uint32_t u)
{
    const int k = u_getIntPropertyValue((UChar32)u, UCHAR_INDIC_SYLLABIC_CATEGORY);
    return hb_unicode_combining_class(hb_unicode_funcs_get_default(), u) ==
           HB_UNICODE_COMBINING_CLASS_VIRAMA && (k == U_INSC_VIRAMA || k == U_INSC_INVISIBLE_STACKER);
}

/* 1 when c is a consonant of the script of v (a virama): Unicode's
 * Indic_Syllabic_Category Consonant* (ICU's data), the only letter a
 * virama joins into a conjunct; an independent vowel is none. */
static int consonant_of(uint32_t c, uint32_t v)
{
    const int k = u_getIntPropertyValue((UChar32)c, UCHAR_INDIC_SYLLABIC_CATEGORY);
    hb_unicode_funcs_t *uf = hb_unicode_funcs_get_default();
    return k >= U_INSC_CONSONANT && k <= U_INSC_CONSONANT_WITH_STACKER &&
           hb_unicode_script(uf, c) == hb_unicode_script(uf, v);
}

/* 1 when the virama v that starts at p (in the text from start) follows a
 * consonant of its script, nuktas between them (KA NUKTA VIRAMA): a
 * virama with nothing to kill (after a space, a vowel) forms nothing. */
static int virama_after_consonant(const char *start, const char *p, uint32_t v)
{
    uint32_t c = 0;
    do
        p = before(start, p, &c);
    while (p && u_getIntPropertyValue((UChar32)c, UCHAR_INDIC_SYLLABIC_CATEGORY) == U_INSC_NUKTA);
    return p && consonant_of(c, v);
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
    if (p && virama(b) && virama_after_consonant(start, p, b)) {
        size_t m;
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
