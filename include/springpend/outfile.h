/* springpend: a file that appears whole or not at all. Every file
 * springpend writes (videos, PNGs, raw frames, CSV, JSON) goes through here:
 *
 *   struct sp_outfile f;
 *   if (sp_outfile_open(&f, "out/a.csv", SP_OUTFILE_STREAM) == 0) {
 *       ... write to f.fd (or open f.path / f.url by name) ...
 *       ret = ok ? sp_outfile_commit(&f) : (sp_outfile_discard(&f), err);
 *   }
 *
 * The promises:
 * - A regular file (or a new name) is written as NAME.XXXXXX.part (as
 *   springpend-XXXXXX.part where that name would pass the folder's NAME_MAX),
 *   a name made unique with O_EXCL in the target's folder, and renamed over the
 *   target only when complete: concurrent runs never share a .part, the last
 *   one to finish wins with a whole file, and nothing that already exists is
 *   opened, truncated or removed (not even a file named like a .part).
 * - A symlink to a regular file (or to nothing) is refused (SP_E_INPUT):
 *   an output folder can come from a repository, and a link there must
 *   not make a write to anywhere (it once replaced /etc/passwd), nor may
 *   the user's link vanish unasked. With SP_OUTFILE_REPLACE_LINK the link
 *   itself is replaced by the file, whatever it points at (compare
 *   --update: a linked baseline becomes a file). A link to a device, FIFO
 *   or /proc/self/fd/N is a stream, as below.
 * - A device, FIFO or socket, and /dev/stdout, /dev/stderr, /dev/fd/N, are
 *   never replaced or removed. With SP_OUTFILE_STREAM (a format written
 *   front to back) they are written through directly (no .part; a FIFO
 *   waits for its reader); without it they are refused (SP_E_INPUT).
 * - While a .part exists its name is in a table a signal handler can read:
 *   sp_outfile_remove_parts removes them all (async-signal-safe).
 * - A wait for a FIFO's reader stops once the flag handed to
 *   sp_outfile_set_cancel is set (main hands it the signal flag).
 * Every failure is logged once, here, naming the path and the cause. */
#ifndef SPRINGPEND_OUTFILE_H
#define SPRINGPEND_OUTFILE_H

#include <signal.h>
#include <stddef.h>
#include <stdio.h>

struct sp_outfile {
    char *target;  /* owned: the file that appears in the end; NULL = closed */
    char *url;     /* owned: "file:" + path, for libav's avio_open */
    const char *path; /* url + 5: where the bytes go now: the .part, or the
                         target itself when written through */
    int fd;        /* open for writing (O_CLOEXEC); -1 once closed */
    int through;   /* 1: a device, FIFO or stdout written directly */
    int slot;      /* the signal table's slot holding path; -1 = none */
};

#define SP_OUTFILE_STREAM 1u /* the format may be written through a device,
                                FIFO or /dev/stdout (no seeking back) */
#define SP_OUTFILE_REPLACE_LINK 2u /* a symlink at target is replaced by the
                                      file, never followed */

/* Opens target for writing as described above. The target's folder must
 * exist (see sp_dirs_make). On failure *f is closed and nothing was
 * created. SP_E_INPUT for a folder or a refused non-regular target, SP_E_IO
 * when the .part cannot be created. */
int sp_outfile_open(struct sp_outfile *f, const char *target, unsigned flags);

/* Closes f->fd and renames the .part over the target (nothing to rename
 * when written through: then it reports the close's fate). On failure the
 * .part is removed. Either way f is closed. SP_E_IO on failure. */
int sp_outfile_commit(struct sp_outfile *f);

/* sp_outfile_commit, but the target is never replaced: when a file (or
 * link) appeared at it since it was opened, the .part is removed and 1 is
 * returned, nothing said (the caller says why it mattered). The rename is
 * renameat2's RENAME_NOREPLACE, or a hard link where the file system has
 * no such rename. 0, 1 or SP_E_IO. */
int sp_outfile_commit_new(struct sp_outfile *f);

/* Commits first, then second (sp_outfile_commit), both renames under an
 * exclusive lock (flock) on the folder of second's target: two runs
 * writing the same pair (a CSV and its CSV-metadata.json) at once put their
 * pairs in place one after the other, never one's first with the other's
 * second. The lock is polled for at most 5 s (a process keeping the folder
 * locked cannot hang the run); then, or where the file system has no
 * flock, the pair goes in unlocked with a note. Either may be closed or
 * written through. On failure the rest is discarded (a first already in
 * place stays). A signal (*cancel set; cancel may be NULL) while the lock
 * is polled discards both: SP_E_INTERRUPTED. 0 or SP_E_IO. */
int sp_outfile_commit_pair(struct sp_outfile *first, struct sp_outfile *second,
                           const volatile sig_atomic_t *cancel);

/* Closes f->fd and removes the .part; a target written through is left
 * alone. Safe on a closed or zeroed f. */
void sp_outfile_discard(struct sp_outfile *f);

/* 0, or SP_E_INPUT (logged) when target is a symlink to a regular file or
 * to nothing, which sp_outfile_open refuses without SP_OUTFILE_REPLACE_LINK:
 * for commands that check their outputs before the work. */
int sp_outfile_refuse_link(const char *target);

/* Whether writing to target would write through it (a device, FIFO,
 * socket or stdout): such a target must never be removed. */
int sp_outfile_is_stream(const char *target);

/* The process's stop flag (nonzero once a run should stop; main's is the
 * signal flag): a wait for a FIFO's reader ends when it is set. NULL, the
 * default: the wait ends only when the open fails otherwise. */
void sp_outfile_set_cancel(const volatile sig_atomic_t *cancel);

/* Writes all n bytes of buf to fd (an outfile's): 0, or -1 with errno.
 * What is written through is non-blocking (a pipe's or FIFO's reader that
 * does not read must not keep a writer thread deaf to signals): EAGAIN is
 * waited out with poll(), 50 ms at a time, never an error. Once the stop
 * flag (sp_outfile_set_cancel) is set, a write that must wait is given a
 * second from the first such wait (a reader that reads takes the frame in
 * hand), then ends: -1 with errno EINTR, and sp_outfile_write_was_stopped
 * says so; the caller returns SP_E_INTERRUPTED without a message, and the
 * command names the signal. A blocking descriptor's write cut by a signal
 * (a socket as stdout) ends at once. */
int sp_outfile_write_all(int fd, const void *buf, size_t n);

/* Once a write ended for the stop flag (sp_outfile_write_all): the flag's
 * value then (main's: the signal's number); 0 before. */
int sp_outfile_write_was_stopped(void);

/* f->fd as a stdio stream for writing ("w"): a stream whose writes go
 * through sp_outfile_write_all where f is written through, else fdopen's.
 * f->fd is the stream's then (-1 in f); NULL with errno on failure. */
FILE *sp_outfile_fdopen(struct sp_outfile *f);

/* Removes every .part now open in this process. Async-signal-safe: for the
 * handler of a second Ctrl-C. */
void sp_outfile_remove_parts(void);

/* 1 when both paths exist and name the same file (links resolved). */
int sp_outfile_same_file(const char *a, const char *b);

/* 1 when two outputs a and b would be one file: the same existing file,
 * or (one or both not there yet) the same name in the same folder (the
 * folders' files compared when they exist, else the folders they will be
 * once made: "nd/../x" is "x" before nd exists). Two outputs at one path
 * would replace each other without a word (attack10 #9, attack11 #4). */
int sp_outfile_same_output(const char *a, const char *b);

/* 1 when the file path would lie in folder dir or a folder under it, each
 * taken as it will be once made (links in what exists followed): compare
 * refuses a report inside its --candidates or --diff folder, where it
 * would replace a candidate or a diff (attack11 #4). */
int sp_outfile_lies_in(const char *path, const char *dir);

/* Refuses (SP_E_INPUT, with a message) an output path that cannot be
 * written: a folder, or under something that is not a writable folder.
 * Looks only; creates nothing. `what` names the option ("-o"). */
int sp_outfile_check_writable(const char *path, const char *what);

/* Refuses (SP_E_INPUT, with a message: what is wrong, what is allowed) an
 * output path whose name, with suffix appended (a partner written beside
 * it, e.g. SP_CSV_METADATA_SUFFIX; "": the name itself), passes its
 * folder's NAME_MAX (the nearest folder that exists). partner names what
 * the longer name is ("metadata"). A stream is never refused. Looks only. */
int sp_outfile_check_name(const char *path, const char *suffix, const char *what,
                          const char *partner);

/* The start of a .part's name where NAME.XXXXXX.part would pass its
 * folder's NAME_MAX (a target name of 244 bytes or more):
 * FOLDER/springpend-XXXXXX.part, in the target's folder. */
#define SP_OUTFILE_SHORT_PART "springpend-"

/* The folders a run created, so that a failed run can remove them. */
struct sp_dirs {
    char *deepest; /* owned: the deepest folder created; NULL = none */
    size_t top;    /* strlen of the topmost folder created */
};

/* mkdir -p of every folder above the file path, remembering in *made the
 * ones that did not exist (made may be NULL). SP_E_IO with a message. */
int sp_dirs_make(const char *path, struct sp_dirs *made);

/* Removes the folders in *made that are empty, deepest first (a folder with
 * anything in it stays), and forgets them. Safe on a zeroed struct. */
void sp_dirs_remove_empty(struct sp_dirs *made);

/* Forgets the folders without removing them (the run succeeded). */
void sp_dirs_keep(struct sp_dirs *made);

#endif
