/* springpend: the process's signals (signals.h, signal_name.h). */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "signals.h"

/* Every signal whose default would kill the process and leave its .part
 * files: each stops a run cleanly like SIGTERM (exit status 128 + number).
 * SIGQUIT and SIGXCPU (ulimit -t) too: a core dump of a render helps
 * nobody, its .part files harm. These ten are caught unless the process
 * started with them ignored (nohup's SIGHUP, a background job's SIGINT:
 * ignored they stay). The others whose default is to terminate (SIGPROF,
 * SIGIO, SIGSTKFLT and SIGRTMIN..SIGRTMAX, which schedulers and container
 * runtimes send as custom stop signals) are caught only where they still
 * have their default action: a profiler's SIGPROF handler stays its own.
 * Not caught: SIGPIPE and SIGXFSZ (ignored: the write fails and is cleaned
 * up), and what cannot be (SIGKILL) or means a bug (SIGSEGV, SIGBUS,
 * SIGILL, SIGFPE, SIGABRT, SIGTRAP, SIGSYS). */
static const int named[] = {SIGINT,  SIGTERM, SIGHUP,    SIGQUIT, SIGUSR1,
                            SIGUSR2, SIGALRM, SIGVTALRM, SIGXCPU, SIGPWR};
static const char *const named_name[] = {"SIGINT",  "SIGTERM", "SIGHUP",    "SIGQUIT", "SIGUSR1",
                                         "SIGUSR2", "SIGALRM", "SIGVTALRM", "SIGXCPU", "SIGPWR"};
static const int if_default[] = {SIGPROF, SIGIO,
#ifdef SIGSTKFLT
                                 SIGSTKFLT,
#endif
};
static const char *const if_default_name[] = {"SIGPROF", "SIGIO",
#ifdef SIGSTKFLT
                                              "SIGSTKFLT",
#endif
};

static int caught[SP_SIGNALS_CAUGHT]; /* filled by sp_signals_install */
static int n_caught;
static char rt_name[SP_SIGNALS_CAUGHT][16]; /* "SIGRTMIN+3", by index in caught */
static volatile sig_atomic_t seen;  /* the first signal, 0 = none */
static volatile sig_atomic_t count; /* signals since sp_signals_hold */
static volatile sig_atomic_t holding; /* 1 between sp_signals_hold and _release */
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

/* Signal 32, the kernel's first real-time signal, which glibc reserves
 * as SIGCANCEL (its SIGRTMIN is 34) and whose sigaction() refuses it
 * (EINVAL): its default kills the process with its .part files left
 * (attack10 #15). Caught through the rt_sigaction system call, with one
 * handler for both states (on_signal, or on_signal_held while held), so
 * that sp_signals_hold never touches it. Why this is safe here:
 * - glibc >= 2.34 installs its own handler for 32 only when the process
 *   first calls pthread_cancel, and then whatever was there before: a
 *   cancellation still works. springpend never calls it; of the libraries
 *   it loads, only libavformat's UDP protocol and libsrt do, and springpend
 *   opens files through the file protocol alone (outfile.c's "file:" URLs,
 *   video_read.c's protocol_whitelist).
 * - 32 is caught only while it has its default action: where glibc's
 *   handler is already there, it stays.
 * - glibc's timer_create(SIGEV_THREAD) also uses 32, in a helper thread
 *   that blocks it and waits for it (sigwaitinfo): a handler never runs
 *   there. springpend makes no such timer.
 * - The handler does what the others do: sets a flag, or (held, a second
 *   signal) removes the .part files and _exits.
 * Signal 33 (SIGSETXID) is left alone: glibc installs its handler at start
 * (setuid and its kind call it on every thread), and that handler ignores a
 * 33 sent from outside, so it kills nothing.
 * The kernel's struct sigaction is the same on x86-64 and AArch64 (handler,
 * flags, restorer, an 8-byte mask); it is read back from a signal that
 * sigaction() set up (caught[0]), so the flags and the restorer (x86-64's
 * SA_RESTORER, which returns from the handler) are glibc's own. Elsewhere
 * 32 is not caught. */
#if defined(SYS_rt_sigaction) && (defined(__x86_64__) || defined(__aarch64__))
#define SP_SIGCANCEL 32
struct kernel_sigaction {
    void (*handler)(int);
    unsigned long flags;
    void (*restorer)(void);
    unsigned long mask;
};

static int cancel_caught; /* 1: SP_SIGCANCEL has on_signal_32 */

static void on_signal_32(int sig)
{
    if (holding)
        on_signal_held(sig);
    else
        on_signal(sig);
}

/* Catches SP_SIGCANCEL (above), once, after set_handlers(on_signal). */
static void catch_32(void)
{
    struct kernel_sigaction like, now;
    if (cancel_caught || n_caught == 0 ||
        syscall(SYS_rt_sigaction, caught[0], NULL, &like, sizeof(like.mask)) != 0 ||
        like.handler != on_signal ||
        syscall(SYS_rt_sigaction, SP_SIGCANCEL, NULL, &now, sizeof(now.mask)) != 0 ||
        now.handler != SIG_DFL)
        return;
    like.handler = on_signal_32;
    cancel_caught = syscall(SYS_rt_sigaction, SP_SIGCANCEL, &like, NULL, sizeof(like.mask)) == 0;
}
#else
static void catch_32(void)
{
}
#endif

/* Sets handler for the caught signals, keeping the old ones in old (NULL:
 * not kept). */
static void set_handlers(void (*handler)(int), struct sigaction old[SP_SIGNALS_CAUGHT])
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = handler;
    sigemptyset(&sa.sa_mask);
    for (int i = 0; i < n_caught; i++)
        sigaction(caught[i], &sa, old ? &old[i] : NULL);
}

/* Adds sig to caught where its disposition now allows: not ignored, and
 * for a signal of if_default[] or the real-time range, not handled. */
static void add_caught(int sig, int only_default)
{
    struct sigaction now;
    if (n_caught >= SP_SIGNALS_CAUGHT || sigaction(sig, NULL, &now) != 0)
        return;
    if (now.sa_handler == SIG_IGN || (only_default && now.sa_handler != SIG_DFL))
        return;
    caught[n_caught++] = sig;
}

void sp_signals_install(void)
{
    n_caught = 0;
    for (size_t i = 0; i < sizeof(named) / sizeof(named[0]); i++)
        add_caught(named[i], 0);
    for (size_t i = 0; i < sizeof(if_default) / sizeof(if_default[0]); i++)
        add_caught(if_default[i], 1);
    for (int sig = SIGRTMIN; sig <= SIGRTMAX; sig++) {
        const int at = n_caught;
        add_caught(sig, 1);
        if (n_caught > at && sig == SIGRTMAX)
            snprintf(rt_name[at], sizeof(rt_name[at]), "SIGRTMAX");
        else if (n_caught > at)
            snprintf(rt_name[at], sizeof(rt_name[at]), "SIGRTMIN+%d", sig - SIGRTMIN);
    }
    set_handlers(on_signal, NULL);
    catch_32();
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
    for (size_t i = 0; i < sizeof(named) / sizeof(named[0]); i++)
        if (named[i] == sig)
            return named_name[i];
    for (size_t i = 0; i < sizeof(if_default) / sizeof(if_default[0]); i++)
        if (if_default[i] == sig)
            return if_default_name[i];
    for (int i = 0; i < n_caught; i++)
        if (caught[i] == sig && rt_name[i][0])
            return rt_name[i];
#ifdef SP_SIGCANCEL
    if (sig == SP_SIGCANCEL && cancel_caught)
        return "signal 32";
#endif
    return "a signal";
}

void sp_signals_hold(struct sp_signals_saved *saved, void (*cleanup)(void))
{
    count = 0;
    held_cleanup = cleanup;
    holding = 1;
    set_handlers(on_signal_held, saved->old);
}

void sp_signals_release(const struct sp_signals_saved *saved)
{
    holding = 0;
    for (int i = 0; i < n_caught; i++)
        sigaction(caught[i], &saved->old[i], NULL);
}
