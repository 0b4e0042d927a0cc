/* SPDX-License-Identifier: BSD-3-Clause */
/* GCL over TCP: one session per connection, each reply line its own send().
 * One server per device (the fleet has one per gripper), on a listener of
 * its own or on one shared by the fleet (--address-per-device); connection storage
 * is allocated on accept and freed on close, so an idle server costs only
 * its listener. Connections have TCP keepalive; a half-closed one is
 * answered and flushed before it closes; idle_timeout_s (0: off) closes
 * quiet connections at their own deadline (tcp_server_next_deadline_us). */
#ifndef HOST_TCP_SERVER_H
#define HOST_TCP_SERVER_H

#include <stdbool.h>
#include <stdint.h>

#include "gripper.h"
#include "hal_clock.h"
#include "list.h"
#include "listener.h"
#include "wire.h"
#include "wsg/wsg_conn.h"

typedef struct tcp_client tcp_client_t;
typedef struct tcp_server_s tcp_server_t;

/* What a set of servers (the fleet's) keeps across them: the open
 * connections, oldest first (the reap visits these only), and the servers
 * whose listener waits for descriptors. Zeroed: empty. */
typedef struct {
    host_loop_t *loop; /* every socket of the set is watched here */
    net_t *net;        /* and is one of its own */
    wire_set_t *wires; /* the wire conditions (a new connection's: wires->all) */
    list_t clients;    /* of tcp_client_t */
    list_t waiting;    /* of tcp_server_t */
    /* Replies an upper layer holds back for this session (NULL: none): a
     * half-closed connection waits for them before it closes. */
    bool (*replies_held)(void *ctx, const wsg_conn_t *conn);
    void *held_ctx;
    /* No connection's --idle-timeout ends before this (0: not known yet).
     * It may be early: input moves a timeout later and leaves it; the
     * connections are scanned again once it is due. */
    uint64_t idle_due_us;
    /* idle_due_us was lowered (an accept) since the owner last asked
     * tcp_server_next_deadline_us(): until then the owner's copy stands. */
    bool deadline_lowered;
    /* The connections something happened to since the last reap, in that
     * order: the reap looks at these only. */
    list_t marked;
    unsigned marked_count;
} tcp_servers_t;

/* A listener shared by several servers (--address-per-device): the server
 * whose device owns the connection's local address, or NULL to refuse it. */
typedef tcp_server_t *(*tcp_route_t)(void *ctx, const struct sockaddr_storage *local);

struct tcp_server_s {
    tcp_servers_t *set;   /* the set it belongs to */
    listener_t own;       /* its own listening socket (fd -1 when it shares one) */
    listener_t *listener; /* the socket its connections arrive on */
    tcp_route_t route;    /* a shared listener's: whose connection it is */
    void *route_ctx;
    gripper_t *gripper; /* the device its connections talk to */
    int max_clients;
    uint64_t idle_timeout_us; /* 0: off */
    unsigned open;            /* connections open */
    bool waits_for_fds;       /* its listener is paused (out of descriptors) */
    list_node_t waiting_link; /* on its set's waiting list, then */
};

bool tcp_server_start(tcp_server_t *s, tcp_servers_t *set, gripper_t *g, const char *addr, int port,
                      int max_clients, int idle_timeout_s);
/* A listener for several servers on addr:port: route() chooses the server
 * of each connection by its local address (getsockname()). */
bool tcp_server_start_shared(tcp_server_t *s, tcp_servers_t *set, const char *addr, int port,
                             tcp_route_t route, void *ctx);
/* A server without a socket of its own: its connections come from the
 * shared listener front (which must outlive it), in front's set. */
void tcp_server_attach(tcp_server_t *s, gripper_t *g, tcp_server_t *front, int max_clients,
                       int idle_timeout_s);
int tcp_server_port(const tcp_server_t *s);
/* Drops every connection of the server as if its cable were pulled (no BYE). */
void tcp_server_close_all(tcp_server_t *s);
void tcp_server_stop(tcp_server_t *s);

/* tcp_server_reap() when something happened to a connection, a listener
 * waits for descriptors or a timeout is due (now: the device time). */
void tcp_server_reap_due(tcp_servers_t *tcp, uint64_t now);
/* Across every server of the set: closes connections that said BYE (once flushed),
 * failed or stayed quiet beyond --idle-timeout. Visits only connections that
 * may have finished since the last reap (all once a timeout is due). Inline:
 * asked after every wake-up, most of which leave it nothing to do. */
static inline void tcp_server_reap(tcp_servers_t *tcp)
{
    uint64_t now = hal_clock_now_us();
    if (tcp->marked_count != 0 || !list_empty(&tcp->waiting) || now >= tcp->idle_due_us) {
        tcp_server_reap_due(tcp, now);
    }
}
/* The earliest --idle-timeout of an open connection (simulated clock), or
 * UINT64_MAX: the loop must wake for it even when the device is idle. */
uint64_t tcp_server_next_deadline_us(tcp_servers_t *tcp);
/* Pulls the cable of the connection that carries this session: the session
 * ends without BYE and the socket is reset. False if none carries it. */
bool tcp_server_cut(tcp_servers_t *tcp, const wsg_conn_t *conn);
/* Gives the connection of conn (NULL: every connection) the wire
 * conditions spec; what its old wire held leaves first. How many. */
unsigned tcp_server_set_wire(tcp_servers_t *tcp, const wsg_conn_t *conn, const wire_spec_t *spec);
/* The wire of the connection that carries conn (NULL: none, or no wire). */
const wire_t *tcp_server_wire(const tcp_servers_t *tcp, const wsg_conn_t *conn);
/* The peer ("ADDR:PORT") of the connection that carries this session, or
 * NULL if none does (the web page's connection list). */
const char *tcp_server_peer_name(const tcp_servers_t *tcp, const wsg_conn_t *conn);
/* The updates (AUTOSEND lines, auto-update frames) dropped so far because
 * the client did not read them (its queue was half full); 0 when not one
 * of this set's connections. */
unsigned long tcp_server_updates_dropped(const tcp_servers_t *tcp, const wsg_conn_t *conn);

#endif
