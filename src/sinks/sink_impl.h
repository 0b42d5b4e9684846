/* springpend: the backend side of sinks. sink.c picks a backend from the
 * path, validates what is common, creates folders, counts frames and owns
 * struct sp_sink; each backend (one file: sink_png.c, sink_video.c, ...)
 * fills a struct sp_sink_backend. A new format is a new file plus one line
 * in sink.c's table. */
#ifndef SPRINGPEND_SINK_IMPL_H
#define SPRINGPEND_SINK_IMPL_H

#include <stddef.h>

#include "springpend/outfile.h"
#include "springpend/sink.h"

struct sp_sink_backend {
    size_t priv_size;      /* bytes of zeroed state sink.c allocates */
    /* The images write takes (enum sp_image_format as bits: 1 << format;
     * 0 = RGBA only) and the one it takes best, with no conversion, unless
     * the desc keeps alpha (then RGBA). */
    unsigned formats;
    int best;

    /* Validates desc without touching the file system (so a refused sink
     * leaves no folder or file). May be NULL. SP_E_INPUT with a message. */
    int (*check)(const struct sp_sink_desc *desc);
    /* Starts writing; parent folders exist. On failure it must have released
     * everything it took and removed every file it created. */
    int (*open)(struct sp_sink *s);
    /* Writes one image of desc's size; s->frames images came before it. */
    int (*write)(struct sp_sink *s, const struct sp_image *img);
    /* Finishes and renames every .part into place. On failure it leaves the
     * rest to abort, which sink.c calls next. */
    int (*close)(struct sp_sink *s);
    /* Releases everything and removes every .part and every file it
     * created. Must work after a failed write or close. */
    void (*abort)(struct sp_sink *s);
};

struct sp_sink {
    const struct sp_sink_backend *backend;
    struct sp_sink_desc desc; /* desc.path points at path below; desc.preset
                                 is the caller's, read in check/open only */
    char *path;               /* owned copy of the target path */
    long frames;              /* images written so far */
    int failed;               /* a write failed: only abort remains */
    void *priv;               /* backend->priv_size bytes, owned by sink.c */
    struct sp_dirs dirs;      /* folders sink.c created for the output */
};

/* In springpend-av.so (sink_video.c, sink_gif.c), found by dlsym. */
extern const struct sp_sink_backend sp_sink_backend_mp4;
extern const struct sp_sink_backend sp_sink_backend_webm;
extern const struct sp_sink_backend sp_sink_backend_gif;
/* Built in. */
extern const struct sp_sink_backend sp_sink_backend_raw;
extern const struct sp_sink_backend sp_sink_backend_yuv;
extern const struct sp_sink_backend sp_sink_backend_png_sequence;
extern const struct sp_sink_backend sp_sink_backend_png_single;

/* Backends write every file through struct sp_outfile (outfile.h). */

#endif
