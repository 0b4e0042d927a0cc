/* SPDX-License-Identifier: BSD-3-Clause */
/* A list of address prefixes (ADDR[/PREFIX], IPv4 or IPv6) and whether a
 * peer's address falls in one: --udp-stream-allow; and whether a peer is
 * this host itself (a loopback address), whose streams need no list. */
#ifndef HOST_NET_ALLOW_H
#define HOST_NET_ALLOW_H

#include <stdbool.h>
#include <sys/socket.h>

#define NET_ALLOW_MAX 8

typedef struct {
    unsigned char addr[16]; /* network byte order; IPv4 in the first 4 */
    unsigned char family;   /* AF_INET or AF_INET6 */
    unsigned char prefix;   /* leading bits that must match */
} net_prefix_t;

typedef struct {
    net_prefix_t entries[NET_ALLOW_MAX];
    unsigned count;
} net_allow_t;

/* Adds the comma-separated ADDR[/PREFIX] items of text (numeric addresses,
 * blanks around an item ignored; no prefix: the whole address). False, with the list unchanged,
 * when an item is malformed or the list would exceed NET_ALLOW_MAX. */
bool net_allow_add(net_allow_t *list, const char *text);
/* Whether the peer's address (IPv4, IPv6, or IPv4 mapped into IPv6 by a
 * dual-stack socket) is in the list. */
bool net_allow_match(const net_allow_t *list, const struct sockaddr_storage *peer);
/* Whether the peer's address is a loopback one: 127.0.0.0/8, ::1, or
 * ::ffff:127.0.0.0/104 (an IPv4 loopback peer of a dual-stack socket).
 * Linux drops a packet with such a source arriving from another host
 * (martian source), and what is sent to it never leaves this host. */
bool net_allow_loopback(const struct sockaddr_storage *peer);

#endif
