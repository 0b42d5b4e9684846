/* springpend tests: the growing-array helper (base/array.h). Growth keeps
 * the elements and doubles the capacity (amortised O(1) appends), `first`
 * is the least capacity, a need within the capacity changes nothing, a
 * need of zero allocates nothing, and a need beyond what the capacity's
 * integer type or capacity * size can hold is refused with SP_E_NOMEM,
 * leaving the array and its capacity as they were.
 * usage: test_array */
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "springpend/common.h"
#include "base/array.h"
#include "tap.h"

struct empty {
};

int main(void)
{
    /* zero: nothing to hold, nothing allocated */
    int *v = NULL, cap = 0, n = 0;
    sp_tap_ok(SP_ARRAY_RESERVE(v, cap, 0, 0) == 0 && !v && cap == 0,
              "a need of 0 allocates nothing (cap %d)", cap);
    /* growth: appends keep every element, capacity first, then doubling */
    int grew = 0, kept = 1, doubled = 1, last = 0;
    for (int i = 0; i < 1000; i++) {
        const int before = cap;
        if (SP_ARRAY_RESERVE(v, cap, n + 1, 16))
            break;
        if (cap != before) {
            grew++;
            doubled &= before ? cap == 2 * before : cap == 16;
        }
        v[n++] = 3 * i;
    }
    for (int i = 0; i < n; i++)
        kept &= v[i] == 3 * i;
    last = cap;
    sp_tap_ok(n == 1000 && kept, "1000 appends kept (%d elements)", n);
    sp_tap_ok(doubled && grew == 7 && last == 1024,
              "capacity 16, then doubled: %d growths to %d (expected 7 to 1024)", grew, last);
    int r = SP_ARRAY_RESERVE(v, cap, 500, 16);
    sp_tap_ok(!r && cap == 1024, "a need within the capacity changes nothing (cap %d)", cap);
    r = SP_ARRAY_RESERVE(v, cap, 5000, 16);
    sp_tap_ok(!r && cap == 5000 && v[999] == 2997,
              "a need past twice the capacity is taken as it is (cap %d)", cap);
    /* overflow: the capacity's type */
    int *before = v;
    sp_tap_ok(SP_ARRAY_RESERVE(v, cap, (size_t)INT_MAX + 1, 0) == SP_E_NOMEM && v == before &&
                  cap == 5000 && v[999] == 2997,
              "an int capacity past INT_MAX is refused, the array unchanged");
    free(v);
    /* overflow: capacity * size past SIZE_MAX (a size_t capacity) */
    double *d = NULL;
    size_t dcap = 0;
    sp_tap_ok(SP_ARRAY_RESERVE(d, dcap, SIZE_MAX / sizeof(double) + 1, 0) == SP_E_NOMEM && !d &&
                  dcap == 0,
              "a count whose bytes wrap size_t is refused");
    /* near the top, doubling stops at the type's limit */
    unsigned char *b = NULL;
    unsigned char bcap = 200;
    r = SP_ARRAY_RESERVE(b, bcap, 201, 0);
    sp_tap_ok(!r && bcap == 255 && b, "doubling stops at the capacity type's maximum (%d)", bcap);
    sp_tap_ok(SP_ARRAY_RESERVE(b, bcap, 256, 0) == SP_E_NOMEM && bcap == 255,
              "and a need past it is refused");
    free(b);
    /* the function: a limit of the caller's (a byte buffer read up to one) */
    char *t = NULL;
    size_t tcap = 0;
    int r1 = sp_array_reserve((void **)&t, 1, &tcap, 2, 100, 150);
    int r2 = sp_array_reserve((void **)&t, 1, &tcap, 101, 100, 150);
    int r3 = sp_array_reserve((void **)&t, 1, &tcap, 151, 100, 150);
    sp_tap_ok(!r1 && !r2 && r3 == SP_E_NOMEM && tcap == 150,
              "with max 150: first 100, then 150 (not 200), then refused (cap %zu)", tcap);
    free(t);
    /* elements of no bytes */
    struct empty *e = NULL;
    long ecap = 0;
    sp_tap_ok(SP_ARRAY_RESERVE(e, ecap, 10, 0) == 0 && ecap == 10 && !e,
              "elements of size 0 take no memory");
    return sp_tap_done();
}
