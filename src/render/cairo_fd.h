/* springpend (internal): cairo's output written to a file descriptor, with
 * every write's fate kept. cairo 1.16's own file streams can drop a failed
 * write (a PDF cut short by a full disk or `ulimit -f` was reported as
 * written), so the figure modules write through this and check `err`
 * whatever cairo's status says. Linked into each cairo module.
 * Shared with: sweep (sweep_plot.c writes through it). */
#ifndef SPRINGPEND_CAIRO_FD_H
#define SPRINGPEND_CAIRO_FD_H

#include <cairo.h>

struct sp_cairo_fd {
    int fd;  /* open for writing; the caller closes it */
    int err; /* errno of the first failed write; 0 = all written */
    const char *svg_metadata; /* written before the SVG's closing </svg> (the
                                 write that ends with it); NULL = nothing */
};

/* A cairo_write_func_t: closure is a struct sp_cairo_fd. Writes all of
 * data (retrying short writes and EINTR); after a failure, writes nothing
 * more and returns CAIRO_STATUS_WRITE_ERROR. */
cairo_status_t sp_cairo_fd_write(void *closure, const unsigned char *data, unsigned int length);

/* Makes a PDF surface's bytes repeat from run to run: cairo 1.16 stamps
 * /CreationDate with the clock. With SOURCE_DATE_EPOCH set (the
 * reproducible-builds convention: whole seconds since 1970 UTC) that time
 * is written; without it, no date at all. Returns 0, or SP_E_INPUT (logged,
 * naming the variable) when SOURCE_DATE_EPOCH is not a whole number of
 * seconds in 0 .. 253402300799 (year 9999). */
int sp_cairo_pdf_date(cairo_surface_t *pdf);

/* Provenance in a figure, which `springpend scene` reads back
 * (sp_figure_read_scene): a PDF's /Subject holds the line
 * SP_FIGURE_SCENE_MARK, then "# command: COMMAND" (when command is not
 * NULL), then the scene file text; an SVG holds them, XML-escaped, in
 * <metadata id="springpend.scene-file"> and <metadata id="springpend.command">,
 * with springpend's version in <metadata id="springpend.version">.
 * command: the command line as recorded (sp_command_line_unnamed: without
 * the output's name, printable UTF-8). scene_file NULL or "": nothing. */
void sp_cairo_pdf_scene(cairo_surface_t *pdf, const char *scene_file, const char *command);
/* The SVG's metadata elements for sink.svg_metadata, malloc'd (free it);
 * NULL when out of memory (logged) or scene_file is NULL. fonts: the font
 * files drawn from (sp_cairo_font_names), in <metadata
 * id="springpend.fonts">, beside the renderer's <metadata
 * id="springpend.renderer"> ("cairo 1.16.0"), as a PDF's /Keywords and
 * /Producer say them; NULL: none yet. */
char *sp_cairo_svg_metadata(const char *scene_file, const char *command, const char *fonts);

#endif
