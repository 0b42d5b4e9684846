/* springpend (internal): how much memory this process may use (memory_limit.c),
 * for work that sizes its threads by memory (compare --jobs).
 * Shared with: every folder. */
#ifndef SPRINGPEND_MEMORY_LIMIT_H
#define SPRINGPEND_MEMORY_LIMIT_H

/* Bytes: the least of the machine's physical memory, the cgroup's
 * memory.max (cgroup v2, when set) and the process's RLIMIT_DATA and
 * RLIMIT_AS (when set). *what names the one that decides ("physical
 * memory", "the cgroup's memory.max", "ulimit -d", "ulimit -v"). 0 when
 * none can be read. */
double sp_memory_limit(const char **what);

#endif
