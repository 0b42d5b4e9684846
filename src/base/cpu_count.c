/* springpend: how many CPUs this process may run on (cpu_count.h). */
#include <sched.h>
#include <stdlib.h>
#include <unistd.h>

#include "cpu_count.h"

int sp_cpu_count(void)
{
    /* A mask large enough for any machine Linux runs on (CPU_SETSIZE is
     * 1024: sched_getaffinity fails with EINVAL on more), grown as needed. */
    for (int ncpu = 1024; ncpu <= 1 << 16; ncpu *= 4) {
        cpu_set_t *set = CPU_ALLOC(ncpu);
        const size_t size = CPU_ALLOC_SIZE(ncpu);
        if (!set)
            break;
        if (sched_getaffinity(0, size, set) == 0) {
            const int n = CPU_COUNT_S(size, set);
            CPU_FREE(set);
            return n > 0 ? n : 1;
        }
        CPU_FREE(set);
    }
    const long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}
