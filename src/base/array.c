/* springpend: growing arrays (array.h). */
#include <stdint.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "array.h"

int sp_array_reserve(void **items, size_t size, size_t *cap, size_t need, size_t first, size_t max)
{
    if (need <= *cap)
        return 0;
    if (!size) { /* elements of no bytes take no memory (GNU C's empty structs) */
        if (need > max)
            return SP_E_NOMEM;
        *cap = need;
        return 0;
    }
    if (max > SIZE_MAX / size)
        max = SIZE_MAX / size;
    if (need > max)
        return SP_E_NOMEM;
    size_t want = *cap <= max / 2 ? 2 * *cap : max;
    if (want < first)
        want = first < max ? first : max;
    if (want < need)
        want = need;
    void *p = realloc(*items, want * size);
    if (!p)
        return SP_E_NOMEM;
    *items = p;
    *cap = want;
    return 0;
}
