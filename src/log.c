/* springpend: logging, and the interrupt flag of commands that do not render. */
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "springpend/common.h"

void sp_log_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("springpend: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}

static volatile sig_atomic_t interrupted;

static void on_signal(int sig)
{
    interrupted = sig;
}

void sp_interrupt_install(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sigaction(SIGHUP, &sa, NULL);
}

void sp_interrupt_note(int sig)
{
    interrupted = sig;
}

int sp_interrupted(void)
{
    return interrupted;
}
