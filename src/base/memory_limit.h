/* springpend (internal): how much memory this process may use (memory_limit.c),
 * for work that sizes its threads by memory (compare --jobs).
 * Shared with: every folder. */
#ifndef SPRINGPEND_MEMORY_LIMIT_H
#define SPRINGPEND_MEMORY_LIMIT_H

#include <stddef.h>

/* Bytes: the least of the machine's physical memory, the process's own
 * cgroup limits and its RLIMIT_DATA and RLIMIT_AS (when set). The cgroups
 * are those /proc/self/cgroup names: for cgroup v2 (its "0::PATH" line)
 * memory.max in /sys/fs/cgroup/PATH and each folder above it up to the root
 * (or under /sys/fs/cgroup/unified on a hybrid host); for cgroup v1 (the
 * line whose controllers hold "memory") memory.limit_in_bytes in
 * /sys/fs/cgroup/memory/PATH and above. *what names the one that decides
 * ("physical memory", the cgroup file's path, "ulimit -d", "ulimit -v"),
 * valid until this thread's next call. 0 when none can be read. */
double sp_memory_limit(const char **what);

/* The same with every path above under folder root ("" for the real ones):
 * for a test on a made-up tree (tests/unit/test_memory_limit.c). */
double sp_memory_limit_in(const char *root, const char **what);

/* 1 when the process runs under ulimit -v or -d: the limits under which
 * an allocation fails on Linux (rather than the kernel ending the
 * process), so that a failure a library reports as something else
 * (FFmpeg's decoders: damaged data) may be out of memory. 0 otherwise. */
int sp_memory_rlimited(void);

/* The least of ulimit -v and -d in buf, as a user sets it
 * ("ulimit -v 270000 kB"), or "no ulimit -v or -d". */
void sp_memory_rlimit_said(char *buf, size_t size);

/* Bytes: the least of ulimit -v and -d (their soft limits), 0 when neither
 * is set. */
double sp_memory_rlimit(void);

/* Bytes: the most address space this process has held (VmPeak, in
 * /proc/self/status), which bounds its data too: under ulimit -v or -d an
 * allocation fails only when what is held and what is asked for exceed the
 * limit. 0 when it cannot be read. */
double sp_memory_peak(void);

#endif
