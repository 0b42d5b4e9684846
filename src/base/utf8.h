#ifndef SP_UTF8_H
#define SP_UTF8_H

#include <stddef.h>

/* The byte length (1..4) of the well-formed UTF-8 character at s, or 0 when
 * s is at its NUL or at a malformed, overlong or surrogate sequence. */
size_t sp_utf8_char(const char *s);

#endif
