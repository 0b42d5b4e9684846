/* springpend: loads springpend-av.so on first use (see av_module.h). */
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "springpend/common.h"
#include "av_module.h"

#define AV_MODULE "springpend-av.so"

void *sp_av_module_symbol(const char *symbol)
{
    static void *module;
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
                     i == 1 ? "/.." : i == 2 ? "/" SP_MODULE_RELDIR : "", AV_MODULE);
            int readable = access(try, R_OK) == 0;
            if (readable)
                module = dlopen(try, RTLD_NOW | RTLD_LOCAL);
            if (!module)
                snprintf(tried + strlen(tried), sizeof(tried) - strlen(tried),
                         "%s%s: %s", tried[0] ? "; " : "", try,
                         readable ? dlerror() : strerror(errno));
        }
        if (!module) {
            sp_log_error("cannot load springpend's FFmpeg module, needed for "
                         "video and GIF (%s); reinstall springpend", tried);
            return NULL;
        }
    }
    void *p = dlsym(module, symbol);
    if (!p)
        sp_log_error("%s lacks %s: %s", AV_MODULE, symbol, dlerror());
    return p;
}
