/* SPDX-License-Identifier: BSD-3-Clause */
#include "udp_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "held_input.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "net_allow.h"
#include "wire.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"

#define GCL_PEERS_MAX 16
#define BINARY_PEERS_MAX 8
/* Datagrams read per wake-up: what a client sent together, while a flood
 * still lets the other descriptors of the wake-up be served. */
#define UDP_READS_PER_WAKE 64u

typedef struct {
    wsg_peer_t peer; /* first: the core's node is the allocation */
    udp_server_t *server;
    struct sockaddr_storage reply_to;
    socklen_t reply_len;
    wire_t *wire; /* its wire conditions; NULL: none (the default) */
    char name[64];
    char addr_text[INET6_ADDRSTRLEN]; /* the address alone, for --udp-stream-allow */
    held_input_t held; /* datagrams after a request waiting for the device's processor */
} udp_peer_t;

#define ACTIVE_SERVER(node) LIST_ITEM(node, udp_server_t, active_link)

static void set_active(udp_server_t *s)
{
    udp_servers_t *set = s->set;
    bool active = s->peers.known > 0;
    if (active == s->active) {
        return;
    }
    s->active = active;
    if (active) {
        list_push_front(&set->active, &s->active_link);
    } else {
        list_remove(&set->active, &s->active_link);
    }
}

udp_protocol_t udp_protocol_gcl(void)
{
    return (udp_protocol_t){&wsg_gcl_driver, "udp", GCL_PEERS_MAX, 0, false};
}

udp_protocol_t udp_protocol_binary(int reply_port)
{
    return (udp_protocol_t){&wsg_bin_driver, "binary udp", BINARY_PEERS_MAX, reply_port, false};
}

/* The first message a peer loses over its budget is logged, with the way
 * out for a stream (rate-limited with every message peers cause). */
static void log_first_drop(const udp_server_t *s, const udp_peer_t *p, wsg_msg_kind_t kind)
{
    if (kind != WSG_MSG_UPDATE && p->peer.dropped == 1) {
        host_log_peer(HAL_LOG_WARN, "%s %s: reply budget spent; lines dropped", s->proto.label,
                      p->name);
    } else if (kind == WSG_MSG_UPDATE && p->peer.updates_dropped == 1) {
        host_log_peer(HAL_LOG_WARN,
                      "%s %s: stream paused: updates are paid by what the peer sends, and its "
                      "budget is spent; they resume when it sends again (for a client that "
                      "subscribes and then only listens: --udp-stream-allow %s)",
                      s->proto.label, p->name, p->addr_text);
    }
}

/* Sends from the server's source address when it has one (a shared
 * socket: the reply leaves from the address the peer wrote to). */
static void send_datagram(const udp_server_t *s, const char *bytes, size_t len,
                          const struct sockaddr_storage *to, socklen_t to_len)
{
    struct iovec iov = {.iov_base = (void *)bytes, .iov_len = len};
    struct msghdr msg = {
        .msg_name = (void *)to, .msg_namelen = to_len, .msg_iov = &iov, .msg_iovlen = 1};
    union {
        char bytes[CMSG_SPACE(sizeof(struct in_pktinfo))];
        struct cmsghdr align;
    } control;
    if (s->source.s_addr != 0) {
        memset(&control, 0, sizeof(control));
        msg.msg_control = control.bytes;
        msg.msg_controllen = sizeof(control.bytes);
        struct cmsghdr *cm = CMSG_FIRSTHDR(&msg);
        cm->cmsg_level = IPPROTO_IP;
        cm->cmsg_type = IP_PKTINFO;
        cm->cmsg_len = CMSG_LEN(sizeof(struct in_pktinfo));
        struct in_pktinfo info = {.ipi_spec_dst = s->source};
        memcpy(CMSG_DATA(cm), &info, sizeof(info));
    }
    sendmsg(s->fd, &msg, MSG_DONTWAIT | MSG_NOSIGNAL);
}

static void write_message(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    udp_peer_t *p = ctx;
    udp_server_t *s = p->server;
    /* a datagram that cannot go out now is lost, as on the wire */
    if (!wsg_peers_may_send(&s->peers, &p->peer, len, kind)) {
        log_first_drop(s, p, kind);
        return;
    }
    if (p->wire != NULL) {
        wire_send(p->wire, bytes, len, kind); /* later, lost, doubled (wire.c) */
        return;
    }
    send_datagram(s, bytes, len, &p->reply_to, p->reply_len);
}

/* The device served the request the peer held (a timing profile): its
 * datagrams that came meanwhile go in now, in order. */
static void resume_input(void *ctx)
{
    udp_peer_t *p = ctx;
    held_input_feed(&p->held, &p->peer.conn);
}

static const wsg_conn_io_t udp_io = {.write = write_message, .resume = resume_input};

static bool wire_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    const udp_peer_t *p = ctx;
    (void)kind;
    send_datagram(p->server, bytes, len, &p->reply_to, p->reply_len);
    return true;
}

static void wire_no_reset(void *ctx)
{
    (void)ctx; /* a datagram socket has no connection to reset */
}

static void wire_touch(void *ctx)
{
    const udp_peer_t *p = ctx;
    gripper_touch(p->server->gripper);
}

static const wire_port_t udp_wire_port = {
    .deliver = wire_write, .reset = wire_no_reset, .touch = wire_touch};

static uint64_t wire_stream(const udp_peer_t *p)
{
    return ((uint64_t)p->server->gripper->index << 32) | (wsg_conn_id(&p->peer.conn) & 0xffffffffu);
}

static void set_wire(udp_peer_t *p, const wire_spec_t *spec)
{
    wire_flush_close(p->wire);
    p->wire = wire_open(p->server->set->wires, spec, wire_stream(p), true, &udp_wire_port, p);
}

static void log_forgetting(void *ctx, wsg_peer_t *peer, wsg_peer_forget_t why)
{
    udp_server_t *s = ctx;
    udp_peer_t *p = peer->port_ctx;
    if (peer->dropped > 0) {
        host_log_peer(HAL_LOG_INFO, "%s %s: %lu lines dropped over the reply budget",
                      s->proto.label, p->name, (unsigned long)peer->dropped);
    }
    if (peer->updates_dropped > 0) {
        host_log_peer(HAL_LOG_INFO, "%s %s: %lu updates dropped over the budget", s->proto.label,
                      p->name, (unsigned long)peer->updates_dropped);
    }
    if (why == WSG_PEER_MADE_ROOM) {
        host_log_peer(HAL_LOG_INFO, "%s %s: forgotten to make room for a new peer", s->proto.label,
                      p->name);
    } else if (why == WSG_PEER_SILENT) {
        host_log_peer(HAL_LOG_INFO, "%s %s: silent for %llu s; forgotten%s", s->proto.label,
                      p->name, (unsigned long long)(s->peers.rules.timeout_us / 1000000u),
                      wsg_conn_busy(&peer->conn) ? " (AUTOSEND ended)" : "");
    } else if (why == WSG_PEER_CUT) {
        host_logf(HAL_LOG_WARN, "%s %s: peer cut (control channel)", s->proto.label, p->name);
    }
}

static void release_peer(void *ctx, wsg_peer_t *peer)
{
    udp_server_t *s = ctx;
    udp_peer_t *p = peer->port_ctx;
    gripper_touch(s->gripper);
    held_input_free(&p->held);
    wire_close(p->wire);
    free(p);
}

static const wsg_peer_port_t peer_port = {.forgetting = log_forgetting, .release = release_peer};

/* The reply address: the sender's, at the protocol's reply port if any. */
static void set_reply_address(udp_peer_t *p, const struct sockaddr_storage *from, socklen_t len,
                              int reply_port)
{
    p->reply_to = *from;
    p->reply_len = len;
    if (reply_port == 0) {
        return;
    }
    if (from->ss_family == AF_INET6) {
        ((struct sockaddr_in6 *)&p->reply_to)->sin6_port = htons((uint16_t)reply_port);
    } else {
        ((struct sockaddr_in *)&p->reply_to)->sin_port = htons((uint16_t)reply_port);
    }
}

static udp_peer_t *new_peer(udp_server_t *s, const wsg_peer_addr_t *addr,
                            const struct sockaddr_storage *ss, socklen_t len)
{
    udp_peer_t *p = wsg_peers_make_room(&s->peers) ? calloc(1, sizeof(*p)) : NULL;
    if (p == NULL) {
        char name[64];
        net_format_peer(ss, name, sizeof(name));
        host_log_peer(HAL_LOG_WARN, "%s %s: refused, %u live peers", s->proto.label, name,
                      s->proto.max_peers);
        return NULL;
    }
    wsg_peers_add(&s->peers, &p->peer, addr);
    p->peer.port_ctx = p;
    p->server = s;
    set_reply_address(p, ss, len, s->proto.reply_port);
    net_format_peer(ss, p->name, sizeof(p->name));
    net_format_address(ss, p->addr_text, sizeof(p->addr_text));
    /* A loopback peer is this host's own client: no other host can send
     * from its address (Linux drops such a martian source), and its stream
     * cannot reach anyone else, so it gets the real device's endless one. */
    p->peer.stream_free =
        net_allow_loopback(ss) || net_allow_match(&s->gripper->opts->udp_stream_allow, ss);
    wsg_conn_open(&p->peer.conn, &s->gripper->device, s->proto.driver, WSG_TRANSPORT_DATAGRAM,
                  &udp_io, p);
    set_wire(p, &s->set->wires->all);
    host_log_peer(HAL_LOG_INFO, "%s %s: new peer", s->proto.label, p->name);
    return p;
}

/* A datagram from one of our own sockets would start the server answering
 * itself (or a twin on the same host); it is dropped unanswered. */
static bool from_ourselves(const udp_server_t *s, const struct sockaddr_storage *ss)
{
    if (!net_is_own_address(s->set->net, ss)) {
        return false;
    }
    char name[64];
    net_format_peer(ss, name, sizeof(name));
    host_log_peer(HAL_LOG_WARN, "%s %s: datagram from the server's own address ignored",
                  s->proto.label, name);
    return true;
}

/* The datagram's destination address (IP_PKTINFO), port 0; AF_UNSPEC
 * when the socket does not report it. */
static void destination_of(struct msghdr *msg, struct sockaddr_storage *dst)
{
    memset(dst, 0, sizeof(*dst));
    for (struct cmsghdr *cm = CMSG_FIRSTHDR(msg); cm != NULL; cm = CMSG_NXTHDR(msg, cm)) {
        if (cm->cmsg_level == IPPROTO_IP && cm->cmsg_type == IP_PKTINFO) {
            struct in_pktinfo info;
            memcpy(&info, CMSG_DATA(cm), sizeof(info));
            struct sockaddr_in *v4 = (struct sockaddr_in *)dst;
            v4->sin_family = AF_INET;
            v4->sin_addr = info.ipi_addr;
        }
    }
}

/* The server a datagram belongs to: s itself, or for a shared socket the
 * one its route() names (NULL: dropped, logged). */
static udp_server_t *owner_of(udp_server_t *s, struct msghdr *msg)
{
    if (s->route == NULL) {
        return s;
    }
    struct sockaddr_storage dst;
    destination_of(msg, &dst);
    udp_server_t *owner = s->route(s->route_ctx, &dst);
    if (owner == NULL) {
        char name[64];
        net_format_peer(msg->msg_name, name, sizeof(name));
        host_log_peer(HAL_LOG_WARN,
                      "%s %s: datagram refused, its destination is no device's address",
                      s->proto.label, name);
    }
    return owner;
}

/* Feeds a datagram; under a timing profile, one that comes while the
 * peer's request waits for the device's processor waits too. */
static void feed_datagram(udp_server_t *s, udp_peer_t *p, const uint8_t *buf, size_t n)
{
    size_t taken =
        held_input_empty(&p->held) ? gripper_feed(s->gripper, &p->peer.conn, buf, n, 1) : 0;
    if (taken < n && !held_input_keep(&p->held, buf + taken, n - taken, true)) {
        host_log_peer(HAL_LOG_WARN, "%s %s: too much input waiting; datagram dropped",
                      s->proto.label, p->name);
    }
}

/* Reads and feeds one datagram; false when none was waiting. */
static bool receive_datagram(udp_server_t *s, int fd)
{
    uint8_t *buf = s->set->datagram;
    struct sockaddr_storage ss;
    union {
        char bytes[CMSG_SPACE(sizeof(struct in_pktinfo))];
        struct cmsghdr align;
    } control;
    struct iovec iov = {.iov_base = buf, .iov_len = UDP_DATAGRAM_MAX};
    struct msghdr msg = {.msg_name = &ss,
                         .msg_namelen = sizeof(ss),
                         .msg_iov = &iov,
                         .msg_iovlen = 1,
                         .msg_control = control.bytes,
                         .msg_controllen = sizeof(control.bytes)};
    memset(&ss, 0, sizeof(ss));
    ssize_t n = recvmsg(fd, &msg, MSG_DONTWAIT);
    socklen_t len = msg.msg_namelen;
    if (n < 0) {
        return false;
    }
    if (len > WSG_PEER_ADDR_BYTES || from_ourselves(s, &ss) || (s = owner_of(s, &msg)) == NULL) {
        return true;
    }
    wsg_peer_addr_t addr = {.len = (uint8_t)len};
    memcpy(addr.bytes, &ss, len);
    /* after BYE or a device reset the peer starts over */
    wsg_peer_t *peer = wsg_peers_session_for(&s->peers, &addr);
    udp_peer_t *p = peer != NULL ? peer->port_ctx : new_peer(s, &addr, &ss, len);
    set_active(s);
    s->set->deadline_moved = true;
    if (p == NULL) {
        return true;
    }
    /* a wire may lose the request or hand it over twice */
    unsigned copies = p->wire != NULL ? wire_receive_copies(p->wire) : 1u;
    for (unsigned i = 0; i < copies; i++) {
        wsg_peers_heard(&s->peers, &p->peer, (size_t)n);
        feed_datagram(s, p, buf, (size_t)n);
    }
    gripper_touch(s->gripper); /* its tick asks the servers' moved deadlines again */
    return true;
}

/* What is waiting is read in one go (up to UDP_READS_PER_WAKE): a control
 * STEP that arrived after these datagrams, in the same wake-up, must not
 * run before them (the pass's settle runs it before the next wait). */
static void on_datagram(void *ctx, int fd, short revents)
{
    (void)revents;
    unsigned reads = 0;
    while (reads < UDP_READS_PER_WAKE && receive_datagram(ctx, fd)) {
        reads++;
    }
}

bool udp_server_start(udp_server_t *s, udp_servers_t *set, gripper_t *g,
                      const udp_protocol_t *proto, const char *addr, int port, int peer_timeout_s)
{
    memset(s, 0, sizeof(*s));
    s->set = set;
    s->gripper = g;
    s->proto = *proto;
    wsg_peer_rules_t rules = WSG_PEER_RULES_DEFAULT(proto->max_peers, peer_timeout_s);
    wsg_peers_init(&s->peers, &rules, &peer_port, s, NULL, 0);
    s->fd = proto->optional ? net_listen_optional(set->net, SOCK_DGRAM, addr, port)
                            : net_listen(set->net, SOCK_DGRAM, addr, port);
    s->port = s->fd >= 0 ? net_local_port(s->fd) : -1;
    return s->fd >= 0 && loop_watch(set->loop, s->fd, POLLIN, on_datagram, s);
}

bool udp_server_start_shared(udp_server_t *s, udp_servers_t *set, const udp_protocol_t *proto,
                             int port, udp_route_t route, void *ctx)
{
    int one = 1;
    if (!udp_server_start(s, set, NULL, proto, "0.0.0.0", port, 0)) {
        return false;
    }
    s->route = route;
    s->route_ctx = ctx;
    return setsockopt(s->fd, IPPROTO_IP, IP_PKTINFO, &one, sizeof(one)) == 0;
}

void udp_server_attach(udp_server_t *s, gripper_t *g, const udp_protocol_t *proto,
                       const udp_server_t *front, struct in_addr source, int peer_timeout_s)
{
    memset(s, 0, sizeof(*s));
    s->set = front->set;
    s->gripper = g;
    s->proto = *proto;
    s->fd = front->fd;
    s->port = front->port;
    s->shares_fd = true;
    s->source = source;
    wsg_peer_rules_t rules = WSG_PEER_RULES_DEFAULT(proto->max_peers, peer_timeout_s);
    wsg_peers_init(&s->peers, &rules, &peer_port, s, NULL, 0);
}

int udp_server_port(const udp_server_t *s)
{
    return s->fd >= 0 ? s->port : -1;
}

void udp_server_reap(udp_servers_t *set)
{
    LIST_EACH_SAFE (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        wsg_peers_reap(&s->peers);
        set_active(s);
    }
}

uint64_t udp_server_next_deadline_us(udp_servers_t *set)
{
    set->deadline_moved = false;
    uint64_t due = UINT64_MAX;
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        uint64_t server_due = wsg_peers_next_deadline_us(&s->peers);
        due = server_due < due ? server_due : due;
    }
    return due;
}

bool udp_server_cut(udp_servers_t *set, const wsg_conn_t *conn)
{
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        wsg_peer_t *peer = wsg_peers_by_conn(&s->peers, conn);
        if (peer != NULL) {
            wsg_peers_forget(&s->peers, peer, WSG_PEER_CUT);
            set_active(s);
            return true;
        }
    }
    return false;
}

/* Every known peer of the set (conn NULL), or conn's, gets spec. */
unsigned udp_server_set_wire(udp_servers_t *set, const wsg_conn_t *conn, const wire_spec_t *spec)
{
    unsigned done = 0;
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        for (wsg_conn_t *c = s->gripper != NULL ? wsg_device_conn_first(&s->gripper->device) : NULL;
             c != NULL; c = wsg_conn_next(c)) {
            wsg_peer_t *peer = wsg_peers_by_conn(&s->peers, c);
            if (peer != NULL && (conn == NULL || c == conn)) {
                set_wire(peer->port_ctx, spec);
                done++;
            }
        }
    }
    return done;
}

const wire_t *udp_server_wire(const udp_servers_t *set, const wsg_conn_t *conn)
{
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        const wsg_peer_t *peer = wsg_peers_by_conn(&s->peers, conn);
        if (peer != NULL) {
            return ((const udp_peer_t *)peer)->wire;
        }
    }
    return NULL;
}

const char *udp_server_peer_name(const udp_servers_t *set, const wsg_conn_t *conn)
{
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        wsg_peer_t *peer = wsg_peers_by_conn(&s->peers, conn);
        if (peer != NULL) {
            return ((const udp_peer_t *)peer)->name; /* the node is the allocation's first member */
        }
    }
    return NULL;
}

unsigned long udp_server_updates_dropped(const udp_servers_t *set, const wsg_conn_t *conn)
{
    LIST_EACH (node, &set->active) {
        udp_server_t *s = ACTIVE_SERVER(node);
        const wsg_peer_t *peer = wsg_peers_by_conn(&s->peers, conn);
        if (peer != NULL) {
            return peer->updates_dropped;
        }
    }
    return 0;
}

void udp_server_close_all(udp_server_t *s)
{
    wsg_peers_forget_all(&s->peers, WSG_PEER_STOPPED);
    set_active(s);
}

void udp_server_stop(udp_server_t *s)
{
    udp_server_close_all(s);
    if (s->shares_fd) {
        s->fd = -1;
    } else if (s->fd >= 0) {
        loop_unwatch(s->set->loop, s->fd);
        close(s->fd);
        s->fd = -1;
    }
}
