/* springpend: the public sink API. Picks a backend from the path, checks
 * what every backend needs, creates folders and keeps the frame count.
 * The backends live in sink_png.c and sink_video.c (see sink_impl.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "springpend/common.h"
#include "av_module.h"
#include "sink_impl.h"

/* The kind: `format` if given, else the file name's extension (any case).
 * Sets *b, or returns SP_E_INPUT for an unknown kind (not logged) or
 * SP_E_CODEC (logged) if the FFmpeg module would not load. */
static int pick_backend(const char *path, const char *format,
                        const struct sp_sink_backend **b)
{
    static const char *const av_kinds[][2] = {
        {"mp4", "sp_sink_backend_mp4"},
        {"webm", "sp_sink_backend_webm"},
        {"gif", "sp_sink_backend_gif"},
    };
    const char *base = strrchr(path, '/');
    base = base ? base + 1 : path;
    const char *dot = strrchr(base, '.');
    const char *kind = format ? format : dot && dot != base ? dot + 1 : "";
    *b = NULL;
    for (size_t i = 0; i < sizeof(av_kinds) / sizeof(av_kinds[0]); i++)
        if (!strcasecmp(kind, av_kinds[i][0]))
            return (*b = sp_av_module_symbol(av_kinds[i][1])) ? 0 : sp_av_module_error();
    if (!strcasecmp(kind, "raw") || !strcasecmp(kind, "rgba"))
        *b = &sp_sink_backend_raw;
    else if (!strcasecmp(kind, "yuv420p") || !strcasecmp(kind, "yuv"))
        *b = &sp_sink_backend_yuv;
    else if (!strcasecmp(kind, "png"))
        *b = strchr(path, '%') ? &sp_sink_backend_png_sequence
                               : &sp_sink_backend_png_single;
    return *b ? 0 : SP_E_INPUT;
}

/* Frees s and what sink.c allocated; the backend has released its part. */
static void sink_free(struct sp_sink *s)
{
    if (!s)
        return;
    sp_dirs_keep(&s->dirs);
    free(s->priv);
    free(s->path);
    free(s);
}

int sp_sink_open(struct sp_sink **out, const struct sp_sink_desc *desc)
{
    struct sp_sink *s = NULL;
    int err;
    *out = NULL;

    if (!desc->path || !desc->path[0]) {
        sp_log_error("no output path given");
        return SP_E_INPUT;
    }
    const struct sp_sink_backend *backend;
    err = pick_backend(desc->path, desc->format, &backend);
    if (err == SP_E_CODEC)
        return err;
    if (!backend && desc->format) {
        sp_log_error("unknown format \"%s\"; use mp4, webm, gif, png, raw or yuv420p",
                     desc->format);
        return SP_E_INPUT;
    }
    if (!backend) {
        sp_log_error("cannot tell what to write from the name %s: use "
                     "NAME.mp4 (H.264 video), NAME.webm (VP9 video), NAME.gif, "
                     "NAME.png (one image), a pattern like frames/%%05d.png "
                     "(one PNG per frame), NAME.yuv (raw YUV 4:2:0 frames), or --format raw",
                     desc->path);
        return SP_E_INPUT;
    }
    if (!strcmp(desc->path, "-") && backend != &sp_sink_backend_raw &&
        backend != &sp_sink_backend_yuv && backend != &sp_sink_backend_png_single) {
        sp_log_error("only raw frames (--format raw or yuv420p) or a still can go to "
                     "stdout; give a file name for other formats");
        return SP_E_INPUT;
    }
    if (desc->width <= 0 || desc->height <= 0) {
        sp_log_error("%s: image size %dx%d is not positive", desc->path,
                     desc->width, desc->height);
        return SP_E_INPUT;
    }
    if (backend->check && (err = backend->check(desc)) != 0)
        return err;

    s = calloc(1, sizeof(*s));
    if (!s || !(s->path = strdup(desc->path)) ||
        (backend->priv_size && !(s->priv = calloc(1, backend->priv_size)))) {
        sp_log_error("out of memory");
        err = SP_E_NOMEM;
        goto fail;
    }
    s->backend = backend;
    s->desc = *desc;
    s->desc.path = s->path;
    if ((!sp_outfile_is_stream(s->path) && (err = sp_dirs_make(s->path, &s->dirs)) != 0) ||
        (err = backend->open(s)) != 0) {
        sp_dirs_remove_empty(&s->dirs);
        goto fail;
    }
    /* the caller's strings, only valid until here */
    s->desc.preset = s->desc.format = NULL;
    *out = s;
    return 0;
fail:
    sink_free(s);
    return err;
}

int sp_sink_image_format(const struct sp_sink *s)
{
    return s->desc.alpha ? SP_IMAGE_RGBA : s->backend->best;
}

int sp_sink_write(struct sp_sink *s, const struct sp_image *img)
{
    if (s->failed) {
        sp_log_error("%s: cannot write after a failed write", s->path);
        return SP_E_IO;
    }
    const unsigned formats = s->backend->formats ? s->backend->formats : 1u << SP_IMAGE_RGBA;
    /* YUV has no alpha plane to keep */
    if (img->format < 0 || img->format > SP_IMAGE_YUV420 || !(formats & (1u << img->format)) ||
        (img->format != SP_IMAGE_RGBA && s->desc.alpha)) {
        sp_log_error("%s: this output takes no %s images", s->path,
                     img->format == SP_IMAGE_YUV420 ? "YUV 4:2:0" : "RGBA");
        return SP_E_INPUT;
    }
    if (!img->pixels || img->width != s->desc.width ||
        img->height != s->desc.height ||
        img->stride < (img->format == SP_IMAGE_YUV420 ? img->width : 4 * img->width)) {
        sp_log_error("%s: got a %dx%d image (stride %d) for a %dx%d output",
                     s->path, img->width, img->height, img->stride,
                     s->desc.width, s->desc.height);
        return SP_E_INPUT;
    }
    int err = s->backend->write(s, img);
    if (err) {
        /* SP_E_INPUT: the image was refused and nothing changed. */
        if (err != SP_E_INPUT)
            s->failed = 1;
        return err;
    }
    s->frames++;
    return 0;
}

int sp_sink_close(struct sp_sink **sp)
{
    struct sp_sink *s = *sp;
    int err;
    if (!s)
        return 0;
    *sp = NULL;

    if (s->failed) {
        err = SP_E_IO; /* logged by the failed write */
    } else if (s->frames == 0) {
        sp_log_error("%s: no image was written", s->path);
        err = SP_E_INPUT;
    } else {
        err = s->backend->close(s);
    }
    if (err) {
        s->backend->abort(s);
        sp_dirs_remove_empty(&s->dirs);
    }
    sink_free(s);
    return err;
}

void sp_sink_abort(struct sp_sink **sp)
{
    struct sp_sink *s = *sp;
    if (!s)
        return;
    *sp = NULL;
    s->backend->abort(s);
    sp_dirs_remove_empty(&s->dirs);
    sink_free(s);
}
