/* springpend: shared error codes and logging.
 * Every function that can fail returns 0 or a negative SP_E_* code and logs
 * once, at the point of failure, in the failing library's own words. */
#ifndef SPRINGPEND_COMMON_H
#define SPRINGPEND_COMMON_H

#define SP_VERSION "0.1.0"

enum sp_error {
    SP_OK = 0,
    SP_E_INPUT = -1,       /* bad scene, option or argument: exit status 2 */
    SP_E_IO = -2,          /* file system or encoder I/O failed */
    SP_E_NOMEM = -3,       /* allocation failed */
    SP_E_GL = -4,          /* GL context or shader failure */
    SP_E_CODEC = -5,       /* libav* reported an error */
    SP_E_UNSTABLE = -6,    /* the integration blew up: exit status 3 */
    SP_E_INTERRUPTED = -7, /* stopped by a signal */
    SP_E_MISMATCH = -8,    /* compare: images differ beyond tolerance: exit status 1 */
};

/* Prints "springpend: <message>\n" to stderr, through sp_fputs_line:
 * messages name files and quote values, and neither may drive the terminal
 * or start a line of its own. */
void sp_log_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* As sp_log_error, for what is worth saying but changes no outcome ("note:
 * ..."), unless sp_log_quiet(1) was called (the commands' -q). */
void sp_log_note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void sp_log_quiet(int quiet);

/* on = 1: sp_log_error and sp_log_note write nothing on the calling thread
 * until sp_log_mute(0), for a probe whose failure its caller says in its
 * own words, without what the probed file holds (a scene file named by a
 * shard's command, which anyone may have written: sweep --merge). */
void sp_log_mute(int on);

/* 1 while this thread is muted (sp_log_mute): code that writes its own
 * messages to stderr (the scene parser's FILE:LINE lines) checks it. */
int sp_log_muted(void);

#include <stdio.h>

/* Writes the UTF-8 string s to fp with what a terminal would obey shown
 * instead: C0 controls but newline and tab, DEL and bytes that are not
 * UTF-8 as \xHH, C1 controls (U+0080..U+009F), noncharacters (U+FDD0..U+FDEF,
 * U+FFFE, U+FFFF and their like in every plane) and the characters that
 * show nothing (utf8.h's sp_utf8_is_invisible) as \uHHHH or \UHHHHHHHH,
 * but for a ZWNJ or ZWJ that joins letters (utf8.h's sp_utf8_is_joiner:
 * Persian's ZWNJ, an Indic conjunct's), which shows in its effect and is
 * written as it is, and a backslash as \\ (so that the shown form is
 * one-to-one: a typed "\u200c" shows as \\u200c, U+200C between Latin
 * letters as \u200c). */
void sp_fputs_printable(const char *s, FILE *fp);

/* As sp_fputs_printable, and a newline shown as \n: text from outside (a
 * --set value, a file name) inside a one-line message. */
void sp_fputs_line(const char *s, FILE *fp);

/* As sp_fputs_line (newline = 1: as sp_fputs_printable), for a text
 * already in the shown form (a recorded command line, compare's lines of
 * shown names): a backslash is written as it is (the text's own \\ and
 * \uHHHH), all else shown as sp_fputs_line shows it, so that no forged
 * record drives the terminal. */
void sp_fputs_record(const char *s, int newline, FILE *fp);

/* The printf-style message, shown as sp_fputs_line shows it, and a newline,
 * on fp: every line that names a file or quotes outside text ("wrote
 * NAME", "scene NAME (PATH)", "PATH: cannot open scene") goes through here
 * or sp_log_error, so that no name drives the terminal. */
void sp_fprintf_line(FILE *fp, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* s as sp_fputs_line shows it (newline = 1: as sp_fputs_printable, a
 * newline kept), into buf (size bytes, cut to fit, NUL ended); returns its
 * length. For names that reach a file or a picture (data's scene column,
 * an RFC 4180 field that may hold a line break; a cell's automatic label). */
size_t sp_text_shown(const char *s, int newline, char *buf, size_t size);

/* 1 when a and b are the same text with blanks and ASCII case ignored: how
 * fontconfig matches family names, so "Latin Modern Roman, serif" is the
 * font list "latin modern roman,serif" (text.c, the side-by-side check). */
int sp_text_same_name(const char *a, const char *b);

/* The first character at or after s (in the text that begins at start)
 * that sp_fputs_line writes as an escape (\n, \xHH, \uHHHH, \UHHHHHHHH;
 * not a backslash's \\), or NULL: a word that holds one is not given back
 * by a shell reading its shown form, and must be retyped. */
const char *sp_text_next_escaped(const char *start, const char *s);

/* Progress of a long integration on stderr: a command calls
 * sp_progress_begin before integrating to t_goal (simulated s; what names
 * the pass), hands sp_progress_sim to the simulation as its progress
 * callback (sim.h; ctx unused; cheap), and sp_progress_end ends it. On a
 * terminal one line is redrawn at most 4 times a second, after 2 s; else
 * (a CI log, a pipe) a line of its own after 10 s, then once a minute.
 * enable = 0 draws nothing. */
void sp_progress_begin(int enable, const char *what, double t_goal);
/* 1 when stderr and stdout are one open file (`-o - 2>&1`): a command whose
 * output goes to stdout then keeps its progress off stderr (attack20 #2). */
int sp_stderr_is_stdout(void);
void sp_progress_sim(void *ctx, double t);
void sp_progress_end(void);

#endif
