/* SPDX-License-Identifier: BSD-3-Clause */
#include "bin_udp_server.h"

#include <netinet/in.h>
#include <poll.h>
#include <string.h>
#include <unistd.h>

#include "hal_clock.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "wsg/wsg_bin.h"

#define DATAGRAM_MAX 65536
/* Reply budget, as for GCL over UDP (docs/behaviour.md, "UDP peers"): each
 * datagram a peer sends earns it REPLY_MULTIPLE times its size in reply
 * bytes, headers counted, so a spoofed sender cannot make the device send
 * much more than it received. Automatic updates are paid for by the peer
 * speaking within the peer timeout. */
#define UDP_HEADER_BYTES 28u
#define REPLY_MULTIPLE 8u
#define REPLY_CREDIT_MAX (64u * 1024u)

static bool silent_too_long(const bin_udp_peer_t *p, uint64_t now)
{
    return now - p->last_seen_us > p->server->peer_timeout_us;
}

/* One frame per datagram. Updates stop going out once the peer has been
 * silent for the peer timeout (the reap then ends them). */
static void write_frame(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    bin_udp_peer_t *p = ctx;
    uint32_t cost = (uint32_t)len + UDP_HEADER_BYTES;
    if (kind == WSG_MSG_UPDATE ? silent_too_long(p, hal_clock_now_us()) : p->credit < cost) {
        return; /* lost, as a datagram may be */
    }
    if (kind != WSG_MSG_UPDATE) {
        p->credit -= cost;
    }
    socklen_t len_to = p->reply_to.ss_family == AF_INET6 ? sizeof(struct sockaddr_in6)
                                                         : sizeof(struct sockaddr_in);
    sendto(p->server->fd, bytes, len, MSG_DONTWAIT | MSG_NOSIGNAL,
           (const struct sockaddr *)&p->reply_to, len_to);
}

static const wsg_conn_io_t bin_udp_io = {.write = write_frame};

static void forget(bin_udp_peer_t *p, wsg_close_reason_t reason)
{
    wsg_conn_close(&p->conn, reason);
    p->in_use = false;
}

static bin_udp_peer_t *find_peer(bin_udp_server_t *s, const struct sockaddr_storage *ss,
                                 socklen_t len)
{
    for (unsigned i = 0; i < BIN_UDP_PEERS_MAX; i++) {
        bin_udp_peer_t *p = &s->peers[i];
        if (p->in_use && p->from_len == len && memcmp(&p->from, ss, len) == 0) {
            return p;
        }
    }
    return NULL;
}

/* A free slot, or the least recently heard peer that runs no motion. */
static bin_udp_peer_t *claim_slot(bin_udp_server_t *s)
{
    bin_udp_peer_t *oldest = NULL;
    for (unsigned i = 0; i < BIN_UDP_PEERS_MAX; i++) {
        bin_udp_peer_t *p = &s->peers[i];
        if (!p->in_use) {
            return p;
        }
        if (!wsg_conn_owns_motion(&p->conn) &&
            (oldest == NULL || p->last_seen_us < oldest->last_seen_us)) {
            oldest = p;
        }
    }
    if (oldest != NULL) {
        host_log_peer(HAL_LOG_INFO, "binary udp %s: forgotten to make room", oldest->name);
        forget(oldest, WSG_CLOSE_EXPIRED);
    }
    return oldest;
}

static void set_reply_address(bin_udp_peer_t *p, int reply_port)
{
    p->reply_to = p->from;
    if (reply_port == 0) {
        return;
    }
    if (p->reply_to.ss_family == AF_INET6) {
        ((struct sockaddr_in6 *)&p->reply_to)->sin6_port = htons((uint16_t)reply_port);
    } else {
        ((struct sockaddr_in *)&p->reply_to)->sin_port = htons((uint16_t)reply_port);
    }
}

static bin_udp_peer_t *new_peer(bin_udp_server_t *s, const struct sockaddr_storage *ss,
                                socklen_t len)
{
    bin_udp_peer_t *p = claim_slot(s);
    if (p == NULL) {
        return NULL;
    }
    memset(p, 0, sizeof(*p));
    p->server = s;
    p->in_use = true;
    p->from = *ss;
    p->from_len = len;
    set_reply_address(p, s->reply_port);
    net_format_peer(ss, p->name, sizeof(p->name));
    wsg_conn_open(&p->conn, &s->gripper->device, &wsg_bin_driver, WSG_TRANSPORT_DATAGRAM,
                  &bin_udp_io, p);
    host_log_peer(HAL_LOG_INFO, "binary udp %s: new peer", p->name);
    return p;
}

static void on_datagram(void *ctx, int fd, short revents)
{
    (void)revents;
    bin_udp_server_t *s = ctx;
    static uint8_t buf[DATAGRAM_MAX];
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    memset(&ss, 0, sizeof(ss));
    ssize_t n = recvfrom(fd, buf, sizeof(buf), MSG_DONTWAIT, (struct sockaddr *)&ss, &len);
    if (n < 0 || net_is_own_address(&ss)) {
        return;
    }
    bin_udp_peer_t *p = find_peer(s, &ss, len);
    if (p != NULL && !wsg_conn_is_open(&p->conn)) {
        p->in_use = false; /* a device reset closed it: start over */
        p = NULL;
    }
    if (p == NULL && (p = new_peer(s, &ss, len)) == NULL) {
        return;
    }
    p->last_seen_us = hal_clock_now_us();
    uint64_t earned = ((uint64_t)n + UDP_HEADER_BYTES) * REPLY_MULTIPLE + p->credit;
    p->credit = earned < REPLY_CREDIT_MAX ? (uint32_t)earned : REPLY_CREDIT_MAX;
    gripper_feed(s->gripper, &p->conn, buf, (size_t)n, 1);
}

bool bin_udp_server_start(bin_udp_server_t *s, gripper_t *gripper, const char *addr, int port,
                          int reply_port, int peer_timeout_s)
{
    memset(s, 0, sizeof(*s));
    s->gripper = gripper;
    s->reply_port = reply_port;
    s->peer_timeout_us = (uint64_t)peer_timeout_s * 1000000u;
    s->fd = net_listen(SOCK_DGRAM, addr, port);
    return s->fd >= 0 && loop_watch(s->fd, POLLIN, on_datagram, s);
}

int bin_udp_server_port(const bin_udp_server_t *s)
{
    return s->fd >= 0 ? net_local_port(s->fd) : -1;
}

void bin_udp_server_reap(bin_udp_server_t *s)
{
    uint64_t now = hal_clock_now_us();
    for (unsigned i = 0; i < BIN_UDP_PEERS_MAX; i++) {
        bin_udp_peer_t *p = &s->peers[i];
        if (p->in_use && silent_too_long(p, now) && !wsg_conn_owns_motion(&p->conn)) {
            host_log_peer(HAL_LOG_INFO, "binary udp %s: silent too long; forgotten", p->name);
            forget(p, WSG_CLOSE_EXPIRED);
        }
    }
}

void bin_udp_server_stop(bin_udp_server_t *s)
{
    for (unsigned i = 0; i < BIN_UDP_PEERS_MAX; i++) {
        if (s->peers[i].in_use) {
            forget(&s->peers[i], WSG_CLOSE_EXPIRED);
        }
    }
    if (s->fd >= 0) {
        loop_unwatch(s->fd);
        close(s->fd);
    }
    s->fd = -1;
}
