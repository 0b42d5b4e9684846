/* springpend (internal): how many CPUs this process may run on (cpu_count.c),
 * for the default thread counts (compare --jobs, sweep, the PNG sequence's
 * writers).
 * Shared with: every folder. */
#ifndef SPRINGPEND_CPU_COUNT_H
#define SPRINGPEND_CPU_COUNT_H

/* The CPUs in the process's affinity mask (sched_getaffinity, as nproc
 * counts them: `taskset -c 0` or a Slurm/cgroup cpuset gives fewer than
 * the machine has), else the machine's online CPUs; at least 1. */
int sp_cpu_count(void);

#endif
