/* springpend: the FFmpeg module's symbols (see av_module.h). */
#include "av_module.h"

void *sp_av_module_symbol(const char *symbol)
{
    return sp_module_symbol("springpend-av.so", "video and GIF", symbol);
}
