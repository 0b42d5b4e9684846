/* springpend tests: a minimal TAP producer. Each test executable prints
 * "1..N" at the end (sp_tap_done) and one "ok"/"not ok" line per check. */
#ifndef SPRINGPEND_TAP_H
#define SPRINGPEND_TAP_H

#ifdef NDEBUG
#error "tests must not be built with NDEBUG"
#endif

#include <stdarg.h>
#include <stdio.h>

static int sp_tap_count, sp_tap_failed;

/* Records one check; returns cond so callers can add diagnostics. */
__attribute__((format(printf, 2, 3))) static int sp_tap_ok(int cond, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    printf("%sok %d - ", cond ? "" : "not ", ++sp_tap_count);
    vprintf(fmt, ap);
    putchar('\n');
    va_end(ap);
    if (!cond)
        sp_tap_failed++;
    fflush(stdout);
    return cond;
}

/* A "# ..." diagnostic line. */
#define sp_tap_diag(...) (printf("# " __VA_ARGS__), putchar('\n'))

/* Prints the plan and returns the exit status. */
static int sp_tap_done(void)
{
    printf("1..%d\n", sp_tap_count);
    return sp_tap_failed ? 1 : 0;
}

/* Skips the whole executable (meson's exit code 77). */
#define SP_TAP_SKIP_ALL(why) do { printf("1..0 # SKIP %s\n", why); return 77; } while (0)

#endif
