/* SPDX-License-Identifier: BSD-3-Clause */
/* The little lwIP needs from the system in NO_SYS mode: a millisecond clock
 * and random numbers (initial sequence numbers and local ports). */
#include "board.h"
#include "hal_clock.h"
#include "lwip/sys.h"

u32_t sys_now(void)
{
    return (u32_t)(hal_clock_now_us() / 1000u);
}

/* xorshift32, seeded from the clock: unpredictable enough for port numbers
 * on a board that has no entropy source. */
uint32_t board_random(void)
{
    static uint32_t state;
    if (state == 0u) {
        state = (uint32_t)hal_clock_now_us() | 1u;
    }
    state ^= state << 13;
    state ^= state >> 17;
    state ^= state << 5;
    return state;
}
