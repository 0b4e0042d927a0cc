/* SPDX-License-Identifier: BSD-3-Clause */
/* The binary protocol over UDP (docs/binary-protocol.md): requests on the
 * binary UDP port, one frame per datagram; each reply (automatic updates
 * included) goes to the sender's IP at the configured reply port, as
 * Drake's driver expects. One object per device: the fleet gives each
 * device its own, with its ports shifted like the others. */
#ifndef HOST_BIN_UDP_SERVER_H
#define HOST_BIN_UDP_SERVER_H

#include <stdbool.h>
#include <stdint.h>
#include <sys/socket.h>

#include "gripper.h"
#include "wsg/wsg_conn.h"

#define BIN_UDP_PEERS_MAX 8

typedef struct bin_udp_server bin_udp_server_t;

typedef struct {
    bin_udp_server_t *server;
    bool in_use;
    struct sockaddr_storage from; /* the sender: the peer's identity */
    socklen_t from_len;
    struct sockaddr_storage reply_to; /* its IP at the reply port */
    wsg_conn_t conn;
    uint64_t last_seen_us;
    uint32_t credit; /* reply bytes it may still be sent */
    char name[64];
} bin_udp_peer_t;

struct bin_udp_server {
    gripper_t *gripper;
    int fd;
    int reply_port; /* 0: reply to the sender's own port */
    uint64_t peer_timeout_us;
    bin_udp_peer_t peers[BIN_UDP_PEERS_MAX];
};

/* port 0 is "off" for the options; here it binds any free port (tests). */
bool bin_udp_server_start(bin_udp_server_t *s, gripper_t *gripper, const char *addr, int port,
                          int reply_port, int peer_timeout_s);
int bin_udp_server_port(const bin_udp_server_t *s);
/* Forgets peers silent longer than the peer timeout (unless in a motion). */
void bin_udp_server_reap(bin_udp_server_t *s);
void bin_udp_server_stop(bin_udp_server_t *s);

#endif
