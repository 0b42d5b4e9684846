/* springpend: how much memory this process may use (memory_limit.h). */
#include <stdio.h>
#include <stdlib.h>
#include <sys/resource.h>
#include <unistd.h>

#include "memory_limit.h"

/* Keeps the smaller of *best and v (v > 0), naming it. */
static void least(double *best, const char **what, double v, const char *name)
{
    if (v > 0 && (*best == 0 || v < *best))
        *best = v, *what = name;
}

double sp_memory_limit(const char **what)
{
    double best = 0;
    const char *name = "nothing";
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0)
        least(&best, &name, (double)pages * (double)page, "physical memory");
    FILE *fp = fopen("/sys/fs/cgroup/memory.max", "r"); /* "max" when unlimited */
    char line[64];
    if (fp && fgets(line, sizeof(line), fp)) {
        char *end;
        const double v = strtod(line, &end);
        if (end != line)
            least(&best, &name, v, "the cgroup's memory.max");
    }
    if (fp)
        fclose(fp);
    struct rlimit rl;
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        least(&best, &name, (double)rl.rlim_cur, "ulimit -d");
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        least(&best, &name, (double)rl.rlim_cur, "ulimit -v");
    if (what)
        *what = name;
    return best;
}
