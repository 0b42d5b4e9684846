/* springpend: an image in memory, the currency between render and sink:
 * RGBA8, or (for video encoders) BT.709 limited-range YUV 4:2:0 planes. */
#ifndef SPRINGPEND_IMAGE_H
#define SPRINGPEND_IMAGE_H

#include <stdint.h>

enum sp_image_format {
    /* RGBA8, top row first, straight (non-premultiplied) alpha; stride >=
     * 4 * width. */
    SP_IMAGE_RGBA = 0,
    /* Y'CbCr 4:2:0, 8 bits, BT.709 matrix, limited range (Y 16..235, Cb and
     * Cr 16..240), chroma sited left (co-sited with the even luma columns,
     * between two luma rows: MPEG-2 and H.264's default). One buffer of
     * 1.5 bytes a pixel, width and height even, stride = width rounded up
     * to a multiple of 8 (the GL pass writes 8 bytes at a time): `height`
     * rows of Y, then height / 2 rows each holding width / 2 Cb samples
     * followed by width / 2 Cr samples (sp_image_planes). */
    SP_IMAGE_YUV420 = 1,
};

struct sp_image {
    uint8_t *pixels; /* see format; top row first */
    int width;       /* px */
    int height;      /* px */
    int stride;      /* bytes from one row to the next */
    int format;      /* enum sp_image_format; 0 = RGBA */
};

/* Allocates a zeroed width x height RGBA image with stride 4*width. */
int sp_image_alloc(struct sp_image *img, int width, int height);
/* The same, saying nothing when memory runs out (SP_E_NOMEM): for readers
 * whose caller says it once (compare retries on one thread first). */
int sp_image_alloc_unsaid(struct sp_image *img, int width, int height);
/* Allocates a width x height SP_IMAGE_YUV420 image (width and height even),
 * black (Y 16, Cb = Cr = 128). 0, SP_E_INPUT (odd size) or SP_E_NOMEM. */
int sp_image_alloc_yuv420(struct sp_image *img, int width, int height);
/* The bytes of an image of `format`, width x height (4 a pixel, or 1.5 and
 * the rows' padding). */
long sp_image_size(int format, int width, int height);
/* A SP_IMAGE_YUV420 image's Y, Cb and Cr planes and their strides, in the
 * order libavcodec's AVFrame takes them. */
void sp_image_planes(const struct sp_image *img, uint8_t *data[3], int linesize[3]);
/* Frees pixels and zeroes the struct. Safe on a zeroed struct. */
void sp_image_free(struct sp_image *img);

#endif
