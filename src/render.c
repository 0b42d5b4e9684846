/* springpend: the off-screen renderer. Every shape is a capsule instance
 * (segment + radius + colour, see shaders/shape.vert), built on the CPU in
 * pixel coordinates and drawn by one program in two instanced draw calls:
 * the trail with GL_MAX blending (no double-blended beads at its joints),
 * then mount, spring, pivot and bob with premultiplied "over". */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <GL/glcorearb.h>

#include "springpend/common.h"
#include "springpend/render.h"
#include "embedded.h"
#include "gl_context.h"

/* The GL functions we call, looked up through the context backend. */
#define SP_GL_FUNCS(X)                                              \
    X(PFNGLGETSTRINGPROC, GetString)                                \
    X(PFNGLGETERRORPROC, GetError)                                  \
    X(PFNGLCREATESHADERPROC, CreateShader)                          \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                          \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                        \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                            \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                  \
    X(PFNGLDELETESHADERPROC, DeleteShader)                          \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                        \
    X(PFNGLATTACHSHADERPROC, AttachShader)                          \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                            \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                          \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                              \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)              \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                    \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                    \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                              \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                              \
    X(PFNGLBUFFERDATAPROC, BufferData)                              \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                        \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)    \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)            \
    X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)            \
    X(PFNGLVIEWPORTPROC, Viewport)                                  \
    X(PFNGLCLEARCOLORPROC, ClearColor)                              \
    X(PFNGLCLEARPROC, Clear)                                        \
    X(PFNGLENABLEPROC, Enable)                                      \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                        \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                \
    X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)

struct gl_api {
#define X(type, name) type name;
    SP_GL_FUNCS(X)
#undef X
};

/* One capsule; layout matches the attributes of shape.vert. */
struct instance {
    float seg[4];   /* p0.xy, p1.xy: px, y down from the top-left corner */
    float style[2]; /* half width (px), kind (0 flat, 1 lit ball) */
    float color[4]; /* straight RGBA, 0..1 */
};

enum {
    COIL_TURNS = 12,
    COIL_STEPS = 16,                      /* polyline segments per turn */
    COIL_SEGS = COIL_TURNS * COIL_STEPS,
    HATCHES = 7,
    /* mount bar + hatches + 2 leads + coil + pivot + bob */
    FIXED_INSTANCES = 1 + HATCHES + 2 + COIL_SEGS + 1 + 1,
    TRAIL_INITIAL = 1024, /* trail segments room before the first growth */
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

/* Colours, straight RGBA. */
static const float BACKGROUND[4] = {0x12 / 255.f, 0x16 / 255.f, 0x1c / 255.f, 1};
static const float MOUNT[4] = {0.56f, 0.60f, 0.66f, 1};
static const float WIRE_FRONT[4] = {0.80f, 0.82f, 0.85f, 1};
static const float WIRE_BACK[4] = {0.47f, 0.50f, 0.55f, 1};
static const float PIVOT[4] = {0.86f, 0.88f, 0.91f, 1};
static const float BOB[4] = {0.93f, 0.33f, 0.16f, 1};

struct sp_renderer {
    struct sp_gl_context *ctx;
    int transparent; /* background alpha 0; pixels un-premultiplied */
    struct gl_api gl;
    GLuint program, vao, vbo;
    struct instance *inst; /* staging for one frame, `capacity` entries */
    int capacity;          /* instances the staging array and the VBO hold */
    int width, height;     /* px */
    float unit;            /* the smaller side, px */
    double scale;          /* px per m */
    double ox, oy;         /* px of the world origin (the pivot) */
    double max_speed;      /* m/s, the top of the trail's colormap */
    const char *name;      /* GL_RENDERER */
};

static int load_gl(struct sp_renderer *r)
{
#define X(type, name)                                                    \
    r->gl.name = (type)sp_gl_context_proc(r->ctx, "gl" #name);           \
    if (!r->gl.name) {                                                   \
        sp_log_error("the GL context lacks gl" #name);                   \
        return SP_E_GL;                                                  \
    }
    SP_GL_FUNCS(X)
#undef X
    return 0;
}

/* Compiles one stage; returns 0 after logging the driver's message. */
static GLuint compile(const struct gl_api *gl, GLenum type, const char *src,
                      const char *what)
{
    GLuint sh = gl->CreateShader(type);
    GLint ok = 0;
    char msg[1024] = "";

    gl->ShaderSource(sh, 1, &src, NULL);
    gl->CompileShader(sh);
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        gl->GetShaderInfoLog(sh, sizeof(msg), NULL, msg);
        sp_log_error("compiling %s: %s", what, msg);
        gl->DeleteShader(sh);
        return 0;
    }
    return sh;
}

static int make_program(struct sp_renderer *r)
{
    const struct gl_api *gl = &r->gl;
    GLuint vs = compile(gl, GL_VERTEX_SHADER, sp_embed_shape_vert, "shape.vert");
    GLuint fs = compile(gl, GL_FRAGMENT_SHADER, sp_embed_shape_frag, "shape.frag");
    GLint ok = 0;
    char msg[1024] = "";
    int err = SP_E_GL;

    if (!vs || !fs)
        goto done;
    r->program = gl->CreateProgram();
    gl->AttachShader(r->program, vs);
    gl->AttachShader(r->program, fs);
    gl->LinkProgram(r->program);
    gl->GetProgramiv(r->program, GL_LINK_STATUS, &ok);
    if (!ok) {
        gl->GetProgramInfoLog(r->program, sizeof(msg), NULL, msg);
        sp_log_error("linking the shape shaders: %s", msg);
        goto done;
    }
    err = 0;
done:
    if (vs)
        gl->DeleteShader(vs);
    if (fs)
        gl->DeleteShader(fs);
    return err;
}

/* Points the instance attributes at entry `first` of the bound VBO. */
static void set_instance_base(const struct gl_api *gl, int first)
{
    const size_t base = (size_t)first * sizeof(struct instance);
    const GLsizei stride = sizeof(struct instance);

    gl->VertexAttribPointer(0, 4, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct instance, seg)));
    gl->VertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct instance, style)));
    gl->VertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride,
                            (const void *)(base + offsetof(struct instance, color)));
}

/* Grows the staging array and the VBO to hold n instances (rarely: only when
 * a longer trail than before arrives). */
static int reserve(struct sp_renderer *r, int n)
{
    struct instance *inst;
    int cap = r->capacity ? r->capacity : n;

    if (n <= r->capacity)
        return 0;
    while (cap < n)
        cap *= 2;
    inst = realloc(r->inst, (size_t)cap * sizeof(*inst));
    if (!inst) {
        sp_log_error("out of memory for %d render instances", cap);
        return SP_E_NOMEM;
    }
    r->inst = inst;
    r->capacity = cap;
    r->gl.BufferData(GL_ARRAY_BUFFER, (GLsizeiptr)cap * sizeof(*inst), NULL,
                     GL_STREAM_DRAW);
    return 0;
}

/* Fits the extent plus a margin into the image, equal scale on both axes. */
static void fit_camera(struct sp_renderer *r, const struct sp_view_extent *e)
{
    const double margin = (BOB_RADIUS + MARGIN) * r->unit;
    const double ew = fmax(e->xmax - e->xmin, 1e-6);
    const double eh = fmax(e->ymax - e->ymin, 1e-6);
    const double aw = fmax(r->width - 2 * margin, 1.0);
    const double ah = fmax(r->height - 2 * margin, 1.0);

    r->scale = fmin(aw / ew, ah / eh);
    r->ox = 0.5 * r->width - r->scale * 0.5 * (e->xmin + e->xmax);
    r->oy = 0.5 * r->height + r->scale * 0.5 * (e->ymin + e->ymax);
    r->max_speed = e->max_speed > 0 ? e->max_speed : 1.0;
}

int sp_render_make(struct sp_renderer **out, const struct sp_render_desc *desc)
{
    struct sp_renderer *r = calloc(1, sizeof(*r));
    const struct gl_api *gl;
    GLenum glerr;
    int err;

    *out = NULL;
    if (!r) {
        sp_log_error("out of memory for the renderer");
        return SP_E_NOMEM;
    }
    err = sp_gl_context_make(&r->ctx, desc->width, desc->height, desc->gl);
    if (err)
        goto fail;
    err = load_gl(r);
    if (err)
        goto fail;
    gl = &r->gl;
    r->width = desc->width;
    r->height = desc->height;
    r->unit = (float)(desc->width < desc->height ? desc->width : desc->height);
    r->name = (const char *)gl->GetString(GL_RENDERER);
    fit_camera(r, &desc->extent);

    err = make_program(r);
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
    err = reserve(r, FIXED_INSTANCES + TRAIL_INITIAL);
    if (err)
        goto fail;
    gl->Viewport(0, 0, r->width, r->height);
    gl->Enable(GL_BLEND);
    r->transparent = desc->transparent;
    if (r->transparent) {
        /* Premultiplied over for colour and alpha on a clear background;
         * sp_render_draw un-premultiplies. */
        gl->ClearColor(0, 0, 0, 0);
        gl->BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ONE,
                              GL_ONE_MINUS_SRC_ALPHA);
    } else {
        gl->ClearColor(BACKGROUND[0], BACKGROUND[1], BACKGROUND[2], 1.0f);
        /* Colour: premultiplied over; alpha stays the cleared 1 (opaque). */
        gl->BlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    }
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

/* ---- geometry, all in px ---- */

static void to_px(const struct sp_renderer *r, double x, double y, float p[2])
{
    p[0] = (float)(r->ox + r->scale * x);
    p[1] = (float)(r->oy - r->scale * y);
}

static struct instance *put(struct instance *in, const float a[2],
                            const float b[2], float radius, float kind,
                            const float color[4], float alpha)
{
    *in = (struct instance){
        {a[0], a[1], b[0], b[1]}, {radius, kind},
        {color[0], color[1], color[2], color[3] * alpha},
    };
    return in + 1;
}

/* Inferno colormap, t in [0, 1] (polynomial fit by Matt Zucker, CC0). */
static void inferno(float t, float rgb[3])
{
    static const float c[7][3] = {
        {0.0002189404f, 0.0016510046f, -0.0194808984f},
        {0.1065134195f, 0.5639564368f, 3.9327123889f},
        {11.6024930825f, -3.9728539657f, -15.9423941063f},
        {-41.7039961314f, 17.4363988821f, 44.3541451987f},
        {77.1629356994f, -33.4023589421f, -81.8073092574f},
        {-71.3194282450f, 32.6260642640f, 73.2095198580f},
        {25.1311262248f, -12.2426689524f, -23.0703250029f},
    };
    for (int k = 0; k < 3; k++) {
        float v = c[6][k];
        for (int i = 5; i >= 0; i--)
            v = v * t + c[i][k];
        rgb[k] = fminf(fmaxf(v, 0.0f), 1.0f);
    }
}

/* Trail segments, oldest first: colour by speed, fading and thinning with
 * age. Returns the end of what it wrote. */
static struct instance *put_trail(const struct sp_renderer *r,
                                  const struct sp_trail *tr, struct instance *in)
{
    const float w = TRAIL_RADIUS * r->unit;
    float a[2], b[2], color[4] = {0, 0, 0, 1};
    const struct sp_trail_point *p = sp_trail_at(tr, 0);

    to_px(r, p->x, p->y, a);
    for (int i = 1; i < tr->count; i++) {
        const struct sp_trail_point *q = sp_trail_at(tr, i);
        const float age = (float)i / (float)(tr->count - 1); /* 1 = newest */
        const float speed = 0.5f * (p->speed + q->speed);

        to_px(r, q->x, q->y, b);
        inferno(0.18f + 0.82f * fminf(speed / (float)r->max_speed, 1.0f), color);
        in = put(in, a, b, w * (0.55f + 0.45f * age), 0, color,
                 0.03f + 0.97f * powf(age, 1.4f));
        a[0] = b[0];
        a[1] = b[1];
        p = q;
    }
    return in;
}

/* Ceiling: a bar just above the pivot with hatch strokes above it. */
static struct instance *put_mount(const struct sp_renderer *r, const float pv[2],
                                  struct instance *in)
{
    const float u = r->unit, half = MOUNT_HALF * u, wr = WIRE_RADIUS * u;
    const float y = pv[1] - PIVOT_RADIUS * u - wr;
    const float hatch = 0.012f * u;

    in = put(in, (float[2]){pv[0] - half, y}, (float[2]){pv[0] + half, y},
             1.2f * wr, 0, MOUNT, 1);
    for (int i = 0; i < HATCHES; i++) {
        const float x = pv[0] - half + hatch + (2 * half - hatch) * i / (HATCHES - 1);
        in = put(in, (float[2]){x - hatch, y - wr - hatch}, (float[2]){x, y - wr},
                 0.55f * wr, 0, MOUNT, 1);
    }
    return in;
}

/* The spring from pivot pv to bob bb: straight leads, then COIL_TURNS turns of
 * a helix seen slightly from the side, its pitch stretching with the length.
 * Segments behind the axis are written first (darker), so the front ones
 * cover them. */
static struct instance *put_spring(const struct sp_renderer *r, const float pv[2],
                                   const float bb[2], struct instance *in)
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
    in = put(in, pv, c0, wr, 0, WIRE_FRONT, 1);
    in = put(in, c1, bb, wr, 0, WIRE_FRONT, 1);

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
                in = put(in, a, b, wr, 0, front ? WIRE_FRONT : WIRE_BACK, 1);
            a[0] = b[0];
            a[1] = b[1];
        }
    }
    return in;
}

/* Premultiplied RGBA (what GL blended) to straight alpha, in place. */
static void unpremultiply(const struct sp_image *img)
{
    for (int y = 0; y < img->height; y++) {
        uint8_t *p = img->pixels + (size_t)y * img->stride;
        for (int x = 0; x < img->width; x++, p += 4) {
            unsigned a = p[3];
            if (a == 0 || a == 255)
                continue;
            for (int c = 0; c < 3; c++) {
                unsigned v = (p[c] * 255u + a / 2) / a;
                p[c] = (uint8_t)(v > 255 ? 255 : v);
            }
        }
    }
}

int sp_render_draw(struct sp_renderer *r, const struct sp_frame *f,
                   struct sp_image *img)
{
    const struct gl_api *gl = &r->gl;
    const int trail_segs = f->trail && f->trail->count > 1 ? f->trail->count - 1 : 0;
    struct instance *in, *rest;
    float pv[2], bb[2];
    GLenum glerr;
    int stride, err;

    err = sp_gl_context_bind(r->ctx);
    if (!err)
        err = reserve(r, FIXED_INSTANCES + trail_segs);
    if (err)
        return err;
    to_px(r, 0, 0, pv);
    to_px(r, f->state.x, f->state.y, bb);
    rest = trail_segs ? put_trail(r, f->trail, r->inst) : r->inst;
    in = put_mount(r, pv, rest);
    in = put_spring(r, pv, bb, in);
    in = put(in, pv, pv, PIVOT_RADIUS * r->unit, 0, PIVOT, 1);
    in = put(in, bb, bb, BOB_RADIUS * r->unit, 1, BOB, 1);

    gl->BufferSubData(GL_ARRAY_BUFFER, 0, (in - r->inst) * sizeof(*in), r->inst);
    gl->Clear(GL_COLOR_BUFFER_BIT);
    if (trail_segs) {
        gl->BlendEquation(GL_MAX);
        set_instance_base(gl, 0);
        gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, trail_segs);
        gl->BlendEquation(GL_FUNC_ADD);
    }
    set_instance_base(gl, (int)(rest - r->inst));
    gl->DrawArraysInstanced(GL_TRIANGLE_STRIP, 0, 4, (GLsizei)(in - rest));
    glerr = gl->GetError();
    if (glerr != GL_NO_ERROR) {
        sp_log_error("drawing a frame failed with GL error 0x%04x", glerr);
        return SP_E_GL;
    }
    img->pixels = sp_gl_context_pixels(r->ctx, &stride);
    img->width = r->width;
    img->height = r->height;
    img->stride = stride;
    if (r->transparent)
        unpremultiply(img);
    return 0;
}

int sp_render_target(struct sp_renderer *r, const struct sp_image *dst)
{
    if (dst && (dst->width != r->width || dst->height != r->height ||
                dst->stride != 4 * r->width)) {
        sp_log_error("render target %dx%d (stride %d) is not the renderer's "
                     "%dx%d", dst->width, dst->height, dst->stride, r->width,
                     r->height);
        return SP_E_INPUT;
    }
    int err = sp_gl_context_bind(r->ctx);
    if (!err)
        sp_gl_context_target(r->ctx, dst ? dst->pixels : NULL);
    return err;
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
    /* The program, VAO and VBO die with their context. */
    sp_gl_context_destroy(&r->ctx);
    free(r->inst);
    free(r);
    *rp = NULL;
}
