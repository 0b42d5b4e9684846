/* springpend (internal): cairo's output written to a file descriptor, with
 * every write's fate kept. cairo 1.16's own file streams can drop a failed
 * write (a PDF cut short by a full disk or `ulimit -f` was reported as
 * written), so the figure modules write through this and check `err`
 * whatever cairo's status says. Linked into each cairo module. */
#ifndef SPRINGPEND_CAIRO_FD_H
#define SPRINGPEND_CAIRO_FD_H

#include <cairo.h>

struct sp_cairo_fd {
    int fd;  /* open for writing; the caller closes it */
    int err; /* errno of the first failed write; 0 = all written */
};

/* A cairo_write_func_t: closure is a struct sp_cairo_fd. Writes all of
 * data (retrying short writes and EINTR); after a failure, writes nothing
 * more and returns CAIRO_STATUS_WRITE_ERROR. */
cairo_status_t sp_cairo_fd_write(void *closure, const unsigned char *data, unsigned int length);

#endif
