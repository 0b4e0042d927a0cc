/* SPDX-License-Identifier: BSD-3-Clause */
/* Telling a supervisor that wsgsim serves: READY=1 through sd_notify() when
 * systemd runs it (Type=notify; a no-op without $NOTIFY_SOCKET), and the
 * --ready-file for any other supervisor or script. */
#ifndef HOST_NOTIFY_H
#define HOST_NOTIFY_H

#include <stdbool.h>

/* Call once every server listens, before saying so in the log: writes the
 * ready file's content (NULL: none) beside it, as shell-style lines: pid=N,
 * tcp_port=N, udp_port=N, sim_port=N, bin_tcp_port=N, bin_udp_port=N and
 * http_port=N
 * (each port only when served). False
 * after a message on stderr when it cannot be written. */
bool notify_prepare(const char *ready_file);
/* Before notify_prepare(): device 0's GCL ports, written as tcp_port=N and
 * udp_port=N (-1: not served). */
void notify_set_ports(int tcp_port, int udp_port);
/* Before notify_prepare(): the binary protocol's ports, written as
 * bin_tcp_port=N and bin_udp_port=N (-1: not served). */
void notify_set_binary_ports(int tcp_port, int udp_port);
/* Before notify_prepare(): the web interface's port, written as http_port=N
 * (-1: not served). */
void notify_set_http_port(int port);
/* Before notify_prepare(): the control channel's port, written as
 * sim_port=N (-1: none). */
void notify_set_sim_port(int port);
/* Then: renames the prepared file into place (a reader never sees half of
 * it) and notifies systemd, with status as its STATUS=. */
bool notify_ready(const char *ready_file, const char *status);
/* At shutdown: STOPPING=1 to systemd, and the ready file is removed, so a
 * stale one never claims a server that is gone. */
void notify_stopping(const char *ready_file);

#endif
