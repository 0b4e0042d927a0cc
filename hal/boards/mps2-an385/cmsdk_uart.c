/* SPDX-License-Identifier: BSD-3-Clause */
#include "cmsdk_uart.h"

#include "board.h"
#include "hal_clock.h"

#define STATE_TXFULL (1u << 0)
#define STATE_RXFULL (1u << 1)
#define CTRL_TX_EN (1u << 0)
#define CTRL_RX_EN (1u << 1)
#define CTRL_RX_INTEN (1u << 3)
#define INT_RX (1u << 1)
#define RING_MASK (sizeof(((cmsdk_uart_rx_t *)0)->data) - 1u)

void cmsdk_uart_init(cmsdk_uart_regs_t *uart, uint32_t baud, bool rx_interrupt)
{
    uart->ctrl = 0u;
    uart->bauddiv = BOARD_SYSCLK_HZ / baud; /* at least 16 by the TRM */
    uart->intstatus = 0xFu;
    uart->ctrl = CTRL_TX_EN | CTRL_RX_EN | (rx_interrupt ? CTRL_RX_INTEN : 0u);
}

bool cmsdk_uart_tx_ready(const cmsdk_uart_regs_t *uart)
{
    return (uart->ctrl & CTRL_TX_EN) != 0u && (uart->state & STATE_TXFULL) == 0u;
}

static bool wait_tx_ready(const cmsdk_uart_regs_t *uart, uint32_t timeout_us)
{
    if ((uart->ctrl & CTRL_TX_EN) == 0u) {
        return false; /* not initialised: the byte would never leave */
    }
    if ((uart->state & STATE_TXFULL) == 0u) {
        return true;
    }
    uint64_t start = hal_clock_now_us();
    while ((uart->state & STATE_TXFULL) != 0u) {
        if (hal_clock_now_us() - start > timeout_us) {
            return false;
        }
    }
    return true;
}

bool cmsdk_uart_write(cmsdk_uart_regs_t *uart, const char *text, size_t len, uint32_t timeout_us)
{
    for (size_t i = 0; i < len; i++) {
        if (!wait_tx_ready(uart, timeout_us)) {
            return false;
        }
        uart->data = (uint8_t)text[i];
    }
    return true;
}

void cmsdk_uart_rx_init(cmsdk_uart_rx_t *rx, cmsdk_uart_regs_t *uart)
{
    rx->uart = uart;
    rx->head = 0u;
    rx->tail = 0u;
    rx->paused = false;
}

void cmsdk_uart_rx_isr(cmsdk_uart_rx_t *rx)
{
    cmsdk_uart_regs_t *uart = rx->uart;
    /* Acknowledge first: a byte arriving while we drain raises it again. */
    uart->intstatus = INT_RX;
    while ((uart->state & STATE_RXFULL) != 0u) {
        uint32_t head = rx->head;
        if (head - rx->tail > RING_MASK) {
            uart->ctrl &= ~CTRL_RX_INTEN; /* full: leave the byte where it is */
            rx->paused = true;
            return;
        }
        rx->data[head & RING_MASK] = (uint8_t)uart->data;
        rx->head = head + 1u;
    }
}

static void resume(cmsdk_uart_rx_t *rx)
{
    uint32_t primask = board_irq_save();
    rx->paused = false;
    rx->uart->ctrl |= CTRL_RX_INTEN;
    cmsdk_uart_rx_isr(rx); /* the held byte raises no new interrupt */
    board_irq_restore(primask);
}

size_t cmsdk_uart_rx_read(cmsdk_uart_rx_t *rx, uint8_t *out, size_t cap)
{
    size_t n = 0;
    uint32_t tail = rx->tail;
    uint32_t head = rx->head;
    while (n < cap && tail != head) {
        out[n++] = rx->data[tail & RING_MASK];
        tail++;
    }
    rx->tail = tail;
    if (rx->paused && n > 0) {
        resume(rx);
    }
    return n;
}
