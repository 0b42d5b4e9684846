/* LD_PRELOAD shim for test_formats.py: getpid() and clock_gettime()'s
 * CLOCK_REALTIME return fixed values, so the random part of the .part names
 * that outfile.c makes repeats from run to run (and in two runs at once);
 * every open() that creates a "*.part" is appended to the file named by
 * SP_OPEN_LOG as "PATH EXCL" (EXCL 1 with O_EXCL, else 0). */
/* open and open64 are two symbols only without the 64-bit redirection. */
#undef _FILE_OFFSET_BITS
#ifndef _GNU_SOURCE
#define _GNU_SOURCE
#endif
#include <dlfcn.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <time.h>
#include <unistd.h>

pid_t getpid(void)
{
    return 4242;
}

int clock_gettime(clockid_t id, struct timespec *ts)
{
    static int (*real)(clockid_t, struct timespec *);
    if (id == CLOCK_REALTIME) {
        ts->tv_sec = 1700000000;
        ts->tv_nsec = 123456789;
        return 0;
    }
    if (!real)
        real = (int (*)(clockid_t, struct timespec *))dlsym(RTLD_NEXT, "clock_gettime");
    return real(id, ts);
}

static void log_open(const char *path, int flags)
{
    const char *log = getenv("SP_OPEN_LOG");
    size_t n = strlen(path);
    if (!log || !(flags & O_CREAT) || n < 5 || strcmp(path + n - 5, ".part"))
        return;
    FILE *fp = fopen(log, "a");
    if (fp) {
        fprintf(fp, "%s %d\n", path, (flags & O_EXCL) != 0);
        fclose(fp);
    }
}

#define WRAP(name)                                                             \
    int name(const char *path, int flags, ...)                                 \
    {                                                                          \
        static int (*real)(const char *, int, ...);                            \
        mode_t mode = 0;                                                       \
        if (flags & (O_CREAT | O_TMPFILE)) {                                   \
            va_list ap;                                                        \
            va_start(ap, flags);                                               \
            mode = va_arg(ap, mode_t);                                         \
            va_end(ap);                                                        \
        }                                                                      \
        if (!real)                                                             \
            real = (int (*)(const char *, int, ...))dlsym(RTLD_NEXT, #name);   \
        log_open(path, flags);                                                 \
        return real(path, flags, mode);                                        \
    }
WRAP(open)
WRAP(open64)
