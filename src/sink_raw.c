/* springpend: raw frames, for piping into other tools: each image as
 * height rows of width RGBA8 pixels (4 bytes each, top row first), no
 * header, no padding. Path "-" is stdout; a file goes through NAME.part. */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "sink_impl.h"

struct raw {
    int fd;     /* 1 for stdout, else owned */
    char *part; /* owned: "PATH.part"; NULL for stdout or once renamed */
    const char *parts[2]; /* {part, NULL} */
};

static int raw_open(struct sp_sink *s)
{
    struct raw *o = s->priv;
    o->fd = 1;
    if (!strcmp(s->path, "-"))
        return 0;
    int err = sp_sink_part_path(s->path, &o->part);
    if (err)
        return err;
    o->parts[0] = o->part;
    o->fd = open(o->part, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    if (o->fd < 0) {
        sp_log_error("%s: cannot create %s: %s", s->path, o->part,
                     strerror(errno));
        o->parts[0] = NULL;
        free(o->part);
        o->part = NULL;
        return SP_E_IO;
    }
    return 0;
}

/* Writes all n bytes of buf, retrying after signals and short writes. */
static int write_all(struct sp_sink *s, const uint8_t *buf, size_t n)
{
    struct raw *o = s->priv;
    while (n > 0) {
        ssize_t k = write(o->fd, buf, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0) {
            sp_log_error("%s: cannot write frame %ld: %s",
                         o->fd == 1 && !o->part ? "stdout" : s->path,
                         s->frames, errno == EPIPE ? "the reader closed the "
                         "pipe" : strerror(errno));
            return SP_E_IO;
        }
        buf += k;
        n -= (size_t)k;
    }
    return 0;
}

static int raw_write(struct sp_sink *s, const struct sp_image *img)
{
    size_t row = 4 * (size_t)img->width;
    if (img->stride == (int)row)
        return write_all(s, img->pixels, row * img->height);
    for (int y = 0; y < img->height; y++) {
        int err = write_all(s, img->pixels + (size_t)y * img->stride, row);
        if (err)
            return err;
    }
    return 0;
}

static int raw_close(struct sp_sink *s)
{
    struct raw *o = s->priv;
    if (!o->part)
        return 0; /* stdout: the caller owns it */
    int fd = o->fd;
    o->fd = -1;
    if (close(fd) != 0) {
        sp_log_error("%s: cannot finish %s: %s", s->path, o->part,
                     strerror(errno));
        return SP_E_IO;
    }
    int err = sp_sink_commit(o->part, s->path);
    if (!err) {
        o->parts[0] = NULL;
        free(o->part);
        o->part = NULL;
    }
    return err;
}

static void raw_abort(struct sp_sink *s)
{
    struct raw *o = s->priv;
    if (!o->part)
        return;
    if (o->fd >= 0)
        close(o->fd);
    sp_sink_discard(o->part);
    o->parts[0] = NULL;
    free(o->part);
    o->part = NULL;
}

static const char *const *raw_part_files(const struct sp_sink *s)
{
    const struct raw *o = s->priv;
    return o->parts;
}

const struct sp_sink_backend sp_sink_backend_raw = {
    .priv_size = sizeof(struct raw),
    .open = raw_open,
    .write = raw_write,
    .close = raw_close,
    .abort = raw_abort,
    .part_files = raw_part_files,
};
