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

#define PEERS_MAX 16
#define DATAGRAM_MAX 65536
/* A peer without AUTOSEND that sends nothing for this long is forgotten. */
#define PEER_IDLE_US (60u * 1000000u)

typedef struct {
    bool in_use;
    struct sockaddr_storage addr;
    socklen_t addr_len;
    wsg_session_t *session;
    uint64_t last_seen_us;
    char name[64];
} udp_peer_t;

static struct {
    int fd;
    udp_peer_t peers[PEERS_MAX];
} udp = {.fd = -1};

static void write_line(void *ctx, const char *line, size_t len, wsg_line_kind_t kind)
{
    const udp_peer_t *p = ctx;
    (void)kind; /* a datagram that cannot go out now is lost, as on the wire */
    sendto(udp.fd, line, len, MSG_DONTWAIT | MSG_NOSIGNAL, (const struct sockaddr *)&p->addr,
           p->addr_len);
}

static const wsg_session_io_t udp_io = {.write_line = write_line};

static void forget(udp_peer_t *p, wsg_close_reason_t reason)
{
    wsg_session_close(gripper_device(), p->session, reason);
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

/* A free slot, or the least recently heard peer's. */
static udp_peer_t *claim_slot(void)
{
    udp_peer_t *oldest = &udp.peers[0];
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (!p->in_use) {
            return p;
        }
        if (p->last_seen_us < oldest->last_seen_us) {
            oldest = p;
        }
    }
    host_logf(HAL_LOG_INFO, "udp %s: forgotten to make room for a new peer", oldest->name);
    forget(oldest, WSG_CLOSE_EXPIRED);
    return oldest;
}

static udp_peer_t *peer_for(const struct sockaddr_storage *ss, socklen_t len)
{
    udp_peer_t *p = find_peer(ss, len);
    if (p != NULL) {
        return p;
    }
    p = claim_slot();
    memset(p, 0, sizeof(*p));
    p->session = wsg_session_open(gripper_device(), WSG_TRANSPORT_DATAGRAM, &udp_io, p);
    if (p->session == NULL) {
        return NULL;
    }
    p->in_use = true;
    p->addr = *ss;
    p->addr_len = len;
    net_format_peer(ss, p->name, sizeof(p->name));
    host_logf(HAL_LOG_INFO, "udp %s: new peer", p->name);
    return p;
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
    if (n < 0) {
        return;
    }
    udp_peer_t *p = peer_for(&ss, len);
    if (p == NULL) {
        return;
    }
    p->last_seen_us = hal_clock_now_us();
    gripper_feed(p->session, buf, (size_t)n, 1);
}

bool udp_server_start(const char *addr, int port)
{
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
        if (wsg_session_wants_close(p->session)) {
            forget(p, WSG_CLOSE_ANNOUNCED);
        } else if (!wsg_session_has_autosend(p->session) && now - p->last_seen_us > PEER_IDLE_US) {
            forget(p, WSG_CLOSE_EXPIRED);
        }
    }
}

bool udp_server_cut(const wsg_session_t *session)
{
    for (unsigned i = 0; i < PEERS_MAX; i++) {
        udp_peer_t *p = &udp.peers[i];
        if (p->in_use && p->session == session) {
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
