/* springpend: image comparison for snapshot tests (see image_compare.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image_compare.h"

/* The rule with defaults patched in. */
static void resolve(const struct sp_compare_opts *o, long pixels, struct sp_compare_result *res)
{
    res->max_diff = o->max_diff == SP_COMPARE_NONE ? 0
                    : o->max_diff > 0             ? o->max_diff
                                                  : SP_COMPARE_MAX_DIFF_DEFAULT;
    if (o->max_pixels == SP_COMPARE_NONE)
        res->allowed = 0;
    else if (o->max_pixels > 0)
        res->allowed = o->max_pixels;
    else
        res->allowed = (long)floor(
            (o->max_fraction > 0 ? o->max_fraction : SP_COMPARE_MAX_FRACTION_DEFAULT) * pixels);
    res->tol = o->tol == SP_COMPARE_NONE ? 0 : o->tol > 0 ? o->tol : SP_COMPARE_TOL_DEFAULT;
}

/* Paints one diff pixel: grey from the expected pixel's luma, magenta
 * where it differs beyond max_diff, blue where it changed within it. */
static void paint(uint8_t *d, const uint8_t *e, int level)
{
    int luma = (77 * e[0] + 150 * e[1] + 29 * e[2]) >> 8;
    int grey = 80 + luma / 2; /* 80..207: faded, still legible */
    d[0] = d[1] = d[2] = (uint8_t)grey;
    d[3] = 255;
    if (level == 2) {
        d[0] = 255, d[1] = 0, d[2] = 255;
    } else if (level == 1) {
        d[0] = 40, d[1] = 110, d[2] = 210; /* a quieter blue */
    }
}

int sp_compare_images(const struct sp_image *expected, const struct sp_image *actual,
                      const struct sp_compare_opts *opts, struct sp_compare_result *res,
                      struct sp_image *diff)
{
    const struct sp_image *e = expected, *a = actual;
    double sum_rgb = 0, sum_a = 0; /* squared level differences */
    int opaque = 1;

    memset(res, 0, sizeof(*res));
    if (diff)
        memset(diff, 0, sizeof(*diff));
    if (e->width != a->width || e->height != a->height) {
        sp_log_error("cannot compare a %dx%d image with a %dx%d one", e->width, e->height,
                     a->width, a->height);
        return SP_E_INPUT;
    }
    if (diff) {
        int err = sp_image_alloc(diff, e->width, e->height);
        if (err)
            return err;
    }
    res->pixels = (long)e->width * e->height;
    resolve(opts, res->pixels, res);
    res->bbox[0] = res->bbox[1] = res->bbox[2] = res->bbox[3] = -1;

    for (int y = 0; y < e->height; y++) {
        const uint8_t *p = e->pixels + (size_t)y * e->stride;
        const uint8_t *q = a->pixels + (size_t)y * a->stride;
        for (int x = 0; x < e->width; x++, p += 4, q += 4) {
            int m = 0;
            for (int c = 0; c < 4; c++) {
                int d = abs(p[c] - q[c]);
                m = d > m ? d : m;
                if (c < 3)
                    sum_rgb += (double)d * d;
                else
                    sum_a += (double)d * d;
            }
            opaque &= p[3] == 255 && q[3] == 255;
            if (m > res->max_channel_diff)
                res->max_channel_diff = m;
            int level = m > res->max_diff ? 2 : m > 0;
            res->changed += level > 0;
            if (level == 2) {
                if (!res->differing++) {
                    res->bbox[0] = res->bbox[2] = x;
                    res->bbox[1] = res->bbox[3] = y;
                }
                res->bbox[0] = x < res->bbox[0] ? x : res->bbox[0];
                res->bbox[2] = x > res->bbox[2] ? x : res->bbox[2];
                res->bbox[3] = y; /* rows are visited in order */
            }
            if (diff)
                paint(diff->pixels + (size_t)y * diff->stride + 4 * (size_t)x, p, level);
        }
    }
    /* matplotlib drops alpha only when both images are fully opaque. */
    res->rms = opaque ? sqrt(sum_rgb / (3.0 * res->pixels))
                      : sqrt((sum_rgb + sum_a) / (4.0 * res->pixels));
    if (opts->metric == SP_COMPARE_RMS)
        res->pass = res->rms <= res->tol;
    else
        res->pass = res->differing <= res->allowed;
    return 0;
}
