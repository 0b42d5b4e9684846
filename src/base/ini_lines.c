/* springpend: the line-counting reader for libinih (ini_lines.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ini_lines.h"

char *sp_ini_lines_next(struct sp_ini_lines *l, char *str, int num, size_t *too_long)
{
    *too_long = 0;
    if (!*l->cursor)
        return NULL;
    const char *start = l->cursor;
    size_t len = strcspn(start, "\r\n");
    /* LF, CRLF, and CR alone (old Mac files) end a line; a lone CR is
     * handed to inih as LF. */
    int lone_cr = start[len] == '\r' && start[len + 1] != '\n';
    len += start[len] == '\r' && start[len + 1] == '\n' ? 2 : start[len] ? 1 : 0;
    l->cursor += len;
    l->line++;
    if (len + 1 > (size_t)num) {
        *too_long = len;
        snprintf(str, (size_t)num, "#\n");
        return str;
    }
    memcpy(str, start, len);
    str[len] = 0;
    if (lone_cr)
        str[len - 1] = '\n';
    return str;
}

enum sp_ini_text sp_ini_text(const char *value, size_t *len, size_t *at)
{
    size_t n = strcspn(value, "\r\n");
    while (n && (value[n - 1] == ' ' || value[n - 1] == '\t'))
        n--;
    *len = n, *at = 0;
    const char *close = n > 1 && value[0] == '"' ? memrchr(value + 1, '"', n - 1) : NULL;
    if (close) { /* quoted: a comment may follow the closing quote */
        const char *rest = close + 1 + strspn(close + 1, " \t");
        *at = (size_t)(rest - value);
        if (rest < value + n && *rest != '#' && *rest != ';')
            return SP_INI_TEXT_AFTER_QUOTE; /* *len: the whole value's */
        *len = (size_t)(close + 1 - value);
        return SP_INI_TEXT_OK;
    }
    for (size_t i = 1; i < n; i++)
        if ((value[i] == '#' || value[i] == ';') && (value[i - 1] == ' ' || value[i - 1] == '\t')) {
            *at = i;
            return SP_INI_TEXT_COMMENT;
        }
    return SP_INI_TEXT_OK;
}

char *sp_ini_text_quoted(const char *text, size_t n)
{
    char *q = malloc(n + 3);
    if (!q)
        return NULL;
    q[0] = '"';
    for (size_t i = 0; i < n; i++)
        q[i + 1] = text[i] == '\t' ? ' ' : text[i];
    q[n + 1] = '"', q[n + 2] = 0;
    return q;
}
