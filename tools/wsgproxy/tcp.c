/* SPDX-License-Identifier: BSD-3-Clause */
/* TCP: each driver connection gets its own connection to the gripper; the
 * bytes go on as they arrive (TCP_NODELAY both ways), and what a side cannot
 * take yet waits in the proxy, which reads no more from the other side
 * until it is gone. An end of stream is passed on as one (shutdown), so a
 * BYE()'s ACK and close reach the driver in order. */
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "proxy.h"

#define PENDING_CAP 65536u

/* One direction: bytes read from `from`, written to `to`. */
typedef struct {
    int from, to;
    char direction; /* '>' driver to gripper, '<' back */
    bool ended;     /* `from` ended its stream; `to` was told once pending went */
    size_t pending_off, pending_len;
    unsigned char pending[PENDING_CAP];
    splitter_t split;
} tcp_flow_t;

typedef struct {
    proxy_t *p;
    bool connected; /* to the gripper */
    char channel[24];
    tcp_flow_t up, down;
} tcp_session_t;

static void session_close(tcp_session_t *s, const char *why)
{
    proxy_t *p = s->p;
    uint64_t now = proxy_now_us(p);
    proxy_record(p, &s->up.split, s->channel, '>', NULL, 0, now, true);
    proxy_record(p, &s->down.split, s->channel, '<', NULL, 0, now, true);
    proxy_note(p, "%s closed: %s", s->channel, why);
    loop_unwatch(p->loop, s->up.from);
    loop_unwatch(p->loop, s->up.to);
    close(s->up.from);
    close(s->up.to);
    split_free(&s->up.split);
    split_free(&s->down.split);
    free(s);
}

/* The events a side waits for: input unless its flow is held up or ended,
 * output while the other flow has bytes for it. */
static short side_events(const tcp_session_t *s, int fd)
{
    const tcp_flow_t *out = fd == s->up.from ? &s->up : &s->down;
    const tcp_flow_t *in = fd == s->up.from ? &s->down : &s->up;
    short events = 0;
    if (!s->connected) {
        return fd == s->up.to ? POLLOUT : 0;
    }
    if (!out->ended && out->pending_len == 0u) {
        events |= POLLIN;
    }
    if (in->pending_len > 0u) {
        events |= POLLOUT;
    }
    return events;
}

static void update_events(tcp_session_t *s)
{
    loop_set_events(s->p->loop, s->up.from, side_events(s, s->up.from));
    loop_set_events(s->p->loop, s->up.to, side_events(s, s->up.to));
}

/* Writes what the flow holds; false when the connection broke. */
static bool flow_drain(tcp_flow_t *f)
{
    while (f->pending_len > 0u) {
        ssize_t n =
            send(f->to, f->pending + f->pending_off, f->pending_len, MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0) {
            return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
        }
        f->pending_off += (size_t)n;
        f->pending_len -= (size_t)n;
    }
    f->pending_off = 0;
    if (f->ended) {
        shutdown(f->to, SHUT_WR);
    }
    return true;
}

/* Reads once from the flow's source and passes it on; false when the
 * connection broke. */
static bool flow_read(tcp_session_t *s, tcp_flow_t *f)
{
    if (f->pending_len > 0u) {
        return true; /* the buffer still holds bytes on their way */
    }
    ssize_t n = recv(f->from, f->pending, PENDING_CAP, MSG_DONTWAIT);
    if (n < 0) {
        return errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR;
    }
    uint64_t at = proxy_now_us(s->p);
    if (n == 0) {
        f->ended = true;
        proxy_record(s->p, &f->split, s->channel, f->direction, NULL, 0, at, true);
        return flow_drain(f);
    }
    f->pending_off = 0;
    f->pending_len = (size_t)n;
    bool ok = flow_drain(f); /* first the bytes on their way, then the record */
    proxy_record(s->p, &f->split, s->channel, f->direction, f->pending, (size_t)n, at, false);
    return ok;
}

static void on_connected(tcp_session_t *s)
{
    int err = 0;
    socklen_t len = sizeof(err);
    if (getsockopt(s->up.to, SOL_SOCKET, SO_ERROR, &err, &len) != 0 || err != 0) {
        char why[128];
        snprintf(why, sizeof(why), "cannot connect to the gripper: %s", strerror(err));
        proxy_log("%s %s", s->channel, why);
        session_close(s, why);
        return;
    }
    s->connected = true;
    update_events(s);
}

static void on_socket(void *ctx, int fd, short revents)
{
    tcp_session_t *s = ctx;
    if (!s->connected) {
        if (fd == s->up.to && (revents & (POLLOUT | POLLERR | POLLHUP)) != 0) {
            on_connected(s);
        }
        return;
    }
    tcp_flow_t *reading = fd == s->up.from ? &s->up : &s->down;
    tcp_flow_t *writing = fd == s->up.from ? &s->down : &s->up;
    bool ok = true;
    if ((revents & POLLOUT) != 0) {
        ok = flow_drain(writing);
    }
    if (ok && (revents & (POLLIN | POLLHUP | POLLERR)) != 0 && !reading->ended) {
        ok = flow_read(s, reading);
    }
    if (!ok ||
        (s->up.ended && s->down.ended && s->up.pending_len == 0u && s->down.pending_len == 0u)) {
        session_close(s, ok ? "both ends closed" : strerror(errno));
        return;
    }
    if ((revents & (POLLHUP | POLLERR)) != 0 && reading->ended) {
        session_close(s, "connection reset");
        return;
    }
    update_events(s);
}

static void set_nodelay(int fd)
{
    int on = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, sizeof(on));
}

/* A session for an accepted driver connection, connecting to the gripper. */
static tcp_session_t *session_open(proxy_t *p, int driver)
{
    tcp_session_t *s = calloc(1, sizeof(*s));
    int gripper = socket(p->gripper.ss_family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (s == NULL || gripper < 0 || !split_init(&s->up.split) || !split_init(&s->down.split)) {
        proxy_log("a driver connection refused: out of memory or descriptors");
        if (s != NULL) {
            split_free(&s->up.split);
            split_free(&s->down.split);
        }
        free(s);
        if (gripper >= 0) {
            close(gripper);
        }
        return NULL;
    }
    s->p = p;
    s->up = (tcp_flow_t){.from = driver, .to = gripper, .direction = '>', .split = s->up.split};
    s->down = (tcp_flow_t){.from = gripper, .to = driver, .direction = '<', .split = s->down.split};
    snprintf(s->channel, sizeof(s->channel), "s%llut", (unsigned long long)++p->next_id);
    set_nodelay(driver);
    set_nodelay(gripper);
    return s;
}

static void start_session(proxy_t *p, int driver)
{
    tcp_session_t *s = session_open(p, driver);
    if (s == NULL) {
        close(driver);
        return;
    }
    struct sockaddr_storage to = proxy_gripper_at(p, p->opt.gripper_tcp_port);
    if (connect(s->up.to, (struct sockaddr *)&to, p->gripper_len) != 0 && errno != EINPROGRESS) {
        char why[128];
        snprintf(why, sizeof(why), "cannot connect to the gripper: %s", strerror(errno));
        proxy_log("%s %s", s->channel, why);
        free(s->up.split.buf);
        free(s->down.split.buf);
        close(s->up.to);
        close(driver);
        proxy_note(p, "%s refused: %s", s->channel, why);
        free(s);
        return;
    }
    proxy_note(p, "%s opened", s->channel);
    if (!loop_watch(p->loop, driver, 0, on_socket, s) ||
        !loop_watch(p->loop, s->up.to, POLLOUT, on_socket, s)) {
        session_close(s, "no room in the event loop");
    }
}

static void on_accept(void *ctx, int fd, short revents)
{
    (void)revents;
    proxy_t *p = ctx;
    for (;;) {
        int driver = accept4(fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
        if (driver < 0) {
            if (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR &&
                errno != ECONNABORTED) {
                proxy_log("accept: %s", strerror(errno));
            }
            return;
        }
        start_session(p, driver);
    }
}

bool proxy_tcp_start(proxy_t *p)
{
    p->tcp_listener =
        net_listen_for(&p->net, SOCK_STREAM, p->opt.listen, p->opt.tcp_port, "--tcp-port");
    return p->tcp_listener >= 0 && loop_watch(p->loop, p->tcp_listener, POLLIN, on_accept, p);
}
