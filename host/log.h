/* Host logging: hal_log() and the server's own messages go to stderr.
 *
 * Logging never blocks the event loop: a line that stderr cannot take at
 * once (a pipe nobody reads, a stalled terminal) is dropped and counted, and
 * the count is logged once stderr takes lines again. Messages remote peers
 * can trigger at will go through host_log_peer(), which is rate-limited. */
#ifndef HOST_LOG_H
#define HOST_LOG_H

#include "hal_log.h"

/* Prepares the non-blocking writer for whatever stderr is (pipe, terminal,
 * socket or file); call once at start, before logging. */
void host_log_init(void);
void host_log_set_verbose(int verbose);
void host_logf(hal_log_level_t level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A message a remote peer caused (connections, refusals, peers): at most a
 * burst of LOG_PEER_BURST, then LOG_PEER_RATE per second; the rest is counted. */
void host_log_peer(hal_log_level_t level, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* One whole line as it is (the trace), through the same writer. */
void host_log_line(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Lines dropped so far because stderr could not take them. */
unsigned long host_log_dropped(void);

#endif
