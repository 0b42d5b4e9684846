/* springpend: reading a file that a command names (a PNG, video, shard CSV)
 * or that lies beside one (a CSV's metadata). Anything can sit at such a
 * path: a FIFO would block the reader forever, a device would never end, a
 * folder reads as a parse error. Every reader opens through here:
 *
 * - nothing but a regular file is ever opened: the path is opened O_PATH
 *   first (which runs no driver's open and waits for no FIFO writer; a link
 *   is followed), fstat'ed, and anything but a regular file is refused at
 *   once with a message that says what it is, as is a file on a kernel's
 *   file system (procfs, sysfs, debugfs, tracefs, securityfs, cgroup, bpf,
 *   efivarfs, pstore, configfs: /proc/kmsg is "regular", and reading it
 *   takes the kernel's log and blocks); the same inode is then reopened for
 *   reading through /proc/self/fd, so a path swapped meanwhile opens
 *   nothing else (without /proc: reopened by name, O_NONBLOCK, and
 *   compared);
 * - a path under a folder compare walked is resolved beneath that folder
 *   (sp_infile_confine): a file swapped for a link out of it after the
 *   walk is refused, not read;
 * - a whole-file read stops when a signal that stops the run arrives
 *   (SP_E_INTERRUPTED, sp_infile_stop_on), rather than retrying the read;
 * - a whole-file read is bounded, so that a forged file cannot cost more
 *   than max bytes of memory.
 * Every failure is logged once, here, naming the path and the cause. */
#ifndef SPRINGPEND_INFILE_H
#define SPRINGPEND_INFILE_H

#include <signal.h>
#include <stddef.h>
#include <sys/types.h>

/* The flag that, set, stops a whole-file read cut by a signal (main.c hands
 * signals.c's; until then, and with NULL, a cut read is retried). */
void sp_infile_stop_on(const volatile sig_atomic_t *flag);

/* What a file that is not a regular one is, for messages: "a folder",
 * "a FIFO", "a character device", ... (st_mode's type bits). */
const char *sp_file_kind(mode_t m);

/* Confines every later open here of a path that lies in folder dir by
 * name ("DIR/NAME", DIR as given, the longest such folder) to files inside
 * it: the name is resolved beneath the descriptor of dir taken now
 * (openat2 RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS), so a file a folder
 * walk took that is swapped for a link out of dir afterwards is refused,
 * never read: "PATH changed after the folder was listed: it leads to
 * WHERE, not inside DIR: not read" (SP_E_INPUT). Links within dir are
 * followed: one that leaves dir and comes back (an absolute link into it),
 * or every one where the kernel has no openat2 (before Linux 5.6), is
 * opened as any name and kept only when the file opened lies in dir's
 * real path (its /proc/self/fd name; without /proc, the name's real path
 * now, if that is the file opened). A folder that does not exist yet (new
 * baselines) is resolved at each open. Compare's folder mode confines its
 * two folders (the walk screens links out of them: compare_run.c), from
 * before compare.ini is read until its reports are written; not
 * thread-safe: call before threads start, end after they are joined. 0,
 * or SP_E_* (said). */
int sp_infile_confine(const char *dir);

/* Ends every confinement (sp_infile_confine). */
void sp_infile_confine_end(void);

/* Opens the regular file at path for reading (O_CLOEXEC). want ends the
 * message when it is not one ("a PNG must be a file"). Returns the
 * descriptor, or SP_E_INPUT after "PATH: is a FIFO, not a regular file;
 * WANT", "PATH: is a kernel's file ...; WANT" or "PATH: cannot open:
 * REASON" (missing, no permission); SP_E_IO when the process or system is
 * out of descriptors or memory (EMFILE, ENFILE, ENOMEM: not the file's
 * fault, exit 1). */
int sp_infile_open(const char *path, const char *want);

/* sp_infile_open without a word: the descriptor, or SP_E_INPUT with *why
 * a short reason ("not a regular file", "cannot be opened", ...) for the
 * caller's own message (a report that leaves an image out says why). */
int sp_infile_try(const char *path, const char **why);

/* Reads the regular file at path whole into *text (malloc'd, NUL added
 * after its *size bytes; the bytes may hold NULs). Refused, SP_E_INPUT,
 * when it is not a regular file or holds more than max bytes; SP_E_IO when
 * a read fails, SP_E_NOMEM (logged); SP_E_INTERRUPTED when a signal stops
 * the run (unsaid: the command says it). */
int sp_infile_read(const char *path, size_t max, const char *want, char **text, size_t *size);

/* As sp_infile_read, from fd (sp_infile_open's, closed here): for a caller
 * that judges the file it opened (fstat) before it reads it, not the name
 * again (compare.ini's owner: attack14 #2). path names it in messages. */
int sp_infile_read_fd(int fd, const char *path, size_t max, const char *want, char **text,
                      size_t *size);

/* A look at a file that a forged record may name (a sweep shard's command
 * names its scene): reads path whole into *text (malloc'd, NUL added) only
 * when it is an ordinary file, and opens nothing else: as sp_infile_open
 * (O_PATH first, then the same inode), a regular file of 1 to max bytes on
 * no kernel file system nor FUSE (whose server may never answer), read
 * O_NONBLOCK, without waiting. 1 read; 0 not such a file (nothing said,
 * *text NULL); SP_E_NOMEM (logged). */
int sp_infile_peek(const char *path, size_t max, char **text, size_t *size);

#endif
