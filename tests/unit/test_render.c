/* springpend tests: the renderer draws what a frame says. A hand-built frame
 * (default pendulum, known bob and trail, known extent) is rendered at
 * 640x360 and probed at projected points. Args: SRCDIR BUILDDIR; on failure
 * the first frame is written to BUILDDIR/render_actual.png.
 * Exits 77 when no GL context can be created at all. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/png_io.h"
#include "springpend/render.h"
#include "render/gl_context.h"
#include "tap.h"

enum { W = 640, H = 360, TRAIL_N = 60, LONG_TRAIL_N = 3000 };

static const struct sp_view_extent EXTENT = {
    .xmin = -2, .xmax = 2, .ymin = -4, .ymax = 0.5, .max_speed = 5,
};

/* The renderer's camera, restated: extent + (bob radius + 6%) of the smaller
 * side as margin, equal scale, centred. Returns the pixel holding (x, y). */
static void project(double x, double y, int *px, int *py)
{
    const double unit = H, margin = (0.022 + 0.06) * unit;
    const double s = fmin((W - 2 * margin) / (EXTENT.xmax - EXTENT.xmin),
                          (H - 2 * margin) / (EXTENT.ymax - EXTENT.ymin));
    *px = (int)floor(W / 2.0 + s * (x - 0.5 * (EXTENT.xmin + EXTENT.xmax)));
    *py = (int)floor(H / 2.0 - s * (y - 0.5 * (EXTENT.ymin + EXTENT.ymax)));
}

static const uint8_t *pixel(const struct sp_image *img, int x, int y)
{
    return img->pixels + (size_t)y * img->stride + 4 * (size_t)x;
}

static const uint8_t *at(const struct sp_image *img, double x, double y)
{
    int px, py;
    project(x, y, &px, &py);
    return pixel(img, px, py);
}

static int is_bob(const uint8_t *p)
{
    return p[0] > 150 && p[0] > p[1] + 60 && p[0] > p[2] + 60;
}

/* The trail's fast end: inferno's warm yellow. */
static int is_hot_trail(const uint8_t *p)
{
    return p[0] > 150 && p[1] > 120 && p[2] < p[1] - 60;
}

static int is_background(const uint8_t *p)
{
    return p[0] == 0x12 && p[1] == 0x16 && p[2] == 0x1c && p[3] == 255;
}

/* The brightest pixel (sum of RGB) within `rad` px of the projection of (x, y). */
static int brightest(const struct sp_image *img, double x, double y, int rad,
                     const uint8_t **best)
{
    int px, py, top = -1;
    project(x, y, &px, &py);
    for (int j = py - rad; j <= py + rad; j++)
        for (int i = px - rad; i <= px + rad; i++) {
            const uint8_t *p = pixel(img, i, j);
            if (p[0] + p[1] + p[2] > top) {
                top = p[0] + p[1] + p[2];
                *best = p;
            }
        }
    return top;
}

static int all_opaque(const struct sp_image *img)
{
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (pixel(img, x, y)[3] != 255)
                return 0;
    return 1;
}

/* A packed copy of img's pixels (the renderer's buffer is reused per draw). */
static uint8_t *copy_pixels(const struct sp_image *img)
{
    uint8_t *out = malloc((size_t)4 * img->width * img->height);
    for (int y = 0; out && y < img->height; y++)
        memcpy(out + (size_t)4 * img->width * y, pixel(img, 0, y),
               (size_t)4 * img->width);
    return out;
}

/* n points left to right along y = -2.5 m, speeding up to 5 m/s, ending
 * at (1, -2.5). */
static int fill_trail(struct sp_trail *tr, int n)
{
    if (sp_trail_make(tr, n))
        return 1;
    for (int i = 0; i < n; i++) {
        const double u = (double)i / (n - 1);
        /* spread over the default trail window, 599 frames at 60 fps */
        const struct sp_state s = {.t = u * 599 / 60.0, .x = -1.5 + 2.5 * u, .y = -2.5, .vx = 5 * u};
        sp_trail_push(tr, &s);
    }
    return 0;
}

int main(int argc, char **argv)
{
    const char *outdir = argc > 2 ? argv[2] : ".";
    const struct sp_params params = {
        .k_over_m = 4, .L0 = 0.5, .g = 9.81, .b_over_m = 0, .mass = 0.5,
        .stiffness = 2,
    };
    struct sp_gl_context *probe = NULL;
    struct sp_renderer *r = NULL;
    struct sp_trail trail;
    struct sp_frame f = {.params = &params, .trail = &trail};
    struct sp_image img = {0};
    const uint8_t *p;
    uint8_t *first = NULL, *second = NULL;
    char path[4096];
    int err;

    if (sp_gl_context_make(&probe, W, H, SP_GL_DEFAULT))
        SP_TAP_SKIP_ALL("no GL context");
    sp_gl_context_destroy(&probe);

    /* The trail ends under the bob. */
    if (fill_trail(&trail, TRAIL_N))
        return 1;
    f.state = (struct sp_state){.t = 1, .x = 1, .y = -2.5, .vx = 5};

    err = sp_render_make(&r, &(struct sp_render_desc){.width = W, .height = H, .extent = EXTENT});
    sp_tap_ok(err == 0, "renderer made (%s)", r ? sp_render_renderer_name(r) : "-");
    if (err)
        goto done;

    err = sp_render_draw(r, &f, &img);
    sp_tap_ok(err == 0 && img.width == W && img.height == H && img.stride >= 4 * W,
              "draw gives a %dx%d image", W, H);
    if (err)
        goto done;
    first = copy_pixels(&img);

    p = at(&img, 1, -2.5);
    sp_tap_ok(is_bob(p), "bob centre is bob-red (%d %d %d)", p[0], p[1], p[2]);
    p = at(&img, -1.8, -3.8);
    sp_tap_ok(is_background(p), "empty corner is background (%d %d %d %d)",
              p[0], p[1], p[2], p[3]);
    brightest(&img, 0.7, -2.5, 1, &p);
    sp_tap_ok(is_hot_trail(p), "trail near its fast newest end is bright yellow (%d %d %d)",
              p[0], p[1], p[2]);
    brightest(&img, -1.45, -2.5, 1, &p);
    sp_tap_ok(p[0] + p[1] + p[2] < 0x12 + 0x16 + 0x1c + 60,
              "trail's oldest end has faded (%d %d %d)", p[0], p[1], p[2]);
    brightest(&img, 0.5, -1.25, 3, &p);
    sp_tap_ok(p[0] > 150 && p[2] > 150 && abs(p[0] - p[2]) < 40,
              "spring wire at its middle is light grey (%d %d %d)", p[0], p[1], p[2]);
    p = at(&img, 0, 0);
    sp_tap_ok(p[0] > 180 && p[1] > 180 && p[2] > 180, "pivot is drawn (%d %d %d)",
              p[0], p[1], p[2]);
    sp_tap_ok(all_opaque(&img), "every pixel is opaque");

    err = sp_render_draw(r, &f, &img);
    second = err ? NULL : copy_pixels(&img);
    sp_tap_ok(first && second && memcmp(first, second, (size_t)4 * W * H) == 0,
              "the same frame renders to the same bytes");

    f.state.x = -1;
    f.state.y = -2;
    f.trail = NULL;
    err = sp_render_draw(r, &f, &img);
    p = at(&img, -1, -2);
    sp_tap_ok(!err && is_bob(p), "moved bob is drawn at its new place (%d %d %d)",
              p[0], p[1], p[2]);
    p = at(&img, 1, -2.5);
    sp_tap_ok(!err && is_background(p), "its old place is background (%d %d %d)",
              p[0], p[1], p[2]);

    /* More trail segments than the renderer first made room for. */
    sp_trail_destroy(&trail);
    if (fill_trail(&trail, LONG_TRAIL_N))
        goto done;
    f.trail = &trail;
    err = sp_render_draw(r, &f, &img);
    brightest(&img, 0.7, -2.5, 1, &p);
    sp_tap_ok(!err && is_hot_trail(p), "a %d-point trail is drawn too (%d %d %d)",
              LONG_TRAIL_N, p[0], p[1], p[2]);

done:
    if (sp_tap_failed && first) {
        const struct sp_image shot = {first, W, H, 4 * W, SP_IMAGE_RGBA};
        snprintf(path, sizeof(path), "%s/render_actual.png", outdir);
        if (sp_png_write(path, &shot, 1) == 0)
            sp_tap_diag("actual image: %s", path);
    }
    free(first);
    free(second);
    sp_render_destroy(&r);
    sp_trail_destroy(&trail);
    return sp_tap_done();
}
