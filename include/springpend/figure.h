/* springpend: one frame as a vector figure (SVG or PDF) for papers and
 * slides: the same composition as the rendered PNG (compose.c), drawn with
 * cairo (springpend-cairo.so, loaded on first use) instead of GL; needs no
 * GL context. One output pixel is one SVG px or one PDF pt. */
#ifndef SPRINGPEND_FIGURE_H
#define SPRINGPEND_FIGURE_H

#include "springpend/frame.h"

enum sp_figure_format { SP_FIGURE_NONE, SP_FIGURE_SVG, SP_FIGURE_PDF };

/* The vector format a path's extension names (.svg, .pdf, any case), or
 * SP_FIGURE_NONE. */
enum sp_figure_format sp_figure_format(const char *path);

struct sp_outfile;
struct sp_figure_desc {
    int width, height;            /* px (SVG) or pt (PDF) of the drawing */
    double page_w, page_h;        /* pt: the page, the drawing scaled to it; 0 =
                                     width x height */
    struct sp_view_extent extent; /* as for sp_render_desc */
    const struct sp_look *look;   /* as for sp_render_desc */
    const char *title;            /* the document's title (the scene's name); NULL = none */
    const char *path;             /* .svg or .pdf; written as PATH.part, renamed */
    int cells;                    /* as for sp_render_desc: scenes side by side */
    const struct sp_look *looks;
    const char *scene_file;       /* provenance: the scene as a scene file
                                     (sp_scene_ini); NULL = none */
    const char *command;          /* provenance: the command line without the
                                     output's name; NULL = none */
    const volatile sig_atomic_t *cancel; /* the caller's stop flag: once set,
                                     drawing stops and nothing is written
                                     (SP_E_INTERRUPTED); NULL = never */
    struct sp_outfile *partner;   /* written, not yet committed: put in place
                                     with the figure under its folder's lock
                                     (sp_outfile_commit_pair: a still's
                                     --state), or discarded; NULL = none */
};

/* An SVG or PDF still of physical size is laid out at this many px per pt
 * (its text sizes are whole px of it); a sweep figure's tick labels follow. */
#define SP_FIGURE_PX_PER_PT 4.0

/* A figure's scene record: the PDF /Subject's first line, the SVG
 * <metadata>'s id (the PNG text's key, provenance.h). */
#define SP_FIGURE_SCENE_MARK "# springpend.scene-file\n"
#define SP_FIGURE_SCENE_ID "springpend.scene-file"
#define SP_FIGURE_COMMAND_MARK "# command: " /* the PDF /Subject's second line */

/* Reads the scene a springpend SVG or PDF figure (still or sweep) records
 * into text (NUL-terminated, at most size bytes): 1 when found, 0 when the
 * file has none (logged by the caller), SP_E_IO (logged) when it cannot be
 * read, SP_E_INPUT (logged) when the record is damaged or too long. */
int sp_figure_read_scene(const char *path, char *text, size_t size);

/* As sp_figure_read_scene, the command line the figure records
 * (SP_FIGURE_COMMAND_MARK's line in a PDF, <metadata
 * id="springpend.command"> in an SVG): 1, 0 when it has none, or SP_E_*. */
int sp_figure_read_command(const char *path, char *text, size_t size);

/* Composes f (side by side: f[0..cells)) and writes it. On failure nothing is left at path. 0,
 * SP_E_INPUT (not .svg/.pdf), SP_E_IO or SP_E_NOMEM (logged). */
int sp_figure_write(const struct sp_figure_desc *d, const struct sp_frame *f);

/* A still of physical size (--size 8.6cm) as it was asked for, for
 * sp_figure_fit_advise. */
struct sp_figure_fit {
    double page_w, page_h;        /* pt */
    double pt_px;                 /* px per pt it is laid out at */
    int supersample;              /* a PNG's --scale; 0 or 1 = none */
    int png;                      /* 1: a PNG (16x16 to 7680x4320 px) */
    const char *unit[2];          /* --size's units as given ("cm", "mm", "in",
                                     "pt"), width's and height's; unit[1] "" =
                                     WIDTH alone: the height followed the scene's
                                     aspect */
    struct sp_view_extent extent; /* as for sp_render_desc */
    const struct sp_look *looks;  /* each cell's (side by side), as drawn */
    int cells;
};

/* After a refusal of fit's figure (its panels cannot hold their texts, a
 * label cannot fit): lays frames f[0..cells) out again (compose only,
 * nothing drawn, the inner messages muted) at other settings and says, on
 * one line, those that fit: the smallest --size in fit's units (0.1 cm,
 * 1 mm, 0.1 in or 1 pt steps; one step smaller is refused; the same aspect,
 * or for WIDTH alone the smallest height at that width), the largest
 * view.font_size (0.5 pt steps, down to 5 pt) and the longest view.panels
 * list (the first ones, else one alone) at fit's size. Says nothing when
 * fit's own settings lay out (the refusal was another's). */
void sp_figure_fit_advise(const struct sp_figure_fit *fit, const struct sp_frame *f);

#endif
