/* SPDX-License-Identifier: BSD-3-Clause */
/* A protocol over UDP with lwIP's raw API: one session per peer (address,
 * port), replies as one datagram per message. GCL on port 1000 replies to
 * the sender; the binary protocol on port 1500 replies to the sender's IP
 * at port 1501 (docs/binary-protocol.md). The peer rules are the core's
 * (wsg/wsg_peers.h) on a static pool per server; this file moves bytes. */
#ifndef LWIP_UDP_H
#define LWIP_UDP_H

#include <stdbool.h>
#include <stdint.h>

#include "wsg/wsg_peers.h"

#define LWIP_UDP_GCL_PEERS 4
#define LWIP_UDP_BINARY_PEERS 2
/* A peer silent this long is forgotten (unless running a motion), as on
 * the host by default (--udp-peer-timeout). */
#define LWIP_UDP_PEER_TIMEOUT_S 60

struct udp_pcb;

typedef struct {
    struct udp_pcb *pcb;
    const wsg_proto_driver_t *driver;
    uint16_t reply_port; /* 0: the sender's own port */
    wsg_peer_table_t peers;
} lwip_udp_server_t;

/* Serves driver on port with a pool of count peers; false if lwIP could
 * not bind. */
bool lwip_udp_start(lwip_udp_server_t *s, const wsg_proto_driver_t *driver, uint16_t port,
                    uint16_t reply_port, wsg_peer_t *pool, unsigned count);

/* Forgets peers that said goodbye or went quiet. */
void lwip_udp_poll(lwip_udp_server_t *s);

#endif
