/* springpend (internal): the process's signals. The one owner of SIGINT,
 * SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU,
 * SIGPWR, SIGPROF, SIGIO, SIGSTKFLT and the real-time signals (every
 * signal that would otherwise kill the process with its .part files left
 * behind; signals.c says which are left alone and why):
 * main installs a handler that sets a flag; the commands (cli/) and the
 * pipeline poll sp_signal_seen and hand sp_signal_flag down as a cancel
 * flag (struct sp_sim's, a desc's): the code below them never reads it
 * itself. While a render holds them (sp_signals_hold), a second signal
 * calls the hold's cleanup (the pipeline's: outfile.h's, which removes the
 * partial files) and exits at once.
 * Shared with: cli (main.c only), pipeline. */
#ifndef SPRINGPEND_SIGNALS_H
#define SPRINGPEND_SIGNALS_H

#include <signal.h>

#include "signal_name.h" /* sp_signal_name */

/* Makes the caught signals set the flag instead of killing the
 * process, so a long run can stop cleanly and remove its partial files.
 * main calls it once. */
void sp_signals_install(void);

/* The first signal's number once one has arrived, else 0. Loops that run
 * for long check it and return SP_E_INTERRUPTED. */
int sp_signal_seen(void);

/* The flag itself (nonzero once a signal arrived), for struct sp_sim's
 * cancel. */
const volatile sig_atomic_t *sp_signal_flag(void);

/* The most signals the flag stands for: SIGINT, SIGTERM, SIGHUP, SIGQUIT,
 * SIGUSR1/2, SIGALRM, SIGVTALRM, SIGXCPU, SIGPWR, SIGPROF, SIGIO,
 * SIGSTKFLT and the real-time ones (signals.c says which are caught). */
#define SP_SIGNALS_CAUGHT 64

/* The handlers a hold replaced. */
struct sp_signals_saved {
    struct sigaction old[SP_SIGNALS_CAUGHT];
};

/* Until sp_signals_release: the first caught signal (counted
 * from here) sets the flag; a second calls cleanup (async-signal-safe, as
 * sp_outfile_remove_parts, which removes every .part now open; NULL: none)
 * and exits the process at once with status 128 + signal. For a render
 * that finishes the file so far on the first. */
void sp_signals_hold(struct sp_signals_saved *saved, void (*cleanup)(void));

/* Restores the handlers sp_signals_hold replaced. */
void sp_signals_release(const struct sp_signals_saved *saved);

#endif
