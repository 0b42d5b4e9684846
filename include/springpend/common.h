/* springpend: shared error codes and logging.
 * Every function that can fail returns 0 or a negative SP_E_* code and logs
 * once, at the point of failure, in the failing library's own words. */
#ifndef SPRINGPEND_COMMON_H
#define SPRINGPEND_COMMON_H

#define SP_VERSION "0.1.0"

enum sp_error {
    SP_OK = 0,
    SP_E_INPUT = -1,       /* bad scene, option or argument: exit status 2 */
    SP_E_IO = -2,          /* file system or encoder I/O failed */
    SP_E_NOMEM = -3,       /* allocation failed */
    SP_E_GL = -4,          /* GL context or shader failure */
    SP_E_CODEC = -5,       /* libav* reported an error */
    SP_E_UNSTABLE = -6,    /* the integration blew up: exit status 3 */
    SP_E_INTERRUPTED = -7, /* stopped by a signal */
    SP_E_MISMATCH = -8,    /* compare: images differ beyond tolerance: exit status 1 */
};

/* Prints "springpend: <message>\n" to stderr. */
void sp_log_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Makes SIGINT, SIGTERM and SIGHUP set a flag instead of killing the
 * process, so a long run can stop cleanly and remove its partial files.
 * main calls it once. */
void sp_interrupt_install(void);

/* The signal's number once one of those signals has arrived, else 0.
 * Loops that run for long check it and return SP_E_INTERRUPTED. */
int sp_interrupted(void);

/* Records sig as if the handler above had caught it; async-signal-safe, for
 * handlers installed elsewhere (the render pipeline's). */
void sp_interrupt_note(int sig);

/* Progress of a long integration, drawn on stderr when it is a terminal:
 * a command calls sp_progress_begin before integrating to t_goal
 * (simulated s; what names the pass), the simulation calls sp_progress_sim
 * as it goes (cheap: it redraws at most 4 times a second and only after
 * 2 s), and sp_progress_end clears the line. enable = 0 draws nothing. */
void sp_progress_begin(int enable, const char *what, double t_goal);
void sp_progress_sim(double t);
void sp_progress_end(void);

#endif
