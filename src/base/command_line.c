/* springpend: the recorded command line (see command_line.h). */
#include <limits.h>
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

/* 1 when word w (at *i) is left out of what an output records (see
 * command_line.h), as one word (-oFILE, --output=FILE, --threads=2) or two
 * (*i is then moved past the second). */
static int omitted(const char *w, int *i)
{
    static const char *const with_value[] = {"-o", "--output", "--csv", "--frames", "--shard",
                                             "--threads"};
    if (!strcmp(w, "-q") || !strcmp(w, "--quiet"))
        return 1;
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

/* The n words w as one line (command_line.h), all of them or (unnamed)
 * those an output records; into buf as snprintf does. */
static int text(char *buf, size_t size, int n, char *const *w, int unnamed)
{
    static const char plain[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                "0123456789_./:=,+@%^-";
    size_t used = 0;
#define EMIT(...)                                                                          \
    used += (size_t)snprintf(used < size ? buf + used : NULL, used < size ? size - used : 0, \
                             __VA_ARGS__)
    if (size)
        buf[0] = 0;
    for (int i = 0, first = 1; i < n; i++) {
        const char *s = w[i];
        if (unnamed && i && omitted(s, &i))
            continue;
        if (!first)
            EMIT(" ");
        first = 0;
        if (*s && strspn(s, plain) == strlen(s)) {
            EMIT("%s", s);
            continue;
        }
        EMIT("'");
        for (const char *q; (q = strchr(s, '\'')); s = q + 1)
            EMIT("%.*s'\\''", (int)(q - s), s);
        EMIT("%s'", s);
    }
#undef EMIT
    return (int)used;
}

int sp_command_line_text(char *buf, size_t size)
{
    return text(buf, size, n_words, words, 0);
}

int sp_command_line_text_unnamed(char *buf, size_t size)
{
    return text(buf, size, n_words, words, 1);
}

/* The words' recorded line, shown (command_line.h); NULL when out of memory. */
static char *shown_of(int n, char *const *w)
{
    const int len = text(NULL, 0, n, w, 1);
    char *line = malloc((size_t)len + 1);
    char *shown = line ? malloc(4 * (size_t)len + 1) : NULL; /* at most \xNN a byte */
    if (shown) {
        text(line, (size_t)len + 1, n, w, 1);
        sp_text_shown(line, 0, shown, 4 * (size_t)len + 1);
    }
    free(line);
    return shown;
}

char *sp_command_line_unnamed(void)
{
    return n_words ? shown_of(n_words, words) : NULL;
}

/* Splits line, as sp_command_line_text writes one, into words (malloc'd,
 * each in the one buffer *store); the count, or -1 when it is not such a
 * line (it may come from a file: a space at its start or two in a row, an
 * empty word, is one springpend never writes) or out of memory. */
static int split(const char *line, char ***out, char **store)
{
    const size_t len = strlen(line), cap = len / 2 + 2; /* a word and its space: 2 bytes */
    char **w = malloc(cap * sizeof(*w)), *s = malloc(len + 1), *at = s;
    size_t n = 0;
    *out = w, *store = s;
    if (!w || !s)
        return -1;
    for (const char *p = line; *p;) {
        if (*p == ' ' || n + 1 >= cap)
            return -1;
        w[n++] = at;
        while (*p && *p != ' ') {
            if (*p != '\'') {
                *at++ = *p++;
                continue;
            }
            const char *close = strchr(p + 1, '\''); /* a quoted part, to its end */
            if (!close)
                return -1;
            memcpy(at, p + 1, (size_t)(close - p - 1));
            at += close - p - 1;
            p = close + 1;
            if (!strncmp(p, "\\''", 3)) /* '\'' : a quote inside */
                *at++ = '\'', p += 2;
        }
        *at++ = 0;
        if (*p == ' ' && !*++p)
            return -1;
    }
    return n > INT_MAX ? -1 : (int)n;
}

char *sp_command_line_recorded(const char *line)
{
    char **w, *store, *shown = NULL;
    const int n = line ? split(line, &w, &store) : -1;
    if (n > 0 && !strcmp(w[0], first_word))
        shown = shown_of(n, w);
    if (line) {
        free(w);
        free(store);
    }
    return shown;
}
