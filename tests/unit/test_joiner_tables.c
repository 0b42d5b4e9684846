/* springpend tests: utf8.c's Indic_Syllabic_Category tables against ICU's
 * data (attack11 #1). The joiner rule keeps a ZWJ raw after a virama that
 * follows a consonant, unless the virama is a pure killer, and a ZWNJ
 * there only before a letter that is no independent vowel; the two
 * property sets are tables in utf8.c (ICU is not linked: its data library
 * maps 30 MB at every start). Here every combining-class-9 code point and
 * every letter of a script with a conjunct-forming virama is put in such a
 * text and sp_utf8_is_joiner's answer checked against ICU's
 * u_getIntPropertyValue(UCHAR_INDIC_SYLLABIC_CATEGORY). Tamil, Gurmukhi and
 * Sinhala, decided by their conjunct rules, are checked by joiner-shaping.
 * usage: test_joiner_tables */
#include <stdio.h>
#include <string.h>

#include <unicode/uchar.h>
#include <unicode/uscript.h>

#include "base/utf8.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

/* Appends c to s as UTF-8; returns the end. */
static char *put(char *s, UChar32 c)
{
    if (c < 0x80)
        *s++ = (char)c;
    else if (c < 0x800)
        *s++ = (char)(0xC0 | c >> 6), *s++ = (char)(0x80 | (c & 0x3F));
    else if (c < 0x10000)
        *s++ = (char)(0xE0 | c >> 12), *s++ = (char)(0x80 | (c >> 6 & 0x3F)),
        *s++ = (char)(0x80 | (c & 0x3F));
    else
        *s++ = (char)(0xF0 | c >> 18), *s++ = (char)(0x80 | (c >> 12 & 0x3F)),
        *s++ = (char)(0x80 | (c >> 6 & 0x3F)), *s++ = (char)(0x80 | (c & 0x3F));
    *s = 0;
    return s;
}

/* sp_utf8_is_joiner on the joiner j in a v j after (after 0: none). */
static int joins(UChar32 a, UChar32 v, UChar32 j, UChar32 after)
{
    char text[32], *at;
    at = put(put(text, a), v);
    char *end = put(at, j);
    if (after)
        put(end, after);
    return sp_utf8_is_joiner(text, at);
}

static int insc(UChar32 c)
{
    return u_getIntPropertyValue(c, UCHAR_INDIC_SYLLABIC_CATEGORY);
}

int main(void)
{
    static UChar32 consonant[USCRIPT_CODE_LIMIT], virama[USCRIPT_CODE_LIMIT];
    UErrorCode e = U_ZERO_ERROR;
    for (UChar32 c = 0x80; c < 0x20000; c++) {
        const int s = uscript_getScript(c, &e), k = insc(c);
        if (s < 0 || s >= USCRIPT_CODE_LIMIT)
            continue;
        if (!consonant[s] && k == U_INSC_CONSONANT && u_charType(c) == U_OTHER_LETTER)
            consonant[s] = c;
        if (!virama[s] && u_getCombiningClass(c) == 9 &&
            (k == U_INSC_VIRAMA || k == U_INSC_INVISIBLE_STACKER))
            virama[s] = c;
    }
    int killers = 0, bad_k = 0, letters = 0, bad_l = 0;
    for (UChar32 c = 0x80; c < 0x20000; c++) {
        const int s = uscript_getScript(c, &e);
        if (s < 0 || s >= USCRIPT_CODE_LIMIT || !consonant[s])
            continue;
        /* the scripts whose virama joins only a few consonants have their
         * own rule (attack12 #17), checked by shaping: test joiner-shaping */
        if (s == USCRIPT_TAMIL || s == USCRIPT_GURMUKHI || s == USCRIPT_SINHALA)
            continue;
        if (u_getCombiningClass(c) == 9) { /* a ZWJ after consonant + c */
            const int want = insc(c) == U_INSC_VIRAMA || insc(c) == U_INSC_INVISIBLE_STACKER;
            killers++;
            if (joins(consonant[s], c, 0x200D, 0) != want && bad_k++ < 5)
                sp_tap_diag("U+%04X (Indic_Syllabic_Category %d): ZWJ after it %s", (unsigned)c,
                            insc(c), want ? "escaped" : "kept raw");
        }
        if (virama[s] && u_charType(c) == U_OTHER_LETTER) { /* consonant virama ZWNJ c */
            const int want = insc(c) != U_INSC_VOWEL_INDEPENDENT;
            letters++;
            if (joins(consonant[s], virama[s], 0x200C, c) != want && bad_l++ < 5)
                sp_tap_diag("U+%04X (Indic_Syllabic_Category %d): ZWNJ before it %s", (unsigned)c,
                            insc(c), want ? "escaped" : "kept raw");
        }
    }
    sp_tap_ok(killers > 50 && bad_k == 0, "a ZWJ after each of %d viramas (combining class 9) "
              "is raw exactly where ICU calls it a virama or stacker, not a pure killer (%d wrong)",
              killers, bad_k);
    sp_tap_ok(letters > 1000 && bad_l == 0, "a ZWNJ after a consonant's virama, before each of "
              "%d letters of its script, is raw exactly where ICU calls the letter no independent "
              "vowel (%d wrong)", letters, bad_l);
    return sp_tap_done();
}
