/* SPDX-License-Identifier: BSD-3-Clause */
/* Published and computed frames of the spec (§2.2, §13, S10's 0x40 frame). */
#ifndef BIN_VECTORS_H
#define BIN_VECTORS_H

#include <stdbool.h>
#include <stddef.h>

typedef struct {
    const char *what;
    bool request;
    const char *hex;
} bin_vector_t;

extern const bin_vector_t bin_vectors[];
extern const size_t bin_vector_count;

#endif
