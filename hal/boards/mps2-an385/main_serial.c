/* SPDX-License-Identifier: BSD-3-Clause */
/* The serial image: GCL and the binary protocol on UART0. */
#include "app.h"
#include "board.h"
#include "hal_log.h"
#include "serial_port.h"
#include "wsg/wsg_bin.h"

/* The UART's first byte chooses, as a TCP connection's does. */
static const wsg_proto_driver_t *const drivers[] = {&wsg_bin_driver, &wsg_gcl_driver};

int main(void)
{
    board_clock_init();
    board_log_init();
    app_init(drivers, sizeof(drivers) / sizeof(drivers[0]));
    serial_port_init();
    hal_log(HAL_LOG_INFO, "wsgsim mps2-an385 serial image: GCL and binary on UART0, ready");
    for (;;) {
        serial_port_poll();
        app_poll();
        board_sleep();
    }
}
