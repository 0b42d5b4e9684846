/* springpend (internal): springpend-av.so, the module with everything that
 * needs FFmpeg (sink_video.c, sink_gif.c, video_read.c). Loading FFmpeg's
 * libraries costs a process some 20-35 ms, which commands that write or
 * read no video should not pay, so the module is loaded on first use. */
#ifndef SPRINGPEND_AV_MODULE_H
#define SPRINGPEND_AV_MODULE_H

/* The address of `symbol` in the module, loading it on the first call; NULL
 * (logged) if it cannot be loaded or lacks the symbol. Not thread-safe on
 * the first call. The module is looked for beside the executable (the build
 * tree), one folder up (tests), at SP_MODULE_RELDIR from the executable's
 * folder (installed, wherever the prefix now is: found through
 * /proc/self/exe), then in SP_MODULE_DIR (the configured prefix). */
void *sp_av_module_symbol(const char *symbol);

#endif
