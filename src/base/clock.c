/* springpend: the one monotonic clock the timings, the progress line and
 * the glyph cache read (clock.h). */
#include <time.h>

#include "clock.h"

double sp_clock_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
