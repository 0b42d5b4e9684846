/* springpend: raw frames, for piping into other tools: each image as
 * height rows of width RGBA8 pixels (4 bytes each, top row first), or
 * (yuv420p) as I420 planes: Y, then Cb, then Cr, each top row first; no
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
    uint8_t *planes;       /* yuv420p: one frame as I420, owned */
};

static int raw_open(struct sp_sink *s)
{
    struct raw *o = s->priv;
    return sp_outfile_open(&o->out, s->path, SP_OUTFILE_STREAM);
}

/* Writes all n bytes of buf (sp_outfile_write_all: a FIFO whose reader
 * does not read waits with the stop flag in view). */
static int write_all(struct sp_sink *s, const uint8_t *buf, size_t n)
{
    struct raw *o = s->priv;
    if (sp_outfile_write_all(o->out.fd, buf, n) == 0)
        return 0;
    if (sp_outfile_write_was_stopped())
        return SP_E_INTERRUPTED; /* a reader that did not read: the pipeline says it */
    sp_log_error("%s: cannot write frame %ld: %s", strcmp(s->path, "-") ? s->path : "stdout",
                 s->frames, errno == EPIPE ? "the reader closed the pipe" : strerror(errno));
    return SP_E_IO;
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

/* A SP_IMAGE_YUV420 image's Cb and Cr rows (side by side in memory,
 * image.h) gathered into I420's planes, and the frame written at once. */
static int yuv_write(struct sp_sink *s, const struct sp_image *img)
{
    struct raw *o = s->priv;
    const size_t w = (size_t)img->width, h = (size_t)img->height, cw = w / 2, ch = h / 2;
    if (!o->planes && !(o->planes = malloc(w * h * 3 / 2))) {
        sp_log_error("%s: out of memory for a %zux%zu frame", s->path, w, h);
        return SP_E_NOMEM;
    }
    uint8_t *data[3];
    int linesize[3];
    sp_image_planes(img, data, linesize);
    for (size_t y = 0; y < h; y++)
        memcpy(o->planes + y * w, data[0] + y * (size_t)linesize[0], w);
    for (int p = 1; p < 3; p++)
        for (size_t y = 0; y < ch; y++)
            memcpy(o->planes + w * h + (size_t)(p - 1) * cw * ch + y * cw,
                   data[p] + y * (size_t)linesize[p], cw);
    return write_all(s, o->planes, w * h * 3 / 2);
}

static int raw_close(struct sp_sink *s)
{
    struct raw *o = s->priv;
    free(o->planes);
    o->planes = NULL;
    return sp_outfile_commit(&o->out);
}

static void raw_abort(struct sp_sink *s)
{
    struct raw *o = s->priv;
    free(o->planes);
    o->planes = NULL;
    sp_outfile_discard(&o->out);
}

/* The size must be even for 4:2:0. */
static int yuv_check(const struct sp_sink_desc *d)
{
    if (d->width % 2 || d->height % 2) {
        sp_log_error("%s: YUV 4:2:0 frames need an even width and height, got %dx%d (try "
                     "%dx%d)", d->path, d->width, d->height, d->width & ~1, d->height & ~1);
        return SP_E_INPUT;
    }
    if (d->alpha) {
        sp_log_error("%s: YUV 4:2:0 frames have no alpha; use --format raw for a transparent "
                     "background", d->path);
        return SP_E_INPUT;
    }
    return 0;
}

const struct sp_sink_backend sp_sink_backend_raw = {
    .priv_size = sizeof(struct raw),
    .open = raw_open,
    .write = raw_write,
    .close = raw_close,
    .abort = raw_abort,
};

const struct sp_sink_backend sp_sink_backend_yuv = {
    .priv_size = sizeof(struct raw),
    .formats = 1u << SP_IMAGE_YUV420,
    .best = SP_IMAGE_YUV420,
    .check = yuv_check,
    .open = raw_open,
    .write = yuv_write,
    .close = raw_close,
    .abort = raw_abort,
};
