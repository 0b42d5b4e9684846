/* springpend (internal): the draw list drawn with GL. See draw_gl.h. */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "draw_gl.h"
#include "embedded.h"

struct instances {
    GLuint program, vao, vbo;
    int capacity; /* instances the VBO holds */
};

struct sp_draw_gl {
    const struct sp_gl_api *gl;
    struct instances shape, text;
    GLuint atlas;
    GLuint accum_fbo, accum_tex; /* SP_LAYER_ACCUM's picture; 0 = none yet */
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

static void shape_base(const struct sp_gl_api *gl, int first)
{
    static const size_t off[3] = {offsetof(struct sp_shape, seg), offsetof(struct sp_shape, style),
                                  offsetof(struct sp_shape, color)};
    static const GLint comps[3] = {4, 2, 4};
    instances_base(gl, first, sizeof(struct sp_shape), off, comps);
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
    err = instances_make(gl, &d->shape, sp_embed_shape_vert, sp_embed_shape_frag, "shape",
                         width, height);
    if (!err && font) {
        static const size_t off[3] = {offsetof(struct sp_glyph_quad, rect),
                                      offsetof(struct sp_glyph_quad, uv),
                                      offsetof(struct sp_glyph_quad, color)};
        static const GLint comps[3] = {4, 4, 4};
        int aw, ah;
        const uint8_t *atlas = sp_font_atlas(font, &aw, &ah);
        err = instances_make(gl, &d->text, sp_embed_text_vert, sp_embed_text_frag, "text",
                             width, height);
        if (!err) {
            gl->Uniform2f(gl->GetUniformLocation(d->text.program, "u_atlas"), (float)aw, (float)ah);
            gl->Uniform1i(gl->GetUniformLocation(d->text.program, "u_atlas_tex"), 0);
            gl->ActiveTexture(GL_TEXTURE0);
            gl->GenTextures(1, &d->atlas);
            gl->BindTexture(GL_TEXTURE_2D, d->atlas);
            gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
            gl->TexImage2D(GL_TEXTURE_2D, 0, GL_R8, aw, ah, 0, GL_RED, GL_UNSIGNED_BYTE, atlas);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
            gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
            instances_base(gl, 0, sizeof(struct sp_glyph_quad), off, comps);
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

/* One instanced draw per run of shape items with the same blending and
 * clip, over the items of the accumulated layer (accum = 1, not clipped)
 * or the others. */
static void draw_shapes(const struct sp_gl_api *gl, const struct sp_canvas *c, int accum, int height)
{
    for (int i = 0; i < c->n_items; i++) {
        const struct sp_item *it = &c->items[i];
        if (it->kind == SP_ITEM_CLIP && !accum)
            clip(gl, it->clip, height);
        if (it->kind == SP_ITEM_TEXT || it->kind == SP_ITEM_CLIP ||
            (it->layer == SP_LAYER_ACCUM) != accum)
            continue;
        int end = it->first + it->count, j = i + 1;
        while (j < c->n_items && c->items[j].kind != SP_ITEM_CLIP &&
               (c->items[j].kind == SP_ITEM_TEXT ||
                ((c->items[j].layer == SP_LAYER_ACCUM) == accum && c->items[j].blend == it->blend))) {
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

/* Makes the accumulation texture and its framebuffer, cleared to bg
 * (premultiplied). 0 or SP_E_GL (logged). */
static int accum_make(struct sp_draw_gl *d, const float bg[4])
{
    const struct sp_gl_api *gl = d->gl;
    gl->GenTextures(1, &d->accum_tex);
    gl->BindTexture(GL_TEXTURE_2D, d->accum_tex);
    gl->TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, d->width, d->height, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    gl->GenFramebuffers(1, &d->accum_fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, d->accum_fbo);
    gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, d->accum_tex, 0);
    if (gl->CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        sp_log_error("GL cannot make a %dx%d framebuffer for the long exposure", d->width, d->height);
        return SP_E_GL;
    }
    gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    return 0;
}

int sp_draw_gl_list(struct sp_draw_gl *d, const struct sp_canvas *c, const float bg[4])
{
    const struct sp_gl_api *gl = d->gl;
    GLint target = 0;
    GLenum glerr;
    int accum = 0, err = 0;

    for (int i = 0; i < c->n_items && !accum; i++)
        accum = c->items[i].layer == SP_LAYER_ACCUM;
    if (c->n_shapes)
        instances_upload(gl, &d->shape, c->shapes, c->n_shapes, sizeof(struct sp_shape));
    gl->GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &target);
    if (accum) { /* what is new of the accumulated layer, into its picture */
        if (!d->accum_fbo && (err = accum_make(d, bg)) != 0)
            return err;
        gl->BindFramebuffer(GL_FRAMEBUFFER, d->accum_fbo);
        gl->UseProgram(d->shape.program);
        gl->BindVertexArray(d->shape.vao);
        draw_shapes(gl, c, 1, d->height);
        gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    }
    if (d->accum_fbo) { /* the accumulated picture instead of the background */
        gl->BindFramebuffer(GL_READ_FRAMEBUFFER, d->accum_fbo);
        gl->BlitFramebuffer(0, 0, d->width, d->height, 0, 0, d->width, d->height,
                            GL_COLOR_BUFFER_BIT, GL_NEAREST);
        gl->BindFramebuffer(GL_FRAMEBUFFER, (GLuint)target);
    } else {
        gl->ClearColor(bg[0] * bg[3], bg[1] * bg[3], bg[2] * bg[3], bg[3]);
        gl->Clear(GL_COLOR_BUFFER_BIT);
    }
    if (c->n_shapes) {
        gl->UseProgram(d->shape.program);
        gl->BindVertexArray(d->shape.vao);
        draw_shapes(gl, c, 0, d->height);
    }
    if (c->n_quads && d->atlas) {
        instances_upload(gl, &d->text, c->quads, c->n_quads, sizeof(struct sp_glyph_quad));
        gl->ActiveTexture(GL_TEXTURE0);
        gl->BindTexture(GL_TEXTURE_2D, d->atlas);
        gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, c->n_quads);
    }
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("drawing a frame failed with GL error 0x%04x", glerr);
        return SP_E_GL;
    }
    return 0;
}

void sp_draw_gl_destroy(struct sp_draw_gl **d)
{
    free(*d);
    *d = NULL;
}
