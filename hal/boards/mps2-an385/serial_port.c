/* SPDX-License-Identifier: BSD-3-Clause */
#include "serial_port.h"

#include "app.h"
#include "board.h"
#include "cmsdk_uart.h"
#include "hal_log.h"

#define GCL_BAUD 115200u
/* QEMU holds the UART while the host does not read its socket; a real line
 * never stalls. Past this wait per byte the rest of the line is lost. */
#define TX_STALL_US 200000u

static cmsdk_uart_rx_t rx;
static wsg_conn_t conn;

void UART0_RX_Handler(void);
void UART0_RX_Handler(void)
{
    cmsdk_uart_rx_isr(&rx);
    board_signal_event();
}

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    (void)ctx;
    cmsdk_uart_regs_t *uart = CMSDK_UART(UART0_BASE);
    /* AUTOSEND values may be dropped under back-pressure, replies may not */
    if (kind == WSG_MSG_UPDATE && !cmsdk_uart_tx_ready(uart)) {
        return;
    }
    if (!cmsdk_uart_write(uart, line, len, TX_STALL_US)) {
        hal_log(HAL_LOG_WARN, "serial: transmit stalled, line lost");
    }
}

static const wsg_conn_io_t serial_io = {.write = write_line};

static void open_session(void)
{
    /* the first byte chooses the protocol: 0xAA binary, else GCL */
    wsg_conn_open(&conn, app_device(), NULL, WSG_TRANSPORT_SERIAL, &serial_io, NULL);
}

void serial_port_init(void)
{
    cmsdk_uart_regs_t *uart = CMSDK_UART(UART0_BASE);
    cmsdk_uart_rx_init(&rx, uart);
    cmsdk_uart_init(uart, GCL_BAUD, true);
    board_irq_enable(IRQ_UART0_RX);
    open_session();
}

void serial_port_poll(void)
{
    uint8_t bytes[64];
    size_t n;
    while ((n = cmsdk_uart_rx_read(&rx, bytes, sizeof(bytes))) > 0) {
        app_feed(&conn, bytes, n, false);
        if (wsg_conn_wants_close(&conn)) {
            wsg_conn_close(&conn, WSG_CLOSE_ANNOUNCED);
            hal_log(HAL_LOG_INFO, "serial: BYE, new session");
            board_log_stack_usage();
            open_session();
        }
    }
}
