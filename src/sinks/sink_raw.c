/* springpend: raw frames, for piping into other tools: each image as
 * height rows of width RGBA8 pixels (4 bytes each, top row first), no
 * header, no padding. Path "-" is stdout; a device or FIFO is written
 * through; a file goes through a .part (outfile.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "sink_impl.h"

struct raw {
    struct sp_outfile out; /* the .part, or stdout / a device written through */
};

static int raw_open(struct sp_sink *s)
{
    struct raw *o = s->priv;
    return sp_outfile_open(&o->out, s->path, SP_OUTFILE_STREAM);
}

/* Writes all n bytes of buf, retrying after signals and short writes. */
static int write_all(struct sp_sink *s, const uint8_t *buf, size_t n)
{
    struct raw *o = s->priv;
    while (n > 0) {
        ssize_t k = write(o->out.fd, buf, n);
        if (k < 0 && errno == EINTR)
            continue;
        if (k < 0) {
            sp_log_error("%s: cannot write frame %ld: %s",
                         strcmp(s->path, "-") ? s->path : "stdout",
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
    return sp_outfile_commit(&o->out);
}

static void raw_abort(struct sp_sink *s)
{
    struct raw *o = s->priv;
    sp_outfile_discard(&o->out);
}

const struct sp_sink_backend sp_sink_backend_raw = {
    .priv_size = sizeof(struct raw),
    .open = raw_open,
    .write = raw_write,
    .close = raw_close,
    .abort = raw_abort,
};
