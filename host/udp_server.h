/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL over UDP: one session per peer address; each reply line is its own
 * datagram, sent back to the peer that asked (AUTOSEND included). One server
 * per device; a peer's storage is allocated when it first speaks. A peer
 * silent for peer_timeout_s is forgotten at that deadline (its AUTOSEND
 * ends), what it gets is bounded by what it sent, and the server's own
 * addresses are ignored. */
#ifndef HOST_UDP_SERVER_H
#define HOST_UDP_SERVER_H

#include <stdbool.h>
#include <stdint.h>

#include "gripper.h"
#include "wsg/wsg_conn.h"

typedef struct udp_peer udp_peer_t;

typedef struct {
    int fd;
    gripper_t *gripper; /* the device its peers talk to */
    uint64_t peer_timeout_us;
    unsigned peers; /* peers known */
} udp_server_t;

bool udp_server_start(udp_server_t *s, gripper_t *g, const char *addr, int port,
                      int peer_timeout_s);
int udp_server_port(const udp_server_t *s);
/* Forgets every peer of the server. */
void udp_server_close_all(udp_server_t *s);
void udp_server_stop(udp_server_t *s);

/* Across every server: forgets peers that said BYE or stayed silent too long
 * (unless running a motion). Visits known peers only. */
void udp_server_reap(void);
/* When the next known peer falls silent for too long, or UINT64_MAX. */
uint64_t udp_server_next_deadline_us(void);
/* Forgets the peer that owns this session, as if it vanished without BYE.
 * False if no peer owns it. */
bool udp_server_cut(const wsg_conn_t *conn);
/* The address ("ADDR:PORT") of the peer that owns this session, or NULL if
 * none does (the web page's connection list). */
const char *udp_server_peer_name(const wsg_conn_t *conn);

#endif
