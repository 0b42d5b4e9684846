/* springpend: image comparison for snapshot tests. Pure: no files, no GL.
 *
 * Two rules, both well known:
 *   reftest (default, Firefox/WPT "fuzzy" style): a pixel differs when any
 *     of its RGBA channels differs by more than max_diff levels of 255; the
 *     images match when at most `allowed` pixels differ.
 *   rms (matplotlib.testing.compare / pytest-mpl): the root mean square of
 *     the channel differences, in levels, over RGB (RGBA when either image
 *     has a pixel with alpha < 255), must be <= tol.
 * Whatever the rule, the result carries every figure. */
#ifndef SPRINGPEND_IMAGE_COMPARE_H
#define SPRINGPEND_IMAGE_COMPARE_H

#include "springpend/image.h"

/* Defaults: llvmpipe on another CPU may move a level or two, and an
 * antialiased edge pixel here and there a little more; a 1 px shift of a
 * rendered still changes far more than 0.1% of the pixels. */
#define SP_COMPARE_MAX_DIFF_DEFAULT 3     /* levels of 255 */
#define SP_COMPARE_MAX_FRACTION_DEFAULT 1e-3 /* of the pixels */
#define SP_COMPARE_TOL_DEFAULT 2.0        /* rms, levels (pytest-mpl's) */

/* Put in a field to ask for zero where zero itself means "default". */
#define SP_COMPARE_NONE (-1)

enum sp_compare_metric {
    SP_COMPARE_REFTEST = 0,
    SP_COMPARE_RMS = 1,
    SP_COMPARE_BLOCKS = 3,     /* videos' default (SP_COMPARE_VIDEO_BLOCK):
                                  sp_compare_images sees the block means */
    SP_COMPARE_PIXELMATCH = 2, /* mapbox/pixelmatch's perceptual rule: a pixel
                                  differs when its YIQ distance exceeds
                                  35215 * threshold^2 and it is not
                                  anti-aliasing (pixelmatch.c) */
};

#define SP_COMPARE_THRESHOLD_DEFAULT 0.1 /* pixelmatch's own default */

/* Videos' default rule, when nothing is set for a video on the command line
 * or in compare.ini: the frames are compared as means of 8x8 blocks; a block
 * differs when a channel's mean moves by more than 16 levels; a frame fails
 * when any block differs. Lossy encoders scatter small errors over edges,
 * which the means smooth away (the same frames at CRF 22, 24 and 28 against
 * 23, at preset medium and veryfast, and as WebM: at most 13.9 levels); a
 * changed parameter moves the pendulum and its trail, which they keep. */
#define SP_COMPARE_VIDEO_BLOCK 8       /* px */
#define SP_COMPARE_VIDEO_BLOCK_DIFF 16 /* levels of 255 */

/* The means of block x block squares of img (partial ones at the right and
 * bottom edges averaged over what they hold) into out, a new image of
 * ceil(w / block) x ceil(h / block) (free with sp_image_free). Returns 0 or
 * SP_E_NOMEM. */
int sp_compare_block_means(const struct sp_image *img, int block, struct sp_image *out);

/* The limits of one rule, as sp_compare_opts holds them (zero: the
 * default; SP_COMPARE_NONE: 0). */
struct sp_compare_limits {
    int max_diff;
    long max_pixels;
    double max_fraction;
    double tol;
    double threshold;
};

/* Zero fields take the defaults above. */
struct sp_compare_opts {
    enum sp_compare_metric metric;
    int max_diff;        /* levels of 255 a channel may move unnoticed;
                            SP_COMPARE_NONE = 0 */
    long max_pixels;     /* differing pixels allowed; SP_COMPARE_NONE = 0;
                            0 = use max_fraction */
    double max_fraction; /* share of the pixels allowed to differ, 0..1, when
                            max_pixels is 0; 0 = default */
    double tol;          /* rms metric: largest rms, levels; SP_COMPARE_NONE
                            = 0 (identical) */
    double threshold;    /* pixelmatch metric: 0..1, 0 = default 0.1;
                            SP_COMPARE_NONE = 0 (any change counts) */
    unsigned given;      /* which fields a command line or compare.ini set
                            (compare_config.h's SP_COMPARE_SET_* bits) */
    /* A limit on the pixels allowed that nothing loosens (the command line's
     * --max-pixels under compare.ini): a count (SP_COMPARE_NONE = 0) or,
     * when 0, a share cap_fraction; both 0 = no limit. */
    long cap_pixels;
    double cap_fraction;
    /* The command line's own rule, checked besides metric's whenever the
     * command line gives a limit: bits 1 << SP_COMPARE_REFTEST, _RMS,
     * _PIXELMATCH (--metric's; else reftest for --max-diff, or --max-pixels
     * without --threshold; rms for --tol; pixelmatch for --threshold), each
     * judged by `own`, the command line's limits with the defaults for what
     * it did not give, never compare.ini's fields (attack15 #7: `metric =
     * rms` loosened --max-diff 0 --max-pixels 0; attack16 #7: `threshold =
     * 1` or `max_diff = 255` loosened --max-pixels 0). A rule that metric's
     * own limits already imply (the same metric, no looser) is not checked
     * again; the image passes only when every rule does. */
    unsigned also;
    struct sp_compare_limits own;
};

struct sp_compare_result {
    long pixels;          /* compared: width * height */
    long differing;       /* pixels with a channel off by more than max_diff */
    long changed;         /* pixels with any channel off at all */
    long allowed;         /* differing pixels the reftest rule allows */
    int max_diff;         /* the max_diff that was applied, levels */
    double tol;           /* the rms tolerance that was applied, levels */
    double threshold;     /* the pixelmatch threshold that was applied */
    long antialiased;     /* pixelmatch: pixels beyond the threshold taken for
                             anti-aliasing, so not counted in differing */
    int max_channel_diff; /* largest channel difference, levels of 255 */
    double rms;           /* levels of 255, see above */
    int bbox[4];          /* x0, y0, x1, y1 (inclusive, px, top-left origin)
                             of the differing pixels; all -1 when none */
    int pass;             /* 1: the images match under opts->metric and
                             every rule in opts->also */
    unsigned also;        /* opts->also less the rules metric's limits
                             imply: the rules checked besides */
    long also_reftest;    /* pixels off by more than also_max_diff */
    long also_pixelmatch; /* with also's pixelmatch: pixels it counts at
                             also_threshold */
    int also_max_diff;    /* the limits of also's rules (opts->own with */
    long also_allowed;    /* the defaults patched in) */
    double also_tol, also_threshold;
    int decided_by;       /* -1: metric decided (or every rule passed); else
                             the rule of also that failed */
};

/* Compares expected with actual. They must have the same size: otherwise
 * logs both sizes and returns SP_E_INPUT. When diff is not NULL it receives
 * a new image of that size (free with sp_image_free): the expected image
 * faded to grey, pixels beyond max_diff in magenta and smaller changes in
 * a quieter blue. Returns 0 (whatever the verdict),
 * SP_E_INPUT or SP_E_NOMEM. */
int sp_compare_images(const struct sp_image *expected, const struct sp_image *actual,
                      const struct sp_compare_opts *opts, struct sp_compare_result *res,
                      struct sp_image *diff);

/* pixelmatch (mapbox/pixelmatch, index.js, v5.3): the number of pixels of
 * a and b (same size) whose YIQ colour distance exceeds 35215 * threshold^2
 * and that are not anti-aliasing in either image (unless include_aa). When
 * marks is not NULL (width * height bytes) it receives per pixel 0 (within
 * the threshold), 1 (beyond it, taken for anti-aliasing) or 2 (differs). */
long sp_compare_pixelmatch(const struct sp_image *a, const struct sp_image *b, double threshold,
                           int include_aa, uint8_t *marks);

/* A rectangle of pixels the comparison ignores (a clock in a HUD). */
struct sp_compare_mask {
    int x, y, w, h; /* px, top-left origin; clipped to the image */
};

/* Copies the masked rectangles of expected into actual, so they compare
 * equal; returns the sum of the rectangles' clipped areas (overlaps
 * counted once per rectangle: sp_compare_masked_pixels counts pixels). */
long sp_compare_apply_masks(const struct sp_image *expected, struct sp_image *actual,
                            const struct sp_compare_mask *masks, int n_masks);

/* The pixels of a width x height image that the masks of a and b cover,
 * each pixel counted once however many masks overlap it (clipped); -1
 * (logged) when out of memory. */
long sp_compare_masked_pixels(int width, int height, const struct sp_compare_mask *a, int na,
                              const struct sp_compare_mask *b, int nb);

/* SHA-256 of the decoded pixels (rows of width * 4 bytes, stride skipped,
 * then the width and height as text), as 64 lower-case hex digits in
 * hex[65]. Equal hashes: identical images, whatever their files hold.
 * Returns 0 or SP_E_NOMEM. */
int sp_compare_pixel_hash(const struct sp_image *img, char hex[65]);

/* The structural similarity (SSIM, Wang et al. 2004) of the two images'
 * luma (BT.601 weights), averaged over 8x8 windows every 4 px: 1 for
 * identical images, lower for structural change; for a person deciding,
 * never part of the verdict. Same sizes only; images smaller than 8 px
 * either way use one window of their size. */
double sp_compare_ssim(const struct sp_image *expected, const struct sp_image *actual);

/* The diff image of two images of different sizes: both side by side on
 * one canvas (expected left, actual right, 8 px apart), the area of each
 * that the other lacks tinted magenta, the rest of the canvas dark grey.
 * Returns 0 or SP_E_NOMEM; free diff with sp_image_free. */
int sp_compare_size_diff(const struct sp_image *expected, const struct sp_image *actual,
                         struct sp_image *diff);

#endif
