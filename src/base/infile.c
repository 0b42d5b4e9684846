/* springpend: reading files that cannot hang or flood the reader
 * (infile.h). */
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/statfs.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/infile.h"
#include "array.h"

static const volatile sig_atomic_t *stop_flag; /* sp_infile_stop_on; NULL = none */

void sp_infile_stop_on(const volatile sig_atomic_t *flag)
{
    stop_flag = flag;
}

static const char *kind(mode_t m)
{
    return S_ISDIR(m) ? "a folder" : S_ISFIFO(m) ? "a FIFO" : S_ISCHR(m) ? "a character device"
         : S_ISBLK(m) ? "a block device" : S_ISSOCK(m) ? "a socket" : "a special file";
}

/* 1 when fs (statfs's f_type) is a kernel's: its "regular" files are not
 * data on a disk (/proc/kmsg reads the kernel's log and blocks), and with
 * fuse_too, FUSE's (a server that may never answer). */
static int pseudo_fs(unsigned long fs, int fuse_too)
{
    static const unsigned long kinds[] = {
        PROC_SUPER_MAGIC, SYSFS_MAGIC, DEBUGFS_MAGIC, TRACEFS_MAGIC, SECURITYFS_MAGIC,
        CGROUP_SUPER_MAGIC, CGROUP2_SUPER_MAGIC, BPF_FS_MAGIC, EFIVARFS_MAGIC,
        PSTOREFS_MAGIC, 0x62656570 /* configfs */,
    };
    for (size_t k = 0; k < sizeof(kinds) / sizeof(kinds[0]); k++)
        if (fs == kinds[k])
            return 1;
    return fuse_too && fs == FUSE_SUPER_MAGIC;
}

enum { OPEN_FAILED = -1, NOT_REGULAR = -2, KERNEL_FILE = -3, SWAPPED = -4 };

/* Opens path for reading (O_CLOEXEC | O_NOCTTY | flags) without opening
 * anything that is not a regular file on an ordinary file system: an
 * O_PATH handle first (it runs no driver's open and waits for no FIFO
 * writer; a link is followed), its type and file system looked at, then
 * that same inode reopened through /proc/self/fd, so that a path swapped
 * meanwhile changes nothing. Where /proc is not mounted the path is opened
 * again by name (O_NONBLOCK, so nothing waits) and must be the inode
 * looked at. The fd, else OPEN_FAILED (errno), NOT_REGULAR (*st says what
 * it is), KERNEL_FILE or SWAPPED (another file there when reopened). */
static int open_regular(const char *path, int flags, int fuse_too, struct stat *st)
{
    struct statfs fs;
    struct stat again;
    char self[64];
    const int at = open(path, O_PATH | O_CLOEXEC);
    if (at < 0)
        return OPEN_FAILED;
    int ret = OPEN_FAILED;
    if (fstat(at, st) != 0 || fstatfs(at, &fs) != 0)
        goto done;
    if (!S_ISREG(st->st_mode)) {
        ret = NOT_REGULAR;
        goto done;
    }
    if (pseudo_fs((unsigned long)fs.f_type, fuse_too)) {
        ret = KERNEL_FILE;
        goto done;
    }
    snprintf(self, sizeof(self), "/proc/self/fd/%d", at);
    ret = open(self, O_RDONLY | O_CLOEXEC | O_NOCTTY | flags);
    if (ret < 0 && errno == ENOENT) /* no /proc: by name, then compared */
        ret = open(path, O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK | flags);
    if (ret >= 0 && (fstat(ret, &again) != 0 || again.st_dev != st->st_dev ||
                     again.st_ino != st->st_ino)) {
        close(ret);
        ret = SWAPPED;
    }
    if (ret >= 0 && !(flags & O_NONBLOCK) &&
        fcntl(ret, F_SETFL, fcntl(ret, F_GETFL) & ~O_NONBLOCK) != 0) {
        close(ret);
        ret = OPEN_FAILED;
    }
done:
    {
        const int e = errno;
        close(at);
        errno = e;
    }
    return ret;
}

int sp_infile_try(const char *path, const char **why)
{
    struct stat st;
    const int fd = open_regular(path, 0, 0, &st);
    *why = fd >= 0 ? NULL : fd == NOT_REGULAR ? "not a regular file"
         : fd == KERNEL_FILE ? "a kernel's file, not data on a disk"
         : fd == SWAPPED ? "replaced while it was opened" : "cannot be opened";
    return fd >= 0 ? fd : SP_E_INPUT;
}

int sp_infile_open(const char *path, const char *want)
{
    struct stat st;
    const int fd = open_regular(path, 0, 0, &st);
    if (fd >= 0)
        return fd;
    if (fd == NOT_REGULAR)
        sp_log_error("%s: is %s, not a regular file; %s", path, kind(st.st_mode), want);
    else if (fd == SWAPPED)
        sp_log_error("%s: was replaced by another file while it was opened; %s", path, want);
    else if (fd == KERNEL_FILE)
        sp_log_error("%s: is a kernel's file (on /proc, /sys or the like), not data on a disk; "
                     "%s", path, want);
    else if (errno == EMFILE || errno == ENFILE || errno == ENOMEM) {
        sp_log_error("%s: cannot open: %s (a limit of this process or system, not the file's "
                     "fault)", path, strerror(errno));
        return SP_E_IO; /* exit 1: the run failed, the input may be fine */
    } else
        sp_log_error("%s: cannot open: %s", path, strerror(errno));
    return SP_E_INPUT; /* missing, unreadable or not a file: bad input, exit 2 */
}

int sp_infile_read(const char *path, size_t max, const char *want, char **text, size_t *size)
{
    const int fd = sp_infile_open(path, want);
    *text = NULL, *size = 0;
    return fd < 0 ? fd : sp_infile_read_fd(fd, path, max, want, text, size);
}

int sp_infile_read_fd(int fd, const char *path, size_t max, const char *want, char **text,
                      size_t *size)
{
    struct stat st;
    int ret = 0;
    *text = NULL, *size = 0;
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
        if (got < 0 && errno == EINTR && stop_flag && *stop_flag) {
            ret = SP_E_INTERRUPTED; /* said by the command, as every stop */
            break;
        }
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

int sp_infile_peek(const char *path, size_t max, char **text, size_t *size)
{
    struct stat st, opened;
    *text = NULL, *size = 0;
    const int fd = open_regular(path, O_NONBLOCK, 1, &st);
    if (fd < 0)
        return 0;
    if (fstat(fd, &opened) != 0 || opened.st_size <= 0 || (unsigned long long)opened.st_size > max) {
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
