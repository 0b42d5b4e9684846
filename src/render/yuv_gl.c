/* springpend (internal): RGBA frame to YUV 4:2:0 planes in GL. See yuv_gl.h. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "springpend/common.h"
#include "springpend/image.h"
#include "base/embedded.h"
#include "yuv_gl.h"

#ifndef GL_PACK_INVERT_MESA
#define GL_PACK_INVERT_MESA 0x8758
#endif

/* The pass's four targets (shaders/yuv.frag), each (width + 7) / 8 x
 * height / 2 texels: a fragment per 8 x 2 block of pixels. */
enum { Y_EVEN, Y_ODD, CB, CR, N_TARGETS };

struct sp_yuv_gl {
    const struct sp_gl_api *gl;
    GLuint program;
    GLuint vao;              /* empty: the triangle comes from gl_VertexID */
    GLuint fbo, tex[N_TARGETS];
    int width, height;       /* px of the output image */
};

int sp_yuv_gl_make(struct sp_yuv_gl **out, const struct sp_gl_api *gl, int width, int height,
                   int ss)
{
    *out = NULL;
    if (width <= 0 || height <= 0 || width % 2 || height % 2 || ss < 1) {
        sp_log_error("YUV 4:2:0 needs an even width and height, got %dx%d", width, height);
        return SP_E_INPUT;
    }
    struct sp_yuv_gl *y = calloc(1, sizeof(*y));
    size_t n = strlen(sp_embed_yuv_frag) + 128;
    char *fs = malloc(n);
    if (!y || !fs) {
        free(y);
        free(fs);
        sp_log_error("out of memory for the YUV pass");
        return SP_E_NOMEM;
    }
    *y = (struct sp_yuv_gl){.gl = gl, .width = width, .height = height};
    /* The sizes as constants: the driver's compiler unrolls the loops. */
    snprintf(fs, n, "#version 330 core\n#define W %d\n#define H %d\n#define SS %d\n%s", width,
             height, ss, sp_embed_yuv_frag);
    int err = sp_gl_program_make(gl, sp_embed_yuv_vert, fs, "yuv", &y->program);
    free(fs);
    if (err) {
        free(y);
        return err;
    }
    gl->UseProgram(y->program);
    gl->Uniform1i(gl->GetUniformLocation(y->program, "u_frame"), 1); /* texture unit 1 */
    gl->GenVertexArrays(1, &y->vao);
    gl->GenTextures(N_TARGETS, y->tex);
    gl->GenFramebuffers(1, &y->fbo);
    gl->BindFramebuffer(GL_FRAMEBUFFER, y->fbo);
    GLenum bufs[N_TARGETS];
    for (int i = 0; i < N_TARGETS; i++) {
        const int luma = i == Y_EVEN || i == Y_ODD; /* 8 bytes a texel, else 4 */
        gl->BindTexture(GL_TEXTURE_2D, y->tex[i]);
        gl->TexImage2D(GL_TEXTURE_2D, 0, luma ? GL_RG32UI : GL_R32UI, (width + 7) / 8,
                       height / 2, 0, luma ? GL_RG_INTEGER : GL_RED_INTEGER, GL_UNSIGNED_INT,
                       NULL);
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST); /* no mipmaps */
        gl->TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        gl->FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i,
                                 GL_TEXTURE_2D, y->tex[i], 0);
        bufs[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
    }
    gl->BindTexture(GL_TEXTURE_2D, 0);
    gl->DrawBuffers(N_TARGETS, bufs);
    GLenum status = gl->CheckFramebufferStatus(GL_FRAMEBUFFER);
    gl->BindFramebuffer(GL_FRAMEBUFFER, 0);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
        sp_log_error("GL cannot make the %dx%d integer framebuffers for the YUV planes (0x%x)",
                     (width + 7) / 8, height / 2, status);
        free(y);
        return SP_E_GL;
    }
    *out = y;
    return 0;
}

void sp_yuv_gl_read(struct sp_yuv_gl *y, struct sp_gl_offscreen *fb, uint8_t *dst)
{
    const struct sp_gl_api *gl = y->gl;
    const int nx = (y->width + 7) / 8, ny = y->height / 2;
    GLint scissor = 0;
    gl->GetIntegerv(GL_SCISSOR_TEST, &scissor);
    gl->BindFramebuffer(GL_FRAMEBUFFER, y->fbo);
    gl->Viewport(0, 0, nx, ny);
    gl->Disable(GL_BLEND);
    gl->Disable(GL_SCISSOR_TEST);
    gl->UseProgram(y->program);
    gl->BindVertexArray(y->vao);
    gl->ActiveTexture(GL_TEXTURE1);
    gl->BindTexture(GL_TEXTURE_2D, fb->tex);
    gl->DrawArraysInstanced(GL_TRIANGLES, 0, 3, 1);
    gl->BindTexture(GL_TEXTURE_2D, 0);
    gl->ActiveTexture(GL_TEXTURE0);

    /* Each target's rows where image.h puts them (row 0 first, so no
     * inversion): Y's even and odd rows two strides apart, Cb and Cr
     * rows one stride apart, Cr's W/2 bytes after Cb's (Cb read first:
     * when W/2 is not a multiple of 4 its last texel spills into Cr's
     * first bytes, which Cr's read then writes). */
    struct sp_image img = {dst, y->width, y->height, (y->width + 7) & ~7, SP_IMAGE_YUV420};
    uint8_t *plane[3];
    int linesize[3];
    sp_image_planes(&img, plane, linesize);
    if (fb->pack_invert)
        gl->PixelStorei(GL_PACK_INVERT_MESA, 0);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, y->fbo);
    for (int i = 0; i < N_TARGETS; i++) {
        const int luma = i == Y_EVEN || i == Y_ODD;
        uint8_t *at = luma ? plane[0] + (i == Y_ODD ? linesize[0] : 0) : plane[i == CB ? 1 : 2];
        gl->ReadBuffer(GL_COLOR_ATTACHMENT0 + (GLenum)i);
        /* in pixels of the target's format: 8 or 4 bytes */
        gl->PixelStorei(GL_PACK_ROW_LENGTH, luma ? 2 * linesize[0] / 8 : linesize[1] / 4);
        gl->ReadPixels(0, 0, nx, ny, luma ? GL_RG_INTEGER : GL_RED_INTEGER, GL_UNSIGNED_INT, at);
    }
    gl->PixelStorei(GL_PACK_ROW_LENGTH, 0);
    gl->ReadBuffer(GL_COLOR_ATTACHMENT0);
    if (fb->pack_invert)
        gl->PixelStorei(GL_PACK_INVERT_MESA, 1);
    /* The state the draw list's passes (draw_gl.c) keep between frames. */
    sp_gl_offscreen_bind(fb);
    gl->Viewport(0, 0, fb->width, fb->height);
    gl->Enable(GL_BLEND);
    if (scissor)
        gl->Enable(GL_SCISSOR_TEST);
}

void sp_yuv_gl_destroy(struct sp_yuv_gl **y)
{
    free(*y);
    *y = NULL;
}
