/* SPDX-License-Identifier: BSD-3-Clause */
/* A TCP server's connection: tcp_server.c's and its helpers' own (the
 * stalled-slot rule, tcp_stall.c; accepting, tcp_accept.c); nothing else includes it. */
#ifndef HOST_TCP_CLIENT_H
#define HOST_TCP_CLIENT_H

#include <stdbool.h>
#include <stdint.h>

#include "held_input.h"
#include "list.h"
#include "tcp_server.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_outq.h"

struct tcp_client {
    tcp_server_t *server;
    list_node_t link; /* on its set's open connections */
    int fd;
    wsg_conn_t conn;
    wsg_outq_t outq;
    held_input_t held; /* bytes after a request waiting for the device's processor */
    bool dead;         /* failed or overflowed: close at the next reap */
    bool eof;          /* the client shut its side: answer, flush, then close */
    bool expired;      /* closed by the server for silence: not a lost link */
    bool marked;       /* on its set's list for the next reap */
    list_node_t mark_link;
    uint64_t connected_us;
    uint64_t heard_us;     /* last input, or connected_us */
    uint64_t completed_us; /* when its last whole command arrived, or connected_us */
    uint32_t messages_in;  /* whole commands so far (wsg_conn_messages_in) */
    unsigned long dropped_autosend;
    wire_t *wire; /* its wire conditions; NULL: none (the default) */
    char peer[64];
};

#define CLIENT(node) LIST_ITEM(node, tcp_client_t, link)

/* The stalled connection of s that completed a command longest ago (none
 * for grace_us, and stuck inside one or none completed), or NULL. */
tcp_client_t *tcp_stalled_connection(const tcp_server_t *s, uint64_t grace_us);

/* A new connection c on fd from peer ss (tcp_accept.c): its socket's
 * options, its session, its wire; false when it cannot be had. */
bool tcp_client_setup(tcp_client_t *c, int fd, const struct sockaddr_storage *ss);
/* Closes c now and frees it (logged, its session closed). */
void tcp_client_close(tcp_client_t *c);

#endif
