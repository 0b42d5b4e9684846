/* springpend: images in memory (image.h). */
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image.h"

long sp_image_size(int format, int width, int height)
{
    return format == SP_IMAGE_YUV420 ? (long)((width + 7) & ~7) * height * 3 / 2
                                     : (long)width * height * 4;
}

int sp_image_alloc_unsaid(struct sp_image *img, int width, int height)
{
    memset(img, 0, sizeof(*img));
    img->pixels = calloc((size_t)width * height, 4);
    if (!img->pixels)
        return SP_E_NOMEM;
    img->width = width;
    img->height = height;
    img->stride = 4 * width;
    return 0;
}

int sp_image_alloc(struct sp_image *img, int width, int height)
{
    int err = sp_image_alloc_unsaid(img, width, height);
    if (err)
        sp_log_error("out of memory for a %dx%d image", width, height);
    return err;
}

int sp_image_alloc_yuv420(struct sp_image *img, int width, int height)
{
    memset(img, 0, sizeof(*img));
    if (width <= 0 || height <= 0 || width % 2 || height % 2) {
        sp_log_error("a YUV 4:2:0 image needs an even width and height, got %dx%d",
                     width, height);
        return SP_E_INPUT;
    }
    const int stride = (width + 7) & ~7;
    const size_t luma = (size_t)stride * (size_t)height;
    img->pixels = malloc(luma * 3 / 2);
    if (!img->pixels) {
        sp_log_error("out of memory for a %dx%d image", width, height);
        return SP_E_NOMEM;
    }
    memset(img->pixels, 16, luma);
    memset(img->pixels + luma, 128, luma / 2);
    img->width = width;
    img->height = height;
    img->stride = stride;
    img->format = SP_IMAGE_YUV420;
    return 0;
}

void sp_image_planes(const struct sp_image *img, uint8_t *data[3], int linesize[3])
{
    data[0] = img->pixels;
    data[1] = img->pixels + (size_t)img->stride * (size_t)img->height;
    data[2] = data[1] + img->width / 2;
    linesize[0] = linesize[1] = linesize[2] = img->stride;
}

void sp_image_free(struct sp_image *img)
{
    free(img->pixels);
    memset(img, 0, sizeof(*img));
}
