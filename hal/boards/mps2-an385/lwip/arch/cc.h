/* SPDX-License-Identifier: BSD-3-Clause */
/* lwIP architecture port for the mps2-an385 board: Cortex-M3, little
 * endian, GCC, no OS. Diagnostics are compiled out; a failed assertion logs
 * and stops the board. */
#ifndef LWIP_ARCH_CC_H
#define LWIP_ARCH_CC_H

#include <stdint.h>

#ifndef BYTE_ORDER
#define BYTE_ORDER LITTLE_ENDIAN
#endif

/* No POSIX headers on a bare board. */
#define LWIP_NO_UNISTD_H 1
/* ctype.h works, but lwIP's own macros avoid newlib's locale tables. */
#define LWIP_NO_CTYPE_H 1

#define LWIP_PLATFORM_DIAG(x)                                                                      \
    do {                                                                                           \
    } while (0)

void board_panic(const char *why) __attribute__((noreturn));
#define LWIP_PLATFORM_ASSERT(x) board_panic("lwIP assertion: " x)

uint32_t board_random(void);
#define LWIP_RAND() board_random()

#endif
