/* springpend: PNG files through libpng. */
#ifndef SPRINGPEND_PNG_IO_H
#define SPRINGPEND_PNG_IO_H

#include <stdio.h>
#include "springpend/image.h"

/* The zlib level sinks use unless told: chosen for speed. On 1080p rendered
 * frames level 1 writes in about 14 ms, level 6 in 24 ms for files 40%
 * smaller. */
#define SP_PNG_LEVEL_DEFAULT 1

/* One text chunk. key: 1..79 printable Latin-1 characters, no leading,
 * trailing or double spaces (e.g. "Software", "Comment"); text: UTF-8.
 * ASCII text is written as tEXt or zTXt, any other as iTXt (the PNG
 * specification's chunk for UTF-8; tEXt and zTXt are Latin-1). */
struct sp_png_text {
    const char *key;
    const char *text;
    int compressed; /* 1: deflated (zTXt, or a compressed iTXt), 0: not */
};

/* How to write. Use designated initializers; a zeroed struct writes
 * uncompressed (level 0) with no text. */
struct sp_png_write_opts {
    int level;                      /* zlib level 0..9, SP_PNG_LEVEL_DEFAULT */
    const struct sp_png_text *text; /* n_text chunks written before IDAT */
    int n_text;                     /* >= 0; text may be NULL when 0 */
    int opaque;                     /* 1: the image is opaque; write RGB
                                       (a quarter less to compress) */
    double dpi;                     /* > 0: a pHYs chunk says so (pixels per
                                       metre), so the image places at its
                                       physical size; 0 = none */
};

/* Writes img as an 8-bit RGBA (RGB if opts->opaque) PNG to an open stream
 * (left open, flushed).
 * `what` names the destination in messages. */
int sp_png_write_stream_opts(FILE *fp, const struct sp_image *img,
                             const struct sp_png_write_opts *opts,
                             const char *what);
/* Writes img to path whole or not at all (outfile.h): through a unique
 * .part renamed into place, or straight through a device, FIFO or stdout.
 * A failed write leaves nothing and removes nothing that was there. */
int sp_png_write_opts(const char *path, const struct sp_image *img,
                      const struct sp_png_write_opts *opts);
struct sp_outfile;
/* Writes img into f, opened by sp_outfile_open: f's descriptor is used up,
 * f stays open for sp_outfile_commit or sp_outfile_discard. */
int sp_png_write_outfile(struct sp_outfile *f, const struct sp_image *img,
                         const struct sp_png_write_opts *opts);

/* Shorthands with a level 0..9 and no text. */
int sp_png_write_stream(FILE *fp, const struct sp_image *img, int level,
                        const char *what);
int sp_png_write(const char *path, const struct sp_image *img, int level);

/* The most pixels sp_png_read decodes: 100 Mpx (400 MB as RGBA8; an 8K
 * still is 33 Mpx). A header asking for more is refused before anything
 * is allocated, so a tiny file declaring 100000x100000, or a decompression
 * bomb, costs nothing. */
#define SP_PNG_MAX_PIXELS 100000000L

/* What a PNG's header says. */
struct sp_png_info {
    int width, height; /* px */
    int bit_depth;     /* 1, 2, 4, 8 or 16 */
    int color_type;    /* PNG_COLOR_TYPE_* */
    int interlaced;    /* 1: Adam7 */
};

/* Reads the header (and the chunks before the image data) only. Returns 0
 * or SP_E_INPUT (logged: cannot open, not a regular file, not a PNG or
 * damaged: bad input, exit 2, with libpng's reason), or SP_E_NOMEM, unsaid:
 * out of memory is not the file's fault, and its caller says it once (compare
 * retries the image on one thread first). */
int sp_png_read_info(const char *path, struct sp_png_info *info);

/* Like sp_png_read_info, but only the width and height, and nothing
 * logged: for an estimate before the file is read in earnest (which then
 * says what is wrong with it). Only a regular file is opened (never
 * blocking on a FIFO). 0, or SP_E_INPUT for anything else. */
int sp_png_read_info_quiet(const char *path, struct sp_png_info *info);

/* SP_E_INPUT (logged) when info's size is beyond SP_PNG_MAX_PIXELS. */
int sp_png_check_size(const char *path, const struct sp_png_info *info);

/* Reads any PNG (palette, grey, grey+alpha, RGB, RGBA, 1 to 16 bits,
 * interlaced or not) into RGBA8 by value: 16-bit samples v become
 * round(v * 255 / 65535), so v * 257 reads as v; no gamma or colour
 * conversion. Stride 4*width, straight alpha; free with sp_image_free; img
 * is zeroed on failure. Refuses (SP_E_INPUT) what is not a regular file and
 * images beyond SP_PNG_MAX_PIXELS, and a damaged or truncated file, including
 * one missing IEND (infile.h: a missing file too). SP_E_NOMEM (unsaid, as
 * sp_png_read_info) when memory runs out, libpng's allocations included. */
int sp_png_read(const char *path, struct sp_image *img);

/* Finds the tEXt/zTXt/iTXt chunk `key` that comes before the image data
 * and copies its text into buf. Returns 1 when found, 0 when the PNG has
 * no such chunk, or SP_E_INPUT (logged) when the file cannot be read as a
 * PNG, holds the chunk twice, or its text does not fit in size - 1 bytes;
 * SP_E_NOMEM (logged) when memory runs out.
 * Bounded: a chunk inflating beyond 256 KiB, and the chunks after the
 * 32nd, are dropped with libpng's reason (8 MiB of text at most, however
 * the file is made); the other readers skip text chunks unread. */
int sp_png_read_text(const char *path, const char *key, char *buf, size_t size);

#endif
