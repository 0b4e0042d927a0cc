/* SPDX-License-Identifier: BSD-3-Clause */
/* Comparing and copying a few bytes (a command name, a polled query line)
 * without a library call: the core is built freestanding, where memcpy()
 * and memcmp() are always calls, and a byte loop costs a compare and a
 * branch per byte. The compiler's builtin copy of a constant size is one
 * load or store (unaligned where the target allows it, bytewise where not). */
#ifndef WSG_SMALL_BYTES_H
#define WSG_SMALL_BYTES_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#if defined(__GNUC__)
#define WSG_COPY_FIXED(dst, src, n) __builtin_memcpy((dst), (src), (n))
#else
#include <string.h>
#define WSG_COPY_FIXED(dst, src, n) memcpy((dst), (src), (n))
#endif

static inline uint64_t wsg_load_u64(const unsigned char *p)
{
    uint64_t v;
    WSG_COPY_FIXED(&v, p, sizeof(v));
    return v;
}

static inline uint32_t wsg_load_u32(const unsigned char *p)
{
    uint32_t v;
    WSG_COPY_FIXED(&v, p, sizeof(v));
    return v;
}

/* Whether a[0..n) and b[0..n) hold the same bytes. From 4 bytes on, the
 * last word may overlap the one before: no byte loop for the tail. */
static inline bool wsg_small_equal(const void *a, const void *b, size_t n)
{
    const unsigned char *pa = a;
    const unsigned char *pb = b;
    if (n >= 8u) {
        for (size_t i = 0; i + 8u < n; i += 8u) {
            if (wsg_load_u64(pa + i) != wsg_load_u64(pb + i)) {
                return false;
            }
        }
        return wsg_load_u64(pa + n - 8u) == wsg_load_u64(pb + n - 8u);
    }
    if (n >= 4u) {
        return wsg_load_u32(pa) == wsg_load_u32(pb) &&
               wsg_load_u32(pa + n - 4u) == wsg_load_u32(pb + n - 4u);
    }
    for (size_t i = 0; i < n; i++) {
        if (pa[i] != pb[i]) {
            return false;
        }
    }
    return true;
}

/* dst[0..n) = src[0..n); the two do not overlap. Words as above. */
static inline void wsg_small_copy(void *dst, const void *src, size_t n)
{
    unsigned char *d = dst;
    const unsigned char *s = src;
    if (n >= 8u) {
        for (size_t i = 0; i + 8u < n; i += 8u) {
            WSG_COPY_FIXED(d + i, s + i, 8u);
        }
        WSG_COPY_FIXED(d + n - 8u, s + n - 8u, 8u);
        return;
    }
    if (n >= 4u) {
        WSG_COPY_FIXED(d, s, 4u);
        WSG_COPY_FIXED(d + n - 4u, s + n - 4u, 4u);
        return;
    }
    for (size_t i = 0; i < n; i++) {
        d[i] = s[i];
    }
}

#endif
