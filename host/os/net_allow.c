/* SPDX-License-Identifier: BSD-3-Clause */
#include "net_allow.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdlib.h>
#include <string.h>

#define ITEM_MAX 64 /* an IPv6 address with a prefix fits */

/* Reads "ADDR" or "ADDR/PREFIX" into e. */
static bool parse_item(const char *item, net_prefix_t *e)
{
    char addr[ITEM_MAX];
    const char *slash = strchr(item, '/');
    size_t len = slash != NULL ? (size_t)(slash - item) : strlen(item);
    if (len == 0 || len >= sizeof(addr)) {
        return false;
    }
    memcpy(addr, item, len);
    addr[len] = '\0';
    memset(e, 0, sizeof(*e));
    unsigned bits;
    if (inet_pton(AF_INET, addr, e->addr) == 1) {
        e->family = AF_INET;
        bits = 32;
    } else if (inet_pton(AF_INET6, addr, e->addr) == 1) {
        e->family = AF_INET6;
        bits = 128;
    } else {
        return false;
    }
    e->prefix = (unsigned char)bits;
    if (slash == NULL) {
        return true;
    }
    char *end = NULL;
    const char *digits = slash + 1;
    unsigned long prefix = strtoul(digits, &end, 10);
    if (*digits < '0' || *digits > '9' || *end != '\0' || prefix > bits) {
        return false;
    }
    e->prefix = (unsigned char)prefix;
    return true;
}

/* The item without the blanks around it ("a, b" is a list of two). */
static char *trimmed(char *item)
{
    while (*item == ' ' || *item == '\t') {
        item++;
    }
    size_t len = strlen(item);
    while (len > 0 && (item[len - 1] == ' ' || item[len - 1] == '\t')) {
        item[--len] = '\0';
    }
    return item;
}

bool net_allow_add(net_allow_t *list, const char *text)
{
    net_allow_t grown = *list;
    const char *item = text;
    for (;;) {
        const char *comma = strchr(item, ',');
        size_t len = comma != NULL ? (size_t)(comma - item) : strlen(item);
        char one[ITEM_MAX];
        if (len >= sizeof(one) || grown.count == NET_ALLOW_MAX) {
            return false;
        }
        memcpy(one, item, len);
        one[len] = '\0';
        if (!parse_item(trimmed(one), &grown.entries[grown.count])) {
            return false;
        }
        grown.count++;
        if (comma == NULL) {
            break;
        }
        item = comma + 1;
    }
    *list = grown;
    return true;
}

static bool prefix_matches(const net_prefix_t *e, const unsigned char *addr)
{
    unsigned whole = e->prefix / 8u;
    unsigned rest = e->prefix % 8u;
    if (memcmp(e->addr, addr, whole) != 0) {
        return false;
    }
    unsigned char mask = (unsigned char)(0xffu << (8u - rest));
    return rest == 0 || ((e->addr[whole] ^ addr[whole]) & mask) == 0;
}

/* The peer's address as a family and bytes; a v4-mapped IPv6 one as IPv4. */
static int peer_address(const struct sockaddr_storage *peer, const unsigned char **addr)
{
    if (peer->ss_family == AF_INET) {
        *addr = (const unsigned char *)&((const struct sockaddr_in *)peer)->sin_addr;
        return AF_INET;
    }
    if (peer->ss_family != AF_INET6) {
        return AF_UNSPEC;
    }
    const struct in6_addr *v6 = &((const struct sockaddr_in6 *)peer)->sin6_addr;
    if (IN6_IS_ADDR_V4MAPPED(v6)) {
        *addr = v6->s6_addr + 12;
        return AF_INET;
    }
    *addr = v6->s6_addr;
    return AF_INET6;
}

bool net_allow_match(const net_allow_t *list, const struct sockaddr_storage *peer)
{
    const unsigned char *addr = NULL;
    int family = peer_address(peer, &addr);
    for (unsigned i = 0; i < list->count; i++) {
        const net_prefix_t *e = &list->entries[i];
        if (e->family == family && prefix_matches(e, addr)) {
            return true;
        }
    }
    return false;
}

bool net_allow_loopback(const struct sockaddr_storage *peer)
{
    const unsigned char *addr = NULL;
    int family = peer_address(peer, &addr);
    if (family == AF_INET) {
        return addr[0] == 127u;
    }
    return family == AF_INET6 && memcmp(addr, &in6addr_loopback, sizeof(in6addr_loopback)) == 0;
}
