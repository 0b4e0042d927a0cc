/* SPDX-License-Identifier: BSD-3-Clause */
#include <check.h>
#include <stdlib.h>

#include "hexbytes.h"

size_t hex_bytes(const char *text, uint8_t *out, size_t cap)
{
    size_t n = 0;
    const char *p = text;
    while (*p != '\0') {
        if (*p == ' ') {
            p++;
            continue;
        }
        char *end;
        unsigned long value = strtoul(p, &end, 16);
        ck_assert_msg(end == p + 2 && value <= 0xFF, "bad hex at \"%s\"", p);
        ck_assert_msg(n < cap, "more than %zu bytes in \"%s\"", cap, text);
        out[n++] = (uint8_t)value;
        p = end;
    }
    return n;
}
