/* SPDX-License-Identifier: BSD-3-Clause */
/* The device log (hal_log.h) on UART1. QEMU maps it to a file or the
 * terminal; the GCL conversation on UART0 never sees it. */
#include <string.h>

#include "board.h"
#include "cmsdk_uart.h"
#include "hal_log.h"

#define LOG_BAUD 115200u
#define LOG_TIMEOUT_US 2000u /* a stalled log must not stall the device */

void board_log_init(void)
{
    cmsdk_uart_init(CMSDK_UART(UART1_BASE), LOG_BAUD, false);
}

void board_log_text(const char *text)
{
    (void)cmsdk_uart_write(CMSDK_UART(UART1_BASE), text, strlen(text), LOG_TIMEOUT_US);
}

void board_log_uint(uint32_t value)
{
    char digits[11];
    unsigned n = sizeof(digits) - 1u;
    digits[n] = '\0';
    do {
        digits[--n] = (char)('0' + value % 10u);
        value /= 10u;
    } while (value != 0u);
    board_log_text(&digits[n]);
}

void board_log_stack_usage(void)
{
    board_log_text("I stack: ");
    board_log_uint(board_stack_size() - board_stack_unused());
    board_log_text(" of ");
    board_log_uint(board_stack_size());
    board_log_text(" bytes used\n");
}

void hal_log(hal_log_level_t level, const char *message)
{
    static const char *const prefixes[] = {
        [HAL_LOG_DEBUG] = "D ",
        [HAL_LOG_INFO] = "I ",
        [HAL_LOG_WARN] = "W ",
        [HAL_LOG_ERROR] = "E ",
    };
    board_log_text(level <= HAL_LOG_ERROR ? prefixes[level] : "? ");
    board_log_text(message);
    board_log_text("\n");
}
