/* SPDX-License-Identifier: BSD-3-Clause */
/* Device log (the real WSG keeps a log file; a board may print to a UART). */
#ifndef HAL_LOG_H
#define HAL_LOG_H

typedef enum { HAL_LOG_DEBUG, HAL_LOG_INFO, HAL_LOG_WARN, HAL_LOG_ERROR } hal_log_level_t;

/* message is a complete, NUL-terminated line without a trailing newline. */
void hal_log(hal_log_level_t level, const char *message);

#endif
