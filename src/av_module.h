/* springpend (internal): springpend-av.so, the module with everything that
 * needs FFmpeg (sink_video.c, sink_gif.c, video_read.c). Loading FFmpeg's
 * libraries costs a process some 20-35 ms, which commands that write or
 * read no video should not pay, so the module is loaded on first use. */
#ifndef SPRINGPEND_AV_MODULE_H
#define SPRINGPEND_AV_MODULE_H

/* The address of `symbol` in the module, loading it on the first call; NULL
 * (logged) if it cannot be loaded or lacks the symbol. Not thread-safe on
 * the first call. The module is looked for beside the executable (the build
 * tree), one folder up (tests), then in SP_MODULE_DIR (installed). */
void *sp_av_module_symbol(const char *symbol);

/* The same for springpend-plot.so, the sweeps' figures (sweep_plot.c, with
 * cairo, which costs a process about 1.2 ms to load). It calls back into
 * the sweep command's code, so only executables that link sweep.c load it. */
void *sp_plot_module_symbol(const char *symbol);

#endif
