/* springpend: where frames go. The kind is `format` if given, else picked
 * from the path's extension:
 *   mp4   *.mp4   H.264 (libx264) yuv420p video, +faststart
 *   webm  *.webm  VP9 (libvpx) video, yuv420p, or yuva420p with `alpha`
 *   gif   *.gif   GIF with a palette built for the content (libavfilter's
 *                 palettegen/paletteuse; holds the frames until the end)
 *   png   *%d*.png (printf pattern, e.g. frames/%05d.png)  one PNG per frame
 *         *.png   a single PNG (exactly one frame may be written)
 *   raw   RGBA8 frames, top row first, no header; path "-" is stdout
 *   yuv420p  *.yuv  raw Y'CbCr 4:2:0 frames (BT.709, limited range, chroma
 *         sited left): each the Y plane, then Cb, then Cr (I420, what
 *         ffmpeg reads as -f rawvideo -pix_fmt yuv420p); path "-" is stdout
 * Files are written through struct sp_outfile (outfile.h): a unique
 * NAME.XXXXXX.part renamed into place, a video on sp_sink_close, each PNG of
 * a sequence as soon as it is complete; raw frames and a single PNG may be
 * written through a device, FIFO or stdout, the others refuse one. A failed
 * or aborted run leaves nothing at the target path (an aborted sequence
 * removes the frames this run wrote, no other) and removes the folders it
 * created when they are empty. Knows nothing of GL. */
#ifndef SPRINGPEND_SINK_H
#define SPRINGPEND_SINK_H

#include "springpend/image.h"
#include "springpend/png_io.h"

struct sp_outfile;
struct sp_sink_desc {
    const char *path;   /* target path (pattern for sequences, "-" = stdout
                           for raw) */
    const char *format; /* "mp4", "webm", "gif", "png", "raw", "yuv420p"; NULL = from
                           the path's extension */
    int width, height;  /* px, every written image must match */
    double fps;         /* frames per second of video */
    long first_frame;   /* number of the first image (PNG sequence names) */
    struct sp_outfile *partner; /* single PNG: a file written, not yet
                           committed, put in place with the image under its
                           folder's lock (a still's --state), or discarded
                           with it; NULL = none */
    int whole;          /* PNG sequence: 1 = the whole video (no --frames or
                           --shard), so the pattern's files numbered past its
                           last frame, an earlier and longer run's, are
                           removed at close (regular files only; said) */
    int alpha;          /* 1: keep the images' alpha (webm, png, raw) */
    int crf;            /* quality: 0 = the format's default */
    const char *preset; /* x264 preset name (VP9: mapped); NULL = default */
    int png_level;      /* level 1..9 for PNGs; 0 = SP_PNG_LEVEL_DEFAULT */
    double dpi;         /* PNG: > 0 is recorded in a pHYs chunk (a figure of
                           physical size); 0 = none */
    const struct sp_png_text *text; /* PNG sinks: text chunks for every image,
                                       read at each write (the caller may
                                       change them in between); borrowed
                                       until close; NULL = none */
    int n_text;
};

struct sp_sink;

/* The encoders' settings where the scene leaves them automatic (video.crf
 * = 0, preset = auto): sink_video.c encodes with these, and side by side
 * compares the values the encoder gets (cli_render.c). */
#define SP_SINK_CRF_H264 23
#define SP_SINK_CRF_VP9 32
#define SP_SINK_PRESET_DEFAULT "superfast"

/* Returns SP_E_INPUT (with a message) for an unknown kind or bad desc,
 * SP_E_CODEC when this FFmpeg lacks the encoder, SP_E_IO naming the path
 * and the cause when it cannot be created. */
int sp_sink_open(struct sp_sink **out, const struct sp_sink_desc *desc);
/* The image format (image.h) s takes best: SP_IMAGE_YUV420 for video
 * without alpha (mp4, webm: no conversion on the CPU) and raw yuv420p (the
 * only one it takes), else SP_IMAGE_RGBA. The others take RGBA too. */
int sp_sink_image_format(const struct sp_sink *s);
/* Writes one image of desc's size, in RGBA or the format
 * sp_sink_image_format names; not thread-safe (one writer at a time). */
int sp_sink_write(struct sp_sink *s, const struct sp_image *img);
/* Flushes, finishes and renames into place; frees and NULLs *s. On failure
 * nothing is left at the target path. */
int sp_sink_close(struct sp_sink **s);
/* Removes every file the sink wrote; frees and NULLs *s. Safe on NULL. */
void sp_sink_abort(struct sp_sink **s);
#endif
