/* springpend (internal): the last GL pass of a video frame. Converts the
 * frame GL drew (the context's framebuffer texture, gl_offscreen.h) into
 * BT.709 limited-range Y'CbCr 4:2:0 planes (image.h's SP_IMAGE_YUV420) in
 * one draw (shaders/yuv.frag: each texel fetched about once), and reads
 * them back at 1.5 bytes a pixel instead of 4: what a video encoder takes,
 * with no conversion on the CPU. */
#ifndef SPRINGPEND_YUV_GL_H
#define SPRINGPEND_YUV_GL_H

#include <stdint.h>

#include "gl_api.h"
#include "gl_offscreen.h"

struct sp_yuv_gl;

/* Builds the program and its integer framebuffers for
 * width x height px output (both even) from a frame drawn at ss times that
 * size (ss >= 1: each output pixel the mean of an ss x ss block). The
 * context of gl must be current; it leaves no framebuffer bound. 0,
 * SP_E_INPUT (odd size), SP_E_GL or SP_E_NOMEM (logged). */
int sp_yuv_gl_make(struct sp_yuv_gl **out, const struct sp_gl_api *gl, int width, int height,
                   int ss);

/* Converts the opaque frame in fb's texture and writes the planes to dst
 * (sp_image_size(SP_IMAGE_YUV420, width, height) bytes, image.h's layout).
 * fb is bound again afterwards, with its pack state as it was. */
void sp_yuv_gl_read(struct sp_yuv_gl *y, struct sp_gl_offscreen *fb, uint8_t *dst);

/* Frees the CPU side and sets *y to NULL (GL objects die with the context).
 * Safe on NULL. */
void sp_yuv_gl_destroy(struct sp_yuv_gl **y);

#endif
