/* springpend: where frames go. The kind is picked from the path:
 *   *.mp4            H.264 (libx264) yuv420p video through libavformat
 *   *%d*.png (printf pattern, e.g. frames/%05d.png)  one PNG per frame
 *   *.png            a single PNG (exactly one frame may be written)
 * Files are written as NAME.part and renamed on sp_sink_close, so a failed
 * or aborted run leaves nothing at the target path. Folders are created.
 * Knows nothing of GL. */
#ifndef SPRINGPEND_SINK_H
#define SPRINGPEND_SINK_H

#include "springpend/image.h"
#include "springpend/png_io.h"

struct sp_sink_desc {
    const char *path; /* target path (pattern for sequences) */
    int width, height; /* px, every written image must match */
    double fps;        /* frames per second of video */
    int crf;           /* H.264 constant rate factor; 0 = default */
    const char *preset; /* x264 preset; NULL = default */
    const struct sp_png_text *text; /* PNG sinks: text chunks for every image,
                                       read at each write (the caller may
                                       change them in between); borrowed
                                       until close; NULL = none */
    int n_text;
};

struct sp_sink;

/* Returns SP_E_INPUT (with a message) for an unknown extension. */
int sp_sink_open(struct sp_sink **out, const struct sp_sink_desc *desc);
int sp_sink_write(struct sp_sink *s, const struct sp_image *img);
/* Flushes, finishes and renames into place; frees and NULLs *s. */
int sp_sink_close(struct sp_sink **s);
/* Removes every partial file; frees and NULLs *s. Safe on NULL. */
void sp_sink_abort(struct sp_sink **s);

#endif
