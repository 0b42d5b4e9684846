/* springpend: loads modules on first use (see av_module.h). */
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "av_module.h"

enum { MAX_MODULES = 4 };

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
        char exe[4096], try[4096 + 256], tried[4 * 4400] = "";
        ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
        const char *where[4] = {NULL, NULL, NULL, SP_MODULE_DIR};
        if (n > 0) {
            exe[n] = '\0';
            char *slash = strrchr(exe, '/');
            if (slash)
                *slash = '\0';
            where[0] = exe;
            where[1] = exe; /* and its parent, below */
            where[2] = exe; /* and the installed layout, below */
        }
        for (int i = 0; i < 4 && !module; i++) {
            if (!where[i])
                continue;
            snprintf(try, sizeof(try), "%s%s/%s", where[i],
                     i == 1 ? "/.." : i == 2 ? "/" SP_MODULE_RELDIR : "", name);
            int readable = access(try, R_OK) == 0;
            if (readable)
                module = dlopen(try, RTLD_NOW | RTLD_LOCAL);
            if (!module)
                snprintf(tried + strlen(tried), sizeof(tried) - strlen(tried),
                         "%s%s: %s", tried[0] ? "; " : "", try,
                         readable ? dlerror() : strerror(errno));
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

void *sp_av_module_symbol(const char *symbol)
{
    return sp_module_symbol("springpend-av.so", "video and GIF", symbol);
}
