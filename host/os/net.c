/* SPDX-License-Identifier: BSD-3-Clause */
#include "net.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <ifaddrs.h>
#include <netdb.h>
#include <netinet/in.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

/* A small backlog makes Linux drop the SYN of a client that reconnects
 * quickly after closing (a 1 s retransmit stall every ~17 connections). */
#define LISTEN_BACKLOG 128
static bool is_wildcard(const struct sockaddr_storage *ss);

void net_init(net_t *net)
{
    memset(net, 0, sizeof(*net));
}

static void remember_own_socket(net_t *net, int fd)
{
    socklen_t len = sizeof(net->own[0]);
    if (net->own_count < NET_OWN_SOCKETS_MAX &&
        getsockname(fd, (struct sockaddr *)&net->own[net->own_count], &len) == 0) {
        net->own_count++;
    }
}

/* A host name such as localhost: its IPv4 address if it has one (clients
 * given "localhost" try both families; those given 127.0.0.1 only IPv4),
 * else its first IPv6 address. */
static bool resolve_name(const char *name, int port, struct sockaddr_storage *ss, socklen_t *len)
{
    static const int families[] = {AF_INET, AF_INET6};
    for (size_t i = 0; i < sizeof(families) / sizeof(families[0]); i++) {
        struct addrinfo hints = {.ai_family = families[i], .ai_flags = AI_PASSIVE};
        struct addrinfo *found = NULL;
        if (getaddrinfo(name, NULL, &hints, &found) != 0 || found == NULL) {
            continue;
        }
        memcpy(ss, found->ai_addr, found->ai_addrlen);
        *len = found->ai_addrlen;
        freeaddrinfo(found);
        if (ss->ss_family == AF_INET6) {
            ((struct sockaddr_in6 *)ss)->sin6_port = htons((uint16_t)port);
        } else {
            ((struct sockaddr_in *)ss)->sin_port = htons((uint16_t)port);
        }
        return true;
    }
    return false;
}

static bool parse_addr(const char *addr, int port, struct sockaddr_storage *ss, socklen_t *len)
{
    memset(ss, 0, sizeof(*ss));
    struct sockaddr_in *v4 = (struct sockaddr_in *)ss;
    struct sockaddr_in6 *v6 = (struct sockaddr_in6 *)ss;
    if (inet_pton(AF_INET, addr, &v4->sin_addr) == 1) {
        v4->sin_family = AF_INET;
        v4->sin_port = htons((uint16_t)port);
        *len = sizeof(*v4);
        return true;
    }
    if (inet_pton(AF_INET6, addr, &v6->sin6_addr) == 1) {
        v6->sin6_family = AF_INET6;
        v6->sin6_port = htons((uint16_t)port);
        *len = sizeof(*v6);
        return true;
    }
    return resolve_name(addr, port, ss, len);
}

/* Binds (and listens); -1 with errno set on failure, printing nothing. */
static int open_listening(net_t *net, int type, const struct sockaddr_storage *ss, socklen_t len)
{
    int fd = socket(ss->ss_family, type | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    int one = 1;
    /* TCP: restart while old connections linger in TIME_WAIT. Never for
     * UDP, where SO_REUSEADDR would let another socket share the port. */
    if (fd >= 0 && type == SOCK_STREAM) {
        setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
    }
    /* "::" serves IPv4 too (as ::ffff:a.b.c.d), whatever net.ipv6.bindv6only says. */
    int v6only = 0;
    if (fd >= 0 && ss->ss_family == AF_INET6 && is_wildcard(ss)) {
        setsockopt(fd, IPPROTO_IPV6, IPV6_V6ONLY, &v6only, sizeof(v6only));
    }
    if (fd < 0 || bind(fd, (const struct sockaddr *)ss, len) != 0 ||
        (type == SOCK_STREAM && listen(fd, LISTEN_BACKLOG) != 0)) {
        int err = errno;
        if (fd >= 0) {
            close(fd);
        }
        errno = err;
        return -1;
    }
    /* Only a datagram socket can send us a datagram: a TCP listener's port
     * number is another port space, and a peer's UDP port may carry it. */
    if (type == SOCK_DGRAM) {
        remember_own_socket(net, fd);
    }
    return fd;
}

int net_listen_optional(net_t *net, int type, const char *addr, int port)
{
    struct sockaddr_storage ss;
    socklen_t len = 0;
    if (!parse_addr(addr, port, &ss, &len)) {
        errno = EADDRNOTAVAIL;
        return -1;
    }
    return open_listening(net, type, &ss, len);
}

/* What to do about a port that cannot be had; option: the one that moves
 * it (NULL: not known here). */
static void listen_hint(int err, const char *option, char *out, size_t cap)
{
    out[0] = '\0';
    if (err == EACCES) {
        snprintf(out, cap, " (ports below 1024 need root or CAP_NET_BIND_SERVICE%s%s%s)",
                 option != NULL ? "; or " : "", option != NULL ? option : "",
                 option != NULL ? " 0 for a free port" : "");
    } else if (err == EADDRINUSE) {
        snprintf(out, cap,
                 " (another program, perhaps another wsgsim, has it: choose another "
                 "port%s%s%s)",
                 option != NULL ? ", or " : "", option != NULL ? option : "",
                 option != NULL ? " 0 for a free one" : "");
    }
}

int net_listen(net_t *net, int type, const char *addr, int port)
{
    return net_listen_for(net, type, addr, port, NULL);
}

int net_listen_for(net_t *net, int type, const char *addr, int port, const char *option)
{
    const char *proto = type == SOCK_STREAM ? "TCP" : "UDP";
    struct sockaddr_storage ss;
    socklen_t len = 0;
    if (!parse_addr(addr, port, &ss, &len)) {
        fprintf(stderr, "wsgsim: cannot listen on %s %s:%d: not an IP address or known host name\n",
                proto, addr, port);
        return -1;
    }
    int fd = open_listening(net, type, &ss, len);
    if (fd < 0) {
        int err = errno;
        char hint[160];
        listen_hint(err, option, hint, sizeof(hint));
        fprintf(stderr, "wsgsim: cannot listen on %s %s:%d: %s%s\n", proto, addr, port,
                strerror(err), hint);
        errno = err;
    }
    return fd;
}

int net_local_port(int fd)
{
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    if (getsockname(fd, (struct sockaddr *)&ss, &len) != 0) {
        return -1;
    }
    if (ss.ss_family == AF_INET6) {
        return ntohs(((struct sockaddr_in6 *)&ss)->sin6_port);
    }
    return ntohs(((struct sockaddr_in *)&ss)->sin_port);
}

void net_format_endpoint(const char *addr, int port, char *out, size_t cap)
{
    snprintf(out, cap, strchr(addr, ':') != NULL ? "[%s]:%d" : "%s:%d", addr, port);
}

void net_format_peer(const struct sockaddr_storage *ss, char *out, size_t cap)
{
    char host[INET6_ADDRSTRLEN] = "?";
    int port = 0;
    if (ss->ss_family == AF_INET6) {
        const struct sockaddr_in6 *v6 = (const struct sockaddr_in6 *)ss;
        inet_ntop(AF_INET6, &v6->sin6_addr, host, sizeof(host));
        port = ntohs(v6->sin6_port);
        snprintf(out, cap, "[%s]:%d", host, port);
        return;
    }
    const struct sockaddr_in *v4 = (const struct sockaddr_in *)ss;
    inet_ntop(AF_INET, &v4->sin_addr, host, sizeof(host));
    port = ntohs(v4->sin_port);
    snprintf(out, cap, "%s:%d", host, port);
}

void net_format_address(const struct sockaddr_storage *ss, char *out, size_t cap)
{
    const struct sockaddr_in6 *v6 = (const struct sockaddr_in6 *)ss;
    const struct sockaddr_in *v4 = (const struct sockaddr_in *)ss;
    char host[INET6_ADDRSTRLEN] = "?";
    if (ss->ss_family == AF_INET6 && IN6_IS_ADDR_V4MAPPED(&v6->sin6_addr)) {
        inet_ntop(AF_INET, v6->sin6_addr.s6_addr + 12, host, sizeof(host));
    } else if (ss->ss_family == AF_INET6) {
        inet_ntop(AF_INET6, &v6->sin6_addr, host, sizeof(host));
    } else {
        inet_ntop(AF_INET, &v4->sin_addr, host, sizeof(host));
    }
    snprintf(out, cap, "%s", host);
}

/* An IPv4-mapped IPv6 address (::ffff:a.b.c.d) as plain IPv4. */
static void unmap(const struct sockaddr_storage *in, struct sockaddr_storage *out)
{
    *out = *in;
    const struct sockaddr_in6 *v6 = (const struct sockaddr_in6 *)in;
    if (in->ss_family != AF_INET6 || !IN6_IS_ADDR_V4MAPPED(&v6->sin6_addr)) {
        return;
    }
    struct sockaddr_in v4;
    memset(&v4, 0, sizeof(v4));
    v4.sin_family = AF_INET;
    v4.sin_port = v6->sin6_port;
    memcpy(&v4.sin_addr, &v6->sin6_addr.s6_addr[12], 4);
    memset(out, 0, sizeof(*out));
    memcpy(out, &v4, sizeof(v4));
}

static int port_of(const struct sockaddr_storage *ss)
{
    return ss->ss_family == AF_INET6 ? ntohs(((const struct sockaddr_in6 *)ss)->sin6_port)
                                     : ntohs(((const struct sockaddr_in *)ss)->sin_port);
}

static bool same_host(const struct sockaddr_storage *a, const struct sockaddr *b)
{
    if (a->ss_family != b->sa_family) {
        return false;
    }
    if (a->ss_family == AF_INET) {
        return ((const struct sockaddr_in *)a)->sin_addr.s_addr ==
               ((const struct sockaddr_in *)b)->sin_addr.s_addr;
    }
    return memcmp(&((const struct sockaddr_in6 *)a)->sin6_addr,
                  &((const struct sockaddr_in6 *)b)->sin6_addr, sizeof(struct in6_addr)) == 0;
}

static bool is_wildcard(const struct sockaddr_storage *ss)
{
    if (ss->ss_family == AF_INET) {
        return ((const struct sockaddr_in *)ss)->sin_addr.s_addr == htonl(INADDR_ANY);
    }
    return IN6_IS_ADDR_UNSPECIFIED(&((const struct sockaddr_in6 *)ss)->sin6_addr);
}

/* One of this host's addresses: loopback, or configured on an interface. */
static bool is_local_host(const struct sockaddr_storage *ss)
{
    if (ss->ss_family == AF_INET &&
        (ntohl(((const struct sockaddr_in *)ss)->sin_addr.s_addr) >> 24) == 127u) {
        return true;
    }
    if (ss->ss_family == AF_INET6 &&
        IN6_IS_ADDR_LOOPBACK(&((const struct sockaddr_in6 *)ss)->sin6_addr)) {
        return true;
    }
    struct ifaddrs *list = NULL;
    if (getifaddrs(&list) != 0) {
        return true; /* cannot tell: assume the worst, it is our own */
    }
    bool found = false;
    for (const struct ifaddrs *i = list; i != NULL && !found; i = i->ifa_next) {
        found = i->ifa_addr != NULL && same_host(ss, i->ifa_addr);
    }
    freeifaddrs(list);
    return found;
}

bool net_is_own_address(const net_t *net, const struct sockaddr_storage *peer)
{
    struct sockaddr_storage src;
    unmap(peer, &src);
    for (unsigned i = 0; i < net->own_count; i++) {
        struct sockaddr_storage mine;
        unmap(&net->own[i], &mine);
        if (port_of(&mine) != port_of(&src)) {
            continue;
        }
        bool dual_stack = mine.ss_family == AF_INET6 && is_wildcard(&mine);
        if (mine.ss_family != src.ss_family && !dual_stack) {
            continue;
        }
        if (is_wildcard(&mine) ? is_local_host(&src)
                               : same_host(&mine, (const struct sockaddr *)&src)) {
            return true;
        }
    }
    return false;
}
