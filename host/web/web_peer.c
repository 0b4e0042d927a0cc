/* SPDX-License-Identifier: BSD-3-Clause */
#include "web/web_peer.h"

#include <netinet/in.h>
#include <string.h>

static bool v4_loopback(const unsigned char *bytes)
{
    return bytes[0] == 127u;
}

bool web_peer_is_loopback(const struct sockaddr *addr)
{
    if (addr == NULL) {
        return false;
    }
    if (addr->sa_family == AF_INET) {
        struct sockaddr_in v4;
        memcpy(&v4, addr, sizeof(v4));
        return v4_loopback((const unsigned char *)&v4.sin_addr);
    }
    if (addr->sa_family != AF_INET6) {
        return false;
    }
    struct sockaddr_in6 v6;
    memcpy(&v6, addr, sizeof(v6));
    if (IN6_IS_ADDR_LOOPBACK(&v6.sin6_addr)) {
        return true;
    }
    return IN6_IS_ADDR_V4MAPPED(&v6.sin6_addr) && v4_loopback(&v6.sin6_addr.s6_addr[12]);
}
