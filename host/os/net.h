/* SPDX-License-Identifier: BSD-3-Clause */
/* Socket helpers shared by the TCP and UDP servers, and the registry of the
 * server's own datagram sockets (net_t) that keeps a UDP server from
 * answering a datagram one of them sent. */
#ifndef HOST_NET_H
#define HOST_NET_H

#include <stdbool.h>
#include <sys/socket.h>

/* The server's own datagram sockets: GCL UDP, binary UDP. */
#define NET_OWN_SOCKETS_MAX 8

/* Every SOCK_DGRAM socket net_listen() opened, by its bound address (the
 * first NET_OWN_SOCKETS_MAX). Set up with net_init(); read with net_is_own_address(). */
typedef struct {
    struct sockaddr_storage own[NET_OWN_SOCKETS_MAX];
    unsigned own_count;
} net_t;

/* Starts with no sockets of its own. */
void net_init(net_t *net);
/* Creates, binds (and for SOCK_STREAM listens on) a non-blocking socket.
 * On failure prints one clear error line and returns -1. */
int net_listen(net_t *net, int type, const char *addr, int port);
/* The same, the error naming `option` (e.g. "--tcp-port") as the way to
 * another port. */
int net_listen_for(net_t *net, int type, const char *addr, int port, const char *option);
/* The same for a port the caller can do without: on failure prints
 * nothing and returns -1 with errno set (EADDRNOTAVAIL for an address that
 * does not resolve); the caller says what it does instead. */
int net_listen_optional(net_t *net, int type, const char *addr, int port);
/* The port a socket is bound to (useful with port 0). */
int net_local_port(int fd);
/* True when the address and port are one of this server's own datagram
 * sockets (on its bound address or, when bound to a wildcard, on any
 * address of this host): such a datagram is never answered. */
bool net_is_own_address(const net_t *net, const struct sockaddr_storage *peer);
/* addr:port, with an IPv6 address in brackets ([::1]:1000). */
void net_format_endpoint(const char *addr, int port, char *out, size_t cap);
void net_format_peer(const struct sockaddr_storage *ss, char *out, size_t cap);
/* The address alone (an IPv4-mapped IPv6 one as IPv4), without the port. */
void net_format_address(const struct sockaddr_storage *ss, char *out, size_t cap);

#endif
