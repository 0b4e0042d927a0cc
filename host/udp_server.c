/* SPDX-License-Identifier: BSD-3-Clause */
#include "udp_server.h"

#include <errno.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "hal_clock.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "wsg/wsg_gcl.h"

#define PEERS_MAX 16
#define DATAGRAM_MAX 65536
/* A peer heard from this recently is never pushed out for a new one. */
#define PEER_RECENT_US (2u * 1000000u)
/* Reply budget (docs/behaviour.md, "UDP peers"): every datagram a peer sends
 * earns it REPLY_MULTIPLE times its size in reply bytes, headers counted. */
#define UDP_HEADER_BYTES 28u
#define REPLY_MULTIPLE 8u
#define REPLY_CREDIT_MAX (64u * 1024u)
/* And whatever it earned, at most PEER_BURST datagrams, refilled at
 * PEER_RATE per simulated second (AUTOSEND at most 600/s included). */
#define PEER_BURST 1000.0
#define PEER_RATE 1000.0

struct udp_peer {
    udp_server_t *server;
    udp_peer_t *prev, *next; /* every server's peers, oldest first */
    struct sockaddr_storage addr;
    socklen_t addr_len;
    wsg_conn_t conn;
    uint64_t last_seen_us;
    uint32_t credit;    /* reply bytes it may still be sent */
    double tokens;      /* datagrams it may still be sent now */
    uint64_t refill_us; /* when tokens were last topped up */
    unsigned long dropped;
    char name[64];
};

/* The peers of every server: the reap and the deadline visit these only. */
static struct {
    udp_peer_t *first, *last;
} udp;

static void link_peer(udp_peer_t *p)
{
    p->prev = udp.last;
    p->next = NULL;
    if (udp.last != NULL) {
        udp.last->next = p;
    } else {
        udp.first = p;
    }
    udp.last = p;
    p->server->peers++;
}

static void unlink_peer(udp_peer_t *p)
{
    if (p->prev != NULL) {
        p->prev->next = p->next;
    } else {
        udp.first = p->next;
    }
    if (p->next != NULL) {
        p->next->prev = p->prev;
    } else {
        udp.last = p->prev;
    }
    p->server->peers--;
}

static void refill(udp_peer_t *p, uint64_t now)
{
    if (now > p->refill_us) {
        p->tokens += (double)(now - p->refill_us) * PEER_RATE / 1e6;
        p->tokens = p->tokens < PEER_BURST ? p->tokens : PEER_BURST;
        p->refill_us = now;
    }
}

static bool silent_too_long(const udp_peer_t *p, uint64_t now)
{
    return now - p->last_seen_us > p->server->peer_timeout_us;
}

/* Whether this line may go out; AUTOSEND lines are paid for by the peer
 * speaking within the timeout, replies by the bytes it sent. */
static bool within_budget(udp_peer_t *p, size_t len, wsg_msg_kind_t kind)
{
    uint64_t now = hal_clock_now_us();
    uint32_t cost = (uint32_t)len + UDP_HEADER_BYTES;
    if (kind == WSG_MSG_UPDATE && silent_too_long(p, now)) {
        return false; /* the reap ends the subscription and says so */
    }
    refill(p, now);
    if (p->tokens < 1.0 || (kind != WSG_MSG_UPDATE && p->credit < cost)) {
        if (p->dropped++ == 0) {
            host_log_peer(HAL_LOG_WARN, "udp %s: reply budget spent; lines dropped", p->name);
        }
        return false;
    }
    p->tokens -= 1.0;
    if (kind != WSG_MSG_UPDATE) {
        p->credit -= cost;
    }
    return true;
}

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    udp_peer_t *p = ctx;
    /* a datagram that cannot go out now is lost, as on the wire */
    if (within_budget(p, len, kind)) {
        sendto(p->server->fd, line, len, MSG_DONTWAIT | MSG_NOSIGNAL,
               (const struct sockaddr *)&p->addr, p->addr_len);
    }
}

static const wsg_conn_io_t udp_io = {.write = write_line};

static void forget(udp_peer_t *p, wsg_close_reason_t reason)
{
    if (p->dropped > 0) {
        host_log_peer(HAL_LOG_INFO, "udp %s: %lu lines dropped over the reply budget", p->name,
                      p->dropped);
    }
    wsg_conn_close(&p->conn, reason);
    gripper_touch(p->server->gripper);
    unlink_peer(p);
    free(p);
}

static udp_peer_t *find_peer(const udp_server_t *s, const struct sockaddr_storage *ss,
                             socklen_t len)
{
    for (udp_peer_t *p = udp.first; p != NULL; p = p->next) {
        if (p->server == s && p->addr_len == len && memcmp(&p->addr, ss, len) == 0) {
            return p;
        }
    }
    return NULL;
}

/* Running a motion, listening to AUTOSEND (it ends with the peer timeout)
 * or heard from lately: its FIN, stream and settings must stay. */
static bool is_live(const udp_peer_t *p, uint64_t now)
{
    return wsg_conn_busy(&p->conn) || now - p->last_seen_us < PEER_RECENT_US;
}

/* Room for one more peer: true while fewer than PEERS_MAX are known, or
 * after forgetting the least recently heard idle one; false when every peer
 * is live. */
static bool make_room(const udp_server_t *s)
{
    if (s->peers < PEERS_MAX) {
        return true;
    }
    uint64_t now = hal_clock_now_us();
    udp_peer_t *oldest = NULL;
    for (udp_peer_t *p = udp.first; p != NULL; p = p->next) {
        bool idle = p->server == s && !is_live(p, now);
        if (idle && (oldest == NULL || p->last_seen_us < oldest->last_seen_us)) {
            oldest = p;
        }
    }
    if (oldest != NULL) {
        host_log_peer(HAL_LOG_INFO, "udp %s: forgotten to make room for a new peer", oldest->name);
        forget(oldest, WSG_CLOSE_EXPIRED);
    }
    return oldest != NULL;
}

static udp_peer_t *new_peer(udp_server_t *s, const struct sockaddr_storage *ss, socklen_t len)
{
    udp_peer_t *p = make_room(s) ? calloc(1, sizeof(*p)) : NULL;
    if (p == NULL) {
        char name[64];
        net_format_peer(ss, name, sizeof(name));
        host_log_peer(HAL_LOG_WARN, "udp %s: refused, %d live peers", name, PEERS_MAX);
        return NULL;
    }
    p->server = s;
    wsg_conn_open(&p->conn, &s->gripper->device, &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM, &udp_io,
                  p);
    link_peer(p);
    p->addr = *ss;
    p->addr_len = len;
    p->tokens = PEER_BURST;
    p->refill_us = hal_clock_now_us();
    net_format_peer(ss, p->name, sizeof(p->name));
    host_log_peer(HAL_LOG_INFO, "udp %s: new peer", p->name);
    return p;
}

/* A datagram from one of our own sockets would start the server answering
 * itself (or a twin on the same host); it is dropped unanswered. */
static bool from_ourselves(const struct sockaddr_storage *ss)
{
    if (!net_is_own_address(ss)) {
        return false;
    }
    char name[64];
    net_format_peer(ss, name, sizeof(name));
    host_log_peer(HAL_LOG_WARN, "udp %s: datagram from the server's own address ignored", name);
    return true;
}

static void on_datagram(void *ctx, int fd, short revents)
{
    udp_server_t *s = ctx;
    (void)revents;
    static uint8_t buf[DATAGRAM_MAX];
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    memset(&ss, 0, sizeof(ss));
    ssize_t n = recvfrom(fd, buf, sizeof(buf), MSG_DONTWAIT, (struct sockaddr *)&ss, &len);
    if (n < 0 || from_ourselves(&ss)) {
        return;
    }
    udp_peer_t *p = find_peer(s, &ss, len);
    if (p == NULL && (p = new_peer(s, &ss, len)) == NULL) {
        return;
    }
    p->last_seen_us = hal_clock_now_us();
    uint64_t earned = ((uint64_t)n + UDP_HEADER_BYTES) * REPLY_MULTIPLE + p->credit;
    p->credit = earned < REPLY_CREDIT_MAX ? (uint32_t)earned : REPLY_CREDIT_MAX;
    gripper_feed(s->gripper, &p->conn, buf, (size_t)n, 1);
}

bool udp_server_start(udp_server_t *s, gripper_t *g, const char *addr, int port, int peer_timeout_s)
{
    memset(s, 0, sizeof(*s));
    s->gripper = g;
    s->peer_timeout_us = (uint64_t)peer_timeout_s * 1000000u;
    s->fd = net_listen(SOCK_DGRAM, addr, port);
    return s->fd >= 0 && loop_watch(s->fd, POLLIN, on_datagram, s);
}

int udp_server_port(const udp_server_t *s)
{
    return s->fd >= 0 ? net_local_port(s->fd) : -1;
}

void udp_server_reap(void)
{
    uint64_t now = hal_clock_now_us();
    udp_peer_t *next;
    for (udp_peer_t *p = udp.first; p != NULL; p = next) {
        next = p->next;
        if (wsg_conn_wants_close(&p->conn)) {
            forget(p, WSG_CLOSE_ANNOUNCED);
        } else if (silent_too_long(p, now) && !wsg_conn_owns_motion(&p->conn)) {
            host_log_peer(HAL_LOG_INFO, "udp %s: silent for %llu s; forgotten%s", p->name,
                          (unsigned long long)(p->server->peer_timeout_us / 1000000u),
                          wsg_conn_busy(&p->conn) ? " (AUTOSEND ended)" : "");
            forget(p, WSG_CLOSE_EXPIRED);
        }
    }
}

/* A peer is forgotten once silent for longer than the timeout: due one
 * microsecond past it. One kept past it for its running motion is looked at
 * again when the motion's own deadlines wake the loop. */
uint64_t udp_server_next_deadline_us(void)
{
    uint64_t now = hal_clock_now_us();
    uint64_t due = UINT64_MAX;
    for (udp_peer_t *p = udp.first; p != NULL; p = p->next) {
        uint64_t silent_at = p->last_seen_us + p->server->peer_timeout_us + 1u;
        due = silent_at > now && silent_at < due ? silent_at : due;
    }
    return due;
}

bool udp_server_cut(const wsg_conn_t *conn)
{
    for (udp_peer_t *p = udp.first; p != NULL; p = p->next) {
        if (&p->conn == conn) {
            host_logf(HAL_LOG_WARN, "udp %s: peer cut (control channel)", p->name);
            forget(p, WSG_CLOSE_DROPPED);
            return true;
        }
    }
    return false;
}

const char *udp_server_peer_name(const wsg_conn_t *conn)
{
    for (const udp_peer_t *p = udp.first; p != NULL; p = p->next) {
        if (&p->conn == conn) {
            return p->name;
        }
    }
    return NULL;
}

void udp_server_close_all(udp_server_t *s)
{
    udp_peer_t *next;
    for (udp_peer_t *p = udp.first; p != NULL; p = next) {
        next = p->next;
        if (p->server == s) {
            forget(p, WSG_CLOSE_EXPIRED);
        }
    }
}

void udp_server_stop(udp_server_t *s)
{
    udp_server_close_all(s);
    if (s->fd >= 0) {
        loop_unwatch(s->fd);
        close(s->fd);
        s->fd = -1;
    }
}
