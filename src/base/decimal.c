/* springpend: the number syntax of scene files and compare.ini (decimal.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "decimal.h"

/* The end of [+-] digits [. digits] [(e|E) [+-] digits] at s, or NULL when
 * s does not start with it. */
static const char *skip_decimal(const char *s)
{
    const char *p = s + (*s == '+' || *s == '-');
    const size_t whole = strspn(p, "0123456789");
    size_t frac = 0;
    p += whole;
    if (*p == '.')
        p++, frac = strspn(p, "0123456789"), p += frac;
    if (!whole && !frac)
        return NULL;
    if (*p == 'e' || *p == 'E') {
        p += 1 + (p[1] == '+' || p[1] == '-');
        const size_t exp = strspn(p, "0123456789");
        if (!exp)
            return NULL;
        p += exp;
    }
    return p;
}

enum sp_decimal_read sp_decimal_read(const char *s, double *v)
{
    const char *p = skip_decimal(s), *word = s + (*s == '+' || *s == '-');
    char *end;
    const double d = strtod(s, &end);
    if (p && !*p && end == p) { /* strtod (C locale) read the same text */
        if (!isfinite(d))
            return SP_DECIMAL_NOT_FINITE;
        *v = d;
        return SP_DECIMAL_OK;
    }
    /* strtod's words for infinite and not-a-number values */
    if (!p && end != s && !*end && (!strncasecmp(word, "inf", 3) || !strncasecmp(word, "nan", 3)))
        return SP_DECIMAL_NOT_FINITE;
    return SP_DECIMAL_NOT_DECIMAL;
}

const char *sp_decimal_in(const char *s, double lo, double hi, int flags, double *v)
{
    switch (sp_decimal_read(s, v)) {
    case SP_DECIMAL_NOT_DECIMAL: return SP_DECIMAL_NOT;
    case SP_DECIMAL_NOT_FINITE: return "not finite";
    case SP_DECIMAL_OK: break;
    }
    if ((flags & SP_DECIMAL_INTEGER) && *v != floor(*v))
        return "not an integer";
    if (*v < lo || ((flags & SP_DECIMAL_ABOVE) && *v == lo) || *v > hi)
        return "out of range";
    return NULL;
}
