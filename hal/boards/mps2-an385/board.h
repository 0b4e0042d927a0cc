/* SPDX-License-Identifier: BSD-3-Clause */
/* ARM MPS2 with the AN385 FPGA image (Cortex-M3, 25 MHz), as QEMU's
 * mps2-an385 machine models it: the registers this port touches, the
 * interrupt numbers it uses, and the board services shared by both images. */
#ifndef BOARD_H
#define BOARD_H

#include <stdbool.h>
#include <stdint.h>

#define BOARD_SYSCLK_HZ 25000000u

/* Cortex-M3 system control space */
#define REG32(addr) (*(volatile uint32_t *)(uintptr_t)(addr))
#define SYST_CSR REG32(0xE000E010u)
#define SYST_RVR REG32(0xE000E014u)
#define SYST_CVR REG32(0xE000E018u)
#define NVIC_ISER0 REG32(0xE000E100u)
#define NVIC_ICPR0 REG32(0xE000E280u)
#define SCB_ICSR REG32(0xE000ED04u)
#define SCB_VTOR REG32(0xE000ED08u)
#define SCB_CCR REG32(0xE000ED14u)

#define SYST_CSR_ENABLE (1u << 0)
#define SYST_CSR_TICKINT (1u << 1)
#define SYST_CSR_CLKSOURCE (1u << 2) /* processor clock */
#define SCB_ICSR_PENDSTSET (1u << 26)
#define SCB_CCR_DIV_0_TRP (1u << 4)

/* Peripheral base addresses (AN385) */
#define UART0_BASE 0x40004000u /* GCL */
#define UART1_BASE 0x40005000u /* device log */
#define LAN9118_BASE 0x40200000u

/* External interrupt numbers (AN385) */
#define IRQ_UART0_RX 0
#define IRQ_UART1_RX 2
#define IRQ_ETHERNET 13

static inline void board_irq_enable(unsigned irq)
{
    NVIC_ICPR0 = 1u << irq;
    NVIC_ISER0 = 1u << irq;
}

static inline uint32_t board_irq_save(void)
{
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");
    return primask;
}

static inline void board_irq_restore(uint32_t primask)
{
    __asm__ volatile("msr primask, %0" ::"r"(primask) : "memory");
}

/* clock.c: SysTick at 1 kHz; hal_clock_now_us() interpolates within a tick. */
void board_clock_init(void);

/* Interrupt handlers call this so that board_sleep() does not sleep through
 * the event that they just signalled. */
void board_signal_event(void);

/* Sleeps until an interrupt: a signalled event, or at the latest the next
 * 1 ms SysTick. Returns at once if an event came since the last call. */
void board_sleep(void);

/* log.c: the device log goes to UART1, so UART0 carries nothing but GCL. */
void board_log_init(void);
void board_log_text(const char *text);
void board_log_uint(uint32_t value);
/* "stack: N of M bytes used" */
void board_log_stack_usage(void);

/* startup.c: logs the reason and stops (used for faults and lwIP asserts). */
void board_panic(const char *why) __attribute__((noreturn));

/* Bytes of the main stack never touched since reset (stack painting). */
uint32_t board_stack_unused(void);
uint32_t board_stack_size(void);

#endif
