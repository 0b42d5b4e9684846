/* springpend: RGBA8 images in memory. */
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image.h"

int sp_image_alloc(struct sp_image *img, int width, int height)
{
    memset(img, 0, sizeof(*img));
    img->pixels = calloc((size_t)width * height, 4);
    if (!img->pixels) {
        sp_log_error("out of memory for a %dx%d image", width, height);
        return SP_E_NOMEM;
    }
    img->width = width;
    img->height = height;
    img->stride = 4 * width;
    return 0;
}

void sp_image_free(struct sp_image *img)
{
    free(img->pixels);
    memset(img, 0, sizeof(*img));
}
