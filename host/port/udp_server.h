/* SPDX-License-Identifier: BSD-3-Clause */
/* A protocol over UDP: one session per peer address, each reply message its
 * own datagram. GCL on the UDP port (replies to the sender), the binary
 * protocol on the binary UDP port (replies to the sender's IP at the reply
 * port, as Drake's driver expects). One server per device and protocol,
 * on a socket of its own or, with --address-per-device, on one socket the
 * fleet's servers share (udp_server_start_shared); a peer's storage is
 * allocated when it first speaks. The peer rules (the
 * timeout, the reply budget and rate, making room) are the core's
 * (wsg/wsg_peers.h); this port moves datagrams and ignores the server's own
 * addresses. */
#ifndef HOST_UDP_SERVER_H
#define HOST_UDP_SERVER_H

#include <stdbool.h>
#include <stdint.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include "gripper.h"
#include "list.h"
#include "loop.h"
#include "net.h"
#include "wire.h"
#include "wsg/wsg_conn.h"
#include "wsg/wsg_peers.h"

typedef struct udp_server udp_server_t;

#define UDP_DATAGRAM_MAX 65536

/* What a set of servers (the fleet's) keeps across them: the servers that
 * know a peer (the reap, the deadline and the cut visit these only) and
 * the buffer a datagram is read into. Zeroed: empty. */
typedef struct {
    host_loop_t *loop; /* every socket of the set is watched here */
    net_t *net;        /* whose own addresses are never answered */
    wire_set_t *wires; /* the wire conditions (a new peer's: wires->all) */
    list_t active;     /* of udp_server_t */
    /* A datagram came (a peer's silence deadline may be new) since the owner
     * last asked udp_server_next_deadline_us(). */
    bool deadline_moved;
    uint8_t datagram[UDP_DATAGRAM_MAX];
} udp_servers_t;

/* A socket shared by several servers (--address-per-device): the server
 * whose device owns the datagram's destination address, or NULL to drop it. */
typedef udp_server_t *(*udp_route_t)(void *ctx, const struct sockaddr_storage *destination);

typedef struct {
    const wsg_proto_driver_t *driver;
    const char *label; /* for the log: "udp", "binary udp" */
    unsigned max_peers;
    int reply_port; /* 0: reply to the sender's own port */
    bool optional;  /* a port that cannot be had: no error line, the caller
                       says what it does without it (errno tells why) */
} udp_protocol_t;

struct udp_server {
    udp_servers_t *set; /* the set it belongs to */
    int fd;
    int port;              /* the port it listens on, asked once at start */
    struct in_addr source; /* a shared socket's replies leave from here (0: any) */
    bool shares_fd;        /* the fd is a shared socket's: not closed here */
    bool active;           /* on the list of servers with peers */
    udp_route_t route;     /* a shared socket's: whose datagram it is */
    void *route_ctx;
    gripper_t *gripper; /* the device its peers talk to */
    udp_protocol_t proto;
    wsg_peer_table_t peers;
    list_node_t active_link; /* on its set's servers with peers */
};

/* GCL over UDP (16 peers, replies to the sender). */
udp_protocol_t udp_protocol_gcl(void);
/* The binary protocol over UDP (8 peers, replies to reply_port). */
udp_protocol_t udp_protocol_binary(int reply_port);

bool udp_server_start(udp_server_t *s, udp_servers_t *set, gripper_t *g,
                      const udp_protocol_t *proto, const char *addr, int port, int peer_timeout_s);
/* A socket for several servers on the IPv4 wildcard address at port: each
 * datagram goes to the server route() names by its destination address
 * (IP_PKTINFO). */
bool udp_server_start_shared(udp_server_t *s, udp_servers_t *set, const udp_protocol_t *proto,
                             int port, udp_route_t route, void *ctx);
/* A server on the shared socket front (which must outlive it): its replies
 * leave from source, the address its peers sent to. */
void udp_server_attach(udp_server_t *s, gripper_t *g, const udp_protocol_t *proto,
                       const udp_server_t *front, struct in_addr source, int peer_timeout_s);
int udp_server_port(const udp_server_t *s);
/* Forgets every peer of the server. */
void udp_server_close_all(udp_server_t *s);
void udp_server_stop(udp_server_t *s);

/* Across every server of the set with peers: forgets peers that said goodbye or stayed
 * silent too long (unless running a motion). */
void udp_server_reap(udp_servers_t *set);
/* When the next known peer falls silent for too long, or UINT64_MAX. */
uint64_t udp_server_next_deadline_us(udp_servers_t *set);
/* Forgets the peer that owns this session, as if it vanished without BYE.
 * False if no peer owns it. */
bool udp_server_cut(udp_servers_t *set, const wsg_conn_t *conn);
/* Gives the peer of conn (NULL: every known peer) the wire conditions
 * spec; what its old wire held leaves first. How many. */
unsigned udp_server_set_wire(udp_servers_t *set, const wsg_conn_t *conn, const wire_spec_t *spec);
/* The wire of the peer that owns conn (NULL: none, or no wire). */
const wire_t *udp_server_wire(const udp_servers_t *set, const wsg_conn_t *conn);
/* The address ("ADDR:PORT") of the peer that owns this session, or NULL if
 * none does (the web page's connection list). */
const char *udp_server_peer_name(const udp_servers_t *set, const wsg_conn_t *conn);
/* The updates dropped over the peer's budget; 0 when not one of its peers. */
unsigned long udp_server_updates_dropped(const udp_servers_t *set, const wsg_conn_t *conn);

#endif
