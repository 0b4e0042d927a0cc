/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL over UDP with lwIP's raw API: one session per peer (address, port).
 * Replies go back to the peer as one datagram per line. */
#ifndef GCL_UDP_H
#define GCL_UDP_H

#include <stdbool.h>
#include <stdint.h>

#define GCL_UDP_MAX_PEERS 4

bool gcl_udp_init(uint16_t port);

/* Forgets peers that went quiet (and stream nothing). */
void gcl_udp_poll(void);

#endif
