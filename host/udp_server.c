#include "udp_server.h"

#include <errno.h>
#include <poll.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "gripper.h"
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

typedef struct {
    bool in_use;
    struct sockaddr_storage addr;
    socklen_t addr_len;
    wsg_conn_t conn;
    uint64_t last_seen_us;
    uint32_t credit;    /* reply bytes it may still be sent */
    double tokens;      /* datagrams it may still be sent now */
    uint64_t refill_us; /* when tokens were last topped up */
    unsigned long dropped;
    char name[64];
} udp_peer_t;

static struct {
    int fd;
    uint64_t peer_timeout_us;
    udp_peer_t peers[PEERS_MAX];
} udp = {.fd = -1};

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
    return now - p->last_seen_us > udp.peer_timeout_us;
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
        sendto(udp.fd, line, len, MSG_DONTWAIT | MSG_NOSIGNAL, (const struct sockaddr *)&p->addr,
               p->addr_len);
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
    p->in_use = false;
}

static udp_peer_t *find_peer(const struct sockaddr_storage *ss, socklen_t len)
{
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (p->in_use && p->addr_len == len && memcmp(&p->addr, ss, len) == 0) {
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

/* A free slot, or the least recently heard idle peer's; NULL when every
 * peer is live. */
static udp_peer_t *claim_slot(void)
{
    uint64_t now = hal_clock_now_us();
    udp_peer_t *oldest = NULL;
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (!p->in_use) {
            return p;
        }
        if (!is_live(p, now) && (oldest == NULL || p->last_seen_us < oldest->last_seen_us)) {
            oldest = p;
        }
    }
    if (oldest != NULL) {
        host_log_peer(HAL_LOG_INFO, "udp %s: forgotten to make room for a new peer", oldest->name);
        forget(oldest, WSG_CLOSE_EXPIRED);
    }
    return oldest;
}

static udp_peer_t *new_peer(const struct sockaddr_storage *ss, socklen_t len)
{
    udp_peer_t *p = claim_slot();
    if (p == NULL) {
        char name[64];
        net_format_peer(ss, name, sizeof(name));
        host_log_peer(HAL_LOG_WARN, "udp %s: refused, %d live peers", name, PEERS_MAX);
        return NULL;
    }
    memset(p, 0, sizeof(*p));
    wsg_conn_open(&p->conn, &gripper_served()->device, &wsg_gcl_driver, WSG_TRANSPORT_DATAGRAM,
                  &udp_io, p);
    p->in_use = true;
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
    (void)ctx;
    (void)revents;
    static uint8_t buf[DATAGRAM_MAX];
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    memset(&ss, 0, sizeof(ss));
    ssize_t n = recvfrom(fd, buf, sizeof(buf), MSG_DONTWAIT, (struct sockaddr *)&ss, &len);
    if (n < 0 || from_ourselves(&ss)) {
        return;
    }
    udp_peer_t *p = find_peer(&ss, len);
    if (p == NULL && (p = new_peer(&ss, len)) == NULL) {
        return;
    }
    p->last_seen_us = hal_clock_now_us();
    uint64_t earned = ((uint64_t)n + UDP_HEADER_BYTES) * REPLY_MULTIPLE + p->credit;
    p->credit = earned < REPLY_CREDIT_MAX ? (uint32_t)earned : REPLY_CREDIT_MAX;
    gripper_feed(gripper_served(), &p->conn, buf, (size_t)n, 1);
}

bool udp_server_start(const char *addr, int port, int peer_timeout_s)
{
    udp.peer_timeout_us = (uint64_t)peer_timeout_s * 1000000u;
    udp.fd = net_listen(SOCK_DGRAM, addr, port);
    return udp.fd >= 0 && loop_watch(udp.fd, POLLIN, on_datagram, NULL);
}

int udp_server_port(void)
{
    return udp.fd >= 0 ? net_local_port(udp.fd) : -1;
}

void udp_server_reap(void)
{
    uint64_t now = hal_clock_now_us();
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (!p->in_use) {
            continue;
        }
        if (wsg_conn_wants_close(&p->conn)) {
            forget(p, WSG_CLOSE_ANNOUNCED);
        } else if (silent_too_long(p, now) && !wsg_conn_owns_motion(&p->conn)) {
            host_log_peer(HAL_LOG_INFO, "udp %s: silent for %llu s; forgotten%s", p->name,
                          (unsigned long long)(udp.peer_timeout_us / 1000000u),
                          wsg_conn_busy(&p->conn) ? " (AUTOSEND ended)" : "");
            forget(p, WSG_CLOSE_EXPIRED);
        }
    }
}

bool udp_server_cut(const wsg_conn_t *conn)
{
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (p->in_use && &p->conn == conn) {
            host_logf(HAL_LOG_WARN, "udp %s: peer cut (control channel)", p->name);
            forget(p, WSG_CLOSE_DROPPED);
            return true;
        }
    }
    return false;
}

void udp_server_close_all(void)
{
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        if (udp.peers[i].in_use) {
            forget(&udp.peers[i], WSG_CLOSE_EXPIRED);
        }
    }
}

void udp_server_stop(void)
{
    udp_server_close_all();
    if (udp.fd >= 0) {
        loop_unwatch(udp.fd);
        close(udp.fd);
        udp.fd = -1;
    }
}
