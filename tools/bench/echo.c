/* SPDX-License-Identifier: BSD-3-Clause */
/* The baseline: the least a single-threaded line server on loopback can do.
 * One epoll set; a wake-up touches only the descriptors the kernel reports
 * ready (no scan of a client table); every TCP line is sent back with its
 * own send() (one line in, one line out, as wsgsim answers); every UDP
 * datagram is returned as it came. A line starting with "AUTOSEND"
 * subscribes the connection to a line every BENCH_PERIOD_MS on absolute
 * deadlines: the timer limit of the machine for the AUTOSEND measurement.
 * Only the subscribers are visited for ticks, so a request costs the same
 * whatever the number of connections. */
#include <errno.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <stdlib.h>
#include <string.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include "bench.h"

#define ECHO_MAX_FD 1024
#define ECHO_BUF 8192
#define ECHO_EVENTS 64

typedef struct echo_client {
    int fd;
    size_t len;
    double next_tick_us;                 /* 0: not subscribed */
    struct echo_client *next_subscriber; /* the list run_ticks() visits */
    char buf[ECHO_BUF];
} echo_client_t;

typedef struct {
    int epoll_fd;
    int tcp_fd;
    int udp_fd;
    echo_client_t *by_fd[ECHO_MAX_FD]; /* NULL: no client on that descriptor */
    echo_client_t *subscribers;
} echo_server_t;

static void subscribe(echo_server_t *srv, echo_client_t *c)
{
    static const char ack[] = "ACK AUTOSEND\n";
    if (c->next_tick_us == 0) {
        c->next_subscriber = srv->subscribers;
        srv->subscribers = c;
    }
    c->next_tick_us = now_us();
    send(c->fd, ack, sizeof(ack) - 1, MSG_DONTWAIT | MSG_NOSIGNAL);
}

static void unsubscribe(echo_server_t *srv, echo_client_t *c)
{
    for (echo_client_t **p = &srv->subscribers; *p != NULL; p = &(*p)->next_subscriber) {
        if (*p == c) {
            *p = c->next_subscriber;
            return;
        }
    }
}

static void drop_client(echo_server_t *srv, echo_client_t *c)
{
    if (c->next_tick_us != 0) {
        unsubscribe(srv, c);
    }
    srv->by_fd[c->fd] = NULL;
    close(c->fd); /* also leaves the epoll set */
    free(c);
}

/* Sends every complete line back; keeps a partial one for the next read. */
static void echo_lines(echo_server_t *srv, echo_client_t *c)
{
    char *start = c->buf;
    char *end = c->buf + c->len;
    char *nl;
    while ((nl = memchr(start, '\n', (size_t)(end - start))) != NULL) {
        size_t len = (size_t)(nl + 1 - start);
        if (len >= 8 && memcmp(start, "AUTOSEND", 8) == 0) {
            subscribe(srv, c);
        } else {
            send(c->fd, start, len, MSG_DONTWAIT | MSG_NOSIGNAL);
        }
        start = nl + 1;
    }
    c->len = (size_t)(end - start);
    if (c->len == sizeof(c->buf)) {
        c->len = 0; /* an overlong line: forget it */
    } else if (start != c->buf && c->len != 0) {
        memmove(c->buf, start, c->len);
    }
}

static void on_readable(echo_server_t *srv, echo_client_t *c)
{
    ssize_t n = recv(c->fd, c->buf + c->len, sizeof(c->buf) - c->len, MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        drop_client(srv, c);
        return;
    }
    if (n > 0) {
        c->len += (size_t)n;
        echo_lines(srv, c);
    }
}

static void on_accept(echo_server_t *srv)
{
    int fd = accept4(srv->tcp_fd, NULL, NULL, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
        return;
    }
    echo_client_t *c = fd < ECHO_MAX_FD ? calloc(1, sizeof(*c)) : NULL;
    struct epoll_event ev = {.events = EPOLLIN, .data.fd = fd};
    if (c == NULL || epoll_ctl(srv->epoll_fd, EPOLL_CTL_ADD, fd, &ev) != 0) {
        free(c);
        close(fd);
        return;
    }
    int one = 1; /* as wsgsim does: no Nagle delay on replies */
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    c->fd = fd;
    srv->by_fd[fd] = c;
}

static void on_datagram(int fd)
{
    char buf[65536];
    struct sockaddr_storage ss;
    socklen_t len = sizeof(ss);
    ssize_t n = recvfrom(fd, buf, sizeof(buf), MSG_DONTWAIT, (struct sockaddr *)&ss, &len);
    if (n >= 0) {
        sendto(fd, buf, (size_t)n, MSG_DONTWAIT, (struct sockaddr *)&ss, len);
    }
}

/* Sends the subscribers' due ticks; returns epoll_wait's timeout in ms
 * (-1: nothing scheduled). */
static int run_ticks(echo_server_t *srv)
{
    static const char tick[] = "@POS=55.0\n";
    const double period_us = BENCH_PERIOD_MS * 1000.0;
    if (srv->subscribers == NULL) {
        return -1;
    }
    double now = now_us();
    double next = now + period_us;
    for (echo_client_t *c = srv->subscribers; c != NULL; c = c->next_subscriber) {
        if (c->next_tick_us <= now) {
            send(c->fd, tick, sizeof(tick) - 1, MSG_DONTWAIT | MSG_NOSIGNAL);
            do {
                c->next_tick_us += period_us;
            } while (c->next_tick_us <= now);
        }
        next = c->next_tick_us < next ? c->next_tick_us : next;
    }
    /* Round up: waking a little late costs a tick's accuracy, waking early
     * an extra pass. */
    return (int)((next - now + 999.0) / 1000.0);
}

static void dispatch(echo_server_t *srv, int fd)
{
    if (fd == srv->tcp_fd) {
        on_accept(srv);
    } else if (fd == srv->udp_fd) {
        on_datagram(fd);
    } else if (srv->by_fd[fd] != NULL) {
        on_readable(srv, srv->by_fd[fd]);
    }
}

void echo_server_run(int tcp_fd, int udp_fd)
{
    static echo_server_t srv; /* the process's one server, too large for a stack */
    srv.tcp_fd = tcp_fd;
    srv.udp_fd = udp_fd;
    srv.epoll_fd = epoll_for_two(tcp_fd, udp_fd, "echo");
    struct epoll_event events[ECHO_EVENTS];
    for (;;) {
        int n = epoll_wait(srv.epoll_fd, events, ECHO_EVENTS, run_ticks(&srv));
        for (int i = 0; i < n; i++) {
            dispatch(&srv, events[i].data.fd);
        }
    }
}
