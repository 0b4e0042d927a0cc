/* SPDX-License-Identifier: BSD-3-Clause */
/* Frames written as the spec writes them ("AA AA AA 20 01 00 01 AE 93"). */
#ifndef BIN_HEXBYTES_H
#define BIN_HEXBYTES_H

#include <stddef.h>
#include <stdint.h>

/* Parses space-separated hex byte pairs into out; fails the test on bad text
 * or when more than cap bytes. Returns the byte count. */
size_t hex_bytes(const char *text, uint8_t *out, size_t cap);

#endif
