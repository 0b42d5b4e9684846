/* springpend (internal): the backends' framebuffer. See gl_offscreen.h. */
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "gl_offscreen.h"

#ifndef GL_PACK_INVERT_MESA
#define GL_PACK_INVERT_MESA 0x8758
#endif

int sp_gl_offscreen_make(struct sp_gl_offscreen *o, void *(*getproc)(const char *name),
                         const char *who, int width, int height)
{
    *o = (struct sp_gl_offscreen){.width = width, .height = height};
#define X(type, name)                                                        \
    if (!(*(void **)&o->gl.name = getproc("gl" #name))) {                    \
        sp_log_error("%s's GL lacks gl" #name, who);                         \
        return SP_E_GL;                                                      \
    }
    SP_GL_OFFSCREEN_FUNCS(X)
#undef X
    if (!(o->row = malloc((size_t)width * 4))) {
        sp_log_error("out of memory for a %dx%d GL colour buffer", width, height);
        return SP_E_NOMEM;
    }
    o->gl.GenTextures(1, &o->tex);
    o->gl.BindTexture(GL_TEXTURE_2D, o->tex);
    o->gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                     NULL);
    o->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST); /* no mipmaps */
    o->gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    o->gl.BindTexture(GL_TEXTURE_2D, 0);
    o->gl.GenFramebuffers(1, &o->fbo);
    o->gl.BindFramebuffer(GL_FRAMEBUFFER, o->fbo);
    o->gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, o->tex, 0);
    GLenum status = o->gl.CheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        sp_log_error("%s: a %dx%d RGBA8 framebuffer is incomplete (0x%x)", who, width, height,
                     status);
        return SP_E_GL;
    }
    GLint n = 0;
    o->gl.GetIntegerv(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; i++) {
        const char *e = (const char *)o->gl.GetStringi(GL_EXTENSIONS, (GLuint)i);
        if (e && !strcmp(e, "GL_MESA_pack_invert"))
            o->pack_invert = 1;
    }
    o->gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    if (o->pack_invert)
        o->gl.PixelStorei(GL_PACK_INVERT_MESA, 1);
    return 0;
}

void sp_gl_offscreen_bind(struct sp_gl_offscreen *o)
{
    o->gl.BindFramebuffer(GL_FRAMEBUFFER, o->fbo);
}

void sp_gl_offscreen_read(struct sp_gl_offscreen *o, uint8_t *dst)
{
    const size_t row = 4 * (size_t)o->width;
    o->gl.BindFramebuffer(GL_READ_FRAMEBUFFER, o->fbo);
    o->gl.ReadPixels(0, 0, o->width, o->height, GL_RGBA, GL_UNSIGNED_BYTE, dst);
    if (!o->pack_invert)
        for (int y = 0; y < o->height / 2; y++) {
            uint8_t *a = dst + y * row;
            uint8_t *b = dst + (o->height - 1 - y) * row;
            memcpy(o->row, a, row);
            memcpy(a, b, row);
            memcpy(b, o->row, row);
        }
}

void sp_gl_offscreen_destroy(struct sp_gl_offscreen *o, int current)
{
    if (current && o->fbo)
        o->gl.DeleteFramebuffers(1, &o->fbo);
    if (current && o->tex)
        o->gl.DeleteTextures(1, &o->tex);
    free(o->row);
    *o = (struct sp_gl_offscreen){0};
}
