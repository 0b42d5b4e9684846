/* springpend: reading files that cannot hang or flood the reader
 * (infile.h). */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/infile.h"
#include "array.h"

static const char *kind(mode_t m)
{
    return S_ISDIR(m) ? "a folder" : S_ISFIFO(m) ? "a FIFO" : S_ISCHR(m) ? "a character device"
         : S_ISBLK(m) ? "a block device" : S_ISSOCK(m) ? "a socket" : "a special file";
}

int sp_infile_open(const char *path, const char *want)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
    if (fd < 0) {
        sp_log_error("%s: cannot open: %s", path, strerror(errno));
        return SP_E_INPUT; /* missing or unreadable: bad input, exit 2 */
    }
    if (fstat(fd, &st) != 0) {
        sp_log_error("%s: cannot open: %s", path, strerror(errno));
    } else if (!S_ISREG(st.st_mode)) {
        sp_log_error("%s: is %s, not a regular file; %s", path, kind(st.st_mode), want);
    } else if (fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) != 0) {
        sp_log_error("%s: cannot open: %s", path, strerror(errno));
    } else {
        return fd;
    }
    close(fd);
    return SP_E_INPUT;
}

int sp_infile_read(const char *path, size_t max, const char *want, char **text, size_t *size)
{
    struct stat st;
    int fd = sp_infile_open(path, want), ret = 0;
    *text = NULL, *size = 0;
    if (fd < 0)
        return fd;
    if (fstat(fd, &st) != 0 || (unsigned long long)st.st_size > max) {
        sp_log_error("%s: %lld bytes; at most %zu are read (%s)", path, (long long)st.st_size,
                     max, want);
        close(fd);
        return SP_E_INPUT;
    }
    /* the size can change while it is read: read up to max + 1 and look */
    size_t cap = 0, n = 0; /* bytes at buf: what was read, one more and the NUL fit */
    char *buf = NULL;
    for (;;) {
        if (n > max) {
            sp_log_error("%s: more than %zu bytes; at most %zu are read (%s)", path, max,
                         max, want);
            ret = SP_E_INPUT;
            break;
        }
        if (sp_array_reserve((void **)&buf, 1, &cap, n + 2, (size_t)st.st_size + 2, max + 2)) {
            sp_log_error("out of memory reading %s", path);
            ret = SP_E_NOMEM;
            break;
        }
        ssize_t got = read(fd, buf + n, cap - 1 - n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            sp_log_error("%s: cannot read: %s", path, strerror(errno));
            ret = SP_E_IO;
        }
        if (got <= 0)
            break;
        n += (size_t)got;
    }
    close(fd);
    if (ret) {
        free(buf);
        return ret;
    }
    buf[n] = 0;
    *text = buf, *size = n;
    return 0;
}
