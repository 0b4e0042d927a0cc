/* SPDX-License-Identifier: BSD-3-Clause */
/* The serial image: GCL on UART0 (stage 1 of the board port). */
#include "app.h"
#include "board.h"
#include "hal_log.h"
#include "serial_port.h"

/* Its one connection is GCL from the start: nothing to detect. */
static const wsg_proto_driver_t *const drivers[] = {&wsg_gcl_driver};

int main(void)
{
    board_clock_init();
    board_log_init();
    app_init(drivers, sizeof(drivers) / sizeof(drivers[0]));
    serial_port_init();
    hal_log(HAL_LOG_INFO, "wsgsim mps2-an385 serial image: GCL on UART0, ready");
    for (;;) {
        serial_port_poll();
        app_poll();
        board_sleep();
    }
}
