/* springpend (internal): the framebuffer every GL context backend draws
 * into: an RGBA8 texture in a framebuffer object (a texture, so that a last
 * pass can sample the frame: yuv_gl.h), read back into a
 * caller's buffer top row first (through GL_MESA_pack_invert where the
 * driver has it, else flipped here). Both backends drawing into the same
 * kind of framebuffer, with the same orientation, as the static cache's
 * textures (draw_gl.c) is what lets the cache draw into those textures and
 * get the very pixels it would get in the target. */
#ifndef SPRINGPEND_GL_OFFSCREEN_H
#define SPRINGPEND_GL_OFFSCREEN_H

#include <stdint.h>

#include <GL/glcorearb.h>

/* GL 1.1 entry points, typed here: a backend's header (GL/gl.h, from
 * osmesa.h) may have hidden glcorearb.h's 1.1 section. */
typedef void (*sp_gl_gen_textures)(GLsizei n, GLuint *textures);
typedef void (*sp_gl_bind_texture)(GLenum target, GLuint texture);
typedef void (*sp_gl_delete_textures)(GLsizei n, const GLuint *textures);

/* GL entry points the framebuffer calls. */
#define SP_GL_OFFSCREEN_FUNCS(X)                                             \
    X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                             \
    X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                             \
    X(sp_gl_gen_textures, GenTextures)                                       \
    X(sp_gl_bind_texture, BindTexture)                                       \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                                       \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                                 \
    X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)                   \
    X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)               \
    X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                       \
    X(sp_gl_delete_textures, DeleteTextures)                                 \
    X(PFNGLREADPIXELSPROC, ReadPixels)                                       \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                                     \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                                     \
    X(PFNGLGETSTRINGIPROC, GetStringi)

struct sp_gl_offscreen {
    struct {
#define X(type, name) type name;
        SP_GL_OFFSCREEN_FUNCS(X)
#undef X
    } gl;
    GLuint fbo, tex;  /* 0 = none; tex: the colour buffer, RGBA8, row 0 the
                         image's bottom row */
    int pack_invert;  /* GL_MESA_pack_invert: rows come top first */
    uint8_t *row;     /* one row of scratch for flipping, owned */
    int width, height; /* px */
};

/* Loads the functions with getproc ("glName" -> address), makes a
 * width x height framebuffer and binds it. The context must be current.
 * `who` names the backend in messages. 0, SP_E_GL or SP_E_NOMEM (logged). */
int sp_gl_offscreen_make(struct sp_gl_offscreen *o, void *(*getproc)(const char *name),
                         const char *who, int width, int height);

/* Binds the framebuffer (after the context was made current again). */
void sp_gl_offscreen_bind(struct sp_gl_offscreen *o);

/* Waits for GL and copies the pixels into dst (width * height * 4 bytes,
 * stride 4 * width, top row first). */
void sp_gl_offscreen_read(struct sp_gl_offscreen *o, uint8_t *dst);

/* Frees the GL objects (the context must be current, or gone: then only
 * the memory) and the memory. */
void sp_gl_offscreen_destroy(struct sp_gl_offscreen *o, int current);

#endif
