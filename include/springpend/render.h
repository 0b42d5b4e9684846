/* springpend: the off-screen renderer. Draws one sp_frame into an RGBA
 * image: background, trail, stroboscopic images, ceiling mount, spring coil,
 * bob, then the panels, heads-up text and colourbar the look (sp_look) asks
 * for. Antialiased analytically in the shaders (no MSAA), optionally
 * supersampled. Knows nothing of files. */
#ifndef SPRINGPEND_RENDER_H
#define SPRINGPEND_RENDER_H

#include "springpend/frame.h"
#include "springpend/image.h"

/* Which headless GL stack draws. Each library is loaded on first use, so
 * commands that never render do not pay for it. */
enum sp_gl {
    SP_GL_DEFAULT = 0, /* OSMesa where it loads, else EGL */
    SP_GL_OSMESA,      /* libOSMesa (Mesa's llvmpipe); gone from Mesa 25.1 */
    SP_GL_EGL,         /* libEGL, surfaceless Mesa platform (a GPU if any) */
};

struct sp_render_desc {
    int width, height;            /* px of the output image */
    struct sp_view_extent extent; /* world rectangle to fit, speed and panel ranges */
    const struct sp_look *look;   /* what is drawn and how (sp_look_of a scene);
                                     NULL = the default scene's */
    int supersample;              /* draw at this many times the size and average
                                     down; 0 or 1 = off */
    enum sp_gl gl;                /* GL backend; 0 = default */
    int cells;                    /* scenes side by side, 2..4, each in its cell
                                     with looks[i]; 0 or 1 = look alone */
    const struct sp_look *looks;  /* cells of them, when cells > 1 */
};

struct sp_renderer;

/* Creates the GL context (see gl_context.h) and the GPU resources. */
int sp_render_make(struct sp_renderer **out, const struct sp_render_desc *desc);

/* Draws f (side by side: f[0..cells), one frame per cell). On success
 * *img points at the renderer's own pixels (top row first), valid until the
 * next draw or destroy; the caller must not free. */
int sp_render_draw(struct sp_renderer *r, const struct sp_frame *f,
                   struct sp_image *img);

/* Makes the following draws land in dst's pixels (dst must be width x
 * height, and outlive its use) instead of the renderer's own buffer; NULL
 * goes back. Saves a copy per frame. dst is RGBA with stride 4 * width, or,
 * with an opaque background, SP_IMAGE_YUV420 as sp_image_alloc_yuv420 makes it: a last GL
 * pass then converts the frame (BT.709 limited range, chroma sited left)
 * and reads back 1.5 bytes a pixel instead of 4. */
int sp_render_target(struct sp_renderer *r, const struct sp_image *dst);

/* Where a renderer's time went so far: seconds of wall time composing the
 * draw lists on the CPU and drawing them with GL (with the readback, or
 * the resolve when supersampled or transparent), and what the static
 * cache did (frames drawn over it, times it was redrawn, frames drawn
 * without it, frames that appended to the charts' settled curves in it,
 * dynamic items left as the last frame drew them). */
struct sp_render_stats {
    double compose_s, draw_s;
    long cached, redrawn, uncached, appended, unchanged;
    int glyphs, glyphs_first;       /* glyphs rasterised: in all, by the first frame */
    double raster_s, raster_first_s; /* and the seconds that took */
    int lines_shaped, lines_composed; /* lines shaped whole, joined from cached pieces */
};
void sp_render_stats(const struct sp_renderer *r, struct sp_render_stats *out);

/* The font files the text drawn so far came from, ", "-separated, into buf
 * (cut to size; "" without text). */
void sp_render_fonts(const struct sp_renderer *r, char *buf, size_t size);

/* Adds each of those font files, with its SHA-256, to the environment text
 * in buf (environment.h: sp_environment_add_font). 0 or an SP_E_* code. */
int sp_render_font_environment(const struct sp_renderer *r, char *buf, size_t size);

/* The overlays' scales after the first frame (compose.h's
 * sp_compose_overlay): "" unless [view] vectors or the energy_bars panel is
 * drawn. */
void sp_render_overlay(const struct sp_renderer *r, char *buf, size_t size);

/* The GL_RENDERER string of the context, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)". */
const char *sp_render_renderer_name(const struct sp_renderer *r);

/* Frees everything and sets *r to NULL. Safe on NULL. */
void sp_render_destroy(struct sp_renderer **r);

/* GL_VERSION of r's context ("4.5 (Core Profile) Mesa 22.3.6"). */
const char *sp_render_gl_version(const struct sp_renderer *r);

/* Makes a 16x16 GL context of backend gl only to read GL_RENDERER and
 * GL_VERSION into renderer and version; returns 0 or the context's error. */
int sp_render_probe(enum sp_gl gl, char *renderer, size_t renderer_size, char *version,
                    size_t version_size);

#endif
