/* springpend: compare.ini, per-image tolerances and masks
 * (compare_config.h). libinih splits the lines; ini_lines.c counts them. */
#include <errno.h>
#include <fnmatch.h>
#include <limits.h>
#include <ini.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/compare_config.h"
#include "springpend/infile.h"
#include "base/array.h"
#include "base/decimal.h"
#include "base/ini_lines.h"
#include "video_names.h"

/* The largest max_pixels count: any count beyond an image's pixels passes it;
 * this one stays below LONG_MAX. */
#define MAX_PIXEL_COUNT 1e18
#define MAX_MASK_PX 1000000000 /* a mask's x, y, width, height: an int */
#define STRING(x) #x
#define QUOTE(x) STRING(x)

#define NOT_DECIMAL SP_DECIMAL_NOT

/* Reads s, blanks around it allowed, as a decimal number (decimal.h) within
 * [lo, hi], an integer when `integer` is set. Returns NULL, or what is wrong
 * with it. */
static const char *read_number(const char *s, double lo, double hi, int integer, double *v)
{
    char num[128];
    size_t n;
    s += strspn(s, " \t");
    for (n = strlen(s); n && (s[n - 1] == ' ' || s[n - 1] == '\t');)
        n--;
    if (n >= sizeof(num))
        return NOT_DECIMAL;
    snprintf(num, sizeof(num), "%.*s", (int)n, s);
    return sp_decimal_in(num, lo, hi, integer ? SP_DECIMAL_INTEGER : 0, v);
}

/* Writes "NAME VALUE: WRONG; expected ALLOWED" into why; SP_E_INPUT. */
static int refuse(char *why, size_t why_size, const char *name, const char *value,
                  const char *wrong, const char *allowed)
{
    snprintf(why, why_size, "%s %s: %s; expected %s%s", name, value, wrong, allowed,
             strstr(wrong, NOT_DECIMAL) ? ", " SP_DECIMAL_ALLOWED : "");
    return SP_E_INPUT;
}

/* A mask: four integers "x, y, width, height" in px. */
static int read_mask(const char *value, struct sp_compare_mask *m, char *why, size_t why_size)
{
    static const char *const field[] = {"x", "y", "width", "height"};
    static const char allowed[] = "x, y, width, height in px: integers with x, y >= 0 and "
                                  "width, height >= 1, all at most " QUOTE(MAX_MASK_PX);
    int *out[] = {&m->x, &m->y, &m->w, &m->h};
    const char *p = value;
    char wrong[64], num[128];
    for (int i = 0; i < 4; i++, p += *p == ',') {
        const size_t n = strcspn(p, ",");
        const char *bad;
        double v;
        if (!*p || (i == 3) != !p[n])
            return refuse(why, why_size, "mask", value, "not four numbers", allowed);
        snprintf(num, sizeof(num), "%.*s", (int)n, p);
        bad = n >= sizeof(num) ? NOT_DECIMAL : read_number(num, i < 2 ? 0 : 1, MAX_MASK_PX, 1, &v);
        if (bad) {
            snprintf(wrong, sizeof(wrong), "%s %s", field[i], bad);
            return refuse(why, why_size, "mask", value, wrong, allowed);
        }
        *out[i] = (int)v;
        p += n;
    }
    return 0;
}

int sp_compare_rule_set(struct sp_compare_rule *r, const char *name, const char *value,
                        char *why, size_t why_size)
{
    struct sp_compare_opts *o = &r->opts;
    const char *wrong;
    double v;
    size_t n = strlen(value);
    if (!strcmp(name, "metric")) {
        if (strcmp(value, "reftest") && strcmp(value, "rms") && strcmp(value, "pixelmatch")) {
            snprintf(why, why_size, "metric %s: expected reftest, rms or pixelmatch", value);
            return SP_E_INPUT;
        }
        o->metric = value[1] == 'm' ? SP_COMPARE_RMS
                    : value[0] == 'p' ? SP_COMPARE_PIXELMATCH : SP_COMPARE_REFTEST;
        r->set |= SP_COMPARE_SET_METRIC;
    } else if (!strcmp(name, "threshold")) {
        if ((wrong = read_number(value, 0, 1, 0, &v)))
            return refuse(why, why_size, name, value, wrong,
                          "a pixelmatch threshold from 0 to 1 (like 0.1)");
        o->threshold = v == 0 ? SP_COMPARE_NONE : v;
        r->set |= SP_COMPARE_SET_THRESHOLD;
    } else if (!strcmp(name, "max-diff") || !strcmp(name, "max_diff")) {
        if ((wrong = read_number(value, 0, 255, 1, &v)))
            return refuse(why, why_size, name, value, wrong,
                          "an integer from 0 to 255 (levels)");
        o->max_diff = v == 0 ? SP_COMPARE_NONE : (int)v;
        r->set |= SP_COMPARE_SET_MAX_DIFF;
    } else if (!strcmp(name, "max-pixels") || !strcmp(name, "max_pixels")) {
        /* a percentage: the number, then '%' */
        char num[128];
        const int pct = n > 0 && value[n - 1] == '%';
        snprintf(num, sizeof(num), "%.*s", (int)(n - (size_t)pct), value);
        wrong = n >= sizeof(num) ? NOT_DECIMAL
              : read_number(num, 0, pct ? 100 : MAX_PIXEL_COUNT, !pct, &v);
        if (wrong)
            return refuse(why, why_size, name, value, wrong,
                          "a pixel count (an integer from 0 to " QUOTE(MAX_PIXEL_COUNT) ", like 100) or a "
                          "percentage from 0% to 100% (like 0.5%)");
        o->max_pixels = v == 0 ? SP_COMPARE_NONE : pct ? 0 : (long)v;
        o->max_fraction = pct ? v / 100 : 0;
        r->set |= SP_COMPARE_SET_MAX_PIXELS;
    } else if (!strcmp(name, "tol")) {
        if ((wrong = read_number(value, 0, 255, 0, &v)))
            return refuse(why, why_size, name, value, wrong, "an RMS from 0 to 255 (levels)");
        o->tol = v == 0 ? SP_COMPARE_NONE : v;
        r->set |= SP_COMPARE_SET_TOL;
    } else if (!strcmp(name, "mask")) {
        struct sp_compare_mask m;
        if (read_mask(value, &m, why, why_size))
            return SP_E_INPUT;
        if (r->n_masks == SP_COMPARE_MAX_MASKS) {
            snprintf(why, why_size, "more than %d masks for one image", SP_COMPARE_MAX_MASKS);
            return SP_E_INPUT;
        }
        r->masks[r->n_masks++] = m;
    } else {
        snprintf(why, why_size, "unknown key '%s'; keys: metric, max_diff, max_pixels, tol, "
                 "threshold, mask", name);
        return SP_E_INPUT;
    }
    return 0;
}

/* A FILE:LINE message on stderr, shown printable (sp_fputs_printable):
 * keys and section names come from a file a pull request may write. */
static void say(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void say(const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof(msg), fmt, ap);
    va_end(ap);
    sp_fputs_printable(msg, stderr);
}

struct config_ctx {
    struct sp_compare_config *cfg;
    struct sp_ini_lines lines;
    int section_line; /* of the last [header] read */
    char section[256];    /* its name whole (a line holds at most 198 bytes) */
    int key_line[4];  /* where the last section set each SP_COMPARE_SET_* key */
    int errors, nomem;
};

/* The index of the SP_COMPARE_SET_* bit key sets, -1 for mask (which may
 * repeat: one line per rectangle) and unknown keys. */
static int key_index(const char *key)
{
    static const char *const keys[4][2] = {
        {"metric", "metric"}, {"max_diff", "max-diff"}, {"max_pixels", "max-pixels"},
        {"tol", "tol"}};
    for (int i = 0; i < 4; i++)
        if (!strcmp(key, keys[i][0]) || !strcmp(key, keys[i][1]))
            return i;
    return -1;
}

static char *read_line(char *str, int num, void *stream)
{
    struct config_ctx *c = stream;
    size_t len;
    char *s = sp_ini_lines_next(&c->lines, str, num, &len);
    if (s && s[strspn(s, " \t")] == '[') {
        /* libinih keeps the first 49 bytes of a section name (MAX_SECTION,
         * 50 in Debian's build) and says nothing: a cut path could widen to
         * a whole folder (attack17 #2). handle() takes it whole from here. */
        const char *open = s + strspn(s, " \t") + 1, *close = strchr(open, ']');
        c->section_line = c->lines.line;
        snprintf(c->section, sizeof(c->section), "%.*s", close ? (int)(close - open) : 0, open);
    }
    if (s && len) {
        say("%s:%d: line is %zu bytes long; at most %d are allowed\n",
                c->cfg->path, c->lines.line, len, num - 2);
        c->errors++;
    }
    return s;
}

const char *sp_compare_env_key_check(const char *key)
{
    static const char word[] = "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-";
    if (!key[0] || strlen(key) > 32 || strspn(key, word) != strlen(key))
        return "expected a key of 1 to 32 letters, digits, '_' or '-' (like llvm19)";
    int reserved = !strcasecmp(key, "diff") || !strcasecmp(key, "png");
    for (int i = 0; i < SP_VIDEO_NAMES_COUNT; i++) /* the video endings, dot aside */
        reserved |= !strcasecmp(key, sp_video_names[i].ending + 1);
    if (reserved)
        return "reserved: compare names its own files NAME.diff.png, and NAME.png, "
               "NAME.mp4... are images; choose another key (like llvm19)";
    return NULL;
}

int sp_compare_config_has_env(const struct sp_compare_config *cfg, const char *key)
{
    for (int i = 0; i < cfg->n_envs; i++)
        if (!strcmp(cfg->envs[i], key))
            return 1;
    return 0;
}

/* The top line `envs = KEY, KEY...`: the environment keys of alternative
 * baselines (NAME.KEY.png). Each key checked; none twice. Returns 1 (inih
 * goes on; errors are counted). */
static int read_envs(struct config_ctx *c, const char *value)
{
    struct sp_compare_config *cfg = c->cfg;
    char key[128];
    if (cfg->envs_line) {
        say("%s:%d: envs is set twice (first on line %d); keep one\n", cfg->path,
            c->lines.line, cfg->envs_line);
        c->errors++;
        return 1;
    }
    cfg->envs_line = c->lines.line;
    for (const char *p = value;; p++) {
        size_t n = strcspn(p, ",");
        const char *t = p + strspn(p, " \t"), *why;
        size_t len = (size_t)(p + n - t);
        while (len && (t[len - 1] == ' ' || t[len - 1] == '\t'))
            len--;
        snprintf(key, sizeof(key), "%.*s", (int)(len < sizeof(key) ? len : sizeof(key) - 1), t);
        if ((why = len >= sizeof(key) ? "too long" : sp_compare_env_key_check(key)) != NULL) {
            say("%s:%d: envs: '%s': %s; envs lists keys separated by commas\n", cfg->path,
                c->lines.line, key, why);
            c->errors++;
        } else if (sp_compare_config_has_env(cfg, key)) {
            say("%s:%d: envs: '%s' is listed twice; keep one\n", cfg->path, c->lines.line, key);
            c->errors++;
        } else if (cfg->n_envs == SP_COMPARE_MAX_ENVS) {
            say("%s:%d: envs: more than %d keys; at most %d are allowed\n", cfg->path,
                c->lines.line, SP_COMPARE_MAX_ENVS, SP_COMPARE_MAX_ENVS);
            c->errors++;
            return 1;
        } else {
            memcpy(cfg->envs[cfg->n_envs++], key, strlen(key) + 1); /* checked: <= 32 */
        }
        p += n;
        if (!*p)
            return 1;
    }
}

static int handle(void *user, const char *section, const char *name, const char *value)
{
    struct config_ctx *c = user;
    struct sp_compare_config *cfg = c->cfg;
    char why[1024], v[256];
    /* An inline comment starts at whitespace then '#' or ';', as in scenes. */
    snprintf(v, sizeof(v), "%s", value);
    for (char *p = v; *p; p++)
        if ((*p == '#' || *p == ';') && p > v && (p[-1] == ' ' || p[-1] == '\t')) {
            *p = 0;
            break;
        }
    for (size_t n = strlen(v); n && (v[n - 1] == ' ' || v[n - 1] == '\t');)
        v[--n] = 0;
    value = v;
    /* inih's name a strict prefix of the line's: cut (a line inih refuses,
     * "[a ;b]", fails the whole file) */
    if (strlen(section) < strlen(c->section) && !strncmp(section, c->section, strlen(section)))
        section = c->section;
    if (!section[0] && !strcmp(name, "envs"))
        return read_envs(c, value);
    if (!section[0]) {
        say("%s:%d: '%s' comes before any section; put it under [*] (every "
                "image) or [NAME.png] (only 'envs = KEY, ...' goes before them)\n",
                cfg->path, c->lines.line, name);
        c->errors++;
        return 1;
    }
    if (!cfg->n_rules || strcmp(cfg->rules[cfg->n_rules - 1].name, section)) {
        for (int i = 0; i < cfg->n_rules; i++)
            if (!strcmp(cfg->rules[i].name, section)) {
                say("%s:%d: [%s] appears twice (first on line %d); keep one\n",
                        cfg->path, c->lines.line, section, cfg->rules[i].line);
                c->errors++;
                return 1;
            }
        if (SP_ARRAY_RESERVE(cfg->rules, cfg->cap_rules, cfg->n_rules + 1, 8)) {
            c->nomem = 1;
            return 0;
        }
        struct sp_compare_rule *r = &cfg->rules[cfg->n_rules++];
        memset(r, 0, sizeof(*r));
        snprintf(r->name, sizeof(r->name), "%s", section);
        r->line = c->section_line;
        memset(c->key_line, 0, sizeof(c->key_line));
    }
    /* A key given twice is refused, as in scenes: the last would win unseen. */
    int k = key_index(name);
    if (k >= 0 && c->key_line[k]) {
        say("%s:%d: %s is set twice in [%s] (first on line %d); keep one\n",
                cfg->path, c->lines.line, name, section, c->key_line[k]);
        c->errors++;
        return 1;
    }
    if (k >= 0)
        c->key_line[k] = c->lines.line;
    if (sp_compare_rule_set(&cfg->rules[cfg->n_rules - 1], name, value, why, sizeof(why))) {
        say("%s:%d: %s\n", cfg->path, c->lines.line, why);
        c->errors++;
    }
    return 1;
}

/* 1 when real path `file` is not dir's real path `in` or below it. */
static int outside(const char *file, const char *in)
{
    size_t n = strlen(in);
    return strncmp(file, in, n) || (file[n] != '/' && file[n] != 0);
}

/* Where path really lies: the real path of the nearest folder on the way
 * up from it that exists (path itself first when self is 1; "/" is never
 * looked at), malloc'd, with in *below (when not NULL) the length of the
 * part of path it resolves; NULL when none exists (or path is longer than
 * PATH_MAX). */
static char *nearest_real(const char *path, int self, size_t *below)
{
    char buf[PATH_MAX];
    if (snprintf(buf, sizeof(buf), "%s", path) >= (int)sizeof(buf))
        return NULL;
    char *real = self ? realpath(buf, NULL) : NULL;
    size_t at = strlen(buf);
    for (char *slash = strrchr(buf, '/'); !real && slash && slash > buf;
         slash = strrchr(buf, '/')) {
        *slash = 0; /* not made yet: look further up */
        at = (size_t)(slash - buf);
        real = realpath(buf, NULL);
    }
    if (below)
        *below = at;
    return real;
}

/* The folder a name under dir really lies in: the nearest existing folder
 * above path, resolved. 1 (and where, in to) when that is outside dir: a
 * folder on the way is a link out of it. */
static int parent_outside(const char *path, const char *in, char *to, size_t size)
{
    size_t at;
    char *real = nearest_real(path, 0, &at);
    int out = real && outside(real, in);
    if (out)
        snprintf(to, size, "%s/%s", real, path + at + 1);
    free(real);
    return out;
}

int sp_compare_folder_within(const char *path, const char *dir)
{
    char *in = realpath(dir, NULL), *real = in ? nearest_real(path, 1, NULL) : NULL;
    if (in && !real && !strchr(path, '/'))
        real = realpath(".", NULL); /* a new folder named alone: the working folder */
    int within = in && real && !outside(real, in);
    free(in);
    free(real);
    return within;
}

int sp_compare_parent_outside(const char *path, const char *dir, char *to, size_t size)
{
    char *in = realpath(dir, NULL);
    int out = in && parent_outside(path, in, to, size);
    free(in);
    return out;
}

int sp_compare_link_outside(const char *path, const char *dir, char *to, size_t size)
{
    struct stat st;
    char *in = realpath(dir, NULL);
    if (!in)
        return 0; /* no folder yet (baselines to be added): nothing to follow */
    if (lstat(path, &st) != 0 || !S_ISLNK(st.st_mode)) {
        int out = parent_outside(path, in, to, size);
        free(in);
        return out;
    }
    char *file = realpath(path, NULL);
    int why = errno;
    int out = !file || outside(file, in) || !strcmp(file, in);
    if (out && file) {
        snprintf(to, size, "%s", file);
    } else if (out) { /* a loop or a dangling link: where it points, and why */
        char link[4096];
        ssize_t len = readlink(path, link, sizeof(link) - 1);
        link[len > 0 ? len : 0] = 0;
        snprintf(to, size, "%s (%s)", link, strerror(why));
    }
    free(file);
    free(in);
    return out;
}

/* 1 (said) when the compare.ini at path (stat st) in folder dir may have
 * been put there by someone else than whoever owns its rules: writable by
 * others than its owner, or owned by another user than root or this one
 * unless the folders from dir up, each writable by its owner alone, lead to
 * one of root's or this user's that others may not write either. Its rules
 * decide a verdict: a planted one with max_pixels = 100% passed a failing
 * pair, in a shared folder (attack11 #17) or in a folder its owner made
 * first in /tmp, 755, where root's job later put its baselines (attack12
 * #14). A checkout of another user's (root's CI in a container, on the
 * runner's workspace) is read: only its owner could write there, and only
 * root made the folder it lies in. */
static int planted(const char *path, const char *dir, const struct stat *st)
{
    if (st->st_mode & S_IWOTH) {
        sp_log_error("%s is writable by anyone: not read (its rules decide the verdict); "
                     "chmod o-w it", path);
        return 1;
    }
    if (st->st_uid == 0 || st->st_uid == geteuid())
        return 0;
    char *real = realpath(dir, NULL), at[PATH_MAX];
    if (!real || snprintf(at, sizeof(at), "%s", real) >= (int)sizeof(at)) {
        sp_log_error("%s belongs to user %u, in %s, which cannot be resolved (%s): not read "
                     "(its rules decide the verdict)", path, (unsigned)st->st_uid, dir,
                     real ? "too long" : strerror(errno));
        free(real);
        return 1;
    }
    free(real);
    for (int first = 1;; first = 0) {
        struct stat d;
        if (stat(at, &d) != 0) {
            sp_log_error("%s belongs to user %u; %s, a folder above it: %s: not read (its "
                         "rules decide the verdict)", path, (unsigned)st->st_uid, at,
                         strerror(errno));
            return 1;
        }
        const int mine = d.st_uid == 0 || d.st_uid == geteuid(),
                  open = (d.st_mode & (S_IWGRP | S_IWOTH)) != 0;
        if (open && first) {
            sp_log_error("%s belongs to user %u, in %s, which others than its owner may "
                         "write: anyone could have put it there; not read (its rules decide "
                         "the verdict): remove it, or take it over (chown)", path,
                         (unsigned)st->st_uid, dir);
            return 1;
        }
        if (open) {
            sp_log_error("%s belongs to user %u, in %s, which lies in %s (user %u's, mode "
                         "%03o), a folder others than its owner may write: user %u could have "
                         "made that folder there before you and put the file in it; not read "
                         "(its rules decide the verdict): take the folder over (chown -R) or "
                         "keep the baselines in a folder of your own", path,
                         (unsigned)st->st_uid, dir, at, (unsigned)d.st_uid,
                         (unsigned)(d.st_mode & 07777), (unsigned)st->st_uid);
            return 1;
        }
        if (mine || !strcmp(at, "/"))
            return 0; /* root's or this user's, closed to others; or "/" */
        char *slash = strrchr(at, '/');
        if (slash == at)
            at[1] = 0;
        else
            *slash = 0;
    }
}

int sp_compare_config_load(struct sp_compare_config *cfg, const char *dir)
{
    char to[4096];
    struct stat st;
    char *text = NULL;
    int ret = 0;
    memset(cfg, 0, sizeof(*cfg));
    snprintf(cfg->path, sizeof(cfg->path), "%s/%s", dir, SP_COMPARE_CONFIG_NAME);
    if (sp_compare_link_outside(cfg->path, dir, to, sizeof(to))) {
        sp_log_error("%s is a link to %s, not inside %s: not read; put the file itself there",
                     cfg->path, to, dir);
        return SP_E_INPUT;
    }
    if (lstat(cfg->path, &st) != 0 && errno == ENOENT) {
        cfg->path[0] = 0; /* none: the defaults */
        return 0;
    }
    /* judged and read through one descriptor: the file read is the file
     * whose owner was judged, whatever the name points at meanwhile
     * (attack14 #2: a squatter flipped the name between root's file and
     * theirs) */
    static const char want[] = "compare.ini must be a text file of at most 1 MiB";
    const int fd = sp_infile_open(cfg->path, want);
    if (fd < 0)
        return fd;
    if (fstat(fd, &st) != 0 || planted(cfg->path, dir, &st)) {
        close(fd);
        return SP_E_INPUT;
    }
    size_t n;
    if ((ret = sp_infile_read_fd(fd, cfg->path, 1u << 20, want, &text, &n)) != 0)
        return ret;
    if (strlen(text) != n) {
        sp_log_error("%s: holds NUL bytes; expected an INI text file", cfg->path);
        free(text);
        return SP_E_INPUT;
    }
    struct config_ctx c = {.cfg = cfg, .lines = {.cursor = text}};
    int rc = ini_parse_stream(read_line, &c, handle, &c);
    if (c.nomem) {
        sp_log_error("out of memory");
        ret = SP_E_NOMEM;
    } else if (rc > 0 && !c.errors) {
        say("%s:%d: expected 'key = value', '[NAME.png]', '[*]' or a '#' comment\n",
                cfg->path, rc);
        ret = SP_E_INPUT;
    } else if (c.errors || rc) {
        ret = SP_E_INPUT;
    }
    free(text);
    if (ret)
        sp_compare_config_free(cfg);
    return ret;
}

/* Applies the fields rule sets onto o. */
static void apply(const struct sp_compare_rule *r, struct sp_compare_opts *o)
{
    if (r->set & SP_COMPARE_SET_METRIC)
        o->metric = r->opts.metric;
    if (r->set & SP_COMPARE_SET_MAX_DIFF)
        o->max_diff = r->opts.max_diff;
    if (r->set & SP_COMPARE_SET_MAX_PIXELS)
        o->max_pixels = r->opts.max_pixels, o->max_fraction = r->opts.max_fraction;
    if (r->set & SP_COMPARE_SET_TOL)
        o->tol = r->opts.tol;
    if (r->set & SP_COMPARE_SET_THRESHOLD)
        o->threshold = r->opts.threshold;
}

/* A max_diff or tol as applied: NONE is 0, 0 the default. */
static double level(double v, double dflt)
{
    return v == SP_COMPARE_NONE ? 0 : v > 0 ? v : dflt;
}

/* Keeps the command line's options (cli) where they are stricter than o's. */
static void tighten(const struct sp_compare_rule *cli, struct sp_compare_opts *o)
{
    const struct sp_compare_opts *c = &cli->opts;
    if (cli->set & SP_COMPARE_SET_METRIC)
        o->metric = c->metric;
    if ((cli->set & SP_COMPARE_SET_MAX_DIFF) &&
        level(c->max_diff, SP_COMPARE_MAX_DIFF_DEFAULT) <
            level(o->max_diff, SP_COMPARE_MAX_DIFF_DEFAULT))
        o->max_diff = c->max_diff;
    if ((cli->set & SP_COMPARE_SET_TOL) &&
        level(c->tol, SP_COMPARE_TOL_DEFAULT) < level(o->tol, SP_COMPARE_TOL_DEFAULT))
        o->tol = c->tol;
    if ((cli->set & SP_COMPARE_SET_THRESHOLD) &&
        level(c->threshold, SP_COMPARE_THRESHOLD_DEFAULT) <
            level(o->threshold, SP_COMPARE_THRESHOLD_DEFAULT))
        o->threshold = c->threshold;
    if (cli->set & SP_COMPARE_SET_MAX_PIXELS) /* a count or a share: judged per image */
        o->cap_pixels = c->max_pixels, o->cap_fraction = c->max_fraction;
}

/* The command line's own rule, when it gives a limit: its limits with the
 * defaults for the rest, never compare.ini's fields, which could loosen a
 * limit through another field (attack16 #7: `threshold = 1` or `max_diff =
 * 255` made --max-pixels 0 pass anything; attack15 #7: `metric = rms`).
 * Its metric is --metric's; else each limit brings the rule that reads it
 * on the command line alone: reftest for --max-diff, and for --max-pixels
 * unless --threshold makes it pixelmatch's; rms for --tol; pixelmatch for
 * --threshold. sp_compare_images checks each beside the metric's rule
 * (unless the latter's limits imply it). */
static void own_rule(const struct sp_compare_rule *cli, struct sp_compare_opts *o)
{
    const unsigned s = cli->set;
    const struct sp_compare_opts *c = &cli->opts;
    if (!(s & (SP_COMPARE_SET_MAX_DIFF | SP_COMPARE_SET_MAX_PIXELS | SP_COMPARE_SET_TOL |
               SP_COMPARE_SET_THRESHOLD)))
        return; /* --metric alone, or nothing: compare.ini's limits */
    o->own = (struct sp_compare_limits){c->max_diff, c->max_pixels, c->max_fraction, c->tol,
                                        c->threshold};
    if (s & SP_COMPARE_SET_METRIC) {
        o->also = 1u << c->metric;
        return;
    }
    if ((s & SP_COMPARE_SET_MAX_DIFF) ||
        ((s & SP_COMPARE_SET_MAX_PIXELS) && !(s & SP_COMPARE_SET_THRESHOLD)))
        o->also |= 1u << SP_COMPARE_REFTEST;
    if (s & SP_COMPARE_SET_TOL)
        o->also |= 1u << SP_COMPARE_RMS;
    if (s & SP_COMPARE_SET_THRESHOLD)
        o->also |= 1u << SP_COMPARE_PIXELMATCH;
}

/* How section `sect` applies to image `name` (relative path): 0 not at
 * all, 1 [*], 2 a wildcard section, 3 the image's own section. */
static int section_match(const char *sect, const char *name)
{
    const char *base = strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
    const char *target = strchr(sect, '/') ? name : base;
    if (!strcmp(sect, "*"))
        return 1;
    if (!strcmp(sect, target))
        return 3;
    if (strpbrk(sect, "*?[") && fnmatch(sect, target, FNM_PATHNAME) == 0)
        return 2;
    return 0;
}

void sp_compare_config_resolve(struct sp_compare_config *cfg, const char *name,
                               const struct sp_compare_rule *cli,
                               struct sp_compare_opts *opts,
                               struct sp_compare_mask masks[SP_COMPARE_RESOLVED_MASKS],
                               int *n_masks)
{
    memset(opts, 0, sizeof(*opts));
    *n_masks = 0;
    apply(cli, opts); /* without compare.ini the command line decides */
    for (int level = 1; level <= 3; level++)
        for (int i = 0; i < cfg->n_rules; i++) {
            struct sp_compare_rule *r = &cfg->rules[i];
            if (section_match(r->name, name) != level)
                continue;
            if (level > 1)
                __atomic_store_n(&r->used, 1, __ATOMIC_RELAXED); /* threads */
            apply(r, opts);
            for (int k = 0; k < r->n_masks && *n_masks < SP_COMPARE_RESOLVED_MASKS; k++)
                masks[(*n_masks)++] = r->masks[k];
        }
    tighten(cli, opts);
    own_rule(cli, opts);
    opts->given = cli->set;
    for (int i = 0; i < cfg->n_rules; i++)
        if (section_match(cfg->rules[i].name, name))
            opts->given |= cfg->rules[i].set;
}

void sp_compare_config_warn_unused(const struct sp_compare_config *cfg)
{
    for (int i = 0; i < cfg->n_rules; i++)
        if (!cfg->rules[i].used && strcmp(cfg->rules[i].name, "*"))
            say("%s:%d: warning: [%s] matches no compared image\n", cfg->path,
                    cfg->rules[i].line, cfg->rules[i].name);
}

void sp_compare_config_free(struct sp_compare_config *cfg)
{
    free(cfg->rules);
    cfg->rules = NULL;
    cfg->n_rules = cfg->cap_rules = 0;
}
