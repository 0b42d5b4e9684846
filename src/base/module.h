/* springpend (internal): modules loaded on first use (module.c).
 * springpend-av.so holds everything that needs FFmpeg (sink_video.c, sink_gif.c, video_read.c);
 * springpend-cairo.so the vector figures (draw_cairo.c); springpend-plot.so
 * the sweeps' figures (sweep_plot.c, cairo; it calls back into the sweep
 * command's code, so only `springpend sweep` loads it). Loading FFmpeg's
 * libraries costs a process some 20-35 ms, cairo's about 1 ms, which commands
 * that write no video or vector figure should not pay.
 * Shared with: every folder. */
#ifndef SPRINGPEND_MODULE_H
#define SPRINGPEND_MODULE_H

/* The address of `symbol` in module `name` ("springpend-av.so"), loading it
 * on the first call; NULL (logged, naming `needed_for`) if it cannot be
 * loaded or lacks the symbol. Not thread-safe on the first call. A module is
 * looked for in the build tree (sp_build_tree) only by an executable in it or
 * one or two folders down (tests), then at SP_MODULE_RELDIR from the executable's
 * folder (installed, wherever the prefix now is: found through
 * /proc/self/exe), then in SP_MODULE_DIR (the configured prefix); never in
 * any other folder (a binary copied to /x/tools/ never loads a module from /x/). A
 * module is loaded only when it and every folder above it belong to root,
 * this user or the executable's owner and none is writable by others (but
 * sticky folders like /tmp), and only when its sp_module_version is
 * SP_VERSION; what was tried and why it was refused is in the message. */
void *sp_module_symbol(const char *name, const char *needed_for, const char *symbol);

/* 1 when the last module that could not be loaded failed for memory: under
 * ulimit -v or -d, the dynamic loader could not map it or a library it
 * needs (dlerror's "failed to map segment", "cannot allocate memory"), as
 * opposed to a missing or refused file. Its message then said "out of
 * memory ...; allow more memory", and callers return SP_E_NOMEM (exit 1,
 * not the input's fault: attack12 #6). */
int sp_module_out_of_memory(void);

#endif
