/* springpend (internal): UTF-8 validation and decoding (utf8.c).
 * Shared with: every folder. */
#ifndef SP_UTF8_H
#define SP_UTF8_H

#include <stddef.h>
#include <stdint.h>

/* The byte length (1..4) of the well-formed UTF-8 character at s, or 0 when
 * s is at its NUL or at a malformed, overlong or surrogate sequence. */
size_t sp_utf8_char(const char *s);

/* The code point at s, its byte length (sp_utf8_char's) in *len; U+FFFD
 * with *len = 1 for a malformed byte and at the NUL. */
uint32_t sp_utf8_decode(const char *s, size_t *len);

/* 1 for the Unicode bidirectional format characters (U+061C, U+200E,
 * U+200F, U+202A..U+202E, U+2066..U+2069): a name holding one displays
 * reordered ("Trojan Source"), so names are shown with them escaped. */
int sp_utf8_is_bidi_control(uint32_t u);

#endif
