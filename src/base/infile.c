/* springpend: reading files that cannot hang or flood the reader
 * (infile.h). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <linux/magic.h>
#if __has_include(<linux/openat2.h>)
#include <linux/openat2.h> /* Linux 5.6 */
#endif
#include <sys/stat.h>
#include <sys/statfs.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/infile.h"
#include "array.h"

static const volatile sig_atomic_t *stop_flag; /* sp_infile_stop_on; NULL = none */

void sp_infile_stop_on(const volatile sig_atomic_t *flag)
{
    stop_flag = flag;
}

const char *sp_file_kind(mode_t m)
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

enum { OPEN_FAILED = -1, NOT_REGULAR = -2, KERNEL_FILE = -3, SWAPPED = -4, ESCAPED = -5 };

/* The folders reads are confined to (sp_infile_confine): set before a
 * compare's threads start, cleared after they end, read-only meanwhile. */
#define CONFINED_MAX 4
static struct confined {
    char *dir;  /* as given, without trailing '/': a path "DIR/..." lies in it */
    char *real; /* its real path when confined (realpath), or NULL */
    int fd;     /* an O_PATH descriptor of it then, or -1 (it did not exist) */
} confined[CONFINED_MAX];
static int n_confined;

/* Where the last path refused as ESCAPED led, and the folder it left
 * (this thread's), for the message. */
static _Thread_local char escaped_to[PATH_MAX];
static _Thread_local const char *escaped_from;

int sp_infile_confine(const char *dir)
{
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/')
        n--;
    if (n_confined == CONFINED_MAX || !n) {
        sp_log_error("%s: cannot confine reads to it (%d folders at most)", dir, CONFINED_MAX);
        return SP_E_INPUT;
    }
    struct confined *c = &confined[n_confined];
    if (!(c->dir = strndup(dir, n))) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    c->fd = open(dir, O_PATH | O_DIRECTORY | O_CLOEXEC);
    c->real = c->fd >= 0 ? realpath(dir, NULL) : NULL;
    n_confined++;
    return 0;
}

void sp_infile_confine_end(void)
{
    for (int i = 0; i < n_confined; i++) {
        if (confined[i].fd >= 0)
            close(confined[i].fd);
        free(confined[i].dir);
        free(confined[i].real);
    }
    memset(confined, 0, sizeof(confined));
    n_confined = 0;
}

/* The confined folder that path lies in by name (the longest such: one
 * folder may lie in another), with *rel the rest of path; NULL when none. */
static const struct confined *confined_of(const char *path, const char **rel)
{
    const struct confined *in = NULL;
    size_t best = 0;
    for (int i = 0; i < n_confined; i++) {
        const size_t n = strlen(confined[i].dir);
        if (n > best && !strncmp(path, confined[i].dir, n) &&
            (path[n] == '/' || confined[i].dir[n - 1] == '/'))
            in = &confined[i], best = n;
    }
    if (in) {
        for (*rel = path + best; **rel == '/';)
            (*rel)++;
        if (!**rel)
            in = NULL; /* the folder itself */
    }
    return in;
}

/* 1 when the file open as `at` (by path) lies in the folder whose real
 * path is real: its name as the kernel holds it (/proc/self/fd), or,
 * without /proc, path's real path now, if that is the file opened. Where
 * it lies goes to escaped_to. */
static int lies_in(int at, const char *path, const char *real)
{
    char self[64];
    struct stat a, b;
    snprintf(self, sizeof(self), "/proc/self/fd/%d", at);
    ssize_t n = readlink(self, escaped_to, sizeof(escaped_to) - 1);
    if (n >= 0) {
        escaped_to[n] = 0;
    } else {
        char *now = realpath(path, NULL);
        snprintf(escaped_to, sizeof(escaped_to), "%s", now ? now : "(cannot be told)");
        if (!now || stat(now, &a) != 0 || fstat(at, &b) != 0 || a.st_dev != b.st_dev ||
            a.st_ino != b.st_ino)
            snprintf(escaped_to, sizeof(escaped_to), "(cannot be told)");
        free(now);
    }
    const size_t k = real ? strlen(real) : 0;
    return real && !strncmp(escaped_to, real, k) &&
           (escaped_to[k] == '/' || (k == 1 && real[0] == '/'));
}

/* An O_PATH descriptor of path, which lies in confined folder c as rel:
 * resolved beneath c's descriptor (openat2 RESOLVE_BENEATH: no component,
 * no link may lead out of it, whatever the name became since the folder
 * was listed). Where the kernel cannot (before Linux 5.6, or a seccomp
 * filter's EPERM), or the name leaves c to come back (an absolute link
 * into c, "../c/x.png"), path is opened as any name and kept only when
 * the file opened lies in c (lies_in). The descriptor, -1 (errno), or
 * ESCAPED (escaped_to and escaped_from say where). */
static int open_beneath(const struct confined *c, const char *rel, const char *path)
{
#if defined(SYS_openat2) && defined(RESOLVE_BENEATH)
    struct open_how how = {.flags = O_PATH | O_CLOEXEC,
                           .resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS};
#define OPEN_BENEATH(dir, rel) (int)syscall(SYS_openat2, dir, rel, &how, sizeof(how))
#else /* headers before Linux 5.6: as a kernel without it */
#define OPEN_BENEATH(dir, rel) ((void)(dir), (void)(rel), errno = ENOSYS, -1)
#endif
    const int dir = c->fd >= 0 ? c->fd : open(c->dir, O_PATH | O_DIRECTORY | O_CLOEXEC);
    char *real = c->fd >= 0 ? c->real : dir >= 0 ? realpath(c->dir, NULL) : NULL;
    int at = -1;
    for (int k = 0; k < 16 && dir >= 0; k++) { /* EAGAIN: a rename meanwhile; again */
        at = OPEN_BENEATH(dir, rel);
        if (at >= 0 || errno != EAGAIN)
            break;
    }
    if (dir >= 0 && at < 0 && (errno == EXDEV || errno == ENOSYS || errno == EPERM)) {
        at = open(path, O_PATH | O_CLOEXEC);
        if (at >= 0 && !lies_in(at, path, real)) {
            close(at);
            escaped_from = c->dir;
            at = ESCAPED;
        }
    }
    const int e = errno;
    if (c->fd < 0) { /* a folder made since it was confined (new baselines) */
        if (dir >= 0)
            close(dir);
        free(real);
    }
    errno = e;
    return at;
}

/* An O_PATH descriptor of path (a link followed), beneath its confined
 * folder if it lies in one (open_beneath). */
static int open_path(const char *path)
{
    const char *rel;
    const struct confined *c = confined_of(path, &rel);
    return c ? open_beneath(c, rel, path) : open(path, O_PATH | O_CLOEXEC);
}

/* Opens path for reading (O_CLOEXEC | O_NOCTTY | flags) without opening
 * anything that is not a regular file on an ordinary file system: an
 * O_PATH handle first (it runs no driver's open and waits for no FIFO
 * writer; a link is followed), its type and file system looked at, then
 * that same inode reopened through /proc/self/fd, so that a path swapped
 * meanwhile changes nothing. Where /proc is not mounted the path is opened
 * again by name (O_NONBLOCK, so nothing waits) and must be the inode
 * looked at. The fd, else OPEN_FAILED (errno), NOT_REGULAR (*st says what
 * it is), KERNEL_FILE, SWAPPED (another file there when reopened) or
 * ESCAPED (it lies in a confined folder by name, and leads out of it). */
static int open_regular(const char *path, int flags, int fuse_too, struct stat *st)
{
    struct statfs fs;
    struct stat again;
    char self[64];
    const int at = open_path(path);
    if (at < 0)
        return at == ESCAPED ? ESCAPED : OPEN_FAILED;
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
         : fd == SWAPPED ? "replaced while it was opened"
         : fd == ESCAPED ? "changed after the folder was listed: it leads out of it now, "
                           "not read" : "cannot be opened";
    return fd >= 0 ? fd : SP_E_INPUT;
}

int sp_infile_open(const char *path, const char *want)
{
    struct stat st;
    const int fd = open_regular(path, 0, 0, &st);
    if (fd >= 0)
        return fd;
    if (fd == NOT_REGULAR)
        sp_log_error("%s: is %s, not a regular file; %s", path, sp_file_kind(st.st_mode), want);
    else if (fd == SWAPPED)
        sp_log_error("%s: was replaced by another file while it was opened; %s", path, want);
    else if (fd == ESCAPED)
        sp_log_error("%s changed after the folder was listed: it leads to %s, not inside %s: "
                     "not read", path, escaped_to, escaped_from);
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
