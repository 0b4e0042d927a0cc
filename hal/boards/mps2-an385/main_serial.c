/* SPDX-License-Identifier: BSD-3-Clause */
/* The serial image: GCL on UART0 (stage 1 of the board port). */
#include "app.h"
#include "board.h"
#include "hal_log.h"
#include "serial_port.h"

int main(void)
{
    board_clock_init();
    board_log_init();
    app_init();
    serial_port_init();
    hal_log(HAL_LOG_INFO, "wsgsim mps2-an385 serial image: GCL on UART0, ready");
    for (;;) {
        serial_port_poll();
        app_poll();
        board_sleep();
    }
}
