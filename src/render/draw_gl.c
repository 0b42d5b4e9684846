/* springpend (internal): the draw list drawn with GL. See draw_gl.h. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "base/array.h"
#include "draw_gl.h"
#include "base/embedded.h"

enum { TILE = 32, MAX_FILLS = 200 }; /* px: the grain of copies and fills */
enum { DTILE = 16 }; /* px: the grain of the damaged rectangles */

/* A rectangle of the static cache: x0, y0, x1, y1 px; v = 1: copied from the
 * cache, v >= 2: filled with fills[v - 2]. */
struct fill_rect {
    float r[4];
    int v;
};

struct instances {
    GLuint program, vao, vbo;
    int capacity; /* instances the VBO holds */
};

struct sp_draw_gl {
    const struct sp_gl_api *gl;
    struct instances shape, text;
    GLuint atlas;
    const struct sp_font *font;  /* the glyph cache the atlas copies; NULL = no text */
    int atlas_w, atlas_h;        /* texels uploaded */
    unsigned atlas_version;      /* sp_font_atlas's version uploaded */
    GLuint accum_fbo, accum_tex; /* SP_LAYER_ACCUM's picture; 0 = none yet */
    /* The static cache: the accumulated picture (or the background) with the
     * static layer drawn over it, then the settled layer (appended to each
     * frame), copied under each frame's dynamic layer. */
    GLuint base_fbo, base_tex;   /* 0 = none yet */
    struct instances patch;      /* draws layers as they are (struct patch) */
    int n_patches;               /* the static cache's, after instance 0 */
    struct fill_rect *rects;     /* where base differs from the background (no
                                    accumulated layer): copied, or filled */
    int n_rects, cap_rects;
    float fills[MAX_FILLS][4];   /* the opaque colours of filled rectangles */
    int n_fills;
    unsigned char *tiles;        /* scratch: what base holds in TILE px squares */
    int base_valid;              /* base holds `key`'s static layer */
    unsigned char *key;          /* the static layer it was drawn from */
    size_t n_key, cap_key;       /* bytes */
    unsigned char *next;         /* this frame's, compared with key */
    size_t n_next, cap_next;     /* bytes */
    /* The target keeps its pixels from frame to frame (both backends draw
     * into a framebuffer object like base's, gl_offscreen.h, read back
     * after each frame). After a cached frame it holds base plus that
     * frame's dynamic items inside `damage`: the next frame restores base
     * there only (and where base grew: new settled or accumulated items),
     * instead of clearing and copying all of base. */
    struct instances restore;    /* draws `damage` with the patch program */
    struct patch *damage;        /* the last frame's dynamic items' tiles */
    int n_damage, cap_damage;
    int kept;                    /* the target holds base + damage, as above */
    unsigned char *dtiles;       /* scratch: DTILE px squares touched */
    struct box *boxes;           /* per item of the list: what it may touch */
    int cap_boxes;
    /* The settled layer as base holds it: per settled item in list order, a
     * struct settled_head and the shapes drawn. A frame whose settled items
     * start with these, unchanged, draws only the rest into base. */
    unsigned char *settled;
    size_t n_settled, cap_settled; /* bytes */
    int *settled_old;            /* scratch: per settled item, shapes base holds */
    int cap_settled_old;
    /* The last cached frame's dynamic items as the target holds them: per
     * dynamic item in list order, a struct dyn_head and its shapes or glyph
     * quads. An item of this frame equal to its counterpart there (same
     * place in the order, byte for byte) is left as it is: the target is
     * restored and the item redrawn only where something else changed. */
    unsigned char *dyn;
    size_t n_dyn, cap_dyn;     /* bytes */
    int n_dyn_items;
    unsigned char *same;       /* scratch: per item of the list, 1 = unchanged */
    int cap_same, any_same;
    struct sp_item *items;       /* scratch: the list's items, those the cache
                                    cannot order moved to the dynamic layer
                                    (lift_items) */
    int cap_items;
    int cache;                   /* 1 = cache the static layer */
    struct sp_draw_gl_stats stats;
    int width, height;           /* px */
};

/* Compiles the pair, sets u_size, makes a VAO with three per-instance
 * attributes and its buffer. */
static int instances_make(const struct sp_gl_api *gl, struct instances *in, const char *vs,
                          const char *fs, const char *name, int width, int height)
{
    int err = sp_gl_program_make(gl, vs, fs, name, &in->program);
    if (err)
        return err;
    gl->UseProgram(in->program);
    gl->Uniform2f(gl->GetUniformLocation(in->program, "u_size"), (float)width, (float)height);
    gl->GenVertexArrays(1, &in->vao);
    gl->BindVertexArray(in->vao);
    gl->GenBuffers(1, &in->vbo);
    gl->BindBuffer(GL_ARRAY_BUFFER, in->vbo);
    for (GLuint i = 0; i < 3; i++) {
        gl->EnableVertexAttribArray(i);
        gl->VertexAttribDivisor(i, 1);
    }
    return 0;
}

/* Binds in's program and buffer and uploads n items of `size` bytes. */
static void instances_upload(const struct sp_gl_api *gl, struct instances *in, const void *data,
                             int n, size_t size)
{
    gl->UseProgram(in->program);
    gl->BindVertexArray(in->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, in->vbo);
    if (n > in->capacity) {
        in->capacity = 2 * n;
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)in->capacity * (GLsizeiptr)size, NULL,
                       GL_STREAM_DRAW);
    }
    gl->BufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)n * (GLsizeiptr)size, data);
}

/* Points the attributes at instance `first` of the bound buffer: three vec
 * attributes at the given offsets of a `stride`-byte record. */
static void instances_base(const struct sp_gl_api *gl, int first, GLsizei stride,
                           const size_t off[3], const GLint comps[3])
{
    const size_t base = (size_t)first * (size_t)stride;
    for (GLuint i = 0; i < 3; i++)
        gl->VertexAttribPointer(i, comps[i], GL_FLOAT, GL_FALSE, stride,
                                (const void *)(base + off[i]));
}

static void text_base(const struct sp_gl_api *gl, int first)
{
    static const size_t off[3] = {offsetof(struct sp_glyph_quad, rect),
                                  offsetof(struct sp_glyph_quad, uv),
                                  offsetof(struct sp_glyph_quad, color)};
    static const GLint comps[3] = {4, 4, 4};
    instances_base(gl, first, sizeof(struct sp_glyph_quad), off, comps);
}

static void shape_base(const struct sp_gl_api *gl, int first)
{
    static const size_t off[3] = {offsetof(struct sp_shape, seg), offsetof(struct sp_shape, style),
                                  offsetof(struct sp_shape, color)};
    static const GLint comps[3] = {4, 2, 4};
    instances_base(gl, first, sizeof(struct sp_shape), off, comps);
}

/* Uploads the glyph cache when it gained glyphs or grew since the last
 * upload (glyphs are rasterised on demand while frames are composed; their
 * places in it never move, so quads made earlier stay right). */
static void atlas_sync(struct sp_draw_gl *d)
{
    const struct sp_gl_api *gl = d->gl;
    int aw, ah;
    unsigned version;
    const uint8_t *atlas = sp_font_atlas(d->font, &aw, &ah, &version);
    if (!d->atlas || (version == d->atlas_version && aw == d->atlas_w && ah == d->atlas_h))
        return;
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, d->atlas);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_R8, aw, ah, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
    if (aw != d->atlas_w || ah != d->atlas_h) {
        gl->UseProgram(d->text.program);
        gl->Uniform2f(gl->GetUniformLocation(d->text.program, "u_atlas"), (float)aw, (float)ah);
    }
    d->atlas_w = aw, d->atlas_h = ah, d->atlas_version = version;
}

int sp_draw_gl_make(struct sp_draw_gl **out, const struct sp_gl_api *gl,
                    const struct sp_font *font, int width, int height)
{
    struct sp_draw_gl *d = calloc(1, sizeof(*d));
    int err;
    *out = NULL;
    if (!d) {
        sp_log_error("out of memory for the GL backend");
        return SP_E_NOMEM;
    }
    d->gl = gl;
    d->width = width;
    d->height = height;
    d->cache = 1;
    err = instances_make(gl, &d->shape, sp_embed_shape_vert, sp_embed_shape_frag, "shape",
                         width, height);
    if (!err && font) {
        err = instances_make(gl, &d->text, sp_embed_text_vert, sp_embed_text_frag, "text",
                             width, height);
        if (!err) {
            d->font = font;
            gl->Uniform1i(gl->GetUniformLocation(d->text.program, "u_atlas_tex"), 0);
            gl->ActiveTexture(GL_TEXTURE0);
            gl->GenTextures(1, &d->atlas);
            gl->BindTexture(GL_TEXTURE_2D, d->atlas);
            gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            atlas_sync(d);
            text_base(gl, 0);
        }
    }
    if (err) {
        free(d);
        return err;
    }
    gl->Viewport(0, 0, width, height);
    gl->Enable(GL_BLEND);
    /* Premultiplied over, for alpha too (transparent backgrounds). */
    gl->BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    *out = d;
    return 0;
}

/* Sets the scissor for a CLIP item (rect in px, y down) of a height px frame. */
static void clip(const struct sp_gl_api *gl, const float r[4], int height)
{
    if (r[2] <= r[0]) {
        gl->Disable(GL_SCISSOR_TEST);
        return;
    }
    const GLint x0 = (GLint)floorf(r[0]), x1 = (GLint)ceilf(r[2]);
    const GLint y0 = (GLint)floorf(r[1]), y1 = (GLint)ceilf(r[3]);
    gl->Enable(GL_SCISSOR_TEST);
    /* GL counts rows from the bottom; a collapsed rectangle shows nothing */
    gl->Scissor(x0, height - y1, x1 > x0 ? x1 - x0 : 0, y1 > y0 ? y1 - y0 : 0);
}

/* Layers as bits, to pick the items a pass draws. */
#define LAYER_BIT(l) (1u << (l))
#define STATIC_BIT LAYER_BIT(SP_LAYER_STATIC)
#define DYNAMIC_BIT LAYER_BIT(SP_LAYER_DYNAMIC)
#define ACCUM_BIT LAYER_BIT(SP_LAYER_ACCUM)
#define SETTLED_BIT LAYER_BIT(SP_LAYER_SETTLED)

/* One instanced draw per run of shape items of the layers in `layers` with
 * the same blending and clip. Clip items apply except to the accumulated
 * layer (never clipped). The shape program must be bound. */
static void draw_shapes(const struct sp_gl_api *gl, const struct sp_canvas *c, unsigned layers,
                        int height)
{
    const int clipped = layers != ACCUM_BIT;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP && clipped)
            clip(gl, it->clip, height);
        if (it->kind == SP_ITEM_TEXT || it->kind == SP_ITEM_CLIP || !(LAYER_BIT(it->layer) & layers))
            continue;
        int end = it->first + it->count, j = i + 1;
        while (j < c->n_items && c->items[j].kind != SP_ITEM_CLIP &&
               (c->items[j].kind == SP_ITEM_TEXT ||
                ((LAYER_BIT(c->items[j].layer) & layers) && c->items[j].blend == it->blend))) {
            if (c->items[j].kind != SP_ITEM_TEXT)
                end = c->items[j].first + c->items[j].count;
            j++;
        }
        const int start = it->first;
        if (it->blend == SP_BLEND_MAX)
            gl->BlendEquation(GL_MAX);
        shape_base(gl, start);
        gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(end - start));
        gl->BlendEquation(GL_FUNC_ADD);
        i = j - 1;
    }
    gl->Disable(GL_SCISSOR_TEST);
}

/* One instanced draw per run of text items of the layers in `layers` (the
 * quads are uploaded). */
static void draw_text(const struct sp_gl_api *gl, const struct instances *text, GLuint atlas,
                      const struct sp_canvas *c, unsigned layers)
{
    int start = -1, end = 0;
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, atlas);
    gl->UseProgram(text->program);
    gl->BindVertexArray(text->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, text->vbo);
    for (int i = 0; i <= c->n_items; i++) {
        const struct sp_item *it = i < c->n_items ? &c->items[i] : NULL;
        if (it && (it->kind != SP_ITEM_TEXT || !it->count))
            continue;
        if (it && (LAYER_BIT(it->layer) & layers) && (start < 0 || it->first == end)) {
            if (start < 0)
                start = it->first;
            end = it->first + it->count;
            continue;
        }
        if (start >= 0) { /* a run ends */
            text_base(gl, start);
            gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(end - start));
            start = -1;
        }
        if (it && (LAYER_BIT(it->layer) & layers)) {
            start = it->first;
            end = it->first + it->count;
        }
    }
    text_base(gl, 0);
}

/* Makes a texture of the target's size and a framebuffer for it, cleared
 * to bg (premultiplied). 0 or SP_E_GL (logged). */
static int layer_make(struct sp_draw_gl *d, GLuint *fbo, GLuint *tex, const float bg[4],
                      const char *what)
{
    const struct sp_gl_api *gl = d->gl;
    gl->GenTextures(1, tex);
    gl->BindTexture(GL_TEXTURE_2D, *tex);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, d->width, d->height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST); /* complete: no mipmaps */
    gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    gl->GenFramebuffers(1, fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, *fbo);
    gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, *tex, 0);
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        sp_log_error("GL cannot make a %dx%d framebuffer for %s", d->width, d->height, what);
        return SP_E_GL;
    }
    gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    return 0;
}

struct box {
    float x0, y0, x1, y1; /* px; x1 < x0 = touches nothing */
    float clip[4];        /* the clip the item is drawn under (x1 <= x0 = none) */
};

/* Patches of a layer drawn into the bound framebuffer as they are, in one
 * instanced draw without blending: each a rectangle (px, whole pixels) that
 * copies the layer's texture texel for pixel, or fills with an opaque
 * colour. Instance 0 is the whole frame (a copy); 1.. the static cache's
 * rectangles. (glBlitFramebuffer of a whole 1080p frame cost llvmpipe
 * about 9 ms of CPU, and a draw or clear per rectangle nearly as much.) */
static const char patch_vs[] =
    "#version 330 core\n"
    "layout(location = 0) in vec4 a_rect;\n"
    "layout(location = 1) in vec4 a_fill;\n"
    "uniform vec2 u_size;\n"
    "flat out vec4 v_fill;\n"
    "void main() {\n"
    "    vec2 c = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1));\n"
    "    vec2 p = mix(a_rect.xy, a_rect.zw, c);\n"
    "    gl_Position = vec4(2.0 * p.x / u_size.x - 1.0, 1.0 - 2.0 * p.y / u_size.y, 0.0, 1.0);\n"
    "    v_fill = a_fill;\n"
    "}\n";
static const char patch_fs[] =
    "#version 330 core\n"
    "uniform sampler2D u_layer;\n"
    "flat in vec4 v_fill;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    o_color = v_fill.a < 0.0 ? texelFetch(u_layer, ivec2(gl_FragCoord.xy), 0) : v_fill;\n"
    "}\n";

struct patch {
    float rect[4]; /* x0, y0, x1, y1 px */
    float fill[4]; /* opaque RGBA; alpha < 0 = copy the texture */
};

/* Makes the patch program and uploads instance 0 plus n patches. */
static int patches_upload(struct sp_draw_gl *d, const struct patch *p, int n)
{
    const struct sp_gl_api *gl = d->gl;
    if (!d->patch.program) {
        int err = sp_gl_program_make(gl, patch_vs, patch_fs, "layer patch", &d->patch.program);
        if (err)
            return err;
        gl->UseProgram(d->patch.program);
        gl->Uniform2f(gl->GetUniformLocation(d->patch.program, "u_size"), (float)d->width,
                      (float)d->height);
        gl->Uniform1i(gl->GetUniformLocation(d->patch.program, "u_layer"), 0);
        gl->GenVertexArrays(1, &d->patch.vao);
        gl->BindVertexArray(d->patch.vao);
        gl->GenBuffers(1, &d->patch.vbo);
        gl->BindBuffer(GL_ARRAY_BUFFER, d->patch.vbo);
        for (GLuint i = 0; i < 2; i++) {
            gl->EnableVertexAttribArray(i);
            gl->VertexAttribDivisor(i, 1);
        }
    }
    gl->UseProgram(d->patch.program);
    gl->BindVertexArray(d->patch.vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, d->patch.vbo);
    if (n + 1 > d->patch.capacity) {
        d->patch.capacity = 2 * (n + 1);
        gl->BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)d->patch.capacity * (GLsizeiptr)sizeof(*p), NULL,
                       GL_STATIC_DRAW);
    }
    const struct patch whole = {{0, 0, (float)d->width, (float)d->height}, {0, 0, 0, -1}};
    gl->BufferSubData(GL_ARRAY_BUFFER, 0, sizeof(whole), &whole);
    if (n)
        gl->BufferSubData(GL_ARRAY_BUFFER, sizeof(whole), (GLsizeiptr)n * (GLsizeiptr)sizeof(*p), p);
    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(*p), (const void *)offsetof(struct patch, rect));
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(*p), (const void *)offsetof(struct patch, fill));
    return 0;
}

/* Draws patches first..first+n-1 of the layer texture tex. */
static int patches_draw(struct sp_draw_gl *d, GLuint tex, int first, int n)
{
    const struct sp_gl_api *gl = d->gl;
    int err = d->patch.program ? 0 : patches_upload(d, NULL, 0);
    if (err || n <= 0)
        return err;
    gl->UseProgram(d->patch.program);
    gl->BindVertexArray(d->patch.vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, d->patch.vbo);
    static const size_t off[3] = {offsetof(struct patch, rect), offsetof(struct patch, fill), 0};
    for (GLuint i = 0; i < 2; i++)
        gl->VertexAttribPointer(i, 4, GL_FLOAT, GL_FALSE, sizeof(struct patch),
                                (const void *)((size_t)first * sizeof(struct patch) + off[i]));
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, tex);
    gl->Disable(GL_BLEND);
    gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, n);
    gl->Enable(GL_BLEND);
    return 0;
}

static int layer_copy(struct sp_draw_gl *d, GLuint tex)
{
    return patches_draw(d, tex, 0, 1);
}

/* ---- the static cache ----
 * Drawing the static layer first (once, into base) and the dynamic layer
 * over it gives the very pixels of drawing the list in order (all shapes,
 * then all text) wherever no dynamic item drawn earlier than a static one
 * touches it: blending is per pixel, so only the order at each pixel
 * counts. The frame is checked for that from the items' bounding boxes
 * (conservative: every pixel a capsule's or glyph's quad may cover, cut by
 * the clip the item is under); a frame that fails is drawn uncached. The
 * cache is redrawn whenever its content would change: the static items
 * (their geometry, colours, blending and clips, byte for byte) differ from
 * those it was drawn from, or new accumulated items touch the static ones.
 * The settled layer (the strip charts' past) is drawn into base after the
 * static one, each frame only what it appends, under the same kind of
 * check (order_keeps); a frame whose settled items do not begin with what
 * base holds, byte for byte, redraws base. */

static void box_add(struct box *b, float x0, float y0, float x1, float y1)
{
    b->x0 = fminf(b->x0, x0), b->y0 = fminf(b->y0, y0);
    b->x1 = fmaxf(b->x1, x1), b->y1 = fmaxf(b->y1, y1);
}

static int box_meets(const struct box *a, const struct box *b)
{
    return a->x1 >= a->x0 && b->x1 >= b->x0 && a->x0 <= b->x1 && b->x0 <= a->x1 &&
           a->y0 <= b->y1 && b->y0 <= a->y1;
}

/* The box of a shape sh, or of a glyph quad q when sh is NULL, of an item
 * of `layer` under the clip cl (x1 <= x0 = none). */
static struct box prim_box_of(const struct sp_shape *sh, const struct sp_glyph_quad *q,
                              enum sp_layer layer, const float cl[4])
{
    struct box b = {INFINITY, INFINITY, -INFINITY, -INFINITY, {0, 0, 0, 0}};
    if (!sh) {
        const float *r = q->rect;
        box_add(&b, fminf(r[0], r[2]) - 1, fminf(r[1], r[3]) - 1, fmaxf(r[0], r[2]) + 1,
                fmaxf(r[1], r[3]) + 1);
        return b; /* text is never clipped */
    }
    const float e = sh->style[0] + 2; /* the quad reaches half width + 1 px */
    /* a box or soft ellipse (kinds 2 and 3, horizontal as sp_canvas_rect and
     * _soft make them) reaches 1 px beyond its ends */
    const float ex = sh->style[1] > 1.5f && sh->seg[1] == sh->seg[3] ? 2 : e;
    box_add(&b, fminf(sh->seg[0], sh->seg[2]) - ex, fminf(sh->seg[1], sh->seg[3]) - e,
            fmaxf(sh->seg[0], sh->seg[2]) + ex, fmaxf(sh->seg[1], sh->seg[3]) + e);
    if (layer != SP_LAYER_ACCUM && cl[2] > cl[0]) { /* the scissor's whole pixels */
        memcpy(b.clip, cl, sizeof(b.clip));
        b.x0 = fmaxf(b.x0, floorf(cl[0]) - 1), b.y0 = fmaxf(b.y0, floorf(cl[1]) - 1);
        b.x1 = fminf(b.x1, ceilf(cl[2]) + 1), b.y1 = fminf(b.y1, ceilf(cl[3]) + 1);
    }
    return b;
}

/* The box of primitive k (a shape, or a glyph quad when text) of item it,
 * cut by the clip cl (x1 <= x0 = none). */
static struct box prim_box(const struct sp_canvas *c, const struct sp_item *it, int k,
                           const float cl[4])
{
    return it->kind == SP_ITEM_TEXT ? prim_box_of(NULL, &c->quads[k], it->layer, cl)
                                    : prim_box_of(&c->shapes[k], NULL, it->layer, cl);
}

/* Fills d->boxes for the items of c: each the union of its primitives'.
 * 0 or SP_E_NOMEM. */
static int boxes_make(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    float cl[4] = {0, 0, 0, 0};
    if (SP_ARRAY_RESERVE(d->boxes, d->cap_boxes, c->n_items, 0))
        return SP_E_NOMEM;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        struct box *b = &d->boxes[i];
        *b = (struct box){INFINITY, INFINITY, -INFINITY, -INFINITY, {0, 0, 0, 0}};
        if (it->kind == SP_ITEM_CLIP) {
            memcpy(cl, it->clip, sizeof(cl));
            continue;
        }
        if (it->kind != SP_ITEM_TEXT && it->layer != SP_LAYER_ACCUM)
            memcpy(b->clip, cl, sizeof(cl));
        for (int k = it->first; k < it->first + it->count; k++) {
            const struct box p = prim_box(c, it, k, cl);
            if (p.x1 >= p.x0)
                box_add(b, p.x0, p.y0, p.x1, p.y1);
        }
    }
    return 0;
}

/* Whether items a and b touch a common pixel: their boxes meet, and so do
 * the boxes of some primitive of each (a coarse test, then a finer one). */
static int items_meet(const struct sp_draw_gl *d, const struct sp_canvas *c, int a, int b)
{
    const struct sp_item *ia = &c->items[a], *ib = &c->items[b];
    if (!box_meets(&d->boxes[a], &d->boxes[b]))
        return 0;
    for (int k = ia->first; k < ia->first + ia->count; k++) {
        const struct box pa = prim_box(c, ia, k, d->boxes[a].clip);
        if (!box_meets(&pa, &d->boxes[b]))
            continue;
        for (int m = ib->first; m < ib->first + ib->count; m++) {
            const struct box pb = prim_box(c, ib, m, d->boxes[b].clip);
            if (box_meets(&pa, &pb))
                return 1;
        }
    }
    return 0;
}

/* Whether drawing c's static layer, then its settled one, then its
 * dynamic one keeps every pixel of drawing the list in order (shapes in
 * list order, then text in list order): no dynamic item that the list draws
 * before a static one touches it; no settled item touches static text, a
 * static shape the list draws after it, a dynamic shape the list draws
 * before it, or another settled item (base gets each frame's new parts of
 * all settled items in turn). */
static int order_keeps(const struct sp_draw_gl *d, const struct sp_canvas *c)
{
    for (int a = 0; a < c->n_items; a++) {
        if (c->items[a].kind == SP_ITEM_CLIP || c->items[a].layer != SP_LAYER_SETTLED)
            continue;
        for (int k = 0; k < c->n_items; k++) {
            const struct sp_item *o = &c->items[k];
            if (k == a || o->kind == SP_ITEM_CLIP)
                continue;
            const int text = o->kind == SP_ITEM_TEXT;
            const int clash = o->layer == SP_LAYER_SETTLED ||
                              (o->layer == SP_LAYER_STATIC && (text || k > a)) ||
                              (o->layer == SP_LAYER_DYNAMIC && !text && k < a);
            if (clash && items_meet(d, c, a, k))
                return 0;
        }
    }
    for (int s = 0; s < c->n_items; s++) {
        const struct sp_item *st = &c->items[s];
        if (st->kind == SP_ITEM_CLIP || st->layer != SP_LAYER_STATIC)
            continue;
        for (int k = 0; k < c->n_items; k++) {
            const struct sp_item *dy = &c->items[k];
            if (dy->kind == SP_ITEM_CLIP || dy->layer != SP_LAYER_DYNAMIC)
                continue;
            const int text_d = dy->kind == SP_ITEM_TEXT, text_s = st->kind == SP_ITEM_TEXT;
            const int before = text_d == text_s ? k < s : text_s;
            if (before && items_meet(d, c, k, s))
                return 0;
        }
    }
    return 1;
}

/* Marks tiles x0..x1, y0..y1 (inclusive, clamped) with v. */
static void tiles_mark(struct sp_draw_gl *d, int tw, int th, int x0, int y0, int x1, int y1,
                       unsigned char v)
{
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= tw ? tw - 1 : x1, y1 = y1 >= th ? th - 1 : y1;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            d->tiles[y * tw + x] = v;
}

/* Sorts the tiles by what base holds there: the background (0), what
 * must be copied (1), or one opaque colour (2 + its index in d->fills):
 * the primitives of the static layer in list order, each marking the tiles
 * its box touches 1, except an opaque box (alpha 1, horizontal) that
 * covers whole tiles, which marks those with its colour (all it covers is
 * that colour, whatever was under it). Then the rectangles: runs of equal
 * tiles along each row, joined with the run above when it spans the same
 * columns with the same value. 0 or SP_E_NOMEM. */
static int rects_make(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    const int tw = (d->width + TILE - 1) / TILE, th = (d->height + TILE - 1) / TILE;
    if (!d->tiles && !(d->tiles = malloc((size_t)tw * (size_t)th)))
        return SP_E_NOMEM;
    memset(d->tiles, 0, (size_t)tw * (size_t)th);
    d->n_fills = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_STATIC)
            continue;
        for (int k = it->first; k < it->first + it->count; k++) {
            const struct box b = prim_box(c, it, k, d->boxes[i].clip);
            if (b.x1 < b.x0)
                continue;
            tiles_mark(d, tw, th, (int)floorf(b.x0 / TILE), (int)floorf(b.y0 / TILE),
                       (int)floorf(b.x1 / TILE), (int)floorf(b.y1 / TILE), 1);
            const struct sp_shape *sh = it->kind == SP_ITEM_TEXT ? NULL : &c->shapes[k];
            if (!sh || sh->style[1] < 1.5f || sh->style[1] > 2.5f || sh->color[3] < 1 ||
                sh->seg[1] != sh->seg[3] ||
                d->boxes[i].clip[2] > d->boxes[i].clip[0] || d->n_fills == MAX_FILLS)
                continue;
            /* pixels whose centres are half a pixel inside are fully covered */
            const float x0 = fminf(sh->seg[0], sh->seg[2]), x1 = fmaxf(sh->seg[0], sh->seg[2]);
            const float y0 = sh->seg[1] - sh->style[0], y1 = sh->seg[1] + sh->style[0];
            const int tx0 = (int)ceilf(x0 / TILE), ty0 = (int)ceilf(y0 / TILE);
            /* whole tiles inside the frame only (the last row and column may be cut) */
            const int tx1 = (int)fminf(floorf(x1 / TILE), (float)(d->width / TILE)) - 1;
            const int ty1 = (int)fminf(floorf(y1 / TILE), (float)(d->height / TILE)) - 1;
            if (tx1 < tx0 || ty1 < ty0)
                continue;
            int f = 0;
            while (f < d->n_fills && memcmp(d->fills[f], sh->color, sizeof(d->fills[f])))
                f++;
            if (f == d->n_fills)
                memcpy(d->fills[d->n_fills++], sh->color, sizeof(d->fills[f]));
            tiles_mark(d, tw, th, tx0, ty0, tx1, ty1, (unsigned char)(2 + f));
        }
    }
    /* base holds the settled layer too, which grows: all it may cover */
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const float *cl = d->boxes[i].clip;
        if (cl[2] > cl[0])
            tiles_mark(d, tw, th, (int)floorf((floorf(cl[0]) - 1) / TILE), (int)floorf((floorf(cl[1]) - 1) / TILE),
                       (int)floorf((ceilf(cl[2]) + 1) / TILE), (int)floorf((ceilf(cl[3]) + 1) / TILE), 1);
        else
            tiles_mark(d, tw, th, 0, 0, tw - 1, th - 1, 1);
    }
    d->n_rects = 0;
    int row_first = 0; /* the rectangles ending on the previous row start here */
    for (int y = 0; y < th; y++) {
        const int prev_first = row_first;
        int prev_end = d->n_rects;
        row_first = d->n_rects;
        for (int x = 0; x < tw;) {
            const unsigned char v = d->tiles[y * tw + x];
            if (!v) {
                x++;
                continue;
            }
            int e = x;
            while (e < tw && d->tiles[y * tw + e] == v)
                e++;
            const struct fill_rect r = {{(float)(x * TILE), (float)(y * TILE), (float)(e * TILE),
                                         (float)((y + 1) * TILE)}, v};
            int k = prev_first;
            while (k < prev_end && !(d->rects[k].r[0] == r.r[0] && d->rects[k].r[2] == r.r[2] &&
                                     d->rects[k].v == v))
                k++;
            if (k < prev_end) { /* the same columns as a run above: grow it down, and
                                   keep this row's rectangles together at the end */
                struct fill_rect t = d->rects[k];
                t.r[3] = r.r[3];
                memmove(d->rects + k, d->rects + k + 1, (size_t)(d->n_rects - k - 1) * sizeof(t));
                d->rects[d->n_rects - 1] = t;
                row_first--;
                prev_end--;
            } else {
                if (SP_ARRAY_RESERVE(d->rects, d->cap_rects, d->n_rects + 1, 16))
                    return SP_E_NOMEM;
                d->rects[d->n_rects++] = r;
            }
            x = e;
        }
    }
    return 0;
}

/* Uploads the static cache's rectangles as patches. 0 or SP_E_NOMEM. */
static int patches_set(struct sp_draw_gl *d)
{
    struct patch *p = malloc((size_t)(d->n_rects ? d->n_rects : 1) * sizeof(*p));
    if (!p) {
        sp_log_error("out of memory for the static cache's rectangles");
        return SP_E_NOMEM;
    }
    for (int k = 0; k < d->n_rects; k++) {
        const struct fill_rect *fr = &d->rects[k];
        memcpy(p[k].rect, fr->r, sizeof(p[k].rect));
        p[k].rect[2] = fminf(p[k].rect[2], (float)d->width); /* the last tiles are cut */
        p[k].rect[3] = fminf(p[k].rect[3], (float)d->height);
        if (fr->v == 1)
            memcpy(p[k].fill, (const float[4]){0, 0, 0, -1}, sizeof(p[k].fill));
        else /* opaque: what the shape shader writes for it (premultiplied, alpha 1) */
            memcpy(p[k].fill, d->fills[fr->v - 2], sizeof(p[k].fill));
    }
    int err = patches_upload(d, p, d->n_rects);
    free(p);
    d->n_patches = d->n_rects;
    return err;
}

static int append(unsigned char **buf, size_t *n, size_t *cap, const void *data, size_t size)
{
    if (SP_ARRAY_RESERVE(*buf, *cap, *n + size, 4096))
        return SP_E_NOMEM;
    memcpy(*buf + *n, data, size);
    *n += size;
    return 0;
}

/* What the cache's pixels depend on: every static item (kind, blending,
 * clip) with its shapes or glyph quads, and the background. */
static int key_make(struct sp_draw_gl *d, const struct sp_canvas *c, const float bg[4])
{
    int err;
    d->n_next = 0;
    err = append(&d->next, &d->n_next, &d->cap_next, bg, 4 * sizeof(float));
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_STATIC)
            continue;
        const int head[3] = {it->kind, it->blend, it->count};
        err = append(&d->next, &d->n_next, &d->cap_next, head, sizeof(head));
        if (!err)
            err = append(&d->next, &d->n_next, &d->cap_next, d->boxes[i].clip, sizeof(d->boxes[i].clip));
        if (!err && it->kind == SP_ITEM_TEXT)
            err = append(&d->next, &d->n_next, &d->cap_next, c->quads + it->first,
                         (size_t)it->count * sizeof(*c->quads));
        else if (!err)
            err = append(&d->next, &d->n_next, &d->cap_next, c->shapes + it->first,
                         (size_t)it->count * sizeof(*c->shapes));
    }
    return err;
}

/* Whether the accumulated items of c touch no static or settled item. */
static int accum_apart(const struct sp_draw_gl *d, const struct sp_canvas *c)
{
    for (int a = 0; a < c->n_items; a++) {
        if (c->items[a].kind == SP_ITEM_CLIP || c->items[a].layer != SP_LAYER_ACCUM)
            continue;
        for (int s = 0; s < c->n_items; s++)
            if (c->items[s].kind != SP_ITEM_CLIP &&
                (c->items[s].layer == SP_LAYER_STATIC || c->items[s].layer == SP_LAYER_SETTLED) &&
                items_meet(d, c, a, s))
                return 0;
    }
    return 1;
}

/* Binds the shape program and its instances (attribute pointers are set
 * from the bound buffer). */
static void shapes_bind(const struct sp_gl_api *gl, const struct instances *shape)
{
    gl->UseProgram(shape->program);
    gl->BindVertexArray(shape->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, shape->vbo);
}

/* Marks the DTILE px squares that shapes [from, to) of item i of c may touch
 * in d->dtiles (sized by dtiles_clear). */
static void dtiles_mark_box(struct sp_draw_gl *d, const struct box *b);

static void dtiles_mark(struct sp_draw_gl *d, const struct sp_canvas *c, int i, int from, int to)
{
    for (int k = from; k < to; k++) {
        const struct box b = prim_box(c, &c->items[i], k, d->boxes[i].clip);
        dtiles_mark_box(d, &b);
    }
}

/* Marks the DTILE px squares box b touches. */
static void dtiles_mark_box(struct sp_draw_gl *d, const struct box *b)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    if (b->x1 < b->x0)
        return;
    int x0 = (int)floorf(b->x0 / DTILE), y0 = (int)floorf(b->y0 / DTILE);
    int x1 = (int)floorf(b->x1 / DTILE), y1 = (int)floorf(b->y1 / DTILE);
    x0 = x0 < 0 ? 0 : x0, y0 = y0 < 0 ? 0 : y0;
    x1 = x1 >= tw ? tw - 1 : x1, y1 = y1 >= th ? th - 1 : y1;
    for (int y = y0; y <= y1; y++)
        memset(d->dtiles + (size_t)y * tw + x0, 1, x1 >= x0 ? (size_t)(x1 - x0 + 1) : 0);
}

/* Empties d->dtiles. 0 or SP_E_NOMEM. */
static int dtiles_clear(struct sp_draw_gl *d)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    if (!d->dtiles && !(d->dtiles = malloc((size_t)tw * (size_t)th)))
        return SP_E_NOMEM;
    memset(d->dtiles, 0, (size_t)tw * (size_t)th);
    return 0;
}

struct dyn_head {
    int kind, blend, count, lanes;
    float clip[4];
};

static size_t dyn_bytes(const struct sp_item *it)
{
    return (size_t)it->count * (it->kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad)
                                                           : sizeof(struct sp_shape));
}

static const void *dyn_data(const struct sp_canvas *c, const struct sp_item *it)
{
    return it->kind == SP_ITEM_TEXT ? (const void *)(c->quads + it->first)
                                    : (const void *)(c->shapes + it->first);
}

/* Records c's dynamic items as the target now holds them. 0 or SP_E_NOMEM. */
static int dyn_save(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    int err = 0;
    d->n_dyn = 0;
    d->n_dyn_items = 0;
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_DYNAMIC)
            continue;
        struct dyn_head h = {it->kind, (int)it->blend, it->count, it->lanes, {0, 0, 0, 0}};
        memcpy(h.clip, d->boxes[i].clip, sizeof(h.clip));
        err = append(&d->dyn, &d->n_dyn, &d->cap_dyn, &h, sizeof(h));
        if (!err)
            err = append(&d->dyn, &d->n_dyn, &d->cap_dyn, dyn_data(c, it), dyn_bytes(it));
        d->n_dyn_items++;
    }
    if (err)
        d->n_dyn = 0, d->n_dyn_items = -1; /* nothing known: all changed */
    return err;
}

/* Compares c's dynamic items with the record (d->same) and marks in
 * d->dtiles the squares of those that changed, in their last frame's form
 * and in this one's. 0 or SP_E_NOMEM. */
static int dyn_compare(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    if (SP_ARRAY_RESERVE(d->same, d->cap_same, c->n_items, 0))
        return SP_E_NOMEM;
    memset(d->same, 0, (size_t)c->n_items);
    d->any_same = 0;
    int n = 0;
    for (int i = 0; i < c->n_items; i++)
        n += c->items[i].kind != SP_ITEM_CLIP && c->items[i].layer == SP_LAYER_DYNAMIC;
    const int paired = n == d->n_dyn_items;
    size_t at = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_DYNAMIC)
            continue;
        if (paired) { /* this item against its counterpart */
            struct dyn_head h;
            memcpy(&h, d->dyn + at, sizeof(h));
            at += sizeof(h);
            const unsigned char *old = d->dyn + at;
            const size_t size = (size_t)h.count * (h.kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad)
                                                                           : sizeof(struct sp_shape));
            at += size;
            d->same[i] = h.kind == (int)it->kind && h.blend == (int)it->blend && h.count == it->count &&
                         h.lanes == it->lanes && !memcmp(h.clip, d->boxes[i].clip, sizeof(h.clip)) &&
                         !memcmp(old, dyn_data(c, it), size);
            d->any_same |= d->same[i];
            if (d->same[i]) {
                d->stats.unchanged++;
                continue;
            }
            for (int k = 0; k < h.count; k++) { /* where it was */
                const struct box b = h.kind == SP_ITEM_TEXT
                    ? prim_box_of(NULL, (const struct sp_glyph_quad *)old + k, SP_LAYER_DYNAMIC, h.clip)
                    : prim_box_of((const struct sp_shape *)old + k, NULL, SP_LAYER_DYNAMIC, h.clip);
                dtiles_mark_box(d, &b);
            }
        }
        dtiles_mark(d, c, i, it->first, it->first + it->count); /* where it is */
    }
    for (size_t b = 0; !paired && b < d->n_dyn;) { /* every old item, where it was */
        struct dyn_head h;
        memcpy(&h, d->dyn + b, sizeof(h));
        b += sizeof(h);
        for (int k = 0; k < h.count; k++) {
            const struct box x = h.kind == SP_ITEM_TEXT
                ? prim_box_of(NULL, (const struct sp_glyph_quad *)(d->dyn + b) + k, SP_LAYER_DYNAMIC, h.clip)
                : prim_box_of((const struct sp_shape *)(d->dyn + b) + k, NULL, SP_LAYER_DYNAMIC, h.clip);
            dtiles_mark_box(d, &x);
        }
        b += (size_t)h.count * (h.kind == SP_ITEM_TEXT ? sizeof(struct sp_glyph_quad) : sizeof(struct sp_shape));
    }
    return 0;
}

/* Sets d->damage to the marked squares, as runs along each row. 0 or
 * SP_E_NOMEM. */
static int damage_runs(struct sp_draw_gl *d)
{
    const int tw = (d->width + DTILE - 1) / DTILE, th = (d->height + DTILE - 1) / DTILE;
    d->n_damage = 0;
    for (int y = 0; y < th; y++)
        for (int x = 0; x < tw;) {
            if (!d->dtiles[y * tw + x]) {
                x++;
                continue;
            }
            int e = x;
            while (e < tw && d->dtiles[y * tw + e])
                e++;
            if (SP_ARRAY_RESERVE(d->damage, d->cap_damage, d->n_damage + 1, 64))
                return SP_E_NOMEM;
            d->damage[d->n_damage++] = (struct patch){
                {(float)(x * DTILE), (float)(y * DTILE), fminf((float)(e * DTILE), (float)d->width),
                 fminf((float)((y + 1) * DTILE), (float)d->height)},
                {0, 0, 0, -1}};
            x = e;
        }
    return 0;
}

/* ---- the settled layer in base ---- */

struct settled_head {
    int blend, lanes, count;
    float clip[4];
};

/* Whether base holds a prefix of each of c's settled items (the same
 * items, blending, lanes and clips; their first shapes byte for byte), and
 * how many shapes of each (d->settled_old). 0 = no, 1 = yes, or
 * SP_E_NOMEM. */
static int settled_prefix(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    size_t at = 0;
    int j = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        struct settled_head h;
        if (at + sizeof(h) > d->n_settled)
            return 0;
        memcpy(&h, d->settled + at, sizeof(h));
        at += sizeof(h);
        if (h.blend != (int)it->blend || h.lanes != it->lanes || h.count > it->count ||
            memcmp(h.clip, d->boxes[i].clip, sizeof(h.clip)) ||
            memcmp(d->settled + at, c->shapes + it->first, (size_t)h.count * sizeof(*c->shapes)))
            return 0;
        at += (size_t)h.count * sizeof(*c->shapes);
        if (SP_ARRAY_RESERVE(d->settled_old, d->cap_settled_old, j + 1, 8))
            return SP_E_NOMEM;
        d->settled_old[j++] = h.count;
    }
    return at == d->n_settled;
}

/* Records c's settled items as base now holds them. 0 or SP_E_NOMEM. */
static int settled_save(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    int err = 0;
    d->n_settled = 0;
    for (int i = 0; i < c->n_items && !err; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        struct settled_head h = {(int)it->blend, it->lanes, it->count, {0, 0, 0, 0}};
        memcpy(h.clip, d->boxes[i].clip, sizeof(h.clip));
        err = append(&d->settled, &d->n_settled, &d->cap_settled, &h, sizeof(h));
        if (!err)
            err = append(&d->settled, &d->n_settled, &d->cap_settled, c->shapes + it->first,
                         (size_t)it->count * sizeof(*c->shapes));
    }
    if (err)
        d->n_settled = 0;
    return err;
}

/* Marks in d->dtiles the squares that what is new of c's settled items
 * (past d->settled_old) may touch. Returns the new shapes. */
static int settled_find_new(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    int j = 0, n_new = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const int old = d->settled_old[j++];
        dtiles_mark(d, c, i, it->first + old, it->first + it->count);
        n_new += it->count - old;
    }
    return n_new;
}

/* Draws what is new of c's settled items into the bound framebuffer, under
 * their clips. The shape program must be bound. */
static void settled_draw_new(struct sp_draw_gl *d, const struct sp_canvas *c)
{
    const struct sp_gl_api *gl = d->gl;
    int j = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const int old = d->settled_old[j++];
        if (it->count == old)
            continue;
        clip(gl, d->boxes[i].clip, d->height);
        if (it->blend == SP_BLEND_MAX)
            gl->BlendEquation(GL_MAX);
        shape_base(gl, it->first + old);
        gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(it->count - old));
        gl->BlendEquation(GL_FUNC_ADD);
    }
    gl->Disable(GL_SCISSOR_TEST);
}

/* Scissors to damage rectangle r cut by the clip cl (x1 <= x0 = none), in
 * whole pixels as clip() rounds it; 0 when that is empty. */
static int scissor_cut(const struct sp_draw_gl *d, const struct patch *r, const float cl[4])
{
    float x0 = r->rect[0], y0 = r->rect[1], x1 = r->rect[2], y1 = r->rect[3];
    if (cl[2] > cl[0]) {
        x0 = fmaxf(x0, floorf(cl[0])), y0 = fmaxf(y0, floorf(cl[1]));
        x1 = fminf(x1, ceilf(cl[2])), y1 = fminf(y1, ceilf(cl[3]));
    }
    if (x1 <= x0 || y1 <= y0)
        return 0;
    clip(d->gl, (const float[4]){x0, y0, x1, y1}, d->height);
    return 1;
}

/* Draws unchanged item i only inside the damage rectangles: per rectangle
 * its box meets, the runs of its primitives whose boxes meet it (the others
 * do not touch it), under the scissor. The item's program must be bound. */
static void draw_unchanged(struct sp_draw_gl *d, const struct sp_canvas *c, int i)
{
    const struct sp_gl_api *gl = d->gl;
    const struct sp_item *it = &c->items[i];
    const float *cl = d->boxes[i].clip;
    const int text = it->kind == SP_ITEM_TEXT;
    for (int r = 0; r < d->n_damage; r++) {
        const struct patch *p = &d->damage[r];
        const struct box rb = {p->rect[0], p->rect[1], p->rect[2], p->rect[3], {0, 0, 0, 0}};
        if (!box_meets(&d->boxes[i], &rb))
            continue;
        int scissored = 0;
        for (int k = it->first; k < it->first + it->count;) {
            const struct box b = prim_box(c, it, k, cl);
            if (!box_meets(&b, &rb)) {
                k++;
                continue;
            }
            int e = k + 1;
            while (e < it->first + it->count) {
                const struct box be = prim_box(c, it, e, cl);
                if (!box_meets(&be, &rb))
                    break;
                e++;
            }
            if (!scissored && !(scissored = scissor_cut(d, p, text ? (const float[4]){0, 0, 0, 0} : cl)))
                break;
            if (text)
                text_base(gl, k);
            else
                shape_base(gl, k);
            if (it->blend == SP_BLEND_MAX)
                gl->BlendEquation(GL_MAX);
            gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(e - k));
            gl->BlendEquation(GL_FUNC_ADD);
            k = e;
        }
    }
}

/* The dynamic layer over a restored target: as draw_shapes and draw_text
 * draw it, except that an item unchanged since the last frame (d->same) is
 * drawn only inside the damage rectangles, where the restore covered it. */
static void draw_dynamic_kept(struct sp_draw_gl *d, const struct sp_canvas *c, int text)
{
    const struct sp_gl_api *gl = d->gl;
    float cl[4] = {0, 0, 0, 0};
    int start = -1, end = 0, blend = 0;
    shapes_bind(gl, &d->shape);
    for (int i = 0; i <= c->n_items; i++) { /* shapes, in runs of changed items */
        const struct sp_item *it = i < c->n_items ? &c->items[i] : NULL;
        const int mine = it && it->kind != SP_ITEM_TEXT && it->kind != SP_ITEM_CLIP &&
                         it->layer == SP_LAYER_DYNAMIC;
        if (it && it->kind == SP_ITEM_TEXT)
            continue; /* runs go on across text, as draw_shapes' do */
        const int joins = mine && !d->same[i] && start >= 0 && it->first == end && (int)it->blend == blend;
        if (joins) {
            end = it->first + it->count;
            continue;
        }
        if (start >= 0) { /* a run ends */
            clip(gl, cl, d->height);
            if (blend == SP_BLEND_MAX)
                gl->BlendEquation(GL_MAX);
            shape_base(gl, start);
            gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(end - start));
            gl->BlendEquation(GL_FUNC_ADD);
            start = -1;
        }
        if (!it)
            break;
        if (it->kind == SP_ITEM_CLIP)
            memcpy(cl, it->clip, sizeof(cl));
        else if (mine && d->same[i])
            draw_unchanged(d, c, i);
        else if (mine)
            start = it->first, end = it->first + it->count, blend = (int)it->blend;
    }
    gl->Disable(GL_SCISSOR_TEST);
    if (!text)
        return;
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, d->atlas);
    gl->UseProgram(d->text.program);
    gl->BindVertexArray(d->text.vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, d->text.vbo);
    start = -1;
    for (int i = 0; i <= c->n_items; i++) { /* text, in runs of changed items */
        const struct sp_item *it = i < c->n_items ? &c->items[i] : NULL;
        if (it && (it->kind != SP_ITEM_TEXT || !it->count || it->layer != SP_LAYER_DYNAMIC))
            continue;
        if (it && !d->same[i] && start >= 0 && it->first == end) {
            end = it->first + it->count;
            continue;
        }
        if (start >= 0) {
            gl->Disable(GL_SCISSOR_TEST); /* text is never clipped */
            text_base(gl, start);
            gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(end - start));
            start = -1;
        }
        if (!it)
            break;
        if (d->same[i])
            draw_unchanged(d, c, i);
        else
            start = it->first, end = it->first + it->count;
    }
    gl->Disable(GL_SCISSOR_TEST);
    text_base(gl, 0);
}

/* Copies base over d->damage, in one instanced draw without blending. */
static int damage_restore(struct sp_draw_gl *d)
{
    const struct sp_gl_api *gl = d->gl;
    int err = d->patch.program ? 0 : patches_upload(d, NULL, 0);
    if (err || !d->n_damage)
        return err;
    if (!d->restore.vao) {
        gl->GenVertexArrays(1, &d->restore.vao);
        gl->BindVertexArray(d->restore.vao);
        gl->GenBuffers(1, &d->restore.vbo);
        gl->BindBuffer(GL_ARRAY_BUFFER, d->restore.vbo);
        for (GLuint i = 0; i < 2; i++) {
            gl->EnableVertexAttribArray(i);
            gl->VertexAttribDivisor(i, 1);
        }
    }
    d->restore.program = d->patch.program;
    instances_upload(gl, &d->restore, d->damage, d->n_damage, sizeof(struct patch));
    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(struct patch),
                            (const void *)offsetof(struct patch, rect));
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(struct patch),
                            (const void *)offsetof(struct patch, fill));
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, d->base_tex);
    gl->Disable(GL_BLEND);
    gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, d->n_damage);
    gl->Enable(GL_BLEND);
    return 0;
}

/* Items whose order against others the cache cannot keep are drawn with
 * the dynamic layer instead, each frame (an unchanged one is left as the
 * last frame drew it; the others of their layer stay cached): a static
 * shape the list draws after a settled item it touches, static text
 * touching a settled item (text is drawn after every shape), a static item
 * that a dynamic one drawn before it touches, a settled item touching a
 * dynamic shape drawn before it or a settled item before it (at small sizes
 * panels, legends, labels and the pendulum crowd each other: such frames
 * were drawn uncached, their cost growing with the curves). Repeated until
 * nothing moves, since a moved item is dynamic for the others; order_keeps
 * then holds. Sets d->items to c's items with those layers changed and
 * *out to c with them. 0 or SP_E_NOMEM. */
static int lift_items(struct sp_draw_gl *d, const struct sp_canvas *c, struct sp_canvas *out)
{
    *out = *c;
    if (SP_ARRAY_RESERVE(d->items, d->cap_items, c->n_items, 0))
        return SP_E_NOMEM;
    if (c->n_items)
        memcpy(d->items, c->items, (size_t)c->n_items * sizeof(*d->items));
    out->items = d->items;
    for (int moved = 1; moved;) {
        moved = 0;
        for (int i = 0; i < c->n_items; i++) {
            struct sp_item *it = &d->items[i];
            const int st = it->layer == SP_LAYER_STATIC, text_i = it->kind == SP_ITEM_TEXT;
            if (it->kind == SP_ITEM_CLIP || !(st || it->layer == SP_LAYER_SETTLED))
                continue;
            for (int k = 0; k < c->n_items; k++) {
                const struct sp_item *o = &d->items[k];
                if (k == i || o->kind == SP_ITEM_CLIP)
                    continue;
                const int text_o = o->kind == SP_ITEM_TEXT;
                const int dyn = o->layer == SP_LAYER_DYNAMIC, set = o->layer == SP_LAYER_SETTLED;
                const int over = st ? (set && (text_i || k < i)) ||
                                          (dyn && (text_o == text_i ? k < i : text_i))
                                    : (dyn && !text_o && k < i) || (set && k < i);
                if (over && items_meet(d, out, k, i)) {
                    it->layer = SP_LAYER_DYNAMIC;
                    moved = 1;
                    break;
                }
            }
        }
    }
    return 0;
}

int sp_draw_gl_list(struct sp_draw_gl *d, const struct sp_canvas *c, const float bg[4])
{
    const struct sp_gl_api *gl = d->gl;
    GLint target = 0;
    GLenum glerr;
    int accum = 0, accum_in_base = 0, err = 0, cached = 0, use_same = 0;
    const int text = c->n_quads && d->atlas;
    const int kept = d->kept; /* cleared until this frame is drawn */
    d->kept = 0;
    for (int i = 0; i < c->n_items; i++)
        if (c->items[i].kind == SP_ITEM_IMAGE ||
            (c->items[i].kind == SP_ITEM_TEXT && c->items[i].scale > 0)) {
            sp_log_error("the GL backend draws no images or turned text; a draw list that "
                         "has them is drawn with cairo (canvas.h)");
            return SP_E_INPUT;
        }
    if (text)
        atlas_sync(d);

    for (int i = 0; i < c->n_items && !accum; i++)
        accum = c->items[i].layer == SP_LAYER_ACCUM && c->items[i].kind != SP_ITEM_CLIP;
    struct sp_canvas lifted;
    if (d->cache) {
        if ((err = boxes_make(d, c)) != 0 || (err = lift_items(d, c, &lifted)) != 0) {
            sp_log_error("out of memory for the static cache's bounds");
            return err;
        }
        c = &lifted;
        /* also with no static item: base is then the background (or the
         * long exposure), restored only where the last frame drew */
        cached = order_keeps(d, c);
    }
    if (c->n_shapes)
        instances_upload(gl, &d->shape, c->shapes, c->n_shapes, sizeof(struct sp_shape));
    gl->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (accum) { /* what is new of the accumulated layer, into its picture */
        if (!d->accum_fbo && (err = layer_make(d, &d->accum_fbo, &d->accum_tex, bg, "the long exposure")) != 0)
            return err;
        gl->BindFramebuffer(GL_FRAMEBUFFER, d->accum_fbo);
        shapes_bind(gl, &d->shape);
        draw_shapes(gl, c, ACCUM_BIT, d->height);
        if (d->base_valid && cached && accum_apart(d, c)) { /* and into the cache, under nothing */
            gl->BindFramebuffer(GL_FRAMEBUFFER, d->base_fbo);
            draw_shapes(gl, c, ACCUM_BIT, d->height);
            accum_in_base = 1;
        } else {
            d->base_valid = 0;
        }
        gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    }
    if (text)
        instances_upload(gl, &d->text, c->quads, c->n_quads, sizeof(struct sp_glyph_quad));
    if (cached) {
        if ((err = key_make(d, c, bg)) != 0) {
            sp_log_error("out of memory for the static cache's key");
            return err;
        }
        int prefix = 0; /* base holds the static layer and a prefix of the settled one */
        if (d->base_valid && d->n_next == d->n_key && !memcmp(d->next, d->key, d->n_key) &&
            (prefix = settled_prefix(d, c)) < 0) {
            sp_log_error("out of memory for the settled layer's record");
            return prefix;
        }
        if (!prefix) {
            /* (re)draw the cache: the long exposure or the background, then
             * the static layer's shapes and text, then the settled layer,
             * drawn into the target itself and copied */
            if (!d->base_fbo &&
                (err = layer_make(d, &d->base_fbo, &d->base_tex, bg, "the static layer")) != 0)
                return err;
            gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
            if (d->accum_fbo) {
                gl->BindFramebuffer(GL_READ_FRAMEBUFFER, d->accum_fbo);
                gl->BlitFramebuffer(0, 0, d->width, d->height, 0, 0, d->width, d->height,
                                    GL_COLOR_BUFFER_BIT, GL_NEAREST);
                gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
            } else {
                gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
                gl->Clear(GL_COLOR_BUFFER_BIT);
            }
            shapes_bind(gl, &d->shape);
            draw_shapes(gl, c, STATIC_BIT, d->height);
            if (text)
                draw_text(gl, &d->text, d->atlas, c, STATIC_BIT);
            shapes_bind(gl, &d->shape);
            draw_shapes(gl, c, SETTLED_BIT, d->height);
            if ((err = settled_save(d, c)) != 0) {
                sp_log_error("out of memory for the settled layer's record");
                return err;
            }
            gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->base_fbo);
            gl->BlitFramebuffer(0, 0, d->width, d->height, 0, 0, d->width, d->height,
                                GL_COLOR_BUFFER_BIT, GL_NEAREST);
            gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
            unsigned char *swap = d->key;
            size_t cap = d->cap_key;
            d->key = d->next, d->n_key = d->n_next, d->cap_key = d->cap_next;
            d->next = swap, d->cap_next = cap, d->n_next = 0;
            d->base_valid = 1;
            d->stats.redrawn++;
            if (!d->accum_fbo && (err = rects_make(d, c)) != 0) {
                sp_log_error("out of memory for the static cache's rectangles");
                return err;
            }
            if (!d->accum_fbo && (err = patches_set(d)) != 0)
                return err;
        } else {
            /* what is new of the settled layer, into base (which has the
             * target's pixel format and orientation: the same pixels as
             * drawing it into the target); then base under this frame,
             * restored where the settled layer grew too */
            if ((err = dtiles_clear(d)) != 0 || (kept && (err = dyn_compare(d, c)) != 0)) {
                sp_log_error("out of memory for the damaged rectangles");
                return err;
            }
            use_same = kept && d->any_same;
            for (int i = 0; accum_in_base && i < c->n_items; i++) /* drawn into base above */
                if (c->items[i].kind != SP_ITEM_CLIP && c->items[i].layer == SP_LAYER_ACCUM)
                    dtiles_mark(d, c, i, c->items[i].first, c->items[i].first + c->items[i].count);
            if (settled_find_new(d, c)) {
                gl->BindFramebuffer(GL_FRAMEBUFFER, d->base_fbo);
                shapes_bind(gl, &d->shape);
                settled_draw_new(d, c);
                gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
                d->stats.appended++;
                if ((err = settled_save(d, c)) != 0) {
                    sp_log_error("out of memory for the settled layer's record");
                    return err;
                }
            }
            if (kept) { /* base where the last frame's dynamic items were */
                if ((err = damage_runs(d)) != 0) {
                    sp_log_error("out of memory for the damaged rectangles");
                    return err;
                }
                if ((err = damage_restore(d)) != 0)
                    return err;
            } else if (d->accum_fbo) { /* the cache under this frame */
                if ((err = layer_copy(d, d->base_tex)) != 0)
                    return err;
            } else { /* the background, and the cache where it differs from it */
                gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
                gl->Clear(GL_COLOR_BUFFER_BIT);
                if ((err = patches_draw(d, d->base_tex, 1, d->n_patches)) != 0)
                    return err;
            }
        }
        d->stats.cached++;
    } else if (d->accum_fbo) { /* the accumulated picture instead of the background */
        d->stats.uncached++;
        if ((err = layer_copy(d, d->accum_tex)) != 0)
            return err;
    } else {
        d->stats.uncached++;
        gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
        gl->Clear(GL_COLOR_BUFFER_BIT);
    }
    const unsigned layers = cached ? DYNAMIC_BIT : DYNAMIC_BIT | STATIC_BIT | SETTLED_BIT;
    if (use_same) {
        draw_dynamic_kept(d, c, text);
    } else {
        if (c->n_shapes) {
            shapes_bind(gl, &d->shape);
            draw_shapes(gl, c, layers, d->height);
        }
        if (text)
            draw_text(gl, &d->text, d->atlas, c, layers);
    }
    if (cached) {
        if ((err = dyn_save(d, c)) != 0) {
            sp_log_error("out of memory for the damaged rectangles");
            return err;
        }
        d->kept = 1;
    }
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("drawing a frame failed with GL error 0x%04x", glerr);
        return SP_E_GL;
    }
    return 0;
}

void sp_draw_gl_cache(struct sp_draw_gl *d, int on)
{
    d->cache = on;
    d->base_valid = 0;
    d->kept = 0;
}

void sp_draw_gl_stats(const struct sp_draw_gl *d, struct sp_draw_gl_stats *out)
{
    *out = d->stats;
}

void sp_draw_gl_destroy(struct sp_draw_gl **d)
{
    if (!*d)
        return;
    free((*d)->key);
    free((*d)->next);
    free((*d)->boxes);
    free((*d)->rects);
    free((*d)->tiles);
    free((*d)->damage);
    free((*d)->dtiles);
    free((*d)->settled);
    free((*d)->settled_old);
    free((*d)->dyn);
    free((*d)->same);
    free((*d)->items);
    free(*d);
    *d = NULL;
}
