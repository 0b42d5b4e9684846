/* springpend: reading video frames back as RGBA8 images through libav*,
 * for `springpend compare a.mp4 b.mp4`. Any container and codec FFmpeg
 * decodes; the first video stream only. */
#ifndef SPRINGPEND_VIDEO_READ_H
#define SPRINGPEND_VIDEO_READ_H

#include <signal.h>
#include <stddef.h>

#include "springpend/image.h"

struct sp_video_reader;

/* The most pixels a video frame may hold for compare to read it: the
 * largest frame of the highest level of H.264, HEVC, VP9 and AV1 (6.2/6.3:
 * 35 651 584 luma samples, 8192x4352); springpend writes at most
 * 7680x4320. A container whose header claims more is refused unread, and
 * the decoder refuses a frame beyond it (AVCodecContext.max_pixels), so a
 * forged size costs no memory and no estimate counts more than this. */
#define SP_VIDEO_MAX_PIXELS 35651584L

/* Opens path and its decoder. SP_E_INPUT (with a message) when it is not a
 * readable video, or its header or decoder says a frame size beyond
 * SP_VIDEO_MAX_PIXELS; SP_E_NOMEM, unsaid, when memory runs out (not the file's
 * fault: its caller says it once; compare retries on one thread first). A file whose format is not the one its name's ending
 * says (.mp4, .m4v, .mov: MP4/MOV; .webm, .mkv: WebM/Matroska; .gif;
 * .h264, .264: raw H.264; .hevc, .h265, .265: raw HEVC) is SP_E_INPUT, so
 * are the other readers below (their message names the format found). */
int sp_video_reader_open(struct sp_video_reader **out, const char *path);

/* Decodes the next frame into *img: pixels owned by the reader, valid
 * until the next read or destroy; *t (when t is not NULL) gets the frame's
 * presentation time, s (its best-effort timestamp; NAN when it has none). The conversion to RGBA is bit-exact
 * (SWS_BITEXACT), so equal frames give equal pixels on any CPU. Returns 1
 * with a frame, 0 after the last one, or a negative SP_E_* code (logged,
 * but SP_E_NOMEM: unsaid, as for sp_video_reader_open). */
int sp_video_reader_read(struct sp_video_reader *r, struct sp_image *img, double *t);

/* While buf is set (size bytes, a string) on the calling thread, the
 * decoder errors the reader would log (SP_E_CODEC: FFmpeg tells some failed
 * allocations as damaged data) and FFmpeg's own log lines are appended to
 * buf instead, a line each ("springpend: PATH: WHAT: WHY\n"; FFmpeg's as
 * it writes them), cut to fit; two threads may hold into one buffer.
 * sp_video_hold_errors(NULL, 0) ends it. For compare's pool, which decodes
 * such a video again alone on one thread and says its errors then, once.
 * Container errors (SP_E_INPUT) are logged as ever. */
void sp_video_hold_errors(char *buf, size_t size);

/* Decodes path's video to its end, nothing converted and nothing said
 * (FFmpeg's lines neither): after a decoder error under ulimit -v or -d,
 * where FFmpeg reports some failed allocations as damaged data, this tells
 * the file's fault from memory's, the same way every run (attack10 #6),
 * with the memory of one decoder rather than compare's two and their
 * frames. 1 when every frame decodes;
 * SP_E_NOMEM when memory runs out again (FFmpeg's ENOMEM or
 * "get_buffer() failed"); another negative SP_E_* code when the file does
 * not decode (damaged, cut short); SP_E_INTERRUPTED once *cancel is set
 * (cancel NULL: never). The decoder stops at the first damage it finds
 * (AV_EF_EXPLODE), which it may otherwise hide. Call it with the
 * other readers destroyed, so that their memory is free. */
int sp_video_decodes_alone(const char *path, const volatile sig_atomic_t *cancel);

/* Reads path's container packet by packet, nothing decoded and nothing
 * said, with the memory of one packet: what a memory limit cannot change.
 * 0 when it finds the file damaged (the demuxer's error, a packet flagged
 * corrupt, fewer frames or bytes than the file's index lists), why in why;
 * 1 when it finds nothing wrong (the decoder's error may still be the
 * file's); SP_E_NOMEM or SP_E_INPUT when it cannot tell. After
 * sp_video_decodes_alone fails under ulimit -v or -d, where FFmpeg's
 * decoders report failed allocations as damaged data (attack12 #5). */
int sp_video_demuxes_whole(const char *path, char *why, size_t size);

/* Frees everything and sets *r to NULL. Safe on NULL. */
void sp_video_reader_destroy(struct sp_video_reader **r);

/* The frame size of path's first video stream as its container's headers
 * say, px, with nothing decoded and nothing logged: for an estimate before
 * the file is read in earnest (which then says what is wrong with it).
 * Only a regular file is opened. 0, or SP_E_INPUT (*width = *height = 0),
 * also for a size beyond SP_VIDEO_MAX_PIXELS, which the reader refuses
 * unread. *alpha: 1 when its frames carry an alpha the reader decodes too
 * (a WebM's VP9 with AlphaMode 1: a second decoder), else 0. */
int sp_video_frame_size(const char *path, int *width, int *height, int *alpha);

/* The container tag key of the video at path (springpend writes its PNG
 * text chunks there too: provenance.h) into buf. Returns 1 when found, 0
 * when not, or a negative SP_E_* when the file cannot be read. */
int sp_video_read_text(const char *path, const char *key, char *buf, size_t size);

#endif
