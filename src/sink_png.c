/* springpend: PNG sinks. A sequence writes frame k (from 0) to
 * snprintf(pattern, k), each through NAME.part renamed at once; a single
 * PNG takes exactly one image, renamed into place on close. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/png_io.h"
#include "sink_impl.h"

/* How every PNG of this sink is written: the default level and the
 * caller's text chunks. */
static struct sp_png_write_opts png_opts(const struct sp_sink *s)
{
    return (struct sp_png_write_opts){
        .level = SP_PNG_LEVEL_DEFAULT, .text = s->desc.text, .n_text = s->desc.n_text};
}

/* ---- sequence ---- */

struct png_sequence {
    char *name; /* owned: the current frame's path, room for any int */
    char *part; /* owned: name + ".part", same room */
    size_t cap; /* bytes of each buffer */
};

/* Accepts exactly one %d or %i with an optional 0 flag and a width of at
 * most 2 digits; every other '%' must be "%%"; no '%' in folder names.
 * This makes snprintf(pattern, int) safe and its output at most strlen +
 * 99 bytes. */
static int png_sequence_check(const struct sp_sink_desc *desc)
{
    const char *path = desc->path, *slash = strrchr(path, '/');
    int conversions = 0;
    if (slash && memchr(path, '%', (size_t)(slash - path)))
        goto bad; /* folders are made once, at open */
    for (const char *p = path; (p = strchr(p, '%')) != NULL; p++) {
        if (p[1] == '%') {
            p++;
            continue;
        }
        const char *q = p + 1;
        if (*q == '0')
            q++;
        for (int digits = 0; *q >= '0' && *q <= '9'; q++)
            if (++digits > 2)
                goto bad;
        if (*q != 'd' && *q != 'i')
            goto bad;
        conversions++;
        p = q;
    }
    if (conversions == 1)
        return 0;
bad:
    sp_log_error("%s: a PNG sequence needs one frame number like %%d or "
                 "%%05d in the file name (not in a folder), and %%%% for a "
                 "literal %%", path);
    return SP_E_INPUT;
}

static int png_sequence_open(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    q->cap = strlen(s->path) + 99 + sizeof(".part");
    q->name = malloc(q->cap);
    q->part = malloc(q->cap);
    if (!q->name || !q->part) {
        free(q->name);
        free(q->part);
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    return 0;
}

static int png_sequence_write(struct sp_sink *s, const struct sp_image *img)
{
    struct png_sequence *q = s->priv;
    /* The pattern passed png_sequence_check: one int conversion. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    snprintf(q->name, q->cap, s->path, (int)s->frames);
#pragma GCC diagnostic pop
    snprintf(q->part, q->cap, "%s.part", q->name);
    struct sp_png_write_opts wo = png_opts(s);
    int err = sp_png_write_opts(q->part, img, &wo);
    if (!err)
        err = sp_sink_commit(q->part, q->name);
    if (err)
        sp_sink_discard(q->part);
    return err;
}

static int png_sequence_close(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    free(q->name);
    free(q->part);
    q->name = q->part = NULL;
    return 0;
}

/* A failed write has already removed its .part; frames renamed into place
 * are complete and stay. */
static void png_sequence_abort(struct sp_sink *s)
{
    png_sequence_close(s);
}

const struct sp_sink_backend sp_sink_backend_png_sequence = {
    .priv_size = sizeof(struct png_sequence),
    .check = png_sequence_check,
    .open = png_sequence_open,
    .write = png_sequence_write,
    .close = png_sequence_close,
    .abort = png_sequence_abort,
};

/* ---- single image ---- */

struct png_single {
    char *part; /* owned: "PATH.part", written by the one write */
};

static int png_single_open(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    return sp_sink_part_path(s->path, &o->part);
}

static int png_single_write(struct sp_sink *s, const struct sp_image *img)
{
    struct png_single *o = s->priv;
    if (s->frames > 0) {
        sp_log_error("%s: a single PNG takes one image; for one file per "
                     "frame use a pattern like frames/%%05d.png", s->path);
        return SP_E_INPUT;
    }
    struct sp_png_write_opts wo = png_opts(s);
    return sp_png_write_opts(o->part, img, &wo);
}

static int png_single_close(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    int err = sp_sink_commit(o->part, s->path);
    if (!err) {
        free(o->part);
        o->part = NULL;
    }
    return err;
}

static void png_single_abort(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    if (o->part)
        sp_sink_discard(o->part);
    free(o->part);
    o->part = NULL;
}

const struct sp_sink_backend sp_sink_backend_png_single = {
    .priv_size = sizeof(struct png_single),
    .open = png_single_open,
    .write = png_single_write,
    .close = png_single_close,
    .abort = png_single_abort,
};
