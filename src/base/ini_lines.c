/* springpend: the line-counting reader for libinih (ini_lines.h). */
#include <stdio.h>
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
