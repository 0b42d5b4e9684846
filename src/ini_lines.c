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
    const char *nl = strchr(start, '\n');
    size_t len = nl ? (size_t)(nl - start + 1) : strlen(start);
    l->cursor += len;
    l->line++;
    if (len + 1 > (size_t)num) {
        *too_long = len;
        snprintf(str, (size_t)num, "#\n");
        return str;
    }
    memcpy(str, start, len);
    str[len] = 0;
    return str;
}
