/* springpend: how much memory this process may use (memory_limit.h). */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "memory_limit.h"

/* The name of the cgroup file that decided, for *what: one per thread. */
static __thread char file_name[PATH_MAX + 64];

/* Keeps the smaller of *best and v (v > 0), naming it. */
static void least(double *best, const char **what, double v, const char *name)
{
    if (v > 0 && (*best == 0 || v < *best))
        *best = v, *what = name;
}

/* Reads a cgroup limit file (a number of bytes, or "max" when unlimited) into
 * *best when it is the least so far, naming the file. */
static void least_file(double *best, const char **what, const char *path)
{
    FILE *fp = fopen(path, "r");
    char line[64];
    if (!fp)
        return;
    if (fgets(line, sizeof(line), fp)) {
        char *end;
        const double v = strtod(line, &end);
        if (end != line && v > 0 && (*best == 0 || v < *best)) {
            snprintf(file_name, sizeof(file_name), "%s", path);
            least(best, what, v, file_name);
        }
    }
    fclose(fp);
}

/* The least of `file` in folder mount + cgroup and each folder above it up
 * to mount (a cgroup's limit holds for everything under it). */
static void least_up(double *best, const char **what, const char *mount, const char *cgroup,
                     const char *file)
{
    char dir[PATH_MAX], path[PATH_MAX + 64];
    if (snprintf(dir, sizeof(dir), "%s%s", mount, cgroup) >= (int)sizeof(dir))
        return;
    for (size_t n = strlen(dir); n > 0 && dir[n - 1] == '/';)
        dir[--n] = 0;
    for (;;) {
        snprintf(path, sizeof(path), "%s/%s", dir, file);
        least_file(best, what, path);
        char *slash = strrchr(dir, '/');
        if (strlen(dir) <= strlen(mount) || !slash)
            break;
        *slash = 0;
    }
}

/* Does the comma-separated controller list `list` name `name`? */
static int names(const char *list, const char *name)
{
    const size_t n = strlen(name);
    for (const char *p = list; p; p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL)
        if (!strncmp(p, name, n) && (p[n] == ',' || p[n] == 0))
            return 1;
    return 0;
}

/* The cgroup limits of this process (root: the file system's root, "" but
 * in a test): /proc/self/cgroup's "0::PATH" line (v2) and its line whose
 * controllers hold "memory" (v1), each followed to its files. */
static void least_cgroup(double *best, const char **what, const char *root)
{
    char path[PATH_MAX], line[PATH_MAX + 128];
    snprintf(path, sizeof(path), "%s/proc/self/cgroup", root);
    FILE *fp = fopen(path, "r");
    if (!fp)
        return;
    while (fgets(line, sizeof(line), fp)) {
        char *a = strchr(line, ':'), *b = a ? strchr(a + 1, ':') : NULL, mount[PATH_MAX];
        if (!b)
            continue;
        line[strcspn(line, "\n")] = 0;
        *a = *b = 0;
        const char *controllers = a + 1, *cgroup = b + 1;
        if (!strcmp(line, "0") && !controllers[0]) {
            /* v2: mounted at /sys/fs/cgroup, or /sys/fs/cgroup/unified on a
             * hybrid host */
            snprintf(mount, sizeof(mount), "%s/sys/fs/cgroup", root);
            least_up(best, what, mount, cgroup, "memory.max");
            snprintf(mount, sizeof(mount), "%s/sys/fs/cgroup/unified", root);
            least_up(best, what, mount, cgroup, "memory.max");
        } else if (names(controllers, "memory")) {
            snprintf(mount, sizeof(mount), "%s/sys/fs/cgroup/memory", root);
            least_up(best, what, mount, cgroup, "memory.limit_in_bytes");
        }
    }
    fclose(fp);
}

double sp_memory_limit_in(const char *root, const char **what)
{
    double best = 0;
    const char *name = "nothing";
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0)
        least(&best, &name, (double)pages * (double)page, "physical memory");
    least_cgroup(&best, &name, root);
    struct rlimit rl;
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        least(&best, &name, (double)rl.rlim_cur, "ulimit -d");
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        least(&best, &name, (double)rl.rlim_cur, "ulimit -v");
    if (what)
        *what = name;
    return best;
}

double sp_memory_limit(const char **what)
{
    return sp_memory_limit_in("", what);
}

void sp_memory_rlimit_said(char *buf, size_t size)
{
    struct rlimit as, data;
    const int has_as = getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY;
    const int has_data = getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY;
    if (has_as && (!has_data || as.rlim_cur <= data.rlim_cur))
        snprintf(buf, size, "ulimit -v %llu kB", (unsigned long long)(as.rlim_cur / 1024));
    else if (has_data)
        snprintf(buf, size, "ulimit -d %llu kB", (unsigned long long)(data.rlim_cur / 1024));
    else
        snprintf(buf, size, "no ulimit -v or -d");
}

double sp_memory_rlimit(void)
{
    struct rlimit as, data;
    double least = 0;
    if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY)
        least = (double)as.rlim_cur;
    if (getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY &&
        (least == 0 || (double)data.rlim_cur < least))
        least = (double)data.rlim_cur;
    return least;
}

double sp_memory_peak(void)
{
    FILE *fp = fopen("/proc/self/status", "r");
    char line[256];
    double peak = 0;
    if (!fp)
        return 0;
    while (peak == 0 && fgets(line, sizeof(line), fp)) {
        unsigned long long kb;
        if (sscanf(line, "VmPeak: %llu kB", &kb) == 1)
            peak = (double)kb * 1024;
    }
    fclose(fp);
    return peak;
}

int sp_memory_rlimited(void)
{
    struct rlimit as, data;
    return (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) ||
           (getrlimit(RLIMIT_DATA, &data) == 0 && data.rlim_cur != RLIM_INFINITY);
}
