/* springpend (internal): UTF-8 validation and decoding (utf8.c).
 * Shared with: every folder. */
#ifndef SP_UTF8_H
#define SP_UTF8_H

#include <stddef.h>
#include <stdint.h>

/* The byte length (1..4) of the well-formed UTF-8 character at s, or 0 when
 * s is at its NUL or at a malformed, overlong or surrogate sequence. */
size_t sp_utf8_char(const char *s);

/* The offset of the first byte of s's n bytes that is not text (a
 * malformed UTF-8 sequence, a C0 control such as TAB, DEL, or a C1 control,
 * bytes 0xc2 0x80..0x9f), or n when all are: the rule of a scene's text
 * keys and timeline texts. */
size_t sp_utf8_not_text(const char *s, size_t n);

/* The code point at s, its byte length (sp_utf8_char's) in *len; U+FFFD
 * with *len = 1 for a malformed byte and at the NUL. */
uint32_t sp_utf8_decode(const char *s, size_t *len);

/* 1 for the Unicode bidirectional format characters (U+061C, U+200E,
 * U+200F, U+202A..U+202E, U+2066..U+2069): a name holding one displays
 * reordered ("Trojan Source"), so names are shown with them escaped. */
int sp_utf8_is_bidi_control(uint32_t u);

/* 1 for the characters that show nothing of themselves: Unicode's
 * Default_Ignorable_Code_Point (U+00AD, U+034F, the Hangul fillers U+115F,
 * U+1160, U+3164, U+FFA0, U+200B..U+200F, U+2060..U+206F, the variation
 * selectors, U+FEFF, the tag characters U+E0000..), U+2800 (braille blank),
 * and, from HarfBuzz's Unicode data, the general categories Cf, Zl, Zp
 * (U+2028, U+2029) and unassigned code points: a name holding one reads as
 * another name, or breaks its line, so names and recorded commands are
 * shown with them escaped (\u200b). */
int sp_utf8_is_invisible(uint32_t u);

/* 1 for a code point the shown form of a text (sp_text_shown, the compare
 * reports) writes escaped, \uNNNN: a C1 control (U+0080..U+009F), a
 * noncharacter or an invisible one (sp_utf8_is_invisible). */
int sp_utf8_is_hidden(uint32_t u);

/* 1 when the character at `at` in the text that begins at start is a
 * U+200C (ZWNJ) or U+200D (ZWJ) that joins by IDNA's contextual rules (RFC
 * 5892 appendix A.1, A.2): either after a virama that follows a consonant
 * of its script (an Indic conjunct: a ZWJ there, a ZWNJ before a consonant
 * of that script; Unicode's Indic_Syllabic_Category), or a
 * ZWNJ between letters of a joining script, (L|D) T* ZWNJ T* (R|D) by
 * Unicode's Joining_Type (FriBidi's data; T: transparent marks), as in
 * Persian's mi<ZWNJ>khaham. There it changes what is drawn (the letters do
 * not join, the conjunct opens), so it is no invisible difference; anywhere
 * else (between Latin letters, in an emoji sequence) it shows nothing. */
int sp_utf8_is_joiner(const char *start, const char *at);

/* 1 when the character at `at` (in the text that begins at start) is one
 * the shown form writes escaped (sp_utf8_is_hidden), which is every hidden
 * one but a joiner (sp_utf8_is_joiner): a byte (ASCII, not UTF-8) is 0. */
int sp_utf8_hidden_at(const char *start, const char *at);

/* 1 when the text that begins at start may be cut before `at` without
 * splitting a character or what draws as one: at is start, or at a
 * character's first byte that is no mark (Mn, Mc, Me: an accent, a vowel
 * sign, a variation selector), format character (Cf: a joiner, a tag),
 * emoji modifier or second regional indicator of a pair (counted from the
 * run's start), that follows no ZWJ, ZWNJ or virama, and that splits no
 * Hangul syllable written as jamo (UAX #29's GB6-GB8: L x L|V|LV|LVT,
 * LV|V x V|T, LVT|T x T). A byte that is not UTF-8 is a character of its
 * own. */
int sp_utf8_breakable(const char *start, const char *at);

#endif
