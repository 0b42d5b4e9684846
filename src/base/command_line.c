/* springpend: the recorded command line (see command_line.h). */
#include <stdio.h>
#include <string.h>

#include "command_line.h"

static int n_words;
static char *const *words;
static char *first_word = "springpend";

void sp_command_line_set(int argc, char **argv)
{
    static char *recorded[4096];
    n_words = argc < (int)(sizeof(recorded) / sizeof(recorded[0]))
                  ? argc : (int)(sizeof(recorded) / sizeof(recorded[0]));
    for (int i = 0; i < n_words; i++)
        recorded[i] = i ? argv[i] : first_word;
    words = recorded;
}

char *const *sp_command_line_argv(int *argc)
{
    *argc = n_words;
    return words;
}

int sp_command_line_text(char *buf, size_t size)
{
    static const char plain[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                "0123456789_./:=,+@%^-";
    size_t used = 0;
#define EMIT(...)                                                                          \
    used += (size_t)snprintf(used < size ? buf + used : NULL, used < size ? size - used : 0, \
                             __VA_ARGS__)
    if (size)
        buf[0] = 0;
    for (int i = 0; i < n_words; i++) {
        const char *w = words[i];
        if (i)
            EMIT(" ");
        if (*w && strspn(w, plain) == strlen(w)) {
            EMIT("%s", w);
            continue;
        }
        EMIT("'");
        for (const char *q; (q = strchr(w, '\'')); w = q + 1)
            EMIT("%.*s'\\''", (int)(q - w), w);
        EMIT("%s'", w);
    }
#undef EMIT
    return (int)used;
}
