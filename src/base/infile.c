/* springpend: reading files that cannot hang or flood the reader
 * (infile.h). */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/statfs.h>
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

/* 1 when fs (statfs's f_type) is a kernel's or FUSE's: its "regular" files
 * are not data on a disk (sp_infile_peek). */
static int pseudo_fs(unsigned long fs)
{
    static const unsigned long kinds[] = {
        PROC_SUPER_MAGIC, SYSFS_MAGIC, DEBUGFS_MAGIC, TRACEFS_MAGIC, SECURITYFS_MAGIC,
        CGROUP_SUPER_MAGIC, CGROUP2_SUPER_MAGIC, BPF_FS_MAGIC, EFIVARFS_MAGIC,
        PSTOREFS_MAGIC, FUSE_SUPER_MAGIC, 0x62656570 /* configfs */,
    };
    for (size_t k = 0; k < sizeof(kinds) / sizeof(kinds[0]); k++)
        if (fs == kinds[k])
            return 1;
    return 0;
}

int sp_infile_peek(const char *path, size_t max, char **text, size_t *size)
{
    struct stat st, opened;
    struct statfs fs;
    *text = NULL, *size = 0;
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode) || st.st_size <= 0 ||
        (unsigned long long)st.st_size > max || statfs(path, &fs) != 0 ||
        pseudo_fs((unsigned long)fs.f_type))
        return 0;
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
    if (fd < 0)
        return 0;
    if (fstat(fd, &opened) != 0 || opened.st_dev != st.st_dev || opened.st_ino != st.st_ino ||
        !S_ISREG(opened.st_mode)) { /* swapped since the stat */
        close(fd);
        return 0;
    }
    const size_t want = (size_t)opened.st_size < max ? (size_t)opened.st_size : max;
    char *buf = malloc(want + 1);
    if (!buf) {
        close(fd);
        sp_log_error("out of memory reading %s", path);
        return SP_E_NOMEM;
    }
    size_t n = 0;
    while (n < want) { /* O_NONBLOCK kept: EAGAIN ends the look */
        const ssize_t got = read(fd, buf + n, want - n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got <= 0)
            break;
        n += (size_t)got;
    }
    close(fd);
    if (n != want) {
        free(buf);
        return 0;
    }
    buf[n] = 0;
    *text = buf, *size = n;
    return 1;
}
