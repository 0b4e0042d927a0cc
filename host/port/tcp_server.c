/* SPDX-License-Identifier: BSD-3-Clause */
#include "tcp_server.h"

#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "hal_clock.h"
#include "held_input.h"
#include "listener.h"
#include "log.h"
#include "loop.h"
#include "net.h"
#include "wire.h"
#include "wsg/wsg_bin.h"
#include "wsg/wsg_gcl.h"
#include "wsg/wsg_outq.h"
#include "wsg/wsg_timing.h"

/* Replies wait here for a slow client; the queue's policy (wsg_outq.h)
 * drops updates from half full on and disconnects a client whose reply
 * does not fit. */
#define OUTQ_BYTES (16u * 1024u)
#define READ_CHUNK 4096
/* Keepalive: probes after 60 s without traffic, every 10 s, 6 unanswered
 * ones end the connection (a dead peer goes within two minutes). */
#define KEEPALIVE_IDLE_S 60
#define KEEPALIVE_INTERVAL_S 10
#define KEEPALIVE_PROBES 6

#include "tcp_client.h"

static void link_client(tcp_client_t *c)
{
    list_push_back(&c->server->set->clients, &c->link);
    c->server->open++;
}

/* Something happened to c that may finish it: the next reap looks. A
 * connection is marked exactly while it is on its set's list. */
static void mark(tcp_client_t *c)
{
    if (!c->marked) {
        tcp_servers_t *tcp = c->server->set;
        c->marked = true;
        list_push_back(&tcp->marked, &c->mark_link);
        tcp->marked_count++;
    }
}

static tcp_client_t *take_first_marked(tcp_servers_t *tcp)
{
    tcp_client_t *c = LIST_ITEM(list_pop_front(&tcp->marked), tcp_client_t, mark_link);
    c->marked = false;
    tcp->marked_count--;
    return c;
}

static void unmark(tcp_client_t *c)
{
    if (c->marked) {
        tcp_servers_t *tcp = c->server->set;
        list_remove(&tcp->marked, &c->mark_link);
        c->marked = false;
        tcp->marked_count--;
    }
}

/* Failed or overflowed: the next reap closes it. */
static void mark_dead(tcp_client_t *c)
{
    c->dead = true;
    mark(c);
}

static void unlink_client(tcp_client_t *c)
{
    list_remove(&c->server->set->clients, &c->link);
    c->server->open--;
}

static void update_events(tcp_client_t *c)
{
    loop_set_events(c->server->set->loop, c->fd,
                    (short)((c->eof || !held_input_empty(&c->held) ? 0 : POLLIN) |
                            (wsg_outq_empty(&c->outq) ? 0 : POLLOUT)));
}

/* Sends one line with one send(); returns bytes sent, or -1 on a fatal error. */
static ssize_t send_line(tcp_client_t *c, const char *line, size_t len)
{
    ssize_t sent = send(c->fd, line, len, MSG_NOSIGNAL | MSG_DONTWAIT);
    if (sent < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) {
        return 0;
    }
    return sent;
}

static void enqueue(tcp_client_t *c, const char *line, size_t len, wsg_msg_kind_t kind)
{
    switch (wsg_outq_offer(&c->outq, line, len, kind)) {
    case WSG_OUTQ_QUEUED:
        update_events(c);
        break;
    case WSG_OUTQ_DROPPED:
        c->dropped_autosend++;
        break;
    case WSG_OUTQ_OVERFLOW:
        host_logf(HAL_LOG_WARN, "tcp %s: not reading its replies; disconnected", c->peer);
        mark_dead(c);
        break;
    }
}

static void write_line(void *ctx, const char *line, size_t len, wsg_msg_kind_t kind)
{
    tcp_client_t *c = ctx;
    if (c->dead) {
        return;
    }
    if (c->wire != NULL) {
        wire_send(c->wire, line, len, kind); /* later, in parts, joined (wire.c) */
        return;
    }
    if (wsg_outq_empty(&c->outq)) {
        ssize_t sent = send_line(c, line, len);
        if (sent < 0) {
            mark_dead(c);
            return;
        }
        if ((size_t)sent == len) {
            return;
        }
        line += sent;
        len -= (size_t)sent;
        kind = WSG_MSG_REPLY; /* a started line must be finished */
    }
    enqueue(c, line, len, kind);
}

static void note_completed(tcp_client_t *c);

/* The device served the request it held (a timing profile): what came
 * after it goes in now, and the socket is read again once all has. */
static void resume_input(void *ctx)
{
    tcp_client_t *c = ctx;
    held_input_feed(&c->held, &c->conn);
    note_completed(c);
    update_events(c);
    if (wsg_conn_wants_close(&c->conn)) {
        mark(c); /* BYE: closes once its reply is out */
    }
}

static const wsg_conn_io_t tcp_io = {.write = write_line, .resume = resume_input};

/* What the device did not take waits, and the socket is not read meanwhile. */
static void keep_input(tcp_client_t *c, const uint8_t *bytes, size_t len)
{
    if (!held_input_keep(&c->held, bytes, len, false)) {
        mark_dead(c);
    }
    update_events(c);
}
/* The wire's writes: the reap looks again (a BYE's reply, a half-closed
 * connection's last line may just have left). */
static bool wire_write(void *ctx, const char *bytes, size_t len, wsg_msg_kind_t kind)
{
    tcp_client_t *c = ctx;
    wire_t *wire = c->wire;
    unsigned long dropped = c->dropped_autosend;
    /* write_line() without the wire: the one write path, kept whole so the
     * compiler inlines it there (the default costs a branch, no call) */
    c->wire = NULL;
    write_line(c, bytes, len, kind);
    c->wire = wire;
    mark(c);
    return c->dropped_autosend == dropped;
}

/* The wire's reset came: the socket is reset (RST), the session ends
 * without BYE at the next reap, as a cut does. */
static void wire_reset(void *ctx)
{
    tcp_client_t *c = ctx;
    struct linger abort_close = {.l_onoff = 1, .l_linger = 0};
    setsockopt(c->fd, SOL_SOCKET, SO_LINGER, &abort_close, sizeof(abort_close));
    host_logf(HAL_LOG_WARN, "tcp %s: connection reset (wire conditions)", c->peer);
    mark_dead(c);
}

static void wire_touch(void *ctx)
{
    tcp_client_t *c = ctx;
    gripper_touch(c->server->gripper);
}

static const wire_port_t tcp_wire_port = {
    .deliver = wire_write, .reset = wire_reset, .touch = wire_touch};

/* The session's number in the run, for its wire's random choices. */
static uint64_t wire_stream(const tcp_client_t *c)
{
    return ((uint64_t)c->server->gripper->index << 32) | (wsg_conn_id(&c->conn) & 0xffffffffu);
}

static void flush(tcp_client_t *c)
{
    char line[OUTQ_BYTES];
    while (!wsg_outq_empty(&c->outq)) {
        size_t len = wsg_outq_peek(&c->outq, line, sizeof(line));
        ssize_t sent = send_line(c, line, len);
        if (sent < 0) {
            mark_dead(c);
            return;
        }
        wsg_outq_consume(&c->outq, (size_t)sent);
        if ((size_t)sent < len) {
            break;
        }
    }
    update_events(c);
}

static wsg_close_reason_t close_reason(const tcp_client_t *c)
{
    if (wsg_conn_wants_close(&c->conn)) {
        return WSG_CLOSE_ANNOUNCED;
    }
    if (c->expired) {
        return WSG_CLOSE_EXPIRED;
    }
    return wsg_conn_close_announced(&c->conn) ? WSG_CLOSE_ANNOUNCED : WSG_CLOSE_DROPPED;
}

/* What the log says of the close: after BYE the server closed it; after
 * the binary disconnect announcement (0x07) the client did. */
static const char *close_note(const tcp_client_t *c, wsg_close_reason_t reason)
{
    if (reason == WSG_CLOSE_DROPPED) {
        return " without BYE";
    }
    bool after_0x07 = reason == WSG_CLOSE_ANNOUNCED && !wsg_conn_wants_close(&c->conn);
    return after_0x07 ? " after the disconnect announcement (0x07)" : "";
}

void tcp_client_close(tcp_client_t *c)
{
    wsg_close_reason_t reason = close_reason(c);
    bool http = wsg_conn_refused_http(&c->conn);
    host_log_peer(http ? HAL_LOG_WARN : HAL_LOG_INFO, "tcp %s: %s%s", c->peer,
                  http ? "an HTTP request (a web page's cross-protocol request?); closed "
                         "without running it"
                       : "closed",
                  http ? "" : close_note(c, reason));
    if (c->dropped_autosend > 0) {
        host_log_peer(HAL_LOG_INFO, "tcp %s: %lu AUTOSEND lines dropped (client not reading)",
                      c->peer, c->dropped_autosend);
    }
    unmark(c);
    wire_close(c->wire);
    loop_unwatch(c->server->set->loop, c->fd);
    close(c->fd);
    wsg_conn_close(&c->conn, reason);
    gripper_touch(c->server->gripper); /* e.g. FAST STOP on a lost link */
    free(c->outq.ring);
    held_input_free(&c->held);
    unlink_client(c);
    listener_fd_freed(c->server->listener);
    free(c);
}

/* End of input: every command before it has been answered; the
 * connection closes once its queued replies are out (see tcp_server_reap). */
static void on_end_of_input(tcp_client_t *c)
{
    c->eof = true;
    update_events(c);
    mark(c); /* and stays marked until it closes (tcp_server_reap) */
}

/* A command completed in this input restarts its grace (stalled()). */
static void note_completed(tcp_client_t *c)
{
    uint32_t messages = wsg_conn_messages_in(&c->conn);
    if (messages != c->messages_in) {
        c->messages_in = messages;
        c->completed_us = c->heard_us;
    }
}

static void on_client(void *ctx, int fd, short revents)
{
    tcp_client_t *c = ctx;
    (void)fd;
    if ((revents & POLLOUT) != 0) {
        flush(c);
        mark(c); /* its queue may be out */
    }
    if (c->eof) {
        /* only the reply direction is left: a hang-up or error ends it */
        if ((revents & (POLLHUP | POLLERR)) != 0) {
            mark_dead(c);
        }
        return;
    }
    if ((revents & (POLLIN | POLLHUP | POLLERR)) == 0 || c->dead) {
        return;
    }
    uint8_t buf[READ_CHUNK];
    ssize_t n = recv(c->fd, buf, sizeof(buf), MSG_DONTWAIT);
    if (n > 0) {
        c->heard_us = hal_clock_now_us();
        size_t taken = held_input_empty(&c->held)
                           ? gripper_feed(c->server->gripper, &c->conn, buf, (size_t)n, 0)
                           : 0;
        if (taken < (size_t)n) {
            keep_input(c, buf + taken, (size_t)n - taken);
        }
        note_completed(c);
        if (wsg_conn_wants_close(&c->conn)) {
            mark(c); /* BYE: closes once its reply is out */
        }
    } else if (n == 0) {
        on_end_of_input(c);
    } else if (errno != EAGAIN && errno != EINTR) {
        mark_dead(c);
    }
}

bool tcp_client_setup(tcp_client_t *c, int fd, const struct sockaddr_storage *ss)
{
    c->fd = fd;
    net_format_peer(ss, c->peer, sizeof(c->peer));
    c->connected_us = hal_clock_now_us();
    c->heard_us = c->connected_us;
    c->completed_us = c->connected_us;
    int one = 1;
    int idle = KEEPALIVE_IDLE_S, interval = KEEPALIVE_INTERVAL_S, probes = KEEPALIVE_PROBES;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    setsockopt(fd, SOL_SOCKET, SO_KEEPALIVE, &one, sizeof(one));
    setsockopt(fd, IPPROTO_TCP, TCP_KEEPIDLE, &idle, sizeof(idle));
    setsockopt(fd, IPPROTO_TCP, TCP_KEEPINTVL, &interval, sizeof(interval));
    setsockopt(fd, IPPROTO_TCP, TCP_KEEPCNT, &probes, sizeof(probes));
    wsg_outq_init(&c->outq, malloc(OUTQ_BYTES), OUTQ_BYTES);
    if (c->outq.ring == NULL) {
        return false;
    }
    /* --protocol auto: the first byte chooses from the gripper's drivers (host/port/gripper.c) */
    static const wsg_proto_driver_t *const drivers[] = {NULL, &wsg_gcl_driver, &wsg_bin_driver};
    gripper_t *g = c->server->gripper;
    wsg_conn_open(&c->conn, &g->device, drivers[g->opts->protocol], WSG_TRANSPORT_STREAM, &tcp_io,
                  c);
    if (!loop_watch(c->server->set->loop, fd, POLLIN, on_client, c)) {
        wsg_conn_close(&c->conn, WSG_CLOSE_ANNOUNCED);
        free(c->outq.ring);
        return false;
    }
    link_client(c);
    c->wire = wire_open(c->server->set->wires, &c->server->set->wires->all, wire_stream(c), false,
                        &tcp_wire_port, c);
    uint64_t timeout = c->server->idle_timeout_us;
    tcp_servers_t *tcp = c->server->set;
    if (timeout != 0 && c->heard_us + timeout < tcp->idle_due_us) {
        tcp->idle_due_us = c->heard_us + timeout;
        tcp->deadline_lowered = true;
    }
    gripper_touch(g); /* its --idle-timeout is a new deadline */
    return true;
}

/* Replies held back above the port (an injected DELAY of the control
 * channel) still count as queued: a half-closed connection waits for them. */
static bool replies_held(const tcp_client_t *c)
{
    const tcp_servers_t *set = c->server->set;
    return set->replies_held != NULL && set->replies_held(set->held_ctx, &c->conn);
}

static bool idle_too_long(tcp_client_t *c, uint64_t now)
{
    uint64_t timeout = c->server->idle_timeout_us;
    if (timeout == 0 || now - c->heard_us < timeout) {
        return false;
    }
    host_log_peer(HAL_LOG_INFO, "tcp %s: idle for %llu s (--idle-timeout); closed", c->peer,
                  (unsigned long long)(timeout / 1000000u));
    c->expired = true;
    return true;
}

static bool finished(tcp_client_t *c, uint64_t now)
{
    bool flushed = wsg_outq_empty(&c->outq) && !wire_holding(c->wire);
    bool said_bye = wsg_conn_wants_close(&c->conn);
    bool input_done = c->eof && flushed && !replies_held(c) && held_input_empty(&c->held) &&
                      !wsg_conn_request_waits(&c->conn);
    return c->dead || (said_bye && flushed) || input_done || idle_too_long(c, now);
}

static void resume_listeners(tcp_servers_t *tcp)
{
    LIST_EACH_SAFE (node, &tcp->waiting) {
        tcp_server_t *s = LIST_ITEM(node, tcp_server_t, waiting_link);
        listener_resume_when_due(s->listener);
        if (!s->listener->starved || s->listener->fd < 0) {
            s->waits_for_fds = false;
            list_remove(&tcp->waiting, node);
        }
    }
}

/* Only the marked connections are looked at: those that failed, said BYE,
 * flushed their queue or ended their input since the last reap, and all
 * once an --idle-timeout is due; a request answered at once marks nothing.
 * One whose input has ended stays marked until it closes: its held replies
 * (DELAY) may go without anything that would mark it again. */
void tcp_server_reap_due(tcp_servers_t *tcp, uint64_t now)
{
    if (now >= tcp->idle_due_us) {
        LIST_EACH (node, &tcp->clients) {
            mark(CLIENT(node));
        }
    }
    /* those marked now, once each; one marked again goes to the end */
    for (unsigned n = tcp->marked_count; n > 0 && !list_empty(&tcp->marked); n--) {
        tcp_client_t *c = take_first_marked(tcp);
        if (finished(c, now)) {
            tcp_client_close(c);
        } else if (c->eof) {
            mark(c);
        }
    }
    resume_listeners(tcp);
}

/* Asked at every touched tick: the connections are scanned only once the
 * earliest timeout is due (or not known yet), not for every request. */
uint64_t tcp_server_next_deadline_us(tcp_servers_t *tcp)
{
    tcp->deadline_lowered = false;
    if (tcp->idle_due_us > hal_clock_now_us()) {
        return tcp->idle_due_us;
    }
    uint64_t due = UINT64_MAX;
    LIST_EACH (node, &tcp->clients) {
        const tcp_client_t *c = CLIENT(node);
        uint64_t timeout = c->server->idle_timeout_us;
        if (timeout != 0 && c->heard_us + timeout < due) {
            due = c->heard_us + timeout;
        }
    }
    tcp->idle_due_us = due;
    return due;
}

bool tcp_server_cut(tcp_servers_t *tcp, const wsg_conn_t *conn)
{
    LIST_EACH (node, &tcp->clients) {
        tcp_client_t *c = CLIENT(node);
        if (&c->conn == conn) {
            struct linger abort_close = {.l_onoff = 1, .l_linger = 0};
            setsockopt(c->fd, SOL_SOCKET, SO_LINGER, &abort_close, sizeof(abort_close));
            host_logf(HAL_LOG_WARN, "tcp %s: connection cut (control channel)", c->peer);
            tcp_client_close(c);
            return true;
        }
    }
    return false;
}

static void set_wire(tcp_client_t *c, const wire_spec_t *spec)
{
    wire_flush_close(c->wire); /* what it held leaves now, in order */
    c->wire = wire_open(c->server->set->wires, spec, wire_stream(c), false, &tcp_wire_port, c);
    mark(c);
}

unsigned tcp_server_set_wire(tcp_servers_t *tcp, const wsg_conn_t *conn, const wire_spec_t *spec)
{
    unsigned set = 0;
    LIST_EACH (node, &tcp->clients) {
        tcp_client_t *c = CLIENT(node);
        if ((conn == NULL || &c->conn == conn) && !c->dead) {
            set_wire(c, spec);
            set++;
        }
    }
    return set;
}

const wire_t *tcp_server_wire(const tcp_servers_t *tcp, const wsg_conn_t *conn)
{
    LIST_EACH (node, &tcp->clients) {
        const tcp_client_t *c = CLIENT(node);
        if (&c->conn == conn) {
            return c->wire;
        }
    }
    return NULL;
}

const char *tcp_server_peer_name(const tcp_servers_t *tcp, const wsg_conn_t *conn)
{
    LIST_EACH (node, &tcp->clients) {
        const tcp_client_t *c = CLIENT(node);
        if (&c->conn == conn) {
            return c->peer;
        }
    }
    return NULL;
}

unsigned long tcp_server_updates_dropped(const tcp_servers_t *tcp, const wsg_conn_t *conn)
{
    LIST_EACH (node, &tcp->clients) {
        const tcp_client_t *c = CLIENT(node);
        if (&c->conn == conn) {
            return c->dropped_autosend;
        }
    }
    return 0;
}

void tcp_server_close_all(tcp_server_t *s)
{
    LIST_EACH_SAFE (node, &s->set->clients) {
        tcp_client_t *c = CLIENT(node);
        if (c->server == s) {
            tcp_client_close(c);
        }
    }
}

void tcp_server_stop(tcp_server_t *s)
{
    tcp_server_close_all(s);
    listener_stop(&s->own); /* a shared listener stops with its front */
}
