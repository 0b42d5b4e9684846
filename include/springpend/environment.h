/* springpend: what produced an image, beyond the scene: the versions of
 * springpend and of every library that shapes its pixels or files, and the
 * font files with their SHA-256. One "key: value" line each, in a fixed
 * order, nothing that changes from run to run:
 *
 *   springpend: 0.1.0
 *   renderer: llvmpipe (LLVM 15.0.6, 256 bits)     GL_RENDERER, or "none"
 *   gl: 4.5 (Core Profile) Mesa 22.3.6             GL_VERSION
 *   mesa: 22.3.6                                   from GL_VERSION
 *   llvm: 15.0.6                                   from GL_RENDERER
 *   freetype: 2.12.1                               FT_Library_Version
 *   font: DejaVu Sans (embedded in springpend, N bytes) sha256 …
 *                                                  the built-in font
 *   font NAME: sha256 … (N bytes)                  each font file fontconfig
 *                                                  gave the image's text
 *   zlib: 1.2.13                                   zlibVersion
 *   libpng: 1.6.39                                 png_get_libver
 *   libavcodec: 59.37.100 (FFmpeg 5.1.6-…)         the video module's
 *
 * `springpend version --verbose` prints it; every PNG carries it as the zTXt
 * chunk springpend.environment; compare names the lines that differ. */
#ifndef SPRINGPEND_ENVIRONMENT_H
#define SPRINGPEND_ENVIRONMENT_H

#include <stddef.h>

#define SP_ENVIRONMENT_MAX 8192 /* bytes of text, NUL included */

/* Writes the environment into buf (at most size bytes, NUL-terminated).
 * renderer and gl_version: GL_RENDERER and GL_VERSION of the context that
 * drew, or NULL when nothing was drawn with GL. Loads the video module to
 * ask libavcodec (its absence is written, not an error). Returns 0. */
int sp_environment_text(char *buf, size_t size, const char *renderer, const char *gl_version);

/* Adds the line "font NAME: sha256 HEX (N bytes)" for the font file at
 * path to an environment text in buf (size bytes), beside the built-in
 * font's line, unless it is there already. NAME is the file's name without
 * its folder: the same files installed in other folders make the same text.
 * hex and bytes are the SHA-256 and size of the bytes the face was drawn
 * from (text.c reads a font file once and hashes what it drew with, never
 * the path again). SP_E_INPUT when the text would not fit (logged); buf is
 * unchanged then. */
int sp_environment_add_font(char *buf, size_t size, const char *path, const char hex[65],
                            long long bytes);

/* What shapes numbers rather than pixels, for a CSV's metadata: the lines
 *
 *   springpend: 0.1.0
 *   compiler: 12.2.0                               __VERSION__
 *   libc: glibc 2.36                               gnu_get_libc_version
 *
 * Loads nothing (sp_environment_text's FFmpeg module and font hashing cost
 * `data` about 150 ms of start-up). Returns 0. */
int sp_environment_numbers(char *buf, size_t size);

#endif
