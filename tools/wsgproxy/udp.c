/* SPDX-License-Identifier: BSD-3-Clause */
/* UDP: each driver address gets a socket of the proxy's own towards the
 * gripper, so the gripper's replies to it can be told apart. GCL replies
 * come back to that socket from the gripper's port. Binary replies go, by
 * the protocol's convention, to the sender's address at the reply port
 * (1501): the proxy listens there and passes them to the driver that sent
 * last, at the driver's reply port (or the port it sent from), from the
 * proxy's binary port, as the gripper would. */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "proxy.h"

#define DATAGRAM_MAX 65536u

static bool same_address(const struct sockaddr_storage *a, const struct sockaddr_storage *b)
{
    if (a->ss_family != b->ss_family) {
        return false;
    }
    if (a->ss_family == AF_INET) {
        const struct sockaddr_in *x = (const void *)a, *y = (const void *)b;
        return x->sin_port == y->sin_port && x->sin_addr.s_addr == y->sin_addr.s_addr;
    }
    const struct sockaddr_in6 *x = (const void *)a, *y = (const void *)b;
    return x->sin6_port == y->sin6_port &&
           memcmp(&x->sin6_addr, &y->sin6_addr, sizeof(x->sin6_addr)) == 0;
}

static void forget(proxy_t *p, udp_peer_t *peer)
{
    loop_unwatch(p->loop, peer->upstream);
    close(peer->upstream);
    proxy_note(p, "%s forgotten (the least recently heard of %d)", peer->channel, PROXY_UDP_PEERS);
    if (p->last_binary == peer) {
        p->last_binary = NULL;
    }
    peer->used = false;
}

/* The driver's reply goes to its reply port (binary with one set), else
 * to the port it sent from. */
static void to_driver(proxy_t *p, udp_peer_t *peer, const unsigned char *data, size_t len)
{
    struct sockaddr_storage to = peer->driver;
    int from = p->udp_gcl;
    if (peer->kind == UDP_BINARY) {
        from = p->udp_bin;
        if (p->opt.bin_reply_port > 0) {
            proxy_set_port(&to, p->opt.bin_reply_port);
        }
    }
    if (sendto(from, data, len, MSG_DONTWAIT, (struct sockaddr *)&to, peer->driver_len) < 0) {
        proxy_note(p, "%s: a reply not passed on: %s", peer->channel, strerror(errno));
    }
}

static void pass_reply(proxy_t *p, udp_peer_t *peer, const unsigned char *data, size_t len)
{
    uint64_t at = proxy_now_us(p);
    to_driver(p, peer, data, len);
    proxy_record(p, &p->datagram, peer->channel, '<', data, len, at, true);
}

/* A datagram on a peer's own socket: the gripper's reply to it. */
static void on_upstream(void *ctx, int fd, short revents)
{
    (void)revents;
    udp_peer_t *peer = ctx;
    static unsigned char data[DATAGRAM_MAX];
    for (;;) {
        ssize_t n = recv(fd, data, sizeof(data), MSG_DONTWAIT);
        if (n < 0) {
            return; /* drained, or an ICMP error of an earlier datagram */
        }
        pass_reply(peer->owner, peer, data, (size_t)n);
    }
}

/* Binary replies at the proxy's reply port: for the driver that sent last. */
static void on_binary_reply(void *ctx, int fd, short revents)
{
    (void)revents;
    proxy_t *p = ctx;
    static unsigned char data[DATAGRAM_MAX];
    for (;;) {
        ssize_t n = recv(fd, data, sizeof(data), MSG_DONTWAIT);
        if (n < 0) {
            return;
        }
        if (p->last_binary != NULL) {
            pass_reply(p, p->last_binary, data, (size_t)n);
        } else {
            proxy_record(p, &p->datagram, "s0u", '<', data, (size_t)n, proxy_now_us(p), true);
        }
    }
}

/* A free slot, else the least recently heard peer's, forgotten. */
static udp_peer_t *free_slot(proxy_t *p)
{
    udp_peer_t *oldest = &p->peers[0];
    for (unsigned i = 0; i < PROXY_UDP_PEERS; i++) {
        if (!p->peers[i].used) {
            return &p->peers[i];
        }
        if (p->peers[i].last_heard_ns < oldest->last_heard_ns) {
            oldest = &p->peers[i];
        }
    }
    forget(p, oldest);
    return oldest;
}

static udp_peer_t *peer_new(proxy_t *p, udp_kind_t kind, const struct sockaddr_storage *driver,
                            socklen_t driver_len)
{
    int up = socket(p->gripper.ss_family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    int port = kind == UDP_BINARY ? p->opt.gripper_bin_port : p->opt.gripper_udp_port;
    struct sockaddr_storage to = proxy_gripper_at(p, port);
    if (up < 0 || connect(up, (struct sockaddr *)&to, p->gripper_len) != 0) {
        proxy_log("no socket towards the gripper: %s", strerror(errno));
        if (up >= 0) {
            close(up);
        }
        return NULL;
    }
    udp_peer_t *peer = free_slot(p);
    *peer = (udp_peer_t){.owner = p,
                         .used = true,
                         .kind = kind,
                         .driver = *driver,
                         .driver_len = driver_len,
                         .upstream = up,
                         .id = ++p->next_id};
    snprintf(peer->channel, sizeof(peer->channel), "s%lluu", (unsigned long long)peer->id);
    if (!loop_watch(p->loop, up, POLLIN, on_upstream, peer)) {
        close(up);
        peer->used = false;
        return NULL;
    }
    char who[64];
    net_format_peer(driver, who, sizeof(who));
    proxy_note(p, "%s opened: %s from %s", peer->channel, kind == UDP_BINARY ? "binary" : "GCL",
               who);
    return peer;
}

static udp_peer_t *peer_of(proxy_t *p, udp_kind_t kind, const struct sockaddr_storage *driver,
                           socklen_t driver_len)
{
    for (unsigned i = 0; i < PROXY_UDP_PEERS; i++) {
        if (p->peers[i].used && p->peers[i].kind == kind &&
            same_address(&p->peers[i].driver, driver)) {
            return &p->peers[i];
        }
    }
    return peer_new(p, kind, driver, driver_len);
}

/* A driver's datagram: on to the gripper from the driver's own socket. */
static void from_driver(proxy_t *p, int fd, udp_kind_t kind)
{
    static unsigned char data[DATAGRAM_MAX];
    for (;;) {
        struct sockaddr_storage driver;
        socklen_t len = sizeof(driver);
        ssize_t n =
            recvfrom(fd, data, sizeof(data), MSG_DONTWAIT, (struct sockaddr *)&driver, &len);
        if (n < 0) {
            return;
        }
        uint64_t at = proxy_now_us(p);
        udp_peer_t *peer = peer_of(p, kind, &driver, len);
        if (peer == NULL) {
            continue;
        }
        peer->last_heard_ns = loop_monotonic_ns();
        if (kind == UDP_BINARY) {
            p->last_binary = peer;
        }
        if (send(peer->upstream, data, (size_t)n, MSG_DONTWAIT) < 0) {
            proxy_note(p, "%s: a request not passed on: %s", peer->channel, strerror(errno));
        }
        proxy_record(p, &p->datagram, peer->channel, '>', data, (size_t)n, at, true);
    }
}

static void on_gcl(void *ctx, int fd, short revents)
{
    (void)revents;
    from_driver(ctx, fd, UDP_GCL);
}

static void on_binary(void *ctx, int fd, short revents)
{
    (void)revents;
    from_driver(ctx, fd, UDP_BINARY);
}

/* The gripper's binary replies arrive at this port of the proxy, on the
 * address the proxy sends from towards it (any, here). */
static bool listen_binary_replies(proxy_t *p)
{
    if (p->opt.gripper_bin_reply_port <= 0) {
        return true;
    }
    const char *any = p->gripper.ss_family == AF_INET6 ? "::" : "0.0.0.0";
    p->udp_bin_replies = net_listen_for(&p->net, SOCK_DGRAM, any, p->opt.gripper_bin_reply_port,
                                        "--gripper-binary-reply-port");
    return p->udp_bin_replies >= 0 &&
           loop_watch(p->loop, p->udp_bin_replies, POLLIN, on_binary_reply, p);
}

bool proxy_udp_start(proxy_t *p)
{
    p->udp_gcl = p->udp_bin = p->udp_bin_replies = -1;
    if (p->opt.udp_port >= 0) {
        p->udp_gcl =
            net_listen_for(&p->net, SOCK_DGRAM, p->opt.listen, p->opt.udp_port, "--udp-port");
        if (p->udp_gcl < 0 || !loop_watch(p->loop, p->udp_gcl, POLLIN, on_gcl, p)) {
            return false;
        }
    }
    if (p->opt.bin_port >= 0) {
        p->udp_bin = net_listen_for(&p->net, SOCK_DGRAM, p->opt.listen, p->opt.bin_port,
                                    "--binary-udp-port");
        if (p->udp_bin < 0 || !loop_watch(p->loop, p->udp_bin, POLLIN, on_binary, p)) {
            return false;
        }
        return listen_binary_replies(p);
    }
    return true;
}

void proxy_udp_stop(proxy_t *p)
{
    for (unsigned i = 0; i < PROXY_UDP_PEERS; i++) {
        if (p->peers[i].used) {
            loop_unwatch(p->loop, p->peers[i].upstream);
            close(p->peers[i].upstream);
            p->peers[i].used = false;
        }
    }
}
