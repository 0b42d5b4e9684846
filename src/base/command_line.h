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

struct option;

/* getopt_long(argc, argv, shortopts, longopts, NULL), and the option it
 * returned noted for the record of the words being parsed (the process's
 * own, or sp_command_line_parse_into's): its long option's full name (an
 * abbreviation, --sha, is recorded as --shard; -q as --quiet), and its
 * value, which is then a value whatever it looks like (--state -q). Every
 * command whose outputs record the command parses with it. */
int sp_command_line_getopt(int argc, char *const *argv, const char *shortopts,
                           const struct option *longopts);

/* What an output records (provenance.h's springpend.command, a PDF's
 * /Subject, an SVG's <metadata>): the words as getopt_long parsed them, as
 * one line a POSIX shell reads back into them. Each option is written by
 * its long name, its value as the next word (--set=a.b=1 and -oFILE as
 * --set a.b=1 and --output FILE); the operands, a '--' and every word
 * after it as given. Left out is what does not change an output's bytes:
 * the output's name (-o, --output), a sweep's --csv FILE, the state file a
 * still writes (--state FILE), which part of the work is written
 * (--frames A:B, --shard I/N: but a video piece's, sp_command_line_piece)
 * and by how many threads (--threads N), and -q/--quiet. The same work
 * writing another file, a part of the PNG frames, a shard later merged or
 * a run on other cores then gives the same bytes (frame 17 of a --frames
 * 17:40 run is the whole run's frame 17; a merged sweep figure is the
 * whole run's). A word of [A-Za-z0-9_./:=,+@%^-] only
 * is written as it is, any other in single quotes (a quote inside as
 * '\''). The line is then shown as messages show it (common.h's
 * sp_text_shown): a control character (ESC and the like, a newline), a
 * noncharacter, an invisible format character, a bidi control or a byte
 * that is not UTF-8 is written as \xNN, \uNNNN or \n, so that the line is
 * printable UTF-8 that drives no terminal. Such a word then does not read
 * back into the same bytes; every other line is read back by a POSIX shell
 * into the words given. malloc'd (free it); NULL when none was recorded or
 * out of memory. */
char *sp_command_line_unnamed(void);

/* As sp_command_line_unnamed, keeping --frames A:B and --shard I/N: what a
 * video piece records (an MP4 or WebM of part of the frames is not the
 * whole run's video, so its record names the part it holds and re-makes
 * it). malloc'd; NULL when none was recorded or out of memory. */
char *sp_command_line_piece(void);

/* Every word as given (an output's name too: a CSV's prov:wasGeneratedBy),
 * one line shown as sp_command_line_unnamed's is. malloc'd; NULL when none
 * was recorded or out of memory. */
char *sp_command_line_whole(void);

/* SP_E_INPUT after a message when a record is longer than springpend's
 * readers take back (SP_PROVENANCE_SCENE_MAX - 1 bytes): record, or (NULL)
 * the process's own command line, whole or as outputs record it; else 0.
 * main refuses such a command line before anything is computed. */
int sp_command_line_check(const char *record);

/* A command line read from a file (a sweep shard's prov:wasGeneratedBy),
 * to parse as its command would and record (a merged figure records its
 * shards' command). */
struct sp_command_line;

/* line, as sp_command_line_whole writes one, split into its words; NULL
 * when line is NULL, is not a line springpend writes (a space at its start
 * or two in a row, an unclosed quote, a first word not "springpend", no
 * command) or out of memory. */
struct sp_command_line *sp_command_line_read(const char *line);

/* r's words from its command on (*argc of them, NULL-terminated), for the
 * command's parser: it may permute them. */
char **sp_command_line_words(struct sp_command_line *r, int *argc);

/* The n words (at most 16) as one line a POSIX shell reads back into them,
 * quoted as a record quotes its words (not shown: the caller's message
 * shows it), into buf as snprintf does; for a command line a message
 * offers to paste. Its length. */
size_t sp_command_line_quote(const char *const *words, int n, char *buf, size_t size);

/* r's words written again as springpend writes a record (each quoted for a
 * POSIX shell where it needs it, shown as sp_text_shown shows text): a
 * shell given this line gets r's words back, whatever the line r was read
 * from held (a forged record's $(...) or ';' become plain words). For
 * `scene FILE --command`. malloc'd; NULL when out of memory. */
char *sp_command_line_text(const struct sp_command_line *r);

/* The options sp_command_line_getopt returns from now on are noted for r
 * (NULL: for the process's own command line again). */
void sp_command_line_parse_into(struct sp_command_line *r);

/* As sp_command_line_unnamed for r (parsed), followed by the options of
 * the process's own command line but skip (a long name) and what outputs
 * omit: a merged sweep figure records its shards' command with the figure
 * options the merge drew at (--size 3in --dpi 200). malloc'd; NULL when out
 * of memory. */
char *sp_command_line_merged(const struct sp_command_line *r, const char *skip);

void sp_command_line_free(struct sp_command_line *r);

#endif
