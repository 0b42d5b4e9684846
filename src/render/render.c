/* springpend: the off-screen renderer: a frame composed on the CPU into a
 * draw list (compose.c) and drawn by the list's GL backend (draw_gl.c) into a
 * headless GL context (gl_context.h), then, when supersampled or
 * transparent, averaged down and un-premultiplied. */
#include <stdlib.h>
#include <string.h>

#include "base/clock.h"
#include "springpend/common.h"
#include "springpend/render.h"
#include "frame/compose.h"
#include "draw_gl.h"
#include "gl_api.h"
#include "yuv_gl.h"

struct sp_renderer {
    struct sp_gl_context *ctx;
    struct sp_gl_api gl;
    struct sp_compose_cells *composer; /* one cell, or scenes side by side */
    struct sp_draw_gl *draw;
    int ss;                   /* supersampling factor, >= 1 */
    int width, height;        /* px drawn (output size times ss) */
    int opaque;               /* the background is opaque */
    struct sp_image out;      /* downsampled or un-premultiplied output, owned */
    struct sp_image target;   /* the caller's buffer for the output (see
                                 sp_render_target); pixels NULL = none */
    struct sp_yuv_gl *yuv;    /* the YUV pass, made for the first YUV target */
    const char *name;         /* GL_RENDERER */
    const char *version;      /* GL_VERSION */
    double compose_s, draw_s; /* s spent so far (sp_render_stats) */
    int frames;               /* drawn so far */
    int glyphs_first;         /* glyphs the first frame rasterised */
    double raster_first_s;    /* s that took */
};

int sp_render_make(struct sp_renderer **out, const struct sp_render_desc *desc)
{
    struct sp_renderer *r = calloc(1, sizeof(*r));
    int err;

    *out = NULL;
    if (!r) {
        sp_log_error("out of memory for the renderer");
        return SP_E_NOMEM;
    }
    r->ss = desc->supersample > 1 ? desc->supersample : 1;
    r->width = desc->width * r->ss;
    r->height = desc->height * r->ss;
    if ((long)r->width * r->height > 7680L * 4320L * 4) {
        sp_log_error("%dx%d supersampled %d times is too large to draw; lower --scale",
                     desc->width, desc->height, r->ss);
        err = SP_E_INPUT;
        goto fail;
    }
    err = sp_compose_cells_make(&r->composer, &(struct sp_compose_desc){
        .width = r->width, .height = r->height, .extent = desc->extent, .look = desc->look,
        .supersample = r->ss}, desc->looks, desc->cells);
    if (!err)
        err = sp_gl_context_make(&r->ctx, r->width, r->height, desc->gl);
    if (!err)
        err = sp_gl_api_load(&r->gl, r->ctx);
    if (err)
        goto fail;
    r->name = (const char *)r->gl.GetString(GL_RENDERER);
    r->version = (const char *)r->gl.GetString(GL_VERSION);
    r->opaque = sp_compose_cells_palette(r->composer)->background[3] >= 1;
    err = sp_draw_gl_make(&r->draw, &r->gl, sp_compose_cells_font(r->composer), r->width, r->height);
    if (err)
        goto fail;
    /* SPRINGPEND_DRAW_CACHE=0 draws every item of every frame: the
     * reference the cached frames are tested against */
    const char *cache = getenv("SPRINGPEND_DRAW_CACHE");
    sp_draw_gl_cache(r->draw, !(cache && !strcmp(cache, "0")));
    *out = r;
    return 0;

fail:
    sp_render_destroy(&r);
    return err;
}

/* Box-filters the ss x ss blocks of src into out, un-premultiplying. */
static void resolve(const struct sp_renderer *r, const uint8_t *src, int stride,
                    const struct sp_image *out)
{
    const int ss = r->ss, w = out->width, h = out->height;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned sum[4] = {0, 0, 0, 0};
            for (int j = 0; j < ss; j++) {
                const uint8_t *s = src + (size_t)(y * ss + j) * stride + 4 * x * ss;
                for (int i = 0; i < ss; i++)
                    for (int c = 0; c < 4; c++)
                        sum[c] += s[4 * i + c];
            }
            uint8_t *d = out->pixels + (size_t)y * out->stride + 4 * x;
            const unsigned n = (unsigned)(ss * ss), a = sum[3];
            for (int c = 0; c < 3; c++)
                d[c] = (uint8_t)(a ? (sum[c] * 255u + a / 2) / a > 255 ? 255 : (sum[c] * 255u + a / 2) / a : 0);
            d[3] = (uint8_t)((a + n / 2) / n);
        }
}

/* GL draws the output itself: not supersampled, opaque background. */
static int direct(const struct sp_renderer *r)
{
    return r->ss == 1 && r->opaque;
}

int sp_render_draw(struct sp_renderer *r, const struct sp_frame *f,
                   struct sp_image *img)
{
    const struct sp_canvas *cv;
    int stride, err;
    uint8_t *pixels;
    double t0 = sp_clock_s(), t1;

    err = sp_gl_context_bind(r->ctx);
    if (!err)
        err = sp_compose_cells_frame(r->composer, f, &cv);
    t1 = sp_clock_s();
    r->compose_s += t1 - t0;
    if (!r->frames++ && sp_compose_cells_font(r->composer))
        sp_font_raster_stats(sp_compose_cells_font(r->composer), &r->glyphs_first, &r->raster_first_s);
    if (!err)
        err = sp_draw_gl_list(r->draw, cv, sp_compose_cells_palette(r->composer)->background);
    if (err)
        return err;
    if (r->target.pixels && r->target.format == SP_IMAGE_YUV420) {
        /* the last pass converts on the GPU; 1.5 bytes a pixel come back */
        sp_yuv_gl_read(r->yuv, sp_gl_context_framebuffer(r->ctx), r->target.pixels);
        *img = r->target;
        r->draw_s += sp_clock_s() - t1;
        return 0;
    }
    pixels = sp_gl_context_pixels(r->ctx, &stride);
    if (direct(r)) {
        *img = (struct sp_image){pixels, r->width, r->height, stride, SP_IMAGE_RGBA};
        r->draw_s += sp_clock_s() - t1;
        return 0;
    }
    /* Supersampled or transparent: average down and un-premultiply. */
    if (!r->target.pixels && !r->out.pixels) {
        err = sp_image_alloc(&r->out, r->width / r->ss, r->height / r->ss);
        if (err)
            return err;
    }
    *img = r->target.pixels ? r->target : r->out;
    resolve(r, pixels, stride, img);
    r->draw_s += sp_clock_s() - t1;
    return 0;
}

void sp_render_stats(const struct sp_renderer *r, struct sp_render_stats *out)
{
    struct sp_draw_cache_stats d;
    sp_draw_gl_stats(r->draw, &d);
    *out = (struct sp_render_stats){.compose_s = r->compose_s, .draw_s = r->draw_s,
                                    .cached = d.cached, .redrawn = d.redrawn,
                                    .uncached = d.uncached, .appended = d.appended,
                                    .unchanged = d.unchanged, .glyphs_first = r->glyphs_first,
                                    .raster_first_s = r->raster_first_s};
    if (sp_compose_cells_font(r->composer)) {
        sp_font_raster_stats(sp_compose_cells_font(r->composer), &out->glyphs, &out->raster_s);
        sp_font_shape_stats(sp_compose_cells_font(r->composer), &out->lines_shaped,
                            &out->lines_composed);
    }
}

void sp_render_fonts(const struct sp_renderer *r, char *buf, size_t size)
{
    if (size)
        buf[0] = 0;
    if (sp_compose_cells_font(r->composer))
        sp_font_files(sp_compose_cells_font(r->composer), buf, size);
}

int sp_render_font_environment(const struct sp_renderer *r, char *buf, size_t size)
{
    return sp_compose_cells_font(r->composer)
               ? sp_font_environment(sp_compose_cells_font(r->composer), buf, size)
               : 0;
}

void sp_render_overlay(const struct sp_renderer *r, char *buf, size_t size)
{
    sp_compose_cells_overlay(r->composer, buf, size);
}

int sp_render_target(struct sp_renderer *r, const struct sp_image *dst)
{
    const int w = r->width / r->ss, h = r->height / r->ss;
    const int yuv = dst && dst->format == SP_IMAGE_YUV420;
    if (dst && (dst->width != w || dst->height != h || dst->stride != (yuv ? (w + 7) & ~7 : 4 * w) ||
                (dst->format != SP_IMAGE_RGBA && !yuv))) {
        sp_log_error("render target %dx%d (stride %d) is not the renderer's "
                     "%dx%d", dst->width, dst->height, dst->stride, w, h);
        return SP_E_INPUT;
    }
    if (yuv && !r->opaque) {
        sp_log_error("a transparent background cannot be drawn into YUV 4:2:0 (no alpha)");
        return SP_E_INPUT;
    }
    int err = sp_gl_context_bind(r->ctx);
    if (!err && yuv && !r->yuv) {
        err = sp_yuv_gl_make(&r->yuv, &r->gl, w, h, r->ss);
        sp_gl_offscreen_bind(sp_gl_context_framebuffer(r->ctx)); /* draws go there */
    }
    if (err)
        return err;
    r->target = dst ? *dst : (struct sp_image){0};
    if (direct(r))
        sp_gl_context_target(r->ctx, dst && !yuv ? dst->pixels : NULL);
    return 0;
}

const char *sp_render_renderer_name(const struct sp_renderer *r)
{
    return r->name ? r->name : "unknown";
}

const char *sp_render_gl_version(const struct sp_renderer *r)
{
    return r->version ? r->version : "unknown";
}

int sp_render_probe(enum sp_gl gl, char *renderer, size_t renderer_size, char *version,
                    size_t version_size)
{
    struct sp_gl_context *ctx = NULL;
    struct sp_gl_api api;
    int err = sp_gl_context_make(&ctx, 16, 16, gl);
    if (!err)
        err = sp_gl_api_load(&api, ctx);
    if (!err) {
        const char *n = (const char *)api.GetString(GL_RENDERER);
        const char *v = (const char *)api.GetString(GL_VERSION);
        snprintf(renderer, renderer_size, "%s", n ? n : "unknown");
        snprintf(version, version_size, "%s", v ? v : "unknown");
    }
    sp_gl_context_destroy(&ctx);
    return err;
}

void sp_render_destroy(struct sp_renderer **rp)
{
    struct sp_renderer *r = *rp;

    if (!r)
        return;
    /* The programs, VAOs, VBOs and texture die with their context. */
    sp_draw_gl_destroy(&r->draw);
    sp_yuv_gl_destroy(&r->yuv);
    sp_gl_context_destroy(&r->ctx);
    sp_compose_cells_destroy(&r->composer);
    sp_image_free(&r->out);
    free(r);
    *rp = NULL;
}
