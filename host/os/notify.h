/* SPDX-License-Identifier: BSD-3-Clause */
/* Telling a supervisor that wsgsim serves: READY=1 through sd_notify() when
 * systemd runs it (Type=notify; a no-op without $NOTIFY_SOCKET), and the
 * --ready-file for any other supervisor or script. */
#ifndef HOST_NOTIFY_H
#define HOST_NOTIFY_H

#include <stdbool.h>

/* The ports the ready file lists (-1: not served); the device's are device 0's. */
typedef struct {
    int tcp_port;
    int udp_port;
    int sim_port;
    int bin_tcp_port;
    int bin_udp_port;
    int http_port;
} notify_ports_t;

/* Call once every server listens, before saying so in the log: writes the
 * ready file's content (NULL: none) beside it, as shell-style lines: pid=N,
 * then tcp_port=N, udp_port=N, sim_port=N, bin_tcp_port=N, bin_udp_port=N
 * and http_port=N for each port served. False after a message on stderr
 * when it cannot be written. */
bool notify_prepare(const char *ready_file, const notify_ports_t *ports);
/* Then: renames the prepared file into place (a reader never sees half of
 * it) and notifies systemd, with status as its STATUS=. */
bool notify_ready(const char *ready_file, const char *status);
/* At shutdown: STOPPING=1 to systemd, and the ready file is removed, so a
 * stale one never claims a server that is gone. */
void notify_stopping(const char *ready_file);

#endif
