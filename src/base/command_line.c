/* springpend: the recorded command line (see command_line.h). */
#include <getopt.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "array.h"
#include "command_line.h"
#include "springpend/common.h"
#include "springpend/provenance.h"

/* One option getopt_long returned, as the record writes it. */
struct taken {
    int c;             /* getopt_long's value */
    const char *name;  /* the long option's full name (NULL: a short option of none) */
    const char *value; /* its value (optarg), NULL when it takes none */
    int apart;         /* 1: the value was the word after the option's */
};

struct sp_command_line {
    int n;                 /* words; w[0] is "springpend", w[1] the command */
    char **w;
    char *store;           /* a line's words (sp_command_line_read); NULL: argv's */
    char **argv;           /* a copy of w + 1 for the parser, which permutes it */
    const char *shortopts; /* the parser's; NULL: no option parsed (every word as given) */
    struct taken *taken;   /* in the order getopt_long returned them */
    int n_taken, cap_taken;
};

static struct sp_command_line process;
static struct sp_command_line *parsing = &process;
static char first_word[] = "springpend";

void sp_command_line_set(int argc, char **argv)
{
    process.w = argc > 0 ? malloc((size_t)argc * sizeof(*process.w)) : NULL;
    process.n = process.w ? argc : 0;
    for (int i = 0; i < process.n; i++)
        process.w[i] = i ? argv[i] : first_word;
}

char *const *sp_command_line_argv(int *argc)
{
    *argc = process.n;
    return process.w;
}

/* The option of longopts that getopt_long returns as c (a short option's
 * long name), or NULL. */
static const struct option *long_of(const struct option *longopts, int c)
{
    for (const struct option *p = longopts; p && p->name; p++)
        if (!p->flag && p->val == c)
            return p;
    return NULL;
}

/* 1 when short option c of shortopts takes a value. */
static int short_takes_value(const char *shortopts, int c)
{
    const char *at = c != ':' ? strchr(shortopts, c) : NULL;
    return at && at[1] == ':';
}

int sp_command_line_getopt(int argc, char *const *argv, const char *shortopts,
                           const struct option *longopts)
{
    int longindex = -1;
    const int c = getopt_long(argc, argv, shortopts, longopts, &longindex);
    struct sp_command_line *r = parsing;
    if (c == -1 || c == '?' || c == ':')
        return c;
    const struct option *o = longindex >= 0 ? &longopts[longindex] : long_of(longopts, c);
    const int takes = longindex >= 0 ? longopts[longindex].has_arg != no_argument
                                     : short_takes_value(shortopts, c);
    r->shortopts = shortopts;
    if (SP_ARRAY_RESERVE(r->taken, r->cap_taken, r->n_taken + 1, 32)) {
        r->n_taken = -1; /* out of memory: the record is every word as given */
        return c;
    }
    if (r->n_taken >= 0)
        r->taken[r->n_taken++] = (struct taken){
            .c = c, .name = o ? o->name : NULL, .value = takes ? optarg : NULL,
            .apart = takes && optarg && optind > 0 && optarg == argv[optind - 1]};
    return c;
}

/* What a record leaves out (command_line.h). */
enum { KEEP_NONE, KEEP_PART /* a video piece: its --frames or --shard too */ };

/* 1 when an output records no word of option `name` (command_line.h). */
static int omitted(const char *name, int keep)
{
    static const char *const names[] = {"output", "csv", "frames", "shard", "threads", "quiet",
                                        "state", "help"};
    if (name && keep == KEEP_PART && (!strcmp(name, "frames") || !strcmp(name, "shard")))
        return 0;
    for (size_t k = 0; name && k < sizeof(names) / sizeof(names[0]); k++)
        if (!strcmp(name, names[k]))
            return 1;
    return 0;
}

/* A word of the record: pre (a "--" or "-") then s. */
struct word {
    const char *pre, *s;
    char c[2]; /* a short option of no long name */
};

/* Appends option t's words to out at *n, unless the record leaves it out
 * (keep: KEEP_*, what it keeps of what outputs omit). */
static void put_taken(const struct taken *t, int keep, struct word *out, int *n)
{
    if (omitted(t->name, keep))
        return;
    if (t->name) {
        out[*n] = (struct word){.pre = "--", .s = t->name};
    } else {
        out[*n] = (struct word){.pre = "-", .c = {(char)t->c, 0}};
        out[*n].s = out[*n].c;
    }
    ++*n;
    if (t->value)
        out[(*n)++] = (struct word){.pre = "", .s = t->value};
}

/* The words r records into out (room for n + 2 n_taken): every word
 * (unnamed 0), or (1) the words as getopt_long parsed them: each option by
 * its long name, its value as the next word, less what outputs omit (but
 * what keep keeps); an operand, '--' and what follows it as given. The
 * count, or -1 when the words do not read as the parser returned them
 * (then nothing is left out: the caller records every word). *rest: the
 * index in out of the '--' that ends the options (parsed words only), or
 * -1 when there is none. */
static int recorded_words(const struct sp_command_line *r, int unnamed, int keep,
                          struct word *out, int *rest)
{
    int n = 0, k = 0;
    *rest = -1;
    if (!unnamed || !r->shortopts || r->n_taken < 0) {
        for (int i = 0; i < r->n; i++)
            out[n++] = (struct word){.pre = "", .s = r->w[i]};
        return n;
    }
    for (int i = 0; i < r->n; i++) {
        const char *s = r->w[i];
        /* the program, the command, an operand, '--' and all after the
         * last option: as given */
        if (i < 2 || k == r->n_taken || s[0] != '-' || !s[1]) {
            if (i >= 2 && *rest < 0 && !strcmp(s, "--"))
                *rest = n;
            out[n++] = (struct word){.pre = "", .s = s};
            continue;
        }
        if (s[1] == '-') { /* --name, --name=VALUE, --name VALUE */
            const struct taken *t = &r->taken[k++];
            if (!s[2] || !t->name || strncmp(s + 2, t->name, strcspn(s + 2, "=")) ||
                (t->apart && (i + 1 >= r->n || r->w[i + 1] != t->value)))
                return -1;
            put_taken(t, keep, out, &n);
            i += t->apart;
            continue;
        }
        for (const char *p = s + 1; *p; p++) { /* -abc, -oFILE, -o FILE */
            const struct taken *t = k < r->n_taken ? &r->taken[k++] : NULL;
            if (!t || t->c != *p)
                return -1;
            put_taken(t, keep, out, &n);
            if (t->value) { /* the rest of the word, or the next word */
                if (t->apart ? p[1] || i + 1 >= r->n || r->w[i + 1] != t->value
                             : t->value != p + 1)
                    return -1;
                i += t->apart;
                break;
            }
        }
    }
    return k == r->n_taken ? n : -1;
}

/* The quoted part [s, end) into at, its shown escapes (sp_text_shown's
 * \n, \xHH, \uHHHH, \UHHHHHHHH: a backslash inside quotes is one of them,
 * as text() writes a backslash itself outside) read back into the bytes
 * they stand for; returns the end of what it wrote (never more bytes than
 * it read). */
static char *unshown(char *at, const char *s, const char *end)
{
    while (s < end) {
        const int digits = s[0] != '\\' || s + 1 >= end ? 0 : s[1] == 'x' ? 2 : s[1] == 'u' ? 4
                                                         : s[1] == 'U' ? 8 : 0;
        char hex[9] = {0};
        unsigned long u = 0;
        if (s + 1 < end && s[0] == '\\' && s[1] == 'n') {
            *at++ = '\n', s += 2;
            continue;
        }
        if (!digits || end - s < 2 + digits ||
            strspn(memcpy(hex, s + 2, (size_t)digits), "0123456789abcdef") != (size_t)digits ||
            (u = strtoul(hex, NULL, 16)) > 0x10FFFF || (digits > 2 && u < 0x80)) {
            *at++ = *s++; /* a backslash an older record wrote as it was */
            continue;
        }
        s += 2 + digits;
        if (digits == 2 || u < 0x80) /* a byte */
            *at++ = (char)u;
        else if (u < 0x800)
            *at++ = (char)(0xC0 | u >> 6), *at++ = (char)(0x80 | (u & 0x3F));
        else if (u < 0x10000)
            *at++ = (char)(0xE0 | u >> 12), *at++ = (char)(0x80 | (u >> 6 & 0x3F)),
            *at++ = (char)(0x80 | (u & 0x3F));
        else
            *at++ = (char)(0xF0 | u >> 18), *at++ = (char)(0x80 | (u >> 12 & 0x3F)),
            *at++ = (char)(0x80 | (u >> 6 & 0x3F)), *at++ = (char)(0x80 | (u & 0x3F));
    }
    return at;
}

/* The n words as one line (command_line.h), into buf as snprintf does. */
static size_t text(char *buf, size_t size, int n, const struct word *w)
{
    static const char plain[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                "0123456789_./:=,+@%^-";
    size_t used = 0;
#define EMIT(...)                                                                          \
    used += (size_t)snprintf(used < size ? buf + used : NULL, used < size ? size - used : 0, \
                             __VA_ARGS__)
    if (size)
        buf[0] = 0;
    for (int i = 0; i < n; i++) {
        const char *s = w[i].s;
        if (i)
            EMIT(" ");
        if (*w[i].pre || (*s && strspn(s, plain) == strlen(s))) {
            EMIT("%s%s", w[i].pre, s);
            continue;
        }
        /* a quote as '"'"', a backslash as '\' (the shown form's \\ then
         * reads back as one backslash outside the quotes) */
        EMIT("'");
        for (const char *q; (q = s + strcspn(s, "'\\")) && *q; s = q + 1)
            EMIT("%.*s'%s'", (int)(q - s), s, *q == '\'' ? "\"'\"" : "\\");
        EMIT("%s'", s);
    }
#undef EMIT
    return used;
}

/* r's record (unnamed: as outputs record it, keeping `keep`, else every
 * word), then (more != NULL) more's options other than `skip` and what
 * outputs omit, as one line shown (sp_text_shown). malloc'd; NULL when out
 * of memory. */
static char *line_of(const struct sp_command_line *r, int unnamed, int keep,
                     const struct sp_command_line *more, const char *skip)
{
    const size_t room = (size_t)r->n + 2 * (size_t)(r->n_taken > 0 ? r->n_taken : 0) +
                        (more && more->n_taken > 0 ? 2 * (size_t)more->n_taken : 0) + 1;
    struct word *w = malloc(room * sizeof(*w));
    char *line = NULL, *shown = NULL;
    int rest, n = w ? recorded_words(r, unnamed, keep, w, &rest) : 0;
    if (w && n < 0)
        n = recorded_words(r, 0, keep, w, &rest);
    /* more's options go before r's '--' (after it they would be operands):
     * r's words from its '--' (as given: no word of them points into
     * itself) are set aside and put back after more's */
    const int tail = w && more && rest >= 0 ? n - rest : 0;
    struct word *aside = tail ? malloc((size_t)tail * sizeof(*w)) : NULL;
    if (tail && !aside) {
        free(w);
        return NULL;
    }
    if (tail) {
        memcpy(aside, &w[rest], (size_t)tail * sizeof(*w));
        n = rest;
    }
    for (int k = 0; w && more && k < more->n_taken; k++)
        if (!skip || !more->taken[k].name || strcmp(more->taken[k].name, skip))
            put_taken(&more->taken[k], KEEP_NONE, w, &n);
    if (tail) {
        memcpy(&w[n], aside, (size_t)tail * sizeof(*w));
        n += tail;
        free(aside);
    }
    const size_t len = w ? text(NULL, 0, n, w) : 0;
    if (w && (line = malloc(len + 1)) && (shown = malloc(4 * len + 1))) { /* at most \xNN a byte */
        text(line, len + 1, n, w);
        sp_text_shown(line, 0, shown, 4 * len + 1);
    }
    free(w);
    free(line);
    return shown;
}

char *sp_command_line_unnamed(void)
{
    return process.n ? line_of(&process, 1, KEEP_NONE, NULL, NULL) : NULL;
}

char *sp_command_line_piece(void)
{
    return process.n ? line_of(&process, 1, KEEP_PART, NULL, NULL) : NULL;
}

char *sp_command_line_whole(void)
{
    return process.n ? line_of(&process, 0, KEEP_NONE, NULL, NULL) : NULL;
}

int sp_command_line_check(const char *record)
{
    char *whole = record ? NULL : sp_command_line_whole();
    char *unnamed = record ? NULL : sp_command_line_unnamed();
    size_t len = record ? strlen(record) : whole ? strlen(whole) : 0;
    if (unnamed && strlen(unnamed) > len)
        len = strlen(unnamed);
    free(whole);
    free(unnamed);
    if (len < SP_PROVENANCE_SCENE_MAX)
        return 0;
    sp_log_error("the command line is %zu bytes as recorded; at most %d are recorded (every "
                 "output carries it, and springpend reads no longer record back): shorten it "
                 "(put long values in the scene file)", len, SP_PROVENANCE_SCENE_MAX - 1);
    return SP_E_INPUT;
}

/* Splits line, as line_of writes one, into words (malloc'd, each in the
 * one buffer *store); the count, or -1 when it is not such a line (it may
 * come from a file: a space at its start or two in a row, an empty word,
 * is one springpend never writes) or out of memory. */
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
            if (*p == '\\' && p[1]) { /* \\ (a backslash), an older record's \' */
                *at++ = p[1], p += 2;
                continue;
            }
            if (!strncmp(p, "\"'\"", 3)) { /* "'": a quote */
                *at++ = '\'', p += 3;
                continue;
            }
            if (*p != '\'') {
                *at++ = *p++;
                continue;
            }
            const char *close = strchr(p + 1, '\''); /* a quoted part, to its end */
            if (!close)
                return -1;
            at = unshown(at, p + 1, close);
            p = close + 1;
        }
        *at++ = 0;
        if (*p == ' ' && !*++p)
            return -1;
    }
    return n > INT_MAX ? -1 : (int)n;
}

struct sp_command_line *sp_command_line_read(const char *line)
{
    struct sp_command_line *r = line ? calloc(1, sizeof(*r)) : NULL;
    if (!r)
        return NULL;
    r->n = split(line, &r->w, &r->store);
    if (r->n < 2 || strcmp(r->w[0], first_word) ||
        !(r->argv = malloc((size_t)r->n * sizeof(*r->argv)))) {
        sp_command_line_free(r);
        return NULL;
    }
    memcpy(r->argv, r->w + 1, (size_t)(r->n - 1) * sizeof(*r->argv));
    r->argv[r->n - 1] = NULL;
    return r;
}

char **sp_command_line_words(struct sp_command_line *r, int *argc)
{
    *argc = r->n - 1;
    return r->argv;
}

void sp_command_line_parse_into(struct sp_command_line *r)
{
    parsing = r ? r : &process;
}

size_t sp_command_line_quote(const char *const *words, int n, char *buf, size_t size)
{
    struct word w[16];
    n = n < 16 ? n : 16;
    for (int i = 0; i < n; i++)
        w[i] = (struct word){.pre = "", .s = words[i]};
    return text(buf, size, n, w);
}

char *sp_command_line_text(const struct sp_command_line *r)
{
    return line_of(r, 0, KEEP_NONE, NULL, NULL);
}

char *sp_command_line_merged(const struct sp_command_line *r, const char *skip)
{
    return line_of(r, 1, KEEP_NONE, &process, skip);
}

void sp_command_line_free(struct sp_command_line *r)
{
    if (!r)
        return;
    if (parsing == r)
        parsing = &process;
    free(r->w);
    free(r->store);
    free(r->argv);
    free(r->taken);
    free(r);
}
