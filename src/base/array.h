/* springpend (internal): growing arrays, one way everywhere (array.c).
 * Shared with: every folder. */
#ifndef SP_ARRAY_H
#define SP_ARRAY_H

#include <stddef.h>

/* Growing arrays, one way everywhere (libplacebo's PL_ARRAY_APPEND is the
 * model). An array is a pointer, a count of elements in use (the caller's)
 * and a capacity; SP_ARRAY_RESERVE makes room for `need` elements in all:
 *
 *     if (SP_ARRAY_RESERVE(v->items, v->cap, v->n + 1, 64))
 *         return SP_E_NOMEM;
 *     v->items[v->n++] = x;
 *
 * The capacity becomes the largest of need, twice the old capacity and
 * `first` (so appends cost amortised O(1)); elements already there are
 * kept. 0, or SP_E_NOMEM with the array and its capacity unchanged: a
 * need beyond what the capacity's integer type (int, long, size_t) or
 * memory holds. Nothing is logged: the caller words the failure. */
#define SP_ARRAY_RESERVE(arr, cap, need, first)                                              \
    __extension__({                                                                          \
        __typeof__(cap) *sp_cap_ = &(cap);                                                   \
        size_t sp_c_ = (size_t)*sp_cap_;                                                     \
        const size_t sp_max_ = (__typeof__(cap))-1 < (__typeof__(cap))1                    \
            ? (((size_t)1 << (sizeof(*sp_cap_) * 8 - 2)) - 1) * 2 + 1                         \
            : (size_t)(__typeof__(cap))-1;                                                   \
        const int sp_r_ = sp_array_reserve((void **)&(arr), sizeof(*(arr)), &sp_c_,          \
                                           (size_t)(need), (size_t)(first), sp_max_);        \
        if (!sp_r_)                                                                          \
            *sp_cap_ = (__typeof__(cap))sp_c_;                                               \
        sp_r_;                                                                               \
    })

/* SP_ARRAY_RESERVE's work on *items, an array of `size`-byte elements with
 * room for *cap: 0 (when *cap >= need, nothing changes), or SP_E_NOMEM. A
 * capacity is never above max, nor above SIZE_MAX / size (so that
 * capacity * size cannot wrap); elements of size 0 take no memory. The one
 * realloc of src/ (test array-growth refuses any other): a byte buffer read
 * up to a limit calls this directly, with size 1 and max the limit. */
int sp_array_reserve(void **items, size_t size, size_t *cap, size_t need, size_t first, size_t max);

#endif
