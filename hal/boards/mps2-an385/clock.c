/* SPDX-License-Identifier: BSD-3-Clause */
/* The device clock (hal_clock.h) from SysTick: a 1 kHz interrupt counts
 * milliseconds and the counter value interpolates within the tick. */
#include "board.h"
#include "hal_clock.h"

#define TICK_HZ 1000u
#define CYCLES_PER_TICK (BOARD_SYSCLK_HZ / TICK_HZ)
#define CYCLES_PER_US (BOARD_SYSCLK_HZ / 1000000u)

static volatile uint64_t ticks_ms;
static volatile bool event_pending;
static uint64_t last_us;

void board_clock_init(void)
{
    SYST_CSR = 0u;
    SYST_RVR = CYCLES_PER_TICK - 1u;
    SYST_CVR = 0u;
    SYST_CSR = SYST_CSR_CLKSOURCE | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
}

void SysTick_Handler(void);
void SysTick_Handler(void)
{
    ticks_ms = ticks_ms + 1u;
}

uint64_t hal_clock_now_us(void)
{
    uint32_t primask = board_irq_save();
    uint64_t ms = ticks_ms;
    uint32_t counter = SYST_CVR;
    /* The counter wrapped but its interrupt has not run yet (it cannot while
     * interrupts are off): count that tick and re-read the counter, which
     * now belongs to it. */
    if ((SCB_ICSR & SCB_ICSR_PENDSTSET) != 0u) {
        ms++;
        counter = SYST_CVR;
    }
    uint64_t now = ms * 1000u + (CYCLES_PER_TICK - 1u - counter) / CYCLES_PER_US;
    /* hal_clock.h promises a clock that never goes backwards */
    if (now < last_us) {
        now = last_us;
    }
    last_us = now;
    board_irq_restore(primask);
    return now;
}

void board_signal_event(void)
{
    event_pending = true;
}

void board_sleep(void)
{
    /* With interrupts masked, WFI still wakes on a pending interrupt, so an
     * event signalled between the check and the WFI cannot be slept through. */
    uint32_t primask = board_irq_save();
    if (!event_pending) {
        __asm__ volatile("dsb\n\twfi" ::: "memory");
    }
    event_pending = false;
    board_irq_restore(primask);
}
