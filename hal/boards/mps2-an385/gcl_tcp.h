/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL over TCP with lwIP's raw API: one session per connection. */
#ifndef GCL_TCP_H
#define GCL_TCP_H

#include <stdbool.h>
#include <stdint.h>

#define GCL_TCP_MAX_CONNECTIONS 4

/* Listens on the port; false if lwIP could not. */
bool gcl_tcp_init(uint16_t port);

/* Main-loop work that must not run inside lwIP callbacks: sending what is
 * queued, closing after BYE, aborting a connection that cannot keep up. */
void gcl_tcp_poll(void);

#endif
