/* springpend tests: image comparison (image_compare.c) on the reviewed
 * golden renders and on small hand-made images whose figures are worked
 * out by hand. usage: test_compare TESTS_SOURCE_DIR OUTPUT_DIR */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image_compare.h"
#include "springpend/png_io.h"
#include "tap.h"

static const struct sp_compare_opts defaults = {0};

static uint8_t *px(const struct sp_image *img, int x, int y)
{
    return img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
}

static void copy(struct sp_image *dst, const struct sp_image *src)
{
    sp_image_alloc(dst, src->width, src->height);
    memcpy(dst->pixels, src->pixels, (size_t)src->stride * src->height);
}

/* dst(x, y) = src(x - dx, y - dy), edges repeated. */
static void shifted(struct sp_image *dst, const struct sp_image *src, int dx, int dy)
{
    sp_image_alloc(dst, src->width, src->height);
    for (int y = 0; y < src->height; y++)
        for (int x = 0; x < src->width; x++) {
            int sx = x - dx < 0 ? 0 : x - dx >= src->width ? src->width - 1 : x - dx;
            int sy = y - dy < 0 ? 0 : y - dy >= src->height ? src->height - 1 : y - dy;
            memcpy(px(dst, x, y), px(src, sx, sy), 4);
        }
}

static int verdict(const struct sp_image *a, const struct sp_image *b,
                   const struct sp_compare_opts *o, struct sp_compare_result *r)
{
    return sp_compare_images(a, b, o, r, NULL) == 0 && r->pass;
}

static void test_golden_variants(const char *src, const char *name)
{
    char path[4096];
    struct sp_image g = {0}, v = {0};
    struct sp_compare_result r;
    int pass;
    snprintf(path, sizeof(path), "%s/golden/%s.png", src, name);
    if (!sp_tap_ok(sp_png_read(path, &g) == 0, "%s: read", name))
        return;

    sp_tap_ok(verdict(&g, &g, &defaults, &r) && r.differing == 0 && r.changed == 0 &&
              r.rms == 0 && r.max_channel_diff == 0 && r.bbox[0] == -1,
              "%s: identical images match with zero figures", name);

    /* Every colour channel one level up (clamped at 255). */
    copy(&v, &g);
    for (int y = 0; y < v.height; y++)
        for (int x = 0; x < v.width; x++)
            for (int c = 0; c < 3; c++)
                px(&v, x, y)[c] += px(&v, x, y)[c] < 255;
    pass = verdict(&g, &v, &defaults, &r);
    sp_tap_ok(pass && r.max_channel_diff == 1 && r.differing == 0 &&
              r.rms <= 1 && r.rms > 0.9,
              "%s: one level brighter matches by default (rms %.3f)", name, r.rms);
    sp_tap_ok(!verdict(&g, &v, &(struct sp_compare_opts){.max_diff = SP_COMPARE_NONE,
                                                         .max_pixels = SP_COMPARE_NONE}, &r),
              "%s: ... but not under --max-diff 0 --max-pixels 0", name);
    sp_tap_ok(verdict(&g, &v, &(struct sp_compare_opts){.metric = SP_COMPARE_RMS}, &r),
              "%s: ... and passes rms tol 2", name);
    sp_image_free(&v);

    /* One pixel sideways, and one pixel down. */
    for (int dir = 0; dir < 2; dir++) {
        shifted(&v, &g, dir == 0, dir == 1);
        pass = verdict(&g, &v, &defaults, &r);
        sp_tap_ok(!pass && r.differing > r.allowed,
                  "%s: shifted 1 px %s fails by default (%ld pixels differ, %ld allowed)", name,
                  dir ? "down" : "right", r.differing, r.allowed);
        sp_image_free(&v);
    }

    /* Recoloured: red and blue swapped. */
    copy(&v, &g);
    for (int y = 0; y < v.height; y++)
        for (int x = 0; x < v.width; x++) {
            uint8_t *p = px(&v, x, y), t = p[0];
            p[0] = p[2], p[2] = t;
        }
    pass = verdict(&g, &v, &defaults, &r);
    sp_tap_ok(!pass && r.max_channel_diff > 100,
              "%s: red and blue swapped fails (%ld pixels differ, largest difference %d)",
              name, r.differing, r.max_channel_diff);
    sp_image_free(&v);

    /* Resized: one column less. */
    sp_image_alloc(&v, g.width - 1, g.height);
    sp_tap_ok(sp_compare_images(&g, &v, &defaults, &r, NULL) == SP_E_INPUT,
              "%s: a %dx%d image against a %dx%d one is an input error", name, g.width,
              g.height, v.width, v.height);
    sp_image_free(&v);
    sp_image_free(&g);
}

/* A 4x3 opaque black image. */
static void small(struct sp_image *img)
{
    sp_image_alloc(img, 4, 3);
    for (int i = 0; i < 12; i++)
        img->pixels[4 * i + 3] = 255;
}

static void test_figures(void)
{
    struct sp_image a, b, d;
    struct sp_compare_result r;
    small(&a);
    small(&b);
    /* (1,0) green +6, (3,2) red +2: one pixel beyond 3 levels, one within. */
    px(&b, 1, 0)[1] = 6;
    px(&b, 3, 2)[0] = 2;
    int ret = sp_compare_images(&a, &b, &(struct sp_compare_opts){.max_pixels = 1}, &r, &d);
    /* rms over RGB of 12 pixels: sqrt((36 + 4) / 36) */
    sp_tap_ok(ret == 0 && r.pass && r.pixels == 12 && r.differing == 1 && r.changed == 2 &&
              r.max_channel_diff == 6 && fabs(r.rms - sqrt(40.0 / 36)) < 1e-12,
              "figures: 1 differing, 2 changed, max 6, rms %.6f = sqrt(40/36)", r.rms);
    sp_tap_ok(r.bbox[0] == 1 && r.bbox[1] == 0 && r.bbox[2] == 1 && r.bbox[3] == 0,
              "bounding box covers only the pixel beyond tolerance: %d,%d..%d,%d", r.bbox[0],
              r.bbox[1], r.bbox[2], r.bbox[3]);
    uint8_t *strong = px(&d, 1, 0), *weak = px(&d, 3, 2), *same = px(&d, 0, 0);
    sp_tap_ok(strong[0] == 255 && strong[1] == 0 && strong[2] == 255 && weak[2] > weak[0] &&
              weak[2] > weak[1] && weak[2] < 255 && same[0] == same[1] && same[1] == same[2] &&
              same[0] > 0 && same[3] == 255,
              "diff image: magenta beyond tolerance, blue within, grey elsewhere");
    sp_image_free(&d);
    sp_tap_ok(!verdict(&a, &b, &(struct sp_compare_opts){.max_pixels = SP_COMPARE_NONE}, &r),
              "max_pixels NONE: one differing pixel fails");
    sp_tap_ok(verdict(&a, &b, &(struct sp_compare_opts){.max_diff = 6, .max_pixels = SP_COMPARE_NONE}, &r),
              "max_diff 6: a difference of exactly 6 is within tolerance");
    sp_tap_ok(!verdict(&a, &b, &(struct sp_compare_opts){.max_fraction = 0.05}, &r) &&
              r.allowed == 0 && verdict(&a, &b, &(struct sp_compare_opts){.max_fraction = 1.0 / 12}, &r),
              "a fraction allows floor(fraction * pixels): 5%% of 12 is 0, 1/12 is 1");
    int pass = verdict(&a, &b, &(struct sp_compare_opts){.metric = SP_COMPARE_RMS, .tol = 1.06}, &r);
    sp_tap_ok(pass && !verdict(&a, &b, &(struct sp_compare_opts){.metric = SP_COMPARE_RMS, .tol = 1.05}, &r),
              "rms rule: sqrt(40/36) = 1.0541 passes tol 1.06, fails tol 1.05");
    /* Transparency anywhere: alpha joins the rms, as matplotlib does. */
    px(&a, 2, 2)[3] = px(&b, 2, 2)[3] = 128;
    ret = sp_compare_images(&a, &b, &defaults, &r, NULL);
    sp_tap_ok(ret == 0 && fabs(r.rms - sqrt(40.0 / 48)) < 1e-12, "with alpha < 255 the rms is over RGBA: %.6f",
              r.rms);
    px(&b, 2, 2)[3] = 0;
    pass = verdict(&a, &b, &(struct sp_compare_opts){.max_pixels = 1}, &r);
    sp_tap_ok(!pass && r.differing == 2 && r.bbox[3] == 2 && r.bbox[2] == 2,
              "an alpha difference counts like a colour one");
    sp_image_free(&a);
    sp_image_free(&b);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_SOURCE_DIR [OUTPUT_DIR]\n", argv[0]);
        return 2;
    }
    test_figures();
    test_golden_variants(argv[1], "default_t3");
    test_golden_variants(argv[1], "default_t0_notrail");
    return sp_tap_done();
}
