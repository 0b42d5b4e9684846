/* springpend: reading a file that a command names (a PNG, video, shard CSV)
 * or that lies beside one (a CSV's metadata). Anything can sit at such a
 * path: a FIFO would block the reader forever, a device would never end, a
 * folder reads as a parse error. Every reader opens through here:
 *
 * - the path is opened with O_NONBLOCK, so that opening a FIFO does not
 *   wait for a writer, then fstat'ed, and anything but a regular file (a
 *   link is followed) is refused at once with a message that says what it
 *   is; O_NONBLOCK is cleared before the descriptor is handed back;
 * - a whole-file read is bounded, so that a forged file cannot cost more
 *   than max bytes of memory.
 * Every failure is logged once, here, naming the path and the cause. */
#ifndef SPRINGPEND_INFILE_H
#define SPRINGPEND_INFILE_H

#include <stddef.h>

/* Opens the regular file at path for reading (O_CLOEXEC). want ends the
 * message when it is not one ("a PNG must be a file"). Returns the
 * descriptor, or SP_E_INPUT after "PATH: is a FIFO, not a regular file;
 * WANT" or "PATH: cannot open: REASON" (missing, no permission). */
int sp_infile_open(const char *path, const char *want);

/* Reads the regular file at path whole into *text (malloc'd, NUL added
 * after its *size bytes; the bytes may hold NULs). Refused, SP_E_INPUT,
 * when it is not a regular file or holds more than max bytes; SP_E_IO when
 * a read fails, SP_E_NOMEM. Logged. */
int sp_infile_read(const char *path, size_t max, const char *want, char **text, size_t *size);

/* A look at a file that a forged record may name (a sweep shard's command
 * names its scene): reads path whole into *text (malloc'd, NUL added) only
 * when it is an ordinary file, and opens nothing else. stat() first, no
 * open: a regular file of 1 to max bytes, on no kernel or FUSE file system
 * (procfs, sysfs, debugfs, tracefs, securityfs, cgroup, bpf, efivarfs,
 * pstore, configfs, FUSE: /proc/kmsg is "regular", and reading it takes the
 * kernel's log and blocks); opened O_NONBLOCK | O_NOCTTY, the same file
 * (st_dev, st_ino) as stat'ed, read without waiting. 1 read; 0 not
 * such a file (nothing said, *text NULL); SP_E_NOMEM (logged). */
int sp_infile_peek(const char *path, size_t max, char **text, size_t *size);

#endif
