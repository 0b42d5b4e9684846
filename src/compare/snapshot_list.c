/* springpend: the images compare's folder mode compares (snapshot_list.h). */
#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "springpend/common.h"
#include "springpend/snapshot_list.h"
#include "base/array.h"
#include "video_names.h"

/* The extension's dot in name's last component, or NULL. */
static const char *ext_of(const char *name)
{
    const char *base = strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
    const char *dot = strrchr(base, '.');
    return dot && dot > base ? dot : NULL;
}

int sp_snapshot_is_folder_link(const char *name)
{
    size_t n = strlen(name);
    return n && name[n - 1] == '/';
}

int sp_snapshot_is_png(const char *name)
{
    const char *e = ext_of(name);
    return e && !strcasecmp(e, ".png");
}

int sp_snapshot_is_video(const char *name)
{
    const char *e = ext_of(name);
    for (int i = 0; e && i < SP_VIDEO_NAMES_COUNT; i++) /* the reader's own list */
        if (!strcasecmp(e, sp_video_names[i].ending))
            return 1;
    return 0;
}

/* A growing list of names. */
struct names {
    char **v;
    int n, cap;
};

static int names_add(struct names *s, const char *name)
{
    if (SP_ARRAY_RESERVE(s->v, s->cap, s->n + 1, 64))
        return SP_E_NOMEM;
    if (!(s->v[s->n] = strdup(name)))
        return SP_E_NOMEM;
    s->n++;
    return 0;
}

static void names_free(struct names *s)
{
    for (int i = 0; i < s->n; i++)
        free(s->v[i]);
    free(s->v);
    memset(s, 0, sizeof(*s));
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* 1 when name is in the sorted list s. */
static int names_has(const struct names *s, const char *name)
{
    return s->n && bsearch(&name, s->v, (size_t)s->n, sizeof(*s->v), by_name) != NULL;
}

/* Folders not to walk, by device and inode. */
struct skips {
    dev_t dev[4];
    ino_t ino[4];
    int n;
};

/* Adds the media files under root/rel to s (rel "" for root itself). */
static int walk(const char *root, const char *rel, const struct skips *skip, struct names *s,
                int depth)
{
    char path[PATH_MAX], sub[PATH_MAX];
    int err = 0;
    snprintf(path, sizeof(path), "%s%s%s", root, rel[0] ? "/" : "", rel);
    DIR *d = opendir(path);
    if (!d) {
        if (!rel[0] && errno == ENOENT)
            return 0; /* no baselines yet */
        sp_log_error("cannot list %s: %s", path, strerror(errno));
        return SP_E_INPUT;
    }
    for (struct dirent *e; !err && (e = readdir(d));) {
        struct stat st;
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
            continue;
        if (snprintf(sub, sizeof(sub), "%s%s%s", rel, rel[0] ? "/" : "", e->d_name) >=
                (int)sizeof(sub) ||
            snprintf(path, sizeof(path), "%s/%s", root, sub) >= (int)sizeof(path)) {
            sp_log_error("%s/%s: the path is too long", root, sub);
            err = SP_E_INPUT;
            break;
        }
        if (lstat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            int skipped = 0;
            for (int i = 0; i < skip->n; i++)
                skipped |= st.st_dev == skip->dev[i] && st.st_ino == skip->ino[i];
            if (!skipped && depth >= SP_SNAPSHOT_MAX_DEPTH) {
                sp_log_error("%s: folders nested more than %d deep; compare does not go "
                             "that deep, so nothing there would be compared: move the "
                             "images up", path, SP_SNAPSHOT_MAX_DEPTH);
                err = SP_E_INPUT;
            } else if (!skipped) {
                err = walk(root, sub, skip, s, depth + 1);
            }
        } else if (S_ISLNK(st.st_mode) && stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
            /* never followed; listed (with a trailing '/') so that the run
             * says so instead of passing without what is behind it */
            char link[PATH_MAX];
            if (snprintf(link, sizeof(link), "%s/", sub) < (int)sizeof(link))
                err = names_add(s, link);
        } else if (sp_snapshot_is_png(e->d_name) || sp_snapshot_is_video(e->d_name)) {
            err = names_add(s, sub);
        }
    }
    closedir(d);
    return err;
}

int sp_snapshot_key_named(const char *name, const char *const *keys, int n_keys, char *stem,
                          int size)
{
    const char *ext = ext_of(name), *base = strrchr(name, '/') ? strrchr(name, '/') + 1 : name;
    if (!ext)
        return 0;
    for (const char *dot = ext - 1; dot > base; dot--) {
        if (*dot != '.')
            continue;
        const size_t len = (size_t)(ext - dot - 1);
        for (int k = 0; k < n_keys; k++)
            if (strlen(keys[k]) == len && !strncmp(keys[k], dot + 1, len)) {
                if (stem)
                    snprintf(stem, (size_t)size, "%.*s%s", (int)(dot - name), name, ext);
                return (int)len;
            }
        return 0;
    }
    return 0;
}

/* The image alt is named for: "a.llvm19.png" is "a.png"'s when llvm19 is
 * one of keys, whatever exists (sp_snapshot_key_named). A dotted name
 * whose last part is no declared key ("fig.1.png", "scene.lyapunov.png")
 * is an image of its own. Returns 1 and the name in out. */
static int stem_of(const char *alt, const char *const *keys, int n_keys, char *out, size_t size)
{
    return sp_snapshot_key_named(alt, keys, n_keys, out, (int)size) > 0;
}

void sp_snapshot_alt_key(const char *name, const char *alt, char *key, int size)
{
    const char *ext = ext_of(name);
    size_t stem = ext ? (size_t)(ext - name) : strlen(name);
    const char *k = alt + stem + 1, *end = ext_of(alt);
    snprintf(key, (size_t)size, "%.*s", end && end > k ? (int)(end - k) : 0, k);
}

void sp_snapshot_alt_name(const char *name, const char *key, char *out, int size)
{
    const char *ext = ext_of(name);
    size_t stem = ext ? (size_t)(ext - name) : strlen(name);
    snprintf(out, (size_t)size, "%.*s.%s%s", (int)stem, name, key, ext ? ext : "");
}

static struct sp_snapshot *item_add(struct sp_snapshot_list *l, int *cap, const char *name)
{
    if (SP_ARRAY_RESERVE(l->items, *cap, l->n + 1, 64))
        return NULL;
    struct sp_snapshot *it = &l->items[l->n];
    memset(it, 0, sizeof(*it));
    if (!(it->name = strdup(name)))
        return NULL;
    l->n++;
    return it;
}

static struct sp_snapshot *item_find(struct sp_snapshot_list *l, const char *name)
{
    for (int lo = 0, hi = l->n - 1; lo <= hi;) {
        int mid = (lo + hi) / 2, c = strcmp(l->items[mid].name, name);
        if (!c)
            return &l->items[mid];
        if (c < 0)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return NULL;
}

static int item_by_name(const void *a, const void *b)
{
    return strcmp(((const struct sp_snapshot *)a)->name, ((const struct sp_snapshot *)b)->name);
}

int sp_snapshot_list_make(struct sp_snapshot_list *l, const char *dir_e, const char *dir_a,
                          const char *const *skip, int n_skip, const char *const *keys,
                          int n_keys)
{
    struct names e = {0}, a = {0};
    struct skips sk = {0};
    char stem[PATH_MAX];
    int err, cap = 0;
    memset(l, 0, sizeof(*l));
    for (int i = 0; i < n_skip && sk.n < 4; i++) {
        struct stat st;
        if (skip[i] && stat(skip[i], &st) == 0 && S_ISDIR(st.st_mode))
            sk.dev[sk.n] = st.st_dev, sk.ino[sk.n++] = st.st_ino;
    }
    if ((err = walk(dir_e, "", &sk, &e, 0)) || (err = walk(dir_a, "", &sk, &a, 0)))
        goto done;
    if (e.n)
        qsort(e.v, (size_t)e.n, sizeof(*e.v), by_name);
    if (a.n)
        qsort(a.v, (size_t)a.n, sizeof(*a.v), by_name);
    /* The images: every actual one (one named like an alternative is an
     * error: alt_named), and every baseline that is not an alternative of
     * another image's plain baseline; one whose image has no plain baseline
     * is that image's when it is an actual one (which screen_item reports),
     * else an error of its own (orphan), as NAME.KEY.KEY.EXT is (nested). */
    for (int i = 0; i < a.n; i++) {
        struct sp_snapshot *it = item_add(l, &cap, a.v[i]);
        if (!it)
            goto nomem;
        it->alt_named = stem_of(a.v[i], keys, n_keys, stem, sizeof(stem));
    }
    for (int i = 0; i < e.n; i++) {
        char stem2[PATH_MAX];
        struct sp_snapshot *it;
        if (names_has(&a, e.v[i]))
            continue;
        if (!stem_of(e.v[i], keys, n_keys, stem, sizeof(stem))) {
            if (!item_add(l, &cap, e.v[i]))
                goto nomem;
        } else if (stem_of(stem, keys, n_keys, stem2, sizeof(stem2))) {
            /* NAME.KEY.KEY.png: a baseline has one KEY; listed, to be
             * reported (it was once in neither list) */
            if (!(it = item_add(l, &cap, e.v[i])))
                goto nomem;
            it->nested = 1;
        } else if (!names_has(&e, stem) && !names_has(&a, stem)) {
            /* an alternative of an image that is in neither folder */
            if (!(it = item_add(l, &cap, e.v[i])))
                goto nomem;
            it->orphan = 1;
        }
    }
    if (l->n)
        qsort(l->items, (size_t)l->n, sizeof(*l->items), item_by_name);
    for (int i = 0; i < l->n; i++) {
        l->items[i].actual = names_has(&a, l->items[i].name);
        l->items[i].expected = names_has(&e, l->items[i].name);
    }
    /* Then the alternatives, each to its image (one whose name an actual
     * image has too is still its image's: that actual image is alt_named) */
    for (int i = 0; i < e.n; i++) {
        char stem2[PATH_MAX];
        struct sp_snapshot *it;
        if (!stem_of(e.v[i], keys, n_keys, stem, sizeof(stem)) ||
            stem_of(stem, keys, n_keys, stem2, sizeof(stem2)) || !(it = item_find(l, stem)))
            continue;
        if (SP_ARRAY_RESERVE(it->alts, it->cap_alts, it->n_alts + 1, 4) ||
            !(it->alts[it->n_alts] = strdup(e.v[i])))
            goto nomem;
        it->n_alts++;
    }
    goto done;
nomem:
    sp_log_error("out of memory listing %s and %s", dir_e, dir_a);
    err = SP_E_NOMEM;
done:
    names_free(&e);
    names_free(&a);
    if (err)
        sp_snapshot_list_free(l);
    return err;
}

void sp_snapshot_list_free(struct sp_snapshot_list *l)
{
    for (int i = 0; i < l->n; i++) {
        for (int k = 0; k < l->items[i].n_alts; k++)
            free(l->items[i].alts[k]);
        free(l->items[i].alts);
        free(l->items[i].name);
    }
    free(l->items);
    memset(l, 0, sizeof(*l));
}
