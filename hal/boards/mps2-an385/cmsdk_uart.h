/* SPDX-License-Identifier: BSD-3-Clause */
/* CMSDK APB UART (ARM DDI0479): 8N1, one-byte transmit and receive buffers. */
#ifndef CMSDK_UART_H
#define CMSDK_UART_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef struct {
    volatile uint32_t data;
    volatile uint32_t state;
    volatile uint32_t ctrl;
    volatile uint32_t intstatus; /* read: status, write 1: clear */
    volatile uint32_t bauddiv;
} cmsdk_uart_regs_t;

#define CMSDK_UART(base) ((cmsdk_uart_regs_t *)(uintptr_t)(base))

/* Enables transmit and receive at the given rate; with rx_interrupt the
 * receive interrupt is raised for every byte that arrives. */
void cmsdk_uart_init(cmsdk_uart_regs_t *uart, uint32_t baud, bool rx_interrupt);

/* Sends len bytes, waiting while the transmit buffer is full, but at most
 * timeout_us per byte: a stalled line loses the rest of the text instead of
 * stopping the device. Returns false if it gave up. */
bool cmsdk_uart_write(cmsdk_uart_regs_t *uart, const char *text, size_t len, uint32_t timeout_us);

/* True if a byte could be written now without waiting. */
bool cmsdk_uart_tx_ready(const cmsdk_uart_regs_t *uart);

/* Interrupt-driven receive into a ring. When the ring is full the receive
 * interrupt is paused and the byte stays in the UART: the sender is held up
 * (QEMU's character backend waits) instead of bytes being lost. */
typedef struct {
    cmsdk_uart_regs_t *uart;
    uint8_t data[256];      /* a power of two: head and tail wrap freely */
    volatile uint32_t head; /* written by the interrupt */
    volatile uint32_t tail; /* written by the main loop */
    volatile bool paused;
} cmsdk_uart_rx_t;

void cmsdk_uart_rx_init(cmsdk_uart_rx_t *rx, cmsdk_uart_regs_t *uart);

/* Called from the UART's receive interrupt handler. */
void cmsdk_uart_rx_isr(cmsdk_uart_rx_t *rx);

/* Main-loop side: takes up to cap received bytes. */
size_t cmsdk_uart_rx_read(cmsdk_uart_rx_t *rx, uint8_t *out, size_t cap);

#endif
