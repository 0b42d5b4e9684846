/* springpend: pixelmatch's perceptual rule (image_compare.h,
 * SP_COMPARE_PIXELMATCH), as mapbox/pixelmatch defines it
 * (https://github.com/mapbox/pixelmatch, index.js, ISC licence; written here
 * from its description, checked against the npm package by
 * tests/e2e/test_pixelmatch.py):
 *
 *   - colour distance: the squared YIQ difference of Kotsarenko and Ramos,
 *     "Measuring perceived color difference using YIQ NTSC transmission color
 *     space in mobile applications" (2010): 0.5053 y² + 0.299 i² + 0.1957 q²,
 *     pixels with alpha < 255 blended over white first; a pixel differs when
 *     the distance exceeds 35215 · threshold² (35215: the largest distance);
 *   - anti-aliasing: a differing pixel is not counted when, in either image,
 *     it looks like anti-aliasing (V. Vysniauskas, "Anti-aliased Pixel and
 *     Intensity Slope Detector", 2009): among its 8 neighbours at most 2
 *     (counting the image edge as one) have its brightness, some are darker
 *     and some brighter, and the darkest or the brightest neighbour has 3 or
 *     more neighbours of exactly its colour in both images (a flat area on
 *     one side of an edge). */
#include <stdint.h>
#include <string.h>

#include "springpend/image_compare.h"

static const uint8_t *px(const struct sp_image *img, int x, int y)
{
    return img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
}

/* One colour channel blended over white by alpha a (0..1). */
static double over_white(double c, double a)
{
    return 255 + (c - 255) * a;
}

/* The pixel's RGB after blending over white (when alpha < 255). */
static void blended(const uint8_t *p, double rgb[3])
{
    double a = p[3] / 255.0;
    for (int c = 0; c < 3; c++)
        rgb[c] = p[3] < 255 ? over_white(p[c], a) : p[c];
}

static double yiq_y(const double c[3])
{
    return c[0] * 0.29889531 + c[1] * 0.58662247 + c[2] * 0.11448223;
}

static double yiq_i(const double c[3])
{
    return c[0] * 0.59597799 - c[1] * 0.27417610 - c[2] * 0.32180189;
}

static double yiq_q(const double c[3])
{
    return c[0] * 0.21147017 - c[1] * 0.52261711 + c[2] * 0.31114694;
}

/* The squared YIQ distance of p and q, or (y_only) their brightness
 * difference y(p) - y(q); 0 for equal RGBA. */
static double color_delta(const uint8_t *p, const uint8_t *q, int y_only)
{
    double a[3], b[3];
    if (!memcmp(p, q, 4))
        return 0;
    blended(p, a);
    blended(q, b);
    double y = yiq_y(a) - yiq_y(b);
    if (y_only)
        return y;
    double i = yiq_i(a) - yiq_i(b), qq = yiq_q(a) - yiq_q(b);
    return 0.5053 * y * y + 0.299 * i * i + 0.1957 * qq * qq;
}

/* 1 when (x1, y1) has 3 or more neighbours of exactly its RGBA in img (the
 * image's edge counts as one). */
static int many_siblings(const struct sp_image *img, int x1, int y1)
{
    int x0 = x1 > 0 ? x1 - 1 : 0, y0 = y1 > 0 ? y1 - 1 : 0;
    int x2 = x1 + 1 < img->width ? x1 + 1 : img->width - 1;
    int y2 = y1 + 1 < img->height ? y1 + 1 : img->height - 1;
    int same = x1 == x0 || x1 == x2 || y1 == y0 || y1 == y2;
    const uint8_t *c = px(img, x1, y1);
    for (int x = x0; x <= x2; x++)
        for (int y = y0; y <= y2; y++) {
            if (x == x1 && y == y1)
                continue;
            same += !memcmp(c, px(img, x, y), 4);
            if (same > 2)
                return 1;
        }
    return 0;
}

/* 1 when (x1, y1) of img looks like anti-aliasing (see the top); other is
 * the other image, where the flat side must be flat too. Neighbours are
 * visited column by column, as pixelmatch does: ties for the darkest and
 * brightest go to the first found. */
static int antialiased(const struct sp_image *img, int x1, int y1, const struct sp_image *other)
{
    int x0 = x1 > 0 ? x1 - 1 : 0, y0 = y1 > 0 ? y1 - 1 : 0;
    int x2 = x1 + 1 < img->width ? x1 + 1 : img->width - 1;
    int y2 = y1 + 1 < img->height ? y1 + 1 : img->height - 1;
    int zeroes = x1 == x0 || x1 == x2 || y1 == y0 || y1 == y2;
    double min = 0, max = 0;
    int min_x = 0, min_y = 0, max_x = 0, max_y = 0;
    const uint8_t *c = px(img, x1, y1);
    for (int x = x0; x <= x2; x++)
        for (int y = y0; y <= y2; y++) {
            if (x == x1 && y == y1)
                continue;
            double d = color_delta(c, px(img, x, y), 1);
            if (d == 0) {
                if (++zeroes > 2)
                    return 0;
            } else if (d < min) {
                min = d, min_x = x, min_y = y;
            } else if (d > max) {
                max = d, max_x = x, max_y = y;
            }
        }
    if (min == 0 || max == 0)
        return 0;
    return (many_siblings(img, min_x, min_y) && many_siblings(other, min_x, min_y)) ||
           (many_siblings(img, max_x, max_y) && many_siblings(other, max_x, max_y));
}

long sp_compare_pixelmatch(const struct sp_image *a, const struct sp_image *b, double threshold,
                           int include_aa, uint8_t *marks)
{
    const double max_delta = 35215 * threshold * threshold;
    long differing = 0;
    for (int y = 0; y < a->height; y++)
        for (int x = 0; x < a->width; x++) {
            uint8_t m = 0;
            if (color_delta(px(a, x, y), px(b, x, y), 0) > max_delta) {
                if (!include_aa && (antialiased(a, x, y, b) || antialiased(b, x, y, a)))
                    m = 1;
                else
                    m = 2, differing++;
            }
            if (marks)
                marks[(size_t)y * a->width + x] = m;
        }
    return differing;
}
