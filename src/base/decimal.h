/* springpend (internal): the one syntax of numbers in scene files, --set and
 * compare.ini, so that none of them takes what strtod takes beyond it (hex
 * floats, inf, nan, leading blanks).
 * Shared with: every folder. */
#ifndef SPRINGPEND_DECIMAL_H
#define SPRINGPEND_DECIMAL_H

/* What is allowed, for messages: "... expected X, " SP_DECIMAL_ALLOWED. */
#define SP_DECIMAL_ALLOWED \
    "written in decimal (digits with an optional sign, point and exponent, e.g. 12, -0.5, 1e-3)"

enum sp_decimal_read {
    SP_DECIMAL_OK = 0,
    SP_DECIMAL_NOT_DECIMAL = -1, /* anything but the syntax below */
    SP_DECIMAL_NOT_FINITE = -2,  /* inf, infinity or nan (any case, optional sign),
                                    or beyond a double's range (1e400) */
};

/* Reads all of s as [+-] digits [. digits] [(e|E) [+-] digits], with a digit
 * before or after the point (5, 5., .5, -2.5e-3): nothing before or after it
 * (no blanks), no hex, no digit separators. Stores the nearest double in *v
 * on SP_DECIMAL_OK only (an underflow reads as 0 or a denormal). */
enum sp_decimal_read sp_decimal_read(const char *s, double *v);

/* sp_decimal_in's answer for text that is no decimal number; a message that
 * holds it adds ", " SP_DECIMAL_ALLOWED to what it expects. */
#define SP_DECIMAL_NOT "not a decimal number"

#define SP_DECIMAL_INTEGER 1 /* sp_decimal_in: the value must be a whole number */
#define SP_DECIMAL_ABOVE 2   /* sp_decimal_in: lo itself is refused (lo < v) */

/* Reads all of s as sp_decimal_read does and checks lo <= v <= hi (lo < v
 * with SP_DECIMAL_ABOVE in flags; a whole number with SP_DECIMAL_INTEGER).
 * Returns NULL with *v stored, or what is wrong, for a message "WHAT: ...;
 * expected ...": SP_DECIMAL_NOT, "not finite", "not an integer" or "out of
 * range" (*v then unspecified). */
const char *sp_decimal_in(const char *s, double lo, double hi, int flags, double *v);

#endif
