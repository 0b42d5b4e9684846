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
 * --output FILE, --output=FILE): what a figure records, so that the same
 * command writing another file gives the same bytes. */
int sp_command_line_text_unnamed(char *buf, size_t size);
/* The same in a malloc'd string (free it); NULL when none was recorded, out
 * of memory, or not UTF-8 (a file name in Latin-1: a PDF's and an SVG's
 * text must be UTF-8, so a figure then records no command). */
char *sp_command_line_unnamed(void);

#endif
