/* springpend (internal): cairo's output to a file descriptor. See cairo_fd.h. */
#include <errno.h>
#include <unistd.h>

#include "cairo_fd.h"

cairo_status_t sp_cairo_fd_write(void *closure, const unsigned char *data, unsigned int length)
{
    struct sp_cairo_fd *k = closure;
    while (length && !k->err) {
        ssize_t n = write(k->fd, data, length);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            k->err = n < 0 ? errno : EIO;
        else
            data += n, length -= (unsigned int)n;
    }
    return k->err ? CAIRO_STATUS_WRITE_ERROR : CAIRO_STATUS_SUCCESS;
}
