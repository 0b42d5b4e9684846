/* springpend: loads modules on first use (see module.h). */
#include <dlfcn.h>
#include <errno.h>
#include <grp.h>
#include <limits.h>
#include <pwd.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/xattr.h>
#include <unistd.h>

#include "memory_limit.h"
#include "module_abi.h"
#include "springpend/common.h"
#include "springpend/infile.h"
#include "module.h"
#include "places.h"

enum { MAX_MODULES = 4 };

/* 1 when members of group gid other than root and this user cannot be
 * told apart from root or this user: gid 0 (root's group), or this user's
 * own private group (the process's group, named as the user, with no
 * members listed: Debian's and Fedora's user private groups, umask 002).
 * A shared group (staff, users, a cluster's project group) is not. */
static int own_group(gid_t gid)
{
    struct passwd pw, *pwp = NULL;
    struct group gr, *grp = NULL;
    char pbuf[4096], gbuf[8192]; /* getpwuid_r/getgrgid_r: modules may load on any thread */
    if (gid == 0)
        return 1;
    return gid == getegid() && !getpwuid_r(geteuid(), &pw, pbuf, sizeof(pbuf), &pwp) && pwp &&
           !getgrgid_r(gid, &gr, gbuf, sizeof(gbuf), &grp) && grp &&
           !strcmp(gr.gr_name, pw.pw_name) && (!gr.gr_mem || !gr.gr_mem[0]);
}

/* Group gid's name into buf, or its number when it has none. */
static void group_name(gid_t gid, char *buf, size_t size)
{
    struct group gr, *grp = NULL;
    char gbuf[8192];
    if (!getgrgid_r(gid, &gr, gbuf, sizeof(gbuf), &grp) && grp)
        snprintf(buf, size, "%s (gid %u)", gr.gr_name, (unsigned)gid);
    else
        snprintf(buf, size, "%u", (unsigned)gid);
}

/* 1 when the file or folder at p has an extended POSIX access ACL (the
 * kernel keeps the system.posix_acl_access attribute only for an ACL that
 * says more than the mode): its group bits are then the ACL's mask, the
 * most that any named user or group may do, not what its group may. */
static int has_acl(const char *p)
{
    return getxattr(p, "system.posix_acl_access", NULL, 0) > 0;
}

/* 0 when the file at path, and every folder above it, could only have been
 * put there by root, by this user or by the executable's owner: each is
 * owned by one of them and none is writable by others (a folder writable by
 * all only with the sticky bit, like /tmp, whose entries others cannot
 * replace; writable by its group only when that group is root's or this
 * user's private group: own_group; never when an ACL lets a named user or
 * group write it, whose mask is those group bits: has_acl). Else -1 with
 * why. Links are resolved first. Nothing here helps once a trusted file is
 * replaced: a module's version is checked after dlopen, which has run its
 * constructors. */
static int trusted(const char *path, uid_t exe_uid, char *why, size_t size)
{
    char *real = realpath(path, NULL);
    int ret = 0;
    if (!real) {
        snprintf(why, size, "%s", strerror(errno));
        return -1;
    }
    /* real is absolute: "/a/b", then "/a", then "" standing for "/". */
    for (size_t len = strlen(real); ret == 0;) {
        struct stat st;
        const char *p = len ? real : "/";
        if (stat(p, &st) != 0) {
            snprintf(why, size, "%s: %s", p, strerror(errno));
            ret = -1;
        } else if (st.st_uid != 0 && st.st_uid != geteuid() && st.st_uid != exe_uid) {
            snprintf(why, size, "%s belongs to user %u, neither root, you nor the owner of "
                     "springpend; not loaded", p, (unsigned)st.st_uid);
            ret = -1;
        } else if ((st.st_mode & S_IWOTH) && !(S_ISDIR(st.st_mode) && (st.st_mode & S_ISVTX))) {
            snprintf(why, size, "%s is writable by anyone; not loaded", p);
            ret = -1;
        } else if ((st.st_mode & S_IWGRP) && has_acl(p)) {
            snprintf(why, size, "%s has an ACL that lets users or groups other than its owner "
                     "write it (getfacl shows them); not loaded", p);
            ret = -1;
        } else if ((st.st_mode & S_IWGRP) && !(S_ISDIR(st.st_mode) && (st.st_mode & S_ISVTX)) &&
                   !own_group(st.st_gid)) {
            char group[96];
            group_name(st.st_gid, group, sizeof(group));
            snprintf(why, size, "%s is writable by group %s; not loaded", p, group);
            ret = -1;
        }
        if (!len)
            break;
        char *slash = strrchr(real, '/');
        *slash = 0;
        len = (size_t)(slash - real);
    }
    free(real);
    return ret;
}

/* Loads the module at path, when it is trusted and carries this version;
 * else NULL with why. */
static void *load(const char *path, uid_t exe_uid, char *why, size_t size)
{
    if (access(path, R_OK) != 0) {
        snprintf(why, size, "%s", strerror(errno));
        return NULL;
    }
    /* checked and opened by the same resolved name: a link swapped into an
     * unchecked folder of path between the two cannot pick the file */
    char *real = realpath(path, NULL);
    if (!real) {
        snprintf(why, size, "%s", strerror(errno));
        return NULL;
    }
    if (trusted(real, exe_uid, why, size)) {
        free(real);
        return NULL;
    }
    /* dlopen opens whatever is there: a FIFO would wait for a writer, a
     * device would run its driver's open (attack17 #4). Only a regular
     * file is a module; trusted() keeps others from swapping it after. */
    struct stat st;
    if (stat(real, &st) != 0 || !S_ISREG(st.st_mode)) {
        if (errno = 0, stat(real, &st) == 0)
            snprintf(why, size, "is %s, not a module; not loaded", sp_file_kind(st.st_mode));
        else
            snprintf(why, size, "%s", strerror(errno));
        free(real);
        return NULL;
    }
    void *module = dlopen(real, RTLD_NOW | RTLD_LOCAL);
    free(real);
    if (!module) {
        snprintf(why, size, "%s", dlerror());
        return NULL;
    }
    const char *version = dlsym(module, "sp_module_version");
    const char *abi = dlsym(module, "sp_module_abi");
    if (!version || strcmp(version, SP_VERSION)) {
        snprintf(why, size, "built for springpend %.32s, not %s", version ? version : "(unknown)",
                 SP_VERSION);
        dlclose(module);
        return NULL;
    }
    if (!abi || strcmp(abi, SP_MODULE_ABI)) { /* same number, another build */
        snprintf(why, size, "built by another build of springpend %s (interface %.16s, not %s): "
                 "install the modules built with this executable", SP_VERSION,
                 abi ? abi : "(none)", SP_MODULE_ABI);
        dlclose(module);
        return NULL;
    }
    return module;
}

/* Set when the last failed load was memory's (sp_module_out_of_memory). */
static int load_nomem;

int sp_module_out_of_memory(void)
{
    return load_nomem;
}

/* 1 when dlopen's error (why) is one the loader raises when mmap or an
 * allocation fails, and the process runs under ulimit -v or -d, under
 * which they fail for the limit (elsewhere the kernel does not refuse a
 * mapping for memory). "failed to map segment" is also raised on a noexec
 * mount, with its reason after it: not taken then. */
static int load_failed_for_memory(const char *why)
{
    return sp_memory_rlimited() &&
           (strstr(why, "failed to map segment") || strstr(why, "cannot map zero-fill") ||
            strstr(why, "annot allocate memory")) &&
           !strstr(why, "not permitted") && !strstr(why, "ermission denied");
}

void *sp_module_symbol(const char *name, const char *needed_for, const char *symbol)
{
    static struct {
        const char *name;
        void *handle;
    } loaded[MAX_MODULES];
    void *module = NULL;
    int slot = 0;
    while (slot < MAX_MODULES && loaded[slot].name && strcmp(loaded[slot].name, name))
        slot++;
    if (slot == MAX_MODULES) {
        sp_log_error("too many modules to load %s", name);
        return NULL;
    }
    module = loaded[slot].handle;
    if (!module) {
        char exe[PATH_MAX], build[PATH_MAX], where[4][PATH_MAX + 256];
        char tried[4 * (sizeof(where[0]) + PATH_MAX + 128 + 2)] = "";
        struct stat st;
        int n_where = 0;
        ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
        uid_t exe_uid = n > 0 && (exe[n] = 0, stat(exe, &st) == 0) ? st.st_uid : 0;
        if (n > 0) {
            char *slash = strrchr(exe, '/');
            if (slash)
                *slash = '\0';
            /* The build tree: the executable, or a test one or two folders
             * down (tests/, tests/unit/), found at run time (places.h). */
            if (sp_build_tree(build, NULL))
                snprintf(where[n_where++], sizeof(where[0]), "%s/%s", build, name);
            /* The installed layout, wherever the prefix now is. */
            snprintf(where[n_where++], sizeof(where[0]), "%s/%s/%s", exe, SP_MODULE_RELDIR, name);
        }
        snprintf(where[n_where++], sizeof(where[0]), "%s/%s", SP_MODULE_DIR, name);
        int nomem = 0;
        for (int i = 0; i < n_where && !module; i++) {
            char why[PATH_MAX + 128];
            if (!(module = load(where[i], exe_uid, why, sizeof(why)))) {
                snprintf(tried + strlen(tried), sizeof(tried) - strlen(tried), "%s%s: %s",
                         tried[0] ? "; " : "", where[i], why);
                nomem |= load_failed_for_memory(why);
            }
        }
        load_nomem = !module && nomem;
        if (load_nomem) {
            static int said; /* once: each caller tries again, and fails alike */
            char limit[64];
            sp_memory_rlimit_said(limit, sizeof(limit));
            if (!said++)
                sp_log_error("cannot load springpend's module %s, needed for %s: out of memory "
                             "(%s) mapping it or the libraries it needs (%s); allow more memory",
                             name, needed_for, limit, tried);
            return NULL;
        }
        if (!module) {
            sp_log_error("cannot load springpend's module %s, needed for %s (%s); "
                         "reinstall springpend", name, needed_for, tried);
            return NULL;
        }
        loaded[slot].name = name;
        loaded[slot].handle = module;
    }
    void *p = dlsym(module, symbol);
    if (!p)
        sp_log_error("%s lacks %s: %s", name, symbol, dlerror());
    return p;
}
