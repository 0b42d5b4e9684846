/* springpend: where an image came from, as PNG text chunks, so a snapshot
 * in CI says which springpend, scene, time and GL renderer made it:
 *   Software                 "springpend 0.1.0"
 *   Source                   the GL_RENDERER string (PNG's keyword for
 *                            "device used to create the image")
 *   springpend.scene-sha256  SHA-256 of sp_scene_canonical's text
 *   springpend.time          simulated time of the frame, s (%.9g)
 *   springpend.scene         sp_scene_canonical's text itself (zTXt, or iTXt
 *                            when it holds UTF-8 beyond ASCII (png_io.h),
 *                            0.6 kB, 0.3 kB deflated), so compare can name the keys
 *                            that changed
 *   springpend.scene-file    the same scene as a scene file (zTXt;
 *                            sp_scene_write_ini: user units, names), which
 *                            `springpend scene FILE` prints
 *   springpend.environment   environment.h's text (zTXt): the versions of
 *                            the libraries, and the SHA-256 of the built-in
 *                            font and of each font file the first frame's
 *                            text was drawn from
 *   springpend.fonts         the font files the first frame's text was drawn
 *                            from, ", "-separated ("" when it has no text)
 *   springpend.command       the command line that made the output, as a
 *                            POSIX shell reads it back, without the
 *                            output's name (-o FILE) and with controls and
 *                            bytes that are not UTF-8 escaped
 *                            (command_line.h: sp_command_line_unnamed);
 *                            "" when none was recorded (a library caller).
 *                            A figure records the same line (figure.h).
 *                            `springpend scene FILE` prints it first, as
 *                            "# command: LINE"
 *   springpend.overlay       only with [view] vectors, the energy_bars
 *                            panel or a perspective camera
 *                            (SP_PROVENANCE_N_TEXT + 1 chunks): their
 *                            scales (the camera's pinhole) in output pixels,
 *                            "key=value" lines
 *                            (sp_render_overlay), so a test can measure them
 * Nothing that changes from run to run (no date): the same frame gives the
 * same bytes. */
#ifndef SPRINGPEND_PROVENANCE_H
#define SPRINGPEND_PROVENANCE_H

#include "springpend/environment.h"
#include "springpend/png_io.h"
#include "springpend/scene.h"

#define SP_PROVENANCE_N_TEXT 9
#define SP_PROVENANCE_SCENE_FILE "springpend.scene-file" /* the key */
#define SP_PROVENANCE_COMMAND "springpend.command"       /* the key */
/* Bytes of scene text an output carries, NUL included: a PNG reader
 * inflates no text chunk beyond 256 KiB (png_io.c). A scene whose text is
 * longer is refused (sp_provenance_init), never recorded empty. */
#define SP_PROVENANCE_SCENE_MAX (256 * 1024)
/* A side-by-side output (2 to 4 scenes) records each: the first as
 * springpend.scene-file, scene K as springpend.scene-file.K (K = 2..4),
 * after the overlay chunk. */
#define SP_PROVENANCE_MAX_SCENES 4

struct sp_provenance {
    char software[32];
    char renderer[128];
    char scene_sha256[65]; /* lower-case hex */
    char time[32];         /* s */
    char *scene;           /* canonical text, "key=value\n" lines: malloc'd */
    char *scene_file;      /* sp_scene_write_ini's text: malloc'd */
    char *command;         /* sp_command_line_unnamed's text: malloc'd */
    char environment[SP_ENVIRONMENT_MAX]; /* environment.h's text: the caller adds
                              the font files (sp_render_font_environment) before
                              the first image */
    char fonts[1024];      /* font files, ", "-separated: the caller fills it
                              (sp_render_fonts) before the first image */
    char overlay[4096];    /* sp_render_overlay's text: the caller fills it (4 cells of
                              arrows, bars and charts fit) */
    char *more_files[SP_PROVENANCE_MAX_SCENES - 1]; /* side by side: scenes 2..,
                                                        sp_scene_write_ini: malloc'd */
    char more_keys[SP_PROVENANCE_MAX_SCENES - 1][48]; /* "springpend.scene-file.K" */
    int n_more;            /* scenes added with sp_provenance_add_scene */
    struct sp_png_text text[SP_PROVENANCE_N_TEXT + SP_PROVENANCE_MAX_SCENES]; /* point
                              into the above: the 9, the overlay, scenes 2.. */
};

/* Hashes the scene and fills every chunk (time 0). renderer and gl_version
 * (GL_RENDERER, GL_VERSION) may be NULL ("none"). Returns 0, SP_E_NOMEM, or
 * SP_E_INPUT (logged) for a scene whose text is SP_PROVENANCE_SCENE_MAX
 * bytes or more. Free with sp_provenance_free, whatever it returned. */
int sp_provenance_init(struct sp_provenance *p, const struct sp_scene *scene,
                       const char *renderer, const char *gl_version);

/* Records one more scene of a side-by-side output (the second, third,
 * fourth) as text[SP_PROVENANCE_N_TEXT + 1 + k], key
 * springpend.scene-file.K: the output then carries
 * SP_PROVENANCE_N_TEXT + 1 + p->n_more chunks (the overlay's among them).
 * 0, SP_E_NOMEM, or SP_E_INPUT (logged) for a fifth scene or a text of
 * SP_PROVENANCE_SCENE_MAX bytes or more. */
int sp_provenance_add_scene(struct sp_provenance *p, const struct sp_scene *scene);

/* Records command (sp_command_line_unnamed's form; NULL: "") as
 * springpend.command in place of this run's: a merged sweep figure records
 * its shards' command. 0 or SP_E_NOMEM. */
int sp_provenance_set_command(struct sp_provenance *p, const char *command);

/* Frees the scene texts; safe on a zeroed or freed p. */
void sp_provenance_free(struct sp_provenance *p);

/* Sets the simulated time, s, that the next image shows. */
void sp_provenance_set_time(struct sp_provenance *p, double t);

/* Checks that text (len bytes), recorded in path under key (a PNG's text
 * chunk, a video's tag, a CSV metadata's dc:source), is a scene as
 * springpend writes it: under SP_PROVENANCE_SCENE_MAX bytes, no NUL, read
 * by the scene parser without a word (UTF-8, no control bytes, no key
 * twice, every value in range) and written back by sp_scene_write_ini byte
 * for byte. Anything else was forged or damaged. 0, or SP_E_INPUT after
 * "PATH: KEY:LINE: what". */
int sp_provenance_scene_check(const char *path, const char *key, const char *text,
                              size_t len);

#endif
