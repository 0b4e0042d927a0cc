/* SPDX-License-Identifier: BSD-3-Clause */
/* Who may use the simulation routes: loopback peers, as on the control
 * channel, unless --sim-bind names a non-loopback address. */
#ifndef HOST_WEB_PEER_H
#define HOST_WEB_PEER_H

#include <stdbool.h>
#include <sys/socket.h>

/* 127.0.0.0/8, ::1 and ::ffff:127.0.0.0/104 (an IPv4 loopback peer of a
 * dual-stack socket); false for anything else or NULL. */
bool web_peer_is_loopback(const struct sockaddr *addr);

#endif
