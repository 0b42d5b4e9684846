/* springpend: the off-screen renderer. Every shape is a capsule instance
 * (segment + radius + colour, see shaders/shape.vert), built on the CPU in
 * pixel coordinates into a canvas (canvas.h) and drawn by one program in two
 * instanced draw calls: the trail (with GL_MAX blending on dark or
 * transparent backgrounds, so no beads at its joints; pre-mixed with the
 * background and opaque on light ones), then everything else with
 * premultiplied "over". Text (text.h) is drawn last from its glyph atlas.
 * Panels, heads-up text and colourbar come from panels.c, placed by layout.c. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/render.h"
#include "canvas.h"
#include "embedded.h"
#include "gl_api.h"
#include "layout.h"
#include "panels.h"
#include "text.h"

enum {
    COIL_TURNS = 12,
    COIL_STEPS = 16,                      /* polyline segments per turn */
    COIL_SEGS = COIL_TURNS * COIL_STEPS,
    HATCHES = 7,
    MAX_STROBE = 400,                     /* stroboscopic images at most */
};

/* Sizes as fractions of the image's smaller side. */
#define BOB_RADIUS 0.022f
#define PIVOT_RADIUS 0.0065f
#define WIRE_RADIUS 0.0021f  /* half the spring wire's thickness */
#define COIL_RADIUS 0.016f   /* half the coil's width */
#define COIL_TILT 0.35f      /* helix seen from this much above: loop depth */
#define LEAD_TOP 0.012f
#define LEAD_BOTTOM 0.008f   /* beyond the bob's radius */
#define TRAIL_RADIUS 0.0022f
#define MOUNT_HALF 0.035f
#define MARGIN 0.06f         /* around the extent, besides the bob's radius */

struct sp_renderer {
    struct sp_gl_context *ctx;
    struct sp_gl_api gl;
    GLuint program, vao, vbo;
    int vbo_capacity;         /* instances the VBO holds */
    struct sp_canvas canvas;  /* this frame's shapes and glyphs */
    struct sp_font *font;     /* NULL when no text is drawn */
    struct sp_text_pass *text;
    struct sp_scene scene;    /* a copy: its [view] options */
    struct sp_view_extent extent;
    struct sp_palette pal;
    struct sp_layout layout;
    int laid_out;             /* layout and camera fitted (at the first frame) */
    char hud[SP_HUD_MAX_LINES][SP_HUD_LINE_BYTES];
    int hud_lines;
    int ss;                   /* supersampling factor, >= 1 */
    int width, height;        /* px drawn (output size times ss) */
    float unit;               /* the smaller side, px */
    double scale;             /* px per m */
    double ox, oy;            /* px of the world origin (the pivot) */
    double max_speed;         /* m/s, the top of the trail's colormap */
    int premix_trail;         /* light opaque background: no GL_MAX */
    struct sp_image out;      /* downsampled or un-premultiplied output, owned */
    const char *name;         /* GL_RENDERER */
};

/* Points the instance attributes at entry `first` of the bound VBO. */
static void set_instance_base(const struct sp_gl_api *gl, int first)
{
    const size_t base = (size_t)first * sizeof(struct sp_shape);
    const GLsizei stride = sizeof(struct sp_shape);

    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct sp_shape, seg)));
    gl->VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct sp_shape, style)));
    gl->VertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct sp_shape, color)));
}

/* Fits the extent plus a margin into rectangle v, equal scale on both axes. */
static void fit_camera(struct sp_renderer *r, const struct sp_rect *v)
{
    const struct sp_view_extent *e = &r->extent;
    const double margin = (BOB_RADIUS + MARGIN) * r->unit;
    const double ew = fmax(e->xmax - e->xmin, 1e-6);
    const double eh = fmax(e->ymax - e->ymin, 1e-6);
    const double aw = fmax(v->x1 - v->x0 - 2 * margin, 1.0);
    const double ah = fmax(v->y1 - v->y0 - 2 * margin, 1.0);

    r->scale = fmin(aw / ew, ah / eh);
    r->ox = 0.5 * (v->x0 + v->x1) - r->scale * 0.5 * (e->xmin + e->xmax);
    r->oy = 0.5 * (v->y0 + v->y1) + r->scale * 0.5 * (e->ymin + e->ymax);
}

/* Text sizes follow the frame's smaller side, with a floor for small frames. */
static void text_sizes(float unit, int px[SP_TEXT_SIZES])
{
    px[SP_TEXT_SMALL] = (int)fmaxf(9, roundf(0.0150f * unit));
    px[SP_TEXT_NORMAL] = (int)fmaxf(10, roundf(0.0175f * unit));
    px[SP_TEXT_LARGE] = (int)fmaxf(12, roundf(0.0230f * unit));
}

int sp_render_make(struct sp_renderer **out, const struct sp_render_desc *desc)
{
    struct sp_renderer *r = calloc(1, sizeof(*r));
    const struct sp_gl_api *gl;
    GLenum glerr;
    int err, px[SP_TEXT_SIZES];

    *out = NULL;
    if (!r) {
        sp_log_error("out of memory for the renderer");
        return SP_E_NOMEM;
    }
    if (desc->scene)
        r->scene = *desc->scene;
    else
        sp_scene_defaults(&r->scene);
    r->ss = desc->supersample > 1 ? desc->supersample : 1;
    r->width = desc->width * r->ss;
    r->height = desc->height * r->ss;
    if ((long)r->width * r->height > 7680L * 4320L * 4) {
        sp_log_error("%dx%d supersampled %d times is too large to draw; lower --scale",
                     desc->width, desc->height, r->ss);
        err = SP_E_INPUT;
        goto fail;
    }
    err = sp_gl_context_make(&r->ctx, r->width, r->height);
    if (!err)
        err = sp_gl_api_load(&r->gl, r->ctx);
    if (err)
        goto fail;
    gl = &r->gl;
    r->unit = (float)(r->width < r->height ? r->width : r->height);
    r->name = (const char *)gl->GetString(GL_RENDERER);
    r->extent = desc->extent;
    r->max_speed = desc->extent.max_speed > 0 ? desc->extent.max_speed : 1.0;
    sp_palette_get(&r->scene, &r->pal);
    r->premix_trail = r->pal.background[3] > 0 &&
                      0.3f * r->pal.background[0] + 0.6f * r->pal.background[1] +
                              0.1f * r->pal.background[2] > 0.35f;

    err = sp_gl_program_make(gl, sp_embed_shape_vert, sp_embed_shape_frag, "shape", &r->program);
    if (err)
        goto fail;
    gl->UseProgram(r->program);
    gl->Uniform2f(gl->GetUniformLocation(r->program, "u_size"),
                  (float)r->width, (float)r->height);
    gl->GenVertexArrays(1, &r->vao);
    gl->BindVertexArray(r->vao);
    gl->GenBuffers(1, &r->vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo);
    for (GLuint i = 0; i < 3; i++) {
        gl->EnableVertexAttribArray(i);
        gl->VertexAttribDivisor(i, 1);
    }
    if (r->scene.view.panels || r->scene.view.hud || r->scene.view.colorbar) {
        text_sizes(r->unit, px);
        err = sp_font_make(&r->font, px);
        if (!err)
            err = sp_text_pass_make(&r->text, gl, r->font, r->width, r->height);
        if (err)
            goto fail;
        r->canvas.font = r->font;
    }
    gl->Viewport(0, 0, r->width, r->height);
    gl->ClearColor(r->pal.background[0] * r->pal.background[3],
                   r->pal.background[1] * r->pal.background[3],
                   r->pal.background[2] * r->pal.background[3], r->pal.background[3]);
    gl->Enable(GL_BLEND);
    /* Premultiplied over, for alpha too (transparent backgrounds). */
    gl->BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("setting up GL failed with error 0x%04x", glerr);
        err = SP_E_GL;
        goto fail;
    }
    *out = r;
    return 0;

fail:
    sp_render_destroy(&r);
    return err;
}

/* Places the view, panels, heads-up text and colourbar (once: the
 * parameters do not change during a run). */
static void lay_out(struct sp_renderer *r, const struct sp_params *p)
{
    struct sp_layout_desc d = {.width = r->width, .height = r->height,
                               .panels = r->scene.view.panels};
    /* The view's width decides the HUD's wrapping: lay out once without it. */
    sp_layout_compute(&d, &r->layout);
    if (r->scene.view.hud) {
        const float w = r->layout.camera.x1 - r->layout.camera.x0 - 2 * r->layout.gap;
        r->hud_lines = sp_hud_lines(r->font, p, w, r->hud, SP_HUD_MAX_LINES);
        d.hud_height = sp_hud_height(r->font, r->hud_lines);
    }
    if (r->scene.view.colorbar)
        d.colorbar_width = sp_colorbar_width(r->font, r->unit, r->max_speed);
    sp_layout_compute(&d, &r->layout);
    fit_camera(r, &r->layout.camera);
    r->laid_out = 1;
}

/* ---- geometry, all in px ---- */

static void to_px(const struct sp_renderer *r, double x, double y, float p[2])
{
    p[0] = (float)(r->ox + r->scale * x);
    p[1] = (float)(r->oy - r->scale * y);
}

/* Trail segments, oldest first: colour by speed, fading and thinning with
 * age. A trail over the whole run (trail = all) fades less. */
static void put_trail(struct sp_renderer *r, const struct sp_trail *tr)
{
    const float w = TRAIL_RADIUS * r->unit;
    const float floor_alpha = r->scene.view.trail == SP_TRAIL_ALL ? 0.3f : 0.03f;
    const float *bg = r->pal.background;
    float a[2], b[2], color[4] = {0, 0, 0, 1};
    const struct sp_trail_point *p = sp_trail_at(tr, 0);

    to_px(r, p->x, p->y, a);
    for (int i = 1; i < tr->count; i++) {
        const struct sp_trail_point *q = sp_trail_at(tr, i);
        const float age = (float)i / (float)(tr->count - 1); /* 1 = newest */
        const float speed = 0.5f * (p->speed + q->speed);
        float alpha = floor_alpha + (1 - floor_alpha) * powf(age, 1.4f);

        to_px(r, q->x, q->y, b);
        sp_colormap(r->scene.view.colormap, r->pal.cmap_lo + (r->pal.cmap_hi - r->pal.cmap_lo) *
                    fminf(speed / (float)r->max_speed, 1.0f), color);
        if (r->premix_trail) {
            for (int k = 0; k < 3; k++)
                color[k] = bg[k] + alpha * (color[k] - bg[k]);
            alpha = 1;
        }
        color[3] = alpha;
        sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], w * (0.55f + 0.45f * age), color);
        a[0] = b[0];
        a[1] = b[1];
        p = q;
    }
}

/* Ceiling: a bar just above the pivot with hatch strokes above it. */
static void put_mount(struct sp_renderer *r, const float pv[2])
{
    const float u = r->unit, half = MOUNT_HALF * u, wr = WIRE_RADIUS * u;
    const float y = pv[1] - PIVOT_RADIUS * u - wr;
    const float hatch = 0.012f * u;

    sp_canvas_line(&r->canvas, pv[0] - half, y, pv[0] + half, y, 1.2f * wr, r->pal.mount);
    for (int i = 0; i < HATCHES; i++) {
        const float x = pv[0] - half + hatch + (2 * half - hatch) * i / (HATCHES - 1);
        sp_canvas_line(&r->canvas, x - hatch, y - wr - hatch, x, y - wr, 0.55f * wr, r->pal.mount);
    }
}

/* The spring from pivot pv to bob bb: straight leads, then COIL_TURNS turns of
 * a helix seen slightly from the side, its pitch stretching with the length.
 * Segments behind the axis are written first (darker), so the front ones
 * cover them. */
static void put_spring(struct sp_renderer *r, const float pv[2], const float bb[2])
{
    const float u = r->unit, wr = WIRE_RADIUS * u, rad = COIL_RADIUS * u;
    const float dx = bb[0] - pv[0], dy = bb[1] - pv[1];
    const float len = sqrtf(dx * dx + dy * dy);
    const float ax = len > 1e-3f ? dx / len : 0, ay = len > 1e-3f ? dy / len : 1;
    float lead0 = LEAD_TOP * u, lead1 = (BOB_RADIUS + LEAD_BOTTOM) * u;
    float c0[2], c1[2], coil;

    if (lead0 + lead1 > 0.3f * len) { /* short spring: shrink the leads */
        const float f = 0.3f * len / (lead0 + lead1);
        lead0 *= f;
        lead1 *= f;
    }
    coil = len - lead0 - lead1;
    c0[0] = pv[0] + ax * lead0;
    c0[1] = pv[1] + ay * lead0;
    c1[0] = bb[0] - ax * lead1;
    c1[1] = bb[1] - ay * lead1;
    sp_canvas_line(&r->canvas, pv[0], pv[1], c0[0], c0[1], wr, r->pal.wire_front);
    sp_canvas_line(&r->canvas, c1[0], c1[1], bb[0], bb[1], wr, r->pal.wire_front);

    for (int front = 0; front <= 1; front++) {
        float a[2] = {c0[0], c0[1]}, b[2];
        for (int i = 1; i <= COIL_SEGS; i++) {
            const float t = (float)i / COIL_SEGS;
            const float phase = 6.28318531f * COIL_TURNS * t;
            /* Ease the radius in and out over the first and last half turn. */
            const float ends = fminf(t, 1.0f - t) * 2.0f * COIL_TURNS;
            const float env = ends >= 1.0f ? 1.0f : ends * ends * (3 - 2 * ends);
            const float side = env * rad * sinf(phase);
            const float along = coil * t + env * rad * COIL_TILT * cosf(phase);
            const float mid = cosf(phase - 3.14159265f / COIL_STEPS); /* mid-segment */

            b[0] = c0[0] + ax * along - ay * side;
            b[1] = c0[1] + ay * along + ax * side;
            if ((mid > 0) == front)
                sp_canvas_line(&r->canvas, a[0], a[1], b[0], b[1], wr,
                               front ? r->pal.wire_front : r->pal.wire_back);
            a[0] = b[0];
            a[1] = b[1];
        }
    }
}

/* The bob every view.strobe seconds back from now, fading with age. */
static void put_strobe(struct sp_renderer *r, const struct sp_history *h)
{
    const double dt = r->scene.view.strobe;
    float p[2], color[4];
    if (!h || h->count < 2 || dt <= 0)
        return;
    const double now = h->samples[h->count - 1].t;
    const int n = (int)fmin(floor(now / dt + 1e-9), MAX_STROBE);
    int j = h->count - 1;
    for (int k = n; k >= 1; k--) { /* oldest first, so newer ones cover them */
        const double t = now - k * dt;
        const float age = 1.0f - (float)k / (float)(n + 1);
        /* the sample nearest to t (samples are in time order) */
        int lo = 0, hi = h->count - 1;
        while (hi - lo > 1) {
            j = (lo + hi) / 2;
            if (h->samples[j].t <= t)
                lo = j;
            else
                hi = j;
        }
        j = t - h->samples[lo].t <= h->samples[hi].t - t ? lo : hi;
        to_px(r, h->samples[j].x, h->samples[j].y, p);
        memcpy(color, r->pal.bob, sizeof(color));
        color[3] = 0.12f + 0.5f * age;
        sp_canvas_disc(&r->canvas, p[0], p[1], 0.8f * BOB_RADIUS * r->unit, 0, color);
    }
}

/* Box-filters the ss x ss blocks of src into r->out, un-premultiplying. */
static void resolve(struct sp_renderer *r, const uint8_t *src, int stride)
{
    const int ss = r->ss, w = r->out.width, h = r->out.height;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            unsigned sum[4] = {0, 0, 0, 0};
            for (int j = 0; j < ss; j++) {
                const uint8_t *s = src + (size_t)(y * ss + j) * stride + 4 * x * ss;
                for (int i = 0; i < ss; i++)
                    for (int c = 0; c < 4; c++)
                        sum[c] += s[4 * i + c];
            }
            uint8_t *d = r->out.pixels + (size_t)y * r->out.stride + 4 * x;
            const unsigned n = (unsigned)(ss * ss), a = sum[3];
            for (int c = 0; c < 3; c++)
                d[c] = (uint8_t)(a ? (sum[c] * 255u + a / 2) / a > 255 ? 255 : (sum[c] * 255u + a / 2) / a : 0);
            d[3] = (uint8_t)((a + n / 2) / n);
        }
}

int sp_render_draw(struct sp_renderer *r, const struct sp_frame *f,
                   struct sp_image *img)
{
    const struct sp_gl_api *gl = &r->gl;
    struct sp_canvas *cv = &r->canvas;
    int trail_segs, n_shapes, stride, err;
    float pv[2], bb[2];
    GLenum glerr;
    uint8_t *pixels;

    err = sp_gl_context_bind(r->ctx);
    if (err)
        return err;
    if (!r->laid_out)
        lay_out(r, f->params);
    sp_canvas_reset(cv);
    const double yp = sp_pivot_y(f->params, f->state.t); /* a driven pivot moves */
    to_px(r, 0, yp, pv);
    to_px(r, f->state.x, f->state.y + yp, bb);
    if (f->trail && f->trail->count > 1)
        put_trail(r, f->trail);
    trail_segs = cv->n_shapes;
    put_strobe(r, f->history);
    put_mount(r, pv);
    put_spring(r, pv, bb);
    sp_canvas_disc(cv, pv[0], pv[1], PIVOT_RADIUS * r->unit, 0, r->pal.pivot);
    sp_canvas_disc(cv, bb[0], bb[1], BOB_RADIUS * r->unit, 1, r->pal.bob);
    if (r->scene.view.panels)
        sp_panels_draw(cv, &r->layout, f, &r->extent, &r->pal, r->unit);
    if (r->scene.view.hud)
        sp_hud_draw(cv, &r->layout.hud, f->state.t, r->hud, r->hud_lines, f->params, &r->pal);
    if (r->scene.view.colorbar)
        sp_colorbar_draw(cv, &r->layout.colorbar, r->scene.view.colormap, r->max_speed,
                         &r->pal, r->unit);
    if (cv->err) {
        sp_log_error("out of memory for %d shapes and %d glyphs", cv->n_shapes, cv->n_quads);
        return cv->err;
    }
    n_shapes = cv->n_shapes;

    gl->UseProgram(r->program);
    gl->BindVertexArray(r->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, r->vbo);
    if (n_shapes > r->vbo_capacity) {
        r->vbo_capacity = 2 * n_shapes;
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)r->vbo_capacity * sizeof(struct sp_shape),
                       NULL, GL_STREAM_DRAW);
    }
    gl->BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)n_shapes * sizeof(struct sp_shape),
                      cv->shapes);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    if (trail_segs) {
        if (!r->premix_trail)
            gl->BlendEquation(GL_MAX);
        set_instance_base(gl, 0);
        gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, trail_segs);
        gl->BlendEquation(GL_FUNC_ADD);
    }
    set_instance_base(gl, trail_segs);
    gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(n_shapes - trail_segs));
    if (r->text)
        sp_text_pass_draw(r->text, cv->quads, cv->n_quads);
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("drawing a frame failed with GL error 0x%04x", glerr);
        return SP_E_GL;
    }
    pixels = sp_gl_context_pixels(r->ctx, &stride);
    if (r->ss == 1 && r->pal.background[3] >= 1) {
        *img = (struct sp_image){pixels, r->width, r->height, stride};
        return 0;
    }
    /* Supersampled or transparent: average down and un-premultiply. */
    if (!r->out.pixels) {
        err = sp_image_alloc(&r->out, r->width / r->ss, r->height / r->ss);
        if (err)
            return err;
    }
    resolve(r, pixels, stride);
    *img = r->out;
    return 0;
}

const char *sp_render_renderer_name(const struct sp_renderer *r)
{
    return r->name ? r->name : "unknown";
}

void sp_render_destroy(struct sp_renderer **rp)
{
    struct sp_renderer *r = *rp;

    if (!r)
        return;
    /* The programs, VAOs, VBOs and texture die with their context. */
    sp_text_pass_destroy(&r->text);
    sp_font_destroy(&r->font);
    sp_gl_context_destroy(&r->ctx);
    sp_canvas_free(&r->canvas);
    sp_image_free(&r->out);
    free(r);
    *rp = NULL;
}
