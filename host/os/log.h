/* SPDX-License-Identifier: BSD-3-Clause */
/* Host logging: hal_log() and the server's own messages go to stderr, or to
 * a file (--log-file) that host_log_reopen() reopens for log rotation.
 *
 * Logging never blocks the event loop: a line that stderr cannot take at
 * once (a pipe nobody reads, a stalled terminal) is dropped and counted, and
 * the count is logged once stderr takes lines again. Messages remote peers
 * can trigger at will go through host_log_peer(), a script's output through
 * host_log_script(): both are rate-limited. A control byte in any message
 * (a CR, an ESC) is logged as \xHH.
 *
 * The log is the process's, like its stderr: the firmware logs through
 * hal_log(), a link-time function without a context, so these functions
 * take no instance either. */
#ifndef HOST_LOG_H
#define HOST_LOG_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "hal_log.h"

/* Prepares the non-blocking writer for whatever stderr is (pipe, terminal,
 * socket or file); call once at start, before logging. */
void host_log_init(void);
/* Messages below level are not logged (--log-level, --quiet; default info). */
void host_log_set_level(hal_log_level_t level);
/* Parses error, warn, info or debug; false for anything else. */
bool host_log_parse_level(const char *name, hal_log_level_t *level);
/* Starts every line with the wall-clock time, ISO 8601 in UTC (--log-timestamps). */
void host_log_set_timestamps(bool on);
/* Logs to the file at path (appending) instead of stderr; false after a
 * message on stderr when it cannot be opened. */
bool host_log_open_file(const char *path);
/* Opens the --log-file path again (after logrotate moved it); the old file
 * stays in use if the new one cannot be opened. No-op when logging to stderr. */
void host_log_reopen(void);
void host_logf(hal_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A message a remote peer caused (connections, refusals, peers): at most a
 * burst of 100, then 20 per second; the rest is counted, and the count
 * logged before the next line let through. */
void host_log_peer(hal_log_level_t level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* A line a user script wrote (print, printf), logged as "who: text": any
 * byte outside printable ASCII as \xHH (a backslash as \\), and
 * rate-limited as host_log_peer() is, in a bucket of its own that every
 * script shares ("N lines from scripts suppressed"). */
void host_log_script(hal_log_level_t level, const char *who, const char *text, size_t len);
/* The last lines logged (at most 100, each cut to 255 bytes), numbered
 * from 0 at start: up to cap pointers to those numbered since and later,
 * oldest first, valid until the next line is logged; *next is the number
 * the next line will get. */
size_t host_log_recent(uint64_t since, const char **lines, size_t cap, uint64_t *next);
/* One whole line as it is (the trace), through the same writer. */
void host_log_line(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#endif
