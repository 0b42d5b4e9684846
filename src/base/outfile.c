/* springpend: files that appear whole or not at all (see outfile.h). */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "springpend/common.h"
#include "springpend/infile.h"
#include "springpend/outfile.h"

/* ---- the .part table a signal handler reads ---- */

/* A PNG sequence has at most 9 .parts open at once; a still and its JSON 2. */
#define PART_SLOTS 32
#define PAIR_LOCK_WAIT_S 5 /* s: how long a pair waits for its folder's lock */

static char part_name[PART_SLOTS][PATH_MAX];
static volatile sig_atomic_t part_armed[PART_SLOTS]; /* 1: part_name exists
                                                        and is ours */
static int part_taken[PART_SLOTS];                   /* under part_lock */
static pthread_mutex_t part_lock = PTHREAD_MUTEX_INITIALIZER;

static const volatile sig_atomic_t *cancel; /* sp_outfile_set_cancel's */

void sp_outfile_set_cancel(const volatile sig_atomic_t *flag)
{
    cancel = flag;
}

void sp_outfile_remove_parts(void)
{
    for (int i = 0; i < PART_SLOTS; i++)
        if (part_armed[i])
            unlink(part_name[i]);
}

static int slot_take(void)
{
    int slot = -1;
    pthread_mutex_lock(&part_lock);
    for (int i = 0; i < PART_SLOTS && slot < 0; i++)
        if (!part_taken[i])
            part_taken[slot = i] = 1;
    pthread_mutex_unlock(&part_lock);
    return slot;
}

/* The .part is renamed or removed already: a handler that still sees it
 * armed unlinks a name nobody else uses. */
static void slot_give(int slot)
{
    if (slot < 0)
        return;
    part_armed[slot] = 0;
    pthread_mutex_lock(&part_lock);
    part_taken[slot] = 0;
    pthread_mutex_unlock(&part_lock);
}

/* ---- targets ---- */

/* The descriptor a name stands for: "-", /dev/stdout, /dev/stderr,
 * /dev/fd/N, /proc/self/fd/N; else -1. */
static int stdio_alias(const char *target)
{
    const char *n = NULL;
    if (!strcmp(target, "-") || !strcmp(target, "/dev/stdout"))
        return 1;
    if (!strcmp(target, "/dev/stderr"))
        return 2;
    if (!strncmp(target, "/dev/fd/", 8))
        n = target + 8;
    else if (!strncmp(target, "/proc/self/fd/", 14))
        n = target + 14;
    if (!n || !*n || strspn(n, "0123456789") != strlen(n) || strlen(n) > 6)
        return -1;
    return atoi(n);
}

int sp_outfile_is_stream(const char *target)
{
    struct stat st;
    return stdio_alias(target) >= 0 ||
           (stat(target, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode));
}

static void outfile_free(struct sp_outfile *f)
{
    free(f->target);
    free(f->url);
    *f = (struct sp_outfile){.fd = -1, .slot = -1};
}

/* Six characters that make the .part's name unique: the process id, a
 * counter and the clock, mixed; O_EXCL settles any collision. */
static void unique_suffix(char out[7])
{
    static const char digits[] =
        "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ";
    static unsigned long counter;
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    unsigned long long x = (unsigned long long)getpid() * 0x9e3779b97f4a7c15ull ^
                           (unsigned long long)ts.tv_nsec * 0xbf58476d1ce4e5b9ull ^
                           (unsigned long long)__atomic_add_fetch(&counter, 1, __ATOMIC_RELAXED) *
                               0x94d049bb133111ebull;
    for (int i = 0; i < 6; i++, x /= 62)
        out[i] = digits[x % 62];
    out[6] = 0;
}

/* A stdio descriptor that is a pipe, a FIFO or a terminal, opened anew
 * through /proc/self/fd/N: a description of its own, which may be
 * non-blocking without changing the one the shell and the reader's other
 * writers share. -1 when it is none of these or cannot be opened so (then it
 * is dup'ed; a socket is written with send(MSG_DONTWAIT) instead, which
 * leaves its shared description blocking: sp_outfile_write_all). Other
 * devices are not opened again (a tape rewinds on open and close), nor a
 * pseudo-terminal's master (its name, /dev/ptmx, opens a new terminal):
 * these are written blocking, as before. */
static int reopen_nonblocking(int fd)
{
    struct stat st;
    char name[40];
    unsigned pty;
    if (fstat(fd, &st) != 0 || !(S_ISFIFO(st.st_mode) || (S_ISCHR(st.st_mode) && isatty(fd))))
        return -1;
    if (ioctl(fd, TIOCGPTN, &pty) == 0)
        return -1; /* a pseudo-terminal's master: opened again, /dev/ptmx makes a new one */
    snprintf(name, sizeof(name), "/proc/self/fd/%d", fd);
    return open(name, O_WRONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
}

/* Writes through the non-regular target (or the stdio descriptor fd). The
 * descriptor stays non-blocking (a pipe's, FIFO's or terminal's, a device's
 * opened by name; a socket's writes are each non-blocking):
 * sp_outfile_write_all waits for its reader with poll(), looking at the stop
 * flag, where a blocking write() on a writer thread would wait deaf to every
 * signal (attack15 #1, attack16 #1). */
static int open_through(struct sp_outfile *f, int fd)
{
    if (fd >= 0) {
        f->fd = reopen_nonblocking(fd);
        if (f->fd < 0)
            f->fd = fcntl(fd, F_DUPFD_CLOEXEC, 3);
        if (f->fd < 0) {
            sp_log_error("%s: cannot write to descriptor %d: %s", f->target, fd,
                         strerror(errno));
            return SP_E_IO;
        }
        return 0;
    }
    /* A FIFO without a reader would wait unseen: say so, then wait (a
     * signal stops the wait) */
    f->fd = open(f->target, O_WRONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    if (f->fd < 0 && errno == ENXIO) {
        fputs("springpend: ", stderr);
        sp_fputs_line(f->target, stderr);
        fputs(" is a FIFO with no reader yet: waiting for one (Ctrl-C stops)\n", stderr);
    }
    /* Polled, not a blocking open: a PNG sequence's frames are opened on
     * writer threads, which a signal does not interrupt, so the wait looks
     * at the stop flag itself every 50 ms (attack13 #14) */
    while (f->fd < 0 && (errno == ENXIO || errno == EINTR) && !(cancel && *cancel)) {
        nanosleep(&(struct timespec){.tv_nsec = 50 * 1000 * 1000}, NULL);
        f->fd = open(f->target, O_WRONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
    }
    if (f->fd < 0 && (errno == EINTR || errno == ENXIO) && cancel && *cancel)
        return SP_E_INTERRUPTED; /* the caller says what stopped it */
    if (f->fd < 0) {
        sp_log_error("%s: cannot open for writing: %s", f->target, strerror(errno));
        return SP_E_IO;
    }
    return 0;
}

/* ---- writing through ---- */

static volatile sig_atomic_t write_stopped; /* the stop flag that ended a write; 0 = none */
static long long stop_seen_ms; /* when a write first saw the stop flag; 0 = not yet */

static long long now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (long long)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

/* Whether a write that cannot go on now should stop: the stop flag is set
 * and (interrupted, or) the readers have had STOP_GRACE_MS since a write
 * first saw it, to take the frame in hand. */
#define STOP_GRACE_MS 1000
static int stop_now(int interrupted)
{
    if (!cancel || !*cancel)
        return 0;
    long long seen = __atomic_load_n(&stop_seen_ms, __ATOMIC_RELAXED), t = now_ms();
    if (!seen)
        __atomic_compare_exchange_n(&stop_seen_ms, &seen, t, 0, __ATOMIC_RELAXED,
                                    __ATOMIC_RELAXED);
    return interrupted || t - (seen ? seen : t) >= STOP_GRACE_MS;
}

int sp_outfile_write_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    struct stat st;
    int sock = fstat(fd, &st) == 0 && S_ISSOCK(st.st_mode);
    while (n > 0) {
        ssize_t k = sock ? send(fd, p, n, MSG_DONTWAIT | MSG_NOSIGNAL) : write(fd, p, n);
        if (k > 0) {
            p += k, n -= (size_t)k;
            continue;
        }
        if (k == 0 || (errno != EINTR && errno != EAGAIN && errno != EWOULDBLOCK)) {
            if (k == 0)
                errno = EIO;
            return -1;
        }
        /* EINTR: a blocking descriptor's write cut by a signal, which the
         * next write would not see; EAGAIN: the reader has not read */
        if (stop_now(errno == EINTR)) {
            write_stopped = *cancel;
            errno = EINTR;
            return -1;
        }
        if (errno != EINTR)
            poll(&(struct pollfd){.fd = fd, .events = POLLOUT}, 1, 50);
    }
    return 0;
}

int sp_outfile_write_was_stopped(void)
{
    return write_stopped;
}

static ssize_t cookie_write(void *c, const char *buf, size_t n)
{
    return sp_outfile_write_all((int)(intptr_t)c, buf, n) ? -1 : (ssize_t)n;
}

static int cookie_close(void *c)
{
    return close((int)(intptr_t)c);
}

FILE *sp_outfile_fdopen(struct sp_outfile *f)
{
    FILE *fp = f->through ? fopencookie((void *)(intptr_t)f->fd, "w",
                                        (cookie_io_functions_t){.write = cookie_write,
                                                                .close = cookie_close})
                          : fdopen(f->fd, "w");
    if (fp)
        f->fd = -1; /* the stream's now */
    return fp;
}

/* The longest name a file in path's folder may have (pathconf's
 * _PC_NAME_MAX of its nearest folder that exists; NAME_MAX where it cannot
 * be told), that folder into dir (size bytes). */
static long folder_name_max(const char *path, char *dir, size_t size)
{
    struct stat st;
    snprintf(dir, size, "%s", path);
    for (;;) {
        char *slash = strrchr(dir, '/');
        if (!slash) {
            snprintf(dir, size, ".");
            break;
        }
        *slash = 0;
        if (slash == dir)
            snprintf(dir, size, "/");
        if (!dir[0] || stat(dir, &st) == 0 || (errno != ENOENT && errno != ENOTDIR))
            break;
    }
    long max = pathconf(dir, _PC_NAME_MAX);
    return max > 0 ? max : NAME_MAX;
}

/* The .part's name for a target whose folder is dir_len bytes of target
 * ("" or "…/") and its name the rest: target.XXXXXX.part beside it; where
 * that passes the folder's NAME_MAX (a name of 244+ bytes, legal) or
 * PATH_MAX, FOLDER/springpend-XXXXXX.part, in the same folder (rename()
 * stays on one file system: attack19 #5). */
static void part_name_for(char *name, const char *target, size_t dir_len, long name_max,
                          const char suffix[7])
{
    const size_t n = strlen(target);
    if (n - dir_len + sizeof(".XXXXXX.part") - 1 <= (size_t)name_max &&
        n + sizeof(".XXXXXX.part") <= PATH_MAX)
        snprintf(name, PATH_MAX, "%s.%s.part", target, suffix);
    else
        snprintf(name, PATH_MAX, "%.*s" SP_OUTFILE_SHORT_PART "%s.part", (int)dir_len, target,
                 suffix);
}

/* Creates the .part (part_name_for) with O_EXCL (mode 0666 less the umask:
 * a link or any file at that name is never opened) and arms its slot. */
static int open_part(struct sp_outfile *f)
{
    char dir[PATH_MAX];
    const char *slash = strrchr(f->target, '/');
    const size_t n = strlen(f->target), dir_len = slash ? (size_t)(slash + 1 - f->target) : 0;
    const long name_max = folder_name_max(f->target, dir, sizeof(dir));
    if (n + 1 > PATH_MAX || dir_len + sizeof(SP_OUTFILE_SHORT_PART "XXXXXX.part") > PATH_MAX) {
        sp_log_error("%s: the path is too long", f->target);
        return SP_E_INPUT;
    }
    if (n - dir_len > (size_t)name_max) {
        sp_log_error("%s: the name is %zu bytes; a name in %s has at most %ld", f->target,
                     n - dir_len, dir, name_max);
        return SP_E_INPUT;
    }
    if ((f->slot = slot_take()) < 0) {
        sp_log_error("%s: more than %d files open for writing at once", f->target,
                     PART_SLOTS);
        return SP_E_NOMEM;
    }
    char *name = part_name[f->slot];
    for (int tries = 0; tries < 100; tries++) {
        char suffix[7];
        unique_suffix(suffix);
        part_name_for(name, f->target, dir_len, name_max, suffix);
        f->fd = open(name, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOCTTY, 0666);
        if (f->fd >= 0 || errno != EEXIST)
            break;
    }
    if (f->fd < 0) {
        sp_log_error("%s: cannot create %s: %s", f->target, name, strerror(errno));
        return SP_E_IO;
    }
    part_armed[f->slot] = 1;
    if (asprintf(&f->url, "file:%s", name) < 0) {
        f->url = NULL;
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    f->path = f->url + 5;
    return 0;
}

int sp_outfile_refuse_link(const char *target)
{
    struct stat lst, st;
    if (stdio_alias(target) >= 0 || lstat(target, &lst) != 0 || !S_ISLNK(lst.st_mode))
        return 0;
    int exists = stat(target, &st) == 0;
    if (exists && !S_ISREG(st.st_mode))
        return 0; /* a stream (or a folder: refused as one) */
    char to[PATH_MAX];
    ssize_t n = readlink(target, to, sizeof(to) - 1);
    to[n > 0 ? n : 0] = 0;
    sp_log_error("%s is a symbolic link (to %s%s); an output is never written through a link "
                 "to a file: remove the link, or give the path of the file itself",
                 target, to, exists ? "" : ", which does not exist");
    return SP_E_INPUT;
}

int sp_outfile_open(struct sp_outfile *f, const char *target, unsigned flags)
{
    struct stat st, lst;
    int fd = stdio_alias(target), err;
    *f = (struct sp_outfile){.fd = -1, .slot = -1};
    /* SP_OUTFILE_REPLACE_LINK: a link is a name like a new one; the .part
     * is renamed over the link itself. */
    int link = (flags & SP_OUTFILE_REPLACE_LINK) && fd < 0 && lstat(target, &lst) == 0 &&
               S_ISLNK(lst.st_mode);
    int exists = fd < 0 && !link && stat(target, &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) {
        sp_log_error("%s is a folder; give a file name", target);
        return SP_E_INPUT;
    }
    if (fd >= 0 || (exists && !S_ISREG(st.st_mode))) {
        if (!(flags & SP_OUTFILE_STREAM)) {
            sp_log_error("%s is %s, not a regular file; this format must be written to "
                         "a file (raw frames, single PNGs and CSV can be written through "
                         "one)", target, fd >= 0 ? "standard output or error"
                         : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "a device"
                         : sp_file_kind(st.st_mode));
            return SP_E_INPUT;
        }
        f->through = 1;
    }
    if (!link && !f->through && (err = sp_outfile_refuse_link(target)) != 0)
        return err;
    f->target = strdup(target);
    if (!f->target) {
        sp_log_error("%s: %s", target, strerror(errno));
        outfile_free(f);
        return SP_E_NOMEM;
    }
    if (f->through) {
        err = asprintf(&f->url, "file:%s", f->target) < 0 ? SP_E_NOMEM : 0;
        if (err)
            f->url = NULL, sp_log_error("out of memory");
        else
            f->path = f->url + 5, err = open_through(f, fd);
    } else {
        err = open_part(f);
    }
    if (err)
        sp_outfile_discard(f);
    return err;
}

/* Puts the .part in place: rename() over the target, or (no_replace)
 * renameat2's RENAME_NOREPLACE, a hard link where the file system has no
 * such rename: 1 when a file appeared at the target (nothing said). 0, 1
 * or SP_E_IO; the .part is gone either way. */
static int put_in_place(struct sp_outfile *f, int no_replace)
{
    int r;
    if (!no_replace) {
        r = rename(f->path, f->target);
    } else {
        r = renameat2(AT_FDCWD, f->path, AT_FDCWD, f->target, RENAME_NOREPLACE);
        if (r != 0 && (errno == EINVAL || errno == ENOSYS)) { /* not on this file system */
            if ((r = link(f->path, f->target)) == 0)
                unlink(f->path);
        }
        if (r != 0 && errno == EEXIST)
            return 1;
    }
    if (r != 0) {
        sp_log_error("cannot rename %s to %s: %s", f->path, f->target, strerror(errno));
        return SP_E_IO;
    }
    return 0;
}

/* sp_outfile_commit and sp_outfile_commit_new: no_replace picks the rename. */
static int commit(struct sp_outfile *f, int no_replace)
{
    int err = 0;
    if (!f->target)
        return 0;
    if (f->fd >= 0 && close(f->fd) != 0) {
        sp_log_error("%s: cannot finish writing: %s", f->target, strerror(errno));
        err = SP_E_IO;
    }
    f->fd = -1;
    if (!err && !f->through)
        err = put_in_place(f, no_replace);
    if (err) {
        sp_outfile_discard(f);
        return err;
    }
    slot_give(f->slot);
    outfile_free(f);
    return 0;
}

int sp_outfile_commit(struct sp_outfile *f)
{
    return commit(f, 0);
}

int sp_outfile_commit_new(struct sp_outfile *f)
{
    return commit(f, 1);
}

int sp_outfile_commit_pair(struct sp_outfile *first, struct sp_outfile *second,
                           const volatile sig_atomic_t *cancel)
{
    const struct sp_outfile *named = second->target ? second : first;
    int dir = -1, err;
    if (named->target && !named->through) {
        char folder[PATH_MAX];
        const char *slash = strrchr(named->target, '/');
        if (!slash)
            snprintf(folder, sizeof(folder), ".");
        else
            snprintf(folder, sizeof(folder), "%.*s", slash == named->target ? 1
                     : (int)(slash - named->target), named->target);
        dir = open(folder, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        /* Another run holds the lock for two renames (well under a
         * millisecond): polled, not waited on, so that a process keeping
         * the folder locked (anyone may lock a shared /tmp) cannot hang this
         * run past its signals; after PAIR_LOCK_WAIT_S, and on a file
         * system without flock, the pair is put in place unlocked, said. */
        int tries = 0;
        while (dir >= 0 && flock(dir, LOCK_EX | LOCK_NB) != 0) {
            const int busy = errno == EWOULDBLOCK || errno == EINTR;
            if (!busy || ++tries > PAIR_LOCK_WAIT_S * 100) {
                sp_log_note("%s: %s %s; put in place without the lock", named->target,
                            busy ? "another process keeps locking its folder"
                                 : "cannot lock its folder", busy ? folder : strerror(errno));
                close(dir);
                dir = -1;
                break;
            }
            nanosleep(&(struct timespec){0, 10 * 1000 * 1000}, NULL); /* 10 ms */
            if (cancel && *cancel) { /* stopped while waiting: neither goes in */
                close(dir);
                sp_outfile_discard(first);
                sp_outfile_discard(second);
                return SP_E_INTERRUPTED;
            }
        }
    }
    err = sp_outfile_commit(first);
    if (!err)
        err = sp_outfile_commit(second);
    else
        sp_outfile_discard(second);
    if (dir >= 0)
        close(dir); /* and the lock with it */
    return err;
}

void sp_outfile_discard(struct sp_outfile *f)
{
    if (!f->target) /* closed, or zeroed and never opened */
        return;
    if (f->fd >= 0)
        close(f->fd);
    f->fd = -1;
    if (!f->through && f->slot >= 0 && part_armed[f->slot] && unlink(part_name[f->slot]) != 0 &&
        errno != ENOENT)
        sp_log_error("cannot remove %s: %s", part_name[f->slot], strerror(errno));
    slot_give(f->slot);
    outfile_free(f);
}

/* ---- folders ---- */

int sp_dirs_make(const char *path, struct sp_dirs *made)
{
    char *dir = strdup(path);
    int err = 0;
    if (!dir) {
        sp_log_error("out of memory");
        return SP_E_NOMEM;
    }
    for (char *p = strchr(dir + 1, '/'); p; p = strchr(p + 1, '/')) {
        if (p[-1] == '/')
            continue; /* "a//b" */
        *p = '\0';
        struct stat st;
        int mkdir_errno = mkdir(dir, 0777) == 0 ? 0 : errno;
        if (!mkdir_errno && made) {
            char *copy = strdup(dir);
            if (copy) { /* without memory it is merely not removed */
                if (!made->deepest)
                    made->top = strlen(dir);
                free(made->deepest);
                made->deepest = copy;
            }
        }
        if (mkdir_errno && mkdir_errno != EEXIST &&
            !(stat(dir, &st) == 0 && S_ISDIR(st.st_mode))) {
            sp_log_error("cannot create folder %s for %s: %s", dir, path,
                         strerror(mkdir_errno));
            err = SP_E_IO;
            break;
        }
        *p = '/';
    }
    free(dir);
    return err;
}

void sp_dirs_remove_empty(struct sp_dirs *made)
{
    char *d = made->deepest;
    while (d && strlen(d) >= made->top && rmdir(d) == 0) {
        char *slash = strrchr(d, '/');
        if (!slash)
            break;
        *slash = '\0';
    }
    sp_dirs_keep(made);
}

void sp_dirs_keep(struct sp_dirs *made)
{
    free(made->deepest);
    *made = (struct sp_dirs){0};
}

int sp_outfile_same_file(const char *a, const char *b)
{
    struct stat sa, sb;
    return stat(a, &sa) == 0 && stat(b, &sb) == 0 && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}

/* path's folder into dir ("." when it has none) and its last name into
 * *name, "./" and repeated slashes left out of dir. */
static void split_output(const char *path, char *dir, size_t size, const char **name)
{
    const char *slash = strrchr(path, '/');
    *name = slash ? slash + 1 : path;
    size_t n = 0;
    for (const char *p = path; slash && p < slash && n + 1 < size; p++) {
        if (*p == '/' && n && dir[n - 1] == '/')
            continue;
        if (p[0] == '.' && p[1] == '/' && (p == path || p[-1] == '/')) {
            p++;
            continue;
        }
        dir[n++] = *p;
    }
    while (n > 1 && dir[n - 1] == '/')
        n--;
    dir[n] = 0;
    if (!n)
        snprintf(dir, size, slash == path ? "/" : ".");
}

/* The folder dir will be once a sink has made what is missing of it, into
 * out (size bytes): walked a name at a time from the working folder (or
 * "/"), each name that exists resolved (realpath: links followed), each
 * that does not appended as the plain folder the sink makes, so that ".."
 * is the folder above in both cases ("nd/.." is "." before nd exists:
 * attack11 #4). 0, or -1 when it cannot be told. */
static int folder_to_be(const char *dir, char *out, size_t size)
{
    char cur[PATH_MAX], copy[PATH_MAX];
    if (snprintf(copy, sizeof(copy), "%s", dir) >= (int)sizeof(copy) ||
        (dir[0] == '/' ? snprintf(cur, sizeof(cur), "/") < 0 : !getcwd(cur, sizeof(cur))))
        return -1;
    for (char *save = NULL, *name = strtok_r(copy, "/", &save); name;
         name = strtok_r(NULL, "/", &save)) {
        if (!strcmp(name, "."))
            continue;
        if (!strcmp(name, "..")) { /* cur is resolved: its parent is its folder above */
            char *slash = strrchr(cur, '/');
            slash[slash == cur] = 0;
            continue;
        }
        const size_t n = strlen(cur);
        if (snprintf(cur + n, sizeof(cur) - n, "%s%s", cur[n - 1] == '/' ? "" : "/", name) >=
            (int)(sizeof(cur) - n))
            return -1;
        char *real = realpath(cur, NULL);
        if (real) {
            snprintf(cur, sizeof(cur), "%s", real);
            free(real);
        }
    }
    return snprintf(out, size, "%s", cur) < (int)size ? 0 : -1;
}

int sp_outfile_same_output(const char *a, const char *b)
{
    struct stat sa, sb;
    char da[PATH_MAX], db[PATH_MAX], fa[PATH_MAX], fb[PATH_MAX];
    const char *na, *nb;
    /* "-", /dev/stdout, /dev/fd/1 …: the file their descriptor has open
     * (-o /dev/stdout --state - wrote both into one stdout: attack16 #4) */
    const int xa = stdio_alias(a), xb = stdio_alias(b);
    if (xa >= 0 && xa == xb)
        return 1;
    const int ea = (xa >= 0 ? fstat(xa, &sa) : stat(a, &sa)) == 0,
              eb = (xb >= 0 ? fstat(xb, &sb) : stat(b, &sb)) == 0;
    if (xa >= 0 || xb >= 0)
        return ea && eb && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea && eb)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    split_output(a, da, sizeof(da), &na);
    split_output(b, db, sizeof(db), &nb);
    return !strcmp(na, nb) &&
           (sp_outfile_same_file(da, db) || !strcmp(da, db) ||
            (folder_to_be(da, fa, sizeof(fa)) == 0 && folder_to_be(db, fb, sizeof(fb)) == 0 &&
             !strcmp(fa, fb)));
}

int sp_outfile_lies_in(const char *path, const char *dir)
{
    char dp[PATH_MAX], fp[PATH_MAX], fd[PATH_MAX];
    const char *name;
    split_output(path, dp, sizeof(dp), &name);
    if (folder_to_be(dp, fp, sizeof(fp)) || folder_to_be(dir, fd, sizeof(fd)))
        return 0;
    const size_t n = strlen(fd);
    return !strncmp(fp, fd, n) && (fp[n] == 0 || fp[n] == '/' || (n == 1 && fd[0] == '/'));
}

int sp_outfile_check_name(const char *path, const char *suffix, const char *what,
                          const char *partner)
{
    char dir[PATH_MAX];
    if (sp_outfile_is_stream(path))
        return 0; /* written through: no name made */
    const char *slash = strrchr(path, '/'), *name = slash ? slash + 1 : path;
    const size_t n = strlen(name), more = strlen(suffix);
    const long max = folder_name_max(path, dir, sizeof(dir));
    if (n + more <= (size_t)max)
        return 0;
    if (!more)
        sp_log_error("%s %s: the name is %zu bytes; a name in %s has at most %ld", what, path, n,
                     dir, max);
    else
        sp_log_error("%s %s: its %s, NAME%s beside it, would have a name of %zu bytes; a name "
                     "in %s has at most %ld: give a name of at most %ld bytes", what, path,
                     partner, suffix, n + more, dir, max, max - (long)more);
    return SP_E_INPUT;
}

int sp_outfile_check_writable(const char *path, const char *what)
{
    char dir[PATH_MAX];
    struct stat st;
    if (sp_outfile_is_stream(path))
        return 0; /* written through: stdout, a device or a FIFO */
    if (sp_outfile_refuse_link(path))
        return SP_E_INPUT;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        sp_log_error("%s %s is a folder; give a file name", what, path);
        return SP_E_INPUT;
    }
    /* The nearest ancestor that exists must be a folder we may write in;
     * the sink creates the missing ones below it. */
    (void)folder_name_max(path, dir, sizeof(dir));
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode)) {
        sp_log_error("%s %s: %s is not a folder", what, path, dir);
        return SP_E_INPUT;
    }
    if (access(dir, W_OK | X_OK) != 0) {
        sp_log_error("%s %s: cannot write in folder %s: %s", what, path, dir, strerror(errno));
        return SP_E_INPUT;
    }
    return sp_outfile_check_name(path, "", what, NULL);
}
