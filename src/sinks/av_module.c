/* springpend: the FFmpeg module's symbols (see av_module.h). */
#include "av_module.h"
#include "springpend/common.h"

int sp_av_module_error(void)
{
    return sp_module_out_of_memory() ? SP_E_NOMEM : SP_E_CODEC;
}

void *sp_av_module_symbol(const char *symbol)
{
    return sp_module_symbol("springpend-av.so", "video and GIF", symbol);
}
