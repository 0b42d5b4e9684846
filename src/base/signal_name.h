/* springpend (internal): the name of a caught signal, for messages and
 * reports. Defined in signals.c, beside the table of caught signals; kept
 * apart from signals.h so that code handed a cancel flag (which holds the
 * signal's number) can name it without reaching the signal handlers.
 * Shared with: every folder. */
#ifndef SPRINGPEND_SIGNAL_NAME_H
#define SPRINGPEND_SIGNAL_NAME_H

/* The caught signal's name ("SIGTERM"), or "a signal". */
const char *sp_signal_name(int sig);

#endif
