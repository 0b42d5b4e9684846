/* springpend: the process's signals (signals.h, signal_name.h). */
#include <signal.h>
#include <string.h>
#include <unistd.h>

#include "signals.h"

/* Every signal whose default would kill the process and leave its .part
 * files: each stops a run cleanly like SIGTERM (exit status 128 + number).
 * SIGQUIT and SIGXCPU (ulimit -t) too: a core dump of a render helps
 * nobody, its .part files harm. Not caught: SIGPIPE and SIGXFSZ (ignored:
 * the write fails and is cleaned up), SIGPROF (profilers' timer), the
 * real-time signals, and what cannot be (SIGKILL) or means a bug (SIGSEGV,
 * SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGTRAP, SIGSYS). */
static const int caught[SP_SIGNALS_CAUGHT] = {SIGINT,  SIGTERM, SIGHUP,    SIGQUIT, SIGUSR1,
                                              SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU, SIGPWR};
static const char *const caught_name[SP_SIGNALS_CAUGHT] = {
    "SIGINT",  "SIGTERM", "SIGHUP",    "SIGQUIT", "SIGUSR1",
    "SIGUSR2", "SIGALRM", "SIGVTALRM", "SIGXCPU", "SIGPWR"};

static volatile sig_atomic_t seen;  /* the first signal, 0 = none */
static volatile sig_atomic_t count; /* signals since sp_signals_hold */
static void (*volatile held_cleanup)(void); /* the hold's; NULL = none */

static void on_signal(int sig)
{
    seen = sig;
}

/* While held: the first sets the flag, the second stops at once. Only
 * async-signal-safe calls here (the cleanup is: outfile.c's .part table
 * stays valid through the sink's close). */
static void on_signal_held(int sig)
{
    if (count++ == 0) {
        seen = sig;
        return;
    }
    static const char msg[] = "springpend: second signal: stopped at once, "
                              "partial file removed\n";
    void (*cleanup)(void) = held_cleanup;
    if (cleanup)
        cleanup();
    if (write(2, msg, sizeof(msg) - 1) < 0) {
        /* nothing more can be done */
    }
    _exit(128 + sig);
}

/* Sets handler for the caught signals, keeping the old ones in old (NULL:
 * not kept). */
static void set_handlers(void (*handler)(int), struct sigaction old[SP_SIGNALS_CAUGHT])
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < SP_SIGNALS_CAUGHT; i++)
        sigaction(caught[i], &sa, old ? &old[i] : NULL);
}

void sp_signals_install(void)
{
    set_handlers(on_signal, NULL);
}

int sp_signal_seen(void)
{
    return seen;
}

const volatile sig_atomic_t *sp_signal_flag(void)
{
    return &seen;
}

const char *sp_signal_name(int sig)
{
    for (int i = 0; i < SP_SIGNALS_CAUGHT; i++)
        if (caught[i] == sig)
            return caught_name[i];
    return "a signal";
}

void sp_signals_hold(struct sp_signals_saved *saved, void (*cleanup)(void))
{
    count = 0;
    held_cleanup = cleanup;
    set_handlers(on_signal_held, saved->old);
}

void sp_signals_release(const struct sp_signals_saved *saved)
{
    for (int i = 0; i < SP_SIGNALS_CAUGHT; i++)
        sigaction(caught[i], &saved->old[i], NULL);
}
