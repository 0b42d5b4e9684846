/* springpend (internal): the one clock of timings (clock.c).
 * Shared with: every folder. */
#ifndef SP_CLOCK_H
#define SP_CLOCK_H

/* The monotonic clock (CLOCK_MONOTONIC), s since an arbitrary start: for
 * timings, progress and cache ages; never a date. */
double sp_clock_s(void);

#endif
