/* springpend: video_read.h's functions for the executable. The decoder
 * itself (video_read.c) lives in springpend-av.so with the rest of FFmpeg's
 * users (av_module.h); these forward to it, loading it on first use. */
#include <stddef.h>

#include "springpend/common.h"
#include "springpend/video_read.h"
#include "sinks/av_module.h"

int sp_video_reader_open(struct sp_video_reader **out, const char *path)
{
    int (*open_fn)(struct sp_video_reader **, const char *);
    *(void **)&open_fn = sp_av_module_symbol("sp_video_reader_open");
    if (!open_fn) {
        *out = NULL;
        return sp_av_module_error();
    }
    return open_fn(out, path);
}

int sp_video_reader_read(struct sp_video_reader *r, struct sp_image *img, double *t)
{
    int (*read_fn)(struct sp_video_reader *, struct sp_image *, double *);
    *(void **)&read_fn = sp_av_module_symbol("sp_video_reader_read");
    return read_fn ? read_fn(r, img, t) : sp_av_module_error();
}

int sp_video_decodes_alone(const char *path, const volatile sig_atomic_t *cancel)
{
    int (*fn)(const char *, const volatile sig_atomic_t *);
    *(void **)&fn = sp_av_module_symbol("sp_video_decodes_alone");
    return fn ? fn(path, cancel) : sp_av_module_error();
}

int sp_video_demuxes_whole(const char *path, char *why, size_t size)
{
    int (*fn)(const char *, char *, size_t);
    *(void **)&fn = sp_av_module_symbol("sp_video_demuxes_whole");
    return fn ? fn(path, why, size) : sp_av_module_error();
}

void sp_video_reader_destroy(struct sp_video_reader **r)
{
    if (!*r)
        return; /* made by nothing: the module need not load */
    void (*destroy_fn)(struct sp_video_reader **);
    *(void **)&destroy_fn = sp_av_module_symbol("sp_video_reader_destroy");
    if (destroy_fn)
        destroy_fn(r);
}

void sp_video_hold_errors(char *buf, size_t size)
{
    void (*fn)(char *, size_t);
    *(void **)&fn = sp_av_module_symbol("sp_video_hold_errors");
    if (fn)
        fn(buf, size);
}

int sp_video_read_text(const char *path, const char *key, char *buf, size_t size)
{
    int (*fn)(const char *, const char *, char *, size_t);
    *(void **)&fn = sp_av_module_symbol("sp_video_read_text");
    return fn ? fn(path, key, buf, size) : sp_av_module_error();
}

int sp_video_frame_size(const char *path, int *width, int *height, int *alpha)
{
    int (*fn)(const char *, int *, int *, int *);
    *(void **)&fn = sp_av_module_symbol("sp_video_frame_size");
    *width = *height = *alpha = 0;
    return fn ? fn(path, width, height, alpha) : sp_av_module_error();
}
