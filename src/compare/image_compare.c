/* springpend: image comparison for snapshot tests (see image_compare.h). */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "base/digest.h"
#include "springpend/common.h"
#include "springpend/image_compare.h"

/* Limits l with the defaults patched in, for an image of `pixels`. */
static void limits_resolve(const struct sp_compare_limits *l, long pixels, int *max_diff,
                           long *allowed, double *tol, double *threshold)
{
    *max_diff = l->max_diff == SP_COMPARE_NONE ? 0
                : l->max_diff > 0             ? l->max_diff
                                              : SP_COMPARE_MAX_DIFF_DEFAULT;
    if (l->max_pixels == SP_COMPARE_NONE)
        *allowed = 0;
    else if (l->max_pixels > 0)
        *allowed = l->max_pixels;
    else
        *allowed = (long)floor(
            (l->max_fraction > 0 ? l->max_fraction : SP_COMPARE_MAX_FRACTION_DEFAULT) * pixels);
    *threshold = l->threshold == SP_COMPARE_NONE ? 0
                 : l->threshold > 0 ? l->threshold : SP_COMPARE_THRESHOLD_DEFAULT;
    *tol = l->tol == SP_COMPARE_NONE ? 0 : l->tol > 0 ? l->tol : SP_COMPARE_TOL_DEFAULT;
}

/* The rule with defaults patched in; the command line's own rule's limits
 * (opts->own), and which of its rules are checked: those that metric's
 * limits do not imply (the same metric, no looser). */
static void resolve(const struct sp_compare_opts *o, long pixels, struct sp_compare_result *res)
{
    const struct sp_compare_limits l = {o->max_diff, o->max_pixels, o->max_fraction, o->tol,
                                        o->threshold};
    limits_resolve(&l, pixels, &res->max_diff, &res->allowed, &res->tol, &res->threshold);
    if (o->cap_pixels || o->cap_fraction > 0) {
        long cap = o->cap_pixels == SP_COMPARE_NONE ? 0
                   : o->cap_pixels > 0 ? o->cap_pixels
                                       : (long)floor(o->cap_fraction * pixels);
        res->allowed = cap < res->allowed ? cap : res->allowed;
    }
    limits_resolve(&o->own, pixels, &res->also_max_diff, &res->also_allowed, &res->also_tol,
                   &res->also_threshold);
    const int implied[3] = {
        [SP_COMPARE_REFTEST] = res->max_diff <= res->also_max_diff &&
                               res->allowed <= res->also_allowed,
        [SP_COMPARE_RMS] = res->tol <= res->also_tol,
        [SP_COMPARE_PIXELMATCH] = res->threshold <= res->also_threshold &&
                                  res->allowed <= res->also_allowed};
    res->also = o->also;
    if (o->metric >= 0 && o->metric < 3 && implied[o->metric])
        res->also &= ~(1u << o->metric);
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
    uint8_t *marks = NULL; /* pixelmatch's verdict per pixel */
    const int pm = opts->metric == SP_COMPARE_PIXELMATCH;
    if (pm) {
        if (!(marks = malloc((size_t)res->pixels))) {
            sp_log_error("out of memory comparing two %dx%d images", e->width, e->height);
            if (diff)
                sp_image_free(diff);
            return SP_E_NOMEM;
        }
        sp_compare_pixelmatch(e, a, res->threshold, 0, marks);
    }
    /* the command line's own pixelmatch rule, at its own threshold */
    const int also_pm = (res->also & (1u << SP_COMPARE_PIXELMATCH)) != 0;
    if (also_pm && !(pm && res->also_threshold == res->threshold))
        res->also_pixelmatch = sp_compare_pixelmatch(e, a, res->also_threshold, 0, NULL);

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
            const int ref = m > res->max_diff ? 2 : m > 0;
            const int pml = marks ? marks[(size_t)y * e->width + x] : 0;
            const int level = pm ? pml : ref;
            res->also_reftest += m > res->also_max_diff;
            res->antialiased += level == 1 && pm;
            res->changed += m > 0;
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
    free(marks);
    if (also_pm && pm && res->also_threshold == res->threshold)
        res->also_pixelmatch = res->differing; /* the same marks */
    if (opts->metric == SP_COMPARE_RMS)
        res->pass = res->rms <= res->tol;
    else
        res->pass = res->differing <= res->allowed;
    res->decided_by = -1;
    const int fails[3] = {
        [SP_COMPARE_REFTEST] = res->also_reftest > res->also_allowed,
        [SP_COMPARE_RMS] = res->rms > res->also_tol,
        [SP_COMPARE_PIXELMATCH] = res->also_pixelmatch > res->also_allowed};
    for (int k = 0; k < 3 && res->pass; k++)
        if ((res->also & (1u << k)) && fails[k])
            res->pass = 0, res->decided_by = k;
    return 0;
}

long sp_compare_apply_masks(const struct sp_image *expected, struct sp_image *actual,
                            const struct sp_compare_mask *masks, int n_masks)
{
    long covered = 0;
    for (int i = 0; i < n_masks; i++) {
        int x0 = masks[i].x < 0 ? 0 : masks[i].x, y0 = masks[i].y < 0 ? 0 : masks[i].y;
        long x1 = (long)masks[i].x + masks[i].w, y1 = (long)masks[i].y + masks[i].h;
        x1 = x1 > expected->width ? expected->width : x1;
        y1 = y1 > expected->height ? expected->height : y1;
        if (x1 <= x0 || y1 <= y0)
            continue;
        covered += (x1 - x0) * (y1 - y0);
        for (int y = y0; y < y1; y++)
            memcpy(actual->pixels + (size_t)y * actual->stride + 4 * (size_t)x0,
                   expected->pixels + (size_t)y * expected->stride + 4 * (size_t)x0,
                   4 * (size_t)(x1 - x0));
    }
    return covered;
}

/* A mask clipped to a w x h image: [x0, x1) x [y0, y1), px; 0 when empty. */
static int clip_mask(const struct sp_compare_mask *m, int w, int h, long box[4])
{
    box[0] = m->x < 0 ? 0 : m->x;
    box[1] = m->y < 0 ? 0 : m->y;
    box[2] = (long)m->x + m->w;
    box[3] = (long)m->y + m->h;
    box[2] = box[2] > w ? w : box[2];
    box[3] = box[3] > h ? h : box[3];
    return box[2] > box[0] && box[3] > box[1];
}

static int by_start(const void *a, const void *b)
{
    const long *x = a, *y = b;
    return (x[0] > y[0]) - (x[0] < y[0]);
}

long sp_compare_masked_pixels(int width, int height, const struct sp_compare_mask *a, int na,
                              const struct sp_compare_mask *b, int nb)
{
    size_t cap = (size_t)(na + nb) + 1;
    long (*boxes)[4] = malloc(sizeof(*boxes) * cap), (*spans)[2] = malloc(sizeof(*spans) * cap);
    long *ys = malloc(sizeof(*ys) * 2 * cap), covered = 0;
    int n = 0;
    if (!boxes || !spans || !ys) {
        free(boxes), free(spans), free(ys);
        sp_log_error("out of memory counting masked pixels");
        return -1;
    }
    for (int i = 0; i < na + nb; i++)
        n += clip_mask(i < na ? &a[i] : &b[i - na], width, height, boxes[n]);
    /* Bands between the masks' top and bottom edges: within one, the same
     * masks cross every row, so one row's merged spans times its height. */
    for (int i = 0; i < n; i++)
        ys[2 * i] = boxes[i][1], ys[2 * i + 1] = boxes[i][3];
    qsort(ys, 2 * (size_t)n, sizeof(*ys), by_start);
    for (int e = 0; e + 1 < 2 * n; e++) {
        long y = ys[e], band = ys[e + 1] - ys[e], end = 0, row = 0;
        int k = 0;
        if (band <= 0)
            continue;
        for (int i = 0; i < n; i++)
            if (boxes[i][1] <= y && y < boxes[i][3]) {
                spans[k][0] = boxes[i][0];
                spans[k++][1] = boxes[i][2];
            }
        qsort(spans, (size_t)k, sizeof(spans[0]), by_start);
        for (int i = 0; i < k; i++) {
            long from = spans[i][0] > end ? spans[i][0] : end;
            if (spans[i][1] > from) {
                row += spans[i][1] - from;
                end = spans[i][1];
            }
        }
        covered += row * band;
    }
    free(boxes);
    free(spans);
    free(ys);
    return covered;
}

int sp_compare_pixel_hash(const struct sp_image *img, char hex[65])
{
    char size[32];
    struct sha256_ctx sha;
    sha256_init(&sha);
    for (int y = 0; y < img->height; y++)
        sha256_update(&sha, 4 * (size_t)img->width, img->pixels + (size_t)y * img->stride);
    int n = snprintf(size, sizeof(size), "%dx%d", img->width, img->height);
    sha256_update(&sha, (size_t)n, (const uint8_t *)size);
    sp_digest_hex(&sha, hex);
    return 0;
}

static double luma(const uint8_t *p)
{
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

double sp_compare_ssim(const struct sp_image *e, const struct sp_image *a)
{
    const double c1 = (0.01 * 255) * (0.01 * 255), c2 = (0.03 * 255) * (0.03 * 255);
    int ww = e->width < 8 ? e->width : 8, wh = e->height < 8 ? e->height : 8;
    double total = 0;
    long windows = 0;
    if (e->width != a->width || e->height != a->height || ww <= 0 || wh <= 0)
        return 0;
    for (int y0 = 0; y0 + wh <= e->height; y0 += 4) {
        for (int x0 = 0; x0 + ww <= e->width; x0 += 4) {
            double se = 0, sa = 0, see = 0, saa = 0, sea = 0, n = (double)ww * wh;
            for (int y = y0; y < y0 + wh; y++) {
                const uint8_t *p = e->pixels + (size_t)y * e->stride + 4 * (size_t)x0;
                const uint8_t *q = a->pixels + (size_t)y * a->stride + 4 * (size_t)x0;
                for (int x = 0; x < ww; x++, p += 4, q += 4) {
                    double u = luma(p), v = luma(q);
                    se += u, sa += v, see += u * u, saa += v * v, sea += u * v;
                }
            }
            double me = se / n, ma = sa / n;
            double ve = see / n - me * me, va = saa / n - ma * ma, cov = sea / n - me * ma;
            total += (2 * me * ma + c1) * (2 * cov + c2) /
                     ((me * me + ma * ma + c1) * (ve + va + c2));
            windows++;
        }
    }
    return windows ? total / windows : 1;
}

/* Copies src into dst at (x0, 0), tinting magenta the part outside
 * other_w x other_h (what the other image lacks). */
static void blit_marked(struct sp_image *dst, int x0, const struct sp_image *src, int other_w,
                        int other_h)
{
    for (int y = 0; y < src->height; y++) {
        const uint8_t *p = src->pixels + (size_t)y * src->stride;
        uint8_t *d = dst->pixels + (size_t)y * dst->stride + 4 * (size_t)x0;
        for (int x = 0; x < src->width; x++, p += 4, d += 4) {
            int extra = x >= other_w || y >= other_h;
            d[0] = extra ? (uint8_t)((p[0] + 255) / 2) : p[0];
            d[1] = extra ? (uint8_t)(p[1] / 2) : p[1];
            d[2] = extra ? (uint8_t)((p[2] + 255) / 2) : p[2];
            d[3] = 255;
        }
    }
}

int sp_compare_size_diff(const struct sp_image *e, const struct sp_image *a,
                         struct sp_image *diff)
{
    int w = e->width + 8 + a->width, h = e->height > a->height ? e->height : a->height;
    int err = sp_image_alloc(diff, w, h);
    if (err)
        return err;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            uint8_t *d = diff->pixels + (size_t)y * diff->stride + 4 * (size_t)x;
            d[0] = d[1] = d[2] = 48, d[3] = 255;
        }
    blit_marked(diff, 0, e, a->width, a->height);
    blit_marked(diff, e->width + 8, a, e->width, e->height);
    return 0;
}

int sp_compare_block_means(const struct sp_image *img, int block, struct sp_image *out)
{
    int w = (img->width + block - 1) / block, h = (img->height + block - 1) / block;
    int err = sp_image_alloc(out, w, h);
    if (err)
        return err;
    for (int by = 0; by < h; by++)
        for (int bx = 0; bx < w; bx++) {
            unsigned sum[4] = {0};
            int n = 0;
            for (int y = by * block; y < (by + 1) * block && y < img->height; y++) {
                const uint8_t *p = img->pixels + (size_t)y * img->stride + 4 * (size_t)bx * block;
                for (int x = bx * block; x < (bx + 1) * block && x < img->width; x++, p += 4, n++)
                    for (int c = 0; c < 4; c++)
                        sum[c] += p[c];
            }
            uint8_t *d = out->pixels + (size_t)by * out->stride + 4 * (size_t)bx;
            for (int c = 0; c < 4; c++)
                d[c] = (uint8_t)((sum[c] + (unsigned)n / 2) / (unsigned)n);
        }
    return 0;
}
