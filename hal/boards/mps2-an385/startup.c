/* SPDX-License-Identifier: BSD-3-Clause */
/* Reset and exception entry: the vector table, C runtime set-up (.data copy,
 * .bss clear, stack painting) and the fault handlers. */
#include <stdint.h>

#include "board.h"

#define STACK_PAINT 0xA5A5A5A5u
#define EXTERNAL_IRQS 32

/* Provided by the linker script. */
extern uint32_t __data_load[], __data_start[], __data_end[];
extern uint32_t __bss_start[], __bss_end[];
extern uint32_t __stack_bottom[], __stack_top[];

int main(void);
void Reset_Handler(void);
void Default_Handler(void);
void HardFault_Handler(void);

/* Handlers a board image may define; unused ones end in Default_Handler. */
#define WEAK_DEFAULT __attribute__((weak, alias("Default_Handler")))
void NMI_Handler(void) WEAK_DEFAULT;
void MemManage_Handler(void) WEAK_DEFAULT;
void BusFault_Handler(void) WEAK_DEFAULT;
void UsageFault_Handler(void) WEAK_DEFAULT;
void SVC_Handler(void) WEAK_DEFAULT;
void PendSV_Handler(void) WEAK_DEFAULT;
void SysTick_Handler(void) WEAK_DEFAULT;
void UART0_RX_Handler(void) WEAK_DEFAULT;
void UART1_RX_Handler(void) WEAK_DEFAULT;
void Ethernet_Handler(void) WEAK_DEFAULT;

typedef void (*vector_t)(void);

typedef struct {
    uint32_t *initial_sp;
    vector_t exceptions[15];
    vector_t irqs[EXTERNAL_IRQS];
} vector_table_t;

/* Only the interrupts the images enable have entries; any other one would
 * vector to 0 and end in the HardFault handler. */
__attribute__((section(".isr_vector"), used)) const vector_table_t vector_table = {
    .initial_sp = __stack_top,
    .exceptions =
        {
            Reset_Handler,
            NMI_Handler,
            HardFault_Handler,
            MemManage_Handler,
            BusFault_Handler,
            UsageFault_Handler,
            [10] = SVC_Handler,
            [13] = PendSV_Handler,
            [14] = SysTick_Handler,
        },
    .irqs =
        {
            [IRQ_UART0_RX] = UART0_RX_Handler,
            [IRQ_UART1_RX] = UART1_RX_Handler,
            [IRQ_ETHERNET] = Ethernet_Handler,
        },
};

/* Fills the unused part of the stack so board_stack_unused() can measure the
 * high-water mark. Runs on the stack it paints: stops short of its own frame. */
static void paint_stack(void)
{
    uint32_t *here = (uint32_t *)__builtin_frame_address(0) - 64;
    for (uint32_t *p = __stack_bottom; p < here; p++) {
        *p = STACK_PAINT;
    }
}

void Reset_Handler(void)
{
    for (uint32_t *src = __data_load, *dst = __data_start; dst < __data_end;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = __bss_start; dst < __bss_end;) {
        *dst++ = 0u;
    }
    paint_stack();
    SCB_VTOR = (uint32_t)(uintptr_t)&vector_table;
    SCB_CCR |= SCB_CCR_DIV_0_TRP;
    (void)main();
    board_panic("main returned");
}

uint32_t board_stack_unused(void)
{
    const uint32_t *p = __stack_bottom;
    while (p < __stack_top && *p == STACK_PAINT) {
        p++;
    }
    return (uint32_t)((uintptr_t)p - (uintptr_t)__stack_bottom);
}

uint32_t board_stack_size(void)
{
    return (uint32_t)((uintptr_t)__stack_top - (uintptr_t)__stack_bottom);
}

void board_panic(const char *why)
{
    (void)board_irq_save();
    board_log_text("PANIC: ");
    board_log_text(why);
    board_log_text("\n");
    for (;;) {
        __asm__ volatile("wfi");
    }
}

void HardFault_Handler(void)
{
    board_panic("hard fault");
}

void Default_Handler(void)
{
    board_panic("unexpected exception");
}
