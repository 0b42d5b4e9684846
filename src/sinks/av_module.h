/* springpend (internal): springpend-av.so, the module that holds everything
 * that needs FFmpeg (sink_video.c, sink_gif.c, video_read.c), loaded on
 * first use by module.h's loader.
 * Shared with: base (environment.c), compare (video_read_stub.c). */
#ifndef SPRINGPEND_AV_MODULE_H
#define SPRINGPEND_AV_MODULE_H

#include "base/module.h"

/* sp_module_symbol of springpend-av.so. */
void *sp_av_module_symbol(const char *symbol);

/* What a caller returns when sp_av_module_symbol gave NULL: SP_E_NOMEM when
 * the module could not be mapped for memory (sp_module_out_of_memory),
 * else SP_E_CODEC. */
int sp_av_module_error(void);

#endif
