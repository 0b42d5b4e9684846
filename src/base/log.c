/* springpend: logging, and the progress line of long integrations. */
#include <sys/stat.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "clock.h"
#include "springpend/common.h"
#include "utf8.h"

/* The code point of the UTF-8 character s of n (2..4) bytes. */
static unsigned long code_point(const unsigned char *s, size_t n)
{
    unsigned long u = s[0] & (0x7f >> n);
    for (size_t i = 1; i < n; i++)
        u = u << 6 | (s[i] & 0x3f);
    return u;
}

/* 1 when the shown form writes the character at s (n bytes: sp_utf8_char's,
 * 0 for a byte that is not UTF-8; in the text from start) as an escape:
 * \n (a newline, unless newline), \xHH (a control byte, DEL, a byte that
 * is not UTF-8), \uHHHH (utf8.h's sp_utf8_hidden_at). A backslash's \\ is
 * not counted: a shell reads it back as it was. */
static int escaped(const char *start, const char *s, size_t n, int newline)
{
    const unsigned char c = (unsigned char)*s;
    if (n == 1)
        return c == '\n' ? !newline : (c < 0x20 && c != '\t') || c == 0x7f;
    return !n || sp_utf8_hidden_at(start, s);
}

/* newline: 1 to write it, 0 to show it as \n; plus SHOWN_ALREADY: a
 * backslash written as it is (s is in the shown form already) */
enum { SHOWN_ALREADY = 2 };
static void fputs_shown(const char *s, FILE *fp, int newline)
{
    const char *start = s;
    for (size_t n; *s; s += n ? n : 1) {
        unsigned char c = (unsigned char)*s;
        n = sp_utf8_char(s);
        if (c == '\\' && !(newline & SHOWN_ALREADY)) /* so that the shown form is one-to-one */
            fputs("\\\\", fp);
        else if (!escaped(start, s, n, newline & 1))
            fwrite(s, 1, n, fp);
        else if (c == '\n')
            fputs("\\n", fp);
        else if (n > 1)
            fprintf(fp, n == 4 ? "\\U%08lx" : "\\u%04lx",
                    code_point((const unsigned char *)s, n));
        else
            fprintf(fp, "\\x%02x", c);
    }
}

const char *sp_text_next_escaped(const char *start, const char *s)
{
    for (size_t n; *s; s += n ? n : 1)
        if (escaped(start, s, n = sp_utf8_char(s), 0))
            return s;
    return NULL;
}

void sp_fputs_printable(const char *s, FILE *fp)
{
    fputs_shown(s, fp, 1);
}

void sp_fputs_line(const char *s, FILE *fp)
{
    fputs_shown(s, fp, 0);
}

void sp_fputs_record(const char *s, int newline, FILE *fp)
{
    fputs_shown(s, fp, (newline != 0) | SHOWN_ALREADY);
}

int sp_text_same_name(const char *a, const char *b)
{
    for (;; a++, b++) {
        while (*a == ' ')
            a++;
        while (*b == ' ')
            b++;
        const int ca = *a >= 'A' && *a <= 'Z' ? *a + 32 : *a;
        const int cb = *b >= 'A' && *b <= 'Z' ? *b + 32 : *b;
        if (ca != cb)
            return 0;
        if (!*a)
            return 1;
    }
}

size_t sp_text_shown(const char *s, int newline, char *buf, size_t size)
{
    FILE *m = size ? fmemopen(buf, size, "w") : NULL;
    if (!m) {
        if (size)
            buf[0] = 0;
        return 0;
    }
    setvbuf(m, NULL, _IONBF, 0);
    fputs_shown(s, m, newline);
    long n = ftell(m);
    fclose(m);
    n = n < 0 ? 0 : n >= (long)size ? (long)size - 1 : n;
    buf[n] = 0;
    return (size_t)n;
}

/* One message: the stream is locked for its whole line (stdio's lock, the
 * one every stdio call takes), so that threads writing messages at once
 * (the PNG sequence's writers on a full disk) never interleave their
 * characters; prefix, when not NULL, goes first. */
static void vprint_line(FILE *fp, const char *prefix, const char *fmt, va_list ap)
{
    char *msg = NULL, fixed[1024];
    va_list again;
    va_copy(again, ap);
    int n = vasprintf(&msg, fmt, ap);
    if (n < 0) {
        /* Out of memory: the message formatted into a fixed buffer, cut at
         * its size, never the bare format (its %s name nothing) */
        msg = NULL;
        vsnprintf(fixed, sizeof(fixed), fmt, again);
    }
    va_end(again);
    flockfile(fp);
    if (prefix)
        fputs(prefix, fp);
    sp_fputs_line(n >= 0 ? msg : fixed, fp); /* one message, one line */
    fputc('\n', fp);
    funlockfile(fp);
    free(msg);
}

void sp_fprintf_line(FILE *fp, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vprint_line(fp, NULL, fmt, ap);
    va_end(ap);
}

/* 1: this thread's sp_log_error and sp_log_note write nothing (sp_log_mute). */
static _Thread_local int log_muted;

void sp_log_mute(int on)
{
    log_muted = on;
}

int sp_log_muted(void)
{
    return log_muted;
}

void sp_log_error(const char *fmt, ...)
{
    va_list ap;
    if (log_muted)
        return;
    va_start(ap, fmt);
    vprint_line(stderr, "springpend: ", fmt, ap);
    va_end(ap);
}

/* 1: sp_log_note says nothing (-q); set once by the command line. */
static int log_quiet;

void sp_log_quiet(int quiet)
{
    log_quiet = quiet;
}

void sp_log_note(const char *fmt, ...)
{
    va_list ap;
    if (log_quiet || log_muted)
        return;
    va_start(ap, fmt);
    vprint_line(stderr, "springpend: ", fmt, ap);
    va_end(ap);
}

/* ---- progress of long integrations ---- */

static struct {
    int on, drawn, tty;
    unsigned calls;
    double goal, t_from;      /* simulated s */
    double wall0, wall_last;  /* s, monotonic */
    const char *what;
} progress;

/* Not on a terminal (a CI log, a pipe, a file): a line of its own after
 * PROGRESS_LOG_FIRST s, then every PROGRESS_LOG_EVERY s, so a long run is
 * never silent there (attack19 #8: a still's pre-pass ran 10 minutes under
 * the estimate's note without a word). */
#define PROGRESS_LOG_FIRST 10.0
#define PROGRESS_LOG_EVERY 60.0

int sp_stderr_is_stdout(void)
{
    struct stat a, b;
    return fstat(1, &a) == 0 && fstat(2, &b) == 0 && a.st_dev == b.st_dev && a.st_ino == b.st_ino;
}

void sp_progress_begin(int enable, const char *what, double t_goal)
{
    sp_progress_end();
    if (!enable)
        return;
    progress.on = 1;
    progress.tty = isatty(2);
    progress.what = what;
    progress.goal = t_goal;
    progress.t_from = -1;
    progress.wall0 = progress.wall_last = sp_clock_s();
}

void sp_progress_sim(void *ctx, double t)
{
    (void)ctx;
    if (!progress.on || (++progress.calls & 0xfff))
        return;
    double now = sp_clock_s();
    if (progress.t_from < 0)
        progress.t_from = t, progress.wall0 = progress.wall_last = now;
    if (!(progress.goal > 0))
        return;
    if (progress.tty ? now - progress.wall_last < 0.25 || now - progress.wall0 < 2
                     : now - progress.wall_last < (progress.drawn ? PROGRESS_LOG_EVERY
                                                                  : PROGRESS_LOG_FIRST))
        return;
    progress.wall_last = now;
    double rate = (t - progress.t_from) / (now - progress.wall0); /* simulated s per s */
    fprintf(stderr, progress.tty ? "\r%s: t = %.4g of %.4g s (%.1f%%), ETA %.0f s "
                                 : "springpend: %s: t = %.4g of %.4g s (%.1f%%), ETA %.0f s\n",
            progress.what, t, progress.goal, 100 * t / progress.goal,
            rate > 0 ? (progress.goal - t) / rate : 0);
    progress.drawn = 1;
}

void sp_progress_end(void)
{
    if (progress.drawn && progress.tty)
        fputc('\n', stderr);
    progress.on = progress.drawn = 0;
}
