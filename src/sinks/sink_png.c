/* springpend: PNG sinks. A sequence writes frame k (from desc.first_frame)
 * to snprintf(pattern, k), each through its own .part renamed at once; a
 * single PNG takes exactly one image, renamed into place on close (or
 * written through a device, FIFO or stdout). */
#include <errno.h>
#include <limits.h>
#include <sys/stat.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/cpu_count.h"
#include "springpend/common.h"
#include "springpend/png_io.h"
#include "base/array.h"
#include "sink_impl.h"

/* How every PNG of this sink is written: its level, RGB when the frames
 * are opaque, and the caller's text chunks. */
static struct sp_png_write_opts png_opts(const struct sp_sink *s)
{
    return (struct sp_png_write_opts){
        .level = s->desc.png_level ? s->desc.png_level : SP_PNG_LEVEL_DEFAULT,
        .opaque = !s->desc.alpha, /* frames without alpha are opaque */
        .text = s->desc.text, .n_text = s->desc.n_text, .dpi = s->desc.dpi,
    };
}

/* ---- sequence ---- */

/* A sequence compresses its frames on a pool of writer threads, one per
 * core (zlib is the slow part), so sp_sink_write only copies the image into
 * a free job and returns; a writer's failure is returned by a later write
 * or by close. */
#define PNG_MAX_WRITERS 8
#define PNG_MAX_TEXT 13         /* text chunks a frame may carry */

enum job_state { JOB_FREE, JOB_PENDING, JOB_RUNNING };

struct png_job {
    enum job_state state;
    struct sp_image img; /* owned copy, allocated at the first write */
    long number;         /* the frame number in the file name */
    char *name;          /* owned: its path, room for any int */
    /* The caller's text chunks as they were at the write (the caller may
     * change them before the writer gets to this job). */
    struct sp_png_text text[PNG_MAX_TEXT]; /* point into text_buf */
    int n_text;
    char *text_buf;      /* owned: their keys and texts, with NULs (a scene may
                            hold 256 KiB of text, up to 4 side by side) */
    size_t text_cap;     /* bytes of text_buf */
};

struct png_sequence {
    pthread_mutex_t lock;
    pthread_cond_t changed;            /* a job changed state, or stop */
    struct png_job job[PNG_MAX_WRITERS + 1];
    pthread_t writer[PNG_MAX_WRITERS];
    int n_jobs, n_writers;             /* writers started */
    int stop;                          /* writers: leave when idle */
    int err;                           /* first writer failure */
    size_t cap;                        /* bytes of each name buffer */
    /* written[k]: frame first_frame + k was renamed into place by this
     * run (so only those are removed on abort); n_written entries */
    uint8_t *written;
    long n_written;
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

/* Puts the name of the frame numbered `number` into buf (cap bytes). */
static void png_sequence_name(const struct sp_sink *s, long number, char *buf,
                              size_t cap)
{
    /* The pattern passed png_sequence_check: one int conversion. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
    snprintf(buf, cap, s->path, (int)number);
#pragma GCC diagnostic pop
}

static void *png_writer(void *arg)
{
    struct sp_sink *s = arg;
    struct png_sequence *q = s->priv;
    pthread_mutex_lock(&q->lock);
    for (;;) {
        struct png_job *j = NULL;
        for (int i = 0; i < q->n_jobs && !j; i++)
            if (q->job[i].state == JOB_PENDING)
                j = &q->job[i];
        if (!j) {
            if (q->stop)
                break;
            pthread_cond_wait(&q->changed, &q->lock);
            continue;
        }
        j->state = JOB_RUNNING;
        int skip = q->err != 0; /* after a failure, only drain */
        pthread_mutex_unlock(&q->lock);
        int err = 0;
        if (!skip) {
            png_sequence_name(s, j->number, j->name, q->cap);
            struct sp_png_write_opts opts = png_opts(s);
            opts.text = j->text;
            opts.n_text = j->n_text;
            err = sp_png_write_opts(j->name, &j->img, &opts); /* whole or nothing */
        }
        pthread_mutex_lock(&q->lock);
        if (!skip && !err)
            q->written[j->number - s->desc.first_frame] = 1;
        if (err && !q->err)
            q->err = err;
        j->state = JOB_FREE;
        pthread_cond_broadcast(&q->changed);
    }
    pthread_mutex_unlock(&q->lock);
    return NULL;
}

/* Waits for every job, stops and joins the writers, frees the jobs.
 * Returns the first writer failure. */
static int png_sequence_finish(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    if (!q->cap)
        return q->err; /* finished already */
    pthread_mutex_lock(&q->lock);
    q->stop = 1;
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
    for (int i = 0; i < q->n_writers; i++)
        pthread_join(q->writer[i], NULL);
    q->n_writers = 0;
    for (int i = 0; i < q->n_jobs; i++) {
        sp_image_free(&q->job[i].img);
        free(q->job[i].name);
        free(q->job[i].text_buf);
        q->job[i].name = q->job[i].text_buf = NULL;
        q->job[i].text_cap = 0;
    }
    q->n_jobs = 0;
    pthread_mutex_destroy(&q->lock);
    pthread_cond_destroy(&q->changed);
    q->cap = 0;
    return q->err;
}

static int png_sequence_open(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    const int cores = sp_cpu_count(); /* those this process may use */
    int writers = cores > PNG_MAX_WRITERS ? PNG_MAX_WRITERS : cores;
    pthread_mutex_init(&q->lock, NULL);
    pthread_cond_init(&q->changed, NULL);
    q->cap = strlen(s->path) + 99;
    for (q->n_jobs = 0; q->n_jobs < writers + 1; q->n_jobs++) {
        struct png_job *j = &q->job[q->n_jobs];
        j->name = malloc(q->cap);
        if (!j->name) {
            q->n_jobs++;
            sp_log_error("out of memory");
            png_sequence_finish(s);
            return SP_E_NOMEM;
        }
    }
    for (; q->n_writers < writers; q->n_writers++)
        if (pthread_create(&q->writer[q->n_writers], NULL, png_writer, s) != 0)
            break;
    if (!q->n_writers) {
        sp_log_error("%s: cannot start a PNG writer thread", s->path);
        png_sequence_finish(s);
        return SP_E_NOMEM;
    }
    return 0;
}

/* Copies the caller's text chunks into j; SP_E_INPUT (logged) if they do
 * not fit. */
static int copy_text(const struct sp_sink *s, struct png_job *j)
{
    size_t used = 0;
    if (s->desc.n_text > PNG_MAX_TEXT) {
        sp_log_error("%s: %d PNG text chunks; at most %d", s->path,
                     s->desc.n_text, PNG_MAX_TEXT);
        return SP_E_INPUT;
    }
    for (int i = 0; i < s->desc.n_text; i++)
        used += strlen(s->desc.text[i].key) + strlen(s->desc.text[i].text) + 2;
    if (SP_ARRAY_RESERVE(j->text_buf, j->text_cap, used, 0)) {
        sp_log_error("%s: out of memory for %zu bytes of PNG text", s->path, used);
        return SP_E_NOMEM;
    }
    used = 0;
    for (int i = 0; i < s->desc.n_text; i++) {
        const struct sp_png_text *t = &s->desc.text[i];
        size_t nk = strlen(t->key) + 1, nt = strlen(t->text) + 1;
        j->text[i].key = memcpy(j->text_buf + used, t->key, nk);
        j->text[i].text = memcpy(j->text_buf + used + nk, t->text, nt);
        j->text[i].compressed = t->compressed;
        used += nk + nt;
    }
    j->n_text = s->desc.n_text;
    return 0;
}

static int png_sequence_write(struct sp_sink *s, const struct sp_image *img)
{
    struct png_sequence *q = s->priv;
    struct png_job *j = NULL;
    pthread_mutex_lock(&q->lock);
    while (!q->err) {
        for (int i = 0; i < q->n_jobs && !j; i++)
            if (q->job[i].state == JOB_FREE)
                j = &q->job[i];
        if (j)
            break;
        pthread_cond_wait(&q->changed, &q->lock);
    }
    int err = q->err;
    pthread_mutex_unlock(&q->lock);
    if (err)
        return err; /* logged by the writer */
    /* A free job is ours until we mark it pending. */
    if (!j->img.pixels && (err = sp_image_alloc(&j->img, img->width, img->height)) != 0)
        return err;
    for (int y = 0; y < img->height; y++)
        memcpy(j->img.pixels + (size_t)y * j->img.stride,
               img->pixels + (size_t)y * img->stride, 4 * (size_t)img->width);
    if ((err = copy_text(s, j)) != 0)
        return err;
    j->number = s->desc.first_frame + s->frames;
    pthread_mutex_lock(&q->lock);
    if (s->frames >= q->n_written) {
        const long had = q->n_written;
        if (SP_ARRAY_RESERVE(q->written, q->n_written, s->frames + 1, 256)) {
            pthread_mutex_unlock(&q->lock);
            sp_log_error("out of memory");
            return SP_E_NOMEM;
        }
        memset(q->written + had, 0, (size_t)(q->n_written - had));
    }
    j->state = JOB_PENDING;
    pthread_cond_broadcast(&q->changed);
    pthread_mutex_unlock(&q->lock);
    return 0;
}

static void png_sequence_free(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    free(q->written);
    q->written = NULL;
    q->n_written = 0;
}

/* A whole video's sequence is the pattern's frames 0 .. its last: the
 * files numbered on from there (consecutively), an earlier and longer
 * run's, are removed, so that an encoder or a folder compare reading the
 * pattern does not take them for this run's (attack13 #11). Only regular
 * files; anything else stops the cleaning, said. */
static void png_sequence_remove_stale(struct sp_sink *s)
{
    const size_t cap = strlen(s->path) + 99;
    char *name = malloc(cap), *first = malloc(cap);
    long removed = 0, last_k = 0;
    for (long k = s->desc.first_frame + s->frames; name && first && k <= INT_MAX; k++) {
        struct stat st;
        png_sequence_name(s, k, name, cap);
        if (lstat(name, &st) != 0)
            break; /* the end of the old sequence (or nothing to see) */
        if (!S_ISREG(st.st_mode) || unlink(name) != 0) {
            sp_log_error("%s is numbered past this video's last frame but %s; remove it, "
                         "or the pattern's readers take it for part of this video", name,
                         !S_ISREG(st.st_mode) ? "is not a regular file" : strerror(errno));
            break;
        }
        if (!removed++)
            memcpy(first, name, cap);
        last_k = k;
    }
    if (removed && name)
        png_sequence_name(s, last_k, name, cap); /* the last one removed */
    if (removed)
        sp_log_note("removed %ld frame%s numbered past this video's last (%s%s%s), left by an "
                    "earlier, longer run", removed, removed == 1 ? "" : "s", first,
                    removed > 1 ? " .. " : "", removed > 1 ? name : "");
    free(name);
    free(first);
}

static int png_sequence_close(struct sp_sink *s)
{
    int err = png_sequence_finish(s);
    if (!err && s->desc.whole)
        png_sequence_remove_stale(s);
    if (!err)
        png_sequence_free(s); /* else abort comes next and needs it */
    return err;
}

/* Every frame this run renamed into place is removed, so a failed or
 * aborted run leaves no partial sequence; files it never wrote (an earlier
 * run's frames) stay, and a failed write has already removed its .part. */
static void png_sequence_abort(struct sp_sink *s)
{
    struct png_sequence *q = s->priv;
    size_t cap = strlen(s->path) + 99;
    png_sequence_finish(s);
    char *name = malloc(cap);
    for (long k = 0; name && k < s->frames && k < q->n_written; k++) {
        if (!q->written[k])
            continue;
        png_sequence_name(s, s->desc.first_frame + k, name, cap);
        if (unlink(name) != 0 && errno != ENOENT)
            sp_log_error("cannot remove %s: %s", name, strerror(errno));
    }
    free(name);
    png_sequence_free(s);
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
    struct sp_outfile out; /* written by the one write */
};

static int png_single_open(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    return sp_outfile_open(&o->out, s->path, SP_OUTFILE_STREAM);
}

static int png_single_write(struct sp_sink *s, const struct sp_image *img)
{
    struct png_single *o = s->priv;
    if (s->frames > 0) {
        sp_log_error("%s: a single PNG takes one image; for one file per "
                     "frame use a pattern like frames/%%05d.png", s->path);
        return SP_E_INPUT;
    }
    struct sp_png_write_opts opts = png_opts(s);
    return sp_png_write_outfile(&o->out, img, &opts);
}

static int png_single_close(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    return s->desc.partner ? sp_outfile_commit_pair(&o->out, s->desc.partner, NULL)
                           : sp_outfile_commit(&o->out);
}

static void png_single_abort(struct sp_sink *s)
{
    struct png_single *o = s->priv;
    sp_outfile_discard(&o->out);
    if (s->desc.partner)
        sp_outfile_discard(s->desc.partner);
}

const struct sp_sink_backend sp_sink_backend_png_single = {
    .priv_size = sizeof(struct png_single),
    .open = png_single_open,
    .write = png_single_write,
    .close = png_single_close,
    .abort = png_single_abort,
};
