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
    int fd;                  /* 1 for stdout, else owned */
    struct sp_sink_part part; /* none for stdout or once renamed */
};

static int raw_open(struct sp_sink *s)
{
    struct raw *o = s->priv;
    o->fd = 1;
    if (!strcmp(s->path, "-"))
        return 0;
    int err = sp_sink_part_begin(&o->part, s->path);
    if (err)
        return err;
    o->fd = open(o->part.path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
    o->part.created = o->fd >= 0;
    if (o->fd < 0) {
        sp_log_error("%s: cannot create %s: %s", s->path, o->part.path,
                     strerror(errno));
        sp_sink_part_discard(&o->part);
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
                         o->fd == 1 && !o->part.url ? "stdout" : s->path,
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
    if (!o->part.url)
        return 0; /* stdout: the caller owns it */
    int fd = o->fd;
    o->fd = -1;
    if (close(fd) != 0) {
        sp_log_error("%s: cannot finish %s: %s", s->path, o->part.path,
                     strerror(errno));
        return SP_E_IO;
    }
    return sp_sink_part_commit(&o->part, s->path);
}

static void raw_abort(struct sp_sink *s)
{
    struct raw *o = s->priv;
    if (!o->part.url)
        return;
    if (o->fd >= 0)
        close(o->fd);
    sp_sink_part_discard(&o->part);
}

static const char *const *raw_part_files(const struct sp_sink *s)
{
    const struct raw *o = s->priv;
    return o->part.list;
}

const struct sp_sink_backend sp_sink_backend_raw = {
    .priv_size = sizeof(struct raw),
    .open = raw_open,
    .write = raw_write,
    .close = raw_close,
    .abort = raw_abort,
    .part_files = raw_part_files,
};
