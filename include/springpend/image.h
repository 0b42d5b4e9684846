/* springpend: an RGBA8 image in memory, the currency between render and sink. */
#ifndef SPRINGPEND_IMAGE_H
#define SPRINGPEND_IMAGE_H

#include <stdint.h>

struct sp_image {
    uint8_t *pixels; /* RGBA8, top row first, straight (non-premultiplied) alpha */
    int width;       /* px */
    int height;      /* px */
    int stride;      /* bytes from one row to the next, >= 4 * width */
};

/* Allocates a zeroed width x height image with stride 4*width. */
int sp_image_alloc(struct sp_image *img, int width, int height);
/* Frees pixels and zeroes the struct. Safe on a zeroed struct. */
void sp_image_free(struct sp_image *img);

#endif
