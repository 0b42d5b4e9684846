/* springpend: loads springpend-av.so on first use (see av_module.h). */
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "av_module.h"

#define AV_MODULE "springpend-av.so"
#define PLOT_MODULE "springpend-plot.so"

/* The address of `symbol` in the module file `name`, loading it into
 * *module on first use; `what` says what it is for in the message. */
static void *module_symbol(void **module_slot, const char *name, const char *what,
                           const char *symbol)
{
    void *module = *module_slot;
    if (!module) {
        char exe[4096], try[4096 + 64], tried[3 * 4200] = "";
        ssize_t n = readlink("/proc/self/exe", exe, sizeof(exe) - 1);
        const char *where[3] = {NULL, NULL, SP_MODULE_DIR};
        if (n > 0) {
            exe[n] = '\0';
            char *slash = strrchr(exe, '/');
            if (slash)
                *slash = '\0';
            where[0] = exe;
            where[1] = exe; /* and its parent, below */
        }
        for (int i = 0; i < 3 && !module; i++) {
            if (!where[i])
                continue;
            snprintf(try, sizeof(try), "%s%s/%s", where[i], i == 1 ? "/.." : "", name);
            int readable = access(try, R_OK) == 0;
            if (readable)
                module = dlopen(try, RTLD_NOW | RTLD_LOCAL);
            if (!module)
                snprintf(tried + strlen(tried), sizeof(tried) - strlen(tried),
                         "%s%s: %s", tried[0] ? "; " : "", try,
                         readable ? dlerror() : strerror(errno));
        }
        if (!module) {
            sp_log_error("cannot load springpend's %s (%s); reinstall springpend", what, tried);
            return NULL;
        }
        *module_slot = module;
    }
    void *p = dlsym(module, symbol);
    if (!p)
        sp_log_error("%s lacks %s: %s", name, symbol, dlerror());
    return p;
}

void *sp_av_module_symbol(const char *symbol)
{
    static void *module;
    return module_symbol(&module, AV_MODULE, "FFmpeg module, needed for video and GIF", symbol);
}

void *sp_plot_module_symbol(const char *symbol)
{
    static void *module;
    return module_symbol(&module, PLOT_MODULE, "plot module, needed for sweep figures", symbol);
}
