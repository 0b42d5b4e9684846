/* springpend (internal): the draw list drawn with GL. See draw_gl.h. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "draw_gl.h"
#include "base/embedded.h"

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
    /* Base (draw_cache.h): the accumulated picture (or the background) with
     * the static layer drawn over it, then the settled layer (appended to
     * each frame), copied under each frame's dynamic layer. */
    GLuint base_fbo, base_tex;   /* 0 = none yet */
    struct instances patch;      /* draws layers as they are (struct sp_draw_rect) */
    int n_patches;               /* base's rectangles, after instance 0 */
    /* The target keeps its pixels from frame to frame (both backends draw
     * into a framebuffer object like base's, gl_offscreen.h, read back
     * after each frame): a plan restores base only over its damage. */
    struct instances restore;    /* draws the damage with the patch program */
    struct sp_draw_cache *cache; /* what to draw each frame */
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
    err = sp_draw_cache_make(&d->cache, width, height);
    if (err) {
        free(d);
        return err;
    }
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
        sp_draw_cache_destroy(&d->cache);
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


/* Makes the patch program and uploads instance 0 plus n patches. */
static int patches_upload(struct sp_draw_gl *d, const struct sp_draw_rect *p, int n)
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
    const struct sp_draw_rect whole = {{0, 0, (float)d->width, (float)d->height}, {0, 0, 0, -1}};
    gl->BufferSubData(GL_ARRAY_BUFFER, 0, sizeof(whole), &whole);
    if (n)
        gl->BufferSubData(GL_ARRAY_BUFFER, sizeof(whole), (GLsizeiptr)n * (GLsizeiptr)sizeof(*p), p);
    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(*p), (const void *)offsetof(struct sp_draw_rect, rect));
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(*p), (const void *)offsetof(struct sp_draw_rect, fill));
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
    static const size_t off[3] = {offsetof(struct sp_draw_rect, rect), offsetof(struct sp_draw_rect, fill), 0};
    for (GLuint i = 0; i < 2; i++)
        gl->VertexAttribPointer(i, 4, GL_FLOAT, GL_FALSE, sizeof(struct sp_draw_rect),
                                (const void *)((size_t)first * sizeof(struct sp_draw_rect) + off[i]));
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


/* Binds the shape program and its instances (attribute pointers are set
 * from the bound buffer). */
static void shapes_bind(const struct sp_gl_api *gl, const struct instances *shape)
{
    gl->UseProgram(shape->program);
    gl->BindVertexArray(shape->vao);
    gl->BindBuffer(GL_ARRAY_BUFFER, shape->vbo);
}


/* Draws what is new of the plan's settled items into the bound framebuffer,
 * under their clips. The shape program must be bound. */
static void settled_draw_new(struct sp_draw_gl *d, const struct sp_draw_plan *p)
{
    const struct sp_gl_api *gl = d->gl;
    const struct sp_canvas *c = p->list;
    int j = 0;
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP || it->layer != SP_LAYER_SETTLED)
            continue;
        const int old = p->settled_old[j++];
        if (it->count == old)
            continue;
        clip(gl, sp_draw_cache_clip(d->cache, i), d->height);
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
static int scissor_cut(const struct sp_draw_gl *d, const struct sp_draw_rect *r, const float cl[4])
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

/* Draws unchanged item i of the plan's list only inside the damage
 * rectangles: per rectangle, the runs of its primitives that meet it
 * (sp_draw_cache_run), under the scissor. The item's program must be
 * bound. */
static void draw_unchanged(struct sp_draw_gl *d, const struct sp_draw_plan *p, int i)
{
    const struct sp_gl_api *gl = d->gl;
    const struct sp_item *it = &p->list->items[i];
    const float *cl = sp_draw_cache_clip(d->cache, i);
    const int text = it->kind == SP_ITEM_TEXT;
    for (int r = 0; r < p->n_damage; r++) {
        const struct sp_draw_rect *rect = &p->damage[r];
        int scissored = 0;
        for (int k = -1, e; sp_draw_cache_run(d->cache, p->list, i, rect, &k, &e); k = e) {
            if (!scissored && !(scissored = scissor_cut(d, rect, text ? (const float[4]){0, 0, 0, 0} : cl)))
                break;
            if (text)
                text_base(gl, k);
            else
                shape_base(gl, k);
            if (it->blend == SP_BLEND_MAX)
                gl->BlendEquation(GL_MAX);
            gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(e - k));
            gl->BlendEquation(GL_FUNC_ADD);
        }
    }
}

/* The dynamic layer over a restored target: as draw_shapes and draw_text
 * draw it, except that an item unchanged since the last frame (plan.same)
 * is drawn only inside the damage rectangles, where the restore covered it. */
static void draw_dynamic_kept(struct sp_draw_gl *d, const struct sp_draw_plan *p, int text)
{
    const struct sp_gl_api *gl = d->gl;
    const struct sp_canvas *c = p->list;
    const unsigned char *same = p->same;
    float cl[4] = {0, 0, 0, 0};
    int start = -1, end = 0, blend = 0;
    shapes_bind(gl, &d->shape);
    for (int i = 0; i <= c->n_items; i++) { /* shapes, in runs of changed items */
        const struct sp_item *it = i < c->n_items ? &c->items[i] : NULL;
        const int mine = it && it->kind != SP_ITEM_TEXT && it->kind != SP_ITEM_CLIP &&
                         it->layer == SP_LAYER_DYNAMIC;
        if (it && it->kind == SP_ITEM_TEXT)
            continue; /* runs go on across text, as draw_shapes' do */
        const int joins = mine && !same[i] && start >= 0 && it->first == end && (int)it->blend == blend;
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
        else if (mine && same[i])
            draw_unchanged(d, p, i);
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
        if (it && !same[i] && start >= 0 && it->first == end) {
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
        if (same[i])
            draw_unchanged(d, p, i);
        else
            start = it->first, end = it->first + it->count;
    }
    gl->Disable(GL_SCISSOR_TEST);
    text_base(gl, 0);
}

/* Copies base over the plan's damage, in one instanced draw without
 * blending. */
static int damage_restore(struct sp_draw_gl *d, const struct sp_draw_plan *p)
{
    const struct sp_gl_api *gl = d->gl;
    int err = d->patch.program ? 0 : patches_upload(d, NULL, 0);
    if (err || !p->n_damage)
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
    instances_upload(gl, &d->restore, p->damage, p->n_damage, sizeof(struct sp_draw_rect));
    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, sizeof(struct sp_draw_rect),
                            (const void *)offsetof(struct sp_draw_rect, rect));
    gl->VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(struct sp_draw_rect),
                            (const void *)offsetof(struct sp_draw_rect, fill));
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, d->base_tex);
    gl->Disable(GL_BLEND);
    gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, p->n_damage);
    gl->Enable(GL_BLEND);
    return 0;
}

/* Rebuilds base (plan.rebuild): the long exposure or the background, then
 * the static layer's shapes and text, then the settled layer, drawn into
 * the target itself and copied; then uploads base's rectangles. */
static int base_rebuild(struct sp_draw_gl *d, const struct sp_draw_plan *p, const float bg[4],
                        GLint target, int text)
{
    const struct sp_gl_api *gl = d->gl;
    int err;
    if (!d->base_fbo && (err = layer_make(d, &d->base_fbo, &d->base_tex, bg, "the static layer")) != 0)
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
    draw_shapes(gl, p->list, STATIC_BIT, d->height);
    if (text)
        draw_text(gl, &d->text, d->atlas, p->list, STATIC_BIT);
    shapes_bind(gl, &d->shape);
    draw_shapes(gl, p->list, SETTLED_BIT, d->height);
    gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, d->base_fbo);
    gl->BlitFramebuffer(0, 0, d->width, d->height, 0, 0, d->width, d->height,
                        GL_COLOR_BUFFER_BIT, GL_NEAREST);
    gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    if (!p->rects)
        return 0;
    err = patches_upload(d, p->rects, p->n_rects);
    d->n_patches = p->n_rects;
    return err;
}

/* Puts under the dynamic layer what the plan says (plan.under). */
static int draw_under(struct sp_draw_gl *d, const struct sp_draw_plan *p, const float bg[4])
{
    const struct sp_gl_api *gl = d->gl;
    switch (p->under) {
    case SP_DRAW_UNDER_REBUILT:
        return 0;
    case SP_DRAW_UNDER_RESTORE: /* base where the last frame's dynamic items were */
        return damage_restore(d, p);
    case SP_DRAW_UNDER_BASE: /* base over the whole frame */
        return layer_copy(d, d->base_tex);
    case SP_DRAW_UNDER_ACCUM: /* the accumulated picture instead of the background */
        return layer_copy(d, d->accum_tex);
    case SP_DRAW_UNDER_RECTS: /* the background, and base where it differs from it */
    case SP_DRAW_UNDER_CLEAR:
        gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
        gl->Clear(GL_COLOR_BUFFER_BIT);
        break;
    }
    return p->under == SP_DRAW_UNDER_RECTS ? patches_draw(d, d->base_tex, 1, d->n_patches) : 0;
}

int sp_draw_gl_list(struct sp_draw_gl *d, const struct sp_canvas *c, const float bg[4])
{
    const struct sp_gl_api *gl = d->gl;
    GLint target = 0;
    GLenum glerr;
    int err;
    struct sp_draw_plan p;
    const int text = c->n_quads && d->atlas;
    for (int i = 0; i < c->n_items; i++)
        if (c->items[i].kind == SP_ITEM_IMAGE ||
            (c->items[i].kind == SP_ITEM_TEXT && c->items[i].scale > 0)) {
            sp_log_error("the GL backend draws no images or turned text; a draw list that "
                         "has them is drawn with cairo (canvas.h)");
            return SP_E_INPUT;
        }
    if (text)
        atlas_sync(d);
    if ((err = sp_draw_cache_plan(d->cache, c, bg, &p)) != 0)
        return err;
    c = p.list;
    if (c->n_shapes)
        instances_upload(gl, &d->shape, c->shapes, c->n_shapes, sizeof(struct sp_shape));
    gl->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (p.accum) { /* what is new of the accumulated layer, into its picture */
        if (!d->accum_fbo && (err = layer_make(d, &d->accum_fbo, &d->accum_tex, bg, "the long exposure")) != 0)
            return err;
        gl->BindFramebuffer(GL_FRAMEBUFFER, d->accum_fbo);
        shapes_bind(gl, &d->shape);
        draw_shapes(gl, c, ACCUM_BIT, d->height);
        if (p.accum_in_base) { /* and into base, under nothing */
            gl->BindFramebuffer(GL_FRAMEBUFFER, d->base_fbo);
            draw_shapes(gl, c, ACCUM_BIT, d->height);
        }
        gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    }
    if (text)
        instances_upload(gl, &d->text, c->quads, c->n_quads, sizeof(struct sp_glyph_quad));
    if (p.rebuild && (err = base_rebuild(d, &p, bg, target, text)) != 0)
        return err;
    if (p.n_new) {
        /* what is new of the settled layer, into base (which has the
         * target's pixel format and orientation: the same pixels as
         * drawing it into the target) */
        gl->BindFramebuffer(GL_FRAMEBUFFER, d->base_fbo);
        shapes_bind(gl, &d->shape);
        settled_draw_new(d, &p);
        gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    }
    if ((err = draw_under(d, &p, bg)) != 0)
        return err;
    const unsigned layers = p.cached ? DYNAMIC_BIT : DYNAMIC_BIT | STATIC_BIT | SETTLED_BIT;
    if (p.same) {
        draw_dynamic_kept(d, &p, text);
    } else {
        if (c->n_shapes) {
            shapes_bind(gl, &d->shape);
            draw_shapes(gl, c, layers, d->height);
        }
        if (text)
            draw_text(gl, &d->text, d->atlas, c, layers);
    }
    sp_draw_cache_drawn(d->cache, &p);
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("drawing a frame failed with GL error 0x%04x", glerr);
        return SP_E_GL;
    }
    return 0;
}

void sp_draw_gl_cache(struct sp_draw_gl *d, int on)
{
    sp_draw_cache_set(d->cache, on);
}

void sp_draw_gl_stats(const struct sp_draw_gl *d, struct sp_draw_cache_stats *out)
{
    sp_draw_cache_stats(d->cache, out);
}

void sp_draw_gl_destroy(struct sp_draw_gl **d)
{
    if (!*d)
        return;
    sp_draw_cache_destroy(&(*d)->cache);
    free(*d);
    *d = NULL;
}
