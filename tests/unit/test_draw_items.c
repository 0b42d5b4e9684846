/* springpend tests: the draw list's items that sweep figures need (canvas.h)
 * and the cairo backend that draws them (draw_cairo.c), composed and drawn
 * here without the program: an IMAGE item (a map's raster) lands where its
 * rectangle says with sharp cells, turned text (a y axis's name) reads
 * upward at -pi/2 and grows with its scale, sp_canvas_append moves both,
 * a character no font has is refused, and a PDF of the list holds the
 * image as an image and the turned text as real text; the GL backend, which
 * draws neither, refuses a list with them instead of leaving them out. Expected pixels and
 * boxes come from the rectangles and angles given, not from a drawing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "frame/canvas.h"
#include "render/draw_cairo.h"
#include "render/draw_gl.h"
#include "render/gl_context.h"
#include "tap.h"

#ifdef NDEBUG
#error "tests need assertions"
#endif

static const float black[4] = {0, 0, 0, 1};

/* Pixel (x, y) of img, straight RGBA. */
static const uint8_t *at(const struct sp_image *img, int x, int y)
{
    return img->pixels + (size_t)y * (size_t)img->stride + 4 * (size_t)x;
}

/* The box of img's dark pixels (ink on white): x0, y0, x1, y1 inclusive;
 * x1 < x0 when there is none. */
static void ink_box(const struct sp_image *img, int box[4])
{
    box[0] = box[1] = 1 << 20, box[2] = box[3] = -1;
    for (int y = 0; y < img->height; y++)
        for (int x = 0; x < img->width; x++)
            if (at(img, x, y)[0] < 128) {
                box[0] = x < box[0] ? x : box[0], box[1] = y < box[1] ? y : box[1];
                box[2] = x > box[2] ? x : box[2], box[3] = y > box[3] ? y : box[3];
            }
}

static int raster(const struct sp_canvas *c, const struct sp_font *f, double w, double h, int pw,
                  int ph, struct sp_image *out)
{
    struct sp_draw_cairo_desc d = {.canvas = c, .font = f, .width = w, .height = h,
                                   .path = "test", .background = {1, 1, 1, 1}};
    return sp_draw_cairo_raster(&d, pw, ph, out);
}

static void test_image(void)
{
    struct sp_canvas c = {0};
    struct sp_image img;
    /* two cells, red then blue, over (10, 5)-(30, 15) px of a 40 x 20 list */
    unsigned char *p = sp_canvas_image(&c, 10, 5, 30, 15, 2, 1);
    sp_tap_ok(p && c.n_items == 1 && c.items[0].kind == SP_ITEM_IMAGE && c.items[0].iw == 2 &&
                  c.items[0].ih == 1 && c.n_pixels == 8,
              "sp_canvas_image adds one IMAGE item of 2x1 pixels (8 bytes)");
    if (!p)
        return;
    memcpy(p, (const unsigned char[8]){255, 0, 0, 255, 0, 0, 255, 255}, 8);
    int err = raster(&c, NULL, 40, 20, 80, 40, &img); /* 2 px per list px */
    sp_tap_ok(err == 0, "the cairo backend rasterises a list with an image");
    if (!err) {
        const uint8_t *red = at(&img, 39, 20), *blue = at(&img, 40, 20), *out = at(&img, 19, 20);
        const uint8_t *in = at(&img, 20, 20), *below = at(&img, 30, 30);
        sp_tap_ok(red[0] == 255 && red[2] == 0 && blue[2] == 255 && blue[0] == 0,
                  "the cells meet sharply halfway, at x = 20 list px (raster 39: %d,%d,%d; 40: "
                  "%d,%d,%d)", red[0], red[1], red[2], blue[0], blue[1], blue[2]);
        sp_tap_ok(out[0] == 255 && out[1] == 255 && in[0] == 255 && in[1] == 0 &&
                      below[1] == 255,
                  "the image starts at x = 10 and ends at y = 15 list px, white around it");
        sp_image_free(&img);
    }
    /* appended with an offset: its rectangle moves, its pixels follow */
    struct sp_canvas dst = {0};
    sp_canvas_line(&dst, 0, 0, 1, 1, 1, black);
    unsigned char *q = sp_canvas_image(&dst, 0, 0, 1, 1, 1, 1);
    if (q)
        memset(q, 7, 4);
    sp_canvas_append(&dst, &c, 100, 50);
    const struct sp_item *it = &dst.items[dst.n_items - 1];
    sp_tap_ok(!dst.err && it->kind == SP_ITEM_IMAGE && it->rect[0] == 110 && it->rect[1] == 55 &&
                  it->rect[2] == 130 && it->rect[3] == 65 && it->first == 4 &&
                  dst.pixels[it->first] == 255 && dst.pixels[it->first + 6] == 255 &&
                  dst.pixels[0] == 7,
              "sp_canvas_append moves an image's rectangle and copies its pixels after dst's");
    sp_canvas_free(&dst);
    sp_canvas_free(&c);
}

static void test_turned(void)
{
    struct sp_font *f = NULL;
    struct sp_font_desc fd = {.px = {20, 20, 20, 20}};
    struct sp_canvas c = {0};
    struct sp_image img;
    int box[4] = {0}, level[4] = {0};
    if (sp_font_make(&f, &fd)) {
        sp_tap_ok(0, "the embedded font is made");
        return;
    }
    c.font = f;
    /* "HHHHHH" level, then the same turned -pi/2 about (100, 150) */
    sp_canvas_text_turned(&c, SP_TEXT_NORMAL, 20, 40, 1, 0, black, "HHHHHH");
    sp_tap_ok(c.n_items == 1 && c.items[0].kind == SP_ITEM_TEXT && c.items[0].count == 0 &&
                  c.items[0].scale == 1 && c.items[0].x == 20,
              "turned text is a TEXT item with a scale, its pen where given, no glyph quads");
    int err = raster(&c, f, 200, 200, 200, 200, &img);
    if (!err) {
        ink_box(&img, level);
        sp_image_free(&img);
    }
    sp_canvas_reset(&c);
    sp_canvas_text_turned(&c, SP_TEXT_NORMAL, 100, 150, 1, (float)(-M_PI / 2), black, "HHHHHH");
    if (!err && !(err = raster(&c, f, 200, 200, 200, 200, &img))) {
        ink_box(&img, box);
        sp_image_free(&img);
    }
    const int lw = level[2] - level[0], lh = level[3] - level[1];
    const int tw = box[2] - box[0], th = box[3] - box[1];
    sp_tap_ok(!err && lw > 3 * lh && th > 3 * tw && abs(th - lw) <= 2 && abs(tw - lh) <= 2,
              "at -pi/2 the text stands upright: ink %dx%d level, %dx%d turned", lw, lh, tw, th);
    sp_tap_ok(!err && box[3] <= 150 && box[3] >= 145 && box[2] <= 100 && box[2] >= 100 - lh - 2,
              "it reads upward from its pen: starts at y = 150 (ink ends at %d), left of x = 100 "
              "(ink ends at %d)", box[3], box[2]);
    /* twice the scale, twice the ink */
    sp_canvas_reset(&c);
    sp_canvas_text_turned(&c, SP_TEXT_NORMAL, 10, 80, 2, 0, black, "HHHHHH");
    if (!err && !(err = raster(&c, f, 400, 200, 400, 200, &img))) {
        ink_box(&img, box);
        sp_image_free(&img);
    }
    sp_tap_ok(!err && fabs((box[2] - box[0]) / (double)lw - 2) < 0.05,
              "scale 2 draws the ink twice as wide (%d vs %d px)", box[2] - box[0], lw);
    /* appended: the pen moves */
    struct sp_canvas dst = {0};
    dst.font = f;
    sp_canvas_append(&dst, &c, 5, 6);
    const struct sp_item *it = &dst.items[dst.n_items - 1];
    sp_tap_ok(it->kind == SP_ITEM_TEXT && it->x == 15 && it->y == 86 && it->scale == 2 &&
                  !strcmp(dst.strings + it->text, "HHHHHH"),
              "sp_canvas_append moves turned text's pen and keeps its scale and string");
    sp_canvas_free(&dst);
    /* what no font has: refused, not a box */
    sp_canvas_reset(&c);
    sp_canvas_text_turned(&c, SP_TEXT_NORMAL, 10, 10, 1, 0, black, "a\xf4\x8f\xbf\xbd"); /* U+10FFFD */
    sp_tap_ok(c.err == SP_E_INPUT && c.n_items == 0,
              "a character no font has is refused (err %d, %d items)", c.err, c.n_items);
    /* a PDF of an image and turned text: the image as an image, the text real */
    sp_canvas_reset(&c);
    unsigned char *p = sp_canvas_image(&c, 10, 10, 60, 60, 3, 2);
    for (int k = 0; p && k < 6; k++) /* opaque grey */
        memcpy(p + 4 * k, (const unsigned char[4]){200, 200, 200, 255}, 4);
    sp_canvas_text_turned(&c, SP_TEXT_NORMAL, 80, 150, 0.5f, (float)(-M_PI / 2), black, "upward");
    char path[] = "/tmp/sp-draw-items-XXXXXX";
    int out_fd = mkstemp(path);
    struct sp_draw_cairo_desc d = {.canvas = &c, .font = f, .width = 200, .height = 200,
                                   .page_w = 100, .page_h = 100, .fd = out_fd, .path = path,
                                   .format = SP_FIGURE_PDF, .background = {1, 1, 1, 1}};
    err = out_fd < 0 ? SP_E_IO : sp_draw_cairo_write(&d);
    if (out_fd >= 0)
        close(out_fd);
    char cmd[256], out[4096] = "";
    snprintf(cmd, sizeof(cmd), "pdfimages -list %s 2>&1; pdftotext -raw %s - 2>&1", path, path);
    FILE *pp = err ? NULL : popen(cmd, "r");
    size_t n = pp ? fread(out, 1, sizeof(out) - 1, pp) : 0;
    out[n] = 0;
    if (pp)
        pclose(pp);
    const int good = !err && strstr(out, "image       3     2") && !strstr(out, "smask") &&
                     strstr(out, "upward");
    sp_tap_ok(good, "a PDF holds the opaque 3x2 image as an image without a soft mask, and the "
                    "turned text as text");
    for (char *line = good ? NULL : strtok(out, "\n"); line; line = strtok(NULL, "\n"))
        printf("# %s\n", line); /* pdfimages' and pdftotext's words, as TAP comments */
    unlink(path);
    sp_canvas_free(&c);
    sp_font_destroy(&f);
}

/* A list drawn in pieces (begin, shapes, keep_text, end) gives the pixels
 * of the whole list drawn at once, its text over every piece's shapes. */
static void test_pieces(void)
{
    struct sp_font *f = NULL;
    struct sp_font_desc fd = {.px = {20, 20, 20, 20}};
    struct sp_canvas whole = {0}, part = {0};
    struct sp_image a = {0}, b = {0};
    if (sp_font_make(&f, &fd)) {
        sp_tap_ok(0, "the embedded font is made");
        return;
    }
    whole.font = part.font = f;
    const float clip[4] = {10, 10, 190, 190}, grey[4] = {0.5f, 0.2f, 0.8f, 0.6f};
    struct sp_draw_cairo_desc d = {.canvas = &whole, .font = f, .width = 200, .height = 200,
                                   .path = "test", .background = {1, 1, 1, 1}};
    struct sp_draw_cairo *dc = NULL;
    int err = sp_draw_cairo_begin(&dc, &d, 200, 200);
    for (int k = 0; k < 2; k++) /* the text first: the shapes after it go under it */
        for (struct sp_canvas *c = k ? &part : &whole; c; c = NULL) {
            sp_canvas_text_turned(c, SP_TEXT_NORMAL, 20, 100, 1.5f, 0, black, "text on top");
            sp_canvas_clip(c, clip);
        }
    for (int i = 0; i < 400 && !err; i++) {
        const float x = (float)(i % 20) * 10, y = (float)(i / 20) * 10;
        sp_canvas_rect(&whole, x, y, x + 14, y + 14, grey);
        sp_canvas_rect(&part, x, y, x + 14, y + 14, grey);
        if (i % 97 == 96) { /* a piece drawn and dropped, its clip and text kept */
            err = sp_draw_cairo_shapes(dc, &part);
            sp_canvas_keep_text(&part);
        }
    }
    const int items = part.n_items;
    err = err ? err : sp_draw_cairo_end(&dc, &part, &a);
    if (!err)
        err = raster(&whole, f, 200, 200, 200, 200, &b);
    sp_tap_ok(!err && a.width == 200 && b.width == 200 &&
                  !memcmp(a.pixels, b.pixels, (size_t)a.stride * 200) && items < 400,
              "a list drawn in pieces of 97 shapes (%d items held at the end) gives the whole "
              "list's pixels, its clip and its text over every piece kept", items);
    sp_image_free(&a), sp_image_free(&b);
    sp_canvas_free(&whole), sp_canvas_free(&part);
    sp_font_destroy(&f);
}

/* GL draws no images or turned text: a list with either is refused. */
static void test_gl_refuses(void)
{
    struct sp_gl_context *ctx = NULL;
    struct sp_gl_api gl;
    struct sp_draw_gl *d = NULL;
    struct sp_canvas c = {0};
    if (sp_gl_context_make(&ctx, 32, 32, SP_GL_DEFAULT) || sp_gl_api_load(&gl, ctx) ||
        sp_draw_gl_make(&d, &gl, NULL, 32, 32)) {
        sp_tap_diag("no GL here: the GL backend's refusal is not tested");
        sp_draw_gl_destroy(&d);
        sp_gl_context_destroy(&ctx);
        return;
    }
    sp_canvas_line(&c, 0, 0, 10, 10, 1, black);
    const int plain = sp_draw_gl_list(d, &c, (const float[4]){1, 1, 1, 1});
    unsigned char *p = sp_canvas_image(&c, 0, 0, 4, 4, 1, 1);
    if (p)
        memset(p, 255, 4);
    sp_tap_ok(plain == 0 && sp_draw_gl_list(d, &c, (const float[4]){1, 1, 1, 1}) == SP_E_INPUT,
              "the GL backend draws a plain list and refuses one with an image");
    sp_draw_gl_destroy(&d);
    sp_gl_context_destroy(&ctx);
    sp_canvas_free(&c);
}

int main(void)
{
    test_image();
    test_turned();
    test_pieces();
    test_gl_refuses();
    return sp_tap_done();
}
