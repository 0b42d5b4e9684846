/* springpend (internal): the line-counting reader that scene files and
 * compare.ini hand to libinih (ini_parse_stream), so that every message
 * can say FILE:LINE.
 * Shared with: every folder. */
#ifndef SPRINGPEND_INI_LINES_H
#define SPRINGPEND_INI_LINES_H

#include <stddef.h>

/* Lines of an in-memory, NUL-terminated text. Zero it, set cursor. */
struct sp_ini_lines {
    const char *cursor; /* next unread byte */
    int line;           /* number of the line last returned, 1-based */
};

/* Copies the next line (with its '\n'; LF, CRLF or a lone CR end a line,
 * a lone CR comes out as '\n') into str, of num bytes, and counts
 * it. A line that does not fit is replaced by "#\n" (a comment) and *len
 * set to its length so the caller can report it; otherwise *len is 0.
 * Returns str, or NULL after the last line. */
char *sp_ini_lines_next(struct sp_ini_lines *l, char *str, int num, size_t *too_long);

/* How a text value is written on a scene line (view.title, view.caption, a
 * [timeline] cue's caption or note), so that libinih's inline comments never
 * cut it silently: in double quotes it is taken whole, and a '#' or ';'
 * comment may follow the closing quote; without quotes it runs to the end of
 * the line and may not hold ' #' or ' ;' (a comment or text?). value runs to
 * its NUL, CR or LF; trailing blanks are not part of it. */
enum sp_ini_text {
    SP_INI_TEXT_OK,          /* *len: the text's length, quotes included */
    SP_INI_TEXT_AFTER_QUOTE, /* *at: what follows the closing quote, not a comment,
                                up to *len */
    SP_INI_TEXT_COMMENT,     /* *at: the '#' or ';' after a blank, unquoted */
};
enum sp_ini_text sp_ini_text(const char *value, size_t *len, size_t *at);

/* The remedy for SP_INI_TEXT_COMMENT: the n bytes of text in double quotes,
 * each tab written as a space (a tab is not text a scene may hold), as a
 * NUL-terminated string the caller frees; NULL when memory ran out. */
char *sp_ini_text_quoted(const char *text, size_t n);

#endif
