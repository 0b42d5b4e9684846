/* springpend: the recorded command line (see command_line.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "command_line.h"
#include "springpend/common.h"

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

static int text(char *buf, size_t size, int unnamed);

/* 1 when word w (at *i) is left out of what an output records: -o FILE,
 * --frames A:B, --shard I/N, as one word (-oFILE, --output=FILE,
 * --frames=A:B) or two (*i is then moved past the second). */
static int omitted(const char *w, int *i)
{
    static const char *const with_value[] = {"-o", "--output", "--frames", "--shard"};
    for (size_t k = 0; k < sizeof(with_value) / sizeof(with_value[0]); k++) {
        const size_t n = strlen(with_value[k]);
        if (!strcmp(w, with_value[k])) {
            ++*i; /* and its argument */
            return 1;
        }
        if (!strncmp(w, with_value[k], n) && (w[n] == '=' || (k == 0 && w[n])))
            return 1;
    }
    return 0;
}

int sp_command_line_text(char *buf, size_t size)
{
    return text(buf, size, 0);
}

int sp_command_line_text_unnamed(char *buf, size_t size)
{
    return text(buf, size, 1);
}

char *sp_command_line_unnamed(void)
{
    const int n = text(NULL, 0, 1);
    char *line = n > 0 ? malloc((size_t)n + 1) : NULL;
    char *shown = line ? malloc(4 * (size_t)n + 1) : NULL; /* at most \xNN a byte */
    if (shown) {
        text(line, (size_t)n + 1, 1);
        sp_text_shown(line, 0, shown, 4 * (size_t)n + 1);
    }
    free(line);
    return shown;
}

static int text(char *buf, size_t size, int unnamed)
{
    static const char plain[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                "0123456789_./:=,+@%^-";
    size_t used = 0;
#define EMIT(...)                                                                          \
    used += (size_t)snprintf(used < size ? buf + used : NULL, used < size ? size - used : 0, \
                             __VA_ARGS__)
    if (size)
        buf[0] = 0;
    for (int i = 0, first = 1; i < n_words; i++) {
        const char *w = words[i];
        if (unnamed && i && omitted(w, &i))
            continue;
        if (!first)
            EMIT(" ");
        first = 0;
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
