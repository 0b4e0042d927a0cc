/* SPDX-License-Identifier: BSD-3-Clause */
/* Monotonic clock: the only way time enters the device core. */
#ifndef HAL_CLOCK_H
#define HAL_CLOCK_H

#include <stdint.h>

/* Microseconds since an arbitrary epoch; never goes backwards. On the host
 * this is simulated time (it may be paused, scaled or stepped). */
uint64_t hal_clock_now_us(void);

#endif
