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

/* As sp_command_line_text, without the output's name (-o FILE, -oFILE,
 * --output FILE, --output=FILE) and without which frames are written
 * (--frames A:B, --shard I/N, either as one word with '='): what an output
 * records, so that the same command writing another file, or a part of the
 * frames, gives the same bytes (frame 17 of a --frames 17:40 run is the
 * whole run's frame 17). An option abbreviated (--out, --fra) is recorded
 * as given. */
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

#endif
