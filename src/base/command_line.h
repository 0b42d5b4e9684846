/* springpend (internal): the command line a run was started with, for the
 * provenance every output carries. argv[0] is recorded as "springpend",
 * whatever path started it, so that the same command gives the same bytes
 * from any build or install.
 * Shared with: every folder. */
#ifndef SPRINGPEND_COMMAND_LINE_H
#define SPRINGPEND_COMMAND_LINE_H

/* Records argv (main calls it once, before any command runs; the strings
 * must outlive the process's outputs). */
void sp_command_line_set(int argc, char **argv);

/* The words recorded: *argc of them (0 before sp_command_line_set); the
 * first is "springpend". */
char *const *sp_command_line_argv(int *argc);

/* The words as one line a POSIX shell reads back into them: a word of
 * [A-Za-z0-9_./:=,+@%^-] only is written as it is, any other in single
 * quotes (a quote inside as '\''). Written into buf as snprintf does;
 * returns the length it would need. */
int sp_command_line_text(char *buf, size_t size);

/* As sp_command_line_text, less what an output records no word of: the
 * output's name (-o FILE, -oFILE, --output FILE, --output=FILE), a sweep's
 * --csv FILE, which part of the work is written (--frames A:B, --shard I/N)
 * and by how many threads (--threads N), and -q/--quiet; a value also as
 * one word with '='. The same work writing another file, a part of the
 * frames, a shard later merged or a run on other cores then gives the same
 * bytes (frame 17 of a --frames 17:40 run is the whole run's frame 17; a
 * merged sweep figure is the whole run's). An option abbreviated (--out,
 * --thr) is recorded as given. */
int sp_command_line_text_unnamed(char *buf, size_t size);

/* What an output records (provenance.h's springpend.command, a PDF's
 * /Subject, an SVG's <metadata>): sp_command_line_text_unnamed's line as
 * messages show it (common.h's sp_text_shown): a control character (ESC
 * and the like, a newline), a noncharacter, a bidi control or a byte that
 * is not UTF-8 is written as \xNN, \uNNNN or \n, so that the line is
 * printable UTF-8 that drives no terminal. Such a word then does not read
 * back into the same bytes; every other line is read back by a POSIX shell
 * into the words given. malloc'd (free it); NULL when none was recorded or
 * out of memory. */
char *sp_command_line_unnamed(void);

/* As sp_command_line_unnamed for the command line `line` that
 * sp_command_line_text wrote (a sweep shard's prov:wasGeneratedBy, which a
 * merged figure records as its own); NULL when line is NULL, is not such a
 * line of springpend's, or out of memory. */
char *sp_command_line_recorded(const char *line);

#endif
