/* springpend tests: the memory a process may use (base/memory_limit.h) is
 * read from the process's own cgroup, on a made-up tree (real cgroups
 * cannot be made here): cgroup v2's memory.max of the cgroup that
 * /proc/self/cgroup's "0::PATH" line names and of each cgroup above it,
 * the least of them; cgroup v1's memory.limit_in_bytes under the memory
 * controller's line; a hybrid host's /sys/fs/cgroup/unified; a sibling
 * cgroup's limit never counts; the deciding file is named (attack7 #4:
 * only /sys/fs/cgroup/memory.max, the namespace root's, was read).
 * usage: test_memory_limit OUTPUT_DIR */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "springpend/common.h"
#include "base/memory_limit.h"
#include "tap.h"

static char root[4096];

/* Writes text to root/rel, making its folders. */
static void put(const char *rel, const char *text)
{
    char path[8192];
    snprintf(path, sizeof(path), "%s/%s", root, rel);
    for (char *p = path + strlen(root) + 1; (p = strchr(p, '/')) != NULL; p++) {
        *p = 0;
        mkdir(path, 0777);
        *p = '/';
    }
    FILE *fp = fopen(path, "w");
    if (!fp || fputs(text, fp) < 0 || fclose(fp)) {
        fprintf(stderr, "cannot write %s: %s\n", path, strerror(errno));
        exit(99);
    }
}

static void clear(void)
{
    char cmd[8300];
    snprintf(cmd, sizeof(cmd), "rm -rf '%s/proc' '%s/sys'", root, root);
    if (system(cmd) != 0)
        exit(99);
}

/* The limit read under root, and whether the file that decided ends in tail. */
static int decides(double want, const char *tail, double *got, const char **what)
{
    *got = sp_memory_limit_in(root, what);
    const size_t n = strlen(*what), m = strlen(tail);
    return *got == want && n >= m && !strcmp(*what + n - m, tail);
}

int main(int argc, char **argv)
{
    double got;
    const char *what;
    int ok;
    snprintf(root, sizeof(root), "%s/memory_limit", argc > 1 ? argv[1] : ".");
    mkdir(root, 0777);

    /* cgroup v2, a job's sub-cgroup without its own namespace: the limit is
     * two levels below the root, whose memory.max says max */
    clear();
    put("proc/self/cgroup", "0::/system.slice/job.scope/step\n");
    put("sys/fs/cgroup/memory.max", "max\n");
    put("sys/fs/cgroup/system.slice/memory.max", "max\n");
    put("sys/fs/cgroup/system.slice/job.scope/memory.max", "123456789\n");
    put("sys/fs/cgroup/system.slice/job.scope/step/memory.max", "max\n");
    put("sys/fs/cgroup/system.slice/other.scope/memory.max", "1000\n"); /* a sibling */
    ok = decides(123456789, "/sys/fs/cgroup/system.slice/job.scope/memory.max", &got, &what);
    sp_tap_ok(ok,
              "v2: the least memory.max from the process's cgroup up to the root, a sibling's "
              "not counted (%.0f from %s)", got, what);

    /* the deepest is the least */
    put("sys/fs/cgroup/system.slice/job.scope/step/memory.max", "23456789\n");
    ok = decides(23456789, "/job.scope/step/memory.max", &got, &what);
    sp_tap_ok(ok,
              "v2: the process's own cgroup when it is the least (%.0f from %s)", got, what);

    /* cgroup v1, as on this build machine: "4:memory:/process_api/ID" */
    clear();
    put("proc/self/cgroup", "9:name=systemd:/\n5:cpu,cpuacct:/x\n4:memory:/process_api/abc\n0::/\n");
    put("sys/fs/cgroup/memory/memory.limit_in_bytes", "9223372036854771712\n");
    put("sys/fs/cgroup/memory/process_api/memory.limit_in_bytes", "9223372036854771712\n");
    put("sys/fs/cgroup/memory/process_api/abc/memory.limit_in_bytes", "99999744\n");
    ok = decides(99999744, "/sys/fs/cgroup/memory/process_api/abc/memory.limit_in_bytes", &got,
                 &what);
    sp_tap_ok(ok,
              "v1: the memory controller's memory.limit_in_bytes (%.0f from %s)", got, what);

    /* v1 with the memory controller mounted beside others' names */
    clear();
    put("proc/self/cgroup", "3:memory,hugetlb:/j\n");
    put("sys/fs/cgroup/memory/j/memory.limit_in_bytes", "88888320\n");
    ok = decides(88888320, "/memory/j/memory.limit_in_bytes", &got, &what);
    sp_tap_ok(ok,
              "v1: 'memory' among several controllers on the line (%.0f from %s)", got, what);

    /* a hybrid host: v2 at /sys/fs/cgroup/unified */
    clear();
    put("proc/self/cgroup", "4:memory:/\n0::/user.slice/u\n");
    put("sys/fs/cgroup/unified/user.slice/memory.max", "77777664\n");
    ok = decides(77777664, "/sys/fs/cgroup/unified/user.slice/memory.max", &got, &what);
    sp_tap_ok(ok,
              "hybrid: v2's memory.max under /sys/fs/cgroup/unified (%.0f from %s)", got, what);

    /* no cgroup limit anywhere: physical memory (or a ulimit) decides */
    clear();
    put("proc/self/cgroup", "0::/a\n");
    put("sys/fs/cgroup/a/memory.max", "max\n");
    got = sp_memory_limit_in(root, &what);
    sp_tap_ok(got > 0 && !strstr(what, "cgroup"),
              "'max' everywhere: no cgroup limit (%.0f from %s)", got, what);

    /* a forged or absent /proc/self/cgroup line changes nothing */
    clear();
    put("proc/self/cgroup", "garbage\n::\n0:memory\n");
    got = sp_memory_limit_in(root, &what);
    sp_tap_ok(got > 0 && !strstr(what, "cgroup"), "lines that are no cgroup are skipped (%s)",
              what);
    clear();
    return sp_tap_done();
}
